#!/usr/bin/env python3
"""stackdepth.py - worst-case stack depth and RAM use of a MAC4 EPROM image
(docs/performance.md, "Stack and RAM").

    tools/stackdepth.py build/eprom/mac4-inc.elf build/fw-inc [--json]

Frames come from GCC's -fstack-usage (build/fw-CARD/*.su: the frame of each
function, pushed arguments included, without the return address); the call
graph from the disassembly (m68k-linux-gnu-objdump -d): JSR/BSR/JMP/BRA to
another function, and - for calls through a register - every function whose
address the caller loads (an over-estimate, never an under-estimate).  Static
functions of the same name are told apart through the link map (address ->
object file -> .su file).

Roots: the main loop (crt0 calls fw_init, then fw_main_step for ever, on the
SRAM stack) and one interrupt entry per level (hal/target/vectors.S: a 6-byte
exception frame, the handler entered directly - HAL_ISR, its saves in its
own frame - or through a stub's MOVEM of d0-d1/a0-a1 and JSR; 16 bytes are
charged either way; the timer's vector enters either tick body on INC/SSI,
the deeper counts).  Levels 4 (serial),
5 (axis board), 6 (timer) and 7 (emergency stop) can each interrupt the one
below, so the worst case is the main loop's deepest path plus each level's
deepest.  fw_boot_stage1 runs before, on the boot stack in the DPRAM, and
fw_fault only once the card is stopping; both are reported apart.
"""
import json
import os
import re
import subprocess
import sys

CROSS = os.environ.get("CROSS", "m68k-linux-gnu-")
# level: the handlers its vector may enter (INC/SSI: tick_select puts either
# tick body in the timer's vector), the deepest counts
ISR_ENTRY = {"_isr_uart": (("fw_isr_uart",), 4), "_isr_axis": (("fw_isr_axis",), 5),
             "_isr_tick": (("fw_isr_tick", "fw_isr_tick_general"), 6), "_isr_estop": (("fw_isr_estop",), 7)}
EXC_FRAME, MOVEM, RET = 6, 16, 4


def run(*cmd):
    return subprocess.run(cmd, check=True, capture_output=True, text=True).stdout


def load_su(fwdir):
    """{(object base name, function): bytes}"""
    su = {}
    for f in sorted(os.listdir(fwdir)):
        if not f.endswith(".su"):
            continue
        base = f[:-3]
        for line in open(os.path.join(fwdir, f)):
            parts = line.rstrip("\n").split("\t")
            if len(parts) < 3:
                continue
            func = parts[0].rsplit(":", 1)[-1]
            su[(base, func)] = (int(parts[1]), parts[2])
    return su


def load_map(mapfile):
    """address -> object base name, from the .text.FUNC input sections"""
    owner = {}
    pending = None
    rx = re.compile(r"^\s*(\.text[.\w]*)?\s+0x([0-9a-f]+)\s+0x([0-9a-f]+)\s+(\S+\.o)\s*$")
    for line in open(mapfile):
        m = rx.match(line)
        if m and (m.group(1) or pending):
            owner[int(m.group(2), 16)] = os.path.splitext(os.path.basename(m.group(4)))[0]
            pending = None
            continue
        pending = line.strip().startswith(".text.") and len(line.split()) == 1
    return owner


def disassemble(elf):
    funcs = {}          # name -> dict(addr, lines)
    order = []
    cur = None
    for line in run(CROSS + "objdump", "-d", "-j", ".text", "--no-show-raw-insn", elf).splitlines():
        m = re.match(r"^([0-9a-f]+) <([^>]+)>:$", line)
        if m:
            cur = {"addr": int(m.group(1), 16), "name": m.group(2), "insns": []}
            order.append(cur)
            continue
        if cur is not None and re.match(r"^\s+[0-9a-f]+:", line):
            cur["insns"].append(line.split(":", 1)[1].strip())
    for f in order:
        funcs.setdefault(f["name"], []).append(f)
    return order


def analyse(elf, fwdir, mapfile):
    su = load_su(fwdir)
    owner = load_map(mapfile)
    order = disassemble(elf)
    by_addr = {f["addr"]: f for f in order}
    starts = set(by_addr)
    sym_addr = {}
    for f in order:
        sym_addr.setdefault(f["name"], f["addr"])
    frames, notes = {}, []
    for f in order:
        base = owner.get(f["addr"])
        key = (base, f["name"]) if base else None
        if key in su:
            frames[f["addr"]] = su[key][0]
        else:
            cands = [v for (b, n), v in su.items() if n == f["name"]]
            frames[f["addr"]] = max((c[0] for c in cands), default=0)
    calls = {}
    indirect = set()
    for f in order:
        targets = set()
        for ins in f["insns"]:
            op = ins.split()[0] if ins else ""
            m = re.search(r"\b([0-9a-f]+) <([^>+]+)(\+0x[0-9a-f]+)?>", ins)
            if op in ("jsr", "bsr", "bsrw", "bsrs", "bsrl", "jbsr") or op.startswith("bsr"):
                if m and int(m.group(1), 16) in starts:
                    targets.add(int(m.group(1), 16))
                elif "%" in ins:
                    indirect.add(f["addr"])
                continue
            if op in ("jmp", "bra", "bras", "braw", "jra") and m and int(m.group(1), 16) in starts \
                    and int(m.group(1), 16) != f["addr"]:
                targets.add(int(m.group(1), 16))             # tail call
                continue
            # a function's address loaded into a register may be called through it
            if op.startswith("mov") or op.startswith("pea"):
                for imm in re.findall(r"#(\d+)", ins):
                    if int(imm) in starts and int(imm) != f["addr"]:
                        targets.add(int(imm))
            if op.startswith("lea") and m and int(m.group(1), 16) in starts and int(m.group(1), 16) != f["addr"]:
                targets.add(int(m.group(1), 16))
        calls[f["addr"]] = targets

    memo, onstack = {}, set()

    def depth(a):
        """bytes below the caller's SP when a is called: return address, frame, deepest callee"""
        if a in memo:
            return memo[a]
        if a in onstack:
            notes.append("recursion through %s: unbounded" % by_addr[a]["name"])
            return (10 ** 6, [by_addr[a]["name"]])
        onstack.add(a)
        best = (0, [])
        for t in calls.get(a, ()):
            d = depth(t)
            if d[0] > best[0]:
                best = d
        onstack.discard(a)
        r = (RET + frames.get(a, 0) + best[0], [by_addr[a]["name"]] + best[1])
        memo[a] = r
        return r

    for a in indirect:
        if not calls[a]:
            notes.append("unresolved indirect call in %s" % by_addr[a]["name"])

    def root(name):
        if name not in sym_addr:
            return (0, [])
        return depth(sym_addr[name])

    main = max(root("fw_init"), root("fw_main_step"))
    levels = {}
    for stub, (handlers, level) in ISR_ENTRY.items():
        d, path = max(root(h) for h in handlers)
        levels[level] = {"bytes": EXC_FRAME + MOVEM + d, "path": [stub] + path}
    boot = root("fw_boot_stage1")
    fault = root("fw_fault")
    size = run(CROSS + "size", elf).splitlines()[1].split()
    text, data, bss = int(size[0]), int(size[1]), int(size[2])
    worst = main[0] + sum(v["bytes"] for v in levels.values())
    return {
        "main_bytes": main[0], "main_path": main[1],
        "isr": {str(k): v for k, v in sorted(levels.items())},
        "stack_bytes": worst,
        "boot_stack_bytes": boot[0], "fault_bytes": fault[0],
        "data_bytes": data, "bss_bytes": bss, "ram_bytes": data + bss,
        "ram_stack_bytes": data + bss + worst,
        "text_bytes": text,
        "notes": sorted(set(notes)),
    }


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    if len(args) != 2:
        print(__doc__)
        return 2
    elf, fwdir = args
    r = analyse(elf, fwdir, os.path.splitext(elf)[0] + ".map")
    if "--json" in sys.argv:
        print(json.dumps(r, indent=1))
        return 0
    print("stack  main loop %5d bytes  %s" % (r["main_bytes"], " > ".join(r["main_path"])))
    for lvl, v in r["isr"].items():
        print("stack  level %s   %5d bytes  %s" % (lvl, v["bytes"], " > ".join(v["path"])))
    print("stack  worst case %4d bytes (main loop + levels 4..7 nested)" % r["stack_bytes"])
    print("ram    data %d + bss %d = %d bytes; with the stack %d bytes" % (
        r["data_bytes"], r["bss_bytes"], r["ram_bytes"], r["ram_stack_bytes"]))
    print("stack  boot stage 1 (DPRAM boot stack) %d bytes; fault path %d bytes" % (
        r["boot_stack_bytes"], r["fault_bytes"]))
    for n in r["notes"]:
        print("note   " + n)
    return 0


if __name__ == "__main__":
    sys.exit(main())
