#!/usr/bin/env python3
"""mutate.py - does the differential lane (and the qemu witness) notice a
small change in the native build?

Each mutation below is one small edit of the firmware's source (a constant,
a comparison, a rounding).  For each, in a temporary copy of the tree (the
tree itself is never touched):
  - the native build of the first card it concerns is rebuilt from the
    mutated source, while the EPROM images and mac4sim stay the ones of
    this tree, and the differential lane (tests/differential) runs on it;
  - while it survives and the mutated file is a witness kernel's
    (tests/witness/kernels.txt), the witness lane runs on the mutant too;
  - the mutation is caught when a lane fails.
A mutation that survives is listed with the reason given below it (an
equivalent change, or one no scenario can reach).

    tools/mutate.py                 every mutation (docs/hardening.md, "Mutation")
    tools/mutate.py -k servo        those whose name contains "servo"
    tools/mutate.py -k stp,servo-sw those whose name contains either
    tools/mutate.py --list          the list only
    tools/mutate.py --check         each text to change occurs once in its file (make test)
Run `make all native witness-bins` first.  Exit status 1 when a mutation
without a stated reason survives (--check: when a text is stale), 2 on a
usage or setup error.
"""
import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
BUILD = os.path.join(ROOT, "build")
SERVO, STP, ALL = ("inc", "ssi"), ("stp",), ("inc", "ssi", "stp")

# (name, file, text, replacement, cards, why it may survive or None)
MUTATIONS = [
    # the servo filter (5.16): every term
    ("servo-gain", "firmware/servo.h", "int32_t u1 = muls16(e, g->ga);\n    if (g->ze)",
     "int32_t u1 = muls16(e, g->ga) + e;\n    if (g->ze)", SERVO, None),
    ("servo-gain-k", "firmware/servo.h", "int32_t u1 = muls16(e, g->ga) * 64;\n    s->u1 = u1;",
     "int32_t u1 = muls16(e, g->ga) * 63;\n    s->u1 = u1;", SERVO, None),
    ("servo-zero", "firmware/servo.c", "g->gzh = (int16_t)(gz >> 8);", "g->gzh = (int16_t)((gz >> 8) + 1);",
     SERVO, None),
    ("servo-zero-round", "firmware/servo.h", "(muls16(ep, g->gzl) >> 2)", "(muls16(ep, g->gzl) >> 3)", SERVO, None),
    ("servo-pole", "firmware/servo.h", "(muls16((int16_t)(a & 0xFF), g->po) >> 8)",
     "(muls16((int16_t)(a & 0xFF), g->po) >> 7)", SERVO, None),
    ("servo-integrator", "firmware/servo.h", "u2 += r >> g->kisc;", "u2 += (r + 1) >> g->kisc;", SERVO, None),
    ("servo-integrator-limit", "firmware/servo.c", "g->u2_hi = (int32_t)hi * 256;", "g->u2_hi = (int32_t)hi * 300;",
     SERVO, None),
    ("servo-sw", "firmware/servo.c", "set_range(g, m, (int16_t)-m);", "set_range(g, (int16_t)(m + 1), (int16_t)-m);",
     SERVO, None),
    ("servo-output-round", "firmware/servo.h", "int32_t t = u1 + u2 + 128;", "int32_t t = u1 + u2 + 64;", SERVO, None),
    ("servo-e-limit", "firmware/servo.c", "divu16(1ul << 18, (uint16_t)ga)", "divu16(1ul << 17, (uint16_t)ga)",
     SERVO, None),
    # the profile generator (5.6)
    # the brake decision at equality: the inline 32-bit one every usual move
    # takes (profile.h), and the 64-bit one behind it
    ("profile-brake-compare", "firmware/profile.h", "            return l >= rl;", "            return l > rl;", ALL,
     None),
    ("profile-brake-compare64", "firmware/profile.c", "return (lhs >> 1) >= rhs;", "return (lhs >> 1) > rhs;", ALL,
     "the 64-bit decision serves moves that do not fit 32 bits (rests of 2^16 units or more, speeds of 2^14 "
     "units/SP or more: prof_fits32) and the STP's 64-bit path; no equality there fits the lane's few hundred "
     "ticks; tests/unit/test_profile.c compares it with the 32-bit one"),
    ("profile-creep", "firmware/profile.c", "            if (v < dec)\n                v = dec;",
     "            if (v < dec)\n                v = dec + 1;", ALL, None),
    # the STP's rate stage (table 4.1) and ramps
    # (the rate path of the firmware is stp_rate.h's stp_load_rate, stepper.h's
    # stp_hz_now, which tests/unit/test_stepper.c tests too)
    ("stp-hz-round", "firmware/stepper.h", "(mulu16(s->rate, 25000u) + 0x4000u) >> 15", "(mulu16(s->rate, 25000u)) >> 15",
     STP, None),
    ("stp-rate-saturate", "firmware/stp_rate.h", "        s->rate = 0xFFFFu;", "        s->rate = 0xFFFEu;", STP, None),
    ("stp-ssf-brake", "firmware/stp_profile.h", "if (rem <= (uint32_t)ssf)", "if (rem < (uint32_t)ssf)", STP,
     "equivalent: at rem == ssf (u > ssf) the mutant asks prof_must_brake32(u, dec, 0), which is 1 as well"),
    ("stp-turbo", "firmware/stepper.h", "        hz *= 10;", "        hz *= 9;", STP, None),
    # measurement paths (4.4)
    ("measure-ssi-shift", "firmware/ssi_meas.c", ">> c->sc) & c->mask;", ">> (c->sc + 1)) & c->mask;", ("ssi",), None),
    ("measure-gray", "firmware/ssi_meas.c", "    if (axes[n].ustat & UB(GRAY))\n        v = gray_to_binary(v);",
     "    if (axes[n].ustat & UB(GRAY))\n        v = gray_to_binary(v) ^ 1u;", ("ssi",), None),
    ("measure-eb-mask", "firmware/measure.c", "(((uint32_t)1 << eb) - 1u)", "(((uint32_t)1 << eb) - 2u)", ALL, None),
    # protective reactions (4.8, 6.3)
    ("protect-ferr-compare", "firmware/motion_supervise.c", "if (x->ferr > mf || x->ferr < -mf) {",
     "if (x->ferr > mf + 1 || x->ferr < -mf) {", ALL, None),
    ("protect-soft-limit", "firmware/motion_supervise.c", "} else if (x->linear && (x->pos > x->lp || x->pos < x->ln)) {",
     "} else if (x->linear && (x->pos > x->lp + 1 || x->pos < x->ln)) {", ALL, None),
    ("protect-hard-limit", "firmware/supervise.c", "    0, UB(HWL_P), UB(HWL_N), UB(HWL_P) | UB(HWL_N),",
     "    0, UB(HWL_N), UB(HWL_P), UB(HWL_P) | UB(HWL_N),", ALL, None),
    ("protect-drive-fault", "firmware/supervise.c", "        axis_error(n, UB(DR_F), ERR_LOGICAL);",
     "        axis_error(n, UB(DR_F), ERR_SYNTAX);", ALL, None),
    # the command path
    ("cmd-counter", "firmware/cmd.c", "hal_wr32(DPC_COMMANDS, ++n_commands);", "hal_wr32(DPC_COMMANDS, n_commands++);",
     ALL, "DPC_COMMANDS is a diagnostic count outside what the lane compares (the axis data, outputs and "
     "responses); tests/system/test_counters.py checks it"),
]


def lanes_for(path):
    """the witness lane covers the kernels' files (tests/witness/kernels.txt)"""
    srcs = set()
    for line in open(os.path.join(ROOT, "tests", "witness", "kernels.txt")):
        f = line.split("#")[0].split()
        if len(f) >= 2:
            srcs.add(f[1])
    return ["differential"] + (["witness"] if path in srcs or path.startswith("firmware/servo") else [])


def sh(cmd, cwd, log):
    with open(log, "a") as f:
        f.write("$ %s\n" % " ".join(cmd))
        f.flush()
        return subprocess.run(cmd, cwd=cwd, stdout=f, stderr=subprocess.STDOUT).returncode


def prepare(tmp):
    """a copy of the tree's tracked files, with this tree's EPROM images,
    mac4sim, Musashi objects and the witness' 68000 side as they are built"""
    files = subprocess.run(["git", "-C", ROOT, "ls-files"], capture_output=True, text=True,
                           check=True).stdout.split("\n")
    for f in files:
        if not f or f.startswith(("tests/conformance/vectors/", "tests/fuzz/corpus/", "docs/images/")):
            continue
        src = os.path.join(ROOT, f)
        if not os.path.isfile(src):
            continue
        dst = os.path.join(tmp, f)
        os.makedirs(os.path.dirname(dst), exist_ok=True)
        shutil.copy2(src, dst)
    b = os.path.join(tmp, "build")
    for sub in ("musashi", "eprom"):
        shutil.copytree(os.path.join(BUILD, sub), os.path.join(b, sub))
    for f in ("mac4sim", "commands.json"):
        shutil.copy2(os.path.join(BUILD, f), os.path.join(b, f))
    os.makedirs(os.path.join(b, "witness"))
    shutil.copy2(os.path.join(BUILD, "witness", "witness-m68k"), os.path.join(b, "witness", "witness-m68k"))


def make_args():
    # Musashi's patched source of this tree; the 68000 side of everything stays as built
    mus = os.path.join(BUILD, "deps", "musashi")
    return ["make", "-j2", "B=build", "MUS=%s" % mus, "-o", os.path.join(mus, ".stamp"),
            "-o", "build/mac4sim", "-o", "build/witness/witness-m68k"] + \
        [x for c in ALL for x in ("-o", "build/eprom/mac4-%s.bin" % c)]


def build(tmp, cards, lanes, log):
    targets = ["build/mac4sim-native-%s" % c for c in cards] if "differential" in lanes else []
    if "witness" in lanes:
        targets.append("build/witness/witness-native")
    return sh(make_args() + targets, tmp, log) == 0


def run_lane(tmp, lane, cards, log):
    if lane == "witness":
        return sh([sys.executable, "-m", "pytest", "-q", "-x", "-p", "no:cacheprovider", "tests/witness"], tmp, log)
    ks = " or ".join(cards)
    return sh([sys.executable, "-m", "pytest", "-q", "-x", "-p", "no:cacheprovider", "tests/differential",
               "-k", ks], tmp, log)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("-k", default="", help="only mutations whose name contains this (or one of these, comma-separated)")
    ap.add_argument("--list", action="store_true")
    ap.add_argument("--check", action="store_true", help="only check that each text occurs once in its file")
    ap.add_argument("--keep", action="store_true", help="keep the temporary tree (its path is printed)")
    a = ap.parse_args()
    chosen = [m for m in MUTATIONS if any(k in m[0] for k in a.k.split(","))]
    if a.list:
        for name, path, *_ in chosen:
            print("%-26s %s" % (name, path))
        return 0
    if not chosen:
        print("mutate.py: no mutation matches '%s'" % a.k, file=sys.stderr)
        return 2
    stale = [(name, path, open(os.path.join(ROOT, path)).read().count(old)) for name, path, old, *_ in chosen]
    stale = [s for s in stale if s[2] != 1]
    for name, path, n in stale:
        print("mutate.py: %s: the text to change occurs %d times in %s" % (name, n, path), file=sys.stderr)
    if a.check:
        return 1 if stale else 0
    if stale:
        return 2
    for need in ("mac4sim", "witness/witness-m68k", "deps/musashi/.stamp"):
        if not os.path.exists(os.path.join(BUILD, need)):
            print("mutate.py: build/%s missing: run `make all native witness-bins` first" % need, file=sys.stderr)
            return 2
    tmp = tempfile.mkdtemp(prefix="mac4-mutate-")
    log = os.path.join(tmp, "mutate.log")
    prepare(tmp)
    # the unmutated native builds first: every lane must pass on them
    if not build(tmp, ALL, ["differential", "witness"], log) or \
            run_lane(tmp, "differential", ALL, log) or run_lane(tmp, "witness", ALL, log):
        print("mutate.py: the lanes fail without a mutation (%s)" % log, file=sys.stderr)
        return 2
    caught, survivors, unexplained = 0, [], 0
    for name, path, old, new, cards, why in chosen:
        t0 = time.time()
        f = os.path.join(tmp, path)
        orig = open(f).read()
        open(f, "w").write(orig.replace(old, new))
        lanes = lanes_for(path)
        by = []
        try:
            # one card of those it concerns (each build links the whole
            # emulator), then the next lane only while it survives
            for lane in lanes:
                if not build(tmp, cards[:1], [lane], log):
                    by.append("build")
                elif run_lane(tmp, lane, cards[:1], log):
                    by.append(lane)
                if by:
                    break
        finally:
            open(f, "w").write(orig)
            now = time.time()
            os.utime(f, (now, now))          # newer than the mutant's objects: rebuilt next time
        dt = time.time() - t0
        if by:
            caught += 1
            print("caught    %-26s %-20s by %s (%.0f s)" % (name, path, ", ".join(by), dt), flush=True)
        else:
            survivors.append((name, path, why))
            unexplained += why is None
            print("SURVIVED  %-26s %-20s %s (%.0f s)" % (name, path, why or "NO REASON GIVEN", dt), flush=True)
    print("\n%d mutations, %d caught, %d survived (%d without a reason)" % (len(chosen), caught, len(survivors),
                                                                             unexplained))
    for name, path, why in survivors:
        print("  survivor %s (%s): %s" % (name, path, why or "none given: a scenario is missing"))
    if a.keep:
        print("temporary tree: %s" % tmp)
    else:
        shutil.rmtree(tmp, ignore_errors=True)
    return 1 if unexplained else 0


if __name__ == "__main__":
    sys.exit(main())
