#!/usr/bin/env python3
"""plot.py - plots of moves with matplotlib (docs/debugging.md, "Plots").

    tools/plot.py OUT.png TRACE.csv [TRACE.csv ...] [--title TEXT]

Each TRACE is a CSV the emulator writes: a plant trace (`trace AXIS FILE
tick card`: the position at every servo tick, the card's published words
beside it) or a `perf sample FILE AXIS` (the published words per tick).
A file named ...-aN.csv or given as N=FILE is axis N (wire number 0-3, shown
as the manual's axis N+1); otherwise the files are axes 0, 1, ... in order.

Three panels over the time from the start of the move: the position (at
the tick, from the plant) with the setpoint the card published, the
following error the card published, and the output (DAC volts, or the step
field in Hz on the STP).  Every axis whose position changed is drawn.
"""
import argparse
import csv
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

COLORS = ["#1f5fbf", "#c0392b", "#1e8449", "#7d3c98"]


def read(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if len(rows) < 2:
        raise SystemExit("plot: %s has fewer than two rows" % path)
    cols = rows[0].keys()
    if "t_ms" not in cols:
        raise SystemExit("plot: %s is not a trace of mac4sim (no t_ms column)" % path)

    def col(name):
        try:
            return [float(r[name]) for r in rows] if name in cols else None
        except ValueError:
            raise SystemExit("plot: %s: column %s is not numeric" % (path, name))
    d = {"t": col("t_ms")}
    if "rotor" in cols:                      # STP plant trace
        d.update(kind="stp", pos=col("rotor"), out=col("field_hz"))
    elif "position" in cols:                 # INC/SSI plant trace
        d.update(kind="servo", pos=col("position"), out=col("volts"))
    elif "pos" in cols:                      # perf sample: the published words only
        d.update(kind="sample", pos=col("pos"), out=col("rate") or [x * 10.0 / 2048 for x in col("dac")],
                 out_is_rate="rate" in cols)
    else:
        raise SystemExit("plot: %s: neither a plant trace nor a perf sample" % path)
    d["setpoint"] = col("setpoint")
    d["ferr"] = col("ferr")
    return d


def axis_of(arg, i):
    m = re.match(r"^(\d)=(.*)$", arg)
    if m:
        return int(m.group(1)), m.group(2)
    m = re.search(r"-a(\d)\.csv$", arg)
    return (int(m.group(1)) if m else i), arg


def move_start(d):
    """The first row where the setpoint (else the position) leaves its first value."""
    ref = d["setpoint"] or d["pos"]
    for i, v in enumerate(ref):
        if abs(v - ref[0]) > 0.5:
            return max(i - 1, 0)
    return 0


def plot(traces, png, title="", unit=None):
    """traces: {axis: csv path}. Writes png; returns the axes drawn."""
    data = {a: read(p) for a, p in traces.items()}
    moved = {a: d for a, d in data.items() if max(d["pos"]) - min(d["pos"]) > 1.0}
    if not moved:
        moved = data
    kinds = {d["kind"] for d in moved.values()}
    stp = "stp" in kinds or any(d.get("out_is_rate") for d in moved.values())
    if unit is None:
        unit = "steps" if stp else "inc"
    t0 = min(d["t"][move_start(d)] for d in moved.values())
    fig, (ax1, ax2, ax3) = plt.subplots(3, 1, sharex=True, figsize=(10, 7.5), dpi=100,
                                        gridspec_kw={"height_ratios": [2.2, 1, 1]})
    for a, d in sorted(moved.items()):
        c = COLORS[a % 4]
        t = [x - t0 for x in d["t"]]
        at_tick = d["kind"] != "sample"
        ax1.plot(t, d["pos"], color=c, lw=1.6, drawstyle="default" if at_tick else "steps-post",
                 label="axis %d position%s" % (a + 1, " (at the tick)" if at_tick else " (published)"))
        if d["setpoint"]:
            ax1.plot(t, d["setpoint"], color=c, lw=1, ls="--", drawstyle="steps-post",
                     label="axis %d setpoint (published)" % (a + 1))
        if d["ferr"]:
            ax2.plot(t, d["ferr"], color=c, lw=1.2, drawstyle="steps-post", label="axis %d" % (a + 1))
        ax3.plot(t, d["out"], color=c, lw=1.2, label="axis %d" % (a + 1))
    ax1.set_ylabel("position [%s]" % unit)
    ax2.set_ylabel("following error [%s]" % unit)
    ax3.set_ylabel("step field [Hz]" if stp else "DAC output [V]")
    ax3.set_xlabel("time from the start of the move [ms]")
    for ax in (ax1, ax2, ax3):
        ax.grid(True, color="#dddddd", lw=0.6)
        for side in ("top", "right"):
            ax.spines[side].set_visible(False)
    ax1.legend(loc="best", fontsize=8, frameon=False, ncol=2)
    if not any(d["ferr"] for d in moved.values()):
        ax2.text(0.5, 0.5, "no card columns in the trace (trace AXIS FILE tick card)", ha="center",
                 va="center", transform=ax2.transAxes, color="#888888")
    ax1.set_xlim(left=0)
    if title:
        fig.suptitle(title, fontsize=11)
    fig.tight_layout()
    fig.savefig(png)
    plt.close(fig)
    return sorted(moved)


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("png")
    ap.add_argument("traces", nargs="+")
    ap.add_argument("--title", default="")
    ap.add_argument("--unit", default=None, help="position unit (default inc, or steps on the STP)")
    a = ap.parse_args(argv)
    traces = {}
    for i, arg in enumerate(a.traces):
        n, path = axis_of(arg, i)
        if not os.path.exists(path):
            raise SystemExit("plot: no such trace %s" % path)
        traces[n] = path
    drawn = plot(traces, a.png, a.title, a.unit)
    print("plot: %s, axes %s" % (a.png, " ".join(str(n + 1) for n in drawn)))


if __name__ == "__main__":
    main(sys.argv[1:])
