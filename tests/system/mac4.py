"""Shared helpers of the system tests, and the card's tables for them.

Nothing here is typed again from the firmware: the commands, status words,
modes and error codes come from build/commands.json (generated from
firmware/commands.def and firmware/status.def), the DPRAM map, the register
bits and the periods from host/mac4card/board.py (generated from
board/mac4.toml, as hal/mac4_map.h is)."""
import json
import os
import struct
import sys

from conftest import BOOT, BUILD, ROOT, sim

sys.path.insert(0, os.path.join(ROOT, "host"))
from mac4card import board  # noqa: E402,F401  (re-exported: `from mac4 import board`)
from mac4card import s32 as signed  # noqa: E402,F401  (a 32-bit word as a signed number)

TABLE = json.load(open(os.path.join(BUILD, "commands.json")))
BY_MN = {c["mnemonic"]: c for c in TABLE["commands"]}
for _a, _of in TABLE["aliases"].items():
    BY_MN[_a] = BY_MN[_of]
BIT = {word: {b["name"]: b["bit"] for b in bits if "width" not in b}
       for word, bits in TABLE["status"].items() if word != "modes"}
MODE = {m["name"]: m["code"] for m in TABLE["status"]["modes"]}
_MODE_FIELD = [b for b in TABLE["status"]["user"] if b["name"] == "mode"][0]
MODE_MASK = ((1 << _MODE_FIELD["width"]) - 1) << _MODE_FIELD["bit"]
# error codes by the status bit they set (6.3): ERR["limit_f"] == 162
ERR = {e["status_bit"]: e["code"] for e in TABLE["errors"]}

# the controller period of each card (manual 7.4), in ms
TICK_MS = {c: us / 1000 for c, us in board.PERIOD_US.items()}


def code(mn):
    return BY_MN[mn]["code"]


def ubits(*names, mode="disable"):
    v = MODE[mode]
    for n in names:
        v |= 1 << BIT["user"][n]
    return v


def _bits(word, names):
    v = 0
    for n in names:
        v |= 1 << BIT[word][n]
    return v


def obits(*names):
    return _bits("overall", names)


def ub(*names):
    """User status bits alone, as a mask (no mode)."""
    return _bits("user", names)


def sb(*names):
    """System status bits as a mask."""
    return _bits("system", names)


def has(st, name):
    """User status `st` has bit `name`."""
    return bool(st & ub(name))


def mode(st):
    """The mode field of a user status word."""
    return (st & MODE_MASK) >> _MODE_FIELD["bit"]


def codes(r):
    """The codes of the responses of a run, in order."""
    return [c for _, c, _ in r.resps()]


# ---- the DPRAM, as table 3.1 of the manual lays it out -------------------------------
def axis_addr(n, field):
    """Address of a published word of axis n: field one of USTAT, SSTAT, POS,
    SETPOINT, FERR, OUT, VEL, RAW (board.DPA_*)."""
    return board.DP_AXIS_DATA(n) + getattr(board, "DPA_" + field)


def ustat_addr(n=0):
    return axis_addr(n, "USTAT")


def pos_addr(n=0):
    return axis_addr(n, "POS")


def stop_bit(n):
    """The stop bit of axis n in the word at DP_STOP_BITS (3.5.1: bits 1, 3, 5, 7)."""
    return 2 << (2 * n)


# the word of an external encoder in axis 0's DPRAM block (4.4, <ea>) and its flag
EXT_POS, EXT_FLAG = board.DP_EXT_POS(0), board.DP_EXT_FLAG(0)


def ext_value(v, flag=True, n=0):
    """Script lines that write an external encoder's value for axis n's block
    in the DPRAM, then set bit 15 of its flag word (new value) unless not flag."""
    out = ["poke32 0x%X %d" % (board.DP_EXT_POS(n), v)]
    return out + (["poke16 0x%X 0x8000" % board.DP_EXT_FLAG(n)] if flag else [])


# the queues (7.3.2): header words and the fields of entry i
CMDQ, RSPQ = board.DP_CMD_QUEUE, board.DP_RSP_QUEUE


def qh(q, field):
    """Address of a header word of queue q: BASE, FRONT, REAR, FREE, WIDTH, NEL."""
    return q + getattr(board, "QH_" + field)


def q_entry(q, i, field="AXIS"):
    """Address of a field of entry i of queue q: AXIS, CODE, PARAM, SOURCE."""
    return q + board.Q_HEADER_SIZE + i * board.Q_WIDTH + getattr(board, "MSG_" + field)


def q_repair(q):
    """Script lines that write queue q's header back as the card creates it."""
    return ["poke32 0x%X 0x%X" % (qh(q, f), v) for f, v in
            (("BASE", board.Q_HEADER_SIZE), ("WIDTH", board.Q_WIDTH), ("NEL", board.Q_NEL),
             ("FRONT", 0), ("REAR", 0))]


def stop_line(*axes):
    """The script line with which the VME host sets the stop bits of `axes` (3.5.1)."""
    return "poke16 0x%X 0x%04X" % (board.DP_STOP_BITS, sum(stop_bit(n) for n in axes))


def watch(n=0, ms=10, count=100):
    """Script lines sampling the published user status and position of axis n."""
    out = []
    for _ in range(count):
        out += ["run %d" % ms, "peek32 0x%X" % ustat_addr(n), "peek32 0x%X" % pos_addr(n)]
    return out


def samples(r, n=0):
    """The samples `watch` took in a run (or its lines): (user status words,
    positions)."""
    lines = getattr(r, "lines", r)
    st = [int(l.split()[2], 16) for l in lines if l.startswith("peek32 0x%X " % ustat_addr(n))]
    ps = [signed(int(l.split()[2], 16)) for l in lines if l.startswith("peek32 0x%X " % pos_addr(n))]
    return st, ps


def crafted(tmp_path, code=b"", name="crafted.bin"):
    """A 64 KiB EPROM image of our own in tmp_path, its path: reset vectors
    (stack at the boot stack's top, PC at EPROM_BASE + $400), clr.w SYS_CTRL
    (release the boot overlay), `code` (bytes or hex), bra.s *."""
    if isinstance(code, str):
        code = bytes.fromhex(code)
    img = bytearray(b"\xff" * board.EPROM_SIZE)
    img[0:8] = struct.pack(">II", board.DPRAM_BOOT_STACK_TOP, board.EPROM_BASE + 0x400)
    prog = b"\x42\x79" + struct.pack(">I", board.SYS_CTRL) + code + bytes.fromhex("60FE")
    img[0x400:0x400 + len(prog)] = prog
    p = tmp_path / name
    p.write_bytes(img)
    return str(p)


def script(cmds, settle=5):
    """cmds: list of (axis, mnemonic-or-code, param) or raw script lines."""
    out = [BOOT]
    for c in cmds:
        if isinstance(c, str):
            out.append(c + "\n")
            continue
        axis, mn, *p = c
        out.append("send %d %s %s\n" % (axis, mn, p[0] if p else ""))
    out.append("run %d\n" % settle)
    return "".join(out)


def run(cmds, card="inc", settle=5, args=()):
    r = sim(script(cmds, settle), card, args=args)
    assert r.rc in (0, 3), r.stderr
    return r


ENABLE = [(0, "INIT"), (0, "ME"), (0, "E")]
