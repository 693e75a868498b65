"""Shared helpers for the command-interface tests: the command table comes
from build/commands.json (generated from firmware/commands.def)."""
import json
import os

from conftest import BOOT, BUILD, sim

TABLE = json.load(open(os.path.join(BUILD, "commands.json")))
BY_MN = {c["mnemonic"]: c for c in TABLE["commands"]}
for _a, _of in TABLE["aliases"].items():
    BY_MN[_a] = BY_MN[_of]
BIT = {word: {b["name"]: b["bit"] for b in bits if "width" not in b}
       for word, bits in TABLE["status"].items() if word != "modes"}
MODE = {m["name"]: m["code"] for m in TABLE["status"]["modes"]}


def code(mn):
    return BY_MN[mn]["code"]


def ubits(*names, mode="disable"):
    v = MODE[mode]
    for n in names:
        v |= 1 << BIT["user"][n]
    return v


def obits(*names):
    v = 0
    for n in names:
        v |= 1 << BIT["overall"][n]
    return v


def script(cmds, settle=5):
    """cmds: list of (axis, mnemonic-or-code, param) or raw script lines."""
    out = [BOOT]
    for c in cmds:
        if isinstance(c, str):
            out.append(c + "\n")
            continue
        axis, mn, *p = c
        out.append("send %d %s %s\n" % (axis, mn, p[0] if p else ""))
    out.append("run %d\n" % settle)
    return "".join(out)


def run(cmds, card="inc", settle=5, args=()):
    r = sim(script(cmds, settle), card, args=args)
    assert r.rc in (0, 3), r.stderr
    return r


ENABLE = [(0, "INIT"), (0, "ME"), (0, "E")]
