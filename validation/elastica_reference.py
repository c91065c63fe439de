"""Independent large-rotation elastica references for femslide (planar rods, shooting method).

This module does not import femslide.  Each problem is a two-point boundary-value problem for the
planar Kirchhoff rod (Euler-Bernoulli: no shear), solved by shooting:

* the initial-value problem is integrated by scipy.integrate.solve_ivp (DOP853, rtol = 1e-12,
  atol = 1e-15 on the nondimensional problem, whose states are O(1) or the small deviations
  below);
* the shooting unknowns are found by Newton's method with the exact Jacobian (variational
  equations integrated alongside), stopped when the step is below 1e-13 (1 + |z|) or the residual
  reaches its round-off floor; scipy.optimize.root (hybr, same Jacobian, xtol 1e-13) is the
  fallback;
* the load is applied by continuation from zero (steps in sqrt(load factor), tangent predictor,
  adaptive steps, rejection of a corrector that lands far from the prediction), so the principal
  branch, the one reached by loading from the unloaded state, is followed.

Units and signs
---------------
SI inputs and outputs (m, N, N m, N/m, rad).  Axes x right, y up; angles from +x and moments are
counter-clockwise positive.  s is the arc length along the undeformed rod, 0 <= s <= L; theta(s)
the tangent angle.  n(s) and M(s) are the force and moment that the part beyond s exerts on the
part before s (so N = n . t is the tension, and M = EI theta' is positive when the rod turns
counter-clockwise as s increases).  Loads are dead (fixed in direction and magnitude).

Equations (per unit undeformed length; EA None = inextensible, eps = 0):

    r' = (1 + eps) t,  theta' = M / EI,  n' = -q,  M' = -(1 + eps) (t x n),  eps = (n . t) / EA,

t = (cos theta, sin theta), a x b = a_x b_y - a_y b_x.  Interior extrema of |M| are where
t x n = 0; they are located as events of the integration (M_max is exact to the integration
tolerance, not a sampled maximum).

Numerical formulation.  Lengths are scaled by L, forces by EI / L^2, moments by EI / L.  The rod is
described in the frame (t0, n0) of its undeformed axis (angle a): phi = theta - a, and the position
is r = (s + xi + rho_t / ea) t0 + (eta + rho_n / ea) n0 with
    xi' = cos phi - 1 = -2 sin^2(phi / 2),  eta' = sin phi,  rho' = (n . t) (cos phi, sin phi),
ea = EA L^2 / EI.  The deviations from the straight rod (xi ~ phi^2, eta ~ phi) and the stretch
(rho / ea) are integrated as separate states, so each keeps its relative accuracy: the axial
shortening of a slightly bent rod, or the ~N / EA stretch that fixes the clamp force of the
sliding-clamp rod, are not lost in the cancellation r(L) - L t0.

Limits (single shooting)
------------------------
* Tip-loaded cantilevers: tested up to P L^2 / EI = 100; near 200 the tip angle (the shooting
  unknown) is resolved to round-off only and the continuation stops (RuntimeError).
* A rod under high tension N has boundary layers ~exp(L sqrt(N / EI)); the sliding-clamp rod with its
  guide (nearly) across the rod and a large EA becomes such a string once the slide exceeds
  ~sqrt(EI / EA) L (EA L^2 / EI = 1e6: slides above ~1e-3 L): there the continuation needs hundreds
  of integrations (seconds) or gives up (RuntimeError after MAX_INTEGRATIONS).  Guides at an angle
  to the rod, the rods in tension or compression below buckling, and EA L^2 / EI <= 1e4 are cheap.
* At a limit point or bifurcation of the loading path (snap-through, buckling) the continuation
  stops with a RuntimeError saying so.

Closed forms used by the self-tests
-----------------------------------
* ``end_moment_circle``: tip moment only, M constant: a circular arc of radius EI / M (exact, also
  with EA: n = 0, no stretch).  M = 2 pi EI / L closes the rod into a full circle.
* ``tip_load_elliptic``: horizontal cantilever, vertical dead tip load P (Bisshopp & Drucker 1945,
  Q. Appl. Math. 3, 272; tabulated by Mattiasson 1981, Int. J. Numer. Meth. Eng. 17, 145):
  with alpha = P L^2 / EI, tip rotation theta_t, k^2 = (1 + sin theta_t) / 2 and
  sin phi0 = 1 / (k sqrt 2):  sqrt(alpha) = K(k) - F(phi0, k),
  y_tip / L = 1 - 2 (E(k) - E(phi0, k)) / sqrt(alpha),  x_tip / L = sqrt(2 sin theta_t / alpha).
"""
from __future__ import annotations

import math

import numpy as np
from scipy import optimize, special
from scipy.integrate import solve_ivp

__all__ = ["inclined_cantilever", "pinned_slider_rod", "end_moment_circle", "tip_load_elliptic",
           "RTOL", "ATOL", "XTOL"]

RTOL = 1e-12     # solve_ivp tolerances (nondimensional problem)
ATOL = 1e-15
XTOL = 1e-13     # Newton / scipy.optimize.root step tolerance on the shooting unknowns
RES_TOL = 1e-9   # largest accepted residual of the shooting equations (nondimensional)
RES_FLOOR = 1e-13  # residual at the integration's noise level: converged
HYBR_MAXFEV = 60 # integrations allowed to the scipy.optimize.root fallback per call
MAX_INTEGRATIONS = 1000   # per continuation, then RuntimeError (bounded run time)
ROT_STEP = 0.5   # continuation: first load step gives about this linear-theory rotation [rad]
ANGLE_TOL = 0.02 # continuation: accepted corrector move of an angle unknown beyond half its increment [rad]


class _BlowUp(Exception):
    """A shooting iterate left the physical range (the residual is then reported as nan)."""


def _blowup_event(i_phi, i_xi, i_eta):
    """Terminal-event factory: stop when the tangent angle exceeds 100 rad or a deviation from the
    straight rod exceeds 10 L (the trial solution left the physical range)."""
    def make():
        def ev(s, Y):
            return 10.0 - max(0.1 * abs(Y[i_phi]), abs(Y[i_xi]), abs(Y[i_eta]))
        ev.terminal = True
        return ev
    return make


_BLOWUP_CANTILEVER = _blowup_event(0, 2, 3)
_BLOWUP_SLIDER = _blowup_event(0, 1, 2)
MAX_STEPS = 5000    # integration steps per shot (a trial with a huge tension is stiff): _BlowUp


def _ivp(rhs, y0, s0=0.0, s1=1.0, events=None, blowup=None):
    """DOP853 from s0 to s1.  ``blowup`` (a factory from _blowup_event) adds a terminal event that
    stops trial solutions leaving the physical range, and more than MAX_STEPS steps also stop the
    shot (an exponentially growing or very stiff trial would otherwise take arbitrarily long):
    both raise _BlowUp."""
    evs = [] if events is None else [events]
    if blowup is not None:
        ev = blowup()
        count = [0]

        def guarded(s, Y):   # event functions are evaluated once per step
            count[0] += 1
            if count[0] > MAX_STEPS:
                raise _BlowUp()
            return ev(s, Y)
        guarded.terminal = True
        evs = [guarded] + evs
    sol = solve_ivp(rhs, (s0, s1), y0, method="DOP853", rtol=RTOL, atol=ATOL, events=evs)
    if sol.status == 1:
        raise _BlowUp()
    if sol.status != 0:
        raise RuntimeError(f"integration failed: {sol.message}")
    if blowup is not None and events is not None:
        sol.t_events, sol.y_events = sol.t_events[1:], sol.y_events[1:]
    return sol


def _cross(a, b):
    return a[0] * b[1] - a[1] * b[0]


# -- root finding and continuation --------------------------------------------------------------------

def _solve(fun, z0, maxiter=15, fallback=True):
    """Root of fun (returning (residual, Jacobian)) from z0: (z, J at z, Newton iterations) or None.

    Newton's method with the exact Jacobian and residual backtracking; converged when the step is
    below XTOL (1 + |z|) (or below sqrt(XTOL) (1 + |z|) and 1e-3 times the previous step: quadratic
    convergence makes the next one negligible), or the residual (nondimensional positions and
    angles) is below RES_FLOOR = 1e-13, the integration's own accuracy, or no step decreases the
    residual any more and it is below RES_TOL (an ill-conditioned Jacobian turns the residual's
    noise into steps above XTOL).  Given up early if the residual has not dropped 100-fold after 4
    iterations.  If Newton fails and ``fallback``: scipy.optimize.root (hybr, same Jacobian, xtol XTOL) from z0.
    Accepted only if max |residual| <= RES_TOL."""
    z = np.atleast_1d(np.asarray(z0, float)).copy()
    nit = 0
    try:
        r, J = fun(z)
        r_start = np.linalg.norm(r)
        prev = math.inf
        for nit in range(1, maxiter + 1):
            dz = -np.linalg.solve(J, r)
            nr = np.linalg.norm(r)
            for _ in range(5):   # backtracking
                zt = z + dz
                rt, Jt = fun(zt)
                if np.all(np.isfinite(rt)) and np.linalg.norm(rt) <= max(nr, 1e-15):
                    break
                dz = 0.5 * dz
            else:
                if np.max(np.abs(r)) <= RES_TOL:
                    break                     # at the round-off floor
                raise FloatingPointError("no decrease")
            z, r, J = zt, rt, Jt
            step = np.max(np.abs(dz)) / (1.0 + np.max(np.abs(z)))
            # converged: the step is below XTOL, or it is below sqrt(XTOL) after a quadratic
            # contraction (then the next step, ~ step^2, would be below XTOL), or the residual is
            # at the integration's noise level
            if (step <= XTOL or (step <= math.sqrt(XTOL) and step <= 1e-3 * prev)
                    or np.max(np.abs(r)) <= RES_FLOOR):
                break
            prev = step
            if nit == 4 and np.linalg.norm(r) > 1e-2 * r_start and np.max(np.abs(r)) > RES_TOL:
                raise FloatingPointError("slow")
        else:
            if np.max(np.abs(r)) > RES_TOL:
                raise FloatingPointError("no convergence")
    except (RuntimeError, ValueError, FloatingPointError, np.linalg.LinAlgError):
        if not fallback:
            return None
        try:
            sol = optimize.root(fun, np.atleast_1d(np.asarray(z0, float)), jac=True, method="hybr",
                                options=dict(xtol=XTOL, maxfev=HYBR_MAXFEV))
        except (RuntimeError, ValueError, FloatingPointError, np.linalg.LinAlgError):
            return None
        z = sol.x
        if not np.all(np.isfinite(z)):
            return None
        r, J = fun(z)
        nit = maxiter
    return (z, J, nit) if np.max(np.abs(r)) <= RES_TOL else None


class _Budget(Exception):
    pass


def _continuation(fun_at, z_zero, z_first, angles=None, max_rejects=30):
    """Follow the root z(lam) of fun_at(lam) from lam = 0 (where it is ``z_zero``) to lam = 1.

    The load factor is lam = tau^2 (equal steps in tau are equal steps in sqrt(load), which sets the
    rod's bending length sqrt(EI / P)).  First step: the linear-theory rotations (the angle
    unknowns of ``z_first(1)``) scaled to ROT_STEP, dtau = min(1, sqrt(ROT_STEP / max |rotation|))
    (a nearly straight rod is solved in one step); then x1.5 after an easy step (<= 5 Newton
    iterations), x0.5 after a rejected one.  Predictor:
    ``z_first(lam)`` (linear theory) for the first step, then the tangent dz/dlam = -J^-1 dr/dlam
    (dr/dlam by a difference in lam, J exact).  A step is rejected if Newton fails, or if an angle
    unknown (``angles``: boolean mask, default all) lands farther from its prediction than half its
    predicted increment plus ANGLE_TOL: with the tangent predictor that distance is O(dlam^2) on
    the followed branch, while distinct elastica branches differ by O(1) rad, so the test guards
    against jumping to another branch.  The hybr fallback of ``_solve`` is used only after three
    rejected steps in a row."""
    calls = [0]
    fun_at_raw = fun_at

    def fun_at(lam):   # counts the integrations (each call of a residual function is one)
        f = fun_at_raw(lam)

        def counted(z):
            calls[0] += 1
            if calls[0] > MAX_INTEGRATIONS:
                raise _Budget()
            return f(z)
        return counted

    z_last, J_last, tau = np.asarray(z_zero, float), None, 0.0
    mask = np.ones(z_last.size, bool) if angles is None else np.asarray(angles, bool)
    rot = float(np.max(np.abs(np.asarray(z_first(1.0), float) - z_last)[mask]))
    dtau = min(1.0, math.sqrt(ROT_STEP / max(rot, 1e-300)))
    rejects = rejects_in_row = 0
    det0 = None
    while tau < 1.0:
        tt = min(1.0, tau + dtau)
        lt = tt * tt
        if tau == 0.0:
            guess = np.asarray(z_first(lt), float)
        else:
            lam, h = tau * tau, 1e-6
            try:
                r_h, _ = fun_at(lam + h)(z_last)    # r(z_last, lam) = 0 (to RES_TOL, ~1e-14)
            except _Budget:
                raise RuntimeError(f"continuation gave up after {MAX_INTEGRATIONS} integrations") from None
            guess = z_last - np.linalg.solve(J_last, r_h / h) * (lt - lam)
        try:
            out = _solve(fun_at(lt), guess, maxiter=10, fallback=rejects_in_row >= 3)
        except _Budget:
            raise RuntimeError(f"continuation gave up after {MAX_INTEGRATIONS} integrations at load "
                               f"factor {tau * tau:.6g} (see the module's notes on hard cases)") from None
        ok = False
        if out is not None:
            z, J, nit = out
            inc = np.abs(guess - z_last)[mask]
            ok = bool(np.all(np.abs(z - guess)[mask] <= 0.5 * inc + ANGLE_TOL))
        if not ok:
            rejects += 1
            rejects_in_row += 1
            if rejects > max_rejects or (tau > 0 and dtau < 1e-9):
                hint = ""
                if J_last is not None and det0:
                    rel = abs(np.linalg.det(J_last) / det0)
                    if rel < 1e-3:
                        hint = (f" (det J fell to {rel:.1e} of its initial value: a limit point or "
                                "bifurcation - the rod snaps or buckles under this load)")
                raise RuntimeError(f"continuation failed at load factor {tau * tau:.6g}{hint}")
            dtau *= 0.5
            continue
        tau, z_last, J_last = tt, z, J
        if det0 is None:
            det0 = np.linalg.det(J)
        rejects_in_row = 0
        if nit <= 5:
            dtau *= 1.5
    return z_last


# -- a. inclined cantilever ---------------------------------------------------------------------------

def _cantilever_rhs(Ft, Fn, qt, qn, ea):
    """Cantilever in its axis frame, integrated from the tip (s = 1) to the root.
    State (phi, m, xi, eta, rho_t, rho_n, phi_p, m_p, I), p = the tip angle phi(1) (the shooting
    unknown), I = int_1^s (r - r_tip) x q ds."""
    iea = 0.0 if ea is None else 1.0 / ea

    def rhs(s, Y):
        ph, m, xi, eta, rt, rn, php, mp, _ = Y
        nt = Ft + qt * (1.0 - s)        # n in the (t0, n0) frame
        nn = Fn + qn * (1.0 - s)
        c, sn = math.cos(ph), math.sin(ph)
        N = c * nt + sn * nn            # n . t  (tension)
        B = c * nn - sn * nt            # t x n
        e1 = 1.0 + N * iea
        sh = math.sin(0.5 * ph)
        X = (s - 1.0 + xi + rt * iea)   # r - r_tip in the axis frame
        Yy = eta + rn * iea
        return [m, -e1 * B, -2.0 * sh * sh, sn, N * c, N * sn,
                mp, -php * (B * B * iea - e1 * N), X * qn - Yy * qt]
    return rhs


def inclined_cantilever(L: float, EI: float, angle: float, Fx: float, Fy: float, M: float = 0.0,
                        q=(0.0, 0.0), EA: float | None = None,
                        rotation_guess: float | None = None) -> dict:
    """Rod clamped at the origin along ``angle`` [rad from +x]; dead tip force (Fx, Fy) [N], tip
    moment M [N m] (counter-clockwise), uniform dead load q = (qx, qy) [N/m] per unit undeformed
    length (self-weight: q = rhoA g); EA [N] None = inextensible.

    With dead loads n(s) = F + q (L - s) is known and the equations do not involve the position,
    so the rod is integrated from the free tip (tangent angle the unknown, M(L) = M) to the root,
    and the equation is theta(0) = angle.  Shooting from the tip is the well-conditioned direction
    (from the clamp, d M(L) / d M(0) grows like exp(L sqrt(P / EI)): ~1e6 at P L^2 / EI = 300).
    Tested up to P L^2 / EI = 100 (single shooting reaches its round-off limit near 200).

    ``rotation_guess`` (tip rotation [rad]): skip the continuation and start Newton there, to
    reach a known equilibrium off the principal branch (e.g. an unstable straight state above the
    buckling load); by default the principal branch (loading from zero) is followed.

    Returns a dict:
      tip        (x, y) tip position [m]
      disp       (u, v) tip displacement [m] from the undeformed tip L (cos angle, sin angle)
      disp_axial, disp_transverse   the same along t0 = (cos angle, sin angle) and n0 (t0 + 90 deg)
      rotation   theta(L) - angle [rad]
      reaction   (Fx, Fy, M) force [N] and moment [N m] of the clamp on the rod
                 (= -(F + q L), -M(0))
      M_max      max |M(s)| [N m] over the rod (interior extrema by event location)
      s_M_max    arc length [m] where it occurs
      equilibrium   moment balance of the rod about the root [N m] (an integration check):
                 reaction M + (r_tip x F) + M + int r x q ds
      root_angle_residual   theta(0) - angle as solved [rad]
    """
    t0 = np.array([math.cos(angle), math.sin(angle)])
    n0 = np.array([-t0[1], t0[0]])
    F = np.array([Fx, Fy], float)
    qv = np.array(q, float)
    fs = L ** 2 / EI
    Ft, Fn = F @ t0 * fs, F @ n0 * fs
    qt, qn = qv @ t0 * fs * L, qv @ n0 * fs * L
    Mn = M * L / EI
    ea = None if EA is None else EA * L ** 2 / EI

    def y_tip(lam, z):
        return [z[0], lam * Mn, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0]

    def fun_at(lam):
        rhs = _cantilever_rhs(lam * Ft, lam * Fn, lam * qt, lam * qn, ea)

        def fun(z):
            try:
                Y = _ivp(rhs, y_tip(lam, z), 1.0, 0.0, blowup=_BLOWUP_CANTILEVER).y[:, -1]
            except _BlowUp:
                return np.array([np.nan]), np.eye(1)
            return np.array([Y[0]]), np.array([[Y[6]]])
        return fun

    rot_lin = Mn + 0.5 * Fn + qn / 6.0        # tip rotation, linear theory
    if rotation_guess is None:
        phL = float(_continuation(fun_at, [0.0], lambda lam: np.array([lam * rot_lin]))[0])
    else:
        out = _solve(fun_at(1.0), [rotation_guess])
        if out is None:
            raise RuntimeError("no equilibrium found from rotation_guess")
        phL = float(out[0][0])

    # final pass, with the extrema of M (t x n = 0) as events
    def txn(s, Y):
        return (math.cos(Y[0]) * (Fn + qn * (1 - s)) - math.sin(Y[0]) * (Ft + qt * (1 - s)))
    sol = _ivp(_cantilever_rhs(Ft, Fn, qt, qn, ea), y_tip(1.0, [phL]), 1.0, 0.0, events=txn,
               blowup=_BLOWUP_CANTILEVER)
    ph0, m0, xi0, eta0, rt0, rn0 = sol.y[:6, -1]
    I0 = sol.y[8, -1]
    iea = 0.0 if ea is None else 1.0 / ea
    ua = -xi0 - rt0 * iea                     # tip displacement along t0, n0 (nondimensional)
    ut = -eta0 - rn0 * iea
    cands = [(abs(m0), 0.0), (abs(Mn), 1.0)]
    cands += [(abs(Ye[1]), se) for se, Ye in zip(sol.t_events[0], sol.y_events[0])]
    mmax, smax = max(cands)
    rtip = (1.0 + ua, ut)                     # tip relative to the root, axis frame
    # int_0^1 (r - r_root) x q = int (r - r_tip) x q + (r_tip - r_root) x q = -I0 + rtip x q
    eq = -m0 + _cross(rtip, (Ft, Fn)) + Mn + (-I0 + _cross(rtip, (qt, qn)))
    disp = (ua * t0 + ut * n0) * L
    return dict(
        tip=tuple(float(v) for v in L * t0 + disp),
        disp=tuple(float(v) for v in disp),
        disp_axial=float(ua * L),
        disp_transverse=float(ut * L),
        rotation=phL,
        reaction=(float(-(Fx + qv[0] * L)), float(-(Fy + qv[1] * L)), float(-m0 * EI / L)),
        M_max=float(mmax * EI / L),
        s_M_max=float(smax * L),
        equilibrium=float(eq * EI / L),
        root_angle_residual=float(ph0),
    )


# -- b. pinned rod in a sliding clamp -----------------------------------------------------------------

def _slider_rhs(nt, nn, gt, gn, ea):
    """Pinned rod in its axis frame, from the base (s = 0) to the top.  n = (nt, nn) constant,
    (gt, gn) = dn/dc (g_perp in the axis frame).  State (phi, xi, eta, rho_t, rho_n) and its
    derivatives with respect to p1 = phi(0) and p2 = c."""
    iea = 0.0 if ea is None else 1.0 / ea

    def rhs(s, Y):
        ph, xi, eta, rt, rn = Y[:5]
        c, sn = math.cos(ph), math.sin(ph)
        X = s + xi + rt * iea
        Yy = eta + rn * iea
        N = c * nt + sn * nn
        B = c * nn - sn * nt
        sh = math.sin(0.5 * ph)
        out = [-(X * nn - Yy * nt), -2.0 * sh * sh, sn, N * c, N * sn]
        for k, (dnt, dnn) in ((5, (0.0, 0.0)), (10, (gt, gn))):
            php, xip, etap, rtp, rnp = Y[k:k + 5]
            Xp = xip + rtp * iea
            Yp = etap + rnp * iea
            Np = B * php + c * dnt + sn * dnn
            out += [-(Xp * nn - Yp * nt) - (X * dnn - Yy * dnt),
                    -sn * php, c * php, Np * c - N * sn * php, Np * sn + N * c * php]
        return out
    return rhs


def pinned_slider_rod(L: float, EI: float, angle: float, guide_angle: float, F,
                      EA: float | None = None) -> dict:
    """Rod of length L pinned at the origin (moment-free), initially straight along ``angle``; its top
    sits in a sliding clamp fixed to the ground: the top stays on the line through the initial top
    T0 = L (cos angle, sin angle) along g = (cos guide_angle, sin guide_angle), its tangent angle stays
    ``angle``, and it slides freely along g.  Dead force F = (Fx, Fy) [N] on the top.  EA [N] None:
    inextensible.

    The internal force n is constant, n = F + c g_perp (g_perp = g turned +90 deg: the clamp
    pushes only across its guide, so n . g = F . g, the along-guide equilibrium), and
    M(s) = -(r(s) x n) (moment-free pin at r = 0).  Shooting unknowns (theta(0), c); equations
    (r(L) - T0) . g_perp = 0 and theta(L) = angle.

    Caveat (kinematics, not numerics): an inextensible rod is locked in this support unless it
    buckles: its top can only move along g if the chord shortens, so below buckling the solution
    is the straight rod with slide 0; with g perpendicular to the rod no equilibrium exists for
    F . g != 0 (ValueError).  A finite EA gives the sliding solution; its small-load limit is two
    springs in series along g: slide = (F . g) / (EA/L cos^2 b + 3EI/L^3 sin^2 b), b = guide_angle -
    angle (axial stretch, and the bending of a rod clamped at the top and loaded at its pinned base).
    With g perpendicular to the rod the extensible rod stiffens like a string once the slide is
    comparable with sqrt(EI / EA) (the chord must stretch).

    Returns a dict:
      slide            (r(L) - T0) . g [m]
      guide_offset     (r(L) - T0) . g_perp [m] (the enforced 0, as solved)
      top_rotation     theta(L) - angle [rad] (the enforced 0, as solved)
      tip              (x, y) top position [m]
      base_reaction    (Fx, Fy) force of the pin on the rod [N] (= -n)
      clamp_transverse c [N], the clamp's force on the rod top along g_perp = (-sin g, cos g)
      clamp_force      (Fx, Fy) = c g_perp [N]
      clamp_moment     moment of the clamp on the rod top [N m] (= M(L))
      M_max, s_M_max   max |M| [N m] and where [m]
      base_rotation    theta(0) - angle [rad]
      axial_force_base tension n . t(0) [N]
    """
    t0 = np.array([math.cos(angle), math.sin(angle)])
    n0 = np.array([-t0[1], t0[0]])
    g = np.array([math.cos(guide_angle), math.sin(guide_angle)])
    gp = np.array([-g[1], g[0]])
    fs = L ** 2 / EI
    Fv = np.array(F, float)
    Ft, Fn = Fv @ t0 * fs, Fv @ n0 * fs
    gpt, gpn = gp @ t0, gp @ n0              # g_perp in the axis frame
    gt = g @ t0                               # 0: guide across the rod
    ea = None if EA is None else EA * L ** 2 / EI
    iea = 0.0 if ea is None else 1.0 / ea

    # linear theory: top displacement d = (N / ea) t0 + (V / 3) n0 with (N, V) = n in the axis
    # frame; c from d . g_perp = 0
    den = gpt ** 2 * iea + gpn ** 2 / 3.0
    if ea is None and abs(gt) < 1e-12 and abs(Fv @ g) > 0.0:       # guide across the rod
        raise ValueError("inextensible rod with the guide perpendicular to it: locked, no "
                             "equilibrium for F . g != 0 (give EA)")
    c_lin = -(Ft * gpt * iea + Fn * gpn / 3.0) / den if den > 0 else 0.0

    def first(lam):
        V = lam * (Fn + c_lin * gpn)
        return np.array([0.5 * V, lam * c_lin])    # base rotation V L^2 / 2EI

    def y_base(z):
        return [z[0], 0.0, 0.0, 0.0, 0.0, 1.0, 0, 0, 0, 0, 0, 0, 0, 0, 0]

    def fun_at(lam):
        def fun(z):
            rhs = _slider_rhs(lam * Ft + z[1] * gpt, lam * Fn + z[1] * gpn, gpt, gpn, ea)
            try:
                Y = _ivp(rhs, y_base(z), blowup=_BLOWUP_SLIDER).y[:, -1]
            except _BlowUp:
                return np.full(2, np.nan), np.eye(2)
            dX, dY = Y[1] + Y[3] * iea, Y[2] + Y[4] * iea          # r(1) - T0, axis frame
            dX1, dY1 = Y[6] + Y[8] * iea, Y[7] + Y[9] * iea
            dX2, dY2 = Y[11] + Y[13] * iea, Y[12] + Y[14] * iea
            r = np.array([dX * gpt + dY * gpn, Y[0]])
            J = np.array([[dX1 * gpt + dY1 * gpn, dX2 * gpt + dY2 * gpn], [Y[5], Y[10]]])
            return r, J
        return fun

    ph0, c = _continuation(fun_at, [0.0, 0.0], first, angles=[True, False])
    nt, nn = Ft + c * gpt, Fn + c * gpn

    def txn(s, Y):
        return math.cos(Y[0]) * nn - math.sin(Y[0]) * nt
    sol = _ivp(_slider_rhs(nt, nn, gpt, gpn, ea), y_base([ph0, c]), events=txn, blowup=_BLOWUP_SLIDER)
    Y = sol.y[:, -1]
    dX, dY = Y[1] + Y[3] * iea, Y[2] + Y[4] * iea

    def mom(s, Ys):
        return -((s + Ys[1] + Ys[3] * iea) * nn - (Ys[2] + Ys[4] * iea) * nt)
    mL = mom(1.0, Y)
    cands = [(0.0, 0.0), (abs(mL), 1.0)]
    cands += [(abs(mom(se, Ye)), se) for se, Ye in zip(sol.t_events[0], sol.y_events[0])]
    mmax, smax = max(cands)
    f = EI / L ** 2
    nvec = (nt * t0 + nn * n0) * f
    d = (dX * t0 + dY * n0) * L
    return dict(
        slide=float(d @ g),
        guide_offset=float((dX * gpt + dY * gpn) * L),
        top_rotation=float(Y[0]),
        tip=tuple(float(v) for v in L * t0 + d),
        base_reaction=(float(-nvec[0]), float(-nvec[1])),
        clamp_transverse=float(c * f),
        clamp_force=(float(c * f * gp[0]), float(c * f * gp[1])),
        clamp_moment=float(mL * EI / L),
        M_max=float(mmax * EI / L),
        s_M_max=float(smax * L),
        base_rotation=float(ph0),
        axial_force_base=float((math.cos(ph0) * nt + math.sin(ph0) * nn) * f),
    )


# -- c. closed forms ----------------------------------------------------------------------------------

def end_moment_circle(L: float, EI: float, M: float, angle: float = 0.0) -> dict:
    """Cantilever clamped at the origin along ``angle``, tip moment M only: constant curvature
    kappa = M / EI (exact; also extensible: no axial force).  Tip on the circle of radius 1/kappa:
    tip = (sin(angle + kappa L) - sin angle, cos angle - cos(angle + kappa L)) / kappa.
    M = 2 pi EI / L: tip back at the root, rotation 2 pi.  Keys as ``inclined_cantilever``."""
    k = M / EI
    if k == 0.0:
        x, y = L * math.cos(angle), L * math.sin(angle)
    else:
        x = (math.sin(angle + k * L) - math.sin(angle)) / k
        y = (math.cos(angle) - math.cos(angle + k * L)) / k
    return dict(tip=(x, y), disp=(x - L * math.cos(angle), y - L * math.sin(angle)),
                rotation=k * L, reaction=(0.0, 0.0, -M), M_max=abs(M))


def tip_load_elliptic(L: float, EI: float, P: float) -> dict:
    """Horizontal cantilever (clamped at the origin along +x), vertical dead tip force P [N] (any
    sign): Bisshopp-Drucker elliptic-integral solution (module docstring), theta_t by brentq on
    sqrt(alpha) = K(k) - F(phi0, k) (scipy.special ellipkm1/ellipkinc/ellipe/ellipeinc, parameter
    m = k^2, 1 - m = sin^2(pi/4 - theta_t/2)).  Returns tip (x, y), disp (u, v), rotation."""
    alpha = abs(P) * L ** 2 / EI
    if alpha == 0.0:
        return dict(tip=(L, 0.0), disp=(0.0, 0.0), rotation=0.0)
    ra = math.sqrt(alpha)

    def parts(tt):
        p = math.sin(math.pi / 4 - tt / 2) ** 2     # 1 - m, without cancellation near tt = pi/2
        m = 1.0 - p
        phi0 = math.asin(min(1.0, 1.0 / math.sqrt(2.0 * m)))
        return m, p, phi0

    def eq(tt):
        m, p, phi0 = parts(tt)
        return special.ellipkm1(p) - special.ellipkinc(phi0, m) - ra
    tt = optimize.brentq(eq, 1e-300, math.pi / 2 - 1e-15, xtol=1e-16, rtol=4 * np.finfo(float).eps)
    m, _, phi0 = parts(tt)
    yt = L * (1.0 - 2.0 * (special.ellipe(m) - special.ellipeinc(phi0, m)) / ra)
    xt = L * math.sqrt(2.0 * math.sin(tt) / alpha)
    sg = 1.0 if P > 0 else -1.0
    return dict(tip=(xt, sg * yt), disp=(xt - L, sg * yt), rotation=sg * tt)
