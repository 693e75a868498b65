"""The emulator's speedups (docs/performance.md, "Emulator speed": the
memory windows, the core's fast loop, the idle skip) change no output: representative scenarios run with
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


def test_addresses_past_16_mb_identical(tmp_path):
    """Addresses whose upper byte is not zero, which the 68000 wraps to 24
    bits: the memory windows (our Musashi patch 0012) test them unmasked, so
    they take the callbacks' way - the same values, cycles and bus counts as
    --no-fast.  A crafted image: SRAM and EPROM data through such addresses,
    then a jump to a PC past 16 MB that goes on in the EPROM; what it read
    lands in the DPRAM for peek32."""
    from conftest import sim as run_sim
    from mac4 import crafted
    sys.path.insert(0, os.path.join(ROOT, "host"))
    from mac4card import board as B
    sram, code, out = B.SRAM_BASE, B.EPROM_BASE + 0x406, 0x5000
    hi = 0xFF000000
    prog = "23FC12345678%08X" % (sram + 0x10)           # move.l #$12345678,SRAM+$10
    prog += "2039%08X" % (hi | sram + 0x10)             # move.l $FF.. SRAM+$10,d0
    prog += "23C0%08X" % out                            # move.l d0,out
    prog += "3239%08X" % (hi | code)                    # move.w $FF.. code,d1 (the EPROM)
    prog += "33C1%08X" % (out + 4)                      # move.w d1,out+4
    after_jmp = code + len(bytes.fromhex(prog)) + 6
    prog += "4EF9%08X" % (hi | after_jmp)               # jmp to the next word, past 16 MB
    prog += "23FCCAFEBABE%08X" % (hi | sram + 0x28)     # move.l #$CAFEBABE,$FF.. SRAM+$28
    prog += "23F9%08X%08X" % (sram + 0x28, out + 8)     # move.l SRAM+$28,out+8
    img = crafted(tmp_path, prog)
    script = "run 5\n" + "".join("peek32 0x%04X\n" % (out + o) for o in (0, 4, 8)) + TAIL
    fast = run_sim(script, img=img)
    slow = run_sim(script, img=img, args=["--no-fast"])
    assert fast.rc == slow.rc == 0, fast.stderr + slow.stderr
    assert fast.peek(out) == 0x12345678
    assert fast.peek(out + 4) >> 16 == int(prog[:4], 16)
    assert fast.peek(out + 8) == 0xCAFEBABE
    assert fast.out == slow.out
