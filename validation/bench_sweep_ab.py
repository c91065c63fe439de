"""A/B benchmark of the in-process EI sweep against another femslide tree (a script, not a test).

    git worktree add --detach /tmp/femslide-old fabcda3      # e.g. the code before the model layer
    python validation/bench_sweep_ab.py /tmp/femslide-old [ROUNDS]

The 9-value EI sweep of beam-slider (1e2 .. 1e10, each case from scratch as `femslide sweep` solves
it), timed in CPU seconds (time.process_time: other processes on a busy machine matter less) in fresh
processes, alternating the two trees, ROUNDS times (default 3):

- cold: one sweep in a fresh process, after a warm-up solve of another scene (imports and first
  calls), so that the sweep builds its own Jacobian patterns - what a user's sweep costs;
- warm: best of 6 sweeps in one process with the patterns kept between them (the old code kept
  them in module-level caches; the current one in the PatternCache the caller owns, here one for
  all six).

Prints both times per round and the ratios this/other.
"""
from __future__ import annotations

import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)

CHILD = r"""
import sys, os, time, math
tree, mode = sys.argv[1], sys.argv[2]
sys.path.insert(0, tree); os.chdir(tree)
from femslide.scenes.catalog import SCENES
try:
    from femslide.scenes.paper import solve_scene
    from femslide.model.patterns import PatternCache
    new = True
except ImportError:
    from femslide.statics import solve_scene
    new = False
solve_scene("beam-fixed", SCENES["beam-fixed"].resolve({"EI": 1e5}))   # warm-up: another topology
cache = PatternCache() if new else None
best = math.inf
for rep in range(1 if mode == "cold" else 6):
    t0 = time.process_time()
    for k in range(2, 11):
        v = SCENES["beam-slider"].resolve({"EI": 10.0 ** k})
        solve_scene("beam-slider", v, cache=cache) if new else solve_scene("beam-slider", v)
    best = min(best, time.process_time() - t0)
print(best)
"""


def run(tree, mode):
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    p = subprocess.run([sys.executable, "-c", CHILD, tree, mode], capture_output=True, text=True, env=env)
    if p.returncode:
        raise SystemExit(f"{tree} ({mode}) failed: {p.stderr.strip()[-500:]}")
    return float(p.stdout.split()[-1])


def main(argv):
    if not argv:
        raise SystemExit(__doc__)
    other = os.path.abspath(argv[0])
    rounds = int(argv[1]) if len(argv) > 1 else 3
    print(f"beam-slider EI sweep (9 cases), CPU ms: this tree {ROOT} vs {other}")
    for r in range(rounds):
        row = []
        for mode in ("cold", "warm"):
            a, b = run(other, mode), run(ROOT, mode)
            row.append(f"{mode}: other {a * 1e3:6.1f}  this {b * 1e3:6.1f}  ratio {b / a:5.2f}")
        print(f"round {r + 1}:  " + "   ".join(row))


if __name__ == "__main__":
    main(sys.argv[1:])
