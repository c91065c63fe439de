"""The compiled part of femslide: the model assembly kernel (femslide/model/_assembly.c).

Everything else is declared in pyproject.toml.  The extension is optional: where it cannot be
built (no C compiler), the install goes on and femslide assembles with numpy (``femslide --version``
says which)."""
from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext


class BuildExt(build_ext):
    """MSVC compiles C89 with extensions by default; the kernel is C99 (``restrict``): ask for C11
    (Visual Studio 2019 16.8 and later).  gcc and clang take the source as it is.  (Not tried here: the
    Windows wheels come from cibuildwheel, whose test asks for the compiled kernel.)"""

    def build_extensions(self):
        if self.compiler.compiler_type == "msvc":
            for ext in self.extensions:
                ext.extra_compile_args = list(ext.extra_compile_args or []) + ["/std:c11"]
        super().build_extensions()


setup(ext_modules=[Extension("femslide.model._assembly", ["femslide/model/_assembly.c"], optional=True)],
      cmdclass={"build_ext": BuildExt})
