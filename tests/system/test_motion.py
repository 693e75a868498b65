"""Closed-loop motion on MAC4-INC and MAC4-SSI against the plant
models, end to end through the EPROM image."""
import re

import pytest

from conftest import BOOT, sim
from mac4 import EXT_POS, MODE, code, has, mode, obits, samples, stop_line, ubits, watch

INIT_EN = ["send %d INIT", "send %d ME", "send %d E"]


def axis(lines, n=0):
    return [l % n if "%d" in l else l for l in lines]


def go(lines, card="inc", args=(), allow=False):
    r = sim(BOOT + "\n".join(lines) + "\n", card, args=list(args) + (["--allow-faults"] if allow else []))
    assert r.rc == 0, (r.stderr, r.faults())
    return r


MOVE = ["send 0 WPV 60", "send 0 WPA 6", "send 0 WPD 6"]


# ---- positioning ----------------------------------------------------------------
def test_positioning_inc_example_gains():
    # 7.2 MAC4-INC controller set-up (USR omitted: the default plant is wired positive)
    cfg = ["send 0 WGA 80", "send 0 WZE 128", "send 0 WPO 0", "send 0 UWKISC 3", "send 0 WKI 41",
           "send 0 WMF 2000", "send 0 WAA 5000", "send 0 WLV 20", "send 0 WIRQ3 0xA2", "send 0 WIRQ4 0xA4"]
    r = go(cfg + axis(INIT_EN) + ["run 20"] + MOVE +
           ["send 0 WAP 30000", "send 0 MP", "send 0 E"] + watch(ms=20, count=600) + ["leds", "plant 0"],
           args=["--irq-level", "4"])
    st, ps = samples(r)
    assert has(st[-1], "pos_end") and mode(st[-1]) == MODE["positioning"]
    assert abs(ps[-1] - 30000) <= 10                       # <tr> default 10
    # overshoot: the integrator (C = 0.02) charges during 5 s of cruising at a
    # constant following error and unwinds after the stop; with the velocity
    # amplifier of the default plant that is ~50 increments (docs/performance.md)
    assert max(ps) <= 30000 + 100
    assert r.grep(r"^vme-irq 4 164$") and len(r.grep(r"^vme-irq 4 164$")) == 1   # interrupt 4 once
    leds = int(r.grep(r"^leds ")[0].split()[1], 16)
    assert leds & 0x2                                      # LED P of axis 1
    first_end = next(i for i, s in enumerate(st) if has(s, "pos_end"))
    assert all(has(s, "pos_end") for s in st[first_end:])


def test_in_pos_is_a_stepper_bit():
    """7.1.2: system status bit 15 in_pos is the MAC4-STP's LED P; a servo
    card leaves it clear at pos_end."""
    r = go(axis(INIT_EN) + ["run 20"] + MOVE + ["send 0 WAP 2000", "send 0 MP", "send 0 E", "run 3000",
                                                 "send 0 RBS", "send 0 RSS", "run 5"])
    rbs, rss = [int(l.split()[3], 16) for l in r.grep(r"^resp 0 (%d|%d) " % (code("RBS"), code("RSS")))][-2:]
    assert rbs & ubits("pos_end")
    assert not rss & (1 << 15)


def test_target_radius_and_time():
    r = go(axis(INIT_EN) + ["run 20"] + MOVE +
           ["send 0 WTR 0", "send 0 WTRT 200", "send 0 WAP 5000", "send 0 MP", "send 0 E"] + watch(count=300))
    st, ps = samples(r)
    first_end = next(i for i, s in enumerate(st) if has(s, "pos_end"))
    # <tr> 0: exactly on target, then for <trt> = 200 ms (20 SP) before pos_end
    at = [i for i, p in enumerate(ps) if p == 5000]
    assert at and first_end >= at[0] + 18
    assert ps[first_end] == 5000


def test_on_fly_new_target_5_15_example_2():
    r = go(axis(INIT_EN) + ["run 20"] + MOVE +
           ["send 0 WAP 20000", "send 0 MP", "send 0 E", "run 600", "send 0 WAP 10000", "send 0 E"] +
           watch(count=400))
    st, ps = samples(r)
    assert max(ps) < 20000                                 # never went to 20000
    assert abs(ps[-1] - 10000) <= 10 and has(st[-1], "pos_end")


def test_off_fly_5_15_example_2():
    r = go(axis(INIT_EN) + ["run 20", "send 0 FLYOFF"] + MOVE +
           ["send 0 WAP 20000", "send 0 MP", "send 0 E", "run 600", "send 0 WAP 10000", "send 0 E"] +
           watch(count=700))
    st, ps = samples(r)
    assert max(ps) >= 20000 - 10                           # went to 20000 first
    assert abs(ps[-1] - 10000) <= 10 and has(st[-1], "pos_end")
    assert not has(st[-1], "on_fly")


def test_off_fly_commands_wait_but_stop_bits_act():
    r = go(axis(INIT_EN) + ["run 20", "send 0 FLYOFF"] + MOVE +
           ["send 0 WAP 40000", "send 0 MP", "send 0 E", "run 300", "send 0 RBS", "run 100",
            stop_line(0)] + watch(count=80))
    st, ps = samples(r)
    # RBS was held while the move ran; the stop bit brakes at once and then it is answered
    assert mode(st[-1]) == MODE["brake"]
    assert ps[-1] < 40000 - 1000
    assert r.resps()[-1][1] == 125


# ---- other modes ----------------------------------------------------------------
def test_speed_mode_and_brake():
    r = go(axis(INIT_EN) + ["run 20", "send 0 WVT 40", "send 0 WPA 4", "send 0 WPD 4", "send 0 MS",
                            "send 0 E"] + watch(count=100) + ["send 0 MB", "send 0 E"] + watch(count=60))
    st, ps = samples(r)
    v = (ps[99] - ps[79]) / 20                            # increments per 10 ms = per SP
    assert 37 <= v <= 43
    assert mode(st[-1]) == MODE["brake"] and ps[-1] == ps[-5]   # stopped


def test_velocity_tracking_and_position_tracking():
    r = go(axis(INIT_EN) + ["run 20", "send 0 WVT -25", "send 0 VT", "send 0 E"] + watch(count=60))
    st, ps = samples(r)
    v = (ps[59] - ps[39]) / 20
    assert -27 <= v <= -23
    # position tracking: the host supplies a ramp of positions, one per SP
    ramp = []
    for k in range(1, 41):
        ramp += ["send 0 WAT %d" % (k * 30), "run 10"]
    r = go(axis(INIT_EN) + ["run 20", "send 0 PT", "send 0 E"] + ramp + watch(count=30))
    st, ps = samples(r)
    assert mode(st[-1]) == MODE["position tracking"] and abs(ps[-1] - 1200) <= 3
    assert not has(st[-1], "ferr_f")


def test_test_mode_drives_and_limit_switch_disables():
    r = go(["switch 0 lp 3000"] + ["send 0 INIT", "send 0 WDA 300", "send 0 MT", "send 0 E"] +
           watch(count=200))
    st, ps = samples(r)
    assert mode(st[-1]) == MODE["disable"]
    assert ps[-1] >= 3000


def test_reset_mode_brakes_then_disables():
    r = go(axis(INIT_EN) + ["run 20", "send 0 WVT 50", "send 0 MS", "send 0 E", "run 500", "send 0 MRE",
                            "send 0 E"] + watch(count=60))
    st, ps = samples(r)
    assert MODE["reset"] in [mode(s) for s in st] or mode(st[0]) == MODE["disable"]
    assert mode(st[-1]) == MODE["disable"]     # <ed> ramp, then the drive is off (it coasts)


# ---- justification --------------------------------------------------------------
def test_search_index_coarse_and_fine():
    r = go(["plant 0 encoder lines 1000 index 1000"] + axis(INIT_EN) +
           ["run 20", "send 0 WCV 30", "send 0 WIRQ4 0x44", "send 0 MC", "send 0 E"] + watch(count=200) +
           ["send 0 MB", "send 0 E", "run 50", "send 0 WCV -1", "send 0 WLV 2", "send 0 MI", "send 0 E"] +
           watch(count=300) + ["plant 0"])
    st, ps = samples(r)
    coarse = [i for i, s in enumerate(st) if has(s, "jus_end") and mode(s) == MODE["search index coarse"]]
    assert coarse
    assert abs(ps[coarse[0] + 5] - 1000) < 300             # stopped near the index at 1000
    assert has(st[-1], "jus_end") and mode(st[-1]) == MODE["search index"]
    assert abs(ps[-1]) <= 2                                # the index is now position 0
    assert len(r.grep(r"^vme-irq 3 68$")) == 2


def test_search_index_needs_the_incremental_encoder():
    got = [c for _, c, _ in go(["send 0 UWET 3", "send 0 UWEA 0x%X" % EXT_POS] + axis(INIT_EN) +
                               ["send 0 MC", "send 0 E", "run 30"]).resps()]
    assert got[-1] == 163


def test_home_left_edge_then_index():
    r = go(["switch 0 ref 6000 2000", "plant 0 encoder lines 1000 index 0"] + axis(INIT_EN) +
           ["run 20", "send 0 WHV 40", "send 0 WHA 5", "send 0 WHD 5", "send 0 WLV 5", "send 0 MH", "send 0 E"] +
           watch(count=800) + ["plant 0"])
    st, ps = samples(r)
    assert has(st[-1], "jus_end") and mode(st[-1]) == MODE["home"]
    assert abs(ps[-1]) <= 2                                # at the index: position 0
    m = re.search(r"pos=(-?\d+)", r.grep(r"^plant 0 ")[0])
    assert 6000 <= int(m.group(1)) <= 8000 + 10            # the index after the left edge 6000 (every 4000)


def test_find_edge_reference_and_negative_limit():
    r = go(["switch 0 ref 3000 1000"] + axis(INIT_EN) +
           ["run 20", "send 0 WFV 40", "send 0 WFA 5", "send 0 WFD 5", "send 0 WLV 4", "send 0 WDL 0",
            "send 0 MF", "send 0 E"] + watch(count=300))
    st, ps = samples(r)
    assert has(st[-1], "jus_end")
    assert 2990 <= ps[-1] <= 3010                          # back to the transition it found first
    r = go(["switch 0 ln -2000"] + axis(INIT_EN) +
           ["run 20", "send 0 WFV 40", "send 0 WFA 5", "send 0 WFD 5", "send 0 WLV 4", "send 0 WDL 1",
            "send 0 MF", "send 0 E"] + watch(count=300))
    st, ps = samples(r)
    assert has(st[-1], "jus_end") and not has(st[-1], "hwl_n")
    assert -2010 <= ps[-1] <= -1990


# ---- protective reactions ---------------------------------------------------------
def test_following_error_stalled_motor():
    r = go(axis(INIT_EN) + ["run 20", "plant 0 motor coulomb 100", "send 0 WMF 500"] + MOVE +
           ["send 0 WAP 20000", "send 0 MP", "send 0 E"] + watch(count=150) + ["send 0 RBS", "send 0 ME",
                                                                               "send 0 ME", "run 5"])
    st, ps = samples(r)
    assert has(st[-1], "ferr_f") and mode(st[-1]) == MODE["disable"]
    got = r.resps()
    assert got[-3][1] == 125 and has(got[-3][2], "ferr_f")   # a read runs and shows the error (6.3)
    assert got[-2][1] == 163 and got[-1][1] == 163        # reported, then not acknowledged


def test_software_limit_brakes_and_disables():
    # find edge towards a reference switch that is not there leaves <lp> (4.3.1.1)
    r = go(["send 0 UWLP 5000", "switch 0 ref 100000 100"] + axis(INIT_EN) +
           ["run 20", "send 0 WFV 50", "send 0 WFA 5", "send 0 WDL 0", "send 0 MF", "send 0 E"] +
           watch(count=200) + ["send 0 RBS", "send 0 ME", "run 5"])
    st, ps = samples(r)
    assert mode(st[-1]) == MODE["disable"] and has(st[-1], "swl_p")
    assert [c for _, c, _ in r.resps()[-2:]] == [125, 163]


def test_speed_mode_brakes_to_stay_within_the_software_limit():
    # 6.3.3: a speed move towards <lp> is braked with <pd> onto it, no error
    r = go(["send 0 UWLP 5000"] + axis(INIT_EN) + ["run 20", "send 0 WVT 50", "send 0 MS", "send 0 E"] +
           watch(count=200) + ["send 0 RBS", "send 0 WVT -50", "send 0 E"] + watch(count=50))
    st, ps = samples(r)
    assert mode(st[199]) == MODE["speed"] and not st[199] & 0x7FFF0000 & ~(1 << 25)
    assert 4900 <= max(ps[:200]) <= 5000 and abs(ps[199] - ps[190]) <= 2
    assert ps[-1] < ps[199] - 300                          # and away from it again


def test_hardware_limit_stops_into_the_switch_not_out():
    r = go(["switch 0 lp 4000"] + axis(INIT_EN) + ["run 20", "send 0 WAA 50", "send 0 WVT 40", "send 0 MS",
                                                   "send 0 E"] + watch(count=200) +
           ["send 0 RBS", "send 0 C", "send 0 WVT -40", "send 0 MS", "send 0 E"] + watch(count=100))
    st, ps = samples(r)
    stopped = st[199]
    assert mode(stopped) == MODE["brake"] and has(stopped, "hwl_p")
    assert ps[199] < 4000 + 1500                           # emergency ramp <ed>
    assert [c for _, c, _ in r.resps()][-5:-3] == [125, 163]   # the read runs; C gets the report
    assert ps[-1] < ps[199] - 500                          # and out again


def test_drive_fault():
    r = go(axis(INIT_EN) + ["run 20", "send 0 WIRQ3 0x33", "send 0 WVT 30", "send 0 MS", "send 0 E", "run 300",
                            "fault 0 drive on"] + watch(count=80) + ["send 0 RBS", "send 0 ME", "run 5"])
    st, ps = samples(r)
    assert mode(st[-1]) == MODE["disable"] and has(st[-1], "dr_f")
    assert [c for _, c, _ in r.resps()[-2:]] == [125, 163]
    assert r.grep(r"^vme-irq 3 51$")


def test_emergency_stop_while_moving():
    r = go([l % n for n in range(4) for l in INIT_EN] + ["run 20"] +
           ["send %d WVT 40" % n for n in range(4)] + ["send %d MS" % n for n in range(4)] +
           ["send %d E" % n for n in range(4)] + ["run 300", "estop on", "run 3", "outputs"])
    assert len(r.grep(r"^output \d en=0 ")) == 4


def test_watchdog_while_moving_ramps_and_disables():
    r = go(axis(INIT_EN) + ["run 20", "send 0 WAA 20", "send 0 WVT 40", "send 0 MS", "send 0 E", "run 200",
                            "send 0 WWD 100"] + watch(count=100) + ["send 0 RBS", "send 0 ME", "run 5"])
    st, ps = samples(r)
    assert mode(st[-1]) == MODE["disable"]
    assert [c for _, c, _ in r.resps()[-2:]] == [125, 164]
    # it braked with <ed> = 20 Inc/SP^2 from 40 Inc/SP (about 2 SP, 40 Inc, not at once) to rest
    # under control before /EN opened: it stands from then on
    fired = next(k for k in range(len(st)) if st[k] & 0xFF == MODE["disable"])
    assert ps[fired] - ps[9] >= 40 and ps[-1] - ps[fired] <= 10 and ps[-1] == ps[fired + 10]


# ---- MAC4-SSI -------------------------------------------------------------------
def test_ssi_example_7_2_vme_absolute_encoder_circular():
    cfg = ["vme-encoder $80C000 0 bits 14 res 10000",
           "send 0 UWSH 2", "send 0 UWCR 10000", "send 0 UWET 4", "send 0 UWEA 0x80C000", "send 0 UWEB 14",
           "send 0 UWEC 10000" if False else "run 1",
           "send 0 UWPS 0", "send 0 UWNS 0", "send 0 UWRS 0", "send 0 UWSO 0", "send 0 FLYOFF",
           "send 0 WMF 500", "send 0 WGA 200", "send 0 WZE 253", "send 0 WPO 0", "send 0 UWKISC 0",
           "send 0 WKI 13", "send 0 WAA 5000", "send 0 WWD 60000"]
    r = go(cfg + axis(INIT_EN) + ["run 20", "send 0 WPV 30", "send 0 WPA 3", "send 0 WPD 3",
                                  "send 0 WAP 7500", "send 0 MP", "send 0 E"] + watch(count=500), card="ssi")
    st, ps = samples(r)
    assert not any(has(s, "encoder_f") for s in st)
    assert has(st[-1], "pos_end") and abs(ps[-1] - 7500) <= 10


def test_ssi_internal_encoder_positioning():
    # the default SSI encoder: 24 bits, Gray, right-justified by <sc> = 2 (docs/plant.md)
    r = go(["send 1 UWSC 2", "send 1 UWET 1"] + axis(INIT_EN, 1) +
           ["run 20", "send 1 WPV 20", "send 1 WPA 2", "send 1 WPD 2", "send 1 WAP 3000", "send 1 MP",
            "send 1 E"] + watch(1, count=300), card="ssi")
    st, ps = samples(r, 1)
    assert has(st[-1], "gray") and has(st[-1], "pos_end")
    assert abs(ps[-1] - 3000) <= 10
