"""Load cases and combinations of a portal frame on an elastic foundation, with their envelope.

A steel portal frame (two 4 m columns, a 6 m beam, sections by E, I, A) stands on a pin at the left
foot and, at the right foot, on a foundation that turns elastically (a weld with a rotational spring
``kr``).  Its loads belong to cases: the self-weight ("dead", with gravity), snow on the beam, wind
on the left column top.  Three combinations (two ultimate, one serviceability) are solved, each as its
own equilibrium - here in first-order theory, as a hand calculation or a linear frame code would, and
then in the exact theory for comparison.  The script prints the envelope (the largest moments and
the reactions' extremes with the combination that governs each) and writes, into the folder given as
its first argument (default: a new temporary folder), ``combinations.csv``, ``envelope_M.csv``,
``envelope_M.png`` (the bending moment of every combination along each rod, and their envelope) and
a VTU file per combination.

    python examples/load_combinations.py out/
"""
import sys
import tempfile
from pathlib import Path

import femslide

STEEL = 210e9   # Pa


def frame() -> femslide.Structure:
    s = femslide.Structure(gravity=(0.0, -9.81))
    column = dict(E=STEEL, I=2.3e-5, A=5.4e-3, rhoA=42.0)           # m^4, m^2, kg/m
    s.rod("left", start=(0.0, 0.0), end=(0.0, 4.0), **column)
    s.rod("right", start=(6.0, 0.0), end=(6.0, 4.0), **column)
    s.rod("beam", start=(0.0, 4.0), end=(6.0, 4.0), E=STEEL, I=5.8e-5, A=7.6e-3, rhoA=60.0)
    s.pin("A", a="left.start", b="ground")
    s.weld("D", a="right.start", b="ground", kr=5e6)                # N m/rad: an elastic foundation
    s.weld("B", a="left.end", b="beam.start")
    s.weld("C", a="right.end", b="beam.end")
    s.distributed("snow", on="beam", force=(0.0, -8000.0), case="snow")   # N/m
    s.force("wind", on="left.end", force=(12000.0, 0.0), case="wind")     # N
    s.combination("ULS-snow", {"dead": 1.35, "snow": 1.5, "wind": 0.9})
    s.combination("ULS-wind", {"dead": 1.35, "snow": 0.75, "wind": 1.5})
    s.combination("SLS", {"dead": 1.0, "snow": 1.0, "wind": 0.6})
    return s


def main(out: Path) -> None:
    out.mkdir(parents=True, exist_ok=True)
    r = femslide.solve(frame(), theory="linear")
    env = r["envelope"]
    print("envelope (first-order theory):")
    for rod, d in env["rods"].items():
        print(f"  {rod:6s} M_max = {d['M_max']:9.1f} N m ({d['M_max_combination']})")
    for sup, d in env["reactions"].items():
        print(f"  {sup}: Fy in [{d['Fy_min']:.1f}, {d['Fy_max']:.1f}] N, M in [{d['M_min']:.1f}, {d['M_max']:.1f}] N m")
    exact = femslide.solve(frame())
    for c in r["combinations"]:
        lin, ex = r["combinations"][c]["M_max"], exact["combinations"][c]["M_max"]
        print(f"  {c:8s} M_max first order {lin:9.1f} N m, exact {ex:9.1f} N m ({(ex - lin) / lin:+.2%})")
    for path in r.write(out):
        print(path)


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path(tempfile.mkdtemp(prefix="femslide-combinations-")))
