import os
import sys

import pytest

# the suite runs numba's compiled tier, as before there were tiers (tests/test_tiers.py
# chooses each tier itself); a mechanism loaded in "auto" would start background workers
os.environ.setdefault("MECHGEN_TIER", "compiled")

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EXAMPLES = os.path.join(ROOT, "examples")
GENERATED = os.path.join(ROOT, "generated")


def cuda_sim_env(**more):
    """The environment of a subprocess on numba's CUDA simulator (numba reads
    NUMBA_ENABLE_CUDASIM when first imported). Its mechanisms answer in the plain tier:
    the kernels are translated from the module's text whatever the tier, the CPU's tables
    they are compared with are the compiled tier's bit for bit (tests/test_tiers.py), and
    the checks that load a compiled tier say so; numba compiling the modules there cost a
    minute and a half of a cold run's CPU for the same numbers."""
    return dict(os.environ, NUMBA_ENABLE_CUDASIM="1", MECHGEN_TIER="python", **more)


def pytest_addoption(parser):
    parser.addoption("--update-golden", action="store_true", default=False,
                     help="rewrite the committed modules in generated/ that differ from what "
                          "the generator emits now (also: MECHGEN_UPDATE_GOLDEN=1)")


@pytest.fixture(scope="session")
def update_golden(request):
    """Whether golden files that differ are rewritten rather than reported."""
    return bool(request.config.getoption("--update-golden")) or \
        os.environ.get("MECHGEN_UPDATE_GOLDEN") == "1"


def example_model(name, model=None):
    from mechgen.model.loader import load_models, pick_model
    return pick_model(load_models(os.path.join(EXAMPLES, name + ".py")), model)


@pytest.fixture(scope="session")
def build_dir(tmp_path_factory):
    return str(tmp_path_factory.mktemp("generated"))


@pytest.fixture(scope="session")
def qr():
    """The crank-driven quick-return of seed 001, from the committed generated module."""
    import mechgen
    return mechgen.load(os.path.join(GENERATED, "quick_return.py"))


@pytest.fixture(scope="session")
def qr_slider():
    import mechgen
    return mechgen.load(os.path.join(GENERATED, "quick_return_slider.py"))


@pytest.fixture(scope="session")
def fourbar():
    import mechgen
    return mechgen.load(os.path.join(GENERATED, "fourbar.py"))


@pytest.fixture(scope="session")
def fourbar_loop():
    import mechgen
    return mechgen.load(os.path.join(GENERATED, "fourbar_loop.py"))


sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
