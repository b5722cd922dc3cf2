"""Parsing of command-line values shared by the commands."""
from __future__ import annotations

from ..errors import MechgenError


def parse_guess(items):
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
