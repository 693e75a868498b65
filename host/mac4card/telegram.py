"""The front-panel serial telegrams of manual 3.3 and 7.3.1: DLE STX, the
seven data bytes (axis, code, parameter big-endian) with every $10 doubled,
the checksum (the low byte of their sum)."""
from dataclasses import dataclass

from .dictionary import Mac4Error

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
