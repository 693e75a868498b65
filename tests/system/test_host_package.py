"""The host package host/mac4card: imported from the checkout without
installing, installable with pip, the ten-line host program of
docs/host-client.md run as it stands there, the error rules of manual 6.3
(acknowledge, retry), waiting for events with timeouts, and a card over the
emulator's TCP serial line."""
import json
import os
import re
import shutil
import subprocess
import sys

import pytest

from conftest import ROOT

sys.path.insert(0, os.path.join(ROOT, "host"))
import mac4card  # noqa: E402

DOC = os.path.join(ROOT, "docs", "host-client.md")


def doc_block(marker):
    """The code block after `<!-- marker -->` in docs/host-client.md."""
    text = open(DOC).read()
    m = re.search(r"<!-- %s -->\n```[a-z]*\n(.*?)```" % marker, text, re.S)
    assert m, "no %s block in docs/host-client.md" % marker
    return m.group(1)


def test_imported_from_the_checkout():
    assert os.path.dirname(mac4card.__file__) == os.path.join(ROOT, "host", "mac4card")
    assert mac4card.find_dictionary() == os.path.join(ROOT, "build", "commands.json")


def test_the_documented_host_program_positions_axis_1():
    prog = doc_block("host-program")
    assert len(prog.strip().splitlines()) <= 10, prog
    r = subprocess.run([sys.executable, "-c", prog], cwd=ROOT, capture_output=True, text=True,
                       timeout=120, env=dict(os.environ, PYTHONPATH=os.path.join(ROOT, "host")))
    assert r.returncode == 0, r.stderr
    m = re.match(r"RCP (-?\d+) user status 0x([0-9A-F]{8}) mode positioning: (.*)$",
                 r.stdout.strip())
    assert m, r.stdout
    assert abs(int(m.group(1)) - 8000) <= 10 and "pos_end" in m.group(3).split()


def test_the_documented_batch_example_ends_in_position():
    r = subprocess.run([sys.executable, os.path.join(ROOT, "tools", "mac4host.py"), "--json",
                        "batch", "-"], input=doc_block("batch-example"), capture_output=True,
                       text=True, timeout=120)
    assert r.returncode == 0, r.stdout + r.stderr
    rs = [o for o in map(json.loads, r.stdout.splitlines()) if o["type"] == "response"]
    assert not [o for o in rs if o["meaning"] == "error"], r.stdout
    assert abs(rs[-2]["value"] - 8000) <= 10
    assert "pos_end" in rs[-1]["status"]["bits"] and "ferr_f" not in rs[-1]["status"]["bits"]


def test_pip_installs_the_package_from_the_checkout(tmp_path):
    # from a copy: setuptools writes build/ and *.egg-info beside the sources
    src = tmp_path / "host"
    shutil.copytree(os.path.join(ROOT, "host"), str(src),
                    ignore=shutil.ignore_patterns("__pycache__", "build", "*.egg-info"))
    target = tmp_path / "site"
    r = subprocess.run([sys.executable, "-m", "pip", "install", "-q", "--no-index",
                        "--no-build-isolation", "--no-deps", "--target", str(target), str(src)],
                       capture_output=True, text=True, timeout=300, cwd=str(tmp_path))
    assert r.returncode == 0, r.stdout + r.stderr
    check = ("import mac4card, sys; print(mac4card.__file__); "
             "print(mac4card.load_dictionary().resolve('WAP').code)")
    r = subprocess.run([sys.executable, "-c", check], capture_output=True, text=True,
                       timeout=60, cwd=str(tmp_path),
                       env=dict(os.environ, PYTHONPATH=str(target),
                                MAC4_COMMANDS=os.path.join(ROOT, "build", "commands.json")))
    assert r.returncode == 0, r.stderr
    path, code = r.stdout.split()
    assert path.startswith(str(target)) and code == "70"


@pytest.fixture
def card():
    with mac4card.connect("sim:inc") as c:
        yield c


def enable(card, axis=0):
    for m in ("INIT", "ME", "E"):
        card.command(m, axis=axis)


def test_commands_answers_and_status_by_name(card):
    assert card.card == "inc"
    r = card.command("INIT")
    assert r.ok and r.meaning == "status" and r.status.mode == "disable" and "init" in r.status
    card.command("ME")
    r = card.command("E")
    assert r.status.mode == "enable" and {"dr_en", "init"} <= r.status.bits
    card.command("WAP", -1234)
    assert card.read("RAP") == -1234                 # signed, as the dictionary's range says
    assert card.status().mode == "enable"
    assert card.status(word="overall").bits == frozenset()
    with pytest.raises(mac4card.Mac4Error, match="unknown mnemonic"):
        card.command("NOSUCH")


def test_syntax_error_is_acknowledged_and_raised(card):
    with pytest.raises(mac4card.CardError) as e:
        card.command(1)                              # code 1: not implemented
    assert e.value.code == 161 and e.value.bits == {"syn_f"}
    assert not e.value.raised_by_card and e.value.acknowledged
    assert "syn_f" not in card.status().bits         # the C went through
    assert card.command("VER").ok and card.errors == [e.value]


def test_false_axis_is_acknowledged(card):
    with pytest.raises(mac4card.CardError) as e:
        card.command("VER", axis=7)
    assert e.value.code == 160 and e.value.axis == 7 and e.value.bits == {"axis_f"}
    assert not e.value.raised_by_card and e.value.acknowledged
    assert card.status(word="overall").bits == frozenset() and card.command("RCP").ok


def test_without_ack_the_card_refuses_until_c(card):
    card.ack_errors = False
    with pytest.raises(mac4card.CardError) as e:
        card.command(1)
    assert not e.value.acknowledged
    with pytest.raises(mac4card.CardError) as e2:        # 6.3: C first
        card.command("INIT")
    assert e2.value.code == 163
    assert card.acknowledge().ok and card.command("INIT").ok


def following_error(card):
    enable(card)
    card.command("WAP", 100000)                      # at the default WPV the plant cannot follow
    card.command("MP")
    card.command("E")


def test_wait_for_raises_the_following_error(card):
    following_error(card)
    with pytest.raises(mac4card.CardError) as e:
        card.wait_for("pos_end", timeout=10)
    assert "ferr_f" in e.value.bits and e.value.raised_by_card and e.value.acknowledged
    card.t.wait(2000)                                # the card brakes the axis and disables it
    assert card.status().mode == "disable"


def test_retry_sends_again_after_an_error_the_card_raised():
    with mac4card.connect("sim:inc", retry=True) as card:
        following_error(card)
        card.t.wait(3000)                            # the following error happens meanwhile
        r = card.command("WPV", 50)                  # answered with the pending error first
        assert r.ok and r.code == card.resolve("WPV").code
        assert [e.code for e in card.errors] == [163] and "ferr_f" in card.errors[0].bits
        assert card.errors[0].raised_by_card and card.errors[0].acknowledged
        assert card.read("RPV") == 50


def test_no_retry_for_the_commands_own_fault():
    with mac4card.connect("sim:inc", retry=True) as card:
        with pytest.raises(mac4card.CardError) as e:
            card.command(1)
        assert e.value.code == 161 and len(card.errors) == 1


def test_wait_for_times_out_in_card_time(card):
    enable(card)
    t0 = card.t.clock()
    with pytest.raises(mac4card.Timeout) as e:
        card.wait_for("pos_end", timeout=0.5)        # no move commanded
    assert 0.5 <= card.t.clock() - t0 < 1.0
    assert e.value.status.mode == "enable"
    with pytest.raises(mac4card.Mac4Error, match="not a bit"):
        card.wait_for("no_such_bit")


def test_connect_to_an_emulated_card_over_tcp():
    from test_serial_connectors import Card as Sim, tcp_port
    sim = Sim(["--serial-tcp", "0", "--serve-seconds", "20"])
    try:
        with mac4card.connect("socket://127.0.0.1:%d" % tcp_port(sim)) as card:
            assert card.card == "inc" and card.version["software"]   # from VER
            enable(card)
            card.command("WPV", 100)
            card.command("WAP", 400)
            card.command("MP")
            card.command("E")
            st = card.wait_for("pos_end", timeout=10)               # wall time on a line
            assert st.mode == "positioning" and abs(card.read("RCP") - 400) <= 10
    finally:
        sim.kill()


def test_connect_to_nothing_is_a_transport_error(tmp_path):
    with pytest.raises(mac4card.TransportError, match="cannot open"):
        mac4card.connect(str(tmp_path / "nosuch"))
    with pytest.raises(mac4card.TransportError, match="inc, ssi and stp"):
        mac4card.connect("sim:xyz")
