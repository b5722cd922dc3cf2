"""A failed sweep's error is a short headline (what failed, where, and the lock that
ended it) with the details on the lines below, indented; the command line prints both,
the headline first. (It was one line of 700 characters.)"""
import os

import pytest

import mechgen
from mechgen.cli import main

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SLIDER = os.path.join(ROOT, "examples", "quick_return_slider.py")
LOCK = "lock (toggle) position at t≈0.2464863829"


def _check_layout(text):
    first, *rest = text.splitlines()
    assert len(first) <= 140, first
    assert rest and all(line.startswith("  ") for line in rest), text
    return first, rest


def test_sweep_error_has_a_headline_and_details(qr_slider):
    with pytest.raises(mechgen.ConvergenceError) as info:
        qr_slider.sweep(0, 1, 101)
    first, rest = _check_layout(str(info.value))
    assert first.startswith("no configuration found at t=") and LOCK in first
    details = "\n".join(rest)
    assert "did not converge in" in details and "could go no further" in details
    assert "cannot fix Th2" in details and "cannot assemble" in details


def test_the_command_prints_the_headline_first(capsys, tmp_path):
    assert main(["sweep", SLIDER, "--outdir", str(tmp_path / "gen"), "-n", "11",
                 "--columns", "X4"]) == 1
    err = capsys.readouterr().err
    first, rest = _check_layout(err.removeprefix("mechgen: ConvergenceError: "))
    assert err.startswith("mechgen: ConvergenceError: no configuration found") and LOCK in first
    assert "Traceback" not in err and len(rest) >= 2
