"""Sphinx configuration of mechgen's documentation site (MyST markdown + sphinx-gallery).

Build it from the top of the repository with

    python3 -m pip install -e ".[docs]"
    python3 -m sphinx -W --keep-going -b html docs docs/_build/html

The gallery's scripts (docs/gallery/plot_*.py) run at every build, in mechgen's plain-Python
tier (no numba compile), and their figures become the gallery's pictures.
"""
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, ROOT)
sys.path.insert(0, os.path.join(HERE, "_ext"))

# the gallery answers in the plain-Python tier: no background numba compile during a build
os.environ.setdefault("MECHGEN_TIER", "python")
os.environ.setdefault("MPLBACKEND", "Agg")

import mechgen  # noqa: E402

project = "mechgen"
author = "the mechgen team"
copyright = "the mechgen team"       # noqa: A001 - Sphinx's name
release = version = mechgen.__version__

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
    "sphinx_gallery.gen_gallery",
    "mechgen_cli",
]

source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
root_doc = "index"
exclude_patterns = ["_build", "gallery/README.txt", "auto_gallery/*.ipynb",
                    "auto_gallery/*.py", "auto_gallery/*.zip", "auto_gallery/*.md5",
                    "auto_gallery/*.json"]

myst_enable_extensions = ["colon_fence", "dollarmath", "deflist"]
myst_heading_anchors = 3

autodoc_member_order = "bysource"
autodoc_typehints = "none"
napoleon_google_docstring = False
napoleon_numpy_docstring = True
napoleon_use_rtype = False

sphinx_gallery_conf = {
    "examples_dirs": "gallery",
    "gallery_dirs": "auto_gallery",
    "filename_pattern": r"plot_",
    "within_subsection_order": "FileNameSortKey",
    "download_all_examples": False,
    "remove_config_comments": True,
    "abort_on_example_error": False,
    "only_warn_on_example_error": False,
    "matplotlib_animations": False,
    "image_scrapers": ("matplotlib",),
    "reset_modules": ("matplotlib",),
    "capture_repr": (),
    "show_memory": False,
    "show_signature": False,
    "min_reported_time": 1e9,
}

html_theme = "alabaster"
html_title = f"mechgen {release}"
html_theme_options = {"description": "planar mechanisms, compiled",
                      "fixed_sidebar": True, "page_width": "1180px",
                      "code_font_size": "0.78em"}
html_static_path = []
