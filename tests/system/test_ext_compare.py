"""Position compare (docs/extensions.md): the axis crossing programmed
positions raises its own VMEbus interrupt and sets pc_hit, once or every N
counts in a window; at most one interrupt per axis per tick, every crossing
counted; the latency from the sampling instant in cycles."""
import csv
import os

import pytest

from conftest import BOOT, sim
from mac4 import code, BIT, board

VECTOR = 97
CPU_HZ = 16000000
PERIOD = {"inc": 40000, "ssi": 40000, "stp": 128000}       # the tick, cycles
SSI_AT = 1000000


def ms_of(line):
    return float(line.split("ms ")[0].lstrip("@"))


def compare_run(tmp_path, card="inc", p0=1000, n=500, end=5000, target=8000, back=False, vel=100):
    base = SSI_AT if card == "ssi" else 0
    trace = str(tmp_path / ("trace-%s.csv" % card))
    lines = [BOOT] + (["plant 0 pos %d" % base] if base else [])
    if card == "ssi":
        lines.append("send 0 UWSC 2")
    lines += ["send 0 INIT", "send 0 ME", "send 0 E", "run 20",
              "send 0 WIRQ7 %d" % VECTOR, "send 0 WPCP %d" % (base + p0), "send 0 WPCN %d" % n,
              "send 0 WPCE %d" % (base + end), "send 0 PCON 1"]
    acc = 500 if card == "stp" else 10
    vel = 2000 if card == "stp" else vel            # Hz on the STP (perfscen.motion)
    lines += ["send 0 WPV %d" % vel, "send 0 WPA %d" % acc, "send 0 WPD %d" % acc,
              "send 0 WAP %d" % (base + target), "send 0 MP", "trace 0 %s tick" % trace, "send 0 E",
              "run %d" % (5500 if card == "stp" else 1500)]
    if back:
        lines += ["send 0 WAP %d" % base, "send 0 E", "run %d" % (3000 if card == "stp" else 1500)]
    lines += ["trace off", "send 0 RPCC", "send 0 RPCI", "send 0 RBS", "peek32 0x%X" % board.DPC_VME_IRQ_LOST, "run 5"]
    r = sim("\n".join(lines) + "\n", card, args=["--timestamps"])
    assert r.rc == 0, r.stderr
    col = "generated" if card == "stp" else "position"     # what the card counts (STP: its steps)
    rows = [(float(x["t_ms"]), float(x[col])) for x in csv.DictReader(open(trace))]
    irqs = [ms_of(l) for l in r.grep(r"vme-irq \d+ %d$" % VECTOR)]
    got = {}
    for l in r.grep(r"ms resp "):                       # (--timestamps: the time first)
        _, _, axis, c, p = l.split()
        got[int(c)] = int(p, 16)
    return r, rows, irqs, got, base


def sample_before(rows, t_ms):
    """The last timer expiry before t_ms: (time, plant position)."""
    prev = None
    for t, x in rows:
        if t > t_ms:
            break
        prev = (t, x)
    return prev


@pytest.mark.parametrize("card", ["inc", "ssi", "stp"])
def test_every_n_counts_in_the_window(tmp_path, card):
    r, rows, irqs, got, base = compare_run(tmp_path, card)
    points = [base + 1000 + 500 * k for k in range(9)]
    assert len(irqs) == 9, irqs
    assert got[code("RPCC")] == 9 and got[code("RPCI")] == 9
    assert got[code("RBS")] & (1 << BIT["user"]["pc_hit"])
    # each one right after the tick whose sample first lay beyond its point:
    # the sampling instant before the request is past the point, the one
    # before that short of it; the latency from that instant within a period
    for pt, t_irq in zip(points, irqs):
        t_s, x_s = sample_before(rows, t_irq - 0.002)    # the request is 2 us before the host's IACK
        i = [t for t, _ in rows].index(t_s)
        assert x_s >= pt - 0.5 and rows[i - 1][1] < pt + 0.5, (pt, rows[i - 1], (t_s, x_s))
        lat = (t_irq - 0.002 - t_s) * CPU_HZ / 1000
        assert 0 < lat < PERIOD[card], lat


def test_a_small_n_at_speed_gives_one_interrupt_per_tick_and_counts_all(tmp_path):
    """Every 10 counts at 25 counts per tick: two or three points per tick,
    one interrupt for them, every crossing counted, none lost."""
    r, rows, irqs, got, base = compare_run(tmp_path, n=10, back=True)
    assert got[code("RPCC")] == 2 * 401, got[code("RPCC")]
    assert got[code("RPCI")] == len(irqs) and 2 * 140 <= len(irqs) < 401, len(irqs)
    expiries = [t for t, _ in rows]
    ticks = [max(k for k, t in enumerate(expiries) if t <= i - 0.002) for i in irqs]
    assert len(set(ticks)) == len(ticks), "two compare interrupts after one tick"
    assert [l.split()[-1] for l in r.grep(r"peek32 0x%X" % board.DPC_VME_IRQ_LOST)] == ["0x00000000"]                              # no VME interrupt lost (DPC_VME_IRQ_LOST)


def test_once_interrupts_once_and_counts_every_crossing(tmp_path):
    r, rows, irqs, got, base = compare_run(tmp_path, p0=3000, n=0, back=True)
    assert len(irqs) == 1
    assert got[code("RPCI")] == 1 and got[code("RPCC")] == 2


def test_off_by_default_and_refused_values(tmp_path):
    r = sim(BOOT + "send 0 INIT\nsend 0 PCON 2\nsend 0 C\nsend 0 RPCI\nsend 0 RBS\nrun 5\n", "inc")
    res = r.resps()
    assert res[1][1] == 162                                  # PCON 2: limit value error
    assert [p for a, c, p in res if c == code("RPCI")] == [0]
    assert not [p for a, c, p in res if c == code("RBS")][0] & (1 << BIT["user"]["pc_hit"])
