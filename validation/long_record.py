"""Issue 24 acceptance: a 40 s ground record (dt = 0.01 s) on a small frame with a frictional slider at
its base runs to the end with exit 0 at the default tolerance, and ``--max-time 2`` on it stops with
exit 1, the reason named and the history so far written.  Prints a table of the measured figures.

The frame: two columns (EI = 4e6 N m^2, 4 elements each, massless) welded to a base slab (2 t) and a
roof (4 t); the slab on a ground slider with mu = 0.08 and a re-centring spring k = 20 kN/m.  The
record: synthetic (femslide.analysis.excitation.synthetic_record, Kanai-Tajimi filtered noise under
an envelope, seed 1, peak 3 m/s^2).  Run::

    python validation/long_record.py [WORK_FOLDER]

Takes a few minutes (the 40 s run twice: the run and its error estimate's check run).
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time

from femslide.analysis.excitation import synthetic_record, write_csv_record

FRAME = """
gravity = [0.0, -9.81]
description = "one-storey frame on a frictional base slider (issue 24 acceptance)"
[[rod]]
name = "left"
start = [0.0, 0.2]
end = [0.0, 3.0]
EI = 4e6
[[rod]]
name = "right"
start = [4.0, 0.2]
end = [4.0, 3.0]
EI = 4e6
[[body]]
name = "base"
mass = 2000.0
inertia = 3000.0
centroid = [2.0, 0.1]
outline = [[-0.2, 0.0], [4.2, 0.0], [4.2, 0.2], [-0.2, 0.2]]
[[body]]
name = "roof"
mass = 4000.0
inertia = 6000.0
centroid = [2.0, 3.1]
outline = [[-0.2, 3.0], [4.2, 3.0], [4.2, 3.2], [-0.2, 3.2]]
[[joint]]
name = "A"
type = "weld"
a = "left.start"
b = "base"
[[joint]]
name = "B"
type = "weld"
a = "right.start"
b = "base"
[[joint]]
name = "C"
type = "weld"
a = "left.end"
b = "roof"
[[joint]]
name = "D"
type = "weld"
a = "right.end"
b = "roof"
[[joint]]
name = "iso"
type = "slider"
a = "base"
b = "ground"
axis = [1.0, 0.0]
at = [2.0, 0.0]
mu = 0.08
k = 20000.0
[simulate]
t_end = 40.0
elements = 4
ground = {direction = [1.0, 0.0], record = "rec40.csv", scale = 1.0}
"""


def main(work):
    os.makedirs(work, exist_ok=True)
    t, a = synthetic_record(40.0, 0.01, pga=3.0, seed=1)
    write_csv_record(os.path.join(work, "rec40.csv"), t, a)
    f = os.path.join(work, "frame40.toml")
    with open(f, "w") as fh:
        fh.write(FRAME)
    rows = []
    for label, extra in (("to the end", []), ("--max-time 2", ["--max-time", "2"])):
        out = os.path.join(work, "out_" + ("full" if not extra else "limited"))
        t0 = time.perf_counter()
        r = subprocess.run([sys.executable, "-m", "femslide", "simulate", f, "--json", "--quiet", "--out", out,
                            *extra], capture_output=True, text=True)
        wall = time.perf_counter() - t0
        d = json.loads(r.stdout) if r.stdout.strip() else {}
        n_rows = sum(1 for _ in open(os.path.join(out, "history.csv"))) - 1 if os.path.isfile(
            os.path.join(out, "history.csv")) else 0
        rows.append((label, r.returncode, wall, d.get("t_reached", d.get("t_end")), d.get("steps"),
                     sum(len(v) for v in d.get("events", {}).values()), d.get("error_estimate"), n_rows,
                     (d.get("reason") or "")[:90]))
    print(f"{'run':<14} {'exit':>4} {'wall [s]':>9} {'t reached':>9} {'steps':>6} {'events':>6} "
          f"{'error_est':>9} {'rows':>6}  reason")
    for lab, code, wall, tr, steps, nev, est, n, why in rows:
        print(f"{lab:<14} {code:>4} {wall:>9.1f} {tr if tr is not None else float('nan'):>9.4g} "
              f"{steps if steps is not None else '-':>6} {nev:>6} {est if est is not None else float('nan'):>9.2g} "
              f"{n:>6}  {why}")
    return rows


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else tempfile.mkdtemp(prefix="femslide-long-record-"))
