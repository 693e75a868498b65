"""The EPROM programmer files of tools/mkeprom.py checked with an
independent tool, srecord (srec_info, srec_cat; Debian package srecord,
installed by tools/bootstrap.sh): Intel HEX of the image and of each chip,
an S-record per chip, device offsets from 0, the per-chip 16-bit sums the
report gives, and the 27C512 recipe of the .chips.txt."""
import os
import re
import shutil
import subprocess

import pytest

from conftest import CARDS, image

SREC_CAT, SREC_INFO = shutil.which("srec_cat"), shutil.which("srec_info")


@pytest.fixture(scope="module", autouse=True)
def srecord():
    assert SREC_CAT and SREC_INFO, "srecord is missing: tools/bootstrap.sh installs it"


def files(card):
    base = image(card)[:-4]
    return {k: base + k for k in (".bin", ".even.bin", ".odd.bin", ".hex", ".even.hex",
                                  ".odd.hex", ".srec", ".even.srec", ".odd.srec", ".chips.txt",
                                  ".size.txt")}


def fmt(path):
    return [path, "-intel"] if path.endswith(".hex") else [path]


def info(path):
    r = subprocess.run([SREC_INFO] + fmt(path), capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    return r.stdout


def cat_binary(tmp_path, *args):
    out = tmp_path / "out.bin"
    r = subprocess.run([SREC_CAT] + list(args) + ["-o", str(out), "-binary"],
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    return out.read_bytes()


def srecord_sum16(tmp_path, path, size):
    """srec_cat's own additive checksum of the file's bytes, 16 bits big-endian."""
    return int.from_bytes(cat_binary(tmp_path, *fmt(path), "-Checksum_Positive_Big_Endian",
                                     hex(size), "2", "1", "-crop", hex(size), hex(size + 2),
                                     "-offset", hex(-size)), "big")


@pytest.mark.parametrize("card", CARDS)
def test_every_file_reads_back_as_the_image(card, tmp_path):
    f = files(card)
    img = open(f[".bin"], "rb").read()
    halves = {"even": open(f[".even.bin"], "rb").read(), "odd": open(f[".odd.bin"], "rb").read()}
    for ext in (".hex", ".srec"):
        assert re.search(r"Data:\s+0000 - FFFF", info(f[ext])), info(f[ext])
        assert cat_binary(tmp_path, *fmt(f[ext])) == img
    for half, data in halves.items():
        for ext in (".hex", ".srec"):
            p = f["." + half + ext]
            assert re.search(r"Data:\s+0000 - 7FFF", info(p)), info(p)   # device offsets from 0
            assert cat_binary(tmp_path, *fmt(p)) == data
    # the two chips interleaved by srecord give the image: even = D8-D15
    assert cat_binary(tmp_path, *fmt(f[".even.hex"]), "-unsplit", "2", "0",
                      *fmt(f[".odd.srec"]), "-unsplit", "2", "1") == img


@pytest.mark.parametrize("card", CARDS)
def test_chip_sums_and_type_said_plainly(card, tmp_path):
    f = files(card)
    text = open(f[".chips.txt"]).read()
    assert "Two 27C256 EPROMs of 32 KiB x 8" in text and "27C512" in text
    sums = dict(re.findall(r"(even|odd) bytes.*\n\s+16-bit sum \$([0-9A-F]{4})", text))
    for half in ("even", "odd"):
        assert int(sums[half], 16) == srecord_sum16(tmp_path, f["." + half + ".hex"], 0x8000)
    size = open(f[".size.txt"]).read()
    assert "even (D8-D15) sum $%s, odd (D0-D7) sum $%s" % (sums["even"], sums["odd"]) in size
    assert "27C256" in size


def test_the_27c512_recipe_works(tmp_path):
    f = files("inc")
    text = open(f[".chips.txt"]).read()
    cmd = re.search(r"^\s+(srec_cat .*?)\n\s*\((the 16-bit sum.*?)\)", text, re.S | re.M)
    assert cmd, text
    argv = cmd.group(1).replace("\\\n", " ").split()
    argv = [os.path.join(os.path.dirname(f[".bin"]), a) if a.startswith("mac4-") else a
            for a in argv]
    argv[argv.index("-o") + 1] = str(tmp_path / "even512.hex")
    r = subprocess.run(argv, capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    chip = cat_binary(tmp_path, str(tmp_path / "even512.hex"), "-intel")
    even = open(f[".even.bin"], "rb").read()
    assert chip == even + even
    want = re.search(r"\$([0-9A-F]{4}) even", cmd.group(2)).group(1)
    assert int(want, 16) == srecord_sum16(tmp_path, str(tmp_path / "even512.hex"), 0x10000)
