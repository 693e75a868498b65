"""The board description board/mac4.toml is the one source of the memory
map: the generated header, the emulator's bus table and the Python map are
what tools/genboard.py makes of it, C and Python agree on every value, and
a description that does not hold together is refused in one line."""
import os
import re
import shutil
import subprocess
import sys

import pytest

from conftest import ROOT

GEN = [sys.executable, os.path.join(ROOT, "tools", "genboard.py")]
BOARD = os.path.join(ROOT, "board", "mac4.toml")
sys.path.insert(0, os.path.join(ROOT, "host"))
from mac4card import board  # noqa: E402


def test_generated_files_are_the_descriptions():
    r = subprocess.run(GEN + ["--check", BOARD], capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    for rel in ("hal/mac4_map.h", "harness/bus_map.h", "host/mac4card/board.py"):
        assert "GENERATED from board/mac4.toml" in open(os.path.join(ROOT, rel)).read()


def test_check_notices_a_hand_edit(tmp_path):
    out = tmp_path / "tree"
    for rel in ("hal", "harness", "host/mac4card"):
        (out / rel).mkdir(parents=True)
    assert subprocess.run(GEN + ["--out", str(out), BOARD], capture_output=True,
                          timeout=60).returncode == 0
    h = out / "hal" / "mac4_map.h"
    h.write_text(h.read_text().replace("(IO_BASE + 0x200)", "(IO_BASE + 0x280)"))
    r = subprocess.run(GEN + ["--check", "--out", str(out), BOARD], capture_output=True,
                       text=True, timeout=60)
    assert r.returncode == 1 and "hal/mac4_map.h not what board/mac4.toml gives" in r.stderr


def test_c_and_python_agree_on_every_value(tmp_path):
    names = [n for n, v in vars(board).items() if n.isupper() and isinstance(v, int)]
    assert len(names) > 150
    prog = tmp_path / "dump.c"
    prog.write_text('#include <stdio.h>\n#include "mac4_map.h"\nint main(void) {\n' +
                    "".join('    printf("%s %%lld\\n", (long long)(%s));\n' % (n, n)
                            for n in names) + "    return 0;\n}\n")
    exe = tmp_path / "dump"
    r = subprocess.run(["cc", "-I", os.path.join(ROOT, "hal"), str(prog), "-o", str(exe)],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    out = subprocess.run([str(exe)], capture_output=True, text=True, timeout=60).stdout
    c = {l.split()[0]: int(l.split()[1]) for l in out.splitlines()}
    assert c == {n: getattr(board, n) for n in names}
    assert board.DP_AXIS_DATA(2) == 0x3800 and board.AX_REG(1, board.AX_CTRL) == 0xF0110A


def test_the_host_side_is_the_manuals_table_3_1():
    """The tests take the DPRAM map from board.py; here it is held against the
    manual once, by its printed numbers (table 3.1, 3.2, diagram 3.2, 7.4)."""
    table_3_1 = {0: 0x3000, 1: 0x3400, 2: 0x3800, 3: 0x3C00}
    for n, at in table_3_1.items():
        assert board.DP_AXIS_DATA(n) == at
        assert board.DP_EXT_FLAG(n) == at + 0x308 and board.DP_EXT_POS(n) == at + 0x30A
    assert (board.DP_CARD_DATA, board.DP_STOP_BITS, board.DP_CMD_QUEUE, board.DP_RSP_QUEUE) == (
        0x4000, 0x4600, 0x4700, 0x4800)
    assert board.DP_HOST_END == 0xFFEE
    assert (board.Q_HEADER_SIZE, board.Q_WIDTH, board.Q_NEL) == (0x18, 10, 10)
    assert (board.QH_FRONT, board.QH_REAR) == (4, 8)             # write index, read index
    assert board.PERIOD_US == {"inc": 2500, "ssi": 2500, "stp": 8000}
    assert board.MAC4_CPU_HZ == 16000000 and board.UART_BAUD == 4800
    assert board.CARD_TYPE == {"inc": 0, "ssi": 1, "stp": 2}     # VER, table 6.1


def test_bus_table_is_the_memory_map():
    rows = [l for l in open(os.path.join(ROOT, "harness", "bus_map.h")) if l.startswith("{")]
    assert [re.search(r'"([^"]+)"', l).group(1) for l in rows] == [m[0] for m in board.MEMORY]
    bus = open(os.path.join(ROOT, "harness", "bus.c")).read()
    assert '#include "bus_map.h"' in bus


BROKEN = [
    ("overlap", "io_offset = 0x200\n", "io_offset = 0x108\n", "overlap"),
    ("twice", 'name = "DPA_VEL"', 'name = "DPA_POS"', "DPA_POS is defined twice"),
    ("outside", '{reg = "UART_CTRL", at = 0x4,', '{reg = "UART_CTRL", at = 0x40,',
     "not an even offset inside the device"),
    ("beyond", "base = 0xE00000", "base = 0xFF8000", "beyond the 68000's 24 address lines"),
    ("syntax", "[board]", "[board", "mac4.toml"),
    ("value", 'value = "MAC4_U(0x4600)"', 'value = "MAC4_U(0x4600"', "does not evaluate"),
    ("card", 'period_us = "SERVO_PERIOD_US_STP"', 'period_us = "SERVO_PERIOD_STP"', "cards.stp does not evaluate"),
    ("card-key", 'stp = {type', 'stp = {typ', "a card is {type = NAME, period_us = NAME}"),
]


@pytest.mark.parametrize("what,old,new,msg", BROKEN, ids=[b[0] for b in BROKEN])
def test_an_inconsistent_description_is_refused(tmp_path, what, old, new, msg):
    text = open(BOARD).read()
    assert old in text
    f = tmp_path / "mac4.toml"
    f.write_text(text.replace(old, new, 1))
    out = tmp_path / "tree"
    shutil.copytree(ROOT + "/hal", out / "hal")
    r = subprocess.run(GEN + ["--out", str(out), str(f)], capture_output=True, text=True,
                       timeout=60)
    assert r.returncode == 1 and "Traceback" not in r.stderr, r.stderr
    assert r.stderr.startswith("genboard: ") and msg in r.stderr and \
        len(r.stderr.strip().splitlines()) == 1, r.stderr
