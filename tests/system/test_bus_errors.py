"""Bus errors and the double bus fault (docs/board.md, "Bus errors";
docs/interpretations.md).  A bus cycle no device acknowledges (an unmapped
address, a write to the EPROM, a byte write to a word-wide I/O register)
ends with /BERR from the card's bus timer and the 68000 takes its group-0
exception through vector 2; a bus or address error while it processes
another (or the reset) halts the CPU until a reset: the watchdog's with J11
in."""
import json
import os
import re
import subprocess
import sys

import pytest

from conftest import BOOT, CARDS, ROOT, SIM, sim
from mac4 import crafted

sys.path.insert(0, os.path.join(ROOT, "host"))
from mac4card import board as B  # noqa: E402

CODE = B.EPROM_BASE + 0x406          # crafted(): the code after clr.w SYS_CTRL
DUMP = 0x5000                        # where the handler copies the frame (DPRAM)
# the handler: the 7-word frame at (sp) to DUMP, then bra.s *
HANDLER = "21D7%04X21EF0004%04X21EF0008%04X31EF000C%04X60FE" % (DUMP, DUMP + 4, DUMP + 8, DUMP + 12)
HALT = r"^fault CPU halted \(double bus fault\): "


def with_handler(fault, vector=None):
    """move.l #handler,$8.w; FAULT; bra.s *; the handler.  vector: put that
    value in vector 2 instead of the handler's address."""
    handler = CODE + 8 + len(bytes.fromhex(fault)) + 2
    return "21FC%08X0008" % (handler if vector is None else vector) + fault + "60FE" + HANDLER, handler


def frame(r):
    """The dumped frame: (status word, access address, IR, SR, PC)."""
    w = [r.peek(DUMP) >> 16, r.peek(DUMP) & 0xFFFF, r.peek(DUMP + 4) >> 16, r.peek(DUMP + 4) & 0xFFFF,
         r.peek(DUMP + 8) >> 16, r.peek(DUMP + 8) & 0xFFFF, r.peek(DUMP + 12) >> 16]
    return w[0], w[1] << 16 | w[2], w[3], w[4], w[5] << 16 | w[6]


PEEKS = "".join("peek32 0x%04X\n" % (DUMP + 4 * i) for i in range(4))

# the faulting instruction at CODE + 8: its words, what the frame must hold and the fault line
CASES = [
    # move.w d0,$F80000: an unmapped write, supervisor data (FC 5), R/W 0
    ("33C000F80000", 0x0005, 0xF80000, 0x33C0, CODE + 14, r"^fault unmapped write16 at \$F80000 pc=\$10040E$"),
    # move.w $F80002,d0: an unmapped read, R/W 1
    ("303900F80002", 0x0015, 0xF80002, 0x3039, CODE + 14, r"^fault unmapped read16 at \$F80002 pc=\$10040E$"),
    # move.l d0,$F7FFFE: the long's first word faults, no second cycle
    ("23C000F7FFFE", 0x0005, 0xF7FFFE, 0x23C0, CODE + 14, r"^fault unmapped write16 at \$F7FFFE"),
    # move.l d0,$207FFE: the long's second word, past the SRAM's end
    ("23C000207FFE", 0x0005, 0x208000, 0x23C0, CODE + 14, r"^fault unmapped write16 at \$208000"),
    # move.w d0,$100000: the EPROM is decoded for reads only
    ("33C000100000", 0x0005, 0x100000, 0x33C0, CODE + 14, r"^fault write to EPROM at \$100000"),
    # move.b d0,$F00000: the I/O decoder acknowledges word writes only
    ("13C000F00000", 0x0005, 0xF00000, 0x13C0, CODE + 14, r"^fault byte write to word register at \$F00000"),
    # jmp $F80000: the opcode fetch there, supervisor program (FC 6); PC past it
    ("4EF900F80000", 0x0016, 0xF80000, 0x4EF9, 0xF80002, r"^fault unmapped read16 at \$F80000 pc=\$F80000$"),
]


@pytest.mark.parametrize("code,status,addr,ir,pc,line", CASES, ids=[c[0] for c in CASES])
def test_bus_error_frame(tmp_path, code, status, addr, ir, pc, line):
    prog, handler = with_handler(code)
    r = sim("run 5\n" + PEEKS, img=crafted(tmp_path, prog))
    assert r.rc == 3, r.out                              # a fault, and exit status 3
    assert r.grep(line), r.out
    assert r.grep(r"^fault exception 2 \(bus error\)"), r.out
    assert not r.grep(HALT), r.out
    # R/W, I/N 0 (an instruction's access), FC; the access address; IR; SR as
    # after the reset (supervisor, mask 7, the flags of move.l #handler); PC
    assert frame(r) == (status, addr, ir, 0x2700, pc), [hex(x) for x in frame(r)]
    assert len(r.faults()) == 2, r.out                   # the access and the exception, once


def test_device_faults_inside_a_window_are_no_bus_error(tmp_path):
    """A register a device does not define, inside its decoded window, is
    acknowledged: a fault report, no bus error."""
    prog, _ = with_handler("303900F0000E")               # move.w $F0000E,d0: sys, undefined
    r = sim("run 5\n" + PEEKS, img=crafted(tmp_path, prog))
    assert r.grep(r"^fault read of undefined system register \+\$E"), r.out
    assert not r.grep(r"exception 2|CPU halted"), r.out


def test_bus_error_cycles(tmp_path):
    """What the faulting instruction costs (profile pcs): its three words'
    fetches (4 + 1 wait each), the faulting cycle's whole length (the bus
    timer), the exception's 50, and the wait states of its 7 writes to the
    DPRAM, its vector's 2 reads and the refill's second word from the EPROM
    (1 each).  The same instruction to the SRAM takes 16 + 3."""
    pcs = tmp_path / "pcs.txt"
    got = {}
    for code in ("33C000F80000", "33C000200000"):
        prog, _ = with_handler(code)
        sim("profile on\nrun 1\nprofile pcs %s\n" % pcs, img=crafted(tmp_path, prog, code + ".bin"))
        rows = {int(p, 16): int(c) for p, c, n in (l.split() for l in pcs.read_text().splitlines())}
        got[code] = rows[CODE + 8]
    assert got["33C000200000"] == 16 + 3
    assert got["33C000F80000"] == 3 * (4 + 1) + B.MAC4_BUS_TIMEOUT_CLOCKS + 50 + 7 + 2 + 1, got


# ---- the double bus fault: the CPU halts ------------------------------------------------

DOUBLE = [
    # the stack in unmapped memory: the bus error's own frame gets a bus error
    ("sp-unmapped", "2E7C00F80000" + "33C000F80000", None,
     r"bus error at \$F7FFFC \(write, FC 5\) in the exception processing of a bus error"),
    # the stack odd: the address error's frame gets an address error
    ("sp-odd", "2E7C00003001" + "303900100001", None,
     r"address error at \$002FFD \(write, FC 5\) in the exception processing of an address error"),
    # vector 2 unmapped: the prefetch of the handler's first word
    ("vector-unmapped", "33C000F80000", 0xF80000,
     r"bus error at \$F80000 \(read, FC 6\) in the exception processing of a bus error"),
    # vector 2 odd: the handler's first fetch is an address error
    ("vector-odd", "33C000F80000", 0x100001,
     r"address error at \$100001 \(read, FC 6\) in the exception processing of a bus error"),
    # a TRAP (group 2) whose frame gets a bus error: a bus error, whose own frame
    # gets another one: the double fault
    ("trap-stack", "2E7C00F80000" + "4E40", None,
     r"bus error at \$F7FFF[0-9A-F] \(write, FC 5\) in the exception processing of a bus error"),
]


@pytest.mark.parametrize("name,code,vector,why", DOUBLE, ids=[d[0] for d in DOUBLE])
def test_double_bus_fault_halts_once(tmp_path, name, code, vector, why):
    prog, _ = with_handler(code, vector)
    r = sim("run 300\nstatus\n", img=crafted(tmp_path, prog), args=["--j11", "out"])
    assert r.rc == 3, r.out
    halts = r.grep(HALT)
    assert len(halts) == 1 and re.search(why, halts[0]), r.out    # once, with its reason
    assert "J11 out: halted until a reset" in halts[0]
    assert not r.grep(r"^reset"), r.out
    assert len(r.faults()) <= 4, r.out                  # no flood while it stays halted
    assert "the CPU is halted" in r.stderr, r.stderr


def test_halted_card_restarts_through_the_watchdog(tmp_path):
    """J11 in: nothing kicks the watchdog while the CPU is halted; it resets
    the card 100 ms after the boot, which halts again: one halt per reset."""
    prog, _ = with_handler("2E7C00F80000" + "33C000F80000")
    r = sim("run 350\n", img=crafted(tmp_path, prog), args=["--timestamps"])
    ev = [l.split(" ", 1)[1] for l in r.lines if re.match(r"^@\S+ (reset|fault CPU halted)", l)]
    assert [e.split()[0] for e in ev] == ["fault", "reset", "fault", "reset", "fault", "reset", "fault"], r.out
    t = [float(l.split()[0][1:-2]) for l in r.lines if re.match(r"^@\S+ reset watchdog", l)]
    assert [round(x) for x in t] == [100, 200, 300], t
    assert r.rc == 3 and all("the watchdog resets the card 100 ms" in e for e in ev if e.startswith("fault"))


def test_reset_button_restarts_a_halted_cpu(tmp_path):
    prog, _ = with_handler("2E7C00F80000" + "33C000F80000")
    r = sim("run 10\nreset\nrun 10\n", img=crafted(tmp_path, prog), args=["--j11", "out"])
    assert len(r.grep(HALT)) == 2 and r.grep(r"^reset button"), r.out


@pytest.mark.parametrize("vectors,why", [
    ("0000300000100401", r"address error at \$100401 \(read, FC 6\) in the exception processing of the reset"),
    ("0000300000F80000", r"bus error at \$F80000 \(read, FC 6\) in the exception processing of the reset"),
    ("000030000010FFFE", r"bus error at \$110000 \(read, FC 6\) in the exception processing of the reset"),
], ids=["odd", "unmapped", "second-word"])
def test_reset_into_nothing_halts(tmp_path, vectors, why):
    """The reset's processing ends with the prefetch at the initial PC."""
    img = tmp_path / "v.bin"
    img.write_bytes(bytes.fromhex(vectors))
    r = sim("run 50\n", img=str(img), args=["--j11", "out"])
    halts = r.grep(HALT)
    assert r.rc == 3 and len(halts) == 1 and re.search(why, halts[0]), r.out


def test_fault_storm_image_ends_in_the_halt():
    """The image libFuzzer found (stack unmapped, PC odd: docs/hardening.md)
    printed a fault line at every instruction; now the reset halts at once,
    and each watchdog reset gives one line.  700 ms: 7 halts."""
    data = open(os.path.join(ROOT, "tests", "fuzz", "corpus", "image", "found-fault-storm"), "rb").read()
    img = os.path.join(ROOT, "build", "fuzz-storm-test.bin")
    with open(img, "wb") as f:
        f.write(data[1:])
    try:
        r = sim("run 700\n", img=img)
        out = subprocess.run([SIM, "--image", img, "--j11", "out", "--script", "-"], input="run 700\n",
                             capture_output=True, text=True, timeout=60)
    finally:
        os.remove(img)
    assert r.rc == 3 and len(r.grep(HALT)) == 7 and len(r.faults()) == 7, r.out
    assert "in the exception processing of the reset" in r.grep(HALT)[0]
    assert out.returncode == 3 and len(out.stdout.splitlines()) == 1, out.stdout
    assert "the CPU is halted" in out.stderr


# ---- the firmware's bus error: vector 2, the fault record, the restart ------------------

TIMER_VECTOR = 4 * (24 + B.IRQ_LEVEL_TIMER)
NOWHERE = 0xF80000                   # no device decodes it
RECORD = ("DPC_FAULT_VECTOR", "DPC_FAULT_PC", "DPC_FAULT_SR", "DPC_FAULT_ADDR", "DPC_FAULT_COUNT",
          "DPC_BOOT_ERROR")


def record(r):
    return {n: r.peek(getattr(B, n)) for n in RECORD}


RECPEEKS = "".join("peek32 0x%04X\n" % getattr(B, n) for n in RECORD)


@pytest.mark.parametrize("card", CARDS)
def test_firmware_bus_error_record_and_restart(card):
    """A stray host write makes the timer's vector point where nothing is: the
    next tick's first fetch gets a bus error, the firmware's vector 2 writes
    the fault record, shows F. and lets the watchdog restart the card, which
    comes up again with the record kept."""
    r = sim(BOOT + "poke32 0x%04X 0x%X\nrun 400\n" % (TIMER_VECTOR, NOWHERE) + BOOT + RECPEEKS
            + "send 0 VER\nrun 20\n", card, args=["--allow-faults"])
    assert r.rc == 0, r.stderr
    assert r.grep(r"^fault unmapped read16 at \$F80000 pc=\$F80000$"), r.out
    assert r.grep(r"^fault exception 2 \(bus error\)"), r.out
    assert not r.grep(HALT), r.out
    ev = r.grep(r"^(display|reset)")
    i = ev.index("display F.")
    assert ev[i + 1:] == ["reset watchdog", "display 1", "display 2", "display 3", "display 5"], ev
    rec = record(r)
    assert rec["DPC_FAULT_VECTOR"] == 2 and rec["DPC_FAULT_ADDR"] == NOWHERE, rec
    assert rec["DPC_FAULT_PC"] == NOWHERE + 2, rec       # past the word it fetched
    assert rec["DPC_FAULT_SR"] & 0x2700 == 0x2600, rec   # supervisor, in the level-6 interrupt
    assert rec["DPC_FAULT_COUNT"] == 1 and rec["DPC_BOOT_ERROR"] == 0, rec
    assert any(a == 0 for a, c, p in r.resps()), r.out


def test_firmware_bus_error_j11_out_stays_at_f():
    r = sim(BOOT + "poke32 0x%04X 0x%X\nrun 1000\n" % (TIMER_VECTOR, NOWHERE) + RECPEEKS, "inc",
            args=["--allow-faults", "--j11", "out"])
    assert r.rc == 0 and not r.grep(r"^reset") and not r.grep(HALT), r.out
    assert r.displays()[-1] == "F."
    rec = record(r)
    assert (rec["DPC_FAULT_VECTOR"], rec["DPC_FAULT_ADDR"], rec["DPC_FAULT_COUNT"]) == (2, NOWHERE, 1), rec
    assert rec["DPC_BOOT_ERROR"] == B.DPC_ERR_EXCEPTION, rec


def test_mac4host_reports_the_bus_error_record(tmp_path):
    """From outside: mac4host, on a card that took the bus error and restarted,
    prints the record (docs/host-client.md)."""
    w = tmp_path / "faultsim"
    w.write_text("#!/bin/sh\n{ printf 'wait-display 5\\npoke32 0x%04X 0x%X\\nrun 400\\n'; cat; } "
                 "| exec %s \"$@\"\n" % (TIMER_VECTOR, NOWHERE, SIM))
    w.chmod(0o755)
    p = subprocess.run([sys.executable, os.path.join(ROOT, "tools", "mac4host.py"), "--json", "--sim-path", str(w),
                        "--sim-arg=--allow-faults", "send", "0", "RBS"], capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr
    fr = [o for o in map(json.loads, p.stdout.splitlines()) if o["type"] == "fault_record"]
    assert fr, p.stdout
    o = fr[0]
    assert (o["vector"], o["exception"], o["pc"], o["address"], o["count"]) == \
        (2, "bus error", NOWHERE + 2, NOWHERE, 1), o
    assert re.match(r"^exception 2 \(bus error\) pc=\$F80002 sr=\$26[0-9A-F]{2} address=\$F80000; "
                    r"1 fault\(s\) since power-on$", o["text"]), o["text"]
