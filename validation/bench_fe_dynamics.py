"""Benchmark of the FE dynamics (femslide/transient.py): order, work-precision and cost per element.

Prints three tables and writes validation/bench_fe_dynamics.csv (+ bench_fe_dynamics.png when
matplotlib is installed):

1. order: a block on a frictionless ground slider with a spring (meshes/structures/sliding-belt.toml)
   released from 7 cm, two periods, against the exact w0 cos(omega t): error, steps and run time per
   tolerance.  The generalized-alpha scheme is second order: the error falls like steps^-2 (and,
   with the local error held at the tolerance, like tolerance^(2/3));
2. work-precision on the paper's section 5.2 structure (meshes/structures/beam-oscillation.toml,
   8 elements, 3 s): relative error of the peak |F2| against the reduced 1-DOF model
   (femslide simulate beam-oscillation, 88.92548492 N; an OpenSees transient agrees with it to
   1.4e-5), steps and run time; the reduced model's own run time measured in the same run;
3. cost per step (the integration alone, without the static start and the modes) against the number
   of elements of the flexible rod (section 5.2 structure with rhoA, 2 s at tolerance 1e-5): the
   banded solve makes a step O(n), on top of a fixed Python cost per step.

Run:  python validation/bench_fe_dynamics.py        (~2-4 min on the 2-core development machine)
"""
from __future__ import annotations

import csv
import math
import os
import pathlib
import sys
import time

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

import numpy as np  # noqa: E402

import femslide  # noqa: E402
from femslide import structfile  # noqa: E402
from femslide.simulation import parse_spec, simulate  # noqa: E402

F2_REF = 88.92548492288407


def order_table(rows):
    omega = math.sqrt(200.0)
    print("\n1. order: frictionless block, 2 periods, exact w0 cos(omega t)")
    print(f"{'tolerance':>10} {'steps':>7} {'max error [m]':>14} {'time [s]':>9}")
    prev = None
    for tol in (1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9):
        t0 = time.perf_counter()
        r = femslide.simulate("meshes/structures/sliding-belt.toml", t_end=4 * math.pi / omega, tolerance=tol)
        wall = time.perf_counter() - t0
        h = r.history
        err = float(np.abs(h["joints.belt.slide"] - 0.07 * np.cos(omega * h["t"])).max())
        slope = "" if prev is None else f"  order {-math.log(err / prev[1]) / math.log(r['steps'] / prev[0]):.2f}"
        print(f"{tol:10.0e} {r['steps']:7d} {err:14.3e} {wall:9.3f}{slope}")
        rows.append({"case": "oscillator", "tolerance": tol, "steps": r["steps"], "error": err, "time_s": wall})
        prev = (r["steps"], err)


def section52_table(rows):
    sf = structfile.load("meshes/structures/beam-oscillation.toml")
    print("\n2. section 5.2 structure (8 elements, 3 s): peak |F2| against the reduced model")
    print(f"{'tolerance':>10} {'steps':>7} {'F2 peak [N]':>14} {'rel. error':>11} {'time [s]':>9}")
    for tol in (1e-3, 1e-4, 1e-5, 1e-6, 1e-7):
        spec = parse_spec(sf.simulate_table)
        spec.tolerance = tol
        t0 = time.perf_counter()
        r = simulate(sf.structure.freeze(), spec)
        wall = time.perf_counter() - t0
        F2 = r["peaks"]["reactions"]["B1"]["Fx"]
        print(f"{tol:10.0e} {r['steps']:7d} {F2:14.8f} {abs(F2 / F2_REF - 1):11.2e} {wall:9.3f}")
        rows.append({"case": "section 5.2", "tolerance": tol, "steps": r["steps"], "error": abs(F2 / F2_REF - 1),
                     "time_s": wall})
    t0 = time.perf_counter()
    red = femslide.simulate("beam-oscillation")
    wall = time.perf_counter() - t0
    print(f"{'reduced':>10} {red['steps']:7d} {red['F2_max']:14.8f} {'(reference)':>11} {wall:9.3f}"
          "   femslide simulate beam-oscillation, same run")
    rows.append({"case": "section 5.2 reduced model", "tolerance": "", "steps": red["steps"], "error": 0.0,
                 "time_s": wall})


def elements_table(rows):
    sf = structfile.load("meshes/structures/beam-oscillation.toml")
    print("\n3. cost per step against the elements of the flexible rod (rhoA = 5 kg/m, 2 s, tolerance 1e-5)")
    print(f"{'elements':>9} {'unknowns':>9} {'steps':>7} {'ms/step':>8} {'total [s]':>9}")
    for n in (8, 32, 128, 512):
        s = sf.structure.copy()
        s.set("right.elements", n)
        s.set("right.rhoA", 5.0)
        spec = parse_spec(sf.simulate_table)
        spec.t_end, spec.tolerance = 2.0, 1e-5
        t0 = time.perf_counter()
        r = simulate(s.freeze(), spec)
        wall = time.perf_counter() - t0
        nq = 3 * (n + 1) + 6
        per = r["integration_time_s"] / r["steps"]
        print(f"{n:9d} {nq:9d} {r['steps']:7d} {1e3 * per:8.3f} {wall:9.3f}")
        rows.append({"case": f"elements {n}", "tolerance": 1e-5, "steps": r["steps"], "error": "",
                     "time_s": wall})


def main():
    rows = []
    only = sys.argv[1:] or ["1", "2", "3"]
    if "1" in only:
        order_table(rows)
    if "2" in only:
        section52_table(rows)
    if "3" in only:
        elements_table(rows)
    path = HERE / "bench_fe_dynamics.csv"
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=["case", "tolerance", "steps", "error", "time_s"])
        w.writeheader()
        w.writerows(rows)
    print(f"\nwritten: {path}")
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    for case, mk in (("oscillator", "o-"), ("section 5.2", "s-")):
        rr = [r for r in rows if r["case"] == case]
        ax[0].loglog([r["steps"] for r in rr], [r["error"] for r in rr], mk, label=case)
        ax[1].loglog([r["time_s"] for r in rr], [r["error"] for r in rr], mk, label=case)
    st = np.array([10.0, 1e4])
    ax[0].loglog(st, 1e-1 * (st / 10) ** -2, "k:", label="slope -2")
    ax[0].set_xlabel("steps")
    ax[1].set_xlabel("run time [s]")
    from matplotlib.ticker import NullFormatter
    for a in ax:
        a.xaxis.set_minor_formatter(NullFormatter())
        a.set_ylabel("error (oscillator: m; section 5.2: relative F2 peak)")
        a.grid(True, which="both", alpha=0.3)
        a.legend()
    fig.tight_layout()
    fig.savefig(HERE / "bench_fe_dynamics.png", dpi=110)
    print(f"written: {HERE / 'bench_fe_dynamics.png'}")


if __name__ == "__main__":
    main()
