"""A dry-friction oscillator under a harmonic force, and its hysteresis loop.

The built-in scene ``sdof-harmonic`` is example 3 of Kalandarbekov et al.: a mass m on a spring k,
sliding with Coulomb friction (kinetic mu, static mu0 >= mu, normal force N = m g) and driven by
F(t) = P0 sin(theta t), theta = theta_ratio * sqrt(k/m).  It is solved exactly, event by event:
the mass sticks (velocity exactly zero) while the spring and the force are held by static friction,
|F - k w| <= mu0 N, and slides with the friction force mu N against its velocity otherwise.

The result keeps the whole time history in memory (``r.history``, ``r.to_dataframe()``): time t,
displacement w, velocity v, state (+1/-1 sliding direction, 0 stuck), applied force F and the
friction force f of m w'' + k w + f = F (mu N sgn(v) while sliding, F - k w while stuck).  Plotted
against w over the last forcing periods (the steady state), f traces the hysteresis loop: horizontal
at +-mu N while sliding, vertical while stuck; its area is the energy friction dissipates per period,
mu N times the distance slid.

Run::

    python examples/friction_hysteresis.py [OUTPUT_FOLDER]

It writes ``history.csv`` (the DataFrame), ``hysteresis.png`` and, in ``run/``, the files of ``femslide
simulate --out`` (``result.json``, ``history.csv`` without F and f,
the event-exact ``turning_points.csv``) into OUTPUT_FOLDER (default: a new temporary folder).
SI units.
Takes a few seconds.
"""
from __future__ import annotations

import math
import os
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import femslide  # noqa: E402

out = sys.argv[1] if len(sys.argv) > 1 else tempfile.mkdtemp(prefix="femslide-friction-")
os.makedirs(out, exist_ok=True)

m, k, g, mu, mu0, P0 = 20.0 / 9.81, 1000.0, 9.81, 0.15, 0.18, 10.0
r = femslide.simulate("sdof-harmonic", m=m, k=k, g=g, mu=mu, mu0=mu0, P0=P0, theta_ratio=0.5, t_end=30.0)
r.write(os.path.join(out, "run"))               # the files of femslide simulate --out: result.json, ...
df = r.to_dataframe()                           # one row per time sample: t, w, v, state, F, f
df.to_csv(os.path.join(out, "history.csv"), index=False)

T = 2 * math.pi / r["theta"]                    # forcing period [s]
last = df[df["t"] >= r["t_end"] - 2 * T]        # the last two periods
fk = mu * m * g                                 # kinetic friction force [N]
steady = (f"{r['steady_amplitude']:.6g} m" if r["steady_amplitude"] is not None
          else f"none ({r['steady_reason']})")
print(f"steady amplitude: {steady}; energy balance {r['energy_balance']:.1e}; "
      f"{len(df)} samples, {(df['state'] == 0).mean():.0%} of them stuck")

# dissipated energy in one period: the loop's area and mu N times the distance slid
one = df[(df["t"] >= r["t_end"] - T) & (df["t"] <= r["t_end"])]
w, f = one["w"].to_numpy(), one["f"].to_numpy()
area = float(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(w)))
slid = float(np.sum(np.abs(np.diff(w))))
print(f"last period: loop area {area:.6g} J, mu N x distance slid {fk * slid:.6g} J")

fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4.2))
ax1.plot(df["t"], df["w"] * 1e3, color="C0", lw=1)
stuck = df["state"] == 0
ax1.plot(df["t"][stuck], df["w"][stuck] * 1e3, ".", color="C3", ms=2, label="stuck")
ax1.set_xlabel("t [s]")
ax1.set_ylabel("w [mm]")
ax1.set_title("displacement")
ax1.legend(fontsize=8)
ax2.plot(last["w"] * 1e3, last["f"], color="C1")
ax2.axhline(fk, color="0.6", lw=0.8, ls="--")
ax2.axhline(-fk, color="0.6", lw=0.8, ls="--", label=r"$\pm\mu N$")
ax2.axhline(mu0 * m * g, color="0.6", lw=0.8, ls=":")
ax2.axhline(-mu0 * m * g, color="0.6", lw=0.8, ls=":", label=r"$\pm\mu_0 N$")
ax2.set_xlabel("w [mm]")
ax2.set_ylabel("friction force f [N]")
ax2.set_title(f"hysteresis loop, last two periods (area {area:.3g} J)")
ax2.legend(fontsize=8)
for ax in (ax1, ax2):
    ax.grid(True, alpha=0.3)
fig.tight_layout()
png = os.path.join(out, "hysteresis.png")
fig.savefig(png, dpi=100)
print(f"wrote {png} and {os.path.join(out, 'history.csv')}")
