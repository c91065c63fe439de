"""The one-mass Coulomb-friction oscillator integrated exactly, event by event (SPEC section 5).

Model (SI units: m [kg], k [N/m], c_v [N s/m], forces [N], w [m], t [s])::

    m w'' + c_v w' + k w + f = F(t),      N = m g,
    F(t) = P0 sin(theta t) - m ag sin(theta t) - m a_rec(t),     theta = theta_ratio * omega,

``w`` is the displacement of the mass relative to its base, ``F`` the applied force (for base
excitation the inertia force of the moving frame) and ``f`` the friction force: mu N sgn(w') while
sliding; at rest the mass sticks while |F - k w| <= mu0 N, else it slides towards the net force.
Between events the equation is linear with a constant friction force and a forcing that is a sine
plus a linear function of time, so :class:`Oscillator` solves each segment in closed form and finds
the events on it (femslide.scenes.sdof has the full description); :class:`Forcing` is F(t).
"""
from __future__ import annotations

import bisect
import math

import numpy as np

from femslide.analysis.events import first_up
from femslide.errors import BadInput, SolverFailure
from femslide.scenes.oscillator_solution import Solution

TWO_PI = 2.0 * math.pi
MAX_STEPS = 5_000_000   # closed-form segments before the run is declared failed (a safety net: the
                        # a-priori bound femslide.scenes.catalog.sdof.MAX_PERIODS is far lower)


class Forcing:
    """F(t) = A sin(theta t) + R(t) [N], R a :class:`femslide.analysis.excitation.Record` (linear
    between its samples, 0 outside them) or None."""

    def __init__(self, A=0.0, theta=0.0, record=None):
        self.A = float(A)
        self.theta = float(theta)
        self.harmonic = self.A != 0.0 and self.theta > 0.0
        if not self.harmonic:
            self.A = 0.0
        self.record = record
        self.has_record = record is not None
        self.forced = self.harmonic or self.has_record

    def piece(self, t):
        """(p, q, t_next): R(t + tau) = p + q tau until the next record node t_next."""
        if self.record is None:
            return 0.0, 0.0, math.inf
        return self.record.piece(t)

    def record_value(self, t):
        p, q, _ = self.piece(t)
        return p

    def value(self, t):
        F = self.record_value(t) if self.has_record else 0.0
        if self.harmonic:
            F += self.A * math.sin(self.theta * t)
        return F

    def slope(self, t):
        d = self.piece(t)[1] if self.has_record else 0.0
        if self.harmonic:
            d += self.A * self.theta * math.cos(self.theta * t)
        return d

    def eval_np(self, t):
        t = np.asarray(t, dtype=float)
        F = self.record.eval_np(t) if self.has_record else np.zeros_like(t)
        if self.harmonic:
            F = F + self.A * np.sin(self.theta * t)
        return F


class Oscillator:
    """Exact event-driven solution of the friction oscillator (see module docstring)."""

    def __init__(self, m, k, c_v, mu, mu0, g, forcing: Forcing):
        if not (m > 0 and k > 0):
            raise BadInput("the one-mass oscillator needs m > 0 and k > 0")
        self.m, self.k, self.c = float(m), float(k), float(c_v)
        self.N = self.m * float(g)
        self.fk = float(mu) * self.N      # kinetic friction force [N]
        self.fs = float(mu0) * self.N     # static friction limit [N]
        self.F = forcing
        self.omega = math.sqrt(self.k / self.m)
        self.sigma = self.c / (2.0 * self.m)
        om, sig = self.omega, self.sigma
        # omega_d or omega_h from the ratio (no overflow of omega^2 or sigma^2, no cancellation)
        if sig < om:
            r = sig / om
            self.kind, self.wd = 0, om * math.sqrt((1.0 - r) * (1.0 + r))   # under-damped (or undamped)
        elif sig == om:
            self.kind, self.wd = 1, 0.0                     # critically damped
        else:
            r = om / sig
            self.kind, self.wd = 2, sig * math.sqrt((1.0 - r) * (1.0 + r))  # over-damped (wd = omega_h)
        # over-damped rates: slow r1 = wd - sigma = -omega^2/(sigma + wd) (computed so: the
        # difference cancels for sigma >> omega), fast r2 = -(sigma + wd)
        self.r1 = -om * (om / (sig + self.wd)) if self.kind == 2 else 0.0
        self.r2 = -(sig + self.wd) if self.kind == 2 else 0.0
        periods = [TWO_PI / (self.wd if self.kind == 0 else self.omega)]
        if forcing.harmonic:
            periods.append(TWO_PI / forcing.theta)
        self.h_scan = min(periods) / 8.0
        th = forcing.theta
        if forcing.harmonic and self.c > 0.0:
            re, im = self.k - self.m * th * th, self.c * th
            h = math.hypot(re, im)
            self.B1 = forcing.A * (re / h) / h
            self.B2 = -forcing.A * (im / h) / h
        else:
            self.B1 = self.B2 = 0.0

    # -- closed form of one segment --------------------------------------------------------------
    def coefficients(self, ts, w0, v0, fc, q):
        """Segment constants for a start (ts, w0, v0), constant force fc [N] and slope q [N/s].

        ``fc`` includes the friction force (-s mu N) and the record part at ts.  Returns
        (x0, u0, a0, a1, phi): homogeneous initial values, linear particular solution a0 + a1 tau,
        forcing phase phi = theta ts (mod 2 pi).
        """
        k = self.k
        a1 = q / k
        a0 = (fc - self.c * a1) / k
        phi = math.fmod(self.F.theta * ts, TWO_PI) if self.F.harmonic else 0.0
        x0, u0 = w0 - a0, v0 - a1
        if self.B1 or self.B2:
            sp, cp = math.sin(phi), math.cos(phi)
            x0 -= self.B1 * sp + self.B2 * cp
            u0 -= self.F.theta * (self.B1 * cp - self.B2 * sp)
        return x0, u0, a0, a1, phi

    def segment(self, x0, u0, a0, a1, phi, s_fric, fc_const_only=False):
        """Closure tau -> (w, v, a) for a sliding segment (s_fric = friction direction, +-1)."""
        sig, om, wd, kind = self.sigma, self.omega, self.wd, self.kind
        om2 = om * om
        m, c, k = self.m, self.c, self.k
        F = self.F
        A, th = F.A, F.theta
        harm = F.harmonic
        xs = u0 + sig * x0
        xv = sig * u0 + om2 * x0
        # constant + linear part of the force (record + friction) for the acceleration
        fconst = k * a0 + c * a1   # = fc
        fq = k * a1                # = q
        cos_, sin_, exp_ = math.cos, math.sin, math.exp
        if harm and c == 0.0:
            Am = A / m / (om + th)
            P, M = 0.5 * (om + th), 0.5 * (om - th)
            sph, cph = sin_(phi), cos_(phi)
            opt = om + th

            def fd(tau):
                cw, sw = cos_(om * tau), sin_(om * tau)
                sP, cP = sin_(P * tau), cos_(P * tau)
                if M != 0.0:
                    Sh = sin_(M * tau) / (2.0 * M)
                    cM = cos_(M * tau)
                else:
                    Sh, cM = 0.5 * tau, 1.0
                w = x0 * cw + xs * sw / om + a0 + a1 * tau \
                    + Am * (sph * 2.0 * sP * Sh + cph * (sw / om - 2.0 * cP * Sh))
                v = u0 * cw - xv * sw / om + a1 \
                    + Am * (sph * (opt * cP * Sh + sP * cM) + cph * 2.0 * th * sP * Sh)
                Ft = A * sin_(th * tau + phi) + fconst + fq * tau
                return w, v, (Ft - k * w) / m
            return fd
        B1, B2 = self.B1, self.B2
        r1, r2 = self.r1, self.r2

        def fd(tau):
            if kind == 0:
                C, S = cos_(wd * tau), sin_(wd * tau) / wd
            elif kind == 1:
                C, S = 1.0, tau
            else:
                # over-damped: e^{-sigma tau} folded into cosh and sinh (0 < wd < sigma), so that
                # neither overflows on long stuck or sliding stretches
                ep, em = exp_(r1 * tau), exp_(r2 * tau)
                C, S = 0.5 * (ep + em), 0.5 * (ep - em) / wd
            e = exp_(-sig * tau) if sig and kind != 2 else 1.0
            w = e * (x0 * C + xs * S) + a0 + a1 * tau
            v = e * (u0 * C - xv * S) + a1
            Ft = fconst + fq * tau
            if harm:
                sa, ca = sin_(th * tau + phi), cos_(th * tau + phi)
                w += B1 * sa + B2 * ca
                v += th * (B1 * ca - B2 * sa)
                Ft += A * sa
            return w, v, (Ft - c * v - k * w) / m
        return fd

    # -- events --------------------------------------------------------------------------------
    def _velocity_zero(self, fd, s, x0, u0, analytic, tau_max, from_rest):
        """First tau in (0, tau_max] where s*v reaches 0, or None."""
        if analytic and self.kind != 0:
            # critically or over-damped, constant force: v is e^{-sigma tau} (u0 - xv tau), or
            # alpha e^{r1 tau} + beta e^{r2 tau}; either has at most one zero.  From rest (u0 = 0)
            # that zero is the start, so the mass creeps towards its end position without stopping.
            if from_rest or u0 == 0.0:
                return None
            om2x = self.omega * (self.omega * x0)
            if self.kind == 1:
                xv = self.sigma * u0 + om2x
                tau = u0 / xv if xv != 0.0 else -1.0
            else:
                alpha = u0 * self.r1 - om2x
                beta = -u0 * self.r2 + om2x
                ratio = -beta / alpha if alpha != 0.0 else -1.0
                tau = math.log(ratio) / (2.0 * self.wd) if ratio > 1.0 else -1.0
            return tau if 0.0 < tau <= tau_max else None
        if analytic:
            wd = self.wd
            b = (self.sigma * u0 + self.omega ** 2 * x0) / wd
            if u0 == 0.0:
                x = math.pi
            else:
                x = (0.5 * math.pi - math.atan2(b, u0)) % math.pi
                if x == 0.0:
                    x = math.pi
            tau = x / wd
            return tau if tau <= tau_max else None

        def g(tau):
            w, v, a = fd(tau)
            return -s * v, -s * a
        return first_up(g, tau_max, self.h_scan, from_zero=from_rest)

    def _breakaway(self, t, w, t_stop=math.inf):
        """First time >= t at which |F - k w| exceeds mu0 N with the mass held at w, or None."""
        F, thr, kw = self.F, self.fs, self.k * w
        if F.harmonic and not F.has_record:
            return _harmonic_exceed(F.A, F.theta, t, -kw, thr)
        if F.has_record and not F.harmonic:
            return self._record_exceed(t, kw, thr)
        if not F.forced:
            return None if abs(kw) <= thr else t
        # both: scan to the end of the record, then the harmonic criterion
        t_rec_end = F.record.times[-1]
        if t < t_rec_end:
            def g(tau):
                tt = t + tau
                G = F.value(tt) - kw
                d = F.slope(tt)
                return abs(G) - thr, (d if G >= 0 else -d)
            h = min(self.h_scan, TWO_PI / F.theta / 16.0)
            tau = first_up(g, min(t_rec_end, t_stop) - t, h)
            if tau is not None:
                return t + tau
            if t_stop < t_rec_end:
                return math.inf  # not found before t_stop: unknown later, "not forever"
            t = t_rec_end
        return _harmonic_exceed(F.A, F.theta, t, -kw, thr)

    def _record_exceed(self, t, kw, thr):
        rt, rF = self.F.record.times, self.F.record.values
        if t < rt[0]:
            if abs(kw) > thr:
                return t
            if abs(rF[0] - kw) > thr:
                return rt[0]
            t = rt[0]
        if t >= rt[-1]:
            return None if abs(kw) <= thr else t
        i = bisect.bisect_right(rt, t) - 1
        G_t = rF[i] + (rF[i + 1] - rF[i]) * (t - rt[i]) / (rt[i + 1] - rt[i]) - kw
        if abs(G_t) > thr:
            return t
        if not hasattr(self, "_rF_np"):
            self._rF_np = np.asarray(rF)
        G = self._rF_np[i + 1:] - kw
        hit = np.flatnonzero(np.abs(G) > thr)
        if hit.size == 0:
            return None if abs(kw) <= thr else rt[-1]
        j = i + 1 + int(hit[0])
        Gb = G[hit[0]]
        if j == i + 1:
            ta, Ga = t, G_t
        else:
            ta, Ga = rt[j - 1], rF[j - 1] - kw
        level = thr if Gb > 0 else -thr
        frac = (level - Ga) / (Gb - Ga)
        tb = ta + frac * (rt[j] - ta)
        # place the event where the threshold is reached (not before)
        return min(max(tb, ta), rt[j])

    def _direction(self, t, w, G):
        """Sliding direction from rest at (t, w) with net force G = F(t) - k w: sign(G), or, when G is
        at the round-off level of its terms (a grazing zero of v and a, e.g. every forcing period of
        the frictionless theta = omega/2 response), the sign of its slope dG/dt = F'(t) (v = 0).
        Taking round-off's sign there started the segment the wrong way, and the scan then reported
        a turning point where v was far from zero (frictionless ex. 3 at t ~ 6e3 s: 1e-3 m error)."""
        F = self.F
        scale = abs(F.A) * (1.0 + F.theta * abs(t)) + abs(F.record_value(t)) + abs(self.k * w)
        if abs(G) <= 16 * 2.2e-16 * scale or G == 0.0:
            dG = F.slope(t)
            if dG != 0.0:
                G = dG
        return 1.0 if G > 0 else -1.0

    # -- the run -------------------------------------------------------------------------------
    def run(self, w0, t_end):
        """Integrate from rest at w0 (t = 0) to t_end.  Returns a :class:`Solution`."""
        F, k, fs, fk = self.F, self.k, self.fs, self.fk
        t, w, v = 0.0, float(w0), 0.0
        segs = []        # (ts, te, x0, u0, a0, a1, phi, state)
        turning = []     # (t, w)
        slid = []        # |w1 - w| of every sliding segment (summed exactly at the end)
        G = F.value(0.0) - k * w
        stuck = abs(G) <= fs
        s = self._direction(0.0, w, G)
        forever = False
        from_rest = True
        analytic_free = not F.harmonic  # closed-form velocity zeros (any damping) when q = 0
        steps = 0
        merge_dt = 1e-6 * 8.0 * self.h_scan  # 1e-6 of the shortest period
        while t < t_end:
            steps += 1
            if steps > MAX_STEPS:
                raise SolverFailure(f"more than {MAX_STEPS} events before t_end = {t_end:g} s "
                                    f"(stopped at t = {t:.6g} s); shorten t_end")
            if stuck:
                tb = self._breakaway(t, w, t_stop=t_end)
                if tb is None or tb >= t_end:
                    segs.append((t, t_end, 0.0, 0.0, w, 0.0, 0.0, 0))
                    forever = tb is None
                    t = t_end
                    break
                if tb > t:
                    segs.append((t, tb, 0.0, 0.0, w, 0.0, 0.0, 0))
                t = tb
                G = F.value(t) - k * w
                s = self._direction(t, w, G)
                stuck, v, from_rest = False, 0.0, True
                continue
            p, q, t_node = F.piece(t)
            t_stop = t_end if t_end < t_node else t_node
            fc = p - s * fk
            x0, u0, a0, a1, phi = self.coefficients(t, w, v, fc, q)
            fd = self.segment(x0, u0, a0, a1, phi, s)
            analytic = analytic_free and q == 0.0
            tau = self._velocity_zero(fd, s, x0, u0, analytic, t_stop - t, from_rest)
            state = 1 if s > 0 else -1
            if tau is None:
                w1, v1, _ = fd(t_stop - t)
                segs.append((t, t_stop, x0, u0, a0, a1, phi, state))
                slid.append(abs(w1 - w))
                t, w, v = t_stop, w1, v1
                if v == 0.0:
                    v = 0.0
                from_rest = False
                continue
            w1 = fd(tau)[0]
            te = t + tau
            segs.append((t, te, x0, u0, a0, a1, phi, state))
            slid.append(abs(w1 - w))
            t, w, v = te, w1, 0.0
            # a grazing zero (v and a vanish together, e.g. frictionless forcing) restarts from a
            # round-off-sized net force and finds the same instant again: it is one turning point
            if turning and te - turning[-1][0] <= merge_dt:
                turning[-1] = (t, w)
            else:
                turning.append((t, w))
            G = F.value(t) - k * w
            if abs(G) <= fs:
                stuck = True
            else:
                s = self._direction(t, w, G)
                from_rest = True
        return Solution(self, float(w0), t_end, segs, turning, forever, fk * math.fsum(slid))


def _harmonic_exceed(A, theta, t0, Gc, thr):
    """First t >= t0 where |A sin(theta t) + Gc| > thr (None: never).  |A sin(theta t0) + Gc| <= thr."""
    if A < 0.0:
        a, off = -A, math.pi
    else:
        a, off = A, 0.0
    U, L = thr - Gc, -thr - Gc      # exceed when a sin(psi) > U or a sin(psi) < L
    psi0 = theta * t0 + off
    cands = []
    if U < a:
        if U < -a:
            return t0
        cands.append(math.asin(U / a))                 # upward crossing of level U
    if L > -a:
        if L > a:
            return t0
        cands.append(math.pi - math.asin(L / a))       # downward crossing of level L
    if not cands:
        return None
    best = math.inf
    tol = 1e-13 * max(1.0, abs(psi0))
    for pc in cands:
        n = math.ceil((psi0 - tol - pc) / TWO_PI)
        psi = pc + TWO_PI * n
        if psi < best:
            best = psi
    return max(t0, (best - off) / theta)
