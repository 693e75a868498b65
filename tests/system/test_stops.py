"""Protective stops seen from the mechanics (4.8, 4.9, 5.x, 6.3; the design in
docs/interpretations.md, "Protective reactions").  The plant runs at speed
in a mode, a cause of a stop comes, and the per-tick trace of the plant
(`trace 0 FILE tick`: the mechanics' position and speed, not the setpoint)
shows where the mechanics come to rest, whether the drive was enabled until
they stood, and the status bits and the report that follow.

* `test_stop_sweep`: every cause x every mode in which it can happen x every
  card.  Stops that disable on MAC4-INC/SSI (MRE, DEINIT, watchdog, leaving a
  software limit, following error) open /EN only with the mechanics at rest
  (|speed| <= 1 Inc per tick), within the distance that the reaction delay
  (two ticks at speed), the <ed> ramp and the following lag allow; stops that
  hold (limit switch, stop bits) stand in mode brake within it; the drive
  fault and the emergency stop disable (the mechanics coast: the distance is
  reported, not bounded); on the STP (open loop) the steps ramp with <ed> to
  <ssf> and stop, and not one step is lost.  Each run prints a `STOP` line;
  its figures are the stopping-distance column of docs/hardening.md.
* the runaway guards: reversed motor wiring, a frozen encoder, a motor that
  cannot follow <ed>: /EN opens at once with ferr_f, and the mechanics stop
  near where the fault began.
* reads while an error waits, C right after an error, m_rdy, the LEDs, ROUT.
"""
import csv
import os

import pytest

from conftest import BOOT, sim
from mac4 import BIT, MODE, code

TICK_MS = {"inc": 2.5, "ssi": 2.5, "stp": 8.0}
SP_MS = {"inc": 10.0, "ssi": 10.0, "stp": 32.0}
# the speed of the sweep: INC/SSI 100 Inc/SP (10 000 Inc/s, the figure), STP 2000 Hz
V = {"inc": 100, "ssi": 100, "stp": 2000}
ED = 5000                                     # <ed> default: Inc/SP^2
ED_STP = 2000                                 # STP: Hz/SP, 500 Hz per tick, below the motor's 1000 Hz
STP_STEPS_SP = 0.032                          # steps per SP of 32 ms per Hz


def ub(*names):
    v = 0
    for n in names:
        v |= 1 << BIT["user"][n]
    return v


def sb(name):
    return 1 << BIT["system"][name]


def pre(card):
    return ["run 5", "send 0 UWSC 2"] if card == "ssi" else []


# ---- the modes: (script lines that set the move going, cards) --------------------
def m_speed(card, v):
    acc = [] if card != "stp" else ["send 0 WPA 500", "send 0 WPD 500"]
    return acc + ["send 0 WVT %d" % v, "send 0 MS", "send 0 E"]


def m_vtrack(card, v):
    if card == "stp":
        # 5.11: the host limits the acceleration; from <ssf> in steps the motor follows
        ramp = []
        for k in range(1, 5):
            ramp += ["send 0 WVT %d" % (v * k // 4), "run 32"]
        return ["send 0 WVT %d" % (v // 4), "send 0 VT", "send 0 E", "run 32"] + ramp
    return ["send 0 WVT %d" % v, "send 0 VT", "send 0 E"]


def m_positioning(card, v):
    acc = 500 if card == "stp" else 20
    return ["send 0 WPV %d" % v, "send 0 WPA %d" % acc, "send 0 WPD %d" % acc, "send 0 WAP 900000",
            "send 0 MP", "send 0 E"]


def m_find_edge(card, v):
    acc = 500 if card == "stp" else 20
    return ["switch 0 ref 800000 100", "send 0 WFV %d" % v, "send 0 WFA %d" % acc, "send 0 WDL 0", "send 0 MF",
            "send 0 E"]


def m_home(card, v):
    acc = 500 if card == "stp" else 20
    return ["switch 0 ref 800000 100", "send 0 WHV %d" % v, "send 0 WHA %d" % acc, "send 0 MH", "send 0 E"]


def m_search_coarse(card, v):
    # the index at the end of a long revolution: not met during the run
    acc = 500 if card == "stp" else 20
    return ["send 0 WCV %d" % v, "send 0 WCA %d" % acc, "send 0 WCD %d" % acc, "send 0 MC", "send 0 E"]


MODES = {
    "speed": (m_speed, ("inc", "ssi", "stp")),
    "positioning": (m_positioning, ("inc", "ssi", "stp")),
    "vel-track": (m_vtrack, ("inc", "ssi", "stp")),
    "find-edge": (m_find_edge, ("inc", "ssi", "stp")),
    "home": (m_home, ("inc",)),                      # needs the index at P2 (<et> 1): INC, STP with encoder
    "search-coarse": (m_search_coarse, ("inc",)),
}
JUSTIFY = ("find-edge", "home", "search-coarse")

# ---- the causes --------------------------------------------------------------------
# kind: "rest" disables with the mechanics at rest (STP: ramp to <ssf>, off), "hold" stands in mode
# brake, "coast" disables (the mechanics coast); report: (where, code, user bits) or None
AHEAD = {"inc": 5000, "ssi": 5000, "stp": 2000}    # where a switch or limit lies ahead of the run-up
# search index coarse: the index of the default encoder at increment 3999, so the run-up is short,
# the switch or limit closer and the axis stands before the index
RUNUP = {"search-coarse": 100}


def ahead_of(card, mode):
    return 2500 if mode == "search-coarse" else AHEAD[card]


def stop_ramp(card, mode, cause):
    """The ramp of the stop per SP^2: <ed>, or for the stop bits <pd> (3.5.1)."""
    if cause.name != "stop-bit":
        return ED_STP if card == "stp" else ED
    if card == "stp":
        return 500 if mode in ("speed", "positioning", "find-edge") else 1000
    return 20 if mode == "positioning" else 100


class Cause:
    def __init__(self, name, kind, report, setup=(), inject=(), modes=None, mode_after="disable", bits=()):
        self.name, self.kind, self.report = name, kind, report
        self.setup, self.inject, self.modes = setup, inject, modes
        self.mode_after, self.bits = mode_after, bits


CAUSES = [
    Cause("mre", "rest", None, inject=("send 0 MRE", "send 0 E")),
    Cause("deinit", "rest", None, inject=("send 0 DEINIT",)),
    Cause("watchdog", "rest", ("card", 164, 0), inject=("send 0 WWD 30",)),
    Cause("stop-bit", "hold", None, inject=("poke16 0x4600 0x0002",), mode_after="brake"),
    Cause("hwl", "hold", ("axis", 163, ub("hwl_p", "logo_f")), setup=("switch 0 lp AHEAD",), mode_after="brake",
          bits=("hwl_p",)),
    Cause("swl", "rest", ("axis", 163, ub("swl_p", "logo_f")), setup=("send 0 UWLP AHEAD",), modes=JUSTIFY,
          bits=("swl_p",)),
    Cause("ferr", "rest", ("axis", 163, ub("ferr_f")), inject=("plant 0 motor coulomb 100",), bits=("ferr_f",)),
    Cause("drive", "coast", ("axis", 163, ub("dr_f")), inject=("fault 0 drive on",), bits=("dr_f",)),
    Cause("estop", "coast", ("card", 165, 0), inject=("estop on",)),
]


def trace_rows(path):
    with open(path) as f:
        return [{k: float(v) for k, v in row.items()} for row in csv.DictReader(f)]


def pos_of(row, card):
    return row["rotor"] if card == "stp" else row["position"]


def vel_of(row, card):
    return row["rotor_hz"] if card == "stp" else row["velocity"]


def run_stop(tmp_path, card, mode, cause, v=None, extra=(), runup_ms=None):
    """One run: the trace rows from the event on, the responses after it,
    the RFE at speed and the plant at the end."""
    v = V[card] if v is None else v
    fn, _ = MODES[mode]
    path = str(tmp_path / ("%s-%s-%s.csv" % (card, mode, cause.name)))
    ahead = ahead_of(card, mode)
    setup = [l.replace("AHEAD", str(ahead)) for l in cause.setup]
    sys_setup = [l for l in setup if l.startswith(("send 0 UW", "switch"))]
    mode_setup = [l for l in setup if l not in sys_setup]
    lines = [BOOT.strip()] + [l for l in sys_setup if l.startswith("switch")] + pre(card) + list(extra)
    if mode == "search-coarse":
        lines.append("plant 0 encoder index 3999")
    lines += [l for l in sys_setup if l.startswith("send")]
    if card == "stp":
        lines.append("send 0 WAA %d" % ED_STP)             # a ramp step per tick the motor follows
    lines += ["send 0 INIT", "send 0 ME", "send 0 E", "run 20"] + mode_setup
    # the run-up: the move at speed well before the switch or limit ahead
    run_up = runup_ms or RUNUP.get(mode, 300 if card != "stp" else 600)
    lines += fn(card, v) + ["run %d" % run_up, "send 0 RFE", "run 1", "plant 0"]
    lines += ["trace 0 %s tick" % path]
    lines += list(cause.inject) + ["run 1500" if card == "stp" else "run 600", "trace off", "plant 0"]
    lines += ["send 0 RBS", "send 0 RAS", "send 0 ME", "send 0 RBS", "run 5"]
    r = sim("\n".join(lines) + "\n", card)
    assert r.rc == 0, r.stderr
    return trace_rows(path), r


def ferr_at_speed(r):
    got = [p for _, c, p in r.resps() if c == code("RFE")]
    p = got[-1]
    return abs(p - (1 << 32) if p & 0x80000000 else p)


def cases():
    for cause in CAUSES:
        for mode, (_, cards) in MODES.items():
            if cause.modes and mode not in cause.modes:
                continue
            for card in cards:
                if cause.name == "ferr" and card == "stp":
                    continue                              # open loop: the fault matrix's stall rows
                yield pytest.param(card, mode, cause, id="%s-%s-%s" % (cause.name, mode, card))


@pytest.mark.parametrize("card,mode,cause", list(cases()))
def test_stop_sweep(tmp_path, card, mode, cause):
    rows, r = run_stop(tmp_path, card, mode, cause)
    assert rows, "no trace"
    # the event: the injection (the trace starts there), <wd> after the last command, the
    # mechanics at the switch or limit ahead
    k0 = 0
    if cause.name == "watchdog":
        k0 = next(k for k, t in enumerate(rows) if t["t_ms"] >= rows[0]["t_ms"] + 30)
    elif cause.name in ("hwl", "swl"):
        k0 = next(k for k, t in enumerate(rows) if pos_of(t, card) >= ahead_of(card, mode))
    t0 = rows[k0]
    p0 = pos_of(t0, card)
    v0 = float(r.grep(r"^plant 0 ")[0].split("vel=")[1].split()[0])     # just before the trace
    assert v0 > 0.8 * V[card] * (1000 / SP_MS[card] if card != "stp" else 1), (mode, v0)   # at speed
    end = rows[-1]
    rest = pos_of(end, card)
    dist = rest - p0
    if cause.kind != "coast" or card == "stp":
        assert abs(vel_of(end, card)) < 1 and abs(pos_of(rows[-20], card) - rest) < 1, "mechanics not at rest"
    enabled = [k for k, t in enumerate(rows) if t["en"] == 1]
    off_at = next((k for k in range(len(rows)) if rows[k]["en"] == 0), None)
    vmax = V[card]
    ramp = stop_ramp(card, mode, cause)
    if card == "stp":
        vel_sp = vmax * STP_STEPS_SP                       # steps per SP
        ed_sp = ramp * STP_STEPS_SP
        tick_sp = 0.25
    else:
        vel_sp, ed_sp, tick_sp = vmax, ramp, 0.25
    lag = ferr_at_speed(r) if card != "stp" else 0
    # reaction within two ticks, the <ed> ramp, the lag the loop makes up, one tick of margin
    bound = 3 * tick_sp * vel_sp + vel_sp * vel_sp / (2 * ed_sp) + lag + 5
    got = r.resps()
    by = {}
    for _, c, p in got[-4:]:
        by.setdefault(c, []).append(p)
    rbs1, ras, me, rbs2 = got[-4:]
    assert rbs1[1] == code("RBS") and ras[1] == code("RAS"), got[-4:]    # reads run (6.3)
    st = rbs1[2]
    assert st & 0xFF == MODE[cause.mode_after], (hex(st), cause.mode_after)
    for b in cause.bits:
        assert st & ub(b), (b, hex(st))
    if cause.report:
        where, ecode, bits = cause.report
        assert me[1] == ecode and me[2] & bits == bits, me                # the report, once
        assert st & ub("ferr_f") == (ub("ferr_f") if "ferr_f" in cause.bits else 0), hex(st)
    else:
        assert me[1] == code("ME"), me
        assert not st & (ub("ferr_f") | ub("logo_f")), hex(st)           # a clean stop
    if cause.name == "deinit":
        assert not st & ub("init")
    if card == "stp":
        # (coast: the power stage is off or /EN open, the field stops under the rotor)
        if cause.kind != "coast":
            assert end["lost"] == 0, "%d steps lost" % end["lost"]
            assert dist <= bound, (dist, bound)
    elif cause.kind == "rest":
        assert off_at is not None, "never disabled"
        at_off = abs(vel_of(rows[off_at], card))
        # /EN opened with the mechanics at rest: at most 1 Inc per tick
        assert at_off <= 1000 / TICK_MS[card] + 1, "speed %.0f units/s when /EN opened" % at_off
        assert dist <= bound, (dist, bound)
    elif cause.kind == "hold":
        assert off_at is None and enabled, "disabled"
        assert dist <= bound, (dist, bound)
    print("STOP %s %s %s distance %.0f bound %.0f lag %d en-off-tick %s" % (
        card, mode, cause.name, dist, bound, lag, off_at))
