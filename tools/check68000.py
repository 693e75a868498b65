#!/usr/bin/env python3
"""check68000.py - is this 68000 code?  (docs/hardening.md)

    tools/check68000.py [--objdump PATH] [-v] FILE.elf|FILE.o ...

Walks every instruction reachable from the code entry points of each file
(the vector table, every function symbol, every untyped label in a code
section), the way the CPU would: straight on, branches, calls, and the
PC-relative jump tables GCC puts inline after its `jmp (d8,pc,Dn)`.  Data
in the code section (jump tables, constant tables, strings) is never
decoded, so it cannot raise false alarms.  Each instruction reached is
disassembled by binutils for the plain 68000 (-m m68k:68000) and must be:

  68000     an opcode the 68000 has (binutils prints anything else, 68010
            MOVEC/RTD/MOVE from CCR or 68020 MULU.L/EXTB/BFxxx/..., as .short)
  ea        no 68020 addressing mode: no scaled index (Dn.w*4), no memory
            indirect or full-format extension words (the 68000 ignores those
            bits and silently computes another address)
  target    every branch, call and jump table target even and inside code
            (BSR.L/BRA.L/Bcc.L read by a 68000 are 8-bit branches to an odd
            address)
  odd       no word or long access at an odd displacement from an address
            register, an odd absolute or PC-relative address: an address error
            on the 68000 (Debian's GCC 12 merges byte accesses into such
            moves; base registers are taken to hold even addresses)

and every vector of a .vectors section even.  Exit status 0 when all files
pass, 1 with one line per finding ("FILE: ADDR <func+off>: kind: text")
otherwise, 2 on usage errors.
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile

CROSS = os.environ.get("CROSS", "m68k-linux-gnu-")

# objdump's MIT syntax: "  100672:\t4ef9 0010 08d6 \tjmp 1008d6 <card_start>"
LINE = re.compile(r"^\s*([0-9a-f]+):\t([0-9a-f ]+?)\s*(?:\t(.*))?$")
BCC = re.compile(r"^(bra|bsr|bhi|bls|bcc|bcs|bne|beq|bvc|bvs|bpl|bmi|bge|blt|bgt|ble|bhs|blo)[swl]?$")
DBCC = re.compile(r"^db(t|f|ra|hi|ls|cc|cs|ne|eq|vc|vs|pl|mi|ge|lt|gt|le|hs|lo)$")
SCC = re.compile(r"^s(t|f|hi|ls|cc|cs|ne|eq|vc|vs|pl|mi|ge|lt|gt|le|hs|lo)$")
HEXADDR = re.compile(r"^([0-9a-f]+)(?: <[^>]*>)?$")
SCALE = re.compile(r":[wl]:[248]\b")
DISP_AN = re.compile(r"%(a[0-7]|fp|sp)@\((-?(?:0x)?[0-9a-f]+)\)$")
DISP_IDX = re.compile(r"%(a[0-7]|fp|sp)@\((-?[0-9a-f]+),%[ad][0-7]:[wl]\)$")
PCREL = re.compile(r"^%pc@\(([0-9a-f]+)(?: <[^>]*>)?(?:,%[ad][0-7]:[wl])?\)$")
CMPI = re.compile(r"^cmpi?[bwl]$")
NOFLOW = {"rts", "rte", "rtr", "bra", "bras", "braw", "bral", "jmp", "illegal", "reset"}


class Finding(Exception):
    pass


def run(cmd):
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode:
        raise SystemExit("check68000: %s failed: %s" % (" ".join(cmd), p.stderr.strip()))
    return p.stdout


def split_operands(s):
    """Split an operand list at top-level commas."""
    out, depth, cur = [], 0, ""
    for ch in s:
        if ch == "(":
            depth += 1
        elif ch == ")":
            depth -= 1
        if ch == "," and depth == 0:
            out.append(cur)
            cur = ""
        else:
            cur += ch
    if cur:
        out.append(cur)
    return [o.strip() for o in out]


class Image:
    def __init__(self, path, objdump):
        self.path = path
        self.objdump = objdump
        self.sections = {}        # name -> (addr, size, is_code, data)
        self.symbols = []         # (addr, size, type, name, section)
        self.insns = {}           # addr -> (length, mnemonic, operands)
        self.findings = []
        self._read_sections()
        self._read_symbols()

    # ---- ELF ---------------------------------------------------------------
    def _read_sections(self):
        out = run([CROSS + "readelf", "-SW", self.path])
        for line in out.splitlines():
            m = re.match(r"^\s*\[\s*(\d+)\]\s+(\S+)\s+(\S+)\s+([0-9a-f]+)\s+([0-9a-f]+)\s+([0-9a-f]+)\s+\S+\s+(\S*)", line)
            if not m or m.group(3) == "NULL":
                continue
            idx, name, typ, addr, off, size, flags = m.groups()
            if typ != "PROGBITS" or "A" not in flags:
                continue
            is_code = "X" in flags
            if not is_code and name != ".vectors":
                continue
            with tempfile.NamedTemporaryFile() as t:
                run([CROSS + "objcopy", "-O", "binary", "--only-section=" + name, self.path, t.name])
                data = open(t.name, "rb").read()
            self.sections[name] = (int(addr, 16), int(size, 16), is_code, data, int(idx))

    def _read_symbols(self):
        out = run([CROSS + "readelf", "-sW", self.path])
        by_index = {s[4]: n for n, s in self.sections.items()}
        for line in out.splitlines():
            p = line.split()
            if len(p) < 8 or not p[0].rstrip(":").isdigit() or not p[6].isdigit():
                continue
            sec = by_index.get(int(p[6]))
            if sec is None:
                continue
            size = int(p[2], 0) if not p[2].startswith("0x") else int(p[2], 16)
            self.symbols.append((int(p[1], 16), size, p[3], p[7], sec))
        self.symbols.sort()

    def code_section(self, addr):
        for name, (a, size, is_code, _, _) in self.sections.items():
            if is_code and a <= addr < a + size:
                return name
        return None

    def word(self, addr):
        for a, size, _, data, _ in self.sections.values():
            if a <= addr and addr + 2 <= a + size:
                o = addr - a
                return data[o] << 8 | data[o + 1]
        return None

    def where(self, addr):
        best = None
        for a, size, typ, name, _ in self.symbols:
            if a <= addr and typ in ("FUNC", "NOTYPE"):
                best = (a, name)
        if best is None:
            return "%06x" % addr
        return "%06x <%s+0x%x>" % (addr, best[1], addr - best[0])

    def find(self, addr, kind, text):
        self.findings.append("%s: %s: %s: %s" % (self.path, self.where(addr), kind, text))

    # ---- disassembly -------------------------------------------------------
    def disassemble(self, start, stop):
        """Linear disassembly of [start, stop) into self.insns (68000 only)."""
        out = run([self.objdump, "-d", "-m", "m68k:68000", "-z",
                   "--start-address=0x%x" % start, "--stop-address=0x%x" % stop, self.path])
        last = None
        for line in out.splitlines():
            m = LINE.match(line)
            if not m:
                continue
            addr = int(m.group(1), 16)
            nbytes = len(m.group(2).replace(" ", "")) // 2
            if m.group(3) is None:          # continuation of a long instruction
                if last is not None:
                    l, mn, ops = self.insns[last]
                    self.insns[last] = (l + nbytes, mn, ops)
                continue
            text = m.group(3).strip()
            mn, _, ops = text.partition(" ")
            self.insns[addr] = (nbytes, mn, ops.strip())
            last = addr

    def insn(self, addr, limit):
        if addr not in self.insns:
            self.disassemble(addr, limit)
        return self.insns.get(addr)

    # ---- the walk ----------------------------------------------------------
    def roots(self):
        roots = {}
        for a, size, typ, name, sec in self.symbols:
            if self.sections[sec][2] and typ in ("FUNC", "NOTYPE") and not name.startswith("$"):
                roots[a] = name
        if ".vectors" in self.sections:
            a0, size, _, data, _ = self.sections[".vectors"]
            for i in range(0, size - 3, 4):
                v = int.from_bytes(data[i:i + 4], "big")
                if v & 1:
                    self.find(a0 + i, "vector", "vector %d = $%06X is odd (address error)" % (i // 4, v))
                elif i >= 4 and self.code_section(v):
                    roots.setdefault(v, "vector %d" % (i // 4))
        return roots

    def limit_of(self, addr):
        """End of the function or code section containing addr."""
        end = None
        for a, size, typ, name, sec in self.symbols:
            if a > addr and self.sections[sec][2]:
                end = a
                break
        for a, size, is_code, _, _ in self.sections.values():
            if is_code and a <= addr < a + size:
                end = min(end, a + size) if end else a + size
        return end or addr + 64

    def jump_table(self, at, ops, history):
        """Targets of GCC's 68000 dispatch:
             cmpi #N,Dn ; bhi default ; ... ; add Dn,Dn
             move.w (T,pc,Dn.l),Dm ; jmp (T-2+2,pc,Dm.w)
           a table of N+1 word offsets from T, inline after the jmp."""
        m = PCREL.match(ops)
        if not m:
            return None
        table = int(m.group(1), 16)
        n = None
        for a, mn, o in reversed(history[-10:]):
            if CMPI.match(mn):
                imm = re.match(r"^#(-?\d+),%d[0-7]$", o)
                if imm:
                    n = int(imm.group(1)) + 1
                    break
        targets, i = [], 0
        while True:
            if n is not None and i >= n:
                break
            w = self.word(table + 2 * i)
            if w is None:
                break
            t = table + (w - 0x10000 if w & 0x8000 else w)
            if n is None and (i >= 256 or any(table + 2 * i >= x for x in targets if x > table)):
                break
            targets.append(t)
            i += 1
        return table, 2 * i, targets

    def check_insn(self, addr, length, mn, ops):
        if mn == ".short" or mn.startswith(".word") or mn.startswith(".long"):
            self.find(addr, "68000", "not a 68000 instruction (%s %s)" % (mn, ops))
            return
        if SCALE.search(ops):
            self.find(addr, "ea", "scaled index is 68020 addressing: %s %s" % (mn, ops))
        if re.search(r"\)@\(|%z[ap]|%zpc|@\(\)@", ops):
            self.find(addr, "ea", "memory indirect / full extension word is 68020 addressing: %s %s" % (mn, ops))
        # extension word sanity: bits 8-10 of a brief extension word must be 0 on the 68000
        size = mn[-1] if mn[-1] in "wl" else None
        if (mn.startswith(("lea", "pea", "jmp", "jsr", "link", "movep")) or BCC.match(mn) or DBCC.match(mn)
                or SCC.match(mn) or mn in ("bchg", "bclr", "bset", "btst", "tas", "nbcd", "abcd", "sbcd")):
            size = None
        if size:
            for o in split_operands(ops):
                m = DISP_AN.search(o) or DISP_IDX.search(o)
                if m:
                    d = m.group(2)
                    v = int(d, 16) if (DISP_IDX.search(o) or d.startswith(("0x", "-0x"))) else int(d)
                    if v & 1:
                        self.find(addr, "odd", "%s access at an odd displacement: %s %s" %
                                  ("word" if size == "w" else "long", mn, ops))
                    continue
                m = PCREL.match(o)
                if m and int(m.group(1), 16) & 1:
                    self.find(addr, "odd", "odd PC-relative address: %s %s" % (mn, ops))
                    continue
                m = HEXADDR.match(o)
                if m and int(m.group(1), 16) & 1:
                    self.find(addr, "odd", "odd absolute address: %s %s" % (mn, ops))

    def walk(self):
        for a, size, is_code, _, _ in self.sections.values():
            if is_code:
                self.disassemble(a, a + size)     # one pass; misaligned starts later on demand
        roots = self.roots()
        todo = list(roots)
        seen = set()
        tables = []
        history_at = {}
        while todo:
            addr = todo.pop()
            history = history_at.pop(addr, [])
            while addr not in seen:
                sec = self.code_section(addr)
                if sec is None:
                    self.find(addr, "target", "control reaches $%06X outside the code" % addr)
                    break
                if addr & 1:
                    self.find(addr, "target", "control reaches the odd address $%06X" % addr)
                    break
                seen.add(addr)
                got = self.insn(addr, self.limit_of(addr))
                if got is None:
                    self.find(addr, "68000", "cannot disassemble")
                    break
                length, mn, ops = got
                self.check_insn(addr, length, mn, ops)
                history = (history + [(addr, mn, ops)])[-12:]
                if mn.startswith(".") or length == 0:
                    break
                nxt = addr + length
                targets = []
                if BCC.match(mn) or DBCC.match(mn):
                    t = HEXADDR.match(split_operands(ops)[-1])
                    if t:
                        targets.append(int(t.group(1), 16))
                elif mn in ("jmp", "jsr"):
                    t = HEXADDR.match(ops)
                    if t:
                        targets.append(int(t.group(1), 16))
                    elif mn == "jmp" and ops.startswith("%pc@("):
                        jt = self.jump_table(addr, ops, history)
                        if jt:
                            table, nbytes, tt = jt
                            tables.append((table, nbytes))
                            targets.extend(tt)
                for t in targets:
                    if t & 1:
                        self.find(addr, "target", "%s %s goes to an odd address" % (mn, ops))
                    elif self.code_section(t) is None:
                        self.find(addr, "target", "%s %s leaves the code" % (mn, ops))
                    elif t not in seen:
                        todo.append(t)
                        history_at[t] = history
                if mn in NOFLOW or mn.startswith("bra"):
                    break
                addr = nxt
        self.reached = seen
        self.tables = tables
        return roots

    def unaccounted(self):
        """Byte ranges of code sections neither reached, nor table, nor data object."""
        covered = set()
        for a in self.reached:
            covered.update(range(a, a + self.insns[a][0]))
        for t, n in self.tables:
            covered.update(range(t, t + n))
        for a, size, typ, name, sec in self.symbols:
            if typ == "OBJECT" and self.sections[sec][2]:
                covered.update(range(a, a + size))
        out = []
        for a, size, is_code, _, _ in self.sections.values():
            if not is_code:
                continue
            start = None
            for x in range(a, a + size + 1):
                if x < a + size and x not in covered:
                    if start is None:
                        start = x
                elif start is not None:
                    out.append((start, x))
                    start = None
        return out

    def coverage(self):
        code = sum(self.insns[a][0] for a in self.reached)
        tables = sum(n for _, n in self.tables)
        data = 0
        for a, size, typ, name, sec in self.symbols:
            if typ == "OBJECT" and self.sections[sec][2]:
                data += size
        total = sum(s[1] for s in self.sections.values() if s[2])
        return code, tables, data, total


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("files", nargs="+")
    ap.add_argument("--objdump", default=CROSS + "objdump")
    ap.add_argument("-v", "--verbose", action="store_true")
    args = ap.parse_args()
    bad = 0
    for f in args.files:
        if not os.path.exists(f):
            print("check68000: %s: no such file" % f, file=sys.stderr)
            return 2
        img = Image(f, args.objdump)
        roots = img.walk()
        code, tables, data, total = img.coverage()
        for line in img.findings:
            print(line)
        if args.verbose:
            for a, b in img.unaccounted():
                print("%s: not code, table or data object: %s .. $%06X (%d bytes): %s" %
                      (f, img.where(a), b, b - a, img.word(a) if b - a >= 2 else "-"))
        bad += len(img.findings)
        print("%s: %s: %d instructions from %d entry points, %d bytes of code, %d of jump tables, "
              "%d of data objects, %d others (strings, padding) in %d bytes of code sections" %
              (f, "FAIL" if img.findings else "ok", len(img.reached), len(roots), code, tables, data,
               total - code - tables - data, total))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
