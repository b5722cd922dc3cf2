"""Parsing of command-line values shared by the commands."""
from __future__ import annotations

import math

import numpy as np

from ..errors import MechgenError


def parse_guess(items):
    """``--guess NAME=VALUE`` values: a dict of start values (None when none given)."""
    guess = {}
    for item in items or ():
        name, sep, value = item.partition("=")
        if not sep:
            raise MechgenError(f"--guess takes NAME=VALUE, got {item!r}")
        try:
            guess[name.strip()] = float(value)
        except ValueError:
            raise MechgenError(f"--guess {item!r}: {value!r} is not a number") from None
    return guess or None


def parse_param_option(items) -> dict:
    """``--param`` values of the command line: ``NAME=V`` fixes a parameter,
    ``NAME=V1,V2,...`` lists values and ``NAME=START:STOP:STEP`` is Mathematica's
    {name, start, stop, step} (stop included)."""
    out = {}
    for item in items or ():
        name, sep, text = item.partition("=")
        name = name.strip()
        if not sep or not name:
            raise MechgenError(f"--param takes NAME=VALUES, got {item!r}")
        try:
            if ":" in text:
                start, stop, step = (float(x) for x in text.split(":"))
                if not step > 0 or stop < start:
                    raise ValueError
                # the 1e-9 keeps a stop that the steps reach up to round-off
                count = int(math.floor((stop - start) / step + 1e-9)) + 1
                values = start + step * np.arange(count)
            elif "," in text:
                values = np.array([float(x) for x in text.split(",")])
            else:
                values = float(text)
        except ValueError:
            raise MechgenError(f"--param {item!r}: give NAME=V, NAME=V1,V2,... or "
                               "NAME=START:STOP:STEP with STEP > 0") from None
        out[name] = values
    return out
