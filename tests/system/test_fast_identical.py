"""The emulator's speedups (docs/performance.md, "Emulator speed": the
memory windows, the idle skip) change no output: representative scenarios run with
them and with `--no-fast`, and every byte of the output - responses,
positions, the interrupt statistics, the bus counts, the profile - compared.
The idle skip's scenarios (perf's instruction hook off, so that it acts) have
things arrive while the card idles: the VME host, a serial telegram, /STOP,
DPRAM pokes; with --timestamps every event's cycle, and --idle-stats shows
that the skip did skip."""
import os
import re
import sys

import pytest

from conftest import ROOT, sim

sys.path.insert(0, os.path.join(ROOT, "tools"))
import bench  # noqa: E402
import perfscen as ps  # noqa: E402

TAIL = "irqstats\nbus-stats\n"


def profiled(card):
    """The profiler on over a move: its cycle figures per function."""
    lines = ps.enable_lines(card) + ["profile on"] + ps.move_lines(card, ps.targets(card))
    lines += ["run 300", "profile off", "profile report 10"]
    return "\n".join(lines) + "\n"


SCENARIOS = {
    "bench": ("inc", lambda: bench.bench_script(3.5)),
    "idle_card": ("inc", lambda: bench.idle_script(1.0)),
    "idle_host": ("ssi", lambda: ps.idle("ssi", 500)),
    "moving_inc": ("inc", lambda: ps.moving("inc", 500)),
    "moving_stp": ("stp", lambda: ps.moving("stp", 500)),
    "commands_ssi": ("ssi", lambda: ps.commands("ssi", 300)),
    "serial_inc": ("inc", lambda: ps.serial("inc", 300)),
    "creep": ("stp", lambda: ps.creep(800)),
    "profile_inc": ("inc", lambda: profiled("inc")),
    # the memory windows charge the wait states of the bus model: with some on
    # the SRAM too (none by default) and more on the EPROM
    "moving_inc_wait_states": ("inc", lambda: ps.moving("inc", 300), ["--wait-states", "sram=1,eprom=2"]),
    "bench_wait_states": ("inc", lambda: bench.bench_script(2.0), ["--wait-states", "sram.read=2,sram.write=1"]),
}


@pytest.mark.parametrize("name", sorted(SCENARIOS))
def test_output_identical_without_speedups(name):
    card, make, *args = SCENARIOS[name]
    args = args[0] if args else []
    script = make() + TAIL
    fast = sim(script, card, args=args, timeout=300)
    slow = sim(script, card, args=args + ["--no-fast"], timeout=300)
    assert fast.rc == slow.rc == 0, fast.stderr + slow.stderr
    assert any(l.startswith("irq source") for l in fast.lines)
    assert any(l.startswith("bus-stats eprom reads=") for l in fast.lines)
    if name == "profile_inc":
        assert any("cycles" in l for l in fast.lines[-40:])
    diff = [(a, b) for a, b in zip(fast.lines, slow.lines) if a != b]
    assert fast.out == slow.out, "first differences (fast, --no-fast): %s" % diff[:5]


def idle_events(card):
    """An idle card (axes enabled at rest, no perf hook) that things reach
    while it idles: host commands, a serial telegram, /STOP, a poke into the
    command queue's memory, a short host-load burst."""
    lines = ps.enable_lines(card) + ["run 200", "status", "bus-stats"]
    lines += ["send 0 RBS", "run 3", "send 1 RCP", "run 97", "status"]          # the VME host during idle
    lines += ["tx-msg 2 RFE", "run 150", "serial-stats", "status"]               # the serial line
    lines += ["estop on", "run 7", "estop off", "run 143", "status"]            # the level-7 interrupt
    lines += ["poke8 0x4700 0x18", "run 50", "poke16 0x7F00 0x1234", "run 50"]  # memory behind the CPU's back
    lines += ["perf host-load on", "run 20", "perf host-load off", "run 180"]
    lines += ["irqstats", "bus-stats", "bus-stats display", "status", "queues"]
    return "\n".join(lines) + "\n"


IDLE_RUNS = {
    "inc": [],
    "ssi": [],
    "stp": [],
    "inc_timestamps": ["--timestamps"],
    "inc_wait_states": ["--wait-states", "2", "--timestamps"],
}


@pytest.mark.parametrize("name", sorted(IDLE_RUNS))
def test_idle_skip_identical(name):
    card = name.split("_")[0]
    args = IDLE_RUNS[name]
    script = idle_events(card)
    fast = sim(script, card, args=args + ["--idle-stats"], timeout=300)
    slow = sim(script, card, args=args + ["--no-fast", "--idle-stats"], timeout=300)
    assert fast.rc == slow.rc == 0, fast.stderr + slow.stderr
    assert any(l.startswith("bus-stats eprom reads=") for l in fast.lines)
    assert any("serial-stats rx_ok=" in l for l in fast.lines)
    diff = [(a, b) for a, b in zip(fast.lines, slow.lines) if a != b]
    assert fast.out == slow.out, "first differences (fast, --no-fast): %s" % diff[:5]
    st = idle_stats(fast.stderr)
    assert st["skips"] > 0 and st["cycles"] > 0, fast.stderr
    assert idle_stats(slow.stderr)["skips"] == 0


def idle_stats(stderr):
    m = re.search(r"idle-skip (.*)", stderr)
    assert m, stderr
    return {k: int(v) for k, v in re.findall(r"(\w+)=(\d+)", m.group(1))}


def test_idle_skip_skips_most_of_an_idle_card():
    """The skip stands for a good part of an idle card's cycles, and none
    while the profiler runs (its instruction hook must see every one)."""
    script = bench.idle_script(1.0)
    r = sim(script, "inc", args=["--idle-stats"])
    total = [int(x.split("=")[1]) for x in r.out.split() if x.startswith("cycles=")][-1]
    st = idle_stats(r.stderr)
    assert st["cycles"] > total // 4, (st, total)
    prof = sim("profile on\n" + script, "inc", args=["--idle-stats"])
    assert idle_stats(prof.stderr)["skips"] == 0
