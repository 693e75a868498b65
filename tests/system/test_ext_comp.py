"""Position compensation tables (docs/extensions.md): loading and read-back,
the refusals, and the plant with a known leadscrew error positioned within a
count with the table, off by the error without it."""
import math

import pytest

from conftest import BOOT, sim
from mac4 import code

AMP, PITCH = 20.0, 4000.0          # the plant's leadscrew error, increments
COLS, SPAN = 128, 16000            # spacing 125: the chord error of the sine stays below 0.1
TARGETS = (2500, 5300, 9100, 700, 12345)


def lead_error(u):
    return AMP * math.sin(2 * math.pi * u / PITCH)


def entries():
    sp = SPAN // COLS
    return [round(16 * lead_error(k * sp)) for k in range(1, COLS + 1)]


def crc16(words):
    crc = 0xFFFF
    for w in words:
        for b in ((w >> 8) & 0xFF, w & 0xFF):
            crc ^= b << 8
            for _ in range(8):
                crc = ((crc << 1) ^ 0x1021) if crc & 0x8000 else crc << 1
                crc &= 0xFFFF
    return crc


def load_table(axis=0, cols=COLS, span=SPAN, values=None):
    out = ["send %d WCCL %d" % (axis, cols), "send %d WCRS %d" % (axis, span), "send %d CDEF" % axis]
    out += ["send %d CENT %d" % (axis, v) for v in (values if values is not None else entries())]
    return out


def plant_load(r):
    return [float(l.split("load=")[1].split()[0]) for l in r.grep(r"^plant 0 ")]


SSI_AT = 1000000     # the SSI encoder starts here (tools/perfscen.py): <ao> puts RCP at 0


def positioning(comp, card="inc"):
    lines = [BOOT, "plant 0 leadscrew %g %g" % (AMP, PITCH)]
    if card == "ssi":
        lines += ["plant 0 pos %d" % SSI_AT, "send 0 UWSC 2", "send 0 UWAO %d" % -SSI_AT]
    lines += ["send 0 INIT"] + load_table()
    v, acc = (2000, 500) if card == "stp" else (100, 10)
    lines += ["send 0 RCSM", "send 0 CON %d" % comp, "send 0 ME", "send 0 E", "run 20",
              "send 0 WPV %d" % v, "send 0 WPA %d" % acc, "send 0 WPD %d" % acc]
    for t in TARGETS:
        lines += ["send 0 WAP %d" % t, "send 0 MP", "send 0 E", "run %d" % (8000 if card == "stp" else 1800),
                  "plant 0", "send 0 RBS", "run 5"]
    r = sim("\n".join(lines) + "\n", card)
    assert r.rc == 0, r.stderr
    return r


def load_errors(r, card):
    """|load - target| in the axis' units, the plant's frame as the card's."""
    base = SSI_AT if card == "ssi" else 0
    return [abs(l - base - t) for l, t in zip(plant_load(r), TARGETS)]


@pytest.mark.parametrize("card", ["inc", "ssi", "stp"])
def test_the_leadscrew_error_is_compensated_within_a_count(card):
    r = positioning(1, card)
    rbs = [p for a, c, p in r.resps() if c == code("RBS")]
    assert len(rbs) == len(TARGETS) and all(p & (1 << 10) for p in rbs), [hex(p) for p in rbs]   # pos_end
    assert all(p & (1 << 29) for p in rbs)                                                       # comp_on
    err = load_errors(r, card)
    assert max(err) <= 1.0, err
    # the checksum the host verifies: count and CRC-16/CCITT of the entries
    sm = [p for a, c, p in r.resps() if c == code("RCSM")][0]
    assert sm >> 16 == COLS and sm & 0xFFFF == crc16([v & 0xFFFF for v in entries()])


@pytest.mark.parametrize("card", ["inc", "ssi", "stp"])
def test_without_the_table_the_load_is_off_by_the_error(card):
    r = positioning(0, card)
    err = load_errors(r, card)
    want = [abs(lead_error(t)) for t in TARGETS]
    assert max(err) >= 10, err
    assert all(abs(e - w) <= 1.5 for e, w in zip(err, want)), (err, want)


def run_cmds(lines, card="inc"):
    r = sim(BOOT + "\n".join(lines) + "\nrun 10\n", card)
    assert r.rc == 0, r.stderr
    return r


def answers(r, mn):
    return [(c, p) for a, c, p in r.resps() if c == code(mn) or (c >= 160 and c <= 165)]


@pytest.mark.parametrize("card", ["inc", "ssi", "stp"])
def test_entries_read_back_and_the_correction_interpolates(card):
    vals = [160, 320, 160, 0]
    lines = ["send 0 INIT"] + load_table(cols=4, span=4000, values=vals)
    lines += ["send 0 CPTR %d" % i + "\nsend 0 RCEN" for i in range(4)]
    lines += ["send 0 CON 1", "run 10", "send 0 RCC", "send 0 RCP"]
    r = run_cmds(lines, card)
    rc = [p for a, c, p in r.resps() if c == code("RCEN")]
    assert rc == vals
    # at 0 the implied zero
    assert [p for a, c, p in r.resps() if c == code("RCC")] == [0]


def test_geometry_and_load_errors():
    lines = ["send 0 WCCL 7", "send 0 WCRS 1000", "send 0 CDEF",          # 1000 / 7: not whole counts
             "send 0 C", "send 0 CENT 5",                                   # no table: logical error
             "send 0 C", "send 0 WCCL 4", "send 0 WCRS 1000", "send 0 CDEF",
             "send 0 CON 1",                                                # entries missing
             "send 0 C", "send 0 CENT 20000",                               # beyond 1/16 x 1024 counts
             "send 0 C", "send 0 WCRW 15", "send 0 WCCL 16", "send 0 CDEF",  # 16 x 17 > 256
             "send 0 C", "send 0 CON 2"]
    r = run_cmds(lines)
    got = [(c, p & 0xFFFF) for a, c, p in r.resps()
           if c in (code("CDEF"), code("CENT"), code("CON"), 162, 163)]
    codes = [c for c, p in got]
    assert codes == [162, 163, code("CDEF"), 163, 162, 162, 162], got


def test_two_dimensional_table_corrects_the_target_from_two_sources():
    """A 2 x 2 table on axis 2 with axes 0 (row source) and 1 (column
    source), sources at rest put by hand: the bilinear value."""
    # grid (row i, column j): [0, 16, 32; 48, 64, 80; 96, 112, 128], spacing 1000 x 500
    vals = [16, 32, 48, 64, 80, 96, 112, 128]
    lines = ["send %d INIT" % a for a in range(3)]
    lines += ["send 2 WCRA 0", "send 2 WCCA 1", "send 2 WCRW 2", "send 2 WCCL 2", "send 2 WCRS 2000",
              "send 2 WCCS 1000", "send 2 CDEF"] + ["send 2 CENT %d" % v for v in vals]
    lines += ["send 2 CON 1", "plant 0 pos 1500", "plant 1 pos 250", "run 10", "send 2 RCC", "send 2 RCP"]
    r = run_cmds(lines)
    rcc = [p for a, c, p in r.resps() if c == code("RCC")][0]
    # row source 1500: between columns 1 and 2 (half); column source 250: between rows 0 and 1 (half)
    want = ((16 + 32) / 2 + (64 + 80) / 2) / 2
    assert rcc == round(want), (rcc, want)
    rcp = [p for a, c, p in r.resps() if c == code("RCP")][0]
    assert rcp == round(want / 16)
