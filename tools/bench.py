#!/usr/bin/env python3
"""bench.py - `make bench` (docs/performance.md).

1. Emulator speed (speed_section): a fixed scenario - MAC4-INC, four axes in closed loop
   moving back and forth without a pause, the host polling status back to
   back - for a fixed emulated time, in emulated seconds per wall second;
   in the same run the bare Musashi core (build/mac4bare: the same image, all
   peripherals and plant stubbed to plain memory, the timer interrupt raised
   every 2.5 ms), so the harness overhead is a ratio; and an idle card.
   Both against the stock bare core (build/mac4bare-stock: the same bare
   program on the fetched Musashi without our patches), and mac4sim
   --no-fast beside them, all in the same run, interleaved, in emulated
   seconds per CPU second of the process.
2. The cycle budgets (the scenarios of tools/perfscen.py, as in make timing):
   the cycle table per interrupt source, the aims (figure beside aim) and
   the deadlines of tests/timing (figure beside limit).
3. Image, RAM and worst-case stack per card.
4. A plot of a move: build/move-inc.png (setpoint, position, following
   error, DAC word over time).
5. Following error and settling time of a standard move on the manual's
   example configurations of 7.2, INC and SSI (tools/perfscen.py,
   tests/scenarios/), in emulated time: deterministic figures.
6. Against the floor (bench/floor/README.md): per card and scenario the
   worst tick beside the hand-written routine's cycles for the same path
   on the same CPU and bus model, tick / floor beside its aim.
All figures go to build/perf.json.  A benchmark, never a test: it fails only
when something does not run.
"""
import json
import os
import platform
import resource
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import perfscen as ps  # noqa: E402
import plot  # noqa: E402

SECONDS = float(os.environ.get("BENCH_SECONDS", "20"))
REPEAT = int(os.environ.get("BENCH_REPEAT", "5"))
BARE = os.path.join(ps.BUILD, "mac4bare")
BARE_STOCK = os.path.join(ps.BUILD, "mac4bare-stock")
# BENCH_BASELINE=PATH: another mac4sim (say the build before a change) timed
# in the same run, interleaved, on the same EPROM image: before and after
BASELINE = os.environ.get("BENCH_BASELINE")
# the emulator against the stock bare core (speed_section)
AIM_BENCH_VS_STOCK = 1.5
AIM_IDLE_VS_STOCK = 3.0


def bench_script(seconds):
    lines = ["perf quiet off"] + ps.enable_lines("inc")      # measurement hooks from the start
    v, acc, dec = ps.motion("inc")
    for a in ps.AXES:
        lines += ["send %d WPV %d" % (a, v), "send %d WPA %d" % (a, acc), "send %d WPD %d" % (a, dec)]
    lines += ["perf quiet on", "perf host-load on"]
    t, k = 1.0, 0
    while t < seconds:
        for a in ps.AXES:
            far = (15000 + 2000 * a) * (1 if k % 2 == 0 else -1)
            lines += ["send %d WAP %d" % (a, far), "send %d MP" % a, "send %d E" % a]
        lines.append("run 2500")
        t += 2.5
        k += 1
    lines += ["perf host-load off", "perf quiet off", "status", "perf latency"]
    return "\n".join(lines) + "\n"


def idle_script(seconds):
    """An idle card: the axes enabled at rest, no host traffic."""
    return "\n".join(ps.enable_lines("inc") + ["perf quiet on", "run %d" % int(seconds * 1000),
                                               "perf quiet off", "status"]) + "\n"


def child_cpu(cmd, stdin=None):
    """Runs cmd; returns (stdout, CPU seconds of the child, user + system).
    CPU time rather than wall: the machine is shared, and both sides of a
    ratio are timed the same way, one after the other."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    p = subprocess.run(cmd, input=stdin, capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if p.returncode != 0:
        raise SystemExit("bench: %s failed: %s" % (cmd[0], p.stderr[-2000:]))
    return p.stdout, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def sim_speed(script, extra=(), binary=None):
    """mac4sim on the INC image: (emulated seconds per CPU second, cycles, CPU s)."""
    image = ["--image", os.path.join(ps.BUILD, "eprom", "mac4-inc.bin")] if binary else []
    out, cpu = child_cpu([binary or ps.SIM, "--card", "inc"] + image + list(extra) + ["--script", "-"], script)
    cyc = [int(x.split("=")[1]) for x in out.split() if x.startswith("cycles=")][-1]
    return cyc / ps.CPU_HZ / cpu, cyc, cpu


def bare_speed(binary):
    out, cpu = child_cpu([binary, os.path.join(ps.BUILD, "eprom", "mac4-inc.bin"), str(SECONDS)])
    kv = dict(x.split("=") for x in out.split()[1:])
    return int(kv["cycles"]) / ps.CPU_HZ / cpu, int(kv["cycles"]), cpu


def median(xs):
    xs = sorted(xs)
    n = len(xs)
    return xs[n // 2] if n % 2 else (xs[n // 2 - 1] + xs[n // 2]) / 2


def speed_section():
    """The emulator against the stock bare core (build/mac4bare-stock: the
    bare-core program on the fetched Musashi without our patches), all
    timed in this run, interleaved, REPEAT times; each ratio is the median
    of the ratios of one repeat (so a load change between repeats cancels).
    mac4sim --no-fast beside it: the same emulator with every speedup off."""
    kinds = [("bench", lambda: sim_speed(bench_script(SECONDS))),
             ("bench_no_fast", lambda: sim_speed(bench_script(SECONDS), ["--no-fast"])),
             ("idle", lambda: sim_speed(idle_script(SECONDS))),
             ("idle_no_fast", lambda: sim_speed(idle_script(SECONDS), ["--no-fast"])),
             ("bare", lambda: bare_speed(BARE)),
             ("stock", lambda: bare_speed(BARE_STOCK))]
    if BASELINE:
        kinds += [("bench_baseline", lambda: sim_speed(bench_script(SECONDS), binary=BASELINE)),
                  ("idle_baseline", lambda: sim_speed(idle_script(SECONDS), binary=BASELINE))]
    runs = {k: [] for k, _ in kinds}
    for _ in range(REPEAT):          # alternate, so all see the same machine load
        for k, f in kinds:
            runs[k].append(f())
    speed = {k: median([r[0] for r in v]) for k, v in runs.items()}
    ratio = {k: median([runs[k][i][0] / runs["stock"][i][0] for i in range(REPEAT)])
             for k in runs if k != "stock"}
    return speed, ratio, runs


def machine():
    model = platform.processor() or "?"
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return {"nproc": os.cpu_count(), "cpu": model, "python": platform.python_version(),
            "system": platform.platform()}


def plot_move(path_png):
    csvp = os.path.join(ps.BUILD, "move-inc.csv")
    tracep = os.path.join(ps.BUILD, "move-inc-a0.csv")      # the position at every tick (tools/plot.py)
    lines = ps.enable_lines("inc")
    lines += ["send 0 WPV 100", "send 0 WPA 10", "send 0 WPD 10", "send 0 WAP 8000", "send 0 MP",
              "perf sample %s 0" % csvp, "trace 0 %s tick card" % tracep, "send 0 E", "run 1300",
              "perf sample off", "trace off"]
    ps.run("inc", "\n".join(lines) + "\n")
    plot.plot({0: tracep}, path_png, "MAC4-INC axis 1 (emulated): WAP 8000 WPV 100 WPA 10 WPD 10, default plant")


def print_rows(rows, limit):
    """A table of perfscen.aims()/deadlines() rows: figure beside aim or limit."""
    for r in rows:
        fig = "-" if r["figure"] is None else ("%.2f" % r["figure"] if isinstance(r["figure"], float)
                                               else "%d" % r["figure"])
        scen = (" (%s)" % r["scenario"]) if r.get("scenario") else ""
        print("  %-13s MAC4-%s%-40s %10s  %s %-8s %-16s %s" % (
            r["name"], r["card"].upper(), scen, fig, limit + (" >=" if r.get("at_least") else ""), r[limit],
            r["unit"], "met" if r["met"] else "NOT MET"))


def floor_section(runs):
    """tick / floor per card and scenario of perfscen.TICK_SCENARIOS (the
    firmware's worst tick of the scenario over the floor routine's cycles
    for its path, both under the default bus model): rows and the ratios
    {card: {scenario: ratio}}.  A scenario without a floor routine is a
    row without a ratio."""
    rows, ratios = [], {}
    for card in ("inc", "ssi", "stp"):
        have = os.path.exists(os.path.join(ps.FLOOR_DIR, "floorrun-%s" % card))
        fl = ps.floors(card) if have else {}
        for name in ps.TICK_SCENARIOS[card]:
            tick = ps.worst(runs.get(name, card), "timer")
            f = fl.get("tick", {}).get(name)
            ratio = round(tick / f["cycles"], 3) if f and tick else None
            rows.append({"card": card, "scenario": name, "tick": tick, "floor": f["cycles"] if f else None,
                         "routine": f["routine"] if f else None, "ratio": ratio})
            if ratio is not None:
                ratios.setdefault(card, {})[name] = ratio
    return rows, ratios


def supervise_floor_section():
    """The supervision after each tick (card_supervise_tick, probed in
    "moving": its worst) and the command path (cycles per command beyond an
    idle pass, the host sending back to back) over their floor routines:
    (rows, {card: {scenario: ratio}}) for each."""
    sup_rows, sup_ratio, cmd_rows, cmd_ratio = [], {}, [], {}
    for card in ("inc", "ssi", "stp"):
        have = os.path.exists(os.path.join(ps.FLOOR_DIR, "floorrun-%s" % card))
        fl = ps.floors(card) if have else {}
        r = ps.supervised(card)
        for kind, fig, rows, ratios in (("supervise", ps.supervise_worst(r), sup_rows, sup_ratio),
                                        ("command", ps.command_cycles(r), cmd_rows, cmd_ratio)):
            f = fl.get(kind, {}).get("moving")
            ratio = round(fig / f["cycles"], 3) if f and fig else None
            rows.append({"card": card, "scenario": "moving", kind: fig, "floor": f["cycles"] if f else None,
                         "routine": f["routine"] if f else None, "ratio": ratio})
            if ratio is not None:
                ratios.setdefault(card, {})["moving"] = ratio
    return sup_rows, sup_ratio, cmd_rows, cmd_ratio


def print_floor_rows(rows, key):
    print("  %-8s %-14s %7s %7s %7s  %-5s %-8s %s" % ("card", "scenario", key, "floor", "ratio", "aim", "", "routine"))
    for r in rows:
        if r["ratio"] is None:
            print("  MAC4-%-3s %-14s %7s %7s %7s  %-5s %-8s" % (r["card"].upper(), r["scenario"], r[key] or "-",
                                                           "-", "-", "", "no floor"))
            continue
        print("  MAC4-%-3s %-14s %7d %7d %7.2f  %-5.2f %-8s %s" % (
            r["card"].upper(), r["scenario"], r[key], r["floor"], r["ratio"], ps.AIM_FLOOR_RATIO,
            "met" if r["ratio"] <= ps.AIM_FLOOR_RATIO else "NOT MET", r["routine"]))


def main():
    for f in (ps.SIM, BARE, BARE_STOCK):
        if not os.path.exists(f):
            raise SystemExit("bench: build %s first (make all build/mac4bare build/mac4bare-stock)" % f)
    mach = machine()
    print("== machine: %s, %d CPUs, %s" % (mach["cpu"], mach["nproc"], mach["system"]))

    print("== emulator speed: %.0f s emulated, %d runs of each, interleaved; emulated s per CPU s, median"
          % (SECONDS, REPEAT))
    speed, ratio, _ = speed_section()
    labels = {"bench": "mac4sim  INC, 4 axes moving, host polling",
              "bench_no_fast": "mac4sim  the same, --no-fast",
              "idle": "mac4sim  INC, axes enabled at rest, no host",
              "idle_no_fast": "mac4sim  the same, --no-fast",
              "bare": "mac4bare the same image, plain memory",
              "stock": "mac4bare-stock, unpatched Musashi",
              "bench_baseline": "BENCH_BASELINE, the bench scenario",
              "idle_baseline": "BENCH_BASELINE, the idle card"}
    for k, label in labels.items():
        if k not in speed:
            continue
        vs = "" if k == "stock" else "  %.2fx the stock bare core" % ratio[k]
        print("  %-46s %8.1f x real time%s" % (label, speed[k], vs))
    full, bare = speed["bench"], speed["bare"]
    print("  bench against the stock bare core %.2fx (aim >= %.1fx: %s); idle card %.2fx (aim >= %.1fx: %s)"
          % (ratio["bench"], AIM_BENCH_VS_STOCK, "met" if ratio["bench"] >= AIM_BENCH_VS_STOCK else "NOT MET",
             ratio["idle"], AIM_IDLE_VS_STOCK, "met" if ratio["idle"] >= AIM_IDLE_VS_STOCK else "NOT MET"))
    print("  harness overhead %.2fx (aim < 2x); real time %.0fx (aim >= 50x)" % (bare / full, full))

    print("== cycle budgets (emulated, deterministic)")
    runs = ps.Runs()          # the scenarios of tests/timing, each run once
    res = {card: runs.get("moving", card) for card in ("inc", "ssi", "stp")}
    res["idle"] = runs.get("idle", "inc")
    cmds = {card: runs.get("commands", card) for card in ("inc", "ssi", "stp")}
    whole = {card: runs.get("whole", card) for card in ("inc", "ssi")}
    fly = {card: runs.get("fly", card) for card in ("inc", "ssi")}
    ffil = {card: runs.get("full", card) for card in ("inc", "ssi")}
    extf = {card: runs.get("external_full", card) for card in ("inc", "ssi")}
    brk = {card: runs.get("braking", card) for card in ("inc", "ssi")}
    lost = {card: runs.get("encoder_loss", card) for card in ("inc", "ssi")}
    res["creep"] = runs.get("creep", "stp")
    res["creep_starts"] = runs.get("creep_starts", "stp")
    for card in ("inc", "ssi", "stp"):
        print("-- MAC4-%s, four axes positioning, host sending back to back (moved %s)"
              % (card.upper(), ps.moved(res[card])))
        out = res[card]["stdout"].splitlines()
        i = next(k for k, l in enumerate(out) if l.startswith("cycles at"))
        for l in out[i:]:
            if not l.startswith("  ") and not l.startswith("cycles at"):
                break
            print("  " + l)
    w = runs.creep_wait()
    if w:
        creep = ("a pulse costs %d cycles at worst (the worst interrupt %d, serving several); with a tick of %d "
                 "and a masked section of %d: %.0f Hz on four axes, %.0f Hz on one (%.0f Hz on four without the "
                 "masked section)" % (w["pulse"], w["pulse_irq"], w["tick"], w["mask"], w["hz_four"], w["hz_one"],
                                      w["hz_unmasked"]))
    else:
        creep = "no pulse-count interrupts seen in the creep scenarios (moved %s, %s)" % (
            ps.moved(res["creep"]), ps.moved(res["creep_starts"]))
    stp_ticks = {n: ps.worst(runs.get(n, "stp"), "timer") for n in ps.TICK_SCENARIOS["stp"]}
    print("-- MAC4-STP controller tick worst: %s (aim %d)"
          % (", ".join("%d %s" % (v or 0, n) for n, v in stp_ticks.items()), ps.BUDGET_STP_TICK))
    print("-- MAC4-STP creep phase: " + creep)
    for card in ("inc", "ssi"):
        print("-- MAC4-%s servo tick, four axes moving: %d cycles with the default K-only gains, %d on circular "
              "axes with every filter term and <sw> (perfscen.full_filter), %d so with external VME encoders "
              "(perfscen.external), %d with four axes braking at once (perfscen.braking), %d with four external "
              "encoders failing at once (perfscen.encoder_loss); aim %d" % (
                  card.upper(), ps.worst(res[card], "timer") or 0, ps.worst(ffil[card], "timer") or 0,
                  ps.worst(extf[card], "timer") or 0, ps.worst(brk[card], "timer") or 0,
                  ps.worst(lost[card], "timer") or 0, ps.BUDGET_SERVO_TICK))
    for card in ("inc", "ssi"):
        print("-- MAC4-%s profile generator, worst SP: %d cycles over whole moves (four axes braking at once), "
              "%d changing course on the fly (aim %d)" % (card.upper(), ps.profile_per_period(whole[card]) or 0,
                                                             ps.profile_per_period(fly[card]) or 0,
                                                             ps.BUDGET_PROFILE_SERVO))
    for card in ("inc", "ssi", "stp"):
        pc = cmds[card].get("mask_worst_pc")
        print("-- MAC4-%s, three axes moving, the host sending E with new targets, INIT/DEINIT and every command: "
              "longest masked section %d cycles, from %s (bound of the tick's latency; measured %d), aim %d"
              % (card.upper(), ps.masked_worst(cmds[card]) or 0,
                 "?" if pc is None else "$%06X in %s" % (pc, ps.symbol_of(card, pc)),
                 ps.timer_latency_worst(cmds[card]) or 0, ps.PERIOD[card] // 10))
    print("-- MAC4-INC idle card (axes enabled at rest), host back to back: latency max %.2f ms, mean %.2f ms"
          % (ps.latency_ms(res["idle"]) or 0, res["idle"]["latency"].get("mean_us", 0) / 1000.0))

    # the UART's deadline: one character time at 4800 baud, both hosts busy
    ser = {card: runs.get("serial", card) for card in ("inc", "ssi", "stp")}
    uart_need = {}
    for card in ("inc", "ssi", "stp"):
        uart = ps.worst(ser[card], "uart") or 0
        uart_need[card] = runs.uart_need(card)     # the same bound as tests/timing
        st = ps.serial_stats(ser[card])
        print("-- MAC4-%s serial line busy (%d telegrams, %d answered, %d overruns) and the VME host back to back: "
              "UART interrupt worst %d cycles; its deadline, one character at 4800 baud: %d of %d cycles "
              "(masked section, tick, creep pulses, handler); CPU load %.1f%%, latency max %.2f ms"
              % (card.upper(), ps.SERIAL_TELEGRAMS, st.get("tx_ok", 0), st.get("overruns", 0), uart,
                 uart_need[card], ps.CHAR_CYCLES, ps.load_percent(ser[card]) or 0, ps.latency_ms(ser[card]) or 0))

    print("== the extensions on four axes (docs/extensions.md; perfscen.EXT_SCENARIOS): worst tick, "
          "their work after the ticks (longest slice, cycles per tick), command latency")
    exts = {}
    for card, names in ps.EXT_SCENARIOS.items():
        for name in names:
            r = runs.get(name, card)
            slice_max, per_tick = ps.ext_cost(r)
            e = exts.setdefault(card, {})[name] = {
                "tick_worst_cycles": ps.worst(r, "timer"), "slice_max_cycles": slice_max,
                "cycles_per_tick": per_tick, "command_latency_ms": ps.latency_ms(r)}
            print("  MAC4-%s %-13s tick %6d  slice %6d  per tick %6d  latency %.2f ms (limit %.1f)"
                  % (card.upper(), name, e["tick_worst_cycles"] or 0, slice_max or 0, per_tick or 0,
                     e["command_latency_ms"] or 0, ps.BUDGET_LATENCY_MS))
    aims, dls = ps.aims(runs), ps.deadlines(runs)
    print("== aims (figure beside aim; make bench only, never a test)")
    print_rows(aims, "aim")
    print("== deadlines (figure beside limit; tests/timing/test_deadlines.py asserts them)")
    print_rows(dls, "limit")

    print("== sensitivity to the bus: the same scenarios with N wait states on every region "
          "(mac4sim --wait-states N) beside the default model (%s)" % ps.bus_timing_line())
    sens = ps.sensitivity(base=runs)
    print("  %-8s %-9s %11s %13s %22s %9s" % ("card", "wait", "worst tick", "longest mask", "UART need / 33333",
                                            "load %"))
    for r in sens:
        print("  MAC4-%-3s %-9s %11d %13d %14d %-7s %9.1f" % (
            r["card"].upper(), r["wait_states"], r["tick"], r["masked"], r["uart_need"],
            "ok" if r["uart_need"] <= r["uart_limit"] else "MISSED", r["load_percent"] or 0))

    print("== against the floor (bench/floor/README.md): the worst tick of each scenario over the floor "
          "routine's cycles for its path, four axes, the SP boundary's tick, the same CPU and bus model; "
          "aim <= %.2f" % ps.AIM_FLOOR_RATIO)
    floor_rows, floor_ratio = floor_section(runs)
    print_floor_rows(floor_rows, "tick")
    sup_rows, sup_ratio, cmd_rows, cmd_ratio = supervise_floor_section()
    print("-- the supervision after each tick (card_supervise_tick, probed, its worst; four axes positioning)")
    print_floor_rows(sup_rows, "supervise")
    print("-- the command path: cycles per command beyond an idle pass (the host's reads back to back)")
    print_floor_rows(cmd_rows, "command")

    boot = {card: ps.boot_ms(card) for card in ("inc", "ssi", "stp")}
    print("-- boot, reset to display $5 (RAM test, EPROM check sum): %s"
          % ", ".join("MAC4-%s %.0f ms" % (c.upper(), boot[c] or 0) for c in boot))

    print("== memory")
    images, stacks = {}, {}
    for card in ("inc", "ssi", "stp"):
        images[card] = ps.image_bytes(card)
        stacks[card] = ps.stack(card)
        st = stacks[card]
        print("  MAC4-%s image %5d of 65536 bytes; RAM data+bss %d + stack %d (main %d, levels 4-7 %s) = %d of 16384"
              % (card.upper(), images[card], st["ram_bytes"], st["stack_bytes"], st["main_bytes"],
                 "/".join(str(v["bytes"]) for v in st["isr"].values()), st["ram_stack_bytes"]))

    print("== following error and settling, standard move (emulated time, deterministic)")
    moves = {}
    for card in ("inc", "ssi"):
        m = moves[card] = ps.standard_move(card)
        unit = "Inc" if card == "inc" else "counts"
        settle = "not settled in the window" if m["settling_ms"] is None else "%.0f ms" % m["settling_ms"]
        print("  MAC4-%s %s" % (card.upper(), m["move"]))
        print("    following error while the setpoint moves (%.0f ms, %d samples): max |ferr| %d %s, RMS %.1f %s"
              % (m["move_ms"], m["ferr_samples"], m["ferr_max"], unit, m["ferr_rms"], unit))
        print("    settling into <tr> = %d after the setpoint reached the target: %s; overshoot %d %s; "
              "pos_end %s ms after the start" % (m["tr"], settle, m["overshoot"], unit,
                                                  "-" if m["pos_end_ms"] is None else "%.0f" % m["pos_end_ms"]))

    png = os.path.join(ps.BUILD, "move-inc.png")
    plot_move(png)
    print("== plot of a move: %s" % os.path.relpath(png, ps.ROOT))

    inc = res["inc"]
    perf = {
        # the worst tick of all the card's scenarios (perfscen.TICK_SCENARIOS)
        "servo_tick_worst_cycles": runs.worst_tick("inc"),          # over perfscen.TICK_SCENARIOS
        "servo_tick_worst_cycles_ssi": runs.worst_tick("ssi"),
        "servo_tick_worst_cycles_external_full_filter": {c: ps.worst(extf[c], "timer") for c in extf},
        "servo_tick_worst_cycles_k_only": {c: ps.worst(res[c], "timer") for c in ("inc", "ssi")},
        "servo_tick_worst_cycles_full_filter": {c: ps.worst(ffil[c], "timer") for c in ffil},
        "servo_tick_worst_cycles_braking": {c: ps.worst(brk[c], "timer") for c in ("inc", "ssi")},
        "servo_tick_worst_cycles_encoder_loss": {c: ps.worst(lost[c], "timer") for c in ("inc", "ssi")},
        # the worst SP of the scenarios: cruising, whole moves, course changes on the fly
        "profile_tick_worst_cycles": max(ps.profile_per_period(r) or 0 for r in (inc, whole["inc"], fly["inc"])),
        "profile_tick_worst_cycles_ssi": max(ps.profile_per_period(r) or 0
                                             for r in (res["ssi"], whole["ssi"], fly["ssi"])),
        "profile_tick_worst_cycles_cruising": {c: ps.profile_per_period(res[c]) for c in ("inc", "ssi")},
        # the worst of four axes positioning, four moves starting, four creep phases beginning
        "stp_tick_worst_cycles": runs.worst_tick("stp"),
        "stp_tick_worst_cycles_per_scenario": stp_ticks,
        "stp_profile_worst_cycles": ps.profile_per_period(res["stp"]),
        "stp_pulse_irq_worst_cycles": w["pulse_irq"] if w else None,
        "stp_pulse_cost_cycles": w["pulse"] if w else None,
        "stp_creep_hz_four_axes": round(w["hz_four"]) if w else None,
        "profile_tick_worst_cycles_whole_moves": {c: ps.profile_per_period(whole[c]) for c in whole},
        "profile_tick_worst_cycles_on_the_fly": {c: ps.profile_per_period(fly[c]) for c in fly},
        "masked_section_worst_cycles": {c: ps.masked_worst(cmds[c]) for c in cmds},
        "timer_latency_worst_cycles": {c: ps.timer_latency_worst(cmds[c]) for c in cmds},
        "cpu_load_percent": ps.load_percent(inc),
        "cpu_load_breakdown_percent": {k: inc["load"].get(k) for k in ("isr", "main", "cmd", "profile")},
        "command_latency_ms": ps.latency_ms(inc),
        "command_latency_ms_per_card": {c: ps.latency_ms(res[c]) for c in ("inc", "ssi", "stp")},
        "command_latency_idle_ms": ps.latency_ms(res["idle"]),
        "emulated_per_wall": round(full, 2),
        "bare_emulated_per_wall": round(bare, 2),
        "harness_overhead_ratio": round(bare / full, 3),
        "emulator_speed": {"emulated_per_cpu_s": {k: round(v, 2) for k, v in speed.items()},
                           "vs_stock_bare": {k: round(v, 3) for k, v in ratio.items()},
                           "aim_bench_vs_stock": AIM_BENCH_VS_STOCK, "aim_idle_vs_stock": AIM_IDLE_VS_STOCK,
                           "met": {"bench": ratio["bench"] >= AIM_BENCH_VS_STOCK,
                                   "idle": ratio["idle"] >= AIM_IDLE_VS_STOCK}},
        "boot_ms": boot,
        "uart_irq_worst_cycles": {c: ps.worst(ser[c], "uart") for c in ser},
        "uart_deadline_need_cycles": uart_need,
        "uart_deadline_cycles": ps.CHAR_CYCLES,
        "cpu_load_percent_both_hosts": {c: ps.load_percent(ser[c]) for c in ser},
        "image_bytes": images,
        "ram_stack_bytes": max(s["ram_stack_bytes"] for s in stacks.values()),
        "ram_stack_bytes_per_card": {c: s["ram_stack_bytes"] for c, s in stacks.items()},
        "stack_bytes_per_card": {c: s["stack_bytes"] for c, s in stacks.items()},
        "moved_in_window": {c: ps.moved(res[c]) for c in ("inc", "ssi", "stp")},
        "aims": aims,
        # tick / floor (bench/floor/README.md): {card: {scenario: ratio}}, and the figures
        "tick_floor_ratio": floor_ratio,
        "tick_floor": floor_rows,
        "supervise_floor_ratio": sup_ratio,
        "supervise_floor": sup_rows,
        "command_floor_ratio": cmd_ratio,
        "command_floor": cmd_rows,
        "aim_floor_ratio": ps.AIM_FLOOR_RATIO,
        "extensions": exts,
        "bus_model": ps.bus_timing_line(),
        "sensitivity": sens,
        "boot_ms_no_wait_states": {c: ps.boot_ms(c, "0") for c in ("inc", "ssi", "stp")},
        "deadlines": dls,
        "budgets": {"servo_tick_cycles": ps.BUDGET_SERVO_TICK, "profile_cycles_per_10ms": ps.BUDGET_PROFILE_SERVO,
                    "stp_tick_cycles": ps.BUDGET_STP_TICK, "stp_profile_cycles_per_32ms": ps.BUDGET_STP_PROFILE,
                    "cpu_load_percent": ps.BUDGET_LOAD_PERCENT, "command_latency_ms": ps.BUDGET_LATENCY_MS,
                    "image_bytes": ps.BUDGET_IMAGE_BYTES, "ram_stack_bytes": ps.BUDGET_RAM_STACK_BYTES},
        "following_error_max": moves["inc"]["ferr_max"],
        "following_error_max_ssi": moves["ssi"]["ferr_max"],
        "following_error_rms": moves["inc"]["ferr_rms"],
        "following_error_rms_ssi": moves["ssi"]["ferr_rms"],
        "settling_time_ms": moves["inc"]["settling_ms"],
        "settling_time_ms_ssi": moves["ssi"]["settling_ms"],
        "standard_move": moves,
        "bench_seconds": SECONDS,
        "machine": mach,
        "plot": os.path.relpath(png, ps.ROOT),
    }
    with open(os.path.join(ps.BUILD, "perf.json"), "w") as f:
        json.dump(perf, f, indent=1, sort_keys=True)
    print("== build/perf.json written")
    return 0


if __name__ == "__main__":
    sys.exit(main())
