"""Independent reference for beam-friction (neither femslide's FE transient nor the reduced model of
validation/reduced_dynamics.py is used here).

The structure of ``beam-friction`` (SPEC section 5, femslide's scene description): rigid body ABCD
pinned at A1 = (0, 0) by its rigid left rod (length l), turning by phi (clockwise); a massless
flexible right rod of length L, pinned at B1 = (2a, 0), whose top S is held in a sliding clamp on
the body: S on the body-fixed line through the body point A + 2a n + (L - l) e along the body axis
e = (sin phi, cos phi) (n = (cos phi, -sin phi)), the rod's tangent along e.  The slide s is S's
position along that line (0 in the undeformed structure).  A spring k along the guide with preload
F0 = P (a + d)/(2a), energy k s^2/2 + F0 s, holds the vertical state.  Coulomb friction in the
clamp: N = |transverse clamp force|, the axial guide force F_fr (on the rod top, along e, spring
excluded) obeys |F_fr| <= mu0 N while stuck and F_fr = -sigma mu N while slipping in the direction
sigma = sign(s').  Body inertia about A1: J = m ((2a)^2 + (2b)^2)/12 + m |G - A1|^2, G at body
offset (a + d, b) from A.  Ground acceleration ag sin(theta t) along x.

What differs from femslide (that is the point of it):
* the rod is the extensible elastica solved by shooting (validation/references.py: Taylor series
  of order 30, complex-step Jacobians), not a corotational FE mesh;
* the body is moved by the moment about A1 of gravity, of the ground-acceleration inertia and of
  the rod's force R on the body: a massless rod pinned at B1 acts on the body as R through B1
  (moment B1 x R), not by -dV/dphi of a constrained statics;
* slip: s(phi) from F_fr + sigma mu N = 0 solved together with the rod; slip ends where
  ds/dt = (ds/dphi) phi' changes sign (ds/dphi by implicit differentiation); stuck: s fixed, the
  breakaway where |F_fr| reaches mu0 N.  At t = 0 (at rest in the vertical state, where F_fr =
  N = 0) the clamp holds only if |dF_fr/dphi| <= mu0 |dN/dphi| along the locked path (finite
  differences at phi = +-1e-6).
* scipy solve_ivp (DOP853, rtol 1e-9) with its own event location.

Only :func:`references.shoot` is shared with femslide's validation of the statics (it is itself
independent of femslide).  Converges to the FE model as n_elements grows (O(h^2)).
"""
from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp

DEFAULTS = dict(a=1.0, b=0.5, d=0.2, l=3.0, m=1.0, g=9.81, L=1.5, k=100.0, EI=1e4, EA=1e6, c_v=0.0,
                mu=0.2, mu0=0.24, phi0=0.0, ag=1.0, theta_ratio=1.0, t_end=3.0)


class Model:
    def __init__(self, **p):
        p = {**DEFAULTS, **p}
        self.p = p
        a, P = p["a"], p["m"] * p["g"]
        self.a, self.P = a, P
        self.b, self.d, self.l, self.L = p["b"] / a, p["d"] / a, p["l"] / a, p["L"] / a
        self.EI = p["EI"] / (P * a * a)
        self.EA = p["EA"] / P
        self.k = p["k"] * a / P
        self.F0 = 0.5 * (1.0 + self.d)
        rho2 = (1.0 + self.d) ** 2 + (self.l + self.b) ** 2
        self.J = p["m"] * a * a * (((2.0) ** 2 + (2.0 * self.b) ** 2) / 12.0 + rho2)   # kg m^2
        self.x = np.array([0.0, 0.5 * (1.0 + self.d), 0.0])   # (theta0, R.e, -R.n), warm start
        self.theta = 0.0

    # -- the rod -----------------------------------------------------------------------------------
    def _shoot(self, x):
        """End (u~, w~, theta~) of the rod in the body frame (e, -n) for x = (theta0~, R.e, -R.n).

        The extensible elastica by a Taylor series (the recurrences of references._taylor), with
        the order chosen so that (h omega)^K < 1e-17 (h omega <= 0.4): the stiff rods of this scene
        (h omega ~ 0.02) need K ~ 12, not 30."""
        th0, Re, Rn = x
        om = math.sqrt(math.hypot(float(np.real(Re)), float(np.real(Rn))) / self.EI)
        n = max(2, math.ceil(self.L * om / 0.4))
        h = self.L / n
        ho = max(h * om, 1e-300)
        K = int(min(30, max(8, math.ceil(17.0 / max(-math.log10(ho), 0.4)))))
        th, u, w = complex(th0), 0j, 0j
        EA, EI = self.EA, self.EI
        Re, Rn = complex(Re), complex(Rn)
        cm = __import__("cmath")
        for _ in range(n):   # plain Python numbers: tiny series, faster than numpy calls
            T, U, W = [th] + [0j] * K, [u] + [0j] * K, [w] + [0j] * K
            C, S, D = [cm.cos(th)] + [0j] * K, [cm.sin(th)] + [0j] * K, [0j] * (K + 1)
            for m_ in range(K):
                k = m_ + 1
                T[k] = (Rn * U[m_] - Re * W[m_]) / (EI * k)
                D[m_] = k * T[k]
                cc = sc = ss = sd = cd = 0j
                for i_ in range(k):
                    ci, si, cj, sj, dj = C[i_], S[i_], C[m_ - i_], S[m_ - i_], D[m_ - i_]
                    cc += ci * cj
                    sc += si * cj
                    ss += si * sj
                    sd += si * dj
                    cd += ci * dj
                U[k] = (C[m_] - (Re * cc + Rn * sc) / EA) / k
                W[k] = (S[m_] - (Re * sc + Rn * ss) / EA) / k
                C[k] = -sd / k
                S[k] = cd / k
            th, u, w = (sum(c * h ** i_ for i_, c in enumerate(ser)) for ser in (T, U, W))
        if not np.iscomplexobj(x):
            return u.real, w.real, th.real
        return u, w, th

    def _res(self, x, phi, s):
        u, w, th = self._shoot(x)
        h2 = 4.0 * np.sin(0.5 * phi) ** 2
        return np.array([u - (self.L + s - 2.0 * np.sin(phi)), w + h2, th])

    def _jac(self, x, phi, s):
        J = np.empty((3, 3))
        for j in range(3):
            xc = x.astype(complex)
            xc[j] += 1e-30j
            J[:, j] = np.imag(self._res(xc, phi, s)) / 1e-30
        return J

    def _solve(self, phi, s, x0, sigma=None, mu=0.0):
        """Rod unknowns x (and, with sigma, the slide s with F_fr + sigma mu |R.n| = 0) by a chord
        Newton method (the Jacobian of the last solve is reused while it converges)."""
        x = np.array(x0, float)
        free = sigma is not None
        for _attempt in range(2):
            self._J = self._jac(x, phi, s)      # Newton's first step, then chord steps
            ok = False
            for _ in range(12):
                r = self._res(x, phi, s)
                if free:
                    F = -x[1] + self.k * s + self.F0
                    r = np.append(r, F + sigma * mu * abs(x[2]))
                    A = np.zeros((4, 4))
                    A[:3, :3] = self._J
                    A[0, 3] = -1.0
                    A[3, 1], A[3, 2], A[3, 3] = -1.0, sigma * mu * math.copysign(1.0, x[2]), self.k
                    d = np.linalg.solve(A, -r)
                    x, s = x + d[:3], s + d[3]
                else:
                    d = np.linalg.solve(self._J, -r)
                    x = x + d
                if np.max(np.abs(d)) < max(1e-14, 1e-15 * self.EA):
                    ok = True
                    break
            if ok:
                return x, s
        raise RuntimeError(f"rod shooting did not converge at phi = {phi}, s = {s}")

    def forces(self, phi, s, x0=None):
        """(F_fr, R.n sign-carrying transverse force, R_y) [P] at (phi, s), and the rod unknowns."""
        x, _ = self._solve(phi, s, self.x if x0 is None else x0)
        self.x = x
        return self._out(phi, s, x)

    def _out(self, phi, s, x):
        Re, Rn = x[1], x[2]
        F_fr = -Re + self.k * s + self.F0
        Ry = Re * math.cos(phi) + Rn * math.sin(phi)
        return F_fr, Rn, Ry, x

    def slip_state(self, phi, sigma, mu, s0):
        """(s, F_fr, R.n, R_y) with F_fr = -sigma mu N (N = |R.n|), the rod solved with it."""
        x, s = self._solve(phi, s0, self.x, sigma, mu)
        self.x = x
        F, Rn, Ry, _ = self._out(phi, s, x)
        return s, F, Rn, Ry

    def slip_rate(self, phi, sigma, mu, s0):
        """ds/dphi on the slip path, by implicit differentiation of the 4 equations."""
        s, F, Rn, Ry = self.slip_state(phi, sigma, mu, s0)
        x = self.x
        A = np.zeros((4, 4))
        A[:3, :3] = self._jac(x, phi, s)
        A[0, 3] = -1.0
        A[3, 1], A[3, 2], A[3, 3] = -1.0, sigma * mu * math.copysign(1.0, x[2]), self.k
        dr = np.array([2.0 * math.cos(phi), 2.0 * math.sin(phi), 0.0, 0.0])
        return float(np.linalg.solve(A, -dr)[3]), s

    # -- dynamics ------------------------------------------------------------------------------------
    def accel(self, t, phi, w, Ry, ag):
        """phi'' [rad/s^2] from the moment about A1 (counter-clockwise M, phi clockwise)."""
        Gx = (1.0 + self.d) * math.cos(phi) + (self.l + self.b) * math.sin(phi)
        Gy = -(1.0 + self.d) * math.sin(phi) + (self.l + self.b) * math.cos(phi)
        a_g = ag * math.sin(self.theta * t)
        M = (-Gx + 2.0 * Ry + self.p["m"] * a_g / self.P * Gy) * self.P * self.a
        return (-M - self.p["c_v"] * w) / self.J


def omega_free(model: Model):
    """Small-oscillation frequency of the frictionless structure (slide free) about phi = 0."""
    h = 1e-6
    vals = []
    for ph in (h, -h):
        s, F, Rn, Ry = model.slip_state(ph, 1.0, 0.0, 0.0)
        vals.append(model.accel(0.0, ph, 0.0, Ry, 0.0))
    K = -(vals[0] - vals[1]) / (2 * h)
    return math.sqrt(K)


def simulate(rtol=1e-9, **p):
    """Run the reference; returns dict(t, phi, stuck segments, turning points, events)."""
    m = Model(**p)
    P = m.p
    mu, mu0 = P["mu"], P["mu0"]
    m.theta = 0.0
    om = omega_free(m)
    m.theta = P["theta_ratio"] * om
    ag = P["ag"]
    s0, _, _, _ = m.slip_state(P["phi0"], 1.0, 0.0, 0.0)      # frictionless statics at phi0
    t, phi, w = 0.0, P["phi0"], 0.0
    # t = 0: can the clamp hold the slide locked at s0?
    mode, sigma, s_c = "stuck", 0.0, s0
    F0_, Rn0, _, _ = m.forces(phi, s0)
    if mu0 == 0.0:
        mode = "slip"
    elif abs(F0_) <= 1e-9 and abs(Rn0) <= 1e-9:
        h = 1e-6
        Fp, Np, _, _ = m.forces(phi + h, s0)
        Fm, Nm, _, _ = m.forces(phi - h, s0)
        rate = max(abs(Fp), abs(Fm)) / h - mu0 * min(abs(Np), abs(Nm)) / h
        if rate > 0:
            # the motion starts where the forcing pushes: sign of phi'' just after t = 0
            _, _, Ry, _ = m.forces(phi, s0)
            d = math.copysign(1.0, m.accel(1e-6, phi, 0.0, Ry, ag))
            Fd = Fp if d > 0 else Fm
            sigma = -math.copysign(1.0, Fd)
            mode = "slip"
    elif abs(F0_) > mu0 * abs(Rn0):
        sigma, mode = -math.copysign(1.0, F0_), "slip"
    s_cur = s0
    turning = []
    segs = []
    while t < P["t_end"] * (1 - 1e-12):
        if mode == "stuck":
            def rhs(tt, z):
                _, _, Ry, _ = m.forces(z[0], s_c)
                return [z[1], m.accel(tt, z[0], z[1], Ry, ag)]

            def ev(tt, z):
                F, Rn, _, _ = m.forces(z[0], s_c)
                return abs(F) - mu0 * abs(Rn) - 1e-10
            ev.terminal, ev.direction = True, 1
        else:
            sg = sigma
            state = {"s": s_cur}

            def rhs(tt, z, sg=sg, state=state):
                s, F, Rn, Ry = m.slip_state(z[0], sg, mu, state["s"])
                state["s"] = s
                return [z[1], m.accel(tt, z[0], z[1], Ry, ag)]

            def ev(tt, z, sg=sg, state=state):
                ds, s = m.slip_rate(z[0], sg, mu, state["s"])
                return sg * ds * z[1]
            ev.terminal, ev.direction = True, -1
            if mu0 == 0.0:
                ev.terminal = False

        def turn(tt, z):
            return z[1]
        sol = solve_ivp(rhs, (t, P["t_end"]), [phi, w], method="DOP853", rtol=rtol, atol=1e-13,
                        events=[turn, ev], dense_output=True)
        if sol.status < 0:
            raise RuntimeError(sol.message)
        segs.append((t, float(sol.t[-1]), mode, sigma, sol.sol))
        for a, b in zip(sol.t_events[0], sol.y_events[0]):   # (a segment's end is the next one's start)
            if a > 1e-12 and (not turning or a > turning[-1][0] + 1e-9):
                turning.append((float(a), float(b[0])))
        t, phi, w = float(sol.t[-1]), float(sol.y[0, -1]), float(sol.y[1, -1])
        if sol.status != 1:
            break
        if mode == "stuck":
            F, Rn, _, _ = m.forces(phi, s_c)
            sigma, mode = -math.copysign(1.0, F), "slip"
            s_cur = s_c
            s_cur, *_ = m.slip_state(phi, sigma, mu, s_cur)
        else:
            s_c, *_ = m.slip_state(phi, sigma, mu, s_cur)
            mode, sigma = "stuck", 0.0
    return {"segments": segs, "turning": turning, "omega": om, "theta": m.theta}


def phi_at(ref, t):
    t = np.atleast_1d(np.asarray(t, float))
    out = np.empty_like(t)
    for i, x in enumerate(t):
        for (a, b, _, _, so) in ref["segments"]:
            if a <= x <= b:
                out[i] = so(x)[0]
                break
    return out


def stuck_time(ref):
    return sum(b - a for a, b, md, _, _ in ref["segments"] if md == "stuck")
