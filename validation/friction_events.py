"""Exact event-driven motion of a linear few-degree-of-freedom structure with one Coulomb friction
contact: an independent reference for femslide's friction dynamics (numpy and scipy only).

The system (SI units; coordinates x relative to the moving ground, from :mod:`linear_dynamics`):

    M x'' + C x' + K x = f_g a_g(t) + F e_b,

F [N] the friction force of the ground (or of the other part) on the coordinate x_b, the slide, under
a constant normal force N [N] (known exactly in the cases built here: the weight carried by a slider
whose vertical motion and rotation are locked), static coefficient mu0 >= kinetic mu:

* stick: x_b' = 0 and F = F_req, the force that keeps x_b'' = 0; it lasts while |F_req| <= mu0 N;
  breakaway when |F_req| reaches mu0 N, into slip in the direction sigma = -sign(F_req);
* slip in the direction sigma (x_b' sigma > 0): F = -sigma mu N; it ends when x_b' returns to zero:
  there the contact sticks if |F_req| <= mu0 N, else it slips on in the direction -sign(F_req) (a
  reversal: the kinetic force alone could not have stopped it).

Between events the motion is linear with a forcing that is itself the solution of a linear ODE: the
base acceleration a_g(t) = a_rec(t) + A sin(W t), a_rec linear between the samples of a record
(a_rec' constant, reset at each sample), and the constant friction force.  With the augmented state
z = (x, v, a_rec, a_rec', sin W t, cos W t, 1) the motion is z' = A_mode z, solved exactly by the
matrix exponential z(t0 + tau) = expm(A_mode tau) z(t0) (:func:`expm_batch`: Taylor with scaling and
squaring, vectorised; round-off ~1e-15 per step, checked against scipy.linalg.expm in the tests).
Event functions are linear in z:

* slip: g = sigma x_b' (crossing from > 0 to <= 0);
* stick: g+- = mu0 N -+ F_req (either crossing to < 0), F_req = c . z from the stuck equations.

They are checked on substeps of at most ``h`` [s] (and at every record sample), including a turning
point of g inside a substep (a sign change of g', located, where g is tested: a double crossing
between two samples is found too), and located by Brent's method to 1e-13 s.  The substep is a
numerical parameter only for *finding* events (the propagation is exact at any length): the tests
halve it and get the same events.

Output: the event list [(t, kind)] ("stick", "slip+", "slip-"; the first at t = 0 is the contact's
state at the start, as femslide lists it), and the state at any times (:meth:`Solution.state`),
from the stored knots by one more matrix exponential.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import brentq

KINDS = {0: "stick", 1: "slip+", -1: "slip-"}


def expm_batch(A, taus, chunk=2048):
    """expm(A tau) for every tau of ``taus`` (k,): (k, n, n).  A is balanced first (LAPACK gebal
    through scipy.linalg.matrix_balance: a diagonal similarity, exact in floating point, that evens
    out the rows and columns of a matrix whose states have different units, e.g. positions and
    velocities of stiff modes), then scaling and squaring with a Taylor polynomial of degree 18 on
    ||B tau / 2^s||_1 <= 1/2 (truncation < 1e-22), vectorised over tau (scipy's expm treats a stack
    one matrix at a time); the squarings are common to a chunk."""
    taus = np.atleast_1d(np.asarray(taus, float))
    n = A.shape[0]
    B, T = _balanced(A)
    d = np.diag(T)
    out = np.empty((taus.size, n, n))
    nB = float(np.abs(B).sum(axis=0).max())
    I = np.eye(n)
    for lo in range(0, taus.size, chunk):
        tau = taus[lo:lo + chunk]
        big = nB * float(np.abs(tau).max(initial=0.0))
        sq = max(0, int(math.ceil(math.log2(big / 0.5)))) if big > 0.5 else 0
        X = B[None, :, :] * (tau / 2.0 ** sq)[:, None, None]
        E = I + X / 18.0
        for k in range(17, 0, -1):
            E = I + (X @ E) / k
        for _ in range(sq):
            E = E @ E
        out[lo:lo + chunk] = d[None, :, None] * E / d[None, None, :]
    return out


_BALANCED = {}


def _balanced(A):
    key = (A.shape, A.tobytes())
    if key not in _BALANCED:
        from scipy.linalg import matrix_balance
        if len(_BALANCED) > 32:
            _BALANCED.clear()
        _BALANCED[key] = matrix_balance(A, permute=False)
    return _BALANCED[key]


def expm1(A, tau):
    """expm(A tau) of one tau (see :func:`expm_batch`)."""
    return expm_batch(A, [tau])[0]


@dataclass
class Ground:
    """a_g(t) = record(t) * scale + amplitude sin(2 pi frequency t) [m/s^2]; the record (times [s],
    values [m/s^2]) linear between samples, zero outside them (femslide's convention)."""

    amplitude: float = 0.0
    frequency: float = 0.0
    times: np.ndarray | None = None
    values: np.ndarray | None = None
    scale: float = 1.0

    @property
    def W(self):
        return 2 * math.pi * self.frequency

    def rec_piece(self, t):
        """(a, slope, t_next): the record on [t, t_next) is a + slope (s - t)."""
        if self.times is None:
            return 0.0, 0.0, math.inf
        rt, rv = self.times, self.values * self.scale
        i = int(np.searchsorted(rt, t, side="right")) - 1
        if i < 0:
            return 0.0, 0.0, float(rt[0])
        if i >= rt.size - 1:
            return 0.0, 0.0, math.inf
        q = (rv[i + 1] - rv[i]) / (rt[i + 1] - rt[i])
        return float(rv[i] + q * (t - rt[i])), float(q), float(rt[i + 1])

    def accel(self, t):
        t = np.asarray(t, float)
        a = self.amplitude * np.sin(self.W * t)
        if self.times is not None:
            inside = (t >= self.times[0]) & (t <= self.times[-1])
            a = a + np.where(inside, np.interp(t, self.times, self.values * self.scale), 0.0)
        return a


@dataclass
class Solution:
    """The motion: ``events`` [(t, kind)], knots (t_k, z_k, mode_k) from which the state at any time
    follows exactly, and the model (to evaluate outputs)."""

    system: "FrictionSystem"
    events: list = field(default_factory=list)
    knot_t: list = field(default_factory=list)
    knot_z: list = field(default_factory=list)
    knot_mode: list = field(default_factory=list)

    def state(self, t):
        """x (m, len(t)), v (m, len(t)) at the times t (within [0, t_end])."""
        t = np.atleast_1d(np.asarray(t, float))
        kt = np.array(self.knot_t)
        idx = np.clip(np.searchsorted(kt, t, side="right") - 1, 0, kt.size - 1)
        m = self.system.m
        X = np.zeros((m, t.size))
        V = np.zeros((m, t.size))
        modes = np.array(self.knot_mode)[idx]
        Zk = np.array(self.knot_z)
        for mode in np.unique(modes):
            sel = np.nonzero(modes == mode)[0]
            E = expm_batch(self.system.A[int(mode)], t[sel] - kt[idx[sel]])
            Z = np.einsum("kij,kj->ki", E, Zk[idx[sel]])
            X[:, sel] = Z[:, :m].T
            V[:, sel] = Z[:, m:2 * m].T
        return X, V

    def kinds(self):
        return [k for _, k in self.events]

    def times(self):
        return np.array([t for t, _ in self.events])


class FrictionSystem:
    """M x'' + C x' + K x = f_g a_g(t) + F e_b with Coulomb friction on x_b (module docstring).

    M, C, K (m, m) [kg, N s/m, N/m in the coordinates' units], f_g (m,) the generalised force of a
    unit base acceleration, ``slide`` the index b of the friction coordinate, N [N], mu, mu0."""

    def __init__(self, M, C, K, f_g, slide, N, mu, mu0, ground: Ground):
        self.Mm, self.Cm, self.Km = (np.asarray(a, float) for a in (M, C, K))
        self.f = np.asarray(f_g, float)
        self.b = int(slide)
        self.N, self.mu, self.mu0 = float(N), float(mu), float(mu0)
        if not 0.0 <= self.mu <= self.mu0:
            raise ValueError("need 0 <= mu <= mu0")
        self.ground = ground
        m = self.m = self.f.size
        self.nz = 2 * m + 5
        self.i_rec, self.i_slope, self.i_sin, self.i_cos, self.i_one = 2 * m, 2 * m + 1, 2 * m + 2, 2 * m + 3, 2 * m + 4
        self.A = {s: self._matrix(s) for s in (0, 1, -1)}
        self.c_req = self._required_force_row()

    # -- the linear pieces --------------------------------------------------------------------------
    def _forcing_rows(self, A, rows, Minv_rows):
        """Fill the accelerations of the coordinates ``rows`` given Minv_rows = (M_rr)^-1."""
        m = self.m
        _W, Amp = self.ground.W, self.ground.amplitude
        A[np.ix_(m + rows, np.arange(m))] = -Minv_rows @ self.Km[rows]
        A[np.ix_(m + rows, m + np.arange(m))] = -Minv_rows @ self.Cm[rows]
        fr = Minv_rows @ self.f[rows]
        A[m + rows, self.i_rec] = fr
        A[m + rows, self.i_sin] = fr * Amp

    def _matrix(self, sigma):
        m, b = self.m, self.b
        A = np.zeros((self.nz, self.nz))
        A[np.arange(m), m + np.arange(m)] = 1.0
        W = self.ground.W
        A[self.i_rec, self.i_slope] = 1.0
        A[self.i_sin, self.i_cos] = W
        A[self.i_cos, self.i_sin] = -W
        if sigma == 0:
            o = np.array([i for i in range(m) if i != b], int)
            if o.size:
                A[np.ix_(m + o, np.arange(m))] = 0.0
                self._forcing_rows(A, o, np.linalg.inv(self.Mm[np.ix_(o, o)]))
            A[b, :] = 0.0                  # x_b' = 0, v_b' = 0: locked
            A[m + b, :] = 0.0
        else:
            rows = np.arange(m)
            Minv = np.linalg.inv(self.Mm)
            self._forcing_rows(A, rows, Minv)
            A[m + rows, self.i_one] = Minv @ (-sigma * self.mu * self.N * np.eye(m)[self.b])
        return A

    def _required_force_row(self):
        """c (nz,): F_req = c . z, the force on x_b that keeps it at rest (stuck equations)."""
        m, b = self.m, self.b
        A0 = self.A[0]
        c = np.zeros(self.nz)
        # row b of M x'' + C v + K x - f a_g = F with x_b'' = 0 and x_o'' from the stuck motion
        o = np.array([i for i in range(m) if i != b], int)
        for j, Mbj in zip(o, self.Mm[b, o]):
            c += Mbj * A0[m + j]
        c[m:2 * m] += self.Cm[b]
        c[:m] += self.Km[b]
        c[self.i_rec] -= self.f[b]
        c[self.i_sin] -= self.f[b] * self.ground.amplitude
        return c

    # -- the run --------------------------------------------------------------------------------------
    def solve(self, t_end, h, x0=None, v0=None, max_events=100000):
        """The motion from (x0, v0) (default rest) at t = 0, stuck at the start unless the
        required force already exceeds mu0 N; events checked on substeps <= h [s]."""
        m, g = self.m, self.ground
        z = np.zeros(self.nz)
        if x0 is not None:
            z[:m] = x0
        if v0 is not None:
            z[m:2 * m] = v0
        a, q, t_next = g.rec_piece(0.0)
        z[self.i_rec], z[self.i_slope] = a, q
        z[self.i_sin], z[self.i_cos], z[self.i_one] = 0.0, 1.0, 1.0
        sol = Solution(self)
        mode = 0
        if abs(self.c_req @ z) > self.mu0 * self.N or abs(z[m + self.b]) > 0:
            mode = int(np.sign(z[m + self.b])) or -int(np.sign(self.c_req @ z))
        sol.events.append((0.0, KINDS[mode]))
        t = 0.0
        cache = {}

        def E(mode_, tau):
            key = (mode_, tau)
            if key not in cache:
                if len(cache) > 64:
                    cache.clear()
                cache[key] = expm1(self.A[mode_], tau)
            return cache[key]

        while t < t_end - 1e-15:
            sol.knot_t.append(t)
            sol.knot_z.append(z.copy())
            sol.knot_mode.append(mode)
            t1 = min(t + h, t_next, t_end)
            tau = t1 - t
            z1 = E(mode, tau) @ z
            hit = self._first_event(mode, z, z1, tau)
            if hit is None:
                t, z = t1, z1
                if t == t_next and t < t_end:       # a record sample: the new slope
                    a, q, t_next = g.rec_piece(t)
                    z[self.i_rec], z[self.i_slope] = a, q
                continue
            tau_e, which = hit
            ze = expm1(self.A[mode], tau_e) @ z
            te = t + tau_e
            new = self._switch(mode, which, ze)
            if mode != 0:
                ze[m + self.b] = 0.0          # the velocity of the slide is exactly zero at a stop
            mode, t, z = new, te, ze
            if sol.events and abs(te - sol.events[-1][0]) < 1e-12 and sol.events[-1][1] == KINDS[mode]:
                raise RuntimeError(f"duplicate event at t = {te}")
            sol.events.append((te, KINDS[mode]))
            if len(sol.events) > max_events:
                raise RuntimeError("too many events")
        sol.knot_t.append(t)
        sol.knot_z.append(z.copy())
        sol.knot_mode.append(mode)
        return sol

    def _gfuns(self, mode):
        """Rows (k, nz) of the event functions of ``mode`` (each > 0 while the mode lasts)."""
        m, b = self.m, self.b
        if mode == 0:
            lim = np.zeros(self.nz)
            lim[self.i_one] = self.mu0 * self.N
            return np.array([lim - self.c_req, lim + self.c_req])
        r = np.zeros(self.nz)
        r[m + b] = mode
        return r[None, :]

    def _first_event(self, mode, z0, z1, tau):
        """(tau_e, which) of the first event function crossing to <= 0 in (0, tau], or None."""
        G = self._gfuns(mode)
        A = self.A[mode]
        g0, g1 = G @ z0, G @ z1
        d0, d1 = G @ (A @ z0), G @ (A @ z1)
        best = None
        for k in range(G.shape[0]):
            row = G[k]

            def g(s, row=row):
                return float(row @ (expm1(A, s) @ z0))

            lo = 0.0
            cand = None
            if g1[k] <= 0.0 < g0[k] or (g0[k] <= 0.0 and g1[k] < 0.0 and d0[k] < 0.0):
                # (g0 = 0 with g falling: a contact that leaves its mode at once, e.g. after a switch)
                if g0[k] > 0.0:
                    cand = brentq(g, lo, tau, xtol=1e-14, rtol=4 * np.finfo(float).eps, maxiter=200)
                else:
                    cand = 0.0
            elif g0[k] >= 0.0 and g1[k] > 0.0 and d0[k] < 0.0 < d1[k]:
                # a minimum of g inside the substep: is g negative there?
                def dg(s, row=row):
                    return float(row @ (A @ (expm1(A, s) @ z0)))
                s_min = brentq(dg, 0.0, tau, xtol=1e-14, rtol=4 * np.finfo(float).eps, maxiter=200)
                if g(s_min) < 0.0:
                    cand = brentq(g, 0.0, s_min, xtol=1e-14, rtol=4 * np.finfo(float).eps, maxiter=200) \
                        if g0[k] > 0.0 else 0.0
            if cand is not None and (best is None or cand < best[0]):
                best = (cand, k)
        return best

    def _switch(self, mode, which, ze):
        """The mode after the event ``which`` of ``mode`` at the state ze."""
        F = float(self.c_req @ self._at_rest(ze))
        if mode == 0:                     # breakaway: |F_req| reached mu0 N
            return -int(np.sign(F)) or (1 if which == 1 else -1)
        if abs(F) <= self.mu0 * self.N:   # the slide stops: static friction holds it
            return 0
        return -int(np.sign(F))           # reversal

    def _at_rest(self, z):
        z = z.copy()
        z[self.m + self.b] = 0.0
        return z
