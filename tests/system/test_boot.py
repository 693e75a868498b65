"""The EPROM images boot on the emulated IPC card."""
import binascii
import os
import shutil

import pytest

from conftest import BOOT, CARDS, image, sim
from mac4 import CMDQ, RSPQ, TICK_MS, board

# the header of both queues after the boot, as the manual gives it (7.3.2)
SPEC_HEADER = {0x00: 0x18, 0x04: 0, 0x08: 0, 0x0C: 0, 0x10: 0xA, 0x14: 0xA}


@pytest.mark.parametrize("card", CARDS)
def test_boot_sequence_banner_and_queues(card):
    peeks = "".join("peek32 0x%04X\n" % (q + off) for q in (CMDQ, RSPQ) for off in SPEC_HEADER)
    r = sim(BOOT + "run 50\nbanner\n" + peeks + "peek32 0x%X\npeek32 0x%X\n" % (board.DPC_BOOT_ERROR, board.DPC_VERSION), card)
    assert r.rc == 0, r.stderr
    assert r.faults() == []
    assert r.displays() == ["1", "2", "3", "5"]
    assert r.grep(r'^banner "MACCON \(C\)1993"$')
    for q in (CMDQ, RSPQ):
        for off, want in SPEC_HEADER.items():
            assert r.peek(q + off) == want, hex(q + off)
    assert r.peek(board.DPC_BOOT_ERROR) == board.DPC_ERR_NONE
    assert r.peek(board.DPC_VERSION) >> 24 == board.CARD_TYPE[card]  # VER: card type in bits 24-31


@pytest.mark.parametrize("card", CARDS)
def test_outputs_in_reset_state(card):
    r = sim(BOOT + "outputs\n", card)
    outs = r.grep(r"^output ")
    assert len(outs) == 4
    for l in outs:
        assert "en=0" in l and "dac=0" in l and "rate=0" in l and "dir=0" in l and "boost=0" in l


@pytest.mark.parametrize("card", CARDS)
def test_tick_runs_and_is_measured(card):
    period_ms = TICK_MS[card]
    r = sim(BOOT + "peek32 0x{0:X}\nrun 1000\npeek32 0x{0:X}\nirqstats\n".format(board.DPC_TICKS), card)
    ticks = [int(l.split()[2], 16) for l in r.grep(r"^peek32 0x%X " % board.DPC_TICKS)]
    assert abs((ticks[1] - ticks[0]) - 1000 / period_ms) <= 1
    row = r.grep(r"^timer \(L6\)")[0].split()
    count, mn, mean, mx = (int(x) for x in row[2:6])
    assert count >= 1000 / period_ms - 1
    assert 0 < mn <= mean <= mx < 10000      # sanity; the cycle budgets live in tests/timing


def _corrupt(tmp_path, card, offset):
    dst = tmp_path / ("mac4-%s-bad.bin" % card)
    shutil.copy(image(card), dst)
    data = bytearray(dst.read_bytes())
    data[offset] ^= 0x01
    dst.write_bytes(data)
    return str(dst)


@pytest.mark.parametrize("offset", [0x0191, 0x8000, 0xFFF0, 0xFFFD])
def test_one_byte_change_stops_at_checksum(tmp_path, offset):
    bad = _corrupt(tmp_path, "inc", offset)
    peeks = "".join("peek32 0x%X\n" % a for a in (board.DPC_BOOT_ERROR, board.DPC_CRC_EXPECTED, board.DPC_CRC_COMPUTED))
    r = sim("run 3000\n" + peeks + "queues\n", img=bad)
    # the card stops cleanly, no emulator fault: exit status 4, the card stopped
    assert r.rc == 4 and not r.faults() and "stopped with the display at 3." in r.stderr, r.stderr
    assert r.displays() == ["1", "2", "3", "3."]
    assert r.peek(board.DPC_BOOT_ERROR) == board.DPC_ERR_CHECKSUM   # the host can read why
    assert r.grep(r"^queue command .* nel=\$A") == []  # never became ready


def test_image_files_are_consistent():
    for card in CARDS:
        base = image(card)[:-4]
        img = open(base + ".bin", "rb").read()
        assert len(img) == 0x10000
        even, odd = open(base + ".even.bin", "rb").read(), open(base + ".odd.bin", "rb").read()
        assert len(even) == len(odd) == 0x8000
        assert bytes(b for pair in zip(even, odd) for b in pair) == img
        crc = binascii.crc_hqx(img[:0xFFFC], 0xFFFF)
        assert img[0xFFFC:] == bytes([crc >> 8, crc & 0xFF, (crc >> 8) ^ 0xFF, (crc & 0xFF) ^ 0xFF])
        # S-records reproduce the image
        rebuilt = bytearray(b"\xff" * 0x10000)
        for line in open(base + ".srec"):
            if line.startswith("S1"):
                rec = bytes.fromhex(line[2:].strip())
                assert (sum(rec) & 0xFF) == 0xFF
                addr = rec[1] << 8 | rec[2]
                rebuilt[addr:addr + rec[0] - 3] = rec[3:-1]
        assert bytes(rebuilt) == img
        for ext in (".elf", ".map", ".size.txt"):
            assert os.path.getsize(base + ext) > 0
        # the reset vectors: SSP in the DPRAM monitor area, PC in the EPROM
        assert int.from_bytes(img[0:4], "big") == board.DPRAM_BOOT_STACK_TOP
        assert board.EPROM_BASE <= int.from_bytes(img[4:8], "big") < board.EPROM_BASE + board.EPROM_SIZE


def test_no_reset_while_running():
    r = sim(BOOT + "run 3000\nstatus\n")
    assert r.grep(r"resets=1$")
    assert r.grep(r"^reset ") == []
