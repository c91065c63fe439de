"""Work-precision of the FE dynamics against OpenSees (issue 22): the paper's section 5.2 structure
(meshes/structures/beam-oscillation.toml, 8 elements, released from phi = -0.01 rad, 3 s), peak |F2|
against the reduced 1-DOF model's 88.92548492 N (validation/reduced_dynamics.py: DOP853 at rtol 1e-11;
OpenSees agrees with it to 1e-8 at small dt).

* femslide: Radau IIA at tolerance 1e-3 .. 1e-8: steps, the integration's time (``integration_time_s``:
  without the static start, the modes and the error estimate's check run), the peak's error, the
  run's ``error_estimate`` and ``energy_balance``;
* OpenSees (openseespy; skipped without it): the same structure (validation/opensees_models.py,
  ``opensees_oscillation``) with Newmark average acceleration and HHT (alpha = 0.9), constant dt from
  8e-3 to 2.5e-4 s: steps, the transient analysis's time, the refined peak's error.

Prints the table, writes validation/bench_dynamics_accuracy.csv and, with matplotlib,
bench_dynamics_accuracy.png (error against steps and against time).  Times are of one run on this
machine; compare them as ratios within the run.
Run:  python validation/bench_dynamics_accuracy.py
"""
from __future__ import annotations

import csv
import os
import sys

import femslide

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
F2_REF = 88.92548492   # N, the reduced model's peak (validation/dynamic_references.py)


def femslide_rows():
    rows = []
    for tol in (1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8):
        r = femslide.simulate("beam-oscillation", tolerance=tol)
        rows.append({"method": "femslide Radau IIA", "setting": f"tolerance {tol:g}", "steps": r["steps"],
                     "time_s": r["integration_time_s"], "err_F2": abs(r["F2_max"] / F2_REF - 1.0),
                     "error_estimate": r["error_estimate"], "energy_balance": r["energy_balance"]})
    return rows


def opensees_rows():
    try:
        from opensees_models import opensees_oscillation
    except ImportError:
        return []
    rows = []
    for name, integ in (("OpenSees Newmark", ("Newmark", 0.5, 0.25)), ("OpenSees HHT 0.9", ("HHT", 0.9))):
        for dt in (8e-3, 4e-3, 2e-3, 1e-3, 5e-4, 2.5e-4):
            o = opensees_oscillation(dt=dt, history=False, integrator=integ)
            if o["status"] != 0:
                continue
            rows.append({"method": name, "setting": f"dt {dt:g} s", "steps": o["steps"], "time_s": o["analysis_s"],
                         "err_F2": abs(o["F2_peak"] / F2_REF - 1.0), "error_estimate": "", "energy_balance": ""})
    return rows


def main():
    rows = femslide_rows() + opensees_rows()
    keys = ["method", "setting", "steps", "time_s", "err_F2", "error_estimate", "energy_balance"]
    print(f"{'method':22s} {'setting':18s} {'steps':>6s} {'time s':>8s} {'err |F2|':>9s} {'estimate':>9s} "
          f"{'energy':>9s}")
    for r in rows:
        f = (lambda x: f"{x:9.2e}" if isinstance(x, float) else f"{'-':>9s}")
        print(f"{r['method']:22s} {r['setting']:18s} {r['steps']:6d} {r['time_s']:8.3f} {f(r['err_F2'])} "
              f"{f(r['error_estimate'])} {f(r['energy_balance'])}")
    with open(os.path.join(HERE, "bench_dynamics_accuracy.csv"), "w", newline="") as fh:
        w = csv.DictWriter(fh, keys)
        w.writeheader()
        w.writerows(rows)
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for m in dict.fromkeys(r["method"] for r in rows):
        sel = [r for r in rows if r["method"] == m]
        for ax, x in zip(axes, ("steps", "time_s")):
            ax.loglog([r[x] for r in sel], [max(r["err_F2"], 1e-12) for r in sel], "o-", label=m)
    for ax, x in zip(axes, ("steps", "time [s] (integration only)")):
        ax.set_xlabel(x)
        ax.set_ylabel("relative error of peak |F2|")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend()
    fig.suptitle("section 5.2, 3 s: femslide Radau IIA against OpenSees")
    fig.tight_layout()
    fig.savefig(os.path.join(HERE, "bench_dynamics_accuracy.png"), dpi=100)


if __name__ == "__main__":
    main()
