"""The CUDA twin of a generated module: the module's own solver functions, translated for
numba.cuda device code, and the design-table kernels built on them.

The GPU runs the same plan as the CPU because it runs the same source: every numba
function of the module that the sweep reaches (sweep_fast, sweep, the sorted block
solvers and closed forms, the full Newton and the rank-revealing solves, ...) is read
back from the module file, translated by a few mechanical rules and compiled with
``cuda.jit(device=True)``:

- an allocation becomes a thread-local array of the same constant size:
  ``np.empty(S)`` -> ``cuda.local.array(S, float64)``, ``np.zeros(S)`` (float or
  ``dtype=np.bool_``) the same filled with zeros, ``np.arange(S)`` the same filled with
  0..S-1 and ``x.copy()`` a local array filled from x. Sizes must be constants of the
  module (N_COORDS, N_EQS, POSITION_INFO_SIZE, a number) or locals bound to one;
  anything else is refused with a TranslationError naming the function (a test
  translates every example module, so a library change that the rules do not cover
  fails there, not on a user's GPU);
- ``max(a, b, ...)`` and ``min(...)`` become the same pairwise comparisons as device
  functions (numba.cuda cannot compile the builtins for two numbers);
- in sweep() and sweep_fast() the rows they write (Q, QD, QDD, STATUS) are indexed
  ``k & mask``: mask -1 keeps every row (the table kernels, nothing changes), mask 0
  one thread-local row (the reducing kernels); sweep_fast_forces' (and
  sweep_fast_statics') LAM, FACTORS and FPIV rows too, where mechgen.runtime.tables.cuda_forces
  translates them (their hook: ``_cu_point_forces``);
- a hook ``_cu_point`` sees each final point once: at the end of each time step of
  sweep(), one step late in sweep_fast() (whose last accepted point sweep() solves
  again when it takes over, as on the CPU), just before the next point's row is
  written over it. It tracks the design's branch status (JUMP,
  THROUGH_SINGULAR) and the running minimum and maximum (and their times) of the
  requested quantity slots.

The twin's text is written to a file (``source_file``: in the module's ``__pycache__``,
else the temporary folder, named by a hash of the text, the module's file and the
options) and the kernels are compiled with numba's on-disk cache: a later process loads
them instead of compiling again (the first compile of a kernel takes tens of seconds).
Where no file can be written, or numba cannot cache, they are compiled in every process.

Nothing here imports numba.cuda: ``build_twin(module, cuda)`` is given it by
mechgen.runtime.tables.cuda, which imports it only when a CUDA table is asked for.
"""
from __future__ import annotations

import ast
import hashlib
import inspect
import itertools
import linecache
import os
import tempfile
import textwrap

from ...errors import MechgenError

ROOTS = ("sweep_fast", "sweep", "outputs", "outputs_d", "outputs_dd")
# the rows a hooked sweep writes (2-D: Q[k, j]; 1-D: FPIV[k]); sweep_fast_forces' λ rows
# too (mechgen.runtime.tables.cuda_forces)
ROW_ARRAYS = ("Q", "QD", "QDD", "STATUS", "LAM", "FACTORS")
ROW_VECTORS = ("FPIV",)
# hooked function -> (its hook, the row arrays the hook is given)
HOOKED = {"sweep_fast": ("_cu_point", ("Q", "QD", "QDD", "STATUS")),
          "sweep": ("_cu_point", ("Q", "QD", "QDD", "STATUS")),
          "sweep_fast_forces": ("_cu_point_forces",
                                ("Q", "QD", "QDD", "STATUS", "LAM", "FACTORS", "FPIV")),
          "sweep_fast_statics": ("_cu_point_forces",
                                 ("Q", "QD", "QDD", "STATUS", "LAM", "FACTORS", "FPIV"))}
# x.copy() of these names: the size of the copy
COPY_SIZES = {"q0": "N_COORDS", "r": "N_EQS"}
# locals whose value is a size only known from an argument's shape: the size it always
# has where the sweep calls the function (_fp_solve solves with Φ_q, N_EQS × N_COORDS)
SIZE_HINTS = {("_fp_solve", "n"): "N_COORDS", ("_fp_solve", "m"): "N_EQS"}
MASK = 6                        # the row mask's place in the context tuple
_DTYPES = {None: ("_cu_f8", 0.0), "float64": ("_cu_f8", 0.0), "bool_": ("_cu_b1", False),
           "int64": ("_cu_i8", 0)}

_counter = itertools.count()


class TranslationError(MechgenError):
    """A function of the generated module uses something the CUDA translation cannot
    express (an allocation of unknown size, a numpy call other than empty/zeros/arange)."""


# Device helpers, kernels and the per-design driver, as Python compiled into the twin's
# namespace (so that they name the module's constants and the translated functions).
SUPPORT = '''
def _cu_max(a, b):
    \"\"\"max(a, b) as numba computes it (b only when b > a: max(nan, 1.0) is nan).\"\"\"
    return b if b > a else a


def _cu_min(a, b):
    \"\"\"min(a, b) as numba computes it (b only when b < a).\"\"\"
    return b if b < a else a


def _cu_fill(a, v):
    for i in range(a.shape[0]):
        a[i] = v
    return a


def _cu_arange(a):
    for i in range(a.shape[0]):
        a[i] = i
    return a


def _cu_copy(src, a):
    for i in range(a.shape[0]):
        a[i] = src[i]
    return a


def _cu_value(s, row, Q, QD, QDD, OUT):
    \"\"\"Flat slot s at a row: coordinates, velocities, accelerations, then the outputs and
    their first and second derivatives (mechgen.runtime.tables.cuda.flat_slots).\"\"\"
    if s < N_COORDS:
        return Q[row, s]
    if s < 2 * N_COORDS:
        return QD[row, s - N_COORDS]
    if s < 3 * N_COORDS:
        return QDD[row, s - 2 * N_COORDS]
    s -= 3 * N_COORDS
    return OUT[s // _CU_NOUT, s % _CU_NOUT]


def _cu_point(k, ts, Q, QD, QDD, S, p, ctx):
    \"\"\"The hook at the end of each time step of sweep() and sweep_fast(): the design's
    branch status from the point's STATUS row, and the running extremes of the slots.\"\"\"
    SL, nsl, R, F, OUT, nord, mask = ctx
    row = k & mask
    s = int(S[row, STATUS_CODE])
    if s == JUMP:
        F[0] = JUMP
    elif s == THROUGH_SINGULAR and F[0] != JUMP:
        F[0] = THROUGH_SINGULAR
    if nsl == 0:
        return
    t = ts[k]
    if nord >= 1:
        outputs(Q[row], QD[row], QDD[row], t, p, OUT[0])
    if nord >= 2:
        outputs_d(Q[row], QD[row], QDD[row], t, p, OUT[1])
    if nord >= 3:
        outputs_dd(Q[row], QD[row], QDD[row], t, p, OUT[2])
    first = F[1] == 0
    for i in range(nsl):
        v = _cu_value(SL[i], row, Q, QD, QDD, OUT)
        if first or v < R[0, i]:
            R[0, i] = v
            R[2, i] = t
        if first or v > R[1, i]:
            R[1, i] = v
            R[3, i] = t
    F[1] = 1


def _cu_fast(d, ts, q0, p, method, tol, xtol, maxit, Q, QD, QDD, S, ctx, QS, FL, DONE,
             DSTATUS):
    \"\"\"The first pass of a design, as the module's sweep_designs() begins it: sweep_fast()
    while nothing is hard. A design it takes to the end is finished; otherwise DONE[d] =
    -1 - the time to resume at, QS[d] the configuration there and FL[d] the flags.\"\"\"
    F = ctx[3]
    mask = ctx[6]
    start = 0
    if SORTED and LEVEL >= 2 and method != METHOD_FULL:
        start = sweep_fast(ts, q0, p, tol, xtol, maxit, Q, QD, QDD, S, ctx)
        if start == ts.shape[0]:
            _cu_point(start - 1, ts, Q, QD, QDD, S, p, ctx)
            DONE[d] = start
            DSTATUS[d] = F[0]
            return
        start = _cu_max(start - 1, 0)
    for j in range(N_COORDS):
        QS[d, j] = Q[start & mask, j] if start > 0 else q0[j]
    for j in range(3):
        FL[d, j] = F[j]
    DONE[d] = -1 - start


def _cu_careful(d, ts, p, level, method, tol, xtol, maxit, Q, QD, QDD, S, ctx, qs, DONE,
                DSTATUS):
    \"\"\"The second pass of a design the first left unfinished: sweep() from the last point
    sweep_fast() accepted, as sweep_designs() goes on. A failed design's status is the
    one its sweep stopped with (the report's REPORT_STATUS); its extremes are those of
    the times it solved.\"\"\"
    start = -1 - DONE[d]
    mask = ctx[6]
    a = start if mask < 0 else 0
    report = cuda.local.array(REPORT_SIZE, _cu_f8)
    n = sweep(ts[start:], qs, p, level, tol, xtol, maxit, method,
              Q[a:], QD[a:], QDD[a:], S[a:], report, ctx)
    DONE[d] = start + n
    if start + n < ts.shape[0]:
        DSTATUS[d] = int(report[REPORT_STATUS])
    else:
        DSTATUS[d] = ctx[3][0]


def _cu_flags(F):
    F[0] = 0                            # branch status (OK, THROUGH_SINGULAR, JUMP)
    F[1] = 0                            # points seen (0: none yet)
    F[2] = 0                            # spare
    return F


def _cu_row(Q, QD, QDD, S):
    \"\"\"The reducing kernels' single thread-local row, zeroed.\"\"\"
    for j in range(N_COORDS):
        Q[0, j] = 0.0
        QD[0, j] = 0.0
        QDD[0, j] = 0.0
    for j in range(_CU_SCOLS):
        S[0, j] = 0


def _cu_fast_table(ts, Q0, P, method, tol, xtol, maxit, SL, nsl, nord, Q, QD, QDD, S, R,
                   QS, FL, DONE, DSTATUS):
    \"\"\"First pass, one thread per design, every point kept (Q, QD, QDD, S: design, time,
    column; QD and QDD may have no rows below the levels that need them).\"\"\"
    d = cuda.grid(1)
    if d >= P.shape[0]:
        return
    F = _cu_flags(cuda.local.array(3, _cu_i8))
    OUT = cuda.local.array((3, _CU_NOUT), _cu_f8)
    ctx = (SL, nsl, R[d], F, OUT, nord, -1)
    _cu_fast(d, ts, Q0[d], P[d], method, tol, xtol, maxit, Q[d], QD[d], QDD[d], S[d], ctx,
             QS, FL, DONE, DSTATUS)


def _cu_fast_reduce(ts, Q0, P, method, tol, xtol, maxit, SL, nsl, nord, R, QS, FL, DONE,
                    DSTATUS):
    \"\"\"First pass, one thread per design, only the last point kept (a thread-local row);
    the reductions R[design] = (min, max, tmin, tmax) of the slots SL.\"\"\"
    d = cuda.grid(1)
    if d >= P.shape[0]:
        return
    F = _cu_flags(cuda.local.array(3, _cu_i8))
    OUT = cuda.local.array((3, _CU_NOUT), _cu_f8)
    Q = cuda.local.array((1, N_COORDS), _cu_f8)
    QD = cuda.local.array((1, N_COORDS), _cu_f8)
    QDD = cuda.local.array((1, N_COORDS), _cu_f8)
    S = cuda.local.array((1, _CU_SCOLS), _cu_i2)
    _cu_row(Q, QD, QDD, S)
    ctx = (SL, nsl, R[d], F, OUT, nord, 0)
    _cu_fast(d, ts, Q0[d], P[d], method, tol, xtol, maxit, Q, QD, QDD, S, ctx,
             QS, FL, DONE, DSTATUS)


def _cu_careful_table(ts, P, IDX, level, method, tol, xtol, maxit, SL, nsl, nord, Q, QD, QDD,
                      S, R, QS, FL, DONE, DSTATUS):
    \"\"\"Second pass over the designs IDX the first left unfinished, every point kept.\"\"\"
    i = cuda.grid(1)
    if i >= IDX.shape[0]:
        return
    d = IDX[i]
    F = cuda.local.array(3, _cu_i8)
    for j in range(3):
        F[j] = FL[d, j]
    qs = cuda.local.array(N_COORDS, _cu_f8)
    for j in range(N_COORDS):
        qs[j] = QS[d, j]
    OUT = cuda.local.array((3, _CU_NOUT), _cu_f8)
    ctx = (SL, nsl, R[d], F, OUT, nord, -1)
    _cu_careful(d, ts, P[d], level, method, tol, xtol, maxit, Q[d], QD[d], QDD[d], S[d],
                ctx, qs, DONE, DSTATUS)


def _cu_careful_reduce(ts, P, IDX, level, method, tol, xtol, maxit, SL, nsl, nord, R, QS, FL,
                       DONE, DSTATUS):
    \"\"\"Second pass over the designs IDX the first left unfinished, reductions only.\"\"\"
    i = cuda.grid(1)
    if i >= IDX.shape[0]:
        return
    d = IDX[i]
    F = cuda.local.array(3, _cu_i8)
    for j in range(3):
        F[j] = FL[d, j]
    qs = cuda.local.array(N_COORDS, _cu_f8)
    for j in range(N_COORDS):
        qs[j] = QS[d, j]
    OUT = cuda.local.array((3, _CU_NOUT), _cu_f8)
    Q = cuda.local.array((1, N_COORDS), _cu_f8)
    QD = cuda.local.array((1, N_COORDS), _cu_f8)
    QDD = cuda.local.array((1, N_COORDS), _cu_f8)
    S = cuda.local.array((1, _CU_SCOLS), _cu_i2)
    _cu_row(Q, QD, QDD, S)
    ctx = (SL, nsl, R[d], F, OUT, nord, 0)
    _cu_careful(d, ts, P[d], level, method, tol, xtol, maxit, Q, QD, QDD, S, ctx, qs,
                DONE, DSTATUS)
'''
KERNELS = ("_cu_fast_table", "_cu_fast_reduce", "_cu_careful_table", "_cu_careful_reduce")


def _is_np(node, attr):
    return (isinstance(node, ast.Attribute) and node.attr == attr and
            isinstance(node.value, ast.Name) and node.value.id == "np")


class _Rewriter(ast.NodeTransformer):
    """The translation rules of the module docstring, for one function."""

    def __init__(self, name, module, locals_):
        self.name = name
        self.module = module
        self.locals = locals_          # simple `name = expr` bindings of the function
        self.calls = set()             # global names called (candidates to translate)

    def fail(self, what):
        raise TranslationError(f"cannot translate {what} in {self.name}() of "
                               f"'{self.module.__name__}' to CUDA")

    def size(self, node, depth=0):
        """The size expression, made of module constants and numbers."""
        if isinstance(node, ast.Constant) and isinstance(node.value, int):
            return node
        if isinstance(node, ast.Tuple):
            return ast.Tuple([self.size(e, depth) for e in node.elts], ast.Load())
        if isinstance(node, ast.Name):
            hint = SIZE_HINTS.get((self.name, node.id))
            if hint is not None:
                return ast.Name(hint, ast.Load())
            if node.id in self.locals and depth < 4:
                return self.size(self.locals[node.id], depth + 1)
            if isinstance(getattr(self.module, node.id, None), int):
                return ast.Name(node.id, ast.Load())
        self.fail(f"an array of size {ast.unparse(node)}")

    def visit_Call(self, node):
        self.generic_visit(node)
        f = node.func
        if isinstance(f, ast.Name) and f.id in ("max", "min") and not node.keywords:
            # numba.cuda (built in to numba 0.68) cannot compile max()/min() of two
            # numbers: the same comparison, pairwise from the left as numba does it
            if len(node.args) < 2:
                self.fail(f"{f.id}() of one argument")
            out = node.args[0]
            for arg in node.args[1:]:
                out = _call(ast.Name("_cu_" + f.id, ast.Load()), [out, arg])
            return out
        if isinstance(f, ast.Name):
            self.calls.add(f.id)
            return node
        if isinstance(f, ast.Attribute) and isinstance(f.value, ast.Name) and f.value.id == "np":
            if f.attr not in ("empty", "zeros", "arange") or len(node.args) != 1:
                self.fail(f"np.{f.attr}(...)")
            dtype = None
            for kw in node.keywords:
                if kw.arg != "dtype" or not isinstance(kw.value, ast.Attribute):
                    self.fail(ast.unparse(node))
                dtype = kw.value.attr
            if f.attr == "arange":
                dtype = "int64"
            if dtype not in _DTYPES:
                self.fail(ast.unparse(node))
            ty, zero = _DTYPES[dtype]
            shape = self.size(node.args[0])
            local = _call(ast.Attribute(ast.Attribute(ast.Name("cuda", ast.Load()), "local",
                                                      ast.Load()), "array", ast.Load()),
                          [shape, ast.Name(ty, ast.Load())])
            if f.attr == "empty":
                return local
            if isinstance(shape, ast.Tuple):
                self.fail(ast.unparse(node) + " (a zero-filled 2-D array)")
            if f.attr == "arange":
                return _call(ast.Name("_cu_arange", ast.Load()), [local])
            return _call(ast.Name("_cu_fill", ast.Load()), [local, ast.Constant(zero)])
        if isinstance(f, ast.Attribute) and f.attr == "copy" and not node.args:
            src = ast.unparse(f.value)
            if src not in COPY_SIZES:
                self.fail(f"{src}.copy()")
            local = _call(ast.Attribute(ast.Attribute(ast.Name("cuda", ast.Load()), "local",
                                                      ast.Load()), "array", ast.Load()),
                          [ast.Name(COPY_SIZES[src], ast.Load()), ast.Name("_cu_f8", ast.Load())])
            return _call(ast.Name("_cu_copy", ast.Load()), [f.value, local])
        return node


class _Rows(ast.NodeTransformer):
    """Q[k, j] -> Q[k & mask, j] for the row arrays, FPIV[k] -> FPIV[k & mask] for the
    row vectors (mask: the context's entry MASK, -1 for full rows, 0 for a single row)."""

    def visit_Subscript(self, node):
        self.generic_visit(node)
        if not isinstance(node.value, ast.Name):
            return node
        mask = ast.Subscript(ast.Name("_cu_ctx", ast.Load()), ast.Constant(MASK), ast.Load())
        if node.value.id in ROW_ARRAYS and isinstance(node.slice, ast.Tuple):
            first = ast.BinOp(node.slice.elts[0], ast.BitAnd(), mask)
            node.slice = ast.Tuple([first] + node.slice.elts[1:], ast.Load())
        elif node.value.id in ROW_VECTORS and not isinstance(node.slice, (ast.Tuple, ast.Slice)):
            node.slice = ast.BinOp(node.slice, ast.BitAnd(), mask)
        return node


def _call(func, args):
    return ast.Call(func=func, args=args, keywords=[])


def _simple_bindings(fn):
    """name -> expr for the `name = expr` statements of a function (sizes like n = N_COORDS)."""
    out = {}
    for node in ast.walk(fn):
        if isinstance(node, ast.Assign) and len(node.targets) == 1 and \
                isinstance(node.targets[0], ast.Name):
            out.setdefault(node.targets[0].id, node.value)
    return out


def _stores_row(stmt):
    """Whether a statement writes into one of the row arrays."""
    for node in ast.walk(stmt):
        if isinstance(node, ast.Subscript) and isinstance(node.ctx, ast.Store) and \
                isinstance(node.value, ast.Name) and node.value.id in ROW_ARRAYS + ROW_VECTORS:
            return True
    return False


def _hook(fn, module):
    """Add the _cu_ctx argument and the per-point hook (HOOKED) to sweep(), sweep_fast()
    or sweep_fast_forces(), and index their rows through the context's mask."""
    fn.args.args.append(ast.arg("_cu_ctx"))
    loops = [s for s in fn.body if isinstance(s, ast.For) and isinstance(s.target, ast.Name)
             and s.target.id == "k"]
    if len(loops) != 1:
        raise TranslationError(f"{fn.name}() of '{module.__name__}' has no single loop over "
                               "the times (for k in ...) to hook the reductions into")
    hook, rows = HOOKED[fn.name]
    args = [ast.Name(n, ast.Load()) for n in ("ts",) + rows + ("p", "_cu_ctx")]
    if fn.name == "sweep":
        # sweep()'s points are final: each is seen when it is written
        loops[0].body.append(ast.Expr(_call(ast.Name(hook, ast.Load()),
                                            [ast.Name("k", ast.Load())] + args)))
    else:
        # sweep_fast()'s last accepted point is solved again by sweep() when sweep_fast
        # stops early (the CPU table keeps sweep()'s): a point is seen once the next one
        # is accepted, just before its rows are written over it (so one row is enough);
        # the driver sees the last one when sweep_fast() went to the end
        body = loops[0].body
        at = next((i for i, st in enumerate(body) if _stores_row(st)), None)
        if at is None:
            raise TranslationError(f"sweep_fast() of '{module.__name__}' writes no Q[k, ...] "
                                   "row in its loop over the times")
        prev = ast.BinOp(ast.Name("k", ast.Load()), ast.Sub(), ast.Constant(1))
        body.insert(at, ast.If(
            test=ast.Compare(ast.Name("k", ast.Load()), [ast.Gt()], [ast.Constant(0)]),
            body=[ast.Expr(_call(ast.Name(hook, ast.Load()), [prev] + args))],
            orelse=[]))
    _Rows().visit(fn)


def translate(module, roots=ROOTS) -> str:
    """The CUDA source of every numba function of ``module`` that the roots reach, as
    plain Python text (defined under the names the module's code calls them by)."""
    todo = list(roots)
    seen = set()
    parts = []
    while todo:
        name = todo.pop(0)
        if name in seen:
            continue
        seen.add(name)
        disp = getattr(module, name, None)
        py = getattr(disp, "py_func", None)
        if py is None:
            continue                    # not a numba function (a Python builtin, min, ...)
        try:
            text = inspect.getsource(py)
        except (OSError, TypeError) as exc:
            raise TranslationError(f"the source of {name}() of '{module.__name__}' cannot be "
                                   f"read ({exc}): the CUDA backend translates the module's "
                                   "own source file") from None
        tree = ast.parse(textwrap.dedent(text))
        fn = tree.body[0]
        fn.name = name
        fn.decorator_list = []
        rw = _Rewriter(name, module, _simple_bindings(fn))
        rw.visit(fn)
        if name in HOOKED:
            _hook(fn, module)
        parts.append(ast.unparse(ast.fix_missing_locations(tree)))
        todo.extend(sorted(c for c in rw.calls if c not in seen))
    return "\n\n\n".join(parts) + "\n"


def build_twin(module, cuda, status_columns=1, max_registers=None, roots=ROOTS, support="",
               kernels=()):
    """The namespace of the CUDA twin of ``module``: the translated functions as device
    functions, and the kernels (KERNELS: first and second pass, keeping every point or
    reducing), compiled by numba at their first launch (max_registers: numba.cuda.jit's
    option). ``roots``, ``support`` and ``kernels``: more functions of the module to
    translate, more source and kernels (mechgen.runtime.tables.cuda_forces)."""
    from numba import types
    text = translate(module, roots) + "\n\n" + SUPPORT + "\n\n" + support
    filename = source_file(module, text, (status_columns, max_registers))
    if filename is None:
        filename = f"<cuda twin {next(_counter)} of {module.__name__}>"
    linecache.cache[filename] = (len(text), None, text.splitlines(True), filename)
    ns = dict(vars(module))
    ns.update(cuda=cuda, _cu_f8=types.float64, _cu_i8=types.int64, _cu_b1=types.boolean,
              _cu_i2=types.int16, _CU_NOUT=max(1, len(module.OUTPUTS)),
              _CU_SCOLS=int(status_columns),
              # the reducing kernels see each point of sweep_fast() as it is accepted:
              # its position sweeps evaluate det Φ_q at every point and never go back
              BRANCH_DET_EVERY=1)
    ns["__name__"] = f"{module.__name__}_cuda"
    exec(compile(text, filename, "exec"), ns)   # noqa: S102 - our own translation
    tree = ast.parse(text)
    defined = [n.name for n in tree.body if isinstance(n, ast.FunctionDef)]
    cache = os.path.isfile(filename)
    for name in defined:
        if name in KERNELS or name in kernels:
            opts = {} if max_registers is None else {"max_registers": int(max_registers)}
            ns[name] = _kernel(cuda, ns[name], opts, cache)
        else:
            ns[name] = cuda.jit(device=True)(ns[name])
    return ns


def _kernel(cuda, fn, opts, cache):
    """cuda.jit(**opts)(fn), with numba's on-disk cache where its source is a file and
    numba takes it (else without: compiled in every process)."""
    if cache:
        try:
            return cuda.jit(cache=True, **opts)(fn)
        except Exception:           # noqa: BLE001 - a numba that cannot cache this kernel
            pass
    return cuda.jit(**opts)(fn)


def source_file(module, text, options=()):
    """The path of a file holding the twin's ``text`` (numba's cache of a kernel needs its
    source in a file: an index is kept beside it, checked against its time stamp), named
    by a hash of the text, of the module's own file (its constants are the twin's
    globals) and of ``options``; written once, atomically, in the module's
    ``__pycache__`` or else the temporary folder. None where neither can be written."""
    key = hashlib.sha256(text.encode())
    path = getattr(module, "__file__", None)
    if path and os.path.isfile(path):
        with open(path, "rb") as fh:
            key.update(fh.read())
    key.update(repr(options).encode())
    name = f"{module.__name__}_cuda_{key.hexdigest()[:20]}.py"
    folders = [os.path.join(tempfile.gettempdir(), "mechgen_cuda")]
    if path:
        folders.insert(0, os.path.join(os.path.dirname(os.path.abspath(path)), "__pycache__"))
    for folder in folders:
        target = os.path.join(folder, name)
        if os.path.isfile(target):
            return target
        try:
            os.makedirs(folder, exist_ok=True)
            tmp = f"{target}.{os.getpid()}.tmp"
            with open(tmp, "w", encoding="utf-8") as fh:
                fh.write(text)
            os.replace(tmp, target)
            return target
        except OSError:
            continue
    return None
