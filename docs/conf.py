"""Sphinx configuration of the gather-verify docs site.

Build (warnings are errors, every cross-reference must resolve)::

    python -m sphinx -W -n --keep-going -b html docs docs/_build/html

The pages are the Markdown files of docs/, read by MyST; the API reference is generated
from the docstrings (autodoc, autosummary) and the command-line reference from the argparse
parser (``_ext/gv_cli.py``). Every internal link of the built site is checked
(``_ext/gv_links.py``: a missing page, file or anchor fails the build), and the short names
the docstrings use are resolved as a reader would (``_ext/gv_refs.py``).
"""

from __future__ import annotations

import importlib.util
import shutil
import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
sys.path.insert(0, str(DOCS.parent))  # the package, from this checkout
sys.path.insert(0, str(DOCS / "_ext"))

project = "gather-verify"
author = "the gather-verify authors"
copyright = "the gather-verify authors"  # noqa: A001 - Sphinx's name

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "gv_cli",
    "gv_refs",
    "gv_links",
]
templates_path = ["_templates"]

source_suffix = {".md": "markdown", ".rst": "restructuredtext"}  # .rst: autosummary's pages
root_doc = "index"
exclude_patterns = ["_build", "examples", "img"]

# MyST: the pages stay plain Markdown that GitHub renders too; headings get GitHub's
# anchors, so links such as findings.md#f5-a-non-guard-... work on both.
myst_heading_anchors = 4
myst_enable_extensions = ["colon_fence"]

# Every cross-reference must resolve (-n, also set here), with no list of exceptions: the
# docstrings' short names are resolved by _ext/gv_refs.py, and the signatures' annotations
# (numpy, networkx, typing) are not turned into references (autodoc_typehints below).
nitpicky = True

autosummary_generate = True
# autosummary writes a page per module and never deletes one: start from none, so that a
# module that moved or was removed leaves no stale page (a warning, so a failed build)
shutil.rmtree(DOCS / "reference" / "_generated", ignore_errors=True)
autodoc_default_options = {
    "members": True,
    "undoc-members": True,
    "ignore-module-all": True,  # a package's __all__ re-exports: documented where defined
    "show-inheritance": True,
}
autodoc_member_order = "bysource"
autodoc_inherit_docstrings = False  # pytest's docstrings cross-reference pytest's own docs
autodoc_typehints = "none"  # the signatures carry them; no cross-reference per annotation

smartquotes = False  # option names (--help) and quotes in help texts stay as typed

html_theme = "furo" if importlib.util.find_spec("furo") else "alabaster"
html_title = "gather-verify"
html_static_path: list[str] = []
