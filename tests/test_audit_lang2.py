"""Second audit of the model language and command line (API.md §1-3): defects found,
each pinned by a small case."""
import subprocess
import sys

import mechgen


def test_star_import_of_mechgen_gives_every_exported_name():
    # `from mechgen import *` at the top of a model file raised ModuleNotFoundError
    # (mechgen.runtime.design): __all__ listed DesignTable, Reduction, OptimizeResult at
    # their modules' old places
    code = ("from mechgen import *\n"
            "m = Model('star'); x = m.coordinate('x', 0.0); m.constraint(x - sin(T))\n"
            "print(DesignTable.__name__, Reduction.__name__, OptimizeResult.__name__)\n")
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         cwd=str(__import__("pathlib").Path(mechgen.__file__).parents[1]))
    assert res.returncode == 0, res.stderr
    assert res.stdout.split() == ["DesignTable", "Reduction", "OptimizeResult"]
    for name in mechgen.__all__:
        assert getattr(mechgen, name) is not None
