#!/usr/bin/env python3
"""onewriter.py - each part of axis_t has its declared writers and one
writer module, each status bit the files status.def names, and only the
parameter store writes the parameters (`make arch-check`, part of `make test`).

    tools/onewriter.py [--root DIR] [--list] [--parts]

A C-aware scan of firmware/*.c and *.h (comments and strings left out):

* the parts: firmware/card.h declares the writers of each part of axis_t
  with a comment `writers: FILE ...` before it; it holds for the fields that
  follow, up to the next one.  A write is an assignment (=, op=), ++ or --,
  or an address taken (&x->f, a callee may write it) of a field of an axis
  expression: `axes[..].f`, `axis_at[..]->f`, or `p->f` where p is declared
  `axis_t *p` in that file.  Code in a header counts to the header
  (tick.h's inline functions are tick.h's), as tools/callgraph.py does.
  A file a part names that writes none of its fields fails (stale), so
  the lines stay true as code moves.
  tools/onewriter.allow lists the other writes a part has on purpose:
  `FIELD FILE  # why`, and `FIELD FILE read  # why` where the address is
  taken for a const pointer (a read: FILE is no writer); an entry that
  matches no write fails (stale);
* one writer module per part: a module is a .c file with its own header
  (motion.c and motion.h; a private header callgraph.py's HEADER_OWNER
  names, motion_priv.h) - a header whose stem has no .c (tick.h,
  servo_card.h) and the shared headers (callgraph.py's SHARED_HEADERS:
  card.h, stepper.h) are modules of their own, as in the call graph.  A
  part whose writers are more than one module fails unless
  tools/onewriter.allow explains it: `part FIELD  # why` (any field of the
  part; the reason is required); an entry for a part with one writer
  module fails (stale).  The status words ustat and sstat are owned bit by
  bit instead (status.def, below): their part is left out of this rule;
* the status bits (status.def USTAT_BY / SSTAT_BY "sets" "clears"): a
  statement that writes ustat or sstat (or a local it is then assigned
  from), or calls axis_error, sets the UB()/SB() bits it names and clears
  those under a `~`; a plain `=` of `(.. & ~M) | ..` writes M both ways.
  A file that sets or clears a bit without its line naming it fails;
* the parameters: par_a, par_w and par_gen are written in params.c and
  params.h alone (params_write, params_activate, params_force).
Limits: an alias other than a declared `axis_t *` (a part's own pointer,
`prof_t *p = &x->prof`, is seen as the address taken) and writes through
memcpy/memset of a whole axis are not told apart from the owner's.

--parts prints each part with its writer files by module.  Exit 1 with
one line per undeclared write or part of several writers; 2 on a setup
error."""
import argparse
import os
import re
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from callgraph import HEADER_OWNER, SHARED_HEADERS  # noqa: E402  (one definition of a module)
STATUS_WORDS = ("ustat", "sstat")   # owned bit by bit (status.def), not by part
PARAM_STORE = ("firmware/params.c", "firmware/params.h")
PARAM_ARRAYS = ("par_a", "par_w", "par_gen")
ASSIGN = r"(?:\s*\[[^\]]*\])*(?:\s*(?:\.|->)\s*\w+(?:\s*\[[^\]]*\])*)*\s*(?:[-+*/%&|^]|<<|>>)?=(?!=)"


_P = r"\b(%s)\b" % "|".join(PARAM_ARRAYS)
PARAM_WRITE = re.compile("|".join([_P + ASSIGN, _P + r"(?:\s*\[[^\]]*\])*\s*(?:\+\+|--)",
                                   r"(?:\+\+|--)\s*" + _P, r"(?:[(,=?:]|\breturn)\s*&\s*" + _P]))


def strip(text):
    """The text with comments and string/char literals blanked, lines kept."""
    out = re.sub(r"/\*.*?\*/|//[^\n]*|\"(?:\\.|[^\"\\\n])*\"|'(?:\\.|[^'\\\n])*'",
                 lambda m: re.sub(r"[^\n]", " ", m.group(0)), text, flags=re.S)
    return out


def parts(card_h, lines_of=None):
    """{field: set of writer files} from axis_t in card.h, and errors;
    lines_of, when given, gets {field: card.h line of its writers: comment}
    (the fields of one line are one part)."""
    text = open(card_h).read()
    m = re.search(r"typedef struct \{(.*?)\n\} axis_t;", text, re.S)
    if not m:
        return None, ["%s: no axis_t" % card_h]
    body, base = m.group(1), m.start(1)
    # the files of a `writers:` comment: its words that name a .c or .h
    marks = [(w.start(), re.findall(r"(?<![\w/])[\w/]+\.[ch]\b", w.group(1)))
             for w in re.finditer(r"writers:((?:(?!\*/).)*)\*/", body, re.S)]
    mark_line = {pos: text.count("\n", 0, base + pos) + 1 for pos, _ in marks}
    code = strip(body)
    fields, bad = {}, []
    for d in re.finditer(r"([^;{}]*);", code):
        decl = d.group(1).strip()
        if not decl or decl.startswith("struct"):
            continue
        decl = re.sub(r"\[[^\]]*\]", "", decl)
        words = decl.split(",")
        # the first has the type in front of it: its last word is the name
        names = [re.findall(r"\w+", words[0])[-1]] + [re.findall(r"\w+", w)[-1] for w in words[1:]]
        ws = [w for pos, w in marks if pos < d.end()]
        at = [mark_line[pos] for pos, _ in marks if pos < d.end()]
        line = text.count("\n", 0, base + d.end()) + 1
        for nm in names:
            if not ws:
                bad.append("firmware/card.h:%d: %s has no writers: line before it" % (line, nm))
            fields[nm] = set("firmware/" + w for w in (ws[-1] if ws else []))
            if lines_of is not None and at:
                lines_of[nm] = at[-1]
    return fields, bad


def sources(root):
    fw = os.path.join(root, "firmware")
    return sorted("firmware/" + f for f in os.listdir(fw) if f.endswith((".c", ".h")))


def axis_exprs(code):
    """The regex of an axis expression in a file: axes[..]., axis_at[..]->, p-> for axis_t *p."""
    ptrs = set(re.findall(r"\baxis_t\s*\*\s*(?:const\s+)?(\w+)", code))
    alts = [r"\baxes\s*\[[^\]]*\]\s*\.", r"\baxis_at\s*\[[^\]]*\]\s*->"]
    if ptrs:
        alts.append(r"\b(?:%s)\s*->" % "|".join(sorted(ptrs)))
    return "(?:%s)" % "|".join(alts)


def field_writes(code, fields):
    """[(line, field)] of the writes of axis fields in a file's code."""
    ax = axis_exprs(code)
    f = r"\s*(?P<f>\w+)"
    rxs = [re.compile(ax + f + ASSIGN),
           re.compile(ax + f + r"(?:\s*\[[^\]]*\])*(?:\s*(?:\.|->)\s*\w+)*\s*(?:\+\+|--)"),
           re.compile(r"(?:\+\+|--)\s*" + ax + f),
           # an address taken: & after ( , = ? : or return, not a binary & or &&
           re.compile(r"(?:[(,=?:]|\breturn)\s*&\s*\(?\s*" + ax + f)]
    out = set()
    for rx in rxs:
        for m in rx.finditer(code):
            if m.group("f") in fields:
                out.add((code.count("\n", 0, m.start()) + 1, m.group("f")))
    return sorted(out)


def statements(code):
    """(line, text) of each statement of a file's code, split at ; { }."""
    pos = 0
    for m in re.finditer(r"[^;{}]*[;{}]", code):
        s = m.group(0)
        lead = len(s) - len(s.lstrip())
        yield code.count("\n", 0, m.start() + lead) + 1, s.strip()
        pos = m.end()


def bit_masks(status_h):
    """{macro: [bits]} of the masks status.h builds of UB()/SB() (US_ERRORS)."""
    out = {}
    for m in re.finditer(r"#define\s+(\w+)\s+\((.*)\)\s*$", strip(open(status_h).read()), re.M):
        bits = re.findall(r"\b([US])B\((\w+)\)", m.group(2))
        if bits:
            out[m.group(1)] = bits
    return out


def bits_in(expr, masks):
    """[(kind U/S, bit, under ~)] named in an expression."""
    out, spans = [], []
    for t in re.finditer(r"~\s*", expr):       # what a ~ covers: its (...) or its operand
        i = t.end()
        if expr[i:i + 1] == "(":
            depth = 0
            for j in range(i, len(expr)):
                depth += {"(": 1, ")": -1}.get(expr[j], 0)
                if depth == 0:
                    break
            spans.append((i, j + 1))
        else:
            w = re.match(r"\w+(?:\s*\([^)]*\))?", expr[i:])
            spans.append((i, i + (w.end() if w else 0)))
    for m in re.finditer(r"\b([US])B\((\w+)\)|\b(\w+)\b", expr):
        if m.group(1):
            found = [(m.group(1), m.group(2))]
        elif m.group(3) in masks:
            found = masks[m.group(3)]
        else:
            continue
        neg = any(a <= m.start() < b for a, b in spans)
        out += [(k, b, neg) for k, b in found]
    return out


def status_writes(code, masks):
    """[(line, kind, bit, 'sets'/'clears')] of a file's code."""
    ax = axis_exprs(code)
    proxies = set(re.findall(ax + r"\s*[us]stat\s*=\s*(\w+)\s*;", code))
    lhs = re.compile(r"(?:(?:" + ax + r"\s*(?P<st>[us]stat))|(?:\b(?P<v>\w+)))\s*"
                     r"(?P<op>\|=|&=|=)(?!=)(?P<rhs>.*)$", re.S)
    out = []
    for line, s in statements(code):
        s = s.rstrip(";{} ")
        hits = []
        call = re.search(r"\baxis_error\s*\((.*)\)", s, re.S)
        if call:
            hits = [(k, b, "sets") for k, b, _ in bits_in(call.group(1), masks)]
        else:
            m = next((m for m in lhs.finditer(s) if m.group("st") or m.group("v") in proxies), None)
            if not m:
                continue
            op = m.group("op")
            for k, b, neg in bits_in(m.group("rhs"), masks):
                if op == "|=":
                    hits.append((k, b, "sets"))
                elif op == "&=":
                    if neg:
                        hits.append((k, b, "clears"))
                elif neg:
                    hits += [(k, b, "sets"), (k, b, "clears")]
                else:
                    hits.append((k, b, "sets"))
        out += [(line, k, b, how) for k, b, how in hits]
    return out


def declared_bits(status_def):
    """{(kind, bit): {'sets': set, 'clears': set}} from USTAT_BY / SSTAT_BY."""
    out = {}
    for m in re.finditer(r"^([US])STAT_BY\(\s*(\w+)\s*,\s*\"([^\"]*)\"\s*,\s*\"([^\"]*)\"\s*\)",
                         open(status_def).read(), re.M):
        out[(m.group(1), m.group(2))] = {"sets": set("firmware/" + f for f in m.group(3).split()),
                                         "clears": set("firmware/" + f for f in m.group(4).split())}
    return out


def module(root, path):
    """The module a firmware file is part of: firmware/X.c and its own
    header X.h are X; a header without a .c of its stem, or a shared one,
    is a module of its own (its file name)."""
    path = HEADER_OWNER.get(path, path)
    if path.endswith(".h") and path not in SHARED_HEADERS and \
            os.path.exists(os.path.join(root, path[:-2] + ".c")):
        path = path[:-2] + ".c"
    return os.path.basename(path[:-2]) if path.endswith(".c") else os.path.basename(path)


def read_allow(path):
    """([(field, file, line)] of the writes on purpose, [(field, file, line)]
    of the const-pointer reads, [(field, line)] of the parts of several
    writers) of the allowlist."""
    writes, reads, several = [], [], []
    if not os.path.exists(path):
        return writes, reads, several
    for n, line in enumerate(open(path), 1):
        words, _, why = line.partition("#")
        words = words.split()
        if not words:
            continue
        if words[0] == "part":
            if len(words) != 2 or not why.strip():
                raise ValueError("%s:%d: want part FIELD  # why" % (path, n))
            several.append((words[1], n))
        elif len(words) == 3 and words[2] == "read":
            reads.append((words[0], words[1], n))
        elif len(words) == 2:
            writes.append((words[0], words[1], n))
        else:
            raise ValueError("%s:%d: want FIELD FILE [read]  # why, or part FIELD  # why" % (path, n))
    return writes, reads, several


def check(root, listing=False, report=None):
    """The lines of the undeclared writes and of the parts of several
    writer modules (empty: the tree keeps the rule); report, when given,
    gets a line per part: its fields and writer files by module."""
    part_line = {}
    fields, bad = parts(os.path.join(root, "firmware", "card.h"), part_line)
    if fields is None:
        return bad
    wrote = set()                   # (card.h line of the part, file)
    allow_path = os.path.join(root, "tools", "onewriter.allow")
    allow, allow_read, allow_part = read_allow(allow_path)
    used = set()
    masks = bit_masks(os.path.join(root, "firmware", "status.h"))
    decl = declared_bits(os.path.join(root, "firmware", "status.def"))
    seen_bits = set()
    for p in sources(root):
        code = strip(open(os.path.join(root, p)).read())
        for line, f in field_writes(code, fields):
            if listing:
                print("%s:%d: writes %s" % (p, line, f))
            if p in fields[f]:
                wrote.add((part_line.get(f), p))
                continue
            ok = [a for a in allow if a[0] == f and a[1] == p]
            if ok:
                used.update(ok)
                wrote.add((part_line.get(f), p))
                continue
            ok = [a for a in allow_read if a[0] == f and a[1] == p]
            if ok:
                used.update(ok)
                continue
            bad.append("%s:%d: writes %s, whose writers are %s" % (p, line, f, " ".join(sorted(fields[f])) or "none"))
        for line, k, b, how in status_writes(code, masks):
            if listing:
                print("%s:%d: %s %sB(%s)" % (p, line, how, k, b))
            seen_bits.add((k, b, how, p))
            d = decl.get((k, b))
            if d is None or p not in d[how]:
                bad.append("%s:%d: %s %sB(%s), which status.def's %sSTAT_BY does not give it" % (p, line, how, k, b, k))
        if p not in PARAM_STORE:
            for m in PARAM_WRITE.finditer(code):
                bad.append("%s:%d: writes %s outside the parameter store (params.c)" %
                           (p, code.count("\n", 0, m.start()) + 1, next(g for g in m.groups() if g)))
    # a writer a part names that writes none of its fields any more
    for ln in sorted(set(part_line.values())):
        names = sorted(set().union(*(fields[f] for f in part_line if part_line[f] == ln)))
        for p in names:
            if (ln, p) not in wrote:
                bad.append("firmware/card.h:%d: %s is named a writer of the part but writes none of it (stale)"
                           % (ln, p))
    for a in allow + allow_read:
        if a not in used:
            bad.append("tools/onewriter.allow:%d: %s %s matches no write (stale)" % (a[2], a[0], a[1]))
    # one writer module per part, the status words apart (bit by bit)
    explained = {}
    for f, n in allow_part:
        if f not in part_line:
            bad.append("tools/onewriter.allow:%d: part %s: no such field of axis_t" % (n, f))
        else:
            explained.setdefault(part_line[f], []).append((f, n))
    for ln in sorted(set(part_line.values())):
        names = [f for f in fields if part_line.get(f) == ln]
        files = sorted(p for (l2, p) in wrote if l2 == ln)
        mods = {}
        for p in files:
            mods.setdefault(module(root, p), []).append(os.path.basename(p))
        status = all(f in STATUS_WORDS for f in names)
        note = ("bit by bit (status.def)" if status else
                "explained (tools/onewriter.allow)" if ln in explained and len(mods) > 1 else "")
        if report is not None:
            report.append("firmware/card.h:%d: %s: %s%s" % (
                ln, " ".join(names), ", ".join("%s (%s)" % (m, " ".join(v)) for m, v in sorted(mods.items())),
                "  [%s]" % note if note else ""))
        if status:
            continue
        if len(mods) > 1 and ln not in explained:
            bad.append("firmware/card.h:%d: part %s has %d writer modules (%s): one owns it and the others "
                       "call it, or tools/onewriter.allow explains it (part %s  # why)"
                       % (ln, names[0], len(mods), " ".join(sorted(mods)), names[0]))
        if len(mods) <= 1:
            for f, n in explained.get(ln, []):
                bad.append("tools/onewriter.allow:%d: part %s has one writer module (stale)" % (n, f))
    for (k, b), d in sorted(decl.items()):
        for how in ("sets", "clears"):
            for p in sorted(d[how]):
                if (k, b, how, p) not in seen_bits:
                    bad.append("firmware/status.def: %sSTAT_BY(%s): %s %s it nowhere (stale)" % (k, b, p, how))
    return bad


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--root", default=ROOT)
    ap.add_argument("--list", action="store_true", help="print every write found")
    ap.add_argument("--parts", action="store_true", help="print each part's writer files by module")
    a = ap.parse_args(argv)
    if not os.path.isfile(os.path.join(a.root, "firmware", "card.h")):
        print("onewriter: no firmware/card.h under %s" % a.root, file=sys.stderr)
        return 2
    report = [] if a.parts else None
    try:
        bad = check(a.root, a.list, report)
    except (OSError, ValueError) as e:
        print("onewriter: %s" % e, file=sys.stderr)
        return 2
    for r in report or []:
        print(r)
    for b in bad:
        print("onewriter: " + b)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
