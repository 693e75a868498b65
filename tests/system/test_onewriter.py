"""`make arch-check`, part 2: each part of axis_t is written by its declared
writers, of one module unless tools/onewriter.allow explains it, each status
bit by the files status.def names, the parameters by the parameter store
alone (tools/onewriter.py), and the check fails when it should."""
import os
import subprocess
import sys

from conftest import ROOT

sys.path.insert(0, os.path.join(ROOT, "tools"))
import onewriter  # noqa: E402

# the fixture paths spelled in parts, so that this file cites none of the tree
F = "firmware" + "/"
TOOL = [sys.executable, os.path.join(ROOT, "tools", "onewriter.py")]

CARD_H = """typedef struct {
    /* writers: a.c */
    struct {
        uint32_t ustat;
        int32_t pos, meas[2];
    };
    /* writers: b.c b.h */
    int32_t vel;
} axis_t;
"""
STATUS_H = "#define US_ERRORS (UB(SYN_F) | UB(DR_F))\n"
STATUS_DEF = 'USTAT_BY(SYN_F, "a.c", "a.c")\nUSTAT_BY(DR_F, "a.c", "a.c")\n'
A_C = """void f(unsigned n, axis_t *x)
{
    x->pos = 1;                     /* b.c's writes in a comment: x->vel = 2; */
    axes[n].meas[1] += 3;
    axis_error(n, UB(SYN_F), 1);
    x->ustat &= ~US_ERRORS;
    if (x->vel == 0 && x->pos != 2)
        x->ustat |= UB(DR_F);
}
"""


def tree(tmp_path, files):
    (tmp_path / "firmware").mkdir(parents=True)
    (tmp_path / "tools").mkdir()
    base = {"card.h": CARD_H, "status.h": STATUS_H, "status.def": STATUS_DEF, "a.c": A_C,
            "b.c": "void g(axis_t *y) { y->vel++; }\n",
            "b.h": "static inline void h(axis_t *z) { z->vel = 0; }\n",
            "params.c": "void params_reset(void) { par_a[0][0] = 0; }\n"}
    base.update(files)
    for name, text in base.items():
        if text is not None:
            (tmp_path / ("tools" if name.endswith(".allow") else "firmware") / name).write_text(text)
    return str(tmp_path)


def test_the_tree_keeps_the_rule():
    r = subprocess.run(TOOL, capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stdout + r.stderr


def test_a_fixture_tree_that_keeps_it_passes(tmp_path):
    assert onewriter.check(tree(tmp_path, {})) == []


def test_a_wrong_writer_is_found(tmp_path):
    root = tree(tmp_path, {"b.c": "void g(axis_t *y) { y->vel++; y->pos = 0; ++axis_at[1]->meas[0]; }\n",
                           "c.c": "void h(void) { int32_t *p = &axes[0].vel; *p = 0; }\n"})
    assert onewriter.check(root) == [
        F + "b.c:1: writes meas, whose writers are " + F + "a.c",
        F + "b.c:1: writes pos, whose writers are " + F + "a.c",
        F + "c.c:1: writes vel, whose writers are " + F + "b.c " + F + "b.h"]
    r = subprocess.run(TOOL + ["--root", root], capture_output=True, text=True, timeout=60)
    assert r.returncode == 1 and "b.c:1: writes pos" in r.stdout


def test_the_allowlist_admits_a_write_and_goes_stale(tmp_path):
    root = tree(tmp_path, {"b.c": "void g(axis_t *y) { y->vel++; y->pos = 0; }\n",
                           "onewriter.allow": "pos " + F + "b.c   # why\nvel " + F + "a.c  # why\n"
                                              "part pos  # b.c's write on purpose: a second writer module\n"})
    assert onewriter.check(root) == ["tools/onewriter.allow:2: vel " + F + "a.c matches no write (stale)"]


def test_a_status_bit_out_of_its_writers_is_found(tmp_path):
    root = tree(tmp_path, {"b.c": "void g(axis_t *y) { y->vel++; axis_error(0, UB(DR_F), 2); }\n"
                                  "void k(axis_t *y) { uint32_t s = y->ustat & ~UB(SYN_F); y->ustat = s; }\n",
                           "status.def": STATUS_DEF + 'USTAT_BY(INIT, "a.c", "")\n'})
    assert onewriter.check(root) == [
        F + "b.c:2: writes ustat, whose writers are " + F + "a.c",
        F + "b.c:1: sets UB(DR_F), which status.def's USTAT_BY does not give it",
        F + "b.c:2: sets UB(SYN_F), which status.def's USTAT_BY does not give it",
        F + "b.c:2: clears UB(SYN_F), which status.def's USTAT_BY does not give it",
        "firmware/status.def: USTAT_BY(INIT): " + F + "a.c sets it nowhere (stale)"]


def test_a_parameter_written_outside_the_store_is_found(tmp_path):
    root = tree(tmp_path, {"c.c": "void h(unsigned n) { int32_t v = par_a[1][n]; par_w[1][n] = v; par_gen[n]++; }\n"})
    assert onewriter.check(root) == [
        F + "c.c:1: writes par_w outside the parameter store (params.c)",
        F + "c.c:1: writes par_gen outside the parameter store (params.c)"]


def test_a_tree_without_card_h_is_a_setup_error(tmp_path):
    r = subprocess.run(TOOL + ["--root", str(tmp_path)], capture_output=True, text=True, timeout=60)
    assert r.returncode == 2 and "no firmware/card.h" in r.stderr


def test_a_writer_that_writes_none_of_its_part_is_stale(tmp_path):
    """A file a part's writers: line names, which writes none of the part's
    fields any more (the code moved), fails: the lines stay true."""
    root = tree(tmp_path, {"b.h": "static inline int h(const axis_t *z) { return z->vel; }\n"})
    assert onewriter.check(root) == [
        "firmware/card.h:7: " + F + "b.h is named a writer of the part but writes none of it (stale)"]


def test_a_part_of_two_writer_modules_fails_unless_explained(tmp_path):
    """A .c file and its own header are one module; a part written by two
    modules fails, unless the allowlist gives the reason; the explanation
    of a part with one writer module is stale."""
    card = CARD_H.replace("writers: b.c b.h", "writers: b.c b.h c.c")
    c_c = "void k(axis_t *w) { w->vel = 1; }\n"
    root = tree(tmp_path, {"card.h": card, "c.c": c_c})
    assert onewriter.check(root) == [
        "firmware/card.h:7: part vel has 2 writer modules (b c): one owns it and the others call it, "
        "or tools/onewriter.allow explains it (part vel  # why)"]
    report = []
    root = tree(tmp_path / "x", {"card.h": card, "c.c": c_c,
                                 "onewriter.allow": "part vel  # a hand-over\npart pos  # why\n"})
    assert onewriter.check(root, report=report) == [
        "tools/onewriter.allow:2: part pos has one writer module (stale)"]
    assert report == ["firmware/card.h:2: ustat pos meas: a (a.c)",
                      "firmware/card.h:7: vel: b (b.c b.h), c (c.c)  [explained (tools/onewriter.allow)]"]
    root = tree(tmp_path / "y", {"card.h": card, "c.c": c_c, "onewriter.allow": "part vel\n"})
    r = subprocess.run(TOOL + ["--root", root], capture_output=True, text=True, timeout=60)
    assert r.returncode == 2 and "want part FIELD  # why" in r.stderr


def test_an_address_read_through_a_const_pointer_is_no_writer(tmp_path):
    root = tree(tmp_path, {"c.c": "void h(void) { show(&axes[0].vel); }\n",
                           "onewriter.allow": "vel " + F + "c.c read  # show takes a const pointer\n"})
    report = []
    assert onewriter.check(root, report=report) == []
    assert report[1] == "firmware/card.h:7: vel: b (b.c b.h)"


def test_the_status_words_are_owned_bit_by_bit(tmp_path):
    """ustat and sstat have their writers per bit (status.def), so their part
    may have several writer modules."""
    card = CARD_H.replace("uint32_t ustat;\n        int32_t pos, meas[2];",
                          "uint32_t ustat;\n    };\n    /* writers: a.c */\n    struct {\n"
                          "        int32_t pos, meas[2];").replace("writers: a.c */\n    struct {\n        uint32_t ustat",
                                                              "writers: a.c b.c */\n    struct {\n        uint32_t ustat")
    root = tree(tmp_path, {"card.h": card, "b.c": "void g(axis_t *y) { y->vel++; y->ustat |= UB(DR_F); }\n",
                           "status.def": 'USTAT_BY(SYN_F, "a.c", "a.c")\nUSTAT_BY(DR_F, "a.c b.c", "a.c")\n'})
    report = []
    assert onewriter.check(root, report=report) == []
    assert report[0] == "firmware/card.h:2: ustat: a (a.c), b (b.c)  [bit by bit (status.def)]"
