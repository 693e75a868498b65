"""The native/68000 differential test's machinery (docs/performance.md,
"Native and 68000 agree").

A scenario is a list of steps at tick boundaries: ("ticks", N) runs N timer
ticks (and on to a tick that begins no profile period when an injection
follows: `run-ticks N off-sp`), anything else is injected at the tick the
previous step stopped at:
("send", axis, mnemonic[, param]) through the DPRAM command queue,
("serial", axis, mnemonic[, param]) as a telegram on the serial line,
("stop", bits) writes the stop-bit word at $4600 as the host, ("script", line)
is a line of the host script (a switch, a drive fault, /STOP).  The same script
runs through build/mac4sim (the EPROM image on Musashi) and
build/mac4sim-native-CARD (the firmware compiled for the host) with the axis
board on logical time (`perf axis-sync on`), and the two runs must agree:

* every timer tick: the DAC word (STP: step rate) and AX_CTRL of every axis,
  the position counter (SSI: the encoder reading; STP also the steps
  generated) and the eight words of axis data the card publishes at
  $3000 + n*$400,
* the responses in the DPRAM response queue and the bytes sent on the serial
  line, in order, each under the tick boundary of the injections it followed.
"""
import os
import re
import subprocess
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "host"))
from mac4card import board  # noqa: E402  (generated from board/mac4.toml)

BUILD = os.path.join(ROOT, "build")
M68K = os.path.join(BUILD, "mac4sim")


def native(card):
    return os.path.join(BUILD, "mac4sim-native-%s" % card)


def script(steps, setup=()):
    """setup: host-script lines (plant configuration) before the card boots."""
    out = ["perf axis-sync on"] + list(setup) + ["wait-display 5 3000", "run-ticks 2 off-sp", "perf ticks -"]
    k, boundary = 0, True
    for i, st in enumerate(steps):
        if st[0] == "ticks":
            # before an injection, stop where the next tick begins no profile period
            inject = i + 1 < len(steps) and steps[i + 1][0] != "ticks"
            out.append("run-ticks %d%s" % (st[1], " off-sp" if inject else ""))
            boundary = True
            continue
        if boundary:                  # responses are grouped by tick boundary
            out.append("echo inject %d" % k)
            k += 1
            boundary = False
        if st[0] == "send":
            out.append("send %d %s %s" % (st[1], st[2], st[3] if len(st) > 3 else ""))
        elif st[0] == "serial":
            out.append("tx-msg %d %s %s" % (st[1], st[2], st[3] if len(st) > 3 else ""))
        elif st[0] == "stop":
            out.append("poke16 0x%X %d" % (board.DP_STOP_BITS, st[1]))
        elif st[0] == "script":        # a host-script line: the plant, a fault, /STOP
            out.append(st[1])
        else:
            raise ValueError(st)
    out.append("run-ticks 4")
    return "\n".join(out) + "\n"


class Run:
    def __init__(self, binary, card, text):
        p = subprocess.run([binary, "--card", card, "--script", "-"], input=text, capture_output=True,
                           text=True, timeout=600)
        self.rc, self.stderr = p.returncode, p.stderr
        self.ticks = {}           # tick number -> the line's fields after "tick N"
        self.events = []          # (injection, kind, text): resp / rx bytes
        self.faults = []
        inj = -1
        for line in p.stdout.splitlines():
            if line.startswith("tick "):
                n, _, rest = line[5:].partition(" ")
                self.ticks[int(n)] = rest
            elif line.startswith("inject "):
                inj = int(line.split()[1])
            elif line.startswith("resp "):
                self.events.append((inj, "resp", line[5:]))
            elif line.startswith("rx "):
                for b in line[3:].split():
                    self.events.append((inj, "rx", b))
            elif line.startswith("fault "):
                self.faults.append(line)


FIELDS = ["out", "ctrl", "counter", "ustat", "sstat", "pos", "setpoint", "ferr", "dpa_out", "vel", "raw"]
FIELDS_STP = ["out", "ctrl", "generated", "counter", "ustat", "sstat", "pos", "setpoint", "ferr", "dpa_out",
              "vel", "raw"]


def explain(card, a, b):
    """Which axis and field differ between two tick lines."""
    names = FIELDS_STP if card == "stp" else FIELDS
    pa, pb = a.split("|")[1:], b.split("|")[1:]
    for ax, (x, y) in enumerate(zip(pa, pb)):
        fx, fy = x.split(), y.split()
        for i, (u, v) in enumerate(zip(fx, fy)):
            if u != v:
                return "axis %d %s: 68000 %s, native %s" % (ax, names[i] if i < len(names) else i, u, v)
    return "line lengths differ"


def compare(card, steps, setup=()):
    """Run both; return (m68k, native, list of differences as text)."""
    text = script(steps, setup)
    m = Run(M68K, card, text)
    n = Run(native(card), card, text)
    problems = []
    for name, r in (("68000", m), ("native", n)):
        if r.rc != 0 or r.faults:
            problems.append("%s run failed (exit %d): %s %s" % (name, r.rc, r.faults[:3], r.stderr.strip()[-2000:]))
    if problems:
        return m, n, problems
    if len(m.ticks) != len(n.ticks):
        problems.append("tick counts differ: 68000 %d, native %d" % (len(m.ticks), len(n.ticks)))
    for t in sorted(set(m.ticks) & set(n.ticks)):
        if m.ticks[t] != n.ticks[t]:
            problems.append("first diverging tick %d: %s\n  68000:  %s\n  native: %s"
                            % (t, explain(card, m.ticks[t], n.ticks[t]), m.ticks[t], n.ticks[t]))
            break
    for i, (x, y) in enumerate(zip(m.events, n.events)):
        if x != y:
            problems.append("responses differ at #%d (after injection %d): 68000 %s, native %s"
                            % (i, min(x[0], y[0]), x, y))
            break
    else:
        if len(m.events) != len(n.events):
            problems.append("response counts differ: 68000 %d, native %d" % (len(m.events), len(n.events)))
    return m, n, problems


def moved(run, axis):
    """How far the counter of an axis went over the run (0 when it never moved)."""
    vals = []
    for t in sorted(run.ticks):
        f = run.ticks[t].split("|")[1 + axis].split()
        c = [x for x in f if re.match(r"^[cs][0-9A-F]{6}$", x)][0]
        v = int(c[1:], 16)
        vals.append(v - (1 << 24) if v & 0x800000 else v)
    return max(vals) - min(vals) if vals else 0
