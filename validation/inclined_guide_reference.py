"""Independent reference for the inclined-guide structure: extensible elastica by shooting.

Not femslide: numpy and scipy only, written from the continuum equations, so that it can serve as an
oracle for femslide's load path, its limit point and its equilibrium after the snap.

The structure (meshes/structures/inclined-guide.toml; SI units, x right, y up, rotations and moments
counter-clockwise):

- rod ``post`` from A = (0, 0) to (1, 0.15), pinned to the ground at A, welded to the body ``head``
  at its end;
- rod ``arm`` from B = (2, 0) to (1, 0.15), welded (clamped) to the ground at B; its end runs in a
  guide of the head along axis e0 = (0.1, 1)/|.| (a slider: the end stays on the guide line through
  the reference point (1, 0.15) carried by the head and turns with the head; the slide is free);
- both rods EI = 10 N m^2, EA = 1e5 N, massless;
- the head (rigid) carries its weight m g, m = 5 kg, g = 9.81 m/s^2, at its centroid (1, 0.35),
  times the load factor lam.

Each rod is an extensible elastica (no shear; s the reference arc length): with n = (nx, ny) the
force that the part beyond s exerts on the part before it (constant: no load along the rods), theta
the tangent angle and M the bending moment (the moment of the part beyond on the part before),

    x' = (1 + e) cos theta,  y' = (1 + e) sin theta,  theta' = M / EI,
    M' = -(x' ny - y' nx),   e = (nx cos theta + ny sin theta) / EA.

This is the continuum limit of femslide's corotational elements (axial force EA times the chord
strain, moment EI times the rotation per reference length).  Shooting unknowns: the post's start
angle and force (M = 0 at the pin), the arm's start moment and force (angle fixed by the clamp); the
six equations: the arm's end on the guide line, its end rotation equal to the head's, no force along
the guide (frictionless), and the head's equilibrium (two forces, one moment).  The head's rotation
is the post's end rotation (weld).  Integration: scipy's DOP853 at rtol = atol = 1e-13; root finding:
scipy.optimize.fsolve to xtol 1e-13.

The load path lam(v) is followed in v, the vertical displacement of the post's end (the head's
point (1, 0.15)), which falls monotonically through the snap: the limit point is the maximum of lam(v)
(Brent), the equilibrium after the snap at lam = 1 the one reached by following v down past the
minimum of lam.
"""
from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq, fsolve, minimize_scalar

EI, EA = 10.0, 1e5
MASS, G = 5.0, 9.81
A, B = np.array([0.0, 0.0]), np.array([2.0, 0.0])
P0 = np.array([1.0, 0.15])          # the head's point: the post's end, the guide's reference point
C0 = np.array([1.0, 0.35])          # the head's centroid
E0 = np.array([0.1, 1.0]) / math.hypot(0.1, 1.0)
N0 = np.array([-E0[1], E0[0]])
L_POST = float(np.hypot(*(P0 - A)))
L_ARM = float(np.hypot(*(P0 - B)))
TH_POST = math.atan2(*(P0 - A)[::-1])
TH_ARM = math.atan2(*(P0 - B)[::-1])
RTOL = 1e-13


def rod(start, theta0, M0, n, length, dense=False):
    """Integrate one elastica from its start; returns the end state (x, y, theta, M) or the solution."""
    nx, ny = n

    def f(s, u):
        x, y, th, M = u
        c, si = math.cos(th), math.sin(th)
        e = (nx * c + ny * si) / EA
        dx, dy = (1 + e) * c, (1 + e) * si
        return [dx, dy, M / EI, -(dx * ny - dy * nx)]

    sol = solve_ivp(f, (0.0, length), [start[0], start[1], theta0, M0], method="DOP853", rtol=RTOL,
                    atol=RTOL, dense_output=dense)
    return sol if dense else sol.y[:, -1]


def rot(phi, v):
    c, s = math.cos(phi), math.sin(phi)
    return np.array([c * v[0] - s * v[1], s * v[0] + c * v[1]])


def state(u, lam):
    """Everything of the shooting unknowns u = (theta_post0, npx, npy, M_arm0, nax, nay) at load lam."""
    thp0, npx, npy, Ma0, nax, nay = u
    p = rod(A, thp0, 0.0, (npx, npy), L_POST)
    a = rod(B, TH_ARM, Ma0, (nax, nay), L_ARM)
    phi = p[2] - TH_POST                  # the head's rotation (welded to the post's end)
    P = p[:2]
    Pa = a[:2]
    e, nrm = rot(phi, E0), rot(phi, N0)
    C = P + rot(phi, C0 - P0)
    W = np.array([0.0, -lam * MASS * G])
    return dict(p=p, a=a, phi=phi, P=P, Pa=Pa, e=e, nrm=nrm, C=C, W=W, n_p=np.array([npx, npy]),
                n_a=np.array([nax, nay]))


def residual(u, lam):
    s = state(u, lam)
    r = np.empty(6)
    r[0] = (s["Pa"] - s["P"]) @ s["nrm"]               # arm end on the guide line
    r[1] = (s["a"][2] - TH_ARM) - s["phi"]               # arm end turns with the head
    r[2] = s["n_a"] @ s["e"]                             # no force along the guide
    F = -s["n_p"] - s["n_a"] + s["W"]                    # the head's equilibrium
    r[3], r[4] = F

    def cross(a, b):
        return a[0] * b[1] - a[1] * b[0]

    r[5] = (-s["p"][3] - s["a"][3] + cross(s["Pa"] - s["P"], -s["n_a"]) + cross(s["C"] - s["P"], s["W"]))
    return r


def solve_at(lam, guess):
    """The shooting unknowns of the equilibrium at load factor lam near ``guess``."""
    u, info, ier, msg = fsolve(residual, guess, args=(lam,), xtol=1e-13, full_output=True)
    if np.abs(residual(u, lam)).max() > 1e-10:   # (fsolve may stop short of xtol at round-off)
        raise RuntimeError(f"no convergence at lam = {lam}: {msg}")
    return u


def solve_at_v(v, guess):
    """(shooting unknowns, lam) of the equilibrium with the head's point lowered by -v (v < 0)."""
    def f(w):
        u, lam = w[:6], w[6]
        return np.append(residual(u, lam), state(u, lam)["P"][1] - (P0[1] + v))
    w, info, ier, msg = fsolve(f, guess, xtol=1e-13, full_output=True)
    if np.abs(f(w)).max() > 1e-10:
        raise RuntimeError(f"no convergence at v = {v}: {msg}")
    return w[:6], float(w[6])


def path(v_end=-1.1, dv=-0.025):
    """[(v, lam, u)] from the unloaded state down to v_end."""
    u = np.array([TH_POST, 0.0, 0.0, 0.0, 0.0, 0.0])
    w = np.append(u, 0.0)
    out = [(0.0, 0.0, u)]
    v = 0.0
    while v > v_end:
        v += dv
        # predictor: the secant of the last two points
        if len(out) >= 2:
            (v1, l1, u1), (v2, l2, u2) = out[-2], out[-1]
            f = (v - v2) / (v2 - v1)
            w = np.append(u2 + f * (u2 - u1), l2 + f * (l2 - l1))
        u, lam = solve_at_v(v, w)
        out.append((v, lam, u))
    return out


def limit_point(pts, sign=+1):
    """(lam, v at it, u there): the first maximum (sign +1) or minimum (-1) of lam(v) along the
    path, by Brent's method on lam(v) between the neighbours of the sampled extremum."""
    i = _first_extremum(pts, sign)
    va, vb = pts[i + 1][0], pts[i - 1][0]
    cache = {}

    def f(v):
        k = min(range(len(pts)), key=lambda j: abs(pts[j][0] - v))
        near = min(cache, key=lambda x: abs(x - v)) if cache else None
        guess = cache[near] if near is not None and abs(near - v) < abs(pts[k][0] - v) else \
            np.append(pts[k][2], pts[k][1])
        u, lam = solve_at_v(v, guess)
        cache[v] = np.append(u, lam)
        return -sign * lam

    res = minimize_scalar(f, bounds=(va, vb), method="bounded", options={"xatol": 1e-10})
    u, lam = solve_at_v(res.x, cache[min(cache, key=lambda x: abs(x - res.x))])
    return lam, float(res.x), u


def _first_extremum(pts, sign):
    """The index of the first local maximum (sign +1) or minimum (-1) of lam along the path."""
    lam = [sign * p[1] for p in pts]
    for i in range(1, len(pts) - 1):
        if lam[i] > lam[i - 1] and lam[i] >= lam[i + 1]:
            return i
    raise RuntimeError("no extremum of the load factor on the path")


def after_snap(pts, lam=1.0):
    """The equilibrium at load factor lam reached along the path after its minimum (the snap's end)."""
    i_min = _first_extremum(pts, -1)
    i_max = _first_extremum(pts, +1)
    assert i_max < i_min, "the path must pass its maximum before its minimum"
    for k in range(i_min, len(pts) - 1):
        (va, la, ua), (vb, lb, ub) = pts[k], pts[k + 1]
        if (la - lam) * (lb - lam) <= 0:
            vv = brentq(lambda v: solve_at_v(v, np.append(ua + (v - va) / (vb - va) * (ub - ua),
                                                          la + (v - va) / (vb - va) * (lb - la)))[1] - lam,
                        va, vb, xtol=1e-14)
            u, _ = solve_at_v(vv, np.append(ua, la))
            return solve_at(lam, u)
    raise RuntimeError(f"the path does not reach lam = {lam} after its minimum; extend v_end")


def results(u, lam):
    """femslide's named results of the equilibrium u at load lam (SI; reactions: forces of the
    ground on the structure; the slide of the guide; the head's centroid and rotation; rods' M_max)."""
    s = state(u, lam)
    thp0, npx, npy, Ma0, nax, nay = u
    sp = rod(A, thp0, 0.0, (npx, npy), L_POST, dense=True)
    sa = rod(B, TH_ARM, Ma0, (nax, nay), L_ARM, dense=True)

    def mmax(sol, length):
        sgrid = np.linspace(0.0, length, 2001)
        M = sol.sol(sgrid)[3]
        k = int(np.argmax(np.abs(M)))
        lo, hi = sgrid[max(k - 1, 0)], sgrid[min(k + 1, 2000)]
        r = minimize_scalar(lambda x: -abs(sol.sol(x)[3]), bounds=(lo, hi), method="bounded",
                            options={"xatol": 1e-12})
        return max(abs(M).max(), -r.fun)

    return {
        "bodies": {"head": {"x": float(s["C"][0]), "y": float(s["C"][1]), "rotation": float(s["phi"])}},
        "reactions": {"A": {"Fx": -npx, "Fy": -npy, "M": 0.0},
                      "B": {"Fx": -nax, "Fy": -nay, "M": -Ma0}},
        "joints": {"guide": {"slide": float((s["Pa"] - s["P"]) @ s["e"])}},
        "rods": {"post": {"M_max": mmax(sp, L_POST)}, "arm": {"M_max": mmax(sa, L_ARM)}},
        "lam": lam,
    }


def reference():
    """{'limit': lam_max, 'after': results at lam = 1 after the snap, 'minimum': lam_min}."""
    pts = path()
    lam_max, v_max, _ = limit_point(pts)
    lam_min, _, _ = limit_point(pts, -1)
    u = after_snap(pts, 1.0)
    return {"limit": lam_max, "v_limit": v_max, "minimum": lam_min, "after": results(u, 1.0)}


if __name__ == "__main__":
    import json
    import time
    t0 = time.time()
    ref = reference()
    print(json.dumps(ref, indent=1))
    print(f"{time.time() - t0:.1f} s")
