"""mechgen.bytecode: mechgen's own modules' code kept where Python keeps none. An edited
source is compiled again, a damaged or foreign file is never run; the finder steps in only
where Python writes no bytecode of its own."""
import os
import subprocess
import sys
import types

from mechgen.bytecode import CachedLoader, folder

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def _run(loader, name):
    module = types.ModuleType(name)
    exec(loader.get_code(name), module.__dict__)     # noqa: S102 - our test's own text
    return module


def _kept(name):
    return sorted(f for f in os.listdir(folder()) if f.startswith(name + "."))


def test_kept_code_follows_the_source_and_survives_damage(tmp_path, monkeypatch):
    monkeypatch.setenv("MECHGEN_CACHE", str(tmp_path / "cache"))
    src = tmp_path / "shape.py"
    src.write_text("X = 1\n")
    name = "mechgen.test_only_shape"
    assert _run(CachedLoader(name, str(src)), name).X == 1
    first = _kept(name)
    assert len(first) == 1
    # loaded from the kept code: a kept file that would give 41 is what runs
    kept = os.path.join(folder(), first[0])
    data = open(kept, "rb").read()
    import marshal
    head = data[:data.index(b"\n", len(b"mechgen-own-bytecode 1\n")) + 1]
    open(kept, "wb").write(head + marshal.dumps(compile("X = 41\n", str(src), "exec")))
    assert _run(CachedLoader(name, str(src)), name).X == 41
    # an edited source: compiled again, never the stale code; the old file removed
    src.write_text("X = 2\n")
    assert _run(CachedLoader(name, str(src)), name).X == 2
    second = _kept(name)
    assert len(second) == 1 and second != first
    # damaged (truncated, garbage): compiled again and rewritten whole
    kept = os.path.join(folder(), second[0])
    for junk in (b"", b"not code at all", open(kept, "rb").read()[:-7]):
        open(kept, "wb").write(junk)
        assert _run(CachedLoader(name, str(src)), name).X == 2
    assert open(kept, "rb").read().startswith(b"mechgen-own-bytecode 1\n")


def test_code_kept_for_another_file_is_not_used(tmp_path, monkeypatch):
    monkeypatch.setenv("MECHGEN_CACHE", str(tmp_path / "cache"))
    a, b = tmp_path / "a.py", tmp_path / "b.py"
    a.write_text("X = 1\n")
    b.write_text("X = 1\n")
    name = "mechgen.test_only_same"
    _run(CachedLoader(name, str(a)), name)
    mod = _run(CachedLoader(name, str(b)), name)
    # the same text elsewhere: its own code, naming its own file (tracebacks, coverage)
    assert mod.X == 1
    code = CachedLoader(name, str(b)).get_code(name)
    assert code.co_filename == str(b)
    assert len(_kept(name)) == 2


def _loader_in_fresh_process(env_extra, tmp_path):
    env = dict(os.environ, PYTHONPATH=ROOT, MECHGEN_CACHE=str(tmp_path / "c"), **env_extra)
    env = {k: v for k, v in env.items() if v is not None}
    code = ("import mechgen.runtime.mechanism as m, sys; "
            "print(type(m.__spec__.loader).__name__, 'sympy' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                         text=True, check=True)
    return out.stdout.split()


def test_the_finder_steps_in_only_where_python_keeps_no_bytecode(tmp_path):
    has_pyc = os.path.exists(os.path.join(ROOT, "mechgen", "runtime", "__pycache__"))
    got = _loader_in_fresh_process({"PYTHONDONTWRITEBYTECODE": "1"}, tmp_path)
    assert got == (["SourceFileLoader" if has_pyc else "CachedLoader", "False"])
    got = _loader_in_fresh_process({"PYTHONDONTWRITEBYTECODE": "1", "MECHGEN_BYTECODE": "0"},
                                   tmp_path)
    assert got[0] == "SourceFileLoader"
    if not has_pyc:
        # kept: the second process loads the code the first one wrote
        assert any(f.startswith("mechgen.runtime.mechanism.")
                   for f in os.listdir(tmp_path / "c" / "bytecode" /
                                       (sys.implementation.cache_tag or "py")))
