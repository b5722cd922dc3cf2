"""The solver plan alone: how each block of the quick-return is solved under each
--closed-forms choice, pruning, constants, shared calls and parts; and the generated
docstring, BLOCKS and code saying the same."""
import dataclasses
import os
import re
import sys

import pytest

from mechgen.compiler.solver.blocks import (CLOSED_FORM_QUADRATIC, CLOSED_FORM_TRIG, EXPLICIT,
                                     NEWTON)
from mechgen.compiler.build import render
from mechgen.compiler.context import module_context
from mechgen.compiler.solver.plan import BlockPlan, make_plan

from conftest import ROOT, example_model

sys.path.insert(0, os.path.join(ROOT, "benchmarks"))
from chain_model import chain  # noqa: E402


def methods(model, **kw):
    eq = model.equations()
    plan = make_plan(model, eq, **kw)
    return plan, [(b.method, [eq.q[v].name for v in b.vars], [eq.q[v].name for v in b.tears])
                  for b in plan.blocks]


def test_quick_return_block_methods():
    m = example_model("quick_return")
    plan, found = methods(m)
    # the blocks that stay the same along a sweep first (the ground pins, the slider's
    # angle on its guide): the fast sweep solves them once, before its loop
    assert found == [(EXPLICIT, ["X2"], []), (EXPLICIT, ["Y2"], []),
                     (EXPLICIT, ["X3"], []), (EXPLICIT, ["Y3"], []),
                     (CLOSED_FORM_TRIG, ["Th4"], ["Th4"]),       # 34 sin(Th4) = 0: no calls
                     (EXPLICIT, ["Th2"], []),
                     (CLOSED_FORM_TRIG, ["Th3"], ["Th3"]),       # a, b vary: by a sign
                     (CLOSED_FORM_QUADRATIC, ["X4", "Y4"], ["X4"])]  # circle-line, Y4 explicit
    assert plan.steady == 5
    th4 = plan.blocks[4]
    assert th4.form[0] == 34 and th4.form[1] == 0 and th4.form[2] == 0
    assert plan.sorted and plan.level == 2 and all(plan.solved) and plan.share
    assert plan.position_parts == ()
    assert {str(s): v for s, v in plan.known} == {"X2": 0, "Y2": 5, "X3": 0, "Y3": 0}
    # the angles whose sin and cos the position code calls as a pair (the sweep turns them)
    assert [str(y) for y in plan.position.trig_pairs] == ["Th3", "Th2"]
    # the forms whose root a sign picks: the lever's angle, the slider's x
    assert [str(y) for y in plan.position.signs] == ["Th3", "X4"]


def test_closed_forms_all_and_none():
    m = example_model("quick_return")
    _, found = methods(m, closed_forms="all")
    assert found[4] == (CLOSED_FORM_TRIG, ["Th4"], ["Th4"])
    assert found[6] == (CLOSED_FORM_TRIG, ["Th3"], ["Th3"])
    assert found[7] == (CLOSED_FORM_QUADRATIC, ["X4", "Y4"], ["X4"])
    _, found = methods(m, closed_forms="none")
    assert [x[0] for x in found[4:]] == [NEWTON, EXPLICIT, NEWTON, NEWTON]
    with pytest.raises(ValueError, match="closed_forms must be"):
        methods(m, closed_forms="some")


def test_the_plan_is_frozen_and_checks_itself():
    plan, _ = methods(example_model("quick_return"))
    with pytest.raises(dataclasses.FrozenInstanceError):
        plan.level = 1
    with pytest.raises(dataclasses.FrozenInstanceError):
        plan.blocks[0].method = NEWTON
    with pytest.raises(ValueError, match="unknown method"):
        BlockPlan(kind="newton", vars=(0,), rows=(0,), method="bisection")
    with pytest.raises(ValueError, match="one tear"):
        BlockPlan(kind="torn", vars=(0, 1), rows=(0, 1), tears=(0, 1), method=CLOSED_FORM_TRIG,
                  form=(1, 0, 0))


def test_pruned_plan():
    m = example_model("quick_return")
    plan, found = methods(m, level="position", outputs=["Th3"])
    assert [x[1] for x in found] == [["X2"], ["Y2"], ["X3"], ["Y3"], ["Th2"], ["Th3"]]
    assert plan.steady == 4
    assert plan.solved == (True,) * 6 + (False,) * 3 and plan.level == 0
    assert plan.outputs == ()


def test_large_model_is_planned_in_parts_without_shared_calls():
    m = chain(10)
    plan = make_plan(m, m.equations())
    assert not plan.share and len(plan.position_parts) > 1
    assert sorted(k for part in plan.position_parts for k in part) == list(range(len(plan.blocks)))
    small = make_plan(chain(2), chain(2).equations())
    assert small.share and small.position_parts == ()


def test_docstring_blocks_and_code_say_how_each_block_is_solved():
    text = render(example_model("quick_return"))
    doc = text[:text.index('"""\nimport math')]
    assert "  5. Th4 (closed form: a sin(Th4) + b cos(Th4) + c = 0)\n" in doc
    assert "  7. Th3 (closed form: a sin(Th3) + b cos(Th3) + c = 0, the guess's sign)\n" in doc
    assert "  8. X4, Y4 (closed form: A X4^2 + B X4 + C = 0, the guess's sign; Y4 explicit)\n" \
        in doc
    assert '    ("closed_form_trig", ("Th3", ), (5, )),' in text
    assert '    ("closed_form_trig", ("Th4", ), (7, )),' in text
    assert '    ("closed_form_quadratic", ("X4", "Y4", ), (6, 8, )),' in text
    solver = text[text.index("def position_sorted("):text.index("def velocity_sorted(")]
    assert "# closed form: a sin(Th4) + b cos(Th4) + c = 0, the root nearest Th4" in solver
    assert solver.count("for _it in range(maxit):") == 0          # no Newton left


def test_context_keys_of_the_fast_sweep():
    m = example_model("quick_return")
    ctx = module_context(m)
    assert {"sweep_step", "sweep_init", "sweep_keep", "sweep_resync"}.isdisjoint(ctx)
    body = ctx["sweep_fast"]
    assert body[0].startswith("# (the loop's own names") and body[-1] == "return ts.shape[0]"
    assert "    if _sw_warm:" in body and "        return _sw_good" in body  # inside the loop
    assert not any(line.strip() in ("return 1", "return 2", "return 4") for line in body)
    assert [b["method"] for b in ctx["blocks"]][4:] == [CLOSED_FORM_TRIG, EXPLICIT,
                                                        CLOSED_FORM_TRIG, CLOSED_FORM_QUADRATIC]
    assert module_context(m, sort=False)["sweep_fast"] is None
    assert module_context(m, level="velocity")["sweep_fast"] is None
    # a model whose solvers are split calls them from the loop instead
    big = module_context(chain(10))["sweep_fast"]
    assert "    if position_sorted(q, t, p, tol, xtol, maxit, info) != 0:" in big


def test_jacobian_rows_are_labelled_once():
    text = render(example_model("quick_return"))
    body = text[text.index("def phi_q("):text.index("def nu(")]
    label = "# 4 point_on_line(manivela[2], colisa.line(1, 2))"
    assert body.count(label) == 1 and " / d" not in body
    # intermediate terms are never a bare symbol or number, or its negation (_t0 = -X3)
    assert not re.search(r"^\s+_t\d+ = -?[\w.]+$", text, re.M)
