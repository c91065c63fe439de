"""The reduced one-degree-of-freedom model of the paper's section 5.2 structure in time: an independent
reference for the scenes beam-oscillation and beam-friction (which run on the FE transient,
femslide/scenes/beam_dynamics.py) - validation only, nothing in femslide/ imports it.

It was femslide's own dynamics of these scenes until the FE transient replaced it (issue 21); here it
is stripped of the progress bar, the work budget and the file writing.  Use::

    from validation.reduced_dynamics import run_oscillation, run_friction
    res = run_oscillation(get("beam-oscillation").resolve({...}))   # the scene's values, SI
    res["history"]      # {t, phi, phi_dot, slide, stuck, F_ax, N, F1, N1, F2, N2}: arrays (SI)

Energy balance and Coulomb's law are checked after every run (SolverFailure when violated).

Model (SI units; the statics inside are nondimensional, lengths by a, forces by P = m g):

* The structure is that of ``beam-extra-mass`` (femslide/scenes/paper.py) at dm = 0: rigid left rod AA1
  (part of the body, pinned at A1), flexible right rod of free length L (n_elements corotational
  beams, pinned at B1) in the sliding clamp at B, the slider spring k preloaded with
  F_el = P (a + d)/(2a) so that phi = 0 is the equilibrium, and the rigid telescopic piece (mass m1,
  length l2) fixed to the rod's top node S, along the guide, its centre at S + (l2/2) e.
* Mesh: a fixed n_elements (scene default 8; no adaptive refinement in the dynamics).  Chord
  rotations are measured from the undeformed chords (valid while every chord turns < 2.5 rad).
* The rods are massless (as in the paper): they carry elastic energy only.  The masses are the body
  (m at G, rotary inertia of a uniform 2a x 2b rectangle about G, J_G = m ((2a)^2 + (2b)^2)/12) and
  the piece (m1 at its centre, m1 l2^2/12 about it).
* For every phi the massless rod takes its static configuration under gravity and the spring (the
  "controlled statics": the body rotation is held at phi by a lock constraint whose multiplier is
  the generalised force -dV/dphi).  The structure is then a one-degree-of-freedom system in phi:
  every mass point is x = R(-phi) rho(s) with rho fixed in the body (the body is pinned at A1) and
  the slide s = s(phi) of the statics, so with s' = ds/dphi, s'' = d2s/dphi2 from the first- and
  second-order sensitivities of the statics (one extra back-substitution each, the second with a
  finite-difference directional derivative of the Jacobian)

      T = M(phi) phi'^2 / 2,    M(phi) phi'' + M'(phi) phi'^2 / 2 = Q(phi) - c_v phi' + Q_g(t, phi),

  Q = -dV/dphi, V = rod strain energy + weights + spring energy of the static state, Q_g the
  generalised force of the ground-acceleration inertia -m_i a_g(t) e_x (beam-friction).  The
  reduction is exact for massless rods except for one neglect, stated here: the piece's inertia
  force along the guide is not fed back into the rod's static configuration (it would change s
  through the rod's axial compliance, by ~ m1 a / (EA/L), and its bending shape by a
  relative ~ N L^2/EI times the chord shortening).
* Reactions at an instant are recovered by d'Alembert: the inertia forces -m a (a = phi'' dx/dphi
  + phi'^2 d2x/dphi2, plus the ground acceleration) and moments are added as loads to the statics
  at that phi, and the pin multipliers give (F, N) as in statics.extract.  The lock multiplier of
  that solve must vanish (the equation of motion): its largest value relative to max |Q| is
  reported as ``dalembert_residual``.

beam-friction (m1 = 0: the rod and the piece are massless; see :func:`run_friction`):
  Coulomb friction in the sliding clamp, normal force N = |transverse clamp force| (the clamp's
  first multiplier; its moment is not counted), axial (guide) force F_ax = the multiplier of a lock
  of the slide.  Stuck: s is held fixed (s' = 0 exactly), the system is 1-DOF in phi with the rod
  clamped in the guide (stiff: the rod must stretch); breakaway when |F_ax| > mu0 N.  Slipping in
  the direction sigma: the massless slide obeys F_ax = sigma mu N (an algebraic equation solved
  together with the statics at each phi); slip ends when s' = (ds/dphi) phi' returns to zero, and the
  slide sticks there only if static friction can hold it (see :func:`run_friction`).  With
  mu0 > mu the massless slide jumps at breakaway (at fixed phi, phi') to the slip state; the elastic
  energy released by the jump is dissipated (reported as ``jump_loss``).  The forcing is a
  horizontal ground acceleration a_g(t) = ag sin(theta t) (+ an optional record), theta =
  theta_ratio * omega with omega = sqrt(K/M) the small-oscillation frequency of the *frictionless*
  structure (slide free, spring k) about the vertical state.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from femslide.errors import BadInput, SolverFailure
from femslide.joints.holds import SlideHold
from femslide.model.state import ElementState
from femslide.model.linalg import lu_factor, lu_solve

N_DEFAULT = 8          # elements of the flexible rod when n_elements is not given
N_MAX_DYN = 150        # dense Jacobians (size < 600)
NEWTON_TOL = 1e-12
ENERGY_TOL = 1e-6      # energy balance worse than this fails the run (SolverFailure)
COULOMB_TOL = 1e-6     # relative: |F_ax| <= mu0 N (1 + tol) while stuck, else the run fails

# -- extra constraints and loads ----------------------------------------------------------------------

@dataclass
class RotationLock:
    """Body rotation held at ``value`` (Theta = -phi); multiplier = -dV/dTheta (a moment, P a)."""
    dof: int
    value: float = 0.0
    name: str = "rotation lock"
    size: int = 1

    @property
    def dofs(self):
        return np.array([self.dof])

    def eval(self, z, mu=None):
        """g, G and the Hessians (or, given the multiplier, their weighted sum): joints.py protocol."""
        return np.array([z[0] - self.value]), np.ones((1, 1)), np.zeros((1, 1) if mu is not None else (1, 1, 1))


@dataclass
class InertiaLoads:
    """Dead forces FG (at the body's centroid, offset rG from its frame origin) and moment MB on the
    body and FC on the piece's frame origin (its centroid): d'Alembert loads for the recovery of
    reactions.  Zero during the run."""
    body_dofs: np.ndarray
    piece_dofs: np.ndarray | None
    rG: tuple
    FG: np.ndarray
    MB: float = 0.0
    FC: np.ndarray = None
    name: str = "inertia"

    @property
    def dofs(self):
        return self.body_dofs if self.piece_dofs is None else np.concatenate([self.body_dofs, self.piece_dofs])

    def eval(self, z, lam=1.0):
        t = float(z[2])
        c, s = math.cos(t), math.sin(t)
        rx, ry = self.rG
        Rx, Ry = c * rx - s * ry, s * rx + c * ry
        FG = self.FG
        g = np.zeros(z.size)
        H = np.zeros((z.size, z.size))
        E = -(FG[0] * (z[0] + Rx - rx) + FG[1] * (z[1] + Ry - ry)) - self.MB * t
        g[:2] = -FG
        g[2] = -(FG[0] * -Ry + FG[1] * Rx) - self.MB
        H[2, 2] = lam * (FG[0] * Rx + FG[1] * Ry)
        if self.FC is not None and self.piece_dofs is not None:
            g[3:5] = -self.FC
            E -= float(self.FC @ z[3:5])
        return lam * E, lam * g, H, g


# -- the reduced structure ------------------------------------------------------------------------------

@dataclass
class Point:
    """The statics at one phi: state, generalised force and slide derivatives (nondimensional)."""
    phi: float
    y: np.ndarray
    alpha: np.ndarray
    Q: float        # -dV/dphi [P a]
    s: float        # slide [a]
    s1: float       # ds/dphi
    s2: float       # d2s/dphi2
    lam_s: float = 0.0  # guide axial force (slide-lock multiplier) [P]
    N: float = 0.0      # |transverse clamp force| [P]
    dQ: float = 0.0     # dQ/dphi along the current mode's path
    lam_s1: float = 0.0  # d lam_s / dphi along the current mode's path [P/rad]
    Nc: float = 0.0      # transverse clamp force, signed (N = |Nc|) [P]
    Nc1: float = 0.0     # d Nc / dphi [P/rad]


class Structure:
    """beam-extra-mass at dm = 0 with a rotation lock (and, with friction, a slide lock)."""

    def __init__(self, v, friction=False):
        from femslide.model.discrete import Model
        from femslide.scenes.paper import declare
        n = v.get("n_elements") or N_DEFAULT
        if n > N_MAX_DYN:
            raise BadInput(f"parameter n_elements = {n} is too large for the dynamic scenes; "
                           f"allowed: 1 <= n_elements <= {N_MAX_DYN}")
        self.n_el = n
        vv = {**v, "dm": 0.0}
        if friction:
            vv["m1"] = 0.0
            vv.setdefault("l2", 1.0)
        self.v = vv
        a = v["a"]
        self.a, self.P = a, v["m"] * v["g"]
        self.Pa = self.P * a
        m = Model(declare("beam-extra-mass", vv).freeze(), {"right": n}, a, self.P, finalize=False)
        self.model = m
        self.clamp = clamp = m.joint["clamp"]
        th_dof = m.body_dof("deck") + 2
        self.th_dof = th_dof
        self.rot = m.add_constraint(RotationLock(th_dof))
        self.slock = m.add_constraint(SlideHold(clamp, name="slide lock")) if friction else None
        self.h = 0.5 * vv["l2"] / a
        piece = np.arange(m.body_dof("piece"), m.body_dof("piece") + 3) if "piece" in m.body_index else None
        rG = np.array([v["a"] + v["d"], v["l"] + v["b"]]) / a - m.body_X0[m.body_index["deck"]]
        self.inertia = m.add_term(InertiaLoads(np.arange(th_dof - 2, th_dof + 1), piece, tuple(rG), np.zeros(2)))
        m.finalize()
        idx = m.constraints.index(self.rot)
        self.row_rot = m.n_q + int(m.c_off[idx])
        self.row_clamp = m.n_q + int(m.c_off[m.constraints.index(clamp)])
        self.row_A1 = m.n_q + int(m.c_off[m.constraints.index(m.joint["A1"])])
        self.row_B1 = m.n_q + int(m.c_off[m.constraints.index(m.joint["B1"])])
        self.row_s = (m.n_q + int(m.c_off[m.constraints.index(self.slock)])) if friction else None
        self.cdofs = clamp.dofs
        # masses (SI)
        self.mass, self.m1 = v["m"], vv["m1"]
        self.JG = v["m"] * ((2 * a) ** 2 + (2 * v["b"]) ** 2) / 12.0
        self.Jc = self.m1 * vv["l2"] ** 2 / 12.0
        self.L = (v.get("L") or v["l"]) / a
        self.rhoG = np.array([1.0 + v["d"] / a, v["l"] / a + v["b"] / a])  # G - A1 in the body frame [a]
        self.M_body = self.JG + v["m"] * a * a * float(self.rhoG @ self.rhoG)
        self.y, _elements = m.zero_state()
        self.alpha = _elements.committed
        self.alpha_ref = self.alpha.copy()
        self.n_solves = 0
        self.n_newton = 0
        # mode: "free" (slide free; friction model only: slide-lock row replaced by lam_s = 0),
        # "stuck" (slide locked at s_c), "slip" (lam_s = sigma mu N)
        self.mode = "free"
        self.sigma = 0.0
        self.mu = 0.0

    # -- statics ----------------------------------------------------------------------------------
    def _system(self, y, alpha):
        es = ElementState(alpha)
        r, A, info = self.model.system(y, es, 1.0, dense=True)
        info["alpha"] = es.trial
        if self.slock is not None and self.mode != "stuck":
            i = self.row_s
            jN = self.row_clamp
            muN = y[jN]
            c = self.sigma * self.mu if self.mode == "slip" else 0.0
            r[i] = y[i] - c * abs(muN)
            A[i, :] = 0.0
            A[i, i] = 1.0
            A[i, jN] -= c * (1.0 if muN >= 0 else -1.0)
        return r, A, info

    def solve(self, phi, y0=None, alpha0=None, s_c=None, maxit=40):
        """Newton solve of the statics at phi from (y0, alpha0) (default: the last state); returns
        (y, alpha, lu of the Jacobian at the solution)."""
        m = self.model
        y = (self.y if y0 is None else y0).copy()
        # chord rotations are measured from the fixed undeformed chords (alpha_ref = 0), not from
        # the last state: the residual is then one smooth function of y to round-off (a moving
        # reference changes the rounding of cos/sin(beta0 + alpha_ref) from solve to solve, which
        # scatters Q by ~1e-8 relative with EI/(P a^2) = 1e5); valid while every chord turns by
        # less than pi - checked below
        alpha = self.alpha_ref
        self.rot.value = -phi
        if self.slock is not None and s_c is not None:
            self.slock.target = s_c
        n_q = m.n_q
        hist = []
        for it in range(maxit):
            r, A, info = self._system(y, alpha)
            res_f = float(np.abs(r[:n_q]).max()) / (1.0 + info["fmax"])
            res_g = float(np.abs(r[n_q:]).max())
            hist.append(max(res_f, res_g))
            if not np.isfinite(hist[-1]):
                break
            try:
                lu = lu_factor(A)
            except (ValueError, np.linalg.LinAlgError) as exc:
                raise SolverFailure(f"singular tangent at phi = {phi:.6g} rad ({exc})", hist)  # noqa: B904 (cause in the message)
            dy = -lu_solve(lu, r)
            res = max(res_f, res_g)
            # converged at the tolerance, or at the round-off floor of the stiff rod (the nearly
            # inextensible rod, EA/EI ~ 1e6 m^-2, floors the force residual near 1e-10 relative):
            # no halving of the residual for 3 iterations while below 1e-8
            floor = 10.0 * info["noise"] / (1.0 + info["fmax"])  # the model's round-off estimate
            conv = res <= NEWTON_TOL or (it >= 3 and res <= max(1e-8, floor)
                                         and min(hist[-4:-1]) <= 2.0 * res)
            # the converged state takes one more (tiny) Newton step: the solution is then a smooth
            # function of phi to round-off, which the high-order integrator needs
            y += dy
            alpha_now = info["alpha"]
            self.n_newton += 1
            if conv:
                if alpha_now.size and float(np.abs(alpha_now).max()) > 2.5:
                    raise SolverFailure(f"a rod chord turned by more than 2.5 rad at phi = {phi:.6g} rad "
                                        f"(outside the dynamic model's fixed chord reference)", hist)
                self.n_solves += 1
                self.y, self.alpha = y, alpha
                return y, alpha, lu
            big = np.abs(dy[:n_q]).max()
            if big > 0.3:
                y -= dy * (1.0 - 0.3 / big)
        raise SolverFailure(f"statics at phi = {phi:.6g} rad did not converge ({self.mode})", hist)

    def slide(self, y):
        return float(self.clamp.slide(y[self.cdofs])[0])

    def potential(self, y, alpha):
        """Total potential energy of a state [P a]: strain energy + weights + spring (no inertia)."""
        return self.model.potential(y, alpha, skip=self.inertia)

    def point(self, phi, second=True, s_c=None):
        """Statics at phi with sensitivities (see :class:`Point`)."""
        y, alpha, lu = self.solve(phi, s_c=s_c)
        m = self.model
        e = np.zeros(y.size)
        e[self.row_rot] = 1.0
        y1 = -lu_solve(lu, e)        # dy/dphi
        s, ds, Hs = self.clamp.slide(y[self.cdofs])
        q1 = y1[self.cdofs]
        s1 = float(ds @ q1)
        s2 = 0.0
        if second and self.m1 > 0:
            # F_yy[y1, y1] by a central difference of the Jacobian along y1
            nrm = float(np.abs(y1[:m.n_q]).max()) or 1.0
            hh = 1e-4 / nrm
            _, Ap, _ = self._system(y + hh * y1, alpha)
            _, Am, _ = self._system(y - hh * y1, alpha)
            Fyy = (Ap @ y1 - Am @ y1) / (2 * hh)
            y2 = -lu_solve(lu, Fyy)
            s2 = float(ds @ y2[self.cdofs] + q1 @ Hs @ q1)
        Q = -float(y[self.row_rot])
        dQ = -float(y1[self.row_rot])
        p = Point(phi, y, alpha, Q, s, s1, s2, dQ=dQ)
        p.Nc, p.Nc1 = float(y[self.row_clamp]), float(y1[self.row_clamp])
        p.N = abs(p.Nc)
        if self.row_s is not None:
            p.lam_s, p.lam_s1 = float(y[self.row_s]), float(y1[self.row_s])
        return p

    # -- kinematics (SI) ------------------------------------------------------------------------------
    def mass_terms(self, p: Point):
        """M(phi) [kg m^2] and M'(phi)/2 at a statics point (the slide moves on the current path)."""
        a = self.a
        M = self.M_body
        half = 0.0
        if self.m1 > 0:
            ry = self.L + p.s + self.h
            M += self.m1 * a * a * (ry * ry + (p.s1 - 2.0) ** 2) + self.Jc
            half = self.m1 * a * a * (ry * p.s1 + (p.s1 - 2.0) * p.s2)
        return M, half

    def dxdphi_x(self, phi, rho):
        """x-component of d(position)/dphi [m/rad] of a body-fixed point rho [a] (s fixed)."""
        vx, vy = rho[1], -rho[0]
        return self.a * (math.cos(phi) * vx + math.sin(phi) * vy)

    def Qg(self, phi, ag, p: Point):
        """Generalised force [N m] of the ground-acceleration inertia -m_i ag e_x."""
        Q = -self.mass * ag * self.dxdphi_x(phi, self.rhoG)
        if self.m1 > 0:
            ry = self.L + p.s + self.h
            vx, vy = ry, p.s1 - 2.0
            Q += -self.m1 * ag * self.a * (math.cos(phi) * vx + math.sin(phi) * vy)
        return Q

    def reactions(self, p: Point, w, acc, ag=0.0):
        """d'Alembert solve at p with phi' = w, phi'' = acc and ground acceleration ag: returns
        (F1, N1, F2, N2 [N], lock residual [N m], state y, alpha)."""
        a, P = self.a, self.P
        phi = p.phi
        c, sn = math.cos(phi), math.sin(phi)

        def glob(v):  # body frame -> global (R(Theta), Theta = -phi)
            return np.array([c * v[0] + sn * v[1], -sn * v[0] + c * v[1]])

        rho = self.rhoG
        aG = glob(np.array([rho[1], -rho[0]]) * acc - rho * w * w) * a + np.array([ag, 0.0])
        self.inertia.FG = -self.mass * aG / P
        MB = self.JG * acc
        if self.m1 > 0:
            ry = self.L + p.s + self.h
            d1 = np.array([ry, p.s1 - 2.0])
            d2 = np.array([-2.0 + 2.0 * p.s1, -ry + p.s2])
            aC = glob(d1 * acc + d2 * w * w) * a + np.array([ag, 0.0])
            self.inertia.FC = -self.m1 * aC / P
            MB += self.Jc * acc
        else:
            self.inertia.FC = None
        self.inertia.MB = MB / (P * a)
        save = (self.y, self.alpha)
        try:
            s_c = p.s if self.mode == "stuck" else None
            y, alpha, _ = self.solve(phi, p.y, p.alpha, s_c=s_c)
        finally:
            self.inertia.FG = np.zeros(2)
            self.inertia.FC = None
            self.inertia.MB = 0.0
            self.y, self.alpha = save
        RA = -y[self.row_A1:self.row_A1 + 2] * P
        RB = -y[self.row_B1:self.row_B1 + 2] * P
        return float(RA[0]), float(RA[1]), float(RB[0]), float(RB[1]), float(y[self.row_rot]) * P * a, y, alpha

    def stiffness(self):
        """K = -dQ/dphi at phi = 0 [N m/rad] (slide free: spring k) and the mass M(0)."""
        p = self.point(0.0)
        M, _ = self.mass_terms(p)
        return -p.dQ * self.Pa, M, p


# -- excitation ----------------------------------------------------------------------------------------

class Ground:
    """Horizontal ground acceleration a_g(t) = ag sin(theta t) + record(t) (linear, 0 outside)."""

    def __init__(self, ag=0.0, theta=0.0, record=None):
        self.ag, self.theta = float(ag or 0.0), float(theta)
        self.rt = self.ra = None
        if record:
            from femslide.analysis.excitation import read_csv_record
            t, acc = read_csv_record(record)
            self.rt, self.ra = np.array(t), np.array(acc)
        self.forced = (self.ag != 0.0 and self.theta > 0) or self.rt is not None

    def __call__(self, t):
        out = self.ag * math.sin(self.theta * t) if self.theta > 0 else 0.0
        if self.rt is not None and self.rt[0] <= t <= self.rt[-1]:
            out += float(np.interp(t, self.rt, self.ra))
        return out


# -- beam-oscillation ------------------------------------------------------------------------------------

RTOL, ATOL_PHI = 1e-11, 1e-14


def _check_common(v):
    if not v["t_end"] > 0:
        raise BadInput(f"parameter t_end = {v['t_end']:g} s: allowed t_end > 0")


class Run:
    """Integration of the reduced equation with history, events and energy."""

    def __init__(self, st: Structure, ground: Ground, c_v: float):
        self.st, self.ground, self.c_v = st, ground, c_v
        self.cache = {}
        self.V0 = None

    def eval(self, t, phi, s_c=None):
        key = (phi, self.st.mode, self.st.sigma, s_c)
        p = self.cache.get(key)
        if p is None:
            p = self.st.point(phi, s_c=s_c)
            if len(self.cache) > 64:
                self.cache.clear()
            self.cache[key] = p
        return p

    def accel(self, t, phi, w, p):
        st = self.st
        M, half = st.mass_terms(p)
        ag = self.ground(t) if self.ground.forced else 0.0
        Qg = st.Qg(phi, ag, p) if ag else 0.0
        F = p.Q * st.Pa - self.c_v * w + Qg
        return (F - half * w * w) / M, Qg, ag

    def energy(self, p, w):
        M, _ = self.st.mass_terms(p)
        return 0.5 * M * w * w + (self.st.potential(p.y, p.alpha) - self.V0) * self.st.Pa


def _integrate(run, t0, t1, y0, events, s_c=None, max_step=np.inf):
    from scipy.integrate import solve_ivp
    st = run.st

    def rhs(t, z):
        phi, w = z[0], z[1]
        p = run.eval(t, phi, s_c)
        acc, Qg, ag = run.accel(t, phi, w, p)
        out = [w, acc, run.c_v * w * w, Qg * w]
        if st.slock is not None:
            out.append(st.mu * p.N * st.P * abs(p.s1 * w) * st.a if st.mode == "slip" else 0.0)
        return out

    return solve_ivp(rhs, (t0, t1), y0, method="DOP853", rtol=RTOL,
                     atol=[ATOL_PHI, ATOL_PHI * 10, 1e-14, 1e-14] + ([1e-14] if st.slock is not None else []),
                     dense_output=True, events=events, max_step=max_step)


def run_oscillation(v):
    """beam-oscillation: free oscillation about the vertical equilibrium from rest at phi0."""
    _check_common(v)
    from femslide.scenes.hinge import k_crit
    kc = k_crit(**{**v, "l1": v["L"]})
    if not v["k"] > kc:
        raise BadInput(f"parameter k = {v['k']:g} N/m is not above k_crit = {kc:.6g} N/m: the vertical "
                       f"state is unstable; allowed: k > {kc:.6g}")
    t0 = time.perf_counter()
    st = Structure(v)
    # vertical state (the equilibrium at dm = 0) and the linearised frequency
    K, M0, p0 = st.stiffness()
    if not K > 0:
        raise SolverFailure(f"the vertical state is not stable in the FE model (K = {K:.6g} N m/rad)")
    omega = math.sqrt(K / M0)
    V0 = st.potential(p0.y, p0.alpha)
    # walk to phi0 (held), warm-starting each step
    phi0 = v["phi0"]
    steps = max(1, int(math.ceil(abs(phi0) / 0.02)))
    for i in range(1, steps + 1):
        st.point(phi0 * i / steps, second=False)
    run = Run(st, Ground(), v.get("c_v", 0.0) or 0.0)
    run.V0 = V0
    pstart = st.point(phi0)
    E0 = run.energy(pstart, 0.0)

    def turn(t, z):
        return z[1]
    turn.terminal = False
    turn.direction = 0
    sol = _integrate(run, 0.0, v["t_end"], [phi0, 0.0, 0.0, 0.0], [turn])
    if sol.status < 0:
        raise SolverFailure(f"time integration failed: {sol.message}")
    tps = [(float(t), float(z[0])) for t, z in zip(sol.t_events[0], sol.y_events[0]) if t > 1e-12]
    T_int = time.perf_counter() - t0
    # energy balance at t_end (and its largest deviation at the turning points)
    pend = st.point(float(sol.y[0, -1]))
    E_end = run.energy(pend, float(sol.y[1, -1]))
    D, W = float(sol.y[2, -1]), float(sol.y[3, -1])
    Eref = abs(E0) if E0 != 0 else 1.0
    bal = abs(E_end + D - W - E0) / Eref
    bal_abs = E_end + D - W - E0
    drift = 0.0
    for t, z in zip(sol.t_events[0], sol.y_events[0]):
        zz = sol.sol(t)
        pe = st.point(float(z[0]), second=False)
        drift = max(drift, abs(run.energy(pe, 0.0) + zz[2] - zz[3] - E0) / Eref)
    hist = _history(run, sol, v, omega, tps)
    _check_energy(bal, bal_abs, st)
    res = {
        "converged": True,
        "turning_points": [{"t": t, "w": w} for t, w in tps],
        "stop": None,
        "w_max": float(max([abs(phi0)] + [abs(w) for _, w in tps] + [float(np.abs(hist['phi']).max())])),
        "steady_amplitude": None,
        "steady_reason": "unforced run (no steady forced response)",
        "steps": int(sol.t.size - 1),
        "F2_max": hist["F2_max"],
        "energy_balance": bal,
        "energy_balance_turning_points": drift,
        "w_is": "phi [rad], the body rotation (positive leaning towards B1)",
        "omega": omega,
        "period_linear": 2 * math.pi / omega,
        "K_eff": K,
        "M_eff": M0,
        "dalembert_residual": hist["dal_res"],
        "n_elements": st.n_el,
        "rhs_evaluations": int(sol.nfev),
        "statics_solves": st.n_solves,
        "t_end": v["t_end"],
        "integration_time_s": T_int,
        "history": history_table(hist),
    }
    return res


def _missed_crossing(event, sol, fractions=(0.25, 0.5, 0.75)):
    """First upward zero of ``event`` inside the steps of ``sol`` that the endpoint test of
    solve_ivp missed (the event function can rise above zero and fall back within one step: in a
    stuck phase |F_ax| - mu0 N oscillates with the stiff locked structure; mu = 2, mu0 = 2.4 went
    0.12 % over mu0 N unnoticed), or None.  Three interior samples per step, then a bracketing root."""
    from scipy.optimize import brentq

    def g(x):
        return event(x, sol.sol(x))
    ts = sol.t
    for i in range(ts.size - 1):
        a, b = float(ts[i]), float(ts[i + 1])
        for f in fractions:
            tm = a + f * (b - a)
            if g(tm) > 0.0:
                if g(a) > 0.0:
                    return a
                return brentq(g, a, tm, xtol=1e-15, rtol=4 * np.finfo(float).eps)
    return None


def _check_coulomb(rows, modes, mu0, mu, P):
    """Coulomb's law on the history samples (columns F_ax, N in N): stuck, |F_ax| <= mu0 N (1 + 1e-6)
    + 1e-9 P (the absolute part: round-off of the multipliers, ~1e-11 P, which matters only for
    tiny mu0); slipping, |F_ax| = mu N.  A violation fails the run (exit 1).  Returns max |F_ax| /
    (mu0 N) and max (|F_ax| - mu0 N) [N] while stuck (None without stuck samples)."""
    worst = excess = None
    for r in rows:
        md, _, _ = modes(r[0])
        F, N = abs(r[9]), r[10]
        tol = COULOMB_TOL * max(F, mu0 * N) + 1e-9 * P
        if md == "stuck":
            ratio = F / (mu0 * N) if mu0 * N > 0 else (0.0 if F <= tol else math.inf)
            worst = ratio if worst is None else max(worst, ratio)
            excess = F - mu0 * N if excess is None else max(excess, F - mu0 * N)
            if F > mu0 * N + tol:
                raise SolverFailure(f"Coulomb's law violated while stuck at t = {r[0]:.6g} s: guide force "
                                    f"|F_ax| = {F:.6g} N > mu0 N = {mu0 * N:.6g} N")
        elif md == "slip" and abs(F - mu * N) > tol:
            raise SolverFailure(f"Coulomb's law violated while slipping at t = {r[0]:.6g} s: guide force "
                                f"|F_ax| = {F:.6g} N, mu N = {mu * N:.6g} N")
    return worst, excess


def _check_energy(bal, err_abs, st):
    """ENERGY_TOL at the default RTOL; a coarser integrator tolerance set on purpose (the
    work-precision study sets RTOL up to 1e-4) is allowed 100 RTOL.  An absolute error below the
    round-off level of the potential energy (~1e-12 P a: strain energy and weights of order P a are
    summed) passes: a run so short or so small that all its energies are at that level (t_end = 1e-6
    s: 1e-22 J) has no meaningful relative balance."""
    tol = max(ENERGY_TOL, 100.0 * RTOL)
    if not (bal <= tol or abs(err_abs) <= 1e-12 * st.Pa):
        raise SolverFailure(f"energy balance {bal:.3g} is worse than the tolerance {tol:g} "
                            f"(relative to the largest energy): the integration cannot be trusted")


def _sample_times(sol, omega, t_end, tps, per_period=64):
    dt = 2 * math.pi / omega / per_period
    n = int(min(200000, math.ceil(t_end / dt)))
    t = np.concatenate([np.linspace(0.0, t_end, n + 1), [t for t, _ in tps]])
    return np.unique(t)


def _history(run, sol, v, omega, tps, modes=None):
    """Time history on a uniform grid (64 per linear period) plus the turning points: phi, phi',
    phi'', the slide and the d'Alembert reactions; F2_max refined around the largest sample."""
    st = run.st
    t = _sample_times(sol, omega, v["t_end"], tps)
    rows = []
    states = []
    dal = 0.0
    Qmax = 1e-300

    def at(ti):
        nonlocal dal, Qmax
        z = sol(ti) if callable(sol) else sol.sol(ti)
        phi, w = float(z[0]), float(z[1])
        extra = modes(ti) if modes else None
        s_c = None
        if extra is not None:
            st.mode, st.sigma, s_c = extra
        p = st.point(phi, s_c=s_c)
        acc, Qg, ag = run.accel(ti, phi, w, p)
        F1, N1, F2, N2, lockres, y, alpha = st.reactions(p, w, acc, ag)
        Qmax = max(Qmax, abs(p.Q) * st.Pa)
        dal = max(dal, abs(lockres))
        stuck = 1 if (extra is not None and extra[0] == "stuck") else 0
        return [ti, phi, w, F2, p.s * st.a, stuck, F1, N1, N2, p.lam_s * st.P, p.N * st.P], (y, alpha)

    for ti in t:
        row, state = at(float(ti))
        rows.append(row)
        states.append(state)
    H = np.array(rows)
    i = int(np.argmax(np.abs(H[:, 3])))
    F2max = abs(H[i, 3])
    # refine the maximum of |F2| by golden-section search between the neighbouring samples
    if 0 < i < len(H) - 1:
        lo, hi = H[i - 1, 0], H[i + 1, 0]
        gr = (math.sqrt(5) - 1) / 2
        f = lambda tt: abs(at(tt)[0][3])
        x1, x2 = hi - gr * (hi - lo), lo + gr * (hi - lo)
        f1, f2 = f(x1), f(x2)
        for _ in range(40):
            if hi - lo < 1e-9 * max(1.0, hi):
                break
            if f1 > f2:
                hi, x2, f2 = x2, x1, f1
                x1 = hi - gr * (hi - lo)
                f1 = f(x1)
            else:
                lo, x1, f1 = x1, x2, f2
                x2 = lo + gr * (hi - lo)
                f2 = f(x2)
        F2max = max(F2max, f1, f2)
    return {"rows": H, "states": states, "F2_max": float(F2max), "dal_res": dal / Qmax,
            "phi": H[:, 1]}


def history_table(hist) -> dict:
    """The time history as named arrays (SI; the samples of history.csv): ``t`` [s], ``phi`` [rad]
    (body rotation, > 0 leaning towards B1), ``phi_dot`` [rad/s], ``slide`` [m] (along the guide),
    ``stuck`` (1 stuck, 0 sliding or free), ``F_ax`` [N] (guide axial force, the slide-lock
    multiplier; 0 without friction), ``N`` [N] (magnitude of the transverse clamp force), and the d'Alembert
    reactions of the ground, ``F1``, ``N1`` at A1 and ``F2``, ``N2`` at B1 [N] (global x and y)."""
    H = hist["rows"]
    cols = {"t": 0, "phi": 1, "phi_dot": 2, "slide": 4, "stuck": 5, "F_ax": 9, "N": 10,
            "F1": 6, "N1": 7, "F2": 3, "N2": 8}
    out = {k: H[:, i].copy() for k, i in cols.items()}
    out["stuck"] = out["stuck"].astype(int)
    return out


# -- beam-friction ---------------------------------------------------------------------------------------

STEADY_RTOL = 1e-6   # two successive forcing periods agree to this (relative to the amplitude)


def run_friction(v):
    """beam-friction: Coulomb friction in the sliding clamp under a horizontal ground acceleration.

    The run is a sequence of segments, each integrated by DOP853 with event location:
    stuck (slide locked at s_c; event: |F_ax| = mu0 N crossing upwards -> slip in the direction of
    F_ax, after the jump of the massless slide to F_ax = sigma mu N) and slipping (F_ax = sigma mu N;
    event: s' = (ds/dphi) phi' reaching zero -> stick at the current slide if static friction can
    hold it there, see below).  m1 = 0 here: the rod and the telescopic piece are massless,
    T = J_A1 phi'^2 / 2 exactly.  Initial state: at rest at phi0 with the slide of the frictionless
    statics.

    Entry into stick (t = 0 and every end of a slip): the slide is locked only if |F_ax| <= mu0 N
    there; on the boundary (within round-off: F_ax = N = 0 in the vertical state, or |F_ax| = mu N =
    mu0 N when a slip ends with mu = mu0) only if |F_ax| - mu0 N does not grow for the coming motion
    (one-sided rates from dF_ax/dphi and dN/dphi with the slide locked; the motion's direction from
    phi', phi'' and the change of the forcing).  Otherwise it slips at once; mu0 = 0 never sticks.
    After the run every history sample is checked against Coulomb's law and the energy balance
    against ENERGY_TOL: a violation fails the run (exit 1).

    Scene defaults EI = 1e4 N m^2, EA = 1e6 N (EA/EI = 100 m^-2, not the inextensible 1e6): while
    stuck, phi can change only by stretching the rod, K_stuck ~ EA (2a)^2 / L, and with the default
    EA/EI the stuck phases would oscillate at ~1e5 rad/s (the explicit integrator would crawl).
    """
    _check_common(v)
    from femslide.scenes.hinge import k_crit
    kc = k_crit(**{**v, "l1": v["L"], "m1": 0.0, "l2": 1.0})
    if not v["k"] > kc:
        raise BadInput(f"parameter k = {v['k']:g} N/m is not above k_crit = {kc:.6g} N/m: the vertical "
                       f"state is unstable; allowed: k > {kc:.6g}")
    if v["mu"] < 0 or v["mu0"] < v["mu"]:
        raise BadInput(f"parameter mu0 = {v['mu0']:g} must be >= mu = {v['mu']:g} >= 0")
    t_wall = time.perf_counter()
    st = Structure(v, friction=True)
    st.mode = "free"
    K, M0, p0 = st.stiffness()
    if not K > 0:
        raise SolverFailure(f"the vertical state is not stable in the FE model (K = {K:.6g} N m/rad)")
    omega = math.sqrt(K / M0)
    theta = v["theta_ratio"] * omega
    ground = Ground(v.get("ag", 0.0), theta, v.get("record"))
    V0 = st.potential(p0.y, p0.alpha)
    phi0 = v["phi0"]
    steps = max(1, int(math.ceil(abs(phi0) / 0.02)))
    for i in range(1, steps + 1):
        st.point(phi0 * i / steps, second=False)
    p_init = st.point(phi0, second=False)
    run = Run(st, ground, v.get("c_v", 0.0) or 0.0)
    run.V0 = V0
    st.mu = v["mu"]
    mu0 = v["mu0"]
    E0 = run.energy(p_init, 0.0)
    t, z = 0.0, np.array([phi0, 0.0, 0.0, 0.0, 0.0])
    segs = []         # (t0, t1, dense, mode, sigma, s_c)
    tps = []
    jump_loss = 0.0
    n_steps = n_fev = 0
    short = 0
    h_probe = 1e-4 * 2 * math.pi / max(omega, theta if ground.forced else 0.0)
    mode, sigma, s_c = "free", 0.0, None

    def set_mode():
        st.mode, st.sigma = mode, sigma
        run.cache.clear()

    def motion_direction(tt, zz, p):
        """Sign of the coming change of phi from (tt, phi, phi'), to third order in time (the
        jerk from the change of the forcing at fixed state): 0 when nothing moves."""
        phi_, w_ = float(zz[0]), float(zz[1])
        a0 = run.accel(tt, phi_, w_, p)[0]
        a1 = run.accel(tt + h_probe, phi_, w_, p)[0]
        h = h_probe
        delta = w_ * h + 0.5 * a0 * h * h + (a1 - a0) * h * h / 6.0
        scale = abs(w_) * h + (abs(a0) + abs(a1)) * h * h
        if scale == 0.0 or abs(delta) <= 1e-12 * scale:
            return 0.0
        return 1.0 if delta > 0 else -1.0

    def stick_test(tt, zz, p):
        """(holds, sigma): can static friction hold the slide locked at this instant?  |F_ax| <=
        mu0 N decides; on the boundary (within round-off, e.g. F_ax = N = 0 in the vertical state,
        or |F_ax| = mu N = mu0 N when a slip ends with mu = mu0) the one-sided rate of
        |F_ax| - mu0 N for the coming motion does (computed from dF_ax/dphi and dN/dphi with the
        slide locked): stick only if it does not grow.  sigma: the slip direction otherwise."""
        F, F1, c, c1 = p.lam_s, p.lam_s1, p.Nc, p.Nc1
        tol = 1e-9 * (1.0 + abs(F) + mu0 * abs(c))
        g = abs(F) - mu0 * abs(c)
        if g < -tol:
            return True, 0.0
        if g > tol:
            return False, (1.0 if F > 0 else -1.0)
        d = motion_direction(tt, zz, p)
        if d == 0.0:
            return True, 0.0      # nothing moves: held until the breakaway event says otherwise

        def rate(dd):
            dF = (1.0 if F > 0 else -1.0) * F1 * dd if abs(F) > tol else abs(F1)
            dN = (1.0 if c > 0 else -1.0) * c1 * dd if abs(c) > tol else abs(c1)
            return dF - mu0 * dN
        if rate(d) <= 1e-9 * (abs(F1) + mu0 * abs(c1)):
            return True, 0.0
        if abs(F) > tol:
            return False, (1.0 if F > 0 else -1.0)
        return False, (1.0 if F1 * d > 0 else -1.0)

    def to_slip(tt, phi, s_lock, sgm):
        """Jump of the massless slide at fixed phi, phi' from the locked state to F_ax = sgm mu N;
        the elastic energy released is dissipated (jump_loss)."""
        nonlocal jump_loss, mode, sigma
        mode, sigma = "stuck", 0.0
        set_mode()
        p = run.eval(tt, phi, s_lock)
        E_before = st.potential(p.y, p.alpha)
        mode, sigma = "slip", sgm
        set_mode()
        try:
            q = st.point(phi, second=False)
        except SolverFailure as exc:
            raise SolverFailure(f"no slip state at breakaway, t = {tt:.6g} s: {exc.reason}", exc.history)  # noqa: B904 (cause in the message)
        if sgm * (q.s - s_lock) < -1e-12:
            raise SolverFailure(f"the slide jumped against the breakaway force at t = {tt:.6g} s")
        jump_loss += (E_before - st.potential(q.y, q.alpha)) * st.Pa
        run.cache.clear()

    def enter_stick(tt, zz, s_lock):
        """At t = 0 and at every end of a slip: stuck at s_lock if static friction can hold the
        slide there, else slip at once (mu0 = 0 never sticks: the slide is free)."""
        nonlocal mode, sigma, s_c
        if mu0 == 0.0:
            mode, sigma, s_c = "free", 0.0, None
            return
        mode, sigma = "stuck", 0.0
        set_mode()
        p = run.eval(tt, float(zz[0]), s_lock)
        holds, sgm = stick_test(tt, zz, p)
        if holds:
            mode, sigma, s_c = "stuck", 0.0, s_lock
        else:
            to_slip(tt, float(zz[0]), s_lock, sgm)
            s_c = None

    def turn(tt, zz):
        return zz[1]
    turn.terminal = False
    turn.direction = 0

    def breakaway(tt, zz):
        # |F_ax| - mu0 N, less the round-off margin of the stick test: a stuck phase entered on
        # the boundary (mu = mu0, or F_ax = N = 0) starts at -margin, not at a round-off sign that
        # would hide the upward crossing from the event search
        p = run.eval(tt, zz[0], s_c)
        return abs(p.lam_s) - mu0 * p.N - 1e-9 * (1.0 + abs(p.lam_s) + mu0 * p.N)
    breakaway.terminal = True
    breakaway.direction = 1

    def slip_end(tt, zz):
        p = run.eval(tt, zz[0], None)
        return sigma * p.s1 * zz[1]
    slip_end.terminal = True
    slip_end.direction = -1

    enter_stick(0.0, z, p_init.s)
    while t < v["t_end"] * (1 - 1e-14):
        set_mode()
        if mode == "stuck":
            sol = _integrate(run, t, v["t_end"], z, [turn, breakaway], s_c=s_c)
        elif mode == "slip":
            sol = _integrate(run, t, v["t_end"], z, [turn, slip_end])
        else:
            sol = _integrate(run, t, v["t_end"], z, [turn])
        if sol.status < 0:
            raise SolverFailure(f"time integration failed at t = {t:.6g} s ({mode}): {sol.message}")
        n_steps += sol.t.size - 1
        n_fev += sol.nfev
        t_new, status, z_new = float(sol.t[-1]), sol.status, sol.y[:, -1].copy()
        if mode == "stuck":
            hit = _missed_crossing(breakaway, sol)
            if hit is not None:
                t_new, status, z_new = hit, 1, np.asarray(sol.sol(hit)).copy()
        segs.append((t, t_new, sol.sol, mode, sigma, s_c))
        tps += [(float(te), float(ze[0])) for te, ze in zip(sol.t_events[0], sol.y_events[0])
                if 1e-12 < te <= t_new and (not tps or te > tps[-1][0] + 1e-12)]
        short = short + 1 if t_new - t < 1e-10 else 0
        if short > 6:
            raise SolverFailure(f"stick-slip switching does not advance at t = {t:.6g} s (chattering)")
        t, z = t_new, z_new
        if status != 1:
            break
        phi = float(z[0])
        if mode == "stuck":            # breakaway: slip in the direction of the guide force
            p = run.eval(t, phi, s_c)
            to_slip(t, phi, s_c, 1.0 if p.lam_s > 0 else -1.0)
            s_c = None
        else:                          # the slip ends: stuck, if static friction holds there
            p = run.eval(t, phi, None)
            enter_stick(t, z, p.s)

    def dense(tt):
        k = max(0, min(len(segs) - 1, int(np.searchsorted([s[0] for s in segs], tt, side="right")) - 1))
        return segs[k][2](tt)

    def modes(tt):
        k = max(0, min(len(segs) - 1, int(np.searchsorted([s[0] for s in segs], tt, side="right")) - 1))
        _, _, _, md, sg, sc = segs[k]
        return md, sg, (sc if md == "stuck" else None)

    # energy balance at t_end
    md, sg, sc = modes(t)
    st.mode, st.sigma = md, sg
    pend = st.point(float(z[0]), second=False, s_c=sc)
    E_end = run.energy(pend, float(z[1]))
    Dv, W, Df = float(z[2]), float(z[3]), float(z[4])
    err = E_end + Dv + Df + jump_loss - W - E0
    hist = _history(run, dense, v, omega, tps, modes=modes)
    rows = hist["rows"]
    M = st.M_body
    if W != 0 or abs(E0) == 0:
        Eref = max(abs(E0), abs(W), float(np.max(0.5 * M * rows[:, 2] ** 2)))
    else:
        Eref = abs(E0)
    bal = abs(err) / Eref if Eref > 0 else 0.0
    ratio, excess = _check_coulomb(rows, modes, mu0, st.mu, st.P)
    _check_energy(bal, err, st)
    amp, reason = _steady(ground, theta, tps, v["t_end"], rows)
    stuck_time = sum(b - a for a, b, _, md_, _, _ in segs if md_ == "stuck")
    # zero drift while stuck: the slide of every stuck sample equals its segment's s_c
    drift = 0.0
    for r in rows:
        md_, _, sc_ = modes(r[0])
        if md_ == "stuck":
            drift = max(drift, abs(r[4] - sc_ * st.a))
    res = {
        "converged": True,
        "turning_points": [{"t": tt, "w": ww} for tt, ww in tps],
        "stop": None,
        "w_max": float(max([abs(phi0)] + [abs(ww) for _, ww in tps] + [float(np.abs(rows[:, 1]).max())])),
        "steady_amplitude": amp,
        **({"steady_reason": reason} if amp is None else {}),
        "steps": int(n_steps),
        "F2_max": hist["F2_max"],
        "energy_balance": bal,
        "w_is": "phi [rad], the body rotation (positive leaning towards B1)",
        "omega": omega,
        "omega_is": "small-oscillation frequency of the frictionless structure (slide free, spring k)",
        "theta": theta if ground.forced else None,
        "segments": len(segs),
        "stick_slip_switches": len(segs) - 1,
        "stuck_time": stuck_time,
        "stuck_slide_drift": drift,
        "stuck_force_ratio_max": ratio,
        "stuck_force_excess_max": excess,
        "friction_work": Df,
        "jump_loss": jump_loss,
        "work_in": W,
        "slide_range": [float(rows[:, 4].min()), float(rows[:, 4].max())],
        "dalembert_residual": hist["dal_res"],
        "n_elements": st.n_el,
        "rhs_evaluations": int(n_fev),
        "t_end": v["t_end"],
        "integration_time_s": time.perf_counter() - t_wall,
        "history": history_table(hist),
    }
    return res


def _steady(ground, theta, tps, t_end, rows):
    """Amplitude of the last forcing period if it repeats the one before (STEADY_RTOL), else None."""
    if not ground.forced:
        return None, "unforced run (no steady forced response)"
    if ground.rt is not None:
        return None, "record excitation is not periodic"
    Tf = 2 * math.pi / theta
    n = int(math.floor(t_end / Tf))
    if n < 2:
        return None, "fewer than two complete forcing periods before t_end"
    pts = np.array([(r[0], r[1]) for r in rows] + list(tps))

    def ext(k):
        sel = pts[(pts[:, 0] >= k * Tf) & (pts[:, 0] <= (k + 1) * Tf)]
        return sel[:, 1].max(), sel[:, 1].min()
    a1, b1 = ext(n - 2)
    a2, b2 = ext(n - 1)
    amp = 0.5 * (a2 - b2)
    if max(abs(a2 - a1), abs(b2 - b1)) > STEADY_RTOL * max(amp, 1e-300):
        return None, (f"not steady by t_end: the last two forcing periods differ by "
                      f"{max(abs(a2 - a1), abs(b2 - b1)):.3g} rad; increase t_end")
    return float(amp), None
