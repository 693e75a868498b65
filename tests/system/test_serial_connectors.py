"""The front-panel serial line as a maintainer connects to it: a raw TCP byte
stream on 127.0.0.1 (--serial-tcp), a fixed name for the pty
(--serial-pty-link), a card that keeps running and keeps its state while
clients come and go (--serve-seconds), the client's line settings on the
pty, and the session log that replays as a host script (--serial-log).
docs/serial.md.  Every emulator started here is bounded in time and stopped."""
import os
import select
import socket
import subprocess
import sys
import time

import pytest

from conftest import BOOT, ROOT, SIM
from test_serial import EXPECTED_7_3_1, MANUAL_TELEGRAMS, encode, parse

serial = pytest.importorskip("serial")          # pyserial, tools/deps/python.txt

HOST = [sys.executable, os.path.join(ROOT, "tools", "mac4host.py")]

# The manual's 7.3.1 machine (test_serial.manual_sequence): INIT, the axis
# held at 1000, ME, E; then the card serves its line.
SETUP_7_3_1 = (BOOT + "send 0 2\nrun 5\nplant 0 motor coulomb 100\ncounter 0 1000\nrun 5\n"
               "send 0 52\nsend 0 3\nrun 50\necho ready\n")


class Card:
    """build/mac4sim with a serial connector, its first line parsed, its
    script run up to `echo ready`; stopped by close() (killed if need be)."""

    def __init__(self, args, script=BOOT + "echo ready\n", lines=1, timeout=30):
        self.p = subprocess.Popen([SIM, "--card", "inc", "--script", "-"] + list(args),
                                  stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                  stderr=subprocess.PIPE, text=True)
        self.out, self.buf = [], b""
        try:
            self.first = [self._line(timeout) for _ in range(lines)]
            self.p.stdin.write(script)
            self.p.stdin.close()
            while self._line(timeout) != "ready":
                pass
        except BaseException:
            self.kill()
            raise

    def _line(self, timeout):
        fd, end = self.p.stdout.fileno(), time.monotonic() + timeout
        while b"\n" not in self.buf:
            r, _, _ = select.select([fd], [], [], max(0, end - time.monotonic()))
            assert r, "mac4sim said nothing for %g s" % timeout
            chunk = os.read(fd, 4096)
            assert chunk, "mac4sim ended early: %s" % self.p.stderr.read()
            self.buf += chunk
        l, self.buf = self.buf.split(b"\n", 1)
        self.out.append(l.decode())
        return l.decode().strip()

    def kill(self):
        if self.p.poll() is None:
            self.p.kill()
        self.p.wait()

    def close(self, timeout=30):
        try:
            self.p.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            self.kill()
            raise
        self.out += (self.buf + self.p.stdout.buffer.read()).decode().splitlines()
        return self.p.returncode, self.out, self.p.stderr.read()


def tcp_port(card):
    w = card.first[0].split()
    assert w[0] == "serial-tcp" and 0 < int(w[1]) < 65536, card.first
    return int(w[1])


def exchange(sock, telegrams, n_answers, timeout=5.0):
    """Send each telegram, wait for its answer; the card's bytes parsed."""
    got = b""
    for i, t in enumerate(telegrams):
        sock.sendall(bytes.fromhex(t) if isinstance(t, str) else t)
        end = time.monotonic() + timeout
        while len(parse_prefix(got)) < i + 1 and time.monotonic() < end:
            r, _, _ = select.select([sock], [], [], 0.1)
            if r:
                chunk = sock.recv(256)
                assert chunk, "the card closed the connection"
                got += chunk
    items = parse(got)
    assert len(items) == n_answers, got.hex(" ")
    return items


def parse_prefix(b):
    try:
        return parse(b)
    except (AssertionError, IndexError):
        return []


def test_tcp_7_3_1_state_kept_across_reconnects():
    card = Card(["--serial-tcp", "0", "--serve-seconds", "8"], SETUP_7_3_1)
    try:
        port = tcp_port(card)
        with socket.create_connection(("127.0.0.1", port), timeout=5) as s:
            items = exchange(s, MANUAL_TELEGRAMS, 5)
        assert items == EXPECTED_7_3_1
        # a second client, later: the card kept running and kept its state
        time.sleep(0.3)
        with socket.create_connection(("127.0.0.1", port), timeout=5) as s:
            items = exchange(s, [encode(0, 71), encode(0, 116), encode(0, 125)], 3)
        rap, rcp, rbs = items
        assert rap == (0, 71, 16)                  # the target of the WAP 16 before
        assert rcp == (0, 116, 1000)
        assert rbs[1] == 125 and rbs[2] & 0xFF == 8 and rbs[2] >> 13 & 1   # positioning, syn_f
        # and a third, through pyserial's socket:// as mac4host uses it
        r = subprocess.run(HOST + ["--json", "--serial", "socket://127.0.0.1:%d" % port,
                                   "send", "0", "C", "RAP"],
                           capture_output=True, text=True, timeout=60)
        assert r.returncode == 0, r.stdout + r.stderr
        assert '"code": 4' in r.stdout and '"value": 16' in r.stdout, r.stdout
    finally:
        rc, out, err = card.close()
    assert rc == 0, err
    assert out.count("serial-tcp connected") == 3
    assert out.count("serial-tcp closed (by the client)") == 3


def test_tcp_without_serve_seconds_stops_when_the_client_closes():
    card = Card(["--serial-tcp", "0"])
    try:
        with socket.create_connection(("127.0.0.1", tcp_port(card)), timeout=5) as s:
            assert exchange(s, [encode(0, 7)], 1) == [(0, 7, 0x00440402)]
        t0 = time.monotonic()
    finally:
        rc, out, err = card.close()
    assert rc == 0 and time.monotonic() - t0 < 10


def test_tcp_second_client_is_refused_while_one_is_connected():
    card = Card(["--serial-tcp", "0"])
    try:
        port = tcp_port(card)
        with socket.create_connection(("127.0.0.1", port), timeout=5) as a:
            b = socket.create_connection(("127.0.0.1", port), timeout=5)
            b.settimeout(5)
            try:
                assert b.recv(16) == b""           # closed at once, nothing sent
            except ConnectionResetError:
                pass
            b.close()
            assert exchange(a, [encode(0, 7)], 1) == [(0, 7, 0x00440402)]
    finally:
        rc, out, err = card.close()
    assert rc == 0 and "serial-tcp refused a second client" in out


def listening(port):
    """Local addresses of the TCP sockets listening on `port` (/proc/net/tcp
    and tcp6: address and port in hex, state 0A = LISTEN)."""
    found = []
    for f in ("/proc/net/tcp", "/proc/net/tcp6"):
        if not os.path.exists(f):
            continue
        for l in open(f).read().splitlines()[1:]:
            w = l.split()
            addr, p = w[1].split(":")
            if w[3] == "0A" and int(p, 16) == port:
                found.append(addr)
    return found


def test_tcp_listens_on_loopback_only():
    card = Card(["--serial-tcp", "0", "--serve-seconds", "1"])
    try:
        assert listening(tcp_port(card)) == ["0100007F"]      # 127.0.0.1, IPv4 only
    finally:
        card.close()


@pytest.mark.parametrize("args", [["--serial-tcp", "x"], ["--serial-tcp", "70000"],
                                  ["--serial-tcp", "-1"], ["--serial-pty", "--serial-tcp", "0"],
                                  ["--serial-tcp", "0", "--serial-pty"]])
def test_bad_serial_tcp_options(args):
    r = subprocess.run([SIM] + args, capture_output=True, text=True, input="", timeout=30)
    assert r.returncode == 1 and "mac4sim:" in r.stderr and "serial-tcp" not in r.stdout


def test_pty_link_and_line_settings(tmp_path):
    link = str(tmp_path / "mac4-serial")
    card = Card(["--serial-pty-link", link, "--serve-seconds", "3"], lines=2)
    try:
        assert card.first[0].startswith("serial-pty /dev/")
        assert card.first[1] == "serial-pty-link " + link
        assert os.path.realpath(link) == card.first[0].split()[1]
        with serial.serial_for_url(link, baudrate=9600, timeout=2) as port:     # wrong speed
            port.write(encode(0, 7))
            assert parse(port.read(10)) == [(0, 7, 0x00440402)]
        time.sleep(0.3)
        with serial.serial_for_url(link, baudrate=4800, timeout=2) as port:
            port.write(encode(0, 7))
            assert parse(port.read(10)) == [(0, 7, 0x00440402)]
    finally:
        rc, out, err = card.close()
    assert rc == 0, err
    assert "serial-pty line 9600 8N1 (not the card's 4800 8N1)" in out, out
    assert out.index("serial-pty line 4800 8N1") > out.index(
        "serial-pty line 9600 8N1 (not the card's 4800 8N1)")
    assert not os.path.lexists(link)                # removed at exit


def test_pty_link_refuses_to_replace_a_file(tmp_path):
    f = tmp_path / "file"
    f.write_text("keep")
    r = subprocess.run([SIM, "--serial-pty-link", str(f)], capture_output=True, text=True,
                       input="", timeout=30)
    assert r.returncode == 1 and "not a symbolic link" in r.stderr and f.read_text() == "keep"


def test_serial_log_replays_the_session(tmp_path):
    log = tmp_path / "session.mac4"
    card = Card(["--serial-tcp", "0", "--serial-log", str(log)], SETUP_7_3_1)
    try:
        with socket.create_connection(("127.0.0.1", tcp_port(card)), timeout=5) as s:
            live = exchange(s, MANUAL_TELEGRAMS, 5)
    finally:
        rc, out, err = card.close()
    assert rc == 0, err
    text = log.read_text()
    assert "\ntx 10 02 00 00 46 00 00 00 10 10 56\n" in text and "# rx " in text, text
    r = subprocess.run([SIM, "--card", "inc", "--script", str(log)], capture_output=True,
                       text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    replayed = b"".join(bytes.fromhex(l[3:]) for l in r.stdout.splitlines()
                        if l.startswith("rx "))
    assert parse(replayed) == live == EXPECTED_7_3_1


def test_mac4host_through_an_rfc2217_server():
    """An RFC 2217 (telnet COM port control) server in front of the emulated
    card's TCP line, built from pyserial's own PortManager as a serial
    device server would be: `mac4host --serial rfc2217://` sets the line and
    talks through it."""
    import threading
    import serial.rfc2217

    card = Card(["--serial-tcp", "0"])           # stops when the bridge closes the line
    srv = socket.socket()
    srv.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    srv.bind(("127.0.0.1", 0))
    srv.listen(1)
    srv.settimeout(20)
    settings = []

    class Conn:                                  # PortManager writes with .write()
        def __init__(self, sock):
            self.sock = sock

        def write(self, data):
            self.sock.sendall(data)

    def serve():
        conn, _ = srv.accept()
        line = serial.serial_for_url("socket://127.0.0.1:%d" % tcp_port(card), timeout=0)
        # the far port: what the client asks for is recorded, as a real
        # server would set its UART
        line._reconfigure_port = lambda *a: settings.append(
            (line.baudrate, line.bytesize, line.parity, line.stopbits))
        pm = serial.rfc2217.PortManager(line, Conn(conn))
        conn.settimeout(0.05)
        end = time.monotonic() + 20
        try:
            while time.monotonic() < end:
                try:
                    data = conn.recv(1024)
                    if not data:
                        break
                    line.write(b"".join(pm.filter(data)))
                except socket.timeout:
                    pass
                back = line.read(line.in_waiting or 1)
                if back:
                    conn.sendall(b"".join(pm.escape(back)))
        finally:
            line.close()
            conn.close()

    t = threading.Thread(target=serve, daemon=True)
    t.start()
    try:
        r = subprocess.run(HOST + ["--json", "--serial", "rfc2217://127.0.0.1:%d"
                                   % srv.getsockname()[1], "send", "0", "VER", "RCP"],
                           capture_output=True, text=True, timeout=60)
    finally:
        t.join(25)
        srv.close()
        rc, out, err = card.close()
    assert r.returncode == 0, r.stdout + r.stderr
    assert '"code": 7' in r.stdout and '"param": 4457474' in r.stdout, r.stdout
    assert (4800, 8, "N", 1) in settings, settings
