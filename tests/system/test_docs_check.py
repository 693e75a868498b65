"""`make docs-check`: the generated command page is what the table gives,
and what the documentation names exists (tools/commands_md.py --check,
tools/doccheck.py)."""
import os
import subprocess
import sys

from conftest import BUILD, ROOT

sys.path.insert(0, os.path.join(ROOT, "tools"))
import doccheck  # noqa: E402

MD = [sys.executable, os.path.join(ROOT, "tools", "commands_md.py")]
JSON = os.path.join(BUILD, "commands.json")


def test_the_command_page_is_the_tables():
    r = subprocess.run(MD + ["--check", JSON, os.path.join(ROOT, "docs", "commands.md")],
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr


def test_a_hand_edit_of_the_command_page_is_noticed(tmp_path):
    page = tmp_path / "commands.md"
    page.write_text(open(os.path.join(ROOT, "docs", "commands.md")).read().replace("| 70 / 71 |", "| 70 / 72 |", 1))
    r = subprocess.run(MD + ["--check", JSON, str(page)], capture_output=True, text=True, timeout=60)
    assert r.returncode == 1 and "make docs" in r.stderr and "Traceback" not in r.stderr, r.stderr
    assert "| 70 / 72 |" in page.read_text()                 # --check writes nothing


def test_the_tree_has_no_stale_reference():
    assert doccheck.check(ROOT, doccheck.tracked()) == []


def test_stale_files_and_names_are_found(tmp_path):
    # the paths spelled in two parts, so that this file itself names none
    gone, old, page = "harness" + "/gone.c", "tools" + "/old.py", "docs" + "/a.md"
    (tmp_path / "harness").mkdir()
    (tmp_path / "docs").mkdir()
    (tmp_path / "harness" / "sim.c").write_text("/* see %s */\nvoid sim_run(void) {}\n" % gone)
    (tmp_path / page).write_text("`sim_run()` and `sim_walk()`, `pos_end`; harness/sim.c, %s, build/x.c, "
                                 "tests/witness/k_NAME.c\n" % old)
    bad = doccheck.check(str(tmp_path), ["harness/sim.c", page])
    assert bad == ["harness/sim.c:1: %s does not exist" % gone,
                   "%s:1: %s does not exist" % (page, old),
                   "%s:1: `sim_walk` is named in no source of the tree" % page,
                   "%s:1: `pos_end` is named in no source of the tree" % page], bad


def test_a_name_cited_with_the_wrong_file_is_found(tmp_path):
    (tmp_path / "firmware").mkdir()
    (tmp_path / "docs").mkdir()
    (tmp_path / "firmware" / "motion.c").write_text("void brake_now(void) {}\nint vq(int v) { return v; }\n")
    (tmp_path / "firmware" / "stepper.h").write_text("static inline int stp_output(void) { return 0; }\n")
    (tmp_path / "firmware" / "card.c").write_text("void card_reset(void) {}\n")
    # the citations spelled in parts, so that this file itself cites none
    m, c, st = "motion" + ".c", "card" + ".c", "stepper" + ".c"
    other = "firmware" + "/other.c"
    (tmp_path / other).write_text("/* the ramp (%s's brake_now), %s (stp_output) */\n"
                                                  "/* %s card_supervise_tick, %s, %s: vq_compute */\n" % (m, st, c, m, c))
    page = "docs" + "/b.md"
    (tmp_path / page).write_text("(`%s`, `brake_now`), `vq()` in %s, `card_reset()` (`%s`)\n" % (m, m, m))
    bad = doccheck.check(str(tmp_path), ["firmware/motion.c", "firmware/stepper.h", "firmware/card.c",
                                         other, page])
    assert bad == ["%s:2: `card_supervise_tick` is not in card.c" % other,
                   "%s:2: `vq_compute` is not in card.c" % other,
                   "%s:1: `card_reset` is not in motion.c" % page], bad
