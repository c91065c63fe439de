"""Exact references for friction in statics under load histories (independent of femslide: floats).

One-dimensional, rate-independent Coulomb friction, exact event by event (the responses are
piecewise linear in the free thermal elongation e, so every switch is found in closed form):

* :func:`one_slider`: an elastic member of axial stiffness k [N/m] (a rod EA/L, or a column's
  3 EI/H^3 in series with a deck's EA/L) between a fixed point and a slider with friction (normal
  force N, static mu0, kinetic mu); e [m] is the member's free elongation (alpha dT L), the member's
  force P = k (s - e) (tension > 0), s the slide.  The friction force on the member's end along +s
  balances the member's pull: F = P.  Stuck while |P| <= mu0 N; slipping: P = -sigma mu N with sigma
  the direction of the slide (a jump of the slide by (mu0 - mu) N / k at a breakaway); a slipping
  slider sticks when e turns back.
* :func:`incline_two_sliders`: a rod of stiffness k on two frictional sliders on an incline, each end
  carrying the normal force N and the downhill force T (its weight's components); slides s1 (lower
  end), s2 (upper end), uphill positive; rod force P = k (s2 - s1 - e); friction on the lower end
  F1 = T - P, on the upper F2 = T + P (each end's equilibrium along the incline).  Heating slides the
  lower end downhill, cooling the upper one: the rod walks downhill by a fixed amount per cycle
  (thermal ratcheting).

Histories are lists of e values at the steps (linear in between, e = 0 at the start).  Each
function returns, per step, the slides, the friction forces and the joints' states.
"""
from __future__ import annotations


def one_slider(k, N, mu, mu0, e_steps):
    """Per step: dict(slide, force, state) of the slider of :func:`one_slider`'s model."""
    s, e, stuck, sigma = 0.0, 0.0, True, 0.0
    out = []
    for e1 in e_steps:
        de = e1 - e
        if not stuck and de != 0.0 and (1.0 if de > 0 else -1.0) != sigma:
            stuck = True                     # the slide would turn back: it sticks where it is
        if stuck:
            P1 = k * (s - e1)
            if abs(P1) > mu0 * N:            # breakaway at P = -+mu0 N, then slip at mu N
                sigma = 1.0 if de > 0 else -1.0
                stuck = False
        if not stuck:
            s = e1 - sigma * mu * N / k
        e = e1
        P = k * (s - e)
        out.append({"slide": s, "force": P, "state": "stuck" if stuck else "slipping"})
    return out


def incline_two_sliders(k, N, T, mu, mu0, e_steps):
    """Per step: dict(s1, s2, F1, F2, P, states) of :func:`incline_two_sliders`' model.  Assumes
    T < mu N (the rod rests on the incline) and never both ends slipping."""
    s1 = s2 = e = 0.0
    st = ["stuck", "stuck"]
    sig = [0.0, 0.0]
    out = []

    def P_of(ee):
        if st[0] == "slip":
            return T + sig[0] * mu * N       # F1 = T - P = -sig1 mu N
        if st[1] == "slip":
            return -sig[1] * mu * N - T      # F2 = T + P = -sig2 mu N
        return k * (s2 - s1 - ee)

    for e1 in e_steps:
        de = e1 - e
        d = 1.0 if de > 0 else -1.0
        # a slipping end whose slide would turn back sticks (lower end: ds1/de = -1, upper: +1)
        if st[0] == "slip" and sig[0] != -d:
            st[0] = "stuck"
        if st[1] == "slip" and sig[1] != d:
            st[1] = "stuck"
        while True:
            if st[0] == "stuck" and st[1] == "stuck":
                # P = k (s2 - s1 - e) from e to e1: the first end to reach mu0 N
                cands = []
                for i in (0, 1):
                    # F1 = T - P, F2 = T + P, linear in ee: T + sgn k (s2 - s1 - ee); solve |F| = mu0 N
                    sgn = -1.0 if i == 0 else 1.0
                    for target in (mu0 * N, -mu0 * N):
                        # T + sgn k (s2 - s1 - ee) = target
                        ee = (s2 - s1) - (target - T) / (sgn * k)
                        if (ee - e) * d > 1e-15 and (e1 - ee) * d >= -1e-15:
                            cands.append((abs(ee - e), ee, i, target))
                if not cands:
                    break
                _, ee, i, target = min(cands)
                # the end i breaks away: it moves against the friction that held it
                st[i] = "slip"
                sig[i] = -1.0 if target > 0 else 1.0
                e = ee
                P = P_of(e)
                if i == 0:
                    s1 = s2 - e - P / k
                else:
                    s2 = s1 + e + P / k
                continue
            break
        P = P_of(e1)
        if st[0] == "slip":
            s1 = s2 - e1 - P / k
        elif st[1] == "slip":
            s2 = s1 + e1 + P / k
        e = e1
        P = k * (s2 - s1 - e)
        out.append({"s1": s1, "s2": s2, "P": P, "F1": T - P, "F2": T + P, "states": tuple(st)})
    return out
