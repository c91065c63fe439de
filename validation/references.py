"""Independent reference solutions for the FE statics scenes (SPEC sections 1, 3).

Nothing here uses femslide's FE code (no mesh, no corotational element, no joint or Newton module of
femslide).  ``femslide.scenes.hinge`` is used in one place only: as a *starting guess* at large EI for the
continuation in EI (the result does not depend on it once the root solver has converged).

Inextensible elastica by shooting
---------------------------------
A massless rod loaded only at its ends carries a constant internal force.  With R the force of the
ground on the rod at its pinned base r0 (moment-free), the bending moment (of the part beyond s on the
part before s, counter-clockwise) is M(s) = (r(s) - r0) x R and

    theta' = M / EI,   x' = cos theta,   y' = sin theta          (theta from +x, counter-clockwise).

With a finite EA (``EA_ratio`` = EA/EI, as femslide's default EA = 1e6 EI) the rod also stretches:
x' = (1 + N/EA) cos theta, y' = (1 + N/EA) sin theta, N = -R . t the tension, theta' = M/EI per unit
undeformed length (the limit the corotational Euler-Bernoulli mesh converges to).  ``EA_ratio`` None
is the inextensible elastica of the paper.

This system is integrated by a Taylor-series method of high order (``ORDER`` = 30) with fixed steps
h <= 0.4 / omega, omega = sqrt(|R| / EI) (the pendulum's complex singularities lie at least
pi / (2 omega) away, so the truncation error is below 1e-17).  The Taylor coefficients follow from
exact recurrences (cos theta and sin theta by C' = -S theta', S' = C theta').  Everything is analytic
in the unknowns, so the Jacobian of the shooting residual is computed exactly by complex-step
differentiation; the equations are solved by scipy.optimize.root (hybr, xtol 1e-14) and polished
with Newton steps.  Lengths are scaled by a and forces by P = m g inside.

Structures (SPEC section 1): A1 = (0, 0), B1 = (2a, 0); the body turns by phi clockwise,
e = (sin phi, cos phi), n = (cos phi, -sin phi); rotating a body point p about the body's reference
point: Rot(p) = (x cos phi + y sin phi, -x sin phi + y cos phi).  Frictionless slide: the guide
transmits no force along e, so the force of the ground on the rod at B1 is R = Q n (one unknown Q).

* beam-slider: left rod rigid (body + rod rotate about A1); right rod an elastica from B1, its top S
  in the sliding clamp.  Unknowns (theta0, Q, phi) (theta0 measured from e in the code, see
  ``_Structure.residual``: the rod is integrated in the body-axis frame); equations: S on the guide line through the
  body point Rot(2a, L) along e; theta(L) = pi/2 - phi (tangent e, no wrapping: the angle is continuous);
  moment of body + left rod about A1: G x (0, -P) + S x R - M(L) = 0.
* beam-fixed: left rod an elastica pinned at A1 and welded at A (tangent e); the body is placed by A
  and phi; the rigid right rod is pinned at B1 and held in the clamp, so it pushes the body with the
  force Q n along a line through B1, and the body point B = A + 2a n stays on the line through B1
  along e.  Ground force on the left rod R = (0, P) - Q n.  Unknowns (theta0, Q, phi); equations:
  (B - B1) x e = 0, theta(l) = pi/2 - phi, body moment about A: (B1 - A) x Q n + (G - A) x (0, -P)
  - M(l) = 0.
* Reactions (ground on structure): B1 = Q n, A1 = (0, P) - Q n; global statics hold exactly.
* Slides as femslide defines them: beam-slider s = (S - Rot(2a, L)) . e; beam-fixed
  s = l - (B - B1) . e.

The principal branch (gravity ramped from zero) is followed by continuation in EI from large EI
(1e12 N m^2, started from the spring-hinge model with the equivalent spring of SPEC section 3), down
in steps of 10^(1/8) with a quadratic predictor in log EI; the default geometry's path is smooth.

Cantilevers (L, EI, clamped at s = 0 along +x)
----------------------------------------------
* End moment M = m_ratio 2 pi EI / L: a circular arc of radius R = EI / M through angle theta = M L / EI;
  tip (R sin theta - L, R (1 - cos theta)).
* Transverse dead tip load P = p_ratio EI / L^2 (+y): the elastica in elliptic integrals
  (Bisshopp & Drucker 1945; Mattiasson 1981).  With alpha = P L^2 / EI, k^2 = (1 + sin theta_t)/2 and
  sin phi0 = 1 / (k sqrt 2):  sqrt(alpha) = K(k) - F(phi0, k),
  v / L = 1 - 2 (E(k) - E(phi0, k)) / sqrt(alpha),  x_tip / L = sqrt(2 sin theta_t / alpha).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from scipy import optimize, special

ORDER = 30
H_OMEGA = 0.4   # step length times omega
DEFAULTS = dict(a=1.0, b=0.5, d=0.2, l=3.0, m=1.0, g=9.81)


# -- elastica integrator ------------------------------------------------------------------------------

def _taylor(th0, u0, w0, Rx, Ry, EI, EA=None):
    """Taylor coefficients (ORDER + 1 each) of theta, u, w about a point where they are th0, u0, w0.

    With a finite EA the rod stretches by eps = N / EA, N = -R . t the tension (R: ground force on
    the rod at its base): u' = (1 + eps) cos theta, w' = (1 + eps) sin theta; theta' = M / EI per
    unit undeformed length."""
    K = ORDER
    dt = np.result_type(th0, u0, w0, Rx, Ry, float)
    th = np.zeros(K + 1, dt)
    u = np.zeros(K + 1, dt)
    w = np.zeros(K + 1, dt)
    C = np.zeros(K + 1, dt)
    S = np.zeros(K + 1, dt)
    d = np.zeros(K + 1, dt)   # coefficients of theta'
    th[0], u[0], w[0] = th0, u0, w0
    C[0], S[0] = np.cos(th0), np.sin(th0)
    for n in range(K):
        k = n + 1
        th[k] = (Ry * u[n] - Rx * w[n]) / (EI * k)
        d[n] = k * th[k]
        if EA is None:
            u[k] = C[n] / k
            w[k] = S[n] / k
        else:
            cc = np.dot(C[:k], C[n::-1])
            sc = np.dot(S[:k], C[n::-1])
            ss = np.dot(S[:k], S[n::-1])
            u[k] = (C[n] - (Rx * cc + Ry * sc) / EA) / k
            w[k] = (S[n] - (Rx * sc + Ry * ss) / EA) / k
        conv_S = np.dot(S[:k], d[n::-1])
        conv_C = np.dot(C[:k], d[n::-1])
        C[k] = -conv_S / k
        S[k] = conv_C / k
    return th, u, w


def _horner(c, h):
    out = c[-1] * 0 + c[-1]
    for x in c[-2::-1]:
        out = out * h + x
    return out


@dataclass
class Shot:
    theta: complex   # tangent angle at the end
    u: complex       # end position relative to the base
    w: complex
    pieces: list     # (s_start, h, th, u, w) Taylor pieces, for M(s) along the rod


def shoot(theta0, Rx, Ry, EI, L, EA=None):
    """Integrate the elastica from a moment-free base (at the origin) with ground force (Rx, Ry);
    ``EA`` None: inextensible."""
    om = math.sqrt(math.hypot(float(np.real(Rx)), float(np.real(Ry))) / EI)
    nsteps = max(2, math.ceil(L * om / H_OMEGA))
    h = L / nsteps
    th, u, w = theta0, 0.0 * theta0, 0.0 * theta0
    pieces = []
    for i in range(nsteps):
        ct, cu, cw = _taylor(th, u, w, Rx, Ry, EI, EA)
        pieces.append((i * h, h, ct, cu, cw))
        th, u, w = _horner(ct, h), _horner(cu, h), _horner(cw, h)
    return Shot(th, u, w, pieces)


def moment_max(shot: Shot, Rx, Ry, EI):
    """max |M(s)| over the rod (dense sampling of the Taylor pieces, then a local refinement)."""
    best, where = -1.0, None
    for (_s0, h, _ct, cu, cw) in shot.pieces:
        cm = Ry * cu - Rx * cw
        t = np.linspace(0.0, h, 201)
        vals = np.abs(np.polyval(cm[::-1], t))
        j = int(np.argmax(vals))
        if vals[j] > best:
            best, where = float(vals[j]), (cm, t, j, h)
    cm, t, j, h = where
    if 0 < j < t.size - 1:   # interior extremum: M' = 0 there
        dcm = np.polynomial.polynomial.polyder(cm)
        try:
            r = optimize.brentq(lambda x: np.polyval(dcm[::-1], x), t[j - 1], t[j + 1], xtol=1e-15)
            best = max(best, abs(float(np.polyval(cm[::-1], r))))
        except ValueError:
            pass
    return best


# -- structures ---------------------------------------------------------------------------------------

def _rot(phi, p):
    c, s = np.cos(phi), np.sin(phi)
    return (p[0] * c + p[1] * s, -p[0] * s + p[1] * c)


def _cross(p, q):
    return p[0] * q[1] - p[1] * q[0]


class _Structure:
    """Nondimensional shooting problem (a = 1, P = 1)."""

    def __init__(self, kind, a, b, d, l, m, g, L=None, EA_ratio=None):
        self.kind = kind
        self.EA_ratio = EA_ratio   # EA / EI [m^-2]; None: inextensible
        self.a, self.P = a, m * g
        self.b, self.d, self.l = b / a, d / a, l / a
        self.L = (L if L is not None else l) / a

    def _EA(self, EI):
        # scaled EA = EA / P = ratio * EI_scaled * a^2
        return None if self.EA_ratio is None else self.EA_ratio * EI * self.a ** 2

    def residual(self, x, EI, full=False):
        """Shooting residual; x = (theta0 - (pi/2 - phi), Q, phi).

        The rod is integrated in the frame (e, -n) of the deformed body axis: the tangent angle is
        measured from e and the end position (u~, w~) has u~ along e and w~ along -n, so the small
        transverse offsets are computed without cancellation (for EI = 1e12 they are ~1e-7 a).  In
        that frame R~ = (R . e, -R . n).  Using cross(v, e) = v . n and cross(n, e) = 1, the
        transverse conditions are written out: beam-slider (S - S_guide) . n = (B1 - S_guide) . n
        - w~ with (B1 - S_guide) . n = 2 cos(phi) - 2 = -4 sin^2(phi/2); beam-fixed
        (B - B1) . n = A . n + 2 - 2 cos(phi) = -w~ + 4 sin^2(phi/2)."""
        th0, Q, phi = x
        e = (np.sin(phi), np.cos(phi))
        n = (np.cos(phi), -np.sin(phi))
        h2 = 4.0 * np.sin(0.5 * phi) ** 2   # 2 - 2 cos(phi), without cancellation
        if self.kind == "slider":
            R = (Q * n[0], Q * n[1])
            Rt = (0.0 * Q, -Q)
            sh = shoot(th0, Rt[0], Rt[1], EI, self.L, self._EA(EI))
            S = (2.0 + sh.u * e[0] - sh.w * n[0], sh.u * e[1] - sh.w * n[1])
            ML = Rt[1] * sh.u - Rt[0] * sh.w
            G = _rot(phi, (1.0 + self.d, self.l + self.b))
            r = [-h2 - sh.w,
                 sh.theta,
                 -G[0] + _cross(S, R) - ML]
            extra = dict(slide=2.0 * np.sin(phi) - self.L + sh.u)
        else:
            R = (-Q * n[0], 1.0 - Q * n[1])
            Rt = (np.cos(phi), np.sin(phi) + Q)
            sh = shoot(th0, Rt[0], Rt[1], EI, self.l, self._EA(EI))
            A = (sh.u * e[0] - sh.w * n[0], sh.u * e[1] - sh.w * n[1])
            G = (A[0] + (1.0 + self.d) * n[0] + self.b * e[0], A[1] + (1.0 + self.d) * n[1] + self.b * e[1])
            ML = Rt[1] * sh.u - Rt[0] * sh.w
            r = [h2 - sh.w,
                 sh.theta,
                 _cross((2.0 - A[0], -A[1]), (Q * n[0], Q * n[1])) - (G[0] - A[0]) - ML]
            extra = dict(slide=self.l - sh.u + 2.0 * np.sin(phi))
        r = np.array(r)
        if full:
            return r, sh, Rt, extra
        return r

    def jac(self, x, EI):
        """Residual and its exact Jacobian by complex-step differentiation."""
        h = 1e-30
        r0 = np.real(self.residual(np.asarray(x, float), EI))
        J = np.empty((3, 3))
        for j in range(3):
            xc = np.array(x, complex)
            xc[j] += 1j * h
            J[:, j] = np.imag(self.residual(xc, EI)) / h
        return r0, J

    def solve(self, EI, x0):
        sol = optimize.root(lambda x: self.jac(x, EI), x0, jac=True, method="hybr",
                            options={"xtol": 1e-14})
        x = sol.x
        for _ in range(3):   # Newton polish with the exact Jacobian
            r, J = self.jac(x, EI)
            x = x - np.linalg.solve(J, r)
        r, J = self.jac(x, EI)
        scale = np.array([1.0, 1.0, max(1.0, abs(x[1]))])
        if not np.all(np.abs(r) / scale < 1e-11):
            raise RuntimeError(f"elastica shooting did not converge at EI = {EI:g}: residual {r}")
        return x

    def result(self, x, EI):
        r, sh, Rt, extra = self.residual(np.asarray(x, float), EI, full=True)
        th0, Q, phi = x
        Pa, P = self.P * self.a, self.P
        n = (math.cos(phi), -math.sin(phi))
        M_max = moment_max(sh, Rt[0], Rt[1], EI)
        return {
            "phi": float(phi),
            "slide": float(extra["slide"]) * self.a,
            "M_max": M_max * Pa,
            "reactions": {"A1": {"Fx": -Q * n[0] * P, "Fy": (1.0 - Q * n[1]) * P},
                          "B1": {"Fx": Q * n[0] * P, "Fy": Q * n[1] * P}},
            "theta0": float(th0) + 0.5 * math.pi - float(phi),
            "Q": float(Q) * P,
            "residual": r.tolist(),
        }


def _hinge_guess(kind, EI_si, p):
    """(theta0, Q, phi) in scaled units from femslide's spring-hinge model (starting guess only)."""
    from femslide.scenes import hinge
    P = p["m"] * p["g"]
    if kind == "slider":
        L = p.get("L") or p["l"]
        h = hinge.solve_slider(**{**p, "c": 3 * EI_si / L, "l1": L, "k": 0.0})
    else:
        h = hinge.solve_fixed(**{**p, "c": 3 * EI_si / (4 * p["l"])})
    phi, psi = h["phi"], h["psi"]
    F2, N2 = h["reactions"]["B1"]["Fx"], h["reactions"]["B1"]["Fy"]
    Q = (F2 * math.cos(phi) - N2 * math.sin(phi)) / P
    if kind == "slider":
        th0 = 0.5 * math.pi - psi
    else:
        # the hinge sits at mid-height; the elastica's pinned base turns by about twice as much
        th0 = 0.5 * math.pi - (phi + 1.5 * (psi - phi))
    return np.array([th0 - (0.5 * math.pi - phi), Q, phi])


EI_TOP = 1e12
N_PER_DECADE = 8


@lru_cache(maxsize=None)
def _path(kind, key):
    """Continuation in EI from EI_TOP down to 1e1 on the grid 10^(k/N_PER_DECADE): {k: x}."""
    p = dict(key)
    st = _Structure(kind, **p)
    P, a = p["m"] * p["g"], p["a"]
    ks = list(range(12 * N_PER_DECADE, 1 * N_PER_DECADE - 1, -1))
    out = {}
    xs = []
    for k in ks:
        EI_si = 10.0 ** (k / N_PER_DECADE)
        EI = EI_si / (P * a * a)
        if len(xs) >= 3:
            guess = 3 * xs[-1] - 3 * xs[-2] + xs[-3]
        elif len(xs) >= 1:
            guess = xs[-1]
        else:
            guess = _hinge_guess(kind, EI_si, p)
        x = st.solve(EI, guess)
        xs.append(x)
        out[k] = x
    return out


def _key(p):
    return tuple(sorted(p.items()))


def solve_structure(kind, EI, **params):
    """Reference solution of 'slider' (beam-slider) or 'fixed' (beam-fixed) at EI [N m^2], SI units.

    Principal branch by continuation in EI (cached per geometry); EI in [1e1, 1e12].
    """
    p = {**DEFAULTS, **params}
    if kind == "slider":
        p.setdefault("L", None)
    else:
        p.pop("L", None)
    st = _Structure(kind, **p)
    P, a = p["m"] * p["g"], p["a"]
    path = _path(kind, _key(p))
    t = math.log10(EI) * N_PER_DECADE
    k_near = min(path, key=lambda k: abs(k - t))
    # start from the nearest continuation point (a Newton step or a few of them away)
    kk = sorted(path, key=lambda k: abs(k - t))[:3]
    if abs(k_near - t) < 1e-9:
        x = path[k_near]
    else:
        # quadratic interpolation in log EI of the three nearest path points as start
        ks = np.array(kk, float)
        X = np.array([path[k] for k in kk])
        guess = np.array([np.polyval(np.polyfit(ks, X[:, i], 2), t) for i in range(3)])
        x = st.solve(EI / (P * a * a), guess)
    return st.result(x, EI / (P * a * a))


def beam_slider(EI, **params):
    return solve_structure("slider", EI, **params)


def beam_fixed(EI, **params):
    return solve_structure("fixed", EI, **params)


# -- cantilevers --------------------------------------------------------------------------------------

def cantilever_moment(m_ratio, L=1.0, EI=1.0):
    """Tip (u, v, theta) of a cantilever under the end moment m_ratio * 2 pi EI / L (exact circle)."""
    theta = m_ratio * 2.0 * math.pi
    if theta == 0.0:
        return {"u": 0.0, "v": 0.0, "theta": 0.0, "M_max": 0.0}
    R = L / theta
    return {"u": R * math.sin(theta) - L, "v": R * (1.0 - math.cos(theta)), "theta": theta,
            "M_max": abs(theta) * EI / L}


def cantilever_load(p_ratio, L=1.0, EI=1.0):
    """Tip (u, v, theta) of a cantilever under a transverse dead tip load p_ratio * EI / L^2 (elliptic
    integrals; u is the displacement along the undeformed axis, i.e. minus the shortening)."""
    alpha = float(p_ratio)
    if alpha == 0.0:
        return {"u": 0.0, "v": 0.0, "theta": 0.0, "M_max": 0.0}
    sa = math.sqrt(alpha)

    def F(m):
        phi0 = math.asin(min(1.0, 1.0 / math.sqrt(2.0 * m)))
        return special.ellipk(m) - special.ellipkinc(phi0, m) - sa

    m = optimize.brentq(F, 0.5, 1.0 - 1e-15, xtol=1e-16, rtol=4 * np.finfo(float).eps, maxiter=500)
    phi0 = math.asin(1.0 / math.sqrt(2.0 * m))
    sin_t = 2.0 * m - 1.0
    theta = math.asin(sin_t)
    v = 1.0 - 2.0 * (special.ellipe(m) - special.ellipeinc(phi0, m)) / sa
    x = math.sqrt(2.0 * sin_t / alpha)
    P = alpha * EI / L ** 2
    return {"u": (x - 1.0) * L, "v": v * L, "theta": theta, "M_max": P * x * L, "k2": m}


def cantilever_load_shooting(p_ratio, L=1.0, EI=1.0, EA=None):
    """The same tip-load cantilever by the Taylor shooting above (a check of both references):
    the rod is integrated from the moment-free tip (where the load (0, P) acts) to the clamp, with the
    tip angle as the unknown and theta(clamp) = 0 as the condition.  ``EA`` [N] finite: the
    extensible elastica (femslide's default EA = 1e6 EI is finite)."""
    P = p_ratio * EI / L ** 2

    # integrate from the tip backwards: reverse arc length, tangent angle theta + pi
    def res(tt):
        sh = shoot(tt + math.pi, 0.0, P, EI, L, EA)
        return sh.theta - math.pi, sh

    t = optimize.brentq(lambda tt: float(np.real(res(tt)[0])), 0.0, 0.5 * math.pi - 1e-12, xtol=1e-16,
                        rtol=4 * np.finfo(float).eps)
    _, sh = res(t)
    # the clamp sits at (-u_rev, -w_rev) from the tip; tip relative to the clamp:
    xt, yt = -float(np.real(sh.u)), -float(np.real(sh.w))
    return {"u": xt - L, "v": yt, "theta": t, "M_max": P * xt}
