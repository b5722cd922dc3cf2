"""A failed sweep's error is a short headline (what failed, where, and the lock that
ended it) with the details on the lines below, indented; the command line prints both,
the headline first. (It was one line of 700 characters.)"""
import os

import pytest

import mechgen
from mechgen.cli import main

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SLIDER = os.path.join(ROOT, "examples", "quick_return_slider.py")


def _lock_time():
    """The slider-driven quick-return's first lock: the crank pin's quadratic on the lever
    has a double root (cos φ = 4/5, sin φ = −3/5 on the guess's mode), the lever's end
    then 5 from the slider where X4² − 10.8 X4 + 12 = 0, and X4 = 4.13931 + 5.40447 sin 2πT
    (tests/closed_forms.slider_driven_configurations)."""
    import mpmath as mp
    x = (mp.mpf("10.8") + mp.sqrt(mp.mpf("10.8") ** 2 - 48)) / 2
    return float(mp.asin((x - mp.mpf("4.13931")) / mp.mpf("5.40447")) / (2 * mp.pi))


LOCK = f"lock (toggle) position at t≈{_lock_time():.10g}"


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
