"""The bus timing model (hal/mac4_map.h MAC4_BUS_TIMING, harness/buswait.c,
docs/memory-map.md "Bus timing"): wait states charged per bus cycle, by
region and access kind, as mac4sim's --wait-states sets them.

The boot - reset to the display's change to $5: the RAM test and the EPROM
check sum, no interrupt yet - is the same instruction stream whatever the
bus costs, so its cycles must change by exactly its bus cycles of each
region times that region's change of wait states."""
import os
import subprocess
import sys

import pytest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "tools"))
sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "host"))
import perfscen as ps  # noqa: E402
from mac4card import board  # noqa: E402  (generated from board/mac4.toml, as hal/mac4_map.h)

# the regions --wait-states takes, in the order of MAC4_BUS_TIMING, the unmapped rest last
REGIONS = [name for name, _, _ in board.BUS_TIMING] + ["unmapped"]

_boot = {}


def boot(card, ws):
    if (card, ws) not in _boot:
        _boot[(card, ws)] = ps.boot_bus(card, ws)
    return _boot[(card, ws)]


def expected_delta(zero, table):
    """Sum over regions and kinds of the bus cycles (of the 0-wait run) times
    the wait states of `table` ({region: (read, write)})."""
    return sum(n * table.get(r, (0, 0))[k] for r, counts in zero["bus"].items() for k, n in enumerate(counts))


def parse_spec(spec):
    """--wait-states SPEC as {region: (read, write)}: N everywhere, or items
    over the defaults of hal/mac4_map.h."""
    names = REGIONS
    if spec.isdigit():
        return {r: (int(spec), int(spec)) for r in names}
    t = {r: [0, 0] for r in names}
    for name, rd, wr in board.BUS_TIMING:
        t[name] = [rd, wr]
    for item in spec.split(","):
        key, v = item.split("=")
        reg, _, kind = key.partition(".")
        for k in ((0,) if kind == "read" else (1,) if kind == "write" else (0, 1)):
            t[reg][k] = int(v)
    return {r: tuple(v) for r, v in t.items()}


# every region a different number of wait states, reads and writes apart;
# small enough that the RAM test's stretches between watchdog kicks stay
# within its 100 ms (at eprom=3 and sram=2 the card resets in a loop: docs)
SPECS = ["1", "2", "dpram=3,eprom=1,sram=2,sys=4,timer=5,uart=6,watchdog=7,axis=8,virq=9",
         "eprom.read=2,sram.read=1,sram.write=3,dpram.write=5"]


@pytest.mark.parametrize("card", ["inc", "stp"])
@pytest.mark.parametrize("spec", SPECS)
def test_the_boot_takes_its_bus_cycles_times_the_wait_states_longer(card, spec):
    zero, ws = boot(card, "0"), boot(card, spec)
    assert zero["resets"] == 0 and ws["resets"] == 0, "a reset during the boot (the watchdog?)"
    assert zero["bus"] == ws["bus"], "the boot's bus cycles differ with the wait states: %s / %s" % (
        zero["bus"], ws["bus"])
    assert sum(sum(v) for v in zero["bus"].values()) > 1000000 and zero["bus"]["eprom"][0] > 0
    table = parse_spec(spec)
    want = expected_delta(zero, table)
    assert want > 0
    # the one other cost: a DPRAM word the VME host held (its polls of the
    # response queue meet the card creating it), which moves with the timing
    want += ws["contention_clocks"] - zero["contention_clocks"]
    assert ws["cycles"] - zero["cycles"] == want, "boot %d -> %d cycles at --wait-states %s: +%d, bus cycles say +%d" % (
        zero["cycles"], ws["cycles"], spec, ws["cycles"] - zero["cycles"], want)
    # and the emulator charged exactly that, region by region
    for r, counts in zero["bus"].items():
        assert ws["wait"][r] == tuple(n * table[r][k] for k, n in enumerate(counts)), r


def test_the_default_model_is_the_table_of_mac4_map_h():
    """The C side (mac4sim's configuration line) and the Python side
    (host/mac4card/board.py, generated with the header) have the same table."""
    line = boot("inc", "default")["timing"]
    assert line == boot("inc", None)["timing"]
    got = dict(item.split("=") for item in line.split()[1:])
    for name, rd, wr in board.BUS_TIMING:
        assert got[name] == "%d/%d" % (rd, wr), (name, line)
    assert got["iack"] == "autovector" and got["unmapped"] == "0/0"
    # and the default model costs the boot what the table says
    zero, dflt = boot("inc", "0"), boot("inc", None)
    table = {name: (rd, wr) for name, rd, wr in board.BUS_TIMING}
    assert dflt["cycles"] - zero["cycles"] == expected_delta(zero, table) + dflt["contention_clocks"] - zero[
        "contention_clocks"]


@pytest.mark.parametrize("spec", ["x", "eprom=", "eprom=256", "rom=1", "eprom.fetch=1", "-1"])
def test_a_bad_wait_state_spec_is_refused(spec):
    p = subprocess.run([ps.SIM, "--card", "inc", "--wait-states", spec, "--script", "-"], input="status\n",
                       capture_output=True, text=True, timeout=60)
    assert p.returncode == 1 and "wait-states" in p.stderr and "status" not in p.stdout, (p.returncode, p.stderr)


def test_the_interrupt_acknowledge_costs_the_e_clock_synchronisation():
    """Autovectored through VPA: 19 clocks at worst where Musashi's 44-cycle
    interrupt assumes 4; vectored: 4 plus the interrupter's wait states.
    The tick, acknowledge to RTE, on an idle card differs by exactly that."""
    script = "wait-display 5 3000\nrun 50\nperf reset\nrun 100\nperf irq\nbus-stats\n"
    ticks = {}
    for iack in ("autovector", "vectored"):
        p = subprocess.run([ps.SIM, "--card", "inc", "--iack", iack, "--script", "-"], input=script,
                           capture_output=True, text=True, timeout=120, check=True)
        r = ps.parse(p.stdout)
        ticks[iack] = (r["irq"]["timer"]["min"], r["irq"]["timer"]["max"], r["irq"]["timer"]["count"])
    auto, vect = ticks["autovector"], ticks["vectored"]
    diff = board.MAC4_IACK_AUTOVECTOR_CLOCKS - 4 - board.MAC4_IACK_VECTORED_WAIT
    # (a tick at the window's edge may fall in one run and not the other: the
    # two boots differ by the acknowledges' cycles, which shift the window)
    assert abs(auto[2] - vect[2]) <= 1 and min(auto[2], vect[2]) >= 39
    assert auto[0] - vect[0] == diff and auto[1] - vect[1] == diff, (auto, vect, diff)


# ---- against the 68000 reference vectors (tests/timing/busvectors.c) -------
def vector_dir():
    """SST=DIR, or ../shared/m68000-tests beside the clone (or its worktree),
    or the subset committed for a clone without it (tests/conformance/vectors)."""
    cands = [os.environ.get("SST")] + [os.path.join(ps.ROOT, up, "shared", "m68000-tests") for up in ("..", "../..")]
    cands.append(os.path.join(ps.ROOT, "tests", "conformance", "vectors"))
    for d in cands:
        if d and os.path.isdir(d) and any(f.endswith(".json.bin") for f in os.listdir(d)):
            return d
    return None


BUSVECTORS = os.path.join(ps.BUILD, "busvectors")


@pytest.mark.skipif(vector_dir() is None, reason="no 68000 reference vectors (SST=DIR or ../shared/m68000-tests)")
def test_every_reference_test_takes_its_length_plus_the_wait_states_of_its_bus_cycles():
    """Each test of the reference, run through the core as mac4sim builds it
    with a different number of wait states for every region (reads and
    writes apart, charged as mac4sim charges them), takes exactly the wait
    states of the bus cycles the core made longer ("mechanism": never
    otherwise), and, wherever the core makes the reference's bus cycles
    region by region, exactly the wait states of the reference's bus
    cycles.  Where the core's bus cycles or length differ from the
    reference's, that is the core's conformance (make conformance), which
    the summary line counts; the number of bus cycles and the length must
    agree everywhere (the patched core)."""
    assert os.path.exists(BUSVECTORS), "make build/busvectors"
    d = vector_dir()
    files = sorted(os.path.join(d, f) for f in os.listdir(d) if f.endswith(".json.bin"))
    p = subprocess.run([BUSVECTORS] + files, capture_output=True, text=True, timeout=300)
    lines = p.stdout.splitlines()
    summary = [l for l in lines if l.startswith("busvectors: ") and " tests, " in l]
    assert p.returncode == 0 and len(summary) == 1, (p.returncode, p.stderr[-2000:], lines[-5:])
    print(summary[0])
    wrong = [l for l in lines if l.startswith("busvectors: ") and " tests, " not in l]
    assert not wrong, wrong[:10]
    per_file = [dict(kv.split("=") for kv in l.split()[2:]) for l in lines if l.startswith("busvectors-file ")]
    assert len(per_file) == len(files)
    tests = sum(int(f["tests"]) for f in per_file)
    exact = sum(int(f["exact"]) for f in per_file)
    assert tests > 1000 and exact > tests * 9 // 10, summary[0]
    assert sum(int(f["mechanism_failed"]) for f in per_file) == 0
    # the core makes as many bus cycles, reads and writes, as the reference in
    # every test (the patch series, harness/musashi-patches); where only the
    # region of one differs (the address the core gives a prefetch refill),
    # the summary's first count says how often
    assert sum(int(f["count_differs"]) for f in per_file) == 0, [f for f in per_file if f["count_differs"] != "0"]
    assert sum(int(f["length_differs"]) for f in per_file) == 0, [f for f in per_file if f["length_differs"] != "0"]


def test_a_corrupt_vector_file_is_refused(tmp_path):
    bad = tmp_path / "bad.json.bin"
    bad.write_bytes(b"\x71\x5d\x3f\x1a\x05\x00\x00\x00\x10\x00")
    p = subprocess.run([BUSVECTORS, str(bad)], capture_output=True, text=True, timeout=60)
    assert p.returncode == 1 and "corrupt" in p.stderr, (p.returncode, p.stderr)
