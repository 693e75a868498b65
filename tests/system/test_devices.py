"""The emulator's devices (docs/board.md, "The emulator's devices"): each
device's register handlers are its own, the bus table names devices, and
the plant reaches the axis boards only through the lines of harness/plant.h
(no plant file reads or writes the boards' state)."""
import glob
import os
import re

from conftest import ROOT

H = os.path.join(ROOT, "harness")
DEVICE_FILES = ["sysctl.c", "timer.c", "uart.c", "virq.c", "axisboard.c"]
PLANT_FILES = sorted(os.path.basename(p) for p in glob.glob(os.path.join(H, "plant*.c")))


def src(name):
    text = open(os.path.join(H, name)).read()
    return re.sub(r"/\*.*?\*/", "", text, flags=re.S)      # comments may name anything


def test_register_handlers_are_static_in_their_device():
    for f in DEVICE_FILES:
        for m in re.finditer(r"^(static )?(?:uint32_t|void) (\w+_(?:rd|wr))\(", src(f), re.M):
            assert m.group(1), "%s: %s is reachable from outside its device" % (f, m.group(2))
    assert not re.search(r"\w+_(rd|wr)\(", src("periph.h"))


def test_the_bus_table_names_devices_and_windows():
    rows = [l for l in open(os.path.join(H, "bus_map.h")) if l.startswith("{")]
    periph = src("periph.h")
    for row in rows:
        m = re.search(r'"[^"]+", &(\w+_device), ([01]), [01]\},$', row.strip())
        assert m, row
        assert re.search(r"\b%s\b" % m.group(1), periph), "%s is not a device of periph.h" % m.group(1)


def test_the_plant_uses_only_the_wires():
    assert "plant.c" in PLANT_FILES and len(PLANT_FILES) > 3
    for f in PLANT_FILES:
        s = src(f)
        assert not re.search(r"->ax\[|\.ax\[[^\]]*\]\.(ctrl|dac|rate|counter|idx_|pstat|ssi|cnt_|acc|pmode|remaining)",
                             s.replace("s->plant.ax[", "")), "%s reaches into the axis boards' state" % f
        assert "axis_hw_t" not in s, f
        assert "s->sys." not in s, "%s reads the system control (/STOP comes as sys.stop)" % f


def test_the_timer_tells_the_axis_board_by_signal():
    s = src("timer.c")
    assert not re.search(r"\b(axb_|plant_|ssi_start)\w*\(", s)
    assert "sig_raise(s, SIG_TMR_EXPIRED" in s
