"""Closed forms of linear (first-order) Euler-Bernoulli beams, independent of femslide (math only).

Units SI; loads downward positive in the formulas' P, q (the tests apply them as -y forces);
moments sagging positive (the beam's M = EI dtheta/ds of femslide for a beam along +x).

* simply supported span L, point load P at a from the left (b = L - a): M_max = P a b / L at x = a;
  deflection under the load P a^2 b^2 / (3 EI L); end rotations theta_A = -P a b (L + b) / (6 EI L),
  theta_B = +P a b (L + a) / (6 EI L) (counter-clockwise positive, deflection downward);
* simply supported, uniform q: M_max = q L^2 / 8 at L / 2;
* cantilever (clamped at x = 0), load linear from q0 at the root to q1 at the tip:
  root moment magnitude q0 L^2 / 2 + (q1 - q0) L^2 / 3, root shear q0 L + (q1 - q0) L / 2,
  tip deflection q0 L^4 / (8 EI) + 11 (q1 - q0) L^4 / (120 EI), tip rotation
  q0 L^3 / (6 EI) + (q1 - q0) L^3 / (8 EI); M(x) = q0 (L - x)^2 / 2 + (q1 - q0) (L - x)^2 (2 L + x) / (6 L)
  [the triangle (q1 - q0) x / L: resultant (q1 - q0) (L^2 - x^2) / (2 L) at its centroid];
* propped cantilever (clamped at 0, pinned at L), uniform q: pin reaction 3 q L / 8, root moment
  q L^2 / 8, largest sagging moment 9 q L^2 / 128 at x = 5 L / 8 (3 L / 8 from the pin);
* propped cantilever whose prop settles by delta (no load): prop force 3 EI delta / L^3, clamp
  moment 3 EI delta / L^2.
"""
from __future__ import annotations


def ss_point(L, EI, P, a):
    b = L - a
    return {"M_max": P * a * b / L, "x_M_max": a, "v_load": P * a * a * b * b / (3 * EI * L),
            "theta_A": -P * a * b * (L + b) / (6 * EI * L), "theta_B": P * a * b * (L + a) / (6 * EI * L),
            "R_A": P * b / L, "R_B": P * a / L}


def ss_uniform(L, q):
    return {"M_max": q * L * L / 8, "x_M_max": L / 2}


def cantilever_trapezoid(L, EI, q0, q1):
    dq = q1 - q0
    return {"M_root": q0 * L * L / 2 + dq * L * L / 3, "V_root": q0 * L + dq * L / 2,
            "v_tip": q0 * L ** 4 / (8 * EI) + 11 * dq * L ** 4 / (120 * EI),
            "theta_tip": q0 * L ** 3 / (6 * EI) + dq * L ** 3 / (8 * EI)}


def cantilever_trapezoid_M(L, q0, q1, x):
    dq = q1 - q0
    return q0 * (L - x) ** 2 / 2 + dq * (L - x) ** 2 * (2 * L + x) / (6 * L)


def propped_uniform(L, q):
    return {"R_pin": 3 * q * L / 8, "M_root": q * L * L / 8, "M_sag": 9 * q * L * L / 128, "x_sag": 5 * L / 8}


def propped_settlement(L, EI, delta):
    return {"R_prop": 3 * EI * delta / L ** 3, "M_root": 3 * EI * delta / L ** 2}
