"""Error against run time (work-precision) of femslide's statics and dynamics.  A script, not a test.

    python validation/work_precision.py          # ~1.5 min on 2 cores

Writes validation/work_precision.csv, validation/work_precision.md, work_precision_statics.png and
work_precision_dynamics.png.

Statics (fixed meshes n_elements = 1, 2, 4, ..., 1024 and the default adaptive run):
* cantilever-load, p_ratio = 1 (L = 1, EI = 1, EA = 1e6 EI): true error against the extensible
  elastica of the same EA (references.cantilever_load_shooting, Taylor shooting; independent of
  femslide).  err_M = relative error of M_max; err_state = largest tip error (|du|, |dv| in units of
  L, |dtheta|/theta: cantilever_convergence.tip_error).
* beam-slider at EI = 1e2, 1e6, 1e10 N m^2 (default EA = 1e6 EI): true error against the elastica
  reference references.solve_structure("slider", EI, EA_ratio=1e6).  err_M = relative error of M_max,
  err_state = relative error of phi.
* femslide's own ``error_estimate`` (estimated relative error of M_max) beside the true error.
* wall time per solve: best of 3 in-process ``femslide.solve`` calls (a fixed-N solve also solves
  N/2 for its error estimate, and meshes finer than 16 climb from coarser levels: all included).
* baselines: OpenSees (openseespy, if importable) on the cantilever, the same N-element corotational
  mesh in one load step (bench_statics.opensees_cantilever: its time excludes model building);
  scipy: the independent elastica reference itself (Taylor shooting + scipy.optimize.root) timed per
  solve with its EI-continuation path already cached (its first call at a geometry builds the path:
  ~2 s, reported separately in the .md).

Dynamics:
* ex. 1-3 of paper 003 (one-mass friction oscillator): bench_dynamics.main() is run as is (femslide
  exact vs scipy solve_ivp event switching vs the paper's recurrence; errors against the exact
  decrement formula / femslide's validated exact solution), with its output directed to a temporary
  directory, and its rows are copied here.
* beam-oscillation (FE section 5.2; default scene, t_end = 3 s): the scene runs on the FE transient
  (Radau IIA, femslide.analysis.transient) at its parameter ``tolerance``; this script runs it at
  tolerance 1e-3 .. 1e-9 and compares the turning points (phi [rad], times [s]) and F2_max with the
  reduced 1-DOF model (validation/reduced_dynamics.py: DOP853 at rtol 1e-11 on the massless rod's
  statics, energy balance ~1e-11 - an independent formulation of the same structure on the same
  8-element rod): err_state = largest |dphi| over the turning points (a missed/extra turning point
  counts as the full amplitude), err_M = relative error of F2_max; the energy balance is reported
  beside them.  The reduced model's own run is a row of its own (its time measured in the same run).
"""
from __future__ import annotations

import csv
import os
import pathlib
import sys
import tempfile
import time

HERE = pathlib.Path(__file__).resolve().parent
for _p in (str(HERE.parent), str(HERE)):
    if _p not in sys.path:
        sys.path.insert(0, _p)

os.environ.setdefault("FEMSLIDE_QUIET", "1")

import references as ref  # noqa: E402
from cantilever_convergence import tip_error  # noqa: E402

import femslide  # noqa: E402

NS = [2 ** k for k in range(11)]
EIS = [1e2, 1e6, 1e10]
REPEATS = 3
FIELDS = ["part", "problem", "method", "setting", "n_elements", "value", "err_M", "err_state",
          "error_estimate", "iterations", "time_s", "note"]


def best_of(fn, repeats=REPEATS):
    """(best time [s], result) of ``repeats`` calls: bench_dynamics.best_time."""
    from bench_dynamics import best_time
    return best_time(fn, repeats)


# -- statics -----------------------------------------------------------------------------------------

def statics_rows():
    rows, notes = [], []
    # cantilever-load p_ratio = 1
    exact = ref.cantilever_load_shooting(1.0, EA=1e6)
    femslide.solve("cantilever-load", p_ratio=1.0, n_elements=2)  # warm-up (imports)
    for n in NS + [None]:
        kw = {} if n is None else {"n_elements": n}
        dt, r = best_of(lambda: femslide.solve("cantilever-load", p_ratio=1.0, **kw))
        rows.append(dict(part="statics", problem="cantilever-load p=1", method="femslide",
                         setting="adaptive" if n is None else f"N={n}",
                         n_elements=r.solution.level.model.elements.size // len(r.solution.model.structure.rods),
                         value=r["M_max"],
                         err_M=abs(r["M_max"] - exact["M_max"]) / exact["M_max"],
                         err_state=tip_error(r["tip"], exact), error_estimate=r["error_estimate"],
                         iterations=r["iterations"], time_s=dt))
    t_ref, _ = best_of(lambda: ref.cantilever_load_shooting(1.0, EA=1e6))
    rows.append(dict(part="statics", problem="cantilever-load p=1", method="scipy-elastica",
                     setting="reference", time_s=t_ref, err_M=0.0, err_state=0.0,
                     note="the reference itself (Taylor shooting + brentq)"))
    try:
        import openseespy.opensees  # noqa: F401
        from bench_statics import opensees_cantilever
        have_ops = True
    except Exception as exc:  # ImportError, or the shared library failing to load
        have_ops = False
        notes.append(f"openseespy not available ({type(exc).__name__}): no OpenSees rows")
    if have_ops:
        for n in NS:
            best = None
            for _ in range(REPEATS):
                ok, dt, its, disp = opensees_cantilever(n)
                best = dt if best is None else min(best, dt)
            tip = {"u": disp[0], "v": disp[1], "theta": disp[2]}
            rows.append(dict(part="statics", problem="cantilever-load p=1", method="opensees",
                             setting=f"N={n}", n_elements=n, err_state=tip_error(tip, exact) if ok == 0
                             else "", iterations=its, time_s=best,
                             note="" if ok == 0 else f"analyze status {ok}"))
    # beam-slider at three EI
    for EI in EIS:
        t0 = time.perf_counter()
        r0 = ref.solve_structure("slider", EI, EA_ratio=1e6)
        t_first = time.perf_counter() - t0
        t_ref, r0 = best_of(lambda: ref.solve_structure("slider", EI, EA_ratio=1e6))
        prob = f"beam-slider EI={EI:.0e}"
        rows.append(dict(part="statics", problem=prob, method="scipy-elastica", setting="reference",
                         value=r0["M_max"], err_M=0.0, err_state=0.0, time_s=t_ref,
                         note=f"first call (builds the EI path) {t_first:.2f} s"))
        for n in NS + [None]:
            kw = {} if n is None else {"n_elements": n}
            try:
                dt, r = best_of(lambda: femslide.solve("beam-slider", EI=EI, **kw))
            except femslide.SolverFailure as exc:
                rows.append(dict(part="statics", problem=prob, method="femslide",
                                 setting="adaptive" if n is None else f"N={n}", n_elements=n,
                                 note=f"failed: {exc}"))
                continue
            rows.append(dict(part="statics", problem=prob, method="femslide",
                             setting="adaptive" if n is None else f"N={n}",
                             n_elements=r.solution.level.model.elements.size // len(r.solution.model.structure.rods),
                             value=r["M_max"],
                             err_M=abs(r["M_max"] - r0["M_max"]) / r0["M_max"],
                             err_state=abs(r["phi"] - r0["phi"]) / abs(r0["phi"]),
                             error_estimate=r["error_estimate"], iterations=r["iterations"], time_s=dt))
    return rows, notes


# -- dynamics ----------------------------------------------------------------------------------------

def sdof_rows():
    """bench_dynamics.main() as is, its files redirected to a temporary directory."""
    import bench_dynamics
    with tempfile.TemporaryDirectory() as tmp:
        bench_dynamics.HERE = pathlib.Path(tmp)
        bench_dynamics.main()
        with open(pathlib.Path(tmp) / "dynamics_work_precision.csv") as fh:
            data = list(csv.DictReader(fh))
    return [dict(part="dynamics", problem=f"sdof {d['example']}", method=d["method"], setting=d["setting"],
                 err_state=float(d["error_m"]), time_s=float(d["time_s"]),
                 note="err_state: largest turning-point error [m]") for d in data]


def _tp_error(got, ref_tp, amp):
    n = min(len(got), len(ref_tp))
    err = max((abs(got[i]["w"] - ref_tp[i]["w"]) for i in range(n)), default=0.0)
    terr = max((abs(got[i]["t"] - ref_tp[i]["t"]) for i in range(n)), default=0.0)
    if len(got) != len(ref_tp):
        err = max(err, amp)
    return err, terr


def oscillation_rows():
    """beam-oscillation on the FE transient per tolerance against the reduced model (see the docstring)."""
    from reduced_dynamics import run_oscillation

    from femslide.scenes.catalog import get
    rows, notes = [], []
    t0 = time.perf_counter()
    refr = run_oscillation(get("beam-oscillation").resolve({}))
    rows.append(dict(part="dynamics", problem="beam-oscillation (default, t_end 3 s)",
                     method="reduced 1-DOF DOP853", setting="rtol=1e-11 (reference)", n_elements=refr["n_elements"],
                     value=refr["F2_max"], err_state=0.0, err_M=0.0, error_estimate="",
                     iterations=refr["rhs_evaluations"], time_s=time.perf_counter() - t0,
                     note=f"validation/reduced_dynamics.py; energy_balance {refr['energy_balance']:.1e}"))
    amp = max(abs(p["w"]) for p in refr["turning_points"])
    for tol in (1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9):
        t0 = time.perf_counter()
        r = femslide.simulate("beam-oscillation", tolerance=tol)
        dt = time.perf_counter() - t0
        e, te = _tp_error(r["turning_points"], refr["turning_points"], amp)
        rows.append(dict(part="dynamics", problem="beam-oscillation (default, t_end 3 s)",
                         method="femslide FE Radau IIA",
                         setting=f"tolerance={tol:g}" + (" (default)" if tol == 1e-6 else ""),
                         n_elements=r["n_elements"], value=r["F2_max"], err_state=e,
                         err_M=abs(r["F2_max"] - refr["F2_max"]) / refr["F2_max"],
                         error_estimate="", iterations=r["steps"], time_s=dt,
                         note=f"vs the reduced model; turning-time error {te:.1e} s; energy_balance "
                              f"{r['energy_balance']:.1e}; err_M: F2_max relative; iterations: steps"))
    return rows, notes


# -- output ------------------------------------------------------------------------------------------

def _f(x, fmt="{:.2e}"):
    if x is None or x == "":
        return "-"
    if isinstance(x, float):
        return fmt.format(x)
    return str(x)


def write_md(rows, notes, path, t_total):
    L = ["# Work-precision: error against run time",
         "",
         "Generated by `python validation/work_precision.py` (this file, `work_precision.csv`, "
         "`work_precision_statics.png`, `work_precision_dynamics.png`); see the script's docstring for "
         "the definitions.  Times are wall-clock seconds on the machine that ran it (2 cores), best of "
         f"{REPEATS} in-process runs for the statics; the whole script took {t_total:.0f} s.",
         "",
         "* `err_M`: relative error of M_max (statics) or of F2_max (beam-oscillation).",
         "* `err_state`: cantilever - largest tip error (|du|, |dv| / L, |dtheta| / theta); beam-slider -"
         " relative error of phi; dynamics - largest turning-point error (m for sdof, rad for "
         "beam-oscillation).",
         "* `estimate`: femslide's `error_estimate` (relative error of M_max; none for N = 1).",
         "* References: cantilever - extensible elastica (Taylor shooting, EA = 1e6 EI); beam-slider - "
         "`references.solve_structure('slider', EI, EA_ratio=1e6)`; sdof - exact decrement formula "
         "(ex. 1, 2) / femslide's exact solution validated to 1e-13 m (ex. 3); beam-oscillation - "
         "the reduced 1-DOF model (validation/reduced_dynamics.py, DOP853 at rtol 1e-11).",
         ""]
    groups = []
    for r in rows:
        key = (r["part"], r["problem"])
        if key not in groups:
            groups.append(key)
    for part, prob in groups:
        sel = [r for r in rows if (r["part"], r["problem"]) == (part, prob)]
        L += [f"## {part}: {prob}", "",
              "| method | setting | N | err_M | err_state | estimate | iterations / nfev | time [s] | note |",
              "|---|---|---|---|---|---|---|---|---|"]
        for r in sel:
            L.append(f"| {r['method']} | {r['setting']} | {_f(r.get('n_elements'))} | {_f(r.get('err_M'))} | "
                     f"{_f(r.get('err_state'))} | {_f(r.get('error_estimate'))} | {_f(r.get('iterations'))} | "
                     f"{_f(r.get('time_s'), '{:.4f}')} | {r.get('note', '')} |")
        L.append("")
    if notes:
        L += ["## Notes", ""] + [f"* {n}" for n in notes] + [""]
    L += ["## Highlights", ""] + [f"* {h}" for h in highlights(rows)] + [""]
    pathlib.Path(path).write_text("\n".join(L))


def highlights(rows):
    out = []
    for prob in ["cantilever-load p=1"] + [f"beam-slider EI={EI:.0e}" for EI in EIS]:
        fs = [r for r in rows if r["problem"] == prob and r["method"] == "femslide" and r.get("err_M") != ""
              and r.get("err_M") is not None]
        if not fs:
            continue
        best = min(fs, key=lambda r: r["err_M"])
        ad = [r for r in fs if r["setting"] == "adaptive"]
        s = (f"{prob}: best fixed/adaptive M_max error {best['err_M']:.1e} ({best['setting']}, "
             f"{best['time_s'] * 1e3:.1f} ms)")
        if ad:
            a = ad[0]
            s += (f"; adaptive run: error {a['err_M']:.1e}, estimate {_f(a['error_estimate'])}, "
                  f"N = {a['n_elements']}, {a['time_s'] * 1e3:.1f} ms")
        worst_ratio = [r["error_estimate"] / r["err_M"] for r in fs
                       if isinstance(r.get("error_estimate"), float) and r["err_M"] > 1e-11]
        if worst_ratio:
            s += (f"; estimate/true over N >= 2 (true > 1e-11): {min(worst_ratio):.2g} .. "
                  f"{max(worst_ratio):.2g}")
        out.append(s)
    ops = [r for r in rows if r["method"] == "opensees" and r.get("err_state") not in ("", None)]
    if ops:
        o32 = [r for r in ops if r["n_elements"] == 32]
        f32 = [r for r in rows if r["problem"] == "cantilever-load p=1" and r["method"] == "femslide"
               and r["setting"] == "N=32"]
        if o32 and f32:
            out.append(f"cantilever N = 32: femslide tip error {f32[0]['err_state']:.2e} in "
                       f"{f32[0]['time_s'] * 1e3:.1f} ms (incl. N = 16 for the estimate), OpenSees "
                       f"{o32[0]['err_state']:.2e} in {o32[0]['time_s'] * 1e3:.1f} ms (analysis only)")
    return out


def plot(rows):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return []
    files = []
    probs = ["cantilever-load p=1"] + [f"beam-slider EI={EI:.0e}" for EI in EIS]
    fig, axes = plt.subplots(1, 4, figsize=(18, 4.3))
    for ax, prob in zip(axes, probs):
        for method, mk in (("femslide", "o-"), ("opensees", "s-")):
            pts = [(r["time_s"], r["err_state"] if prob.startswith("cantilever") else r["err_M"],
                    r.get("error_estimate")) for r in rows
                   if r["problem"] == prob and r["method"] == method and r["setting"] != "adaptive"
                   and isinstance(r.get("time_s"), float)
                   and isinstance(r["err_state"] if prob.startswith("cantilever") else r.get("err_M"), float)]
            if pts:
                x, y, e = zip(*pts)
                ax.loglog(x, [max(v, 1e-17) for v in y], mk, ms=4,
                          label=f"{method} ({'tip' if prob.startswith('cantilever') else 'M_max'} error)")
                if method == "femslide":
                    xe = [a for a, b in zip(x, e) if isinstance(b, float)]
                    ye = [b for b in e if isinstance(b, float)]
                    ax.loglog(xe, [max(v, 1e-17) for v in ye], "x:", color="gray", label="femslide error_estimate")
        ad = [r for r in rows if r["problem"] == prob and r["setting"] == "adaptive"]
        if ad and isinstance(ad[0].get("err_M"), float):
            y = ad[0]["err_state"] if prob.startswith("cantilever") else ad[0]["err_M"]
            ax.loglog([ad[0]["time_s"]], [max(y, 1e-17)], "*", ms=12, label="femslide adaptive")
        ax.set_title(prob)
        ax.set_xlabel("wall time per solve [s]")
        ax.set_ylabel("true error")
        ax.grid(True, which="both", lw=0.3)
    axes[0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(HERE / "work_precision_statics.png", dpi=100)
    plt.close(fig)
    files.append("work_precision_statics.png")
    dprobs = []
    for r in rows:
        if r["part"] == "dynamics" and r["problem"] not in dprobs:
            dprobs.append(r["problem"])
    fig, axes = plt.subplots(1, len(dprobs), figsize=(4.5 * len(dprobs), 4.2))
    for ax, prob in zip(axes, dprobs):
        methods = []
        for r in rows:
            if r["problem"] == prob and r["method"] not in methods:
                methods.append(r["method"])
        for meth in methods:
            groups = {}
            for r in rows:
                if r["problem"] == prob and r["method"] == meth:
                    kind = r["setting"].split("=")[0]
                    groups.setdefault(kind, []).append((r["time_s"], max(r["err_state"], 1e-17)))
            for kind, pts in groups.items():
                x, y = zip(*pts)
                ax.loglog(x, y, "*" if meth == "femslide" else "o-", ms=10 if meth == "femslide" else 4,
                          label=f"{meth} {kind}" if kind != meth else meth)
        ax.set_title(prob, fontsize=9)
        ax.set_xlabel("wall time [s]")
        ax.set_ylabel("turning-point error")
        ax.grid(True, which="both", lw=0.3)
        ax.legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(HERE / "work_precision_dynamics.png", dpi=100)
    plt.close(fig)
    files.append("work_precision_dynamics.png")
    return files


def main():
    t0 = time.perf_counter()
    rows, notes = statics_rows()
    rows += sdof_rows()
    r2, n2 = oscillation_rows()
    rows += r2
    notes += n2
    with open(HERE / "work_precision.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=FIELDS)
        w.writeheader()
        for r in rows:
            w.writerow({k: r.get(k, "") for k in FIELDS})
    files = plot(rows)
    write_md(rows, notes, HERE / "work_precision.md", time.perf_counter() - t0)
    for h in highlights(rows):
        print(h)
    print(f"wrote work_precision.csv, work_precision.md, {', '.join(files)} in "
          f"{time.perf_counter() - t0:.0f} s")


if __name__ == "__main__":
    main()
