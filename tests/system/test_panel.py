"""The live front panel (docs/debugging.md, "Front panel"): `mac4sim --panel 0`
loaded in a real headless Chromium (Debian's chromium and chromium-driver,
selenium from PyPI) during a move: the display and the LEDs read from the
DOM, the axis table decoded by name from build/commands.json, the /STOP
button, and reset showing the boot sequence.  The emulator is bounded by
--serve-seconds and killed at the end in any case."""
import json
import os
import re
import shutil
import subprocess
import time

import pytest

from conftest import BUILD, SIM

CHROMIUM = shutil.which("chromium")
DRIVER = shutil.which("chromedriver")
try:
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service
    from selenium.webdriver.common.by import By
except ImportError:                                  # pragma: no cover
    webdriver = None

pytestmark = pytest.mark.skipif(not (CHROMIUM and DRIVER and webdriver),
                                reason="no headless browser: chromium, chromium-driver (tools/deps/apt.txt) "
                                       "and selenium (tools/deps/python.txt) are needed")

MOVE = """wait-display 5 3000
send 0 INIT
send 0 ME
send 0 E
run 20
send 0 WPV 100
send 0 WPA 10
send 0 WPD 10
send 0 WAP 60000
send 0 MP
send 0 E
run 100
"""
TABLE = json.load(open(os.path.join(BUILD, "commands.json")))


def wait_for(pred, timeout=10.0, step=0.02):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        v = pred()
        if v:
            return v
        time.sleep(step)
    raise AssertionError("timed out")


@pytest.fixture
def panel(tmp_path):
    script = tmp_path / "move.mac4"
    script.write_text(MOVE)
    sim = subprocess.Popen([SIM, "--card", "inc", "--panel", "0", "--serve-seconds", "40", "--script", str(script)],
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    drv = None
    try:
        m = re.match(r"panel-port (\d+)$", sim.stdout.readline().strip())
        assert m, sim.stderr.read()
        opts = webdriver.ChromeOptions()
        opts.binary_location = CHROMIUM
        for a in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                  "--window-size=1200,560", "--user-data-dir=%s" % (tmp_path / "profile")):
            opts.add_argument(a)
        drv = webdriver.Chrome(service=Service(DRIVER), options=opts)
        drv.set_page_load_timeout(20)
        drv.get("http://127.0.0.1:%s/" % m.group(1))
        yield drv, sim
    finally:
        if drv:
            drv.quit()
        sim.kill()
        sim.wait(timeout=10)


def lit(drv, axis):
    return {e.get_attribute("data-name") for e in drv.find_elements(By.CSS_SELECTOR, ".led.on[data-axis='%d']" % axis)}


def cell(drv, axis, cls):
    return drv.find_element(By.CSS_SELECTOR, "#axis-%d .%s" % (axis, cls)).text


def test_panel_in_chromium(panel):
    drv, sim = panel
    # the page fills itself from /state; the move of axis 1 runs in real time
    wait_for(lambda: cell(drv, 1, "mode") == "positioning")
    w1, t1, p1 = time.monotonic(), float(drv.find_element(By.ID, "time").text), int(cell(drv, 1, "pos"))
    time.sleep(0.5)
    w2, t2, p2 = time.monotonic(), float(drv.find_element(By.ID, "time").text), int(cell(drv, 1, "pos"))
    ferr = int(cell(drv, 1, "ferr"))                  # read while it moves: the move ends in some seconds
    assert p2 - p1 > 2000, (p1, p2)                  # ~12 500 inc/s at 8 V
    # paced to the wall clock: emulated time goes as fast as the wall's (the 50 ms page updates aside)
    assert abs((t2 - t1) - 1000 * (w2 - w1)) < 150 + 0.2 * 1000 * (w2 - w1), (t1, t2, w2 - w1)
    disp = drv.find_element(By.ID, "display")
    assert disp.get_attribute("data-digit") == "0" and disp.get_attribute("data-dp") == "0"
    on = {e.get_attribute("id") for e in drv.find_elements(By.CSS_SELECTOR, "#display .seg.on")}
    assert on == {"seg-a", "seg-b", "seg-c", "seg-d", "seg-e", "seg-f"}   # a 0 on seven segments
    # six LEDs per axis: axis 1 enabled (D off), the others disabled (D on)
    assert len(drv.find_elements(By.CSS_SELECTOR, ".led[data-axis]")) == 24
    assert "D" not in lit(drv, 1) and all("D" in lit(drv, a) for a in (2, 3, 4))
    # status bits by their names in commands.json
    bits = cell(drv, 1, "bits").split()
    names = {b["name"] for b in TABLE["status"]["user"] if "width" not in b}
    assert "dr_en" in bits and "init" in bits and set(bits) <= names, bits
    assert abs(ferr) > 50, ferr
    os.makedirs(os.path.join(BUILD, "screenshots"), exist_ok=True)
    drv.save_screenshot(os.path.join(BUILD, "screenshots", "panel-moving.png"))
    # /STOP: the STOP LED lights, the axis is stopped (the firmware's reaction)
    drv.find_element(By.ID, "stop").click()
    wait_for(lambda: "on" in drv.find_element(By.ID, "led-stop").get_attribute("class"))
    wait_for(lambda: "D" in lit(drv, 1))
    drv.find_element(By.ID, "stop").click()
    wait_for(lambda: "on" not in drv.find_element(By.ID, "led-stop").get_attribute("class"))
    # reset: the boot sequence on the display, 1 2 3 5 (2.5.2), every axis disabled
    resets = int(drv.find_element(By.ID, "resets").text)
    drv.find_element(By.ID, "reset").click()
    seen = []

    def booted():
        # the log first, then the digit: once the log is complete, the digit read after it is
        # the last one of the boot, however the page and the poll interleave
        done = drv.find_element(By.ID, "displog").text == "1 2 3 5"
        d = drv.find_element(By.ID, "display").get_attribute("data-digit")
        if d and (not seen or seen[-1] != d):
            seen.append(d)
        return done
    wait_for(booted, timeout=15)
    assert int(drv.find_element(By.ID, "resets").text) == resets + 1
    assert seen[-1] == "5" and len(seen) >= 2, seen     # watched live, not only in the log
    wait_for(lambda: all("D" in lit(drv, a) for a in (1, 2, 3, 4)))
    assert cell(drv, 1, "mode") == "disable"
