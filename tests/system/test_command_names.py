"""tools/gen_commands.c refuses a commands.def in which one mnemonic names
two commands (a parameter's W../R.. name, a mode, an alias): built here
against a copy of the table with one duplicate added."""
import os
import shutil
import subprocess

from conftest import ROOT


def build_and_run(tmp_path, extra):
    d = tmp_path / "fw"
    shutil.copytree(os.path.join(ROOT, "firmware"), d)
    with open(d / "commands.def") as f:
        text = f.read()
    text = text.replace("ALIAS(WED, WAA)", "ALIAS(WED, WAA)\n" + extra)
    (d / "commands.def").write_text(text)
    exe = tmp_path / "gen"
    subprocess.run(["cc", "-std=gnu11", "-I", str(d), "-I", os.path.join(ROOT, "hal"),
                    os.path.join(ROOT, "tools", "gen_commands.c"), "-o", str(exe)], check=True)
    return subprocess.run([str(exe)], capture_output=True, text=True)


def test_the_table_as_it_is_has_unique_mnemonics(tmp_path):
    r = build_and_run(tmp_path, "")
    assert r.returncode == 0 and not r.stderr, r.stderr


def test_a_duplicate_mnemonic_is_an_error(tmp_path):
    r = build_and_run(tmp_path, "ALIAS(CDEF, WAP)")
    assert r.returncode != 0
    assert "CDEF defined twice" in r.stderr
