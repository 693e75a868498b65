"""Off-fly operation (manual 5.15, docs/interpretations.md "Off-fly"):
commands for an axis whose move runs off-fly wait, in the order they came,
until the move ends; reads and C are answered at once, and the other axes
are not held up.  A command held behind a move that never ends (a
search that finds no index) used to hold the whole card."""
import pytest

from conftest import BOOT, sim
from mac4 import CMDQ, MODE, code, pos_addr, qh, stop_line, ustat_addr

REAR = qh(CMDQ, "REAR")


def enable(*axes):
    out = []
    for m in ("INIT", "ME", "E"):
        out += ["send %d %s" % (a, m) for a in axes]
    return out + ["run 20"]


def endless_search(n=0):
    """Search index coarse at 1 increment per SP: the next index is 4000
    increments (40 s) away, so for the test the search never ends."""
    return ["send %d FLYOFF" % n, "send %d WCV 1" % n, "send %d MC" % n, "send %d E" % n, "run 100"]


def long_move(card, n, target=None):
    far = {"inc": 40000, "ssi": 40000, "stp": 20000}[card] if target is None else target
    v = "WPV 2000" if card == "stp" else "WPV 60"
    return ["send %d FLYOFF" % n, "send %d %s" % (n, v), "send %d WAP %d" % (n, far), "send %d MP" % n,
            "send %d E" % n, "run 100"]


def go(lines, card="inc"):
    r = sim(BOOT + "\n".join(lines) + "\n", card, args=["--timestamps"])
    assert r.rc == 0, r.stderr
    return r


def events(r):
    """(ms, kind, fields) for resp, rx, echo and peek lines, in the order
    the emulator printed them (echo lines, which carry no time, get the time
    of the event before them)."""
    out, ms = [], 0.0
    for l in r.lines:
        if l.startswith("@"):
            t, rest = l.split(" ", 1)
            ms = float(t[1:-2])
        else:
            rest = l
        p = rest.split()
        if not p:
            continue
        if p[0] == "resp":
            out.append((ms, "resp", (int(p[1]), int(p[2]), int(p[3], 16))))
        elif p[0].startswith("=="):                 # echo ==NAME
            out.append((ms, "mark", p[0][2:]))
        elif p[0].startswith("peek"):
            out.append((ms, "peek", (int(p[1], 16), int(p[2], 16))))
        elif p[0] == "rx":
            out.append((ms, "rx", rest[3:]))
    return out


def idx(r, name):
    ev = events(r)
    i = [n for n, (ms, k, f) in enumerate(ev) if k == "mark" and f == name]
    assert i, name
    return i[0]


def answers(r, axis, mn):
    """Positions (in events()) and parameters of the responses to mn on axis."""
    c = code(mn)
    return [(n, f[2]) for n, (ms, k, f) in enumerate(events(r)) if k == "resp" and f[0] == axis and f[1] == c]


def between(r, i0, i1, kind="resp"):
    return [f for n, (ms, k, f) in enumerate(events(r)) if k == kind and i0 < n < i1]


# ---- the case of the audit: a search that finds no index ---------------------------
def test_endless_search_reads_c_and_other_axes_answer_at_once():
    r = go(enable(0, 1) + endless_search(0) +
           ["echo ==held", "send 0 WAP 5000", "send 0 MP", "send 0 E", "run 10",
            "echo ==others", "send 0 RBS", "send 1 RBS", "send 0 VER", "send 0 RCP", "send 1 WPV 50", "send 0 C",
            "send 0 RAP", "send 1 RPV", "send 2 RBS", "run 300",
            "echo ==stop", stop_line(0), "run 50", "peek32 0x%X" % ustat_addr(0), "run 50"])
    t_held, t_others, t_stop = idx(r, "held"), idx(r, "others"), idx(r, "stop")
    # while the search runs: every read, C and every command of the other axes answered, each once
    during = between(r, t_held, t_stop)
    got = [(a, c) for a, c, _ in during]
    want = [(0, code(m)) for m in ("RBS", "VER", "RCP", "C", "RAP")] + \
           [(1, code(m)) for m in ("RBS", "WPV", "RPV")] + [(2, code("RBS"))]
    assert sorted(got) == sorted(want), during
    # in the order they were sent: nothing waits behind the held commands
    assert got == [(0, code("RBS")), (1, code("RBS")), (0, code("VER")), (0, code("RCP")), (1, code("WPV")),
                   (0, code("C")), (0, code("RAP")), (1, code("RPV")), (2, code("RBS"))], got
    # the reads see the running search and the target not yet written
    rbs0 = answers(r, 0, "RBS")[0][1]
    assert rbs0 & 0xFF == MODE["search index coarse"]
    assert answers(r, 0, "RAP")[0][1] == 0
    assert answers(r, 1, "RPV")[0][1] == 50            # axis 2's write took effect at once
    # the held commands: answered only when the stop bit ended the search, in their order
    held = [(n, f[1]) for n, (ms, k, f) in enumerate(events(r)) if k == "resp" and f[0] == 0 and
            f[1] in (code("WAP"), code("MP"), code("E")) and n > t_held]
    assert [c for _, c in held] == [code("WAP"), code("MP"), code("E")], held
    assert all(n > t_stop for n, _ in held), (held, t_stop)
    # ... and executed: the axis positions now (off-fly again)
    st = [f[1] for ms, k, f in events(r) if k == "peek" and f[0] == ustat_addr(0)][-1]
    assert st & 0xFF == MODE["positioning"], hex(st)


@pytest.mark.parametrize("card", ["inc", "ssi", "stp"])
def test_long_move_other_axes_not_held(card):
    """Axis 1 positions far off-fly; axis 2's commands and all reads go on."""
    r = go(enable(0, 1) + long_move(card, 0) +
           ["echo ==now", "send 0 WPA 5", "send 1 WPA 5", "send 1 RPA", "send 0 RPA", "send 0 RBS", "run 50",
            "echo ==stop", stop_line(0), "run 50"], card)
    t_now, t_stop = idx(r, "now"), idx(r, "stop")
    during = [(a, c, p) for a, c, p in between(r, t_now, t_stop)]
    assert [(a, c) for a, c, _ in during] == [(1, code("WPA")), (1, code("RPA")), (0, code("RPA")),
                                              (0, code("RBS"))], during
    assert during[1][2] == 5                            # axis 2's write
    assert during[2][2] != 5                            # axis 1's write waits: RPA reads the old value
    assert during[3][2] & 0xFF == MODE["positioning"]
    wpa0 = [n for n, p in answers(r, 0, "WPA") if n > t_now]
    assert len(wpa0) == 1 and wpa0[0] > t_stop


def test_two_axes_off_fly_released_each_by_its_own_move():
    r = go(enable(0, 1) + endless_search(0) + long_move("inc", 1) +
           ["echo ==held", "send 0 WPV 11", "send 1 WPV 12", "send 0 WPV 21", "send 1 WPV 22", "run 20",
            "echo ==stop2", stop_line(1), "run 50",
            "echo ==stop1", stop_line(0), "run 50", "send 0 RPV", "send 1 RPV", "run 10"])
    t_held, t_stop2, t_stop1 = idx(r, "held"), idx(r, "stop2"), idx(r, "stop1")
    assert between(r, t_held, t_stop2) == []
    # axis 2's move ends: its two writes, in order; axis 1's still wait
    assert [(a, c) for a, c, _ in between(r, t_stop2, t_stop1)] == [(1, code("WPV"))] * 2
    assert [(a, c) for a, c, _ in between(r, t_stop1, 10 ** 9)][:2] == [(0, code("WPV"))] * 2
    assert answers(r, 0, "RPV")[0][1] == 21 and answers(r, 1, "RPV")[0][1] == 22


def test_commands_of_the_held_axis_stay_in_series():
    """5.15, example 2 with two targets queued: each new target waits for the
    move before it (the commands of one axis never overtake each other)."""
    r = go(enable(0) + long_move("inc", 0, 3000) +
           ["send 0 WAP 6000", "send 0 E", "send 0 WAP 1000", "send 0 E", "run 10"] +
           sum([["run 20", "peek32 0x%X" % pos_addr(0)] for _ in range(400)], []))
    pos = [f[1] - (1 << 32) if f[1] & 0x80000000 else f[1] for ms, k, f in events(r) if k == "peek"
           and f[0] == pos_addr(0)]
    beyond = next(i for i, p in enumerate(pos) if p > 3050)
    assert any(abs(p - 3000) <= 10 for p in pos[:beyond])  # at 3000 first ...
    assert abs(max(pos) - 6000) <= 10                    # ... then at 6000 ...
    assert abs(pos[-1] - 1000) <= 10                     # ... and then at 1000
    assert len(answers(r, 0, "E")) == 4                  # ME's, the first move's and the two held


def test_hold_list_full_stops_the_interfaces_until_room():
    """At most 16 commands wait; with 16 held no interface is read (the 17th
    command and everything behind it wait in the queue), and all of them are
    answered, in order, once the move ends."""
    lines = enable(0, 1) + endless_search(0) + ["echo ==held"]
    for i in range(16):
        lines += ["send 0 WPV %d" % (100 + i), "run 2"]
    lines += ["run 10", "peek32 0x%X" % REAR, "send 1 RBS", "run 20", "peek32 0x%X" % REAR, "echo ==stop",
              stop_line(0), "run 100"]
    r = go(lines)
    t_held, t_stop = idx(r, "held"), idx(r, "stop")
    assert between(r, t_held, t_stop) == []       # not even axis 2's read
    rears = [f[1] for ms, k, f in events(r) if k == "peek" and f[0] == REAR]
    assert rears[0] == rears[1]                          # the read stays in the queue
    after = between(r, t_stop, 10 ** 9)
    assert [(a, c) for a, c, _ in after] == [(0, code("WPV"))] * 16 + [(1, code("RBS"))], after


def test_serial_commands_are_held_and_answered_on_the_serial_line():
    r = go(enable(0) + endless_search(0) +
           ["echo ==held", "tx-msg 0 WPV 77", "run 60", "echo ==read", "tx-msg 0 RBS", "run 60",
            "echo ==stop", stop_line(0), "run 60"])
    t_held, t_read, t_stop = idx(r, "held"), idx(r, "read"), idx(r, "stop")
    # the telegram of the read comes at once (axis 0, code 125 = $7D), the write's after the stop
    assert between(r, t_held, t_read, "rx") == []
    assert [f[:14] for f in between(r, t_read, t_stop, "rx")] == ["10 02 00 00 7D"]
    assert [f[:14] for f in between(r, t_stop, 10 ** 9, "rx")] == ["10 02 00 00 48"]   # WPV = 72 = $48
    assert between(r, t_held, 10 ** 9) == []          # nothing on the VMEbus
