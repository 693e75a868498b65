"""The following-error and settling figures of `make bench` (tools/perfscen.py,
docs/performance.md): the metric on rows whose answer is known, and the
standard move on the 7.2 examples runs and gives consistent figures.  A
benchmark is not a timed test: nothing here asserts how good the figures are."""
import os
import sys

import pytest

from conftest import ROOT

sys.path.insert(0, os.path.join(ROOT, "tools"))
import perfscen as ps  # noqa: E402

POS_END = 1 << ps.POS_END_BIT


def row(t, sp, pos, ustat=0, out=0):
    return {"t_ms": t, "card_pos": pos, "setpoint": sp, "ferr": sp - pos, "out": out, "ustat": ustat}


def synthetic(repeat=1):
    """A move 0 -> 100, the setpoint moving from 10 to 50 ms, lagging by 4, 3, 2,
    1, 2; then an overshoot to 115, inside <tr> = 5 at 100 ms, out again at
    110 and 120, inside from 130 ms on; pos_end from 100 ms."""
    pts = [(0, 0, 0), (10, 20, 16), (20, 40, 37), (30, 60, 58), (40, 80, 79), (50, 100, 98),
           (60, 100, 108), (70, 100, 115), (80, 100, 111), (90, 100, 107), (100, 100, 104),
           (110, 100, 107), (120, 100, 106), (130, 100, 103), (140, 100, 101), (150, 100, 100)]
    out = []
    for t, sp, pos in pts:
        st = POS_END if t >= 100 else 0
        for k in range(repeat):                 # the card's words repeat between refreshes
            out.append(row(t + 2.5 * k, sp, pos, st))
    return out


def test_move_metrics_on_a_known_move():
    m = ps.move_metrics(synthetic(), 100, 5)
    assert m["ferr_max"] == 4 and m["ferr_samples"] == 5
    assert m["ferr_rms"] == pytest.approx(((16 + 9 + 4 + 1 + 4) / 5) ** 0.5, abs=0.01)
    assert m["move_ms"] == 40                    # first sample off the start to the first at the target
    assert m["settling_ms"] == 130 - 50          # inside from 130 on (120 is still out: 106)
    assert m["overshoot"] == 15 and m["pos_end_ms"] == 90 and m["final_pos"] == 100


def test_repeated_rows_count_once():
    assert ps.move_metrics(synthetic(4), 100, 5) == ps.move_metrics(synthetic(), 100, 5)


def test_move_metrics_without_settling_or_arrival():
    rows = synthetic()
    rows[-1] = row(150, 100, 120)               # out of <tr> at the end of the window
    assert ps.move_metrics(rows, 100, 5)["settling_ms"] is None
    assert ps.move_metrics(synthetic(), 200, 5) is None       # the setpoint never got there
    neg = [dict(r, setpoint=-r["setpoint"], card_pos=-r["card_pos"], ferr=-r["ferr"]) for r in synthetic()]
    m = ps.move_metrics(neg, -100, 5)
    assert m["overshoot"] == 15 and m["ferr_max"] == 4 and m["settling_ms"] == 80


@pytest.mark.parametrize("card", ["inc", "ssi"])
def test_the_standard_move_runs_and_its_figures_agree(card, tmp_path):
    m = ps.standard_move(card, str(tmp_path))
    target = ps.STANDARD_MOVE[card]["target"]
    assert m["tr"] >= 0 and abs(m["final_pos"] - target) <= m["tr"]
    assert m["ferr_max"] >= m["ferr_rms"] > 0
    # the move takes at least the distance at WPV (10 ms per SP)
    assert m["move_ms"] >= target / ps.STANDARD_MOVE[card]["pv"] * 10
    assert m["settling_ms"] is not None and m["pos_end_ms"] is not None
    assert m["pos_end_ms"] >= m["move_ms"]
    assert m["overshoot"] <= m["ferr_max_settling"]
