"""The emulator's speedups (docs/performance.md, "Emulator speed": the fetch
window, the idle skip) change no output: representative scenarios run with
them and with `--no-fast`, and every byte of the output - responses,
positions, the interrupt statistics, the bus counts, the profile - compared."""
import os
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
}


@pytest.mark.parametrize("name", sorted(SCENARIOS))
def test_output_identical_without_speedups(name):
    card, make = SCENARIOS[name]
    script = make() + TAIL
    fast = sim(script, card, timeout=300)
    slow = sim(script, card, args=["--no-fast"], timeout=300)
    assert fast.rc == slow.rc == 0, fast.stderr + slow.stderr
    assert any(l.startswith("irq source") for l in fast.lines)
    assert any(l.startswith("bus-stats eprom reads=") for l in fast.lines)
    if name == "profile_inc":
        assert any("cycles" in l for l in fast.lines[-40:])
    diff = [(a, b) for a, b in zip(fast.lines, slow.lines) if a != b]
    assert fast.out == slow.out, "first differences (fast, --no-fast): %s" % diff[:5]
