"""Work-precision benchmark of the one-mass friction oscillator (paper 003, ex. 1-3).  Not a test.

    python validation/bench_dynamics.py [--quick]

Methods (all in-process, best of several repeats, wall-clock seconds):
* femslide   - femslide.scenes.sdof.run (exact closed form + events; includes energy balance and summary);
* RK45/DOP853 - scipy solve_ivp with event switching (validation/sdof_reference.ivp_simulate) at
  rtol = 1e-3 .. 1e-12 (atol = 1e-3 rtol m);
* recurrence - the paper's first-order recurrence (7)-(9), Newmark average acceleration, friction
  lagging one step, with a stick rule, at tau = 1e-2 .. 1e-5 s.
Errors [m]:
* ex. 1, 2: the largest error of the turning points and the stop against the exact decrement formula
  (for the recurrence: the extreme w next to each velocity sign change, and the final position);
* ex. 3 (theta = 0.5 omega, 30 s from rest): the largest turning-point error against scipy's DOP853
  with event switching at rtol 1e-12, atol 1e-15 m (independent of femslide; it agrees with femslide
  to ~1e-13 m, validation/test_friction_oscillator.py); for the recurrence the error of the last
  forcing period's amplitude against the same reference.
A missed or extra turning point counts as an error of the full amplitude.
Writes validation/dynamics_work_precision.csv and .png and prints the time ratios femslide/scipy
at the scipy run that first reaches 1e-6 m.
"""
from __future__ import annotations

import csv
import math
import pathlib
import sys
import time

HERE = pathlib.Path(__file__).resolve().parent
for p in (str(HERE.parent), str(HERE)):
    if p not in sys.path:
        sys.path.insert(0, p)

import sdof_reference as ref  # noqa: E402

from femslide.scenes import sdof  # noqa: E402
from femslide.scenes.catalog import get  # noqa: E402

QUICK = "--quick" in sys.argv

EXAMPLES = {
    "ex1": dict(scene="sdof-free", m=1.0, k=200.0, mu=0.2, mu0=0.24, g=9.81, w0=0.07, A=0.0, r=0.0,
                t_end=2.0),
    "ex2": dict(scene="sdof-decay", m=20 / 9.81, k=1000.0, mu=0.15, mu0=0.18, g=9.81, w0=0.08, A=0.0,
                r=0.0, t_end=3.0),
    "ex3": dict(scene="sdof-harmonic", m=20 / 9.81, k=1000.0, mu=0.15, mu0=0.18, g=9.81, w0=0.0,
                A=10.0, r=0.5, t_end=30.0),
}


def best_time(fn, repeats):
    best, out = math.inf, None
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def tp_error(got, exact, amp):
    """Largest |w| error over matched turning points; a count mismatch costs the full amplitude."""
    n = min(len(got), len(exact))
    err = max((abs(got[i][1] - exact[i][1]) for i in range(n)), default=0.0)
    if len(got) != len(exact):
        err = max(err, amp)
    return err


def recurrence_turning(t, w, v):
    """Turning points of a stepped history: the extreme w next to each sign change / stop of v."""
    out = []
    moving = v != 0
    for i in range(1, len(v)):
        if moving[i - 1] and (v[i] == 0 or v[i] * v[i - 1] < 0):
            j = i if abs(w[i]) >= abs(w[i - 1]) else i - 1
            out.append((t[j], w[j]))
    return out


def main():
    rows = []
    ratios = {}
    for name, ex in EXAMPLES.items():
        m, k, mu, mu0, g, w0, A, r, t_end = (ex[x] for x in ("m", "k", "mu", "mu0", "g", "w0", "A", "r",
                                                           "t_end"))
        omega = math.sqrt(k / m)
        theta = r * omega
        values = get(ex["scene"]).resolve({"theta_ratio": r} if r else {})
        # exact reference
        if A == 0.0:
            exact = ref.decrement_turning_points(w0, k, m, mu, mu0, m * g)
            ref_amp = None
        else:
            # independent reference: scipy's DOP853 with event switching at rtol 1e-12
            iv_ref = ref.ivp_simulate(m, k, 0.0, mu, mu0, g, w0, A=A, theta=theta, t_end=t_end,
                                      method="DOP853", rtol=1e-12, atol=1e-15)
            exact = list(iv_ref.turning)
            amps, _, _ = ref.period_amplitudes(exact, lambda t: ref.ivp_eval(iv_ref, t), theta, t_end)
            ref_amp = float(amps[-1])
        amp = max(abs(w) for _, w in exact)
        # femslide
        tf, res = best_time(lambda: sdof.run(values), 5 if QUICK else 30)
        got = [(p["t"], p["w"]) for p in res["turning_points"]]
        err = tp_error(got, exact, amp)
        rows.append((name, "femslide", "exact", max(err, 1e-17), tf))
        # scipy
        rtols = [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12]
        if QUICK:
            rtols = rtols[::3]
        for method in ("RK45", "DOP853"):
            for rtol in rtols:
                if method == "RK45" and rtol < 1e-10:
                    continue

                def go():
                    return ref.ivp_simulate(m, k, 0.0, mu, mu0, g, w0, A=A, theta=theta, t_end=t_end,
                                            method=method, rtol=rtol, atol=rtol * 1e-3, dense=False)
                ts, iv = best_time(go, 2 if QUICK else 3)
                rows.append((name, method, f"rtol={rtol:g}", tp_error(iv.turning, exact, amp), ts))
        # the paper's recurrence
        taus = [1e-2, 3e-3, 1e-3, 3e-4, 1e-4] + ([] if name == "ex3" else [3e-5, 1e-5])
        if QUICK:
            taus = taus[::2]
        for tau in taus:
            tr, (t, w, v) = best_time(lambda: ref.paper_recurrence(m, k, 0.0, mu, mu0, g, w0, A=A,
                                                                   theta=theta, t_end=t_end, tau=tau), 1)
            if A == 0.0:
                got = recurrence_turning(t, w, v)
                err = tp_error(got, exact, amp)
                err = max(err, abs(w[-1] - exact[-1][1]))
            else:
                Tf = 2 * math.pi / theta
                sel = t >= t[-1] - Tf
                amp_rec = 0.5 * (w[sel].max() - w[sel].min())
                err = abs(amp_rec - ref_amp)
            rows.append((name, "recurrence", f"tau={tau:g}", err, tr))
        # ratio femslide / first scipy run reaching 1e-6 m
        sc = [rw for rw in rows if rw[0] == name and rw[1] in ("RK45", "DOP853") and rw[3] <= 1e-6]
        if sc:
            cheapest = min(sc, key=lambda rw: rw[4])
            ratios[name] = (tf, cheapest)
    # output
    out_csv = HERE / "dynamics_work_precision.csv"
    with open(out_csv, "w", newline="") as fh:
        wr = csv.writer(fh)
        wr.writerow(["example", "method", "setting", "error_m", "time_s"])
        wr.writerows(rows)
    print(f"{'ex':<4} {'method':<11} {'setting':<12} {'error [m]':>11} {'time [ms]':>10}")
    for rw in rows:
        print(f"{rw[0]:<4} {rw[1]:<11} {rw[2]:<12} {rw[3]:>11.3e} {rw[4] * 1e3:>10.3f}")
    print()
    for name, (tf, sc) in ratios.items():
        err = min(r[3] for r in rows if r[0] == name and r[1] == 'femslide')
        print(f"{name}: femslide {tf * 1e3:.3f} ms (error <= {err:.1e} m)"
              f" vs cheapest scipy reaching 1e-6 m: {sc[1]} {sc[2]} {sc[4] * 1e3:.2f} ms "
              f"(error {sc[3]:.1e} m) -> ratio femslide/scipy = {tf / sc[4]:.4f}")
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, axes = plt.subplots(1, 3, figsize=(14, 4.2))
        for ax, name in zip(axes, EXAMPLES):
            for method, mk in (("femslide", "*"), ("RK45", "o-"), ("DOP853", "s-"), ("recurrence", "^-")):
                pts = [(rw[4], rw[3]) for rw in rows if rw[0] == name and rw[1] == method]
                if pts:
                    x, y = zip(*pts)
                    ax.loglog(x, y, mk, label=method, ms=10 if method == "femslide" else 5)
            ax.axhline(1e-6, color="gray", lw=0.6, ls=":")
            ax.set_title(name)
            ax.set_xlabel("in-process time [s]")
            ax.set_ylabel("error [m]")
            ax.grid(True, which="both", lw=0.3)
        axes[0].legend()
        fig.tight_layout()
        fig.savefig(HERE / "dynamics_work_precision.png", dpi=110)
        print(f"wrote {out_csv.name} and dynamics_work_precision.png")
    except ImportError:
        print(f"wrote {out_csv.name} (matplotlib missing: no plot)")


if __name__ == "__main__":
    main()
