"""Independent references for the one-mass friction oscillator (femslide/scenes/sdof.py is NOT used here).

* :func:`decrement_turning_points` - exact free vibration with Coulomb friction (c_v = 0): the
  amplitude drops by 2 mu N/k per half-swing, turning points at j pi/omega, stop at the first
  turning point inside the dead zone |w| <= mu0 N/k.
* :func:`den_hartog` - Den Hartog's (1931) exact steady state without stops of
  m w'' + k w + f sgn(w') = P0 sin(theta t), derived from the half-period symmetry
  w(t + pi/theta) = -w(t): X = sqrt((P0/k)^2/(1 - r^2)^2 - (f/k)^2 (tan(pi/(2r))/r)^2); its turning
  points sit at the forcing phase psi with X = -B sin(psi), B = P0/(k(1 - r^2)).
  :func:`den_hartog_is_stop_free` checks that this motion really has no stops (velocity of one sign
  over the half-cycle, net force beyond mu0 N at the turning points).
* :func:`formula6` - the paper's equivalent-linearisation amplitude (6) (approximate).
* :func:`ivp_simulate` - a scipy ``solve_ivp`` integrator with event switching (velocity zero ->
  stick/reverse decision; while stuck, breakaway event |F - k w| = mu0 N), an independent code.
* :func:`paper_recurrence` - the paper's first-order recurrence (7)-(9) with Newmark (average
  acceleration) coefficients, friction lagging one step (sgn of the previous velocity), plus a
  stick rule.

SI units throughout: m [kg], k [N/m], forces [N], w [m], t [s].
"""
from __future__ import annotations

import math

import numpy as np


def decrement_turning_points(w0, k, m, mu, mu0, N):
    """Exact (t_j, w_j) of the free motion from rest at w0 (c_v = 0), ending with the stop."""
    omega = math.sqrt(k / m)
    fs, delta = mu0 * N, 2.0 * mu * N / k
    out, a, sign, j = [], abs(w0), (1.0 if w0 > 0 else -1.0), 0
    if k * a <= fs:
        return out
    while True:  # a may turn negative on the last half-swing (ends on the side it started from)
        j += 1
        a = a - delta
        sign = -sign
        out.append((j * math.pi / omega, sign * a))
        if k * abs(a) <= fs:
            break
    return out


def den_hartog(r, P0, k, f):
    """Steady amplitude X [m] of the stop-free motion (None when the formula has no real value)."""
    if r == 1.0:
        return None
    B = P0 / (k * (1.0 - r * r))
    U = math.tan(math.pi / (2.0 * r)) / r
    val = B * B - (f / k * U) ** 2
    return math.sqrt(val) if val > 0 else None


def den_hartog_is_stop_free(r, P0, k, m, f, fs, n=2001):
    """True if Den Hartog's motion has one-signed velocity on each half-cycle and does not stick."""
    X = den_hartog(r, P0, k, f)
    if X is None:
        return False
    omega = math.sqrt(k / m)
    th = r * omega
    B = P0 / (k * (1.0 - r * r))
    sinpsi = -X / B
    cospsi_sq = 1.0 - sinpsi * sinpsi
    # cos(psi) = -(f/k) tan(pi/(2r)) / (B r)
    cospsi = -(f / k) * math.tan(math.pi / (2.0 * r)) / (B * r)
    if abs(cospsi * cospsi - cospsi_sq) > 1e-9:
        return False
    psi = math.atan2(sinpsi, cospsi)
    # half-cycle from w = -X upwards with friction -f:  w = -f/k + B sin(th tau + psi) + C1 cos + C2 sin
    C1, C2 = f / k, -B * r * math.cos(psi)
    tau = np.linspace(0.0, math.pi / th, n)[1:-1]
    v = B * th * np.cos(th * tau + psi) - omega * C1 * np.sin(omega * tau) + omega * C2 * np.cos(omega * tau)
    if np.any(v <= 0):
        return False
    net = r * r * k * X  # |F - k w| at the turning point
    return net > fs


def formula6(r, P0, k, f):
    """The paper's formula (6): X = (P0/k) sqrt(1 - (4 f/(pi P0))^2)/|1 - r^2|."""
    return P0 / k * math.sqrt(1.0 - (4.0 * f / (math.pi * P0)) ** 2) / abs(1.0 - r * r)


# ---------------------------------------------------------------------------------------------
# solve_ivp with event switching
# ---------------------------------------------------------------------------------------------

class IvpResult:
    def __init__(self):
        self.turning = []   # (t, w)
        self.stop = None
        self.pieces = []    # (t0, t1, callable t -> w)
        self.nfev = 0


def ivp_simulate(m, k, c, mu, mu0, g, w0, A=0.0, theta=0.0, t_end=5.0, rec=None,
                 method="DOP853", rtol=1e-12, atol=1e-15, dense=True):
    """Integrate with scipy and switch modes at events; returns :class:`IvpResult`.

    F(t) = A sin(theta t) [+ record force rec(t) given as (times, forces), linear, split at nodes].
    """
    from scipy.integrate import solve_ivp

    N = m * g
    fk, fs = mu * N, mu0 * N
    rt = np.asarray(rec[0]) if rec is not None else None
    rF = np.asarray(rec[1]) if rec is not None else None

    def Fval(t):
        val = A * math.sin(theta * t)
        if rt is not None and rt[0] <= t < rt[-1]:
            val += float(np.interp(t, rt, rF))
        return val

    res = IvpResult()
    breaks = [] if rt is None else [float(x) for x in rt]
    t, w, v = 0.0, float(w0), 0.0
    G = Fval(0.0) - k * w
    stuck = abs(G) <= fs
    s = 1.0 if G > 0 else -1.0
    guard = 0
    while t < t_end:
        guard += 1
        if guard > 10_000_000:
            raise RuntimeError("too many events")
        t_stop = min([t_end] + [b for b in breaks if b > t + 1e-15])
        if stuck:
            wstuck = w

            def ev(tt, y):
                return abs(Fval(tt) - k * wstuck) - fs
            ev.terminal, ev.direction = True, 1
            if theta > 0 and A != 0:
                sol = solve_ivp(lambda tt, y: [0.0], (t, t_stop), [0.0], events=ev, method="RK45",
                                rtol=1e-10, atol=1e-12, max_step=2 * math.pi / theta / 16)
                res.nfev += sol.nfev
                hit = sol.t_events[0]
            else:
                hit = []
                if rt is not None:
                    ts = np.linspace(t, t_stop, 65)
                    vals = [ev(x, None) for x in ts]
                    for i in range(64):
                        if vals[i + 1] > 0:
                            from scipy.optimize import brentq
                            hit = ([brentq(lambda x: ev(x, None), ts[i], ts[i + 1], xtol=1e-15)] if vals[i] < 0
                                   else [ts[i]])
                            break
            if len(hit):
                tb = float(hit[0])
                res.pieces.append((t, tb, lambda tt, w_=wstuck: np.full_like(np.asarray(tt, float), w_)))
                t = tb
                G = Fval(t) - k * w
                s = 1.0 if G > 0 else -1.0
                stuck, v = False, 0.0
            else:
                res.pieces.append((t, t_stop, lambda tt, w_=wstuck: np.full_like(np.asarray(tt, float), w_)))
                t = t_stop
                if t >= t_end:
                    # forever? (harmonic only: |A| + |k w| <= mu0 N)
                    if abs(A) + abs(k * w) <= fs and (rt is None or t_end >= rt[-1]):
                        res.stop = res.turning[-1] if res.turning else (0.0, w0)
            continue
        sgn = s

        def rhs(tt, y):
            return [y[1], (Fval(tt) - c * y[1] - k * y[0] - sgn * fk) / m]

        def vzero(tt, y):
            return y[1]
        vzero.terminal, vzero.direction = True, -sgn
        sol = solve_ivp(rhs, (t, t_stop), [w, v], method=method, rtol=rtol, atol=atol,
                        events=vzero, dense_output=dense)
        res.nfev += sol.nfev
        if dense:
            res.pieces.append((t, float(sol.t[-1]), lambda tt, so=sol: so.sol(tt)[0]))
        if sol.status == 1:
            t = float(sol.t_events[0][0])
            w = float(sol.y_events[0][0][0])
            v = 0.0
            res.turning.append((t, w))
            G = Fval(t) - k * w
            if abs(G) <= fs:
                stuck = True
            else:
                s = 1.0 if G > 0 else -1.0
        else:
            t, w, v = float(sol.t[-1]), float(sol.y[0, -1]), float(sol.y[1, -1])
    return res


def ivp_eval(res: IvpResult, t):
    """w at times t from the stored pieces."""
    t = np.atleast_1d(np.asarray(t, float))
    starts = np.array([p[0] for p in res.pieces])
    idx = np.clip(np.searchsorted(starts, t, side="right") - 1, 0, len(starts) - 1)
    out = np.empty_like(t)
    for i in np.unique(idx):
        sel = idx == i
        out[sel] = res.pieces[i][2](t[sel])
    return out


def period_amplitudes(turning, w_at, theta, t_end):
    """(max - min)/2 of w over each complete forcing period [n T, (n+1) T]."""
    T = 2 * math.pi / theta
    n = int(math.floor(t_end / T * (1 + 1e-14)))
    tb = T * np.arange(n + 1)
    wb = w_at(tb)
    wmax = np.maximum(wb[:-1], wb[1:])
    wmin = np.minimum(wb[:-1], wb[1:])
    for t, w in turning:
        i = int(t // T)
        if i < n:
            wmax[i] = max(wmax[i], w)
            wmin[i] = min(wmin[i], w)
    return 0.5 * (wmax - wmin), wmax, wmin


# ---------------------------------------------------------------------------------------------
# the paper's recurrence (7)-(9)
# ---------------------------------------------------------------------------------------------

def paper_recurrence(m, k, c, mu, mu0, g, w0, A=0.0, theta=0.0, t_end=5.0, tau=1e-3,
                     beta=0.25, gamma=0.5):
    """Newmark (beta, gamma) in the form (7)-(9); friction lags one step; stick rule added.

    Returns (t, w, v) arrays.  Stick rule: when the velocity changes sign (or is zero) and
    |F - k w| <= mu0 N, the mass is held (v = a = 0) until |F - k w| exceeds mu0 N.
    """
    N = m * g
    fk, fs = mu * N, mu0 * N
    a1_, a2_, a3_ = 1 / beta, 1 / beta, 1 / (2 * beta) - 1          # alpha_1..3 of (8)
    b1_, b2_, b3_ = gamma / beta, gamma / beta - 1, gamma / (2 * beta) - 1  # beta_1..3 of (7)
    n = int(math.ceil(t_end / tau))
    t = np.arange(n + 1) * tau
    F = A * np.sin(theta * t)
    w = np.empty(n + 1)
    v = np.empty(n + 1)
    w[0], v[0] = w0, 0.0
    stuck = abs(F[0] - k * w0) <= fs
    sgn = 0.0 if stuck else math.copysign(1.0, F[0] - k * w0)
    a = 0.0 if stuck else (F[0] - k * w0 - sgn * fk) / m
    ka = m * a1_ / tau ** 2 + c * b1_ / tau + k
    for i in range(1, n + 1):
        if stuck:
            w[i], v[i] = w[i - 1], 0.0
            G = F[i] - k * w[i]
            if abs(G) > fs:
                stuck = False
                sgn = math.copysign(1.0, G)
                a = (G - sgn * fk) / m
            continue
        rhs = (F[i] - sgn * fk + m * (a1_ * w[i - 1] / tau ** 2 + a2_ * v[i - 1] / tau + a3_ * a)
               + c * (b1_ * w[i - 1] / tau + b2_ * v[i - 1] + tau * b3_ * a))
        wi = rhs / ka
        vi = b1_ * (wi - w[i - 1]) / tau - b2_ * v[i - 1] - tau * b3_ * a
        ai = a1_ * (wi - w[i - 1]) / tau ** 2 - a2_ * v[i - 1] / tau - a3_ * a
        w[i], v[i] = wi, vi
        if vi * v[i - 1] < 0 or vi == 0.0:   # velocity reversed in the step: stick check
            G = F[i] - k * wi
            if abs(G) <= fs:
                stuck, v[i], a = True, 0.0, 0.0
                continue
        sgn = math.copysign(1.0, vi) if vi != 0 else sgn
        a = ai
    return t, w, v


def harmonic_breakaway(g, mu, mu0, A, W):
    """A block at rest on a ground belt with Coulomb friction (static mu0, kinetic mu) under the base
    acceleration A sin(W t) [m/s^2, rad/s]: (t0, t1, w1) - it breaks away when A sin(W t0) = mu0 g,
    slides back with w'' = -a_g + mu g (w' and w integrated in closed form) and sticks at t1 when w' = 0
    again, its slide w1 [m] there (negative: against the base's first push)."""
    from scipy.optimize import brentq
    t0 = math.asin(mu0 * g / A) / W
    t1 = brentq(lambda t: A / W * (math.cos(W * t) - math.cos(W * t0)) + mu * g * (t - t0), t0 + 1e-3, t0 + 0.9)
    w1 = A / W * ((math.sin(W * t1) - math.sin(W * t0)) / W - (t1 - t0) * math.cos(W * t0)) \
        + 0.5 * mu * g * (t1 - t0) ** 2
    return t0, t1, w1
