"""The command line run in-process, as the CLI tests do: a model file written from text,
``mechgen`` run on argv with its exit code (argparse's usage errors and --help included)
and what it printed."""
import textwrap

from mechgen.cli import main


def write(tmp_path, text, name="model.py"):
    """``text`` (dedented) as the file ``name`` in tmp_path; its path."""
    path = tmp_path / name
    path.write_text(textwrap.dedent(text).lstrip())
    return str(path)


def run(capsys, *argv):
    """(exit code, stdout, stderr) of ``mechgen *argv``."""
    try:
        code = main([str(a) for a in argv])
    except SystemExit as exc:           # argparse's usage errors, --help
        code = exc.code
    out, err = capsys.readouterr()
    return code, out, err
