"""The card's counters in the card data block live in the card's RAM and are
published to the DPRAM: a host write to one lasts until the next tick
publishes the true count again (at most one profile period)."""
import os
import sys

import pytest

from conftest import BOOT, CARDS, ROOT, sim

sys.path.insert(0, os.path.join(ROOT, "host"))
from mac4card import board as B  # noqa: E402

COUNTERS = ("DPC_RSP_LOST", "DPC_QUEUE_ERRORS", "DPC_VME_IRQ_LOST", "DPC_COMMANDS",
            "DPC_SERIAL_RX_OK", "DPC_SERIAL_NAKS", "DPC_SERIAL_GARBAGE", "DPC_SERIAL_OVERRUNS",
            "DPC_SERIAL_FRAMING", "DPC_SERIAL_CMD_LOST", "DPC_SERIAL_TX_OK", "DPC_SERIAL_TX_LOST")
JUNK = 0xDEAD0000


def peek_all(tag):
    return "echo %s\n" % tag + "".join("peek32 0x%04X\n" % getattr(B, n) for n in COUNTERS)


def sections(r):
    out, cur = {}, None
    for l in r.lines:
        p = l.split()
        if len(p) == 1 and p[0] in ("true", "poked", "after"):
            cur = out.setdefault(p[0], {})
        elif cur is not None and len(p) == 3 and p[0] == "peek32":
            cur[int(p[1], 16)] = int(p[2], 16)
    return {k: {n: v[getattr(B, n)] for n in COUNTERS} for k, v in out.items()}


@pytest.mark.parametrize("card", CARDS)
def test_a_host_write_to_a_counter_is_overwritten_by_the_true_count(card):
    work = ("send 0 VER\nsend 1 VER\nrun 20\n"
            "tx-msg 0 1\nrun 60\n"                    # a serial command: RX_OK, TX_OK
            "tx FF 00 41\nrun 40\n"                   # bytes outside a telegram: GARBAGE
            "tx 10 02 00 00 01 00 00 00 00 02\nrun 60\n")   # a bad checksum: NAKS
    script = (BOOT + work + peek_all("true")
              + "".join("poke32 0x%04X 0x%X\n" % (getattr(B, n), JUNK + i) for i, n in enumerate(COUNTERS))
              + peek_all("poked") + "run 40\n" + peek_all("after"))
    r = sim(script, card)
    s = sections(r)
    true, poked, after = s["true"], s["poked"], s["after"]
    assert true["DPC_COMMANDS"] == 3 and true["DPC_SERIAL_RX_OK"] == 1, true
    assert true["DPC_SERIAL_GARBAGE"] >= 3 and true["DPC_SERIAL_NAKS"] == 1, true
    assert all(poked[n] == JUNK + i for i, n in enumerate(COUNTERS)), poked   # the writes landed
    assert after == true, (after, true)


def test_the_count_goes_on_from_the_true_value():
    r = sim(BOOT + "send 0 VER\nrun 20\npoke32 0x%04X 0x%X\nsend 0 VER\nrun 20\npeek32 0x%04X\n"
            % (B.DPC_COMMANDS, JUNK, B.DPC_COMMANDS))
    assert r.peek(B.DPC_COMMANDS) == 2
