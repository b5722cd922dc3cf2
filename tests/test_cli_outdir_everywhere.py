"""The README says ``--outdir DIR`` works on every command: every subcommand of mechgen
accepts it (where nothing is built it is accepted and harmless, its help says so)."""
import argparse

import pytest

from mechgen.cli import main, parser


def _subparsers():
    ap = parser()
    action = next(a for a in ap._actions if isinstance(a, argparse._SubParsersAction))
    return action.choices


def test_every_command_has_outdir():
    missing = [name for name, p in _subparsers().items()
               if "--outdir" not in p._option_string_actions]
    assert not missing, f"commands without --outdir: {missing}"


@pytest.mark.parametrize("argv", [
    ["check", "examples/fourbar.py", "-t", "0", "--starts", "4"],
    ["equations", "examples/fourbar.py"],
])
def test_outdir_is_harmless_where_nothing_is_built(argv, tmp_path, capsys):
    outdir = tmp_path / "gen"
    assert main(argv + ["--outdir", str(outdir)]) == 0
    assert not outdir.exists()          # check and equations build nothing
    assert capsys.readouterr().out


def test_synthesize_outdir_is_where_its_verify_module_is_built(tmp_path):
    args = parser().parse_args(["synthesize", "examples/gate_poses.csv",
                                "--outdir", str(tmp_path / "gen")])
    assert args.outdir == str(tmp_path / "gen")
    assert parser().parse_args(["synthesize", "examples/gate_poses.csv"]).outdir is None
