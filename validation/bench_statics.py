"""Benchmark of the FE statics (a script, not a test): prints a table, writes bench_statics.csv.

    python validation/bench_statics.py

1. A 9-value EI sweep (1e2 .. 1e10) of beam-slider and beam-fixed at default accuracy, each case
   solved from scratch with the spring-hinge predictor as `femslide sweep` does (so that a sweep row
   equals `femslide solve` bit for bit): summed solve time, Newton iterations, largest error estimate.
2. Cost per element per Newton iteration (residual + tangent + linear solve) of a cantilever with
   N = 1e4 elements (and 32 for comparison); the cost of one ``Model.system`` call (residual and
   Jacobian, and the residual alone) of beam-slider with 8 elements (36 unknowns), the size at which
   the sweep spends most of its time in numpy's per-call overhead.
3. With openseespy installed, the same work in OpenSees in the same run: beam-slider with 32 elements
   (penalty model of the sliding clamp; OpenSees finds the equilibrium itself: displacement control of
   the body rotation until the load factor passes 1, then secant steps to lam = 1; see
   validation/opensees_models.py ``opensees_slider_equilibrium``),
   the 32-element cantilever under a tip load (corotational transformation, Newton) and the cost per
   element per iteration at N = 1e4.  Timings are quoted as ratios measured in this one run (the
   machines are noisy).
"""
from __future__ import annotations

import csv
import math
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))

from opensees_models import opensees_slider_equilibrium  # noqa: E402

from femslide.model.linalg import solve_linear  # noqa: E402
from femslide.model.patterns import PatternCache  # noqa: E402
from femslide.scenes.catalog import SCENES  # noqa: E402
from femslide.scenes.paper import solve_scene  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))


def sweep(scene, repeats=5):
    """Best of ``repeats`` summed solve times of the 9-value EI sweep: (total, iterations, largest
    error estimate, {EI: (best time of the case, its result)})."""
    best = None
    cases = {}
    for _ in range(repeats):
        total, its, worst = 0.0, 0, 0.0
        cache = PatternCache()  # one sweep in one process shares its Jacobian patterns, as `sweep` does
        for k in range(2, 11):
            v = SCENES[scene].resolve({"EI": 10.0 ** k})
            t0 = time.perf_counter()
            sol = solve_scene(scene, v, cache=cache)
            dt = time.perf_counter() - t0
            res = {"M_max": float(sol.watched[0]), "phi": float(sol.watched[1]),
                   "iterations": sol.iterations, "error_estimate": sol.error_estimate}
            total += dt
            its += res["iterations"]
            worst = max(worst, res["error_estimate"])
            if dt < cases.get(k, (math.inf,))[0]:
                cases[k] = (dt, res)
        if best is None or total < best[0]:
            best = (total, its, worst)
    return best + (cases,)


def per_iteration(n, repeats=5):
    """Seconds per Newton iteration (residual, tangent, linear solve) of an n-element cantilever,
    measured at its converged state (reached by climbing from coarse meshes, as solve_scene does)."""
    v = SCENES["cantilever-load"].resolve({"n_elements": n})
    lv = solve_scene("cantilever-load", v).level
    m, y, alpha = lv.model, lv.y, lv.elements
    best = np.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        r, A, _info = m.system(y, alpha, 1.0)
        solve_linear(A, r)
        best = min(best, time.perf_counter() - t0)
    return best


def system_call(n=8, calls=200, repeats=5):
    """(unknowns, seconds per Model.system call with the Jacobian, without) of beam-slider with n
    elements at its converged state (EI = 1e6 N m^2), best of ``repeats`` batches of ``calls``."""
    v = SCENES["beam-slider"].resolve({"EI": 1e6, "n_elements": n})
    lv = solve_scene("beam-slider", v).level
    m, y, alpha = lv.model, lv.y, lv.elements
    out = []
    for jac in (True, False):
        best = np.inf
        for _ in range(repeats):
            t0 = time.perf_counter()
            for _ in range(calls):
                m.system(y, alpha, 1.0, jacobian=jac)
            best = min(best, (time.perf_counter() - t0) / calls)
        out.append(best)
    return m.n, out[0], out[1]


def opensees_cantilever(n, P=1.0, steps=1, tol=1e-8, test_iters=50, test="NormUnbalance", clock=time.perf_counter):
    import openseespy.opensees as ops
    ops.wipe()
    ops.model("basic", "-ndm", 2, "-ndf", 3)
    for i in range(n + 1):
        ops.node(i + 1, i / n, 0.0)
    ops.fix(1, 1, 1, 1)
    ops.geomTransf("Corotational", 1)
    for i in range(n):
        ops.element("elasticBeamColumn", i + 1, i + 1, i + 2, 1.0, 1e6, 1e-6, 1)  # EA = 1e6, EI = 1
    ops.timeSeries("Linear", 1)
    ops.pattern("Plain", 1, 1)
    ops.load(n + 1, 0.0, P, 0.0)
    ops.system("BandGeneral")
    ops.numberer("RCM")
    ops.constraints("Plain")
    ops.test(test, tol, test_iters, 0)
    ops.algorithm("Newton")
    ops.integrator("LoadControl", 1.0 / steps)
    ops.analysis("Static")
    t0 = clock()
    ok = ops.analyze(steps)
    dt = clock() - t0
    its = ops.testIter()
    return ok, dt, its, ops.nodeDisp(n + 1)


def main():
    rows = []
    print("femslide statics benchmark (times are best of repeats, this machine, this run)\n")
    slider_cases = None
    for scene in ("beam-slider", "beam-fixed"):
        t, its, worst, cases = sweep(scene)
        if scene == "beam-slider":
            slider_cases = cases
        rows.append({"case": f"{scene} EI sweep 1e2..1e10 (9 solves)", "femslide_s": t,
                     "iterations": its, "note": f"max error_estimate {worst:.1e}"})
        print(f"{scene:12s} 9-value EI sweep: {t * 1e3:7.1f} ms, {its} Newton iterations, "
              f"max error estimate {worst:.1e}   (quoted for OpenSees: ~47 ms at ~1.5e-6)")
        print("    EI [N m^2]: " + "  ".join(f"1e{k}: {cases[k][0] * 1e3:.1f}" for k in sorted(cases)) + "  ms")
    for n in (32, 10000):
        t = per_iteration(n)
        rows.append({"case": f"cantilever N={n} per iteration", "femslide_s": t,
                     "note": f"{t / n * 1e6:.3f} us per element per iteration"})
        print(f"cantilever N={n:5d}: {t * 1e3:7.3f} ms per Newton iteration = {t / n * 1e6:.3f} us per element")
    n_un, t_jac, t_res = system_call()
    rows.append({"case": f"beam-slider 8 elements ({n_un} unknowns): one Model.system call", "femslide_s": t_jac,
                 "note": f"residual and Jacobian; residual alone {t_res * 1e6:.0f} us"})
    print(f"beam-slider 8 elements ({n_un} unknowns): Model.system {t_jac * 1e6:.0f} us with the Jacobian, "
          f"{t_res * 1e6:.0f} us the residual alone")
    try:
        import importlib
        importlib.import_module("openseespy.opensees")
        have_ops = True
    except Exception as exc:  # ImportError, or the shared library failing to load
        have_ops = False
        print(f"\nopenseespy not available ({type(exc).__name__}): OpenSees columns skipped")
    if have_ops:
        print()
        # beam-slider in OpenSees (32 elements, penalty clamp, finding the equilibrium itself)
        t_o = t_ob = t_f = 0.0
        failed, worst_lam, worst_M = [], 0.0, 0.0
        for k in sorted(slider_cases):
            dt_f, res = slider_cases[k]
            v = SCENES["beam-slider"].resolve({"EI": 10.0 ** k})
            runs = [opensees_slider_equilibrium(v) for _ in range(3)]
            best = min(runs, key=lambda r: r["analysis_s"])
            if best["status"] != 0:
                failed.append(f"1e{k}")
                continue
            t_o += best["analysis_s"]
            t_ob += min(r["all_s"] for r in runs)
            t_f += dt_f
            worst_lam = max(worst_lam, abs(best["lam"] - 1.0))
            worst_M = max(worst_M, abs(best["M_max"] / res["M_max"] - 1.0))
        done = len(slider_cases) - len(failed)
        rows.append({"case": f"beam-slider EI sweep, the {done} EI values OpenSees solved", "femslide_s": t_f,
                     "opensees_s": t_o, "ratio": t_f / t_o if t_o else "",
                     "note": f"OpenSees: 32 elements, penalty clamp, finds the equilibrium; analysis only "
                             f"(with model building {t_ob * 1e3:.1f} ms); |lam-1| <= {worst_lam:.1e}, "
                             f"M_max within {worst_M:.1e} of femslide; failed at EI = {', '.join(failed) or '-'}"})
        print(f"beam-slider, OpenSees (32 elements, penalty clamp, finding the equilibrium: displacement control "
              f"of the body rotation, secant to lam = 1) on the {done} EI values it solves: OpenSees "
              f"{t_o * 1e3:.1f} ms (analysis; {t_ob * 1e3:.1f} ms with building the model), femslide "
              f"{t_f * 1e3:.1f} ms, ratio {t_f / max(t_o, 1e-300):.2f}; OpenSees |lam - 1| <= "
              f"{worst_lam:.1e}, M_max within {worst_M:.1e} of femslide; no convergence at EI = "
              f"{', '.join(failed) or '-'}")
        # 32-element cantilever under the tip load EI/L^2, one load step, Newton
        best_o = min(opensees_cantilever(32)[1] for _ in range(5))
        v = SCENES["cantilever-load"].resolve({"n_elements": 32})
        best_f = np.inf
        for _ in range(5):
            t0 = time.perf_counter()
            solve_scene("cantilever-load", v)
            best_f = min(best_f, time.perf_counter() - t0)
        # solve_scene at n_elements=32 also solves 16 (for its error estimate)
        rows.append({"case": "cantilever 32 elements, tip load (+16 for the estimate)", "femslide_s": best_f,
                     "opensees_s": best_o, "ratio": best_f / best_o})
        print(f"cantilever 32 el. tip load: femslide {best_f * 1e3:.2f} ms (incl. the 16-element "
              f"solve for the error estimate), OpenSees {best_o * 1e3:.2f} ms, ratio {best_f / best_o:.2f}")
        # per iteration at N = 1e4: a small load converges in a few iterations; time / iterations
        ok, dt, its, _ = opensees_cantilever(10000, P=0.01, tol=1e-12, test="NormDispIncr")
        t_f = per_iteration(10000)
        per_o = dt / max(its, 1)
        rows.append({"case": "cantilever N=10000 per iteration", "femslide_s": t_f, "opensees_s": per_o,
                     "ratio": t_f / per_o, "note": f"OpenSees status {ok}, {its} iterations"})
        print(f"cantilever N=10000 per Newton iteration: femslide {t_f * 1e3:.2f} ms, OpenSees "
              f"{per_o * 1e3:.2f} ms, ratio {t_f / per_o:.2f}")
    path = os.path.join(HERE, "bench_statics.csv")
    keys = ["case", "femslide_s", "opensees_s", "ratio", "iterations", "note"]
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=keys)
        w.writeheader()
        for r in rows:
            w.writerow({k: r.get(k, "") for k in keys})
    print(f"\nwritten {path}")


if __name__ == "__main__":
    main()
