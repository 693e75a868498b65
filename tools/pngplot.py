#!/usr/bin/env python3
"""pngplot.py - a plot of a move as PNG, with the standard library only
(zlib): setpoint and position, following error, and the DAC word (STP: the
step rate) over time, from the CSV that `perf sample FILE AXIS` writes
(t_ms,setpoint,pos,ferr,out,dac|rate; docs/performance.md).

    tools/pngplot.py SAMPLES.csv OUT.png [TITLE]
"""
import csv
import struct
import sys
import zlib

# 5x7 glyphs, seven rows of five, '#' = ink
FONT = {
    '0': [' ### ', '#   #', '#  ##', '# # #', '##  #', '#   #', ' ### '],
    '1': ['  #  ', ' ##  ', '  #  ', '  #  ', '  #  ', '  #  ', ' ### '],
    '2': [' ### ', '#   #', '    #', '   # ', '  #  ', ' #   ', '#####'],
    '3': ['#####', '   # ', '  #  ', '   # ', '    #', '#   #', ' ### '],
    '4': ['   # ', '  ## ', ' # # ', '#  # ', '#####', '   # ', '   # '],
    '5': ['#####', '#    ', '#### ', '    #', '    #', '#   #', ' ### '],
    '6': ['  ## ', ' #   ', '#    ', '#### ', '#   #', '#   #', ' ### '],
    '7': ['#####', '    #', '   # ', '  #  ', ' #   ', ' #   ', ' #   '],
    '8': [' ### ', '#   #', '#   #', ' ### ', '#   #', '#   #', ' ### '],
    '9': [' ### ', '#   #', '#   #', ' ####', '    #', '   # ', ' ##  '],
    '-': ['     ', '     ', '     ', '#####', '     ', '     ', '     '],
    '.': ['     ', '     ', '     ', '     ', '     ', ' ##  ', ' ##  '],
    ':': ['     ', ' ##  ', ' ##  ', '     ', ' ##  ', ' ##  ', '     '],
    ' ': ['     ', '     ', '     ', '     ', '     ', '     ', '     '],
    '(': ['   # ', '  #  ', ' #   ', ' #   ', ' #   ', '  #  ', '   # '],
    ')': [' #   ', '  #  ', '   # ', '   # ', '   # ', '  #  ', ' #   '],
    '=': ['     ', '     ', '#####', '     ', '#####', '     ', '     '],
    '/': ['     ', '    #', '   # ', '  #  ', ' #   ', '#    ', '     '],
    'A': [' ### ', '#   #', '#   #', '#####', '#   #', '#   #', '#   #'],
    'B': ['#### ', '#   #', '#   #', '#### ', '#   #', '#   #', '#### '],
    'C': [' ### ', '#   #', '#    ', '#    ', '#    ', '#   #', ' ### '],
    'D': ['#### ', '#   #', '#   #', '#   #', '#   #', '#   #', '#### '],
    'E': ['#####', '#    ', '#    ', '#### ', '#    ', '#    ', '#####'],
    'F': ['#####', '#    ', '#    ', '#### ', '#    ', '#    ', '#    '],
    'G': [' ### ', '#   #', '#    ', '# ###', '#   #', '#   #', ' ####'],
    'H': ['#   #', '#   #', '#   #', '#####', '#   #', '#   #', '#   #'],
    'I': [' ### ', '  #  ', '  #  ', '  #  ', '  #  ', '  #  ', ' ### '],
    'K': ['#   #', '#  # ', '# #  ', '##   ', '# #  ', '#  # ', '#   #'],
    'L': ['#    ', '#    ', '#    ', '#    ', '#    ', '#    ', '#####'],
    'M': ['#   #', '## ##', '# # #', '#   #', '#   #', '#   #', '#   #'],
    'N': ['#   #', '#   #', '##  #', '# # #', '#  ##', '#   #', '#   #'],
    'O': [' ### ', '#   #', '#   #', '#   #', '#   #', '#   #', ' ### '],
    'P': ['#### ', '#   #', '#   #', '#### ', '#    ', '#    ', '#    '],
    'R': ['#### ', '#   #', '#   #', '#### ', '# #  ', '#  # ', '#   #'],
    'S': [' ####', '#    ', '#    ', ' ### ', '    #', '    #', '#### '],
    'T': ['#####', '  #  ', '  #  ', '  #  ', '  #  ', '  #  ', '  #  '],
    'U': ['#   #', '#   #', '#   #', '#   #', '#   #', '#   #', ' ### '],
    'V': ['#   #', '#   #', '#   #', '#   #', '#   #', ' # # ', '  #  '],
    'W': ['#   #', '#   #', '#   #', '# # #', '# # #', '# # #', ' # # '],
    'X': ['#   #', '#   #', ' # # ', '  #  ', ' # # ', '#   #', '#   #'],
    'Y': ['#   #', '#   #', ' # # ', '  #  ', '  #  ', '  #  ', '  #  '],
    'Z': ['#####', '    #', '   # ', '  #  ', ' #   ', '#    ', '#####'],
}
COLORS = {"setpoint": (200, 40, 40), "pos": (30, 90, 200), "ferr": (20, 140, 60), "out": (120, 60, 160)}


class Canvas:
    def __init__(self, w, h):
        self.w, self.h = w, h
        self.px = bytearray(b"\xff" * (w * h * 3))

    def dot(self, x, y, c):
        if 0 <= x < self.w and 0 <= y < self.h:
            i = (y * self.w + x) * 3
            self.px[i:i + 3] = bytes(c)

    def line(self, x0, y0, x1, y1, c):
        dx, dy = abs(x1 - x0), -abs(y1 - y0)
        sx, sy = (1 if x0 < x1 else -1), (1 if y0 < y1 else -1)
        err = dx + dy
        while True:
            self.dot(x0, y0, c)
            if x0 == x1 and y0 == y1:
                return
            e2 = 2 * err
            if e2 >= dy:
                err += dy
                x0 += sx
            if e2 <= dx:
                err += dx
                y0 += sy

    def text(self, x, y, s, c=(0, 0, 0)):
        for ch in s.upper():
            g = FONT.get(ch, FONT[" "])
            for r in range(7):
                for k in range(5):
                    if g[r][k] == "#":
                        self.dot(x + k, y + r, c)
            x += 6

    def png(self, path):
        raw = b"".join(b"\x00" + bytes(self.px[y * self.w * 3:(y + 1) * self.w * 3]) for y in range(self.h))

        def chunk(t, d):
            return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF)
        data = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", self.w, self.h, 8, 2, 0, 0, 0))
        data += chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
        with open(path, "wb") as f:
            f.write(data)


def nice(v):
    return ("%d" % v) if abs(v) >= 10 or v == int(v) else ("%.1f" % v)


def panel(cv, x, y, w, h, t, series, title):
    """series: [(name, values, colour)]"""
    vals = [v for _, vs, _ in series for v in vs]
    lo, hi = min(vals + [0]), max(vals + [0])
    if hi == lo:
        hi, lo = hi + 1, lo - 1
    pad = (hi - lo) * 0.05
    lo, hi = lo - pad, hi + pad
    t0, t1 = t[0], t[-1] if t[-1] > t[0] else t[0] + 1

    def X(tv):
        return x + int((tv - t0) / (t1 - t0) * (w - 1))

    def Y(v):
        return y + h - 1 - int((v - lo) / (hi - lo) * (h - 1))
    grey = (200, 200, 200)
    for k in range(5):                       # horizontal grid with values
        v = lo + (hi - lo) * k / 4
        cv.line(x, Y(v), x + w - 1, Y(v), grey)
        cv.text(x - 6 * len(nice(v)) - 4, Y(v) - 3, nice(v))
    if lo < 0 < hi:
        cv.line(x, Y(0), x + w - 1, Y(0), (120, 120, 120))
    for a, b in ((x, y), (x + w - 1, y)):
        cv.line(a, b, a, b + h - 1, (0, 0, 0))
    cv.line(x, y, x + w - 1, y, (0, 0, 0))
    cv.line(x, y + h - 1, x + w - 1, y + h - 1, (0, 0, 0))
    for name, vs, c in series:
        for i in range(1, len(vs)):
            cv.line(X(t[i - 1]), Y(vs[i - 1]), X(t[i]), Y(vs[i]), c)
    cv.text(x + 4, y - 10, title)
    lx = x + w - 4
    for name, _, c in reversed(series):
        lx -= 6 * len(name) + 16
        cv.line(lx, y - 7, lx + 8, y - 7, c)
        cv.text(lx + 11, y - 10, name)
    return X


def plot(csv_path, png_path, title=""):
    rows = list(csv.DictReader(open(csv_path)))
    if len(rows) < 2:
        raise SystemExit("pngplot: %s has fewer than two samples" % csv_path)
    outcol = "rate" if "rate" in rows[0] else "dac"
    t = [float(r["t_ms"]) for r in rows]
    col = {k: [float(r[k]) for r in rows] for k in ("setpoint", "pos", "ferr", outcol)}
    W, H, L = 1000, 760, 90
    cv = Canvas(W, H)
    cv.text(L, 8, title)
    pw = W - L - 20
    panel(cv, L, 40, pw, 300, t, [("setpoint", col["setpoint"], COLORS["setpoint"]),
                                  ("position", col["pos"], COLORS["pos"])], "POSITION (UNITS)")
    panel(cv, L, 380, pw, 150, t, [("ferr", col["ferr"], COLORS["ferr"])], "FOLLOWING ERROR (UNITS)")
    X = panel(cv, L, 570, pw, 150, t, [(outcol, col[outcol], COLORS["out"])],
              "STEP RATE REGISTER" if outcol == "rate" else "DAC WORD (LSB = 4.88 MV)")
    for k in range(6):                       # time axis
        tv = t[0] + (t[-1] - t[0]) * k / 5
        lab = "%.0f" % tv
        cv.text(X(tv) - 3 * len(lab), 726, lab)
    cv.text(L + pw // 2 - 30, 742, "TIME (MS)")
    cv.png(png_path)


if __name__ == "__main__":
    if len(sys.argv) < 3:
        print(__doc__)
        sys.exit(2)
    plot(sys.argv[1], sys.argv[2], sys.argv[3] if len(sys.argv) > 3 else "")
