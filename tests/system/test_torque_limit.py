"""Torque (force) limitation <sw> (manual 5.16, diagram 5.12, index "Torque
(Force) Limitation"; docs/interpretations.md): the magnitude of the
controller's output is at most <sw> DAC LSB.  A mode parameter (WSW/RSW),
in force from the next E like the controller's gains; 2048, the default, is
the whole DAC range."""
import pytest

from conftest import BOOT, sim
from mac4 import TICK_MS, code


def s16(v):
    v &= 0xFFFFFFFF
    return v - (1 << 32) if v & 0x80000000 else v


def track_jump(card, sw=None, usr=False, jump=1500):
    """Position tracking, then a jump of the target: the controller asks
    for far more than the DAC gives; ROUT every 2.5 ms for 150 ms."""
    lines = ["send 0 USR"] if usr else []
    lines += ["send 0 INIT", "send 0 ME", "send 0 E", "run 20"]
    if sw is not None:
        lines.append("send 0 WSW %d" % sw)
    lines += ["send 0 PT", "send 0 E", "run 20", "send 0 RSW"]
    lines += ["send 0 WAT %d" % jump] + sum([["run %g" % TICK_MS["inc"], "send 0 ROUT"] for _ in range(60)], [])
    r = sim(BOOT + "\n".join(lines) + "\n", card)
    assert r.rc == 0, r.stderr
    outs = [s16(p) for a, c, p in r.resps() if c == code("ROUT")]
    rsw = [p for a, c, p in r.resps() if c == code("RSW")]
    return outs, rsw[0]


@pytest.mark.parametrize("card", ["inc", "ssi"])
def test_the_output_stays_within_sw(card):
    outs, rsw = track_jump(card, sw=300)
    assert rsw == 300
    assert max(abs(o) for o in outs) == 300, outs       # reached, never beyond
    assert sum(1 for o in outs if o == 300) >= 20        # held at the limit while it catches up


@pytest.mark.parametrize("card", ["inc", "ssi"])
def test_without_a_limit_the_same_jump_saturates_the_dac(card):
    outs, rsw = track_jump(card)
    assert rsw == 2048                                   # the default: the whole range
    assert max(outs) == 2047, outs


def test_the_limit_holds_for_a_reversed_motor_direction():
    outs, _ = track_jump("inc", sw=250, usr=True)       # USR negates the output (4.2): -250
    assert min(outs) == -250 and max(abs(o) for o in outs) == 250, outs


def test_sw_takes_effect_at_the_next_e():
    # WSW after the E that started position tracking: not in force yet
    lines = ["send 0 INIT", "send 0 ME", "send 0 E", "send 0 PT", "send 0 E", "run 20", "send 0 WSW 200",
             "send 0 WAT 1500", "run 40", "send 0 ROUT", "send 0 E", "run 10", "send 0 ROUT", "run 5"]
    r = sim(BOOT + "\n".join(lines) + "\n", "inc")
    outs = [s16(p) for a, c, p in r.resps() if c == code("ROUT")]
    assert outs[0] > 200 and outs[1] == 200, outs


def test_sw_is_not_on_the_stepper_card():
    r = sim(BOOT + "send 0 WSW 300\nsend 0 RSW\nrun 5\n", "stp")
    assert [c for a, c, p in r.resps()] == [161, 161]
