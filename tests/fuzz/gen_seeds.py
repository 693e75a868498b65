#!/usr/bin/env python3
"""gen_seeds.py - writes the hand-made seed inputs of tests/fuzz/corpus/.

    python3 tests/fuzz/gen_seeds.py        (rewrites the seed-* files only)

The input format of each target is in tests/fuzz/README.md; the encoders
below use only its stable forms (raw codes F8 hi lo, raw parameters
80 + 4 bytes), so a seed means the same whatever commands.def holds.
Inputs that libFuzzer found and `make fuzz-merge` kept sit beside these
under their hash names."""
import json
import os

HERE = os.path.dirname(os.path.abspath(__file__))

# manual 7.3.1, host -> card (WAP 16, MP, E, RCP, code 1 not implemented)
MANUAL_CMDS = [(0, 70, 16), (0, 59, 0), (0, 3, 0), (0, 116, 0), (0, 1, 0)]
MANUAL_TELEGRAMS = [
    "10 02 00 00 46 00 00 00 10 10 56",
    "10 02 00 00 3B 00 00 00 00 3B",
    "10 02 00 00 03 00 00 00 00 03",
    "10 02 00 00 74 00 00 00 00 74",
    "10 02 00 00 01 00 00 00 00 01",
]
# manual 7.3.1, card -> host (what the manual prints)
MANUAL_RESPONSES = [
    "10 02 00 00 46 02 00 01 01 4A",
    "10 02 00 00 3B 02 00 01 01 3F",
    "10 02 00 00 03 02 00 01 08 0E",
    "10 02 00 00 74 00 00 03 E8 5F",
    "10 02 00 00 A1 02 00 21 08 CC",
]

C = dict(INIT=2, E=3, C=4, DEINIT=5, MR=6, VER=7, FLYON=8, FLYOFF=9, USR=10, USN=11, TURBO=12,
         WAP_R=158, UE=50, MD=51, ME=52, MC=53, MI=54, MH=55, MF=56, MS=57, MB=58, MP=59, VT=60,
         MT=61, PT=62, MRE=63, WAP=70, WPV=72, WPA=74, WPD=76, WCV=78, WHV=84, WFV=90, WDL=96,
         WLV=98, WVT=100, WAT=102, WDA=104, WTR=106, WMF=112, WAA=114, WGA=130, WZE=132, WPO=134,
         WKI=136, WWD=138, WSSF=140, WIRQ1=144, WIRQ2=146, WIRQ5=152, WZP=156, UWSH=170, UWLP=172,
         UWLN=174, UWCR=176, UWET=178, UWEA=180, UWEB=182, UWEC=184, UWSC=186, UWPS=192, UWNS=194,
         UWRS=196, UWDF=198, UWSF=202, UWAO=204, RCP=116, RED=119, RFE=120, RAS=124, RBS=125, RSS=126,
         # the extensions (codes 210 on)
         WCRA=210, WCCA=212, WCSD=214, WCRW=216, WCCL=218, WCRS=220, WCCS=222, WCWR=224, CDEF=226,
         CENT=227, CPTR=228, RCEN=229, RCSM=230, CON=231, RCC=232, REXL=233, REXB=234, WPCP=240,
         WPCN=242, WPCE=244, WIRQ7=246, PCON=248, RPCC=249, RPCI=250, FBX=260, FBS=261, FBW1=262,
         FBW2=263, RFBS=264, RFW1=265, RFW2=266, RFBR=267, WFBE=270)


def u16(v):
    return bytes([(v >> 8) & 0xFF, v & 0xFF])


def u32(v):
    v &= 0xFFFFFFFF
    return bytes([v >> 24, (v >> 16) & 0xFF, (v >> 8) & 0xFF, v & 0xFF])


def axis(a):
    return bytes([a]) if a < 4 else bytes([a | 0x80])


def code(c):
    return b"\xF8" + u16(C.get(c, c) if isinstance(c, str) else c)


def param(p):
    return b"\x80" + u32(p)


def triple(a, c, p=0):
    return axis(a) + code(c) + param(p)


# ---- queue target (fuzz_queue.c) -------------------------------------------
def q_send(a, c, p=0):
    return b"\x00" + triple(a, c, p)


def q_passes(n):
    return b"\x01" + bytes([(n - 1) % 16])


def q_hdr(q, word, value):
    idx = ["base", "front", "rear", "free", "width", "nel"].index(word)
    op = b"\x02" if q == "cmd" else b"\x04"
    if 0 <= value < 16:
        return op + bytes([idx]) + bytes([value])
    return op + bytes([0x80 | idx]) + u32(value)


def q_idle(ms):
    return b"\x07" + bytes([max(0, ms - 1)])


QUEUE = {
    "ver": q_send(0, "VER"),
    "manual-7.3.1": b"".join(q_send(a, c, p) for a, c, p in MANUAL_CMDS) + q_passes(4),
    "position-each-axis": b"".join(q_send(n, c, p) for n in range(4) for c, p in
                                   [("INIT", 0), ("ME", 0), ("E", 0), ("WAP", 1000), ("MP", 0), ("E", 0)])
    + q_idle(200) + b"".join(q_send(n, c) for n in range(4) for c in ("RCP", "RBS", "RSS")),
    "host-not-reading": b"\x06" + b"\x0b\x00" + code("VER") + param(0) + q_passes(16) + b"\x06" + q_passes(16),
    "corrupt-front": q_send(0, "VER") + q_hdr("cmd", "front", 10) + q_passes(3) + b"\x05" + q_send(0, "VER"),
    "corrupt-rear": q_hdr("cmd", "rear", 0xFFFFFFFF) + q_passes(2) + b"\x05" + q_send(1, "RBS"),
    "corrupt-base-width": q_hdr("cmd", "base", 0x1000) + q_passes(2) + q_hdr("cmd", "width", 0x100)
    + q_passes(2) + b"\x05" + q_send(0, "VER"),
    "corrupt-response-nel": q_hdr("rsp", "nel", 11) + q_send(0, "VER") + q_passes(2) + b"\x05" + q_send(0, "VER"),
    "response-front-moved": q_hdr("rsp", "front", 7) + q_send(0, "VER") + q_passes(2) + b"\x05",
    "garbage-elements": b"\x03\x00\x63" + bytes((i * 37 + 11) & 0xFF for i in range(100)) + q_hdr("cmd", "front", 9)
    + q_passes(12),
    "false-axes": q_send(4, "VER") + q_send(255, "RBS") + q_send(0x80, 1) + q_send(0, "RAS"),
    "mr-j11-in": q_send(0, "MR") + q_idle(250) + q_send(0, "VER"),
    "mr-j11-out": b"\x0a\x00" + q_send(0, "MR") + q_idle(20) + q_send(0, "VER"),
    "estop": q_send(0, "INIT") + q_send(0, "ME") + q_send(0, "E") + b"\x09\x01" + q_passes(8)
    + q_send(0, "RBS") + b"\x09\x00" + q_send(0, "C") + q_send(0, "C") + q_send(0, "RAS"),
    "stop-bits": b"".join(q_send(n, c) for n in range(4) for c in ("INIT", "ME", "E", "MS", "E"))
    + b"\x08\x00\xaa" + q_passes(8) + b"".join(q_send(n, "RBS") for n in range(4)),
    "watchdog": q_send(0, "WWD", 5) + q_idle(30) + q_send(0, "VER") + q_send(0, "C") + q_send(0, "C")
    + q_send(0, "WWD", 0) + q_send(0, "VER"),
    "all-codes": b"".join(q_send(0, c) for c in range(0, 212)) + q_passes(4),
    "off-fly-hold": q_send(0, "INIT") + q_send(0, "ME") + q_send(0, "E") + q_send(0, "FLYOFF")
    + q_send(0, "WAP", 5000) + q_send(0, "MP") + q_send(0, "E") + q_send(0, "RCP") + q_send(1, "VER") + q_idle(250),
}


# ---- serial target (fuzz_serial.c) -----------------------------------------
def hexb(s):
    return bytes(int(x, 16) for x in s.split())


def s_raw(data, more=False):
    out = b""
    while data:
        chunk, data = data[:48], data[48:]
        out += bytes([0x82 if (more or data) else 0x02, len(chunk) - 1]) + chunk
    return out


def s_cmd(a, c, p=0):
    return b"\x00" + triple(a, c, p)


def s_pause(ms, long=False):
    return b"\x03" + bytes([(0x80 if long else 0) | min(ms, 63)])


SERIAL = {
    "manual-7.3.1-telegrams": b"".join(s_raw(hexb(t)) for t in MANUAL_TELEGRAMS),
    "manual-7.3.1-commands": b"".join(s_cmd(a, c, p) for a, c, p in MANUAL_CMDS),
    "manual-7.3.1-back-to-back": s_raw(b"".join(hexb(t) for t in MANUAL_TELEGRAMS)),
    "manual-7.3.1-responses-sent-back": b"".join(s_raw(hexb(t)) for t in MANUAL_RESPONSES),
    "checksum-10-doubled": s_raw(hexb("10 02 00 00 01 00 00 00 0F 10 10")) + s_cmd(0, "VER"),
    "checksum-10-single-then-next": s_raw(hexb("10 02 00 00 01 00 00 00 0F 10 10 02 00 00 07 00 00 00 00 07")),
    "checksum-10-at-end": s_raw(hexb("10 02 00 00 01 00 00 00 0F 10")) + s_pause(0, True),
    "all-dles": s_cmd(0x10 | 0, 0x1010, 0x10101010) + s_raw(hexb("10 02 10 10 10 10 10 10 10 10 10 10 10 10 10 10 70")),
    "truncated": s_raw(hexb("10 02 00 00 46 10 02 00 00 07 00 00 00 00 07")),
    "broken": s_raw(hexb("10 02 00 10 05 00 00 00")) + s_cmd(0, "VER"),
    "eight-data-bytes": s_raw(hexb("10 02 00 00 07 00 00 00 00 00 07")) + s_cmd(0, "VER"),
    "wrong-checksum": s_raw(hexb("10 02 00 00 07 00 00 00 00 08")),
    "stalled": s_raw(hexb("10 02 00 00 46")) + s_pause(40, True) + s_cmd(0, "RCP"),
    "lone-dle-timeout": s_raw(hexb("10")) + s_pause(10, True) + s_cmd(0, "VER"),
    "noise-between": s_raw(hexb("00 FF 15 02 10 03 AA")) + s_cmd(1, "RBS") + s_raw(hexb("10 10 10 02")),
    "burst-ten": b"\x04\x08" + b"".join(triple(n & 3, "VER") for n in range(10)),
    "stall-overrun": b"\x05\x07" + b"".join(triple(0, "RCP") for _ in range(8)) + b"\xff",
    "framing": b"\x06" + s_cmd(0, "VER"),
    "corrupted-byte": b"\x07" + b"\x00" + code("WAP") + param(16) + b"\x04\x01",
    "serial-mr": s_cmd(0, "MR") + s_pause(63, True) + s_pause(63, True) + s_cmd(0, "VER"),
    "serial-watchdog-lockout": s_cmd(0, "WWD", 7) + s_cmd(0, "VER") + s_cmd(0, "C"),
    "false-axis": s_cmd(7, "VER") + s_cmd(255, "RAS"),
}


# ---- cmd target (fuzz_cmd.c) -----------------------------------------------
def c_cmd(a, c, p=0):
    return b"\x00" + triple(a, c, p)


def c_run(passes):
    return b"\x04" + bytes([passes - 1])


def c_mode(n, mode_code):
    return b"\x0a" + bytes([n | ((mode_code - 50) << 2)])


CMD = {
    "modes-axis0": b"".join(c_mode(0, m) + c_run(40) for m in range(50, 64)),
    "modes-all-axes": b"".join(c_mode(n, m) + c_run(8) for n in range(4) for m in (52, 57, 59, 61, 58)),
    "param-edges": b"".join(c_cmd(0, w, v) for w in range(70, 206, 2)
                            for v in (0, 1, 0xFFFFFFFF, 0x7FFFFFFF, 0x80000000)),
    "param-reads": b"".join(c_cmd(1, w + 1) for w in range(70, 206, 2)),
    "positioning": c_cmd(0, "INIT") + c_cmd(0, "ME") + c_cmd(0, "E") + c_cmd(0, "WAP", 2000) + c_cmd(0, "MP")
    + c_cmd(0, "E") + c_run(255) + c_run(255) + c_cmd(0, "RCP") + c_cmd(0, "RFE") + c_cmd(0, "WAP_R", 0xFFFFFC18)
    + c_cmd(0, "E") + c_run(255),
    "test-mode": c_cmd(0, "INIT") + c_cmd(0, "MT") + c_cmd(0, "E") + c_cmd(0, "WDA", 2047) + c_run(40)
    + c_cmd(0, "WDA", 0xFFFFF800) + c_run(40) + b"\x05\x04" + c_run(4),
    "circular": c_cmd(2, "UWSH", 2) + c_cmd(2, "UWCR", 1000) + c_cmd(2, "INIT") + c_cmd(2, "ME") + c_cmd(2, "E")
    + c_cmd(2, "WAP", 999) + c_cmd(2, "MP") + c_cmd(2, "E") + c_run(255) + c_cmd(2, "WZP", 500) + c_cmd(2, "RCP"),
    "limits-and-drive-fault": c_mode(0, 57) + c_run(20) + b"\x05\x04" + c_run(8) + b"\x05\x20" + c_run(8)
    + c_cmd(0, "RBS") + c_cmd(0, "C") + c_cmd(0, "C"),
    "encoder-faults": c_mode(1, 59) + b"\x08\x05" + c_run(20) + b"\x08\x09" + c_run(10) + b"\x08\x81"
    + u32(1 << 20) + c_run(10) + c_cmd(1, "RBS"),
    "external-encoder-dpram": c_cmd(3, "UWET", 3) + c_cmd(3, "UWEA", 0x3000 + 3 * 0x400 + 0x30A)
    + c_cmd(3, "UWEB", 32) + c_cmd(3, "INIT") + b"\x09\x03" + u32(12345) + c_run(8) + c_cmd(3, "RCP"),
    "external-encoder-vme": c_cmd(0, "UWET", 4) + c_cmd(0, "UWEA", 0x200000) + c_cmd(0, "UWEB", 16)
    + c_cmd(0, "INIT") + c_run(8) + c_cmd(0, "RBS"),
    "estop-and-stop-bits": c_mode(0, 57) + c_mode(1, 59) + b"\x06\x01" + c_run(4) + b"\x06\x00"
    + c_cmd(0, "C") + c_cmd(0, "C") + c_mode(2, 57) + b"\x07\x00\xaa" + c_run(4),
    "servo-gains": c_cmd(0, "WGA", 32767) + c_cmd(0, "WZE", 255) + c_cmd(0, "WPO", 0xFFFFFF01)
    + c_cmd(0, "WKI", 32767) + c_cmd(0, "UWSF", 16) + c_mode(0, 57) + c_cmd(0, "WVT", 8388607) + c_run(255),
    "watchdog-and-mr": c_cmd(0, "WWD", 3) + c_run(8) + c_cmd(0, "VER") + c_cmd(0, "C") + b"\x0b\x01"
    + c_cmd(0, "MR") + c_run(255) + c_run(255),
    "deinit-usr": c_mode(0, 52) + c_cmd(0, "DEINIT") + c_cmd(0, "USR") + c_cmd(0, "INIT") + c_cmd(0, "USN")
    + c_cmd(0, "TURBO", 1) + c_cmd(0, "FLYOFF") + c_cmd(0, "FLYON"),
    # the extensions (docs/extensions.md), each set up as a host would and
    # then run: a table, a compare window, the feedback entries
    "ext-comp-1d": c_cmd(0, "INIT") + c_cmd(0, "WCCL", 4) + c_cmd(0, "WCRS", 4000) + c_cmd(0, "CDEF")
    + b"".join(c_cmd(0, "CENT", v & 0xFFFFFFFF) for v in (0, 160, -320, 480, 0)) + c_cmd(0, "RCSM")
    + c_cmd(0, "CON", 1) + c_cmd(0, "ME") + c_cmd(0, "E") + c_cmd(0, "WAP", 3000) + c_cmd(0, "MP") + c_cmd(0, "E")
    + c_run(255) + c_cmd(0, "RCC") + c_cmd(0, "CPTR", 2) + c_cmd(0, "RCEN") + c_cmd(0, "WCWR", 1)
    + c_cmd(0, "REXL") + c_cmd(0, "REXB") + c_cmd(0, "CON", 0) + c_cmd(0, "DEINIT"),
    "ext-comp-2d": b"".join(c_cmd(a, "INIT") for a in range(3)) + c_cmd(2, "WCRA", 0) + c_cmd(2, "WCCA", 1)
    + c_cmd(2, "WCSD", 3) + c_cmd(2, "WCRW", 2) + c_cmd(2, "WCCL", 2) + c_cmd(2, "WCRS", 2000)
    + c_cmd(2, "WCCS", 1000) + c_cmd(2, "CDEF") + b"".join(c_cmd(2, "CENT", 16 * k) for k in range(9))
    + c_cmd(2, "CON", 1) + c_mode(0, 57) + c_mode(1, 59) + c_mode(2, 52) + c_run(255) + c_cmd(2, "RCC")
    + b"\x08\x80" + u32(1 << 16) + c_run(20) + c_cmd(2, "CDEF"),
    "ext-compare": c_cmd(0, "INIT") + c_cmd(0, "ME") + c_cmd(0, "E") + c_cmd(0, "WIRQ7", 0x40)
    + c_cmd(0, "WPCP", 1000) + c_cmd(0, "WPCN", 500) + c_cmd(0, "WPCE", 5000) + c_cmd(0, "PCON", 1)
    + c_cmd(0, "WAP", 6000) + c_cmd(0, "MP") + c_cmd(0, "E") + c_run(255) + c_run(255) + c_cmd(0, "RPCC")
    + c_cmd(0, "RPCI") + c_cmd(0, "WAP", 0) + c_cmd(0, "E") + c_run(255) + c_cmd(0, "PCON", 2) + c_cmd(0, "C")
    + c_cmd(0, "PCON", 0),
    "ext-feedback": c_cmd(0, "INIT") + c_cmd(1, "INIT") + c_cmd(0, "FBX", 0) + c_cmd(0, "FBS", 0xE01110)
    + c_cmd(0, "FBX", 1) + c_cmd(0, "FBW2", 1 << 20) + c_cmd(0, "FBS", 0xD00000)
    + c_cmd(0, "FBX", 2) + c_cmd(0, "FBW1", 16) + c_cmd(0, "FBW2", 100) + c_cmd(0, "FBS", 0x300020)
    + c_cmd(0, "FBX", 3) + c_cmd(0, "FBW1", 1 << 18) + c_cmd(0, "FBW2", 1 << 10) + c_cmd(0, "FBS", 0xB00010)
    + c_cmd(0, "RFBS") + c_cmd(0, "RFW1") + c_cmd(0, "RFW2") + c_cmd(0, "WFBE", 2) + c_mode(0, 59)
    + c_mode(1, 57) + c_run(255) + c_cmd(0, "FBX", 1) + c_cmd(0, "RFBR") + c_cmd(0, "FBX", 9) + c_cmd(0, "C")
    + c_cmd(0, "FBX", 0) + c_cmd(0, "FBS", 0),
}


# the emulator's power-on DPRAM pattern is (i * 131 + 7) & $FF: the first
# even address below $400 whose word has bit 15 set, plus 2
VEC_EA = next(a for a in range(4, 0x400, 2) if (a * 131 + 7) & 0x80) + 2


# ---- reproducers of known bugs (tests/fuzz/known, make fuzz-known) --------
# name: (target, cards, input).  Each fails with FUZZ_STRICT=1 while its bug
# is open; fixed, it belongs in the corpus.
KNOWN = {
}

# Reproducers of bugs fixed since: seeds of their target now (corpus/TARGET/
# seed-NAME, replayed on every card), so that they stay fixed.
FIXED = {
    # K3: position tracking to a far position: the setpoint interpolation
    # overflowed 32 bits (undefined behaviour in C); positions wrap modulo 2^32 now
    "K3-setpoint-overflow": ("cmd", c_mode(1, 62) + c_cmd(1, "WAT", 0xC2212A2B) + c_run(200)),
    # K1: <ea> unchecked: ET 3 with the default <ea> 0 read and wrote $FFFFFE
    "K1-ea-zero": ("queue", q_send(0, "UWET", 3) + q_send(0, "INIT") + q_passes(8)),
    # K1: an odd <ea>: address error on the 68000
    "K1-ea-odd": ("cmd", c_cmd(0, "UWET", 3) + c_cmd(0, "UWEA", 0x3301) + c_cmd(0, "INIT") + c_run(8)),
    # K1: <ea> inside the command queue: the card wrote its header
    "K1-ea-in-queue": ("queue", q_send(0, 0x8000) + q_send(0, "C") + q_send(0, "UWET", 3) + q_send(0, "UWEA", 0x471C)
                       + q_send(0, "INIT") + q_passes(16)),
    # K1: <ea> below $3002: the flag word read (and zeroed) was in the live
    # vector table (here the low word of vector 1, $8xxx in the emulator's
    # power-on pattern; on the card any handler above $108000)
    "K1-ea-in-vectors": ("cmd", c_cmd(0, "UWET", 3) + c_cmd(0, "UWEA", VEC_EA) + c_cmd(0, "INIT") + c_run(16)),
    # K2: an external VME encoder with no board answering: a bus error every
    # tick was reported again every tick, 163 to every command of the axis
    "K2-vme-encoder-missing": ("serial", s_cmd(0, "UWET", 3) + s_cmd(0, "UWEA", 0xF01000)
                               + s_cmd(0, "INIT") + s_cmd(0, "C") + s_cmd(0, "DEINIT")),
}


# ---- the targets on the emulator (fuzz_script.c, fuzz_image.c, fuzz_card68k.c):
# byte 0 the card (% 3), then the target's own format

def _scenario(name):
    with open(os.path.join(HERE, "..", "scenarios", name), "rb") as f:
        return f.read()


SCRIPT = {
    "boot-%s" % c: bytes([i]) + b"wait-display 5 3000\nqueues\nbanner\nstatus\n"
    for i, c in enumerate(("inc", "ssi", "stp"))
}
SCRIPT.update({
    "vocabulary": b"\0send 0 WAP 0100\nsend 0 MP\nrun 2.5\npeek32 0x4700\npoke16 $5000 0x1234\n"
                  b"peek16 0x5000\npeek8 0xFFFF\nhost read off\nestop on\nestop off\nfc 3\n"
                  b"jumper j11 out\ntx 10 02 00 00 46 00 00 00 10 10 56\ntx-msg 0 WAP 16\n"
                  b"serial-stats\nleds\noutputs\nirqstats\nbus-stats\nprofile report 3\n"
                  b"wait-display 7 1\nrun-ticks 1\nplant 0 gear 2.5\nplant 0 encoder lines 500\n"
                  b"switch 0 lp 1000 high\nfault 0 drive on\ncounter 0 $123\naxreg 0 in\n"
                  b"vme-encoder $80C000 0 bits 14 res 10000\nvme-boards\nstepper 0 steps 200\n"
                  b"trace 0 t.csv\nvcd v.vcd\ngdb 0\necho done\nquit\n",
    "include": b"\0include a.mac4\ninclude loop.mac4\ninclude deep.mac4\ninclude /dev/zero\n"
               b"include self.mac4\ninclude nothing.mac4\ninclude .\n",
    "bad-numbers": b"\0run nan\nrun 0x10\nwait-display 5 99999999999999999999\nrun-ticks 0\n"
                   b"peek32 0xFFFE\nsend 0 WAP 0o17\nestop maybe\nhost read maybe\n",
    "long-line": b"\0echo " + b"a" * 1100 + b"\nrun 1\n",
    "nul": b"\0echo a\0b\nrun 1\n",
    "scenario-inc": b"\0" + _scenario("inc-7.2-plant.mac4"),
    "scenario-ssi": b"\1" + _scenario("ssi-7.2-plant.mac4"),
})

IMAGE = {
    "inc": b"\6", "ssi": b"\4", "stp": b"\5",                        # the build's images (mode & 4)
    "inc-one-byte": b"\6\x80\x00\x01",                                # a change the checksum sees
    "ssi-crc-word": b"\4\xff\xfc\xff\xff\xfd\xff",                    # the CRC word itself
    "stp-vectors": b"\5\x00\x04\xff\x00\x05\xff",                    # the reset PC
    "empty": b"\0",
    "tiny": b"\0\x4e\x71",
    "too-large": b"\x08\x4e\x71",
    "blank": b"\x08",
}


def _u16(v):
    return bytes([(v >> 8) & 255, v & 255])


def _u32(v):
    return bytes([(v >> 24) & 255, (v >> 16) & 255, (v >> 8) & 255, v & 255])


def k_cmd(a, c, p=0):              # opcode 3, code F8 hi lo
    return bytes([3, a, 0xF8]) + _u16(c) + _u32(p)


def k_tel(a, c, p=0):              # opcode 5
    return bytes([5, a, 0xF8]) + _u16(c) + _u32(p)


def k_poke32(off, v):              # off from $3000
    return bytes([2]) + _u16(off - 0x3000) + _u32(v)


CARD68K = {
    "manual-%s" % c: bytes([i]) + b"".join(k_cmd(a, code, p) for a, code, p in MANUAL_CMDS)
    + bytes([6, 200])
    for i, c in enumerate(("inc", "ssi", "stp"))
}
CARD68K.update({
    "serial-manual": b"\0" + b"".join(bytes([4, len(hexb(t)) - 1]) + hexb(t) for t in MANUAL_TELEGRAMS)
                     + bytes([6, 100]),
    "telegrams": b"\1" + b"".join(k_tel(0, code, p) for _, code, p in MANUAL_CMDS) + bytes([6, 100]),
    "wreck-headers": b"\0" + k_poke32(0x4700 + 4, 0xFFFFFFFF) + k_cmd(0, 7) + k_poke32(0x4800 + 8, 99)
                     + bytes([6, 40]),
    "estop-stopbits": b"\2" + k_cmd(0, 3) + bytes([7, 0, 1, 6, 10, 7, 1, 0, 0xAA, 7, 0, 0, 7, 3])
                      + k_cmd(1, 7),
    "counters": b"\0" + k_poke32(0x4024, 0xFFFFFFFF) + k_poke32(0x4040, 0x12345678) + bytes([6, 20]),
})


# ---- the host side in Python (fuzz_host.py): byte 0 of a batch input says
# what the rest is (bit 0: a dictionary; bits 1-2: the card), telegrams are
# the bytes on the line

BATCH = {
    "manual": b"\0# the manual's sequence (7.3.1)\n0 WAP 16\n0 MP 0\nsend 0 E\nwait 5\n0 RCP\n0 1\n",
    "numbers": b"\2" + b"0 WAP 0100\n0 WAP $64\n0 WAP 0x64\n1 WAP -5\n3 70 16\n255 VER\nrun 2.5\n",
    "bad": b"\4" + b"0\n0 NOSUCH\nwait\n0 WAP 1 2 3\n9999 VER\n",
    "latin1": b"\0" + "0 VER # M\u00fcller\n".encode("latin-1"),
    "dict-small": b"\1" + json.dumps({"cards": {"inc": 0}, "status": {"user": [{"bit": 0, "name": "x"}]},
                                        "errors": [], "aliases": {"WED": "WAA"},
                                        "commands": [{"mnemonic": "VER", "code": 7, "kind": "read",
                                                      "cards": ["inc"]}]}).encode(),
    "dict-aliases-list": b"\1" + b'{"cards": {}, "status": {}, "errors": [], "aliases": [1], "commands": []}',
    "dict-deep": b"\1" + b"[" * 5000 + b"]" * 5000,
}

TELEGRAM = {"manual-%d" % i: hexb(t) for i, t in enumerate(MANUAL_TELEGRAMS + MANUAL_RESPONSES)}
TELEGRAM.update({
    "nak-between": hexb("15 10 02 00 00 46 00 00 00 10 10 56 15"),
    "dle-checksum-single": hexb("10 02 00 00 46 00 00 00 10 10 10 10 02"),
    "garbage": hexb("00 FF 10 10 10 03 10 02 00"),
})


def write_known():
    d = os.path.join(HERE, "known")
    os.makedirs(d, exist_ok=True)
    for f in os.listdir(d):
        if f.startswith("K"):
            os.remove(os.path.join(d, f))
    for name, (target, cards, data) in KNOWN.items():
        for card in cards.split():
            with open(os.path.join(d, "%s.%s.%s" % (name, target, card)), "wb") as f:
                f.write(data)
    print("%s: %d reproducers" % (d, len(KNOWN)))


def write(target, seeds):
    d = os.path.join(HERE, "corpus", target)
    os.makedirs(d, exist_ok=True)
    for f in os.listdir(d):
        if f.startswith("seed-"):
            os.remove(os.path.join(d, f))
    for name, data in seeds.items():
        with open(os.path.join(d, "seed-" + name), "wb") as f:
            f.write(data)
    print("%s: %d seeds" % (d, len(seeds)))


def with_fixed(target, seeds):
    return dict(seeds, **{name: data for name, (t, data) in FIXED.items() if t == target})


if __name__ == "__main__":
    write("queue", with_fixed("queue", QUEUE))
    write("serial", with_fixed("serial", SERIAL))
    write("cmd", with_fixed("cmd", CMD))
    write("script", SCRIPT)
    write("image", IMAGE)
    write("card68k", CARD68K)
    write("batch", BATCH)
    write("telegram", TELEGRAM)
    write_known()
