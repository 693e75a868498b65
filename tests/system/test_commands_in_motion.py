"""Commands that run partly with interrupts enabled (docs/performance.md,
"Masked sections"): an E masks only its checks and its commit, INIT on the
INC and SSI hardly at all - so the ticks of the other axes, and of the axis
itself, come in the middle of them.  Whatever the tick hits, every move must
still end where it was sent, with no error, and INIT must measure from where
the axis stands."""
import pytest

from conftest import BOOT, sim
from mac4 import TABLE, code

ERRORS = {e["code"] for e in TABLE["errors"]}

SSI_AT = 1000000          # SSI encoders start here: no move crosses their wrap at 0


def setup(card):
    lines = ["plant %d pos %d" % (a, SSI_AT) for a in range(4)] if card == "ssi" else []
    lines += [BOOT.strip()]
    if card == "ssi":
        lines += ["send %d UWSC 2" % a for a in range(4)]
    for m in ("INIT", "ME", "E"):
        lines += ["send %d %s" % (a, m) for a in range(4)]
    lines.append("run 20")
    v, acc, dec = (2000, 500, 500) if card == "stp" else (100, 10, 10)
    for a in range(4):
        lines += ["send %d WPV %d" % (a, v), "send %d WPA %d" % (a, acc), "send %d WPD %d" % (a, dec)]
    return lines


@pytest.mark.parametrize("card", ["inc", "ssi", "stp"])
def test_moves_land_exactly_while_the_host_retargets_and_reinitialises(card):
    base = SSI_AT if card == "ssi" else 0
    span = 1500 if card == "stp" else 6000
    lines = setup(card)
    lines += ["send 3 MD", "send 3 E", "run 5"]
    # 60 rounds, 7 ms apart (not a multiple of the tick): a new target on the
    # fly for one of axes 1-3 and INIT or DEINIT of axis 4, both executed
    # wherever the ticks fall
    for k in range(60):
        a = k % 3
        t = base + (span if (k // 3) % 2 == 0 else -span) + 37 * k
        lines += ["send %d WAP %d" % (a, t), "send %d MP" % a, "send %d E" % a,
                  "send 3 %s" % ("INIT" if k % 2 == 0 else "DEINIT"), "run 7"]
    final = [base + 1234, base - 2345, base + 3456]
    for a in range(3):
        lines += ["send %d WAP %d" % (a, final[a]), "send %d MP" % a, "send %d E" % a]
    lines += ["send 3 INIT", "run %d" % (12000 if card == "stp" else 6000)]
    lines += ["send %d RCP" % a for a in range(4)] + ["send %d RBS" % a for a in range(4)] + ["run 10"]
    r = sim("\n".join(lines) + "\n", card)
    assert r.rc == 0 and not r.faults(), (r.stderr[-500:], r.faults()[:3])
    resps = r.resps()
    errors = [x for x in resps if x[1] in ERRORS]
    assert not errors, errors[:5]
    assert sum(1 for x in resps if x[1] == code("E")) == 4 + 1 + 60 + 3   # every E answered, none refused
    rcp = {a: p - (1 << 32) if p & 0x80000000 else p for a, c, p in resps if c == code("RCP")}
    for a in range(3):
        assert abs(rcp[a] - final[a]) <= (2 if card == "stp" else 10), (a, rcp[a], final[a])
    # the fourth, INITed again and again at rest: measured where it stands
    assert abs(rcp[3] - base) <= 2, rcp[3]
