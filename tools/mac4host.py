#!/usr/bin/env python3
"""mac4host - a host-side client for the MACCON MAC4 axis controller.

Talks to the emulated card (build/mac4sim, its host script on a pipe) or to a
card's front-panel serial line (manual 3.3: 4800 baud 8N1, DLE STX telegrams),
sends commands by mnemonic or number and explains what the card answers.

Everything it knows about commands, status bits, error codes and modes comes
from build/commands.json (generated from firmware/commands.def and
firmware/status.def); nothing of it is written down here.  See
docs/host-client.md.

Usable as a module:

    from mac4host import load_dictionary, encode_telegram, TelegramDecoder
    d = load_dictionary()
    d.resolve("WAP").code                        -> 70
    encode_telegram(0, 70, 16).hex(" ")          -> '10 02 00 00 46 00 00 00 10 10 56'
    d.explain(0, 70, 0x02000101)["text"]         -> 'WAP: user status mode enable; dr_en on_fly'
    with SimTransport(card="inc") as t: t.transact(0, 7, 0)
"""
import argparse
import json
import os
import select
import subprocess
import sys
import time
from dataclasses import dataclass, field

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
DEFAULT_DICT = os.path.join(ROOT, "build", "commands.json")
DEFAULT_SIM = os.path.join(ROOT, "build", "mac4sim")

EXIT_OK, EXIT_USAGE, EXIT_TRANSPORT, EXIT_CARD_ERROR = 0, 1, 2, 3


class Mac4Error(Exception):
    """A problem the user has to fix (bad command, parameter, dictionary)."""


class TransportError(Exception):
    """The card or the emulator did not answer as it should."""


def parse_number(tok, what="number"):
    """Decimal (signed), 0x.. or $.. hexadecimal, 0b.. binary."""
    s = str(tok).strip().replace("_", "")
    neg = s.startswith("-")
    body = s[1:] if neg or s.startswith("+") else s
    try:
        if body.startswith("$"):
            v = int(body[1:], 16)
        elif body[:2].lower() in ("0x", "0b", "0o"):
            v = int(body, 0)
        else:
            v = int(body, 10)
    except ValueError:
        raise Mac4Error("bad %s '%s' (decimal, 0x.. or $.. hex)" % (what, tok)) from None
    return -v if neg else v


def is_number(tok):
    try:
        parse_number(tok)
        return True
    except Mac4Error:
        return False


def s32(v):
    v &= 0xFFFFFFFF
    return v - (1 << 32) if v & 0x80000000 else v


# ---- the command dictionary ------------------------------------------------------

@dataclass
class Command:
    mnemonic: str
    code: int
    kind: str
    cards: list
    description: str
    raw: dict = field(repr=False, default_factory=dict)

    @property
    def is_read(self):
        """A read command: the card answers the value instead of the user status (3.4)."""
        return self.kind.startswith("read") or self.kind == "diagnosis"

    @property
    def takes_parameter(self):
        return bool(self.raw.get("takes_parameter")) or self.kind.startswith("write")

    def on_card(self, card):
        return card is None or card in self.cards

    def range(self, card):
        r = self.raw.get("range") or {}
        if card in r:
            return tuple(r[card])
        return None

    def units(self, card=None):
        u = self.raw.get("units") or {}
        if card in u:
            return u[card]
        vals = set(u.values())
        if len(vals) == 1:
            return vals.pop()
        return None

    def signed(self):
        """Whether a value this command reads is a signed quantity: the range
        reaches below zero (positions, velocities), or, for the diagnosis reads
        without a range, anything that is not a bit field or an address."""
        r = self.raw.get("range")
        if r:
            return any(lo < 0 for lo, _ in r.values())
        return self.status_word() is None and self.units() not in ("address",)

    def status_word(self):
        """For a read that answers a status word (RAS, RBS, RSS): which one,
        found from its description ("overall status (7.1.3)") and the status
        words the dictionary defines; else None."""
        words = self.raw.get("_status_words") or ()
        desc = self.description.lower()
        for w in words:
            if "%s status" % w in desc:
                return w
        return None


class Dictionary:
    """build/commands.json, indexed."""

    def __init__(self, data, path=None):
        self.path = path
        self.data = data
        try:
            self.cards = dict(data["cards"])            # name -> card type number (VER)
            self.status = data["status"]
            self.errors = {e["code"]: e for e in data["errors"]}
            self.aliases = {k.upper(): v.upper() for k, v in data.get("aliases", {}).items()}
            self.not_implemented = data.get("not_implemented")
            words = [k for k, v in self.status.items()
                     if isinstance(v, list) and v and "bit" in v[0]]
            self.status_words = words                   # user, system, overall
            self.commands = []
            for c in data["commands"]:
                raw = dict(c)
                raw["_status_words"] = words
                self.commands.append(Command(c["mnemonic"], int(c["code"]), c["kind"],
                                             list(c["cards"]), c.get("description", ""), raw))
        except (KeyError, TypeError, ValueError) as e:
            raise Mac4Error("%s: not a MAC4 command dictionary (%s)" % (path or "dictionary", e))
        self.by_mnemonic = {c.mnemonic.upper(): c for c in self.commands}
        self.by_code = {c.code: c for c in self.commands}

    # -- lookup --
    def lookup(self, mnemonic):
        m = mnemonic.upper()
        m = self.aliases.get(m, m)
        return self.by_mnemonic.get(m)

    def resolve(self, token, card=None):
        """A mnemonic (or alias, any case) or a code number -> Command.  A number
        the dictionary does not know (e.g. 1, to provoke error 161) gives a bare
        Command of kind "unknown" named "#CODE".  A mnemonic the dictionary does
        not know, or one `card` does not have, raises Mac4Error."""
        tok = str(token).strip()
        if is_number(tok):
            code = parse_number(tok, "code")
            if not 0 <= code <= 0xFFFF:
                raise Mac4Error("code %s out of 0..65535" % tok)
            c = self.by_code.get(code)
            if c is not None:
                return c
            return Command("#%d" % code, code, "unknown", [], "not in the dictionary", {})
        c = self.lookup(tok)
        if c is None:
            near = sorted(m for m in list(self.by_mnemonic) + list(self.aliases)
                          if m.startswith(tok.upper()[:2]))
            hint = ("; similar: " + " ".join(near[:12])) if near else ""
            raise Mac4Error("unknown mnemonic '%s'%s (see: mac4host dict)" % (tok, hint))
        if not c.on_card(card):
            raise Mac4Error("%s (code %d) does not exist on MAC4-%s (cards: %s); "
                            "give the code number to send it anyway"
                            % (c.mnemonic, c.code, card.upper(), ", ".join(c.cards)))
        return c

    def mode_name(self, code):
        for m in self.status.get("modes", []):
            if m["code"] == code:
                return m["name"]
        return None

    # -- decoding --
    def decode_status(self, word, value):
        """Decode a status word: {"word", "value", "hex", "fields", "bits",
        "bit_descriptions", "undefined_bits"}.  A field of several bits (the
        user status' mode, bits 0-7) is named from the dictionary's list of the
        same name plus "s" ("mode" -> "modes")."""
        if word not in self.status_words:
            raise Mac4Error("unknown status word '%s' (one of: %s)"
                            % (word, ", ".join(self.status_words)))
        value &= 0xFFFFFFFF
        fields, bits, descs, covered = {}, [], {}, 0
        for b in self.status[word]:
            width = b.get("width", 1)
            mask = ((1 << width) - 1) << b["bit"]
            covered |= mask
            v = (value & mask) >> b["bit"]
            if width > 1:
                f = {"value": v, "bits": "%d-%d" % (b["bit"], b["bit"] + width - 1)}
                table = self.status.get(b["name"] + "s")
                if isinstance(table, list):
                    names = [m["name"] for m in table if m.get("code") == v]
                    f["name"] = names[0] if names else None
                fields[b["name"]] = f
            elif v:
                bits.append(b["name"])
                descs[b["name"]] = b.get("description", "")
        undefined = [i for i in range(32) if value >> i & 1 and not covered >> i & 1]
        return {"word": word, "value": value, "hex": "0x%08X" % value, "fields": fields,
                "bits": bits, "bit_descriptions": descs, "undefined_bits": undefined}

    @staticmethod
    def status_summary(st):
        parts = []
        for name, f in st["fields"].items():
            parts.append("%s %s" % (name, f["name"] if f.get("name") else f["value"]))
        bits = " ".join(st["bits"]) or "-"
        s = "%s status %s" % (st["word"], "; ".join(parts + [bits]))
        if st["undefined_bits"]:
            s += " (undefined bits %s)" % ",".join(map(str, st["undefined_bits"]))
        return s

    def decode_version(self, value):
        """VER (manual table 6.1): card type, hardware release letter, version."""
        card_no = value >> 24 & 0xFF
        names = [n for n, v in self.cards.items() if v == card_no]
        hw = value >> 16 & 0xFF
        return {"card": names[0] if names else card_no,
                "hardware_release": chr(hw) if 0x20 < hw < 0x7F else hw,
                "software": "%d.%d" % (value >> 8 & 0xFF, value & 0xFF)}

    def explain(self, axis, code, param, card=None, sent=None):
        """What a response (axis, code, param) means.  `sent` is the Command
        this answers, if known.  Returns a dict with "text" for people."""
        param &= 0xFFFFFFFF
        out = {"axis": axis, "code": code, "param": param,
               "raw": "%d %d 0x%08X" % (axis, code, param)}
        if sent is not None:
            out["sent"] = sent.mnemonic
        if code in self.errors:
            e = self.errors[code]
            st = self.decode_status(e["status_word"], param)
            out.update(meaning="error", error={"code": code, "status_bit": e["status_bit"],
                                               "description": e["description"],
                                               "status_word": e["status_word"]},
                       status=st)
            text = "error %d (%s) %s | %s" % (code, e["status_bit"], e["description"],
                                              self.status_summary(st))
            if sent is not None and sent.code != code:
                text += " [answering %s]" % sent.mnemonic
            out["text"] = text
            return out
        cmd = self.by_code.get(code)
        name = cmd.mnemonic if cmd else "code %d" % code
        if cmd is not None:
            out["mnemonic"] = cmd.mnemonic
        if cmd is not None and cmd.is_read:
            word = cmd.status_word()
            if word:
                st = self.decode_status(word, param)
                out.update(meaning="status-read", status=st)
                out["text"] = "%s: %s" % (name, self.status_summary(st))
                return out
            value = s32(param) if cmd.signed() else param
            units = cmd.units(card)
            out.update(meaning="value", value=value, units=units)
            text = "%s: value %d (0x%08X)%s" % (name, value, param,
                                                 " " + units if units and units != "-" else "")
            if cmd.kind == "read" and "version" in cmd.description.lower():
                ver = self.decode_version(param)
                out["version"] = ver
                text = "%s: 0x%08X = MAC4-%s, hardware release %s, software %s" % (
                    name, param, str(ver["card"]).upper(), ver["hardware_release"],
                    ver["software"])
            out["text"] = text
            return out
        st = self.decode_status("user", param)
        out.update(meaning="status", status=st)
        if cmd is None and code == self.not_implemented:
            name += " (not implemented)"
        out["text"] = "%s: %s" % (name, self.status_summary(st))
        return out


def load_dictionary(path=None):
    path = path or DEFAULT_DICT
    try:
        with open(path) as f:
            data = json.load(f)
    except FileNotFoundError:
        raise Mac4Error("%s not found: run `make all` in the repository first (or give --dict)"
                        % path) from None
    except (OSError, ValueError) as e:
        raise Mac4Error("%s: %s" % (path, e)) from None
    return Dictionary(data, path)


# ---- serial telegrams (manual 3.3, 7.3.1) ------------------------------------------

DLE, STX, NAK = 0x10, 0x02, 0x15


def telegram_data(axis, code, param):
    """The 7 data bytes: axis, code MSB, LSB, parameter big-endian."""
    if not 0 <= axis <= 0xFF:
        raise Mac4Error("axis %d out of 0..255" % axis)
    if not 0 <= code <= 0xFFFF:
        raise Mac4Error("code %d out of 0..65535" % code)
    return bytes([axis, code >> 8 & 0xFF, code & 0xFF]) + (param & 0xFFFFFFFF).to_bytes(4, "big")


def checksum(data):
    """Low byte of the sum of the data bytes (doubled DLEs not counted)."""
    return sum(data) & 0xFF


def encode_telegram(axis, code, param=0, double_dle_checksum=False):
    """DLE STX, the 7 data bytes with every $10 doubled, the checksum.
    The manual doubles only data bytes; double_dle_checksum=True also doubles
    a checksum of $10 (the decoder accepts both)."""
    data = telegram_data(axis, code, param)
    out = bytearray([DLE, STX])
    for b in data:
        out.append(b)
        if b == DLE:
            out.append(DLE)
    cs = checksum(data)
    out.append(cs)
    if cs == DLE and double_dle_checksum:
        out.append(DLE)
    return bytes(out)


@dataclass
class Telegram:
    axis: int
    code: int
    param: int


@dataclass
class Nak:
    pass


@dataclass
class ChecksumError:
    axis: int
    code: int
    param: int
    received: int
    computed: int


@dataclass
class Garbage:
    data: bytes
    why: str


class TelegramDecoder:
    """Feed it bytes as they come; feed() returns the events completed by them:
    Telegram, Nak (a lone $15 between telegrams), ChecksumError, Garbage.
    A checksum of $10 may come doubled or not: a DLE right after it that does
    not start a header is dropped silently."""

    HUNT, HUNT_DLE, DATA, DATA_DLE, CSUM = range(5)

    def __init__(self):
        self.state = self.HUNT
        self.data = bytearray()
        self.junk = bytearray()
        self.free_dle = 0         # DLEs after a $10 checksum that are not garbage

    def _garbage(self, events, why):
        if self.junk:
            events.append(Garbage(bytes(self.junk), why))
            self.junk = bytearray()

    def feed(self, chunk):
        events = []
        for b in bytes(chunk):
            self._step(b, events)
        return events

    def flush(self):
        """Call after a quiet line: reports an incomplete telegram as garbage."""
        events = []
        if self.state in (self.DATA, self.DATA_DLE, self.CSUM):
            self.junk += bytes([DLE, STX]) + self.data
            self._garbage(events, "incomplete telegram")
        elif self.state == self.HUNT_DLE:
            self._drop_held_dle()
        self._garbage(events, "bytes outside a telegram")
        self.state, self.free_dle = self.HUNT, 0
        return events

    def _step(self, b, events):
        st = self.state
        if st == self.HUNT:
            if b == DLE:
                self.state = self.HUNT_DLE
            elif b == NAK:
                self._garbage(events, "bytes outside a telegram")
                events.append(Nak())
            else:
                self.junk.append(b)
        elif st == self.HUNT_DLE:
            if b == STX:
                self.free_dle = 0
                self._garbage(events, "bytes outside a telegram")
                self.state, self.data = self.DATA, bytearray()
            else:
                self._drop_held_dle()
                if b != DLE:                    # the DLE held started no header
                    self.free_dle = 0
                    self.state = self.HUNT
                    self._step(b, events)
        elif st == self.DATA:
            if b == DLE:
                self.state = self.DATA_DLE
            else:
                self._data(b)
        elif st == self.DATA_DLE:
            if b == DLE:
                self._data(DLE)
            elif b == STX:                  # a new header: the one before was cut short
                self.junk += bytes([DLE, STX]) + self.data
                self._garbage(events, "telegram cut short by a new header")
                self.state, self.data = self.DATA, bytearray()
            else:
                self.junk += bytes([DLE, STX]) + self.data + bytes([DLE, b])
                self._garbage(events, "DLE not doubled inside a telegram")
                self.state = self.HUNT
        elif st == self.CSUM:
            d = bytes(self.data)
            axis, code, param = d[0], d[1] << 8 | d[2], int.from_bytes(d[3:7], "big")
            want = checksum(d)
            if b == want:
                events.append(Telegram(axis, code, param))
            else:
                events.append(ChecksumError(axis, code, param, b, want))
            self.state = self.HUNT
            if b == DLE:
                # held as a possible header DLE; it and one doubling of it are
                # not garbage
                self.state, self.free_dle = self.HUNT_DLE, 2

    def _drop_held_dle(self):
        if self.free_dle:
            self.free_dle -= 1
        else:
            self.junk.append(DLE)

    def _data(self, b):
        self.data.append(b)
        self.state = self.CSUM if len(self.data) == 7 else self.DATA


# ---- transports ------------------------------------------------------------------

class SimTransport:
    """build/mac4sim with its host script on a pipe.  transact() writes
    `send AXIS CODE PARAM`, `run MS` and an `echo` marker and reads stdout up to
    the marker, running more emulated time until the response comes or
    `max_ms` of emulated time have passed.  Other lines go to on_event."""

    name = "sim"

    def __init__(self, card="inc", sim_path=None, sim_args=(), on_event=None,
                 step_ms=5, max_ms=2000, timeout=30.0):
        self.card = card
        self.sim_path = sim_path or DEFAULT_SIM
        self.sim_args = list(sim_args)
        self.on_event = on_event or (lambda src, text: None)
        self.step_ms, self.max_ms, self.timeout = step_ms, max_ms, timeout
        self.proc = None
        self.marker = 0
        self.buf = {"out": b"", "err": b""}
        self.lines = []
        self.eof = False

    def __enter__(self):
        self.open()
        return self

    def __exit__(self, *exc):
        self.close()

    def open(self):
        if not os.access(self.sim_path, os.X_OK):
            raise TransportError("%s not found or not executable: run `make all` (or give "
                                 "--sim-path)" % self.sim_path)
        cmd = [self.sim_path, "--card", self.card, "--script", "-"] + self.sim_args
        self.proc = subprocess.Popen(cmd, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                     stderr=subprocess.PIPE, bufsize=0)
        for f in (self.proc.stdout, self.proc.stderr):
            os.set_blocking(f.fileno(), False)
        # boot: display 1, 2, 3, 5 (manual 2.5.2)
        lines = self._script("wait-display 5")
        for l in lines:
            if l.startswith("timeout wait-display"):
                raise TransportError("the emulated card did not boot (%s)" % l)

    def close(self):
        p = self.proc
        if p is None:
            return None
        self.proc = None
        try:
            p.stdin.close()
        except OSError:
            pass
        deadline = time.monotonic() + 10
        while p.poll() is None and time.monotonic() < deadline:
            self._read_some(0.2, p)
            for src, line in self._take():
                self._event(src, line)
        if p.poll() is None:
            p.kill()
            p.wait()
        self._read_some(0, p, drain=True)
        for src, line in self._take(final=True):
            self._event(src, line)
        for f in (p.stdout, p.stderr):
            f.close()
        if p.returncode not in (0, None):
            self.on_event("sim", "mac4sim exited with status %d%s" % (
                p.returncode, " (emulator faults)" if p.returncode == 3 else ""))
        return p.returncode

    # -- plumbing --
    def _write(self, text):
        try:
            self.proc.stdin.write(text.encode())
            self.proc.stdin.flush()
        except (BrokenPipeError, OSError):
            raise TransportError("mac4sim has gone (exit status %s)" % self.proc.poll()) from None

    def _read_some(self, timeout, proc=None, drain=False):
        p = proc or self.proc
        fds = {p.stdout.fileno(): "out", p.stderr.fileno(): "err"}
        r, _, _ = select.select(list(fds), [], [], timeout) if not drain else (list(fds), 0, 0)
        got = False
        for fd in r:
            try:
                chunk = os.read(fd, 65536)
            except BlockingIOError:
                continue
            if not chunk:
                if fds[fd] == "out":
                    self.eof = True
                continue
            got = True
            key = fds[fd]
            self.buf[key] += chunk
            *full, self.buf[key] = self.buf[key].split(b"\n")
            self.lines += [(key, l.decode("latin-1").rstrip("\r")) for l in full]
        return got

    def _take(self, final=False):
        out, self.lines = self.lines, []
        if final:
            for key in ("out", "err"):
                if self.buf[key]:
                    out.append((key, self.buf[key].decode("latin-1")))
                    self.buf[key] = b""
        return out

    def _event(self, src, line):
        if not line.strip():
            return
        self.on_event("sim" if src == "out" else "sim-stderr", line)

    def _script(self, *cmds):
        """Write script lines plus a marker; return stdout lines up to it (stderr
        lines and everything go to on_event except resp lines, returned)."""
        self.marker += 1
        mark = "mac4host-sync %d" % self.marker
        self._write("".join(c + "\n" for c in cmds) + "echo %s\n" % mark)
        deadline = time.monotonic() + self.timeout
        seen = []
        while True:
            for src, line in self._take():
                if src == "out" and line == mark:
                    return seen
                core = line.split(" ", 1)[-1] if line.startswith("@") else line  # --timestamps
                if src == "out" and (core.startswith("resp ") or core.startswith("timeout ")):
                    seen.append(core)
                else:
                    self._event(src, line)
            if self.eof:
                raise TransportError("mac4sim ended (exit status %s) while running: %s"
                                     % (self.proc.wait(), " / ".join(cmds)))
            if time.monotonic() > deadline:
                raise TransportError("no answer from mac4sim within %.0f s (to: %s)"
                                     % (self.timeout, " / ".join(cmds)))
            self._read_some(0.5)

    def transact(self, axis, code, param, is_ours=None):
        """Send one command; return (axis, code, param) of its response, or
        raise TransportError.  Responses that are not ours (is_ours(axis, code)
        false) go to on_event."""
        is_ours = is_ours or (lambda a, c: c == code)
        cmds = ["send %d %d %d" % (axis, code, param & 0xFFFFFFFF), "run %g" % self.step_ms]
        ran = self.step_ms
        while True:
            found = None
            for line in self._script(*cmds):
                p = line.split()
                if p[0] == "resp" and len(p) == 4:
                    a, c, v = int(p[1]), int(p[2]), int(p[3], 16)
                    if found is None and is_ours(a, c):
                        found = (a, c, v)
                        continue
                    self.on_event("sim", "unsolicited " + line)
                else:
                    self.on_event("sim", line)
            if found:
                return found
            if ran >= self.max_ms:
                raise TransportError("no response to %d %d 0x%08X within %g ms emulated"
                                     % (axis, code, param & 0xFFFFFFFF, ran))
            step = min(self.step_ms * 10, self.max_ms - ran)
            cmds = ["run %g" % step]
            ran += step

    def wait(self, ms):
        for line in self._script("run %g" % ms):
            self.on_event("sim", "unsolicited " + line if line.startswith("resp") else line)


class SerialTransport:
    """A serial device (the card's front panel, or mac4sim --serial-pty),
    4800 baud 8N1 raw through termios."""

    name = "serial"

    def __init__(self, device, on_event=None, timeout=2.0, retries=2, double_dle_checksum=False):
        self.device = device
        self.on_event = on_event or (lambda src, text: None)
        self.timeout, self.retries = timeout, retries
        self.double_dle_checksum = double_dle_checksum
        self.fd = None
        self.dec = TelegramDecoder()
        self.pending = []

    def __enter__(self):
        self.open()
        return self

    def __exit__(self, *exc):
        self.close()

    def open(self):
        import termios
        try:
            fd = os.open(self.device, os.O_RDWR | os.O_NOCTTY | os.O_NONBLOCK)
        except OSError as e:
            raise TransportError("cannot open %s: %s" % (self.device, e.strerror)) from None
        try:
            a = termios.tcgetattr(fd)
            iflag, oflag, cflag, lflag, ispeed, ospeed, cc = a
            iflag &= ~(termios.IGNBRK | termios.BRKINT | termios.PARMRK | termios.ISTRIP
                       | termios.INLCR | termios.IGNCR | termios.ICRNL | termios.IXON
                       | termios.IXOFF | termios.IXANY | termios.INPCK)
            oflag &= ~termios.OPOST
            lflag &= ~(termios.ECHO | termios.ECHONL | termios.ICANON | termios.ISIG
                       | termios.IEXTEN)
            cflag &= ~(termios.CSIZE | termios.PARENB | termios.CSTOPB
                       | getattr(termios, "CRTSCTS", 0))
            cflag |= termios.CS8 | termios.CREAD | termios.CLOCAL
            cc[termios.VMIN], cc[termios.VTIME] = 0, 0
            termios.tcsetattr(fd, termios.TCSANOW,
                              [iflag, oflag, cflag, lflag, termios.B4800, termios.B4800, cc])
            termios.tcflush(fd, termios.TCIFLUSH)
        except termios.error as e:
            os.close(fd)
            raise TransportError("%s: cannot set 4800 8N1 raw: %s" % (self.device, e)) from None
        self.fd = fd

    def close(self):
        if self.fd is not None:
            self._pump(0.05)
            for ev in self.dec.flush():
                self._report(ev)
            os.close(self.fd)
            self.fd = None

    def _pump(self, timeout):
        r, _, _ = select.select([self.fd], [], [], max(timeout, 0))
        if not r:
            return False
        try:
            chunk = os.read(self.fd, 256)
        except (BlockingIOError, InterruptedError):
            return True
        except OSError as e:
            raise TransportError("%s: %s" % (self.device, e.strerror)) from None
        if not chunk:
            raise TransportError("%s: closed by the other side" % self.device)
        self.pending += self.dec.feed(chunk)
        return True

    def _report(self, ev):
        if isinstance(ev, Garbage):
            self.on_event("serial", "%d byte(s) of garbage (%s): %s"
                          % (len(ev.data), ev.why, ev.data.hex(" ")))
        elif isinstance(ev, ChecksumError):
            self.on_event("serial", "response %d %d 0x%08X with a bad checksum ($%02X, "
                          "computed $%02X)" % (ev.axis, ev.code, ev.param, ev.received,
                                               ev.computed))
        elif isinstance(ev, Nak):
            self.on_event("serial", "NAK")
        elif isinstance(ev, Telegram):
            self.on_event("serial", "unsolicited response %d %d 0x%08X"
                          % (ev.axis, ev.code, ev.param))

    def _write(self, data):
        deadline = time.monotonic() + self.timeout + len(data) / 480.0
        while data:
            try:
                n = os.write(self.fd, data)
                data = data[n:]
            except BlockingIOError:
                if time.monotonic() > deadline:
                    raise TransportError("%s: cannot write" % self.device) from None
                select.select([], [self.fd], [], 0.1)

    def transact(self, axis, code, param, is_ours=None):
        is_ours = is_ours or (lambda a, c: c == code)
        tg = encode_telegram(axis, code, param, self.double_dle_checksum)
        for attempt in range(self.retries + 1):
            self._write(tg)
            deadline = time.monotonic() + self.timeout
            nak = False
            while not nak:
                while self.pending:
                    ev = self.pending.pop(0)
                    if isinstance(ev, Telegram) and is_ours(ev.axis, ev.code):
                        return ev.axis, ev.code, ev.param
                    self._report(ev)
                    if isinstance(ev, Nak):
                        nak = True
                    elif isinstance(ev, ChecksumError):
                        raise TransportError("the response to %d %d 0x%08X had a bad checksum"
                                             % (axis, code, param & 0xFFFFFFFF))
                if nak:
                    break
                left = deadline - time.monotonic()
                if left <= 0:
                    for ev in self.dec.flush():
                        self._report(ev)
                    raise TransportError("no response from %s within %.1f s to %d %d 0x%08X"
                                         % (self.device, self.timeout, axis, code,
                                            param & 0xFFFFFFFF))
                self._pump(min(left, 0.2))
            if attempt < self.retries:
                self.on_event("serial", "card answered NAK, sending again")
        raise TransportError("the card answered NAK %d times" % (self.retries + 1))

    def wait(self, ms):
        end = time.monotonic() + ms / 1000.0
        while time.monotonic() < end:
            self._pump(end - time.monotonic())
            while self.pending:
                self._report(self.pending.pop(0))


# ---- the client ------------------------------------------------------------------

@dataclass
class Step:
    axis: int
    cmd: Command
    param: int
    token: str = ""
    wait_ms: float = None       # a `wait MS` line of a batch file instead of a command


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

    def emit(self, obj, text):
        if self.json:
            print(json.dumps(obj), file=self.out, flush=True)
        else:
            print(text, file=self.out, flush=True)

    def event(self, source, text):
        self.emit({"type": "event", "source": source, "text": text}, "%s: %s" % (source, text))

    def run(self, steps):
        errors = set(self.d.errors)
        for s in steps:
            if s.wait_ms is not None:
                self.t.wait(s.wait_ms)
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
        return self.results


def parse_param(dictionary, cmd, tok, card):
    v = parse_number(tok, "parameter for %s" % cmd.mnemonic)
    if not -(1 << 31) <= v <= 0xFFFFFFFF:
        raise Mac4Error("parameter %s for %s does not fit 32 bits" % (tok, cmd.mnemonic))
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
    a = parse_number(tok, "axis")
    if not 0 <= a <= 255:
        raise Mac4Error("axis %s out of 0..255 (the card counts 0-3)" % tok)
    return a


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
        if i + 1 < len(tokens) and is_number(tokens[i + 1]):
            param = parse_param(dictionary, cmd, tokens[i + 1], card)
            i += 1
        elif cmd.takes_parameter:
            print("mac4host: note: %s without a parameter, sending 0" % cmd.mnemonic,
                  file=sys.stderr)
        steps.append(Step(axis, cmd, param, tok))
        i += 1
    return steps


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
                    raise Mac4Error("wait needs MS")
                steps.append(Step(0, None, 0, wait_ms=float(toks[1])))
                continue
            if not 2 <= len(toks) <= 3:
                raise Mac4Error("expected AXIS CMD [PARAM]")
            steps += parse_send_args(dictionary, toks, card)
        except (Mac4Error, ValueError) as e:
            raise Mac4Error("%s:%d: %s" % (name, n, e)) from None
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
        code = parse_number(args.values[0], "code")
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
    st = d.decode_status(what, parse_number(args.values[0], "status word"))
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
        client.run(steps)
    except TransportError as e:
        print("mac4host: %s" % e, file=sys.stderr)
        t.close()
        return EXIT_TRANSPORT
    rc = t.close()
    if rc not in (0, None):
        return EXIT_TRANSPORT
    return EXIT_CARD_ERROR if client.card_errors else EXIT_OK


def build_parser():
    common = argparse.ArgumentParser(add_help=False)
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
    common.add_argument("--sim-max-ms", type=float, default=S, metavar="MS",
                        help="emulated time to wait for a response (default 2000)")
    common.add_argument("--serial", metavar="DEVICE", default=S,
                        help="talk over a serial line (4800 8N1), e.g. /dev/ttyS0 or the pty "
                             "of mac4sim --serial-pty")
    common.add_argument("--timeout", type=float, default=S, metavar="S",
                        help="wall-clock seconds to wait for an answer (serial 2, sim 30)")
    common.add_argument("--retries", type=int, default=S,
                        help="serial: send again this often after a NAK (default 2)")
    common.add_argument("-v", "--verbose", action="store_true", default=S,
                        help="also print each command as it is sent")

    p = argparse.ArgumentParser(
        prog="mac4host", parents=[common],
        description="Host client for the MACCON MAC4 axis controller: the command dictionary, "
                    "status decoding, and commands over the emulator or a serial line.",
        epilog="Numbers: decimal (signed), 0x.. or $.. hex. Exit status: 0 ok, 1 usage or "
               "unknown command, 2 no answer/transport failure, 3 the card answered an "
               "error code (160-165). See docs/host-client.md.")
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
            if args.file == "-":
                lines, name = sys.stdin.read().splitlines(), "stdin"
            else:
                try:
                    with open(args.file) as f:
                        lines, name = f.read().splitlines(), args.file
                except OSError as e:
                    raise Mac4Error("%s: %s" % (args.file, e.strerror)) from None
            steps = parse_batch(d, lines, args.card, name)
        return cmd_send(d, args, steps)
    except Mac4Error as e:
        print("mac4host: %s" % e, file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        return 130


if __name__ == "__main__":
    sys.exit(main())
