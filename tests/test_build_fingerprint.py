"""An unchanged model is not rendered again (issue 12): build_if_changed keeps a build
fingerprint beside numba's cache and skips the symbolic work when it matches; any change
to the model, the options or the module file renders again, and the text is the render's."""
import importlib
import os

import pytest

from conftest import example_model
from mechgen.compiler.build import build_if_changed, render
from mechgen.compiler.fingerprint import fingerprint, record_path


@pytest.fixture
def counting(monkeypatch):
    """Counts the renders build_if_changed makes."""
    calls = []
    build_mod = importlib.import_module("mechgen.compiler.render")
    real = build_mod.render

    def spy(model, **kw):
        calls.append(model.name)
        return real(model, **kw)

    monkeypatch.setattr(build_mod, "render", spy)
    return calls


def _model(longitud=3.0, guess_x4=6.0, distance=5, output=True):
    from mechgen import Model, T, location, pi
    m = Model("qr_fp")
    lon = m.param("longitud", longitud)
    vel = m.param("velocidad", 2 * pi)
    base = m.ground("base", points=[(0, 0), (0, 5), (-5, 10), (12, 10)])
    man = m.body("manivela", points=[(0, 0), (lon, 0)], guess=(0, 5, 0))
    col = m.body("colisa", points=[(0, 0), (0, 9)], guess=(0, 0, -0.5))
    des = m.body("deslizadera", points=[(0, 0), (2, 0)], guess=(guess_x4, 10, 0))
    m.revolute(base[2], man[1])
    m.rotation_lock(man, base, vel * T, name="crank driver")
    m.revolute(base[1], col[1])
    m.point_on_line(man[2], col.line(1, 2))
    m.relative_distance(col[2], des[1], distance)
    m.translate(base.line(3, 4), des.line(1, 2))
    if output:
        m.output("stroke_x", location(des[1])[0])
    return m


def test_an_unchanged_model_is_not_rendered_again(tmp_path, counting):
    path = build_if_changed(_model(), str(tmp_path), level="position")
    assert counting == ["qr_fp"] and os.path.isfile(record_path(path))
    mtime = os.stat(path).st_mtime_ns
    assert build_if_changed(_model(), str(tmp_path), level="position") == path
    assert counting == ["qr_fp"]                      # a new but equal model: no render
    assert os.stat(path).st_mtime_ns == mtime         # nor a rewrite (numba's cache stays)
    with open(path, encoding="utf-8") as fh:
        assert fh.read() == render(_model(), level="position")


@pytest.mark.parametrize("change", [dict(longitud=3.5), dict(guess_x4=6.5), dict(distance=4),
                                    dict(output=False)])
def test_every_change_of_the_model_renders_again(tmp_path, counting, change):
    build_if_changed(_model(), str(tmp_path), level="position")
    changed = _model(**change)
    assert fingerprint(changed, level="position") != fingerprint(_model(), level="position")
    path = build_if_changed(changed, str(tmp_path), level="position")
    assert counting == ["qr_fp", "qr_fp"]
    with open(path, encoding="utf-8") as fh:
        assert fh.read() == render(changed, level="position")


def test_other_options_or_an_edited_module_render_again(tmp_path, counting):
    path = build_if_changed(_model(), str(tmp_path), level="position")
    build_if_changed(_model(), str(tmp_path), level="velocity")
    assert len(counting) == 2
    with open(path, encoding="utf-8") as fh:
        assert fh.read() == render(_model(), level="velocity")
    with open(path, "a", encoding="utf-8") as fh:
        fh.write("# edited\n")
    build_if_changed(_model(), str(tmp_path), level="velocity")
    assert len(counting) == 3
    with open(path, encoding="utf-8") as fh:
        assert fh.read() == render(_model(), level="velocity")


def test_the_fingerprint_of_an_example_is_stable():
    a = fingerprint(example_model("quick_return"))
    assert a == fingerprint(example_model("quick_return"))
    assert a != fingerprint(example_model("quick_return_slider"))
