"""Helpers for the system tests: run the EPROM image in build/mac4sim."""
import os
import re
import subprocess
from dataclasses import dataclass, field

import pytest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
BUILD = os.path.join(ROOT, "build")
SIM = os.environ.get("MAC4SIM") or os.path.join(BUILD, "mac4sim")   # make sanitize: build/san/mac4sim
CARDS = ("inc", "ssi", "stp")


def image(card):
    return os.path.join(BUILD, "eprom", "mac4-%s.bin" % card)


@dataclass
class Run:
    rc: int
    lines: list
    stderr: str
    out: str = field(repr=False, default="")

    def grep(self, pattern):
        rx = re.compile(pattern)
        return [l for l in self.lines if rx.search(l)]

    def faults(self):
        return self.grep(r"^fault ")

    def displays(self):
        return [l.split()[1] for l in self.grep(r"^display ")]

    def resps(self):
        out = []
        for l in self.grep(r"^resp "):
            _, axis, code, param = l.split()
            out.append((int(axis), int(code), int(param, 16)))
        return out

    def peek(self, addr):
        for l in self.lines:
            p = l.split()
            if len(p) == 3 and p[0].startswith("peek") and int(p[1], 16) == addr:
                return int(p[2], 16)
        raise KeyError(hex(addr))


def sim(script, card="inc", img=None, args=(), timeout=120):
    cmd = [SIM, "--card", card, "--script", "-"] + list(args)
    if img:
        cmd += ["--image", img]
    p = subprocess.run(cmd, input=script, capture_output=True, text=True, timeout=timeout)
    r = Run(p.returncode, p.stdout.splitlines(), p.stderr, p.stdout)
    if img is None and "--allow-faults" not in args:
        # The guard of docs/hardening.md: the firmware images of this build
        # never cause an address or bus error, an unmapped access, a write to
        # the EPROM, an illegal instruction or a double bus fault, in any test
        # (mac4sim prints each as a `fault` line and exits 3).  Tests that
        # want faults use a crafted image (img=) or --allow-faults.
        assert r.rc != 3 and not r.faults(), "emulator fault with the %s image:\n%s" % (
            card, "\n".join(r.faults()) or r.stderr)
    return r


BOOT = "wait-display 5 3000\n"


@pytest.fixture(scope="session", autouse=True)
def built():
    for c in CARDS:
        assert os.path.exists(image(c)), "run make first"
    assert os.path.exists(SIM)
