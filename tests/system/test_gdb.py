"""The gdb stub (docs/debugging.md): gdb-multiarch itself, in batch mode,
against `mac4sim --gdb 0` on each card: a breakpoint at fw_isr_tick, bt with
file and line, registers, a line stepped, an axis' state read, memory
written, the next tick; the EPROM never written; emulated time standing
still while the CPU is stopped; and a run with stops equal, line for line,
to the run without."""
import os
import re
import select
import shutil
import subprocess
import tempfile
import time

import pytest

from conftest import BUILD, CARDS, SIM
from mac4 import CMDQ, TICK_MS, board, qh

GDB = shutil.which("gdb-multiarch")
pytestmark = pytest.mark.skipif(GDB is None, reason="gdb-multiarch missing (tools/deps/apt.txt)")


def elf(card):
    return os.path.join(BUILD, "eprom", "mac4-%s.elf" % card)


def symbol(card, name):
    out = subprocess.run(["m68k-linux-gnu-nm", elf(card)], capture_output=True, text=True, check=True).stdout
    for line in out.splitlines():
        a, _, n = line.split()
        if n == name:
            return int(a, 16)
    raise KeyError(name)


def debug(card, script, gdb_cmds, extra_args=(), timeout=90):
    """Run mac4sim --gdb 0 with `script`, gdb-multiarch -batch with
    gdb_cmds against it; both bounded in time and stopped.  Returns
    (mac4sim stdout lines, gdb output)."""
    with tempfile.NamedTemporaryFile("w", suffix=".mac4", delete=False) as f:
        f.write(script)
    sim = subprocess.Popen([SIM, "--card", card, "--gdb", "0", "--script", f.name] + list(extra_args),
                           stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        first = sim.stdout.readline()
        m = re.match(r"gdb-port (\d+)$", first.strip())
        assert m, "first line %r, stderr %s" % (first, sim.stderr.read())
        cmds = ["set pagination off", "set confirm off", "target remote 127.0.0.1:%s" % m.group(1)] + gdb_cmds
        args = [GDB, "-nx", "-batch", elf(card)]
        for c in cmds:
            args += ["-ex", c]
        g = subprocess.run(args, capture_output=True, text=True, timeout=timeout)
        out, err = sim.communicate(timeout=timeout)
        assert sim.returncode == 0, err
        return [first.strip()] + out.splitlines(), g.stdout + g.stderr
    finally:
        os.unlink(f.name)
        if sim.poll() is None:
            sim.kill()
            sim.wait()


@pytest.mark.parametrize("card", CARDS)
def test_batch_session(card):
    tick = symbol(card, "fw_isr_tick")
    lines, g = debug(card, "run 800\nstatus\n", [
        "break fw_isr_tick",
        "continue",
        "monitor time",     # at the breakpoint, as the second: one period apart, not less the `next`
        "bt",
        "info registers",
        "print/x $pc",
        "next",
        "print/x $pc",
        "print axes[0].mode",
        "print axes[1].ustat",
        "print card_ticks",
        "set var card_ticks = 1000",
        "print card_ticks + 0",
        "continue",
        "print card_ticks",
        "monitor time",
        "delete",
        "detach",
    ])
    # stopped at the breakpoint, the backtrace with file and line; the tick is the servo
    # cards' or the stepper's file (docs/firmware.md), entered from the timer's vector
    # directly (HAL_ISR): the frame below it is the 68000's exception frame, which gdb
    # does not unwind (docs/debugging.md)
    src = "tick_stp" if card == "stp" else "tick_servo"
    assert re.search(r"Breakpoint 1, fw_isr_tick \(\) at firmware/%s\.c:\d+" % src, g), g
    assert re.search(r"#0\s+fw_isr_tick \(\) at firmware/%s\.c:\d+" % src, g), g
    # info registers: all 18, the PC at the function's first instruction (nothing of it ran)
    for r in ("d0", "d7", "a0", "fp", "sp", "ps", "pc"):
        assert re.search(r"^%s\s+0x[0-9a-f]+" % r, g, re.M), (r, g)
    pcs = [int(x, 16) for x in re.findall(r"^\$\d+ = (0x[0-9a-f]+)$", g, re.M)]
    assert pcs[0] == tick and pcs[1] > tick, (hex(tick), pcs)
    # the axis' state read from SRAM: axis 1 disabled after reset (mode 0)
    assert re.search(r"^\$\d+ = 0 '\\000'$", g, re.M), g
    # memory written, and the next tick counts on from it
    assert "= 1000" in g and re.search(r"^\$\d+ = 1001$", g, re.M), g
    times = [float(x) for x in re.findall(r"^time ([0-9.]+) ms", g, re.M)]
    period = TICK_MS[card]
    assert len(times) == 2 and abs(times[1] - times[0] - period) < 0.01, times
    assert "detached" in g
    assert any(l.startswith("status time=800.0") for l in lines), lines   # the script ran on


def test_time_stands_still_and_eprom_is_not_written():
    lines, g = debug("inc", "run 700\nstatus\n", [
        "break fw_isr_tick",
        "hbreak fw_main_step",
        "continue",
        "monitor time",
        "shell sleep 0.3",
        "monitor time",
        "compare-sections .vectors",
        "compare-sections .text",
        "set {short}fw_isr_tick = 0x4e71",
        "x/2xb fw_isr_tick",
        "info breakpoints",
        "delete",
        "detach",
    ])
    times = re.findall(r"^time ([0-9.]+) ms cycles (\d+)", g, re.M)
    assert len(times) == 2 and times[0] == times[1], times          # no model ran while stopped
    assert re.search(r"Section \.vectors, range .*: matched", g), g
    assert re.search(r"Section \.text, range .*: matched", g), g      # breakpoints not in the EPROM
    assert "Cannot access memory at address" in g, g                   # the EPROM is read-only
    code = open(os.path.join(BUILD, "eprom", "mac4-inc.bin"), "rb").read()
    first = code[symbol("inc", "fw_isr_tick") - board.EPROM_BASE:][:2]
    assert re.search(r":\s+0x%02x\s+0x%02x" % (first[0], first[1]), g), g


SCENARIO = """wait-display 5 3000
send 0 INIT
send 0 ME
send 0 E
run 50
send 0 WPV 100
send 0 WPA 10
send 0 WPD 10
send 0 WAP 4000
send 0 MP
tx-msg 0 RFE
send 0 E
run 300
send 0 RCP
run 5
irqstats
perf irq
perf latency
plant 0
status
"""


# Breakpoint stops and steps in the tick, a watchpoint, stops in cmd_execute.
STOPS = (["break fw_isr_tick"] + ["continue", "stepi", "next"] * 8 +
         ["delete", "watch card_ticks", "continue", "continue", "delete",
          "break cmd_execute", "continue", "continue", "delete"])


def test_stops_do_not_change_the_run():
    """Breakpoints, steps, a watchpoint and Ctrl-C-free continues: the card's
    output and cycle counts equal those of the run without gdb."""
    ref = subprocess.run([SIM, "--card", "inc", "--timestamps", "--script", "-"], input=SCENARIO, capture_output=True,
                         text=True, timeout=60)
    assert ref.returncode == 0, ref.stderr
    cmds = STOPS + ["stepi 20000",        # every instruction its own stop, ISRs and commands included
                    "detach"]
    lines, g = debug("inc", SCENARIO, cmds, extra_args=["--timestamps"])
    assert g.count("Breakpoint 1, fw_isr_tick") == 8, g
    assert "Hardware watchpoint" in g and "New value" in g, g
    assert "cmd_execute" in g, g
    assert lines[0].startswith("gdb-port ")
    assert lines[1:] == ref.stdout.splitlines()


class MI:
    """gdb-multiarch over its machine interface, for what batch mode cannot
    do: interrupt a running target (Ctrl-C, -exec-interrupt)."""

    def __init__(self, card):
        self.p = subprocess.Popen([GDB, "--interpreter=mi2", "-nx", "-q", elf(card)], stdin=subprocess.PIPE,
                                  stdout=subprocess.PIPE, text=True)
        self.buf = ""

    def send(self, cmd):
        self.p.stdin.write(cmd + "\n")
        self.p.stdin.flush()

    def until(self, pat, timeout=20):
        end, seen = time.monotonic() + timeout, []
        while time.monotonic() < end:
            while "\n" in self.buf:
                line, self.buf = self.buf.split("\n", 1)
                seen.append(line)
                if pat in line:
                    return seen
            if select.select([self.p.stdout], [], [], 0.1)[0]:
                self.buf += os.read(self.p.stdout.fileno(), 65536).decode()
        raise AssertionError("no %r from gdb: %s" % (pat, "\n".join(seen[-10:])))

    def close(self):
        if self.p.poll() is None:
            self.p.kill()
        self.p.wait(timeout=10)


def test_ctrl_c_stops_a_running_card():
    sim = subprocess.Popen([SIM, "--card", "inc", "--gdb", "0", "--serve-seconds", "30", "--script", "-"],
                           stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    sim.stdin.close()                                    # an empty script: the card runs on for gdb
    mi = MI("inc")
    try:
        port = re.match(r"gdb-port (\d+)$", sim.stdout.readline().strip()).group(1)
        mi.send("-gdb-set mi-async on")
        mi.send("-target-select remote 127.0.0.1:%s" % port)
        mi.until("^connected")
        mi.send("-exec-continue")
        mi.until("*running")
        time.sleep(1.2)                                   # paced to the wall clock: the card boots meanwhile
        mi.send("-exec-interrupt")
        stop = mi.until("*stopped")[-1]
        assert 'signal-name="SIGINT"' in stop, stop
        mi.send('-interpreter-exec console "monitor time"')
        t = float(re.search(r"time ([0-9.]+) ms", "".join(mi.until("^done"))).group(1))
        assert 900 < t < 5000, t                          # about the wall time it ran
        # a read watchpoint on the DPRAM: the main loop polls the command queue's write index
        mi.send('-break-watch -r "*(unsigned long *)0x%x"' % qh(CMDQ, "FRONT"))
        mi.until("^done")
        mi.send("-exec-continue")
        stop = mi.until("*stopped")[-1]
        assert 'reason="read-watchpoint-trigger"' in stop, stop
        mi.send("-target-detach")
        mi.until("^done")
        mi.send("-gdb-exit")
    finally:
        mi.close()
        sim.kill()
        sim.wait(timeout=10)


def test_script_command_gdb():
    """`gdb PORT` in a script stops the card there, at that emulated time
    (the time the same script reaches without gdb: a slice ends at the
    first instruction boundary past the line's end, wait states included)."""
    plain = subprocess.run([SIM, "--card", "ssi", "--script", "-"], input="run 100\nstatus\nrun 100\nstatus\n",
                           capture_output=True, text=True, timeout=60)
    st = [l for l in plain.stdout.splitlines() if l.startswith("status ")]
    cycles_at_stop = int(re.search(r"cycles=(\d+)", st[0]).group(1))
    time_at_end = re.search(r"time=\S+", st[1]).group(0)
    sim = subprocess.Popen([SIM, "--card", "ssi", "--script", "-"], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                           stderr=subprocess.PIPE, text=True)
    try:
        sim.stdin.write("run 100\ngdb 0\nrun 100\nstatus\n")
        sim.stdin.close()
        before = []
        for line in sim.stdout:
            if line.startswith("gdb-port "):
                break
            before.append(line.strip())
        assert before == ["display 1", "display 2"], before
        port = line.split()[1]
        g = subprocess.run([GDB, "-nx", "-batch", elf("ssi"), "-ex", "target remote 127.0.0.1:%s" % port,
                            "-ex", "monitor time", "-ex", "detach"], capture_output=True, text=True, timeout=60)
        assert re.search(r"time [0-9.]+ ms cycles %d\b" % cycles_at_stop, g.stdout + g.stderr), \
            (cycles_at_stop, g.stdout + g.stderr)
        out = sim.stdout.read()
        assert sim.wait(timeout=30) == 0
        assert "status " + time_at_end + " " in out, (time_at_end, out)
    finally:
        if sim.poll() is None:
            sim.kill()
            sim.wait()
    bad = subprocess.run([SIM, "--card", "inc", "--script", "-"], input="gdb 70000\n", capture_output=True,
                         text=True, timeout=30)
    assert bad.returncode == 1 and "usage: gdb PORT" in bad.stderr


def test_a_fault_stops_gdb():
    """What a real card would not survive (an unmapped access here, the PC
    set into nowhere by gdb) stops the CPU for gdb with SIGSEGV."""
    sim = subprocess.Popen([SIM, "--card", "inc", "--gdb", "0", "--script", "-"], stdin=subprocess.PIPE,
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        sim.stdin.write("run 700\n")
        sim.stdin.close()
        port = sim.stdout.readline().split()[1]
        g = subprocess.run([GDB, "-nx", "-batch", elf("inc"), "-ex", "target remote 127.0.0.1:%s" % port,
                            "-ex", "break fw_main_step", "-ex", "continue", "-ex", "delete",
                            "-ex", "set var $pc = 0x300000", "-ex", "continue", "-ex", "print/x $pc",
                            "-ex", "detach"], capture_output=True, text=True, timeout=60)
        assert "Program received signal SIGSEGV" in g.stdout, g.stdout + g.stderr
        out = sim.stdout.read()
        assert sim.wait(timeout=30) == 3 and "fault unmapped read16 at $300000" in out, out
    finally:
        if sim.poll() is None:
            sim.kill()
            sim.wait()
