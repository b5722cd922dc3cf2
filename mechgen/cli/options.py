"""Parsing of command-line values shared by the commands: numbers written as expressions
(``2*pi``), start values, parameter ranges, column lists, and the two kinds of path (a
folder of generated modules, a file to write)."""
from __future__ import annotations

import argparse
import ast
import contextlib
import math
import operator
import os
import tempfile

import numpy as np

from ..errors import MechgenError
from ..runtime.guards import fits

# What a number on the command line may be built from: no names beyond these, no
# attributes, no calls but these functions (the text is parsed, never eval'd).
CONSTANTS = {"pi": math.pi, "e": math.e, "tau": math.tau}
FUNCTIONS = {"sqrt": math.sqrt, "sin": math.sin, "cos": math.cos, "tan": math.tan,
             "asin": math.asin, "acos": math.acos, "atan": math.atan, "atan2": math.atan2,
             "exp": math.exp, "log": math.log, "abs": abs, "radians": math.radians,
             "degrees": math.degrees}
_BINARY = {ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul,
           ast.Div: operator.truediv, ast.Pow: operator.pow, ast.Mod: operator.mod}
_UNARY = {ast.UAdd: operator.pos, ast.USub: operator.neg}
# extensions that name a file, never a folder of generated modules
FILE_SUFFIXES = (".csv", ".png", ".gif", ".svg", ".pdf", ".mp4", ".jpg", ".jpeg", ".txt")


def _evaluate(node):
    if isinstance(node, ast.Expression):
        return _evaluate(node.body)
    if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)) \
            and not isinstance(node.value, bool):
        return float(node.value)
    if isinstance(node, ast.Name) and node.id in CONSTANTS:
        return CONSTANTS[node.id]
    if isinstance(node, ast.BinOp) and type(node.op) in _BINARY:
        return float(_BINARY[type(node.op)](_evaluate(node.left), _evaluate(node.right)))
    if isinstance(node, ast.UnaryOp) and type(node.op) in _UNARY:
        return _UNARY[type(node.op)](_evaluate(node.operand))
    if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) \
            and node.func.id in FUNCTIONS and not node.keywords:
        return float(FUNCTIONS[node.func.id](*(_evaluate(a) for a in node.args)))
    raise ValueError


def number(text) -> float:
    """A number, or an arithmetic expression of numbers, pi, e and tau with + - * / ** %,
    parentheses and sqrt, sin, cos, tan, asin, acos, atan, atan2, exp, log, abs (``2*pi``,
    ``0.5/3``). Raises ValueError naming the text otherwise."""
    text = str(text).strip()
    try:
        return float(text)          # also nan and inf: the commands say why they refuse them
    except ValueError:
        pass
    try:
        if len(text) > 200:
            raise ValueError
        value = _evaluate(ast.parse(text, mode="eval"))
    except (ValueError, SyntaxError, TypeError, ZeroDivisionError, OverflowError,
            RecursionError):
        raise ValueError(f"{text!r} is not a number or an expression such as 2*pi or "
                         "sqrt(2)/2") from None
    return float(value)


def number_type(text) -> float:
    """``number`` as an argparse type: a usage error names the option."""
    try:
        return number(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def positive_type(largest):
    """An argparse type: a positive finite number up to ``largest`` (--dpi, --width,
    --fps: a zero divides by zero, a negative one or a huge one breaks the writers)."""
    def positive(text) -> float:
        value = number_type(text)
        if not (0 < value <= largest):
            raise argparse.ArgumentTypeError(f"{text!r} must be a positive number up to "
                                             f"{largest:g}")
        return value
    return positive


def parse_guess(items):
    """``--guess NAME=VALUE`` values: a dict of start values (None when none given)."""
    guess = {}
    for item in items or ():
        name, sep, value = item.partition("=")
        if not sep:
            raise MechgenError(f"--guess takes NAME=VALUE, got {item!r}")
        try:
            guess[name.strip()] = number(value)
        except ValueError:
            raise MechgenError(f"--guess {item!r}: {value!r} is not a number") from None
    return guess or None


def _count(text) -> int:
    """A count of values: a positive integer."""
    text = text.strip()
    if not text.isdigit() or int(text) < 1:
        raise ValueError
    return int(text)


def _not_too_many(name, count):
    """A parameter's values become designs of a table (each at least a row of numbers):
    refuse counts that could not fit in memory before making them."""
    try:
        fits(count, 128, "values", f"--param {name}")
    except ValueError as exc:
        raise MechgenError(str(exc)) from None


def parse_param_option(items) -> dict:
    """``--param`` values of the command line: ``NAME=V`` fixes a parameter,
    ``NAME=V1,V2,...`` lists values, ``NAME=START:STOP:COUNT`` is COUNT values from START
    to STOP, both included (numpy's linspace; ``NAME=START:STOP:n=COUNT`` says the same),
    and ``NAME=START:STOP:step=H`` is Mathematica's {name, start, stop, h} (START, START +
    H, ... up to STOP, included when a step reaches it). Each value may be an expression."""
    out = {}
    for item in items or ():
        name, sep, text = item.partition("=")
        name = name.strip()
        if not sep or not name:
            raise MechgenError(f"--param takes NAME=VALUES, got {item!r}")
        try:
            if ":" in text:
                start, stop, last = text.split(":")
                start, stop = number(start), number(stop)
                key, eq, value = last.partition("=")
                if eq and key.strip() == "step":
                    step = number(value)
                    if not step > 0 or stop < start:
                        raise ValueError
                    # the 1e-9 keeps a stop that the steps reach up to round-off
                    count = int(math.floor((stop - start) / step + 1e-9)) + 1
                    _not_too_many(name, count)
                    values = start + step * np.arange(count)
                else:
                    if eq and key.strip() != "n":
                        raise ValueError
                    count = _count(value if eq else last)
                    _not_too_many(name, count)
                    if count > 1 and stop == start:
                        raise ValueError
                    values = np.linspace(start, stop, count)
            elif "," in text:
                values = np.array([number(x) for x in text.split(",")])
            else:
                values = number(text)
        except ValueError:
            raise MechgenError(f"--param {item!r}: give NAME=V, NAME=V1,V2,..., "
                               "NAME=START:STOP:COUNT (COUNT >= 1 values) or "
                               "NAME=START:STOP:step=H with H > 0") from None
        out[name] = values
    return out


def parse_columns(items):
    """``--columns X4,X4d`` (repeatable): the names, in order, or None for all."""
    names = [n.strip() for item in items or () for n in item.split(",") if n.strip()]
    return names or None


def module_folder(path) -> str:
    """The folder of generated modules (--outdir): refuse a name that reads as a file."""
    if str(path).lower().endswith(FILE_SUFFIXES):
        raise MechgenError(f"--outdir {path}: that names a file, not a folder of generated "
                           "modules (-o FILE names the file a command writes)")
    if os.path.exists(path) and not os.path.isdir(path):
        raise MechgenError(f"--outdir {path}: that is a file, not a folder")
    return str(path)


def output_file(path, option="-o") -> str:
    """A file a command writes: its folder must exist and it must not be a folder."""
    if os.path.isdir(path) or str(path).endswith(("/", os.sep)):
        raise MechgenError(f"{option} {path}: that is a folder; {option} names the file to "
                           "write (the folder of generated modules is --outdir)")
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        raise MechgenError(f"cannot write {path}: folder {folder} does not exist")
    return str(path)


def model_file(path) -> str:
    """The model file argument: a clear error when it is missing."""
    if not os.path.isfile(path):
        what = "is a folder" if os.path.isdir(path) else "does not exist"
        raise MechgenError(f"model file {path} {what}")
    return path


@contextlib.contextmanager
def written(path):
    """The name to write ``path``'s content under: a file beside it with the same
    extension (the writers pick the format from it), moved onto ``path`` once written
    whole; removed when writing fails or is interrupted, so that a failed command leaves
    no half-written file (and an older file of that name as it was). A path that is not
    a regular file (/dev/stdout, a pipe) is written directly; a link, where it leads."""
    if os.path.exists(path) and not os.path.isfile(path):
        yield path
        return
    path = os.path.realpath(path)
    folder, base = os.path.split(path)
    root, ext = os.path.splitext(base)
    fd, tmp = tempfile.mkstemp(dir=folder, prefix=f".{root}.", suffix=ext)
    os.close(fd)
    try:
        yield tmp
        mask = os.umask(0)
        os.umask(mask)
        os.chmod(tmp, 0o666 & ~mask)        # as open() would have made it
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise
