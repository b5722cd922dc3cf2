"""Audit of what a user sees (pictures, the live view): defects found and fixed."""
import math
import os

import numpy as np
import pytest

from conftest import EXAMPLES


def test_view_trace_keeps_the_comma_of_a_local_point():
    # `mechgen view fourbar.py --trace "coupler.at(1.25, 0.8)"` (README, and the option's
    # own help: 'foot.at(1, 2)') was cut at the comma: "no point 'coupler.at(1.25'"
    from mechgen.cli.view_command import _names
    assert _names(["coupler.at(1.25, 0.8)"]) == ["coupler.at(1.25, 0.8)"]
    assert _names(["colisa[2], foot.at(1, 2)", "crank[1]"]) == \
        ["colisa[2]", "foot.at(1, 2)", "crank[1]"]
    assert _names(["X4,X4d"]) == ["X4", "X4d"]
    assert _names(None) is None
