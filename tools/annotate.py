#!/usr/bin/env python3
"""annotate.py - where the 68000's cycles went, instruction by instruction.

    tools/annotate.py CARD PCS [--from ADDR --to ADDR | --func NAME] [--top N]

PCS is what the host-script command `profile pcs FILE` wrote (harness/profile.c:
"pc cycles executions" per instruction of the EPROM, from `profile on`).  Without
a range: the N most expensive runs of consecutive instructions (the firmware
inlines its hot paths, so a function name says little).  With a range or a
function: its disassembly (build/eprom/mac4-CARD.elf, objdump) with each
instruction's cycles and executions beside it.  A tool for people tuning the
firmware; docs/performance.md, "Finding the cycles".
"""
import argparse
import os
import re
import subprocess

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
OBJDUMP = "m68k-linux-gnu-objdump"
LINE = re.compile(r"^\s*([0-9a-f]+):\s+((?:[0-9a-f]{4} )+)\s*(.*)$")
FUNC = re.compile(r"^([0-9a-f]+) <([^>]+)>:$")


def load_pcs(path):
    pcs = {}
    for line in open(path):
        a, c, k = line.split()
        pcs[int(a, 16)] = (int(c), int(k))
    return pcs


def disassembly(card):
    elf = os.path.join(ROOT, "build", "eprom", "mac4-%s.elf" % card)
    out = subprocess.run([OBJDUMP, "-d", "-m", "m68k:68000", elf], capture_output=True, text=True,
                         check=True).stdout
    rows, func = [], "?"
    for line in out.splitlines():
        m = FUNC.match(line)
        if m:
            func = m.group(2)
            continue
        m = LINE.match(line)
        if m:
            rows.append((int(m.group(1), 16), func, m.group(3).strip()))
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("card", choices=("inc", "ssi", "stp"))
    ap.add_argument("pcs")
    ap.add_argument("--from", dest="lo", type=lambda v: int(v, 0))
    ap.add_argument("--to", dest="hi", type=lambda v: int(v, 0))
    ap.add_argument("--func")
    ap.add_argument("--top", type=int, default=15)
    a = ap.parse_args()
    pcs = load_pcs(a.pcs)
    rows = disassembly(a.card)
    total = sum(c for c, _ in pcs.values()) or 1
    if a.func or a.lo is not None:
        sel = [r for r in rows if (r[1] == a.func if a.func else a.lo <= r[0] < (a.hi or a.lo + 0x100))]
        s = 0
        for addr, func, text in sel:
            c, k = pcs.get(addr, (0, 0))
            s += c
            print("%8d %7d  %06x  %s" % (c, k, addr, text))
        print("%8d cycles (%.2f%% of all profiled)" % (s, 100.0 * s / total))
        return
    # runs: consecutive instructions that executed, split where the count changes
    runs, cur = [], None
    for addr, func, text in rows:
        c, k = pcs.get(addr, (0, 0))
        if not k:
            cur = None
            continue
        if cur and cur["func"] == func and cur["k"] == k:
            cur["c"] += c
            cur["n"] += 1
        else:
            cur = {"start": addr, "func": func, "k": k, "c": c, "n": 1}
            runs.append(cur)
    by_func = {}
    for addr, func, _ in rows:
        by_func[func] = by_func.get(func, 0) + pcs.get(addr, (0, 0))[0]
    print("cycles   share  function")
    for f, c in sorted(by_func.items(), key=lambda kv: -kv[1])[:a.top]:
        print("%8d %6.2f%%  %s" % (c, 100.0 * c / total, f))
    print("\ncycles   share  executions  instrs  start   function")
    for r in sorted(runs, key=lambda r: -r["c"])[:a.top]:
        print("%8d %6.2f%%  %9d  %6d  %06x  %s" % (r["c"], 100.0 * r["c"] / total, r["k"], r["n"], r["start"],
                                                  r["func"]))


if __name__ == "__main__":
    main()
