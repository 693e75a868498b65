"""Waveforms (docs/debugging.md): `vcd FILE [SIGNALS]` read back with a VCD
parser of its own (pyvcd) and opened by GTKWave's vcd2fst and PulseView's
libsigrok (sigrok-cli); the edges against what the plant counted, the DAC
word against the trace, and every other output unchanged by the dump."""
import csv
import os
import re
import shutil
import subprocess

import pytest
from vcd.reader import TokenKind, tokenize

from conftest import ROOT, SIM
from mac4 import board, code

SCEN = os.path.join(ROOT, "tests", "scenarios")
CYC = 10 ** 10 // board.MAC4_CPU_HZ          # 100 ps units per 68000 cycle (625)
CYC_MS = board.MAC4_CPU_HZ // 1000            # 68000 cycles per ms


def parse(path):
    """{scope.name: [(t, value), ...]} and the header's names and widths."""
    ids, names, scope, t = {}, {}, [], 0
    waves = {}
    with open(path, "rb") as f:
        for tok in tokenize(f):
            k = tok.kind
            if k == TokenKind.SCOPE:
                scope.append(tok.data.ident)
            elif k == TokenKind.UPSCOPE:
                scope.pop()
            elif k == TokenKind.VAR:
                name = ".".join(scope[1:] + [tok.data.reference])
                ids.setdefault(tok.data.id_code, []).append(name)
                names[name] = tok.data.size
                waves[name] = []
            elif k == TokenKind.CHANGE_TIME:
                t = tok.data
            elif k in (TokenKind.CHANGE_SCALAR, TokenKind.CHANGE_VECTOR):
                v = tok.data.value
                v = int(v) if isinstance(v, str) else v
                for n in ids[tok.data.id_code]:
                    waves[n].append((t, v))
    return waves, names


def value_at(wave, t):
    v = None
    for tt, vv in wave:
        if tt > t:
            break
        v = vv
    return v


BIT = board.MAC4_CPU_HZ * CYC / board.UART_BAUD   # one bit at 4800 baud, 100 ps units


def uart_bytes(wave):
    """Decode 8N1 characters from a serial line's changes, sampling the
    middle of each bit."""
    out, i = [], 1
    while i < len(wave):
        t, x = wave[i]
        if x == 0 and value_at(wave, t - 1) == 1:      # a start bit
            bits = [value_at(wave, t + BIT * (k + 1.5)) for k in range(8)]
            assert value_at(wave, t + BIT * 9.5) == 1, "stop bit"
            out.append(sum(b << k for k, b in enumerate(bits)))
            while i < len(wave) and wave[i][0] < t + BIT * 9.5:
                i += 1
            continue
        i += 1
    return out


def run(card, script, args=()):
    p = subprocess.run([SIM, "--card", card, "--script", "-"] + list(args), input=script, capture_output=True,
                       text=True, timeout=120, cwd=ROOT)
    assert p.returncode == 0, p.stderr
    return p.stdout


MOVE_INC = """include tests/scenarios/inc-7.2.mac4
trace 0 {csv} tick
send 0 ME
send 0 E
run 20
send 0 WAP 3000
send 0 MP
send 0 E
tx-msg 0 RCP
run 700
plant 0
trace off
"""


def test_inc_72_machine(tmp_path):
    v, c = tmp_path / "inc.vcd", tmp_path / "inc.csv"
    out = run("inc", "vcd %s\n" % v + MOVE_INC.format(csv=c) + "vcd off\n")
    waves, names = parse(v)
    for sig in ("card.irq6_timer", "card.ipl", "card.handler", "card.txd", "card.rxd", "card.digit", "card.dp",
                "card.leds", "card.stop", "axis1.dac", "axis1.en_n", "axis1.counter", "axis1.enc_a",
                "axis1.enc_b", "axis1.enc_z", "axis1.iesp", "axis1.iesn", "axis1.rs", "axis1.df", "axis4.dac"):
        assert sig in names, sig
    assert names["axis1.dac"] == 12 and names["axis1.counter"] == 24
    # the DAC word at every tick of the trace is the trace's
    rows = list(csv.DictReader(open(c)))
    assert len(rows) > 200
    dac = waves["axis1.dac"]
    for r in rows:
        t = round(float(r["t_ms"]) * CYC_MS) * CYC
        w = value_at(dac, t)
        assert (w - 4096 if w >= 2048 else w) == int(r["dac"]), r
    assert len(set(r["dac"] for r in rows)) > 20                     # it did move
    # the counter: where the plant left it, and A/B in quadrature with it
    plant = re.search(r"^plant 0 .*counter=0x([0-9A-F]+)", out, re.M)
    cnt = waves["axis1.counter"]
    assert cnt[-1][1] == int(plant.group(1), 16)
    a, b = waves["axis1.enc_a"], waves["axis1.enc_b"]
    edges = len(a) + len(b) - 2
    moved = sum(abs(((y - x + 2 ** 23) % 2 ** 24) - 2 ** 23) for (_, x), (_, y) in zip(cnt, cnt[1:]))
    assert moved > 1000 and abs(edges - moved) <= 4, (edges, moved)   # one A or B edge per increment
    phase = {(0, 0): 0, (1, 0): 1, (1, 1): 2, (0, 1): 3}
    for t, _ in cnt[-50:]:
        assert phase[(value_at(a, t), value_at(b, t))] == (value_at(cnt, t) - cnt[-1][1] + phase[(a[-1][1], b[-1][1])]) % 4
    # the handler: the tick every 2.5 ms, acknowledge to RTE
    h = [(t, x) for t, x in waves["card.handler"] if t > 600 * CYC_MS * CYC]
    starts = [t for t, x in h if x == board.IRQ_LEVEL_TIMER]
    period = board.PERIOD_CYCLES["inc"]
    assert all(abs((y - x) / CYC - period) < period / 10 for x, y in zip(starts, starts[1:])), starts[:5]
    # the serial telegram to the card and the answer on TxD: 10 bits of 3333 cycles
    for line in ("card.rxd", "card.txd"):
        got = uart_bytes(waves[line])
        assert got[:2] == [0x10, 0x02] and len(got) >= 10, (line, got)   # DLE STX ... (6.2)
    rcp = code("RCP")
    assert uart_bytes(waves["card.rxd"])[:10] == [0x10, 0x02, 0, rcp >> 8, rcp & 0xFF, 0, 0, 0, 0, rcp & 0xFF]
    # the boot on the display
    digits = [x for _, x in waves["card.digit"]]
    assert digits[:1] == [0xF] and 5 in digits


def test_ssi_72_machine_and_ssi_lines(tmp_path):
    v = tmp_path / "ssi.vcd"
    run("ssi", "vcd %s\ninclude tests/scenarios/ssi-7.2.mac4\nsend 0 ME\nsend 0 E\n"
        "send 1 INIT\nsend 1 ME\nsend 1 E\nrun 50\nvcd off\n" % v)
    waves, names = parse(v)
    assert "axis1.ssi_clk" in names and "axis1.ssi_data" in names and "axis1.counter" not in names
    # axis 1 of the example reads a VME encoder; axis 2, initialised, its SSI encoder at every tick
    assert len(waves["axis1.ssi_clk"]) == 1
    clk = waves["axis2.ssi_clk"]
    rises = [t for (t, x), (_, p) in zip(clk[1:], clk) if x == 1 and p == 0]
    assert len(rises) >= board.SSI_CLOCKS * 10
    # 26 clocks per read at J2's 750 kHz: 21.33 cycles each
    n = board.SSI_CLOCKS - 1
    assert abs((rises[n] - rises[0]) / CYC / n - board.MAC4_CPU_HZ / 750e3) < 0.05


def test_stp_step_edges_equal_the_steps_counted(tmp_path):
    v = tmp_path / "stp.vcd"
    out = run("stp", "vcd %s step,dir,rate,counter,en_n\nwait-display 5 3000\n" % v +
              "".join("send %d INIT\nsend %d ME\nsend %d E\n" % (a, a, a) for a in range(2)) +
              "run 40\nsend 0 WAP 1500\nsend 0 MP\nsend 0 E\nsend 1 WAP -700\nsend 1 MP\nsend 1 E\n"
              "run 1500\nplant 0\nplant 1\nvcd off\n")
    waves, names = parse(v)
    assert set(names) == {"axis%d.%s" % (a, s) for a in range(1, 5) for s in ("step", "dir", "rate", "counter", "en_n")}
    for a in (0, 1):
        gen = int(re.search(r"^plant %d .*generated=(-?\d+)" % a, out, re.M).group(1))
        st = waves["axis%d.step" % (a + 1)]
        rises = sum(1 for (_, x), (_, p) in zip(st[1:], st) if x == 1 and p == 0)
        assert gen != 0 and rises == abs(gen), (a, rises, gen)
        assert waves["axis%d.counter" % (a + 1)][-1][1] == gen % 2 ** 24
        d = waves["axis%d.dir" % (a + 1)]
        assert value_at(d, st[-1][0]) == (1 if gen > 0 else 0)


def test_outputs_unchanged_by_the_dump(tmp_path):
    c1, c2 = tmp_path / "a.csv", tmp_path / "b.csv"
    plain = run("inc", MOVE_INC.format(csv=c1) + "irqstats\nperf irq\nstatus\n", ["--timestamps"])
    dumped = run("inc", "vcd %s\n" % (tmp_path / "x.vcd") + MOVE_INC.format(csv=c2) + "irqstats\nperf irq\nstatus\n",
                 ["--timestamps"])
    assert plain == dumped
    assert open(c1).read() == open(c2).read()


def test_signal_selection_and_errors(tmp_path):
    v = tmp_path / "s.vcd"
    run("inc", "vcd %s axis2.dac,digit\nrun 5\nvcd off\n" % v)
    _, names = parse(v)
    assert set(names) == {"axis2.dac", "card.digit"}
    p = subprocess.run([SIM, "--card", "inc", "--script", "-"], input="vcd %s step\n" % v, capture_output=True,
                       text=True, timeout=30)
    assert p.returncode == 1 and "no signal 'step'" in p.stderr
    listing = run("stp", "vcd signals\n")
    assert "vcd-signal axis1.step 1 " in listing and "dac" not in listing


@pytest.mark.parametrize("tool", ["vcd2fst", "sigrok-cli"])
def test_opens_in_gtkwave_and_pulseview(tmp_path, tool):
    if shutil.which(tool) is None:
        pytest.skip("%s missing (tools/deps/apt.txt: gtkwave, sigrok-cli)" % tool)
    v = tmp_path / "inc.vcd"
    run("inc", "vcd %s\n" % v + MOVE_INC.format(csv=tmp_path / "t.csv") + "vcd off\n")
    if tool == "vcd2fst":
        p = subprocess.run(["vcd2fst", str(v), str(tmp_path / "inc.fst")], capture_output=True, text=True, timeout=60)
        assert p.returncode == 0 and os.path.getsize(tmp_path / "inc.fst") > 1000, p.stderr
    else:
        p = subprocess.run(["sigrok-cli", "-I", "vcd", "-i", str(v), "--show"], capture_output=True, text=True,
                           timeout=60)
        assert p.returncode == 0 and "enc_a" in p.stdout and "Samplerate: 10000000000" in p.stdout, p.stdout + p.stderr
