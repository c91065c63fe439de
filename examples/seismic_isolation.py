"""A two-storey frame on frictional sliding supports under a suite of (synthetic) ground records.

The frame: two columns per storey (EI = 8e6 N m^2, massless) welded to three rigid floors (the base
slab and two floors, 6 t, 5 t and 4 t); the base slab stands on two sliders along the ground with
Coulomb friction (mu = 0.08, mu0 = 0.1) - a sliding isolation, without re-centring springs.  The
same frame with its base welded to the ground is the reference.  No damping besides the friction
(``damping`` left out): the fixed frame's sway modes (4 and 10 Hz) amplify the ground motion freely.

The records are **synthetic**, not recorded earthquakes: white noise through a Kanai-Tajimi ground
filter (2.5 Hz, damping 0.6) under a Jennings-Housner-Tsai envelope (rise 1 s, strong motion 4 s,
then decaying), sampled every 0.02 s for 8 s, scaled to a peak ground acceleration of 3 m/s^2
(:func:`femslide.analysis.excitation.synthetic_record`, one seed per record), written as CSV
(t [s], a [m/s^2]).

Both frames are run under every record by :func:`femslide.sweep` (``simulate.ground.record`` varied;
the isolated frame's friction makes each run event-driven: stick, slip+, slip-).  The slab's slider
carries its transverse force and moment on two bearings 4 m apart (``bearing = 4``): the normal force
of the friction is the sum of their contact forces' magnitudes.  The script writes
``records.png`` (the suite), ``comparison.csv`` (per frame and record: the peak base moment of a
column - the reactions at the welded base, the moments at the columns' feet on the slab for the
isolated frame -, the peak inter-storey drifts, the peak floor accelerations and the residual slide)
and ``comparison.png``.  What the sliders do: the slab slides once the inertia of the frame exceeds
the friction, which caps the shear the ground can pass up (about mu g per unit mass), so the floor
accelerations, the drifts and the column moments fall; the price is a residual slide at the end.

Run::

    python examples/seismic_isolation.py [OUTPUT_FOLDER]

Takes several minutes (FEMSLIDE_EXAMPLE_SIZE=small: two 1.5 s records, as the tests run it, about a
minute).  Tolerance 1e-5 and no error estimate (``simulate.error_estimate = false``) to keep it short.
SI units.
"""
from __future__ import annotations

import os
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import femslide  # noqa: E402
from femslide.analysis.excitation import synthetic_record, write_csv_record  # noqa: E402

out = sys.argv[1] if len(sys.argv) > 1 else tempfile.mkdtemp(prefix="femslide-seismic-")
os.makedirs(out, exist_ok=True)
small = os.environ.get("FEMSLIDE_EXAMPLE_SIZE") == "small"
duration, seeds = (1.5, (1, 2)) if small else (8.0, (1, 2, 3))

# the synthetic record suite
records = []
for seed in seeds:
    t, a = synthetic_record(duration, dt=0.02, pga=3.0, f_g=2.5, zeta_g=0.6, rise=1.0, strong=4.0, decay=0.5,
                            seed=seed)
    records.append(write_csv_record(os.path.join(out, f"record_{seed}.csv"), t, a))


def frame(isolated: bool) -> femslide.Structure:
    """The two-storey frame; its base slab on two friction sliders, or welded to the ground."""
    s = femslide.Structure(gravity=(0.0, -9.81))
    levels = [(0.0, "slab", 6000.0), (3.0, "floor1", 5000.0), (6.0, "floor2", 4000.0)]
    for y, name, m in levels:
        s.body(name, mass=m, inertia=m * 4.0 ** 2 / 12, centroid=(2.0, y),
               outline=[(-0.2, y - 0.15), (4.2, y - 0.15), (4.2, y + 0.15), (-0.2, y + 0.15)])
    for k, ((y0, lo, _), (y1, up, _)) in enumerate(zip(levels, levels[1:]), 1):
        for side, x in (("L", 0.0), ("R", 4.0)):
            col = f"{side}{k}"
            s.rod(col, start=(x, y0), end=(x, y1), EI=8e6, EA=1e9)
            s.weld(f"{col}_foot", f"{col}.start", lo)
            s.weld(f"{col}_head", f"{col}.end", up)
    if isolated:   # one slider, its transverse force and moment carried on two bearings 4 m apart
        s.slider("bearing", "slab", "ground", axis=(1.0, 0.0), at=(2.0, 0.0), mu=0.08, mu0=0.1, bearing=4.0)
    else:
        s.weld("base", "slab", "ground", at=(2.0, 0.0))
    return s


rows = []
for isolated in (False, True):
    df = femslide.sweep(frame(isolated), quiet=True,
                        fixed={"simulate.t_end": duration, "simulate.tolerance": 1e-5,
                               "simulate.error_estimate": False, "simulate.elements": 2,
                               "simulate.ground.direction": [1.0, 0.0]},
                        **{"simulate.ground.record": records})
    for _, r in df.iterrows():
        assert r["status"] == "converged", r["reason"]
        foot = max(r[f"peaks.rods.{c}.M_max"] for c in ("L1", "R1"))
        rows.append({"frame": "isolated" if isolated else "fixed base",
                     "record": os.path.basename(r["simulate.ground.record"]),
                     "column foot M [kN m]": foot / 1e3,
                     "drift 1 [mm]": 1e3 * r["peaks.drifts.floor1-slab.dx"],
                     "drift 2 [mm]": 1e3 * r["peaks.drifts.floor2-floor1.dx"],
                     "floor2 abs. acc. [m/s^2]": r["peaks.bodies.floor2.ax"],
                     "residual slide [mm]": 1e3 * r.get("residual.slides.bearing", 0.0)
                     if isolated else 0.0,
                     "slip events": int(r.get("events.bearing", 0)) if isolated else 0})

import pandas as pd  # noqa: E402

table = pd.DataFrame(rows)
table.to_csv(os.path.join(out, "comparison.csv"), index=False)
print(table.to_string(index=False, float_format=lambda x: f"{x:.3g}"))

# pictures: the suite, and what the sliders change
fig, axes = plt.subplots(len(records), 1, figsize=(7, 1.6 * len(records) + 0.6), sharex=True, squeeze=False)
for ax, path in zip(axes[:, 0], records):
    d = np.loadtxt(path, delimiter=",", skiprows=1)
    ax.plot(d[:, 0], d[:, 1], lw=0.6)
    ax.set_ylabel("a_g [m/s^2]")
    ax.set_title(f"{os.path.basename(path)} (synthetic)", fontsize=8)
axes[-1, 0].set_xlabel("t [s]")
fig.tight_layout()
fig.savefig(os.path.join(out, "records.png"), dpi=100)

keys = ["column foot M [kN m]", "drift 1 [mm]", "drift 2 [mm]", "floor2 abs. acc. [m/s^2]", "residual slide [mm]"]
fig, axes = plt.subplots(1, len(keys), figsize=(3.0 * len(keys), 3.4))
x = np.arange(len(records))
for ax, key in zip(axes, keys):
    for k, (name, sub) in enumerate(table.groupby("frame", sort=False)):
        ax.bar(x + (k - 0.5) * 0.38, np.abs(sub[key].to_numpy()), width=0.36, label=name)
    ax.set_xticks(x, [f"rec {s}" for s in seeds], fontsize=7)
    ax.set_title(key, fontsize=8)
    ax.grid(True, axis="y", alpha=0.3)
axes[0].legend(fontsize=7)
fig.suptitle("two-storey frame: fixed base vs frictional sliding supports (mu = 0.08)", fontsize=9)
fig.tight_layout()
fig.savefig(os.path.join(out, "comparison.png"), dpi=100)
print(f"written to {out}")
