"""Whole-process wall time of ``femslide solve hinge-slider --json`` (best of N), printed, not tested.

    cd /work/main && /work/venv/bin/python validation/bench_cli.py [N] [SCENE ...]

Runs ``python -m femslide solve SCENE --json`` as a fresh process N times (default 10) and prints
the best and median wall times, plus the bare interpreter start-up (``python -c pass``) for scale.
"""
from __future__ import annotations

import json
import os
import pathlib
import statistics
import subprocess
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]


def wall_times(cmd, n, env):
    out = []
    for _ in range(n):
        t0 = time.perf_counter()
        r = subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT, env=env)
        out.append(time.perf_counter() - t0)
        if r.returncode != 0:
            raise SystemExit(f"{' '.join(cmd)} exited {r.returncode}: {r.stderr.strip()}")
    return out, r


def main(argv):
    n = int(argv[0]) if argv else 10
    scenes = argv[1:] or ["hinge-slider"]
    env = dict(os.environ)
    env["PYTHONPATH"] = str(ROOT) + os.pathsep + env.get("PYTHONPATH", "")
    base, _ = wall_times([sys.executable, "-c", "pass"], n, env)
    print(f"python -c pass                         best {min(base) * 1e3:7.1f} ms   "
          f"median {statistics.median(base) * 1e3:7.1f} ms")
    for scene in scenes:
        times, r = wall_times([sys.executable, "-m", "femslide", "solve", scene, "--json"], n, env)
        res = json.loads(r.stdout)
        print(f"femslide solve {scene:<18} --json  best {min(times) * 1e3:7.1f} ms   "
              f"median {statistics.median(times) * 1e3:7.1f} ms   "
              f"(in-process solve {res['wall_time_s'] * 1e3:.3f} ms, {n} runs)")


if __name__ == "__main__":
    main(sys.argv[1:])
