"""Cost of friction in statics: a load history with a frictional bearing against the same history
without friction and against one solve per step (measured in one run, same machine).

The structure is examples/thermal_friction_deck.py's deck on two columns (9 steps: two summer-winter
cycles) in first-order and exact theory.  Prints a table: wall time, Newton iterations, friction
events, and the time per step; the ratios are of one run (the machine is shared: compare ratios, not
seconds).

    python validation/bench_history.py
"""
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "examples"))

import femslide  # noqa: E402
import thermal_friction_deck as ex  # noqa: E402


def main():
    rows = []
    for theory in ("linear", "nonlinear"):
        base = None
        for case in ("free", "friction"):
            s = ex.deck(case)
            t = time.perf_counter()
            r = femslide.solve(s, theory=theory)
            dt = time.perf_counter() - t
            base = base or dt
            rows.append((theory, case, dt, r["iterations"], len(r["events"]), dt / len(r["steps"]), dt / base,
                         r["error_estimate"]))
        # one plain solve per step's load state (no history): the cost floor
        s = ex.deck("free")
        s.steps = []
        s.set("temperature.dT", 25.0)       # the summer state as a plain load of case "dead"
        s.set("temperature.case", "dead")
        t = time.perf_counter()
        for _ in ex.TEMPS:
            femslide.solve(s, theory=theory, elements=16)
        dt = time.perf_counter() - t
        rows.append((theory, "9 plain solves", dt, 0, 0, dt / len(ex.TEMPS), dt / base, float("nan")))
    print(f"{'theory':10s} {'case':16s} {'wall [s]':>9s} {'Newton its':>10s} {'events':>6s} {'s/step':>8s} "
          f"{'x free':>7s} {'estimate':>9s}")
    for th, case, dt, its, ev, per, ratio, est in rows:
        print(f"{th:10s} {case:16s} {dt:9.3f} {its:10d} {ev:6d} {per:8.3f} {ratio:7.2f} {est:9.2e}")


if __name__ == "__main__":
    main()
