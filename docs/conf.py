"""Sphinx configuration of the Manikin documentation (MyST Markdown pages, API reference from the docstrings).

Build (warnings are errors in the test suite, tests/test_docs.py)::

    .venv/bin/python -m sphinx -W --keep-going docs docs/_build/html
"""

from __future__ import annotations

import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
sys.path[:0] = [str(DOCS.parent), str(DOCS / "_ext")]  # the checkout's solver (autodoc) and our helpers

project = "Manikin"
author = "the Manikin authors"
copyright = "the Manikin authors; GPL-3.0-or-later"
release = version = "0.1.0"  # pyproject.toml's version (tests/test_docs.py checks they agree)

extensions = ["myst_parser", "sphinx.ext.autodoc", "sphinx.ext.mathjax", "manikin_docs"]
source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
exclude_patterns = ["_build", "_ext"]
root_doc = "index"

myst_enable_extensions = ["colon_fence", "deflist", "dollarmath"]
myst_heading_anchors = 3  # "[Stepping](#stepping)"-style links to headings up to ###

autodoc_member_order = "bysource"
autodoc_typehints = "description"  # signatures stay short; the types go under each parameter
autodoc_preserve_defaults = True  # show a default as written (``TOLERANCE``), not its value
add_module_names = False
python_use_unqualified_type_names = True

html_theme = "furo"
html_title = "Manikin"
html_static_path: list[str] = []
html_show_sourcelink = False
