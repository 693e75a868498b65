#!/usr/bin/env python3
"""callgraph.py - the firmware's file-to-file call graph has no cycle except
through the interfaces declared in tools/callgraph.allow (`make callgraph`,
part of `make test`).

    tools/callgraph.py [--graph] [--allow FILE] [BUILD/fw-CARD ...]

Reads the 68000 objects of each card (build/fw-inc, fw-ssi, fw-stp by
default) and builds who calls whom, from the compiled code, not the source:

* a call is a relocation in a code section against a function (a global one
  of any object, or a static one of the same object); the caller is the
  source file of the instruction it sits in, as the object's line table
  (-g) says.  So code a header inlines into a .c file (FW_INLINE, static
  inline) counts to the header: tick.h's brake_step calling motion.c counts
  as tick.h -> motion.c, not as tick_servo.c -> motion.c;
* a file whose code contains a header's inlined code uses that header: an
  edge file -> header ("inline");
* a header with a .c of its stem (measure.h, motion.h, ...) is that file:
  the header declares the file's functions and carries its hot paths;
* a function address in data (a dispatch table, a callback) is an edge of
  the table's file to the function's ("ref").
Limits: a call through a pointer loaded at run time from anywhere else is not
seen; code inlined across files other than through headers cannot happen
(no LTO); the line table attributes an instruction the compiler shared
between inlined copies to one of them.

A cycle is a strongly connected set of files.  An edge listed in the
allowlist (caller -> callee: the functions, and why that direction is an
interface) is left out first; the check fails (exit 1), listing each cycle
with the calls that make it, when any remains, and when an allowlist entry
matches no call any more (stale).  --graph prints every edge.  Exit 2 on a
usage or setup error (no objects, no objdump)."""
import argparse
import os
import re
import subprocess
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
CROSS = os.environ.get("CROSS", "m68k-linux-gnu-")
ALLOW = os.path.join(ROOT, "tools", "callgraph.allow")
SRC = re.compile(r"^(?:\S*/)?((?:firmware|hal)/[\w/]+\.[ch]):\d+")
RELOC = re.compile(r"^\s+[0-9a-f]+:\s+R_68K_\w+\s+(\S+?)(?:[+-]0x[0-9a-f]+)?$")
LABEL = re.compile(r"^[0-9a-f]+ <([^>]+)>:$")
CONTEXT = re.compile(r"^([A-Za-z_]\w*)\(\):$")
SECTION = re.compile(r"^Disassembly of section (\S+):$")


class SetupError(Exception):
    pass


# headers that are no one file's interface, a node of their own: card.h holds
# the card's state and declares the functions of card.c, supervise.c, axis.c
# and vme_irq.c; stepper.h the STP's helpers that stepper.c, stp_rate.c,
# stp_profile.c and the tick share, and its output stage (stp_output)
SHARED_HEADERS = {"firmware/card.h", "firmware/stepper.h"}
# ... whose inline functions belong to the file they front: the test before
# the call (the rest of card.h's inline code calls nothing)
INLINE_OWNER = {"card_supervise": "firmware/supervise.c", "card_supervise_due": "firmware/supervise.c",
                "vme_irq_service": "firmware/vme_irq.c"}


# private headers of a stage, which are the file they are named after
HEADER_OWNER = {"firmware/motion_priv.h": "firmware/motion.c"}


def owner(path, func):
    """Whose code an instruction of `path` is, inlined from function `func` there."""
    return INLINE_OWNER.get(func, path) if path in SHARED_HEADERS else path


def node(path):
    """The graph's node for a source file: a header with a .c of its stem is that file."""
    if path in HEADER_OWNER:
        return HEADER_OWNER[path]
    if path.endswith(".h") and path not in SHARED_HEADERS:
        c = path[:-2] + ".c"
        if os.path.exists(os.path.join(ROOT, c)):
            return c
    return path


def _run(args):
    try:
        return subprocess.run(args, capture_output=True, text=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError) as e:
        raise SetupError("%s: %s" % (" ".join(args), e))


def read_object(path):
    """(functions, code, inlined, data) of one object: functions maps each
    function symbol (and its section, .text.NAME) to its home file; code lists
    (file of the instruction, symbol, function it sits in); inlined holds (file,
    inlined function, function it sits in) of every line record; data lists the
    symbols referenced from data sections."""
    dis = _run([CROSS + "objdump", "-drl", "--no-show-raw-insn", path])
    funcs, code, inl, cur_file, cur_func, want_home, section, cur_ctx = {}, [], set(), None, None, None, None, None
    for line in dis.splitlines():
        m = SECTION.match(line)
        if m:
            section = m.group(1)
            continue
        m = LABEL.match(line)
        if m:
            cur_func, want_home = m.group(1), m.group(1)
            continue
        m = CONTEXT.match(line)
        if m:
            cur_ctx = m.group(1)
            continue
        m = SRC.search(line)
        if m:
            cur_file = m.group(1)
            inl.add((owner(cur_file, cur_ctx), cur_ctx, cur_func))
            # a function's home is where its own lines are, not the code it inlines first
            if want_home and cur_ctx == want_home:
                funcs[want_home] = cur_file
                if section and section.startswith(".text."):
                    funcs.setdefault(section, cur_file)
                want_home = None
            continue
        m = RELOC.match(line)
        if m and cur_file:
            code.append((owner(cur_file, cur_ctx), m.group(1), cur_func))
    # which objects' symbols are functions, and the data references
    data = []
    rel = _run([CROSS + "readelf", "-rW", path])
    sect = None
    for line in rel.splitlines():
        m = re.match(r"^Relocation section '\.rela(\S+)'", line)
        if m:
            sect = m.group(1)
            continue
        f = line.split()
        if sect and not sect.startswith(".text") and len(f) >= 5 and re.match(r"^[0-9a-f]{8}$", f[0]):
            data.append(f[4])
    return funcs, code, inl, data


def objects(d):
    """The firmware's and the target HAL's C objects of a card's build directory."""
    return sorted(os.path.join(d, f) for f in os.listdir(d)
                  if f.endswith(".o") and not f.startswith("asm_"))


def source_of(obj):
    """firmware/axis.c for build/fw-inc/axis.o, hal/target/runtime.c for hal_runtime.o."""
    b = os.path.basename(obj)[:-2]
    return "hal/target/%s.c" % b[4:] if b.startswith("hal_") else "firmware/%s.c" % b


def build_graph(dirs):
    """{(caller, callee): {kind: set of "caller_function -> callee_function"}} over the cards' objects."""
    edges = {}

    def add(a, b, kind, what):
        if a != b:
            edges.setdefault((a, b), {}).setdefault(kind, set()).add(what)

    for d in dirs:
        objs = objects(d)
        if not objs:
            raise SetupError("%s: no objects (make images first)" % d)
        parsed = {o: read_object(o) for o in objs}
        glob = {}
        for o in objs:
            for ln in _run([CROSS + "nm", "--defined-only", o]).splitlines():
                f = ln.split()
                if len(f) == 3 and f[1] == "T":
                    glob[f[2]] = source_of(o)
        for o, (funcs, code, inl, data) in parsed.items():
            home = source_of(o)
            for file, ctx, fn in inl:
                add(node(home), node(file), "inline", "%s -> %s" % (fn, ctx))
            for file, sym, fn in code:
                callee = funcs.get(sym) if sym in funcs else glob.get(sym)
                caller = node(file)
                if callee:
                    add(caller, node(callee), "call", "%s -> %s" % (fn, sym.replace(".text.", "")))
            for sym in data:
                callee = funcs.get(sym) if sym in funcs else glob.get(sym)
                if callee:
                    add(node(home), node(callee), "ref", sym.replace(".text.", ""))
    return edges


def read_allow(path):
    """[(caller, callee, set of functions or None for any, line number)] of the allowlist."""
    out = []
    for n, line in enumerate(open(path, encoding="utf-8"), 1):
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        m = re.match(r"^(\S+)\s*->\s*(\S+?)\s*:\s*(.*)$", line) or re.match(r"^(\S+)\s*->\s*(\S+)()$", line)
        if not m:
            raise SetupError("%s:%d: not 'caller -> callee: functions'" % (path, n))
        fns = set(m.group(3).split()) or None
        out.append((m.group(1), m.group(2), fns, n))
    return out


def _callees(whats):
    return {w.split(" -> ")[-1] for w in whats}


def apply_allow(edges, allow):
    """The edges left once the allowlist's are taken out, and the allowlist lines that match nothing."""
    left = {k: {kind: set(v) for kind, v in kinds.items()} for k, kinds in edges.items()}
    stale = []
    for a, b, fns, n in allow:
        kinds = left.get((a, b))
        if not kinds:
            stale.append(n)
            continue
        if fns is None:
            del left[(a, b)]
            continue
        used = False
        for kind in list(kinds):
            keep = {w for w in kinds[kind] if w.split(" -> ")[-1] not in fns}
            used |= keep != kinds[kind]
            if keep:
                kinds[kind] = keep
            else:
                del kinds[kind]
        if not used:
            stale.append(n)
        if not kinds:
            del left[(a, b)]
    return left, stale


def cycles(edges):
    """The strongly connected sets of more than one node (Tarjan), each sorted."""
    succ = {}
    for a, b in edges:
        succ.setdefault(a, set()).add(b)
        succ.setdefault(b, set())
    index, low, stack, on, out, i = {}, {}, [], set(), [], [0]

    def visit(v):
        index[v] = low[v] = i[0]
        i[0] += 1
        stack.append(v)
        on.add(v)
        for w in sorted(succ[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    sys.setrecursionlimit(10000)
    for v in sorted(succ):
        if v not in index:
            visit(v)
    return sorted(out)


def report(edges, comps):
    lines = []
    for comp in comps:
        lines.append("cycle among %s:" % ", ".join(comp))
        for (a, b), kinds in sorted(edges.items()):
            if a in comp and b in comp:
                for kind, whats in sorted(kinds.items()):
                    lines.append("  %s -> %s (%s): %s" % (a, b, kind, ", ".join(sorted(whats)[:6])
                                                          + (" ..." if len(whats) > 6 else "")))
    return lines


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("dirs", nargs="*", help="card build directories (default build/fw-inc, fw-ssi, fw-stp)")
    ap.add_argument("--allow", default=ALLOW)
    ap.add_argument("--graph", action="store_true", help="print every edge")
    a = ap.parse_args(argv)
    dirs = a.dirs or [os.path.join(ROOT, "build", "fw-" + c) for c in ("inc", "ssi", "stp")]
    try:
        for d in dirs:
            if not os.path.isdir(d):
                raise SetupError("%s: no such build directory (make images first)" % d)
        edges = build_graph(dirs)
        allow = read_allow(a.allow) if a.allow else []
    except (SetupError, OSError) as e:
        print("callgraph: %s" % e, file=sys.stderr)
        return 2
    if a.graph:
        for (x, y), kinds in sorted(edges.items()):
            for kind, whats in sorted(kinds.items()):
                print("%s -> %s (%s) %s" % (x, y, kind, " ".join(sorted(_callees(whats)))))
    left, stale = apply_allow(edges, allow)
    comps = cycles(left)
    bad = report(left, comps) + ["%s:%d: allows a call the firmware no longer makes" % (a.allow, n)
                                 for n in stale]
    for b in bad:
        print("callgraph: " + b, file=sys.stderr)
    if not bad:
        print("callgraph: %d files, %d edges, no cycle but the %d declared interfaces of %s"
              % (len({f for e in edges for f in e}), len(edges), len(allow), os.path.relpath(a.allow, ROOT)))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
