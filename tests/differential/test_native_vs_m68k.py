"""Native and 68000 agree: the same scenario through the EPROM image
on Musashi and through the firmware compiled for the host gives bit-identical
DAC words (step rates), counters, published axis data and responses, tick for
tick.  A difference is a bug in one of the two builds (endianness, integer
widths, undefined behaviour - the native build aborts on UB) and the failure
names the first diverging tick.  Machinery: diffrun.py."""
import os

import pytest

from diffrun import M68K, compare, moved, native

AXES = range(4)


def enable_all(card="inc"):
    steps = []
    if card == "ssi":       # 24-bit encoders, left-aligned in the 26 bits: shift by 2 (4.4.2.2)
        steps += [("send", a, "UWSC", 2) for a in AXES] + [("ticks", 2)]
    steps += [("send", a, "INIT") for a in AXES] + [("ticks", 4)]
    steps += [("send", a, "ME") for a in AXES] + [("ticks", 4)]
    steps += [("send", a, "E") for a in AXES] + [("ticks", 8)]
    return steps


def positioning(targets, v, acc, extra=()):
    steps = []
    for a, t in zip(AXES, targets):
        steps += [("send", a, "WPV", v), ("send", a, "WPA", acc), ("send", a, "WPD", acc)]
        steps += [("send", a) + tuple(e) for e in extra]
        steps += [("send", a, "WAP", t), ("send", a, "MP")]
    steps.append(("ticks", 2))
    steps += [("send", a, "E") for a in AXES]
    return steps


def reads(axes=AXES):
    steps = []
    for a in axes:
        steps += [("send", a, m) for m in ("RCP", "RFE", "RBS", "RSS", "ROUT", "RAV", "RPS")]
    return steps


def servo_scenario(card, targets):
    s = enable_all(card)
    s += positioning(targets, 100, 10)
    s += [("ticks", 60)] + reads() + [("ticks", 40)]
    s += [("serial", 0, "RCP"), ("serial", 1, "RBS"), ("ticks", 10)]
    # on the fly: a new target for axis 0 while it moves, then back
    s += [("send", 0, "WAP", (targets[0] + targets[2]) // 2), ("send", 0, "E"), ("ticks", 80)]
    # errors: a false axis number, a code that does not exist
    s += [("send", 7, "RCP"), ("send", 0, 1), ("send", 0, "C"), ("ticks", 4)]
    # stop bit for axis 3 (3.5.1): brake
    s += [("stop", 0x80), ("ticks", 120)] + reads() + [("ticks", 4)]
    return s


def stp_scenario():
    s = enable_all("stp")
    s += positioning([1500, -2000, 800, -600], 2000, 500, extra=[("WLV", 100)])
    s += [("ticks", 30)] + reads() + [("ticks", 20)]
    s += [("serial", 2, "RCP"), ("ticks", 4)]
    s += [("send", 7, "RCP"), ("send", 0, 1), ("send", 0, "C"), ("ticks", 2)]
    s += [("stop", 0x08), ("ticks", 60)] + reads() + [("ticks", 4)]
    return s


# The SSI encoders start at 100000 counts, so that no move crosses 0 (their wrap).
SSI_AT = 100000
SCENARIOS = {
    "inc": (lambda: servo_scenario("inc", [3000, -2500, 4000, -1500]), ()),
    "ssi": (lambda: servo_scenario("ssi", [SSI_AT + 3000, SSI_AT - 2500, SSI_AT + 2000, SSI_AT - 1500]),
            ["plant %d pos %d" % (a, SSI_AT) for a in AXES]),
    "stp": (stp_scenario, ()),
}


@pytest.fixture(scope="module")
def runs():
    for c in SCENARIOS:
        if not os.path.exists(native(c)):
            pytest.fail("build %s first (make native)" % native(c))
    assert os.path.exists(M68K)
    return {}


def run(runs, card):
    if card not in runs:
        steps, setup = SCENARIOS[card]
        runs[card] = compare(card, steps(), setup)
    return runs[card]


@pytest.mark.parametrize("card", ["inc", "ssi", "stp"])
def test_native_and_68000_agree_tick_for_tick(runs, card):
    m, n, problems = run(runs, card)
    assert not problems, "\n".join(problems)
    assert len(m.ticks) > 300 if card != "stp" else len(m.ticks) > 100
    assert any(e[1] == "resp" for e in m.events) and any(e[1] == "rx" for e in m.events)


@pytest.mark.parametrize("card", ["inc", "ssi", "stp"])
def test_the_scenario_really_moves(runs, card):
    """Without motion the comparison above proves little: every axis of the
    scenario must have moved (the counter changed by at least 200 units)."""
    m, n, problems = run(runs, card)
    if problems:
        pytest.skip("the runs differ or failed: see the test above")
    still = [a for a in AXES if moved(m, a) < 200]
    assert not still, "%s: axes %s did not move in the scenario" % (card, still)


@pytest.mark.parametrize("card", ["inc", "stp"])
def test_native_backend_resets_like_the_68000(runs, card):
    """MR resets the card through the watchdog: the native build starts over
    with its static data as crt0 leaves it, and both answer alike."""
    import subprocess
    text = ("wait-display 5 3000\nsend 0 INIT\nrun 10\nsend 0 MR\nrun 300\nwait-display 5 3000\n"
            "send 0 RBS\nsend 0 VER\nrun 10\nestop on\nrun 10\nsend 1 RBS\nrun 10\n")
    out = {}
    for name, binary in (("68000", M68K), ("native", native(card))):
        p = subprocess.run([binary, "--card", card, "--script", "-"], input=text, capture_output=True, text=True)
        assert p.returncode == 0, p.stderr
        out[name] = [l for l in p.stdout.splitlines() if l.split()[0] in ("resp", "reset", "display")]
    assert "reset watchdog" in out["native"]
    # the same answers, resets and displays, each in order; how a display
    # change interleaves with a response the host sees at its next poll
    # depends on the CPU's speed
    for kind in ("resp", "reset", "display"):
        n = [l for l in out["native"] if l.startswith(kind)]
        m = [l for l in out["68000"] if l.startswith(kind)]
        assert n and n == m, kind


def stop_scenario(card, extra):
    """Positioning on all axes, then stop bits for all four at a tick `extra`
    ticks later: over four runs every phase of the profile period."""
    if card == "stp":
        s = enable_all("stp") + positioning([1500, -2000, 800, -600], 2000, 500, extra=[("WLV", 100)])
        s += [("ticks", 12 + extra)]
    elif card == "ssi":
        s = enable_all("ssi") + positioning([SSI_AT + 3000, SSI_AT - 2500, SSI_AT + 2000, SSI_AT - 1500], 100, 10)
        s += [("ticks", 40 + extra)]
    else:
        s = enable_all("inc") + positioning([3000, -2500, 4000, -1500], 100, 10) + [("ticks", 40 + extra)]
    return s + [("stop", 0xAA), ("ticks", 40)] + reads()


@pytest.mark.parametrize("extra", range(4))
@pytest.mark.parametrize("card", ["inc", "ssi", "stp"])
def test_stop_bits_at_every_phase_of_the_profile_period(card, extra):
    """A protective reaction taken by the tick while the main loop's profile
    generator works on the period: the result must not depend on how far the
    generator has got, i.e. on how fast the CPU is."""
    m, n, problems = compare(card, stop_scenario(card, extra), SCENARIOS[card][1])
    assert not problems, "\n".join(problems)
