#!/usr/bin/env python3
"""commands_md.py - docs/commands.md from build/commands.json (which
tools/gen_commands.c writes from firmware/commands.def).  Never edit
docs/commands.md by hand: change commands.def and run `make docs`.

    tools/commands_md.py [--check] build/commands.json docs/commands.md

With --check, writes nothing and fails (exit 1) when the page is not what
the table gives (`make docs-check`, part of `make test`)."""
import json
import sys


def per_card(d, fmt=str):
    """One value, or the cards grouped by value: 'INC/SSI: 100; STP: 1000'."""
    groups = {}
    for k, v in d.items():
        groups.setdefault(fmt(v), []).append(k.upper())
    if len(groups) == 1:
        return next(iter(groups))
    return "; ".join("%s: %s" % ("/".join(ks), v) for v, ks in groups.items())


def rng(r):
    lo, hi = r
    def f(x):
        return {-2147483648: "-2^31", 2147483647: "2^31-1"}.get(x, str(x))
    return "%s .. %s" % (f(lo), f(hi))


def main():
    args = sys.argv[1:]
    check = args[:1] == ["--check"]
    if check:
        args = args[1:]
    if len(args) != 2:
        print("usage: commands_md.py [--check] COMMANDS.json PAGE.md", file=sys.stderr)
        return 2
    src, dst = args
    t = json.load(open(src))
    out = ["# MAC4 command dictionary", "",
           "Generated from `firmware/commands.def` and `firmware/status.def` by `make docs`"
           " (tools/gen_commands.c, tools/commands_md.py); the same table builds the firmware's"
           " dispatch and parameter store and `build/commands.json`. Do not edit by hand.", "",
           "Codes the manual gives are kept (E = 3, MP = 59, WAP = 70, RCP = 116; code 1 is not"
           " implemented and answers 161; errors 160-165). All other codes are ours, chosen once"
           " and never renumbered. A parameter's read code is its write code + 1. SP is the"
           " profile generator's sampling period (10 ms INC/SSI, 32 ms STP).", ""]
    kinds = [("general", "General instructions"), ("read", None), ("mode", "Mode selection (activated by E)"),
             ("write-mode", "Mode parameters (W.. / R..)"), ("write-system", "System parameters (UW.. / UR..)"),
             ("diagnosis", "Diagnosis")]
    cmds = t["commands"]
    by_mn = {c["mnemonic"]: c for c in cmds}
    for kind, title in kinds:
        if title is None:
            continue
        out.append("## " + title)
        out.append("")
        if kind in ("write-mode", "write-system"):
            out.append("| write | read | codes | range | default | units | cards | notes |")
            out.append("|---|---|---|---|---|---|---|---|")
            for c in cmds:
                if c["kind"] != kind:
                    continue
                rd = by_mn[("UR" if kind == "write-system" else "R") + c["mnemonic"][len("UW" if kind == "write-system" else "W"):]]
                notes = []
                if c.get("immediate"):
                    notes.append("takes effect at once")
                if c.get("card_wide"):
                    notes.append("one value for all axes")
                out.append("| %s | %s | %d / %d | %s | %s | %s | %s | %s%s |" % (
                    c["mnemonic"], rd["mnemonic"], c["code"], rd["code"], per_card(c["range"], rng),
                    per_card(c["default"]), per_card(c["units"]), ", ".join(c["cards"]).upper(),
                    c["description"], ("; " + ", ".join(notes)) if notes else ""))
        else:
            out.append("| mnemonic | code | cards | description |")
            out.append("|---|---|---|---|")
            for c in cmds:
                if c["kind"] == kind or (kind == "general" and c["kind"] == "read"):
                    desc = c["description"]
                    if c["kind"] == "mode":
                        desc += " (mode code %d)" % c["mode"]
                    if c["kind"] == "read":
                        desc += " (read: answers a value)"
                    if "units" in c:
                        desc += "; units: " + per_card(c["units"])
                    out.append("| %s | %d | %s | %s |" % (c["mnemonic"], c["code"], ", ".join(c["cards"]).upper(), desc))
        out.append("")
    out += ["## Aliases", ""]
    for a, of in t["aliases"].items():
        out.append("- `%s` = `%s`" % (a, of))
    out += ["", "## Errors (6.3)", "", "| code | status bit | status word | meaning |", "|---|---|---|---|"]
    for e in t["errors"]:
        out.append("| %d | %s | %s | %s |" % (e["code"], e["status_bit"], e["status_word"], e["description"]))
    for word, title in (("user", "User status (RBS, 7.1.1)"), ("system", "System status (RSS, 7.1.2)"),
                        ("overall", "Overall status (RAS, 7.1.3)")):
        out += ["", "## " + title, "", "| bit | name | meaning |", "|---|---|---|"]
        for b in t["status"][word]:
            bit = "%d-%d" % (b["bit"], b["bit"] + b["width"] - 1) if "width" in b else str(b["bit"])
            out.append("| %s | %s | %s |" % (bit, b["name"], b["description"]))
    out += ["", "## Mode codes", "", "| code | mode |", "|---|---|"]
    for m in t["status"]["modes"]:
        out.append("| %d | %s |" % (m["code"], m["name"]))
    text = "\n".join(out) + "\n"
    if check:
        try:
            old = open(dst).read()
        except OSError:
            old = None
        if old != text:
            print("commands_md: %s is not what %s gives: change firmware/commands.def or "
                  "firmware/status.def, not the page, and run `make docs`" % (dst, src), file=sys.stderr)
            return 1
        return 0
    open(dst, "w").write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
