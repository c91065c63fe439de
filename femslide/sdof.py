"""One-mass Coulomb-friction oscillator integrated exactly, event by event (SPEC section 5).

Model (SI units: m [kg], k [N/m], c_v [N s/m], forces [N], w [m], t [s])::

    m w'' + c_v w' + k w + f = F(t),      N = m g,
    F(t) = P0 sin(theta t) - m ag sin(theta t) - m a_rec(t),     theta = theta_ratio * omega,

``w`` is the displacement of the mass relative to its base (positive along the guide), ``F`` the
applied force (for base excitation the inertia force -m z0'' of the moving frame) and ``f`` the
friction force on the mass, opposite to the relative velocity:

* sliding (w' != 0): f = mu N sgn(w');
* at rest (w' = 0): the mass sticks while |F - k w| <= mu0 N (mu0 >= mu, the static coefficient);
  otherwise it starts to slide in the direction of the net force F - k w.

While stuck the velocity is exactly 0 and the position constant (no regularised sign function).
Between events the equation is linear with a constant friction force and a forcing that is a sine
plus a linear function of time (the record is interpolated linearly), so each segment is solved in
closed form: homogeneous part (under-, critically or over-damped) plus the exact particular
solution.  For c_v = 0 the harmonic response is written in a form that stays exact and stable at and
near resonance (theta = omega).  Events are found on the closed form:

* sliding -> velocity zero: analytically (atan2) for unforced under-damped segments, otherwise by a
  scan in sub-steps of 1/8 of the shortest period (with a check of interior extrema, so that a zero
  touched between two samples is not missed) and a bracketing root finder to ~1e-14 s;
* stuck -> breakaway, the first time |F(t) - k w| exceeds mu0 N: analytically for a harmonic force,
  exactly per record interval for a record, by scan + root for both together.

The record acceleration is zero outside its time range.  Energy balance, dense histories and
per-period amplitudes are evaluated afterwards, vectorised, from the stored closed forms.
"""
from __future__ import annotations

import bisect
import math
import os

import numpy as np

from .errors import BadInput, SolverFailure
from .params import floor_g

# 10-point Gauss-Legendre rule on [-1, 1] (energy balance): computed once
_GAUSS10 = np.polynomial.legendre.leggauss(10)

TWO_PI = 2.0 * math.pi
STEADY_TOL = 1e-10      # m: two successive forcing periods must agree to this for a steady state
MAX_STEPS = 5_000_000   # closed-form segments before the run is declared failed (a safety net: the
                        # a-priori bound MAX_PERIODS below is far lower)
# Bounded work (issue 12).  The run follows the motion period by period: closed-form segments
# between events, located by a scan of 8 samples per shortest period.  Measured on the 2-core
# development machine under load: 150-210 us per period of the shortest time scale for the solve,
# energy balance and summary of a forced run (the slowest kind: 2 events and 16 scan samples per
# period; unforced runs need one closed form per half-swing), and as much again for --out (history
# and JSON).  A run may follow at most MAX_PERIODS such periods: about US_PER_PERIOD * MAX_PERIODS
# = 20 s of solving (40 s with --out) and under 1 GiB, inside the 2 minutes and 4 GiB of the
# contract with room to spare.
US_PER_PERIOD = 200
MAX_PERIODS = 100_000
MAX_RECORD_ROWS = 1_000_000       # each row is a segment boundary (~20 us each: 20 s)
MAX_RECORD_BYTES = 64 * 2**20     # a 1e6-row CSV of full-precision numbers is ~40 MB
E_MAX = 1e250                     # J: energies (and so w, v, forces) stay far inside the float range
ENERGY_TOL = 1e-6                 # a run whose energy balance is worse than this fails (exit 1)
HISTORY_ROWS = 1_000_000          # history.csv: 64 samples per shortest period, at most this many


# ---------------------------------------------------------------------------------------------
# Excitation
# ---------------------------------------------------------------------------------------------

def read_record(path: str):
    """Read a base-acceleration record: CSV with columns t [s], a [m/s^2].

    One header line (non-numeric first field) and blank or ``#`` comment lines are allowed; times
    must be finite and strictly increasing, at least two rows.  Returns ``(times, accelerations)``
    as lists of floats.  Raises :class:`BadInput` naming ``record`` otherwise.
    """
    allowed = "a readable CSV text file with columns t [s], a [m/s^2]"
    try:
        size = os.path.getsize(path)
        if size > MAX_RECORD_BYTES:
            raise BadInput(f"parameter record: {path!r} is {size / 2**20:.0f} MiB; allowed: {allowed} "
                           f"of at most {MAX_RECORD_BYTES // 2**20} MiB and {MAX_RECORD_ROWS} rows")
        with open(path, newline="", encoding="utf-8") as fh:
            text = fh.read()
    except OSError as exc:
        raise BadInput(f"parameter record: cannot read {path!r} ({exc.strerror or exc}); "
                       f"allowed: {allowed}") from None
    except (UnicodeDecodeError, ValueError) as exc:
        raise BadInput(f"parameter record: {path!r} is not text ({exc}); allowed: {allowed}") from None
    ts, acc = [], []
    seen_data = False
    for lineno, line in enumerate(text.splitlines(), 1):
        s = line.strip()
        if not s or s.startswith("#"):
            continue
        parts = [p.strip() for p in s.replace(";", ",").split(",")]
        if len(parts) == 1:
            parts = s.split()
        try:
            if len(parts) < 2:
                raise ValueError
            t, a = float(parts[0]), float(parts[1])
        except ValueError:
            if not seen_data and not ts:
                seen_data = True  # the header line
                continue
            raise BadInput(f"parameter record: {path!r} line {lineno}: expected two numbers "
                           f"'t, a', got {s[:60]!r}") from None
        seen_data = True
        if not (math.isfinite(t) and math.isfinite(a)):
            raise BadInput(f"parameter record: {path!r} line {lineno}: non-finite value")
        if ts and not t > ts[-1]:
            raise BadInput(f"parameter record: {path!r} line {lineno}: times must be strictly "
                           f"increasing (t = {t:g} s after {ts[-1]:g} s)")
        ts.append(t)
        acc.append(a)
        if len(ts) > MAX_RECORD_ROWS:
            raise BadInput(f"parameter record: {path!r} has more than {MAX_RECORD_ROWS} data rows; "
                           f"allowed: at most {MAX_RECORD_ROWS} rows (each is a segment of the exact "
                           f"solution; resample the record)")
    if len(ts) < 2:
        raise BadInput(f"parameter record: {path!r} has {len(ts)} data rows; "
                       f"allowed: a CSV file with at least two rows 't, a'")
    return ts, acc


class Forcing:
    """F(t) = A sin(theta t) + R(t), R linear between record nodes, 0 outside them [N]."""

    def __init__(self, A=0.0, theta=0.0, rec_t=None, rec_F=None):
        self.A = float(A)
        self.theta = float(theta)
        self.harmonic = self.A != 0.0 and self.theta > 0.0
        if not self.harmonic:
            self.A = 0.0
        self.rt = list(rec_t) if rec_t is not None else []
        self.rF = list(rec_F) if rec_F is not None else []
        self.has_record = bool(self.rt)
        self.forced = self.harmonic or self.has_record

    def piece(self, t):
        """(p, q, t_next): R(t + tau) = p + q tau until the next record node t_next."""
        rt = self.rt
        if not rt:
            return 0.0, 0.0, math.inf
        i = bisect.bisect_right(rt, t) - 1
        if i < 0:
            return 0.0, 0.0, rt[0]
        if i >= len(rt) - 1:
            return 0.0, 0.0, math.inf
        q = (self.rF[i + 1] - self.rF[i]) / (rt[i + 1] - rt[i])
        return self.rF[i] + q * (t - rt[i]), q, rt[i + 1]

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
        F = np.zeros_like(t)
        if self.has_record:
            rt = np.asarray(self.rt)
            inside = (t >= rt[0]) & (t < rt[-1])
            F = np.where(inside, np.interp(t, rt, np.asarray(self.rF)), 0.0)
        if self.harmonic:
            F = F + self.A * np.sin(self.theta * t)
        return F


# ---------------------------------------------------------------------------------------------
# Bracketing root finder (keeps the bracket; returns the point on the "f >= 0" side)
# ---------------------------------------------------------------------------------------------

def _root_up(f, lo, hi, flo, fhi, xtol=1e-14):
    """Root of f on [lo, hi] with f(lo) < 0 <= f(hi); Anderson-Bjorck regula falsi + bisection.

    Returns a point x with f(x) >= 0 and a point of the bracket no further than ``xtol``
    (relative to max(1, |x|)) below it, so the event is never placed before it happens.
    """
    tol = xtol * max(1.0, abs(hi))
    side = 0
    for _ in range(200):
        if hi - lo <= tol or fhi == 0.0:
            return hi
        x = hi - fhi * (hi - lo) / (fhi - flo)
        if not (lo < x < hi) or side == 2:  # safeguard: bisect
            x = 0.5 * (lo + hi)
            side = 0
        # keep steps away from the endpoints so both ends shrink
        w = hi - lo
        if x - lo < 0.5 * tol:
            x = lo + 0.5 * tol
        elif hi - x < 0.5 * tol:
            x = hi - 0.5 * tol
        fx = f(x)
        if fx >= 0.0:
            g = 1.0 - fx / fhi if fhi != 0 else 0.5
            hi, fhi = x, fx
            if side == -1:
                flo *= g if g > 0 else 0.5
            side = -1 if side != -1 else 2
        else:
            g = 1.0 - fx / flo
            lo, flo = x, fx
            if side == 1:
                fhi *= g if g > 0 else 0.5
            side = 1 if side != 1 else 2
        if hi - lo > 0.9 * w and side != 2:
            side = 2  # poor progress: bisect next
    return hi


def _first_up(fd, tau_max, h, from_zero=False):
    """First tau in (0, tau_max] where f(tau) reaches 0 from below, or None.

    ``fd(tau) -> (f, f')``.  ``f(0) <= 0``; with ``from_zero`` f(0) = 0 is a start (f < 0 just
    after 0), otherwise f(0) = 0 with f'(0) > 0 counts as an event at 0.  Samples every ``h``
    (<= 1/8 of the shortest period of f) and checks interior maxima between samples.
    """
    f = lambda x: fd(x)[0]  # noqa: E731
    dfun = lambda x: fd(x)[1]  # noqa: E731
    flo, dlo = fd(0.0)
    if not from_zero and (flo > 0.0 or (flo == 0.0 and dlo > 0.0)):
        return 0.0
    lo = 0.0
    while lo < tau_max:
        hi = lo + h
        if hi > tau_max:
            hi = tau_max
        fhi, dhi = fd(hi)
        if fhi >= 0.0:
            if flo >= 0.0:  # starting from f(0) = 0: find a point with f < 0 inside
                x = hi
                for _ in range(100):
                    x *= 0.5
                    fx = f(x)
                    if fx < 0.0:
                        break
                else:
                    return hi
                lo, flo = x, fx
            return _root_up(f, lo, hi, flo, fhi)
        if dlo > 0.0 and dhi <= 0.0 and flo < 0.0:  # interior maximum: did f touch 0?
            tm = _root_up(lambda x: -dfun(x), lo, hi, -dlo, -dhi)
            fm = f(tm)
            if fm >= 0.0:
                return _root_up(f, lo, tm, flo, fm)
        lo, flo, dlo = hi, fhi, dhi
    return None


# ---------------------------------------------------------------------------------------------
# The exact integrator
# ---------------------------------------------------------------------------------------------

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
        return _first_up(g, tau_max, self.h_scan, from_zero=from_rest)

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
        t_rec_end = F.rt[-1]
        if t < t_rec_end:
            def g(tau):
                tt = t + tau
                G = F.value(tt) - kw
                d = F.slope(tt)
                return abs(G) - thr, (d if G >= 0 else -d)
            h = min(self.h_scan, TWO_PI / F.theta / 16.0)
            tau = _first_up(g, min(t_rec_end, t_stop) - t, h)
            if tau is not None:
                return t + tau
            if t_stop < t_rec_end:
                return math.inf  # not found before t_stop: unknown later, "not forever"
            t = t_rec_end
        return _harmonic_exceed(F.A, F.theta, t, -kw, thr)

    def _record_exceed(self, t, kw, thr):
        rt, rF = self.F.rt, self.F.rF
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


# ---------------------------------------------------------------------------------------------
# Post-processing of a run
# ---------------------------------------------------------------------------------------------

class Solution:
    """Stored closed-form segments of a run, with vectorised evaluation and summary quantities."""

    def __init__(self, osc: Oscillator, w0, t_end, segs, turning, forever, friction_work):
        self.osc, self.w0, self.t_end = osc, w0, t_end
        self.segs, self.turning, self.forever = segs, turning, forever
        self.friction_work = friction_work
        self._np = None

    # arrays of the segment table
    def _arrays(self):
        if self._np is None:
            a = np.array(self.segs, dtype=float).reshape(-1, 8)
            self._np = {"ts": a[:, 0], "te": a[:, 1], "x0": a[:, 2], "u0": a[:, 3],
                        "a0": a[:, 4], "a1": a[:, 5], "phi": a[:, 6], "state": a[:, 7]}
        return self._np

    def eval(self, t, seg=None, tau=None):
        """w [m], v [m/s], state (+1/-1 sliding direction, 0 stuck) at times ``t`` (array), or at
        offsets ``tau`` into segments ``seg`` (exact offsets: no round-off of t - ts at large t)."""
        o = self.osc
        A_ = self._arrays()
        if tau is None:
            t = np.asarray(t, dtype=float)
            if seg is None:
                seg = np.clip(np.searchsorted(A_["ts"], t, side="right") - 1, 0, len(A_["ts"]) - 1)
            tau = t - A_["ts"][seg]
        tau = np.asarray(tau, dtype=float)
        x0, u0, a0, a1, phi, st = (A_[n][seg] for n in ("x0", "u0", "a0", "a1", "phi", "state"))
        sig, om, wd = o.sigma, o.omega, o.wd
        if o.kind == 0:
            C, S = np.cos(wd * tau), np.sin(wd * tau) / wd
        elif o.kind == 1:
            C, S = np.ones_like(tau), tau
        else:  # over-damped: e^{-sigma tau} folded in (no overflow), as in the segment solution
            ep, em = np.exp(o.r1 * tau), np.exp(o.r2 * tau)
            C, S = 0.5 * (ep + em), 0.5 * (ep - em) / wd
        e = np.exp(-sig * tau) if o.kind != 2 else 1.0
        w = e * (x0 * C + (u0 + sig * x0) * S) + a0 + a1 * tau
        v = e * (u0 * C - (sig * u0 + om * om * x0) * S) + a1
        F = o.F
        if F.harmonic:
            sliding = st != 0
            th, A = F.theta, F.A
            if o.c == 0.0:
                Am = A / o.m / (om + th)
                P, M = 0.5 * (om + th), 0.5 * (om - th)
                sph, cph = np.sin(phi), np.cos(phi)
                sP, cP, sw = np.sin(P * tau), np.cos(P * tau), np.sin(om * tau)
                if M != 0.0:
                    Sh, cM = np.sin(M * tau) / (2 * M), np.cos(M * tau)
                else:
                    Sh, cM = 0.5 * tau, np.ones_like(tau)
                hw = Am * (sph * 2 * sP * Sh + cph * (sw / om - 2 * cP * Sh))
                hv = Am * (sph * ((om + th) * cP * Sh + sP * cM) + cph * 2 * th * sP * Sh)
            else:
                sa, ca = np.sin(th * tau + phi), np.cos(th * tau + phi)
                hw = o.B1 * sa + o.B2 * ca
                hv = th * (o.B1 * ca - o.B2 * sa)
            w = w + np.where(sliding, hw, 0.0)
            v = v + np.where(sliding, hv, 0.0)
        v = np.where(st == 0, 0.0, v)
        return w, v, st

    # energy balance ---------------------------------------------------------------------------
    def energy_balance(self):
        """Relative energy error |E(t_end) + D_friction + D_viscous - W_in - E(0)| / E_ref.

        E = m v^2/2 + k w^2/2; D_friction = mu N * (distance slid), exact; D_viscous = int c v^2 dt
        and W_in = int F v dt by 10-point Gauss-Legendre on pieces of each sliding segment:
        under-damped, pieces no longer than half the shortest period (of omega and theta) and
        3/sigma; critically and over-damped (no oscillation of the free motion), pieces graded
        geometrically from each segment start (0.5/lambda_fast, growing by 1.5: every piece is at
        most half its distance from the start, so each decaying exponential is resolved where it
        matters), then of half a forcing period when there is one.  So a stiff over-damped run needs
        O(log(sigma t_end)) pieces per segment, not sigma t_end.  The pieces are evaluated in chunks
        (bounded memory) and summed with math.fsum.  E_ref = E(0), or the largest E seen when
        E(0) = 0, or the work put in or dissipated when that is larger.
        """
        o = self.osc
        A_ = self._arrays()
        E0 = 0.5 * o.k * self.w0 ** 2
        sl = np.flatnonzero(A_["state"] != 0)
        w_end, v_end, _ = self.eval(np.array([self.t_end]))
        E_end = 0.5 * o.m * v_end[0] ** 2 + 0.5 * o.k * w_end[0] ** 2
        Emax = max(E0, E_end)
        W_parts, D_parts = [], []
        if sl.size:
            ts_all, te_all = A_["ts"], A_["te"]
            Lmax = float(np.max(te_all[sl] - ts_all[sl]))
            if o.kind == 0:
                lim = [math.pi / o.omega]
                if o.sigma > 0:
                    lim.append(3.0 / o.sigma)
                grade = np.zeros(1)
            else:
                lim = [math.inf]
                fast = -o.r2 if o.kind == 2 else o.sigma
                g, h = [0.0], 0.5 / fast
                top = min(Lmax, math.pi / o.F.theta if o.F.harmonic else math.inf)
                while g[-1] < top:
                    g.append(g[-1] + h)
                    h *= 1.5
                grade = np.array(g)
            if o.F.harmonic:
                lim.append(math.pi / o.F.theta)
            hq = min(lim)
            K = grade.size - 1
            xg, wg = _GAUSS10
            chunk = max(1, 100_000 // (K + 1))
            for c0 in range(0, sl.size, chunk):
                idx = sl[c0:c0 + chunk]
                ts, te = ts_all[idx], te_all[idx]
                L = te - ts
                # graded pieces [g_j, g_j+1] clipped at the segment end, then uniform pieces of at
                # most hq from min(g_K, L) to L; starts are offsets into the segment
                starts, lengths, segs = [], [], []
                if K > 0:
                    ga = np.minimum(grade[None, :-1], L[:, None])
                    gb = np.minimum(grade[None, 1:], L[:, None])
                    starts.append(ga.ravel())
                    lengths.append((gb - ga).ravel())
                    segs.append(np.repeat(idx, K))
                g_end = np.minimum(grade[-1], L)
                rest = L - g_end
                if math.isfinite(hq):
                    nu = np.where(rest > 0, np.maximum(1, np.ceil(rest / hq)), 0).astype(np.int64)
                else:
                    nu = (rest > 0).astype(np.int64)
                k = np.repeat(np.arange(idx.size), nu)
                j = np.arange(k.size) - np.repeat(np.cumsum(nu) - nu, nu)
                hl = rest[k] / nu[k]
                starts.append(g_end[k] + j * hl)
                lengths.append(hl)
                segs.append(idx[k])
                a = np.concatenate(starts)
                length = np.concatenate(lengths)
                seg = np.concatenate(segs)
                keep = length > 0
                a, length, seg = a[keep], length[keep], seg[keep]
                for p0 in range(0, a.size, 400_000):  # one long segment may have many pieces
                    aa, ll, ss = a[p0:p0 + 400_000], length[p0:p0 + 400_000], seg[p0:p0 + 400_000]
                    tau = aa[:, None] + 0.5 * ll[:, None] * (xg[None, :] + 1.0)
                    segm = np.repeat(ss[:, None], 10, axis=1)
                    w, v, _ = self.eval(None, segm.ravel(), tau.ravel())
                    w, v = w.reshape(tau.shape), v.reshape(tau.shape)
                    half = 0.5 * ll[:, None] * wg[None, :]
                    if o.F.forced:
                        W_parts.append(np.sum(half * self._force(tau, segm) * v, axis=1))
                    if o.c:
                        D_parts.append(np.sum(half * o.c * v * v, axis=1))
                    Emax = max(Emax, float(np.max(0.5 * o.m * v * v + 0.5 * o.k * w * w)))
        W_in = math.fsum(np.concatenate(W_parts).tolist()) if W_parts else 0.0
        D_visc = math.fsum(np.concatenate(D_parts).tolist()) if D_parts else 0.0
        err = math.fsum([E_end, self.friction_work, D_visc, -W_in, -E0])
        # relative to the largest term of the balance: E(0) (or the largest E when E(0) = 0), or the
        # work put in / dissipated when that is larger (strong damping: c_v = 1e9 has W_in = 9e-8 J
        # through a motion whose energy never exceeds 5e-16 J; the round-off of the balance scales
        # with the throughput)
        Eref = max(E0 if E0 > 0 else Emax, abs(W_in), D_visc, self.friction_work)
        if Eref == 0.0:
            return 0.0
        return abs(err) / Eref

    def _force(self, tau, seg):
        """F at offsets tau into segments seg as the segment solutions see it: the harmonic part
        with the segment's own phase, A sin(phi + theta tau), and the record's linear piece
        p + q tau of the segment (a phase theta t computed afresh differs by round-off
        ~ eps theta t, which over a long run made the energy balance drift as t_end^2)."""
        F = self.osc.F
        A_ = self._arrays()
        out = np.zeros_like(tau)
        if F.has_record:
            # the segment's record piece: a0 k + a1 c = p - s mu N, a1 k = q (see coefficients)
            o = self.osc
            st = A_["state"][seg]
            q = A_["a1"][seg] * o.k
            p = A_["a0"][seg] * o.k + A_["a1"][seg] * o.c + st * o.fk
            out = np.where(st != 0, p + q * tau, 0.0)
        if F.harmonic:
            out = out + F.A * np.sin(A_["phi"][seg] + F.theta * tau)
        return out

    # per-period amplitudes ---------------------------------------------------------------------
    def period_amplitudes(self):
        """(max w, min w) over each complete forcing period [n T, (n+1) T], T = 2 pi/theta."""
        F = self.osc.F
        Tf = TWO_PI / F.theta
        n = int(math.floor(self.t_end / Tf * (1 + 1e-14)))
        if n < 1:
            return np.empty(0), np.empty(0)
        tb = Tf * np.arange(n + 1)
        tb[-1] = min(tb[-1], self.t_end)
        wb, _, _ = self.eval(tb)
        wmax = np.maximum(wb[:-1], wb[1:])
        wmin = np.minimum(wb[:-1], wb[1:])
        if self.turning:
            tp = np.array(self.turning)
            idx = np.floor(tp[:, 0] / Tf).astype(int)
            ok = idx < n
            np.maximum.at(wmax, idx[ok], tp[ok, 1])
            np.minimum.at(wmin, idx[ok], tp[ok, 1])
        return wmax, wmin

    def steady(self):
        """(amplitude or None, reason or None, t from which successive periods agree)."""
        F = self.osc.F
        if not F.forced:
            return None, "unforced run (no steady forced response)", None
        if not F.harmonic:
            return None, "record excitation is not periodic", None
        if F.has_record:
            return None, "record plus harmonic excitation is not periodic", None
        wmax, wmin = self.period_amplitudes()
        if wmax.size < 2:
            return None, "fewer than two complete forcing periods before t_end", None
        dmax = abs(wmax[-1] - wmax[-2])
        dmin = abs(wmin[-1] - wmin[-2])
        if max(dmax, dmin) > STEADY_TOL:
            amp = 0.5 * (wmax - wmin)
            grow = amp[-1] - amp[-2]
            return None, (f"not steady by t_end: the last two forcing periods differ by "
                          f"{max(dmax, dmin):.3g} m (amplitude change {grow:+.3g} m per period; "
                          f"tolerance {STEADY_TOL:g} m); increase t_end"
                          + (" - at resonance it grows without bound" if grow > 0 and
                             abs(F.theta - self.osc.omega) < 1e-9 * self.osc.omega else "")), None
        agree = (abs(wmax[1:] - wmax[:-1]) <= STEADY_TOL) & (abs(wmin[1:] - wmin[:-1]) <= STEADY_TOL)
        i = len(agree)
        while i > 0 and agree[i - 1]:
            i -= 1
        return float(0.5 * (wmax[-1] - wmin[-1])), None, float(i * TWO_PI / F.theta)

    def stop(self):
        if not self.forever:
            return None
        if self.turning:
            t, w = self.turning[-1]
            return {"t": t, "w": w}
        return {"t": 0.0, "w": self.w0}

    def w_max(self):
        vals = [abs(self.w0)] + [abs(w) for _, w in self.turning]
        if self.segs:
            w_end, _, _ = self.eval([self.t_end])
            vals.append(abs(float(w_end[0])))
            # segment ends at record nodes / t_end while sliding
            A_ = self._arrays()
            sl = A_["state"] != 0
            if sl.any():
                idx = np.flatnonzero(sl)
                we, _, _ = self.eval(A_["te"][idx], idx)
                vals.append(float(np.max(np.abs(we))))
        return max(vals)

    def history(self, points_per_period=64):
        """The time history as arrays (SI), sampled uniformly (``points_per_period`` per shortest
        period of the free motion and the forcing, at most HISTORY_ROWS) plus every segment boundary
        (events), up to the start of a final stop and then only t_end:

        ``t`` [s]; ``w`` [m] displacement relative to the base; ``v`` [m/s]; ``state`` (+1/-1
        sliding direction, 0 stuck); ``F`` [N] the applied force F(t); ``f`` [N] the friction force
        of the equation m w'' + c_v w' + k w + f = F: mu N sgn(w') while sliding, F - k w (what
        static friction holds) while stuck; the friction force on the mass is -f.
        """
        o = self.osc
        periods = [TWO_PI / o.omega]
        if o.F.harmonic:
            periods.append(TWO_PI / o.F.theta)
        dt = min(periods) / points_per_period
        A_ = self._arrays()
        # uniform samples up to the start of a final stop (then only its end): a mass at rest for
        # the rest of a long run needs no samples; at most HISTORY_ROWS (coarser for long runs)
        t_s = float(A_["ts"][-1]) if self.forever else self.t_end
        n = int(min(HISTORY_ROWS, math.ceil(t_s / dt)))
        t = np.unique(np.concatenate([np.linspace(0.0, t_s, n + 1), A_["ts"], A_["te"], [self.t_end]]))
        t = t[(t >= 0) & (t <= self.t_end)]
        seg = np.clip(np.searchsorted(A_["ts"], t, side="right") - 1, 0, len(A_["ts"]) - 1)
        # an instant that ends a segment belongs to the next one (same w, v = 0 at events)
        w, v, st = self.eval(t, seg)
        F = o.F.eval_np(t)
        f = np.where(st == 0, F - o.k * w, st * o.fk)
        return {"t": t, "w": w, "v": v, "state": st.astype(int), "F": F, "f": f}

    def write(self, outdir, points_per_period=64):
        """Write history.csv (t, w, v, state) and turning_points.csv; return the file names."""
        h = self.history(points_per_period)
        t, w, v, st = h["t"], h["w"], h["v"], h["state"]
        if not (np.isfinite(w).all() and np.isfinite(v).all()):
            raise SolverFailure("the time history is not finite; nothing written")
        path = os.path.join(outdir, "history.csv")
        np.savetxt(path, np.column_stack([t, w, v, st]), delimiter=",",
                   header="t [s],w [m],v [m/s],state (+1/-1 sliding direction; 0 stuck)",
                   fmt=["%.17g", "%.17g", "%.17g", "%d"], comments="")
        path2 = os.path.join(outdir, "turning_points.csv")
        tp = np.array(self.turning, dtype=float).reshape(-1, 2)
        np.savetxt(path2, tp, delimiter=",", header="t [s],w [m]", fmt="%.17g", comments="")
        return ["history.csv", "turning_points.csv"]


# ---------------------------------------------------------------------------------------------
# Runners (scene registry: femslide/scenes.py)
# ---------------------------------------------------------------------------------------------

def build(values: dict) -> tuple[Oscillator, float, float]:
    """Oscillator, w0 and t_end from validated scene parameters (see module docstring)."""
    m, k = values["m"], values["k"]
    if not k > 0:
        raise BadInput(f"parameter k = {k:g} N/m: the one-mass oscillator needs a spring; "
                       f"allowed: k > 0")
    omega = math.sqrt(k / m)
    ag = values.get("ag") or 0.0
    rec = values.get("record")
    P0 = values.get("P0", 0.0)
    if P0 is None:  # default of sdof-harmonic: 10 N unless a base excitation is given
        P0 = 0.0 if (ag or rec) else 10.0
    theta = values.get("theta_ratio", 1.0) * omega
    A = P0 - m * ag
    rec_t = rec_F = None
    if rec:
        rec_t, acc = read_record(rec)
        rec_F = [-m * a for a in acc]
    forcing = Forcing(A, theta if A else 0.0, rec_t, rec_F)
    _check_finite(values, m=m, k=k, omega=omega, theta=theta, A=A, sigma=values.get("c_v", 0.0) / (2 * m),
                  N=m * values["g"], fk=values["mu"] * m * values["g"], fs=values["mu0"] * m * values["g"],
                  rec_F=rec_F, rec=rec)
    osc = Oscillator(m, k, values.get("c_v", 0.0), values["mu"], values["mu0"], values["g"], forcing)
    w0, t_end = float(values.get("w0", 0.0)), float(values["t_end"])
    check_bounds(osc, w0, t_end, values)
    return osc, w0, t_end


# ---------------------------------------------------------------------------------------------
# Bounded input: numbers the solver can compute with, work within MAX_PERIODS (issue 12)
# ---------------------------------------------------------------------------------------------

def _check_finite(values, **q):
    """Derived quantities (omega, forces, rates) must be finite floats: an overflow here (e.g.
    m ag with ag = 1e308, or a record acceleration times m) is bad input naming its parameters."""
    names = {"omega": ("k, m", "omega = sqrt(k/m)", "k/m < 1e308 s^-2"),
             "theta": ("theta_ratio, k, m", "theta = theta_ratio sqrt(k/m)", "theta_ratio sqrt(k/m) < 1e308 rad/s"),
             "A": ("P0, ag, m", "the force amplitude |P0 - m ag|", "|P0 - m ag| < 1e308 N"),
             "sigma": ("c_v, m", "sigma = c_v/(2m)", "c_v/(2m) < 1e308 s^-1"),
             "N": ("m, g", "N = m g", "m g < 1e308 N"),
             "fk": ("mu, m, g", "the friction force mu m g", "mu m g < 1e308 N"),
             "fs": ("mu0, m, g", "the static friction limit mu0 m g", "mu0 m g < 1e308 N")}
    for key, (params, what, allowed) in names.items():
        x = q.get(key)
        if x is not None and not math.isfinite(x):
            raise BadInput(f"parameters {params}: {what} overflows the floating-point range; "
                           f"allowed: {allowed}")
    rec_F = q.get("rec_F")
    if rec_F is not None and not all(math.isfinite(f) for f in rec_F):
        raise BadInput(f"parameter record: m a(t) overflows for the accelerations in {q['rec']!r} "
                       f"(m = {q['m']:g} kg); allowed: |a| * m < 1e308 N")


def _impulse(osc, t_end):
    """Upper bound of int_0^t_end |F| dt [N s] (harmonic amplitude times t_end plus the record's
    piecewise-linear |force| integrated over [0, t_end])."""
    F = osc.F
    imp = abs(F.A) * t_end if F.harmonic else 0.0
    if F.has_record:
        if not hasattr(F, "_imp_cum"):   # cumulative bound at the nodes (t_end is bisected on)
            rt, rF = np.asarray(F.rt), np.abs(np.asarray(F.rF))
            piece = np.maximum(rF[:-1], rF[1:])
            lo, hi = np.maximum(rt[:-1], 0.0), np.maximum(rt[1:], 0.0)
            F._imp_cum = (hi, piece, np.concatenate([[0.0], np.cumsum(piece * (hi - lo))]))
        hi, piece, cum = F._imp_cum
        j = int(np.searchsorted(hi, t_end, side="left"))   # pieces 0 .. j-1 end before t_end
        imp += float(cum[j])
        if j < piece.size:
            start = hi[j - 1] if j > 0 else max(F.rt[0], 0.0)
            imp += float(piece[j]) * max(0.0, t_end - start)
    return imp


def energy_bound(osc, w0, t_end):
    """log of an upper bound of the oscillator's energy up to t_end [log J]: friction and damping only
    take energy out, and d sqrt(E)/dt <= |F| / sqrt(2 m), so sqrt(E) <= sqrt(E0) + int |F| dt / sqrt(2m).
    Logarithms, so that the bound itself cannot overflow.  Returns (log E_bound, log sqrt(E0) part,
    log forcing part)."""
    lo = -math.inf
    e0 = math.log(0.5 * osc.k) / 2 + math.log(abs(w0)) if w0 else lo     # log sqrt(E0)
    imp = _impulse(osc, t_end)
    ef = math.log(imp) - 0.5 * math.log(2 * osc.m) if imp > 0 else lo   # log of the forcing part
    big = max(e0, ef)
    if big == lo:
        return lo, e0, ef
    return 2 * (big + math.log1p(math.exp(min(e0, ef) - big))), e0, ef


def work_periods(osc, w0, t_end):
    """A-priori bound of the shortest periods the run has to follow up to t_end, and that period.

    Forced stretches (harmonic: all of [0, t_end]; a record: its span) are followed period by
    period.  Unforced, the motion stops or creeps: critically or over-damped a single closed-form
    segment; under-damped with kinetic friction mu N > 0 each half-swing lowers the amplitude by at
    least 2 mu N/k (energy: friction and damping only remove energy), so at most A k/(2 mu N) + 1
    half-swings for an amplitude bound A; with damping alone the amplitude reaches the dead zone
    mu0 N/k after ln(A k/(mu0 N))/(sigma T/2) half-swings."""
    F = osc.F
    om = max(osc.omega, F.theta) if F.harmonic else osc.omega
    T = TWO_PI / om
    if F.harmonic:
        return t_end / T, T
    span = min(t_end, F.rt[-1]) if F.has_record else 0.0
    n_nodes = bisect.bisect_right(F.rt, t_end) if F.has_record else 0
    P = span / T + n_nodes / 4.0          # a record node costs about a quarter period's work
    tail = t_end - span
    if tail <= 0:
        return P, T
    if osc.kind != 0:
        return P + 1.0, T
    logE = energy_bound(osc, w0, t_end)[0]
    A = math.exp(0.5 * (logE - math.log(0.5 * osc.k))) if logE > -700 else 0.0   # amplitude bound
    Td = TWO_PI / osc.wd
    half = tail / (Td / 2)
    if osc.fk > 0:
        half = min(half, A * osc.k / (2 * osc.fk) + 1)
    if osc.fs > 0 and osc.sigma > 0 and A * osc.k > osc.fs:
        half = min(half, math.log(A * osc.k / osc.fs) / (osc.sigma * Td / 2) + 1)
    if A * osc.k <= osc.fs and not F.has_record:
        half = 0.0                            # held by static friction from the start
    return P + half * (Td / 2) / T, T


def check_bounds(osc, w0, t_end, values):
    """BadInput unless the run's energies stay within E_MAX and its work within MAX_PERIODS."""
    logE, e0, ef = energy_bound(osc, w0, t_end)
    if logE > math.log(E_MAX):
        half_log = 0.5 * math.log(E_MAX)
        if e0 >= ef:
            wmax = math.exp(half_log - 0.5 * math.log(0.5 * osc.k))
            raise BadInput(f"parameter w0 = {w0:g} m: the initial energy k w0^2/2 = 10^{e0 * 2 / math.log(10):.0f} J "
                           f"is beyond the range the solver computes in (energies up to {E_MAX:g} J); "
                           f"allowed: |w0| <= {wmax:.6g} m for k = {osc.k:g} N/m")
        lim = math.exp(half_log + 0.5 * math.log(2 * osc.m))    # max impulse [N s]
        F = osc.F
        if F.harmonic and abs(F.A) * t_end >= _impulse(osc, t_end) - abs(F.A) * t_end:
            name = "P0" if abs(values.get("P0") or 0.0) >= osc.m * abs(values.get("ag") or 0.0) else "ag"
            val = values.get(name) or 0.0
            raise BadInput(f"parameter {name} = {val:g}: the force amplitude |P0 - m ag| = {abs(F.A):g} N can "
                           f"put up to 10^{ef * 2 / math.log(10):.0f} J into the oscillator by t_end = {t_end:g} s, "
                           f"beyond the range the solver computes in (energies up to {E_MAX:g} J); allowed: "
                           f"|P0 - m ag| <= {lim / t_end:.6g} N for t_end = {t_end:g} s and m = {osc.m:g} kg")
        raise BadInput(f"parameter record: the record's force m a(t) can put up to 10^{ef * 2 / math.log(10):.0f} J "
                       f"into the oscillator by t_end = {t_end:g} s, beyond the range the solver computes in "
                       f"(energies up to {E_MAX:g} J); allowed: int |a| dt <= {lim / osc.m:.6g} m/s over the record")
    P, T = work_periods(osc, w0, t_end)
    if P > MAX_PERIODS:
        lo, hi = 0.0, t_end                    # the largest t_end within MAX_PERIODS (P grows with t)
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            if work_periods(osc, w0, mid)[0] <= MAX_PERIODS:
                lo = mid
            else:
                hi = mid
        what = "forcing period" if osc.F.harmonic and osc.F.theta > osc.omega else "natural period"
        raise BadInput(f"parameter t_end = {t_end:g} s: the run would follow {P:.3g} periods of its "
                       f"shortest time scale ({what} {T:.4g} s); the exact solver takes about "
                       f"{US_PER_PERIOD} us per period and a run may follow at most {MAX_PERIODS:g} "
                       f"(about {MAX_PERIODS * US_PER_PERIOD * 1e-6:.0f} s); allowed: t_end <= {floor_g(lo)} s "
                       f"for these parameters")


def run(values: dict) -> dict:
    """Simulate one scene; returns the contract result dict.  SolverFailure (exit 1) when the
    result is not finite or the energy balance is worse than ENERGY_TOL."""
    osc, w0, t_end = build(values)
    try:
        return _run(osc, w0, t_end)
    except (OverflowError, ZeroDivisionError, FloatingPointError, MemoryError) as exc:
        raise SolverFailure(f"floating-point failure in the exact solution ({type(exc).__name__}: {exc}); "
                            f"the parameters are outside the range this solver computes in") from None


def _run(osc, w0, t_end):
    sol = osc.run(w0, t_end)
    amp, reason, t_steady = sol.steady()
    res = {
        "converged": True,
        "turning_points": [{"t": t, "w": w} for t, w in sol.turning],
        "stop": sol.stop(),
        "w_max": sol.w_max(),
        "steady_amplitude": amp,
    }
    if amp is None:
        res["steady_reason"] = reason
    else:
        res["steady_since_t"] = t_steady
    res.update({
        "steps": len(sol.segs),
        "energy_balance": sol.energy_balance(),
        "t_end": t_end,
        "omega": osc.omega,
        "period": TWO_PI / osc.omega,
        "theta": osc.F.theta if osc.F.harmonic else None,
        "_write": sol.write,
        "_history": sol.history,   # the time history as arrays, computed when asked for
    })
    bad = [key for key in ("w_max", "energy_balance") if not math.isfinite(res[key])]
    if bad or not all(math.isfinite(t) and math.isfinite(w) for t, w in sol.turning):
        raise SolverFailure(f"the solution is not finite ({', '.join(bad) or 'turning points'}): "
                            f"the parameters are outside the range this solver computes in")
    if res["energy_balance"] > ENERGY_TOL:
        raise SolverFailure(f"energy balance {res['energy_balance']:.3g} is worse than the tolerance "
                            f"{ENERGY_TOL:g} (relative to the largest energy)")
    return res


run_free = run_decay = run_harmonic = run
