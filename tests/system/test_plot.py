"""Plots of moves (tools/plot.py, docs/debugging.md): matplotlib PNGs of
every axis that moved, from plant traces at the tick; the bench's plot; bad
input said plainly."""
import os
import subprocess
import sys

import matplotlib.image as mpimg
import numpy as np

from conftest import ROOT, SIM

PLOT = os.path.join(ROOT, "tools", "plot.py")
sys.path.insert(0, os.path.join(ROOT, "tools"))


def traces(tmp_path, targets):
    lines = ["wait-display 5 3000"]
    for a in range(4):
        lines += ["send %d INIT" % a, "send %d ME" % a, "send %d E" % a]
    lines.append("run 20")
    for a, tgt in targets.items():
        lines += ["send %d WPV 100" % a, "send %d WPA 10" % a, "send %d WPD 10" % a, "send %d WAP %d" % (a, tgt),
                  "send %d MP" % a]
    files = {}
    for a in range(4):
        files[a] = str(tmp_path / ("m-a%d.csv" % a))
        lines.append("trace %d %s tick card" % (a, files[a]))
    lines += ["send %d E" % a for a in targets] + ["run 1200", "trace off"]
    p = subprocess.run([SIM, "--card", "inc", "--script", "-"], input="\n".join(lines) + "\n", capture_output=True,
                       text=True, timeout=120)
    assert p.returncode == 0, p.stderr
    return files


def has_color(img, hexcolor, tol=0.08):
    rgb = np.array([int(hexcolor[i:i + 2], 16) / 255 for i in (1, 3, 5)])
    return int((np.abs(img[:, :, :3] - rgb).max(axis=2) < tol).sum())


def test_every_axis_that_moved(tmp_path):
    import plot
    files = traces(tmp_path, {0: 6000, 2: -4000})          # axes 1 and 3 move, 2 and 4 stand
    png = tmp_path / "m.png"
    p = subprocess.run([sys.executable, PLOT, str(png)] + [files[a] for a in range(4)] + ["--title", "two moves"],
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr
    assert "axes 1 3" in p.stdout
    img = mpimg.imread(str(png))
    assert img.shape[:2] == (750, 1000)
    assert has_color(img, plot.COLORS[0]) > 500 and has_color(img, plot.COLORS[2]) > 500
    assert has_color(img, plot.COLORS[1]) == 0 and has_color(img, plot.COLORS[3]) == 0


def test_bench_plot(tmp_path):
    import bench
    png = tmp_path / "bench.png"
    bench.plot_move(str(png))
    img = mpimg.imread(str(png))
    assert img.shape[:2] == (750, 1000) and has_color(img, "#1f5fbf") > 500


def test_bad_input(tmp_path):
    bad = tmp_path / "bad.csv"
    bad.write_text("a,b\n1,2\n3,4\n")
    for args, msg in (([str(bad)], "not a trace"), ([str(tmp_path / "none.csv")], "no such trace")):
        p = subprocess.run([sys.executable, PLOT, str(tmp_path / "x.png")] + args, capture_output=True, text=True,
                           timeout=60)
        assert p.returncode != 0 and msg in p.stderr and "Traceback" not in p.stderr, p.stderr
