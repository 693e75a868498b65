"""make demo's host script (tools/demo.mac4) shows what it says: the error
answered and acknowledged, then axis 1 really moving to its target."""
import csv
import os
import subprocess

from conftest import ROOT, SIM


def test_demo_script_moves_axis_1():
    p = subprocess.run([SIM, "--card", "inc", "--script", os.path.join(ROOT, "tools", "demo.mac4")],
                       cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr[-2000:]
    assert "resp 0 161 " in p.stdout                     # code 1: syntax error
    assert "resp 0 4 " in p.stdout                       # C acknowledges it
    with open(os.path.join(ROOT, "build", "demo-move.csv")) as f:
        rows = list(csv.DictReader(f))
    pos = [int(r["pos"]) for r in rows]
    assert max(pos) >= 7990 and abs(pos[-1] - 8000) <= 10, (min(pos), max(pos), pos[-1])


def test_make_demo_says_which_budgets_are_met():
    """tools/demo.sh: every budget line says met or not met, by its figure;
    the comments give the manual's axis number beside the wire number."""
    p = subprocess.run([os.path.join(ROOT, "tools", "demo.sh")], cwd=ROOT, capture_output=True,
                       text=True, timeout=300)
    assert p.returncode == 0, p.stderr[-2000:]
    lines = p.stdout.splitlines()
    head = [i for i, l in enumerate(lines) if l.startswith("cycles at 16 MHz over")]
    assert len(head) == 1, p.stdout
    rows = []
    for l in lines[head[0] + 1:]:
        if not l.startswith("  "):
            break
        rows.append(l)
    assert len(rows) >= 4, p.stdout
    for l in rows:
        used = int([w for w in l.split() if w.endswith("%") and w[:-1].isdigit()][-1][:-1])
        assert l.endswith("  met") == (used <= 100), l
        assert l.endswith("NOT MET yet (an aim: make bench)") == (used > 100), l
    assert "the manual's axis 1" in p.stdout
