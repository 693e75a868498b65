"""The command dictionary: build/commands.json (generated from
firmware/commands.def and firmware/status.def), checked and indexed.
Everything the package knows about commands, status bits, error codes and
modes comes from there."""
import json
import os
import re
from dataclasses import dataclass, field

from .paths import find_dictionary


class Mac4Error(Exception):
    """A problem the user has to fix (bad command, parameter, dictionary)."""


# The one reader of numbers (mac4host's command line and batch files, the
# package's string parameters).  The same syntax as mac4sim's script reader,
# stricter: no '+', no sign where the field cannot be negative.
_INTEGER = re.compile(r"(-?)(?:0[xX]([0-9A-Fa-f]+)|\$([0-9A-Fa-f]+)|([0-9]+))")
_FRACTION = re.compile(r"[0-9]+(?:\.[0-9]+)?|\.[0-9]+")
S32_MIN, U32_MAX = -(1 << 31), 0xFFFFFFFF
_SYMBOLS = {S32_MIN: "-2^31", (1 << 31) - 1: "2^31-1", U32_MAX: "2^32-1"}


def _show(tok):
    """A token for an error message: printable, at most 40 characters."""
    t = tok if len(tok) <= 40 else tok[:37] + "..."
    return "'%s'" % t.encode("unicode_escape").decode("ascii").replace("'", "\\'")


def _span(lo, hi):
    def f(v):
        if isinstance(v, float):
            return str(int(v)) if v.is_integer() else "%g" % v
        return _SYMBOLS.get(v, str(v))
    return "%s..%s" % (f(lo), f(hi))


def parse_number(tok, what="number", lo=S32_MIN, hi=U32_MAX, fraction=False):
    """A number from text, checked against its field's range lo..hi (default:
    any 32-bit word, signed or unsigned).

    Integers: decimal digits (a leading zero is still decimal: 0100 is one
    hundred), or hexadecimal 0x.. / $..; a leading '-' only where lo < 0.
    Nothing else: no '+', no 0b/0o, no '_', no blanks, no fraction, no
    exponent, no other characters.  fraction=True (times): decimal digits
    with an optional decimal fraction (2, 0.5, .5), no sign, no hex, no
    exponent, no nan/inf; returns a float.  Anything else raises Mac4Error
    naming `what`."""
    s = tok if isinstance(tok, str) else str(tok)
    if fraction:
        if not _FRACTION.fullmatch(s):
            raise Mac4Error("bad %s %s: expected a decimal number of %s (digits, "
                            "optionally a decimal fraction)" % (what, _show(s), _span(lo, hi)))
        v = float(s) if len(s) <= 40 else float("inf")
    else:
        m = _INTEGER.fullmatch(s)
        if not m:
            raise Mac4Error("bad %s %s: expected decimal digits or 0x../$.. hex" % (what, _show(s)))
        neg, digits = m.group(1), m.group(2) or m.group(3) or m.group(4)
        if neg and lo >= 0:
            raise Mac4Error("bad %s %s: no sign here (%s)" % (what, _show(s), _span(lo, hi)))
        digits = digits.lstrip("0") or "0"
        if len(digits) > 20:                      # far beyond any field: no huge ints
            raise Mac4Error("%s %s out of %s" % (what, _show(s), _span(lo, hi)))
        v = int(digits, 10 if m.group(4) else 16)
        v = -v if neg else v
    if not lo <= v <= hi:
        raise Mac4Error("%s %s out of %s" % (what, _show(s), _span(lo, hi)))
    return v


def looks_like_number(tok):
    """Whether a token is meant as a number (mnemonics begin with a letter),
    so that a malformed one is reported as a bad number."""
    return str(tok)[:1] in tuple("0123456789-+$.")


def is_number(tok):
    """Whether parse_number takes tok as a 32-bit word."""
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
        check_dictionary(data, path or "dictionary")
        self.cards = dict(data["cards"])                # name -> card type number (VER)
        self.status = data["status"]
        self.errors = {e["code"]: e for e in data["errors"]}
        self.aliases = {k.upper(): v.upper() for k, v in data.get("aliases", {}).items()}
        self.not_implemented = data.get("not_implemented")
        words = [k for k, v in self.status.items()
                 if isinstance(v, list) and v and "bit" in v[0]]
        self.status_words = words                       # user, system, overall
        # the user status bits that mean an error (status.h US_ERRORS), and
        # the overall status bits of the errors that carry the overall status
        self.user_error_bits = list(data.get("user_error_bits") or
                                    [e["status_bit"] for e in data["errors"]
                                     if e["status_word"] == "user"])
        self.overall_error_bits = [e["status_bit"] for e in data["errors"]
                                   if e["status_word"] == "overall"]
        self.commands = []
        for c in data["commands"]:
            raw = dict(c)
            raw["_status_words"] = words
            self.commands.append(Command(c["mnemonic"], c["code"], c["kind"],
                                         list(c["cards"]), c.get("description", ""), raw))
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
        if looks_like_number(tok):
            code = parse_number(tok, "code", 0, 0xFFFF)
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
    def bit_keys(self, word):
        """(key, entry) of every entry of a status word.  The key is the
        manual's name, or NAME@BIT where the manual gives one name to several
        bits of the word (system status bits 10 and 22, both dr_disable,
        7.1.2), so that each bit stays a key of its own."""
        entries = [b for b in self.status[word] if "bit" in b]
        seen = {}
        for b in entries:
            seen[b["name"]] = seen.get(b["name"], 0) + 1
        return [("%s@%d" % (b["name"], b["bit"]) if seen[b["name"]] > 1 else b["name"], b)
                for b in entries]

    def decode_status(self, word, value):
        """Decode a status word: {"word", "value", "hex", "fields", "bits",
        "bit_descriptions", "bit_numbers", "undefined_bits"}.  "bits" lists the
        keys of the bits set (bit_keys(): the name, NAME@BIT for a name the
        manual gives to several bits), "bit_numbers" their bit numbers.  A
        field of several bits (the user status' mode, bits 0-7) is named from
        the dictionary's list of the same name plus "s" ("mode" -> "modes")."""
        if word not in self.status_words:
            raise Mac4Error("unknown status word '%s' (one of: %s)"
                            % (word, ", ".join(self.status_words)))
        value &= 0xFFFFFFFF
        fields, bits, descs, numbers, covered = {}, [], {}, {}, 0
        for key, b in self.bit_keys(word):
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
                bits.append(key)
                descs[key] = b.get("description", "")
                numbers[key] = b["bit"]
        undefined = [i for i in range(32) if value >> i & 1 and not covered >> i & 1]
        return {"word": word, "value": value, "hex": "0x%08X" % value, "fields": fields,
                "bits": bits, "bit_descriptions": descs, "bit_numbers": numbers,
                "undefined_bits": undefined}

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
    """Read and check a command dictionary (default: build/commands.json of
    the checkout, or $MAC4_COMMANDS).  Any problem is a Mac4Error of one line."""
    path = path or find_dictionary()
    try:
        with open(path, encoding="utf-8") as f:
            data = json.load(f)
    except FileNotFoundError:
        raise Mac4Error("%s not found: run `make all` in the repository first (or give --dict)"
                        % path) from None
    except IsADirectoryError:
        raise Mac4Error("%s is a directory, not a command dictionary" % path) from None
    except UnicodeDecodeError as e:
        raise Mac4Error("%s: not UTF-8 text (byte $%02X at offset %d)"
                        % (path, e.object[e.start], e.start)) from None
    except RecursionError:
        raise Mac4Error("%s: not a MAC4 command dictionary (nested too deeply)" % path) from None
    except (OSError, ValueError) as e:
        raise Mac4Error("%s: %s" % (path, e)) from None
    return Dictionary(data, path)


# ---- the dictionary's shape ----------------------------------------------------------

def _kind(v):
    if isinstance(v, bool):
        return "true/false"
    return {dict: "an object", list: "a list", str: "a string", int: "a number",
            float: "a number", type(None): "null"}.get(type(v), type(v).__name__)


def check_dictionary(data, name="dictionary"):
    """That `data` has the shape tools/gen_commands.c writes, every field
    this package reads of the type it reads; else Mac4Error naming the
    first field that is not."""
    def bad(where, what, v):
        raise Mac4Error("%s: not a MAC4 command dictionary (%s: expected %s, found %s)"
                        % (name, where, what, _kind(v)))

    def obj(v, where):
        if not isinstance(v, dict):
            bad(where, "an object", v)
        return v

    def lst(v, where):
        if not isinstance(v, list):
            bad(where, "a list", v)
        return v

    def string(v, where):
        if not isinstance(v, str):
            bad(where, "a string", v)
        return v

    def integer(v, where, lo=None, hi=None):
        if isinstance(v, bool) or not isinstance(v, int):
            bad(where, "a whole number", v)
        if (lo is not None and v < lo) or (hi is not None and v > hi):
            raise Mac4Error("%s: not a MAC4 command dictionary (%s: %d outside %d..%d)"
                            % (name, where, v, lo, hi))
        return v

    def need(o, key, where):
        if key not in o:
            raise Mac4Error("%s: not a MAC4 command dictionary (%s: no \"%s\")"
                            % (name, where, key))
        return o[key]

    obj(data, "the top level")
    for k, v in obj(need(data, "cards", "top level"), "cards").items():
        integer(v, "cards.%s" % k, 0, 255)
    status = obj(need(data, "status", "top level"), "status")
    for word, bits in status.items():
        for i, b in enumerate(lst(bits, "status.%s" % word)):
            w = "status.%s[%d]" % (word, i)
            obj(b, w)
            if "bit" in b:
                integer(b["bit"], w + ".bit", 0, 31)
                string(need(b, "name", w), w + ".name")
                if "width" in b:
                    integer(b["width"], w + ".width", 1, 32 - b["bit"])
                if "description" in b:
                    string(b["description"], w + ".description")
            else:
                integer(need(b, "code", w), w + ".code")
                string(need(b, "name", w), w + ".name")
    words = [k for k, v in status.items() if v and "bit" in v[0]]
    for i, e in enumerate(lst(need(data, "errors", "top level"), "errors")):
        w = "errors[%d]" % i
        obj(e, w)
        integer(need(e, "code", w), w + ".code", 0, 0xFFFF)
        string(need(e, "status_bit", w), w + ".status_bit")
        string(need(e, "description", w), w + ".description")
        if need(e, "status_word", w) not in words:
            raise Mac4Error("%s: not a MAC4 command dictionary (%s.status_word: '%s' is not a "
                            "status word)" % (name, w, e["status_word"]))
    for k, v in obj(data.get("aliases", {}), "aliases").items():
        string(v, "aliases.%s" % k)
    if data.get("not_implemented") is not None:
        integer(data["not_implemented"], "not_implemented", 0, 0xFFFF)
    if "user_error_bits" in data:
        for i, b in enumerate(lst(data["user_error_bits"], "user_error_bits")):
            string(b, "user_error_bits[%d]" % i)
    for i, c in enumerate(lst(need(data, "commands", "top level"), "commands")):
        w = "commands[%d]" % i
        obj(c, w)
        string(need(c, "mnemonic", w), w + ".mnemonic")
        w = "commands[%d] (%s)" % (i, c["mnemonic"])
        integer(need(c, "code", w), w + ".code", 0, 0xFFFF)
        string(need(c, "kind", w), w + ".kind")
        for j, k in enumerate(lst(need(c, "cards", w), w + ".cards")):
            string(k, "%s.cards[%d]" % (w, j))
        if "description" in c:
            string(c["description"], w + ".description")
        for key in ("range", "units", "default"):
            if key in c and c[key] is not None:
                for k, v in obj(c[key], "%s.%s" % (w, key)).items():
                    ww = "%s.%s.%s" % (w, key, k)
                    if key == "range":
                        if len(lst(v, ww)) != 2:
                            bad(ww, "a list [low, high]", v)
                        integer(v[0], ww + "[0]")
                        integer(v[1], ww + "[1]")
                    elif key == "units":
                        string(v, ww)
        if "parameter" in c:
            string(c["parameter"], w + ".parameter")
        if "mode" in c:
            integer(c["mode"], w + ".mode")
