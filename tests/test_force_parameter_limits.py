"""Parameters the model refuses are refused at run time too (issue 43): a spring's negative
stiffness or free length, a damper's negative coefficient, given through ``with_params``
or ``load(..., params=)``, is a ValueError naming the load and the parameter, as the model
refuses the same values at its defaults (model/forces/loads.py)."""
import math

import pytest

import mechgen
from mechgen import Model, T


def sprung(name="force_parameter_limits"):
    """A crank turning 2π rad/s, a spring ``spr`` (k = kk, free length L0) and a damper
    ``dmp`` (c = cc) from its tip to the ground point (0, 3)."""
    m = Model(name)
    g = m.ground("g", points=[(0, 0), (0, 3)])
    crank = m.body("crank", points=[(0, 0), (1, 0)], guess=(0, 0, 0), mass=1.0,
                   inertia=0.1, centroid=(0.5, 0))
    m.revolute(g[1], crank[1])
    m.rotation_lock(crank, 2 * math.pi * T, name="drive")
    kk, L0, cc = m.param("kk", 100.0), m.param("L0", 0.5), m.param("cc", 2.0)
    m.spring(crank[2], g[2], kk, L0, name="spr")
    m.damper(crank[2], g[2], cc, name="dmp")
    return m


@pytest.fixture(scope="module")
def mech(tmp_path_factory):
    return mechgen.compile(sprung(), outdir=str(tmp_path_factory.mktemp("gen")),
                           tier="python")


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
