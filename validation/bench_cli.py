"""Whole-process wall times (best of N), printed, not tested.

    python validation/bench_cli.py [N] [SCENE ...]

1. ``python -m femslide solve SCENE --json`` as a fresh process N times (default 10): best and median
   wall times, next to the run's own ``wall_time_s`` and ``import_time_s`` and the bare interpreter
   start-up (``python -c pass``) for scale.
2. The whole-process EI sweep of the paper's structure, ``femslide sweep beam-slider --vary
   EI=1e2,...,1e10 --json --quiet``, against a Python script doing the same in OpenSees: it imports
   numpy and openseespy and finds each equilibrium itself (validation/opensees_models.py
   ``opensees_slider_equilibrium``: 32 elements, penalty clamp, displacement control of the body
   rotation until the load factor passes 1, secant steps to lam = 1; all 9 EI values solve), with
   openseespy installed.  (The script this bench used before was handed femslide's phi instead of
   finding the equilibrium, imported no numpy, and failed at EI = 1e2 and 1e3.)  The ratio is
   measured in this run.

Both with bytecode, as users run installed packages: the processes run with PYTHONPYCACHEPREFIX set
to a folder that a first run fills (this environment sets PYTHONDONTWRITEBYTECODE=1, under which an
editable install recompiles femslide's source at every start).  validation/bench_fastcore.py measures
the same with and without bytecode, next to the other ratios of issue 23.
"""
from __future__ import annotations

import json
import os
import pathlib
import statistics
import subprocess
import sys
import tempfile
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


OPENSEES_SWEEP = """
import sys, json
import numpy
sys.path.insert(0, {here!r})
from opensees_models import opensees_slider_equilibrium
for v in json.loads(sys.argv[1]):
    if opensees_slider_equilibrium(v)["status"] != 0:
        raise SystemExit("OpenSees failed at EI = %g" % v["EI"])
"""


def sweep_vs_opensees(n, env):
    """Best-of-n whole-process times of the 9-value EI sweep: femslide's CLI against an OpenSees script."""
    vary = ",".join(f"1e{k}" for k in range(2, 11))
    cmd = [sys.executable, "-m", "femslide", "sweep", "beam-slider", "--vary", f"EI={vary}", "--json", "--quiet"]
    times, r = wall_times(cmd, n, env)
    rows = json.loads(r.stdout)
    solves = sum(x["wall_time_s"] for x in rows)
    imports = sum(x.get("import_time_s", 0.0) for x in rows)
    print(f"femslide sweep beam-slider (9 EI values)  best {min(times) * 1e3:7.1f} ms   "
          f"median {statistics.median(times) * 1e3:7.1f} ms   (solves {solves * 1e3:.1f} ms, "
          f"imports {imports * 1e3:.1f} ms)")
    try:
        import openseespy.opensees  # noqa: F401
    except Exception:  # noqa: BLE001 - optional oracle
        print("OpenSees: openseespy not importable; no comparison")
        return
    sys.path.insert(0, str(ROOT))
    from femslide.scenes.catalog import SCENES
    cases = [SCENES["beam-slider"].resolve({"EI": float(x["EI"])}) for x in rows]
    script = OPENSEES_SWEEP.format(here=str(ROOT / "validation"))
    o_times, _ = wall_times([sys.executable, "-c", script, json.dumps(cases)], n, env)
    print(f"OpenSees script, the same 9 cases        best {min(o_times) * 1e3:7.1f} ms   "
          f"median {statistics.median(o_times) * 1e3:7.1f} ms")
    print(f"ratio femslide / OpenSees (whole process, best of {n}): {min(times) / min(o_times):.2f}")


def main(argv):
    n = int(argv[0]) if argv else 10
    scenes = argv[1:] or ["hinge-slider"]
    env = dict(os.environ)
    env["PYTHONPATH"] = str(ROOT) + os.pathsep + env.get("PYTHONPATH", "")
    env.pop("PYTHONDONTWRITEBYTECODE", None)           # bytecode, as users have it
    env["PYTHONPYCACHEPREFIX"] = tempfile.mkdtemp(prefix="femslide-pyc-")
    env["OPENBLAS_NUM_THREADS"] = "1"
    wall_times([sys.executable, "-m", "femslide", "sweep", "beam-slider", "--vary", "EI=1e4", "--json", "--quiet"],
               1, env)                                  # fills the bytecode folder
    base, _ = wall_times([sys.executable, "-c", "pass"], n, env)
    print(f"python -c pass                         best {min(base) * 1e3:7.1f} ms   "
          f"median {statistics.median(base) * 1e3:7.1f} ms")
    for scene in scenes:
        times, r = wall_times([sys.executable, "-m", "femslide", "solve", scene, "--json"], n, env)
        res = json.loads(r.stdout)
        print(f"femslide solve {scene:<18} --json  best {min(times) * 1e3:7.1f} ms   "
              f"median {statistics.median(times) * 1e3:7.1f} ms   "
              f"(wall_time_s {res['wall_time_s'] * 1e3:.3f} ms, import_time_s "
              f"{res.get('import_time_s', 0.0) * 1e3:.1f} ms, {n} runs)")
    sweep_vs_opensees(n, env)


if __name__ == "__main__":
    main(sys.argv[1:])
