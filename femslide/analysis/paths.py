"""How the principal branch is followed on one mesh: the path's choice, load stepping, stability.

:func:`choose_path` looks at the undeformed structure under full load, on the coarsest mesh:

- stable there (the reduced tangent, with the initial stresses of the loads, is positive definite on
  the unloaded structure's first-order mechanisms, or there are none): load control, in load steps
  whose predicted increments stay bounded, each checked against its tangent prediction and for
  stability; the steps shrink towards a limit point, where the run exits 1 with its load factor
  (:func:`_load_steps`);
- not stable (a near-mechanism such as the paper's structure, whose undeformed tangent is singular
  in the rigid limit, or a structure that must deform to carry its loads): displacement control of
  the dof that moves most in the softest mode (a body rotation when one takes part), marching in the
  direction in which the loads do work (femslide.analysis.continuation); a maximum of the load factor
  before full load is a limit point (exit 1);
- singular with and without the loads' initial stresses: a mechanism (exit 1 naming the free part
  and direction).

:func:`check_stable`: the equilibrium reached must be stable; a negative eigenvalue of the reduced
tangent at full load means the path crossed a bifurcation (exit 1).  :func:`solve_level` solves one
mesh along the chosen :class:`Path`.
"""
from __future__ import annotations

import math

import numpy as np

from femslide.analysis.continuation import principal_branch
from femslide.analysis.newton import newton
from femslide.errors import SolverFailure
from femslide.model.discrete import Model
from femslide.model.linalg import det_sign, solve_linear
from femslide.records import dataclass

N_START = 2       # elements per (shortest) rod on the coarsest adaptive level
MAX_STEP_ROTATION = 0.8      # rad: largest predicted rotation increment of a load step
MAX_STEP_TRANSLATION = 0.5   # model lengths: largest predicted translation increment of a load step
DENSE_CHECK = 600  # unknowns: the path choice and the stability check run on meshes up to this size


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
    ``load_steps`` the first number of load steps.  Also "linear" (first-order theory: one linear
    solve) and "arc-length" (the first equilibrium at full load along the path traced by arc-length
    continuation, through limit points; ``trace`` keeps the path traced on the first mesh)."""

    kind: str
    control: Control | None = None
    sign: float = 1.0
    guess: float | None = None
    start: object = None
    load_steps: int = 1
    phi_max: float = math.pi
    first_n: int = N_START
    note: str = ""
    trace: object = None


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
    y, elements = model.zero_state()
    if model.n_c:
        r, A, info = model.system(y, elements, lam, dense=True)
        G = A[model.n_q:, :model.n_q]
        mu, *_ = np.linalg.lstsq(G.T, -r[:model.n_q], rcond=None)
        y[model.n_q:] = mu
    return y, elements


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
    y0, e0 = model.zero_state()
    _, A0, _ = model.system(y0, e0, 0.0, dense=True)
    Z, w0, V0 = _reduced(A0, n_q)
    if w0.size == 0:
        return Path("load")  # fully fixed by the joints
    tol0 = 1e-9 + 1e3 * np.finfo(float).eps * float(np.abs(w0).max())
    null = w0 <= tol0
    if not null.any():
        return _load_path(model)
    y, elements = _initial_stress(model)
    r, A1, info = model.system(y, elements, 1.0, dense=True)
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
        # a stiffness above the absolute floor that is null only against the stiffest part: the
        # contrast, not a free part (a rod 1e-3 of the others' length, EA 1e15 on a short rod)
        contrast = float(w0[null].max()) > 1e-9
        raise SolverFailure(
            f"mechanism: {part.describe(model.structure)} is free to move (its stiffness is zero with "
            f"and without the loads{'; the loads push it along that freedom' if pushed else ''}); "
            f"add a joint or a spring that holds it"
            + (f" - or, if it is held, the stiffest part is over {1.0 / (1e3 * np.finfo(float).eps):.0e} "
               f"times stiffer than it (beyond double precision): declare a very short or very stiff "
               f"rod as a rigid body or a weld" if contrast else ""))
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
    y, elements = _initial_stress(model)
    r, A, _ = model.system(y, elements, 1.0, dense=True)
    try:
        dy = solve_linear(A, -r)
        rot = float(np.abs(dy[model.rotation_dofs()]).max()) if model.rotation_dofs().size else 0.0
    except np.linalg.LinAlgError:
        rot = math.inf
    steps = max(1, math.ceil(rot / 0.8)) if math.isfinite(rot) else 8
    return Path("load", load_steps=min(steps, 64))


def is_stable(model: Model, y, elements) -> bool | None:
    """Whether an equilibrium is stable: its reduced tangent positive definite (dense models up to
    DENSE_CHECK unknowns; None above)."""
    if model.n > DENSE_CHECK or model.n_q == 0:
        return None
    _, A, _ = model.system(y, elements, 1.0, dense=True)
    elements.revert()
    _, w, _ = _reduced(A, model.n_q)
    return not (w.size and w[0] < -1e-9 * (1.0 + 1e-3 * float(np.abs(w).max())))


def check_stable(model: Model, y, elements):
    """Raise SolverFailure if the equilibrium (coarse mesh) has a negative reduced-tangent eigenvalue.

    With m independent joint equations, det [[K, G^T], [G, 0]] has the sign (-1)^m exactly when the
    reduced tangent Z^T K Z (Z: the joints' null space) has an even number of negative eigenvalues
    (Sylvester): a sign test by one LU; only when it fails are the eigenvalues computed."""
    if model.n > DENSE_CHECK or model.n_q == 0:
        return
    # the last tangent Newton assembled (one step, at most 1e-7, before the solution) will do
    A = getattr(model, "last_tangent", None)
    if A is None or A.shape[0] != model.n:
        _, A, _ = model.system(y, elements, 1.0, dense=True)
        elements.revert()
    n_q = model.n_q
    sign = det_sign(A)
    if sign == (-1.0) ** model.n_c:
        return
    Z, w, V = _reduced(A, n_q)
    if w.size and w[0] < -1e-9 * (1.0 + 1e-3 * float(np.abs(w).max())):
        part = _mode_part(model, Z @ V[:, 0])
        raise SolverFailure(f"the equilibrium reached at full load is unstable (reduced tangent eigenvalue "
                            f"{w[0]:.3g}; softest: {part.describe(model.structure)}): the load path crossed a "
                            f"bifurcation or limit point before full load", critical=True)


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
        if info.converged and near(model, y, start[0]):
            return y, start[1].commit(), info.iterations
        start[1].revert()
    dense = model.n <= DENSE_CHECK
    # the undeformed state with the multipliers that hold the loads there: a structure held only by
    # its loads' initial stresses (a hanging pendulum) has a singular tangent without them
    y, es = _initial_stress(model, 1.0 / path.load_steps) if dense else model.zero_state()
    step0 = 1.0 / path.load_steps
    lam, step, its = 0.0, step0, 0
    stable = (-1.0) ** model.n_c
    tangent, _, fl = _load_tangent(model, model.zero_state()[0], es.copy(), 0.0)
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
                                f"bifurcation of the loaded structure ({why})", hist, critical=True)
        target = lam + dlam
        # Euler predictor: the tangent's first-order response to the step's load (multipliers kept)
        y_pred = y.copy()
        y_pred[:model.n_q] += tangent * dlam
        y_new, info = newton(model, y_pred, es, lam=target)
        its += info.iterations
        ok, reason, hist = info.converged, info.reason, info.history
        if ok:
            # the increment against the tangent prediction (translations and rotations, model units)
            pred = tangent * dlam
            size = float(np.abs(pred).max())
            if float(np.abs(y_new[:model.n_q] - y[:model.n_q] - pred).max()) > max(size, 1e-12):
                ok, reason = False, "the step left the tangent's neighbourhood: it jumped past a limit point"
        es_new = es.committed_trial() if ok else None   # (es keeps the last accepted state)
        es.revert()
        if ok and target < 1.0:   # (the stability at full load is checked on the solution)
            new_tangent, sign, fl = _load_tangent(model, y_new, es_new, target)
            if sign is not None and sign != stable:
                ok, reason = False, "the equilibrium lost its stability"
        if not ok:
            step = 0.5 * dlam
            continue
        es = es_new.revert()
        y, lam = y_new, target
        step = min(1.0, 2.0 * step)
        if lam < 1.0:
            tangent = new_tangent
            # the structure's stiffness against its loads (1 / compliance) falls to zero at a limit
            # point and turns negative past it
            compliance = -float(fl @ tangent) if tangent is not None else math.inf
            if not (0.0 < compliance <= 1e4 * max(compliance0, 1e-300)) and compliance0 > 0:
                raise SolverFailure(f"load stepping stalled at load factor {lam:.6g}: a limit point of the "
                                    f"loaded structure (its stiffness against the loads fell to "
                                    f"{compliance0 / compliance if math.isfinite(compliance) else 0.0:.2g} of "
                                    f"the initial)", hist, critical=True)
    return y, es, its


def near(model: Model, y, y0, within=0.25) -> bool:
    """Whether the equilibrium y, solved from the interpolated coarser solution y0, is the same
    equilibrium refined: its frame dofs moved by at most ``within`` of y0's largest (a finer mesh
    changes a solution by its discretisation error; a Newton solve that lands on another branch -
    past a limit point the finer mesh no longer reaches - moves it by order one)."""
    dq = float(np.abs(y[:model.n_q] - y0[:model.n_q]).max()) if model.n_q else 0.0
    return dq <= within * (float(np.abs(y0[:model.n_q]).max()) if model.n_q else 0.0) + 1e-12


def _load_tangent(model: Model, y, elements, lam):
    """(d q / d lam, the sign of the tangent's determinant (dense models, else None), d r / d lam) at
    a converged state: the first-order response to the loads, from one assembly."""
    r, A, info = model.system(y, elements, lam, dense=model.n <= DENSE_CHECK)
    sign = float(np.linalg.slogdet(A)[0]) if isinstance(A, np.ndarray) else None
    rhs = np.zeros(model.n)
    rhs[:model.n_q] = -info["fl"]
    rows = getattr(model, "_motion_rows", None)
    if rows is not None and rows.size:   # a prescribed support motion: its equations move with lam
        rhs[rows] = -model._motion_vals
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
    y0 = e0 = None
    if start is not None:
        y0, e0 = start
        y, info = newton(model, y0, e0, lam=1.0, maxit=maxit)
        if info.converged and y[dof] * y0[dof] > 0 and abs(y[dof] - y0[dof]) <= within * abs(y0[dof]):
            return y, e0.commit(), info.iterations
        e0.revert()
        its = info.iterations
    br = principal_branch(model, dof, path.sign, path.guess, y0, e0, phi_max=path.phi_max)
    return br.y, br.elements, its + br.iterations


def solve_level(model: Model, path: Path, start=None):
    """(y, elements, iterations) on one mesh: the equilibrium and its elements' history
    (femslide.model.state.ElementState, committed there).  ``start``: (y, elements) of the
    interpolated coarser solution, or None (then the path's own start state, if it has one)."""
    if path.kind == "load":
        return _load_steps(model, path, start)
    if path.kind == "arc-length":
        return _arc_length(model, path, start)
    if path.kind == "linear":   # first-order theory: one linear solve (Newton converges in one step)
        y, es = model.zero_state() if start is None else start
        y, info = newton(model, y, es, lam=1.0)
        if not info.converged:
            es.revert()
            raise SolverFailure(f"the linear system could not be solved ({info.reason}): a mechanism or a "
                                f"structure held only by its loads' stresses, which first-order theory leaves "
                                f"out", info.history)
        return y, es.commit(), info.iterations
    within, maxit = 0.1, 40
    if start is None and path.start is not None and path.guess:
        start = path.start(model, path.guess)
        within, maxit = 0.05, 15  # a good prediction converges in a few iterations
    return _controlled(model, path, start, within, maxit)


def _arc_length(model: Model, path: Path, start=None):
    """The first equilibrium at full load along the path traced by arc-length continuation
    (femslide.analysis.arclength), or - on a finer mesh - the equilibrium refined from the
    interpolated coarser one (kept if it stays near it, else the path is traced on this mesh too)."""
    from femslide.analysis.arclength import Tracer
    from femslide.model.state import ElementState
    if start is not None:
        y, info = newton(model, start[0], start[1], lam=1.0)
        if info.converged and near(model, y, start[0]):
            return y, start[1].commit(), info.iterations
        start[1].revert()
    tr = Tracer(model).trace()
    tr.model = model
    if path.trace is None:
        path.trace = tr
    return tr.end.y, ElementState(tr.end.alpha.copy()), tr.iterations
