"""Parameters the model refuses are refused at run time too (issue 43): a spring's negative
stiffness or free length, a damper's negative coefficient, given through ``with_params``
or ``load(..., params=)``, is a ValueError naming the load and the parameter, as the model
refuses the same values at its defaults (model/forces/loads.py); in a force design table
(a negative mass too), design by design, naming the design's index and values."""
import math

import numpy as np
import pytest

import mechgen
from mechgen import Model
from models import sprung_crank


@pytest.fixture(scope="module")
def mech(tmp_path_factory):
    return mechgen.compile(sprung_crank("force_parameter_limits"),
                           outdir=str(tmp_path_factory.mktemp("gen")), tier="python")


@pytest.mark.parametrize("given, load, said", [
    (dict(kk=-100.0), "spring 'spr'", r"stiffness k kk = -100 is negative"),
    (dict(L0=-0.5), "spring 'spr'", r"free length L0 = -0.5 is negative"),
    (dict(cc=-1.0), "damper 'dmp'", r"coefficient c cc = -1 is negative"),
])
def test_with_params_refuses_what_the_model_refuses(mech, given, load, said):
    with pytest.raises(ValueError, match=rf"{load}: the {said}"):
        mech.with_params(**given)
    with pytest.raises(mechgen.ModelError, match="negative"):   # the model's own word
        m = Model("refused")
        g = m.ground("g", points=[(0, 0), (0, 3)])
        b = m.body("b", points=[(0, 0), (1, 0)], guess=(0, 0, 0), mass=1.0)
        value = next(iter(given.values()))
        if "cc" in given:
            m.damper(b[2], g[2], value)
        else:
            m.spring(b[2], g[2], value if "kk" in given else 1.0,
                     value if "L0" in given else 0.5)


def test_allowed_values_pass_and_solve(mech):
    soft = mech.with_params(kk=0.0, L0=0.0, cc=0.0)     # zero is allowed through a parameter
    assert soft.parameters["kk"] == 0.0
    s = soft.solve(0.1, level="dynamic")
    assert math.isfinite(s.driver("drive"))


def test_load_with_params_refuses_too(mech):
    with pytest.raises(ValueError, match=r"spring 'spr'.*kk = -3"):
        mechgen.load(mech.module, params={"kk": -3.0})


def test_the_module_names_its_load_constants(mech):
    names = [(kind, name, expr) for kind, name, _, expr, _ in mech.module.LOAD_CONSTANTS]
    assert names == [("spring", "spr", "kk"), ("spring", "spr", "L0"), ("damper", "dmp", "cc")]


@pytest.mark.parametrize("params, said", [
    (dict(kk=[100.0, 50.0, -100.0]), r"design 2 \(kk=-100\): spring 'spr'.*negative"),
    (dict(cc=[1.0, -1.0], kk=[10.0, 20.0]),
     r"design 2 \(cc=-1, kk=10\): damper 'dmp'.*negative"),
    (dict(L0=[0.5, -0.5]), r"design 1 \(L0=-0.5\): spring 'spr'.*free length"),
    (dict(mm=[1.0, 2.0, -1.0]), r"design 2 \(mm=-1\): body 'crank' has a negative mass"),
])
def test_a_refused_design_is_named(mech, params, said):
    with pytest.raises(ValueError, match=rf"model 'force_parameter_limits': {said}"):
        mech.sweep(0.0, 1.0, 5, params=params, level="dynamic")


def test_allowed_designs_run_and_kinematic_tables_are_not_judged(mech):
    tab = mech.sweep(0.0, 1.0, 5, params=dict(kk=[100.0, 0.0, 50.0]), level="dynamic")
    assert np.all(tab.ok)
    # the kinematics does not read the springs: nothing to refuse there
    tab = mech.sweep(0.0, 1.0, 5, params=dict(kk=[100.0, -100.0]), level="position")
    assert np.all(tab.ok)
