"""Static equilibrium of a frozen structure on its principal branch, with adaptive mesh refinement.

The answer is the equilibrium reached by ramping all loads together from zero (the principal
branch).  How the path is followed is chosen from the undeformed structure under full load, on the
coarsest mesh (:func:`choose_path`):

- stable there (the reduced tangent, with the initial stresses of the loads, is positive definite on
  the unloaded structure's first-order mechanisms, or there are none): load control, in load steps
  whose predicted increments stay bounded, each checked against its tangent prediction and for
  stability; the steps shrink towards a limit point, where the run exits 1 with its load factor
  (see :func:`_load_steps`);
- not stable (a near-mechanism such as the paper's structure, whose undeformed tangent is singular
  in the rigid limit, or a structure that must deform to carry its loads): displacement control of
  the dof that moves most in the softest mode (a body rotation when one takes part), marching in the
  direction in which the loads do work (:func:`femslide.newton.principal_branch`); a maximum of the
  load factor before full load is a limit point (exit 1);
- singular with and without the loads' initial stresses: a mechanism (exit 1 naming the free part
  and direction).
The equilibrium reached must be stable: on the coarsest mesh, a negative eigenvalue of the reduced
tangent at full load means the path crossed a bifurcation (exit 1).

Accuracy: with no fixed mesh the rods are refined by doubling (2, 4, 8, ... elements per rod, times
each rod's length over the shortest rod's) and the named results are Richardson-extrapolated from the
two finest meshes (the corotational discretisation error is O(h^2)).  Refinement stops when every
watched result is estimated accurate to ``TARGET``; or when the first two meshes already agree to
TARGET/10 (the finer mesh's raw values are reported); or when the level-to-level changes stop
shrinking like h^2 *and* are down at the round-off level of the model (the raw finest values are
reported).  ``error_estimate`` is the estimated relative error of the largest rod moment, and at
least its round-off scatter (Newton reconverged from a slightly perturbed state).  A rod with a
fixed number of elements is not refined; when every rod is fixed the estimate compares the mesh with
one of half as many elements.  Meshes finer than 16 elements per rod start from the
Hermite-interpolated solution of the coarser mesh.

Everything inside is nondimensional: lengths by ``Lref`` (the structure's extent) and forces by
``Fref`` (the total applied load), so that EI/(P L^2) from 1 to 1e12 needs no tuning.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from . import corotational
from .errors import BadInput, SolverFailure
from .model import Model, PatternCache, load_lapack, solve_linear
from .newton import newton, principal_branch
from .results import end_moments, extract, flatten, largest_moment, rod_arrays, unflatten
from .structure import Frozen

load_lapack()   # every solve needs it: loaded with the module, so that a timed solve does not pay for it

TARGET = 1e-7     # estimated relative error the adaptive refinement aims for (10x below 1e-6)
N_START = 2       # elements per (shortest) rod on the coarsest adaptive level
N_MAX = 4096
N_DIRECT = 16     # meshes finer than this start from the interpolated solution of the coarser one
MAX_STEP_ROTATION = 0.8      # rad: largest predicted rotation increment of a load step
MAX_STEP_TRANSLATION = 0.5   # model lengths: largest predicted translation increment of a load step
ROUNDOFF_LIMIT = 1e-3  # relative round-off scatter of the largest moment above which a result is refused
DENSE_CHECK = 600  # unknowns: the path choice and the stability check run on meshes up to this size


# -- scales ---------------------------------------------------------------------------------------

def scales(fs: Frozen):
    """(Lref [m], Fref [N]): the structure's extent and its total applied load (sum of magnitudes;
    without loads, EI/L^2 of the stiffest rod)."""
    L = fs.length_scale
    body_w, rod_w = fs.weights()
    F = sum(math.hypot(*w) for w in body_w.values())
    F += sum(math.hypot(*rod_w[r.name]) * r.length for r in fs.rods)
    for ld in fs.loads:
        if ld.type == "distributed":
            F += math.hypot(*ld.force) * fs.rod(ld.on).length
        else:
            F += math.hypot(*ld.force) + abs(ld.moment) / L
    F += sum(abs(j.preload) for j in fs.joints)
    if F == 0.0:
        EI = [r.EI if isinstance(r.EI, float) else r.EI.max for r in fs.rods]
        F = max(EI, default=1.0) / (L * L)
    return L, F


# the stiffness range in which the solver is verified (validation/STABILITY.md: beyond it round-off of
# the stiff terms outgrows the answers while the estimates do not notice)
KAPPA_MAX = 1e15     # EI / (F L^2): bending stiffness against the loads
EA_RATIO_MAX = 1e14  # EA L^2 / EI (L: the model length unit)


def check_stiffness_range(fs: Frozen, L: float, F: float):
    """Bad input (naming the rod and the field) outside the verified stiffness range."""
    for r in fs.rods:
        EI = max(r.EI.value) if not isinstance(r.EI, float) else r.EI
        EA = max(r.EA.value) if not isinstance(r.EA, float) else r.EA
        EImin = min(r.EI.value) if not isinstance(r.EI, float) else r.EI
        if not math.isfinite(EA):
            raise BadInput(f"rod {r.name}: EA = {EA:g} N is not finite (the default EA is 1e6 m^-2 * EI); give EA")
        if EI / (F * L * L) > KAPPA_MAX:
            raise BadInput(f"rod {r.name}: EI = {EI:g} N m^2 is more than {KAPPA_MAX:g} times the loads' scale "
                           f"F L^2 = {F * L * L:g} N m^2; allowed: EI <= {KAPPA_MAX * F * L * L:g} N m^2 "
                           f"for these loads")
        if EA * L * L / EImin > EA_RATIO_MAX:
            raise BadInput(f"rod {r.name}: EA L^2 / EI = {EA * L * L / EImin:g} exceeds {EA_RATIO_MAX:g} (L = {L:g} m, "
                           f"the structure's size); allowed: EA <= {EA_RATIO_MAX * EImin / (L * L):g} N")


# -- how the path is followed ------------------------------------------------------------------------

@dataclass
class Control:
    """A controlled dof, named so that it can be found on every mesh: a body's ("body", name, comp)
    or a rod node's ("node", rod, fraction of the rod's length, comp); comp 0 = u, 1 = v, 2 = theta."""

    kind: str
    name: str
    comp: int
    fraction: float = 0.0

    def dof(self, model: Model) -> int:
        if self.kind == "body":
            return model.body_dof(self.name) + self.comp
        nodes = model.rod_nodes[model.rod_index[self.name]]
        return 3 * int(nodes[int(round(self.fraction * (nodes.size - 1)))]) + self.comp

    def describe(self, structure) -> str:
        what = ("x", "y", "rotation")[self.comp]
        if self.kind == "body":
            return f"body {self.name} ({what})"
        return f"rod {self.name} at {self.fraction:.3g} of its length ({what})"


@dataclass
class Path:
    """How to reach the principal equilibrium: ``kind`` "load" (load stepping) or "control"
    (displacement control of ``control`` in direction ``sign``); ``guess`` a first value of the
    controlled dof's magnitude, ``start(model, value)`` an optional start state at that value,
    ``load_steps`` the first number of load steps."""

    kind: str
    control: Control | None = None
    sign: float = 1.0
    guess: float | None = None
    start: object = None
    load_steps: int = 1
    phi_max: float = math.pi
    first_n: int = N_START
    note: str = ""


def _reduced(A, n_q):
    """Null-space basis Z of the constraint rows and the reduced tangent Z^T K Z (dense)."""
    K = A[:n_q, :n_q]
    G = A[n_q:, :n_q]
    Z = _null_space(G) if G.shape[0] else np.eye(n_q)
    Hr = Z.T @ K @ Z
    w, V = np.linalg.eigh(0.5 * (Hr + Hr.T))
    return Z, w, V


def _null_space(G):
    """Orthonormal basis of the null space of G (SVD; rank tolerance max(shape) eps s_max, as
    scipy.linalg.null_space)."""
    _, s, Vt = np.linalg.svd(G, full_matrices=True)
    tol = max(G.shape) * np.finfo(float).eps * (s[0] if s.size else 0.0)
    rank = int(np.sum(s > tol))
    return Vt[rank:].T.conj()


def _initial_stress(model: Model, lam=1.0):
    """The undeformed state with the multipliers that hold the loads there (least squares): the
    state whose tangent carries the loads' initial stresses."""
    y, alpha = model.zero_state()
    if model.n_c:
        r, A, info = model.system(y, alpha, lam, dense=True)
        G = A[model.n_q:, :model.n_q]
        mu, *_ = np.linalg.lstsq(G.T, -r[:model.n_q], rcond=None)
        y[model.n_q:] = mu
    return y, alpha


def _mode_part(model: Model, v):
    """The part and direction that move most in the mode v (a vector over the frame dofs)."""
    k = int(np.argmax(np.abs(v)))
    comp = k % 3
    frame = k // 3
    if frame >= model.n_nodes:
        name = model.structure.bodies[frame - model.n_nodes].name
        return Control("body", name, comp)
    for r, nodes in zip(model.structure.rods, model.rod_nodes):
        if nodes[0] <= frame <= nodes[-1]:
            return Control("node", r.name, comp, (frame - nodes[0]) / max(1, nodes.size - 1))
    raise AssertionError("dof outside the model")


def choose_path(model: Model) -> Path:
    """Load control, displacement control or a mechanism (see the module docstring).

    The first-order mechanisms of the unloaded structure are the null space of its reduced elastic
    tangent K0 (eigenvalues at the round-off level of its largest); along them the loaded structure's
    stiffness is the geometric one, K_geo = K(full load, initial stresses) - K0 at the undeformed
    state (the elastic parts cancel exactly, so K_geo keeps its accuracy however stiff the rods are).
    Positive definite on the mechanisms: the loads hold them (a hanging pendulum, a preloaded slider
    spring): load control.  Negative in some direction: the structure must deform to carry its loads
    (the paper's structure, a weight above its pivot): displacement control along the most negative
    direction.  Zero: a mechanism.  Without first-order mechanisms: load control (a bifurcation on the
    way is caught by the stability check of the solution)."""
    n_q = model.n_q
    if model.n > DENSE_CHECK or n_q == 0:
        return Path("load")
    y0, a0 = model.zero_state()
    _, A0, _ = model.system(y0, a0, 0.0, dense=True)
    Z, w0, V0 = _reduced(A0, n_q)
    if w0.size == 0:
        return Path("load")  # fully fixed by the joints
    tol0 = 1e-9 + 1e3 * np.finfo(float).eps * float(np.abs(w0).max())
    null = w0 <= tol0
    if not null.any():
        return _load_path(model)
    y, alpha = _initial_stress(model)
    r, A1, info = model.system(y, alpha, 1.0, dense=True)
    Kg = A1[:n_q, :n_q] - A0[:n_q, :n_q]
    Vn = Z @ V0[:, null]
    wg, Vg = np.linalg.eigh(0.5 * (Vn.T @ (Kg + Kg.T) @ Vn))
    gtol = 1e-9 * (1.0 + float(np.abs(wg).max()))
    if wg[0] > gtol:
        return _load_path(model)
    mode = Vn @ Vg[:, 0]
    fl = info["fl"]
    if wg[0] >= -gtol:
        part = _mode_part(model, mode)
        pushed = abs(fl @ mode) > 1e-9 * (np.abs(fl).max() + 1e-300) * np.abs(mode).max()
        raise SolverFailure(
            f"mechanism: {part.describe(model.structure)} is free to move (its stiffness is zero with "
            f"and without the loads{'; the loads push it along that freedom' if pushed else ''}); "
            f"add a joint or a spring that holds it")
    # displacement control on the softest mode: a body rotation if one takes part, else the dof
    # that moves most
    rot_b = [(abs(mode[model.body_dof(b.name) + 2]), b.name) for b in model.structure.bodies]
    top = float(np.abs(mode).max())
    ctrl = None
    if rot_b:
        best, name = max(rot_b)
        if best >= 0.25 * top:
            ctrl = Control("body", name, 2)
    if ctrl is None:
        ctrl = _mode_part(model, mode)
    d = ctrl.dof(model)
    work = -float(fl @ mode)   # work of the loads along +mode
    sign = math.copysign(1.0, mode[d]) * (1.0 if work >= 0 else -1.0)
    note = ("" if abs(work) > 1e-12 * (np.abs(fl).max() + 1e-300)
            else "the loads do no first-order work on the softest mode")
    return Path("control", ctrl, sign, phi_max=math.pi if ctrl.comp == 2 else 10.0, note=note)


def _load_path(model: Model) -> Path:
    """Load stepping: as many steps as the linear response's rotations need (0.8 rad a step)."""
    y, alpha = _initial_stress(model)
    r, A, _ = model.system(y, alpha, 1.0, dense=True)
    try:
        dy = solve_linear(A, -r)
        rot = float(np.abs(dy[model.rotation_dofs()]).max()) if model.rotation_dofs().size else 0.0
    except np.linalg.LinAlgError:
        rot = math.inf
    steps = max(1, math.ceil(rot / 0.8)) if math.isfinite(rot) else 8
    return Path("load", load_steps=min(steps, 64))


def check_stable(model: Model, y, alpha):
    """Raise SolverFailure if the equilibrium (coarse mesh) has a negative reduced-tangent eigenvalue.

    With m independent joint equations, det [[K, G^T], [G, 0]] has the sign (-1)^m exactly when the
    reduced tangent Z^T K Z (Z: the joints' null space) has an even number of negative eigenvalues
    (Sylvester): a sign test by one LU; only when it fails are the eigenvalues computed."""
    if model.n > DENSE_CHECK or model.n_q == 0:
        return
    # the last tangent Newton assembled (one step, at most 1e-7, before the solution) will do
    A = getattr(model, "last_tangent", None)
    if A is None or A.shape[0] != model.n:
        _, A, _ = model.system(y, alpha, 1.0, dense=True)
    n_q = model.n_q
    sign, _ = np.linalg.slogdet(A)
    if sign == (-1.0) ** model.n_c:
        return
    Z, w, V = _reduced(A, n_q)
    if w.size and w[0] < -1e-9 * (1.0 + 1e-3 * float(np.abs(w).max())):
        part = _mode_part(model, Z @ V[:, 0])
        raise SolverFailure(f"the equilibrium reached at full load is unstable (reduced tangent eigenvalue "
                            f"{w[0]:.3g}; softest: {part.describe(model.structure)}): the load path crossed a "
                            f"bifurcation or limit point before full load")


# -- one mesh level ----------------------------------------------------------------------------------

def _load_steps(model: Model, path: Path, start=None):
    """Load stepping from the undeformed state, or one Newton solve at full load from ``start``.

    Each step is checked against the path: its increment must stay within its own size of the tangent
    prediction (a Newton solve that jumps past a limit point onto another branch lands far from it),
    and on dense models the equilibrium must stay stable (the sign of the tangent's determinant,
    (-1)^m for m joint equations, must not change).  A step that fails either check is halved; when
    the step cannot be halved further the loads have reached a limit point or a bifurcation: exit 1
    with the load factor."""
    if start is not None:
        y, info = newton(model, start[0], start[1], lam=1.0)
        if info.converged:
            return y, info.alpha, info.iterations
    dense = model.n <= DENSE_CHECK
    # the undeformed state with the multipliers that hold the loads there: a structure held only by
    # its loads' initial stresses (a hanging pendulum) has a singular tangent without them
    y, alpha = _initial_stress(model, 1.0 / path.load_steps) if dense else model.zero_state()
    step0 = 1.0 / path.load_steps
    lam, step, its = 0.0, step0, 0
    stable = (-1.0) ** model.n_c
    tangent, _, fl = _load_tangent(model, model.zero_state()[0], alpha, 0.0)
    if tangent is None:
        tangent = np.zeros(model.n_q)
    compliance0 = -float(fl @ tangent)   # work rate of the loads per load factor: 1 / stiffness
    bound = np.full(model.n_q, MAX_STEP_TRANSLATION)
    bound[model.rotation_dofs()] = MAX_STEP_ROTATION
    reason, hist = "", []
    while lam < 1.0:
        # the predicted increment stays within the bounds: near a limit point the tangent grows
        # without bound and the steps shrink towards it
        grow = float(np.max(np.abs(tangent) / bound))
        dlam = min(step, 1.0 - lam, 1.0 / grow if grow > 0 else math.inf)
        if 1.0 - lam <= 1e-6:
            dlam = 1.0 - lam          # the last sliver of load
        elif dlam < 1e-6:
            why = "the response to the loads grows without bound" if dlam < step else reason
            raise SolverFailure(f"load stepping stalled at load factor {lam:.6g}: a limit point or a "
                                f"bifurcation of the loaded structure ({why})", hist)
        target = lam + dlam
        y_new, info = newton(model, y, alpha, lam=target)
        its += info.iterations
        ok, reason, hist = info.converged, info.reason, info.history
        if ok:
            # the increment against the tangent prediction (translations and rotations, model units)
            pred = tangent * dlam
            size = float(np.abs(pred).max())
            if float(np.abs(y_new[:model.n_q] - y[:model.n_q] - pred).max()) > max(size, 1e-12):
                ok, reason = False, "the step left the tangent's neighbourhood: it jumped past a limit point"
        if ok and target < 1.0:   # (the stability at full load is checked on the solution)
            new_tangent, sign, fl = _load_tangent(model, y_new, info.alpha, target)
            if sign is not None and sign != stable:
                ok, reason = False, "the equilibrium lost its stability"
        if not ok:
            step = 0.5 * dlam
            continue
        alpha = info.alpha
        y, lam = y_new, target
        step = min(step0, 2.0 * step)
        if lam < 1.0:
            tangent = new_tangent
            # the structure's stiffness against its loads (1 / compliance) falls to zero at a limit
            # point and turns negative past it
            compliance = -float(fl @ tangent) if tangent is not None else math.inf
            if not (0.0 < compliance <= 1e4 * max(compliance0, 1e-300)) and compliance0 > 0:
                raise SolverFailure(f"load stepping stalled at load factor {lam:.6g}: a limit point of the "
                                    f"loaded structure (its stiffness against the loads fell to "
                                    f"{compliance0 / compliance if math.isfinite(compliance) else 0.0:.2g} of "
                                    f"the initial)", hist)
    return y, alpha, its


def _load_tangent(model: Model, y, alpha, lam):
    """(d q / d lam, the sign of the tangent's determinant (dense models, else None), d r / d lam) at
    a converged state: the first-order response to the loads, from one assembly."""
    r, A, info = model.system(y, alpha, lam, dense=model.n <= DENSE_CHECK)
    sign = float(np.linalg.slogdet(A)[0]) if isinstance(A, np.ndarray) else None
    rhs = np.zeros(model.n)
    rhs[:model.n_q] = -info["fl"]
    try:
        dy = solve_linear(A, rhs)
    except np.linalg.LinAlgError:
        return None, sign, info["fl"]
    return (dy[:model.n_q] if np.all(np.isfinite(dy)) else None), sign, info["fl"]


def _controlled(model: Model, path: Path, start=None, within=0.1, maxit=40):
    """Principal equilibrium by displacement control; a plain Newton solve at full load from
    ``start`` is kept if it stays on the branch (same sign of the controlled dof, within ``within``
    of its start value)."""
    dof = path.control.dof(model)
    its = 0
    y0 = alpha0 = None
    if start is not None:
        y0, alpha0 = start
        y, info = newton(model, y0, alpha0, lam=1.0, maxit=maxit)
        if info.converged and y[dof] * y0[dof] > 0 and abs(y[dof] - y0[dof]) <= within * abs(y0[dof]):
            return y, info.alpha, info.iterations
        its = info.iterations
    br = principal_branch(model, dof, path.sign, path.guess, y0, alpha0, phi_max=path.phi_max)
    return br.y, br.alpha, its + br.iterations


def solve_level(model: Model, path: Path, start=None):
    """(y, alpha, iterations) on one mesh.  ``start``: the interpolated coarser solution, or None
    (then the path's own start state, if it has one)."""
    if path.kind == "load":
        return _load_steps(model, path, start)
    within, maxit = 0.1, 40
    if start is None and path.start is not None and path.guess:
        start = path.start(model, path.guess)
        within, maxit = 0.05, 15  # a good prediction converges in a few iterations
    return _controlled(model, path, start, within, maxit)


def _prolongation_plan(mc: Model, mf: Model):
    """Per rod, the geometric part of :func:`prolong` (coarse element of every fine node, Hermite
    weights, coarse element of every fine element's midpoint), shared by all solves of one geometry."""
    plans = mf.mesh.prolongations
    key = id(mc.mesh)
    if key in plans and plans[key][0] is mc.mesh:
        return plans[key][1]
    out = []
    for r in range(len(mc.rod_nodes)):
        nc, nf = mc.rod_nodes[r], mf.rod_nodes[r]
        Xc, Xf = mc.X0[nc], mf.X0[nf]
        L = np.hypot(*(Xc[-1] - Xc[0]))
        sc = np.hypot(*(Xc - Xc[0]).T) / L
        sf = np.hypot(*(Xf - Xf[0]).T) / L
        k = np.clip(np.searchsorted(sc, sf, side="right") - 1, 0, nc.size - 2)
        h = sc[k + 1] - sc[k]
        t = (sf - sc[k]) / h
        hL = (h * L)[:, None]
        H = (2 * t**3 - 3 * t**2 + 1, (t**3 - 2 * t**2 + t)[:, None] * hL, -2 * t**3 + 3 * t**2,
             (t**3 - t**2)[:, None] * hL)
        beta0 = np.arctan2(*(Xc[-1] - Xc[0])[::-1])
        ef = np.nonzero(mf.elem_rod == r)[0]
        ec = np.nonzero(mc.elem_rod == r)[0]
        kmid = np.clip(np.searchsorted(sc, 0.5 * (sf[1:] + sf[:-1]), side="right") - 1, 0, ec.size - 1)
        out.append((nc, nf, Xc, Xf, k, t, H, beta0, ef, ec[kmid]))
    plans[key] = (mc.mesh, out)
    return out


def prolong(mc: Model, y, alpha, mf: Model):
    """Interpolate a converged state onto a finer mesh of the same structure (a Newton start).

    Node positions are cubic Hermite in the arc length, with the nodal tangents, so that the
    interpolated elements are stretched only by O(h^4) (linear interpolation would shorten them by
    O(h^2) and, with EA/EI ~ 1e6, start Newton from enormous axial forces); rotations are linear.
    Body dofs and joint multipliers carry over (same bodies and joints).
    """
    yf = np.zeros(mf.n)
    Uc = mc.nodal(y[:mc.n_q])
    Uf = mf.nodal(yf[:mf.n_q])
    af = np.zeros(mf.elements.size) if mf.elements is not None else np.zeros(0)
    for nc, nf, Xc, Xf, k, t, H, beta0, ef, ecm in _prolongation_plan(mc, mf):
        P = Xc + Uc[nc, :2]
        ang = beta0 + Uc[nc, 2]
        T = np.column_stack([np.cos(ang), np.sin(ang)])
        pos = H[0][:, None] * P[k] + H[1] * T[k] + H[2][:, None] * P[k + 1] + H[3] * T[k + 1]
        Uf[nf, :2] = pos - Xf
        Uf[nf, 2] = (1 - t) * Uc[nc[k], 2] + t * Uc[nc[k + 1], 2]
        D = np.diff(Xf + Uf[nf, :2], axis=0)
        ref = mc.elements.beta0[ecm] + alpha[ecm]
        cr, sr = np.cos(ref), np.sin(ref)
        beta = ref + np.arctan2(cr * D[:, 1] - sr * D[:, 0], cr * D[:, 0] + sr * D[:, 1])
        af[ef] = beta - mf.elements.beta0[ef]
    yf[: 3 * mf.n_nodes] = Uf.ravel()
    yf[3 * mf.n_nodes:mf.n_q] = y[3 * mc.n_nodes:mc.n_q]
    yf[mf.n_q:] = y[mc.n_q:]
    return yf, af


# -- refinement and error estimate ---------------------------------------------------------------------

class Level:
    """The converged state on one mesh; its named results (``res``) and rod arrays are computed
    when first asked for."""

    def __init__(self, n, model, y, alpha):
        self.n, self.model, self.y, self.alpha = n, model, y, alpha
        self._arrays = self._res = self._watched = self._noise = self._scatter = self._cuts = None

    @property
    def cuts(self):
        """The elements' end moments and middle cut forces from equilibrium
        (:func:`femslide.results.end_moments` with ``resultant``)."""
        if self._cuts is None:
            self._cuts = end_moments(self.model, self.y, resultant=True)
        return self._cuts

    @property
    def arrays(self):
        if self._arrays is None:
            self._arrays = rod_arrays(self.model, self.y, self.alpha, self.cuts)
        return self._arrays

    def largest_moment(self) -> float:
        """Largest |bending moment| [N m] over all rods."""
        return largest_moment(self.model, self.y, self.alpha, self.cuts)

    @property
    def res(self):
        if self._res is None:
            self._res = extract(self.model, self.y, self.alpha, self.arrays)
        return self._res


def default_watch(level, structure):
    """Every named result is watched (values, kinds): see :func:`femslide.results.flatten`."""
    return flatten(level.res, structure)


GROUPS = (("moment",), ("length", "angle"), ("force",))


def _units(kinds, L, F):
    u = {"moment": F * L, "force": F, "length": L, "angle": 1.0}
    return np.array([u[k] for k in kinds])


def _scales(vals, kinds):
    """Per-output scales for relative errors: |value|, floored at 1e-3 of its group's largest and at
    1e-10 in model units: changes below that are round-off, not discretisation error.  (A handful of
    values: Python floats.)"""
    group = [next(i for i, g in enumerate(GROUPS) if k in g) for k in kinds]
    a = [abs(v) for v in vals.tolist()]
    top = [0.0] * len(GROUPS)
    for x, g in zip(a, group):
        top[g] = max(top[g], x)
    return np.array([max(x, 1e-3 * top[g], 1e-10) for x, g in zip(a, group)])


def _force_like(kinds):
    return np.array([k in ("force", "moment") for k in kinds])


def _force_noise(lv: Level) -> float:
    """Round-off level of the element forces of a level (model units), from the model's estimate."""
    if lv._noise is None:
        m = lv.model
        lv._noise = 4.0 * float(corotational.force_noise(m.elements, m.nodal(lv.y[:m.n_q]), lv.alpha).max()) \
            if m.elements is not None else 0.0
    return lv._noise


def _roundoff_scatter(lv: Level) -> float:
    """The round-off scatter of a level's largest rod moment (computed once per level)."""
    if lv._scatter is None:
        lv._scatter = _scatter(lv)
    return lv._scatter


def _scatter(lv: Level) -> float:
    """Relative change of the largest rod moment when Newton reconverges from the solution perturbed
    by 1e-13 (relative, alternating signs): how well round-off lets the equilibrium be determined.

    Two full Newton steps: the first is taken from a residual dominated by the perturbation (1e-13
    is far above eps) and leaves its square times the model's nonlinearity, which with stiff rods
    (EA L^2/EI ~ 1e12, fine meshes) can still be ~1e-8; the second, from a residual near round-off,
    is the last step of a solve.  (A perturbation of 1e-10 needs three steps there and a chord step
    with the solve's last tangent leaves it at 1e-5.)
    """
    m = lv.model
    if m.elements is None:
        return 0.0
    y = lv.y.copy()
    q = y[:m.n_q]
    sign = np.where(np.arange(m.n_q) % 2 == 0, 1.0, -1.0)
    q += 1e-13 * sign * np.maximum(np.abs(q), 1e-6 * np.abs(q).max())
    try:
        for _ in range(2):
            r, A, _ = m.system(y, lv.alpha, 1.0)
            y -= solve_linear(A, r)
    except (np.linalg.LinAlgError, RuntimeError, ValueError):
        return 0.0
    if not np.all(np.isfinite(y)):
        return 0.0
    M0 = np.abs(lv.cuts[0]).max()
    M1 = np.abs(end_moments(m, y)).max()
    # relative to the moment, or to 1e-6 of the loads' moment scale (model unit) when the rods carry
    # (almost) none: the noise of a zero moment is no relative error of anything
    return float(abs(M1 - M0) / max(M0, 1e-6))


@dataclass
class Solution:
    """A converged static solution.

    ``result``: the named results of SPEC section 8 (SI units), Richardson-extrapolated from the two
    finest meshes when the mesh was refined (``coarse`` is then the second finest level; None when the
    finest mesh's raw values are reported); ``watched``: the watched values, likewise;
    ``error_estimate``: relative, of the largest rod moment (None for a single fixed element);
    ``level``: the finest mesh (``model``, ``y``, ``alpha``, ``arrays``: its raw per-rod arrays);
    ``path``: how the equilibrium was reached."""

    error_estimate: float | None
    iterations: int
    level: Level
    coarse: Level | None
    path: Path
    watched: np.ndarray
    raw_values: bool = False
    _result: dict | None = None

    @property
    def model(self):
        return self.level.model

    @property
    def result(self) -> dict:
        if self._result is None:
            fs = self.model.structure
            if self.coarse is None:
                self._result = self.level.res
            else:
                self._result = unflatten(self.level.res, _extrapolate_all(self.coarse, self.level, fs), fs)
        return self._result


def solve(fs: Frozen, elements: int | None = None, watch=None, path: Path | None = None,
          Lref=None, Fref=None, cache: PatternCache | None = None, target=TARGET) -> Solution:
    """Principal equilibrium of a frozen structure with adaptive refinement (module docstring).

    ``elements``: a fixed number of elements for every rod (overrides the rods' own); ``watch``:
    ``watch(level, structure) -> (values, kinds)``, the results whose accuracy decides the
    refinement (first: the moment the error estimate is about; default: every named result);
    ``path``: how to reach the equilibrium (default: :func:`choose_path` on the coarsest mesh);
    ``Lref``, ``Fref``: the model units (default: :func:`scales`); ``cache``: patterns shared with
    other solves of the same topology (a sweep).
    """
    if Lref is None or Fref is None:
        L0, F0 = scales(fs)
        Lref, Fref = Lref or L0, Fref or F0
    check_stiffness_range(fs, Lref, Fref)
    cache = cache or PatternCache()
    watch = watch or default_watch
    rods = fs.rods
    uniform = elements is not None
    fixed = {} if uniform else {r.name: r.elements for r in rods if r.elements}
    adaptive = [r for r in rods if r.name not in fixed]
    hmin = min((r.length for r in adaptive), default=1.0)
    mult = {r.name: (1 if uniform else max(1, round(r.length / hmin))) for r in adaptive}
    cache_lv: dict[int, Level] = {}
    its = [0]
    state = {"path": path}

    def counts(n):
        return {r.name: fixed.get(r.name) or n * mult[r.name] for r in rods}

    def level(n: int) -> Level:
        """The solution with n elements per (shortest adaptive) rod; meshes finer than N_DIRECT, or
        whose coarser mesh is solved already, start from the interpolated coarser solution."""
        if n in cache_lv:
            return cache_lv[n]
        start = None
        c = level((n + 1) // 2) if adaptive and n > 1 and (n > N_DIRECT or (n + 1) // 2 in cache_lv) else None
        model = Model(fs, counts(n), Lref, Fref, cache)
        if c is not None:
            start = prolong(c.model, c.y, c.alpha, model)
        if state["path"] is None:
            # on the coarsest mesh: the mechanisms and the loads' work on them do not depend on the
            # mesh, and a fine mesh of a stiff rod (EA L^2/EI ~ 1e9, 64 elements) spreads the
            # tangent's eigenvalues beyond what the round-off test for a null space can separate
            cn = {r.name: min(int(c), N_START) for r, c in zip(rods, counts(n).values())}
            state["path"] = choose_path(model if cn == counts(n) else Model(fs, cn, Lref, Fref, cache))
        y, a, k = solve_level(model, state["path"], start)
        if not cache_lv:
            check_stable(model, y, a)
        its[0] += k
        cache_lv[n] = lv = Level(n, model, y, a)
        # meshes coarser than the next coarser one are used up (started this one): drop them, so that
        # a fine solve holds two levels, not the whole hierarchy
        for k in [k for k in cache_lv if k < (n + 1) // 2]:
            del cache_lv[k]
        return lv

    def values(lv):
        if lv._watched is None:
            v, kinds = watch(lv, fs)
            lv._watched = (np.asarray(v, float), list(kinds))
        return lv._watched

    raw_values = False
    if uniform:
        fine = level(elements)
        coarse, err = None, None
        if elements >= 2:
            f1, _ = values(level(elements // 2))
            f2, _ = values(fine)
            ratio = (elements / (elements // 2)) ** 2
            err = abs(f2[0] - f1[0]) / (ratio - 1.0) / max(abs(f2[0]), 1e-300)
    elif not adaptive:
        fine = level(1)
        coarse, err = None, (0.0 if not rods else None)
        half = {r.name: fixed[r.name] // 2 for r in rods}
        if rods and all(h >= 1 for h in half.values()):
            mh = Model(fs, half, Lref, Fref, cache)
            y, a, k = solve_level(mh, state["path"], None)
            its[0] += k
            f1, _ = values(Level(0, mh, y, a))
            f2, _ = values(fine)
            r0 = rods[0].name
            ratio = (fixed[r0] / half[r0]) ** 2
            err = abs(f2[0] - f1[0]) / (ratio - 1.0) / max(abs(f2[0]), 1e-300)
    else:
        p0 = path.first_n if path is not None else N_START
        n = p0
        ext = []
        prev_raw = None
        fine = level(n)
        while True:
            coarse, fine = fine, level(2 * n)
            f1, kinds = values(coarse)
            f2, _ = values(fine)
            units = _units(kinds, Lref, Fref)
            ext.append((4.0 * f2 - f1) / 3.0)
            scale = _scales(ext[-1] / units, kinds)
            change = np.abs(f2 - f1) / units
            raw = change / scale
            if len(ext) >= 2:
                errs = np.abs(ext[-1] - ext[-2]) / units / 15.0 / scale
                err = float(min(errs[0], raw[0] / 3.0))
            else:
                errs = raw / 3.0 * 10.0  # one level only: no estimate of the extrapolated error yet
                err = float(raw[0] / 3.0)
            # an output is settled when its estimate meets the target, when it does not change, or
            # (forces and moments that are zero but for round-off, e.g. the shear of a rod in pure
            # bending) when its change is within the round-off level of the element forces
            settled = (errs <= target) | (raw <= 1e-13)
            small = ~settled & _force_like(kinds) & (np.abs(f2) / units < scale)  # below their group's floor
            if small.any():
                zero = 10.0 * _force_noise(fine)
                settled |= small & (np.abs(f2) / units <= zero) & (change <= zero)
            if (len(ext) >= 2 or np.all(raw <= 1e-13)) and settled.all():
                break
            # the first two meshes already agree to 3e-8: the finer one is accurate to its O(h^2)
            # estimate raw / 3 <= target / 10; reported as it is (not extrapolated)
            if len(ext) == 1 and np.all((raw / 3.0 <= 0.1 * target) | settled):
                raw_values = True
                break
            # the changes must shrink like h^2 (x 1/4); outputs whose changes stop shrinking *at the
            # round-off level* of the stiff model only gain noise from refining: when all unsettled
            # outputs are such, stop and report the finest level's raw values.  (On coarse meshes
            # changes can stall far above round-off: then keep refining.)
            if prev_raw is not None:
                stalled = raw > 0.6 * prev_raw
                if np.all(settled | stalled):
                    noise = 1e3 * max(_roundoff_scatter(fine), 1e-13)
                    if np.all(settled | (raw <= noise)):
                        err = float(max(raw[0], prev_raw[0]))
                        raw_values = True
                        break
            prev_raw = raw
            if 2 * n >= N_MAX:
                raise SolverFailure(f"the mesh refinement reached {2 * n} elements per rod without meeting "
                                    f"the error target {target:g} (estimate {err:.3g}); fix a mesh with "
                                    f"`elements` to accept a coarser answer")
            n *= 2
        if raw_values:
            coarse = None
    if err is not None:
        scatter = _roundoff_scatter(fine)
        err = max(err, scatter)
        if scatter > ROUNDOFF_LIMIT:
            n_el = fine.model.elements.size if fine.model.elements is not None else 0
            raise SolverFailure(f"round-off dominates the answer: the largest rod moment of the {n_el}-element "
                                f"mesh is determined only to {scatter:.2g} (relative) by the stiff axial terms "
                                f"(EA/EI of the rods, element length); use fewer elements (or the adaptive default)")
    watched = values(fine)[0] if coarse is None else (4.0 * values(fine)[0] - values(coarse)[0]) / 3.0
    return Solution(err, its[0], fine, coarse, state["path"], watched, raw_values)


def _extrapolate_all(coarse: Level, fine: Level, fs):
    f1, _ = flatten(coarse.res, fs)
    f2, _ = flatten(fine.res, fs)
    return (4.0 * f2 - f1) / 3.0
