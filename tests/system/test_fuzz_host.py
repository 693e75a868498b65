"""The Python fuzz targets of tests/fuzz/fuzz_host.py find a planted bug
(so a clean campaign means something) and pass on the code as it is."""
import os
import sys

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "fuzz"))
import fuzz_host  # noqa: E402


@pytest.mark.parametrize("target", ["batch", "telegram"])
def test_clean_on_the_code_as_it_is(target):
    rc, execs, lines, corpus = fuzz_host.campaign(target, iterations=150, seed=3)
    assert rc == 0 and execs == 150 and lines > 50


def test_finds_a_traceback_in_the_batch_parser(monkeypatch, capsys, tmp_path):
    real = fuzz_host.mac4host.parse_batch

    def broken(d, lines, card=None, name="-"):
        if any("$" in l for l in lines):
            raise KeyError("planted")          # a traceback, not a Mac4Error
        return real(d, lines, card, name)

    monkeypatch.setattr(fuzz_host.mac4host, "parse_batch", broken)
    rc, *_ = fuzz_host.campaign("batch", iterations=150, seed=3, crash_dir=str(tmp_path))
    assert rc == 1 and "KeyError: 'planted'" in capsys.readouterr().err and list(tmp_path.iterdir())


def test_finds_a_decoder_that_loses_a_telegram(monkeypatch, capsys, tmp_path):
    real = fuzz_host.TelegramDecoder._data

    def broken(self, b):
        real(self, b ^ 1 if b == 0x46 else b)   # one data byte decoded wrongly
    monkeypatch.setattr(fuzz_host.TelegramDecoder, "_data", broken)
    rc, *_ = fuzz_host.campaign("telegram", iterations=150, seed=3, crash_dir=str(tmp_path))
    assert rc == 1 and "PROPERTY VIOLATED (telegram)" in capsys.readouterr().err
