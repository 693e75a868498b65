#!/usr/bin/env python3
"""mkeprom.py - turn the linked firmware into burnable EPROM images.

From the raw binary that objcopy extracts from build/eprom/mac4-CARD.elf
(EPROM contents from offset 0), write:
  CARD.bin        64 KiB, padded with $FF, CRC-16/CCITT at $FFFC and its
                  complement at $FFFE (checked by the firmware at "$3")
  CARD.even.bin   bytes at even addresses (D8-D15, the "high" EPROM), 32 KiB
  CARD.odd.bin    bytes at odd addresses (D0-D7, the "low" EPROM), 32 KiB
  CARD.srec       Motorola S-record of CARD.bin
  CARD.hex        Intel HEX of CARD.bin
  CARD.even.hex, CARD.odd.hex, CARD.even.srec, CARD.odd.srec
                  each chip for an EPROM programmer
  CARD.chips.txt  what to burn: the chip type, per-chip 16-bit sums
  CARD.size.txt   size report
All programmer files carry device offsets from 0 (the chip's own
addresses), not the card's bus addresses.
"""
import argparse
import binascii
import os
import sys

SIZE = 0x10000
CRC_OFFSET = 0xFFFC


def crc16(data: bytes) -> int:
    # CRC-16/CCITT-FALSE: poly $1021, init $FFFF (firmware/crc16.c)
    return binascii.crc_hqx(data, 0xFFFF)


CHIP = "27C256"          # 32 KiB x 8: one half of the 16-bit image
CHIP_SIZE = SIZE // 2


def sum16(data: bytes) -> int:
    """The 16-bit sum of the bytes, as EPROM programmers display it."""
    return sum(data) & 0xFFFF


def srec(data: bytes, header=b"mac4 eprom") -> str:
    def rec(kind, addr, payload, alen):
        body = bytes([len(payload) + alen + 1]) + addr.to_bytes(alen, "big") + payload
        csum = (~sum(body)) & 0xFF
        return "S%d%s%02X\n" % (kind, body.hex().upper(), csum)
    out = [rec(0, 0, header, 2)]
    for off in range(0, len(data), 32):
        out.append(rec(1, off, data[off:off + 32], 2))
    out.append(rec(5, len(out) - 1 if len(out) - 1 < 0x10000 else 0, b"", 2))
    out.append(rec(9, 0, b"", 2))
    return "".join(out)


def ihex(data: bytes) -> str:
    """Intel HEX, 16 data bytes a record, 16-bit addresses (the files are at
    most 64 KiB), then the end-of-file record."""
    assert len(data) <= 0x10000
    out = []
    for off in range(0, len(data), 16):
        chunk = data[off:off + 16]
        body = bytes([len(chunk), off >> 8, off & 0xFF, 0]) + chunk
        out.append(":%s%02X\n" % (body.hex().upper(), -sum(body) & 0xFF))
    out.append(":00000001FF\n")
    return "".join(out)


def chips_text(name, img, crc):
    even, odd = img[0::2], img[1::2]
    return """EPROMs for %(name)s.bin (%(size)d bytes, the 68000's 16-bit bus)

Two %(chip)s EPROMs of 32 KiB x 8 (32768 bytes each), device offsets 0-$7FFF:
  even bytes, data lines D8-D15 (the "high" chip): %(name)s.even.hex / .even.srec / .even.bin
      16-bit sum $%(se)04X
  odd bytes, data lines D0-D7 (the "low" chip):    %(name)s.odd.hex / .odd.srec / .odd.bin
      16-bit sum $%(so)04X
The sum is the one EPROM programmers display: all bytes of the chip added,
modulo $10000.  The whole image: sum $%(sa)04X, CRC-16/CCITT $%(crc)04X at $FFFC
(the firmware checks it at boot, display "3").

27C512 sockets (64 KiB x 8) instead: burn each half twice, at device offsets
0 and $8000, so the chip answers the same whatever its A15 pin sees, e.g.
  srec_cat %(name)s.even.hex -intel %(name)s.even.hex -intel -offset 0x8000 \\
           -o %(name)s.even.27c512.hex -intel
(the 16-bit sum of such a chip is twice the half's: $%(se2)04X even, $%(so2)04X odd).

The card's local memory map and this two-chip layout are this project's
design (docs/memory-map.md): the manual does not give them, and an image
for a real MAC4's IPC card may need another layout.
""" % dict(name=name, size=len(img), chip=CHIP, se=sum16(even), so=sum16(odd),
           sa=sum16(img), crc=crc, se2=sum16(even * 2), so2=sum16(odd * 2))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("raw", help="objcopy -O binary output of the ELF")
    ap.add_argument("out", help="output prefix, e.g. build/eprom/mac4-inc")
    ap.add_argument("--sections", help="text file from size -A for the report")
    ap.add_argument("--corrupt", type=lambda s: int(s, 0),
                    help="flip one byte at this offset after the CRC (for tests)")
    a = ap.parse_args()

    raw = open(a.raw, "rb").read()
    if len(raw) > CRC_OFFSET:
        sys.exit("mkeprom: image is %d bytes, only %d fit before the CRC" % (len(raw), CRC_OFFSET))
    img = bytearray(raw + b"\xff" * (CRC_OFFSET - len(raw)))
    crc = crc16(bytes(img))
    img += crc.to_bytes(2, "big") + (crc ^ 0xFFFF).to_bytes(2, "big")
    assert len(img) == SIZE
    if a.corrupt is not None:
        img[a.corrupt] ^= 0x01

    even, odd = bytes(img[0::2]), bytes(img[1::2])
    assert len(even) == len(odd) == CHIP_SIZE
    name = os.path.basename(a.out)
    open(a.out + ".bin", "wb").write(img)
    open(a.out + ".even.bin", "wb").write(even)
    open(a.out + ".odd.bin", "wb").write(odd)
    open(a.out + ".srec", "w").write(srec(bytes(img)))
    open(a.out + ".hex", "w").write(ihex(bytes(img)))
    for half, data, lines in (("even", even, "D8-D15"), ("odd", odd, "D0-D7")):
        open("%s.%s.hex" % (a.out, half), "w").write(ihex(data))
        open("%s.%s.srec" % (a.out, half), "w").write(
            srec(data, ("%s %s %s %s" % (name, half, lines, CHIP)).encode()))
    open(a.out + ".chips.txt", "w").write(chips_text(name, bytes(img), crc))
    used = len(raw)
    report = ["EPROM image %s.bin (65536 bytes: two %s of 32 KiB, %s.chips.txt)"
              % (a.out, CHIP, name),
              "  used      %6d bytes (%.1f%%)" % (used, 100.0 * used / SIZE),
              "  free      %6d bytes" % (CRC_OFFSET - used),
              "  checksum  $%04X at $%04X, complement $%04X" % (crc, CRC_OFFSET, crc ^ 0xFFFF),
              "  chips     even (D8-D15) sum $%04X, odd (D0-D7) sum $%04X" % (sum16(even),
                                                                         sum16(odd))]
    if a.sections:
        report.append("  sections (size -A):")
        report += ["    " + l for l in open(a.sections).read().splitlines() if l.strip()]
    open(a.out + ".size.txt", "w").write("\n".join(report) + "\n")
    print(report[0].split(" (")[0] + ": %d bytes used, checksum $%04X" % (used, crc))


if __name__ == "__main__":
    main()
