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
