"""The measurement itself (harness/perf.c, docs/performance.md): nested
interrupts accounted correctly, latency pairs every command with its answer,
probes and passes see what they claim."""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "tools"))
import perfscen as ps  # noqa: E402

ENABLE = "wait-display 5 3000\nsend 0 INIT\nsend 0 ME\nsend 0 E\nrun 10\n"


def test_emergency_stop_nested_in_the_tick_is_counted_once_and_subtracted():
    # stop 0.1 ms into a tick (the tick handler takes longer): level 7 nests in level 6
    r = ps.run("inc", ENABLE + "perf reset\nrun-ticks 1\nrun 0.1\nestop on\nrun 10\nperf irq\n")
    estop, timer = r["irq"]["estop"], r["irq"]["timer"]
    assert estop["count"] == 1, "one /STOP edge, one interrupt: %s" % estop
    assert timer["max"] - timer["xmax"] == estop["max"], (timer, estop)
    assert timer["worst_at_ms"] < estop["worst_at_ms"] < timer["worst_at_ms"] + timer["max"] / (ps.CPU_HZ / 1000)


def test_latency_pairs_every_command_with_its_answer():
    sends = "".join("send %d RCP\nrun 1\n" % (i % 4) for i in range(20))
    r = ps.run("inc", ENABLE + "perf reset\n" + sends + "run 10\nperf latency\n")
    lat = r["latency"]
    assert lat["count"] == 20 and lat["unmatched"] == 0 and lat["pending"] == 0, lat
    assert 0 < lat["min_us"] <= lat["max_us"] < 20000


def test_run_ticks_stops_at_the_expiry():
    r = ps.run("inc", ENABLE + "perf ticks -\nrun-ticks 7\nstatus\nrun-ticks 1\nstatus\n")
    ticks = [l for l in r["lines"] if l.startswith("tick ")]
    assert len(ticks) == 8
    cyc = [int(l.split("cycles=")[1].split()[0]) for l in r["lines"] if l.startswith("status ")]
    assert abs(cyc[1] - cyc[0] - ps.PERIOD["inc"]) < 200, "one tick is 2.5 ms (to an instruction)"


def test_probe_and_passes():
    r = ps.run("inc", ENABLE + "perf track on\nperf probe card_profile_tick\nperf reset\nrun 100\nperf report\n")
    p = r["probe"][ps.PROFILE_PROBE]
    assert p["count"] > 10 and p["min"] > 0
    assert r["period"][ps.PROFILE_PROBE]["count"] in (10, 11), "one profile period per 10 ms"
    assert r["pass"]["idle"]["count"] > 10 and r["pass"]["idle"]["min"] > 0
    assert r["load"]["tracked"] == 1 and 0 < r["load"]["total"] < 100


def test_profile_per_instruction_adds_up_and_counts_executions(tmp_path):
    # profile pcs: every instruction's cycles, the same cycles profile report
    # charges to functions; the EPROM check sum's loop runs once per word,
    # exactly (the instruction that ends a scheduler slice counts too)
    pcs = tmp_path / "boot.pcs"
    r = ps.run("inc", "profile on\nwait-display 5 3000\nprofile off\nprofile pcs %s\nprofile report 500\n" % pcs)
    by_func = sum(int(l.split()[2]) for l in r["lines"] if l.startswith("profile ") and l.split()[2].isdigit())
    rows = [l.split() for l in open(pcs)]
    assert rows and all(int(a, 16) % 2 == 0 and int(c) > 0 and int(k) > 0 for a, c, k in rows)
    assert sum(int(c) for _, c, _ in rows) == by_func
    out = ps.subprocess.run([sys.executable, os.path.join(ps.ROOT, "tools", "annotate.py"), "inc", str(pcs),
                             "--func", "fw_init"], capture_output=True, text=True, check=True).stdout
    import mkeprom
    words = mkeprom.CRC_OFFSET // 2              # the words before the CRC
    loop = [l for l in out.splitlines()[:-1] if int(l.split()[1]) == words]
    assert len(loop) >= 8, "the check sum's loop, once per EPROM word:\n" + out
