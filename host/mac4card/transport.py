"""Ways to a card: the emulator's host script on a pipe (SimTransport) and
a serial line through pyserial (SerialTransport): a device (/dev/ttyS0, the
emulator's pty), or any URL pyserial opens (socket://HOST:PORT for the
emulator's --serial-tcp or a serial-to-TCP server, rfc2217://HOST:PORT).

Both have transact(axis, code, param, is_ours) -> (axis, code, param),
wait(ms) and clock() (seconds of the card's time).  `dpram` says whether
the transport reaches the card's DPRAM (peek32): the emulator's host script
does, a serial line does not."""
import os
import select
import subprocess
import time

from .paths import find_sim
from .telegram import (ChecksumError, Garbage, Nak, Telegram, TelegramDecoder,
                       encode_telegram)


class TransportError(Exception):
    """The card or the emulator did not answer as it should."""


class _Transport:
    """A transport is a context manager: opened on entry, closed on exit."""

    def __enter__(self):
        self.open()
        return self

    def __exit__(self, *exc):
        self.close()


class SimTransport(_Transport):
    """build/mac4sim with its host script on a pipe.  transact() writes
    `send AXIS CODE PARAM`, `run MS` and an `echo` marker and reads stdout up to
    the marker, running more emulated time until the response comes or
    `max_ms` of emulated time have passed.  Other lines go to on_event."""

    name = "sim"
    dpram = True

    def __init__(self, card="inc", sim_path=None, sim_args=(), on_event=None,
                 step_ms=5, max_ms=2000, timeout=30.0):
        self.card = card
        self.sim_path = sim_path or find_sim()
        self.sim_args = list(sim_args)
        self.on_event = on_event or (lambda src, text: None)
        self.step_ms, self.max_ms, self.timeout = step_ms, max_ms, timeout
        self.proc = None
        self.marker = 0
        self.buf = {"out": b"", "err": b""}
        self.emulated_ms = 0.0         # emulated time run since the card booted
        self.lines = []
        self.eof = False

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

    def _script(self, *cmds, keep=("resp ", "timeout ")):
        """Write script lines plus a marker; return the stdout lines up to it
        that begin with one of `keep` (resp and timeout lines); everything
        else, stderr too, goes to on_event."""
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
                if src == "out" and core.startswith(keep):
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
            self.emulated_ms += float(cmds[-1].split()[1])
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

    def clock(self):
        """Seconds of the card's time: emulated time."""
        return self.emulated_ms / 1000.0

    def peek32(self, offsets):
        """The DPRAM's 32-bit words at these offsets, read as the VME host
        reads them (the script's peek32; no emulated time passes)."""
        got = {}
        for line in self._script(*["peek32 0x%04X" % o for o in offsets],
                                 keep=("peek32 ", "resp ")):
            p = line.split()
            if p[0] == "peek32" and len(p) == 3:
                got[int(p[1], 16)] = int(p[2], 16)
            else:
                self.on_event("sim", "unsolicited " + line)
        missing = [o for o in offsets if o not in got]
        if missing:
            raise TransportError("mac4sim did not answer peek32 0x%04X" % missing[0])
        return [got[o] for o in offsets]

    def wait(self, ms):
        self.emulated_ms += ms
        for line in self._script("run %g" % ms):
            self.on_event("sim", "unsolicited " + line if line.startswith("resp") else line)


class SerialTransport(_Transport):
    """A serial line at 4800 baud 8N1 (manual 3.3) through pyserial:
    `device` is anything serial.serial_for_url() opens."""

    name = "serial"
    dpram = False               # the front-panel line carries telegrams only (manual 3.3)

    def __init__(self, device, on_event=None, timeout=2.0, retries=2, double_dle_checksum=False):
        self.device = device
        self.on_event = on_event or (lambda src, text: None)
        self.timeout, self.retries = timeout, retries
        self.double_dle_checksum = double_dle_checksum
        self.port = None
        self.dec = TelegramDecoder()
        self.pending = []

    def open(self):
        try:
            import serial
        except ImportError:
            raise TransportError("a serial line needs pyserial: python3 -m pip install "
                                 "pyserial==3.5 (tools/deps/python.txt)") from None
        self._serial = serial
        url = self.device
        if url.startswith("tcp://"):             # as QEMU and socat write it
            url = "socket://" + url[len("tcp://"):]
        # no flow control: the MAC4's connector has none (manual 3.3)
        opts = dict(baudrate=4800, bytesize=serial.EIGHTBITS, parity=serial.PARITY_NONE,
                    stopbits=serial.STOPBITS_ONE, xonxoff=False, rtscts=False, dsrdtr=False,
                    timeout=0)
        # a bound on writes where the port has one (pyserial's rfc2217 has none)
        if not url.startswith("rfc2217:"):
            opts["write_timeout"] = self.timeout + 1.0
        try:
            self.port = serial.serial_for_url(url, **opts)
            self.port.reset_input_buffer()
        except (serial.SerialException, ValueError, OSError, NotImplementedError) as e:
            self.port = None
            raise TransportError("cannot open %s: %s" % (self.device, _why(e))) from None

    def close(self):
        if self.port is not None:
            try:
                self._pump(0.05)
            except TransportError:
                pass
            for ev in self.dec.flush():
                self._report(ev)
            self.port.close()
            self.port = None

    def _pump(self, timeout):
        try:
            self.port.timeout = max(timeout, 0)
            chunk = self.port.read(1)
            if chunk and self.port.in_waiting:
                chunk += self.port.read(self.port.in_waiting)
        except (self._serial.SerialException, OSError, NotImplementedError) as e:
            raise TransportError("%s: %s" % (self.device, _why(e))) from None
        if not chunk:
            return False
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
        try:
            self.port.write(data)
            self.port.flush()
        except (self._serial.SerialException, OSError, NotImplementedError) as e:
            raise TransportError("%s: cannot write: %s" % (self.device, _why(e))) from None

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

    def clock(self):
        """Seconds of the card's time: wall-clock time on a real line."""
        return time.monotonic()

    def wait(self, ms):
        end = time.monotonic() + ms / 1000.0
        while time.monotonic() < end:
            self._pump(end - time.monotonic())
            while self.pending:
                self._report(self.pending.pop(0))


def _why(e):
    """An exception's message without pyserial's repetitions."""
    if isinstance(e, OSError) and e.strerror:
        return e.strerror
    text = str(e) or type(e).__name__
    return text.split(": ", 1)[1] if text.startswith("[Errno") and ": " in text else text


def open_transport(where, on_event=None, timeout=None, retries=2, sim_args=(), max_ms=2000):
    """A transport from a name: "sim" or "sim:CARD" starts an emulated card
    (build/mac4sim, default inc); anything else is a serial port or URL for
    pyserial ("/dev/ttyS0", "socket://127.0.0.1:PORT", "tcp://...",
    "rfc2217://...").  Not opened yet."""
    if where == "sim" or where.startswith("sim:"):
        card = where[4:] or "inc"
        if card not in ("inc", "ssi", "stp"):
            raise TransportError("sim:%s: the emulated cards are inc, ssi and stp" % card)
        return SimTransport(card=card, sim_args=sim_args, on_event=on_event, max_ms=max_ms,
                            timeout=timeout or 30.0)
    return SerialTransport(where, on_event=on_event, timeout=timeout or 2.0, retries=retries)
