"""tools/musashi-patch.sh, the build step that makes the patched Musashi
(harness/musashi-patches/README.md): the series applies in order onto the
pristine fetch, a patch that does not apply stops it with the patch's name,
the stamp follows the series, and the tree the build uses is the series'."""
import os
import shutil
import subprocess

import pytest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
ORIG = os.path.join(ROOT, "build", "deps", "musashi-orig")
SCRIPT = os.path.join(ROOT, "tools", "musashi-patch.sh")
SERIES = os.path.join(ROOT, "harness", "musashi-patches")


def apply(dest, series):
    return subprocess.run([SCRIPT, ORIG, str(dest), str(series)], capture_output=True, text=True, timeout=120)


@pytest.fixture(scope="module", autouse=True)
def fetched():
    if not os.path.exists(os.path.join(ORIG, ".stamp")):
        pytest.fail("build/deps/musashi-orig missing: run make deps")


def pristine():
    return open(os.path.join(ORIG, "readme.txt"), encoding="latin-1").read().splitlines(True)


def one_line_patch(series, name, old, new, text=None):
    """A patch of readme.txt's first line with old in it (of text, the
    readme as the patches before leave it); the readme it makes."""
    text = text or pristine()
    i = next(n for n, l in enumerate(text) if old in l)
    lo, hi = max(0, i - 3), min(len(text), i + 4)
    body = "".join(" " + l for l in text[lo:i]) + "-" + text[i] + "+" + text[i].replace(old, new) + \
        "".join(" " + l for l in text[i + 1:hi])
    hdr = "--- a/readme.txt\n+++ b/readme.txt\n@@ -%d,%d +%d,%d @@\n" % (lo + 1, hi - lo, lo + 1, hi - lo)
    (series / name).write_text(hdr + body, encoding="latin-1")
    return text[:i] + [text[i].replace(old, new)] + text[i + 1:]


def test_series_applies_and_stamp_names_it(tmp_path):
    series = tmp_path / "series"
    series.mkdir()
    after = one_line_patch(series, "0001-a.patch", "MUSASHI", "MUSASHI-A")
    one_line_patch(series, "0002-b.patch", "MUSASHI-A", "MUSASHI-B", after)
    dest = tmp_path / "mus"
    p = apply(dest, series)
    assert p.returncode == 0, p.stderr
    assert p.stdout.index("0001-a.patch") < p.stdout.index("0002-b.patch")
    assert "MUSASHI-B" in (dest / "readme.txt").read_text(encoding="latin-1")
    stamp = (dest / ".stamp").read_text()
    assert "0001-a.patch" in stamp and "0002-b.patch" in stamp
    # the same series again: nothing rebuilt; a patch removed: rebuilt from the pristine tree
    (dest / "marker").write_text("x")
    assert apply(dest, series).returncode == 0 and (dest / "marker").exists()
    (series / "0002-b.patch").unlink()
    assert apply(dest, series).returncode == 0
    assert not (dest / "marker").exists()
    text = (dest / "readme.txt").read_text(encoding="latin-1")
    assert "MUSASHI-A" in text and "MUSASHI-B" not in text


def test_patch_that_does_not_apply_stops_the_build(tmp_path):
    series = tmp_path / "series"
    series.mkdir()
    one_line_patch(series, "0001-a.patch", "MUSASHI", "MUSASHI-A")
    one_line_patch(series, "0002-twice.patch", "MUSASHI", "MUSASHI-A")   # context gone after 0001
    dest = tmp_path / "mus"
    p = apply(dest, series)
    assert p.returncode != 0
    assert "0002-twice.patch does not apply" in p.stderr
    assert not dest.exists() and not (tmp_path / "mus.tmp").exists()


def test_build_tree_is_the_series():
    """build/deps/musashi is the pristine tree plus exactly harness/musashi-patches."""
    stamp = open(os.path.join(ROOT, "build", "deps", "musashi", ".stamp")).read()
    names = sorted(n for n in os.listdir(SERIES) if n.endswith(".patch"))
    assert names, "the series is empty"
    for n in names:
        assert n in stamp
    patched = open(os.path.join(ROOT, "build", "deps", "musashi", "m68kcpu.h")).read()
    assert "M68K_BUS_EXTRA_CALLBACK" in patched
    assert "M68K_BUS_EXTRA_CALLBACK" not in open(os.path.join(ORIG, "m68kcpu.h")).read()
