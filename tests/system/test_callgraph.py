"""`make arch-check`, part 1: the firmware's file-to-file call graph has no
cycle except through the interfaces of tools/callgraph.allow
(tools/callgraph.py), and the check fails when it should."""
import os
import shutil
import subprocess
import sys

from conftest import BUILD, ROOT

sys.path.insert(0, os.path.join(ROOT, "tools"))
import callgraph  # noqa: E402

TOOL = [sys.executable, os.path.join(ROOT, "tools", "callgraph.py")]
CARDS = [os.path.join(BUILD, "fw-" + c) for c in ("inc", "ssi", "stp")]


def run(*args):
    return subprocess.run(TOOL + list(args), capture_output=True, text=True, timeout=300)


def edges(*pairs):
    """A synthetic graph: ("a.c", "b.c", "f") is a.c's call of b.c's f."""
    g = {}
    for a, b, f in pairs:
        g.setdefault((a, b), {}).setdefault("call", set()).add("x -> " + f)
    return g


def test_cycles_of_a_synthetic_graph():
    g = edges(("a.c", "b.c", "f"), ("b.c", "c.c", "g"), ("c.c", "a.c", "h"), ("c.c", "d.c", "i"),
              ("d.c", "e.c", "j"), ("e.c", "d.c", "k"), ("e.c", "f.c", "l"))
    assert callgraph.cycles(g) == [["a.c", "b.c", "c.c"], ["d.c", "e.c"]]
    assert callgraph.cycles(edges(("a.c", "b.c", "f"), ("b.c", "c.c", "g"))) == []


def test_the_allowlist_takes_out_only_the_functions_it_names():
    g = edges(("a.c", "b.c", "f"), ("b.c", "a.c", "g"), ("b.c", "a.c", "h"))
    left, stale = callgraph.apply_allow(g, [("b.c", "a.c", {"g"}, 1)])
    assert callgraph.cycles(left) == [["a.c", "b.c"]] and stale == []     # h still closes it
    left, stale = callgraph.apply_allow(g, [("b.c", "a.c", {"g", "h"}, 1)])
    assert callgraph.cycles(left) == [] and stale == []
    left, stale = callgraph.apply_allow(g, [("b.c", "a.c", {"gone"}, 3), ("x.c", "y.c", None, 4)])
    assert callgraph.cycles(left) == [["a.c", "b.c"]] and stale == [3, 4]  # entries that match nothing


def test_the_firmware_has_no_cycle_but_the_declared_ones():
    r = run(*CARDS)
    assert r.returncode == 0, r.stderr
    assert "no cycle" in r.stdout


def test_a_missing_allowlist_entry_shows_the_cycle(tmp_path):
    allow = tmp_path / "allow"
    allow.write_text("".join(line for line in open(callgraph.ALLOW)
                             if "fw_halt_for_watchdog" not in line))
    r = run("--allow", str(allow), *CARDS)
    assert r.returncode == 1, r.stdout + r.stderr
    assert "cycle among firmware/boot.c, firmware/card.c" in r.stderr
    assert "firmware/card.c -> firmware/boot.c (call): fw_fault -> fw_halt_for_watchdog" in r.stderr


def test_a_stale_allowlist_entry_fails(tmp_path):
    allow = tmp_path / "allow"
    allow.write_text(open(callgraph.ALLOW).read() + "firmware/queue.c -> firmware/cmd.c: cmd_publish\n")
    r = run("--allow", str(allow), *CARDS)
    assert r.returncode == 1 and "no longer makes" in r.stderr, r.stderr


def test_an_injected_cycle_is_found(tmp_path):
    """queue.c, which cmd.c calls, compiled with a call back into cmd.c."""
    d = tmp_path / "fw-inc"
    shutil.copytree(CARDS[0], d)
    (tmp_path / "firmware").mkdir()
    src = tmp_path / "firmware" / "queue.c"             # the line table names firmware/queue.c
    src.write_text(open(os.path.join(ROOT, "firmware", "queue.c")).read() +
                   "\nvoid cmd_publish(void);\nvoid q_injected(void);\nvoid q_injected(void) { cmd_publish(); }\n")
    cc = os.environ.get("CROSS", "m68k-linux-gnu-") + "gcc"
    subprocess.run([cc, "-g", "-m68000", "-Os", "-std=c11", "-ffreestanding", "-fno-builtin", "-ffunction-sections",
                    "-Ihal", "-Ihal/target", "-Ifirmware", "-DHAL_TARGET", "-DMAC4_CARD=0", "-c", str(src),
                    "-o", str(d / "queue.o")], cwd=ROOT, check=True, capture_output=True)
    r = run(str(d))
    assert r.returncode == 1, r.stdout + r.stderr
    assert "firmware/queue.c -> firmware/cmd.c (call): q_injected -> cmd_publish" in r.stderr, r.stderr


def test_bad_input_is_a_clear_error(tmp_path):
    r = run(str(tmp_path / "none"))
    assert r.returncode == 2 and "no such build directory" in r.stderr and "Traceback" not in r.stderr
    bad = tmp_path / "allow"
    bad.write_text("a.c b.c\n")                       # no arrow
    r = run("--allow", str(bad), *CARDS)
    assert r.returncode == 2 and "not 'caller -> callee" in r.stderr and "Traceback" not in r.stderr
