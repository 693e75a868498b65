#!/usr/bin/env python3
"""mkeprom.py - turn the linked firmware into burnable EPROM images.

From the raw binary that objcopy extracts from build/eprom/mac4-CARD.elf
(EPROM contents from offset 0), write:
  CARD.bin        64 KiB, padded with $FF, CRC-16/CCITT at $FFFC and its
                  complement at $FFFE (checked by the firmware at "$3")
  CARD.even.bin   bytes at even addresses (D8-D15, the "high" EPROM)
  CARD.odd.bin    bytes at odd addresses (D0-D7, the "low" EPROM)
  CARD.srec       Motorola S-record of CARD.bin, device offsets from 0
  CARD.size.txt   size report
"""
import argparse
import binascii
import sys

SIZE = 0x10000
CRC_OFFSET = 0xFFFC


def crc16(data: bytes) -> int:
    # CRC-16/CCITT-FALSE: poly $1021, init $FFFF (firmware/crc16.c)
    return binascii.crc_hqx(data, 0xFFFF)


def srec(data: bytes) -> str:
    def rec(kind, addr, payload, alen):
        body = bytes([len(payload) + alen + 1]) + addr.to_bytes(alen, "big") + payload
        csum = (~sum(body)) & 0xFF
        return "S%d%s%02X\n" % (kind, body.hex().upper(), csum)
    out = [rec(0, 0, b"mac4 eprom", 2)]
    for off in range(0, len(data), 32):
        out.append(rec(1, off, data[off:off + 32], 2))
    out.append(rec(5, len(out) - 1 if len(out) - 1 < 0x10000 else 0, b"", 2))
    out.append(rec(9, 0, b"", 2))
    return "".join(out)


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

    open(a.out + ".bin", "wb").write(img)
    open(a.out + ".even.bin", "wb").write(img[0::2])
    open(a.out + ".odd.bin", "wb").write(img[1::2])
    open(a.out + ".srec", "w").write(srec(bytes(img)))
    used = len(raw)
    report = ["EPROM image %s.bin (27C512, 65536 bytes)" % a.out,
              "  used      %6d bytes (%.1f%%)" % (used, 100.0 * used / SIZE),
              "  free      %6d bytes" % (CRC_OFFSET - used),
              "  checksum  $%04X at $%04X, complement $%04X" % (crc, CRC_OFFSET, crc ^ 0xFFFF)]
    if a.sections:
        report.append("  sections (size -A):")
        report += ["    " + l for l in open(a.sections).read().splitlines() if l.strip()]
    open(a.out + ".size.txt", "w").write("\n".join(report) + "\n")
    print(report[0].split(" (")[0] + ": %d bytes used, checksum $%04X" % (used, crc))


if __name__ == "__main__":
    main()
