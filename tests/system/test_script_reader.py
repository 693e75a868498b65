"""mac4sim's script reader and exit statuses (docs/host-script.md): bad input
is an error with its line number and a non-zero exit, never a hang, a crash
or a silent guess; numbers are decimal unless written 0x or $."""
import os
import subprocess

import pytest

from conftest import BOOT, SIM, image, sim

# exit statuses of docs/host-script.md
OK, ERROR, TIMEOUT, FAULT, STOPPED = 0, 1, 2, 3, 4


def mac4sim(*args, script=None, timeout=30):
    p = subprocess.run([SIM, "--card", "inc"] + list(args), input=script, capture_output=True,
                       text=True, timeout=timeout)
    return p.returncode, p.stdout, p.stderr


# (script, the words of the error): each refused on its line 2, after a good line 1
BAD_LINES = {
    "run nan": "usage: run MS",
    "run inf": "usage: run MS",
    "run 0x10": "usage: run MS",
    "run -1": "usage: run MS",
    "run 3600001": "usage: run MS",
    "wait-display 5 99999999999999999999": "usage: wait-display",
    "wait-display 5 nan": "usage: wait-display",
    "wait-display 16": "usage: wait-display",
    "run-ticks 0": "usage: run-ticks",
    "estop maybe": "usage: estop on|off",
    "host read maybe": "usage: host read on|off",
    "jumper j11 maybe": "usage: jumper j11 in|out",
    "peek32 0xFFFE": "bad DPRAM offset '0xFFFE' for a long",
    "poke32 0xFFFE 1": "bad DPRAM offset '0xFFFE' for a long",
    "peek16 0x10000": "bad DPRAM offset",
    "peek8 010x": "bad DPRAM offset",
    "send 0 WAP 12abc": "bad parameter",
    "send 0 WAP 0o17": "bad parameter",
    "send 0 WAP 99999999999999999999999": "bad parameter",
    "send 0 0x1FFFF": "unknown code",
    "fc 8": "usage: fc",
    "profile report -1": "usage: profile",
    "plant 0 gear nan": "bad or out-of-range number",
    "plant 0 gear 0x10": "bad or out-of-range number",
    "tx " + " ".join(["10"] * 63) + " zz": "bad hex bytes 'zz'",
}


@pytest.mark.parametrize("line", sorted(BAD_LINES))
def test_bad_line_is_an_error_with_its_line_number(line):
    rc, out, err = mac4sim("--script", "-", script="echo first\n" + line + "\necho after\n")
    assert rc == ERROR, (rc, err)
    assert "-:2: " in err and BAD_LINES[line] in err, err
    assert "after" in out               # an error does not end the script


def test_numbers_are_decimal_unless_hex():
    # a leading zero is decimal, as in mac4host: WAP 0100 is one hundred
    r = sim(BOOT + "send 0 WAP 0100\nsend 0 RAP\nsend 0 WAP $64\nsend 0 RAP\nsend 0 WAP 0x064\n"
            "send 0 RAP\nsend 0 WAP -0100\nsend 0 RAP\nrun 20\n")
    assert r.rc == OK, r.stderr
    reads = [p for _, code, p in r.resps() if code == 71]   # RAP
    assert reads == [100, 100, 100, (-100) & 0xFFFFFFFF], r.resps()
    r = sim("poke16 0100 0x1234\npeek16 0x64\npoke8 $0065 011\npeek8 101\n")
    assert r.peek(0x64) == 0x1234 and r.peek(0x65) == 11, r.out


def test_peek32_at_the_top_of_the_dpram_does_not_wrap():
    r = sim("poke32 0xFFFC 0x11223344\npeek32 0xFFFC\npeek16 0xFFFE\npeek8 0xFFFF\n")
    assert r.rc == OK and r.peek(0xFFFC) == 0x11223344 and r.peek(0xFFFE) == 0x3344, r.out


def test_tx_takes_every_byte_of_a_long_line():
    # 70 tokens: the 64th and later ones used to be dropped without a word
    r = sim(BOOT + "tx " + " ".join(["55"] * 70) + "\nrun 300\nserial-stats\n")
    assert r.rc == OK, r.stderr
    stats = dict(kv.split("=") for kv in r.grep(r"^serial-stats ")[0].split()[1:])
    assert int(stats["garbage"]) == 70, stats


def test_a_line_longer_than_1023_characters():
    script = "echo " + "a" * 1100 + "\necho after\n"
    rc, out, err = mac4sim("--script", "-", script=script)
    assert rc == ERROR and "-:1: line longer than 1023 characters" in err, err
    assert "after" not in out           # the script ends there: nothing runs from its tail
    # 1023 characters is still a line
    rc, out, err = mac4sim("--script", "-", script="echo " + "b" * 1018 + "\necho after\n")
    assert rc == OK and "b" * 1018 in out and "after" in out, err


def test_nul_byte_in_a_line():
    rc, out, err = mac4sim("--script", "-", script="echo one\necho a\0run 5\necho two\n")
    assert rc == ERROR and "-:2: a NUL byte in the line" in err, err
    assert "two" not in out


def test_dev_zero_as_script_and_include(tmp_path):
    rc, out, err = mac4sim("--script", "/dev/zero", timeout=10)
    assert rc == ERROR and "/dev/zero:1: a NUL byte" in err, err
    rc, out, err = mac4sim("--script", "-", script="include /dev/zero\necho after\n", timeout=10)
    assert rc == ERROR and "/dev/zero:1: a NUL byte" in err and "after" in out, err


def test_directory_as_script_and_include(tmp_path):
    rc, out, err = mac4sim("--script", str(tmp_path))
    assert rc == ERROR and "a directory" in err, err
    rc, out, err = mac4sim("--script", "-", script="include %s\n" % tmp_path)
    assert rc == ERROR and "-:1: include: '%s' is a directory" % tmp_path in err, err


def test_include_line_numbers_after_a_bad_line(tmp_path):
    inc = tmp_path / "inc.mac4"
    inc.write_text("echo in\n\nfrobnicate\n")
    rc, out, err = mac4sim("--script", "-", script="echo a\ninclude %s\nrun nan\n" % inc)
    assert rc == ERROR and "inc.mac4:3: unknown command" in err and "-:3: usage: run" in err, err


@pytest.mark.parametrize("args,words", [
    (["--irq-level", "3abc"], "bad --irq-level"),
    (["--irq-level", "8"], "bad --irq-level"),
    (["--irq-level", ""], "bad --irq-level"),
    (["--j11", "maybe"], "bad --j11"),
    (["--serve-seconds", "nan"], "bad --serve-seconds"),
    (["--serve-seconds", "0x10"], "bad --serve-seconds"),
    (["--serial-tcp", "08x"], "bad --serial-tcp"),
])
def test_bad_option_values(args, words):
    rc, out, err = mac4sim("--script", "-", *args, script="quit\n")
    assert rc == ERROR and words in err, err


def test_good_option_values():
    rc, out, err = mac4sim("--script", "-", "--irq-level", "0x5", "--j11", "out", script=BOOT + "quit\n")
    assert rc == OK, err


def test_exit_status_wait_display_timeout():
    rc, out, err = mac4sim("--script", "-", script=BOOT + "wait-display 7 20\n")
    assert rc == TIMEOUT and "timeout wait-display 7" in out and "timed out" in err, (out, err)
    rc, out, err = mac4sim("--script", "-", script=BOOT + "wait-display 7 20\nfrobnicate\n")
    assert rc == ERROR, err             # a script error first


def test_exit_status_card_stopped_at_boot(tmp_path):
    bad = tmp_path / "bad.bin"
    data = bytearray(open(image("inc"), "rb").read())
    data[0x8000] ^= 1                   # the checksum fails: the card stops at 3.
    bad.write_bytes(data)
    rc, out, err = mac4sim("--image", str(bad), "--script", "-", script=BOOT)
    assert rc == STOPPED and "display 3." in out and "stopped with the display at 3." in err, (out, err)


def test_exit_status_emulator_fault_before_stop(tmp_path):
    # an illegal opcode at the reset entry: the emulator's fault wins over the rest
    data = bytearray(open(image("inc"), "rb").read())
    pc = int.from_bytes(data[4:8], "big") - 0x100000
    data[pc:pc + 2] = b"\x4a\xfc"
    bad = tmp_path / "ill.bin"
    bad.write_bytes(data)
    rc, out, err = mac4sim("--image", str(bad), "--script", "-", script="wait-display 5 50\n")
    assert rc == FAULT and "fault illegal opcode" in out, (out, err)
    rc, out, err = mac4sim("--image", str(bad), "--allow-faults", "--script", "-",
                           script="wait-display 5 50\n")
    assert rc == TIMEOUT, (rc, out, err)    # --allow-faults: neither 3 nor 4, the wait timed out


def test_includes_that_multiply_stop_at_1000_files(tmp_path):
    # ten includes of itself a level, 8 deep: 10^8 files without the bound
    many = tmp_path / "many.mac4"
    many.write_text("include many.mac4\n" * 10)
    rc, out, err = mac4sim("--script", "-", script="include %s\necho after\n" % many, timeout=60)
    assert rc == ERROR and "more than 1000 files included in all" in err and "after" in out, err[-300:]
