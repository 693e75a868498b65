"""Native and 68000 agree: the same scenario through the EPROM image
on Musashi and through the firmware compiled for the host gives bit-identical
DAC words (step rates), counters, published axis data and responses, tick for
tick.  A difference is a bug in one of the two builds (endianness, integer
widths, undefined behaviour - the native build aborts on UB) and the failure
names the first diverging tick.  Machinery: diffrun.py."""
import os
import subprocess
import sys

import pytest

from diffrun import M68K, compare, moved, native

AXES = range(4)
ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))


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


# ---- every term, mode, measurement path and protective reaction ----------
# (docs/hardening.md, "Mutation": tools/mutate.py shows that a small change
# of the native build in any of them makes these fail)

def test_every_mutation_still_applies():
    """tools/mutate.py's list names texts of the firmware: each must occur
    once, or the mutation run would stop on a stale entry (the list follows
    the code as it moves)."""
    p = subprocess.run([sys.executable, os.path.join(ROOT, "tools", "mutate.py"), "--check"],
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stderr


def servo_terms(card, at=0):
    """Each axis its own filter, so that every term reaches the DAC word:
    axis 0 zero and pole, axis 1 integrator against the torque limit <sw>,
    axis 2 a large gain (the following error limit) with a small integrator
    and a negative pole, axis 3 K only.  Then the modes one after another."""
    s = []
    if card == "ssi":
        s += [("send", a, "UWSC", 2) for a in AXES] + [("ticks", 2)]
    s += [("send", 1, "UWKISC", 3), ("send", 2, "UWKISC", 6), ("send", 0, "UWAO", 100), ("ticks", 2)]
    if card == "inc":       # a circular axis (4.3.1.2)
        s += [("send", 3, "UWSH", 2), ("send", 3, "UWCR", 3000), ("ticks", 1)]
    s += [("send", a, "INIT") for a in AXES] + [("ticks", 4)]
    s += [("send", a, "ME") for a in AXES] + [("ticks", 2)]
    s += [("send", 0, "WGA", 80), ("send", 0, "WZE", 200), ("send", 0, "WPO", 60),
          ("send", 1, "WKI", 3000), ("send", 1, "WSW", 300),
          ("send", 2, "WGA", 3000), ("send", 2, "WKI", 40), ("send", 2, "WZE", 30), ("send", 2, "WPO", -100),
          ("send", 3, "WGA", 50)]
    s += [("send", a, "E") for a in AXES] + [("ticks", 6)]
    s += positioning([at + 2500, at - 4000, at + 1500, at + 2000], 150, 15)
    s += [("ticks", 90)] + reads() + [("ticks", 30)]
    # the modes: speed and brake, velocity tracking and back to enable,
    # position tracking, test (a DAC word), reset with <ed>
    s += [("send", 0, "WPV", 80), ("send", 0, "MS"), ("send", 0, "E"),
          ("send", 1, "WVT", -60), ("send", 1, "VT"), ("send", 1, "E"),
          ("send", 2, "PT"), ("send", 2, "E"), ("send", 2, "WAT", at + 1800),
          ("send", 3, "WDA", 250), ("send", 3, "MT"), ("send", 3, "E"), ("ticks", 12)]
    s += [("send", 2, "WAT", at + 2300), ("send", 1, "WVT", 40), ("ticks", 12)]
    s += [("send", 0, "MB"), ("send", 0, "E"), ("send", 1, "UE"), ("send", 1, "E"), ("send", 2, "WAT", at + 2000),
          ("send", 3, "WDA", -300), ("ticks", 16)]
    s += [("send", 3, "MRE"), ("send", 3, "E"), ("send", 0, "MRE"), ("send", 0, "E"), ("ticks", 30)]
    s += reads() + [("send", a, m) for a in AXES for m in ("RED", "RCT")] + [("ticks", 4)]
    return s


def servo_protect(card, at=0):
    """The protective reactions: following error (axis 0, a small <mf>),
    software limit (axis 1), a limit switch (axis 2), then /STOP for all and
    the watchdog <wd>.  (A drive fault is an input the main loop samples
    between ticks: servo_exact injects it at a tick's expiry, with the axis
    at rest, where both builds see it in the same tick.)"""
    s = []
    if card == "ssi":
        s += [("send", a, "UWSC", 2) for a in AXES] + [("ticks", 2)]
    s += [("send", 1, "UWLP", at + 1200), ("ticks", 1)]
    s += [("send", a, "INIT") for a in AXES] + [("ticks", 4)]
    s += [("send", a, "ME") for a in AXES] + [("send", 0, "WMF", 60)]
    s += [("send", a, "E") for a in AXES] + [("ticks", 6)]
    s += positioning([at + 3000, at + 3000, at + 3000, at - 3000], 200, 20)
    s += [("ticks", 80)] + reads()
    s += [("send", a, "C") for a in AXES] + [("ticks", 4)]
    s += [("send", 3, "WAP", at - 500), ("send", 3, "MP"), ("send", 3, "E"), ("ticks", 10),
          ("script", "estop on"), ("ticks", 10), ("script", "estop off"), ("ticks", 4)] + reads()
    s += [("send", 0, "WWD", 30), ("ticks", 30)] + reads([0])
    return s


def servo_setup(card, at):
    lines = ["switch 2 lp %d" % (at + 1500)]
    if card == "ssi":
        lines += ["plant %d pos %d" % (a, at) for a in AXES]
    return lines


def stp_terms():
    """The STP's rate stage: TURBO (axis 0), a start/stop frequency with the
    creep phase (axis 1), speed and brake (axis 2), velocity and position
    tracking (axis 3), test mode; then a soft limit and a limit switch."""
    s = [("send", 2, "UWLP", 2500), ("ticks", 1)]
    s += [("send", a, "INIT") for a in AXES] + [("ticks", 4)]
    s += [("send", a, "ME") for a in AXES] + [("send", 0, "TURBO", 1), ("ticks", 2)]
    s += [("send", a, "E") for a in AXES] + [("ticks", 8)]
    s += [("send", 1, "WSSF", 400), ("send", 1, "WSTC", 30), ("send", 1, "WLV", 80)]
    s += positioning([6000, -2500, 800, 1200], 3000, 700)
    s += [("ticks", 40)] + reads() + [("ticks", 30)]
    s += [("send", 2, "WPV", 2500), ("send", 2, "MS"), ("send", 2, "E"),
          ("send", 3, "WVT", -900), ("send", 3, "VT"), ("send", 3, "E"), ("ticks", 20)]
    s += [("send", 3, "PT"), ("send", 3, "E"), ("send", 3, "WAT", 400), ("ticks", 8),
          ("send", 3, "WAT", 900), ("ticks", 20), ("send", 0, "WDA", 3000), ("send", 0, "MT"), ("send", 0, "E"),
          ("ticks", 10)] + reads()
    s += [("send", 0, "MB"), ("send", 0, "E"), ("ticks", 40)]
    s += reads() + [("send", a, m) for a in AXES for m in ("RED", "RCT", "RCPI")] + [("ticks", 4)]
    return s


TERMS = {
    "inc": (lambda: servo_terms("inc"), ()),
    "ssi": (lambda: servo_terms("ssi", SSI_AT), ["plant %d pos %d" % (a, SSI_AT) for a in AXES]),
    "stp": (stp_terms, ["switch 3 lp 700"]),
}
PROTECT = {
    "inc": (lambda: servo_protect("inc"), servo_setup("inc", 0)),
    "ssi": (lambda: servo_protect("ssi", SSI_AT), servo_setup("ssi", SSI_AT)),
}


@pytest.mark.parametrize("card", ["inc", "ssi", "stp"])
def test_every_filter_term_and_mode_agrees(card):
    steps, setup = TERMS[card]
    m, n, problems = compare(card, steps(), setup)
    assert not problems, "\n".join(problems)
    still = [a for a in AXES if moved(m, a) < 200]
    assert not still, "%s: axes %s did not move" % (card, still)


@pytest.mark.parametrize("card", ["inc", "ssi"])
def test_the_protective_reactions_agree(card):
    steps, setup = PROTECT[card]
    m, n, problems = compare(card, steps(), setup)
    assert not problems, "\n".join(problems)
    # the reactions happened: errors answered (163 logical error) on the axes
    assert sum(1 for e in m.events if e[1] == "resp" and e[2].split()[1] == "163") >= 3, m.events[-40:]


def servo_exact(card="inc"):
    """Scenarios that land on the compared values exactly (tools/mutate.py):
    axis 0 a following error growing by less than a unit a tick past <mf>
    (its encoder frozen under a slow move), axis 1 turned by hand to one
    unit past its software limit, axis 2 against <sw> in the positive direction, axis 3
    positioning where v^2 + v d = 2 d rem falls on a profile period (5.6:
    the brake decision at equality), then a drive fault injected at a tick
    boundary: both builds sample it in the same tick's supervision."""
    s = [("send", 1, "UWLP", 100), ("ticks", 1)]
    s += [("send", a, "INIT") for a in AXES] + [("ticks", 4)]
    s += [("send", a, "ME") for a in AXES]
    s += [("send", 0, "WMF", 40), ("send", 2, "WGA", 3000), ("send", 2, "WSW", 300)]
    s += [("send", a, "E") for a in AXES] + [("ticks", 4)]
    s += [("script", "fault 0 encoder frozen")]
    for a, v, acc, t in ((0, 2, 1, 5000), (2, 200, 20, 3000), (3, 100, 10, 1100)):
        s += [("send", a, "WPV", v), ("send", a, "WPA", acc), ("send", a, "WPD", acc), ("send", a, "WAP", t),
              ("send", a, "MP"), ("send", a, "E")]
    s += [("ticks", 120)] + reads() + [("ticks", 20)]
    # the mechanics of axis 1 turned by hand to one unit past <lp>
    s += [("script", "plant 1 pos 101"), ("ticks", 80)]
    s += [("send", 3, "WAP", 2700), ("send", 3, "E"), ("ticks", 160)] + reads()
    s += [("script", "fault 3 drive on"), ("ticks", 8), ("send", 3, "RBS"), ("send", 3, "E"), ("ticks", 8),
          ("script", "fault 3 drive off"), ("ticks", 4)] + reads()
    return s


def stp_saturate():
    """The STP's rate register at and beyond 50 kHz (table 4.1): velocity
    tracking at 50 kHz on axis 0 (saturated: 400 steps a tick), 45 kHz on axis 1."""
    s = [("send", a, "INIT") for a in (0, 1)] + [("ticks", 4)]
    s += [("send", a, "ME") for a in (0, 1)] + [("ticks", 2)]
    s += [("send", a, "E") for a in (0, 1)] + [("ticks", 4)]
    s += [("send", 0, "WVT", 50000), ("send", 0, "VT"), ("send", 0, "E"),
          ("send", 1, "WVT", 45000), ("send", 1, "VT"), ("send", 1, "E"), ("ticks", 16)]
    s += reads((0, 1)) + [("send", a, "MB") for a in (0, 1)] + [("send", a, "E") for a in (0, 1)] + [("ticks", 30)]
    return s


def test_stp_rate_saturates_alike():
    m, n, problems = compare("stp", stp_saturate())
    assert not problems, "\n".join(problems)
    rates = [int(m.ticks[t].split("|")[1].split()[0]) for t in sorted(m.ticks)]
    assert 0xFFFF in rates, sorted(set(rates))[-5:]


def brake_equality(card="inc"):
    """Positionings at <pv> 100, <pa> = <pd> 10: braking must begin where
    v^2 + v d = 2 d rem (5.6), i.e. 550 units before the target.  Moves of
    2000 + 10 k units, k = 0..11, put every residue of the cruise's
    100-unit grid on that point once."""
    s = [("send", a, "INIT") for a in AXES] + [("ticks", 4)]
    s += [("send", a, "ME") for a in AXES] + [("send", a, "E") for a in AXES] + [("ticks", 4)]
    s += [("send", a, m, 100 if m == "WPV" else 10) for a in AXES for m in ("WPV", "WPA", "WPD")]
    at = [0] * 4
    for r in range(3):
        for a in AXES:
            at[a] += 2000 + 10 * (4 * r + a)
            s += [("send", a, "WAP", at[a]), ("send", a, "MP"), ("send", a, "E")]
        s += [("ticks", 170)]
    return s + reads()


@pytest.mark.parametrize("card", ["inc"])
def test_brake_decision_at_equality_agrees(card):
    m, n, problems = compare(card, brake_equality(card))
    assert not problems, "\n".join(problems)


@pytest.mark.parametrize("card", ["inc"])
def test_exact_boundaries_agree(card):
    m, n, problems = compare(card, servo_exact(card))
    assert not problems, "\n".join(problems)
    # the reactions happened: following error (axes 0, 2), software limit, drive fault
    import sys
    sys.path.insert(0, os.path.join(os.path.dirname(M68K), "..", "host"))
    from mac4card.dictionary import load_dictionary
    d = load_dictionary(os.path.join(os.path.dirname(M68K), "commands.json"))
    last = {}
    for e in m.events:
        f = e[2].split()
        if e[1] == "resp" and f[1] == "125":           # RBS: the user status
            last[int(f[0])] = d.decode_status("user", int(f[2], 16))["bits"]
    for a, bit in ((0, "ferr_f"), (1, "swl_p"), (2, "ferr_f"), (3, "dr_f")):
        assert bit in last[a], (a, last[a])
