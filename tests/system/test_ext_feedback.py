"""Feedback processing (docs/extensions.md): dual feedback with the plant.
Axis 0's motor drives a leadscrew with a known error; a scale on the load
(a VME encoder board, `shaft load`) is read by axis 1 (<et> 4, disabled).
The conversion table takes the difference load - motor ($E), smooths it
($D) and axis 0 adds it to its own measurement (<fbe>): the position loop
keeps the motor encoder's stiffness and the load lands within a count; with
<fbe> 0 the load is off by the leadscrew's error."""
import pytest

from conftest import BOOT, sim
from mac4 import code

TARGETS = (2500, 5300, 9100, 700, 12345)
AMP, PITCH = 20.0, 4000.0
DIFF = 0xE20000 | 0x10 << 8 | 0x11      # $E: axis 1's measurement minus axis 0's
SMOOTH = 0xD00000 | 0x00                 # $D of entry 0
GAIN = (1 << 23) // 16


def dual(fbe):
    lines = ["vme-encoder $80C000 0 bits 24 res 4000 turns 0 shaft load", BOOT,
             "plant 0 leadscrew %g %g" % (AMP, PITCH),
             "send 1 UWET 4", "send 1 UWEA %d" % 0x80C000, "send 1 UWEB 24", "send 1 INIT", "send 0 INIT",
             "send 0 FBX 0", "send 0 FBS %d" % DIFF, "send 0 FBX 1", "send 0 FBW2 %d" % GAIN,
             "send 0 FBS %d" % SMOOTH, "send 0 RFBS", "send 0 RFW2",
             "send 0 WFBE %d" % fbe, "send 0 ME", "send 0 E", "run 20",
             "send 0 WPV 100", "send 0 WPA 10", "send 0 WPD 10"]
    for t in TARGETS:
        lines += ["send 0 WAP %d" % t, "send 0 MP", "send 0 E", "run 1800", "plant 0", "send 0 RBS",
                  "send 1 RCP", "run 5"]
    r = sim("\n".join(lines) + "\n", "inc")
    assert r.rc == 0, r.stderr
    load = [float(l.split("load=")[1].split()[0]) for l in r.grep(r"^plant 0 ")]
    return r, [abs(l - t) for l, t in zip(load, TARGETS)]


def test_dual_feedback_puts_the_load_within_a_count():
    r, err = dual(2)
    assert max(err) <= 1.0, err
    rbs = [p for a, c, p in r.resps() if c == code("RBS")]
    assert len(rbs) == len(TARGETS) and all(p & (1 << 10) for p in rbs)        # pos_end, no error
    assert not any(p & 0xFF0000 for p in rbs)
    # axis 1 reads the load: its position is the target too
    load_axis = [p for a, c, p in r.resps() if a == 1 and c == code("RCP")]
    assert all(abs(p - t) <= 1 for p, t in zip(load_axis, TARGETS)), load_axis
    got = {c: p for a, c, p in r.resps()}
    assert got[code("RFBS")] == SMOOTH and got[code("RFW2")] == GAIN


def test_motor_feedback_alone_leaves_the_leadscrew_error():
    r, err = dual(0)
    assert max(err) >= 10, err


def test_setup_words_are_checked():
    lines = ["send 0 FBX 8", "send 0 C",                       # no entry 8
             "send 0 FBX 0", "send 0 FBS %d" % 0x700000, "send 0 C",    # no method 7
             "send 0 FBS %d" % (0xE00000 | 0x44), "send 0 C",  # no source $44
             "send 0 FBW1 40", "send 0 FBS %d" % 0x300020,     # $3: width 40
             "send 0 C", "send 0 FBW1 8", "send 0 FBS %d" % 0x300020, "send 0 FBW1 9"]   # on: FBS 0 first
    r = sim(BOOT + "\n".join(lines) + "\nrun 10\n", "inc")
    codes = [c for a, c, p in r.resps() if c not in (code("C"),)]
    assert codes == [162, code("FBX"), 162, 162, code("FBW1"), 162, code("FBW1"), code("FBS"), 163], codes


@pytest.mark.parametrize("card,refused", [("inc", True), ("ssi", True), ("stp", False)])
def test_the_budget_refuses_what_the_main_loop_cannot_hold(card, refused):
    """firmware/ext.h: 2-D tables on four axes fit every card's budget;
    compares on four axes besides them do not on INC/SSI (the second) - the command that
    would exceed it is refused with 163 and nothing of it is on - and do
    on the STP (an 8 ms tick)."""
    lines = []
    for a in range(4):
        lines += ["send %d WCRW 1" % a, "send %d WCCL 1" % a, "send %d CDEF" % a] + \
                 ["send %d CENT 0" % a] * 3 + ["send %d CON 1" % a]
    lines += ["send %d PCON 1" % a for a in range(4)] + ["send 3 RPCI", "send 0 REXB"]
    r = sim(BOOT + "\n".join(lines) + "\nrun 10\n", card)
    con = [c for a, c, p in r.resps() if c in (code("CON"), 163)]
    assert con[:4] == [code("CON")] * 4
    pcon = [c for a, c, p in r.resps() if c in (code("PCON"), 163)]
    budget = [p for a, c, p in r.resps() if c == code("REXB")][0]
    if refused:
        assert 163 in pcon, pcon
        assert (budget & 0xFFFF) <= budget >> 16
    else:
        assert pcon == [code("PCON")] * 4, pcon
