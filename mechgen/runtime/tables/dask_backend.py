"""``backend="dask"``: a design table in chunks of designs over a dask.distributed cluster.

The generated module travels to the workers as its text (scattered once); a worker writes
it into a folder named by its content stamp under the machine's temporary folder and
imports it there, once per process (a worker that sees the client's own file, unchanged,
imports that one and shares the client's numba cache). Workers on one machine share that folder and numba's
on-disk cache of it: a file lock around the import and the first compiled call (which
compiles, or loads numba's cache) keeps two processes from writing the cache at once.
Each chunk returns its designs' solved counts and statuses with their points or their
reductions, computed on the worker (mechgen.runtime.tables.chunks.solve_chunk), so failed
designs come back marked, never dropped. dask is imported only here, only when used.
"""
from __future__ import annotations

import contextlib
import os
import tempfile
import threading

import numpy as np

from ...errors import MechgenError
from ...protocol import content_digest
from .chunks import Collector, chunks, solve_chunk

_MODULES = {}                 # content stamp -> the module imported in this process
_LOCK = threading.Lock()      # worker threads of one process import once
_SCRATCH = threading.local()  # a worker thread's point arrays for reduced chunks


@contextlib.contextmanager
def _file_lock(path):
    """An exclusive lock between processes (fcntl where there is one; else none is
    needed: then every process takes a folder of its own, see _folder)."""
    try:
        import fcntl
    except ImportError:      # pragma: no cover (Windows)
        yield
        return
    with open(path, "a+") as fh:
        fcntl.flock(fh.fileno(), fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(fh.fileno(), fcntl.LOCK_UN)


def _folder(digest):
    root = os.path.join(tempfile.gettempdir(), f"mechgen-dask-{os.getuid() if hasattr(os, 'getuid') else 0}")
    try:
        import fcntl  # noqa: F401
    except ImportError:      # pragma: no cover (no lock: one folder per process)
        return os.path.join(root, f"{digest[:16]}-{os.getpid()}")
    return os.path.join(root, digest[:16])


def worker_module(text, digest, source, warm):
    """The generated module on this worker (written and imported once per process):
    the client's own file ``source`` where this machine sees it with the same content
    (then the worker shares numba's cache with the client), else the shipped text written
    to a folder named by its stamp. ``warm`` (a callable of the module) runs under a file
    lock the first time, so that numba compiles or loads its cache there, one process at a
    time."""
    with _LOCK:
        module = _MODULES.get(digest)
        if module is not None:
            return module
        from ..loading.loader import import_path
        folder = _folder(digest)
        os.makedirs(folder, exist_ok=True)
        path = os.path.join(folder, os.path.basename(source))
        with _file_lock(os.path.join(folder, ".lock")):
            if os.path.isfile(source) and content_digest(_read(source)) == digest:
                path = source
            elif not os.path.isfile(path) or content_digest(_read(path)) != digest:
                tmp = f"{path}.{os.getpid()}.tmp"
                with open(tmp, "w", encoding="utf-8") as fh:
                    fh.write(text)
                os.replace(tmp, path)
            module = import_path(path)
            warm(module)
        _MODULES[digest] = module
        return module


def _read(path):
    with open(path, encoding="utf-8") as fh:
        return fh.read()


def dask_chunk(text, digest, source, ts, Q0, P, lev, tol, xtol, maxit, meth, slots):
    """One chunk of designs on a worker (see solve_chunk; Q0: their starts)."""
    def warm(module):           # every compiled function a chunk may call, once
        solve_chunk(module, ts[:2], Q0[:1], P[:1], lev, tol, xtol, maxit, meth, slots)
        if len(module.OUTPUTS):
            z = np.zeros((1, Q0.shape[1]))
            module.eval_outputs(z, z, z, ts[:1], P[0], 0, np.zeros((1, len(module.OUTPUTS))))
    module = worker_module(text, digest, source, warm)
    return solve_chunk(module, ts, Q0, P, lev, tol, xtol, maxit, meth, slots, _SCRATCH.__dict__)


def get_client(client):
    """``client``, or the current dask.distributed client; a clear error without one."""
    try:
        import distributed
    except ImportError:
        raise MechgenError("backend='dask' needs dask.distributed: pip install 'dask[distributed]'") from None
    if client is not None:
        return client
    try:
        return distributed.get_client()
    except ValueError:
        raise MechgenError("backend='dask' needs a cluster: pass client=distributed.Client(...) "
                           "or start a Client first (it becomes the default)") from None


TASK_POINTS = 20_000          # no task of fewer points: a task's round trip costs ~ms
_SHIPPED = {}                 # (client, content stamp) -> the text scattered to its workers


def _shipped(client, text, digest):
    """The module's text on every worker of ``client``, scattered once per client (again
    when the cluster lost it)."""
    key = (id(client), digest)
    fut = _SHIPPED.get(key)
    if fut is None or fut.status != "finished" or fut.client is not client:
        fut = client.scatter(text, broadcast=True, hash=False)
        _SHIPPED.clear()                # one module at a time is kept
        _SHIPPED[key] = fut
    return fut


def run_dask(module, ts, Q0, P, lev, tol, xtol, maxit, meth, client=None, slots=None,
             progress=None):
    """The table over the cluster of ``client`` (or the current one): a TableData."""
    client = get_client(client)
    from distributed import as_completed
    path = getattr(module, "__file__", None)
    if not path or not os.path.isfile(path):
        raise MechgenError("backend='dask' ships the generated module's file to the workers; "
                           "this module has none")
    text = _read(path)
    digest = content_digest(text)
    source = os.path.abspath(path)
    D, N, nq = P.shape[0], ts.shape[0], Q0.shape[1]
    threads = sum(w.get("nthreads", 1) for w in client.scheduler_info()["workers"].values())
    spans = chunks(D, N, 2 * max(threads, 1), least=TASK_POINTS)
    shipped = _shipped(client, text, digest)
    futures = {}
    for a, b in spans:
        fut = client.submit(dask_chunk, shipped, digest, source, ts,
                            np.ascontiguousarray(Q0[a:b]), np.ascontiguousarray(P[a:b]), lev,
                            tol, xtol, maxit, meth, slots, pure=False)
        futures[fut] = (a, b)
    out = Collector(D, N, nq, slots, lev)
    total = 0
    try:
        for fut in as_completed(list(futures)):
            a, b = futures[fut]
            out.put(a, b, fut.result())
            total += b - a
            if progress is not None:
                progress(total, D)
    finally:
        for fut in futures:
            fut.release()
    return out.table()
