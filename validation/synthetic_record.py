"""A synthetic ground-acceleration record (not a recorded earthquake): filtered white noise with an
envelope, from a fixed seed, for the base-isolated frame of issue 22.

    python validation/synthetic_record.py      # writes meshes/structures/synthetic-record-20s.csv

Generator (the classic stationary model of a firm site, modulated in time):

* white noise: independent standard normal values w_k (numpy's default_rng(seed)), one per sample
  (dt = 0.01 s), held constant over each sample interval;
* Kanai-Tajimi filter (omega_g = 5 pi rad/s, i.e. 2.5 Hz; zeta_g = 0.6): x'' + 2 zeta_g omega_g x'
  + omega_g^2 x = w(t), a(t) = 2 zeta_g omega_g x' + omega_g^2 x, integrated exactly over each
  sample interval (matrix exponential of the filter, input held constant), from rest;
* envelope (Jennings type): (t / 2 s)^2 up to 2 s, 1 up to 10 s, exp(-0.3 (t - 10 s)) after, and a
  half-cosine taper over the last second so that the record ends at zero;
* scaled to the peak ground acceleration ``pga`` (default 3.0 m/s^2, 0.31 g).

CSV: a header line ``t,a``, then t [s], a [m/s^2] with 10 significant digits; femslide reads it as a
record linear between samples and zero after its end (``ground = {direction = [1.0, 0.0],
record = "synthetic-record-20s.csv", scale = 1.0}``), and so does the reference
(validation/friction_events.py).
"""
from __future__ import annotations

import math
import os

import numpy as np
from scipy.linalg import expm

SEED = 22
DT = 0.01
DURATION = 20.0
OMEGA_G = 5 * math.pi
ZETA_G = 0.6
PGA = 3.0
OUT = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "meshes", "structures",
                   "synthetic-record-20s.csv")


def envelope(t, t1=2.0, t2=10.0, c=0.3, end=DURATION):
    t = np.asarray(t, float)
    e = np.where(t < t1, (t / t1) ** 2, np.where(t <= t2, 1.0, np.exp(-c * (t - t2))))
    taper = np.where(t > end - 1.0, 0.5 * (1 + np.cos(math.pi * (t - (end - 1.0)))), 1.0)
    return e * taper


def generate(seed=SEED, dt=DT, duration=DURATION, omega_g=OMEGA_G, zeta_g=ZETA_G, pga=PGA):
    """(t [s], a [m/s^2]) of the synthetic record (module docstring)."""
    n = int(round(duration / dt))
    t = np.arange(n + 1) * dt
    w = np.random.default_rng(seed).standard_normal(n + 1)
    # the filter x' = F x + b w with x = (x, x'), exact over dt for w held: augmented exponential
    F = np.array([[0.0, 1.0], [-omega_g ** 2, -2 * zeta_g * omega_g]])
    Aug = np.zeros((3, 3))
    Aug[:2, :2] = F
    Aug[1, 2] = 1.0
    E = expm(Aug * dt)
    Phi, gam = E[:2, :2], E[:2, 2]
    x = np.zeros(2)
    a = np.zeros(n + 1)
    for k in range(n + 1):
        a[k] = 2 * zeta_g * omega_g * x[1] + omega_g ** 2 * x[0]
        x = Phi @ x + gam * w[k]
    a *= envelope(t, end=duration)
    a *= pga / np.abs(a).max()
    a[0] = 0.0
    a[-1] = 0.0
    return t, a


def write(path=OUT, **kw):
    t, a = generate(**kw)
    with open(path, "w", encoding="utf-8") as f:
        f.write("t,a\n")
        for ti, ai in zip(t, a):
            f.write(f"{ti:.2f},{ai:.10g}\n")
    return path


if __name__ == "__main__":
    print(write())
