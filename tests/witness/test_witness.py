"""The qemu-m68k witness (docs/hardening.md): the firmware's fixed-point
kernels built for the host (ASan+UBSan) and for the 68000 (freestanding,
-m68000, run under qemu-m68k -cpu m68000, an emulator independent of
Musashi) print their results for the same input vectors; they must agree
byte for byte.  One test per kernel of tests/witness/kernels.txt; a kernel
whose firmware source does not exist yet is skipped with the reason.

Built by `make witness-bins` (make witness / make test build and run this)."""
import os
import shutil
import subprocess

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
WB = os.path.join(ROOT, "build", "witness")
QEMU = os.environ.get("QEMU_M68K", "qemu-m68k")


def kernels():
    out = []
    for line in open(os.path.join(HERE, "kernels.txt")):
        if line.strip() and not line.startswith("#"):
            name, src, *what = line.split()
            out.append((name, src, " ".join(what)))
    return out


KERNELS = kernels()


def sections(text):
    """{kernel: [lines]} of one witness run."""
    out = {}
    for line in text.splitlines():
        out.setdefault(line.split(" ", 1)[0], []).append(line)
    return out


@pytest.fixture(scope="module")
def runs():
    native = os.path.join(WB, "witness-native")
    m68k = os.path.join(WB, "witness-m68k")
    for f in (native, m68k):
        assert os.path.exists(f), "%s missing: run make witness-bins" % f
    assert shutil.which(QEMU), "%s not found (Debian package qemu-user; tools/bootstrap.sh installs it)" % QEMU
    n = subprocess.run([native], capture_output=True, text=True, timeout=300)
    assert n.returncode == 0, n.stderr
    m = subprocess.run([QEMU, "-cpu", "m68000", m68k], capture_output=True, text=True, timeout=300)
    assert m.returncode == 0, "qemu-m68k -cpu m68000: exit %d %s" % (m.returncode, m.stderr)
    assert n.stdout.endswith("end\n") and m.stdout.endswith("end\n"), "a witness run stopped early"
    return sections(n.stdout), sections(m.stdout)


@pytest.mark.parametrize("name,src,what", KERNELS, ids=[k[0] for k in KERNELS])
def test_kernel_bit_identical_on_qemu_m68k(runs, name, src, what):
    if not os.path.exists(os.path.join(ROOT, src)):
        pytest.skip("%s does not exist yet: kernel '%s' (%s) not built" % (src, name, what))
    native, m68k = runs
    assert name in native, "kernel %s printed nothing natively (not built? see tests/witness/witness.mk)" % name
    a, b = native[name], m68k.get(name, [])
    assert len(a) >= 10, "kernel %s printed only %d lines" % (name, len(a))
    for i, (x, y) in enumerate(zip(a, b)):
        assert x == y, "%s: first difference at its line %d:\n  host:  %s\n  68000: %s" % (name, i + 1, x, y)
    assert len(a) == len(b), "%s: %d lines on the host, %d on the 68000" % (name, len(a), len(b))


def test_the_68000_side_is_68000_code():
    """The witness binary itself passes the 68000 check: no 68020 code
    (qemu -cpu m68000 would trap it too) and no odd word accesses."""
    p = subprocess.run([os.path.join(ROOT, "tools", "check68000.py"), os.path.join(WB, "witness-m68k")],
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stdout + p.stderr
