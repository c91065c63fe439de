"""Output paths checked before any work: ``--out`` (a folder, or the file of ``femslide mesh``),
``--plot`` and ``--screenshot`` (image files).

A solve, simulation or sweep can take minutes; a path it cannot write must be rejected first (exit 2,
the message names the option and the path), not after the work.  Each check *tries* the write (a
folder is created and a probe file written and removed; an image file is opened for appending and,
if it did not exist, removed again): permission bits say nothing for root, read-only mounts or paths
under a file.  Only the standard library is imported, except that ``--plot`` asks matplotlib which
image formats it writes (it is needed for the plot anyway).
"""
from __future__ import annotations

import os

from femslide.errors import BadInput

#: pyvista/VTK screenshot formats (``Plotter.screenshot`` picks the writer by extension)
SCREENSHOT_EXT = (".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff")


def _why(exc: OSError) -> str:
    return exc.strerror or str(exc)


def check_out_dir(path: str, option: str = "--out") -> None:
    """``path`` is, or can be made, a writable folder (it is created now)."""
    if not path:
        raise BadInput(f"{option}: empty path; allowed: a writable folder")
    if os.path.exists(path) and not os.path.isdir(path):
        raise BadInput(f"{option} {path}: an existing file, not a folder; allowed: a writable folder "
                       f"(existing or new)")
    try:
        os.makedirs(path, exist_ok=True)
        import tempfile
        fd, probe = tempfile.mkstemp(prefix=".femslide-probe-", dir=path)
        os.close(fd)
        os.remove(probe)
    except OSError as exc:
        raise BadInput(f"{option} {path}: cannot write there ({_why(exc)}); allowed: a writable folder "
                       f"(existing or new)") from None


def check_out_file(path: str, option: str, extensions=None, what="a file") -> None:
    """``path`` names a file that can be written (its folder is created now); ``extensions``, when
    given, are the allowed (lower-case, dotted) extensions."""
    if not path:
        raise BadInput(f"{option}: empty path; allowed: {what}")
    ext = os.path.splitext(path)[1].lower()
    if extensions is not None and ext not in extensions:
        raise BadInput(f"{option} {path}: unsupported file type {ext or '(none)'!r}; allowed: {what} "
                       f"with extension {', '.join(sorted(extensions))}")
    if os.path.isdir(path):
        raise BadInput(f"{option} {path}: an existing folder; allowed: {what}")
    existed = os.path.exists(path)
    try:
        d = os.path.dirname(path)
        if d:
            os.makedirs(d, exist_ok=True)
        with open(path, "ab"):
            pass
        if not existed:
            os.remove(path)
    except OSError as exc:
        raise BadInput(f"{option} {path}: cannot write there ({_why(exc)}); allowed: {what} in a "
                       f"writable folder") from None


def plot_extensions():
    try:
        from matplotlib.backend_bases import FigureCanvasBase
    except ImportError:
        raise BadInput("--plot needs matplotlib: pip install 'femslide[plot]'") from None
    return tuple("." + e for e in FigureCanvasBase.get_supported_filetypes())


def check(args) -> None:
    """Check every output path of a parsed command line (argparse namespace); BadInput otherwise."""
    cmd = getattr(args, "cmd", None)
    out = getattr(args, "out", None)
    if cmd in ("solve", "simulate", "sweep", "modes", "buckling") and out is not None:
        check_out_dir(out)
    if cmd == "mesh" and out is not None:
        check_out_file(out, "--out", what="a mesh file")
    plot = getattr(args, "plot", None)
    if plot is not None:
        check_out_file(plot, "--plot", plot_extensions(), what="an image file")
    shot = getattr(args, "screenshot", None)
    if shot is not None:
        check_out_file(shot, "--screenshot", SCREENSHOT_EXT, what="an image file")
