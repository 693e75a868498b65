"""Position measurement systems (manual 4.4, table 4.3, 3.5.2, 6.3.8) on the
EPROM images: the external encoder address <ea>, encoder errors, the counter
range <ec> in relative and absolute mode, the automatic values of the
internal systems.  docs/interpretations.md, "Position measurement"."""
import re

import pytest

from conftest import CARDS
from mac4 import ERR, EXT_POS, MODE, board, codes, ext_value, has, run, signed, ubits
from test_serial import parse, rx_bytes

ERR_LIMIT, ERR_LOGICAL = ERR["limit_f"], ERR["logo_f"]


def rcp(r):
    return [signed(p) for _, c, p in r.resps() if c == 116]


def plant_rev(r, n=0):
    return [float(m.group(1)) for m in map(re.compile(r"rev=(-?[\d.]+)").search, r.grep(r"^plant %d " % n))]


def vme_value(r):
    return [int(m.group(1)) for m in map(re.compile(r"value=(\d+)").search, r.grep(r"^vme-encoder "))]


# ---- K1: <ea> of an external encoder ------------------------------------------------
@pytest.mark.parametrize("card", CARDS)
@pytest.mark.parametrize("et", [3, 4])
def test_init_refuses_the_default_ea(card, et):
    # <ea> = 0 (the default) once read $FFFFFE and wrote it back: 162 at INIT now
    r = run([(0, "UWET", et), (0, "INIT"), "run 20", (0, "RBS"), (0, "C"),
             (0, "UWEA", EXT_POS), (0, "INIT"), "run 20", (0, "RBS")], card)
    got = r.resps()
    assert [c for _, c, _ in got] == [178, ERR_LIMIT, 125, 4, 180, 2, 125]
    assert got[1][2] & ubits("limit_f") and not has(got[2][2], "init")
    assert has(got[-1][2], "init") and not has(got[-1][2], "encoder_f")
    assert "F." not in r.displays()


# <ea> the host must not be given: odd (an address error on the 68000), in the
# vector table and monitor area, in the card's axis data, its data block, the
# stop bits, the queues, past $FFEE, or an A24 address past $FFFFFE
BAD_EA = [1, 0x3301, 0x330B, 0x80C001, 0xFFFFFF,
          2, 0x0102, 0x0400, 0x2FFE, 0x3000, 0x3002, 0x3020, 0x3308, 0x36FE, 0x3708,
          0x33FE,                                  # value crosses into axis 2's block
          board.DP_CARD_DATA + 2, board.DP_STOP_BITS - 2, board.DP_STOP_BITS, board.DP_STOP_BITS + 2,   # card data, stop bits
          board.DP_CMD_QUEUE, board.DP_CMD_QUEUE + 4, board.DP_CMD_QUEUE + 0x18,               # queues
          board.DP_RSP_QUEUE, board.DP_RSP_QUEUE + 0x18, board.DP_RSP_QUEUE + 0xFE, board.DP_RSP_QUEUE + 0x100,
          0xFFEC, 0xFFFE]
GOOD_EA = [0x330A, 0x370A, 0x3B0A, 0x3F0A, 0x330C, 0x33FA, 0x3F0C, 0x4902, 0x8000, 0xFFEA,
           0x10000, 0x80C000, 0xFFFFFE]


@pytest.mark.parametrize("card", CARDS)
def test_uwea_refuses_addresses_the_card_must_not_touch(card):
    cmds = []
    for ea in BAD_EA:
        cmds += [(0, "UWEA", ea), (0, "C")]
    for ea in GOOD_EA:
        cmds += [(0, "UWEA", ea), (0, "UREA")]
    got = run(cmds, card, settle=20).resps()
    assert [c for _, c, _ in got[:2 * len(BAD_EA)]] == [ERR_LIMIT, 4] * len(BAD_EA)
    rest = got[2 * len(BAD_EA):]
    assert [c for _, c, _ in rest] == [180, 181] * len(GOOD_EA)
    assert [p for _, c, p in rest if c == 181] == GOOD_EA


def test_odd_ea_no_longer_halts_the_card():
    # the audit's reproducer: UWET 3, UWEA $3301, INIT gave an address error and "F."
    r = run([(0, "UWET", 3), (0, "UWEA", 0x3301), (0, "C"), (0, "INIT"), "run 20", (0, "C"), (0, "VER")])
    assert codes(r) == [178, ERR_LIMIT, 4, ERR_LIMIT, 4, 7]
    assert "F." not in r.displays()


def peeks(r, addr):
    return [int(l.split()[2], 16) for l in r.lines
            if l.startswith("peek32 ") and int(l.split()[1], 16) == addr]


def test_vector_table_and_queues_are_left_alone():
    # a vector whose low word has bit 15 set looked like a raised interlock flag
    # and was cleared; a DPRAM <ea> in a queue read and cleared the host's words
    r = run(["poke16 0x1000 0x8000", (0, "UWET", 4), (0, "UWEA", 0x1002), (0, "C"), (0, "INIT"), (0, "C"),
             (0, "UWEA", 0x4706), (0, "C"), (0, "INIT"), (0, "C"), "run 50", "peek32 0x1000", "peek32 0x4704",
             (0, "VER")])
    assert codes(r) == [178, ERR_LIMIT, 4, ERR_LIMIT, 4, ERR_LIMIT, 4, ERR_LIMIT, 4, 7]
    assert peeks(r, 0x1000)[0] >> 16 == 0x8000          # the monitor word with bit 15 is still there
    assert peeks(r, 0x4704)[0] != 0                     # the command queue's front is the host's


def test_vme_two_words_must_not_cross_the_window_page():
    # <eb> > 16: MSW at <ea>, LSW at <ea>+2 (4.4.2.1); $8FFFFE+2 is in the next
    # 1 MiB page of the master window, outside what VME_PAGE maps
    r = run(["vme-encoder $8FFFFE 0 bits 16", (0, "UWET", 4), (0, "UWEA", 0x8FFFFE), (0, "UWEB", 24),
             (0, "INIT"), (0, "C"), (0, "UWEB", 16), (0, "INIT"), "run 20", (0, "RBS")])
    got = r.resps()
    assert [c for _, c, _ in got] == [178, 180, 182, ERR_LIMIT, 4, 182, 2, 125]
    assert not has(got[-1][2], "encoder_f")


def test_internal_systems_ignore_ea():
    # <et> 1: the counter register, whatever <ea> says (table 4.3 "def.")
    r = run([(0, "UWEA", 0x80C000), (0, "INIT"), "run 5", "counter 0 1234", "run 10", (0, "RCP")])
    assert codes(r) == [180, 2, 116] and rcp(r) == [1234]


# ---- K2: an encoder error is raised once --------------------------------------------
def test_absolute_value_beyond_ec_is_reported_once_then_the_host_recovers():
    r = run([(0, "UWET", 4), (0, "UWEA", EXT_POS), (0, "UWEC", 1000),
             *ext_value(5000), (0, "INIT"), "run 20",
             (0, "RBS"), "run 20", (0, "C"), "run 20", (0, "C"), "run 20", (0, "DEINIT"), "run 20",
             (0, "UWEC", 10000), "run 20", (0, "INIT"), "run 20", (0, "RBS"), (0, "RCP")])
    got = r.resps()
    # the read is executed with the error bits (6.3); the first C gets the report and acknowledges it
    assert [c for _, c, _ in got] == [178, 180, 184, 2, 125, ERR_LOGICAL, 4, 5, 184, 2, 125, 116]
    for err in (got[4][2], got[5][2]):
        assert has(err, "encoder_f") and has(err, "logo_f") and err & 0xFF == MODE["disable"]
    assert not has(got[-2][2], "encoder_f") and has(got[-2][2], "init")
    assert rcp(r) == [5000]


def test_missing_vme_encoder_reported_once_and_again_when_enabled():
    # no board at the address: a bus error in every tick
    r = run([(0, "UWET", 3), (0, "UWEA", 0x80C000), (0, "INIT"), "run 30", (0, "RBS"), "run 30",
             (0, "C"), "run 30", (0, "RBS"), "run 30", (0, "ME"), "run 30", (0, "E"), "run 30",
             (0, "RBS"), "run 30", (0, "C"), "run 30", (0, "DEINIT"), "run 30", (0, "RBS")])
    got = r.resps()
    # reads executed (6.3), each report answered once, by the C that acknowledges it
    assert [c for _, c, _ in got] == [178, 180, 2, 125, ERR_LOGICAL, 125, 52, 3, 125, ERR_LOGICAL, 5, 125]
    assert has(got[3][2], "encoder_f")
    assert not has(got[5][2], "encoder_f")             # acknowledged, not raised again while disabled
    assert has(got[8][2], "encoder_f")                 # enabled again: the next failure counts
    assert got[8][2] & 0xFF == MODE["disable"]
    assert not has(got[-1][2], "init")


def test_an_encoder_error_during_e_is_never_overridden_by_it():
    # E runs parts of its work with interrupts enabled (cmd_general.c, do_execute); a
    # tick there that fails to measure the axis raises encoder_f and disables
    # it (6.3.8).  Whatever the tick's instant, E must not then enable the
    # axis: it answers "not acknowledged" (163, 6.3.7), or it was done before
    # the tick and its status shows no error.  The bad value comes at every
    # offset in a tick period (step 10 us, the stretches are ~100 us).
    outcomes = set()
    for k in range(250):
        r = run([(0, "UWET", 4), (0, "UWEA", EXT_POS), (0, "UWEC", 100000), *ext_value(500),
                 (0, "INIT"), "run 20", (0, "ME"), (0, "E"), "run 20",
                 (0, "WAP", 800), (0, "MP"), "run 5", "run-ticks 1", "run %.2f" % (k * 0.01),
                 *ext_value(500000), (0, "E"), "run 20", (0, "RBS")])
        got = r.resps()
        assert [c for _, c, _ in got[:-2]] == [178, 180, 184, 2, 52, 3, 70, 59], got
        _, code, st = got[-2]
        outcomes.add(code)
        assert code == ERR_LOGICAL or not has(st, "encoder_f"), "offset %.2f ms: E done with %s" % (k * 0.01, got[-2:])
        assert has(got[-1][2], "encoder_f") and got[-1][2] & 0xFF == MODE["disable"]
    assert outcomes == {3, ERR_LOGICAL}, outcomes        # both sides of the tick were met


def test_encoder_error_over_the_serial_line_can_be_acknowledged():
    # a serial host needs ~21 ms per telegram: with the error raised every tick
    # it never got C and DEINIT through
    lines = ["send 0 UWET 3", "send 0 UWEA 0x80C000", "send 0 INIT", "run 20"]
    for mn in ("RBS", "C", "DEINIT", "RBS"):
        lines += ["tx-msg 0 %s" % mn, "run 60"]
    r = run(lines)
    got = [m[1] for m in parse(rx_bytes(r))]
    assert got == [125, ERR_LOGICAL, 5, 125]           # the read runs; C gets the report and clears it


# ---- K3: relative measurement modulo <ec> ------------------------------------------
def dpram_values(values, et=3, ec=1000, eb=None):
    # STP: <ms> = 4 <es>, one step per increment (4.4.2.3)
    cmds = [(0, "UWET", et), (0, "UWEA", EXT_POS), (0, "UWEC", ec), (0, "UWMS", 2000), (0, "C")]
    cmds += [(0, "UWEB", eb)] if eb else []
    cmds += [*ext_value(values[0]), (0, "INIT"), "run 10", (0, "RCP"),
             "run 10"]
    for v in values[1:]:
        cmds += [*ext_value(v), "run 10", (0, "RCP"), "run 10"]
    return cmds


@pytest.mark.parametrize("card", CARDS)
def test_relative_counter_wraps_at_ec(card):
    r = run(dpram_values([990, 5, 400, 700, 995, 990, 5]), card)
    assert rcp(r) == [0, 15, 410, 710, 1005, 1000, 1015]
    r = run(dpram_values([5, 990, 600, 300, 2, 998]), card)
    assert rcp(r) == [0, -15, -405, -705, -1003, -1007]


def test_relative_ec_power_of_two_below_2_eb():
    r = run(dpram_values([1020, 3], ec=1024, eb=24))
    assert rcp(r) == [0, 7]


def test_relative_value_outside_ec_is_an_encoder_error():
    r = run(dpram_values([990, 1000]) + [(0, "RBS")], settle=20)
    got = r.resps()
    assert [c for _, c, _ in got][-2:] == [116, 125] and has(got[-1][2], "encoder_f")   # reads run (6.3)


def test_relative_vme_encoder_turning_through_its_wrap():
    # the board counts 0..999 per output revolution; test mode drives the motor
    # open loop for several revolutions each way
    cmds = ["vme-encoder $80C000 0 bits 16 res 1000 turns 1", (0, "UWET", 3), (0, "UWEA", 0x80C000),
            (0, "UWEB", 16), (0, "UWEC", 1000), (0, "INIT"), (0, "WDA", 1500), (0, "MT"), (0, "E")]
    for da, ms in ((1500, 1500), (-1500, 3000)):
        cmds += [(0, "WDA", da), "run %d" % ms, (0, "RCP"), "run 2", "plant 0"]
    r = run(cmds)
    revs = plant_rev(r)
    assert revs[0] > 3 and revs[1] < -3                # several wraps both ways
    for pos, rev in zip(rcp(r), revs):
        assert abs(pos - rev * 1000) < 40              # the shaft moves on while RCP is answered
    assert ERR_LOGICAL not in codes(r)


# ---- K4: automatic values of the internal systems ---------------------------------------
def test_ssi_12_bit_relative_crossing_4095():
    # <sc> 14 justifies a 12-bit word: <eb> in force is 12, the counter wraps at 4096
    r = run(["plant 0 ssi bits 12 binary res 4096", "counter 0 4090", (0, "UWSC", 14), (0, "UWET", 1),
             (0, "INIT"), "run 10", (0, "RCP"), "run 2", "counter 0 4095", "run 10", (0, "RCP"), "run 2",
             "counter 0 2", "run 10", (0, "RCP"), "run 2", "counter 0 4093", "run 10", (0, "RCP"),
             (0, "UREB"), (0, "UREC")], "ssi")
    assert rcp(r) == [0, 5, 8, 3]
    assert [p for _, c, p in r.resps() if c in (183, 185)] == [24, 0]   # read back as written


def test_ssi_12_bit_relative_turning():
    r = run(["plant 0 ssi bits 12 binary res 4096", (0, "UWSC", 14), (0, "UWET", 1), (0, "INIT"),
             (0, "WDA", 1500), (0, "MT"), (0, "E"), "run 1500", (0, "RCP"), "run 2", "plant 0"], "ssi")
    rev, = plant_rev(r)
    pos, = rcp(r)
    assert rev > 3 and abs(pos - rev * 4096) < 150


def test_ssi_written_eb_narrower_than_the_word_is_honoured():
    # 4.4.2.1: bits above <eb> are ignored
    r = run(["plant 0 ssi bits 12 binary res 4096", "counter 0 1000", (0, "UWSC", 14), (0, "UWET", 2),
             (0, "UWEB", 8), (0, "INIT"), "run 10", (0, "RCP"), (0, "RCT")], "ssi")
    assert rcp(r) == [1000 & 0xFF]


def test_inc_counter_stays_24_bits_whatever_was_written():
    r = run([(0, "UWEB", 12), (0, "UWEC", 1000), (0, "INIT"), "run 5", "counter 0 5000", "run 10", (0, "RCP"),
             (0, "UREB"), (0, "UREC")])
    assert rcp(r) == [5000]
    assert [p for _, c, p in r.resps() if c in (183, 185)] == [12, 1000]


def test_stp_counter_stays_24_bits_whatever_was_written():
    r = run([(0, "UWEB", 12), (0, "UWEC", 1000), (0, "INIT"), "run 20", "counter 0 5000", "run 20", (0, "RCP")],
            "stp")
    assert rcp(r) == [5000]


def test_ssi_absolute_target_outside_written_ec():
    # 6.3.3: a target outside the absolute encoder's range is a limit value error
    r = run(["plant 0 ssi bits 12 binary res 4096", "counter 0 100", (0, "UWSC", 14), (0, "UWET", 2),
             (0, "UWEC", 4000), (0, "INIT"), (0, "WAP", 3999), (0, "WAP", 4000), (0, "C"),
             (0, "UWEC", 0), (0, "INIT"), (0, "WAP", 4095), (0, "WAP", 4096)], "ssi", settle=20)
    assert codes(r) == [186, 178, 184, 2, 70, ERR_LIMIT, 4, 184, 2, 70, ERR_LIMIT]


# ---- K5: SSI data stuck at ones ------------------------------------------------------
def test_ssi_stuck_at_ones_outside_ec_disables_without_ramp():
    r = run(["plant 0 ssi bits 12 binary res 4096", "counter 0 100", (0, "UWSC", 14), (0, "UWET", 2),
             (0, "UWEC", 4000), (0, "WAA", 1), (0, "INIT"), (0, "ME"), (0, "E"), "run 20",
             (0, "WVT", 20), (0, "MS"), (0, "E"), "run 300", "fault 0 encoder stuck1", "run 3", "outputs",
             (0, "RBS"), (0, "ME"), (0, "RCP"), (0, "RED")], "ssi")
    got = r.resps()
    err = [p for _, c, p in got if c == ERR_LOGICAL]
    assert len(err) == 1 and has(err[0], "encoder_f") and not has(err[0], "ferr_f")
    assert err[0] & 0xFF == MODE["disable"]
    assert r.grep(r"^output 0 en=0 dac=0 ")         # at once: <ed> = 1 would take seconds
    red = [p for _, c, p in got if c == 119]
    assert red == [0xFFF]
    assert rcp(r)[0] < 4000                           # the bad value is not taken as the position


def test_ssi_stuck_at_ones_inside_the_range_is_no_encoder_error():
    # <ec> not written: 2^<eb>, all ones is a valid absolute value
    r = run(["plant 0 ssi bits 12 binary res 4096", "counter 0 100", (0, "UWSC", 14), (0, "UWET", 2),
             (0, "INIT"), "fault 0 encoder stuck1", "run 20", (0, "RBS"), (0, "RCP")], "ssi")
    got = r.resps()
    assert not has(got[-2][2], "encoder_f") and rcp(r) == [4095]
