#!/usr/bin/env python3
"""genboard.py - generate the card's memory map from its one description.

    tools/genboard.py [--check] [board/mac4.toml]

From board/mac4.toml (docs/board.md) writes
    hal/mac4_map.h        names for the firmware, hal/ and the emulator
    harness/bus_map.h     the rows of the emulator's bus table (harness/bus.c)
    host/mac4card/board.py    the same names and the map for Python
With --check, writes nothing and fails (exit 1) when a generated file
differs from what the description gives.  A description that is not
consistent (a name twice, regions that overlap, a register outside its
device, an address beyond 24 bits) is refused with one line and exit 1.
"""
import argparse
import os
import re
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
OUTPUTS = {"header": "hal/mac4_map.h", "bus": "harness/bus_map.h", "python": "host/mac4card/board.py"}
COL = 39                      # value column of the header's #defines


class BoardError(Exception):
    pass


def load(path):
    try:
        import tomllib
    except ImportError:
        raise BoardError("Python 3.11 or later is needed (tomllib)") from None
    try:
        with open(path, "rb") as f:
            return tomllib.load(f)
    except OSError as e:
        raise BoardError("%s: %s" % (path, e.strerror)) from None
    except tomllib.TOMLDecodeError as e:
        raise BoardError("%s: %s" % (path, e)) from None


# ---- C expressions evaluated (for the checks and the Python map) ---------------------

def py_expr(c):
    """A C constant expression of the header as Python."""
    e = re.sub(r"MAC4_U\(([^()]*)\)", r"(\1)", c)
    e = re.sub(r"\b(0[xX][0-9A-Fa-f]+|\d+)[uU][lL]?\b", r"\1", e)
    return e


class Values:
    def __init__(self):
        self.ns = {}

    def define(self, name, value, where):
        m = re.match(r"^([A-Za-z_]\w*)(?:\(([^)]*)\))?$", name)
        if not m:
            raise BoardError("%s: '%s' is not a macro name" % (where, name))
        if m.group(1) in self.ns:
            raise BoardError("%s: %s is defined twice" % (where, m.group(1)))
        try:
            if m.group(2) is not None:
                args = [a.strip() for a in m.group(2).split(",")]
                v = eval("lambda %s: %s" % (", ".join(args), py_expr(value)), self.ns)
                for trial in (0, 1):                        # it evaluates for some axis
                    v(*([trial] * len(args)))
            else:
                v = eval(py_expr(value), self.ns)
        except Exception as e:                             # noqa: BLE001 - reported as one line
            raise BoardError("%s: %s = %s does not evaluate (%s)" % (where, name, value, e)) \
                from None
        self.ns[m.group(1)] = v
        return m.group(1), v, m.group(2)


# ---- the description, checked -----------------------------------------------------

def entries(board):
    """Every define in order: (block, entry, name, C value), the memory and
    device windows as (name, base, size, word_io, (device, window))."""
    vals = Values()
    defs, windows, waits = [], [], {}
    blocks = board.get("block")
    if not isinstance(blocks, list) or not blocks:
        raise BoardError("no [[block]] in the description")
    for i, b in enumerate(blocks):
        where = "block %d (%s)" % (i + 1, b.get("title") or b.get("bus_name") or
                                   (b.get("comment") or "").strip().split("\n")[0])
        kind = b.get("kind", "defines")
        if kind not in ("defines", "memory", "device"):
            raise BoardError("%s: kind '%s' (memory, device or none)" % (where, kind))
        pre = []
        if kind == "memory":
            for k in ("prefix", "base", "size", "device", "bus_name"):
                if k not in b:
                    raise BoardError("%s: a memory block needs '%s'" % (where, k))
            pre = [{"name": b["prefix"] + "_BASE", "value": "MAC4_U(0x%06X)" % b["base"]},
                   {"name": b["prefix"] + "_SIZE", "value": "MAC4_U(0x%X)" % b["size"]}]
        if kind == "device":
            for k in ("device", "bus_name"):
                if k not in b:
                    raise BoardError("%s: a device block needs '%s'" % (where, k))
            if "bus_base" not in b and ("io_offset" not in b or "size" not in b):
                raise BoardError("%s: a device needs io_offset and size, or bus_base and "
                                 "bus_size" % where)
        out = []
        for e in pre + list(b.get("define", [])):
            if not isinstance(e, dict):
                raise BoardError("%s: a define is a table {name = ..., value = ...}" % where)
            if "reg" in e:
                if kind != "device" or "io_offset" not in b:
                    raise BoardError("%s: reg %s outside a device with io_offset"
                                     % (where, e["reg"]))
                if not 0 <= e.get("at", -1) < b["size"] or e["at"] % 2:
                    raise BoardError("%s: register %s at %s: not an even offset inside the "
                                     "device's %d bytes" % (where, e["reg"], e.get("at"),
                                                            b["size"]))
                e = dict(e, name=e["reg"], value="(IO_BASE + 0x%03X)" % (b["io_offset"] + e["at"]))
            if "name" in e:
                if "value" not in e:
                    raise BoardError("%s: %s has no value" % (where, e["name"]))
                vals.define(e["name"], str(e["value"]), where)
            out.append(e)
        if kind in ("memory", "device"):
            # the bus timing (docs/memory-map.md, "Bus timing"): wait states
            # per bus cycle, [read, write]; MAC4_BUS_TIMING in the header
            w = b.get("wait", [0, 0])
            if not (isinstance(w, list) and len(w) == 2 and all(isinstance(x, int) and 0 <= x <= 255 for x in w)):
                raise BoardError("%s: wait is [read, write], wait states 0..255" % where)
            waits[b["bus_name"]] = tuple(w)
        dev = (b.get("device"), b.get("window", 0))
        if kind in ("memory", "device") and not (isinstance(dev[1], int) and 0 <= dev[1] < 2):
            raise BoardError("%s: window is 0 or 1 (a device's register windows)" % where)
        if kind == "memory":
            windows.append((b["bus_name"], "%s_BASE" % b["prefix"], "%s_SIZE" % b["prefix"],
                            b["base"], b["size"], 0, dev))
        elif kind == "device":
            if "bus_base" in b:
                bb, bs = b["bus_base"], b.get("bus_size", "2")
            else:
                bb, bs = "IO_BASE + 0x%03X" % b["io_offset"], "0x%02X" % b["size"]
            base = eval(py_expr(bb), vals.ns)
            size = eval(py_expr(bs), vals.ns)
            windows.append((b["bus_name"], bb, bs, base, size, 1, dev))
        defs.append((b, out))
    names = set()
    for w in windows:
        if w[0] in names:
            raise BoardError("bus name '%s' twice" % w[0])
        names.add(w[0])
        if not (0 <= w[3] and w[3] + w[4] <= 1 << 24):
            raise BoardError("%s: $%X + $%X is beyond the 68000's 24 address lines"
                             % (w[0], w[3], w[4]))
    ws = sorted(windows, key=lambda w: w[3])
    for a, b in zip(ws, ws[1:]):
        if a[3] + a[4] > b[3]:
            raise BoardError("%s ($%06X-$%06X) and %s ($%06X) overlap"
                             % (a[0], a[3], a[3] + a[4] - 1, b[0], b[3]))
    vals.waits = waits
    return defs, windows, vals


# ---- the outputs -----------------------------------------------------------------

def c_comment(text, indent=""):
    lines = text.strip("\n").split("\n")
    if len(lines) == 1:
        return ["%s/* %s */" % (indent, lines[0])]
    return ["%s/*%s" % (indent, "" if not lines[0] else " " + lines[0])] + \
        ["%s * %s" % (indent, l) if l else "%s *" % indent for l in lines[1:]] + \
        ["%s */" % indent]


def bus_timing(windows, waits):
    """MAC4_BUS_TIMING(X): a row X(name, base, size, read, write) per window,
    its wait states per bus cycle (harness/buswait.c; BUS_TIMING in board.py)."""
    out = ["#define MAC4_BUS_TIMING(X) \\"]
    for i, (name, bb, bs, _, _, _, _) in enumerate(windows):
        rd, wr = waits[name]
        out.append("    X(%-11s %-21s %-27s %3d, %3d)%s" % ('"%s",' % name, bb + ",", bs + ",", rd, wr,
                                                        " \\" if i + 1 < len(windows) else ""))
    return out


def header(board, defs, src, windows=(), waits=None):
    out = ["/*", " * mac4_map.h - GENERATED from %s by tools/genboard.py: do not edit;" % src,
           " * change the description and run `make board` (docs/board.md).", " *"]
    for l in board["board"]["header"].strip("\n").split("\n"):
        out.append(" * " + l if l else " *")
    out += [" */", "#ifndef MAC4_MAP_H", "#define MAC4_MAP_H", "",
            "#ifdef __ASSEMBLER__", "#define MAC4_U(x) x", "#else", "#define MAC4_U(x) x##UL",
            "#endif"]
    for b, es in defs:
        out.append("")
        if b.get("title"):
            out.append("/* ---- %s %s */" % (b["title"], "-" * max(3, 70 - len(b["title"]))))
        if b.get("comment"):
            out += c_comment(b["comment"])
        for e in es:
            if e.get("blank"):
                out.append("")
            elif "comment" in e and "name" not in e:
                out += c_comment(e["comment"])
            else:
                line = "#define %-*s %s" % (COL - 9, e["name"], e["value"])
                if e.get("doc"):
                    line += " /* %s */" % e["doc"]
                out.append(line)
        if b.get("bus_timing"):
            out += bus_timing(windows, waits)
    out += ["", "#endif /* MAC4_MAP_H */", ""]
    return "\n".join(out)


def bus_map(windows, src):
    out = ["/* bus_map.h - GENERATED from %s by tools/genboard.py: do not edit." % src,
           " * The rows of the emulator's bus table (harness/bus.c): base, size, name,",
           " * the device that answers and which of its register windows, word-wide I/O",
           " * (no byte writes). */"]
    for name, bb, bs, _, _, word_io, (dev, win) in windows:
        out.append("{%s, %s, \"%s\", &%s_device, %d, %d}," % (bb, bs, name, dev, win, word_io))
    return "\n".join(out) + "\n"


def python_map(defs, windows, vals, src, cards=None):
    out = ['"""board.py - GENERATED from %s by tools/genboard.py: do not edit.' % src,
           "",
           "The card's local memory map and device registers (our design, docs/board.md),",
           'the same names as hal/mac4_map.h.  MEMORY lists the bus windows."""', ""]
    for b, es in defs:
        for e in es:
            if "name" not in e:
                continue
            m = re.match(r"^(\w+)(?:\(([^)]*)\))?$", e["name"])
            if m.group(2) is not None:
                out.append("%s = lambda %s: %s" % (m.group(1), m.group(2),
                                                   py_expr(e["value"])))
            else:
                v = vals.ns[m.group(1)]
                hexa = "0x" in e["value"].lower() and v > 9
                out.append("%s = %s" % (m.group(1), ("0x%X" % v) if hexa else str(v)))
    out += ["", "# (name, base, size, word-wide I/O) of every window on the 68000's bus",
            "MEMORY = ["]
    for name, _, _, base, size, word_io, _ in windows:
        out.append("    (%r, 0x%06X, 0x%X, %s)," % (name, base, size, bool(word_io)))
    out.append("]")
    if cards:
        # the cards by name, from [cards]: the card type (VER), the controller
        # period (firmware/card.c TICK_US) in us and cycles, the profile generator's
        cyc, div = vals.ns["MAC4_CYCLES_PER_US"], vals.ns["PROFILE_DIVIDER"]
        out += ["", "# the cards by name ([cards]): type (VER bits 24-31), controller period in us",
                "# and in cycles, the profile generator's period (PROFILE_DIVIDER ticks) in cycles"]
        for var, f in (("CARD_TYPE", lambda t, p: t), ("PERIOD_US", lambda t, p: p),
                       ("PERIOD_CYCLES", lambda t, p: p * cyc),
                       ("PROFILE_PERIOD_CYCLES", lambda t, p: p * cyc * div)):
            out.append("%s = {%s}" % (var, ", ".join("%r: %d" % (n, f(*c)) for n, c in cards.items())))
    out += ["", "# (name, read, write) wait states per bus cycle of every window (MAC4_BUS_TIMING)",
            "BUS_TIMING = ["]
    for name, _, _, _, _, _, _ in windows:
        out.append("    (%r, %d, %d)," % ((name,) + vals.waits[name]))
    out.append("]")
    return "\n".join(out) + "\n"


def generate(path):
    board = load(path)
    if "board" not in board or "header" not in board["board"]:
        raise BoardError("%s: no [board] with a header text" % path)
    src = os.path.relpath(os.path.abspath(path), ROOT)
    defs, windows, vals = entries(board)
    cards = {}
    for name, c in board.get("cards", {}).items():
        if not isinstance(c, dict) or set(c) != {"type", "period_us"}:
            raise BoardError("cards.%s: a card is {type = NAME, period_us = NAME}" % name)
        try:
            cards[name] = tuple(int(eval(py_expr(c[k]), dict(vals.ns))) for k in ("type", "period_us"))
        except Exception as e:                             # noqa: BLE001 - reported as one line
            raise BoardError("cards.%s does not evaluate (%s)" % (name, e)) from None
    return {OUTPUTS["header"]: header(board, defs, src, windows, vals.waits), OUTPUTS["bus"]: bus_map(windows, src),
            OUTPUTS["python"]: python_map(defs, windows, vals, src, cards)}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("board", nargs="?", default=os.path.join(ROOT, "board", "mac4.toml"))
    ap.add_argument("--check", action="store_true",
                    help="fail when a generated file differs, write nothing")
    ap.add_argument("--out", default=ROOT, help="where the generated tree is (default: the "
                                                "checkout)")
    a = ap.parse_args(argv)
    try:
        files = generate(a.board)
    except BoardError as e:
        print("genboard: %s" % e, file=sys.stderr)
        return 1
    stale = []
    for rel, text in files.items():
        p = os.path.join(a.out, rel)
        try:
            old = open(p).read()
        except OSError:
            old = None
        if old == text:
            continue
        if a.check:
            stale.append(rel)
        else:
            try:
                with open(p, "w") as f:
                    f.write(text)
            except OSError as e:
                print("genboard: %s: %s" % (p, e.strerror), file=sys.stderr)
                return 1
            print("genboard: wrote %s" % rel)
    if stale:
        print("genboard: %s not what %s gives: edit the description, not the generated file, "
              "and run `make board`" % (", ".join(stale), os.path.relpath(a.board, ROOT)),
              file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
