"""Linear buckling of a sway frame: the load factors at which it loses stability and its modes.

A portal frame (two 5 m steel columns clamped at their feet, a stiff 6 m beam) carries 400 kN on
each column top and a small lateral load.  ``femslide.buckling`` scales the stresses of the loaded
equilibrium (and, for comparison, of the first-order solution on the reference geometry) and finds
the lowest load factors at which the tangent stiffness turns singular, refining the mesh until they
are accurate to about 1e-6.  The first mode is the frame's sway, whose critical load lies between
those of a column clamped at its foot and free at its top, pi^2 EI / (4 L^2), and of a column
clamped at both ends that may sway, pi^2 EI / L^2.  Writes ``buckling_modes.png`` and the mode
shapes (``structure_buckling.pvd``, one VTU frame per mode) into the folder given as the first argument.

    python examples/column_buckling.py out/
"""
import math
import sys
import tempfile
from pathlib import Path

import femslide

E, I_COL, L_COL = 210e9, 8.36e-5, 5.0


def frame() -> femslide.Structure:
    s = femslide.Structure(gravity=(0.0, 0.0))
    s.rod("left", start=(0.0, 0.0), end=(0.0, L_COL), E=E, I=I_COL, A=5.38e-3)
    s.rod("right", start=(6.0, 0.0), end=(6.0, L_COL), E=E, I=I_COL, A=5.38e-3)
    s.rod("beam", start=(0.0, L_COL), end=(6.0, L_COL), E=E, I=4e-4, A=1.2e-2)
    s.weld("A", a="left.start", b="ground")
    s.weld("D", a="right.start", b="ground")
    s.weld("B", a="left.end", b="beam.start")
    s.weld("C", a="right.end", b="beam.end")
    s.force("P1", on="left.end", force=(0.0, -400e3))
    s.force("P2", on="right.end", force=(0.0, -400e3))
    s.force("H", on="left.end", force=(2e3, 0.0))
    return s


def main(out: Path) -> None:
    out.mkdir(parents=True, exist_ok=True)
    r = femslide.buckling(frame(), count=3)
    ref = femslide.buckling(frame(), count=3, about="reference")
    EI = E * I_COL
    lo, hi = math.pi**2 * EI / (4 * L_COL**2), math.pi**2 * EI / L_COL**2
    print(f"column bounds: {lo / 1e3:.0f} kN (free top) < P_cr < {hi / 1e3:.0f} kN (clamped sway)")
    for k, (a, b) in enumerate(zip(r["load_factors"], ref["load_factors"])):
        print(f"mode {k + 1}: load factor {a:.6f} about the equilibrium, {b:.6f} about the reference "
              f"(P_cr = {a * 400:.0f} kN per column)")
    print(f"error estimate {r['error_estimate']:.1e}, elements {r['elements']}")
    for path in r.write(out):
        print(path)


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path(tempfile.mkdtemp(prefix="femslide-buckling-")))
