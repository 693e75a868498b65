"""The floor routines (bench/floor/README.md) are the firmware's function:
every routine, on random inputs - saturation, the limits and bounds, the
error paths among them - leaves what the firmware's C (firmware/servo.h,
measure.h, measure.c ... compiled for the host) leaves on the same inputs,
bit for bit; and the check is able to fail.  The figures (tick / floor)
are make bench's (tools/bench.py): aims, not tested here."""
import os
import re
import shutil
import subprocess
import sys

import pytest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "tools"))
import perfscen as ps  # noqa: E402

ROOT = ps.ROOT
FLOOR_SRC = os.path.join(ROOT, "bench", "floor")
CROSS = os.environ.get("CROSS", "m68k-linux-gnu-")
CARDS = ("inc", "ssi", "stp")


def routines(card):
    rc, out, err = ps.floor_run(card, "--list")
    assert rc == 0, err
    return [l.split()[3] for l in out.splitlines() if l.startswith("routine ")]


@pytest.mark.parametrize("card", CARDS)
def test_every_routine_is_the_firmware_on_random_inputs(card):
    rc, out, err = ps.floor_run(card, "--check", "3000", "--seed", "12345")
    assert rc == 0, out + err
    ok = re.findall(r"^check %s \w+ (\w+) samples=3000 ok" % card, out, re.M)
    assert sorted(ok) == sorted(routines(card)), out


@pytest.mark.parametrize("card", CARDS)
def test_the_scenarios_inputs_are_the_firmware_too(card):
    # --measure checks every input it measures, as --check does; its
    # scenarios are tools/perfscen.py's, by name (make bench pairs them)
    figures = ps.floors(card, samples=50)
    assert figures["tick"], figures
    for scen, f in figures["tick"].items():
        assert scen in ps.TICK_SCENARIOS[card], "not a tick scenario of perfscen: %s" % scen
        assert f["cycles"] > 0, (scen, f)
    for kind in figures:
        for scen in figures[kind]:
            assert scen in ps.SCRIPTS, "not a scenario of perfscen: %s %s" % (kind, scen)


def assemble(tmp, include_dir, routine):
    """routine.S assembled beside include_dir's servo.inc (cpp looks in the
    source's own folder first: the copy is there)."""
    obj, binf = os.path.join(tmp, routine + ".o"), os.path.join(tmp, routine + ".bin")
    src = os.path.join(include_dir, routine + ".S")
    shutil.copy(os.path.join(FLOOR_SRC, routine + ".S"), src)
    subprocess.run([CROSS + "gcc", "-m68000", "-I" + os.path.join(ROOT, "hal"), "-I" + include_dir, "-c",
                    src, "-o", obj], check=True)
    subprocess.run([CROSS + "objcopy", "-O", "binary", "-j", ".text", obj, binf], check=True)
    return binf


# A changed constant or condition in the routines' parts (bench/floor/servo.inc, stp.inc)
# must show: each mutant assembled from a copy and checked against the C.
MUTANTS = [
    ("inc_counter", "the K term's x 64", r"asl\.l   #6,%d0\n    move\.l  %d0,SV_U1", "asl.l   #5,%d0\n    move.l  %d0,SV_U1"),
    ("inc_counter", "the rounding's 128 (t = (u1 + u2 + 128) >> 4)", r"addq\.l  #8,%d0", "addq.l  #7,%d0"),
    ("inc_counter", "the DAC's range", r"jne     \.Lks\\@\n", "jra     .Lks9\\@\n.Lks9\\@:\n"),
    ("inc_counter_circ", "the integral term's residual", r"and\.l   %d1,%d4", "or.l    %d1,%d4"),
    ("inc_counter_circ", "the pole term's low byte", r"and\.w   #0xFF,%d2", "and.w   #0x7F,%d2"),
    ("ssi_abs", "<ec>'s bound (raw > lim, not >=)", r"jhi     \\err", "jcc     \\err"),
    ("ssi_abs", "the SSI poll's bit", r"moveq   #AX_IN_SSI_BUSY,%d0", "moveq   #AX_IN_GRAY,%d0"),
    ("inc_counter_brake", "the brake's carry", r"jcc     \.Lb2\\@", "jcs     .Lb2\\@"),
    ("stp_counter", "the rate's carry (DIVU's remainder)", r"clr\.w   %d6\n    swap    %d6", "clr.w   %d6"),
    ("stp_counter", "USR on the step counter", r"jne     \.Lsr\\@", "jeq     .Lsr\\@"),
    ("stp_encoder", "the increments' al x rh", r"(mulu\.w  %d7,%d1 +/\* al rh \*/\n    )add\.l", "mulu.w  %d7,%d1\n    sub.l"),
    ("stp_counter_brake", "brake_split's borrow", r"subq\.l  #1,%d0\n\.Lb3", "subq.l  #2,%d0\n.Lb3"),
    ("stp_counter", "TRIM_MAX", r"moveq   #FL_TRIM_MAX,%d1", "moveq   #2,%d1"),
    ("stp_counter_creep", "the creep's direction", r"tst\.b   ST_CREEPDIR\(%a0\)\n    jpl", "tst.b   ST_CREEPDIR(%a0)\n    jmi"),
    ("stp_counter_creep", "the reversal's wait", r"move\.b  #FL_CREEP_WAIT,ST_CREEP", "move.b  #FL_CREEP_RUN,ST_CREEP"),
    ("stp_counter", "motion_hold's fraction", r"clr\.w   ST_SPF\(%a0\)\n    clr\.w   ST_STARTF", "clr.w   ST_STARTF"),
    ("inc_supervise", "the LED of pos_end", r"or\.w    #\(SYS_LED_P", "or.w    #(SYS_LED_D"),
    ("inc_supervise", "RED of the counter path", r"move\.l  REC\(COUNTER\)\(%a0\),REC\(RAW\)\(%a0\)", "nop"),
    ("ssi_supervise", "the Gray bit of the inputs", r"btst    #5,%d0", "btst    #4,%d0"),
    ("inc_cmd", "the queue's wrap (rear)", r"cmp\.w   #Q_NEL,%d2", "cmp.w   #Q_NEL+1,%d2"),
    ("inc_cmd", "a corrupt header counted once", r"move\.b  #1,FLOOR_CARD\+CD_QBAD", "nop"),
    ("inc_cmd", "a full response queue", r"cmp\.w   %d2,%d1", "cmp.w   %d1,%d1"),
    ("stp_supervise", "the STP's fault LED of an error", r"and\.l   #FL_US_ERRORS,%d0", "and.l   #0,%d0"),
    ("stp_supervise", "ROUT's Hz rounding", r"add\.l   #0x4000,%d0", "add.l   #0x3000,%d0"),
    ("stp_cmd", "ROUT's Steps/SP rounding", r"moveq   #62,%d1", "moveq   #61,%d1"),
]


@pytest.mark.parametrize("routine,what,pattern,repl", MUTANTS, ids=[m[1] for m in MUTANTS])
def test_the_check_catches_a_changed_routine(tmp_path, routine, what, pattern, repl):
    card = routine.split("_")[0]
    part = ("sup.inc" if routine.endswith("_supervise") else "cmd.inc" if routine.endswith("_cmd")
            else "stp.inc" if card == "stp" else "servo.inc")
    src = open(os.path.join(FLOOR_SRC, part)).read()
    mutated, n = re.subn(pattern, lambda m: repl, src, count=1)
    assert n == 1, "the mutant's pattern is no longer in %s: %s" % (part, pattern)
    inc = tmp_path / "inc"
    inc.mkdir()
    for f in ("floor.h", "servo.inc", "stp.inc", "sup.inc", "cmd.inc"):     # the parts, the one mutated
        shutil.copy(os.path.join(FLOOR_SRC, f), inc / f)
    (inc / part).write_text(mutated)
    binf = assemble(str(tmp_path), str(inc), routine)
    rc, out, err = ps.floor_run(card, "--check", "3000", "--seed", "12345", "--routine", routine, "--bin", binf)
    assert rc == 1 and "MISMATCH" in out, "%s survived: %s%s" % (what, out, err)
    # and the unchanged source passes the same check
    (inc / part).write_text(src)
    binf = assemble(str(tmp_path), str(inc), routine)
    rc, out, err = ps.floor_run(card, "--check", "3000", "--seed", "12345", "--routine", routine, "--bin", binf)
    assert rc == 0, out + err
