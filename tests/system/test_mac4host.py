"""tools/mac4host.py: the serial telegram codec against the manual (7.3.1),
status decoding, the dictionary listing, and commands end to end through the
emulator (its host script, and its serial line on a pseudo-terminal)."""
import json
import os
import re
import select
import subprocess
import sys
import threading
import time

import pytest

from conftest import ROOT, SIM

sys.path.insert(0, os.path.join(ROOT, "tools"))
import mac4host  # noqa: E402
from mac4card import board as B, faults  # noqa: E402  (the path: mac4host's)

HOST = [sys.executable, os.path.join(ROOT, "tools", "mac4host.py")]
DICT = mac4host.load_dictionary()


def host(*args, stdin=None, timeout=120):
    return subprocess.run(HOST + list(args), input=stdin, capture_output=True, text=True,
                          timeout=timeout)


def responses(stdout):
    out = []
    for line in stdout.splitlines():
        o = json.loads(line)
        if o["type"] == "response":
            out.append(o)
    return out


# ---- the codec, byte for byte against manual 7.3.1 (decimal there) ------------------

COMMANDS_731 = [  # (code, parameter, telegram)
    (70, 16, [16, 2, 0, 0, 70, 0, 0, 0, 16, 16, 86]),
    (59, 0, [16, 2, 0, 0, 59, 0, 0, 0, 0, 59]),
    (3, 0, [16, 2, 0, 0, 3, 0, 0, 0, 0, 3]),
    (116, 0, [16, 2, 0, 0, 116, 0, 0, 0, 0, 116]),
    (1, 0, [16, 2, 0, 0, 1, 0, 0, 0, 0, 1]),
]
RESPONSES_731 = [
    (70, 0x02000101, [16, 2, 0, 0, 70, 2, 0, 1, 1, 74]),
    (59, 0x02000101, [16, 2, 0, 0, 59, 2, 0, 1, 1, 63]),
    (3, 0x02000108, [16, 2, 0, 0, 3, 2, 0, 1, 8, 14]),
    (116, 0x000003E8, [16, 2, 0, 0, 116, 0, 0, 3, 232, 95]),
    (161, 0x02002108, [16, 2, 0, 0, 161, 2, 0, 33, 8, 204]),
]


@pytest.mark.parametrize("code,param,wire", COMMANDS_731 + RESPONSES_731)
def test_encode_matches_manual(code, param, wire):
    assert mac4host.encode_telegram(0, code, param) == bytes(wire)


def test_encode_wap16_hex():
    assert mac4host.encode_telegram(0, 70, 16).hex(" ") == "10 02 00 00 46 00 00 00 10 10 56"


@pytest.mark.parametrize("code,param,wire", COMMANDS_731 + RESPONSES_731)
def test_decode_matches_manual(code, param, wire):
    whole = mac4host.TelegramDecoder().feed(bytes(wire))
    assert whole == [mac4host.Telegram(0, code, param)]
    dec = mac4host.TelegramDecoder()                   # one byte at a time
    evs = [e for b in wire for e in dec.feed(bytes([b]))]
    assert evs == [mac4host.Telegram(0, code, param)]


def test_decoder_checksum_dle_doubled_or_not_nak_and_errors():
    # data 00 00 07 00 00 00 09: checksum $10
    plain = mac4host.encode_telegram(0, 7, 9)
    doubled = mac4host.encode_telegram(0, 7, 9, double_dle_checksum=True)
    assert plain[-1] == 0x10 and doubled[-2:] == b"\x10\x10" and len(doubled) == len(plain) + 1
    nxt = mac4host.encode_telegram(1, 116, 0x10101010)
    for first in (plain, doubled):
        evs = mac4host.TelegramDecoder().feed(first + nxt + b"\x15")
        assert evs == [mac4host.Telegram(0, 7, 9), mac4host.Telegram(1, 116, 0x10101010),
                       mac4host.Nak()], first.hex(" ")
    bad = bytearray(mac4host.encode_telegram(0, 70, 16))
    bad[-1] ^= 1
    evs = mac4host.TelegramDecoder().feed(b"\x55" + bytes(bad))
    assert isinstance(evs[0], mac4host.Garbage) and evs[0].data == b"\x55"
    assert evs[1] == mac4host.ChecksumError(0, 70, 16, 0x57, 0x56)


# ---- decoding ------------------------------------------------------------------

def test_decode_manual_response_statuses():
    st = DICT.decode_status("user", 0x02000101)
    assert st["fields"]["mode"]["name"] == "enable" and st["bits"] == ["dr_en", "on_fly"]
    st = DICT.decode_status("user", 0x02002108)
    assert st["fields"]["mode"]["name"] == "positioning"
    assert st["bits"] == ["dr_en", "syn_f", "on_fly"]
    ex = DICT.explain(0, 161, 0x02002108)
    assert ex["meaning"] == "error" and ex["error"]["status_bit"] == "syn_f"
    assert ex["status"]["word"] == "user"
    ex = DICT.explain(0, 116, 0x000003E8)
    assert ex["meaning"] == "value" and ex["value"] == 1000
    assert DICT.explain(0, 116, 0xFFFFFFFB)["value"] == -5          # positions are signed
    assert DICT.explain(0, 70, 0x02000101)["status"]["fields"]["mode"]["name"] == "enable"


def test_decode_cli():
    r = host("decode", "user", "0x02002108")
    assert r.returncode == 0 and "positioning" in r.stdout
    for b in ("dr_en", "syn_f", "on_fly"):
        assert b in r.stdout
    r = host("--json", "decode", "response", "160", "2")      # false axis: overall status
    ex = json.loads(r.stdout)
    assert ex["error"]["status_word"] == "overall" and ex["status"]["bits"] == ["axis_f"]
    r = host("--json", "decode", "response", "124", "7")      # RAS reads the overall status
    assert json.loads(r.stdout)["status"]["bits"] == ["h_stop", "axis_f", "watch_f"]
    r = host("decode", "bogus", "1")
    assert r.returncode == 1


def test_dict_inc():
    r = host("dict", "--card", "inc")
    assert r.returncode == 0
    first = {l.split()[0]: int(l.split()[1]) for l in r.stdout.splitlines()
             if l[:1].strip()}
    assert first["WAP"] == 70 and first["RCP"] == 116
    stp_only = [c["mnemonic"] for c in DICT.data["commands"] if c["cards"] == ["stp"]]
    assert stp_only and not set(stp_only) & set(first)
    j = json.loads(host("--json", "dict", "--card", "inc", "WAP").stdout)
    assert [c["code"] for c in j if c["mnemonic"] == "WAP"] == [70]


# ---- end to end through the emulator's host script -----------------------------------

def test_send_sequence_through_sim():
    r = host("--json", "send", "0", "INIT", "0", "ME", "0", "E", "0", "WAP", "16",
             "MP", "0", "E", "0", "RCP", "0", "1")
    rs = responses(r.stdout)
    assert [x["code"] for x in rs] == [2, 52, 3, 70, 59, 3, 116, 161], r.stdout + r.stderr
    params = [x["param"] for x in rs]
    assert params[:6] + params[7:] == [0x02001000, 0x02001000, 0x02001101, 0x02001101,
                                       0x02001101, 0x02001108, 0x02003108]
    # the actual position: 0 while nothing moves the emulated axis; at most the
    # target 16 should a plant model move it within the few ms since E
    assert 0 <= rs[6]["value"] <= 16 and params[6] == rs[6]["value"]
    assert rs[0]["status"]["bits"] == ["init", "on_fly"]
    assert rs[0]["status"]["fields"]["mode"]["name"] == "disable"
    assert rs[5]["status"]["fields"]["mode"]["name"] == "positioning"
    assert rs[6]["meaning"] == "value" and rs[6]["value"] == 0
    assert rs[7]["error"]["status_bit"] == "syn_f"
    assert r.returncode == mac4host.EXIT_CARD_ERROR      # the card answered an error code
    # the emulator's other lines come through, marked
    assert any(json.loads(l).get("text") == "display 5" for l in r.stdout.splitlines())


def test_send_text_output():
    r = host("send", "0", "VER", "RCP")
    assert r.returncode == 0, r.stderr
    lines = r.stdout.splitlines()
    assert "sim: display 5" in lines
    assert any(l.startswith("0 7 0x00440402 ") and "MAC4-INC" in l for l in lines), r.stdout
    assert any(l.startswith("0 116 0x00000000 ") and "RCP" in l for l in lines), r.stdout


def test_unknown_mnemonic_fails_before_sending(tmp_path):
    started = tmp_path / "started"
    fake = tmp_path / "fakesim"
    fake.write_text("#!/bin/sh\ntouch %s\nexec %s \"$@\"\n" % (started, SIM))
    fake.chmod(0o755)
    r = host("--sim-path", str(fake), "send", "0", "INIT", "0", "NOSUCH", "1")
    assert r.returncode == mac4host.EXIT_USAGE
    assert "unknown mnemonic 'NOSUCH'" in r.stderr
    assert not started.exists() and r.stdout == ""
    r = host("--sim-path", str(fake), "send", "0", "VER")       # the fake sim itself works
    assert r.returncode == 0 and started.exists(), r.stderr


def test_command_not_on_card_fails_before_sending():
    r = host("--sim", "inc", "send", "0", "UWMS", "400")
    assert r.returncode == mac4host.EXIT_USAGE and "MAC4-INC" in r.stderr


def test_alias_wed_works_like_waa():
    got = {}
    for name in ("WED", "WAA", "wed"):
        r = host("--json", "send", "0", name, "1234", "RAA")
        rs = responses(r.stdout)
        assert r.returncode == 0, r.stderr
        got[name] = [(x["code"], x["param"]) for x in rs]
    assert got["WED"] == got["WAA"] == got["wed"]
    assert got["WED"][0][0] == DICT.lookup("WAA").code and got["WED"][1][1] == 1234


def test_batch_file_and_stp(tmp_path):
    f = tmp_path / "cmds.txt"
    f.write_text("# a MAC4-STP axis\n0 UWMS 400   # motor steps\nsend 0 URMS\nwait 10\n"
                 "0 RCP\n")
    r = host("--json", "--sim", "stp", "batch", str(f))
    rs = responses(r.stdout)
    assert r.returncode == 0, r.stderr
    assert [(x["code"], x.get("value")) for x in rs] == [(190, None), (191, 400), (116, 0)]
    assert rs[1]["units"] == "steps"
    r = host("batch", "-", stdin="0 VER extra words\n")
    assert r.returncode == mac4host.EXIT_USAGE and "stdin:1" in r.stderr


def test_false_axis_answers_160():
    r = host("--json", "send", "7", "VER")
    rs = responses(r.stdout)
    assert [(x["axis"], x["code"]) for x in rs] == [(7, 160)]
    assert rs[0]["status"]["word"] == "overall" and "axis_f" in rs[0]["status"]["bits"]


# ---- the serial transport -----------------------------------------------------------

def test_serial_nak_is_retried():
    """A fake card on a pseudo-terminal: NAK to the first telegram, an answer
    to the second."""
    master, slave = os.openpty()
    seen = []

    def card():
        dec = mac4host.TelegramDecoder()
        deadline = time.monotonic() + 20
        while len(seen) < 2 and time.monotonic() < deadline:
            r, _, _ = select.select([master], [], [], 0.2)
            if not r:
                continue
            for ev in dec.feed(os.read(master, 64)):
                if isinstance(ev, mac4host.Telegram):
                    seen.append(ev)
                    os.write(master, b"\x15" if len(seen) == 1 else
                             b"\x99" + mac4host.encode_telegram(ev.axis, ev.code, 0x02000101))

    t = threading.Thread(target=card, daemon=True)
    t.start()
    try:
        r = host("--json", "--serial", os.ttyname(slave), "send", "0", "WAP", "16", timeout=30)
    finally:
        t.join(5)
        os.close(master)
        os.close(slave)
    assert seen == [mac4host.Telegram(0, 70, 16)] * 2
    lines = [json.loads(l) for l in r.stdout.splitlines()]
    assert any(l["type"] == "event" and l["text"] == "NAK" for l in lines), r.stdout
    assert any(l["type"] == "event" and "garbage" in l["text"] for l in lines), r.stdout
    rs = [l for l in lines if l["type"] == "response"]
    assert [(x["code"], x["param"]) for x in rs] == [(70, 0x02000101)] and r.returncode == 0


def test_serial_no_answer_times_out():
    master, slave = os.openpty()
    try:
        t0 = time.monotonic()
        r = host("--serial", os.ttyname(slave), "--timeout", "0.5", "--retries", "0",
                 "send", "0", "VER", timeout=30)
        assert time.monotonic() - t0 < 20
    finally:
        os.close(master)
        os.close(slave)
    assert r.returncode == mac4host.EXIT_TRANSPORT and "no response" in r.stderr


def test_serial_through_emulator_pty():
    h = subprocess.run([SIM, "--help"], capture_output=True, text=True)
    if "--serial-pty" not in h.stdout + h.stderr:
        pytest.skip("build/mac4sim has no --serial-pty yet")
    # without --serve-seconds the card stops when the client closes the pty
    p = subprocess.Popen([SIM, "--card", "inc", "--serial-pty", "--script", "-"],
                         stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True)
    try:
        p.stdin.write("wait-display 5\n")
        p.stdin.close()
        path, deadline = None, time.monotonic() + 20
        while path is None and time.monotonic() < deadline:
            r, _, _ = select.select([p.stdout], [], [], 1)
            if r:
                line = p.stdout.readline()
                if not line:
                    break
                if line.startswith("serial-pty "):
                    path = line.split()[1]
        assert path, "no serial-pty line"
        r = host("--json", "--serial", path, "send", "0", "VER", timeout=30)
        rs = responses(r.stdout)
        assert [(x["code"], x["param"]) for x in rs] == [(7, 0x00440402)], r.stdout + r.stderr
        assert rs[0]["version"]["card"] == "inc" and r.returncode == 0
    finally:
        try:
            p.wait(10)
        except subprocess.TimeoutExpired:
            p.kill()
            p.wait()
            raise


# ---- bad input: one line on stderr, a non-zero exit, never a traceback --------------

def _bad_dict(tmp_path, how):
    data = json.loads(open(mac4host.DEFAULT_DICT).read())
    if how == "aliases-list":
        data["aliases"] = list(data["aliases"].items())
    elif how == "status-list":
        data["status"] = list(data["status"].values())
    elif how == "mnemonic-number":
        data["commands"][0]["mnemonic"] = 7
    elif how == "status-word-of-strings":
        data["status"]["user"] = ["mode", "dr_en"]
    elif how == "code-string":
        data["commands"][3]["code"] = "70"
    f = tmp_path / ("%s.json" % how)
    if how == "deep":
        f.write_text("[" * 100000 + "]" * 100000)
    else:
        f.write_text(json.dumps(data))
    return str(f)


BAD_DICTS = ["aliases-list", "status-list", "mnemonic-number", "deep", "status-word-of-strings",
             "code-string"]
SUBCOMMANDS = [["dict"], ["decode", "user", "0x02002108"], ["send", "0", "VER"],
               ["batch", "-"]]


def one_line_error(r):
    assert r.returncode == mac4host.EXIT_USAGE, (r.returncode, r.stderr)
    assert "Traceback" not in r.stderr, r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("mac4host: "), r.stderr
    return lines[0]


@pytest.mark.parametrize("how", BAD_DICTS)
@pytest.mark.parametrize("sub", SUBCOMMANDS, ids=lambda s: s[0])
def test_bad_dictionary_is_one_line(tmp_path, how, sub):
    r = host("--dict", _bad_dict(tmp_path, how), *sub, stdin="0 VER\n", timeout=60)
    line = one_line_error(r)
    assert "not a MAC4 command dictionary" in line and r.stdout == "", line


def test_bad_dictionary_names_the_field(tmp_path):
    line = one_line_error(host("--dict", _bad_dict(tmp_path, "mnemonic-number"), "dict"))
    assert "commands[0].mnemonic: expected a string, found a number" in line
    line = one_line_error(host("--dict", _bad_dict(tmp_path, "aliases-list"), "dict"))
    assert "aliases: expected an object, found a list" in line
    line = one_line_error(host("--dict", _bad_dict(tmp_path, "deep"), "dict"))
    assert "nested too deeply" in line
    line = one_line_error(host("--dict", str(tmp_path), "dict"))
    assert "is a directory" in line


def batch_error(r, where):
    """A batch file's error: `FILE:LINE: message` alone on stderr, exit status 1."""
    assert r.returncode == mac4host.EXIT_USAGE, (r.returncode, r.stderr)
    assert "Traceback" not in r.stderr, r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(where + ": "), r.stderr
    return lines[0]


def test_batch_not_utf8_is_one_line(tmp_path):
    f = tmp_path / "latin1.txt"
    f.write_bytes(b"0 VER\n0 WAP 16  # Stra\xdfe\n")
    line = batch_error(host("batch", str(f)), "%s:2" % f)
    assert "not UTF-8 text (byte $DF" in line
    r = subprocess.run(HOST + ["batch", "-"], input=b"\xff\xfe0 VER\n", capture_output=True,
                       timeout=60)
    r.stderr, r.stdout = r.stderr.decode(), r.stdout.decode()
    assert "not UTF-8 text (byte $FF" in batch_error(r, "stdin:1")
    f.write_bytes(b"0 VER\n\x000 RCP\n")
    assert "a NUL byte" in batch_error(host("batch", str(f)), "%s:2" % f)
    assert "is a directory" in one_line_error(host("batch", str(tmp_path)))
    line = one_line_error(host("batch", str(tmp_path / "nosuch.txt")))
    assert line == "mac4host: %s: No such file or directory" % (tmp_path / "nosuch.txt"), line
    line = one_line_error(host("batch", "/dev/zero", timeout=60))    # read no further
    assert line == "mac4host: /dev/zero: more than 1048576 bytes: not a batch file", line
    f.write_bytes(b"0 VER\n" * (1 << 20))
    assert "not a batch file" in one_line_error(host("batch", "-", stdin=f.read_text()))


def test_serial_port_that_does_not_open_is_one_line(tmp_path):
    for port in (str(tmp_path / "nosuch"), "socket://127.0.0.1:1", "bogus://x"):
        r = host("--serial", port, "send", "0", "VER", timeout=60)
        assert r.returncode == mac4host.EXIT_TRANSPORT and "Traceback" not in r.stderr, r.stderr
        assert r.stderr.startswith("mac4host: cannot open %s: " % port) and \
            len(r.stderr.strip().splitlines()) == 1, r.stderr


# ---- numbers: one strict reader for the command line and batch files ----------------

@pytest.mark.parametrize("tok,value", [
    ("0", 0), ("0100", 100), ("007", 7), ("-5", -5), ("0x10", 16), ("0X1f", 31), ("$ff", 255),
    ("-0x10", -16), ("-$10", -16), ("4294967295", 0xFFFFFFFF), ("-2147483648", -(1 << 31)),
    ("0xFFFFFFFF", 0xFFFFFFFF), ("0" * 30 + "1", 1)])
def test_number_accepted(tok, value):
    assert mac4host.parse_number(tok, "x") == value


BAD_NUMBERS = ["", "+5", "+-5", "--5", "-", "0b101", "0o17", "1_000", "0x1_0", "1.5", "1e3",
               "nan", "inf", "5abc", " 5", "5 ", "0x", "$", "0x-5", "\uff11\uff12",
               "4294967296", "-2147483649", "0x100000000", "9" * 5000]


@pytest.mark.parametrize("tok", BAD_NUMBERS)
def test_number_rejected(tok):
    with pytest.raises(mac4host.Mac4Error) as e:
        mac4host.parse_number(tok, "widget")
    assert "widget" in str(e.value) and "\n" not in str(e.value) and len(str(e.value)) < 160


def test_number_sign_only_where_negative_and_range_of_the_field():
    assert mac4host.parse_number("255", "axis", 0, 255) == 255
    for tok in ("-1", "-0", "256", "0x100"):
        with pytest.raises(mac4host.Mac4Error, match="axis"):
            mac4host.parse_number(tok, "axis", 0, 255)
    assert mac4host.parse_number("-0", "p") == 0                    # signed field


@pytest.mark.parametrize("tok,ok", [("0.5", 0.5), (".5", 0.5), ("2", 2.0), ("3600", 3600.0),
                                    ("1e3", None), ("nan", None), ("inf", None), ("-1", None),
                                    ("+1", None), ("0x10", None), ("5.", None), ("1_0", None),
                                    ("3600.5", None), ("", None)])
def test_fraction_for_times(tok, ok):
    if ok is None:
        with pytest.raises(mac4host.Mac4Error):
            mac4host.parse_number(tok, "t", 0.001, 3600, fraction=True)
    else:
        assert mac4host.parse_number(tok, "t", 0.001, 3600, fraction=True) == ok


@pytest.fixture
def fake_sim(tmp_path):
    """build/mac4sim behind a wrapper that leaves a file when it starts."""
    started = tmp_path / "started"
    fake = tmp_path / "fakesim"
    fake.write_text("#!/bin/sh\ntouch %s\nexec %s \"$@\"\n" % (started, SIM))
    fake.chmod(0o755)
    return str(fake), started


@pytest.mark.parametrize("args,what", [
    (["send", "+0", "VER"], "axis"), (["send", "0x100", "VER"], "axis"),
    (["send", "-1", "VER"], "axis"), (["send", "0", "WAP", "1_000"], "parameter for WAP"),
    (["send", "0", "WAP", "16.0"], "parameter for WAP"), (["send", "0", "WAP", "0b11"], "WAP"),
    (["send", "0", "WAP", "4294967296"], "WAP"), (["send", "0", "RCP", "0", "1.5"], "code"),
    (["send", "0", "VER", "0", "70000"], "code"), (["send", "0", "VER", "0", "-7"], "code"),
    (["send", "0", "VER", "0", "0x"], "code")])
def test_bad_number_on_the_command_line_sends_nothing(fake_sim, args, what):
    fake, started = fake_sim
    line = one_line_error(host("--sim-path", fake, *args))
    assert what in line, line
    assert not started.exists()


def test_numbers_in_decode():
    r = host("decode", "user", "0100")                        # decimal, not octal
    assert r.returncode == 0 and "0x00000064" in r.stdout, r.stdout
    assert host("decode", "user", "$64").stdout == r.stdout
    for args in (["decode", "user", "-1"], ["decode", "user", "0b1"], ["decode", "user", "1_0"],
                 ["decode", "user", "0x100000000"], ["decode", "response", "1.6e2", "0"],
                 ["decode", "response", "-161", "0"], ["decode", "response", "161", "nan"],
                 ["decode", "response", "7", "0", "--axis", "-1"]):
        one_line_error(host(*args))
    r = host("--json", "decode", "response", "116", "-5")      # a signed parameter
    assert json.loads(r.stdout)["value"] == -5


def test_batch_wait_takes_0_to_3600000_ms(tmp_path):
    steps = mac4host.parse_batch(DICT, ["wait 0", "run 3600000", "sleep 0x10", "wait 0100"])
    assert [s.wait_ms for s in steps] == [0, 3600000, 16, 100]
    for bad in ("1.5", "-1", "3600001", "nan", "inf", "1e3", "+5", "10ms", "1_000"):
        with pytest.raises(mac4host.BatchError) as e:
            mac4host.parse_batch(DICT, ["0 VER", "wait %s" % bad], name="b.txt")
        assert str(e.value).startswith("b.txt:2: ") and "wait" in str(e.value), str(e.value)
    with pytest.raises(mac4host.BatchError, match=r"^b.txt:1: wait needs MS"):
        mac4host.parse_batch(DICT, ["wait"], name="b.txt")


@pytest.mark.parametrize("line,what", [
    ("wait 1.5", "wait"), ("wait 3600001", "wait"), ("wait", "wait needs MS"),
    ("0 WAP 1e3", "parameter for WAP"), ("0 WAP +16", "parameter for WAP"),
    ("0x 0 VER", "axis"), ("0 NOSUCH", "unknown mnemonic"), ("0 VER extra words", "expected"),
    ("1_0 VER", "axis")])
def test_batch_errors_are_file_line_message_and_nothing_is_sent(tmp_path, fake_sim, line, what):
    fake, started = fake_sim
    f = tmp_path / "b.txt"
    f.write_text("# first line\n0 VER\n%s\n0 RCP\n" % line)
    err = batch_error(host("--sim-path", fake, "batch", str(f)), "%s:3" % f)
    assert what in err, err
    assert not started.exists()
    err = batch_error(host("--sim-path", fake, "batch", "-", stdin="%s\n" % line), "stdin:1")
    assert what in err and not started.exists(), err


# ---- option errors: exit status 1 like every usage error, not argparse's 2 ----------

@pytest.mark.parametrize("args", [
    ["--card", "bogus", "dict"], ["--sim", "xyz", "send", "0", "VER"], ["--frobnicate", "dict"],
    ["send"], [], ["bogus-command"], ["--timeout", "nan", "send", "0", "VER"],
    ["--timeout", "1e3", "send", "0", "VER"], ["--timeout", "0", "send", "0", "VER"],
    ["--retries", "1.5", "send", "0", "VER"], ["--retries", "-1", "send", "0", "VER"],
    ["--retries", "0b1", "send", "0", "VER"], ["--sim-max-ms", "inf", "send", "0", "VER"],
    ["send", "0", "VER", "--sim-max-ms", "-5"], ["decode"]])
def test_option_errors_exit_1(fake_sim, args):
    fake, started = fake_sim
    r = host("--sim-path", fake, *args)
    assert r.returncode == mac4host.EXIT_USAGE != mac4host.EXIT_TRANSPORT, (r.returncode, r.stderr)
    assert "Traceback" not in r.stderr and "error:" in r.stderr and "usage:" in r.stderr, r.stderr
    assert r.stdout == "" and not started.exists()


def test_help_exits_0():
    r = host("--help")
    assert r.returncode == 0 and "Exit status" in r.stdout and "130" in r.stdout


def test_negative_hex_parameter_after_double_dash():
    r = host("--json", "send", "--", "0", "WAP", "-0x10", "RAP")
    rs = responses(r.stdout)
    assert r.returncode == 0 and [x["code"] for x in rs] == [70, 71], r.stdout + r.stderr
    assert rs[0]["sent"]["param"] == 0xFFFFFFF0 and rs[1]["value"] == -16


# ---- a name the manual gives two bits: system status 10 and 22, both dr_disable -----

def test_dr_disable_bits_10_and_22_stay_apart():
    named = [b["bit"] for b in DICT.status["system"] if b.get("name") == "dr_disable"]
    assert named == [10, 22]                          # the manual's names, kept (7.1.2)
    both = DICT.decode_status("system", 1 << 10 | 1 << 22 | 1)
    assert both["bits"] == ["m_rdy", "dr_disable@10", "dr_disable@22"]
    assert both["bit_numbers"] == {"m_rdy": 0, "dr_disable@10": 10, "dr_disable@22": 22}
    d10, d22 = both["bit_descriptions"]["dr_disable@10"], both["bit_descriptions"]["dr_disable@22"]
    assert "interlocking" in d10 and d22 == "MAC4-STP: internal control bit"
    for bit in (10, 22):
        st = DICT.decode_status("system", 1 << bit)
        assert st["bits"] == ["dr_disable@%d" % bit] and not st["undefined_bits"]
    # the package's Status: each bit by its key, either by the manual's name
    from mac4card.card import _status
    st = _status(DICT.decode_status("system", 1 << 22))
    assert "dr_disable@22" in st and "dr_disable" in st and "dr_disable@10" not in st
    assert st.bits == {"dr_disable@22"} and len(_status(both).bits) == 3
    assert "m_rdy" not in st and "dr_disable" not in _status(DICT.decode_status("system", 1))


def test_dr_disable_decoded_apart_on_the_command_line():
    r = host("decode", "system", "0x400400")
    assert r.returncode == 0, r.stderr
    assert "system status dr_disable@10 dr_disable@22" in r.stdout
    lines = [l.split(None, 1) for l in r.stdout.splitlines()[1:]]
    assert [l[0] for l in lines] == ["dr_disable@10", "dr_disable@22"] and lines[0][1] != lines[1][1]
    j = json.loads(host("--json", "decode", "system", "0x400000").stdout)
    assert j["bits"] == ["dr_disable@22"] and j["bit_numbers"] == {"dr_disable@22": 22}


# ---- the fault record (DPRAM $4010-$401C, count $4068) -------------------------------

TIMER_VECTOR = 4 * (24 + B.IRQ_LEVEL_TIMER)
BAD = 0x100001                  # odd: the timer's vector fetch ends in an address error
RECORD_RE = (r"^fault record: exception 3 \(address error\) pc=\$100001 sr=\$26[0-9A-F]{2} "
             r"address=\$100001; (\d+) fault\(s\) since power-on$")


@pytest.fixture
def faulting_sim(tmp_path):
    """build/mac4sim that takes one stray host write into the live vector
    table once booted, before mac4host's script: a fault, then the
    watchdog's restart (J11 in), as in tests/system/test_fault_restart.py."""
    w = tmp_path / "faultsim"
    w.write_text("#!/bin/sh\n{ printf 'wait-display 5\\npoke32 0x%04X 0x%X\\nrun 400\\n'; cat; } "
                 "| exec %s \"$@\"\n" % (TIMER_VECTOR, BAD, SIM))
    w.chmod(0o755)
    return ["--sim-path", str(w), "--sim-arg=--allow-faults"]


def fault_lines(stdout):
    return [l for l in stdout.splitlines() if l.startswith("fault record")]


def test_exception_names_from_the_vector_number():
    assert [faults.exception_name(v) for v in (2, 3, 4, 5, 8, 10, 11)] == [
        "bus error", "address error", "illegal instruction", "zero divide",
        "privilege violation", "line 1010 emulator", "line 1111 emulator"]
    assert faults.exception_name(15) == "uninitialized interrupt vector"
    assert faults.exception_name(24 + 6) == "level 6 interrupt autovector"
    assert faults.exception_name(32 + 15) == "TRAP #15 instruction"
    assert faults.exception_name(12) == "reserved vector"
    assert faults.exception_name(200) == "user interrupt vector"
    assert faults.exception_name(256) == "not a 68000 vector number"


def test_fault_record_layout_from_the_board():
    assert [off for _, off in faults.RECORD] == [B.DPC_FAULT_VECTOR, B.DPC_FAULT_PC,
                                                 B.DPC_FAULT_SR, B.DPC_FAULT_ADDR,
                                                 B.DPC_FAULT_COUNT]
    zero = dict.fromkeys(("vector", "pc", "sr", "address", "count"), 0)
    assert faults.decode_fault_record(zero) is None                 # power-on: none
    rec = faults.decode_fault_record(dict(zero, vector=4, pc=0x10ABCD, sr=0x2700, count=2,
                                          address=0x1234))
    assert rec["address"] is None and rec["exception"] == "illegal instruction"
    assert rec["text"] == ("exception 4 (illegal instruction) pc=$10ABCD sr=$2700; "
                           "2 fault(s) since power-on")
    got = []
    rec = faults.read_fault_record(lambda offs: got.extend(offs) or [2, 0x100F00, 0x2604,
                                                                     0xF01000, 1])
    assert got == [off for _, off in faults.RECORD]
    assert rec["text"] == ("exception 2 (bus error) pc=$100F00 sr=$2604 address=$F01000; "
                           "1 fault(s) since power-on")


def test_no_fault_record_after_power_on():
    r = host("--json", "send", "0", "RBS", "RSS", "RAS")
    assert r.returncode == 0, r.stderr
    objs = [json.loads(l) for l in r.stdout.splitlines()]
    assert [o["code"] for o in objs if o["type"] == "response"] == [125, 126, 124]
    assert not [o for o in objs if o["type"] == "fault_record"], r.stdout


def test_fault_record_after_restart_and_status_reads(faulting_sim):
    r = host(*faulting_sim, "send", "0", "VER", "RBS", "RCP", "RSS", "RAS")
    assert r.returncode == 0, r.stderr
    lines = r.stdout.splitlines()
    recs = [i for i, l in enumerate(lines) if l.startswith("fault record")]
    assert all(re.match(RECORD_RE, lines[i]) and re.match(RECORD_RE, lines[i]).group(1) == "1"
               for i in recs), lines
    # once for the restart (before VER's answer), once after each status read
    after = [lines[i - 1].split()[1] if not lines[i - 1].startswith("sim:") else "restart"
             for i in recs]
    assert after == ["restart", "125", "126", "124"], lines
    assert lines[recs[0] - 1] == "sim: display 5" and "sim: reset watchdog" in lines[:recs[0]]
    j = host("--json", *faulting_sim, "send", "0", "RBS")
    objs = [json.loads(l) for l in j.stdout.splitlines()]
    fr = [o for o in objs if o["type"] == "fault_record"]
    assert [o["trigger"] for o in fr] == ["reset watchdog", "RBS"], j.stdout
    o = fr[1]
    assert (o["vector"], o["exception"], o["pc"], o["address"], o["count"]) == \
        (3, "address error", BAD, BAD, 1)
    assert o["sr"] & 0x2700 == 0x2600                   # in the level-6 interrupt
    assert o["text"] in lines[recs[1]]


def test_fault_record_after_a_restart_in_a_batch(faulting_sim):
    """MR restarts the card through the watchdog too: the record of the earlier
    fault is still there, with the same count."""
    r = host("--json", *faulting_sim, "batch", "-", stdin="0 VER\n0 MR\nwait 1500\n0 RCP\n")
    assert r.returncode == 0, r.stderr
    objs = [json.loads(l) for l in r.stdout.splitlines()]
    seq = [o["type"] if o["type"] != "response" else o["code"] for o in objs
           if o["type"] in ("fault_record", "response")]
    assert seq == ["fault_record", 7, 6, "fault_record", 116], seq
    assert [o["count"] for o in objs if o["type"] == "fault_record"] == [1, 1]


def test_fault_record_when_the_card_stays_at_f(faulting_sim):
    """J11 out: no restart, the card stops at "F."; the client reports why it
    does not answer."""
    r = host(*faulting_sim, "--sim-arg=--j11", "--sim-arg=out", "send", "0", "VER")
    assert r.returncode == mac4host.EXIT_TRANSPORT and "did not boot" in r.stderr, r.stderr
    recs = fault_lines(r.stdout)
    assert len(recs) == 1 and re.match(RECORD_RE, recs[0]), r.stdout
    assert "Traceback" not in r.stderr


def test_card_fault_record_in_the_package(faulting_sim):
    from mac4card import Card, SimTransport
    t = SimTransport(card="inc", sim_path=faulting_sim[1], sim_args=["--allow-faults"])
    with Card(t, DICT, card="inc").open() as card:
        rec = card.fault_record()
    assert (rec["vector"], rec["pc"], rec["count"]) == (3, BAD, 1)
    with Card(SimTransport(card="inc"), DICT, card="inc").open() as card:
        assert card.fault_record() is None


def fake_serial_card(master, answers, seen):
    """A card on a pseudo-terminal: answers each telegram with the user status
    (RBS, ... are answered too; a serial line carries nothing else)."""
    dec = mac4host.TelegramDecoder()
    deadline = time.monotonic() + 20
    while len(seen) < answers and time.monotonic() < deadline:
        r, _, _ = select.select([master], [], [], 0.2)
        if r:
            for ev in dec.feed(os.read(master, 64)):
                if isinstance(ev, mac4host.Telegram):
                    seen.append(ev)
                    os.write(master, mac4host.encode_telegram(ev.axis, ev.code, 0x02000101))


def test_no_fault_record_over_a_serial_line():
    """The DPRAM is not reachable over the front-panel line: no record, and
    no claim that there is none; the package says so."""
    master, slave = os.openpty()
    seen = []
    t = threading.Thread(target=fake_serial_card, args=(master, 3, seen), daemon=True)
    t.start()
    try:
        r = host("--json", "--serial", os.ttyname(slave), "send", "0", "RBS", "RSS", timeout=30)
        from mac4card import Card, Mac4Error, SerialTransport
        card = Card(SerialTransport(os.ttyname(slave)), DICT, card="inc")
        card.open()
        card.command("RBS")
        with pytest.raises(Mac4Error, match="DPRAM"):
            card.fault_record()
        card.close()
    finally:
        t.join(5)
        os.close(master)
        os.close(slave)
    assert r.returncode == 0, r.stderr
    objs = [json.loads(l) for l in r.stdout.splitlines()]
    assert [o["code"] for o in objs if o["type"] == "response"] == [125, 126]
    assert not [o for o in objs if o["type"] == "fault_record"] and "fault" not in r.stdout
