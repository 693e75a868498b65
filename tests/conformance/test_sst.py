"""The conformance lane's runner (build/sst, docs/cpu-timing.md) on vectors
altered here: a changed expectation is reported as a mismatch naming the
test, the field, the expected and the seen value, the skip list is what it
says, and a malformed file is an error, not a result."""
import os
import re
import struct
import subprocess

import pytest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
SST = os.path.join(ROOT, "build", "sst")
VECTORS = os.path.join(ROOT, "tests", "conformance", "vectors")


def run(*args):
    p = subprocess.run([SST, "-n", "0", *args], capture_output=True, text=True, timeout=120)
    return p.returncode, p.stdout, p.stderr


def records(path):
    data = open(path, "rb").read()
    magic, count = struct.unpack_from("<II", data, 0)
    off, out = 8, []
    for _ in range(count):
        size, = struct.unpack_from("<I", data, off)
        out.append(bytearray(data[off:off + size]))
        off += size
    return out


def write(path, recs):
    with open(path, "wb") as f:
        f.write(struct.pack("<II", 0x1A3F5D71, len(recs)))
        for r in recs:
            f.write(r)


def block_offsets(rec):
    """Offsets of the name, initial state, final state and transactions blocks."""
    off, out = 8, []
    for _ in range(4):
        out.append(off)
        off += struct.unpack_from("<I", rec, off)[0]
    return out


def final_line(out):
    lines = out.strip().splitlines()
    m = re.fullmatch(r"conformance: (\d+) passed, (\d+) failed, (\d+) skipped", lines[-1])
    assert m, lines[-1]
    return tuple(int(x) for x in m.groups())


@pytest.fixture(scope="module", autouse=True)
def built():
    if not os.path.exists(SST):
        pytest.fail("build/sst missing: run make conformance")


def test_subset_passes():
    rc, out, _ = run(VECTORS)
    passed, failed, skipped = final_line(out)
    assert rc == 0 and failed == 0 and passed > 1000
    assert re.search(r"^address error: \d+ tests skipped", out, re.M)


def test_changed_cycles_and_ram_are_mismatches(tmp_path):
    recs = records(os.path.join(VECTORS, "NOP.json.bin"))
    name_off, init_off, final_off, tr_off = block_offsets(recs[0])
    cycles, = struct.unpack_from("<I", recs[0], tr_off + 8)
    struct.pack_into("<I", recs[0], tr_off + 8, cycles + 2)
    # the final d3 of the second test, one bit off
    _, _, final1, _ = block_offsets(recs[1])
    d3, = struct.unpack_from("<I", recs[1], final1 + 8 + 3 * 4)
    struct.pack_into("<I", recs[1], final1 + 8 + 3 * 4, d3 ^ 0x100)
    write(tmp_path / "NOP.json.bin", recs)
    rc, out, _ = run(str(tmp_path))
    assert rc == 1
    n = len(recs)
    assert final_line(out) == (n - 2, 2, 0)
    assert re.search(r'MISMATCH NOP "000 NOP 4e71": cycles expected %d seen %d' % (cycles + 2, cycles), out)
    assert re.search(r'MISMATCH NOP "[0-9]+ NOP 4e71": d3 expected \$%08X seen \$%08X' % (d3 ^ 0x100, d3), out)
    assert re.search(r"^NOP .* 2 failed: d3 1, cycles 1$", out, re.M)


def test_changed_bus_cycles_are_mismatches(tmp_path):
    """One more read in the reference's transaction log than the core makes."""
    recs = records(os.path.join(VECTORS, "RTS.json.bin"))
    rec = recs[0]
    _, _, _, tr_off = block_offsets(rec)
    n, = struct.unpack_from("<I", rec, tr_off + 12)
    entry = bytes([2]) + struct.pack("<I", 4) + struct.pack("<5I", 6, 0x100, 0, 1, 1)
    rec[tr_off + 12:tr_off + 16] = struct.pack("<I", n + 1)
    rec.extend(entry)
    struct.pack_into("<I", rec, 0, len(rec))
    struct.pack_into("<I", rec, tr_off, struct.unpack_from("<I", rec, tr_off)[0] + len(entry))
    write(tmp_path / "RTS.json.bin", [rec])
    rc, out, _ = run(str(tmp_path))
    assert rc == 1 and final_line(out) == (0, 1, 0)
    assert re.search(r'MISMATCH RTS "000 RTS 4e75": reads expected (\d+) seen (\d+)', out)


def test_skip_list(tmp_path):
    for f in ("TAS.json.bin", "TRAPV.json.bin", "MOVE.w.json.bin"):
        write(tmp_path / f, records(os.path.join(VECTORS, f)))
    rc, out, _ = run(str(tmp_path))
    tas = len(records(os.path.join(VECTORS, "TAS.json.bin")))
    trapv = len(records(os.path.join(VECTORS, "TRAPV.json.bin")))
    m = re.search(r"^address error: (\d+) tests skipped .*: MOVE\.w (\d+)$", out, re.M)
    assert m and m.group(1) == m.group(2) and int(m.group(1)) >= 1
    passed, failed, skipped = final_line(out)
    assert rc == 0 and failed == 0 and skipped == tas + trapv + int(m.group(1))
    assert re.search(r"^TAS +0 run, +0 failed, %d skipped$" % tas, out, re.M)


@pytest.mark.parametrize("cut", [3, 8, 200])
def test_malformed_file_is_an_error(tmp_path, cut):
    data = open(os.path.join(VECTORS, "NOP.json.bin"), "rb").read()
    (tmp_path / "NOP.json.bin").write_bytes(data[:cut])
    rc, out, err = run(str(tmp_path))
    assert rc == 2
    assert "malformed vector file" in err or "too short" in err or "magic" in err
    assert "conformance:" not in out


def test_empty_folder_is_an_error(tmp_path):
    rc, out, err = run(str(tmp_path))
    assert rc == 2 and "no *.json.bin vector files" in err
