"""The accuracy of a time history's reactions against the tolerance asked: error against run time where
vibrations too fast for the steps carry a share of a reaction.  A script, not a test.

    python validation/bench_reaction_accuracy.py        # ~10 s; needs openseespy for its reference

Case: validation/massive-cantilever.toml (32 elements, rhoA = 1 kg/m, EI = 10 N m^2, EA = 1e7 N,
clamped, base shaken across it at 1 Hz from rest) over its first 0.3 s.  Its bending modes at 60-210
Hz are excited at the start and carry ~1e-4 of the clamp's shear; femslide's L-stable Radau IIA steps
damp the ones they do not resolve.

Reference (independent of femslide): the same model in OpenSees (validation/opensees_models.py
opensees_massive_cantilever: corotational elasticBeamColumn elements, the same lumped masses),
Newmark's average acceleration (no numerical damping, order 2) at dt = 1e-5 s, the clamp's reaction
from ``nodeReaction``; its own error is shown by the same run at dt = 2e-5 s (the difference over 3,
Richardson, printed).  Each history's error: the largest |femslide - reference| at femslide's samples
(output_interval 1 ms) over the reference's largest |value|, the sign of femslide's reaction matched
to OpenSees' (the force of the support on the rod) by the sign that fits better.

For each tolerance 1e-3 .. 1e-8: steps, time, error_estimate (with its check run), within_promise,
and the actual errors of the clamp's Fx, Fy, M.  Writes validation/bench_reaction_accuracy.csv and
.png (actual error and estimate against the tolerance).
"""
from __future__ import annotations

import csv
import os
import pathlib
import sys
import time

HERE = pathlib.Path(__file__).resolve().parent
for _p in (str(HERE.parent), str(HERE)):
    if _p not in sys.path:
        sys.path.insert(0, _p)

os.environ.setdefault("FEMSLIDE_QUIET", "1")

import numpy as np  # noqa: E402

import femslide  # noqa: E402

PATH = str(HERE / "massive-cantilever.toml")
T_END = 0.3
SAMPLE = 1e-3
TOLS = [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8]
COLS = {"Fx": 0, "Fy": 1, "M": 2}


def reference(dt):
    """OpenSees' clamp reaction history (t, (steps + 1, 3)) at the step dt, plus the inertia load of the
    half element's mass that femslide lumps at the clamped node (rhoA L / 64 = 1/64 kg, loaded by
    -m a_g like every node's, held by the clamp; OpenSees' model puts no mass on its fixed node):
    Fy + m a_g(t), a_g = sin(2 pi t) [m/s^2] across the rod."""
    from opensees_models import opensees_massive_cantilever
    r = opensees_massive_cantilever(dt=dt, t_end=T_END, history=True, reactions=True)
    assert r["status"] == 0, r
    reac = r["reaction"].copy()
    reac[:, 1] += (1.0 / 64.0) * np.sin(2.0 * np.pi * r["t"])
    return r["t"], reac


def error(t, values, t_ref, ref):
    """Largest |values - ref(t)| over max |ref|, ref linear between its samples (1e-5 s apart), with
    the sign of values that fits better."""
    r = np.interp(t, t_ref, ref)
    scale = np.abs(ref).max()
    return min(np.abs(values - r).max(), np.abs(values + r).max()) / scale


def main():
    try:
        import openseespy.opensees  # noqa: F401
    except ImportError:
        print("openseespy is not installed: pip install openseespy (its reference is needed)")
        return 1
    t0 = time.perf_counter()
    t_ref, ref = reference(1e-5)
    t_ref2, ref2 = reference(2e-5)
    t_os = time.perf_counter() - t0
    print(f"reference: OpenSees Newmark (average acceleration) at dt = 1e-5 s, {T_END} s ({t_os:.1f} s for "
          f"both runs)")
    own = {c: error(t_ref2, ref2[:, j], t_ref, ref[:, j]) / 3.0 for c, j in COLS.items()}
    print("   its own error (the run at 2e-5 s against it, over 3): " +
          ", ".join(f"{c} {e:.1e}" for c, e in own.items()))
    rows = []
    print(f"\n{'tolerance':>9} {'steps':>6} {'time s':>7} {'estimate':>9} {'promise':>7}   actual error: "
          f"{'Fx':>8} {'Fy':>8} {'M':>8}")
    for tol in TOLS:
        t1 = time.perf_counter()
        res = femslide.simulate(PATH, tolerance=tol, t_end=T_END, output_interval=SAMPLE)
        wall = time.perf_counter() - t1
        h = res.history
        t = np.asarray(h["t"])
        errs = {c: error(t, np.asarray(h[f"reactions.clamp.{c}"]), t_ref, ref[:, j]) for c, j in COLS.items()}
        acc = res["accuracy"]
        row = {"tolerance": tol, "steps": res["steps"], "wall_s": wall, "error_estimate": res["error_estimate"],
               "within_promise": acc.get("within_promise"), "worst": acc.get("worst_history") or acc.get("worst_peak"),
               **{f"error_{c}": e for c, e in errs.items()}}
        rows.append(row)
        print(f"{tol:9.0e} {res['steps']:6d} {wall:7.2f} {res['error_estimate']:9.1e} {str(row['within_promise']):>7}"
              f"   {'':13s} {errs['Fx']:8.1e} {errs['Fy']:8.1e} {errs['M']:8.1e}")
    out = HERE / "bench_reaction_accuracy.csv"
    with open(out, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    print(f"\nwritten: {out}")
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return 0
    fig, ax = plt.subplots(figsize=(6.0, 4.2))
    tol = np.array([r["tolerance"] for r in rows])
    for c, m in (("Fx", "s"), ("Fy", "o"), ("M", "^")):
        ax.loglog(tol, [r[f"error_{c}"] for r in rows], m + "-", label=f"actual error, clamp {c}")
    ax.loglog(tol, [r["error_estimate"] for r in rows], "k--", label="error_estimate (largest)")
    ax.loglog(tol, 3 * tol, ":", color="grey", label="3 x tolerance (the promise)")
    ax.set_xlabel("tolerance")
    ax.set_ylabel("relative error of the history")
    ax.set_title("massive cantilever, 0.3 s: reactions against OpenSees at dt = 1e-5", fontsize=9)
    ax.legend(fontsize=7)
    fig.tight_layout()
    png = HERE / "bench_reaction_accuracy.png"
    fig.savefig(png, dpi=120)
    print(f"written: {png}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
