"""Every cache is checked against the module it came from; a damaged one is rebuilt, never
loaded: the plain-Python tier's bytecode (runtime/loading/plain.py) and numba's on-disk cache
(runtime/loading/caches.py), each edited and truncated, and the numbers checked against the
four-bar's closed form (crank a = 0.8, coupler b = 2.5, rocker c = 2, ground d = 3,
θ2 = π/3 + 2πt)."""
import glob
import marshal
import math
import os
import shutil
import subprocess
import sys
import warnings

import pytest

import mechgen
from mechgen.runtime.loading import plain

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
GENERATED = os.path.join(ROOT, "generated")
T = 0.1


def th4_closed_form(t):
    """The rocker angle of both assemblies at t (|B − A| = b with A the crank pin, B the
    rocker pin): a sin θ4 + b cos θ4 = c form solved exactly."""
    a, b, c, d = 0.8, 2.5, 2.0, 3.0
    th2 = math.pi / 3 + 2 * math.pi * t
    ax, ay = a * math.cos(th2), a * math.sin(th2)
    # |D + c(cos φ, sin φ) − A|² = b²  ->  P cos φ + Q sin φ = R
    px, py = d - ax, -ay
    P, Q, R = 2 * c * px, 2 * c * py, b * b - c * c - px * px - py * py
    base, half = math.atan2(Q, P), math.acos(R / math.hypot(P, Q))
    return [math.remainder(base + s * half, 2 * math.pi) for s in (1, -1)]


def near_closed_form(value):
    return min(abs(math.remainder(value - r, 2 * math.pi)) for r in th4_closed_form(T)) < 1e-12


def test_the_closed_form_reference():
    assert any(abs(r - 1.98642258) < 1e-8 for r in th4_closed_form(T))


# -- the plain-Python tier's bytecode -----------------------------------------------------
@pytest.fixture
def module_copy(tmp_path):
    path = tmp_path / "fourbar.py"
    shutil.copy2(os.path.join(GENERATED, "fourbar.py"), path)
    return str(path)


def kept_file(path):
    found = glob.glob(os.path.join(plain.state_dir(path), "fourbar.*.plain"))
    assert len(found) == 1
    return found[0]


def plain_th4(path):
    return mechgen.load(path, tier="python").solve(T)["Th4"]


def edited_code(path):
    """The module's code with the rocker's length changed: what an edited cache holds."""
    with open(path, encoding="utf-8") as fh:
        text = fh.read()
    return compile(text.replace("2.0, 3.0, 1.0471975511965979", "2.0000001, 3.0, "
                                "1.0471975511965979"), path, "exec")


def damage_flip(file):
    """A byte changed under the same time stamp: a disk's damage (a file written anew, by
    numba in another process, has a new one and is only read back)."""
    st = os.stat(file)
    data = bytearray(open(file, "rb").read())
    data[len(data) * 2 // 3] ^= 0x20
    open(file, "wb").write(bytes(data))
    os.utime(file, ns=(st.st_atime_ns, st.st_mtime_ns))


def damage_truncate(file):
    data = open(file, "rb").read()
    open(file, "wb").write(data[: len(data) // 2])


def damage_replace(file):
    """Another code object put in its place, as the bare marshal of the older layout."""
    path = os.path.join(os.path.dirname(os.path.dirname(file)), "fourbar.py")
    open(file, "wb").write(marshal.dumps(edited_code(path)))


def test_the_edit_would_move_the_numbers(module_copy):
    ns = {"__mechgen_python__": (plain.njit, plain.MATH), "__name__": "x"}
    exec(edited_code(module_copy), ns)        # noqa: S102 - the damage this file guards against
    assert ns["PARAMETER_DEFAULTS"][2] == 2.0000001


@pytest.mark.parametrize("damage", [damage_flip, damage_truncate, damage_replace])
def test_a_damaged_bytecode_cache_is_discarded(module_copy, damage):
    assert near_closed_form(plain_th4(module_copy))
    kept = kept_file(module_copy)
    damage(kept)
    with pytest.warns(RuntimeWarning, match="bytecode cache"):
        value = plain_th4(module_copy)
    assert near_closed_form(value)
    with warnings.catch_warnings():            # rewritten whole: no warning the next time
        warnings.simplefilter("error")
        assert near_closed_form(plain_th4(module_copy))


def test_a_cache_of_another_module_is_not_loaded(module_copy):
    plain_th4(module_copy)
    kept = kept_file(module_copy)
    code = plain._unpack(open(kept, "rb").read(), "0" * 64)
    assert code is None                        # another module's digest: refused


# -- numba's cache ------------------------------------------------------------------------
SCRIPT = ("import sys, mechgen; m = mechgen.load(sys.argv[1], tier='compiled'); "
          "print(repr(m.solve(%r)['Th4']))" % T)


def run_compiled(path):
    env = dict(os.environ, PYTHONPATH=ROOT, PYTHONWARNINGS="default")
    env.pop("NUMBA_CACHE_DIR", None)
    return subprocess.run([sys.executable, "-c", SCRIPT, path], capture_output=True,
                          text=True, env=env, timeout=600)


@pytest.mark.slow
def test_a_damaged_numba_cache_is_deleted_and_compiled_again(module_copy):
    # numba's cache of the committed module, copied beside the copy (the time stamp kept:
    # numba's index checks it), or made by a first run
    cache = os.path.join(os.path.dirname(module_copy), "__pycache__")
    os.makedirs(cache, exist_ok=True)
    for f in glob.glob(os.path.join(GENERATED, "__pycache__", "fourbar.*.nb[ic]")):
        shutil.copy2(f, cache)
    first = run_compiled(module_copy)
    assert first.returncode == 0 and near_closed_form(float(first.stdout)), first.stderr
    mark = os.path.join(cache, "fourbar-0123456789abcdef.compiled")
    open(mark, "w").close()                    # as runtime.tiers marks a complete cache
    names = lambda pattern: sorted(glob.glob(os.path.join(cache, pattern)))  # noqa: E731
    targets = {
        "index cut short": names("fourbar.solve_point_sorted-*.nbi"),
        "data cut short": names("fourbar.sweep_fast-*.nbc"),
        "data with a byte changed": names("fourbar.phi-*.nbc"),
        "empty index": names("fourbar.unwrap_turns-*.nbi"),
    }
    assert all(targets.values()), targets
    damage_truncate(targets["index cut short"][0])
    damage_truncate(targets["data cut short"][0])
    damage_flip(targets["data with a byte changed"][0])
    open(targets["empty index"][0], "wb").close()
    second = run_compiled(module_copy)
    assert second.returncode == 0, second.stderr
    assert "Traceback" not in second.stderr and "EOFError" not in second.stderr
    assert "numba's cache of" in second.stderr and "damaged" in second.stderr
    for what in ("solve_point_sorted", "sweep_fast", "phi-", "unwrap_turns"):
        assert what in second.stderr
    assert near_closed_form(float(second.stdout))
    assert not glob.glob(os.path.join(cache, "fourbar-*.compiled"))   # the tiers' mark gone
    third = run_compiled(module_copy)          # rebuilt whole: loaded without a word
    assert third.returncode == 0 and "damaged" not in third.stderr, third.stderr
    assert near_closed_form(float(third.stdout))
