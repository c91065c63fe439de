"""The compiled part of femslide: the model assembly kernel (femslide/model/_assembly.c).

Everything else is declared in pyproject.toml.  The extension is optional: where it cannot be
built (no C compiler), the install goes on and femslide assembles with numpy (``femslide --version``
says which)."""
from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext


class BuildExt(build_ext):
    """The kernel does the numpy path's arithmetic in its order, so the two agree to the last bit
    (tests/test_kernel.py): gcc and clang are told not to fuse a multiply and an add into one rounding
    (``-ffp-contract=off``; they do by default where the target has fused multiply-adds: aarch64,
    Apple silicon, x86-64 with -mfma).  MSVC does not fuse under its default /fp:precise; its C has no
    ``restrict``, which _assembly.c defines as ``__restrict`` there.  (Only gcc on x86-64 Linux was
    tried here; the other platforms' wheels come from cibuildwheel, whose test asks for the compiled
    kernel.)"""

    def build_extensions(self):
        if self.compiler.compiler_type in ("unix", "mingw32", "cygwin"):
            for ext in self.extensions:
                ext.extra_compile_args = list(ext.extra_compile_args or []) + ["-ffp-contract=off"]
        super().build_extensions()


setup(ext_modules=[Extension("femslide.model._assembly", ["femslide/model/_assembly.c"], optional=True)],
      cmdclass={"build_ext": BuildExt})
