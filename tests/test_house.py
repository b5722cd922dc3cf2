"""The shape of the house: imports flow one way between the layers of mechgen, and no
module of mechgen imports itself back through others (function-level imports included)."""
import ast
import os

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


def layer(module):
    parts = module.split(".")
    if module in ("mechgen", "mechgen.__main__"):
        return "api"
    if parts[1] in ("errors", "protocol", "turns", "units"):
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


def imports(name, path):
    """(imported module, line) for every import in the file, at any depth."""
    package = name if path.endswith("__init__.py") else name.rsplit(".", 1)[0]
    found = []
    with open(path, encoding="utf-8") as fh:
        tree = ast.parse(fh.read(), path)
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found += [(a.name, node.lineno) for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[:len(package.split(".")) - node.level + 1]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
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
        if theirs != mine and theirs not in ALLOWED[mine]:
            wrong.append(f"line {line}: {target} (the {mine} layer may not import the {theirs} layer)")
    assert not wrong, f"{name} imports against the direction of the layers:\n  " + "\n  ".join(wrong)


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
