"""The stored closed-form segments of an exact one-mass oscillator run, evaluated afterwards.

:class:`Solution` evaluates the displacement, velocity, forcing and friction force at any times
(vectorised over the stored segments), the energy balance (10-point Gauss on every segment), the
turning points, the stop and the steady amplitude of a forced run, and writes the history.
"""
from __future__ import annotations

import math
import numpy as np

from femslide.errors import SolverFailure
from femslide.results.outcome import Table

# 10-point Gauss-Legendre rule on [-1, 1] (energy balance): computed once
_GAUSS10 = np.polynomial.legendre.leggauss(10)
TWO_PI = 2.0 * math.pi
STEADY_TOL = 1e-10      # m: two successive forcing periods must agree to this for a steady state
E_MAX = 1e250           # J: energies (and so w, v, forces) stay far inside the float range
HISTORY_ROWS = 1_000_000  # history.csv: 64 samples per shortest period, at most this many


class Solution:
    """Stored closed-form segments of a run, with vectorised evaluation and summary quantities."""

    def __init__(self, osc, w0, t_end, segs, turning, forever, friction_work):
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

    def tables(self, points_per_period=64):
        """The files of a run: history.csv (t, w, v, state) and turning_points.csv (t, w)."""
        h = self.history(points_per_period)
        t, w, v, st = h["t"], h["w"], h["v"], h["state"]
        if not (np.isfinite(w).all() and np.isfinite(v).all()):
            raise SolverFailure("the time history is not finite; nothing written")
        tp = np.array(self.turning, dtype=float).reshape(-1, 2)
        return [Table("history.csv", ["t [s]", "w [m]", "v [m/s]", "state (+1/-1 sliding direction; 0 stuck)"],
                      [t, w, v, st], ["%.17g", "%.17g", "%.17g", "%d"]),
                Table("turning_points.csv", ["t [s]", "w [m]"], [tp[:, 0], tp[:, 1]])]
