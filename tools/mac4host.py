#!/usr/bin/env python3
"""mac4host - a command-line client for the MACCON MAC4 axis controller.

Talks to the emulated card (build/mac4sim, its host script on a pipe) or to a
card's front-panel serial line (manual 3.3: 4800 baud 8N1, DLE STX telegrams)
through pyserial: a device, the emulator's pty, socket://HOST:PORT or
rfc2217://...; sends commands by mnemonic or number and explains what the
card answers.  See docs/host-client.md.

A thin layer over the Python package `mac4card` (host/mac4card/ of the checkout):
everything it knows about commands, status bits, error codes and modes comes
from build/commands.json through it.  The package's names are re-exported,
so `import mac4host` keeps working:

    from mac4host import load_dictionary, encode_telegram, TelegramDecoder
    d = load_dictionary()
    d.resolve("WAP").code                        -> 70
    encode_telegram(0, 70, 16).hex(" ")          -> '10 02 00 00 46 00 00 00 10 10 56'
"""
import argparse
import json
import os
import re
import sys
from dataclasses import dataclass

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
sys.path.insert(0, os.path.join(ROOT, "host"))      # the package, from the checkout

from mac4card import (ChecksumError, Command, Dictionary, Garbage, Mac4Error, Nak,  # noqa: E402,F401
                  SerialTransport, SimTransport, Telegram, TelegramDecoder, TransportError,
                  checksum, encode_telegram, find_dictionary, find_sim, is_number,
                  load_dictionary, looks_like_number, parse_number, read_fault_record, s32,
                  telegram_data)

DEFAULT_DICT = find_dictionary()
DEFAULT_SIM = find_sim()

# Exit statuses (docs/host-client.md); argparse's own 2 for a bad option is
# turned into EXIT_USAGE (Parser below), so 2 always means the transport.
EXIT_OK, EXIT_USAGE, EXIT_TRANSPORT, EXIT_CARD_ERROR, EXIT_INTERRUPTED = 0, 1, 2, 3, 130
WAIT_MAX_MS = 3600000           # a batch `wait`: at most an hour, as mac4sim's `run`
BATCH_MAX_BYTES = 1 << 20       # some 100000 commands; read no further


class BatchError(Mac4Error):
    """A batch file's fault, already worded `FILE:LINE: message`."""


# ---- the client ------------------------------------------------------------------

# emulator lines that say the card restarted (a watchdog reset after a fault,
# MR, the reset button) or stopped at "F." after an unexpected exception (J11 out)
RESTART = re.compile(r"(?:@\S+ )?(reset \w+|display F\.)")

@dataclass
class Step:
    axis: int
    cmd: Command
    param: int
    token: str = ""
    wait_ms: int = None         # a `wait MS` line of a batch file instead of a command


class Client:
    def __init__(self, dictionary, transport, card=None, json_out=False, out=None,
                 verbose=False):
        self.d = dictionary
        self.t = transport
        self.card = card
        self.json = json_out
        self.out = out or sys.stdout
        self.verbose = verbose
        self.card_errors = 0
        self.results = []
        self.fault_records = []
        self.restarted = None       # the line that said the card restarted, until looked at

    def emit(self, obj, text):
        if self.json:
            print(json.dumps(obj), file=self.out, flush=True)
        else:
            print(text, file=self.out, flush=True)

    def event(self, source, text):
        self.emit({"type": "event", "source": source, "text": text}, "%s: %s" % (source, text))
        m = RESTART.fullmatch(text) if source == "sim" else None
        if m:
            self.restarted = m.group(1)           # the latest: "reset watchdog" after "F."

    def fault_record(self, trigger):
        """Print the card's fault record (DPRAM $4010-$401C, count $4068) if
        the card has one; nothing where the transport does not reach the
        DPRAM (a serial line)."""
        if not getattr(self.t, "dpram", False):
            return None
        rec = read_fault_record(self.t.peek32)
        if rec is not None:
            self.fault_records.append(rec)
            self.emit(dict(type="fault_record", trigger=trigger, **rec),
                      "fault record: %s" % rec["text"])
        return rec

    def check_faults(self, step=None):
        """After a status read (RAS, RBS, RSS) or once the card has restarted."""
        trigger, self.restarted = self.restarted, None
        if trigger is None and step is not None and step.cmd is not None \
                and step.cmd.is_read and step.cmd.status_word():
            trigger = step.cmd.mnemonic
        if trigger is not None:
            self.fault_record(trigger)

    def run(self, steps):
        errors = set(self.d.errors)
        for s in steps:
            if s.wait_ms is not None:
                self.t.wait(s.wait_ms)
                self.check_faults()
                continue
            if self.verbose:
                self.emit({"type": "sent", "axis": s.axis, "code": s.cmd.code, "param": s.param},
                          "> %d %s(%d) 0x%08X" % (s.axis, s.cmd.mnemonic, s.cmd.code,
                                                   s.param & 0xFFFFFFFF))
            a, c, v = self.t.transact(s.axis, s.cmd.code, s.param,
                                      is_ours=lambda a, c, s=s: c == s.cmd.code or c in errors)
            sent = s.cmd if not s.cmd.mnemonic.startswith("#") else None
            ex = dict(type="response", **self.d.explain(a, c, v, card=self.card, sent=sent))
            ex["sent"] = {"axis": s.axis, "code": s.cmd.code, "param": s.param & 0xFFFFFFFF,
                          "mnemonic": s.cmd.mnemonic}
            if c in errors:
                self.card_errors += 1
            self.results.append(ex)
            self.emit(ex, "%-22s %s" % (ex["raw"], ex["text"]))
            self.check_faults(s)
        return self.results


def parse_param(dictionary, cmd, tok, card):
    v = parse_number(tok, "parameter for %s" % cmd.mnemonic)      # any 32-bit word
    cards = [card] if card else cmd.cards
    for c in cards:
        r = cmd.range(c)
        if r and not r[0] <= s32(v) <= r[1] and not r[0] <= v <= r[1]:
            print("mac4host: note: %s %s is outside %d..%d on MAC4-%s; the card will answer "
                  "a limit value error" % (cmd.mnemonic, tok, r[0], r[1], c.upper()),
                  file=sys.stderr)
            break
    return v


def parse_axis(tok):
    try:
        return parse_number(tok, "axis", 0, 255)
    except Mac4Error as e:
        raise Mac4Error("%s (the wire numbers of the axes are 0-3)" % e) from None


def parse_send_args(dictionary, tokens, card=None):
    """AXIS CMD [PARAM] [CMD [PARAM]]...: CMD is a mnemonic/alias or a code; a
    number right after a command is its parameter, any other number starts the
    next command (so `70 16 59 0` is WAP 16, MP 0)."""
    if len(tokens) < 2:
        raise Mac4Error("send needs AXIS and at least one command")
    axis = parse_axis(tokens[0])
    steps, i = [], 1
    while i < len(tokens):
        tok = tokens[i]
        cmd = dictionary.resolve(tok, card)
        param = 0
        if i + 1 < len(tokens) and looks_like_number(tokens[i + 1]):
            param = parse_param(dictionary, cmd, tokens[i + 1], card)
            i += 1
        elif cmd.takes_parameter:
            print("mac4host: note: %s without a parameter, sending 0" % cmd.mnemonic,
                  file=sys.stderr)
        steps.append(Step(axis, cmd, param, tok))
        i += 1
    return steps


def read_batch_file(path):
    """The lines of a batch file ('-': standard input), which must be UTF-8
    text (ASCII in practice) of at most BATCH_MAX_BYTES."""
    name = "stdin" if path == "-" else path
    try:
        if path == "-":
            data = sys.stdin.buffer.read(BATCH_MAX_BYTES + 1)
        else:
            with open(path, "rb") as f:
                data = f.read(BATCH_MAX_BYTES + 1)
    except IsADirectoryError:
        raise Mac4Error("%s: is a directory, not a batch file" % name) from None
    except OSError as e:
        raise Mac4Error("%s: %s" % (name, e.strerror or e)) from None
    if len(data) > BATCH_MAX_BYTES:                # /dev/zero, a disk image: not a batch
        raise Mac4Error("%s: more than %d bytes: not a batch file" % (name, BATCH_MAX_BYTES))
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as e:
        line = data.count(b"\n", 0, e.start) + 1
        raise BatchError("%s:%d: not UTF-8 text (byte $%02X at offset %d)"
                         % (name, line, data[e.start], e.start)) from None
    if "\0" in text:
        line = text.count("\n", 0, text.index("\0")) + 1
        raise BatchError("%s:%d: a NUL byte: not a text file" % (name, line))
    return text.splitlines(), name


def parse_batch(dictionary, lines, card=None, name="-"):
    """One command a line, `AXIS CMD [PARAM]` (a leading `send` is allowed, so
    mac4sim `send` lines work), `wait MS` to let time pass, `#` comments."""
    steps = []
    for n, line in enumerate(lines, 1):
        toks = line.split("#", 1)[0].split()
        if not toks:
            continue
        try:
            if toks[0].lower() == "send":
                toks = toks[1:]
            if toks and toks[0].lower() in ("wait", "run", "sleep"):
                if len(toks) != 2:
                    raise Mac4Error("%s needs MS (0..%d)" % (toks[0].lower(), WAIT_MAX_MS))
                ms = parse_number(toks[1], "wait time (ms)", 0, WAIT_MAX_MS)
                steps.append(Step(0, None, 0, wait_ms=ms))
                continue
            if not 2 <= len(toks) <= 3:
                raise Mac4Error("expected AXIS CMD [PARAM]")
            steps += parse_send_args(dictionary, toks, card)
        except Mac4Error as e:
            raise BatchError("%s:%d: %s" % (name, n, e)) from None
    return steps


# ---- CLI ---------------------------------------------------------------------------

def fmt_range(cmd, card):
    r = cmd.range(card)
    if not r:
        return ""
    def f(v):
        return {-(1 << 31): "-2^31", (1 << 31) - 1: "2^31-1"}.get(v, str(v))
    return "%s..%s" % (f(r[0]), f(r[1]))


def cmd_dict(d, args):
    flt = (args.filter or "").upper()
    rows = []
    for c in sorted(d.commands, key=lambda c: c.code):
        if args.card and args.card not in c.cards:
            continue
        if flt and flt not in c.mnemonic.upper() and flt not in c.description.upper() \
                and flt != str(c.code) and flt not in c.kind.upper():
            aliases = [a for a, t in d.aliases.items() if t == c.mnemonic.upper()]
            if not any(flt in a for a in aliases):
                continue
        rows.append(c)
    if args.json:
        out = []
        for c in rows:
            o = {k: v for k, v in c.raw.items() if not k.startswith("_")}
            al = [a for a, t in d.aliases.items() if t == c.mnemonic.upper()]
            if al:
                o["aliases"] = al
            out.append(o)
        print(json.dumps(out, indent=1))
        return EXIT_OK
    cards = [args.card] if args.card else list(d.cards)
    for c in rows:
        al = [a for a, t in d.aliases.items() if t == c.mnemonic.upper()]
        head = "%-7s %3d  %-12s %-12s %s" % (c.mnemonic, c.code, c.kind, ",".join(c.cards),
                                             c.description)
        if al:
            head += "  (alias %s)" % ", ".join(al)
        if "mode" in c.raw:
            head += "  [mode %d %s]" % (c.raw["mode"], d.mode_name(c.raw["mode"]) or "")
        print(head)
        per = {}                                   # text -> cards, identical ones grouped
        for k in cards:
            if k not in c.cards:
                continue
            bits = []
            rg = fmt_range(c, k)
            if rg:
                bits.append("range " + rg)
            if k in (c.raw.get("default") or {}):
                bits.append("default %s" % c.raw["default"][k])
            u = (c.raw.get("units") or {}).get(k)
            if u:
                bits.append("units " + u)
            if bits:
                per.setdefault(", ".join(bits), []).append(k)
        per = ["%s: %s" % ("/".join(ks), text) for text, ks in per.items()]
        flags = [f for f in ("system", "immediate", "card_wide") if c.raw.get(f)]
        if c.raw.get("parameter"):
            flags.insert(0, "<%s>" % c.raw["parameter"].lower())
        if per or flags:
            print("%22s%s" % ("", "; ".join(([" ".join(flags)] if flags else []) + per)))
    if not rows:
        print("no command matches", file=sys.stderr)
        return EXIT_USAGE
    return EXIT_OK


def cmd_decode(d, args):
    what = args.what.lower()
    if what == "response":
        if len(args.values) != 2:
            raise Mac4Error("decode response CODE PARAM")
        code = parse_number(args.values[0], "code", 0, 0xFFFF)
        param = parse_number(args.values[1], "parameter")
        axis = parse_axis(args.axis)
        ex = d.explain(axis, code, param, card=args.card)
        if args.json:
            print(json.dumps(ex, indent=1))
        else:
            print("%s  %s" % (ex["raw"], ex["text"]))
            if "status" in ex:
                print_status(ex["status"])
        return EXIT_OK
    if what not in d.status_words:
        raise Mac4Error("decode %s: one of %s, response"
                        % (what, ", ".join(d.status_words)))
    if len(args.values) != 1:
        raise Mac4Error("decode %s VALUE" % what)
    st = d.decode_status(what, parse_number(args.values[0], "status word", 0, 0xFFFFFFFF))
    if args.json:
        print(json.dumps(st, indent=1))
    else:
        print("%s  (%s)" % (d.status_summary(st), st["hex"]))
        print_status(st)
    return EXIT_OK


def print_status(st):
    for name, f in st["fields"].items():
        print("  bits %-5s %-10s = %d%s" % (f["bits"], name, f["value"],
                                           " (%s)" % f["name"] if f.get("name") else ""))
    v = st["value"]
    for name in st["bits"]:
        print("  %-16s %s" % (name, st["bit_descriptions"].get(name, "")))
    for b in st["undefined_bits"]:
        print("  bit %-12d (not defined)" % b)
    if not st["bits"] and not st["undefined_bits"] and not v:
        print("  (no bits set)")


def open_transport(args, on_event):
    if args.serial:
        return SerialTransport(args.serial, on_event=on_event,
                               timeout=args.timeout if args.timeout else 2.0,
                               retries=args.retries)
    return SimTransport(card=args.sim_card, sim_path=args.sim_path, sim_args=args.sim_arg or [],
                        on_event=on_event, max_ms=args.sim_max_ms,
                        timeout=args.timeout if args.timeout else 30.0)


def cmd_send(d, args, steps):
    client = Client(d, None, card=args.card, json_out=args.json, verbose=args.verbose)
    t = open_transport(args, on_event=client.event)
    client.t = t
    try:
        t.open()
        client.check_faults()                     # a restart while it booted
        client.run(steps)
    except TransportError as e:
        if client.restarted:                      # why, if the card can still tell
            try:
                client.check_faults()
            except TransportError:
                pass
        print("mac4host: %s" % e, file=sys.stderr)
        t.close()
        return EXIT_TRANSPORT
    rc = t.close()
    if rc not in (0, None):
        return EXIT_TRANSPORT
    return EXIT_CARD_ERROR if client.card_errors else EXIT_OK


class Parser(argparse.ArgumentParser):
    """argparse exits 2 on a bad option; 2 is mac4host's transport failure,
    so option errors exit EXIT_USAGE like every other usage error."""

    def error(self, message):
        self.print_usage(sys.stderr)
        self.exit(EXIT_USAGE, "%s: error: %s\n" % (self.prog, message))


def number_option(what, lo, hi, fraction=False):
    """An option's value through parse_number (argparse's type=)."""
    def convert(tok):
        try:
            return parse_number(tok, "value", lo, hi, fraction)
        except Mac4Error as e:
            raise argparse.ArgumentTypeError(str(e)) from None
    convert.__name__ = what             # argparse names it in some messages
    return convert


def build_parser():
    common = Parser(add_help=False)
    S = argparse.SUPPRESS
    common.add_argument("--dict", dest="dict", metavar="PATH", default=S,
                        help="command dictionary (default build/commands.json)")
    common.add_argument("--json", action="store_true", default=S,
                        help="machine-readable output (JSON; one object a line for send/batch)")
    common.add_argument("--card", choices=("inc", "ssi", "stp"), default=S,
                        help="card type: filters `dict`, checks commands exist, picks units; "
                             "with the emulator the same as --sim")
    common.add_argument("--sim", dest="sim", choices=("inc", "ssi", "stp"), default=S,
                        help="talk to build/mac4sim emulating this card (the default, inc)")
    common.add_argument("--sim-path", default=S, metavar="PATH", help="the emulator binary")
    common.add_argument("--sim-arg", action="append", default=S, metavar="ARG",
                        help="extra mac4sim option (repeatable), e.g. --sim-arg=--timestamps")
    common.add_argument("--sim-max-ms", type=number_option("--sim-max-ms", 1, WAIT_MAX_MS, True),
                        default=S, metavar="MS",
                        help="emulated time to wait for a response (default 2000)")
    common.add_argument("--serial", metavar="PORT", default=S,
                        help="talk over a serial line (4800 8N1) through pyserial: a device "
                             "(/dev/ttyS0, the pty of mac4sim --serial-pty) or a URL "
                             "(socket://127.0.0.1:PORT for mac4sim --serial-tcp, rfc2217://...)")
    common.add_argument("--timeout", type=number_option("--timeout", 0.001, 3600, True),
                        default=S, metavar="S",
                        help="wall-clock seconds to wait for an answer (serial 2, sim 30)")
    common.add_argument("--retries", type=number_option("--retries", 0, 100), default=S,
                        metavar="N",
                        help="serial: send again this often after a NAK (default 2)")
    common.add_argument("-v", "--verbose", action="store_true", default=S,
                        help="also print each command as it is sent")

    p = Parser(
        prog="mac4host", parents=[common],
        description="Host client for the MACCON MAC4 axis controller: the command dictionary, "
                    "status decoding, and commands over the emulator or a serial line.",
        epilog="Numbers: decimal (a leading 0 is still decimal), 0x.. or $.. hex, '-' where "
               "a value may be negative. Exit status: 0 ok, 1 usage error (a bad option or "
               "number, an unknown command, a bad batch line), 2 no answer/transport failure, "
               "3 the card answered an error code (160-165), 130 interrupted. "
               "See docs/host-client.md.")
    sub = p.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True

    sp = sub.add_parser("dict", parents=[common], help="print the command dictionary",
                        description="Print the command dictionary, optionally only the "
                                    "commands of one card (--card) or matching FILTER (a "
                                    "substring of mnemonic, kind or description, or a code).")
    sp.add_argument("filter", nargs="?", metavar="FILTER")

    sp = sub.add_parser("decode", parents=[common], help="decode a status word or a response",
                        description="decode user|system|overall VALUE: the bits of a status "
                                    "word (user: also the mode). decode response CODE PARAM: "
                                    "what a response means.")
    sp.add_argument("what", metavar="user|system|overall|response")
    sp.add_argument("values", nargs="+", metavar="VALUE")
    sp.add_argument("--axis", default="0", help="axis of the response (decode response)")

    sp = sub.add_parser("send", parents=[common], help="send commands to one axis",
                        description="send AXIS CMD [PARAM] [CMD [PARAM]]... CMD is a mnemonic "
                                    "(or alias) or a code number; a number right after a "
                                    "command is its parameter (default 0).")
    sp.add_argument("tokens", nargs="+", metavar="ARG")

    sp = sub.add_parser("batch", parents=[common], help="send commands from a file ('-': stdin)",
                        description="One command a line: AXIS CMD [PARAM] (a leading 'send' is "
                                    "allowed); 'wait MS' lets time pass; '#' starts a comment.")
    sp.add_argument("file", metavar="FILE")
    return p


# Defaults of the options every subcommand takes too (before or after its name).
# Not set_defaults(): the parsers share the option objects, whose default must
# stay SUPPRESS so a subcommand does not overwrite what came before its name.
DEFAULTS = dict(dict=None, json=False, card=None, sim=None, sim_path=None, sim_arg=None,
                sim_max_ms=2000.0, serial=None, timeout=None, retries=2, verbose=False)


def parse_args(argv=None):
    args = build_parser().parse_args(argv)
    for k, v in DEFAULTS.items():
        if not hasattr(args, k):
            setattr(args, k, v)
    return args


def main(argv=None):
    args = parse_args(argv)
    try:
        return _main(args)
    except BrokenPipeError:                       # `mac4host dict | head`
        try:
            sys.stdout = open(os.devnull, "w")
        except OSError:
            pass
        return EXIT_OK


def _main(args):
    try:
        d = load_dictionary(args.dict)
        if args.command == "dict":
            return cmd_dict(d, args)
        if args.command == "decode":
            return cmd_decode(d, args)
        if args.serial and args.sim:
            raise Mac4Error("--sim and --serial exclude each other")
        if args.sim and args.card and args.sim != args.card:
            raise Mac4Error("--sim %s and --card %s disagree" % (args.sim, args.card))
        if not args.serial:
            args.sim_card = args.sim or args.card or "inc"
            args.card = args.sim_card
        if args.command == "send":
            steps = parse_send_args(d, args.tokens, args.card)
        else:
            lines, name = read_batch_file(args.file)
            steps = parse_batch(d, lines, args.card, name)
        return cmd_send(d, args, steps)
    except BatchError as e:                       # FILE:LINE: message, as compilers and mac4sim
        print(e, file=sys.stderr)
        return EXIT_USAGE
    except Mac4Error as e:
        print("mac4host: %s" % e, file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        return EXIT_INTERRUPTED


if __name__ == "__main__":
    sys.exit(main())
