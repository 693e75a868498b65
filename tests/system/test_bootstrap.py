"""Every external tool the build, the tests and the docs use comes from a
package in tools/deps/apt.txt or tools/deps/python.txt, the lists
tools/bootstrap.sh installs from: a tool used anywhere in the tree but
provided by no listed package fails here, so a clean machine (CI) cannot
lack it after the bootstrap."""
import ast
import os
import re
import shutil
import subprocess
import sys

import pytest

from conftest import ROOT

# tool -> the Debian package that provides it ("essential": on every Debian
# system, dpkg and apt themselves)
TOOLS = {
    "m68k-linux-gnu-gcc": "gcc-m68k-linux-gnu",
    "m68k-linux-gnu-objcopy": "binutils-m68k-linux-gnu",
    "m68k-linux-gnu-objdump": "binutils-m68k-linux-gnu",
    "m68k-linux-gnu-nm": "binutils-m68k-linux-gnu",
    "m68k-linux-gnu-size": "binutils-m68k-linux-gnu",
    "m68k-linux-gnu-as": "binutils-m68k-linux-gnu",
    "cc": "gcc",
    "gcc": "gcc",
    "objcopy": "binutils",
    "make": "make",
    "git": "git",
    "python3": "python3",
    "pip": "python3-pip",
    "pkg-config": "pkg-config",
    "qemu-m68k": "qemu-user",
    "gdb-multiarch": "gdb-multiarch",
    "cppcheck": "cppcheck",
    "clang": "clang",
    "llvm-cov": "llvm",
    "llvm-profdata": "llvm",
    "srec_cat": "srecord",
    "srec_info": "srecord",
    "gtkwave": "gtkwave",
    "vcd2fst": "gtkwave",
    "sigrok-cli": "sigrok-cli",
    "chromium": "chromium",
    "chromedriver": "chromium-driver",
    "valgrind": "valgrind",
    "dpkg-query": "essential",
    "apt-get": "essential",
}
# Tools a test or a document might reach for that no list provides today:
# using one must add it to TOOLS and its package to apt.txt first.
UNLISTED = ["socat", "xxd", "gnuplot", "iverilog", "pulseview", "picocom", "minicom",
            "shellcheck", "srec_cmp", "qemu-system-m68k", "m68k-elf-gcc", "vasm", "lcov", "gcovr",
            "afl-fuzz", "hexdump", "ncat", "jq", "xvfb-run", "firefox", "geckodriver"]
# Named in the docs as one choice among any the user has; nothing of the
# project runs them, so the bootstrap need not install them.
OPTIONAL = {
    "picocom": "docs/serial.md: an example of any serial terminal program on the pty",
    "socat": "docs/serial.md: an example of a TCP client for --serial-tcp",
}
# Python imports -> the PyPI project pinned in python.txt
IMPORTS = {"pytest": "pytest", "matplotlib": "matplotlib", "numpy": "numpy", "serial": "pyserial", "vcd": "pyvcd",
           "selenium": "selenium", "setuptools": "setuptools", "wheel": "wheel"}


def listed(name):
    out = set()
    for line in open(os.path.join(ROOT, "tools", "deps", name)):
        line = line.split("#")[0].strip()
        if line:
            out.add(line.split("==")[0].lower())
    return out


APT, PYPI = listed("apt.txt"), listed("python.txt")


def scanned_files():
    files = subprocess.run(["git", "-C", ROOT, "ls-files"], capture_output=True, text=True,
                           check=True).stdout.split()
    keep = []
    for f in files:
        if f.startswith("tests/conformance/vectors/") or f.startswith("tests/fuzz/corpus/"):
            continue
        if (f in ("Makefile", "README.md", ".ci/run") or f.endswith((".mk", ".py", ".sh"))
                or (f.startswith("docs/") and f.endswith(".md")) or f.startswith("tools/")):
            keep.append(f)
    return keep


def uses():
    """tool -> files of the tree that name it as a command"""
    found = {}
    texts = {f: open(os.path.join(ROOT, f), errors="replace").read() for f in scanned_files()}
    names = sorted(list(TOOLS) + UNLISTED + list(OPTIONAL), key=len, reverse=True)
    rx = re.compile(r"(?<![\w/.$\\-])(%s)(?![\w-])" % "|".join(map(re.escape, names)))
    for f, text in texts.items():
        if f == "tests/system/test_bootstrap.py":
            continue
        for tool in set(rx.findall(text)):
            found.setdefault(tool, []).append(f)
    # commands Python starts itself: the first element of a literal argv, shutil.which
    for f, text in texts.items():
        if not f.endswith(".py") or f == "tests/system/test_bootstrap.py":
            continue
        for m in re.finditer(r'(?:subprocess\.\w+\(\s*\[\s*|shutil\.which\(\s*)"([\w.+-]+)"', text):
            found.setdefault(m.group(1), []).append(f)
    return found


def test_every_tool_in_the_table_comes_from_a_listed_package():
    bad = {t: p for t, p in TOOLS.items() if p != "essential" and p not in APT}
    assert not bad, "packages missing from tools/deps/apt.txt: %s" % bad


def test_every_tool_the_tree_uses_is_in_the_table():
    found = uses()
    missing = {t: fs[:3] for t, fs in found.items() if t not in TOOLS
               and not (t in OPTIONAL and set(fs) <= {OPTIONAL[t].split(":")[0], "host/mac4card/transport.py"})}
    assert not missing, ("tools used but provided by no package of tools/deps/apt.txt "
                         "(add them to TOOLS here and their package to the list): %s" % missing)
    # the scan sees the tools named in the brief of the bootstrap
    for t in ("gdb-multiarch", "srec_cat", "sigrok-cli", "vcd2fst", "chromium", "qemu-m68k", "cppcheck"):
        assert t in found, t


def test_every_python_import_comes_from_a_listed_project():
    own = {"conftest", "mac4", "mac4card", "diffrun", "fuzzlib"}
    for f in scanned_files():
        if f.endswith(".py"):
            own.add(os.path.splitext(os.path.basename(f))[0])
    bad = {}
    for f in scanned_files():
        if not f.endswith(".py"):
            continue
        tree = ast.parse(open(os.path.join(ROOT, f)).read(), f)
        for node in ast.walk(tree):
            names = []
            if isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
                names = [node.module]
            for n in names:
                top = n.split(".")[0]
                if top in sys.stdlib_module_names or top in own:
                    continue
                if IMPORTS.get(top, "").lower() not in PYPI:
                    bad.setdefault(top, []).append(f)
    assert not bad, "imports from no project pinned in tools/deps/python.txt: %s" % bad


@pytest.mark.parametrize("tool", sorted(t for t, p in TOOLS.items() if p != "essential"))
def test_the_package_provides_the_tool(tool):
    """Where the tool is installed from a Debian package, it is the package the
    table names (a wrong table entry would let a missing package pass)."""
    path = shutil.which(tool)
    if path is None:
        pytest.fail("%s is not installed: run tools/bootstrap.sh (package %s)" % (tool, TOOLS[tool]))
    real = os.path.realpath(path)
    owners = set(OWNERS().get(path, ())) | set(OWNERS().get(real, ()))
    if not owners:
        pytest.skip("%s (%s) is not from a Debian package on this machine" % (tool, real))
    # the package itself, or what it installs (cc: gcc -> gcc-12; pkg-config -> pkgconf)
    assert owners & depends(TOOLS[tool], 2), "%s comes from %s, not from %s" % (tool, owners, TOOLS[tool])


_owners = {}


def OWNERS():
    """path -> Debian packages, for every tool of the table: one dpkg-query"""
    if not _owners:
        paths = set()
        for t in TOOLS:
            p = shutil.which(t)
            if p:
                paths |= {p, os.path.realpath(p)}
        r = subprocess.run(["dpkg-query", "-S"] + sorted(paths), capture_output=True, text=True)
        for line in r.stdout.splitlines():
            pkgs, _, path = line.partition(": ")
            _owners[path.strip()] = {o.strip().split(":")[0] for o in pkgs.split(",")}
        _owners.setdefault("", set())
    return _owners


def depends(pkg, levels):
    out = {pkg}
    if levels == 0:
        return out
    r = subprocess.run(["dpkg-query", "-W", "-f=${Depends}", pkg], capture_output=True, text=True)
    for alt in r.stdout.split(","):
        name = alt.strip().split(" ")[0].split(":")[0]
        if name:
            out |= depends(name, levels - 1)
    return out
