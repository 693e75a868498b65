#!/usr/bin/env python3
"""doccheck.py - what the documentation and the comments name exists
(`make docs-check`, part of `make test`).

    tools/doccheck.py

Fails (exit 1), one line per stale reference, when
* a path under the tree's folders (firmware/card.c, tools/perfscen.py, ...)
  named in a Markdown page, a source or a Makefile is not there;
* a function `name()` or a snake_case name `a_name` in backticks on a
  Markdown page occurs in no source, table or script of the tree;
* a name cited with its file ("motion.c's brake_now", "(`queue.c`:
  `q_get()`", "`vq()` in motion.c", "card.c card_reset") does not occur in
  that file or the header (.c) of its stem (a file named by its base name
  alone is looked up when the tree has exactly one of that name).
Paths under build/ and the fetched Musashi are produced by the build and not
checked; a path with a wildcard or a placeholder (CARD, NAME, N) is a
pattern, not a file."""
import os
import re
import subprocess
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
DIRS = ("firmware", "hal", "harness", "tools", "tests", "host", "board", "docs", "linker", "bench")
EXTS = (r"[A-Za-z][A-Za-z0-9]*",)    # any extension
PATH = re.compile(r"(?<![\w./$-])((?:%s)/[\w./-]*?\.(?:%s))(?![\w/])" % ("|".join(DIRS), "|".join(EXTS)))
IDENT = re.compile(r"`([A-Za-z_]\w*)\(\)`|`([a-z][a-z0-9]*_[a-z0-9_]+)`")
WORD = re.compile(r"[A-Za-z_]\w*")
# a file, then a name: "motion.c's brake_now", "(`queue.c`: `q_get()`", "card.c card_reset"
_F = r"`?(?P<file>[\w/-]*\w\.[chS])`?"
_N = r"`?(?P<name>[a-z_][a-z0-9]*_[a-z0-9_]*[a-z0-9]|[a-z_]\w*(?=\(\)))\b(?!\.\w|'s)(?:\(\))?`?"
CITE = [re.compile(r"(?<![\w.])" + _F + r"(?:'s|,|:)?\s+\(?" + _N),
        # a function, then its file: "`vq()` in motion.c", "`q_get()` (`queue.c`"
        re.compile(r"`(?P<name>[A-Za-z_]\w*)\(\)`,?\s+(?:\(|in\s+)" + _F + r"(?!'s)\b")]
PLACEHOLDER = re.compile(r"[*?]|CARD|NAME|NNNN|TARGET|FILE|\bN\b|\bX\b|/\.\.\.")


def tracked(root=ROOT):
    out = subprocess.run(["git", "-C", root, "ls-files"], capture_output=True, text=True, check=True).stdout
    return [p for p in out.splitlines() if os.path.exists(os.path.join(root, p))]


def _read(root, p):
    return open(os.path.join(root, p), encoding="utf-8", errors="replace").read()


def check(root, files):
    """The stale references among `files` (paths relative to root), as lines."""
    have = set(files)
    words = set()
    for p in files:
        if p.endswith((".c", ".h", ".S", ".py", ".def", ".patch", ".sh", ".mk", ".toml", ".mac4", ".ld")) \
                or os.path.basename(p) == "Makefile":
            words |= set(WORD.findall(_read(root, p)))
    scan = [p for p in files if p.endswith((".md", ".c", ".h", ".S", ".py", ".mk", ".sh", ".toml", ".def"))
            or os.path.basename(p) == "Makefile"]
    bad = []
    by_base, text_of = {}, {}
    for p in files:
        by_base.setdefault(os.path.basename(p), []).append(p)

    def cited_ok(f, name):
        """Whether `name` occurs in file `f` (None: f is not one file of the tree)."""
        cands = [f] if "/" in f else by_base.get(f, [])
        if len(cands) != 1 or cands[0] not in have:
            return None
        # a .c file and the header of its stem are one module (either may hold it)
        mod = [c for c in (cands[0], re.sub(r"\.c$", ".h", cands[0]) if cands[0].endswith(".c")
                           else re.sub(r"\.h$", ".c", cands[0])) if c in have]
        for c in mod:
            if c not in text_of:
                text_of[c] = set(WORD.findall(_read(root, c)))
        return any(name in text_of[c] for c in mod)

    for p in scan:
        if p.startswith(("tests/conformance/vectors/", "tests/fuzz/corpus/")):
            continue
        for n, line in enumerate(_read(root, p).splitlines(), 1):
            for m in PATH.finditer(line):
                ref = m.group(1).rstrip(".")
                if PLACEHOLDER.search(ref) or ref in have or os.path.exists(os.path.join(root, ref)):
                    continue
                bad.append("%s:%d: %s does not exist" % (p, n, ref))
            seen = set()
            for rx in CITE:
                for m in rx.finditer(line):
                    key = (m.group("name"), m.group("file"))
                    if key not in seen and cited_ok(key[1], key[0]) is False:
                        bad.append("%s:%d: `%s` is not in %s" % ((p, n) + key))
                    seen.add(key)
            if p.endswith(".md"):
                for m in IDENT.finditer(line):
                    name = m.group(1) or m.group(2)
                    if name not in words:
                        bad.append("%s:%d: `%s` is named in no source of the tree" % (p, n, name))
    return bad


def main():
    bad = check(ROOT, tracked())
    for b in bad:
        print("doccheck: " + b, file=sys.stderr)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
