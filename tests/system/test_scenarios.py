"""Host-script tooling: plant scenario files (`include FILE`,
tests/scenarios/*.mac4), the reversed motor wiring of the plant, and the
card-side columns of `trace` (docs/host-script.md, "Plant")."""
import csv
import os
import re

import pytest

from conftest import BOOT, ROOT, sim
from mac4 import MODE, TICK_MS, code, has, signed

SCEN = os.path.join(ROOT, "tests", "scenarios")


def scen(name):
    return os.path.join(SCEN, name)


def go(text, card="inc", args=()):
    r = sim(text, card, args=list(args))
    assert r.rc == 0, r.stderr
    return r


def rows(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def num(v):
    return int(v, 16) if v.startswith("0x") else float(v)


# ---- include ------------------------------------------------------------------------
def test_include_runs_the_lines_of_a_file_as_if_they_stood_there(tmp_path):
    sub = tmp_path / "sub"
    sub.mkdir()
    (sub / "inner.mac4").write_text("echo inner-1\nswitch 0 lp 1234\necho inner-2\n")
    # a relative name is looked for beside the including file first
    (sub / "outer.mac4").write_text("echo outer-1\ninclude inner.mac4\necho outer-2\n")
    r = go("echo main-1\ninclude %s\necho main-2\nplant 0\n" % (sub / "outer.mac4"))
    said = [l for l in r.lines if re.match(r"^(main|outer|inner)-\d$", l)]
    assert said == ["main-1", "outer-1", "inner-1", "inner-2", "outer-2", "main-2"]
    assert r.grep(r"^plant 0 .* lp=0 ")           # the switch is wired (and not on at 0)
    r = go("include %s\nplant 0 pos 2000\nplant 0\n" % (sub / "inner.mac4"))
    assert r.grep(r"^plant 0 .* lp=1 ")


def test_include_errors_name_the_file_and_line(tmp_path):
    (tmp_path / "bad.mac4").write_text("echo ok\n\nfrobnicate 3\n")
    r = sim("include %s\necho after\n" % (tmp_path / "bad.mac4"), "inc")
    assert r.rc == 1
    assert "%s:3: unknown command 'frobnicate'" % (tmp_path / "bad.mac4") in r.stderr
    assert "after" in r.lines                     # the script goes on, as after any error
    r = sim("include %s\n" % (tmp_path / "missing.mac4"), "inc")
    assert r.rc == 1 and "cannot open" in r.stderr
    r = sim("include\n", "inc")
    assert r.rc == 1 and "usage" in r.stderr


def test_include_of_itself_stops_at_the_nesting_limit(tmp_path):
    loop = tmp_path / "loop.mac4"
    loop.write_text("echo again\ninclude loop.mac4\n")
    r = sim("include %s\n" % loop, "inc", timeout=20)
    assert r.rc == 1 and "nested deeper than 8" in r.stderr
    assert r.lines.count("again") == 8


def test_quit_in_an_included_file_ends_the_script(tmp_path):
    (tmp_path / "q.mac4").write_text("echo before\nquit\necho not-this\n")
    r = go("include %s\necho nor-this\n" % (tmp_path / "q.mac4"))
    assert "before" in r.lines and "not-this" not in r.lines and "nor-this" not in r.lines


# ---- the scenario files of 7.2 --------------------------------------------------------
def scenario_sends(name):
    """The `send 0 MN [VALUE]` lines of a card-side scenario file."""
    out = []
    for line in open(scen(name)):
        line = line.split("#")[0].split()
        if line and line[0] == "send":
            v = line[3] if len(line) > 3 else None
            out.append((line[2], None if v is None else int(v.replace("$", "0x"), 0)))
    return out


@pytest.mark.parametrize("card", ["inc", "ssi"])
def test_the_7_2_scenario_sets_every_parameter_it_names(card):
    """Every command of the card-side file is answered with its own code, and
    every parameter written reads back (read code = write code + 1) as given."""
    sends = scenario_sends("%s-7.2-card.mac4" % card)
    assert sends[-1] == ("INIT", None) and len(sends) >= 15
    reads = [mn for mn, v in sends if v is not None]
    text = "include %s\n" % scen("%s-7.2.mac4" % card)
    text += "".join("send 0 %d\n" % (code(mn) + 1) for mn in reads) + "send 0 RBS\nrun 10\n"
    r = go(text, card)
    got = r.resps()
    assert [c for _, c, _ in got[:len(sends)]] == [code(mn) for mn, _ in sends]
    back = got[len(sends):len(sends) + len(reads)]
    for (mn, v), (_, c, p) in zip([(mn, v) for mn, v in sends if v is not None], back):
        assert c == code(mn) + 1 and signed(p) == signed(v & 0xFFFFFFFF), (mn, v, c, p)
    st = got[-1][2]
    assert has(st, "init") and not any(has(st, b) for b in ("syn_f", "limit_f", "logo_f", "encoder_f",
                                                              "dr_f", "ferr_f", "hwl_p", "hwl_n", "ref"))
    assert has(st, "rev_o") == (card == "inc")               # USR in the INC example only
    assert has(st, "on_fly") == (card == "inc")              # FLYOFF in the SSI example only


def test_the_inc_7_2_plant_wires_every_switch_high_active():
    r = go("include %s\nplant 0\nplant 0 pos 22000\nplant 0\n" % scen("inc-7.2-plant.mac4"))
    at0, in_ref = r.grep(r"^plant 0 ")
    # high active: an inactive switch holds its input at 0 V (AX_IN bit 1), the
    # drive-fault line too; in the reference switch its bit goes to 0
    assert "ref=0" in at0 and re.search(r"in=0x000F$", at0)
    assert "ref=1" in in_ref and re.search(r"in=0x000B$", in_ref)


# ---- reversed wiring ------------------------------------------------------------------
@pytest.mark.parametrize("card", ["inc", "ssi"])
def test_reversed_wiring_turns_a_positive_dac_word_negative(card):
    base = "plant 0 pos 100000\n" if card == "ssi" else ""
    cmd = "axreg 0 ctrl 1\naxreg 0 dac 400\nrun 50\nplant 0\naxreg 0 dac 0\n"
    normal = go(base + cmd, card)
    rev = go(base + "plant 0 wiring reversed\n" + cmd + "plant 0 wiring normal\n" + cmd, card)
    pos = [float(re.search(r" rev=(-?[\d.]+)", l).group(1)) for l in normal.grep(r"^plant 0 ") +
           rev.grep(r"^plant 0 ")]
    start = 100000 / 4096 if card == "ssi" else 0.0
    assert pos[0] - start > 0.02 and pos[1] - start < -0.02       # +400 LSB: forwards / backwards
    assert pos[2] - pos[1] > 0.02                                 # normal again: forwards
    assert sim("plant 0 wiring sideways\n", card).rc == 1
    r = sim("plant 0 wiring reversed\n", "stp")
    assert r.rc == 1 and "servo cards only" in r.stderr


# ---- trace: the card-side columns -------------------------------------------------------
def traced_move(tmp_path, opts="tick card", card="inc"):
    path = tmp_path / "t.csv"
    text = BOOT + "send 0 INIT\nsend 0 ME\nsend 0 E\nrun 20\nsend 0 WPV 60\nsend 0 WPA 6\nsend 0 WPD 6\n"
    text += "send 0 WAP 3000\nsend 0 MP\ntrace 0 %s %s\nsend 0 E\nrun 1500\ntrace off\n" % (path, opts)
    return go(text, card), rows(path)


def test_trace_tick_card_writes_one_row_per_servo_tick_with_the_published_axis_data(tmp_path):
    r, rs = traced_move(tmp_path)
    assert list(rs[0].keys()) == ["t_ms", "dac", "volts", "en", "position", "velocity", "motor_rpm", "counter",
                                  "card_pos", "setpoint", "ferr", "out", "ustat"]
    t = [float(x["t_ms"]) for x in rs]
    assert len(rs) == 600 or len(rs) == 601
    # every controller period, the timer's expiries (printed to 1 us)
    assert all(abs((b - a) - TICK_MS["inc"]) < 0.0015 for a, b in zip(t, t[1:]))
    v = [{k: num(x[k]) for k in x} for x in rs]
    # the card's own numbers agree with each other and with the plant: ferr =
    # setpoint - position, the position the card publishes is at most one
    # profile period (and a tick) behind the counter, and the output it publishes
    # is one the DAC had in the last 4 ticks
    for i, x in enumerate(v):
        assert x["ferr"] == x["setpoint"] - x["card_pos"], x
        assert abs(x["counter"] - x["card_pos"]) <= 5 * 15 + 1, (i, x)    # WPV 60: 15 per tick
        if i >= 4 and x["out"] != v[i - 1]["out"]:
            assert x["out"] in [v[j]["dac"] for j in range(i - 4, i + 1)], (i, x)
    moving = [x for x in v if x["velocity"] > 1000]
    assert moving and max(x["ferr"] for x in moving) > 10              # a following error while moving
    end = v[-1]
    assert end["setpoint"] == 3000 and abs(end["card_pos"] - 3000) <= 10
    assert has(int(end["ustat"]), "pos_end") and int(end["ustat"]) & 0xFF == MODE["positioning"]
    assert not has(int(v[0]["ustat"]), "pos_end")


def test_trace_interval_and_card_columns_are_independent(tmp_path):
    _, rs = traced_move(tmp_path, "5000 card")
    t = [float(x["t_ms"]) for x in rs]
    # t_ms is printed to 1 us: two roundings may differ by one digit
    assert "setpoint" in rs[0] and all(abs((b - a) - 5.0) < 0.0015 for a, b in zip(t, t[1:]))
    _, rs = traced_move(tmp_path, "tick")
    assert "setpoint" not in rs[0] and len(rs) >= 600


def test_trace_tick_rows_on_the_stepper(tmp_path):
    path = tmp_path / "s.csv"
    go(BOOT + "trace 0 %s tick card\nrun 80\ntrace off\n" % path, "stp")
    rs = rows(path)
    t = [float(x["t_ms"]) for x in rs]
    assert "field_hz" in rs[0] and "setpoint" in rs[0]
    assert len(rs) == 10 and all(abs((b - a) - 8.0) < 0.0015 for a, b in zip(t, t[1:]))   # the STP tick


def test_trace_usage_errors(tmp_path):
    f = tmp_path / "x.csv"
    for bad in ("trace 0 %s tick 500\n", "trace 0 %s card card\n", "trace 0 %s 500 500\n",
                "trace 0 %s card 500\n", "trace 0 %s 0\n", "trace 0 %s tick card extra\n"):
        r = sim(bad % f, "inc")
        assert r.rc == 1, bad
