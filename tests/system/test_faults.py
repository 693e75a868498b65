"""The fault matrix.  Every fault the emulator can inject, each with
the reaction the manual gives (sections 2.1.3, 2.5.1, 3.5.1, 4.6, 4.7, 4.8,
6.3; where the manual is silent, docs/interpretations.md), as one table
(MATRIX) and one test that applies the same checks to every row:

* the end state of every axis involved: mode, dr_en, status and error bits,
  the outputs (enable and DAC / step rate), the LEDs and the display;
* reads executed while the error waits, the status read showing its bits
  (6.3: "read commands are an exception, these are always executed"); the
  error code answered exactly once, on the next other command (on the axis,
  or on any axis for the card's own errors 164/165), every other command
  refused with 163 until C, and the error bits cleared by C;
* every command sent is answered exactly once, in order and none twice (or,
  where the manual says the response is lost, counted in the DPRAM and not
  answered at all), and the commands are executed;
* no emulator fault line (unmapped access, address error, ...);
* the card answers VER at the end;
* where timing is stated, the reaction in the outputs sampled every servo
  tick (`perf ticks`): the emergency stop opens every axis in the same tick,
  without a ramp; a protective reaction shows within one servo period of
  the event (docs/hardening.md, "Fault matrix", for how that is measured).

Rows whose fault shows a firmware bug are strict xfails that fail only with
the finding they name (a Finding subclass): any other broken check still
fails the row.  Results and the measured latencies: docs/hardening.md."""
import re
from dataclasses import dataclass, field, replace

import pytest

from conftest import BOOT, sim
from mac4 import (CMDQ, EXT_POS, MODE, RSPQ, TICK_MS, board, code, ext_value, obits, pos_addr, q_repair, qh,
                  signed, ubits)

EN = board.AX_CTRL_EN                         # /EN driven
ERROR_BITS = ("syn_f", "limit_f", "logo_f", "encoder_f", "dr_f", "ferr_f")
CARD_BITS = ("h_stop", "axis_f", "watch_f")
DPC_RSP_LOST, DPC_QUEUE_ERRORS, DPC_COMMANDS = board.DPC_RSP_LOST, board.DPC_QUEUE_ERRORS, board.DPC_COMMANDS
STOP_BITS = board.DP_STOP_BITS
RBS, VER = code("RBS"), code("VER")
CMDQ_REAR, RSPQ_FRONT = qh(CMDQ, "REAR"), qh(RSPQ, "FRONT")


def ub(*names):
    """The user status bits alone, as a mask: mode "disable" adds nothing."""
    return ubits(*names, mode="disable")


ob = obits


# ---- findings: the kinds of failure an xfail row may name ---------------------
class Finding(AssertionError):
    """A check of the matrix the firmware fails."""


class ReactionLate(Finding):
    """The reaction shows in the outputs later than the bound of the row."""


class ReportedAgain(Finding):
    """The error is answered again on a later command (C included)."""


class NotCleared(Finding):
    """C does not clear the error bits."""


class NotAcknowledged(Finding):
    """A command after the error report is executed without C (6.3)."""


class ReadThrough(Finding):
    """The card took a command out of a queue whose header was corrupt."""


class AnsweredTwice(Finding):
    """A response to a command that was never sent, or a second one."""


# ---- the script of one run ------------------------------------------------------
@dataclass
class Send:
    axis: int
    mn: str
    expect: object                    # the response code, or a set of codes allowed
    lose: str = ""                    # "": answered once; "may": at most once; "must": never
    tag: str = ""


class Script:
    def __init__(self, card):
        self.card = card
        self.lines = [BOOT.strip()]
        self.sends = []

    def __call__(self, *lines):
        self.lines += lines
        return self

    def send(self, axis, mn, param=None, expect=None, lose="", tag=""):
        self.lines.append("send %d %s%s" % (axis, mn, "" if param is None else " %s" % param))
        self.sends.append(Send(axis, mn, code(mn) if expect is None else expect, lose, tag))
        return self

    def mark(self, name):
        return self("echo @" + name, "status")

    def text(self):
        return "\n".join(self.lines) + "\n"


# ---- what the card printed -------------------------------------------------------
TS = re.compile(r"^@([\d.]+)ms (.*)$")


class Out:
    def __init__(self, run, card):
        self.card = card
        self.ev = []                                  # (time or None, text), in order
        for line in run.lines:
            m = TS.match(line)
            self.ev.append((float(m.group(1)), m.group(2)) if m else (None, line))
        self.marks = {}
        for i, (_, text) in enumerate(self.ev):
            if text.startswith("@"):
                self.marks[text[1:]] = i
        self.ticks = []                               # one dict per `perf ticks` line
        for i, (_, text) in enumerate(self.ev):
            if text.startswith("tick "):
                self.ticks.append(self._tick(i, text))

    def _tick(self, i, text):
        parts = text.split(" | ")
        t = {"no": int(parts[0].split()[1]), "ev": i, "ax": []}
        for p in parts[1:]:
            f = p.split()
            a = {"out": int(f[0]), "ctrl": int(f[1], 16)}
            rest = f[2:]
            if rest[0].startswith("g"):
                a["gen"] = int(rest[0][1:])
                rest = rest[1:]
            cnt = int(rest[0][1:], 16)
            a["cnt"] = cnt - (1 << 24) if cnt & 0x800000 else cnt
            w = [int(x, 16) for x in rest[1:]]
            a["words"] = [x - (1 << 32) if x & 0x80000000 else x for x in w]
            t["ax"].append(a)
        return t

    def between(self, a, b=None):
        lo = self.marks[a]
        hi = self.marks[b] if b else len(self.ev)
        return self.ev[lo:hi]

    def lines(self, pattern, a=None, b=None):
        rx = re.compile(pattern)
        evs = self.between(a, b) if a else self.ev
        return [(t, x) for t, x in evs if rx.search(x)]

    def time_of(self, mark):
        """The emulated time printed by `status` right after a mark."""
        for t, text in self.ev[self.marks[mark]:]:
            if text.startswith("status time="):
                return t
        raise KeyError(mark)

    def resps(self):
        out = []
        for t, text in self.ev:
            if text.startswith("resp "):
                _, axis, c, p = text.split()
                p = int(p, 16)
                out.append((t, int(axis), int(c), p))
        return out

    def peeks(self, addr, a=None, b=None):
        vals = []
        for _, text in (self.between(a, b) if a else self.ev):
            p = text.split()
            if len(p) == 3 and p[0].startswith("peek") and int(p[1], 16) == addr:
                vals.append(int(p[2], 16))
        return vals

    def outputs(self, mark):
        """`outputs` after a mark: per axis (en, dac, rate)."""
        got = {}
        for _, text in self.between(mark):
            m = re.match(r"output (\d) en=(\d) dac=(-?\d+) rate=(\d+)", text)
            if m:
                got.setdefault(int(m.group(1)), tuple(int(m.group(k)) for k in (2, 3, 4)))
                if len(got) == 4:
                    break
        return got

    def leds(self, mark):
        for _, text in self.between(mark):
            m = re.match(r"leds 0x([0-9A-F]+) stop=(\d)", text)
            if m:
                return int(m.group(1), 16), int(m.group(2))
        raise KeyError("leds after @" + mark)

    def display_at(self, mark):
        shown = None
        for _, text in self.ev[:self.marks[mark]]:
            if text.startswith("display "):
                shown = text.split()[1]
        return shown


# ---- the card-specific parts of a scenario ------------------------------------------
# A move: INC/SSI 40 increments (SSI counts) per SP of 10 ms, 10 per 2.5 ms
# tick; STP 2000 Hz, 16 steps per 8 ms tick.  The SSI card reads the plant's
# default SSI encoder (24 bits, Gray, absolute, right-justified by <sc> = 2).
V = {"inc": 40, "ssi": 40, "stp": 2000}
V_TICK = {"inc": 10, "ssi": 10, "stp": 16}
SETTLE = {"inc": 300, "ssi": 300, "stp": 500}        # ms from E to a steady move
K = 2                                                # DAC LSB per increment of the P controller
CARD_NO = {"inc": 0, "ssi": 1, "stp": 2}


def init(s, axes, sysparams=()):
    """INIT, ME, E on each axis; `sysparams` for axis 0 only.  The SSI card
    gets one servo tick after the boot first: before it, the Gray jumper is
    not in the status and an INIT decodes the absolute position as binary
    (docs/hardening.md, fault matrix, finding K5)."""
    if s.card == "ssi":
        s("run 5")
    for n in axes:
        if s.card == "ssi":
            s.send(n, "UWSC", 2)
        for mn, p in sysparams if n == 0 else ():
            s.send(n, mn, p)
        s.send(n, "INIT").send(n, "ME").send(n, "E")
    s("run 20")


def move(s, n, v=None):
    """Mode speed at v (default V), from enable or brake."""
    v = V[s.card] if v is None else v
    if s.card == "stp":
        s.send(n, "WPA", 500).send(n, "WPD", 500)
    s.send(n, "WVT", v).send(n, "MS").send(n, "E")


def p_only(s, n, mf):
    """DAC = K x following error: no zero, pole or integral (5.16), so the
    DAC sampled every tick shows the following error."""
    s.send(n, "WGA", 4 * K).send(n, "WZE", 0).send(n, "WPO", 0).send(n, "WKI", 0).send(n, "WMF", mf)


STP_ENCODER_SYS = (("UWET", 1), ("UWES", 1000))     # with `br 0 encoder`: 8 increments per step


def watch(s, before):
    """The per-tick output log (`perf ticks`) from `before` ticks ahead of
    the injection point @inject, which lies on a tick expiry."""
    s("perf ticks -", "run-ticks %d" % before)
    s.mark("inject")
    s("plant")                                       # where the mechanics are (stop_distance)


# ---- the scenarios: build(s, card, variant) -> the event locator --------------------
def b_estop(s, card, ph):
    init(s, range(4))
    for n in range(4):
        move(s, n)
    s("run %d" % SETTLE[card])
    watch(s, 8 + ph)
    s("estop on", "run-ticks 12", "perf ticks off")
    return {"event": ("inject",)}


def b_hwl_move(s, card, ph):
    # the switch lies ahead; crossed in a different tick of the SP per variant
    at = {"inc": 6000, "ssi": 6000, "stp": 1500}[card] + ph * V_TICK[card]
    s("switch 0 lp %d" % at)
    init(s, (0, 1))
    move(s, 0)
    s("run %d" % (at / (V_TICK[card] / TICK_MS[card]) - 30 * TICK_MS[card]))
    watch(s, 8)
    s("run-ticks 80", "perf ticks off", "run 100")
    return {"event": ("cross", 0, at)}


def b_hwl_overrun(s, card, ph):
    # the axis stands behind the switch it overran (the switch stays on over
    # the whole forbidden range, 2.2.3): a move further into it must stop at
    # once; the SSI axis stands at 100000, its absolute encoder has no negative
    base = 100000 if card == "ssi" else 0
    s("plant 0 pos %d" % base, "switch 0 lp %d" % (base - 50))
    init(s, (0, 1))
    s("run 100")
    watch(s, 8 + ph)
    move(s, 0)
    s("run-ticks 40", "perf ticks off", "run 100")
    return {"event": ("starts", 0)}


def post_out_of_switch(s, card):
    s.mark("out")
    s("peek32 0x%X" % pos_addr(0))
    move(s, 0, -V[card])
    s("run 400", "peek32 0x%X" % pos_addr(0))


def out_of_switch(out, card, variant, info):
    """After C the axis drives out of the switch (negative), answered
    without an error (the accounting checks every code)."""
    p = [signed(x) for x in out.peeks(pos_addr(0), "out")]
    assert len(p) == 2 and p[1] < p[0] - 100, p


def b_drive_fault(s, card, ph):
    init(s, (0, 1))
    s.send(0, "WIRQ3", 0x33)
    move(s, 0)
    s("run %d" % SETTLE[card])
    watch(s, 8 + ph)
    s("fault 0 drive on", "run-ticks 40", "perf ticks off", "run 100")
    return {"event": ("inject",)}


def irq3_once_in_a_tick(out, card, variant, info):
    irqs = out.lines(r"^vme-irq 3 51$")
    assert len(irqs) == 1, irqs                          # interrupt 3, vector $33, once (4.6)
    t0 = out.time_of("inject")
    assert 0 <= irqs[0][0] - t0 <= TICK_MS[card] + 0.5, (irqs, t0)
    info.setdefault("irq3_ms", []).append(round(irqs[0][0] - t0, 3))


def b_ferr(inject):
    """A move whose following error grows after `inject`.  INC/SSI: the P
    controller, DAC = K ferr, <mf> shifted by a tick's travel per variant so
    that the event falls in every tick of the SP; STP: encoder feedback."""
    def build(s, card, ph):
        if card == "stp":
            s("br 0 encoder")
            init(s, (0, 1), STP_ENCODER_SYS)
            mf = 200 + V_TICK[card] * ph
            s.send(0, "WMF", mf)
            move(s, 0)
            s("run %d" % SETTLE[card])
            watch(s, 8)
            s(*inject, "run-ticks 60", "perf ticks off", "run 200")
            return {"event": ("pub_ferr", 0, mf)}
        init(s, (0, 1))
        mf = 600 + V_TICK[card] * ph
        p_only(s, 0, mf)
        move(s, 0)
        s("run %d" % SETTLE[card])
        watch(s, 8)
        s(*inject, "run-ticks 60", "perf ticks off", "run 100")
        return {"event": ("over", 0, K * mf)}
    return build


def b_stall(s, card, ph):
    if card != "stp":
        return b_ferr(["plant 0 motor coulomb 100"])(s, card, ph)   # jammed mid-move
    # a stepper that cannot follow the firmware's start/stop frequency of
    # 100 Hz never starts; its encoder shows it standing
    s("br 0 encoder", "stepper 0 ssf 50")
    init(s, (0, 1), STP_ENCODER_SYS)
    mf = 200 + V_TICK[card] * ph
    s.send(0, "WMF", mf)
    watch(s, 8)
    move(s, 0)
    s("run-ticks 60", "perf ticks off", "run 200")
    return {"event": ("pub_ferr", 0, mf)}


def b_jump(inject, inject_stp=None):
    """The position jumps by more than <mf> at once: the injection is the event."""
    def build(s, card, ph):
        if card == "stp":
            s("br 0 encoder")
            init(s, (0, 1), STP_ENCODER_SYS)
            s.send(0, "WMF", 200)
        else:
            init(s, (0, 1))
            p_only(s, 0, 600)
        move(s, 0)
        s("run %d" % SETTLE[card])
        watch(s, 8 + ph)
        s(inject_stp if card == "stp" and inject_stp else inject, "run-ticks 40", "perf ticks off", "run 100")
        return {"event": ("inject", "encoder")}
    return build


def b_ec(s, card, ph):
    # the position comes from the host through the DPRAM (3.5.2), absolute
    # (<et> 4), <ec> = 100000 (4.4.2.1); the host's encoder reports 150000
    s.send(0, "UWET", 4).send(0, "UWEA", EXT_POS).send(0, "UWEB", 24).send(0, "UWEC", 100000)
    s(*ext_value(5000))
    init(s, (0, 1))
    s("run 50")
    watch(s, 8 + ph)
    s(*ext_value(150000), "run-ticks 12", "perf ticks off", "run 50")
    return {"event": ("inject",)}


def b_watchdog(s, card, ph):
    init(s, range(4))
    for n in range(4):
        move(s, n)
    s("run %d" % SETTLE[card])
    wd = 100 + int(ph * TICK_MS[card])              # expires in a different tick of the SP per variant
    s.send(0, "WWD", wd, tag="last")
    s("run-ticks 2")
    watch(s, 8)
    s("run-ticks %d" % (wd / TICK_MS[card] + 30), "perf ticks off", "run 20")
    return {"event": ("after_last", wd)}


def b_stop_bits(s, card, ph):
    # axis 1 moving, axis 2 holding, axis 3 in test mode, axis 4 moving
    # without a stop bit (wire axes 0-3; bits 1, 3, 5 = $2A, table 3.2)
    init(s, range(4))
    move(s, 0)
    move(s, 3)
    s.send(2, "WDA", 300).send(2, "MT").send(2, "E")
    s("run %d" % SETTLE[card])
    watch(s, 8 + ph)
    for k in range(40):
        s("poke16 0x%X 0x002A" % STOP_BITS, "run-ticks 1", "peek16 0x%X" % STOP_BITS)
        if k == 20:
            move(s, 0)                                   # a new move: accepted, braked again
    s("perf ticks off", "run 100")
    return {"event": ("inject",)}


def stop_bits_cleared(out, card, variant, info):
    got = out.peeks(STOP_BITS, "inject", "state")
    assert len(got) == 40 and set(got) == {0}, got     # cleared by the card every tick (3.5.1)


# The host overwrites one header word (table 7.1) with a value the card must
# not trust, many times over at different points of the card's main loop,
# and repairs the header (as the card created it, 7.3.2) after each; the
# fixed words (base, width, nel) and the two indices.
CORRUPT_HEADER = [(qh(CMDQ, "BASE"), 0x1000), (qh(CMDQ, "WIDTH"), 11), (qh(CMDQ, "NEL"), 200)]
CORRUPT_INDEX = [(qh(CMDQ, "FRONT"), 10), (qh(CMDQ, "FRONT"), 0x80000000), (qh(CMDQ, "REAR"), 10),
                 (qh(CMDQ, "REAR"), 0xFFFFFFFF)]
REPAIR_CMDQ = q_repair(CMDQ)
ATTEMPTS = 100


def b_cmdq(fields):
    def build(s, card, v):
        field_, value = fields[v]
        init(s, (0, 1))
        move(s, 0)
        s("run 100")
        for _ in range(10):                              # every element an RBS of axis 2, answered
            s.send(1, "RBS")
        s("run 30")
        s.mark("inject")
        for k in range(ATTEMPTS):
            # each time 3.7 us later: the main loop is met at every point of its pass;
            # 3 ms with the header corrupt and 3 ms repaired, so that the card sees each
            s("run %.4f" % (3 + 0.0037 * k), "peek32 0x%X" % DPC_COMMANDS, "peek32 0x%X" % DPC_QUEUE_ERRORS,
              "poke32 0x%X 0x%X" % (field_, value), "run 3",
              "peek32 0x%X" % DPC_COMMANDS, "peek32 0x%X" % DPC_QUEUE_ERRORS, *REPAIR_CMDQ)
        s("run 5")
        if fields is CORRUPT_INDEX:                      # only axis 4 from here: see cmdq_counted_once
            s.send(3, "VER", tag="ver")
            s("run 5")
        return {}
    return build


def cmdq_counted_once(out, card, variant, info):
    """No command is taken while the header is corrupt; each corruption is
    counted once where the host sees it (docs/interpretations.md)."""
    pk = out.peeks(DPC_COMMANDS, "inject", "state")
    qe = out.peeks(DPC_QUEUE_ERRORS, "inject", "state")
    assert len(pk) == len(qe) == 2 * ATTEMPTS
    took = [k for k in range(ATTEMPTS) if pk[2 * k + 1] != pk[2 * k]]
    info.setdefault("read_through", []).append(len(took))
    if took:
        raise ReadThrough("commands taken through a corrupt header in %d of %d attempts (attempts %s), "
                          "%d commands" % (len(took), ATTEMPTS, took[:8], sum(pk[2 * k + 1] - pk[2 * k] for k in took)))
    wrong = [(k, qe[2 * k], qe[2 * k + 1]) for k in range(ATTEMPTS) if qe[2 * k + 1] != qe[2 * k] + 1]
    assert not wrong, "corruptions not counted once (attempt, before, after): %s" % wrong


CORRUPT_RSP = [(qh(RSPQ, "WIDTH"), 11), (qh(RSPQ, "NEL"), 9), (qh(RSPQ, "BASE"), 0x20), (qh(RSPQ, "FRONT"), 10)]


def b_rspq(s, card, v):
    field_, value = CORRUPT_RSP[v]
    init(s, (0, 1))
    s.mark("inject")
    s("peek32 0x%X" % DPC_COMMANDS, "poke32 0x%X 0x%X" % (field_, value))
    for k in range(3):
        s.send(0, "WAP", 1000 + k, lose="must")          # executed, the answers lost (counted)
        s("run 2")
    s("run 20", "peek32 0x%X" % DPC_COMMANDS, "peek32 0x%X" % DPC_RSP_LOST,
      # repaired as the card created it; the queue is empty (front = rear)
      *q_repair(RSPQ), "run 2")
    s.send(0, "RAP", tag="rap")
    s("run 5")
    return {}


def rspq_lost_counted(out, card, variant, info):
    before, after = out.peeks(DPC_COMMANDS, "inject", "state")
    assert after - before == 3, (before, after)
    assert out.peeks(DPC_RSP_LOST, "inject", "state") == [3]
    assert [p for _, a, c, p in out.resps() if c == code("RAP")] == [1002]   # all three executed


def b_rsp_full(s, card, v):
    init(s, (0, 1))
    s.send(0, "WIRQ2", 0xA2)
    move(s, 0)
    s("run 100")
    s.mark("inject")
    s("host read off", "peek32 0x%X" % DPC_COMMANDS)
    for k in range(12):
        # 9 answers fit (10 elements, one kept free): the last three are lost (4.6)
        s.send(0, "WAP", 100 + k, lose="must" if k >= 9 else "")
        s("run 1")
    s("run 10", "peek32 0x%X" % DPC_COMMANDS, "peek32 0x%X" % DPC_RSP_LOST)
    s.mark("reading")
    s("host read on", "run 2")
    s.send(0, "RAP", tag="rap")
    s("run 5")
    return {}


def rsp_full_counted(out, card, variant, info):
    before, after = out.peeks(DPC_COMMANDS, "inject", "state")
    assert after - before == 12, (before, after)         # all executed
    assert out.peeks(DPC_RSP_LOST, "inject", "state") == [3]
    irq2 = out.lines(r"^vme-irq 5 162$", "inject", "reading")
    assert len(irq2) == 9, irq2                          # interrupt 2 only for the answers written
    assert [p for _, a, c, p in out.resps() if c == code("RAP")] == [111]


def b_mr(j11):
    def build(s, card, ph):
        s("jumper j11 %s" % j11)
        init(s, (0, 1))
        move(s, 0)
        s("run %d" % SETTLE[card])
        s.mark("inject")
        s.send(0, "MR", expect=6 if j11 == "in" else 163, tag="mr")
        s("run 5", "outputs", "run 200")
        if j11 == "in":
            s("wait-display 5 3000", "outputs")
            s.send(0, "RBS", tag="b0").send(1, "RBS", tag="b1").send(0, "VER", tag="ver")
            s("run 5")
        return {}
    return build


def outputs_after_reset(out):
    """The second `outputs` after @inject (the first is before the reset)."""
    seen, got = 0, {}
    for _, text in out.between("inject"):
        m = re.match(r"output (\d) en=(\d) dac=(-?\d+) rate=(\d+)", text)
        if m:
            seen += 1
            if seen > 4:
                got[int(m.group(1))] = tuple(int(m.group(k)) for k in (2, 3, 4))
    assert len(got) == 4, got
    return got


def in_reset_state(out, tags):
    for tag in tags:
        _, _, c, p = out.by_tag[tag]
        assert c == RBS and p & 0xFF == MODE["disable"] and not p & ub("init", "dr_en"), (tag, hex(p))


def mr_resets_within_100ms(out, card, variant, info):
    mr = [t for t, a, c, p in out.resps() if c == 6]
    rs = out.lines(r"^reset watchdog$")
    assert len(mr) == 1 and len(rs) == 1, (mr, rs)
    # the card stops retriggering the hardware watchdog (100 ms) once MR is answered
    dt = rs[0][0] - mr[0]
    assert 0 < dt <= 100 + TICK_MS[card] + 1, dt
    info.setdefault("reset_after_ms", []).append(round(dt, 1))
    o = out.outputs("inject")
    assert o[0][0] == 1, o                              # driving until the reset
    assert all(v == (0, 0, 0) for v in outputs_after_reset(out).values())   # 2.5.1
    assert [d for _, d in out.lines(r"^display ", "inject")][-4:] == [
        "display 1", "display 2", "display 3", "display 5"]
    in_reset_state(out, ("b0", "b1"))


def mr_without_j11(out, card, variant, info):
    assert out.lines(r"^reset ") == []                   # 2.1.3: nothing happens without J11
    o = out.outputs("state")
    assert o[0][0] == 1 and o[0][1 if card != "stp" else 2] != 0, o   # still moving


BROWNOUT_US = tuple(range(0, 3000, 100))         # a command takes 1.2-2.2 ms at an SP boundary


def b_brownout(s, card, v):
    init(s, (0, 1, 2))
    move(s, 0)
    s("run %d" % SETTLE[card], "run-ticks 1")
    s.mark("inject")
    # the reset line goes while a command is on its way through the card:
    # in the queue, being executed, or answered and not yet read
    s("peek32 0x%X" % CMDQ_REAR, "peek32 0x%X" % RSPQ_FRONT)
    s.send(2, "DEINIT", lose="may", tag="victim")
    s("run %.3f" % (BROWNOUT_US[v] / 1000.0), "peek32 0x%X" % CMDQ_REAR, "peek32 0x%X" % RSPQ_FRONT, "reset", "outputs",
      "wait-display 5 3000", "run 20")
    s.mark("booted")
    s.send(0, "RBS", tag="b0").send(2, "RBS", tag="b2").send(1, "VER", tag="ver")
    s("run 5", "peek32 0x%X" % DPC_COMMANDS)
    return {}


def brownout_reset_state(out, card, variant, info):
    o = out.outputs("inject")
    assert all(v == (0, 0, 0) for v in o.values()), o     # 2.5.1: every output in its default state at once
    rear0, rear1 = out.peeks(CMDQ_REAR, "inject", "booted")[:2]
    front0, front1 = out.peeks(RSPQ_FRONT, "inject", "booted")[:2]
    taken, answered = rear1 != rear0, front1 != front0
    victim = [r for r in out.resps() if r[1] == 2 and r[2] == code("DEINIT")]
    # answered once if the answer was in the queue before the reset, else never
    assert len(victim) == (1 if answered else 0), (victim, taken, answered)
    info.setdefault("cases", set()).add("answered" if answered else "executing" if taken else "queued")
    in_reset_state(out, ("b0", "b2"))
    assert out.peeks(DPC_COMMANDS, "booted") == [3]       # nothing from before the reset ran again


def brownout_covers_every_case(info):
    assert info["cases"] == {"queued", "executing", "answered"}, info["cases"]


# ---- the rows ----------------------------------------------------------------------
@dataclass
class Row:
    id: str
    fault: str
    cards: tuple
    manual: str
    build: object                   # build(s, card, variant) -> {"event": locator}
    err: tuple = None               # (where, code, bits): "axis" next command on the axis,
    #                                 "card" next command on any axis, "self" the injecting command
    state: dict = field(default_factory=dict)    # axis -> (mode, bits set), before C
    after: dict = field(default_factory=dict)    # axis -> (mode, bits set), after C
    display: str = "0"
    leds: dict = field(default_factory=dict)     # "D": axes whose LED D is lit, "stop": 0/1
    timing: tuple = ()              # ((axes, signals, bound in ticks), ...): see check_timing
    at_once: bool = False           # every axis of `timing` in the same tick
    repair: tuple = ()              # script lines before C
    variants: tuple = (0, 1, 2, 3)
    probe: bool = True
    args: tuple = ()
    at_rest: tuple = ()             # axes that stand still at @state
    extra: object = None            # extra(out, card, variant, info): row-specific checks
    post: object = None             # post(s, card): commands after the probe
    final: object = None            # final(info): after all variants
    known: dict = field(default_factory=dict)    # card -> (findings, reason): strict xfail


ALL = ("inc", "ssi", "stp")
AXES4 = (0, 1, 2, 3)
RAMP = {"drop", "off"}            # a reaction with the <ed> ramp: braking or already disabled

# A row whose fault shows a firmware bug names it in `known` (known(): the
# findings and the reason per card), a strict xfail that fails only with the
# findings it names; none is open (the fixed ones: docs/hardening.md, "Fault
# matrix", Findings).
def known(findings, reason, cards=ALL):
    return {c: (findings, reason) for c in cards}


MATRIX = [
    Row("estop", "emergency stop mid-move, all axes", ALL, "2.2.3, 2.5.3, 6.3.5",
        b_estop, err=("card", 165, ob("h_stop")),
        state={n: ("disable", ()) for n in AXES4}, after={0: ("disable", ())},
        display="E", leds={"D": AXES4, "stop": 1}, timing=((AXES4, {"off"}, 1),), at_once=True,
        repair=("estop off",)),
    # the limit reports set logo_f, so C comes first (display 8 until then)
    Row("hwl-move", "positive limit switch reached during a move", ALL, "2.2.3, 4.8.2",
        b_hwl_move, err=("axis", 163, ub("hwl_p", "logo_f")),
        state={0: ("brake", ("hwl_p", "logo_f")), 1: ("enable", ())}, after={0: ("brake", ("hwl_p",))},
        display="8", leds={"D": ()}, timing=(((0,), RAMP | {"fall"}, 2),), at_rest=(0,)),
    Row("hwl-overrun", "a move further into a limit switch the axis has overrun", ALL, "2.2.3, 4.8.2",
        b_hwl_overrun, err=("axis", 163, ub("hwl_p", "logo_f")),
        state={0: ("brake", ("hwl_p", "logo_f")), 1: ("enable", ())}, after={0: ("brake", ("hwl_p",))},
        display="8", leds={"D": ()}, timing=(((0,), {"back", "off"}, 2),), at_rest=(0,),
        post=post_out_of_switch, extra=out_of_switch),
    Row("drive-fault", "drive fault during a move", ALL, "6.3.4, 4.8.2, 4.6",
        b_drive_fault, err=("axis", 163, ub("dr_f")),
        state={0: ("disable", ("dr_f",)), 1: ("enable", ())}, after={0: ("disable", ())},
        leds={"D": (0,)}, timing=(((0,), RAMP, 2),), repair=("fault 0 drive off",),
        args=("--irq-level", "3"), extra=irq3_once_in_a_tick),
    Row("stall", "following error: the motor stalls", ALL, "4.8.1, 6.3.9",
        b_stall, err=("axis", 163, ub("ferr_f")),
        state={0: ("disable", ("ferr_f",)), 1: ("enable", ())}, after={0: ("disable", ())},
        leds={"D": (0,)}, timing=(((0,), RAMP | {"flat"}, 2),), repair=("plant 0 motor coulomb 0.005",)),
    Row("enc-frozen", "encoder counter (SSI: reading) frozen during a move", ALL, "4.8.1, 6.3.9",
        b_ferr(["fault 0 encoder frozen"]), err=("axis", 163, ub("ferr_f")),
        state={0: ("disable", ("ferr_f",)), 1: ("enable", ())}, after={0: ("disable", ())},
        leds={"D": (0,)}, timing=(((0,), RAMP | {"flat"}, 2),), repair=("fault 0 encoder off",)),
    Row("enc-jump", "encoder jumps by more than <mf> during a move", ALL, "4.8.1, 6.3.9",
        b_jump("fault 0 encoder jump 1000", "fault 0 encoder jump 8000"), err=("axis", 163, ub("ferr_f")),
        state={0: ("disable", ("ferr_f",)), 1: ("enable", ())}, after={0: ("disable", ())},
        # INC/SSI: the loop brakes the mechanics to rest in the jumped frame before /EN opens
        leds={"D": (0,)}, timing=(((0,), RAMP, 2),)),
    Row("ssi-stuck0", "SSI data line stuck at 0 during a move", ("ssi",), "4.8.1, 6.3.9",
        b_jump("fault 0 encoder stuck0"), err=("axis", 163, ub("ferr_f")),
        state={0: ("disable", ("ferr_f",)), 1: ("enable", ())}, after={0: ("disable", ())},
        leds={"D": (0,)}, timing=(((0,), {"off"}, 2),), repair=("fault 0 encoder off",)),
    Row("ssi-stuck1", "SSI data line stuck at 1 during a move", ("ssi",), "4.8.1, 6.3.9",
        b_jump("fault 0 encoder stuck1"), err=("axis", 163, ub("ferr_f")),
        state={0: ("disable", ("ferr_f",)), 1: ("enable", ())}, after={0: ("disable", ())},
        leds={"D": (0,)}, timing=(((0,), {"off"}, 2),), repair=("fault 0 encoder off",)),
    Row("enc-range", "absolute position outside <ec> (external encoder via the DPRAM)", ALL,
        "4.4.2.1, 6.3.8", b_ec, err=("axis", 163, ub("encoder_f", "logo_f")),
        state={0: ("disable", ("encoder_f", "logo_f")), 1: ("enable", ())}, after={0: ("disable", ())},
        display="C", leds={"D": (0,)}, timing=(((0,), {"off"}, 1),),
        repair=tuple(ext_value(5000))),
    Row("watchdog", "the host stops sending (watchdog <wd>), all axes moving", ALL, "4.7, 6.3.6, 4.8.2",
        b_watchdog, err=("card", 164, ob("watch_f")),
        state={n: ("disable", ()) for n in AXES4}, after={0: ("disable", ())},
        display="D", leds={"D": AXES4}, timing=((AXES4, RAMP | {"fall"}, 2),), at_rest=(0, 1)),
    Row("stop-bits", "stop bits of axes 1-3 set every tick (axis 3 in test mode)", ALL, "3.5.1",
        b_stop_bits,
        state={0: ("brake", ()), 1: ("brake", ()), 2: ("disable", ()), 3: ("speed", ())},
        # the <pd> ramp (mode brake) begins in the tick after the supervision that takes the
        # bits, but a P controller's DAC shows a twentieth of its fall only one tick later: bound 3
        after={0: ("brake", ())}, leds={"D": (2,)}, timing=(((0,), RAMP | {"fall"}, 3), ((2,), {"off"}, 1)),
        at_rest=(0, 1), extra=stop_bits_cleared),
    Row("cmdq-header", "the host corrupts base, width or nel of the command queue", ALL, "3.2, 7.3.2",
        b_cmdq(CORRUPT_HEADER), state={0: ("speed", ()), 1: ("enable", ())}, after={0: ("speed", ())},
        leds={"D": ()}, variants=tuple(range(len(CORRUPT_HEADER))), extra=cmdq_counted_once),
    Row("cmdq-index", "the host writes an index out of range into the command queue header", ALL,
        "3.2, 7.3.2", b_cmdq(CORRUPT_INDEX), variants=tuple(range(len(CORRUPT_INDEX))), probe=False,
        extra=cmdq_counted_once),
    Row("rspq-corrupt", "the host corrupts the response queue header", ALL, "3.2, 4.6",
        b_rspq, state={0: ("enable", ()), 1: ("enable", ())}, after={0: ("enable", ())}, leds={"D": ()},
        variants=tuple(range(len(CORRUPT_RSP))), extra=rspq_lost_counted),
    Row("rspq-full", "the host stops reading responses (output queue full)", ALL, "4.6",
        b_rsp_full, state={0: ("speed", ()), 1: ("enable", ())}, after={0: ("speed", ())}, leds={"D": ()},
        variants=(0,), args=("--irq-level", "5"), extra=rsp_full_counted),
    Row("mr-j11-in", "software reset MR, watchdog jumper J11 in, during a move", ALL, "2.1.3, 2.5.1",
        b_mr("in"), variants=(0,), probe=False, extra=mr_resets_within_100ms),
    Row("mr-j11-out", "software reset MR without J11, during a move", ALL, "2.1.3",
        b_mr("out"), err=("self", 163, ub("logo_f")), state={0: ("speed", ("logo_f",)), 1: ("enable", ())},
        after={0: ("speed", ())}, display="8", leds={"D": ()}, variants=(0,), extra=mr_without_j11),
    Row("brownout", "reset line (brown-out) while a command is on its way, during a move", ALL, "2.5.1",
        b_brownout, variants=tuple(range(len(BROWNOUT_US))), probe=False,
        extra=brownout_reset_state, final=brownout_covers_every_case),
]


# ---- the common checks ---------------------------------------------------------------
def add_probe(s, row):
    where, ecode, _ = row.err or (None, None, None)
    s.mark("probe")
    # 1. reads are always executed (6.3), an error waiting or not: the status
    #    read on the axis shows the error bits, the overall status the card's
    s.send(1, "RBS", tag="p1")
    s.send(0, "RBS", tag="p2")
    s.send(1, "RAS", tag="pras")
    s("run 5")
    # 2. the next other command gets the error, in place of its own answer, and
    #    is not executed: on the axis, or for the card's own errors on any axis
    #    (an ME: it only selects a mode, and the probe's next ME selects it again)
    if where in ("axis", "card"):
        s.send(1 if where == "card" else 0, "ME", expect=ecode, tag="report")
        s("run 5")
    # 3. once: a read runs
    s.send(0, "RBS", tag="again")
    for n in sorted(row.state):
        if n:
            s.send(n, "RBS", tag="st%d" % n)
    s("run 5")
    # 4. anything else is refused until C (6.3, 6.3.7)
    s.send(0, "ME", expect=163 if where else code("ME"), tag="unack")
    s("run 5", *row.repair)
    s("run 20")
    s.send(0, "C", tag="clear")
    s("run 5")
    for n in sorted(set(row.after) | {0}):
        s.send(n, "RBS", tag="after%d" % n)
    s.send(0, "RAS", tag="ostat").send(0, "VER", tag="ver")
    s("run 10")


class Checks:
    def __init__(self, label):
        self.label = label
        self.fails = []

    def __call__(self, cond, msg, kind=AssertionError):
        if not cond:
            self.fails.append(kind("%s: %s" % (self.label, msg)))
        return cond


def account(chk, out, sends):
    """Every command answered exactly once, in order, by its own code or
    the expected error; those the manual lets go unanswered, never.
    Returns whether every answer was found (the later checks read them)."""
    resps = out.resps()
    out.by_tag = {}
    i = 0
    for snd in sends:
        if snd.lose == "must":
            continue
        allowed = snd.expect if isinstance(snd.expect, set) else {snd.expect}
        r = resps[i] if i < len(resps) else None
        if snd.lose == "may" and (r is None or r[1] != snd.axis or not (r[2] in allowed or 160 <= r[2] <= 165)):
            continue
        while r is not None and r[1] != snd.axis:         # an answer for another axis: one too many
            chk(False, "a response to no command sent (or a second time): %s" % (r,), AnsweredTwice)
            i += 1
            r = resps[i] if i < len(resps) else None
        if not chk(r is not None, "%s on axis %d (%s) not answered" % (snd.mn, snd.axis, snd.tag)):
            return False
        i += 1
        if snd.tag:
            out.by_tag[snd.tag] = r
        kind = AssertionError
        if snd.tag in ("again", "clear") and 160 <= r[2] <= 165:
            kind = ReportedAgain                          # the error once more
        if snd.tag == "unack" and r[2] == code(snd.mn):
            kind = NotAcknowledged                        # executed without C
        chk(r[2] in allowed, "%s on axis %d (%s) answered %d, expected %s (0x%08X)" % (
            snd.mn, snd.axis, snd.tag or "setup", r[2], sorted(allowed), r[3]), kind)
    return chk(i == len(resps), "responses to no command sent (or a second time): %s" % (resps[i:],),
               AnsweredTwice)


def ustat_is(chk, label, p, mode, bits, kind=AssertionError):
    chk(p & 0xFF == MODE[mode], "%s: mode %d, expected %s (0x%08X)" % (label, p & 0xFF, mode, p), kind)
    chk(bool(p & ub("dr_en")) == (mode != "disable"), "%s: dr_en wrong (0x%08X)" % (label, p), kind)
    for b in bits:
        chk(p & ub(b), "%s: %s not set (0x%08X)" % (label, b, p), kind)
    for b in ERROR_BITS:
        if b not in bits:
            chk(not p & ub(b), "%s: %s set (0x%08X)" % (label, b, p), kind)


def tick_time(out, tick_no, card):
    t0 = out.time_of("inject")
    n0 = [t["no"] for t in out.ticks if t["ev"] < out.marks["inject"]][-1]
    return t0 + (tick_no - n0) * TICK_MS[card]


def event_tick(out, card, loc):
    """The sampling instant (tick line) at which the firmware can first see the event."""
    after = [t for t in out.ticks if t["ev"] > out.marks["inject"]]
    kind = loc[0]
    if kind == "inject":
        e = [t["no"] for t in out.ticks if t["ev"] < out.marks["inject"]][-1]
        # the SSI receivers read the encoders at the timer's expiry
        # (AX_CTRL_SSI_SYNC): an encoder fault injected at the expiry is in
        # the reading of the next sampling instant
        return e + 1 if card == "ssi" and loc[1:] == ("encoder",) else e
    if kind == "cross":                                   # the counter at the expiry
        return next(t["no"] for t in after if t["ax"][loc[1]]["cnt"] >= loc[2])
    # A line's DAC was computed at the tick before; a reaction that disables
    # the axis in the same period overwrites it, so a line with the axis off
    # also marks the event at the tick before.
    if kind == "over":
        return next(t["no"] for t in after if abs(t["ax"][loc[1]]["out"]) > loc[2] or off(t["ax"][loc[1]])) - 1
    if kind == "pub_ferr":                                # published by the tick before (at most)
        return next(t["no"] for t in after
                    if abs(t["ax"][loc[1]]["words"][4]) > loc[2] or off(t["ax"][loc[1]])) - 1
    if kind == "starts":                                  # the first output of the move
        thr = 0 if card == "stp" else 30
        return next(t["no"] for t in after if abs(t["ax"][loc[1]]["out"]) > thr) - 1
    if kind == "after_last":                              # <wd> after the last command's answer
        te = out.by_tag["last"][0] + loc[1]
        return next(t["no"] for t in out.ticks if tick_time(out, t["no"], card) >= te)
    raise ValueError(kind)


def off(a):
    return not a["ctrl"] & EN and a["out"] == 0


def reaction_tick(out, card, n, e, signals):
    """The first `perf ticks` line after tick e whose outputs of axis n show
    one of the signals.  Line k shows what the card put out after the tick
    at expiry k-1 (that tick's outputs and whatever the main loop did after
    it).  Signals, against the 7 lines up to e: "off" /EN open and output 0;
    "drop" the DAC (step rate) below 70% of the move's; "fall" the DAC falls
    by a twentieth of the move's in one tick (a brake that holds the axis: the
    DAC then follows the motor's own deceleration); "flat" the growth of
    the DAC, which shows the following error (P controller), halved: the
    setpoint brakes; "back" the output of a move that began stops growing
    (STP: the rate is 0 again)."""
    lines = {t["no"]: t["ax"][n] for t in out.ticks}
    base = [lines[k] for k in range(e - 6, e + 1) if k in lines]
    sign = 1 if sum(a["out"] for a in base) >= 0 else -1
    cruise = min(sign * a["out"] for a in base)
    slope = (sign * (base[-1]["out"] - base[0]["out"])) / max(len(base) - 1, 1)
    for k in sorted(lines):
        if k <= e or k - 1 not in lines:
            continue
        a, prev = lines[k], lines[k - 1]
        if "off" in signals and off(a):
            return k
        if "drop" in signals and sign * a["out"] < 0.7 * cruise:
            return k
        if "fall" in signals and sign * (a["out"] - prev["out"]) < -0.05 * cruise:
            return k
        if "flat" in signals and slope > 0 and sign * (a["out"] - prev["out"]) < 0.5 * slope:
            return k
        if "back" in signals:
            if card == "stp" and a["out"] == 0 and prev["out"] != 0:
                return k
            if card != "stp" and k - 2 in lines and abs(prev["out"]) > 30 and \
                    sign * (a["out"] - prev["out"]) <= 0:
                return k
    return None


def plant_at(out, mark, n):
    """(position, velocity) of axis n in the first `plant` print after a mark."""
    for _, text in out.between(mark):
        if text.startswith("plant %d " % n):
            return float(text.split("pos=")[1].split()[0]), float(text.split("vel=")[1].split()[0])
    raise KeyError("plant %d after @%s" % (n, mark))


def stop_distance(out, card, row, ev):
    """How far the mechanics of the row's first axis moved from the fault
    to where they came to rest 1.5 s after the reaction (docs/hardening.md,
    the fault matrix's column), and their speed then.  From the plant at the
    injection - the fault itself (a drive fault, a jam, a frozen or jumping
    encoder, the emergency stop, a move into the switch) - or from the switch
    a move crosses, or from the plant carried on at its speed to the tick in
    which the watchdog expires."""
    n = row.timing[0][0][0]
    p0, v0 = plant_at(out, "inject", n)
    kind = ev["event"][0]
    if kind == "cross":
        p0 = ev["event"][2]
    elif kind == "after_last":
        e_inj = [t["no"] for t in out.ticks if t["ev"] < out.marks["inject"]][-1]
        p0 += v0 * (event_tick(out, card, ev["event"]) - e_inj) * TICK_MS[card] / 1000.0
    rest, v_end = plant_at(out, "state", n)
    return round(rest - p0), v_end


def check_timing(chk, out, card, row, ev, info):
    """Event at tick e (the sampling instant at which the firmware can first
    see it); the reaction in line r.  r - e = 1: in the outputs of the tick
    that saw the event (a disable at once); 2: in those of the next tick,
    one servo period later (a ramp that starts there).  A move that the
    firmware stops before its first output ("starts" never comes) is the
    reaction at once: latency 0."""
    try:
        e = event_tick(out, card, ev["event"])
    except StopIteration:
        if ev["event"][0] != "starts":
            raise
        for axes, _, _ in row.timing:
            for n in axes:
                info.setdefault("latency", {}).setdefault(n, []).append(0)
        return
    seen = []
    for axes, signals, bound in row.timing:
        for n in axes:
            r = reaction_tick(out, card, n, e, signals)
            if not chk(r is not None, "axis %d: no reaction (%s) in the outputs after tick %d" % (n, signals, e)):
                continue
            seen.append(r)
            info.setdefault("latency", {}).setdefault(n, []).append(r - e)
            chk(r - e <= bound, "axis %d: reaction (%s) in the output of tick %d, %d ticks after the event "
                "(%.1f ms; bound %d)" % (n, "/".join(sorted(signals)), r, r - e, (r - e) * TICK_MS[card], bound),
                ReactionLate)
    if row.at_once:
        chk(len(set(seen)) == 1, "the axes did not react in the same tick: %s" % seen)


def run_variant(row, card, v, info):
    s = Script(card)
    ev = row.build(s, card, v)
    s.mark("state")
    s("outputs", "leds", "peek32 0x%X" % pos_addr(0), "peek32 0x%X" % pos_addr(1), "run 40",
      "peek32 0x%X" % pos_addr(0), "peek32 0x%X" % pos_addr(1))
    if row.timing:
        s("run 1500", "plant")                       # at rest by now, coasting included (stop_distance)
    if row.probe:
        add_probe(s, row)
    if row.post:
        row.post(s, card)
    s.mark("end")
    s("run 20", "leds")
    r = sim(s.text(), card, args=["--timestamps"] + list(row.args))
    out = Out(r, card)
    chk = Checks("%s %s variant %s" % (row.id, card, v))
    chk(r.rc == 0, "mac4sim exit %d: %s" % (r.rc, r.stderr.strip()))
    bad = [x for _, x in out.ev if x.startswith(("fault ", "timeout ", "timer-overrun"))]
    chk(not bad, "emulator reports: %s" % bad)
    if not account(chk, out, s.sends):          # the rest reads the answers: stop here
        return chk.fails

    if row.probe:
        where, ecode, ebits = row.err or (None, None, 0)
        if where in ("axis", "card"):
            rep = out.by_tag["report"]
            chk(rep[3] & ebits == ebits, "error %d reported with 0x%08X, bits 0x%X missing" % (ecode, rep[3], ebits))
            polled = out.by_tag["p2" if where == "axis" else "pras"][3]
            chk(polled & ebits == ebits, "the status read before the report: 0x%08X, bits 0x%X missing" % (
                polled, ebits))
        if where == "axis":
            ustat_is(chk, "reported status", rep[3], row.state[0][0], row.state[0][1])
            ustat_is(chk, "status read", out.by_tag["p2"][3], row.state[0][0], row.state[0][1])
        if where == "self":
            mr = out.by_tag["mr"]
            chk(mr[3] & ebits == ebits, "MR answered with 0x%08X" % mr[3])
        for n, (mode, bits) in row.state.items():
            ustat_is(chk, "axis %d after the fault" % n, out.by_tag["again" if n == 0 else "st%d" % n][3], mode, bits)
        chk(out.display_at("probe") == row.display, "display %s after the fault, expected %s" % (
            out.display_at("probe"), row.display))
        for n, (mode, bits) in row.after.items():
            ustat_is(chk, "axis %d after C" % n, out.by_tag["after%d" % n][3], mode,
                     [b for b in bits if b not in ERROR_BITS], NotCleared)
        ost = out.by_tag["ostat"][3]
        chk(not ost & ob(*CARD_BITS), "overall status 0x%X after C" % ost, NotCleared)
        chk(out.display_at("end") == "0", "display %s after C" % out.display_at("end"), NotCleared)
        leds, stop = out.leds("state")
        for n in row.state:
            chk(bool(leds & (1 << 4 * n)) == (n in row.leds.get("D", ())), "LED D of axis %d: 0x%04X" % (n, leds))
            if card == "stp":
                faulty = any(b in ERROR_BITS for b in row.state[n][1])
                chk(bool(leds & (4 << 4 * n)) == faulty, "LED F of axis %d: 0x%04X" % (n, leds))
        chk(stop == row.leds.get("stop", 0), "LED STOP %d" % stop)
        if card == "stp":
            chk(not out.leds("end")[0] & 0x4, "LED F of axis 1 after C: 0x%04X" % out.leds("end")[0], NotCleared)
        o = out.outputs("state")
        for n, (mode, _) in row.state.items():
            chk(o[n][0] == (mode != "disable"), "axis %d: output enable %d in mode %s" % (n, o[n][0], mode))
            if mode == "disable":
                chk(o[n][1:] == (0, 0), "axis %d disabled with output %s" % (n, o[n]))
        pos0 = [signed(x) for x in out.peeks(pos_addr(0), "state", "probe")]
        pos1 = [signed(x) for x in out.peeks(pos_addr(1), "state", "probe")]
        for n, got in ((0, pos0), (1, pos1)):
            if n in row.at_rest:
                chk(abs(got[1] - got[0]) <= 2, "axis %d not at rest: %s" % (n, got))
    ver = out.by_tag.get("ver")
    chk(ver is not None and ver[2] == VER and ver[3] >> 24 == CARD_NO[card], "VER at the end: %s" % (ver,))
    if row.timing:
        check_timing(chk, out, card, row, ev, info)
        d, v_end = stop_distance(out, card, row, ev)
        chk(abs(v_end) < 1, "axis %d still moving 1.5 s after the reaction: %.1f units/s" % (
            row.timing[0][0][0], v_end))
        info.setdefault("stop_distance", []).append(d)
    if row.extra:
        try:
            row.extra(out, card, v, info)
        except AssertionError as x:
            chk(False, "%s: %s" % (row.extra.__name__, x), type(x))
    return chk.fails


def cases():
    for row in MATRIX:
        for card in row.cards:
            marks = []
            if card in row.known:
                findings, reason = row.known[card]
                marks.append(pytest.mark.xfail(strict=True, raises=findings, reason=reason))
            yield pytest.param(row, card, id="%s-%s" % (row.id, card), marks=marks)


def run_row(row, card):
    """Every variant of a row, then the row's final check; raises the
    failures: as the one finding class of an xfail row when every failure
    is one it names, else as an AssertionError."""
    info, fails = {}, []
    for v in row.variants:
        fails += run_variant(row, card, v, info)
    if row.final and not fails:
        try:
            row.final(info)
        except AssertionError as x:
            fails.append(AssertionError("%s %s: %s" % (row.id, card, x)))
    print("MATRIX %s %s %s" % (row.id, card, {k: v for k, v in info.items() if k != "cases"}))
    if not fails:
        return
    named = row.known[card][0] if card in row.known else ()
    kind = fails[0].__class__ if named and all(isinstance(f, named) for f in fails) else AssertionError
    x = kind("\n".join(str(f) for f in fails))
    x.fails = fails
    raise x


@pytest.mark.parametrize("row,card", list(cases()))
def test_fault_matrix(row, card):
    run_row(row, card)


# ---- the checks can fail ---------------------------------------------------------------
ROWS = {r.id: r for r in MATRIX}


def unlose(build):
    """The same scenario, but every command expected to be answered."""
    def b(s, card, v):
        ev = build(s, card, v)
        for snd in s.sends:
            snd.lose = ""
        return ev
    return b


def forget_last(build):
    """The same scenario with the last command of the set-up not counted:
    its answer is one the accounting did not expect."""
    def b(s, card, v):
        ev = build(s, card, v)
        s.sends.pop()
        return ev
    return b


def mutant(rowid, card, **changes):
    return replace(ROWS[rowid], variants=changes.pop("variants", (0,)), known={}, **changes), card


@pytest.mark.parametrize("row,card,finding", [
    pytest.param(*mutant("estop", "inc", state={n: ("brake", ()) for n in AXES4}), AssertionError, id="mode"),
    pytest.param(*mutant("estop", "stp", timing=((AXES4, {"off"}, 0),)), ReactionLate, id="timing"),
    pytest.param(*mutant("drive-fault", "ssi", err=("axis", 164, ub("dr_f"))), AssertionError, id="code"),
    pytest.param(*mutant("drive-fault", "inc", state={0: ("disable", ()), 1: ("enable", ())}), AssertionError,
                 id="error-bit"),
    pytest.param(*mutant("mr-j11-out", "stp", display="0"), AssertionError, id="display"),
    pytest.param(*mutant("estop", "ssi", leds={"D": (0,), "stop": 1}), AssertionError, id="leds"),
    pytest.param(*mutant("rspq-full", "inc", build=unlose(b_rsp_full)), AssertionError, id="lost"),
    pytest.param(*mutant("estop", "inc", build=forget_last(b_estop)), AnsweredTwice, id="twice"),
    pytest.param(*mutant("brownout", "stp", variants=(0, 1)), AssertionError, id="brownout-cases"),
    pytest.param(*mutant("hwl-move", "inc", state={0: ("brake", ("hwl_p",)), 1: ("speed", ())}), AssertionError,
                 id="bystander"),
])
def test_the_matrix_checks_fail_when_they_should(row, card, finding):
    """Rows with a wrong expectation (or a scenario that miscounts its
    commands) fail, with the right kind of failure."""
    with pytest.raises(AssertionError) as e:
        run_row(row, card)
    assert any(isinstance(f, finding) for f in e.value.fails), e.value


# ---- found on the way ----------------------------------------------------------------
# K5 (fixed): the SSI card put the Gray jumper J1 into the user status only at the first servo tick
# after the boot; an INIT before it decoded the absolute SSI position as binary.
def test_ssi_position_at_an_init_right_after_boot():
    """4.9: the state of the Gray/binary jumpers is available from basic
    initialisation on, and INIT activates the position measurement."""
    r = sim(BOOT + "plant 0 pos 100000\nsend 0 UWSC 2\nsend 0 INIT\nsend 0 RCP\nsend 0 ME\nsend 0 E\n"
            "run 50\nsend 0 RBS\nrun 5\n", "ssi")
    got = r.resps()
    assert [p for _, c, p in got if c == code("RCP")] == [100000], got
    assert got[-1][1] == RBS and not got[-1][2] & ub("ferr_f"), got
