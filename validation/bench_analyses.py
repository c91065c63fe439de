"""Cost of the engineering analyses, measured in one run (wall times on this machine; ratios are what
carry over).  Prints a table:

- load combinations: a portal frame with 3 combinations solved together (shared patterns) against 3
  separate solves of the same loads scaled by hand, in first-order and in exact theory;
- linear buckling of a cantilever and of a sway frame at default settings (adaptive meshes);
- the inclined-guide structure: the default solve that fails naming its limit point (the path traced
  and the limit point refined), and the arc-length solve through the snap.

    python validation/bench_analyses.py
"""
from __future__ import annotations

import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "examples"))

import femslide  # noqa: E402


def timed(f, repeat=3):
    best = float("inf")
    out = None
    for _ in range(repeat):
        t0 = time.perf_counter()
        try:
            out = f()
        except femslide.SolverFailure as exc:
            out = exc
        best = min(best, time.perf_counter() - t0)
    return best, out


def main():
    from column_buckling import frame as sway_frame
    from load_combinations import frame as portal
    rows = []
    for theory in ("linear", "nonlinear"):
        s = portal()
        t_all, r = timed(lambda s=s, theory=theory: femslide.solve(s, theory=theory))
        t_sep = 0.0
        for c in s.combinations.values():
            one = portal()
            one.combinations.clear()
            f = dict(c.factors)
            one.gravity = (0.0, -9.81 * f.get("dead", 0.0))
            for ln, ld in list(one.loads.items()):
                k = f.get(ld.case, 0.0)
                one.set(f"{ln}.force", (k * ld.force[0], k * ld.force[1]))
            t, _ = timed(lambda one=one, theory=theory: femslide.solve(one, theory=theory))
            t_sep += t
        rows.append((f"3 combinations, {theory} theory", t_all, f"3 separate solves {t_sep:.3f} s "
                     f"(ratio {t_all / t_sep:.2f})"))
    col = femslide.Structure(gravity=(0.0, 0.0))
    col.rod("c", (0.0, 0.0), (0.0, 3.0), EI=2.4e5)
    col.weld("base", "c.start", "ground")
    col.force("P", "c.end", force=(0.0, -1e4))
    for about in ("equilibrium", "reference"):
        t, r = timed(lambda about=about: femslide.buckling(col, count=3, about=about), 1)
        rows.append((f"buckling, cantilever, about the {about}", t,
                     f"{r['elements']['c']} elements, estimate {r['error_estimate']:.1e}"))
    t, r = timed(lambda: femslide.buckling(sway_frame(), count=3), 1)
    rows.append(("buckling, sway frame (3 rods)", t, f"{r['elements']} elements, estimate {r['error_estimate']:.1e}"))
    ig = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "meshes", "structures", "inclined-guide.toml")
    s = femslide.load(ig)
    t, exc = timed(lambda: femslide.solve(s), 1)
    rows.append(("inclined guide, default (fails at the limit)", t, exc.reason[:46]))
    t, r = timed(lambda: femslide.solve(s, path="arc-length"), 1)
    rows.append(("inclined guide, arc-length through the snap", t,
                 f"{len(r['path'])} path points, {r['iterations']} Newton iterations"))
    print(f"{'case':48s} {'wall [s]':>9s}  notes")
    for name, t, note in rows:
        print(f"{name:48s} {t:9.3f}  {note}")


if __name__ == "__main__":
    main()
