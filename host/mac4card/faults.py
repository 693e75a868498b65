"""The card's fault record in the DPRAM (docs/interpretations.md, "A fault
restarts the card"): an unexpected exception writes its vector number,
stacked PC and SR and, for bus and address errors, the access address, and
counts it; a watchdog reset keeps them, power-on clears them.  The offsets
come from board.py (generated from board/mac4.toml, as hal/mac4_map.h).

Only a host that reaches the DPRAM can read it: the emulator's host script
does (`peek32`); a serial line does not (docs/host-client.md)."""
from . import board as B

# (key, DPRAM offset) of the record's 32-bit big-endian words and the count
RECORD = (("vector", B.DPC_FAULT_VECTOR), ("pc", B.DPC_FAULT_PC), ("sr", B.DPC_FAULT_SR),
          ("address", B.DPC_FAULT_ADDR), ("count", B.DPC_FAULT_COUNT))

# the exceptions whose group-0 frame holds the access address (hal/target/vectors.S)
ACCESS_ADDRESS = (2, 3)

# the 68000's exception vector assignments (vector number: name)
_NAMES = {0: "reset: initial SSP", 1: "reset: initial PC", 2: "bus error", 3: "address error",
          4: "illegal instruction", 5: "zero divide", 6: "CHK instruction",
          7: "TRAPV instruction", 8: "privilege violation", 9: "trace",
          10: "line 1010 emulator", 11: "line 1111 emulator",
          15: "uninitialized interrupt vector", 24: "spurious interrupt"}


def exception_name(vector):
    """The 68000's name of an exception vector number."""
    if vector in _NAMES:
        return _NAMES[vector]
    if 25 <= vector <= 31:
        return "level %d interrupt autovector" % (vector - 24)
    if 32 <= vector <= 47:
        return "TRAP #%d instruction" % (vector - 32)
    if 64 <= vector <= 255:
        return "user interrupt vector"
    if 0 <= vector <= 63:
        return "reserved vector"
    return "not a 68000 vector number"


def decode_fault_record(words):
    """The record from its words ({key: value} of RECORD): a dict with
    "vector", "exception", "pc", "sr", "address" (None where the exception
    stacks none), "count" and "text"; None when the card has recorded no
    fault since power-on (vector and count 0)."""
    v, count = words["vector"], words["count"]
    if not v and not count:
        return None
    rec = {"vector": v, "exception": exception_name(v), "pc": words["pc"],
           "sr": words["sr"] & 0xFFFF,
           "address": words["address"] if v in ACCESS_ADDRESS else None, "count": count}
    text = "exception %d (%s) pc=$%06X sr=$%04X" % (v, rec["exception"], rec["pc"], rec["sr"])
    if rec["address"] is not None:
        text += " address=$%06X" % rec["address"]
    rec["text"] = "%s; %d fault(s) since power-on" % (text, count)
    return rec


def read_fault_record(peek32):
    """Read the record through peek32(offsets) -> values (a transport's)
    and decode it (decode_fault_record)."""
    values = peek32([off for _, off in RECORD])
    return decode_fault_record({key: val for (key, _), val in zip(RECORD, values)})
