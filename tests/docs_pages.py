"""The documentation site's pages as the tests read them: a guide page's Python blocks
(every ```python fence, in order, but those under a ``<!-- not run: why -->`` line) and
the text of the pages (docs/**/*.md), so that a test of what a page says or runs never
reads a file the site does not show."""
import glob
import os
import re

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DOCS = os.path.join(ROOT, "docs")
FENCE = re.compile(r"(<!-- not run: [^\n]*-->\n)?```python\n(.*?)```", re.S)


def page(name) -> str:
    """The text of docs/NAME (e.g. "guide/forces.md")."""
    with open(os.path.join(DOCS, name), encoding="utf-8") as fh:
        return fh.read()


def section(name, title) -> str:
    """The part of page ``name`` under its heading ``title`` (any level), up to the next
    heading of the same or a higher level (a ``#`` inside a fenced block is no heading)."""
    lines, level, out, fenced = page(name).splitlines(keepends=True), None, [], False
    for line in lines:
        if line.startswith("```"):
            fenced = not fenced
        heading = None if fenced else re.match(r"(#+) (.*)", line)
        if level is None:
            if heading and heading.group(2).strip() == title:
                level = len(heading.group(1))
            continue
        if heading and len(heading.group(1)) <= level:
            break
        out.append(line)
    assert level is not None, f"docs/{name} has no heading {title!r}"
    return "".join(out)


def python_blocks(text, runnable=True) -> list:
    """The ```python blocks of ``text``; with ``runnable``, only those not marked
    ``<!-- not run: ... -->`` on the line before."""
    return [code for mark, code in FENCE.findall(text) if not (runnable and mark)]


def guide_pages() -> list:
    """Every page whose Python blocks run as a doctest: the getting-started page and
    the user guide, as paths relative to docs/."""
    pages = ["getting-started.md"] + sorted(
        os.path.relpath(p, DOCS) for p in glob.glob(os.path.join(DOCS, "guide", "*.md")))
    return [p for p in pages if python_blocks(page(p))]


def all_pages_text() -> str:
    """Every page of the site (docs/**/*.md) and the README, one text."""
    paths = [os.path.join(ROOT, "README.md")] + sorted(
        glob.glob(os.path.join(DOCS, "**", "*.md"), recursive=True))
    return "\n".join(open(p, encoding="utf-8").read() for p in paths
                     if "_build" not in p)
