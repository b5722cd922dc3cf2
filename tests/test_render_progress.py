"""A long render says how long it will take and how far it is (``mechgen animate`` of
1001 frames took 640 s without a word): Animation.save reports each frame to a
``progress`` callable, and the command prints an estimate, then its progress, on stderr
when the film will take more than a few seconds (a quick one says nothing)."""
import io
import os

import matplotlib

matplotlib.use("Agg")

from mechgen import plot                                          # noqa: E402
from mechgen.cli import main                                      # noqa: E402
from mechgen.cli import progress as progress_module               # noqa: E402
from mechgen.cli.progress import RenderProgress                   # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


class Clock:
    def __init__(self, step):
        self.now, self.step = 0.0, step

    def __call__(self):
        now = self.now
        self.now += self.step
        return now


def test_save_reports_every_frame(fourbar, tmp_path):
    import matplotlib.pyplot as plt
    a = plot.animate(fourbar, fourbar.sweep(0, 0.5, 6))
    calls = []
    a.save(str(tmp_path / "f.gif"), progress=lambda done, total: calls.append((done, total)))
    plt.close(a.figure)
    assert calls == [(k, len(a)) for k in range(1, len(a) + 1)]


def test_a_long_render_says_its_estimate_and_progress():
    out = io.StringIO()
    p = RenderProgress("leg.gif", stream=out, clock=Clock(0.64))   # 0.64 s a frame
    for k in range(1, 1002):
        p(k, 1001)
    lines = out.getvalue().splitlines()
    assert lines[0].startswith("mechgen: rendering 1001 frames of the leg.gif: about 64")
    assert any("frame 501/1001 (50 %), about 3" in x for x in lines)
    assert lines[-1].startswith("mechgen: rendered 1001 frames in 64")
    assert 9 <= len(lines) <= 12


def test_a_quick_render_says_nothing():
    out = io.StringIO()
    p = RenderProgress(stream=out, clock=Clock(0.001))
    for k in range(1, 201):
        p(k, 200)
    assert out.getvalue() == ""


def test_mechgen_animate_prints_it(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(progress_module, "QUIET_SECONDS", -1.0)    # any film is long
    target = tmp_path / "fb.gif"
    assert main(["animate", os.path.join(ROOT, "examples", "fourbar.py"), "--outdir",
                 str(tmp_path / "gen"), "-n", "8", "-o", str(target)]) == 0
    err = capsys.readouterr().err
    assert "rendering 7 frames of the fb.gif" in err and target.exists()
