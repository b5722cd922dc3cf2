"""The one bridge between the runtime and sympy: ``mechgen.compile`` and the symbolic side
it attaches to a Mechanism, to evaluate any symbolic quantity on a solved configuration
or a whole sweep.

The runtime never imports this module (nor sympy): ``compile_model`` builds and loads a
module, then ``attach`` sets ``mech.model`` and ``mech.symbolic`` (a :class:`Symbolic`),
which the runtime calls for ``mech.evaluate(expr, s)`` and for the time derivative and
level of a symbolic quantity (interpolation, extremes, roots). The expression is
lambdified once (numpy backend) in the symbols it uses, then called on whole columns of
a sweep at once.

Symbols are matched by name against the mechanism's coordinates (``X4``), velocities
(``X4d``), accelerations (``X4dd``), parameters (values from ``mech.p``, so
``with_params`` is honoured) and the time ``T``.
"""
from __future__ import annotations

import functools
import hashlib
import json
import os
import sys

import numpy as np

from .errors import MechgenError, ModelError
from .protocol import LEVEL, LEVELS, MECHGEN_VERSION
from .runtime import load
from .runtime.results import Solution, Sweep

# sympy, the model and the compiler are imported where they are used: a model file whose
# module is already built loads without them (compile_file)


def _slots(mech):
    """name -> (kind, index): kind the level (an index into LEVELS: q, qd, qdd) for a
    coordinate and its derivatives, 'p' for a parameter, 't' for T."""
    table = {"T": ("t", 0)}
    for k, name in enumerate(mech.parameter_names):
        table[name] = ("p", k)
    for k, c in enumerate(mech.coordinates):
        table[c] = (LEVEL["position"], k)
        table[c + "d"] = (LEVEL["velocity"], k)
        table[c + "dd"] = (LEVEL["acceleration"], k)
    return table


def _compiled(mech, expr):
    """(function, symbols, shape) for ``expr``, cached on the mechanism."""
    import sympy as sp
    cache = mech.state.evaluate_cache
    if isinstance(expr, (list, tuple)):
        expr = sp.Matrix(expr)
    if isinstance(expr, sp.MatrixBase):
        expr = sp.ImmutableMatrix(expr)
    else:
        try:
            expr = sp.sympify(expr)
        except (sp.SympifyError, TypeError):
            raise TypeError(f"evaluate() takes a sympy expression or Matrix, got {expr!r}") from None
        if not isinstance(expr, sp.Expr):
            raise TypeError(f"evaluate() takes a sympy expression or Matrix, got {expr!r}")
    hit = cache.get(expr)
    if hit is not None:
        return hit
    table = _slots(mech)
    syms = sorted(expr.free_symbols, key=lambda s: s.name)
    unknown = [s.name for s in syms if s.name not in table]
    if unknown:
        raise ModelError(
            f"evaluate(): {', '.join(unknown)} {'is' if len(unknown) == 1 else 'are'} not a "
            f"coordinate (or its d/dd derivative), parameter or T of '{mech.name}'",
            where="")
    if isinstance(expr, sp.MatrixBase):
        shape = expr.shape
        entries = list(expr)
    else:
        shape = None
        entries = [expr]
    from .model.rates import almost_everywhere       # the module's own rates
    fn = sp.lambdify(syms, [almost_everywhere(e) for e in entries], modules="numpy")
    hit = (fn, [table[s.name] for s in syms], shape)
    cache[expr] = hit
    return hit


def _needed_level(slots) -> int:
    return max((kind for kind, _ in slots if isinstance(kind, int)), default=LEVEL["position"])


def evaluate(mech, expr, solution_or_sweep):
    """The value of ``expr`` at a :class:`Solution` (a float, or an array shaped like the
    Matrix with column vectors flattened) or along a :class:`Sweep` (the same with a
    leading axis of length ``len(sweep)``)."""
    target = solution_or_sweep
    if not isinstance(target, (Solution, Sweep)):
        raise TypeError("evaluate() needs a Solution or a Sweep (from mech.solve or mech.sweep), "
                        f"got {type(target).__name__}")
    if tuple(target.mechanism.coordinates) != tuple(mech.coordinates):
        raise ValueError(f"evaluate(): the solution belongs to '{target.mechanism.name}', "
                         f"not to '{mech.name}'")
    fn, slots, shape = _compiled(mech, expr)
    need = _needed_level(slots)
    if isinstance(target, Solution):
        vectors = (target.q, target.qd, target.qdd)
        t = target.t
        npts = None
    else:
        vectors = (target.Q, target.QD, target.QDD)
        t = target.t
        npts = len(target)
    if vectors[need] is None:
        missing = sorted({mech.coordinates[k] + "d" * kind
                          for kind, k in slots if isinstance(kind, int)
                          and kind >= LEVEL["velocity"] and vectors[kind] is None})
        what = "solution" if npts is None else "sweep"
        raise ValueError(
            f"evaluate(): the expression needs {', '.join(missing)}, but this {what} is at level "
            f"{target.level}: {'solve' if npts is None else 'sweep'} with "
            f"level={LEVELS[need]!r} or higher")
    args = []
    for kind, k in slots:
        if kind == "t":
            args.append(t)
        elif kind == "p":
            args.append(float(mech.p[k]))
        elif npts is None:
            args.append(float(vectors[kind][k]))
        else:
            args.append(vectors[kind][:, k])
    with np.errstate(all="ignore"):
        values = fn(*args)
    if npts is None:
        out = np.array([float(v) for v in values])
    else:
        out = np.stack([np.broadcast_to(np.asarray(v, dtype=np.float64), (npts,))
                        for v in values], axis=-1) if values else np.zeros((npts, 0))
    if shape is None:
        return float(out[0]) if npts is None else out[..., 0].copy()
    if shape[1] == 1:      # a column vector (a point, a direction): flat
        return out
    return out.reshape(out.shape[:-1] + shape)


def expression_sensitivity(mech, expr, result, param, sens):
    """Symbolic.sensitivity: the chain rule with each partial derivative differentiated by
    sympy and evaluated on the result (the same evaluator as mech.evaluate)."""
    import sympy as sp
    matrix = isinstance(expr, (list, tuple, sp.MatrixBase))
    expr = sp.ImmutableMatrix(expr) if matrix else sp.sympify(expr)
    j = int(sens.columns[sens.params.index(param)])
    table = _slots(mech)
    total = 0.0
    for s in sorted(expr.free_symbols, key=lambda x: x.name):
        kind, k = table.get(s.name, (None, None))
        if kind is None or kind == "t" or (kind == "p" and k != j):
            continue
        partial = expr.diff(s)
        if (partial.is_zero_matrix if matrix else partial == 0):
            continue
        value = np.asarray(evaluate(mech, partial, result), dtype=np.float64)
        if kind == "p":
            total = total + value
            continue
        D = sens.full[kind]
        factor = D[..., k, j]
        if value.ndim > np.ndim(factor):
            factor = np.reshape(factor, np.shape(factor) + (1,) * (value.ndim - np.ndim(factor)))
        total = total + value * factor
    if np.ndim(total) == 0 and not matrix:
        return float(total) if not hasattr(result, "Q") else np.full(len(result), float(total))
    return total


class LazySymbolic:
    """The symbolic side of a mechanism loaded from a model file without sympy: it runs
    the model file (sympy) when first asked, then answers as :class:`Symbolic`."""

    def __init__(self, path, name=None, mech=None):
        self.path, self.name = path, name
        self._mech = mech
        self._real = None

    @property
    def model(self):
        """The model, loaded from its file on first use."""
        return self._side().model

    def _side(self):
        if self._real is None:
            from .model.loader import load_model
            model = load_model(self.path, self.name)
            self._real = Symbolic(model)
            if self._mech is not None and self._mech.model is None:
                self._mech.model = model
        return self._real

    def evaluate(self, mech, expr, solution_or_sweep):
        """As Symbolic.evaluate."""
        return self._side().evaluate(mech, expr, solution_or_sweep)

    def derivative(self, expr):
        """As Symbolic.derivative."""
        return self._side().derivative(expr)

    def level(self, mech, expr) -> int:
        """As Symbolic.level."""
        return self._side().level(mech, expr)

    def build_sensitivities(self, module_path):
        """As Symbolic.build_sensitivities (loads the model)."""
        return self._side().build_sensitivities(module_path)

    def sensitivity(self, mech, expr, result, param, sens):
        """As Symbolic.sensitivity."""
        return self._side().sensitivity(mech, expr, result, param, sens)

    def check_contacts(self, mech, given):
        """As Symbolic.check_contacts once the model is loaded (never loads it: a
        with_params of a module loaded without sympy stays without it)."""
        if self._real is not None:
            self._real.check_contacts(mech, given)


class Symbolic:
    """The symbolic side of a mechanism built by ``mechgen.compile``: what the runtime
    calls (through ``mech.symbolic``) for a quantity given as a sympy expression."""

    def __init__(self, model):
        self.model = model

    def evaluate(self, mech, expr, solution_or_sweep):
        """The value of ``expr`` on a Solution or along a Sweep (see :func:`evaluate`)."""
        return evaluate(mech, expr, solution_or_sweep)

    def derivative(self, expr):
        """The total time derivative of ``expr`` (coordinates move, so do the drivers)."""
        from .model.quantities import dt
        return dt(expr, model=self.model)

    def level(self, mech, expr) -> int:
        """The solve level ``expr`` needs (an index into LEVELS): velocity when it holds a
        velocity symbol (X4d), acceleration when it holds an acceleration (X4dd)."""
        names = {s.name for s in getattr(expr, "free_symbols", ())}
        coords = mech.coordinates
        if any(c + "dd" in names for c in coords):
            return LEVEL["acceleration"]
        if any(c + "d" in names for c in coords):
            return LEVEL["velocity"]
        return LEVEL["position"]

    def build_sensitivities(self, module_path):
        """Write the sensitivity module beside the module at ``module_path``
        (mechgen.compiler.sensitivities): the runtime asks for it the first time a call
        wants sensitivities and none is there."""
        from .compiler.sensitivities import build_sensitivities
        return build_sensitivities(self.model, module_path)

    def sensitivity(self, mech, expr, result, param, sens):
        """∂expr/∂param on a Solution or Sweep carrying sensitivities ``sens``
        (mechgen.runtime.sensitivity): Σ ∂expr/∂x · dx/dparam over the coordinates and
        their rates x it holds, plus ∂expr/∂param, each partial derivative symbolic."""
        return expression_sensitivity(mech, expr, result, param, sens)

    def check_contacts(self, mech, given):
        """Warn (RuntimeWarning) for each cam whose contact geometry is lost at ``mech``'s
        parameters, ``given`` (name -> value) the ones with_params changed: the check runs
        where a cam is declared, at the defaults (mechgen.model.library2d.cams.contact_problems)."""
        if not any(getattr(c, "checks", ()) for c in self.model.constraints):
            return
        import warnings
        from .model.library2d.cams import contact_problems
        values = mech.parameters
        said = ", ".join(f"{k}={v!r}" for k, v in given.items())
        for msg in contact_problems(self.model, values):
            warnings.warn(f"model '{mech.name}' with {said}: {msg}; solves and sweeps there "
                          "do not give the follower's physical motion", RuntimeWarning,
                          stacklevel=3)


def attach(mech, model):
    """Give a loaded mechanism its symbolic side: ``mech.model`` and ``mech.symbolic``, so
    that ``mech.evaluate(expr, s)`` and symbolic quantities in interpolate/extrema/roots
    work. ``model`` must be the model the mechanism's module was built from."""
    mech.model = model
    mech.symbolic = Symbolic(model)
    return mech


def cache_folder() -> str:
    """Where ``mechgen.compile`` writes modules by default: ``$MECHGEN_CACHE``, else
    ``~/.cache/mechgen``."""
    return os.environ.get("MECHGEN_CACHE") or os.path.join(
        os.path.expanduser("~"), ".cache", "mechgen")


def build_if_changed(model, outdir, **kwargs) -> str:
    """Write ``outdir/<name>.py`` unless it already holds this model's module (see
    mechgen.compiler.build.build_if_changed: an unchanged model is not rendered again)."""
    from .compiler.build import build_if_changed as _build_if_changed
    return _build_if_changed(model, outdir, **kwargs)


def compile_model(model, outdir=None, tier=None, name=None, **kwargs):
    """``mechgen.compile``: build ``model`` into a folder (``outdir``, default
    :func:`cache_folder`; rewritten only when its text changed) and load it, keeping the
    symbolic model so that ``mech.evaluate(expr, solution_or_sweep)`` works.

    ``model`` is a Model, or the path of a model file (``name=`` picks one of several):
    a file whose module was built before, unchanged (its text, the local files it
    imports, mechgen's and sympy's versions), loads without sympy (compile_file);
    its symbolic side loads the model when first used. ``tier`` as for mechgen.load.
    ``sensitivities=True`` also builds (or finds up to date) the sensitivity module
    beside it now, rather than at the first call that asks for derivatives."""
    sensitivities = kwargs.pop("sensitivities", False)
    if outdir is None:
        outdir = cache_folder()
    if isinstance(model, (str, os.PathLike)):
        mech = compile_file(os.fspath(model), outdir, name=name, tier=tier, **kwargs)
    else:
        from .model.language import Model       # sympy: only for a Model itself
        if not isinstance(model, Model):
            raise TypeError(f"compile(model): model must be a mechgen.Model or the path of a "
                            f"model file, got {type(model).__name__} {repr(model)[:60]}")
        if name is not None:
            raise TypeError("compile(): name= picks a model of a model file; pass the "
                            "file's path")
        mech = attach(load(build_if_changed(model, outdir, **kwargs), tier=tier), model)
    if sensitivities:
        from .runtime.sensitivity.companion import companion
        companion(mech)         # built where missing or stale, and loaded
    return mech


# -- a model file to a loaded mechanism, without sympy when its module is up to date -------
def _sympy_version() -> str:
    """sympy's version, read from its release file (importing sympy takes 0.4 s)."""
    import importlib.util
    spec = importlib.util.find_spec("sympy")
    if spec is None or not spec.origin:
        return "none"
    try:
        with open(os.path.join(os.path.dirname(spec.origin), "release.py"), encoding="utf-8") as fh:
            for line in fh:
                if line.startswith("__version__"):
                    return line.split("=", 1)[1].strip().strip("\"'")
    except OSError:
        pass
    return "unknown"


@functools.lru_cache(maxsize=1)
def _builder_digest() -> str:
    """A digest of the code that writes a module (mechgen's model and compiler packages and
    the templates): a manifest made by other code (a newer checkout of the same version)
    is not taken for this one's."""
    here = os.path.dirname(os.path.abspath(__file__))
    h = hashlib.sha256()
    for folder in ("model", "compiler", os.path.join("compiler", "library"),
                   os.path.join("..", "templates"), "templates"):
        where = os.path.join(here, folder)
        if not os.path.isdir(where):
            continue
        for name in sorted(os.listdir(where)):
            if name.endswith((".py", ".j2")):
                h.update(name.encode())
                h.update(_digest(os.path.join(where, name)).encode())
    return h.hexdigest()


def _digest(path) -> str | None:
    try:
        with open(path, "rb") as fh:
            return hashlib.sha256(fh.read()).hexdigest()
    except OSError:
        return None


def _manifest_path(path, outdir, name, options) -> str:
    """The manifest of building model file ``path`` into ``outdir``: named by everything
    its module depends on but the local files the model file imports (listed inside)."""
    with open(path, "rb") as fh:
        text = fh.read()
    key = json.dumps([os.path.abspath(path), hashlib.sha256(text).hexdigest(), name,
                      os.path.abspath(outdir), sorted((k, repr(v)) for k, v in options.items()),
                      MECHGEN_VERSION, _builder_digest(), _sympy_version(), sys.version],
                     sort_keys=True)
    return os.path.join(cache_folder(), "manifests",
                        hashlib.sha256(key.encode()).hexdigest()[:24] + ".json")


def _local_imports(path, outdir) -> dict:
    """{file: sha256} of the modules loaded from the model file's folder (its own local
    imports: a module of shapes, of dimensions), not mechgen's nor the generated ones."""
    here = os.path.dirname(os.path.abspath(path)) + os.sep
    skip = (os.path.dirname(os.path.abspath(__file__)) + os.sep, os.path.abspath(outdir) + os.sep)
    found = {}
    for module in list(sys.modules.values()):
        f = getattr(module, "__file__", None)
        if not f:
            continue
        f = os.path.abspath(f)
        if f.startswith(here) and not f.startswith(skip) and f != os.path.abspath(path):
            found[f] = _digest(f)
    return found


def compile_file(path, outdir=None, name=None, tier=None, **kwargs):
    """``mechgen.compile("model.py")``: the mechanism of a model file. When a manifest
    says this file (same text, same local imports, same mechgen and sympy, same build
    options) was built into ``outdir`` and the module is there, it is loaded at once,
    without sympy or the compiler, and its symbolic side (``mech.evaluate``) loads the
    model on first use; otherwise the model is built as ``compile(model)`` does and the
    manifest written."""
    from .runtime.loading.loader import verify
    if outdir is None:
        outdir = cache_folder()
    path = os.path.abspath(path)
    if not os.path.isfile(path):
        raise ModelError("the model file does not exist", where=path)
    manifest = _manifest_path(path, outdir, name, kwargs)
    fresh = False
    try:
        with open(manifest, encoding="utf-8") as fh:
            entry = json.load(fh)
        module = entry["module"]
        fresh = all(_digest(f) == d for f, d in entry["imports"].items()) and \
            verify(module) == entry["digest"]
    except (OSError, ValueError, KeyError, TypeError, MechgenError):
        fresh = False     # no manifest, or a module gone or changed: build
    if fresh:
        mech = load(module, tier=tier)
        mech.symbolic = LazySymbolic(path, name, mech)
        return mech
    from .model.loader import load_model
    model = load_model(path, name)
    module = build_if_changed(model, outdir, **kwargs)
    imports = _local_imports(path, outdir)
    imports.update({f: _digest(f) for f in getattr(model, "read_files", ())})
    entry = {"model_file": path, "name": name, "module": module, "digest": verify(module),
             "imports": imports}
    os.makedirs(os.path.dirname(manifest), exist_ok=True)
    tmp = f"{manifest}.{os.getpid()}.tmp"
    with open(tmp, "w", encoding="utf-8") as fh:
        json.dump(entry, fh, indent=1)
    os.replace(tmp, manifest)
    return attach(load(module, tier=tier), model)
