"""The emulator reports what a real card would not survive, never ignores it."""

import pytest

from conftest import SIM, sim
from mac4 import crafted


@pytest.mark.parametrize("code,pattern", [
    ("33C000F80000", r"^fault unmapped write16 at \$F80000 pc=\$100406$"),
    ("303900F80002", r"^fault unmapped read16 at \$F80002 pc=\$100406$"),
    ("33C000100000", r"^fault write to EPROM at \$100000 pc=\$100406$"),
    ("303900100001", r"^fault exception 3 \(address error\)"),
    ("4AFC", r"^fault illegal opcode \$4AFC pc=\$100406$"),
    ("13C000F00000", r"^fault byte write to word register at \$F00000"),
])
def test_faults_are_reported_with_pc(tmp_path, code, pattern):
    r = sim("run 5\n", img=crafted(tmp_path, code))
    assert r.rc == 3, r.out
    assert r.grep(pattern), r.out


def test_allow_faults_exit_code(tmp_path):
    r = sim("run 5\n", img=crafted(tmp_path, "4AFC"), args=["--allow-faults"])
    assert r.rc == 0 and r.faults()


def test_double_bus_fault_halts_and_is_reported(tmp_path):
    # SSP odd: the address error's own stack frame faults again
    r = sim("run 5\n", img=crafted(tmp_path, "2E7C00003001" + "303900100001"))
    assert r.grep(r"^fault CPU halted \(double bus fault\)"), r.out


def test_help_and_bad_usage():
    import subprocess
    h = subprocess.run([SIM, "--help"], capture_output=True, text=True)
    assert h.returncode == 0 and "--card" in h.stdout and "--script" in h.stdout
    b = subprocess.run([SIM, "--card", "xyz"], capture_output=True, text=True)
    assert b.returncode == 1
    r = sim("frobnicate 1\n")
    assert r.rc == 1 and "unknown command" in r.stderr


def test_script_peek_poke_round_trip():
    r = sim("poke32 0x5000 0x12345678\npeek32 0x5000\npeek16 0x5002\npeek8 0x5001\n")
    assert r.peek(0x5000) == 0x12345678
    assert r.grep(r"^peek16 0x5002 0x5678$") and r.grep(r"^peek8 0x5001 0x34$")
