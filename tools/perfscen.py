"""perfscen.py - the measurement scenarios (docs/performance.md),
shared by the budget tests (tests/timing) and `make bench` (tools/bench.py).

Every scenario is a host script for build/mac4sim.  "Four axes moving":
INIT, ME, E on all four axes, then WPV/WPA/WPD within what the default plant
can follow, WAP to a distant target, MP, E on each axis; once they are under
way a measurement window opens (`perf reset`) with the main loop tracked,
the profile generator probed and, for the load and latency figures, the host
sending commands back to back (`perf host-load on`: one command in flight,
the next sent at the host's first poll after the answer).  The positions the
card publishes are read before and after the window, so a test can see that
the axes really moved.
"""
import os
import re
import subprocess
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
sys.path.insert(0, os.path.join(ROOT, "host"))
from mac4card import board  # noqa: E402  (generated from board/mac4.toml)

BUILD = os.path.join(ROOT, "build")
SIM = os.path.join(BUILD, "mac4sim")
AXES = range(4)
PROFILE_PROBE = "card_profile_tick"
SSI_AT = 1000000              # SSI encoders start here: no move crosses their wrap at 0
CPU_HZ = board.MAC4_CPU_HZ
PERIOD = board.PERIOD_CYCLES                    # controller tick, cycles
PROFILE_PERIOD = board.PROFILE_PERIOD_CYCLES

# Deadlines: missing one breaks the card (tests/timing/test_deadlines.py).
# The controller tick, alone and delayed by the longest masked section, within
# PERIOD; the UART's character time (CHAR_CYCLES, below); these; the boot guard
# (BOOT_GUARD_MS, below).
BUDGET_LATENCY_MS = 2.0
BUDGET_IMAGE_BYTES = 65536
BUDGET_RAM_STACK_BYTES = 16384
# Aims below the deadlines: `make bench` and build/perf.json print each figure
# beside its aim (aims() below); no test fails on them.
BUDGET_SERVO_TICK = 4000                  # INC/SSI, cycles, 10% of 2.5 ms
BUDGET_PROFILE_SERVO = 6000               # INC/SSI, cycles per 10 ms
BUDGET_STP_TICK = PERIOD["stp"] // 10     # 10% of 8 ms
BUDGET_STP_PROFILE = PROFILE_PERIOD["stp"] // 10   # 10% of 32 ms
BUDGET_MASKED_FRACTION = 10               # longest masked section, percent of the tick's period
BUDGET_LOAD_PERCENT = 25.0
CREEP_RATE_HZ = 1000          # pulse rate the creep-phase interrupts should follow, all four axes at once


def setup_lines(card):
    if card == "ssi":
        return ["plant %d pos %d" % (a, SSI_AT) for a in AXES]
    return []


def targets(card, far=True):
    if card == "ssi":
        base = SSI_AT
        d = [40000, -40000, 30000, -30000] if far else [3000, -2500, 2000, -1500]
        return [base + x for x in d]
    if card == "stp":
        return [20000, -20000, 15000, -15000] if far else [400, -300, 250, -350]
    return [40000, -40000, 30000, -30000] if far else [3000, -2500, 4000, -1500]


def motion(card):
    """WPV, WPA, WPD the default plant follows: INC/SSI 100 increments per
    10 ms (10 000/s, 8 V of 10), STP 2000 steps/s."""
    return (2000, 500, 500) if card == "stp" else (100, 10, 10)


def enable_lines(card):
    out = ["wait-display 5 3000"]
    if card == "ssi":
        out += ["send %d UWSC 2" % a for a in AXES]      # 24 bits left-aligned in 26 (4.4.2.2)
    for m in ("INIT", "ME", "E"):
        out += ["send %d %s" % (a, m) for a in AXES]
    out.append("run 20")
    return out


def move_lines(card, tg, extra=()):
    v, acc, dec = motion(card)
    out = []
    for a, t in zip(AXES, tg):
        out += ["send %d WPV %d" % (a, v), "send %d WPA %d" % (a, acc), "send %d WPD %d" % (a, dec)]
        out += ["send %d %s" % (a, e) for e in extra]
        out += ["send %d WAP %d" % (a, t), "send %d MP" % a]
    out += ["send %d E" % a for a in AXES]
    return out


def positions_lines():
    return ["peek32 0x%04X" % (board.DP_AXIS_DATA(a) + board.DPA_POS) for a in AXES]


def window_lines(ms, host_load, probes=(PROFILE_PROBE,), lead_ms=0):
    out = ["run %d" % lead_ms] if lead_ms else []
    out += positions_lines()
    out += ["perf track on"] + ["perf probe %s" % p for p in probes]
    out += ["perf quiet on", "perf reset"]
    if host_load:
        out.append("perf host-load on")
    out += ["run %d" % ms, "perf host-load off", "perf quiet off", "perf report", "perf table"]
    out += positions_lines()
    return out


MOVING_LEAD_MS = {"inc": 200, "ssi": 200, "stp": 400}     # under way before a window opens


def moving_start(card):
    """The script of moving() up to its window: four axes positioning to
    distant targets, under way."""
    return setup_lines(card) + enable_lines(card) + move_lines(card, targets(card))


def moving(card, ms=1000, host_load=True):
    """Four axes positioning to distant targets, the window while they move."""
    lines = moving_start(card) + window_lines(ms, host_load, lead_ms=MOVING_LEAD_MS[card])
    return "\n".join(lines) + "\n"


# Every term of the servo filter (5.16) and a torque limit: the INC example's
# zero and integral gain (docs/performance.md, the 7.2 examples: K 20, zero
# 0.5, KI 0.02) with a pole and <sw> besides, so that the tick takes the
# general filter's longest path on every axis (the defaults are K only).
FULL_FILTER = ("WZE 128", "WPO 10", "WKI 41", "WSW 2000")
# Circular axes (4.3.1.2), the longer measurement path: the encoder's wrap
# is the axis', the displayed position kept in 0 .. <cr>-1.  The targets of
# targets() lie inside <cr> (the INC's shifted by CIRCULAR_SHIFT).
CIRCULAR = ("UWSH 2", "UWCR 2000000")
CIRCULAR_SHIFT = {"inc": 100000, "ssi": 0, "stp": 100000}


def configured(card, system=(), mode=(), shift=0, ms=1000):
    """Four axes moving as in moving(), with the system parameters `system`
    written before INIT and the mode parameters `mode` before E."""
    lines = setup_lines(card) + ["wait-display 5 3000"] + ["send %d %s" % (a, c) for a in AXES for c in system]
    lines += enable_lines(card)[1:]
    lines += move_lines(card, [t + shift for t in targets(card)], extra=mode)
    lines += window_lines(ms, False, lead_ms=200)
    return "\n".join(lines) + "\n"


def external(card, mode=()):
    """moving() with each axis measured by an absolute encoder board on the
    VMEbus (<et> 4, 24 bits at $80C000 + $10 n, 4 000 counts per turn: the
    manual's 7.2 SSI example has one), which measure_ext reads over the
    master window in every tick: the external path."""
    boards = ["vme-encoder $%X %d bits 24 res 4000 turns 0" % (0x80C000 + 0x10 * a, a) for a in AXES]
    system = []
    for a in AXES:
        system += ["send %d UWET 4" % a, "send %d UWEA %d" % (a, 0x80C000 + 0x10 * a), "send %d UWEB 24" % a]
    lines = boards + ["wait-display 5 3000"] + system + enable_lines(card)[1:]
    lines += move_lines(card, [t + CIRCULAR_SHIFT[card] for t in targets(card)], extra=mode)
    lines += window_lines(1000, False, lead_ms=200)
    return "\n".join(lines) + "\n"


def stp_encoder():
    """MAC4-STP: four axes positioning, each measured by the encoder on its
    motor (<et> 1, BR open: the counter counts increments, 4.4.2.3), <ms>
    500 and <es> 1000 as the default plant's motor and encoder (0.125 steps
    per increment): the tick converts the increments every tick."""
    s = configured("stp", system=("UWET 1", "UWMS 500", "UWES 1000"))
    return "".join("br %d encoder\n" % a for a in AXES) + s


def encoder_loss(card):
    """external() with all four encoder boards failing at once (removed from
    the VMEbus) 100 ms into the window: the tick's bus errors on four axes,
    each an encoder error that disables its axis at once (6.3.8)."""
    off = "".join("vme-encoder $%X off\n" % (0x80C000 + 0x10 * a) for a in AXES)
    return external(card).replace("perf reset\nrun 1000", "perf reset\nrun 100\n" + off + "run 50")


def circular(card):
    """moving() on circular axes, the default gains."""
    return configured(card, system=CIRCULAR, shift=CIRCULAR_SHIFT[card])


def full_filter(card):
    """The tick's worst case: circular axes, every filter term and <sw>."""
    return configured(card, system=CIRCULAR, mode=FULL_FILTER, shift=CIRCULAR_SHIFT[card])


def whole_moves(card, ms=1400):
    """Four axes through whole moves inside the window: accelerate, cruise,
    brake and land (INC/SSI 8000 increments at 100 per SP, two each way), all
    four in step, so that the profile generator's worst SP - four axes
    braking or landing at once - is in it."""
    base = SSI_AT if card == "ssi" else 0
    tg = [base + d for d in (8000, -8000, 8000, -8000)]
    lines = setup_lines(card) + enable_lines(card) + move_lines(card, tg)
    lines += window_lines(ms, False, lead_ms=5)
    return "\n".join(lines) + "\n"


def on_the_fly(card):
    """Four axes far from their targets (INC/SSI 60 000 increments) change
    course on the fly: a target on the other side (WAP, E: they brake, turn
    round and accelerate away) and then a lower <pv> (WPV 40, E: they brake
    down to it), all four at once - the profile generator's steps that the
    32-bit paths do not take (a rest of 2^31 Q16 or more, a speed above
    <pv>, moving away from the target)."""
    base = SSI_AT if card == "ssi" else 0
    far = [60000, -60000, 60000, -60000]
    lines = setup_lines(card) + enable_lines(card) + move_lines(card, [base + d for d in far])
    lines += ["run 300"] + positions_lines() + ["perf track on", "perf probe %s" % PROFILE_PROBE, "perf quiet on",
                                                 "perf reset"]
    for a in AXES:
        lines += ["send %d WAP %d" % (a, base - far[a]), "send %d E" % a]
    lines.append("run 400")
    for a in AXES:
        lines += ["send %d WPV 40" % a, "send %d E" % a]
    lines += ["run 400", "perf quiet off", "perf report"] + positions_lines()
    return "\n".join(lines) + "\n"


def every_command_lines(card, tg):
    """Every command of the card's table but MR once on axis 2 and once on
    axis 4 (writes with the parameter's default, WAP with the axis' target),
    3 ms apart."""
    import json
    table = json.load(open(os.path.join(BUILD, "commands.json")))
    out = []
    for c in table["commands"]:
        if card not in c["cards"] or c["mnemonic"] == "MR":
            continue
        for a in (1, 3):
            if c["kind"].startswith("write"):
                v = tg[a] if c["mnemonic"] == "WAP" else c["default"][card]
                out.append("send %d %s %d" % (a, c["mnemonic"], v))
            else:
                out.append("send %d %s" % (a, c["mnemonic"]))
            out.append("run 3")
    return out


def commands(card, ms=1000):
    """Three axes positioning while the host reconfigures: every 10 ms a new
    target on the fly for one of them (WAP, E) and INIT or DEINIT of the
    fourth - the commands that run longest with interrupts masked - and then
    every other command once, every mode taken up by a moving axis (MRE
    among them), a compare window armed on a moving axis, and last a
    watchdog expiry, which stops all four moving axes at once: so that the
    longest masked section (the bound of every interrupt's latency) and the
    tick's measured latency are in the window."""
    tg = targets(card)
    lines = setup_lines(card) + enable_lines(card) + move_lines(card, tg[:3] + [tg[3]])
    lines += ["send 3 MD", "send 3 E", "send 3 DEINIT", "run 200"] + positions_lines()
    lines += ["perf track on", "perf quiet on", "perf reset"]
    for k in range(ms // 10):
        a = k % 3
        far = tg[a] + (1 if k % 2 else -1) * (2000 + 100 * k)
        lines += ["send %d WAP %d" % (a, far), "send %d E" % a, "send 3 %s" % ("INIT" if k % 2 == 0 else "DEINIT"),
                  "run 10"]
    lines += ["perf quiet off"] + positions_lines() + ["perf quiet on"] + every_command_lines(card, tg)
    # every mode taken up by a moving axis (its set-up is the E's masked
    # commit; MRE's ramp, 4.8.2, among them), then time for a stop it began,
    # C (a refused E, a following error after a disable leave logo_f) and
    # the axis enabled again
    table = __import__("json").load(open(os.path.join(BUILD, "commands.json")))
    modes = [c["mnemonic"] for c in table["commands"] if card in c["cards"] and c["kind"] == "mode"]
    for k, m in enumerate(modes):
        far = tg[2] + (1 if k % 2 else -1) * 20000
        lines += ["send 2 WAP %d" % far, "send 2 MP", "send 2 E", "run 40", "send 2 %s" % m, "send 2 E", "run 200",
                  "send 2 C", "send 2 ME", "send 2 E", "run 20", "send 2 C"]
    lines += ["send 2 MRE", "send 2 E", "run 300", "send 2 ME", "send 2 E", "run 20"]
    # a full compensation table (16 x 16 points, 255 entries) and its checksum read
    # (RCSM), a feedback entry set up: the extensions' longest commands
    lines += ["send 1 C", "send 1 WCRW 15", "send 1 WCCL 15", "send 1 WCRS 15000", "send 1 WCCS 15000",
              "send 1 WCRA 0", "send 1 WCCA 1", "send 1 CDEF"] + ["send 1 CENT %d" % (k % 50) for k in range(255)]
    # (CON 1 is not sent: the table's work after the ticks, masked slices of
    # their own, is the extension scenarios' - perfscen.ext_cost)
    lines += ["send 1 RCSM", "run 20", "send 0 FBX 0", "send 0 FBS %d" % 0xE01110, "run 20", "send 0 FBS 0", "run 5"]
    # position compare armed on a moving axis (the extensions' set-up)
    lines += ["send 1 WPCN 100", "send 1 WPCE %d" % (tg[1] + 100000), "send 1 PCON 1", "run 20", "send 1 PCON 0"]
    # and last the watchdog (4.7) with all four axes moving: <wd> 20 ms, then
    # silence - all axes stop at once (watchdog_fire)
    lines += ["send 3 INIT", "send 3 ME", "send 3 E", "run 20", "send 3 WAP %d" % tg[3], "send 3 MP"]
    lines += ["send %d E" % a for a in AXES] + ["run 20", "send 0 WWD 20", "run 60"]
    lines += ["perf quiet off", "perf report"]
    return "\n".join(lines) + "\n"


def idle(card, ms=1000):
    """The card booted, axes enabled at standstill; the host sending back to back."""
    lines = setup_lines(card) + enable_lines(card) + window_lines(ms, True)
    return "\n".join(lines) + "\n"


def creep(ms=1500):
    """MAC4-STP: four short moves that end in the creep phase (<stc> steps at
    <lv>, each pulse counted by an interrupt, 5.6)."""
    lines = enable_lines("stp") + move_lines("stp", targets("stp", far=False), extra=("WSTC 20", "WLV 100"))
    lines += window_lines(ms, False)
    return "\n".join(lines) + "\n"


def braking(card, ms=300):
    """moving(), then a protective stop of all four axes at once: the stop
    bits of $4600 (3.5.1) while they move at speed.  The tick then brakes
    every axis by itself (motion.c brake_now: <pd> per SP^2 divided into the
    four ticks) until the profile generator takes over at rest: the tick's
    braking path on four axes."""
    lines = moving_start(card) + ["run %d" % MOVING_LEAD_MS[card]] + positions_lines()
    lines += ["perf track on", "perf quiet on", "perf reset", "run 7", "poke16 0x%04X 0x00AA" % board.DP_STOP_BITS,
              "run %d" % ms, "perf quiet off", "perf report"] + positions_lines()
    return "\n".join(lines) + "\n"


SERIAL_TELEGRAMS = 44       # 11 bytes each at 4800 baud: about 1 s of a busy serial line
CHAR_CYCLES = CPU_HZ * 10 // board.UART_BAUD    # one character time (8N1) in cycles: 33 333


def serial(card, ms=1000):
    """moving() with both hosts busy: the VME host back to back and, on the
    front-panel serial line (4800 baud, 3.3), telegrams one after the other
    (RCP, RBS, RFE, RAP on axes 1-4), each answered: the UART interrupt
    (level 4) for every byte received and sent."""
    lines = moving_start(card) + ["run %d" % MOVING_LEAD_MS[card]] + positions_lines()
    lines += ["perf track on", "perf quiet on", "perf reset", "perf host-load on"]
    lines += ["tx-msg %d %s" % (k % 4, ("RCP", "RBS", "RFE", "RAP")[k % 4]) for k in range(SERIAL_TELEGRAMS)]
    lines += ["run %d" % ms, "perf host-load off", "perf quiet off", "perf report", "serial-stats"]
    lines += positions_lines()
    return "\n".join(lines) + "\n"


def serial_stats(r):
    for line in r["lines"]:
        if line.startswith("serial-stats "):
            return {k: num(v) for k, v in KV.findall(line)}
    return {}


def uart_wait(card, uart, mask, tick, pulse):
    """The UART's deadline (docs/performance.md): a received character must
    be read before the next one has arrived, one character time later.  The
    worst until its handler has done so: a main-loop masked section that has
    just begun, the one controller tick that can begin within a character
    time (the period is longer), the STP's creep pulses of four axes at up
    to 1 kHz (three each in a character time, each at the worst cost per
    pulse, pulse_cost) and the handler."""
    pulses = 4 * -(-CHAR_CYCLES // (CPU_HZ // 1000)) if card == "stp" else 0
    return mask + tick + pulses * pulse + uart


def creep_starts(ms=1500):
    """MAC4-STP: four moves of the same length (400 steps, two each way) that
    end in the creep phase, started inside the window: the four start in one
    SP and their creep phases begin in one tick (creep_begin on every axis),
    the STP tick's longest path."""
    lines = enable_lines("stp") + positions_lines() + ["perf track on", "perf quiet on", "perf reset"]
    lines += move_lines("stp", [400, -400, 400, -400], extra=("WSTC 20", "WLV 100"))
    lines += ["run %d" % ms, "perf quiet off", "perf report"] + positions_lines()
    return "\n".join(lines) + "\n"


def pulse_cost(results):
    """What one step pulse of the creep phase costs at worst, cycles: over
    the axis interrupts of the results by the pulses each served (perf-axis
    pulses=J), the worst cost per pulse, max over J of ceil(c_J / J) - an
    interrupt that serves J pulses at once costs c_J for all J, so any
    number P of pulses, however the interrupts group them, costs at most P
    times this.  An axis interrupt that served none (none is expected: the
    index interrupt is never enabled) counts whole, as if for one pulse."""
    per = 0
    for r in results:
        for j, st in r["pulses"].items():
            if st.get("count"):
                per = max(per, -(-st["max"] // max(j, 1)))
    return per


def creep_wait(results):
    """The creep phase's worst wait for a pulse interrupt, over the creep
    scenarios' results (creep(), creep_starts()): a main-loop masked section
    that has just begun, then a controller tick (level 6 outranks the axis
    board's 5), then the pulses of all four axes, each at the worst cost per
    pulse (pulse_cost; "pulse_irq" is the worst interrupt, which may have
    served several).  None if a scenario saw no pulse interrupt."""
    if not all(r["net"].get("axis", {}).get("count") for r in results):
        return None
    w = {"pulse": pulse_cost(results), "pulse_irq": max(r["net"]["axis"]["max"] for r in results),
         "tick": max(worst(r, "timer") or 0 for r in results),
         "mask": max(masked_worst(r) or 0 for r in results)}
    w["need"] = w["mask"] + w["tick"] + 4 * w["pulse"]
    w["hz_four"] = CPU_HZ / w["need"]
    w["hz_one"] = CPU_HZ / (w["mask"] + w["tick"] + w["pulse"])
    w["hz_unmasked"] = CPU_HZ / (w["tick"] + 4 * w["pulse"])
    return w


# Boot (display $1 .. $5, manual 2.5.2): the RAM test and the EPROM check sum
# take nearly all of it.  Not a budget: a guard that the figure
# (docs/performance.md, "Boot") does not creep back.
BOOT_GUARD_MS = 600.0


def boot_ms(card, wait_states=None):
    """Emulated time from reset to display $5 (the card ready), ms."""
    r = run(card, "wait-display 5 3000\nstatus\n", wait_states=wait_states)
    for line in r["lines"]:
        m = re.match(r"status time=([0-9.]+)ms .*display=5", line)
        if m:
            return float(m.group(1))
    return None


# ---- the extensions (docs/extensions.md) switched on for all four axes -----
EXT_PROBE = "ext_slice"
EXT_TABLE = (4, 4)            # rows, columns of each axis' 2-D table (the cost does not depend on the size)


def ext_lines(card, table=True, compare=True, feedback=True):
    """Every extension on, on every axis, in its longest path: a 2-D table
    per axis (row source the axis' actual position, column source the next
    axis' desired position, wrap: always inside a cell), the compare armed
    every 10 counts over the whole travel (two or three points per tick at
    the scenario's speed: an interrupt per axis per tick, own vectors), and
    the conversion table's eight entries on - per axis a tracking filter of
    its measurement and a difference of it with itself, which <fbe> adds
    (0: the full cost, the motion unchanged)."""
    rows, cols = EXT_TABLE
    out = []
    span = 160000
    for a in AXES:
        if table:
            out += ["send %d WCRA %d" % (a, a), "send %d WCCA %d" % (a, (a + 1) % 4), "send %d WCSD 2" % a,
                    "send %d WCRW %d" % (a, rows), "send %d WCCL %d" % (a, cols), "send %d WCRS %d" % (a, span),
                    "send %d WCCS %d" % (a, span), "send %d WCWR 1" % a, "send %d CDEF" % a]
            n = (rows + 1) * (cols + 1) - 1
            out += ["send %d CENT %d" % (a, (7 * k) % 17 - 8) for k in range(1, n + 1)]
            out += ["send %d CON 1" % a]
        if compare:
            lo = -10000000 if card != "ssi" else 0
            out += ["send %d WIRQ7 %d" % (a, 0x70 + a), "send %d WPCP %d" % (a, lo), "send %d WPCN 10" % a,
                    "send %d WPCE 10000000" % a, "send %d PCON 1" % a]
    if feedback:
        for a in AXES:
            out += ["send 0 FBX %d" % (2 * a), "send 0 FBW1 %d" % (1 << 21), "send 0 FBW2 %d" % (1 << 17),
                    "send 0 FBS %d" % (0xB00000 | (0x10 + a)),
                    "send 0 FBX %d" % (2 * a + 1), "send 0 FBS %d" % (0xE20000 | (2 * a) << 8 | (2 * a)),
                    "send %d WFBE %d" % (a, 2 * a + 2)]
    return out


def extensions(card, ms=1000, host_load=True, **which):
    """moving() with the extensions on (ext_lines), the supervision's part
    of them probed."""
    lines = setup_lines(card) + enable_lines(card) + ext_lines(card, **which) + move_lines(card, targets(card))
    lines += window_lines(ms, host_load, probes=(PROFILE_PROBE, EXT_PROBE), lead_ms=MOVING_LEAD_MS[card])
    return "\n".join(lines + EXT_READ_LINES) + "\n"


# After a window: what the firmware charges for what is on (REXB, bits
# 0-15: ext_charged) and its count of late rounds (REXL: ext_late).
EXT_READ_LINES = ["send 0 REXB", "send 0 REXL", "run 10"]


def command_code(mnemonic):
    """A command's code from build/commands.json (firmware/commands.def)."""
    import json
    table = json.load(open(os.path.join(BUILD, "commands.json")))
    return [c["code"] for c in table["commands"] if c["mnemonic"] == mnemonic][0]


def _ext_reads(r, mnemonic):
    head = "resp 0 %d " % command_code(mnemonic)
    vals = [int(l.split()[3], 16) for l in r["lines"] if l.startswith(head)]
    return vals[-1] if vals else None


def ext_charged(r):
    """The cycles per tick firmware/ext.h charges for the extensions on
    (REXB's bits 0-15, read after the window), or None."""
    v = _ext_reads(r, "REXB")
    return None if v is None else v & 0xFFFF


def ext_budget(r):
    """The card's budget (REXB's bits 16-31), or None."""
    v = _ext_reads(r, "REXB")
    return None if v is None else v >> 16


def ext_late(r):
    """REXL after the window: the rounds not done before the next tick."""
    return _ext_reads(r, "REXL")


def ext_cost(r):
    """The extensions' work after each tick (ext_slice, six slices per
    tick): the longest slice, and the cycles per tick of all of them."""
    p = r["probe"].get(EXT_PROBE, {})
    ticks = r["net"].get("timer", {}).get("count")
    if not p.get("count") or not ticks:
        return (None, None)
    return (p.get("max"), round(p["mean"] * p["count"] / ticks))


# Every scenario's script by name, one source for the budget tests and the bench.
SCRIPTS = {
    "moving": moving, "idle": idle, "commands": commands, "whole": whole_moves, "fly": on_the_fly,
    "circular": circular, "full": full_filter, "external": external,
    "external_full": lambda card: external(card, mode=FULL_FILTER), "braking": braking,
    "encoder_loss": encoder_loss, "serial": serial,
    "creep": lambda card: creep(), "creep_starts": lambda card: creep_starts(), "encoder": lambda card: stp_encoder(),
    "ext": extensions, "ext_table": lambda card: extensions(card, compare=False, feedback=False),
    "ext_compare": lambda card: extensions(card, table=False, feedback=False),
    "ext_feedback": lambda card: extensions(card, table=False, compare=False),
}
# The scenarios whose worst tick is the card's worst tick, and those with the
# longest main-loop masked sections (the commands; the profile generator's
# steps, which card_profile_tick runs masked).
TICK_SCENARIOS = {
    "inc": ("moving", "circular", "full", "external", "external_full", "braking", "encoder_loss"),
    "stp": ("moving", "creep", "creep_starts", "braking", "external", "encoder_loss", "encoder"),
}
TICK_SCENARIOS["ssi"] = TICK_SCENARIOS["inc"]
# The extensions on four axes (docs/extensions.md): each alone on every card,
# all at once where the budget (firmware/ext.h) admits them (the STP); on
# INC/SSI the firmware refuses what would exceed it.  They count as tick
# scenarios and their command latency is a deadline too.
EXT_SCENARIOS = {"inc": ("ext_table", "ext_compare", "ext_feedback"),
                 "ssi": ("ext_table", "ext_compare", "ext_feedback"),
                 "stp": ("ext_table", "ext_compare", "ext_feedback", "ext")}
for _c in TICK_SCENARIOS:
    TICK_SCENARIOS[_c] = TICK_SCENARIOS[_c] + EXT_SCENARIOS[_c]
MASKED_SCENARIOS = {"inc": ("commands", "whole", "fly"), "ssi": ("commands", "whole", "fly"),
                    "stp": ("commands", "moving", "creep_starts")}


class Runs:
    """Each scenario run once per card, on first use."""

    def __init__(self, wait_states=None):
        self.done = {}
        self.wait_states = wait_states      # mac4sim --wait-states; None: the defaults

    def get(self, name, card):
        if (name, card) not in self.done:
            self.done[(name, card)] = run(card, SCRIPTS[name](card), wait_states=self.wait_states)
        return self.done[(name, card)]

    def worst_tick(self, card):
        return max(worst(self.get(n, card), "timer") or 0 for n in TICK_SCENARIOS[card])

    def worst_masked(self, card):
        return max(masked_worst(self.get(n, card)) or 0 for n in MASKED_SCENARIOS[card])

    def creep_wait(self):
        return creep_wait([self.get("creep", "stp"), self.get("creep_starts", "stp")])

    def uart_need(self, card):
        """The UART's deadline for card (uart_wait), from the serial scenario's
        handler and the worst figures of all scenarios."""
        w = self.creep_wait() if card == "stp" else None
        return uart_wait(card, worst(self.get("serial", card), "uart") or 0, self.worst_masked(card),
                         self.worst_tick(card), w["pulse"] if w else 0)


PROFILE_SCENARIOS = {"inc": ("moving", "whole", "fly"), "ssi": ("moving", "whole", "fly"), "stp": ("moving",)}


def aims(runs):
    """The aims below the deadlines (docs/performance.md, "Deadlines and
    aims"), each figure beside its aim: a list of rows {name, card,
    scenario, figure, aim, unit, met}.  `make bench` prints them and writes
    them to build/perf.json; no test fails on them."""
    rows = []

    def add(name, card, scenario, figure, aim, unit):
        rows.append({"name": name, "card": card, "scenario": scenario, "figure": figure, "aim": aim,
                     "unit": unit, "met": figure is not None and figure <= aim})
    for card in ("inc", "ssi", "stp"):
        tick_aim = BUDGET_STP_TICK if card == "stp" else BUDGET_SERVO_TICK
        for n in TICK_SCENARIOS[card]:
            add("tick", card, n, worst(runs.get(n, card), "timer"), tick_aim, "cycles")
        prof_aim = BUDGET_STP_PROFILE if card == "stp" else BUDGET_PROFILE_SERVO
        for n in PROFILE_SCENARIOS[card]:
            add("profile_step", card, n, profile_per_period(runs.get(n, card)), prof_aim, "cycles per SP")
        add("masked", card, "+".join(MASKED_SCENARIOS[card]), runs.worst_masked(card),
            PERIOD[card] * BUDGET_MASKED_FRACTION // 100, "cycles")
        add("load", card, "moving", load_percent(runs.get("moving", card)), BUDGET_LOAD_PERCENT, "percent")
    w = runs.creep_wait()
    add("creep_rate", "stp", "creep+creep_starts", None if w is None else round(w["hz_four"]), CREEP_RATE_HZ,
        "Hz on four axes")
    rows[-1]["met"] = w is not None and rows[-1]["figure"] >= CREEP_RATE_HZ      # a rate: at least the aim
    rows[-1]["at_least"] = True
    return rows


def deadlines(runs):
    """The deadlines of tests/timing/test_deadlines.py as figures (for make
    bench; the tests assert them): rows as aims() gives."""
    rows = []

    def add(name, card, figure, limit, unit):
        rows.append({"name": name, "card": card, "figure": figure, "limit": limit, "unit": unit,
                     "met": figure is not None and figure <= limit})
    for card in ("inc", "ssi", "stp"):
        add("tick", card, runs.worst_tick(card), PERIOD[card], "cycles")
        add("masked+tick", card, runs.worst_masked(card) + runs.worst_tick(card), PERIOD[card], "cycles")
        add("uart", card, runs.uart_need(card), CHAR_CYCLES, "cycles")
        add("latency", card, latency_ms(runs.get("moving", card)), BUDGET_LATENCY_MS, "ms")
        add("latency_serial", card, latency_ms(runs.get("serial", card)), BUDGET_LATENCY_MS, "ms")
    add("latency_idle", "inc", latency_ms(runs.get("idle", "inc")), BUDGET_LATENCY_MS, "ms")
    for card in ("inc", "ssi", "stp"):
        for n in EXT_SCENARIOS[card]:
            add("latency_" + n, card, latency_ms(runs.get(n, card)), BUDGET_LATENCY_MS, "ms")
    return rows


def boot_bus(card, wait_states=None):
    """Reset to the display's change to $5 (the card ready), to the cycle of
    that write: {"cycles", "bus": {region: (reads, writes)}, "wait":
    {region: (read clocks, write clocks)}, "contention_clocks": the DPRAM
    accesses' waits for the VME host, "timing": the configuration line,
    "resets"} (`bus-stats display`, harness/buswait.c)."""
    r = run(card, "wait-display 5 3000\nstatus\nbus-stats display\n", wait_states=wait_states)
    out = {"bus": {}, "wait": {}, "cycles": None, "timing": None,
           "resets": sum(1 for l in r["lines"] if l.startswith("reset "))}
    for line in r["lines"]:
        kv = {k: num(v) for k, v in KV.findall(line)}
        parts = line.split()
        if line.startswith("bus-timing "):
            out["timing"] = line
        elif line.startswith("bus-stats cycles="):
            out["cycles"] = kv["cycles"]
        elif line.startswith("bus-stats contention "):
            out["contention_clocks"] = kv["clocks"]
        elif line.startswith("bus-stats ") and "reads" in kv:
            out["bus"][parts[1]] = (kv["reads"], kv["writes"])
            out["wait"][parts[1]] = (kv["wait_read"], kv["wait_write"])
    return out


SENSITIVITY_WAIT_STATES = (0, 1, 2)


def sensitivity(base=None, levels=SENSITIVITY_WAIT_STATES):
    """The deadline figures with N wait states on every region (mac4sim
    --wait-states N) beside the default model's (`base`, a Runs of the
    defaults, or run here): per card and setting the worst tick, the longest
    masked section, the UART's need against its character time and the CPU
    load (moving).  make bench, docs/performance.md."""
    rows = []
    for ws in ("default",) + tuple(levels):
        runs = base if ws == "default" and base is not None else Runs(None if ws == "default" else str(ws))
        for card in ("inc", "ssi", "stp"):
            rows.append({"wait_states": ws, "card": card, "tick": runs.worst_tick(card),
                         "masked": runs.worst_masked(card), "uart_need": runs.uart_need(card),
                         "uart_limit": CHAR_CYCLES, "period": PERIOD[card],
                         "load_percent": load_percent(runs.get("moving", card))})
    return rows


def bus_timing_line(wait_states=None):
    """mac4sim's bus timing configuration line (`bus-stats`)."""
    r = run("inc", "bus-stats\n", wait_states=wait_states)
    return next(l for l in r["lines"] if l.startswith("bus-timing "))


KV = re.compile(r"(\w+)=(\S+)")


def num(v):
    try:
        return int(v)
    except ValueError:
        try:
            return float(v)
        except ValueError:
            return v


def parse(text):
    r = {"irq": {}, "net": {}, "pulses": {}, "probe": {}, "period": {}, "pass": {}, "load": {}, "latency": {}, "stack": None, "mask": {},
         "peeks": [], "faults": [], "lines": text.splitlines()}
    for line in r["lines"]:
        parts = line.split()
        if not parts:
            continue
        tag = parts[0]
        kv = {k: num(v) for k, v in KV.findall(line)}
        if tag == "perf-irq":
            r["irq"][parts[1]] = kv
        elif tag == "perf-net":
            r["net"][parts[1]] = kv
        elif tag == "perf-axis":           # the axis interrupts by pulses served (harness/perf.c)
            r["pulses"][int(parts[1].split("=")[1])] = kv
        elif tag == "perf-probe":
            r["probe"][parts[1]] = kv
        elif tag == "perf-probe-period":
            r["period"][parts[1]] = kv
        elif tag == "perf-pass":
            r["pass"][parts[1]] = kv
        elif tag == "perf-load":
            r["load"] = kv
        elif tag == "perf-mask":
            r["mask"] = kv
        elif tag == "perf-mask-worst":
            r["mask_worst_pc"] = int(kv["pc"], 16)
        elif tag == "perf-latency":
            r["latency"] = kv
        elif tag == "perf-stack":
            r["stack"] = kv.get("deepest_bytes")
        elif tag == "peek32":
            v = int(parts[2], 16)
            r["peeks"].append(v - (1 << 32) if v & 0x80000000 else v)
        elif tag == "fault":
            r["faults"].append(line)
    return r


def run(card, script, binary=SIM, timeout=600, wait_states=None):
    """script on `card`; wait_states: mac4sim's --wait-states (None: the
    defaults of hal/mac4_map.h, docs/memory-map.md "Bus timing")."""
    ws = [] if wait_states is None else ["--wait-states", str(wait_states)]
    p = subprocess.run([binary, "--card", card, "--script", "-", "--allow-faults"] + ws, input=script,
                       capture_output=True, text=True, timeout=timeout)
    if p.returncode != 0:
        raise RuntimeError("mac4sim --card %s failed (%d): %s" % (card, p.returncode, p.stderr[-2000:]))
    r = parse(p.stdout)
    r["stdout"] = p.stdout
    return r


def moved(r):
    """How far each axis went during the window (published positions)."""
    p = r["peeks"]
    if len(p) < 8:
        return [0] * 4
    return [abs(p[4 + a] - p[a]) for a in AXES]


def worst(r, src):
    """The worst occurrence of an interrupt source: exclusive of nested
    interrupts and of the probes (the profile generator) inside it."""
    return r["net"].get(src, {}).get("max", 0) if r["net"].get(src, {}).get("count") else None


def masked_worst(r):
    """The longest main-loop section with interrupts masked (perf mask): no
    interrupt waits longer to be acknowledged (but for level 7)."""
    return r["mask"].get("max") if r["mask"].get("count") else None


def symbol_of(card, pc):
    """The function of the EPROM image that holds address pc."""
    best = None
    for line in open(os.path.join(BUILD, "eprom", "mac4-%s.sym" % card)):
        parts = line.split()
        if len(parts) >= 3 and parts[1] in "tTW":
            a = int(parts[0], 16)
            if a <= pc and (best is None or a > best[0]):
                best = (a, parts[2])
    return best[1] if best else "?"


def timer_latency_worst(r):
    """The tick's latency as measured, timer request to acknowledge."""
    return r["irq"].get("timer", {}).get("lat_max")


def profile_per_period(r, probe=PROFILE_PROBE):
    w = r["period"].get(probe, {})
    return w.get("max", 0) if w.get("count") else None


def load_percent(r):
    return r["load"].get("total")


def latency_ms(r):
    lat = r["latency"]
    return lat["max_us"] / 1000.0 if lat.get("count") else None


def image_bytes(card):
    """Bytes of the 64 KiB EPROM the image uses (vectors, code, constants,
    initial data) and its CRC, from the build's size report."""
    used = None
    for line in open(os.path.join(BUILD, "eprom", "mac4-%s.size.txt" % card)):
        m = re.match(r"\s*used\s+(\d+) bytes", line)
        if m:
            used = int(m.group(1))
    return used


def stack(card):
    import stackdepth
    return stackdepth.analyse(os.path.join(BUILD, "eprom", "mac4-%s.elf" % card),
                              os.path.join(BUILD, "fw-%s" % card),
                              os.path.join(BUILD, "eprom", "mac4-%s.map" % card))


# ---- following error and settling of a standard move (make bench) ----------
# The manual's example configurations of 7.2 (tests/scenarios/, the card and
# the machine), axis 1, one standard move: WPV 100, WPA 10, WPD 10 (10 000
# increments or counts per second), INC 20 000 increments (2.5 output
# revolutions), SSI 5 000 counts (half a turn of the circular axis, no wrap).
# Per servo tick the card's published axis data (`trace 0 FILE tick card`):
# the figures are in emulated time and deterministic.
SCENARIOS = os.path.join(ROOT, "tests", "scenarios")
STANDARD_MOVE = {
    "inc": {"scenario": "inc-7.2.mac4", "target": 20000, "pv": 100, "pa": 10, "pd": 10, "run_ms": 15000},
    "ssi": {"scenario": "ssi-7.2.mac4", "target": 5000, "pv": 100, "pa": 10, "pd": 10, "run_ms": 15000},
}


def standard_move_script(card, trace_path):
    m = STANDARD_MOVE[card]
    lines = ["include %s" % os.path.join(SCENARIOS, m["scenario"]), "send 0 ME", "send 0 E", "run 20",
             "send 0 RTR", "send 0 RTRT", "send 0 WPV %d" % m["pv"], "send 0 WPA %d" % m["pa"],
             "send 0 WPD %d" % m["pd"], "send 0 WAP %d" % m["target"], "send 0 MP", "run 5",
             "trace 0 %s tick card" % trace_path, "send 0 E", "run %d" % m["run_ms"], "trace off",
             "send 0 RBS", "run 5"]
    return "\n".join(lines) + "\n"


POS_END_BIT = 10          # user status (7.1.1, firmware/status.def)


def move_metrics(rows, target, tr):
    """rows: the trace rows (dicts of numbers) from the E on.  Returns the
    figures of docs/performance.md, "Following error and settling":

    * the card-side samples: a row whose card columns differ from the row
      before (the card refreshes an axis' words once per 10 ms profile
      period; the rows between repeat them);
    * the move: from the first sample whose setpoint left the start to the
      first one at the target; max |ferr| and its RMS over those samples;
    * settling: from that sample to the first one after which every sample's
      position is inside <tr> of the target; None if the window ends first;
    * overshoot: the furthest the published position went past the target;
    * pos_end: the first sample with pos_end, from the start of the move."""
    keys = ("card_pos", "setpoint", "ferr", "out", "ustat")
    fresh, last = [], None
    for r in rows:
        k = tuple(r[c] for c in keys)
        if k != last:
            fresh.append(r)
            last = k
    start = fresh[0]["setpoint"]
    sign = 1 if target >= start else -1
    i0 = next((i for i, r in enumerate(fresh) if r["setpoint"] != start), None)
    if i0 is None:
        return None
    i1 = next((i for i in range(i0, len(fresh)) if fresh[i]["setpoint"] == target), None)
    if i1 is None:
        return None
    move = fresh[i0:i1 + 1]
    ferr = [r["ferr"] for r in move]
    rms = (sum(f * f for f in ferr) / len(ferr)) ** 0.5
    settled = None
    for i in range(len(fresh) - 1, i1 - 1, -1):
        if abs(fresh[i]["card_pos"] - target) > tr:
            break
        settled = i
    t0, tsp = fresh[i0]["t_ms"], fresh[i1]["t_ms"]
    pe = next((r["t_ms"] for r in fresh[i0:] if int(r["ustat"]) >> POS_END_BIT & 1), None)
    return {
        "ferr_max": max(abs(f) for f in ferr),
        "ferr_rms": round(rms, 2),
        "ferr_samples": len(ferr),
        "move_ms": round(tsp - t0, 3),
        "settling_ms": None if settled is None else round(fresh[settled]["t_ms"] - tsp, 3),
        "overshoot": max(0, max(sign * (r["card_pos"] - target) for r in fresh[i1:])),
        "pos_end_ms": None if pe is None else round(pe - t0, 3),
        "ferr_max_settling": max(abs(r["ferr"]) for r in fresh[i1:]),
        "final_pos": fresh[-1]["card_pos"],
        "tr": tr,
    }


def read_trace(path):
    import csv
    with open(path) as f:
        return [{k: (int(v, 16) if v.startswith("0x") else float(v) if "." in v else int(v))
                 for k, v in row.items()} for row in csv.DictReader(f)]


def standard_move(card, workdir=BUILD):
    """Run the standard move on the 7.2 example of `card`; its figures."""
    m = STANDARD_MOVE[card]
    path = os.path.join(workdir, "move-std-%s.csv" % card)
    r = run(card, standard_move_script(card, path))
    resp = [l.split() for l in r["lines"] if l.startswith("resp 0 ")]
    tr = next(int(p[3], 16) for p in resp if p[2] == "107")        # RTR
    trt = next(int(p[3], 16) for p in resp if p[2] == "109")       # RTRT
    if any(p[2] in ("162", "163", "164", "165") for p in resp):
        raise RuntimeError("standard move on %s: an error was reported: %s" % (card, resp))
    res = move_metrics(read_trace(path), m["target"], tr)
    if res is None:
        raise RuntimeError("standard move on %s: the setpoint never reached the target" % card)
    res.update({"trt_ms": trt, "move": "7.2 %s example, axis 1: 0 -> %d, WPV %d WPA %d WPD %d"
                % (card.upper(), m["target"], m["pv"], m["pa"], m["pd"]), "trace": os.path.relpath(path, ROOT)})
    return res


# ---- the floor routines (bench/floor/README.md): the hand-written 68000
# sequences of the tick (and of the command path and the supervision), run
# by build/floor/floorrun-CARD on the emulator's CPU and bus model, held bit
# for bit to the firmware's C; make bench sets the firmware's figures
# against them (tick / floor).
FLOOR_DIR = os.path.join(BUILD, "floor")
AIM_FLOOR_RATIO = 1.05        # tick / floor: an aim, make bench only


def floor_run(card, *args, timeout=600):
    """build/floor/floorrun-CARD FLOOR_DIR ARGS: (returncode, stdout, stderr)."""
    p = subprocess.run([os.path.join(FLOOR_DIR, "floorrun-%s" % card), FLOOR_DIR] + list(args),
                       capture_output=True, text=True, timeout=timeout)
    return p.returncode, p.stdout, p.stderr


SUPERVISE_PROBE = "card_supervise_tick"


def supervised(card, name="moving"):
    """A scenario with the supervision after each tick probed
    (card_supervise_tick, main loop): its run, for supervise_worst() and
    command_cycles()."""
    s = SCRIPTS[name](card)
    return run(card, s.replace("perf probe %s" % PROFILE_PROBE,
                               "perf probe %s\nperf probe %s" % (PROFILE_PROBE, SUPERVISE_PROBE), 1))


def supervise_worst(r):
    """The longest supervision after a tick in run r (supervised())."""
    p = r["probe"].get(SUPERVISE_PROBE, {})
    return p.get("max") if p.get("count") else None


def command_cycles(r):
    """Cycles per command in run r (supervised(): the supervision and the
    profile generator probed, so neither is in it): the command passes'
    work beyond the cheapest idle pass (perf load "cmd"), per command pass."""
    ld = r["load"]
    if not ld.get("cmd_passes"):
        return None
    return round(ld["cmd"] / 100.0 * ld["window_ms"] * CPU_HZ / 1000.0 / ld["cmd_passes"])


def floors(card, samples=None):
    """The floor of every scenario the card's routines cover:
    {kind: {scenario: {"cycles", "min", "routine"}}} (kind: tick, supervise,
    command).  Raises if a routine differs from the firmware's C."""
    rc, out, err = floor_run(card, "--measure", *([str(samples)] if samples else []))
    if rc != 0:
        raise RuntimeError("floorrun-%s --measure failed (%d): %s%s" % (card, rc, out[-2000:], err[-2000:]))
    res = {}
    for line in out.splitlines():
        parts = line.split()
        if parts[:1] == ["floor"] and len(parts) >= 4:
            kv = {k: num(v) for k, v in KV.findall(line)}
            res.setdefault(parts[2], {})[parts[3]] = {"cycles": kv["cycles"], "min": kv["min"],
                                                      "routine": kv["routine"]}
    return res
