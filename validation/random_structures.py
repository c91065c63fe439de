"""Random declared structures: frames of columns on the ground with a deck or beams on top, random
joints, stiffnesses and loads, and the check of each run against global statics.  A script and a
library (validation/test_random_structures.py runs a sample).

    python validation/random_structures.py [--count 50] [--seed 0] [--jobs 2]

Each structure (``structure(seed)``) has 2 or 3 columns standing on the ground (welded or pinned),
tied at the top either by a rigid deck (welds, pins or sliders along the column) or by beams (rods
welded, pinned or in a sliding clamp), gravity on the deck and on rod masses, a horizontal force and
vertical loads; EI from 1e5 to 1e8 N m^2, EA = 1e6 m^-2 EI or random in [1e3, 1e6] EI.

The check of a run (``check``):

* exit 0: the reactions balance the loads, forces within 2e-9 of the largest force (dead loads: the
  sum is exact whatever the deformation) and, without distributed loads, moments about the origin
  with the loads at their deformed points (2e-9 of the largest force times the structure's size);
  the error estimate must be finite;
* exit 1 with a limit point or a mechanism: an independent look at the linearised structure
  (``linear_check``): the undeformed tangent's null space with the loads' work on it, to tell a
  genuine mechanism or limit point from a false failure;
* exit 1 "refinement reached ... elements": a false failure when a fixed mesh of 64 elements per rod
  solves and balances (reported as WRONG: the adaptive refinement should have stopped).
"""
from __future__ import annotations

import json
import math
import os
import pathlib
import subprocess
import sys
import tempfile
from dataclasses import replace

import numpy as np

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

import femslide  # noqa: E402
from femslide.app.structfile import dumps  # noqa: E402

G = 9.81


def structure(seed: int) -> femslide.Structure:
    """A random frame (see the module docstring), reproducible from ``seed``."""
    rng = np.random.default_rng(seed)
    s = femslide.Structure(gravity=(0.0, -G))
    n_col = int(rng.integers(2, 4))
    xs = np.cumsum(np.concatenate([[0.0], rng.uniform(2.0, 5.0, n_col - 1)]))
    h = float(rng.uniform(2.5, 5.0))
    deck = bool(rng.integers(0, 2))

    def stiffness():
        EI = float(10 ** rng.uniform(5, 8))
        EA = None if rng.random() < 0.5 else float(EI * 10 ** rng.uniform(3, 6))
        return EI, EA

    supports = []
    for i, x in enumerate(xs):
        EI, EA = stiffness()
        top = h + float(rng.uniform(-0.3, 0.3)) if not deck else h
        s.rod(f"c{i}", start=(float(x), 0.0), end=(float(x), top), EI=EI, EA=EA,
              rhoA=float(rng.choice([0.0, rng.uniform(5, 50)])))
        kind = "weld" if rng.random() < 0.6 else "pin"
        supports.append(kind)
        getattr(s, kind)(f"S{i}", a=f"c{i}.start", b="ground")
    if all(k == "pin" for k in supports):      # pinned bases need a rigid top: weld the first
        s.joints["S0"] = replace(s.joints["S0"], type="weld")
    if deck:
        m = float(rng.uniform(100, 2000))
        w = float(xs[-1] - xs[0])
        s.body("deck", mass=m, centroid=(float(xs[0]) + w / 2, h + 0.25),
               outline=[(float(xs[0]), h), (float(xs[-1]), h), (float(xs[-1]), h + 0.5), (float(xs[0]), h + 0.5)])
        for i in range(n_col):
            kind = "weld" if i == 0 else str(rng.choice(["weld", "pin", "slider"]))
            if kind == "slider":
                s.slider(f"T{i}", a=f"c{i}.end", b="deck", axis=(0.0, 1.0))
            else:
                getattr(s, kind)(f"T{i}", a=f"c{i}.end", b="deck")
        s.force("wind", on="deck", force=(float(rng.uniform(-0.3, 0.3)) * m * G, 0.0),
                at=(float(xs[0]), h + 0.5))
    else:
        for i in range(n_col - 1):
            EI, EA = stiffness()
            top_a = s.rods[f"c{i}"].end
            top_b = s.rods[f"c{i + 1}"].end
            s.rod(f"b{i}", start=top_a, end=top_b, EI=EI, EA=EA)
            s.weld(f"L{i}", a=f"b{i}.start", b=f"c{i}.end")
            kind = str(rng.choice(["weld", "pin", "slider"]))
            if kind == "slider":
                d = np.subtract(top_b, top_a)
                s.slider(f"R{i}", a=f"c{i + 1}.end", b=f"b{i}.end", axis=tuple(float(v) for v in d / np.hypot(*d)))
            else:
                getattr(s, kind)(f"R{i}", a=f"b{i}.end", b=f"c{i + 1}.end")
            s.distributed(f"q{i}", on=f"b{i}", force=(0.0, -float(rng.uniform(1e3, 2e4))))
        s.force("wind", on="c0.end", force=(float(rng.uniform(-1, 1)) * 5e3, 0.0))
    return s


def _loads(s, r):
    """(sum of the loads' forces [N], their moment about the origin [N m] or None) of a result: dead
    loads, gravity on bodies and rod masses, at their deformed points (None with distributed loads
    or rod masses, whose moment needs the FE's own quadrature)."""
    F = np.zeros(2)
    M = 0.0
    exact_moment = True
    g = np.asarray(s.gravity, float)
    for b in s.bodies.values():
        F += b.mass * g
        rb = r["bodies"][b.name]
        M += rb["x"] * b.mass * g[1] - rb["y"] * b.mass * g[0]
    for rod in s.rods.values():
        L = math.dist(rod.start, rod.end)
        F += rod.rhoA * L * g
        exact_moment &= rod.rhoA == 0.0
    for ld in s.loads.values():
        f = np.asarray(ld.force, float)
        if ld.type == "distributed":
            F += f * math.dist(s.rods[ld.on].start, s.rods[ld.on].end)
            exact_moment = False
            continue
        F += f
        if ld.on in s.bodies:
            b, rb = s.bodies[ld.on], r["bodies"][ld.on]
            c, sn = math.cos(rb["rotation"]), math.sin(rb["rotation"])
            at = ld.at or b.centroid
            d = np.subtract(at, b.centroid)
            p = (rb["x"] + c * d[0] - sn * d[1], rb["y"] + sn * d[0] + c * d[1])
        else:
            rod, end = ld.on.split(".")
            p0 = getattr(s.rods[rod], end)
            e = r["rods"][rod][end]
            p = (p0[0] + e["u"], p0[1] + e["v"])
        M += p[0] * f[1] - p[1] * f[0] + ld.moment
    return F, (M if exact_moment else None)


def balance(s, r):
    """(force error, moment error or None), relative (see the module docstring)."""
    F, M = _loads(s, r)
    R = np.zeros(2)
    MR = 0.0
    for name, rc in r["reactions"].items():
        j = s.joints[name]
        a = j.a
        if a in s.bodies:
            b, rb = s.bodies[a], r["bodies"][a]
            c, sn = math.cos(rb["rotation"]), math.sin(rb["rotation"])
            d = np.subtract(j.at, b.centroid)
            p = (rb["x"] + c * d[0] - sn * d[1], rb["y"] + sn * d[0] + c * d[1])
        else:
            rod, end = a.split(".")
            p0 = getattr(s.rods[rod], end)
            e = r["rods"][rod][end]
            p = (p0[0] + e["u"], p0[1] + e["v"])
        R += (rc["Fx"], rc["Fy"])
        MR += p[0] * rc["Fy"] - p[1] * rc["Fx"] + rc["M"]
    big = max(float(np.abs(F).max()), max(max(abs(rc["Fx"]), abs(rc["Fy"])) for rc in r["reactions"].values()))
    size = max(max(abs(v) for rod in s.rods.values() for p in (rod.start, rod.end) for v in p), 1.0)
    ef = float(np.abs(F + R).max()) / big
    em = None if M is None else abs(M + MR) / (big * size)
    return ef, em


def run(seed, timeout=60.0, extra=()):
    """(exit status, result or None, stderr) of ``femslide solve`` of structure(seed) in a subprocess
    with a time limit and a 4 GiB memory cap."""
    s = structure(seed)
    d = tempfile.mkdtemp(prefix="femslide_rand_")
    f = os.path.join(d, f"random{seed}.toml")
    with open(f, "w") as fh:
        fh.write(dumps(s, header=f"validation/random_structures.py structure({seed})"))
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    cmd = [sys.executable, "-m", "femslide", "solve", f, "--json", "--quiet", *extra]
    pre = None
    if hasattr(os, "fork"):
        import resource

        def pre():
            resource.setrlimit(resource.RLIMIT_AS, (4 * 2**30, 4 * 2**30))
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=env, preexec_fn=pre)
    except subprocess.TimeoutExpired:
        return None, None, "timeout", f
    r = None
    if p.stdout.strip():
        try:
            r = json.loads(p.stdout.strip().splitlines()[-1])
        except json.JSONDecodeError:
            r = None
    return p.returncode, r, p.stderr.strip(), f


def check(seed, timeout=60.0):
    """(outcome, detail) of structure(seed): solved, failed cleanly, WRONG, internal error, timeout."""
    s = structure(seed)
    code, r, err, f = run(seed, timeout)
    if code is None:
        return "timeout", f
    if "internal error" in err or "Traceback" in err:
        return "internal error", err[-300:]
    if code == 0:
        ef, em = balance(s, r)
        ok = ef <= 2e-9 and (em is None or em <= 2e-9) and r["error_estimate"] is not None
        return ("solved" if ok else "WRONG"), f"forces {ef:.1e}, moments {em if em is None else f'{em:.1e}'}; " \
                                               f"error_estimate {r['error_estimate']}"
    if code == 2:
        return "failed cleanly", "exit 2: " + err.splitlines()[-1]
    msg = err.splitlines()[-1] if err else ""
    if "refinement reached" in msg:
        c2, r2, e2, _ = run(seed, timeout, ("--set", "elements=64"))
        if c2 == 0:
            return "WRONG", f"false failure: '{msg}', but 64 fixed elements per rod solve"
    return "failed cleanly", "exit 1: " + msg


def main():
    count = int(sys.argv[sys.argv.index("--count") + 1]) if "--count" in sys.argv else 50
    seed0 = int(sys.argv[sys.argv.index("--seed") + 1]) if "--seed" in sys.argv else 0
    jobs = int(sys.argv[sys.argv.index("--jobs") + 1]) if "--jobs" in sys.argv else 2
    import concurrent.futures as cf
    counts = {}
    with cf.ThreadPoolExecutor(jobs) as ex:
        futs = {ex.submit(check, seed): seed for seed in range(seed0, seed0 + count)}
        rows = []
        for fut in cf.as_completed(futs):
            seed = futs[fut]
            out, detail = fut.result()
            rows.append((seed, out, detail))
            print(f"{seed:4d} {out:16s} {detail}", flush=True)
            counts[out] = counts.get(out, 0) + 1
    print(f"{count} structures: " + ", ".join(f"{n} {k}" for k, n in sorted(counts.items())))
    return 0 if not any(o in ("WRONG", "internal error", "timeout") for _, o, _ in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
