"""A MAC4 card as a host program sees it: commands by mnemonic, answers
decoded by name, status words as sets of bit names, waiting for an event,
and the error rules of manual 6.3 (docs/host-client.md, "The Python package").

Axes are the wire numbers 0-3 the card uses (the manual counts them 1-4:
axis 0 is the manual's axis 1).
"""
from dataclasses import dataclass, field

from .dictionary import Mac4Error, load_dictionary, parse_number
from .faults import read_fault_record
from .transport import TransportError, open_transport


class Timeout(TimeoutError):
    """An event did not come within its time; .status is the last status read."""

    def __init__(self, text, status=None):
        super().__init__(text)
        self.status = status


@dataclass
class Status:
    """A status word decoded: `bits` the names of the bits set, `mode` the
    mode's name (user status), `value` the word.  A name the manual gives to
    several bits of a word is NAME@BIT in `bits` (dr_disable@10,
    dr_disable@22 of the system status); `"dr_disable" in status` is true
    for either, `"dr_disable@22" in status` for that bit only."""
    word: str
    value: int
    bits: frozenset
    mode: str = None
    fields: dict = field(default_factory=dict, repr=False)

    def __contains__(self, name):
        return name in self.bits or any(b.split("@", 1)[0] == name for b in self.bits)

    def __str__(self):
        return "%s status 0x%08X%s: %s" % (self.word, self.value,
                                          " mode %s" % self.mode if self.mode else "",
                                          " ".join(sorted(self.bits)) or "-")


def _status(st):
    mode = st["fields"].get("mode", {}).get("name")
    return Status(st["word"], st["value"], frozenset(st["bits"]), mode, st["fields"])


@dataclass
class Response:
    """One answer of the card.  `sent` is the mnemonic it answers, `mnemonic`
    that of the code answered (None for an error code), `meaning` one of
    "status", "value", "status-read", "error"; `value` for a read, `status`
    the status word it carries (a Status), `error` the error's entry of the
    dictionary (code, status_bit, description, status_word)."""
    axis: int
    code: int
    param: int
    sent: str
    meaning: str
    text: str
    mnemonic: str = None
    value: int = None
    units: str = None
    status: Status = None
    error: dict = None
    version: dict = None

    @property
    def ok(self):
        return self.error is None


class CardError(Exception):
    """The card reported an error (manual 6.3): an error code as the answer to
    a command, or error bits in a status word read while waiting.

    code           160-165, or None when found in a status word
    bits           the error bits set
    response       the Response that carried it (None from a status word)
    raised_by_card True for an error the card raised by itself (drive fault,
                   following error, encoder error, watchdog, emergency stop):
                   the command it answered was not executed (6.3.4-6.3.9);
                   False for the command's own fault (false axis, syntax,
                   limit value, logical error)
    acknowledged   True once a C has been answered without an error
    """

    def __init__(self, text, code=None, bits=(), response=None, raised_by_card=False,
                 axis=None):
        super().__init__(text)
        self.code, self.bits, self.response = code, frozenset(bits), response
        self.raised_by_card, self.axis = raised_by_card, axis
        self.acknowledged = False


class Card:
    """A connected card.  Use connect(); or Card(transport).open().

    ack_errors  (default True) acknowledge every error with C at once, as
                6.3 requires before the card accepts further commands, then
                raise CardError
    retry       (default False) after an error the card raised by itself
                (not the command's fault) and its acknowledgement, send the
                command that got it once more instead of raising
    """

    def __init__(self, transport, dictionary=None, card=None, ack_errors=True, retry=False):
        self.t = transport
        self.d = dictionary if dictionary is not None else load_dictionary()
        self.card = card
        self.version = None
        self.ack_errors, self.retry = ack_errors, retry
        self.errors = []                      # every CardError seen, oldest first
        self._status_read = {w: self._find_status_read(w) for w in self.d.status_words}

    # -- connection --
    def open(self):
        self.t.open()
        if self.card is None:                 # the card type, from VER (table 6.1)
            r = self.command("VER")
            self.version = r.version
            card = r.version and r.version.get("card")
            self.card = card if card in self.d.cards else None
        return self

    def close(self):
        return self.t.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    # -- commands --
    def _find_status_read(self, word):
        for c in self.d.commands:
            if c.is_read and c.status_word() == word:
                return c
        return None

    def _transact(self, cmd, param, axis):
        errors = set(self.d.errors)
        a, c, v = self.t.transact(axis, cmd.code, param,
                                  is_ours=lambda a, c: c == cmd.code or c in errors)
        ex = self.d.explain(a, c, v, card=self.card, sent=cmd)
        st = ex.get("status")
        return Response(a, c, v, cmd.mnemonic, ex["meaning"], ex["text"], ex.get("mnemonic"),
                        ex.get("value"), ex.get("units"), _status(st) if st else None,
                        ex.get("error"), ex.get("version"))

    def resolve(self, mnemonic):
        return self.d.resolve(mnemonic, self.card)

    def command(self, mnemonic, param=0, axis=0):
        """Send one command (a mnemonic, an alias, or a code) and return its
        Response.  An error answer is handled by the 6.3 rules (class doc)
        and raised as CardError."""
        cmd = self.resolve(mnemonic)
        if isinstance(param, str):
            param = parse_number(param, "parameter for %s" % cmd.mnemonic)
        if not -(1 << 31) <= param <= 0xFFFFFFFF:
            raise Mac4Error("parameter %d for %s does not fit 32 bits" % (param, cmd.mnemonic))
        r = self._transact(cmd, param, axis)
        if r.ok:
            return r
        err = self._error(r)
        if self.ack_errors and cmd.mnemonic != "C":
            self.acknowledge(0 if r.code == 160 else axis, err)
        if self.retry and err.raised_by_card and err.acknowledged:
            r2 = self._transact(cmd, param, axis)
            if r2.ok:
                return r2
            err = self._error(r2)
            if self.ack_errors:
                self.acknowledge(0 if r2.code == 160 else axis, err)
        raise err

    send = command

    def _card_bits(self):
        """The error bits of errors the card raises by itself: the user status'
        error bits beyond those of the command's own errors (syntax, limit,
        logical: encoder_f, dr_f, ferr_f), and the overall status' error bits
        but the false axis number (watch_f, h_stop)."""
        own = {e["status_bit"] for e in self.d.errors.values() if e["status_word"] == "user"}
        return (set(self.d.user_error_bits) - own) | (set(self.d.overall_error_bits) - {"axis_f"})

    def _error(self, r):
        e = r.error
        bits = set(r.status.bits) & (set(self.d.user_error_bits) | set(self.d.overall_error_bits))
        err = CardError("axis %d: %s answered error %d (%s): %s | %s"
                        % (r.axis, r.sent, r.code, e["status_bit"], e["description"],
                           r.status), r.code, bits, r, bool(bits & self._card_bits()), r.axis)
        self.errors.append(err)
        return err

    def acknowledge(self, axis=0, err=None):
        """C (6.3): acknowledge an error.  A pending error may come as the
        answer to this C; then one more C.  Returns the last Response; sets
        err.acknowledged when a C was answered without an error."""
        c = self.resolve("C")
        r = None
        for _ in range(2):
            r = self._transact(c, 0, axis)
            if r.ok:
                if err is not None:
                    err.acknowledged = True
                return r
        return r

    def read(self, mnemonic, axis=0):
        """A read command's value (signed where the dictionary says so)."""
        r = self.command(mnemonic, 0, axis)
        if r.meaning == "status-read":
            return r.status.value
        if r.meaning != "value":
            raise Mac4Error("%s is not a read command (it answered %s)" % (r.sent, r.meaning))
        return r.value

    def status(self, axis=0, word="user"):
        """A status word (user: RBS, system: RSS, overall: RAS) as a Status."""
        cmd = self._status_read.get(word)
        if cmd is None:
            raise Mac4Error("no read command for the %s status in the dictionary" % word)
        return self.command(cmd.mnemonic, 0, axis).status

    def fault_record(self):
        """The card's fault record (mac4card.faults.decode_fault_record: vector,
        exception, pc, sr, address, count, text), or None when the card has
        recorded no fault since power-on.  It lives in the DPRAM: a transport
        that does not reach it (a serial line) raises Mac4Error."""
        if not getattr(self.t, "dpram", False):
            raise Mac4Error("the fault record is in the card's DPRAM, which a %s transport "
                            "does not reach" % getattr(self.t, "name", "this"))
        return read_fault_record(self.t.peek32)

    # -- events --
    def wait_for(self, bit, axis=0, timeout=10.0, poll_ms=10):
        """Read the user and the overall status until `bit` (a user or overall
        status bit, e.g. "pos_end") is set and return the user status.  Any
        error bit on the way (the user status' error bits, or the overall
        status' h_stop, watch_f, axis_f) raises CardError (acknowledged with C
        when ack_errors); `timeout` seconds of the card's time (emulated time
        on an emulated card) without it raise Timeout."""
        words = {w: {b["name"] for b in self.d.status[w] if "bit" in b}
                 for w in ("user", "overall")}
        if bit not in words["user"] | words["overall"]:
            raise Mac4Error("'%s' is not a bit of the user or overall status" % bit)
        t0 = self.t.clock()
        while True:
            user = self.status(axis, "user")
            overall = self.status(axis, "overall")
            bad = (user.bits & set(self.d.user_error_bits)) | \
                (overall.bits & set(self.d.overall_error_bits))
            if bad:
                err = CardError("axis %d: error %s while waiting for %s | %s | %s"
                                % (axis, " ".join(sorted(bad)), bit, user, overall),
                                None, bad, None, bool(bad & self._card_bits()), axis)
                self.errors.append(err)
                if self.ack_errors:
                    self.acknowledge(axis, err)
                raise err
            if bit in user or bit in overall:
                return user
            if self.t.clock() - t0 >= timeout:
                raise Timeout("axis %d: no %s within %g s | %s" % (axis, bit, timeout, user),
                              user)
            self.t.wait(poll_ms)


def connect(where="sim:inc", dictionary=None, card=None, timeout=None, retries=2,
            ack_errors=True, retry=False, on_event=None, sim_args=()):
    """Open a card and return it (a Card; use it in a `with`).

    where  "sim:inc", "sim:ssi", "sim:stp": an emulated card started for it
           (build/mac4sim); a serial device ("/dev/ttyS0", the emulator's
           pty); or a pyserial URL ("socket://127.0.0.1:PORT" for
           `mac4sim --serial-tcp`, "rfc2217://HOST:PORT")
    card   the card type; by default the emulator's, or VER's answer
    on_event(source, text) gets what else the card or emulator reports."""
    d = dictionary if dictionary is not None else load_dictionary()
    t = open_transport(where, on_event=on_event, timeout=timeout, retries=retries,
                       sim_args=sim_args)
    if card is None and getattr(t, "card", None):
        card = t.card
    c = Card(t, d, card, ack_errors=ack_errors, retry=retry)
    try:
        return c.open()
    except BaseException:
        try:
            t.close()
        except (TransportError, OSError):
            pass
        raise
