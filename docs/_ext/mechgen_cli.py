"""The command line's reference, rendered from argparse at every build.

``.. mechgen-help:: build`` (in MyST: a ```{mechgen-help} build``` fence) becomes the text
``mechgen build --help`` prints, read from :func:`mechgen.cli.parser` itself, so that the
page can never disagree with the command; ``.. mechgen-help::`` without an argument is the
top-level help, and ``.. mechgen-commands::`` the list of every subcommand (the reference
page's test checks that each has its section).
"""
import argparse
import os

from docutils import nodes
from sphinx.util.docutils import SphinxDirective

WIDTH = "92"        # argparse wraps at $COLUMNS: fixed, so that a build does not depend on it


def subparsers():
    """{name: parser} of every ``mechgen`` subcommand, in the order they were added."""
    from mechgen.cli import parser
    top = parser()
    for action in top._actions:
        if isinstance(action, argparse._SubParsersAction):
            return top, dict(action.choices)
    raise RuntimeError("mechgen's parser has no subcommands")


def help_text(command=None) -> str:
    old = os.environ.get("COLUMNS")
    os.environ["COLUMNS"] = WIDTH
    try:
        top, subs = subparsers()
        if command is None:
            return top.format_help()
        if command not in subs:
            raise KeyError(f"mechgen has no command {command!r} (it has {', '.join(subs)})")
        return subs[command].format_help()
    finally:
        if old is None:
            os.environ.pop("COLUMNS", None)
        else:
            os.environ["COLUMNS"] = old


class MechgenHelp(SphinxDirective):
    optional_arguments = 1
    has_content = False

    def run(self):
        command = self.arguments[0] if self.arguments else None
        try:
            text = help_text(command)
        except KeyError as exc:
            raise self.error(str(exc))
        block = nodes.literal_block(text, text)
        block["language"] = "text"
        return [block]


def setup(app):
    app.add_directive("mechgen-help", MechgenHelp)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
