"""Protective stops seen from the mechanics (4.8, 4.9, 5.x, 6.3; the design in
docs/interpretations.md, "Protective reactions").  The plant runs at speed
in a mode, a cause of a stop comes, and the per-tick trace of the plant
(`trace 0 FILE tick`: the mechanics' position and speed, not the setpoint)
shows where the mechanics come to rest, whether the drive was enabled until
they stood, and the status bits and the report that follow.

* `test_stop_sweep`: every cause x every mode in which it can happen x every
  card: speed, positioning, velocity and position tracking, find edge, home
  and the two searches (INC, STP with an encoder), on-fly and, where 5.15
  allows it, off-fly.  Stops that disable on MAC4-INC/SSI (MRE, DEINIT,
  watchdog, leaving a software limit, following error) open /EN only with
  the mechanics at rest (|speed| <= 1 Inc per tick), within the distance that
  the reaction delay (three ticks at speed), the <ed> ramp and the following
  lag allow; stops that hold (limit switch, stop bits) stand in mode brake
  within it; the drive fault, the emergency stop and the encoder error
  disable (the mechanics coast: the distance is reported, not bounded); on
  the STP (open loop) the steps ramp with <ed> to <ssf> and stop, and not one
  step is lost (but by a motor that stalls).  Each run prints a `STOP` line;
  its figures are the table "Stopping distances at speed" of
  docs/hardening.md.
* the runaway guards (INC, SSI): reversed motor wiring, a frozen encoder, a
  motor that cannot follow <ed>: /EN opens at once with ferr_f; the trace
  shows where the mechanics stop.
* reads while an error waits, C right after an error, m_rdy, the LEDs, ROUT.
"""
import csv
import os

import pytest

from conftest import BOOT, sim
from mac4 import BIT, MODE, TICK_MS, axis_addr, board, code, sb, stop_line, ub

SP_MS = {c: TICK_MS[c] * board.PROFILE_DIVIDER for c in TICK_MS}     # the profile generator's period
# the speed of the sweep: INC/SSI 100 Inc/SP (10 000 Inc/s, the issue's figure), STP 2000 Hz
V = {"inc": 100, "ssi": 100, "stp": 2000}
ED = 5000                                     # <ed> default: Inc/SP^2
ED_STP = 2000                                 # STP: Hz/SP, 500 Hz per tick, below the motor's 1000 Hz
STP_STEPS_SP = 0.032                          # steps per SP of 32 ms per Hz


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


def m_search_index(card, v):
    # at <lv> in the direction of <cv> (5.8), no ramp (STP: <lv> at most <ssf>, below the motor's
    # own start/stop frequency of 1000 Hz); the index far ahead as for search-coarse
    ssf = ["send 0 WSSF %d" % v] if card == "stp" else []
    return ssf + ["send 0 WCV 1", "send 0 WLV %d" % v, "send 0 MI", "send 0 E"]


def speed(card, mode):
    return 500 if card == "stp" and base(mode) == "search-index" else V[card]


# MAC4-STP with an incremental encoder at P2 (BR open, <et> 1, 4.4.2.3), which home and the
# searches need: 20:1 gear, 50 000 increments and 10 000 steps per output revolution (5 per
# step), the index at the end of the revolution: not met during a run
STP_INDEX = ["plant 0 gear 20", "plant 0 encoder lines 12500 index 49999", "br 0 encoder", "send 0 UWET 1",
             "send 0 UWES 12500", "send 0 UWMS 10000"]


def m_pos_track(card, v):
    # 5.12: the host streams the targets, one WAT per SP (PosTrack.run); E with the first
    return ["send 0 WAT 0", "send 0 PT", "send 0 E"]


def off_fly(fn):
    # off-fly (5.15): the axis' other commands wait for the end of the move, so a stop can come
    # only from the card itself, a switch, a stop bit or the emergency stop
    return lambda card, v: ["send 0 FLYOFF"] + fn(card, v)


def base(mode):
    """The mode itself, off-fly or on-fly."""
    return mode[len("off-fly-"):] if mode.startswith("off-fly-") else mode


class PosTrack:
    """The host of position tracking: a WAT every SP, the target's step
    growing in eight SPs to v per SP (STP: v Hz as steps per SP), so the
    motor follows from stand-still; the steps continue through the stop."""

    def __init__(self, card, v):
        self.sp = SP_MS[card]
        self.v = v * STP_STEPS_SP if card == "stp" else v
        self.k, self.t, self.left = 0, 0.0, 0.0

    def run(self, ms):
        out = []
        self.left += ms
        while self.left >= self.sp:
            self.k += 1
            self.t += self.v * min(self.k, 8) / 8
            out += ["send 0 WAT %d" % round(self.t), "run %g" % self.sp]
            self.left -= self.sp
        return out


MODES = {
    "speed": (m_speed, ("inc", "ssi", "stp")),
    "positioning": (m_positioning, ("inc", "ssi", "stp")),
    "vel-track": (m_vtrack, ("inc", "ssi", "stp")),
    "find-edge": (m_find_edge, ("inc", "ssi", "stp")),
    # the index at P2 (<et> 1): INC, STP with an encoder (STP_INDEX); the SSI has no such modes
    "home": (m_home, ("inc", "stp")),
    "search-coarse": (m_search_coarse, ("inc", "stp")),
    "search-index": (m_search_index, ("inc", "stp")),
    "pos-track": (m_pos_track, ("inc", "ssi", "stp")),
}
# 5.15: off-fly can be selected in these modes; all others, and these by default, run on-fly
for _m in ("positioning", "find-edge", "home", "search-coarse", "search-index"):
    MODES["off-fly-" + _m] = (off_fly(MODES[_m][0]), MODES[_m][1])
JUSTIFY = ("find-edge", "home", "search-coarse", "search-index")
# the causes that are commands: off-fly holds them until the move ends (5.15); the host that
# streams position-tracking targets keeps the watchdog from expiring
BY_COMMAND = ("mre", "deinit", "watchdog")

# ---- the causes --------------------------------------------------------------------
# kind: "rest" disables with the mechanics at rest (STP: ramp to <ssf>, off), "hold" stands in mode
# brake, "coast" disables (the mechanics coast); report: (where, code, user bits) or None
AHEAD = {"inc": 5000, "ssi": 5000, "stp": 2000}    # where a switch or limit lies ahead of the run-up
# search index coarse: the index of the default encoder at increment 3999, so the run-up is short,
# the switch or limit closer and the axis stands before the index
RUNUP = {"search-coarse": 100, "search-index": 100}
SEARCH = ("search-coarse", "search-index")


def ahead_of(card, mode):
    return 2500 if base(mode) in SEARCH and card != "stp" else AHEAD[card]


def stop_ramp(card, mode, cause):
    """The ramp of the stop per SP^2: <ed>, or for the stop bits <pd> (3.5.1)."""
    if cause.name != "stop-bit":
        return ED_STP if card == "stp" else ED
    if card == "stp":
        return 500 if base(mode) in ("speed", "positioning", "find-edge") else 1000
    return 20 if base(mode) == "positioning" else 100


class Cause:
    def __init__(self, name, kind, report, setup=(), inject=(), modes=None, mode_after="disable", bits=(),
                 per_card=None):
        self.name, self.kind, self.report = name, kind, report
        self.setup, self.inject, self.modes = setup, inject, modes
        self.mode_after, self.bits = mode_after, bits
        self.per_card = per_card or {}           # card -> (setup, inject) in place of the common ones

    def setup_on(self, card):
        return self.per_card[card][0] if card in self.per_card else self.setup

    def inject_on(self, card):
        return self.per_card[card][1] if card in self.per_card else self.inject


# 6.3.8 at speed: INC and STP read an absolute encoder board over the VMEbus (<et> 4) that then
# stops answering (a bus error on every read); the SSI encoder's data line sticks at 1, which in
# Gray code decodes beyond <ec> = 2^23
# 4.8.1 on the STP: the encoder on the motor (8 increments per step) shows the following error of a
# motor whose torque is gone above 3/4 of the speed of the run (1500 Hz at 2000 Hz)
STP_FERR = ["br 0 encoder", "send 0 UWET 1", "send 0 UWES 1000", "send 0 WMF 50"]
VME_ENC = ["send 0 UWET 4", "send 0 UWEA 0x80C000", "send 0 UWEB 24"]
ENCODER_LOSS = {
    "inc": (["vme-encoder 0x80C000 0 bits 24 res 4000 turns 0"] + VME_ENC, ["vme-encoder 0x80C000 off"]),
    "stp": (["vme-encoder 0x80C000 0 bits 24 res 500 turns 0 shaft motor"] + VME_ENC, ["vme-encoder 0x80C000 off"]),
    "ssi": (["send 0 UWEC 8388608"], ["fault 0 encoder stuck1"]),
}


CAUSES = [
    Cause("mre", "rest", None, inject=("send 0 MRE", "send 0 E")),
    Cause("deinit", "rest", None, inject=("send 0 DEINIT",)),
    Cause("watchdog", "rest", ("card", 164, 0), inject=("send 0 WWD 30",)),
    Cause("stop-bit", "hold", None, inject=(stop_line(0),), mode_after="brake"),
    Cause("hwl", "hold", ("axis", 163, ub("hwl_p", "logo_f")), setup=("switch 0 lp AHEAD",), mode_after="brake",
          bits=("hwl_p",)),
    Cause("swl", "rest", ("axis", 163, ub("swl_p", "logo_f")), setup=("send 0 UWLP AHEAD",), modes=JUSTIFY,
          bits=("swl_p",)),
    Cause("ferr", "rest", ("axis", 163, ub("ferr_f")), inject=("plant 0 motor coulomb 100",), bits=("ferr_f",),
          per_card={"stp": (STP_FERR, ["stepper 0 fmax FMAX"])}),
    Cause("drive", "coast", ("axis", 163, ub("dr_f")), inject=("fault 0 drive on",), bits=("dr_f",)),
    Cause("estop", "coast", ("card", 165, 0), inject=("estop on",)),
    Cause("encoder", "coast", ("axis", 163, ub("encoder_f", "logo_f")), per_card=ENCODER_LOSS,
          modes=("speed", "positioning", "vel-track", "find-edge", "pos-track"), bits=("encoder_f",)),
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
    v = speed(card, mode) if v is None else v
    fn, _ = MODES[mode]
    path = str(tmp_path / ("%s-%s-%s.csv" % (card, mode, cause.name)))
    ahead = ahead_of(card, mode)
    setup = [l.replace("AHEAD", str(ahead)) for l in cause.setup_on(card)]
    index = card == "stp" and base(mode) in ("home",) + SEARCH
    if index:                                  # STP_INDEX's encoder in place of a cause's own
        setup = [l for l in setup if not l.startswith(("br ", "send 0 UWET", "send 0 UWES"))]
    sys_setup = [l for l in setup if l.startswith(("send 0 UW", "switch", "vme-encoder", "plant", "br ", "stepper"))]
    mode_setup = [l for l in setup if l not in sys_setup]
    lines = [BOOT.strip()] + [l for l in sys_setup if not l.startswith("send")] + pre(card) + list(extra)
    if index:
        lines += STP_INDEX
    elif base(mode) in SEARCH:
        lines.append("plant 0 encoder index 3999")
    lines += [l for l in sys_setup if l.startswith("send")]
    if card == "stp":
        lines.append("send 0 WAA %d" % ED_STP)             # a ramp step per tick the motor follows
    lines += ["send 0 INIT", "send 0 ME", "send 0 E", "run 20"] + mode_setup
    # the run-up: the move at speed well before the switch or limit ahead
    # (STP_INDEX: the index far; search index at 500 Hz needs longer to reach the switch ahead)
    run_up = runup_ms or ((3000 if base(mode) == "search-index" else 600) if card == "stp" else
                          RUNUP.get(base(mode), 300))
    host = PosTrack(card, v) if mode == "pos-track" else None

    def run(ms):
        return host.run(ms) if host else ["run %d" % ms]
    lines += fn(card, v) + run(run_up) + ["send 0 RFE", "run 1", "plant 0"]
    lines += ["trace 0 %s tick" % path, "echo @inject"]
    # (FMAX: the stepper's torque gone at 3/4 of the speed of the run)
    lines += [l.replace("FMAX", str(speed(card, mode) * 3 // 4)) for l in cause.inject_on(card)] + run(1500 if card == "stp" else 600) + ["trace off", "plant 0"]
    lines += ["send 0 RBS", "send 0 RAS", "send 0 ME", "send 0 RBS", "run 5"]
    r = sim("\n".join(lines) + "\n", card)
    assert r.rc == 0, r.stderr
    return trace_rows(path), r


def errors_after_inject(r):
    """(code, parameter) of the error answers 160-165 after the injection, in order."""
    k = r.lines.index("@inject")
    out = []
    for l in r.lines[k:]:
        if l.startswith("resp "):
            _, _, c, p = l.split()
            if 160 <= int(c) <= 165:
                out.append((int(c), int(p, 16)))
    return out


def ferr_at_speed(r):
    got = [p for _, c, p in r.resps() if c == code("RFE")]
    p = got[-1]
    return abs(p - (1 << 32) if p & 0x80000000 else p)


def cases():
    for cause in CAUSES:
        for mode, (_, cards) in MODES.items():
            if cause.modes and base(mode) not in cause.modes:
                continue
            if cause.name in BY_COMMAND and (mode.startswith("off-fly") or mode == "pos-track"):
                continue
            for card in cards:
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
    assert v0 > 0.8 * speed(card, mode) * (1000 / SP_MS[card] if card != "stp" else 1), (mode, v0)   # at speed
    end = rows[-1]
    rest = pos_of(end, card)
    dist = rest - p0
    if cause.kind != "coast" or card == "stp":
        assert abs(vel_of(end, card)) < 1 and abs(pos_of(rows[-20], card) - rest) < 1, "mechanics not at rest"
    enabled = [k for k, t in enumerate(rows) if t["en"] == 1]
    off_at = next((k for k in range(len(rows)) if rows[k]["en"] == 0), None)
    vmax = speed(card, mode)
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
    errs = errors_after_inject(r)
    if cause.report:
        where, ecode, bits = cause.report
        # the report, once: the first other command after the event gets it (position tracking:
        # a streamed WAT), every later one 163 until C (6.3.7)
        assert errs and errs[0][0] == ecode and errs[0][1] & bits == bits, errs
        assert all(c == 163 for c, _ in errs[1:]), errs
        if mode != "pos-track":
            assert len(errs) == 1 and me[1] == ecode, (errs, me)
        assert st & ub("ferr_f") == (ub("ferr_f") if "ferr_f" in cause.bits else 0), hex(st)
    else:
        assert errs == [] and me[1] == code("ME"), (errs, me)
        assert not st & (ub("ferr_f") | ub("logo_f")), hex(st)           # a clean stop
    if cause.name == "deinit":
        assert not st & ub("init")
    if card == "stp":
        # (coast: the power stage is off or /EN open, the field stops under the rotor)
        if cause.kind != "coast":
            if cause.name != "ferr":                      # (the motor that stalls loses them)
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


# ---- the runaway guards (6.3.9: a reversed or frozen encoder; a motor that cannot follow <ed>) ----
K = 2                                                 # P controller: DAC = K x following error
P_ONLY = ["send 0 WGA %d" % (4 * K), "send 0 WZE 0", "send 0 WPO 0", "send 0 WKI 0"]
MF = 500
STOP_GROW_TICKS, STOP_SETTLE_TICKS = 4, 40            # firmware/card.h


def guard_run(tmp_path, name, before, inject, ms=4000, card="inc"):
    path = str(tmp_path / (name + ".csv"))
    # (the SSI's absolute encoder away from its 0, which a reversed run would cross)
    lines = [BOOT.strip()] + (["plant 0 pos 100000"] if card == "ssi" else []) + pre(card) + before + [
        "trace 0 %s tick" % path] + inject + [
        "run %d" % ms, "trace off", "plant 0", "send 0 RBS", "send 0 ME", "run 5"]
    r = sim("\n".join(lines) + "\n", card)
    assert r.rc == 0, r.stderr
    rows = trace_rows(path)
    off = next(k for k, t in enumerate(rows) if t["en"] == 0)
    rbs, me = r.resps()[-2:]
    assert rbs[2] & 0xFF == MODE["disable"] and rbs[2] & ub("ferr_f"), hex(rbs[2])
    assert me[1] == 163 and me[2] & ub("ferr_f"), me
    return rows, off


def over_mf(rows):
    """The first trace row whose DAC shows |RFE| > <mf>: it was computed by the tick before."""
    return next(k for k, t in enumerate(rows) if abs(t["dac"]) > K * MF)


@pytest.mark.parametrize("card", ("inc", "ssi"))
def test_runaway_guard_reversed_wiring(tmp_path, card):
    """The motor's leads swapped (USR missing): the loop drives away from the
    setpoint.  Following error, and the braking loop runs away too: /EN opens
    STOP_GROW_TICKS ticks after the stop began, not when the following error
    has grown by <mf>/2 more, nor after the time bound."""
    rows, off = guard_run(tmp_path, "reversed", ["plant 0 wiring reversed"] + P_ONLY + [
        "send 0 WMF %d" % MF, "send 0 INIT", "send 0 ME", "send 0 E", "run 20"],
        ["send 0 WVT 100", "send 0 MS", "send 0 E"], card=card)
    k = over_mf(rows)
    assert rows[k]["velocity"] < 0                    # the wrong way
    assert off - k <= 2 + STOP_GROW_TICKS, (k, off)   # the stop's first tick, then the guard
    assert abs(rows[-1]["velocity"]) < 1                # coasted to rest
    print("GUARD %s reversed: /EN open %d ticks after RFE > <mf>, at %.0f Inc; mechanics at rest at %.0f Inc" % (
        card, off - k, rows[off]["position"], rows[-1]["position"]))


@pytest.mark.parametrize("card", ("inc", "ssi"))
def test_runaway_guard_frozen_encoder(tmp_path, card):
    """The counter stops mid-move: the axis measures no motion with more
    than <mf> to go: /EN opens in the tick after the stop began."""
    rows, off = guard_run(tmp_path, "frozen", P_ONLY + [
        "send 0 WMF %d" % MF, "send 0 INIT", "send 0 ME", "send 0 E", "run 20", "send 0 WVT 40", "send 0 MS",
        "send 0 E", "run 300"], ["fault 0 encoder frozen"], card=card)
    assert rows[0]["en"] == 1 and rows[0]["velocity"] > 3500
    k = over_mf(rows)
    assert off - k <= 3, (k, off)
    assert abs(rows[-1]["velocity"]) < 1
    print("GUARD %s frozen: /EN open %d ticks after RFE > <mf>, at %.0f Inc (frozen at %.0f); at rest at %.0f Inc" % (
        card, off - k, rows[off]["position"], rows[0]["position"], rows[-1]["position"]))


@pytest.mark.parametrize("card", ("inc", "ssi"))
def test_runaway_guard_motor_cannot_follow_ed(tmp_path, card):
    """A current-controlled drive whose current limit decelerates the load
    at 16 000 Inc/s^2, where <ed> asks for 5e7: the setpoint stands after a
    tick, the motor overshoots it; /EN opens once the following error has
    grown beyond its value at the stop for STOP_GROW_TICKS ticks without the
    mechanics slowing down measurably, within the time bound in any case."""
    rows, off = guard_run(tmp_path, "slow", ["plant 0 motor mode current imax 2 inertia 5e-4",
                                             "send 0 WMF %d" % MF, "send 0 INIT", "send 0 ME", "send 0 E", "run 20",
                                             "send 0 WVT 40", "send 0 WPA 1", "send 0 MS", "send 0 E", "run 3000"],
                          ["send 0 MRE", "send 0 E"], ms=8000, card=card)
    assert rows[0]["velocity"] > 3500 and rows[0]["en"] == 1
    ramp_ticks = 1                                    # 40 Inc/SP with <ed> 5000: one tick
    assert off <= 2 * ramp_ticks + STOP_SETTLE_TICKS + 3, off
    assert rows[off]["velocity"] > 1000                # it had not stopped: the guard, not the rest test
    # (after /EN the load coasts on its own friction: far, it has no brake)
    print("GUARD %s slow motor: /EN open %d ticks after MRE at %.0f Inc/s, %.0f Inc after it; +%.0f Inc after 8 s" % (
        card, off, rows[off]["velocity"], rows[off]["position"] - rows[0]["position"],
        rows[-1]["position"] - rows[0]["position"]))


# ---- errors and reads (6.3), m_rdy (7.1.2), targets (6.3.3), LEDs (2.5.3), ROUT (table 6.2) ----
def cmds(lines, card="inc"):
    r = sim(BOOT + "\n".join(lines) + "\n", card)
    assert r.rc == 0, r.stderr
    return r


FAULTS = {   # a cause raised by the card itself, on a moving axis 0: (lines, code, bits, card-wide)
    "drive": (["fault 0 drive on", "run 200"], 163, ("dr_f",), False),
    "ferr": (["plant 0 motor coulomb 100", "run 800"], 163, ("ferr_f",), False),
    "watchdog": (["send 0 WWD 30", "run 300"], 164, (), True),
    "estop": (["estop on", "run 50"], 165, (), True),
}


@pytest.mark.parametrize("card", ("inc", "ssi", "stp"))
@pytest.mark.parametrize("fault", sorted(FAULTS))
def test_reads_run_and_c_right_after_the_error_acknowledges_it(card, fault):
    """6.3: reads are always executed while the error waits, the status read
    shows the error bits; the first other command - here C - is answered with
    the error code and, being C, acknowledges it: one C is enough, the next
    command runs."""
    lines, ecode, bits, cardwide = FAULTS[fault]
    setup = []
    if card == "stp" and fault == "ferr":
        setup = STP_FERR                          # the encoder shows the stall (at 1000 Hz here)
        lines = ["stepper 0 fmax 500", "run 800"]
    r = cmds(pre(card) + setup + ["send 0 INIT", "send 0 ME", "send 0 E", "run 20"] + m_speed(card, V[card] // 2) +
             ["run 300"] + lines + (["estop off"] if fault == "estop" else []) +
             ["send 0 RBS", "send 0 RCP", "send 0 RAS", "send 1 RBS", "send 0 C", "send 0 RBS", "send 0 RAS",
              "send 0 ME", "run 5"], card)
    got = r.resps()[-8:]
    assert [c for _, c, _ in got] == [code("RBS"), code("RCP"), code("RAS"), code("RBS"), ecode, code("RBS"),
                                      code("RAS"), code("ME")], got
    for b in bits:
        assert got[0][2] & ub(b) and not got[5][2] & ub(b)      # shown by the read, cleared by the one C
    if cardwide:
        ob = {164: "watch_f", 165: "h_stop"}[ecode]
        assert got[2][2] & (1 << BIT["overall"][ob]) and not got[6][2] & (1 << BIT["overall"][ob])
        assert got[4][2] & (1 << BIT["overall"][ob])           # the report carries the overall status
    assert got[0][2] & 0xFF == MODE["disable"]


@pytest.mark.parametrize("card", ("inc", "ssi", "stp"))
def test_m_rdy_from_the_boot_until_mr(card):
    # after MR the card takes no command: its published system status (DPA_SSTAT) shows it
    sstat = "peek32 0x%X" % axis_addr(3, "SSTAT")
    r = cmds(["send 0 RSS", "send 3 RSS", "run 40", sstat, "jumper j11 in", "send 1 MR", "run 50", sstat], card)
    ss = [p for _, c, p in r.resps() if c == code("RSS")]
    assert len(ss) == 2 and all(p & sb("m_rdy") for p in ss), ss   # command operational
    pub = [int(l.split()[2], 16) for l in r.grep("^%s " % sstat)]
    assert pub[0] & sb("m_rdy") and not pub[1] & sb("m_rdy"), pub   # MR accepted: no more commands


@pytest.mark.parametrize("card", ("inc", "ssi", "stp"))
def test_tracking_targets_beyond_the_software_limits_are_refused(card):
    """6.3.3: WAT beyond <lp>/<ln> is answered 162 and ignored; the axis
    stays within its limits."""
    lim = 200 if card == "stp" else 2000
    r = cmds(pre(card) + ["send 0 UWLP %d" % lim, "send 0 UWLN %d" % -lim, "send 0 INIT", "send 0 ME", "send 0 E",
                          "run 20", "send 0 WAT 100", "send 0 PT", "send 0 E", "run 300", "send 0 WAT %d" % (lim + 1),
                          "send 0 C", "send 0 WAT %d" % (-lim - 1), "send 0 C", "send 0 RAT", "send 0 WAT %d" % lim,
                          "run 1500", "send 0 RCP", "send 0 RBS", "run 5"], card)
    got = [(c, p) for _, c, p in r.resps()]
    assert [c for c, _ in got[-8:]] == [162, 4, 162, 4, code("RAT"), code("WAT"), code("RCP"), code("RBS")], got
    assert got[-4][1] == 100                                     # the refused targets were ignored
    pos = got[-2][1] - (1 << 32) if got[-2][1] & 0x80000000 else got[-2][1]
    assert lim - 20 <= pos <= lim and got[-1][1] & 0xFF == MODE["position tracking"]
    assert not got[-1][1] & (ub("swl_p") | ub("logo_f"))


def leds_of(line):
    """`leds 0xWORD stop=S 0=D,LP 1=- ...` -> {axis: set of names}."""
    out = {}
    for f in line.split()[3:]:
        a, names = f.split("=")
        out[int(a)] = set() if names == "-" else set(names.split(","))
    return out


@pytest.mark.parametrize("card", ("inc", "ssi", "stp"))
def test_leds_by_name(card):
    """2.5.3: the limit and reference LEDs light at 0 V whatever the
    configuration; the drive-fault LED F whenever the card recognises the
    signal as on, with either polarity (UWSO); D disabled, P pos_end."""
    r = cmds(["switch 0 lp 100", "switch 1 ln -100 high", "switch 2 ref -50 100", "switch 3 df high",
              "plant 0 pos 200", "send 0 UWPS 0", "run 20", "leds", "fault 0 drive on", "send 3 UWSO 2",
              "send 3 INIT", "run 40", "leds", "fault 3 drive on", "run 40", "leds"] + pre(card), card)
    lines = r.grep(r"^leds ")
    first, second, third = [leds_of(l) for l in lines]
    assert first[0] == {"D", "LP"}                               # at 0 V, though configured off (UWPS 0)
    assert first[1] == {"D", "LN"}                               # high active, off: the line is at 0 V
    # axis 3's amplifier signals a fault high: no fault puts 0 V on the line, which the card, still
    # configured low active (<df> 1), recognises as a fault: F; configured high active (UWSO 2,
    # INIT): off; the fault on, the line high: F again, whatever the level
    assert first[2] == {"D", "REF"} and first[3] == {"D", "F"}
    assert "F" not in second[3]
    assert "F" in third[0]                                       # low active (default): on at 0 V
    assert "F" in third[3]
    for line, named in zip(lines, (first, second, third)):
        word = int(line.split()[1], 16)                          # the register word agrees with the names
        for a in range(4):
            for bit, name in ((1, "D"), (2, "P"), (4, "F")):
                assert bool(word >> (4 * a) & bit) == (name in named[a]), (line, a, name)


def test_rout_and_rps_in_steps_per_sp_on_the_stp():
    """Table 6.2: ROUT and RPS in Steps/SP (32 ms): 2000 Hz are 64."""
    r = cmds(["send 0 INIT", "send 0 ME", "send 0 E", "run 20"] + m_speed("stp", 2000) +
             ["run 1500", "send 0 ROUT", "send 0 RPS", "send 0 RAV", "run 5"], "stp")
    got = {c: p for _, c, p in r.resps()[-3:]}
    assert got[code("ROUT")] == 64 and got[code("RPS")] == 64
    assert 15 <= got[code("RAV")] <= 17                          # Steps per 8 ms sampling period
