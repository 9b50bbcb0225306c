"""Sphinx configuration of the polyell documentation (built with warnings as errors)."""

from __future__ import annotations

import polyell

project = "polyell"
author = "polyell developers"
copyright = "2026, polyell developers"
release = polyell.__version__

extensions = [
    "myst_nb",  # MyST Markdown, and notebooks executed at every build (they cannot rot)
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",
    # MathJax 3 copied into _static/mathjax: the pages render their mathematics offline
    # (the default would load it from a CDN). The package's folder name has hyphens.
    "sphinx-mathjax-offline",
]
source_suffix = {".md": "myst-nb", ".rst": "restructuredtext", ".ipynb": "myst-nb"}
nb_execution_mode = "force"
nb_execution_raise_on_error = True  # a notebook that fails fails the build
nb_execution_timeout = 600
myst_enable_extensions = ["dollarmath", "amsmath"]
myst_heading_anchors = 3
exclude_patterns = ["_build", "tutorials/*.py"]
# numpy-style types such as "array-like, shape (m, n)" would otherwise be resolved as
# references to every attribute called m or n.
suppress_warnings = ["ref.python"]

napoleon_numpy_docstring = True
napoleon_google_docstring = False
napoleon_use_rtype = False
autodoc_member_order = "bysource"
autodoc_typehints = "none"  # the numpy docstrings state the types and shapes
autosummary_generate = False

html_theme = "alabaster"
html_title = f"polyell {release}"
# No intersphinx: builds run offline (CI reaches only the package registries).
