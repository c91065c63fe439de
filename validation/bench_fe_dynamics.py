"""Benchmark of the FE dynamics (femslide/analysis/transient.py): order, work-precision and cost per element.

Prints three tables and writes validation/bench_fe_dynamics.csv (+ bench_fe_dynamics.png when
matplotlib is installed):

1. order: a block on a frictionless ground slider with a spring (meshes/structures/sliding-belt.toml)
   released from 7 cm, two periods, against the exact w0 cos(omega t): error, steps and run time per
   tolerance.  Radau IIA is of order 5 and its step control holds RADAU5's local error estimate
   (~ (omega h)^4) at the tolerance: the steps grow like tolerance^(-1/4) and the global error
   follows the tolerance (0.01-0.9 of it over 2-20 periods);
2. work-precision on the paper's section 5.2 structure (meshes/structures/beam-oscillation.toml,
   8 elements, 3 s): relative error of the peak |F2| against the reduced 1-DOF model
   (validation/reduced_dynamics.py, 88.92548492 N; the OpenSees transient of table 4 agrees with
   it to 1e-8: its refined peak at dt = 1e-3), steps and run time; the reduced model's own run time
   measured in the same run;
3. cost per step (the integration alone, without the static start and the modes) against the number
   of elements of the flexible rod (section 5.2 structure with rhoA, 2 s at tolerance 1e-5): the
   banded solve makes a step O(n), on top of a fixed Python cost per step;
4. an OpenSees Newmark transient of the section 5.2 structure (validation/opensees_models.py,
   ``opensees_oscillation``: average acceleration, Newton, constant dt; skipped without openseespy):
   a. max |F2| against dt, its relative error against the reduced model (the largest sample, and the
      top sample refined by a parabola as femslide refines its peaks; also with OpenSees' own zero
      initial acceleration), single runs;
   b. max |F2| against the penalty stiffness of the clamp and the rigid offsets at dt = 1e-3;
   c. the speed comparison of issue 13, in one run, best of 3 (perf_counter): femslide's FE transient
      at tolerance 1e-4 (whole simulate call; its integration alone) against OpenSees at dt = 1e-3 and
      at the largest dt of table a whose error (and that of every smaller dt of the table) is at most
      femslide's; OpenSees times are the transient analyze loop alone (+ building and the static hold).

Run:  python validation/bench_fe_dynamics.py [1 2 3 4]   (all: ~3-5 min on the 2-core development machine)
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
sys.path.insert(0, str(HERE))

import numpy as np  # noqa: E402
from dynamic_references import OSCILLATION_F2  # noqa: E402

import femslide  # noqa: E402
from femslide.analysis.simulate import parse_spec, simulate  # noqa: E402
from femslide.app import structfile  # noqa: E402

F2_REF = OSCILLATION_F2


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
    from reduced_dynamics import run_oscillation

    from femslide.scenes.catalog import get
    t0 = time.perf_counter()
    red = run_oscillation(get("beam-oscillation").resolve({}))
    wall = time.perf_counter() - t0
    print(f"{'reduced':>10} {red['steps']:7d} {red['F2_max']:14.8f} {'(reference)':>11} {wall:9.3f}"
          "   validation/reduced_dynamics.py, same run")
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


def _best_of(k, fn):
    """(best seconds, last result) of k calls of fn() -> (seconds, result)."""
    best, res = math.inf, None
    for _ in range(k):
        sec, res = fn()
        best = min(best, sec)
    return best, res


def opensees_table(rows):
    try:
        import openseespy.opensees  # noqa: F401
    except ImportError:
        print("\n4. OpenSees: skipped (openseespy not importable)")
        return
    from opensees_models import opensees_oscillation

    def err(x):
        return abs(x / F2_REF - 1)

    print("\n4a. OpenSees Newmark (average acceleration) transient, section 5.2 structure, 3 s: max |F2| against dt")
    print("    (error of the largest sample; of the refined peak; of the largest sample with OpenSees' zero start)")
    print(f"{'dt [s]':>9} {'steps':>6} {'max |F2| [N]':>14} {'error':>9} {'refined [N]':>14} {'error':>9} "
          f"{'zero a0':>9} {'analysis [s]':>12}")
    sweep = {}
    for dt in (1.28e-1, 6.4e-2, 3.2e-2, 1.6e-2, 8e-3, 4e-3, 2e-3, 1e-3, 5e-4, 2.5e-4):
        r = opensees_oscillation(dt=dt, history=False)
        z = opensees_oscillation(dt=dt, history=False, start_step=None)
        assert r["status"] == 0 and z["status"] == 0, (dt, r["status"], z["status"])
        sweep[dt] = r
        print(f"{dt:9.2e} {r['steps']:6d} {r['F2_max']:14.8f} {err(r['F2_max']):9.2e} {r['F2_peak']:14.8f} "
              f"{err(r['F2_peak']):9.2e} {err(z['F2_max']):9.2e} {r['analysis_s']:12.3f}")
        rows.append({"case": "opensees sweep", "dt": dt, "steps": r["steps"], "error": err(r["F2_max"]),
                     "error_refined": err(r["F2_peak"]), "time_s": r["analysis_s"],
                     "note": f"zero-start error {err(z['F2_max']):.3e}; single run"})

    print("\n4b. OpenSees at dt = 1e-3 against the penalty (EI of the clamp and of the rigid offsets")
    print("    = penalty x 1e6 N m^2; EA of the offsets = axial)")
    print(f"{'penalty':>9} {'axial [N]':>10} {'max |F2| [N]':>14} {'error':>9} {'refined [N]':>14} {'error':>9}")
    for pen, ax in ((1e7, 1e15), (1e8, 1e15), (1e9, 1e15), (1e10, 1e15), (1e9, 1e14), (1e9, 1e16)):
        r = opensees_oscillation(dt=1e-3, penalty=pen, axial=ax, history=False)
        print(f"{pen:9.0e} {ax:10.0e} {r['F2_max']:14.8f} {err(r['F2_max']):9.2e} {r['F2_peak']:14.8f} "
              f"{err(r['F2_peak']):9.2e}")
        rows.append({"case": "opensees penalty", "dt": 1e-3, "steps": r["steps"], "error": err(r["F2_max"]),
                     "error_refined": err(r["F2_peak"]), "time_s": r["analysis_s"],
                     "note": f"penalty {pen:.0e}, axial {ax:.0e}"})

    print("\n4c. speed, one run, best of 3: femslide FE transient at tolerance 1e-4 against OpenSees")
    sf = structfile.load("meshes/structures/beam-oscillation.toml")

    integration = []

    def femslide_run():
        spec = parse_spec(sf.simulate_table)
        spec.tolerance = 1e-4
        t0 = time.perf_counter()
        r = simulate(sf.structure.freeze(), spec)
        integration.append(r["integration_time_s"])
        return time.perf_counter() - t0, r
    fs_wall, fr = _best_of(3, femslide_run)
    fs_int = min(integration)
    fs_err = err(fr["peaks"]["reactions"]["B1"]["Fx"])

    def ops_run(dt):
        def run():
            r = opensees_oscillation(dt=dt, history=False)
            return r["analysis_s"], r
        best, r = _best_of(3, run)
        return best, r

    def matched(key):
        """Largest dt of table 4a whose error, and that of every smaller dt there, is <= femslide's."""
        ok = None
        for dt in sorted(sweep):
            if err(sweep[dt][key]) > fs_err:
                break
            ok = dt
        return ok

    print("    femslide: seconds of the whole simulate call (static start, modes, integration) | of its integration;")
    print("    OpenSees: seconds of the transient analyze loop | of that plus model building and the static hold;")
    print("    ratios: femslide whole / OpenSees loop, femslide integration / OpenSees loop")
    print(f"{'run':>34} {'steps':>6} {'error':>9} {'whole|loop':>10} {'integ.|+build':>13} {'ratios':>12}")
    print(f"{'femslide FE, tolerance 1e-4':>34} {fr['steps']:6d} {fs_err:9.2e} {fs_wall:10.3f} {fs_int:13.3f}")
    rows.append({"case": "comparison femslide", "tolerance": 1e-4, "steps": fr["steps"], "error": fs_err,
                 "time_s": fs_wall, "note": f"best of 3 wall of simulate(); integration_time_s {fs_int:.4f}"})
    cases = [("at dt = 1e-3", 1e-3, "F2_max")]
    for key, what in (("F2_max", "largest sample"), ("F2_peak", "refined peak")):
        dt = matched(key)
        if dt is None:
            print(f"    OpenSees: no dt of table 4a reaches femslide's error {fs_err:.2e} ({what})")
        else:
            cases.append((f"matched ({what})", dt, key))
    for label, dt, key in cases:
        best, r = ops_run(dt)
        e = err(r[key])
        name = f"OpenSees {label}, dt = {dt:g}" if label.startswith("matched") else f"OpenSees {label}"
        print(f"{name:>34} {r['steps']:6d} {e:9.2e} {best:10.3f} {best + r['build_s']:13.3f} "
              f"{fs_wall / best:6.2f} {fs_int / best:5.2f}")
        rows.append({"case": f"comparison opensees {label}", "dt": dt, "steps": r["steps"], "error": e,
                     "error_refined": err(r["F2_peak"]), "time_s": best,
                     "note": f"best of 3 analysis loop; build+hold {r['build_s']:.4f} s; "
                     f"femslide wall/this {fs_wall / best:.3f}; femslide integration/this {fs_int / best:.3f}"})


def main():
    rows = []
    only = sys.argv[1:] or ["1", "2", "3", "4"]
    if "1" in only:
        order_table(rows)
    if "2" in only:
        section52_table(rows)
    if "3" in only:
        elements_table(rows)
    if "4" in only:
        opensees_table(rows)
    path = HERE / "bench_fe_dynamics.csv"
    with open(path, "w", newline="") as fh:
        fields = ["case", "tolerance", "steps", "error", "time_s", "dt", "error_refined", "note"]
        w = csv.DictWriter(fh, fieldnames=fields, restval="")
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
    rr = [r for r in rows if r["case"] == "opensees sweep"]
    if rr:
        for key, mk, what in (("error", "^--", "largest sample"), ("error_refined", "v:", "refined peak")):
            lab = f"section 5.2, OpenSees Newmark ({what})"
            ax[0].loglog([r["steps"] for r in rr], [r[key] for r in rr], mk, label=lab)
            ax[1].loglog([r["time_s"] for r in rr], [r[key] for r in rr], mk, label=lab)
    st = np.array([10.0, 1e4])
    ax[0].loglog(st, 1e-1 * (st / 10) ** -2, "k:", label="slope -2")
    ax[0].set_xlabel("steps")
    ax[1].set_xlabel("run time [s]")
    from matplotlib.ticker import NullFormatter
    for a in ax:
        a.xaxis.set_minor_formatter(NullFormatter())
        a.set_ylabel("error (oscillator: m; section 5.2: relative F2 peak)")
        a.grid(True, which="both", alpha=0.3)
        a.legend(fontsize="small")
    fig.tight_layout()
    fig.savefig(HERE / "bench_fe_dynamics.png", dpi=110)
    print(f"written: {HERE / 'bench_fe_dynamics.png'}")


if __name__ == "__main__":
    main()
