"""femslide's base-isolated frame (meshes/structures/base-isolated-frame.toml, 20 s synthetic record)
against its nonlinear reference (issue 22): validation/nonlinear_frames.py through
dynamic_cases.base_isolated_frame_nonlinear - the same corotational model solved independently
(bodies with massless columns condensed by an inner Newton, friction events located by solve_ivp on
DOP853's dense output; numpy and scipy only).

* ``reference``: the reference's own accuracy and cost: runs at two rtols (default 1e-10 and 1e-12),
  their histories' largest difference relative to each history's largest |value| on a 1 ms grid, the
  event times' largest difference, the energy balance (Run.energy_balance), CPU time, steps;
* ``linear``: the nonlinear reference against the linear event-driven one
  (dynamic_cases.base_isolated_frame: the frame linearised about its static state, exact by matrix
  exponentials) at record scales 0.01 (no slip), 0.25, 1: their difference is the linearisation's,
  of first order in the amplitude relative to the motion;
* ``femslide`` (default): femslide at tolerances 1e-3 .. 1e-6 (``--tols``) and record scales
  (``--scales``): its histories joints.iso.slide, bodies.deck.x, rods.colL.M_max, rods.colR.M_max
  (the error: largest |femslide - reference| at femslide's history times over the history's
  largest |reference value|), its events (kinds equal, largest time difference), its
  error_estimate, wall time.  ``--h-cap S``: an experiment, femslide's largest step capped at S
  [s] (its integrate wrapped; femslide unchanged): with S = 2.5e-4 s its steps follow the deck's
  vertical and rocking vibration (108.7, 188.0 Hz) that the friction events excite and that
  carries up to ~37 N of the normal force, which its own steps (3 ms at 1e-6) do not.

Prints tables, writes validation/nonlinear_frame_accuracy.csv for ``femslide`` (the committed one: scales
0.25, 1, 2, and two rows with --h-cap 2.5e-4, column h_cap_s).  Times are of one run
on this (shared) machine.
The committed csv: scales 0.25, 1, 2 at 1e-3 .. 1e-7 with the steps' watch of vibrating modes, by their
displacement (transient._mode_steps) and by their share of the friction forces (transient._mode_grip);
before the watches (the two h_cap rows are from then) scale 1 was 13.8 and 128 x the tolerance off at
1e-6 and 1e-7, scale 2 27.7 at 1e-6.
Run:  python validation/bench_nonlinear_frame.py [femslide|reference|linear] [--t-end 20]
      [--scales 1,0.25,2] [--tols 1e-3,1e-4,1e-5,1e-6] [--ref-rtol 1e-10] [--no-estimate] [--cache DIR] [--h-cap S]
"""
from __future__ import annotations

import argparse
import csv
import math
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import dynamic_cases  # noqa: E402

COLS = ("joints.iso.slide", "bodies.deck.x", "rods.colL.M_max", "rods.colR.M_max")


CACHE = None      # a directory where the reference runs are pickled (--cache)


def reference(scale=1.0, t_end=20.0, rtol=1e-10):
    """The nonlinear reference at the record's ``scale`` over [0, t_end]; atol = rtol 1e-2 scale
    [m, rad, m/s] (the motion scales with the record).  Returns (Reference, CPU seconds)."""
    import pickle
    f = None if CACHE is None else os.path.join(CACHE, f"nonlinear_frame_{scale:g}_{t_end:g}_{rtol:g}.pkl")
    if f and os.path.exists(f):
        with open(f, "rb") as fh:
            run, cpu = pickle.load(fh)
        path = dynamic_cases.read("base-isolated-frame.toml")[0]
        ref = dynamic_cases.Reference("base-isolated-frame (nonlinear)", path, t_end,
                                      dynamic_cases.nonlinear_histories(run.frames, run), {}, np.array([]),
                                      float("nan"), {"bodies.deck.x": 2.5}, events=run.events,
                                      extra={"frames": run.frames, "run": run})
        return ref, cpu
    t0 = time.process_time()
    ref = dynamic_cases.base_isolated_frame_nonlinear(t_end=t_end, rtol=rtol, atol=1e-2 * rtol * scale,
                                                      peaks=False, scale=scale)
    cpu = time.process_time() - t0
    if f:
        with open(f, "wb") as fh:
            pickle.dump((ref.extra["run"], cpu), fh)
    return ref, cpu


def event_errors(got, ref):
    """(kinds equal, largest |time difference| [s] or None, counts (got, want))."""
    want = dynamic_cases.without_zero_duration_pairs(ref.events)
    same = [k for _, k in got] == [k for _, k in want]
    dt = max(abs(a[0] - b[0]) for a, b in zip(got, want)) if same else None
    return same, dt, (len(got), len(want))


def cap_steps(h_cap):
    """An experiment, femslide unchanged: its time integration (femslide.analysis.transient.integrate,
    looked up at each run) wrapped so that its largest step is at most h_cap [s]."""
    import femslide.analysis.transient as tr
    orig = getattr(tr.integrate, "wrapped", tr.integrate)

    def capped(*args, **kw):
        kw["h_max"] = min(kw.get("h_max") or math.inf, h_cap)
        return orig(*args, **kw)
    capped.wrapped = orig
    tr.integrate = capped if h_cap else orig


def femslide_run(ref, tol, scale, estimate=True):
    """femslide.simulate of the reference's file at ``tol`` and ``scale`` over the reference's
    t_end; returns (result, wall seconds)."""
    import femslide
    t0 = time.perf_counter()
    res = femslide.simulate(ref.path, **{"simulate.tolerance": tol, "simulate.error_estimate": estimate,
                                         "simulate.ground.scale": scale, "simulate.t_end": ref.t_end,
                                         "simulate.max_time": 1200.0})
    return res, time.perf_counter() - t0


def compare(res, ref):
    """Row of the femslide table: history errors, events, estimate."""
    err = dynamic_cases.history_errors(res.history, ref, COLS)
    got = [(e["t"], e["kind"]) for evs in res["events"].values() for e in evs]
    got.sort()
    same, dt, (ng, nw) = event_errors(got, ref)
    return {"events": ng, "ref_events": nw, "events_agree": same, "event_dt_s": dt, **err,
            "worst": max(err.values()), "error_estimate": res.get("error_estimate"), "steps": res["steps"],
            "converged": res["converged"]}


def main_femslide(a):
    rows = []
    for scale in a.scales:
        ref, cpu = reference(scale, a.t_end, a.ref_rtol)
        print(f"reference scale {scale:g}: {len(ref.events)} events, CPU {cpu:.0f} s", flush=True)
        for tol in a.tols:
            try:
                res, wall = femslide_run(ref, tol, scale, not a.no_estimate)
            except Exception as exc:       # a failed run is a row of the table
                print(f"{scale:<5g}  {tol:<6.0e}  failed: {str(exc).splitlines()[0]}", flush=True)
                continue
            row = {"scale": scale, "tolerance": tol, **compare(res, ref), "wall_s": wall, "h_cap_s": a.h_cap}
            rows.append(row)
            print(fmt(row), flush=True)
    keys = list(rows[0])
    with open(os.path.join(HERE, "nonlinear_frame_accuracy.csv") if a.csv is None else a.csv, "w", newline="") as f:
        w = csv.DictWriter(f, keys)
        w.writeheader()
        w.writerows(rows)
    print("\nscale  tol     events(ref)  agree  max|dt| s   slide     deck x    colL Mmax colR Mmax  worst/tol "
          "estimate  wall s")
    for r in rows:
        print(fmt(r))


def fmt(r):
    dt = f"{r['event_dt_s']:.1e}" if r["event_dt_s"] is not None else "   -   "
    est = f"{r['error_estimate']:.1e}" if r["error_estimate"] is not None else "   -   "
    return (f"{r['scale']:<5g}  {r['tolerance']:<6.0e}  {r['events']:>4d} ({r['ref_events']:>3d})   "
            f"{'yes' if r['events_agree'] else 'NO ':3s}   {dt:>9s}  " + "  ".join(f"{r[c]:.1e}" for c in COLS)
            + f"  {r['worst'] / r['tolerance']:8.2f}  {est:>8s}  {r['wall_s']:6.1f}")


def main_reference(a):
    runs = []
    for rtol in a.ref_rtols:
        ref, cpu = reference(a.scales[0], a.t_end, rtol)
        run = ref.extra["run"]
        t = np.unique(np.concatenate([np.linspace(0.0, a.t_end, int(round(a.t_end * 1000)) + 1),
                                      [e for e, _ in run.events]]))
        eb = float(np.abs(run.energy_balance(t)).max())
        runs.append((rtol, ref, cpu, run, eb))
        print(f"rtol {rtol:g}: CPU {cpu:.0f} s, steps {run.steps}, f evaluations {run.nfev}, "
              f"{len(run.events)} events, energy balance {eb:.1e}", flush=True)
    (r1, ref1, *_), (r2, ref2, *_) = runs[0], runs[-1]
    t = np.linspace(0.0, a.t_end, int(round(a.t_end * 1000)) + 1)
    print(f"rtol {r1:g} against {r2:g} (largest difference / largest |value|, 1 ms grid):")
    for c in COLS:
        x1, x2 = ref1.histories[c](t), ref2.histories[c](t)
        print(f"  {c:18s} {np.abs(x1 - x2).max() / np.abs(x2).max():.1e}   (largest |value| {np.abs(x2).max():.4g})")
    same = [k for _, k in ref1.events] == [k for _, k in ref2.events]
    dt = max(abs(x[0] - y[0]) for x, y in zip(ref1.events, ref2.events)) if same else None
    print(f"  events: kinds {'equal' if same else 'DIFFERENT'}, largest time difference {dt} s")


def main_linear(a):
    print("scale  events lin/nonlin  max|dt| s   slide     deck x    colL Mmax colR Mmax  (relative differences)")
    for scale in a.scales:
        lin = dynamic_cases.base_isolated_frame(scale=scale, t_end=a.t_end)
        non, _ = reference(scale, a.t_end, a.ref_rtol)
        t = np.linspace(0.0, a.t_end, int(round(a.t_end * 1000)) + 1)
        d = {}
        for c in COLS:
            xl, xn = lin.histories[c](t), non.histories[c](t)
            d[c] = np.abs(xl - xn).max() / np.abs(xn).max() if np.abs(xn).max() > 0 else float("nan")
        el, en = dynamic_cases.without_zero_duration_pairs(lin.events), non.events
        same = [k for _, k in el] == [k for _, k in en]
        dt = f"{max(abs(x[0] - y[0]) for x, y in zip(el, en)):.1e}" if same and len(el) > 1 else "   -   "
        print(f"{scale:<5g}  {len(el):>4d} / {len(en):<4d}{'' if same else ' (differ)':9s}  {dt:>9s}  "
              + "  ".join(f"{d[c]:.1e}" for c in COLS), flush=True)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("what", nargs="?", default="femslide", choices=("femslide", "reference", "linear"))
    p.add_argument("--t-end", type=float, default=20.0)
    p.add_argument("--scales", default=None)
    p.add_argument("--tols", default="1e-3,1e-4,1e-5,1e-6")
    p.add_argument("--ref-rtol", type=float, default=1e-10)
    p.add_argument("--ref-rtols", default="1e-10,1e-12")
    p.add_argument("--no-estimate", action="store_true")
    p.add_argument("--csv", default=None)
    p.add_argument("--cache", default=None, help="a directory to keep the reference runs in (pickles)")
    p.add_argument("--h-cap", type=float, default=0.0,
                   help="experiment: femslide's largest step capped at this [s] (femslide unchanged)")
    a = p.parse_args(argv)
    if a.h_cap:
        cap_steps(a.h_cap)
    global CACHE
    CACHE = a.cache
    default_scales = {"femslide": "1", "reference": "1", "linear": "0.01,0.25,1"}[a.what]
    a.scales = [float(x) for x in (a.scales or default_scales).split(",")]
    a.tols = [float(x) for x in a.tols.split(",")]
    a.ref_rtols = [float(x) for x in a.ref_rtols.split(",")]
    {"femslide": main_femslide, "reference": main_reference, "linear": main_linear}[a.what](a)


if __name__ == "__main__":
    main()
