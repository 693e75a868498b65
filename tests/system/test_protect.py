"""Protective reactions, the rules of 6.3 around them (docs/interpretations.md,
"Protective reactions"): the cases the sweep of test_stops.py does not make.

* a C sent while the following-error stop still brakes acknowledges the
  error, and the stop's runaway guard that opens /EN later raises nothing
  more: the host sees the error once;
* a stronger stop during a weaker brake (a limit switch or a following
  error while a stop bit brakes with <pd>) takes the stronger ramp.
"""
from conftest import BOOT, sim
from mac4 import BIT, MODE, board, code


def ub(*names):
    v = 0
    for n in names:
        v |= 1 << BIT["user"][n]
    return v


def pre(card):
    return ["run 5", "send 0 UWSC 2"] if card == "ssi" else []


def frozen_mid_move(card):
    """Axis 0 in speed mode at 40 Inc/SP with a slow <ed> (WAA 5) and a
    tight <mf>, its encoder frozen after 300 ms: the following-error stop
    brakes, and its runaway guard opens /EN."""
    return pre(card) + ["send 0 WAA 5", "send 0 WMF 100", "send 0 INIT", "send 0 ME", "send 0 E", "run 20",
                        "send 0 WVT 40", "send 0 MS", "send 0 E", "run 300", "fault 0 encoder frozen"]


def c_every_tick(lines, card):
    """The script, then a C every tick for 40 ticks, an RBS and ME: the
    card's responses (the last 42 those of the C's, the RBS and the ME)."""
    lines = lines + ["send 0 C", "run 2.5"] * 40 + ["send 0 RBS", "send 0 ME", "run 5"]
    return run(lines, card).resps()


def run(lines, card):
    r = sim(BOOT + "\n".join(lines) + "\n", card)
    assert r.rc == 0, r.stderr
    return r


def test_c_while_the_following_error_stop_brakes_reports_once():
    """The encoder freezes mid-move: following error, the setpoint brakes
    with a slow <ed> (8 SP from 40 Inc/SP), the frozen feedback makes the
    following error grow on, and the runaway guard opens /EN.  A host that
    sends C every tick gets 163 once - on the first C, which acknowledges
    it - and never again; the axis ends disabled with no error bit."""
    for card in ("inc", "ssi"):
        lines = frozen_mid_move(card)
        got = c_every_tick(lines, card)
        cs = [c for _, c, _ in got[-42:-2]]
        assert cs.count(163) == 1 and set(cs) == {4, 163}, (card, cs)
        first = cs.index(163)
        assert first > 0, (card, cs)                               # the C before the error: plain 4
        rep = got[-42 + first][2]
        assert rep & ub("ferr_f"), (card, hex(rep))                # the report carries ferr_f
        # the stop was still braking when the C came: the axis still enabled, in speed mode
        after = got[-42 + first + 1][2]
        assert after & 0xFF == MODE["speed"] and not after & ub("ferr_f"), (card, hex(after))
        rbs, me = got[-2:]
        assert rbs[2] & 0xFF == MODE["disable"] and not rbs[2] & ub("ferr_f", "logo_f"), (card, hex(rbs[2]))
        assert me[1] == code("ME"), (card, me)                     # nothing left to report


def plant_pos(line):
    return float(line.split("pos=")[1].split()[0])


def test_a_limit_switch_during_a_stop_bit_brake_takes_the_ed_ramp():
    """A stop bit brakes with a gentle <pd> (INC/SSI 2 Inc/SP^2: 5 000 Inc
    from 100 Inc/SP; STP 20 Hz/SP: 3 200 steps from 2000 Hz); the positive
    limit switch lies 1 500 Inc (600 steps) ahead.  There the <ed> ramp takes
    over (4.8.2): the mechanics stand within a few ticks' travel of the switch,
    held in mode brake with hwl_p, reported once."""
    for card in ("inc", "ssi", "stp"):
        stp = card == "stp"
        sw, lim = (1500, 100) if stp else (4000, 300)
        lines = pre(card) + ["switch 0 lp %d" % sw] + (["send 0 WAA 2000"] if stp else []) + [
            "send 0 INIT", "send 0 ME", "send 0 E", "run 20",
            "send 0 WPA %d" % (500 if stp else 20), "send 0 WPD %d" % (20 if stp else 2),
            "send 0 WVT %d" % (2000 if stp else 100), "send 0 MS", "send 0 E", "run %d" % (600 if stp else 300),
            "plant 0", "poke16 0x%X 0x0002" % board.DP_STOP_BITS, "run 3000", "plant 0", "send 0 RBS", "send 0 ME", "send 0 RBS",
            "run 5"]
        r = run(lines, card)
        p = r.grep(r"^plant 0 ")
        at, rest = plant_pos(p[0]), plant_pos(p[1])
        assert sw - at > 500, (card, at)                           # the switch well ahead of the stop bit
        assert " vel=0.0 " in p[1] and sw <= rest <= sw + lim, (card, rest)
        if stp:
            assert " lost=0 " in p[1], p[1]
        rbs, me, rbs2 = r.resps()[-3:]
        assert rbs[2] & 0xFF == MODE["brake"] and rbs[2] & ub("hwl_p", "logo_f") == ub("hwl_p", "logo_f"), hex(rbs[2])
        assert me[1] == 163 and rbs2[1] == code("RBS")
        print("STOP-BIT then HWL %s: switch at %d, at rest at %.0f" % (card, sw, rest))


def test_the_stp_creep_phase_stops_at_a_limit_switch():
    """MAC4-STP positioning to 1000 with a creep phase of 400 steps at <lv>
    (5.6): the profile stands while the down-counter sends the creep's
    pulses.  The positive limit switch at 800 lies within the creep: the
    pulses stop there (hwl_p, mode brake, 163), not at the target."""
    r = run(["switch 0 lp 800", "send 0 INIT", "send 0 ME", "send 0 E", "run 20", "send 0 WSTC 400", "send 0 WLV 100",
             "send 0 WPV 2000", "send 0 WPA 500", "send 0 WPD 500", "send 0 WAP 1000", "send 0 MP", "send 0 E",
             "run 6000", "plant 0", "send 0 RBS", "send 0 ME", "run 5"], "stp")
    p = r.grep(r"^plant 0 ")[0]
    assert " vel=0.0 " in p and " lost=0 " in p and 800 <= plant_pos(p) <= 802, p
    rbs, me = r.resps()[-2:]
    assert rbs[2] & 0xFF == MODE["brake"] and rbs[2] & ub("hwl_p", "logo_f") == ub("hwl_p", "logo_f"), hex(rbs[2])
    assert not rbs[2] & ub("pos_end") and me[1] == 163


def test_test_mode_turns_the_axis_off_at_a_limit_switch():
    """5.13: in test mode <da> goes straight to the output; a limit switch
    reached turns the axis off (no ramp: the controller is not active), and
    it can then be driven out of the switch in test mode again."""
    for card in ("inc", "ssi", "stp"):
        sw, da = (1000, 900) if card == "stp" else (3000, 800)
        r = run(pre(card) + ["switch 0 lp %d" % sw, "send 0 INIT", "send 0 MT", "send 0 E", "send 0 WDA %d" % da,
                             "run 2000", "plant 0", "send 0 RBS", "send 0 MT", "send 0 E", "send 0 WDA %d" % -da,
                             "run 1000", "plant 0", "send 0 RBS", "run 5"], card)
        p1, p2 = r.grep(r"^plant 0 ")
        assert " en=0 " in p1 and plant_pos(p1) >= sw, (card, p1)        # off in the switch
        rbs1, mt, e, wda, rbs2 = r.resps()[-5:]
        assert rbs1[2] & 0xFF == MODE["disable"] and rbs1[2] & ub("hwl_p"), (card, hex(rbs1[2]))
        assert not rbs1[2] & ub("logo_f", "ferr_f") and e[1] == code("E"), (card, e)
        assert " en=1 " in p2 and plant_pos(p2) < sw, (card, p2)         # out again, in test mode
        assert rbs2[2] & 0xFF == MODE["test"] and not rbs2[2] & ub("hwl_p"), (card, hex(rbs2[2]))


def test_c_then_mre_while_the_following_error_stop_brakes_reports_once():
    """A host's error handler: after the report, C, then MRE and E to be sure
    the axis stops - while the following-error stop still brakes.  The MRE
    joins the stop under way (its guards included); the error is not raised
    a second time when the guard opens /EN."""
    for card in ("inc", "ssi"):
        lines = frozen_mid_move(card)
        for _ in range(6):
            lines += ["send 0 RBS", "run 2.5"]
        lines += ["send 0 C", "send 0 MRE", "send 0 E"]
        got = c_every_tick(lines, card)
        polls = [p for _, c, p in got[-51:-45]]
        assert any(p & ub("ferr_f") for p in polls), (card, [hex(p) for p in polls])   # raised by then
        tail = [c for _, c, _ in got[-45:]]
        assert tail[:3] == [163, code("MRE"), code("E")], (card, tail[:3])      # the first C acknowledges
        assert got[-45][2] & 0xFF == MODE["speed"], (card, hex(got[-45][2]))    # ... while the stop brakes
        assert got[-43][2] & 0xFF == MODE["reset"], (card, hex(got[-43][2]))    # E: mode reset, enabled
        assert 163 not in tail[3:-2] and set(tail[3:-2]) == {4}, (card, tail)
        rbs, me = got[-2:]
        assert rbs[2] & 0xFF == MODE["disable"] and not rbs[2] & ub("ferr_f", "logo_f"), (card, hex(rbs[2]))
        assert me[1] == code("ME"), (card, me)
