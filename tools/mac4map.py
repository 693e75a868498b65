"""mac4map.py - the bus timing of hal/mac4_map.h (generated from
board/mac4.toml, docs/board.md), read from the header the emulator is built
with: the table MAC4_BUS_TIMING (docs/memory-map.md, "Bus timing") and the
constants beside it, with their C expressions evaluated.

    import mac4map
    mac4map.bus_timing()   # [{"name", "base", "size", "read", "write"}], the regions in order
    mac4map.constant("MAC4_IACK_AUTOVECTOR_CLOCKS")
"""
import os
import re

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
HEADER = os.path.join(ROOT, "hal", "mac4_map.h")


def _text():
    with open(HEADER) as f:
        return f.read()


def _defines(text):
    """Object-like #defines: name -> expression text (MAC4_U(x) as x)."""
    out = {}
    for m in re.finditer(r"^#define\s+(\w+)\s+(.+?)\s*(?:/\*.*)?$", text, re.M):
        out[m.group(1)] = re.sub(r"MAC4_U\((\w+)\)", r"\1", m.group(2))
    return out


def _eval(expr, defs, depth=0):
    if depth > 20:
        raise ValueError("mac4_map.h: %s does not resolve" % expr)
    expr = re.sub(r"MAC4_U\((\w+)\)", r"\1", expr)

    def sub(m):
        name = m.group(0)
        return "(%s)" % _eval(defs[name], defs, depth + 1) if name in defs else name
    py = re.sub(r"\b[A-Za-z_]\w*\b", sub, expr)
    py = re.sub(r"\b(0[xX][0-9A-Fa-f]+|\d+)[uUlL]+\b", r"\1", py)
    if not re.fullmatch(r"[\s0-9xXa-fA-F()+\-*/<>|&]+", py):
        raise ValueError("mac4_map.h: cannot evaluate %r" % expr)
    return eval(py.replace("/", "//"))       # noqa: S307 - digits and operators only, checked above


def constant(name):
    defs = _defines(_text())
    return _eval(defs[name], defs)


def bus_timing():
    """The rows of MAC4_BUS_TIMING, in order (the emulator's region numbers),
    with their default wait states per bus cycle."""
    text = _text()
    m = re.search(r"#define MAC4_BUS_TIMING\(X\)((?:.*\\\n)*.*)", text)
    if not m:
        raise ValueError("mac4_map.h: no MAC4_BUS_TIMING table")
    defs = _defines(text)
    rows = []
    for x in re.finditer(r"X\(([^()]*(?:\([^()]*\)[^()]*)*)\)", m.group(1)):
        name, base, size, rd, wr = [p.strip() for p in x.group(1).split(",")]
        rows.append({"name": name.strip('"'), "base": _eval(base, defs), "size": _eval(size, defs),
                     "read": int(rd), "write": int(wr)})
    return rows


def regions():
    """The region names --wait-states takes, the unmapped rest last."""
    return [r["name"] for r in bus_timing()] + ["unmapped"]


if __name__ == "__main__":
    for r in bus_timing():
        print("%-9s $%06X %7d bytes  read %d  write %d" % (r["name"], r["base"], r["size"], r["read"], r["write"]))
    for c in ("MAC4_DPRAM_HOST_CLOCKS", "MAC4_IACK_AUTOVECTOR_CLOCKS", "MAC4_IACK_VECTORED_WAIT"):
        print(c, constant(c))
