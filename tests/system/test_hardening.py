"""Hardening checks that belong with the system tests
(docs/hardening.md): the EPROM images are 68000 code, and the checker that
says so fails when it should; the guard against emulator faults; warnings
as errors and cppcheck configured so that they bite."""
import os
import re
import subprocess

import pytest

import conftest
from conftest import BUILD, CARDS, ROOT

CHECK = os.path.join(ROOT, "tools", "check68000.py")
CROSS = os.environ.get("CROSS", "m68k-linux-gnu-")


def check(*files):
    p = subprocess.run([CHECK] + list(files), capture_output=True, text=True)
    return p.returncode, p.stdout + p.stderr


@pytest.mark.parametrize("card", CARDS)
def test_image_is_68000_code(card):
    elf = os.path.join(BUILD, "eprom", "mac4-%s.elf" % card)
    rc, out = check(elf)
    assert rc == 0, out
    m = re.search(r": ok: (\d+) instructions from (\d+) entry points, (\d+) bytes of code", out)
    assert m and int(m.group(1)) > 1000, out
    # nearly all of the code section is accounted for: code, jump tables, data objects
    other = int(re.search(r"(\d+) others", out).group(1))
    assert other < 256, out


FN = """    .text
    .globl f
    .type f,@function
f:
"""

# (assembler text, the kind of finding, a word of the message): one 68010/68020
# feature or one odd access each; assembled with -m68020 so gas accepts them
BAD = {
    "mulu.l": ("mulu.l %d1,%d0\n rts", "68000", "not a 68000 instruction"),
    "divs.l": ("divs.l %d1,%d0\n rts", "68000", "not a 68000"),
    "extb.l": ("extb.l %d0\n rts", "68000", "not a 68000"),
    "bsr.l": ("bsr.l f\n rts", "target", "odd address"),
    "bra.l": ("nop\n bra.l f", "target", "odd address"),
    "rtd": ("rtd #4", "68000", "not a 68000"),
    "movec": ("movec %d0,%vbr\n rts", "68000", "not a 68000"),
    "move-from-ccr": ("move.w %ccr,%d0\n rts", "68000", "not a 68000"),
    "link.l": ("link.l %a6,#-8\n unlk %a6\n rts", "68000", "not a 68000"),
    "bfextu": ("bfextu %d0{1:3},%d1\n rts", "68000", "not a 68000"),
    "cas": ("cas.l %d0,%d1,(%a0)\n rts", "68000", "not a 68000"),
    "bkpt": ("bkpt #1\n rts", "68000", "not a 68000"),
    "scaled-index": ("move.l (4,%a0,%d1.l*4),%d2\n rts", "ea", "scaled index"),
    "memory-indirect": ("move.l ([4,%a0]),%d0\n rts", "ea", "memory indirect"),
    "odd-word": ("move.w 5(%a0),%d0\n rts", "odd", "odd displacement"),
    "odd-long-store": ("move.l %d0,3(%a1)\n rts", "odd", "odd displacement"),
    "odd-indexed": ("move.w 7(%a0,%d1.w),%d0\n rts", "odd", "odd displacement"),
    "odd-absolute": ("move.w 0x4001,%d0\n rts", "odd", "odd absolute"),
}


def assemble(tmp_path, name, body, cpu="-m68020"):
    src = tmp_path / (name + ".S")
    src.write_text(FN + " " + body + "\n")
    obj = tmp_path / (name + ".o")
    p = subprocess.run([CROSS + "gcc", cpu, "-c", str(src), "-o", str(obj)], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    return str(obj)


@pytest.mark.parametrize("name", sorted(BAD))
def test_check68000_fails_on_purpose(tmp_path, name):
    body, kind, words = BAD[name]
    rc, out = check(assemble(tmp_path, name, body))
    assert rc == 1, out
    assert re.search(r": %s: .*%s" % (re.escape(kind), words), out), out


def test_check68000_passes_clean_68000_code(tmp_path):
    """No false alarms: odd byte accesses, address arithmetic at odd
    offsets, bit operations, and GCC's inline jump tables (data inside the
    code section, never decoded)."""
    obj = assemble(tmp_path, "bytes", """move.b 5(%a0),%d0
 move.b %d0,3(%a1)
 lea 5(%a0),%a1
 pea 3(%a1)
 btst #0,5(%a0)
 st 1(%a0)
 tst.b 7(%a0,%d0.w)
 move.w 6(%a0),%d1
 move.l -4(%a6),%d2
 rts""", cpu="-m68000")
    rc, out = check(obj)
    assert rc == 0, out
    c = tmp_path / "switch.c"
    c.write_text("""int sw(int x, volatile unsigned char *p) {
    switch (x) {
    case 0: return p[1]; case 1: return p[3] + 7; case 2: return p[5] * 3; case 3: return 11;
    case 4: return p[7] - 1; case 5: return 99; case 6: return p[9]; case 7: return 42;
    default: return -1; } }
""")
    o = tmp_path / "switch.o"
    p = subprocess.run([CROSS + "gcc", "-m68000", "-Os", "-c", str(c), "-o", str(o)], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    rc, out = check(str(o))
    assert rc == 0, out
    assert "0 of jump tables" not in out, out      # the table was found and skipped


def test_fault_guard_fails_a_run_of_the_real_image(tmp_path, monkeypatch):
    """conftest.sim() fails any test whose run of a build image saw an
    emulator fault (address error, unmapped access, EPROM write, illegal
    instruction), even if the test itself only looks at responses."""
    fake = tmp_path / "mac4sim"
    fake.write_text("#!/bin/sh\ncat >/dev/null\necho 'fault exception 3 (address error) pc=$100abc'\nexit 3\n")
    fake.chmod(0o755)
    monkeypatch.setattr(conftest, "SIM", str(fake))
    with pytest.raises(AssertionError, match="address error"):
        conftest.sim("run 1\n")
    r = conftest.sim("run 1\n", args=["--allow-faults"])     # asked for: passes through
    assert r.rc == 3


def make_var(name):
    p = subprocess.run(["make", "-C", ROOT, "-pn", "--no-print-directory", "nothing-at-all"],
                       capture_output=True, text=True)
    for line in p.stdout.splitlines():
        if line.startswith(name + " :=") or line.startswith(name + " ="):
            return line.split("=", 1)[1]
    raise KeyError(name)


def test_firmware_warnings_are_errors():
    flags = make_var("CFLAGS68")
    for f in ("-m68000", "-Wall", "-Wextra", "-Werror", "-Wconversion", "-fno-store-merging"):
        assert f in flags.split() or f in make_var("WARN").split(), (f, flags)


def test_cppcheck_configuration_bites(tmp_path):
    """The flags of `make cppcheck` report a planted out-of-bounds write."""
    bad = tmp_path / "bad.c"
    bad.write_text("#include <stdint.h>\nstatic uint8_t buf[4];\n"
                   "void f(void);\nvoid f(void) { for (int i = 0; i <= 4; i++) buf[i] = 0; }\n")
    p = subprocess.run(["cppcheck", "-q", "--enable=warning,style,performance,portability", "--std=c11",
                        "--error-exitcode=1", str(bad)], capture_output=True, text=True)
    assert p.returncode == 1 and "arrayIndexOutOfBounds" in p.stderr + p.stdout, p.stderr
