"""Gravity on a model whose moving bodies have no mass acts on nothing: building it warns
(ModelWarning, naming the model), `mechgen check` notes it; with a mass, no word."""
import warnings

import pytest

from mechgen import Model, ModelWarning, T
from mechgen.cli import main
from mechgen.compiler.build import render


def pendulum_crank(mass=None, gravity=True):
    m = Model("heavy" if mass else "weightless")
    ground = m.ground("ground", points=[(0, 0)])
    kw = {} if mass is None else {"mass": mass, "inertia": 0.1, "centroid": (0.5, 0)}
    crank = m.body("crank", points=[(0, 0), (1, 0)], guess=(0, 0, 0), **kw)
    m.revolute(ground[1], crank[1])
    m.rotation_lock(crank, ground, T, name="drive")
    if gravity:
        m.gravity(9.81)
    return m


def test_building_gravity_without_mass_warns_naming_the_model():
    with pytest.warns(ModelWarning, match="'weightless' sets gravity, but none of its"):
        render(pendulum_crank())


@pytest.mark.parametrize("model", [pendulum_crank(mass=2.0), pendulum_crank(gravity=False)],
                         ids=["with a mass", "without gravity"])
def test_no_warning_where_gravity_acts_or_is_absent(model):
    with warnings.catch_warnings():
        warnings.simplefilter("error", ModelWarning)
        render(model)


def test_check_notes_it(tmp_path, capsys):
    path = tmp_path / "weightless.py"
    path.write_text("from mechgen import Model, T\n"
                    "m = Model('weightless')\n"
                    "ground = m.ground('ground', points=[(0, 0)])\n"
                    "crank = m.body('crank', points=[(0, 0), (1, 0)], guess=(0, 0, 0))\n"
                    "m.revolute(ground[1], crank[1])\n"
                    "m.rotation_lock(crank, ground, T, name='drive')\n"
                    "m.gravity(9.81)\n")
    main(["check", str(path)])
    assert "note: model 'weightless' sets gravity, but none of its moving bodies has a mass" \
        in capsys.readouterr().out
