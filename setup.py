"""The compiled part of femslide: the model assembly kernel (femslide/model/_assembly.c).

Everything else is declared in pyproject.toml.  The extension is optional: where it cannot be
built (no C compiler), the install goes on and femslide assembles with numpy (``femslide --version``
says which)."""
from setuptools import Extension, setup

setup(ext_modules=[Extension("femslide.model._assembly", ["femslide/model/_assembly.c"], optional=True)])
