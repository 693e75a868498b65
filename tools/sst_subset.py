#!/usr/bin/env python3
"""sst_subset.py SRC DST [--per-file N] - the subset of the SingleStepTests
68000 vectors committed under tests/conformance/vectors (docs/cpu-timing.md),
so that the conformance lane also runs on a clone without ../shared.

Per vector file of SRC: the first test of every instruction form (the test's
name with its number, registers and constants left out: "ADD.l D4, D1" and
"ADD.l D0, D7" are one form, A7 one of its own), in file order, then the next tests in order,
up to N (default 16) that do not end in an address error, and the first one
that does (so the lane's skip of those is exercised). Records are copied
byte for byte; only the count in the file header changes. LICENSE is copied.
"""
import argparse
import os
import re
import shutil
import struct
import sys

FILE_MAGIC = 0x1A3F5D71
TEST_MAGIC = 0xABC12367


class BadVectors(Exception):
    pass


def records(data, path):
    if len(data) < 8:
        raise BadVectors("%s: too short" % path)
    magic, count = struct.unpack_from("<II", data, 0)
    if magic != FILE_MAGIC:
        raise BadVectors("%s: not a vector file (magic %08X)" % (path, magic))
    off = 8
    for _ in range(count):
        if off + 8 > len(data):
            raise BadVectors("%s: truncated at byte %d" % (path, off))
        size, magic = struct.unpack_from("<II", data, off)
        if magic != TEST_MAGIC or size < 8 or off + size > len(data):
            raise BadVectors("%s: bad test record at byte %d" % (path, off))
        yield data[off:off + size]
        off += size
    if off != len(data):
        raise BadVectors("%s: %d trailing bytes" % (path, len(data) - off))


def name_of(rec):
    # name block: u32 size, u32 magic, u32 length, bytes
    length, = struct.unpack_from("<I", rec, 16)
    return rec[20:20 + length].decode("utf-8", "replace")


def ends_in_address_error(rec):
    """The transactions block is the record's last; kinds 4/5 are address errors."""
    # skip name, initial state, final state
    off = 8
    for _ in range(3):
        size, = struct.unpack_from("<I", rec, off)
        off += size
    n, = struct.unpack_from("<I", rec, off + 12)
    off += 16
    for _ in range(n):
        kind = rec[off]
        off += 5
        if kind:
            off += 20
            if kind in (4, 5):
                return True
    return False


def form(name):
    text = name.split(" ", 1)[1] if " " in name else name
    text = re.sub(r"\s+[0-9a-f]{4}$", "", text)          # the opcode
    text = re.sub(r"\b(D[0-7]|A[0-6])\b", "R", text)       # registers (A7 kept: SP)
    return re.sub(r"-?\b\d+\b", "n", text)               # constants


def subset(recs, per_file):
    chosen, forms, aerr = [], set(), None
    plain = [r for r in recs if not ends_in_address_error(r)]
    for r in recs:
        if aerr is None and ends_in_address_error(r):
            aerr = r
    for r in plain:
        f = form(name_of(r))
        if f not in forms and len(chosen) < per_file:
            forms.add(f)
            chosen.append(r)
    for r in plain:
        if len(chosen) >= per_file:
            break
        if r not in chosen:
            chosen.append(r)
    chosen.sort(key=recs.index)
    if aerr is not None:
        chosen.append(aerr)
    return chosen


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("src")
    ap.add_argument("dst")
    ap.add_argument("--per-file", type=int, default=16)
    a = ap.parse_args()
    if a.per_file < 1:
        ap.error("--per-file wants 1 or more")
    try:
        names = sorted(n for n in os.listdir(a.src) if n.endswith(".json.bin"))
    except OSError as e:
        sys.exit("sst_subset: %s" % e)
    if not names:
        sys.exit("sst_subset: %s: no *.json.bin vector files" % a.src)
    os.makedirs(a.dst, exist_ok=True)
    total = 0
    try:
        for n in names:
            with open(os.path.join(a.src, n), "rb") as f:
                recs = list(records(f.read(), n))
            out = subset(recs, a.per_file)
            with open(os.path.join(a.dst, n), "wb") as f:
                f.write(struct.pack("<II", FILE_MAGIC, len(out)))
                for r in out:
                    f.write(r)
            total += len(out)
    except (BadVectors, OSError) as e:
        sys.exit("sst_subset: %s" % e)
    lic = os.path.join(a.src, "LICENSE")
    if os.path.exists(lic):
        shutil.copy(lic, os.path.join(a.dst, "LICENSE"))
    print("sst_subset: %d tests from %d files into %s" % (total, len(names), a.dst))


if __name__ == "__main__":
    main()
