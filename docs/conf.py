"""Sphinx configuration of the femslide documentation (user guide and API reference).

Build: ``python -m sphinx -W -b html docs docs/_build/html`` (``pip install -e ".[docs]"``).
"""
from __future__ import annotations

import os
import sys

sys.path.insert(0, os.path.abspath(".."))   # document this checkout's femslide

import femslide  # noqa: E402

project = "femslide"
author = "femslide authors"
release = femslide.__version__
version = release

extensions = ["sphinx.ext.autodoc", "sphinx.ext.napoleon",
              "sphinx.ext.viewcode"]
exclude_patterns = ["_build"]
root_doc = "index"

autodoc_member_order = "bysource"
autodoc_typehints = "none"          # the numpy-style docstrings give types and units
napoleon_google_docstring = False
napoleon_numpy_docstring = True
napoleon_use_rtype = False
napoleon_use_ivar = True

html_theme = "alabaster"
html_title = f"femslide {release}"
html_static_path = []


def _plot_section() -> str:
    """The API section of ``femslide.plot`` (member diagrams), when this version has it."""
    plot = getattr(femslide, "plot", None)
    if plot is None:
        return ""
    if callable(plot):
        return "Pictures\n--------\n\n.. autofunction:: femslide.plot\n"
    return "Pictures\n--------\n\n.. automodule:: femslide.output.diagrams\n   :members:\n"


def _inject(app, docname, source):
    if docname == "api":
        source[0] = source[0].replace(".. femslide-plot-section", _plot_section())


def setup(app):
    app.connect("source-read", _inject)
