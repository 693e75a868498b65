"""The plant models behind the axis boards (docs/plant.md) and their script
commands (docs/host-script.md, "Plant"), in the emulator.

The EPROM images do not drive the axes yet, so most tests run a crafted image
that releases the boot overlay and idles, and drive the axis registers with
`axreg` as the 68000 would."""
import csv
import re

import pytest

from conftest import BOOT, CARDS, sim
from mac4 import crafted


def run_idle(tmp_path, script, card="inc"):
    r = sim(script, card=card, img=crafted(tmp_path), args=["--j11", "out"])
    assert r.rc == 0, r.stderr + r.out
    assert r.faults() == []
    return r


def plant_lines(r, axis):
    out = []
    for l in r.grep(r"^plant %d " % axis):
        out.append(dict(kv.split("=", 1) for kv in l.split()[2:] if "=" in kv))
    return out


def axreg(r, axis, reg):
    return [int(l.split()[3], 16) for l in r.grep(r"^axreg %d %s " % (axis, reg))]


@pytest.mark.parametrize("card", CARDS)
def test_eprom_unaffected_and_plant_at_rest(card):
    r = sim(BOOT + "run 200\nplant\nstatus\n", card)
    assert r.rc == 0, r.stderr
    assert r.faults() == []
    assert r.displays() == ["1", "2", "3", "5"]
    for a in range(4):
        p = plant_lines(r, a)[-1]
        assert p["pos"] == "0" and p["en"] == "0"
        assert p["lp"] == p["ln"] == p["ref"] == p["df"] == "0"
    assert "faults=0" in r.grep(r"^status ")[0]


def test_counter_command_sets_what_the_card_reads():
    r = sim(BOOT + "counter 0 1000\ncounter 3 -1\naxreg 0 cnt_hi\naxreg 0 cnt_lo\n"
            "axreg 3 cnt_hi\naxreg 3 cnt_lo\nplant 0\n", "inc")
    assert r.rc == 0, r.stderr
    assert axreg(r, 0, "cnt_hi") == [0] and axreg(r, 0, "cnt_lo") == [1000]
    assert axreg(r, 3, "cnt_hi") == [0xFF] and axreg(r, 3, "cnt_lo") == [0xFFFF]
    assert plant_lines(r, 0)[0]["counter"] == "0x0003E8"


def test_dac_drives_the_servo(tmp_path):
    r = run_idle(tmp_path, "axreg 0 dac 1000\nrun 50\nplant 0\n"
                           "axreg 0 ctrl 1\nrun 500\nplant 0\nrun 100\nplant 0\n"
                           "axreg 0 ctrl 0\nrun 3000\nplant 0\n")
    p = plant_lines(r, 0)
    assert p[0]["pos"] == "0" and p[0]["en"] == "0"            # /EN open: no motion
    assert int(p[1]["pos"]) > 2500 and p[1]["en"] == "1"       # ~6100 inc/s at 1000 LSB
    assert 550 < int(p[2]["pos"]) - int(p[1]["pos"]) < 620
    assert float(p[1]["volts"]) == pytest.approx(4.883, abs=0.001)
    assert float(p[2]["rpm"]) == pytest.approx(1465, rel=0.02)  # motor, before the 16:1 gear
    assert p[3]["en"] == "0" and float(p[3]["vel"]) == 0.0     # coasted to a stop


def test_switches_polarity_and_faults(tmp_path):
    r = run_idle(tmp_path, "switch 1 lp 500\nswitch 1 ln -500 high\nswitch 1 ref 0 100\n"
                           "axreg 1 in\nplant 1 pos 600\naxreg 1 in\nplant 1\n"
                           "switch 1 df high\naxreg 1 in\nfault 1 drive on\naxreg 1 in\n"
                           "switch 1 lp off\nswitch 1 ln off\nswitch 1 ref off\nswitch 1 df low\n"
                           "axreg 1 in\n")
    ins = axreg(r, 1, "in")
    assert ins[0] == 0x2 | 0x4          # ln high-active and off: 0 V; ref on (low active)
    assert ins[1] == 0x2 | 0x1          # at 600: lp on, ref off
    assert plant_lines(r, 1)[0]["lp"] == "1"
    assert ins[2] == 0x3 | 0x8          # DF high active, no fault: its line is at 0 V
    assert ins[3] == 0x3                # fault: 24 V
    assert ins[4] == 0x8                # nothing wired, DF low active and on


def test_index_latch_and_encoder_commands(tmp_path):
    r = run_idle(tmp_path, "plant 0 encoder lines 500 index 100\n"
                           "axreg 0 ctrl 3\naxreg 0 dac 2047\nrun 300\n"
                           "axreg 0 in\naxreg 0 idx_hi\naxreg 0 idx_lo\naxreg 0 irq\n"
                           "fault 0 encoder frozen\naxreg 0 cnt_hi\naxreg 0 cnt_lo\nrun 10\n"
                           "axreg 0 cnt_hi\naxreg 0 cnt_lo\n"
                           "fault 0 encoder jump 100\naxreg 0 cnt_hi\naxreg 0 cnt_lo\n"
                           "fault 0 encoder off\n")
    assert axreg(r, 0, "in")[0] & 0x10
    assert axreg(r, 0, "idx_lo") == [100]    # the first time increment 100 comes by
    assert axreg(r, 0, "irq") == [1]
    lo = axreg(r, 0, "cnt_lo")   # reading cnt_hi latches cnt_lo
    assert lo[0] == lo[1] > 0 and lo[2] == lo[1] + 100


def test_ssi_commands(tmp_path):
    r = run_idle(tmp_path, "ssi-clock A\nplant 0 ssi bits 13 binary res 8192\nplant 0 pos 1234\n"
                           "axreg 0 in\naxreg 0 ssi_start 0\naxreg 0 in\nrun 0.2\naxreg 0 in\n"
                           "run 0.1\naxreg 0 in\naxreg 0 ssi_hi\naxreg 0 ssi_lo\n"
                           "counter 0 77\naxreg 0 ssi_start 0\nrun 1\naxreg 0 ssi_hi\naxreg 0 ssi_lo\n",
                 card="ssi")
    ins = axreg(r, 0, "in")
    assert ins[0] == 0                          # binary: J1 closed
    assert ins[1] & 0x40 and ins[2] & 0x40      # busy for 26 clocks at 93.75 kHz = 277 us
    assert not ins[3] & 0x40
    hi, lo = axreg(r, 0, "ssi_hi"), axreg(r, 0, "ssi_lo")
    assert (hi[0] << 16 | lo[0]) == 1234 << 13
    assert (hi[1] << 16 | lo[1]) == 77 << 13


def test_stepper_loses_steps_above_ssf(tmp_path):
    # 0x11 = EN | DIR (positive); rate 2097 = 1600 Hz, 524 = 400 Hz
    r = run_idle(tmp_path, "stepper 0 ssf 500\nstepper 1 ssf 500\n"
                           "axreg 0 ctrl 0x11\naxreg 1 ctrl 0x11\n"
                           "axreg 0 rate 524\naxreg 1 rate 2097\nrun 100\nplant 0\nplant 1\n"
                           "axreg 0 rate 0\naxreg 1 rate 0\nrun 10\n"
                           "axreg 0 cnt_hi\naxreg 0 cnt_lo\nplant 0\n", card="stp")
    p0, p1 = plant_lines(r, 0), plant_lines(r, 1)
    assert p0[0]["lost"] == "0" and p0[0]["sync"] == "1" and int(p0[0]["pos"]) > 35
    assert p1[0]["sync"] == "0" and p1[0]["pos"] == "0"
    assert int(p1[0]["lost"]) == int(p1[0]["generated"]) > 150
    cnt = axreg(r, 0, "cnt_lo")[0]               # BR closed: the generated steps
    assert cnt == int(p0[1]["generated"]) == int(p0[1]["pos"])
    assert p0[1]["counter"] == "0x%06X" % cnt


def test_br_and_stepper_errors():
    r = sim("br 0 encoder\n", "inc")
    assert r.rc == 1 and "MAC4-STP only" in r.stderr
    r = sim("br 0 encoder\nplant 0\n", "stp")
    assert r.rc == 0 and plant_lines(r, 0)[0]["in"] == "0x0000"


def test_vme_encoder_through_the_window(tmp_path):
    # move.w #8,$F00304 (VME_PAGE); loop: move.w $E0C000,$5000; bra loop
    code = bytes.fromhex("33FC000800F00304") + bytes.fromhex("33F900E0C0000000500060F4")
    img = crafted(tmp_path, code, "vme.bin")
    script = ("vme-encoder $80C000 0 bits 14 res 10000\nplant 0 pos 6144\n"   # 1.5 rev of 4096
              "run 1\npeek16 0x5000\nvme-boards\nvme-encoder $80C000 off\nrun 1\npeek16 0x5000\n")
    r = sim(script, card="ssi", img=img, args=["--j11", "out"])
    assert r.rc == 0, r.stderr
    vals = [int(l.split()[2], 16) for l in r.grep(r"^peek16 0x5000 ")]
    assert vals == [5000, 0xFFFF]
    assert r.grep(r"^vme-encoder \$80C000 axis=0 bits=14 res=10000 .* value=5000$")


def test_trace_csv(tmp_path):
    path = tmp_path / "t.csv"
    r = run_idle(tmp_path, "trace 0 %s 500\naxreg 0 ctrl 1\naxreg 0 dac 500\nrun 20\ntrace off\n" % path)
    rows = list(csv.DictReader(open(path)))
    assert list(rows[0].keys()) == ["t_ms", "dac", "volts", "en", "position", "velocity",
                                    "motor_rpm", "counter"]
    assert len(rows) == 41
    assert float(rows[-1]["position"]) > float(rows[10]["position"]) > 0
    assert rows[-1]["dac"] == "500"


def test_plant_command_errors():
    for bad, msg in [("plant 4\n", "bad axis"), ("plant 0 motor rpm\n", "usage"),
                     ("plant 0 encoder lines 0\n", "out-of-range"), ("switch 0 xx 1\n", "usage"),
                     ("fault 0 encoder melted\n", "usage"), ("ssi-clock E\n", "usage"),
                     ("vme-encoder $80C001 0\n", "even"), ("trace 0\n", "usage"),
                     ("axreg 0 nothing\n", "unknown axis register")]:
        r = sim(bad, "inc")
        assert r.rc == 1 and msg in r.stderr, (bad, r.stderr)
