#!/usr/bin/env python3
"""fuzz_host.py - fuzz targets of the host side in Python: mac4host's batch
parser (with the command dictionary it reads) and the telegram decoder of
host/mac4card.  A deterministic mutation fuzzer, guided by line coverage
(sys.settrace over host/mac4card and tools/mac4host.py): the same --seed
gives the same inputs.

    tests/fuzz/fuzz_host.py --target batch|telegram [--seconds N] [--seed S]
    tests/fuzz/fuzz_host.py --replay      the corpus and 300 inputs per target (make test)

Properties
  batch:    for any bytes as a batch file (read_batch_file, parse_batch) and
            any mutation of build/commands.json (load_dictionary): steps, or
            a Mac4Error of one line; never another exception.
  telegram: TelegramDecoder.feed never raises; the events of a byte stream do
            not depend on how it is split into chunks; after a quiet line
            (flush), an encoded telegram (DLE doubled or not in its checksum)
            decodes as exactly that telegram, whatever came before.
A finding prints the input's hex, keeps it as build/fuzz/crash-host-TARGET-N
and exits 1.  One summary line as tests/fuzz/run.sh prints.
"""
import argparse
import contextlib
import io
import json
import os
import random
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "tools"))
import mac4host  # noqa: E402
from mac4host import (Garbage, Mac4Error, Nak, ChecksumError, Telegram, TelegramDecoder,  # noqa: E402
                      encode_telegram)

COVERED_FILES = (os.path.join(ROOT, "host", "mac4card"), os.path.join(ROOT, "tools", "mac4host.py"))
BUILD = os.path.join(ROOT, "build")


class Finding(Exception):
    pass


# ---- the targets -----------------------------------------------------------------

_dict_text = None
_dictionary = None


def dictionary():
    global _dictionary, _dict_text
    if _dictionary is None:
        path = os.path.join(BUILD, "commands.json")
        if not os.path.isfile(path):
            sys.exit("fuzz_host.py: %s is missing (make %s)" % (path, os.path.relpath(path, ROOT)))
        _dict_text = open(path, "rb").read()
        _dictionary = mac4host.load_dictionary(path)
    return _dictionary


def one_line(e):
    if "\n" in str(e):
        raise Finding("an error of more than one line: %r" % str(e))


def target_batch(data, tmp):
    """byte 0 bit 0: the input is a dictionary (JSON) instead of a batch file."""
    d = dictionary()
    kind, body = (data[0] if data else 0), data[1:]
    path = os.path.join(tmp, "input")
    with open(path, "wb") as f:
        f.write(body)
    try:
        if kind & 1:
            d2 = mac4host.load_dictionary(path)
            # a dictionary that loads is one the parser can use
            mac4host.parse_batch(d2, ["0 VER", "send 1 RBS", "wait 5"], None, "x")
        else:
            lines, name = mac4host.read_batch_file(path)
            card = (None, "inc", "ssi", "stp")[kind >> 1 & 3]
            mac4host.parse_batch(d, lines, card, name)
    except Mac4Error as e:
        one_line(e)
    except RecursionError:
        raise Finding("RecursionError")
    except Exception as e:               # noqa: BLE001 - any other is the finding
        raise Finding("%s: %s" % (type(e).__name__, e))


def events_of(dec, chunks):
    out = []
    for c in chunks:
        out += dec.feed(c)
    return out


def target_telegram(data, tmp):
    del tmp
    try:
        whole = events_of(TelegramDecoder(), [data])
        rnd = random.Random(len(data) ^ (data[0] if data else 0))
        chunks, i = [], 0
        while i < len(data):
            k = rnd.randint(1, 9)
            chunks.append(data[i:i + k])
            i += k
        split = events_of(TelegramDecoder(), chunks)
        if whole != split:
            raise Finding("the events depend on the chunks: %r / %r" % (whole[:4], split[:4]))
        for e in whole:
            if not isinstance(e, (Telegram, Nak, ChecksumError, Garbage)):
                raise Finding("an event of type %s" % type(e).__name__)
        # after a quiet line, a good telegram is decoded as itself
        axis, code, param = (data[0] if data else 0), len(data) * 257 & 0xFFFF, (sum(data) * 2654435761) & 0xFFFFFFFF
        dec = TelegramDecoder()
        dec.feed(data)
        dec.flush()
        for dbl in (False, True):
            got = dec.feed(encode_telegram(axis, code, param, double_dle_checksum=dbl))
            got += dec.flush()
            if got != [Telegram(axis, code, param)]:
                raise Finding("telegram %d %d $%08X (DLE doubled: %s) after a flush decoded as %r"
                              % (axis, code, param, dbl, got))
    except Finding:
        raise
    except Exception as e:               # noqa: BLE001
        raise Finding("%s: %s" % (type(e).__name__, e))


TARGETS = {"batch": target_batch, "telegram": target_telegram}


# ---- seeds, mutation, coverage ----------------------------------------------------

def seeds(target):
    d = os.path.join(HERE, "corpus", target)
    out = []
    if os.path.isdir(d):
        for f in sorted(os.listdir(d)):
            out.append(open(os.path.join(d, f), "rb").read())
    return out or [b"\0"]


def mutate(rnd, data, pool, deep=True):
    b = bytearray(data)
    for _ in range(rnd.randint(1, 6)):
        op = rnd.randrange(9 if deep else 7)
        pos = rnd.randint(0, len(b))
        if op == 0 and b:
            b[rnd.randrange(len(b))] ^= 1 << rnd.randrange(8)
        elif op == 1 and b:
            b[rnd.randrange(len(b))] = rnd.randrange(256)
        elif op == 2:
            b[pos:pos] = bytes(rnd.randrange(256) for _ in range(rnd.randint(1, 8)))
        elif op == 3 and b:
            del b[pos:pos + rnd.randint(1, 16)]
        elif op == 4:
            b[pos:pos] = rnd.choice((b"\x10", b"\x10\x02", b"\x15", b"\x10\x10", b"\n", b"#", b" ",
                                     b"0x", b"$", b"-", b"\xff", b"\xc3\xa9", b"\0", b"[", b"{", b'"',
                                     b"99999999999999999999", b"nan", b"1e9", b"0100", b"WAP", b"send",
                                     b"wait", b'"aliases": [', b'"mnemonic": 5', b'"status": []'))
        elif op == 5 and pool:                      # splice another input
            o = rnd.choice(pool)
            i = rnd.randint(0, len(o))
            b[pos:pos] = o[i:i + rnd.randint(1, 64)]
        elif op == 6 and b:                         # repeat a piece
            i = rnd.randrange(len(b))
            b[pos:pos] = b[i:i + rnd.randint(1, 8)] * rnd.randint(2, 50)
        elif op == 7:
            b[pos:pos] = b"[" * rnd.randint(1, 3000)  # deep nesting (batch only)
        elif op == 8 and len(b) > 1:
            b = b[:rnd.randint(1, len(b))]
    return bytes(b[:8192 if deep else 512])


class Coverage:
    def __init__(self):
        self.lines = set()
        self.new = False

    def tracer(self, frame, event, arg):
        f = frame.f_code.co_filename
        if not f.startswith(COVERED_FILES):
            return None
        if event == "line":
            k = (f, frame.f_lineno)
            if k not in self.lines:
                self.lines.add(k)
                self.new = True
        return self.tracer

    def run(self, fn, *a):
        self.new = False
        sys.settrace(self.tracer)
        try:
            fn(*a)
        finally:
            sys.settrace(None)
        return self.new


def campaign(target, seconds=None, iterations=None, seed=1, crash_dir=os.path.join(BUILD, "fuzz")):
    fn = TARGETS[target]
    rnd = random.Random(seed)
    cov = Coverage()
    pool = []
    execs = 0
    t0 = time.monotonic()
    with tempfile.TemporaryDirectory() as tmp:
        def one(data):
            nonlocal execs
            execs += 1
            try:
                with contextlib.redirect_stderr(io.StringIO()):   # mac4host's notes
                    new = cov.run(fn, data, tmp)
                if new:
                    pool.append(data)
            except Finding as e:
                os.makedirs(crash_dir, exist_ok=True)
                keep = os.path.join(crash_dir, "crash-host-%s-%d" % (target, execs))
                with open(keep, "wb") as f:
                    f.write(data)
                print("PROPERTY VIOLATED (%s): %s\n  input %s (kept as %s)"
                      % (target, e, data[:200].hex(), keep), file=sys.stderr)
                return False
            return True

        for s in seeds(target):
            if not one(s):
                return 1, execs, len(cov.lines), len(pool)
        while True:
            if iterations is not None and execs >= iterations:
                break
            if seconds is not None and time.monotonic() - t0 >= seconds:
                break
            if not one(mutate(rnd, rnd.choice(pool or [b"\0"]), pool, deep=target == "batch")):
                return 1, execs, len(cov.lines), len(pool)
    return 0, execs, len(cov.lines), len(pool)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--target", choices=sorted(TARGETS))
    ap.add_argument("--seconds", type=float)
    ap.add_argument("--iterations", type=int)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--replay", action="store_true")
    a = ap.parse_args(argv)
    sys.setrecursionlimit(1000)
    targets = sorted(TARGETS) if a.replay or not a.target else [a.target]
    worst = 0
    for t in targets:
        t0 = time.monotonic()
        if a.replay:
            rc, execs, lines, corp = campaign(t, iterations=300, seed=a.seed)
        else:
            rc, execs, lines, corp = campaign(t, seconds=a.seconds if a.seconds else 60,
                                              iterations=a.iterations, seed=a.seed)
        print("%-7s %-4s %5ss  execs %-10s cov %-6s lines     corpus %-5s crashes %d%s"
              % (t, "host", int(round(time.monotonic() - t0)), execs, lines, corp, rc,
                 "  (see above)" if rc else ""))
        worst = max(worst, rc)
    return worst


if __name__ == "__main__":
    sys.exit(main())
