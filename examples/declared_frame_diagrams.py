"""A declared portal frame under a distributed load and wind: its M, V and N diagrams as PNG files.

Two columns (4 m, pinned at the left foot, welded at the right one) carry a 6 m beam welded to both
column tops; the beam carries 2 kN/m downwards, the left column top a 1.5 kN wind load.  The script
solves the frame, prints the largest |M|, |V|, |N| of every rod and saves ``frame-M.png``,
``frame-V.png`` and ``frame-N.png`` into the folder given as the first argument (default: a new
temporary folder), displacements magnified 20 times.

    python examples/declared_frame_diagrams.py out/
"""
import sys
import tempfile
from pathlib import Path

import matplotlib

matplotlib.use("Agg")   # files only, no window
import matplotlib.pyplot as plt  # noqa: E402

import femslide  # noqa: E402


def frame() -> femslide.Structure:
    s = femslide.Structure(gravity=(0.0, -9.81))
    s.rod("left", start=(0.0, 0.0), end=(0.0, 4.0), EI=8e6)            # N m^2
    s.rod("right", start=(6.0, 0.0), end=(6.0, 4.0), EI=8e6)
    s.rod("beam", start=(0.0, 4.0), end=(6.0, 4.0), EI=2e7)
    s.pin("A", a="left.start", b="ground")                              # supports
    s.weld("D", a="right.start", b="ground")
    s.weld("B", a="left.end", b="beam.start")                           # rigid frame corners
    s.weld("C", a="right.end", b="beam.end")
    s.distributed("snow", on="beam", force=(0.0, -2000.0))              # N/m
    s.force("wind", on="left.end", force=(1500.0, 0.0))                 # N
    return s


def main(out: Path) -> None:
    out.mkdir(parents=True, exist_ok=True)
    r = femslide.solve(frame())
    for name, d in r["rods"].items():
        print(f"{name:6s} M_max = {d['M_max']:9.1f} N m   V_max = {d['V_max']:8.1f} N   N_max = {d['N_max']:8.1f} N")
    for diagram in ("M", "V", "N"):
        ax = femslide.plot(r, diagram=diagram, magnify=20.0)
        path = out / f"frame-{diagram}.png"
        ax.figure.savefig(path, dpi=110, bbox_inches="tight")
        plt.close(ax.figure)
        print(path)


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path(tempfile.mkdtemp(prefix="femslide-frame-")))
