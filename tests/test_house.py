"""The shape of the house: imports flow one way between the layers of mechgen and between
the packages of its runtime, no module of mechgen imports itself back through others
(function-level imports and imports by name, importlib.import_module or __import__,
included), no module imports another package's private (underscore) names, and nothing
outside runtime/mechanism.py reaches into a Mechanism's private attributes."""
import ast
import os
import re

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PACKAGE = os.path.join(ROOT, "mechgen")

# the layer each may import from (besides itself); "api" is mechgen/__init__.py
ALLOWED = {
    "base": set(),
    "model": {"base"},
    "compiler": {"base", "model"},
    "runtime": {"base"},
    "plot": {"base", "runtime"},
    "bridge": {"base", "model", "compiler", "runtime"},
    "view": {"base", "runtime", "plot"},
    "synthesis": {"base", "model", "runtime", "bridge"},
    "cli": {"base", "model", "compiler", "runtime", "plot", "bridge", "view", "synthesis",
            "api"},
    "api": {"base", "model", "compiler", "runtime", "plot", "bridge", "view", "synthesis",
            "cli"},
}
NO_SYMPY = {"base", "runtime", "plot", "view"}
# imports against the layers made by name where they are used: none. ``mech.explore()``
# reaches the live view (a layer above the runtime) through mechgen.extensions' slot, which
# the package's __init__ fills
UPWARD_BY_NAME = set()

# the runtime's packages and modules from the bottom up: each imports only those before it
# (mechgen/DESIGN.md draws them). An entry names a package or a module; a module belongs
# to the longest entry that names it or a package above it.
RUNTIME_ORDER = (
    "loading",                  # the generated module, checked, and its tiers
    "guards",                   # the arguments users pass, checked
    "state",                    # RuntimeState: what a Mechanism holds between calls
    "quantity",                 # names of coordinates, outputs and their rates
    "unit_columns",             # a table's columns in the model's units
    "analysis.cycle",           # curves of a sweep: whether it is one closed period,
    "analysis.interpolate",     # its interpolants,
    "analysis.events",          # its extremes and roots (Sweep's methods)
    "results",                  # Solution, Sweep
    "analysis",                 # rank loss, locks, assembly modes, the errors of a solve
    "kinematics",               # solve, sweep, follow the motion, stages
    "forces",                   # multipliers, efforts, reactions, simulate
    "sensitivity",              # derivatives with respect to the parameters, tolerances
    "tables",                   # design tables: threads, Dask, CUDA; synthesis
    "fitting",                  # path fitting
    "mechanism",                # the façade users call
    "",                         # mechgen.runtime itself
)
# processes' entry points: the top of the house, whatever folder they sit in
RUNTIME_ENTRY_POINTS = {"mechgen.runtime.loading.warmup"}


def layer(module):
    parts = module.split(".")
    if module in ("mechgen", "mechgen.__main__"):
        return "api"
    if parts[1] in ("errors", "protocol", "turns", "units", "extensions"):
        return "base"
    return parts[1]


def modules():
    out = {}
    for folder, _, files in os.walk(PACKAGE):
        for f in files:
            if f.endswith(".py"):
                path = os.path.join(folder, f)
                rel = os.path.relpath(path, ROOT)[:-3].replace(os.sep, ".")
                name = rel[:-len(".__init__")] if rel.endswith(".__init__") else rel
                out[name] = path
    return out


def _resolve(package, level, module):
    """The absolute name of ``from <level dots><module> import``, inside ``package``."""
    if not level:
        return module or ""
    base = package.split(".")[:len(package.split(".")) - level + 1]
    return ".".join(base + ([module] if module else []))


def _by_name(node, package, constants):
    """The modules an importlib.import_module(...) or __import__(...) call imports: its
    argument where it is a string (relative to ``package=__name__``); where it is made at
    run time (``"." + name``, an f-string), every module of the package a string of the
    file names (a lazy table of submodules), so that none hides."""
    func = node.func
    called = func.attr if isinstance(func, ast.Attribute) else getattr(func, "id", None)
    if called not in ("import_module", "__import__") or not node.args:
        return []
    arg = node.args[0]
    if isinstance(arg, ast.Constant) and isinstance(arg.value, str):
        text = arg.value
        if text.startswith("."):
            dots = len(text) - len(text.lstrip("."))
            return [_resolve(package, dots, text[dots:])]
        return [text]
    return [f"{package}.{c}" for c in constants] + [f"{package.split('.')[0]}.{c}"
                                                    for c in constants]


def imports(name, path):
    """(imported module, line) for every import in the file, at any depth, those made by
    name (importlib) included."""
    package = name if path.endswith("__init__.py") else name.rsplit(".", 1)[0]
    found = []
    with open(path, encoding="utf-8") as fh:
        tree = ast.parse(fh.read(), path)
    constants = {n.value.lstrip(".") for n in ast.walk(tree) if isinstance(n, ast.Constant)
                 and isinstance(n.value, str) and re.fullmatch(r"\.?[\w.]+", n.value)}
    for node in ast.walk(tree):
        if isinstance(node, ast.Call):
            found += [(target, node.lineno) for target in _by_name(node, package, constants)
                      if target in MODULES]
        elif isinstance(node, ast.Import):
            found += [(a.name, node.lineno) for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            target = _resolve(package, node.level, node.module)
            found.append((target, node.lineno))
            found += [(target + "." + a.name, node.lineno) for a in node.names]
    return found


MODULES = modules()


def test_the_layers_are_where_the_design_note_says():
    for package in ("model", "compiler", "runtime", "plot", "view", "cli"):
        assert f"mechgen.{package}" in MODULES
    assert "mechgen.protocol" in MODULES and "mechgen.bridge" in MODULES


@pytest.mark.parametrize("name", sorted(MODULES))
def test_imports_flow_one_way(name):
    mine = layer(name)
    wrong = []
    for target, line in imports(name, MODULES[name]):
        top = target.split(".")[0]
        if top == "sympy" and mine in NO_SYMPY:
            wrong.append(f"line {line}: sympy (the {mine} layer never imports sympy)")
        if top != "mechgen" or target not in MODULES or target == "mechgen":
            continue
        theirs = layer(target)
        if theirs != mine and theirs not in ALLOWED[mine] and \
                (name, ".".join(target.split(".")[:2])) not in UPWARD_BY_NAME:
            wrong.append(f"line {line}: {target} (the {mine} layer may not import the {theirs} layer)")
    assert not wrong, f"{name} imports against the direction of the layers:\n  " + "\n  ".join(wrong)


def runtime_rank(module):
    """The place of a runtime module in RUNTIME_ORDER (the longest entry naming it)."""
    if module in RUNTIME_ENTRY_POINTS:
        return len(RUNTIME_ORDER)
    inner = module[len("mechgen.runtime."):] if module != "mechgen.runtime" else ""
    best = None
    for rank, entry in enumerate(RUNTIME_ORDER):
        if inner == entry or inner.startswith(entry + ".") or (entry == "" and not inner):
            if best is None or len(entry) > len(RUNTIME_ORDER[best]):
                best = rank
    return best


@pytest.mark.parametrize("name", sorted(m for m in MODULES if m.startswith("mechgen.runtime")))
def test_the_runtime_imports_only_downwards(name):
    """Inside runtime/, a module imports only packages below its own (RUNTIME_ORDER)."""
    mine = runtime_rank(name)
    assert mine is not None, f"{name} is in no entry of RUNTIME_ORDER: place it there"
    wrong = []
    for target, line in imports(name, MODULES[name]):
        if target in MODULES and target.startswith("mechgen.runtime"):
            theirs = runtime_rank(target)
            if theirs is not None and theirs > mine:
                above = RUNTIME_ORDER[min(theirs, len(RUNTIME_ORDER) - 1)]
                wrong.append(f"line {line}: {target} ({above!r} is above "
                             f"{RUNTIME_ORDER[mine]!r})")
    assert not wrong, f"{name} imports up the runtime:\n  " + "\n  ".join(wrong)


def _private_imports(name, path):
    """(line, module, name) for each underscore name imported from another package."""
    package = name if path.endswith("__init__.py") else name.rsplit(".", 1)[0]
    with open(path, encoding="utf-8") as fh:
        tree = ast.parse(fh.read(), path)
    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            target = _resolve(package, node.level, node.module)
            if not target.startswith("mechgen"):
                continue
            theirs = target if MODULES.get(target, "").endswith("__init__.py") else \
                target.rsplit(".", 1)[0]
            out += [(node.lineno, target, a.name) for a in node.names
                    if a.name.startswith("_") and not a.name.startswith("__")
                    and theirs != package]
    return out


def test_no_module_imports_another_packages_private_names():
    wrong = [f"{name}:{line} {target}.{what}" for name, path in sorted(MODULES.items())
             for line, target, what in _private_imports(name, path)]
    assert not wrong, "private names imported across packages (make them public):\n  " + \
        "\n  ".join(wrong)


PRIVATE_OF_MECHANISM = re.compile(r"\bmech(anism)?\._[a-z]|getattr\(mech, \"_|setattr\(mech, \"_")


def test_nothing_outside_the_facade_touches_a_mechanisms_private_attributes():
    """What a Mechanism holds is its ``state`` (runtime.state.RuntimeState): no module but
    runtime/mechanism.py reads or attaches ``mech._x``."""
    wrong = []
    for name, path in sorted(MODULES.items()):
        if name == "mechgen.runtime.mechanism":
            continue
        with open(path, encoding="utf-8") as fh:
            for k, text in enumerate(fh, 1):
                if PRIVATE_OF_MECHANISM.search(text):
                    wrong.append(f"{name}:{k}: {text.strip()}")
    assert not wrong, "private attributes of a Mechanism reached from outside:\n  " + \
        "\n  ".join(wrong)


def _mechanism_methods():
    """The public methods of Mechanism, read from its source (no import: the house test
    imports nothing of mechgen)."""
    with open(MODULES["mechgen.runtime.mechanism"], encoding="utf-8") as fh:
        tree = ast.parse(fh.read())
    cls = next(n for n in tree.body if isinstance(n, ast.ClassDef) and n.name == "Mechanism")
    return {f.name for f in cls.body if isinstance(f, ast.FunctionDef)
            and not f.name.startswith("_") and not any(
                isinstance(d, ast.Name) and d.id == "property" or
                isinstance(d, ast.Attribute) and d.attr == "setter" for d in f.decorator_list)}


# the names a Mechanism goes by in the runtime's code
MECHANISM_NAMES = {"mech", "mechanism", "owner", "ref", "other"}


@pytest.mark.parametrize("name", sorted(m for m in MODULES
                                        if m.startswith("mechgen.runtime.kinematics")))
def test_the_kinematics_never_call_the_mechanism(name):
    """The kinematics take the state and return results: no call of a Mechanism's
    methods (mech.sweep, mech.with_params(...).set_guess, ...) from runtime/kinematics/."""
    methods = _mechanism_methods()
    with open(MODULES[name], encoding="utf-8") as fh:
        tree = ast.parse(fh.read())
    wrong = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and \
                node.func.attr in methods:
            owner = node.func.value
            said = owner.attr if isinstance(owner, ast.Attribute) else \
                getattr(owner, "id", None)
            if said in MECHANISM_NAMES:
                wrong.append(f"line {node.lineno}: {ast.unparse(node.func)}()")
    assert not wrong, f"{name} calls the Mechanism:\n  " + "\n  ".join(wrong)


def test_no_import_cycles():
    graph = {m: {t for t, _ in imports(m, p) if t in MODULES and t not in (m, "mechgen")}
             for m, p in MODULES.items()}
    index, low, stack, on, cycles = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in sorted(graph[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                cycles.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    assert not cycles, "import cycles inside mechgen: " + "; ".join(" <-> ".join(c) for c in cycles)


def test_no_file_is_too_long_to_read():
    long = {m: n for m, p in MODULES.items() if (n := sum(1 for _ in open(p, encoding="utf-8"))) > 600}
    assert not long, f"files over 600 lines: {long}"


def test_every_package_is_installed():
    """pyproject.toml lists every folder of mechgen that holds an __init__.py: a package
    left out is missing from a wheel (an editable install hides it)."""
    import re
    text = open(os.path.join(ROOT, "pyproject.toml"), encoding="utf-8").read()
    listed = set(re.findall(r'"(mechgen(?:\.\w+)*)"', text.split("packages =", 1)[1]
                            .split("]", 1)[0]))
    found = {os.path.relpath(d, ROOT).replace(os.sep, ".")
             for d, _, files in os.walk(PACKAGE) if "__init__.py" in files}
    assert found <= listed, sorted(found - listed)


def test_the_templates_lay_out_and_the_library_computes():
    """The templates hold layout (under 400 lines together, the house tool's limit): the
    numerics of a module are Python in compiler/library/, tested as Python."""
    folder = os.path.join(ROOT, "templates")
    lines = sum(sum(1 for _ in open(os.path.join(folder, f), encoding="utf-8"))
                for f in os.listdir(folder) if f.endswith(".j2"))
    assert lines < 400, f"templates/: {lines} lines"
