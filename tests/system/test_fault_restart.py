"""An unexpected exception: the fault record in the DPRAM survives the
watchdog's restart (J11 in) or stays with "F." (J11 out).  The fault is a
single stray host write into the live vector table: the timer's autovector
(level 6, $78) made odd, so the next tick takes an address error."""
import os
import sys

import pytest

from conftest import BOOT, CARDS, ROOT, sim

sys.path.insert(0, os.path.join(ROOT, "host"))
from mac4card import board as B  # noqa: E402

TIMER_VECTOR = 4 * (24 + B.IRQ_LEVEL_TIMER)
BAD = 0x100001                         # odd: the vector fetch ends in an address error
RECORD = ("DPC_FAULT_VECTOR", "DPC_FAULT_PC", "DPC_FAULT_SR", "DPC_FAULT_ADDR", "DPC_FAULT_COUNT")


def peeks():
    return "".join("peek32 0x%04X\n" % getattr(B, n) for n in RECORD + ("DPC_BOOT_ERROR",)) + \
        "peek32 0x%04X\n" % TIMER_VECTOR


def record(r):
    return {n: r.peek(getattr(B, n)) for n in RECORD + ("DPC_BOOT_ERROR",)}


def stray_write(n=1):
    return ("poke32 0x%04X 0x%X\nrun 400\n" % (TIMER_VECTOR, BAD) + BOOT) * n


@pytest.mark.parametrize("card", CARDS)
def test_power_on_clears_the_record(card):
    r = sim(BOOT + peeks(), card)
    rec = record(r)
    assert all(v == 0 for v in rec.values()), rec    # the power-on DPRAM is not zero in the model


@pytest.mark.parametrize("card", CARDS)
def test_j11_in_the_watchdog_restarts_the_card_and_the_record_stays(card):
    r = sim(BOOT + stray_write() + peeks() + "send 0 VER\nrun 20\n", card, args=["--allow-faults", "--j11", "in"])
    assert r.rc == 0, r.stderr
    assert r.grep(r"^fault exception 3 \(address error\)"), r.out
    ev = r.grep(r"^(display|reset)")
    i = ev.index("display F.")
    assert ev[i + 1] == "reset watchdog", ev               # F., then the watchdog's reset
    assert ev[i + 2:] == ["display 1", "display 2", "display 3", "display 5"], ev
    rec = record(r)
    assert rec["DPC_FAULT_VECTOR"] == 3 and rec["DPC_FAULT_ADDR"] == BAD, rec
    assert rec["DPC_FAULT_PC"] == BAD, rec
    assert rec["DPC_FAULT_SR"] & 0x2700 == 0x2600, rec     # supervisor, in the level-6 interrupt
    assert rec["DPC_FAULT_COUNT"] == 1 and rec["DPC_BOOT_ERROR"] == 0, rec
    vec = r.peek(TIMER_VECTOR)
    assert vec != BAD and 0x100000 <= vec < 0x110000, hex(vec)   # the boot copied the vectors again
    assert any(a == 0 for a, c, p in r.resps()), r.out     # the card answers again


def test_j11_in_each_fault_is_counted():
    r = sim(BOOT + stray_write(3) + peeks(), "inc", args=["--allow-faults"])
    assert len(r.grep(r"^reset watchdog")) == 3, r.out
    assert record(r)["DPC_FAULT_COUNT"] == 3


@pytest.mark.parametrize("card", CARDS)
def test_j11_out_stays_at_f_with_the_record_readable(card):
    r = sim(BOOT + "poke32 0x%04X 0x%X\nrun 1000\n" % (TIMER_VECTOR, BAD) + peeks(), card,
            args=["--allow-faults", "--j11", "out"])
    assert r.rc == 0, r.stderr
    assert not r.grep(r"^reset"), r.out
    assert r.displays()[-1] == "F.", r.displays()
    rec = record(r)
    assert rec["DPC_FAULT_VECTOR"] == 3 and rec["DPC_FAULT_PC"] == BAD and rec["DPC_FAULT_ADDR"] == BAD, rec
    assert rec["DPC_FAULT_COUNT"] == 1, rec
    assert rec["DPC_BOOT_ERROR"] == B.DPC_ERR_EXCEPTION, rec


def test_mr_keeps_the_record_of_an_earlier_fault():
    """A watchdog reset keeps the record whatever started it: MR after a fault
    restart still shows the fault (cleared only at power-on)."""
    r = sim(BOOT + stray_write() + "send 0 MR\nrun 400\n" + BOOT + peeks(), "inc", args=["--allow-faults"])
    assert len(r.grep(r"^reset watchdog")) == 2, r.out
    assert record(r)["DPC_FAULT_COUNT"] == 1
