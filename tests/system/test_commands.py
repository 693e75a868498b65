"""The command interface of the EPROM image, driven through the
DPRAM queues exactly as a VME host does."""
import pytest

from conftest import BOOT, CARDS, sim
from mac4 import (BY_MN, CMDQ, ENABLE, EXT_FLAG, EXT_POS, RSPQ, TABLE, board, code, ext_value, obits, q_entry,
                  q_repair, qh, run, script, stop_bit, ubits)

STOP = "0x%X" % board.DP_STOP_BITS

ON_FLY_INIT = ubits("init", "on_fly")


# ---- the manual's example, 7.3.1 --------------------------------------------
def test_manual_example_7_3_1():
    # the axis stands at 1000 (counter set after INIT, before enabling)
    r = run([(0, "INIT"), "run 5", "plant 0 motor coulomb 100", "counter 0 1000", "run 5",
             (0, "ME"), (0, "E"), "run 10",
             (0, 70, 16), (0, 59), (0, 3), (0, 116), (0, 1)])
    resps = r.resps()
    assert resps[:3] == [(0, 2, ON_FLY_INIT), (0, 52, ON_FLY_INIT), (0, 3, ON_FLY_INIT | ubits("dr_en", mode="enable"))]
    # the manual shows $02000101, $02000101, $02000108, 1000, $02002108 without
    # the init bit (12) that 4.9 sets after INIT: docs/interpretations.md
    init = 1 << 12
    assert resps[3:] == [
        (0, 70, 0x02000101 | init),
        (0, 59, 0x02000101 | init),
        (0, 3, 0x02000108 | init),
        (0, 116, 1000),
        (0, 161, 0x02002108 | init),
    ]


def test_queue_entries_are_byte_exact():
    # ENABLE gives three responses (entries 0-2); WAP's is entry 3 at $4818 + 3*10
    e = {f: q_entry(RSPQ, 3, f) for f in ("AXIS", "CODE", "PARAM", "SOURCE")}
    assert e["AXIS"] == 0x4836
    r = run(["host read off"] + ENABLE + [(0, "WAP", 16), "run 5", "peek16 0x%X" % e["AXIS"],
                                          "peek16 0x%X" % e["CODE"], "peek32 0x%X" % e["PARAM"],
                                          "peek16 0x%X" % e["SOURCE"], "peek32 0x%X" % qh(RSPQ, "FRONT")])
    assert r.peek(e["AXIS"]) >> 8 == 0               # axis 0
    assert r.peek(e["CODE"]) == 70                   # code
    assert r.peek(e["PARAM"]) == 0x02001101          # user status, big-endian
    assert r.peek(e["SOURCE"]) >> 8 == 0             # source 0: VMEbus
    assert r.peek(qh(RSPQ, "FRONT")) == 4            # front (write index): four responses


# ---- the whole table ----------------------------------------------------------
def _effective_range(card, c):
    lo, hi = c["range"][card]
    p = c["parameter"]
    if p in ("AP", "AT"):
        lo, hi = -1000000000, 1000000000             # targets: the default software limits <ln>, <lp>
    if p == "LV" and card == "stp":
        hi = 100                                     # at most <ssf> (default 100 Hz, 4.8.3)
    if p == "ET":
        lo = {"inc": 1, "ssi": 1, "stp": 0}[card]
    return lo, hi


@pytest.mark.parametrize("card", CARDS)
def test_every_write_read_pair_round_trips_and_range_edges(card):
    cmds, expect = [], []
    for c in TABLE["commands"]:
        if not c["kind"].startswith("write") or card not in c["cards"]:
            continue
        rd = BY_MN[("UR" if c["system"] else "R") + c["mnemonic"][2 if c["system"] else 1:]]
        lo, hi = _effective_range(card, c)
        for v in (lo, hi):
            if c["parameter"] == "ET" and card == "inc" and v == 2:
                continue
            cmds += [(0, c["code"], v), (0, rd["code"])]
            expect += [(c["code"], None), (rd["code"], v & 0xFFFFFFFF)]
        for v in (lo - 1, hi + 1):
            if -2**31 <= v < 2**31:
                cmds += [(0, c["code"], v), (0, "C")]
                expect += [(162, None), (4, None)]
        # restore the default so later parameters see a sane axis
        cmds.append((0, c["code"], c["default"][card]))
        expect.append((c["code"], None))
    r = run(cmds, card, settle=20)
    got = r.resps()
    assert len(got) == len(expect)
    for (axis, gcode, gparam), (ecode, eparam), cmd in zip(got, expect, cmds):
        assert gcode == ecode, cmd
        if eparam is not None:
            assert gparam == eparam, cmd


@pytest.mark.parametrize("card", CARDS)
def test_system_parameters_need_disable_or_deinit(card):
    syswrites = [c for c in TABLE["commands"] if c["kind"] == "write-system" and card in c["cards"]]
    cmds = [(0, "INIT"), (0, "ME"), (0, "E")]
    for c in syswrites:
        cmds += [(0, c["code"], c["default"][card]), (0, "C")]
    cmds += [(0, "MD"), (0, "E")]
    for c in syswrites:
        cmds.append((0, c["code"], c["default"][card]))
    got = [c for _, c, _ in run(cmds, card, settle=20).resps()]
    n = len(syswrites)
    assert got[3:3 + 2 * n] == [163, 4] * n               # initialised and enabled: logical error
    assert got[3 + 2 * n:5 + 2 * n] == [51, 3]
    assert got[5 + 2 * n:] == [c["code"] for c in syswrites]   # disabled: accepted


@pytest.mark.parametrize("card", CARDS)
def test_commands_of_other_cards_are_syntax_errors(card):
    other = [c for c in TABLE["commands"] if card not in c["cards"]]
    assert other, "every card lacks some command"
    cmds = []
    for c in other:
        cmds += [(0, c["code"], 0), (0, "C")]
    got = [c for _, c, _ in run(cmds, card).resps()]
    assert got == [161, 4] * len(other)


def test_version_word():
    for card in CARDS:
        (_, c, v), = run([(0, "VER")], card).resps()
        assert c == 7 and v >> 24 == CARDS.index(card)
        assert (v >> 16) & 0xFF in (ord("A"), ord("D"))


# ---- errors -------------------------------------------------------------------
@pytest.mark.parametrize("axis", [4, 5, 16, 127, 255])
def test_false_axis_number(axis):
    r = run([(0, "WIRQ2", 0xA2), (axis, "ME"), (0, "ME"), (0, "RBS"), (1, "ME"), (1, "C"), (1, "ME")],
            args=["--irq-level", "5"])
    got = r.resps()
    assert got[1] == (axis, 160, obits("axis_f"))          # the false number comes back
    assert got[2][1] == 163                                # all axes blocked until C
    assert got[3][1] == 125                                # reads still run
    assert got[4][1] == 163
    assert got[5][1] == 4                                  # C on any axis
    assert got[6][1] == 52
    # interrupt 2 with the vector of the last valid axis, also for the 160;
    # axis 1 has no vector
    assert len(r.grep(r"^vme-irq 5 162$")) == 4


@pytest.mark.parametrize("bad", [0, 1, 13, 49, 64, 69, 127, 159, 160, 165, 206, 999, 65535])
def test_unknown_codes_give_161(bad):
    got = run([(2, bad), (2, "RBS"), (2, "ME"), (2, "C"), (2, "ME")]).resps()
    assert got[0] == (2, 161, ubits("syn_f", "on_fly"))
    assert got[1] == (2, 125, ubits("syn_f", "on_fly"))
    assert [g[1] for g in got[2:]] == [163, 4, 52]        # not acknowledged -> logical error


def test_limit_value_errors():
    got = run([(0, "WAP", 1000000001), (0, "C"), (0, "UWSH", 4), (0, "C"), (0, "WDL", 3), (0, "C"),
               (0, "UWLP", -5), (0, "UWLN", 5), (0, "INIT")]).resps()
    assert [g[1] for g in got] == [162, 4, 162, 4, 162, 4, 172, 174, 162]
    assert got[-1][2] & ubits("limit_f")


# (command, expected code): every logical error 6.3.7 that commands alone can cause
LOGICAL = [
    ((0, "MP"), 59), ((0, "E"), 163), ((0, "C"), 4),                       # motion before INIT
    ((0, "INIT"), 2), ((0, "MP"), 59), ((0, "E"), 163), ((0, "C"), 4),     # motion from disable
    ((0, "ME"), 52), ((0, "E"), 3), ((0, "INIT"), 163), ((0, "C"), 4),     # INIT while enabled
    ((0, "UWSH", 2), 163), ((0, "C"), 4),                                  # system parameter
    ((0, "USR"), 163), ((0, "C"), 4),                                      # direction while enabled
    ((0, "MD"), 51), ((0, "E"), 3), ((0, "UWRS", 0), 196), ((0, "INIT"), 2),
    ((0, "ME"), 52), ((0, "E"), 3), ((0, "MH"), 55), ((0, "E"), 163), ((0, "C"), 4),  # RS is off
    ((0, "WDL", 0), 96), ((0, "MF"), 56), ((0, "E"), 163), ((0, "C"), 4),  # find edge to an off switch
    ((0, "WDL", 1), 96), ((0, "MF"), 56), ((0, "E"), 3),                   # ... to the negative limit: ok
    ((0, "MP"), 59), ((0, "E"), 163), ((0, "C"), 4),                       # motion to motion
    ((0, "WAP", 3000), 70),                                                # (a target away from here)
    ((0, "MB"), 58), ((0, "E"), 3), ((0, "MP"), 59), ((0, "E"), 3),        # via brake: ok
    ((0, "WZP", 5), 163), ((0, "C"), 4),                                   # position set while moving
    ((0, "MB"), 58), ((0, "E"), 3), ((0, "MD"), 51), ((0, "E"), 3),
    ((0, "MB"), 58), ((0, "E"), 163), ((0, "C"), 4),                       # brake from disable
    ((0, "UWSH", 2), 170), ((0, "UWET", 4), 178), ((0, "UWEC", 100), 163), ((0, "C"), 4),  # <ec>
    ((0, "UWET", 3), 178), ((0, "UWEA", EXT_POS), 180), ((0, "INIT"), 2),
    ((0, "ME"), 52), ((0, "E"), 3), ((0, "MC"), 53), ((0, "E"), 163), ((0, "C"), 4),  # no index
    ((0, "MI"), 54), ((0, "E"), 163), ((0, "C"), 4),
    ((0, "WDL", 2), 96), ((0, "MF"), 56), ((0, "E"), 163), ((0, "C"), 4),  # circular: limit switch
    ((0, "RBS"), 125),
]


def test_logical_errors_from_commands():
    got = [g[1] for g in run([c for c, _ in LOGICAL], settle=20).resps()]
    assert got == [e for _, e in LOGICAL]


def test_mr_needs_j11():
    r = run([(0, "MR"), "run 300"], args=["--j11", "out"])
    assert r.resps()[0][1] == 163
    assert r.grep(r"^reset ") == []
    r = run([(0, "MR"), "run 1500"])
    assert r.resps()[0][1] == 6                           # answered before the reset
    assert r.grep(r"^reset watchdog$")
    assert r.displays()[-4:] == ["1", "2", "3", "5"]      # and boots again


# ---- queues -------------------------------------------------------------------
def test_nine_queued_commands_at_once():
    lines = [BOOT, "host read off"]
    for i in range(9):
        lines.append("send %d WAP %d" % (i % 4, 100 + i))
    lines += ["run 20", "queues", "host read on", "run 2"]
    r = sim("\n".join(lines) + "\n")
    got = r.resps()
    assert [(a, c) for a, c, _ in got] == [(i % 4, 70) for i in range(9)]
    assert r.grep(r"^queue response .* front=9 rear=0 ")


def test_host_that_never_reads_loses_responses_and_counts_them():
    lines = [BOOT, "host read off", "send 0 WIRQ2 0xA2"]
    for i in range(14):
        lines += ["send 0 RBS", "run 1"]
    lines += ["run 10", "peek32 0x%X" % board.DPC_RSP_LOST, "queues"]
    r = sim("\n".join(lines) + "\n")
    assert r.peek(board.DPC_RSP_LOST) == 15 - 9                        # 15 responses, 9 fit
    assert len(r.grep(r"^vme-irq 3 162$")) == 9            # interrupt 2 only for those written
    assert r.grep(r"^queue response .* front=9 rear=0 ")


@pytest.mark.parametrize("field,value", [("FRONT", 10), ("FRONT", 0xFFFFFFFF), ("REAR", 200),
                                         ("NEL", 11), ("WIDTH", 0x100), ("BASE", 0x1000), ("NEL", 0)])
def test_corrupt_command_queue_header(field, value):
    lines = [BOOT, "send 0 RBS", "run 2", "poke32 0x%X 0x%X" % (qh(CMDQ, field), value), "run 20",
             "peek32 0x%X" % board.DPC_QUEUE_ERRORS, "peek32 0x%X" % board.DPC_BOOT_ERROR, "status"]
    # the host repairs the header (as the card created it) and goes on
    lines += q_repair(CMDQ) + ["run 2", "send 1 VER", "run 5"]
    r = sim("\n".join(lines) + "\n")
    assert r.rc == 0 and r.faults() == []
    assert r.peek(board.DPC_QUEUE_ERRORS) == 1                             # reported once, where the host can see it
    assert r.resps()[-1][:2] == (1, 7)                     # and the card still answers


def test_corrupt_header_never_writes_outside_the_queue():
    beyond = range(RSPQ + 0x100, RSPQ + 0x200, 4)              # past the response queue
    lines = [BOOT, "poke32 0x%X 0x7FFF" % qh(CMDQ, "REAR"), "poke32 0x%X 3" % qh(CMDQ, "FRONT")]
    lines += ["peek32 0x%X" % a for a in beyond]
    lines += ["run 20"] + ["peek32 0x%X" % a for a in beyond]
    r = sim("\n".join(lines) + "\n")
    vals = [l for l in r.lines if l.startswith("peek32")]
    assert vals[:64] == vals[64:]


# ---- direct DPRAM access --------------------------------------------------------
def test_stop_bits_brake_and_are_cleared():
    cmds = [(a, m) for a in range(4) for m in ("INIT", "ME", "E")]
    cmds += [(1, "MS"), (1, "E"), (3, "WDA", 500), (3, "MT"), (3, "E"), "run 20",
             "poke16 %s 0x00AA" % STOP, "run 3", "peek16 %s" % STOP,
             (0, "RBS"), (1, "RBS"), (2, "RBS"), (3, "RBS")]
    r = run(cmds)
    assert r.peek(board.DP_STOP_BITS) == 0
    st = [p for _, c, p in r.resps() if c == 125]
    assert [s & 0xFF for s in st] == [7, 7, 7, 0]          # brake; the test-mode axis is disabled


def test_stop_bits_only_for_their_axis_and_byte_access():
    cmds = [(a, m) for a in range(2) for m in ("INIT", "ME", "E")]
    cmds += ["run 20", "poke8 %s 0x%02X" % (STOP, stop_bit(1)), "run 3", (0, "RBS"), (1, "RBS"),
             "peek16 %s" % STOP]
    r = run(cmds)
    st = [p & 0xFF for _, c, p in r.resps() if c == 125]
    assert st == [1, 7]
    assert r.peek(board.DP_STOP_BITS) == 0


def test_test_mode_outputs_da_and_ignores_usr():
    r = run([(0, "USR"), (0, "INIT"), (0, "WDA", -700), (0, "MT"), (0, "E"), "run 20", "outputs"])
    assert r.grep(r"^output 0 en=1 dac=-700 ")


def test_external_position_via_dpram_handshake():
    cmds = [(0, "UWET", 4), (0, "UWEA", EXT_POS), (0, "UWEB", 32), (0, "UWEC", 0),
            *ext_value(12345), (0, "INIT"), "run 5",
            "peek16 0x%X" % EXT_FLAG, (0, "RCP"), "run 5",
            *ext_value(777), "run 5", "peek16 0x%X" % EXT_FLAG, (0, "RCP"), "run 5",
            *ext_value(999, flag=False), "run 5", (0, "RCP")]            # no flag: the card keeps 777
    r = run(cmds)
    pos = [p for _, c, p in r.resps() if c == 116]
    assert pos == [12345, 777, 777]
    assert [int(l.split()[2], 16) for l in r.grep(r"^peek16 0x%X " % EXT_FLAG)] == [0, 0]


# ---- watchdog, emergency stop, interrupts ----------------------------------------
def test_watchdog_disables_all_axes_and_reports_164_once():
    cmds = [(a, m) for a in range(4) for m in ("INIT", "ME", "E")]
    cmds += ["run 20", (2, "WWD", 50), "run 80", "peek32 0x%X" % board.DPC_OSTAT, (1, "RBS"), (1, "ME"), (1, "C"), (1, "RAS")]
    r = run(cmds)
    got = r.resps()
    assert r.peek(board.DPC_OSTAT) & obits("watch_f")
    assert got[-4][1] == 125                               # a read is executed (6.3)
    assert got[-3] == (1, 164, obits("watch_f"))           # the next other instruction gets the error
    assert got[-2][1] == 4
    assert got[-1] == (1, 124, 0)
    assert "D" in r.displays()


def test_watchdog_is_retriggered_by_commands():
    cmds = [(0, "INIT"), (0, "ME"), (0, "E"), (0, "WWD", 50)]
    for _ in range(6):
        cmds += ["run 30", (0, "RBS")]
    got = run(cmds).resps()
    assert all(c != 164 for _, c, _ in got)
    assert got[-1][2] & 0xFF == 1


def test_emergency_stop():
    cmds = [(a, m) for a in range(4) for m in ("INIT", "ME", "E")]
    cmds += [(0, "WIRQ5", 0x55), "run 20", "estop on", "run 5", "outputs", (3, "RBS"), (3, "ME"), (3, "C"),
             (3, "RAS"), "run 10", "estop off", (3, "C"), (3, "RAS"), (3, "ME"), (3, "E")]
    r = run(cmds, args=["--irq-level", "6"])
    got = r.resps()
    assert len(r.grep(r"^output \d en=0 ")) == 4
    assert got[-8][1] == 125                               # a read is executed (6.3)
    assert got[-7] == (3, 165, obits("h_stop"))            # the next other instruction gets the error
    assert got[-6][1] == 4
    assert got[-5][2] & obits("h_stop")                    # C cannot clear it while /STOP is on
    assert got[-3][2] & obits("h_stop") == 0
    assert [c for _, c, _ in got[-2:]] == [52, 3]
    assert r.grep(r"^vme-irq 6 85$")
    assert "E" in r.displays()


def test_interrupt_1_and_2_per_axis_vectors():
    r = run([(1, "WIRQ1", 0x11), (1, "WIRQ2", 0x12), (2, "WIRQ2", 0x22), (1, "RBS"), (2, "RBS"),
             (3, "RBS")], args=["--irq-level", "2"])
    irqs = r.grep(r"^vme-irq ")
    # WIRQ1 itself: no vector yet when it was read; its response: none either
    assert irqs == ["vme-irq 2 17", "vme-irq 2 18", "vme-irq 2 34", "vme-irq 2 17", "vme-irq 2 18",
                    "vme-irq 2 34"]


def test_read_commands_run_despite_unacknowledged_error():
    got = run([(0, 1), (0, "RBS"), (0, "RAS"), (0, "RCP"), (0, "VER"), (0, "RAP"), (0, "ME")]).resps()
    assert [c for _, c, _ in got] == [161, 125, 124, 116, 7, 71, 163]
