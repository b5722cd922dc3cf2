"""The compiler's structure work (issue 6): block sorting and tearing, demand-driven pruning,
split functions for large models, the combined velocity/acceleration pass — each checked
against the full-Newton reference path of the same module."""
import os
import re
import sys

import numpy as np
import pytest

import mechgen
from mechgen.compiler.solver.blocks import sort_blocks
from mechgen.compiler.build import build, render

from conftest import ROOT, example_model

sys.path.insert(0, os.path.join(ROOT, "benchmarks"))
from chain_model import chain  # noqa: E402


def _at(model):
    at = {s: v for s, v in zip(model.coords, model.guess_vector())}
    at.update({sym: val for sym, val in model.params.values()})
    return at


def test_quick_return_sorts_like_the_hand_written_solver():
    """Th2 explicit, 1-unknown Newtons for Th3 and Th4, X4 torn with Y4 explicit."""
    m = example_model("quick_return")
    eq = m.equations()
    blocks = sort_blocks(eq.phi, eq.q, _at(m))
    kinds = [(b.kind, [str(eq.q[v]) for v in b.vars], [str(eq.q[v]) for v in b.tears])
             for b in blocks]
    assert ("explicit", ["Th2"], []) in kinds
    assert ("newton", ["Th3"], ["Th3"]) in kinds
    assert ("newton", ["Th4"], ["Th4"]) in kinds
    assert ("torn", ["X4", "Y4"], ["X4"]) in kinds
    assert len(blocks) == 8 and sum(b.size for b in blocks) == 9
    # every block only uses unknowns solved by itself or earlier blocks
    from mechgen.compiler.solver.blocks import incidence
    inc = incidence(eq.phi, eq.q)
    known = set()
    for b in blocks:
        for e in b.eqs:
            assert set(inc[e]) <= known | set(b.vars)
        known |= set(b.vars)


def test_derivatives_pass_equals_separate_solves(qr):
    mod = qr.module
    for t in (0.05, 0.3, 0.62, 0.85):
        s = qr.solve(t)
        qd, qdd = np.empty(qr.n), np.empty(qr.n)
        piv = np.zeros(1)
        assert mod.derivatives_sorted(s.q, t, qr.p, qd, qdd, piv) == 0
        assert abs(piv[0]) > 0                  # det Φ_q up to sign
        qd2, qdd2 = np.empty(qr.n), np.empty(qr.n)
        assert mod.velocity_full(s.q, t, qr.p, qd2) == 0
        assert mod.acceleration_full(s.q, qd2, t, qr.p, qdd2) == 0
        assert np.allclose(qd, qd2, rtol=1e-12, atol=1e-12)
        assert np.allclose(qdd, qdd2, rtol=1e-11, atol=1e-11)


@pytest.fixture(scope="module")
def pruned(build_dir):
    out = os.path.join(build_dir, "pruned")
    m = example_model("quick_return_slider")
    path = build(m, out, level="velocity", outputs=["X4"])
    return mechgen.load(path)


def test_pruned_build_solves_fewer_blocks(pruned, qr_slider):
    mod = pruned.module
    assert len(mod.BLOCKS) == 1 and len(qr_slider.module.BLOCKS) == 9
    assert mod.LEVEL == 1 and sum(mod.SOLVED) == 1
    s = pruned.solve(0.1, level="velocity")
    full = qr_slider.solve(0.1, level="velocity")
    assert abs(s["X4"] - full["X4"]) < 1e-12 and abs(s["X4d"] - full["X4d"]) < 1e-12
    with pytest.raises(KeyError, match="not solved by this build"):
        s["Th3"]
    with pytest.raises(ValueError, match="built for level velocity"):
        pruned.solve(0.1, level="acceleration")
    assert pruned.sweep(0.0, 0.2, 5, level="velocity").columns() == ["X4", "X4d"]


def test_pruned_text_is_smaller_and_names_what_it_left_out():
    m = example_model("quick_return")
    full = render(m)
    small = render(m, level="position", outputs=["Th3"])
    assert len(small) < 0.8 * len(full)
    for fn in ("velocity_sorted", "acceleration_sorted"):   # not built: a stub in their place
        assert re.search(rf'^def {fn}\(.*\):\n    """Not built in this module', small, re.M)
    assert "SOLVED = (True, True, True, True, True, True, False, False, False, )" in small


def test_pruning_rejects_unknown_names():
    m = example_model("quick_return")
    with pytest.raises(mechgen.ModelError, match="'Z9' is neither an output nor a coordinate"):
        render(m, outputs=["Z9"])


@pytest.fixture(scope="module")
def chain6_path(build_dir):
    """A chain of 4 four-bar loops, built with small parts so that every solver is split
    (as a 10-loop chain is with the default sizes)."""
    import mechgen.compiler.solver.plan as cg
    sizes = cg.CHUNK_LINES, cg.CHUNK_STORES
    cg.CHUNK_LINES, cg.CHUNK_STORES = 60, 16
    try:
        return build(chain(4, "chain4_split"), os.path.join(build_dir, "chain"))
    finally:
        cg.CHUNK_LINES, cg.CHUNK_STORES = sizes


@pytest.fixture(scope="module")
def chain6(chain6_path):
    """The split chain as plain Python: the same text and numbers as compiled, without
    compiling both solvers of it (numba compiles split parts of the velocity, acceleration,
    Φ_q and mass matrix in tests/test_andrews.py's module; the position's below)."""
    return mechgen.load(chain6_path, tier="python")


def test_large_model_is_split_into_parts(chain6):
    names = [n for n in dir(chain6.module) if "_part" in n]
    assert any(n.startswith("_position_part") for n in names)
    assert any(n.startswith("_phi_q_part") for n in names)
    assert any(n.startswith("_velocity_part") for n in names)
    assert any(n.startswith("_acceleration_part") for n in names)


def test_split_solvers_agree_with_full_newton(chain6, chain6_path):
    for t in (0.0, 0.13, 0.4):
        s = chain6.solve(t, level="acceleration", method="sorted")
        f = chain6.solve(t, level="acceleration", method="full", guess=s)
        assert s.method == "sorted"
        assert np.abs(s.q - f.q).max() < 1e-10
        assert np.abs(s.qd - f.qd).max() < 1e-9
        assert np.abs(s.qdd - f.qdd).max() < 1e-8
        assert s.residual < 1e-10
    # numba compiles the split position solver (in no committed module): the same numbers
    compiled = mechgen.load(chain6_path, tier="compiled")
    s = compiled.solve(0.0, method="sorted")
    assert s.method == "sorted" and compiled.tier == "compiled"
    assert np.abs(s.q - chain6.solve(0.0, method="sorted").q).max() < 1e-12


@pytest.fixture(scope="module")
def closed_form_builds(build_dir):
    """The quick-return and the four-bar with every standard-form block in closed form,
    and with Newton everywhere (as plain Python: the same text and numbers as compiled,
    without four modules' compiles)."""
    out = {}
    for name in ("quick_return", "fourbar"):
        for mode in ("all", "none"):
            m = example_model(name)
            m.name = f"{name}_{mode}"
            out[name, mode] = mechgen.load(build(m, os.path.join(build_dir, "cf"),
                                                 closed_forms=mode), tier="python")
    return out


def test_closed_forms_are_emitted_as_asked(closed_form_builds):
    import inspect
    src_all = inspect.getsource(closed_form_builds["quick_return", "all"].module)
    src_none = inspect.getsource(closed_form_builds["quick_return", "none"].module)
    assert "closed form: a sin(Th3) + b cos(Th3) + c = 0" in src_all
    assert "closed form: A X4^2 + B X4 + C = 0" in src_all
    assert "closed form:" not in src_none      # (the library's text speaks of them)
    assert "# Regenerate with: mechgen build quick_return.py --closed-forms all" in src_all


@pytest.mark.parametrize("mode", ["all", "none"])
def test_closed_forms_agree_with_full_newton(closed_form_builds, mode):
    mech = closed_form_builds["quick_return", mode]
    for t, guess in ((0.0, None), (0.3, None), (0.85, None), (0.85, {"X4": 1.0}), (0.62, None)):
        s = mech.solve(t, guess=guess, level="acceleration", method="sorted")
        f = mech.solve(t, guess=s, level="acceleration", method="full")
        assert np.abs(s.q - f.q).max() < 1e-12
        assert np.abs(s.qd - f.qd).max() < 1e-10 and np.abs(s.qdd - f.qdd).max() < 1e-9
    assert abs(mech.solve(0.85, guess={"X4": 1.0})["X4"] - 0.802632) < 1e-6
    fb = closed_form_builds["fourbar", mode]
    for th3, th4 in ((0.5274103891, 1.792465604), (-1.048246730, -2.313301945)):
        s = fb.solve(0.0, guess={"Th3": th3 + 0.2, "Th4": th4 - 0.2}, method="sorted")
        assert abs(s["Th3"] - th3) < 1e-9 and abs(s["Th4"] - th4) < 1e-9
    sw = mech.sweep(0.0, 1.0, 41, level="acceleration")
    ref = closed_form_builds["quick_return", "none"].sweep(0.0, 1.0, 41, level="acceleration")
    assert np.abs(sw.Q - ref.Q).max() < 1e-10


def test_closed_form_reports_no_assembly(build_dir):
    """The slider-driven quick-return inside its gap: the closed form finds no root and the
    solve fails with ConvergenceError instead of returning numbers. As plain Python (the
    same text and statuses; numba compiles closed forms in every committed module)."""
    m = example_model("quick_return_slider")
    m.name = "quick_return_slider_all"
    mech = mechgen.load(build(m, os.path.join(build_dir, "cf"), closed_forms="all"),
                        tier="python")
    assert abs(mech.solve(0.0)["Th3"] - 0.083778) < 1e-5
    with pytest.raises(mechgen.ConvergenceError):
        mech.solve(0.25, guess={"Th2": -1.0, "Th3": -0.64, "X4": 9.54})
