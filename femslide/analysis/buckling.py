"""Linear buckling: the load factors at which a loaded structure loses stability, and its mode shapes.

The tangent stiffness of a state splits into an elastic part K_E (the rods' material stiffness at
the state's geometry, the springs' k) and a geometric part K_G (what the stresses add: the rods'
axial forces and moments turning with their chords, the joints' forces on their curved
constraints, loads turning with their bodies, springs' forces on turning guides), linear in those
stresses.  Scaling the stresses by lam, the structure loses stability where

    (K_E + lam K_G) phi = 0  on the joints' null space (G phi = 0),

the generalized eigenproblem solved here for the lowest positive lam (the buckling load factors of
the structure under its loads, load factor 1 = the loads as declared or as a combination gives
them):

- ``about = "equilibrium"`` (default): the state is the equilibrium under the loads (exact theory,
  femslide.analysis.static's principal branch), K_E = K_T - K_G there; lam = 1 is that equilibrium
  itself, so lam > 1 for a stable one, and the prebuckling deformation is taken into account;
- ``about = "reference"``: classic linear buckling, the reference geometry with the stresses of the
  first-order solution (femslide.model.linear): K_E the linear stiffness, K_G the initial-stress
  matrix.

For a column whose prebuckling state is pure compression both give the Euler loads (a cantilever
under an end load pi^2 EI / (4 L^2), pinned-roller pi^2 EI / L^2).

Accuracy: the rods are meshed like the statics (2, 4, 8, ... elements per shortest rod) and each
load factor is Richardson-extrapolated from the two finest meshes (O(h^2)) until the estimated
relative error of every reported one is below ``target``; ``error_estimate`` is the largest.  Mode
shapes come from the finest mesh, over the frame dofs in model units, scaled to a largest translation
of 1 (rotation-only modes: a largest rotation of 1).  Dense eigen-solves up to DENSE_LIMIT frame dofs,
ARPACK on the saddle-point factorisation above.
"""
from __future__ import annotations

import math
import time

import numpy as np
import scipy.sparse as sp

from femslide.analysis.paths import N_START, choose_path, solve_level
from femslide.analysis.refine import prolong
from femslide.analysis.static import Meshes, check_stiffness_range, scales
from femslide.elements import corotational
from femslide.errors import BadInput, SolverFailure
from femslide.model.discrete import PatternCache
from femslide.results.outcome import Buckling, Figure, Outcome

DENSE_LIMIT = 150    # frame dofs: dense generalized eigenproblem up to here (ARPACK above: O(n) per step)
TARGET = 1e-6        # estimated relative error of the reported load factors
N_MAX = 1024
NOISE = 1e-9         # 1/lam below this fraction of the largest |1/lam| is round-off (no buckling)
ABOUT = ("equilibrium", "reference")


def buckling(fs, count=4, about="equilibrium", elements=None, combination=None, name="structure",
             target=TARGET) -> Outcome:
    """`femslide buckling`: the ``count`` lowest positive buckling load factors (module docstring),
    with their error estimates and mode shapes.  ``elements``: a fixed mesh for every rod;
    ``combination``: the name of a load combination whose loads are scaled (default: every load)."""
    t0 = time.perf_counter()
    if about not in ABOUT:
        raise BadInput(f"about = {about!r}; allowed: {', '.join(ABOUT)}")
    factors = None
    if combination is not None:
        cb = next((c for c in fs.combinations if c.name == combination), None)
        if cb is None:
            raise BadInput(f"combination {combination!r}: no such combination; combinations: "
                           f"{', '.join(c.name for c in fs.combinations) or 'none'}")
        factors = cb.factor_dict()
    if not fs.rods:
        raise BadInput("buckling: the structure has no rods (only rods buckle; bodies are rigid)")
    L, F = scales(fs)
    check_stiffness_range(fs, L, F)
    cache = PatternCache()
    meshes = Meshes(fs, elements, "nonlinear", L, F, cache, factors)
    lin = Meshes(fs, elements, "linear", L, F, cache, factors) if about == "reference" else None
    state = {"path": None, "prev": None}

    def level(n):
        model = meshes(n)
        if about == "reference":
            lm = lin(n)
            y, es, _ = solve_level(lm, _linear_path(), None)
            return model, lm, y, es
        if state["path"] is None:
            cn = {k: min(int(c), N_START) for k, c in meshes.counts(n).items()}
            state["path"] = choose_path(meshes(n, cn))
        start = None
        if state["prev"] is not None:
            pm, py, pe = state["prev"]
            start = prolong(pm, py, pe, model)
        y, es, _ = solve_level(model, state["path"], start)
        state["prev"] = (model, y, es)
        return model, None, y, es

    n = meshes.first
    lams, ext, err = [], None, None
    while True:
        model, lm, y, es = level(n)
        lam, shapes = _eigen(model, lm, y, es, count)
        lams.append((n, lam))
        if not meshes.adaptive:
            if state["path"] is None and about == "equilibrium":
                state["path"] = choose_path(model)
            ext, err = lam, _fixed_error(meshes, lin, about, state, n, count, lam)
            break
        if len(lams) >= 2:
            (_, l1), (_, l2) = lams[-2], lams[-1]
            k = min(l1.size, l2.size)
            if k == 0:
                ext, err = l2, np.zeros(0)
                break
            new = (4.0 * l2[:k] - l1[:k]) / 3.0
            raw = np.abs(l2[:k] - l1[:k]) / 3.0 / np.abs(new)
            if ext is not None and ext.size >= k:
                errs = np.minimum(raw, np.abs(new - ext[:k]) / 15.0 / np.abs(new))
                done = bool(np.all(errs <= target))
            else:
                errs = raw
                done = bool(np.all(raw <= 0.1 * target))
            ext, err = new, errs
            if done:
                break
        if 2 * n > N_MAX:
            break
        n *= 2
    vals = [float(v) for v in ext[:count]]
    errs = [None if e is None else float(e) for e in list(err)[:count]] if err is not None else [None] * len(vals)
    res = {"converged": True, "about": about, "load_factors": vals, "error_estimates": errs,
           "error_estimate": max((e for e in errs if e is not None), default=None),
           "elements": {r.name: int(nd.size - 1) for r, nd in zip(fs.rods, model.rod_nodes)}}
    if combination is not None:
        res["combination"] = combination
    if not vals:
        res["note"] = ("no positive load factor: the loads' stresses only stiffen the structure (tension); "
                       "reversed loads may buckle it")
    res["wall_time_s"] = time.perf_counter() - t0
    base = y if about == "equilibrium" else np.zeros(model.n)
    out = Outcome(res, name, buckling=Buckling(model, base, es.committed if about == "equilibrium"
                                               else np.zeros_like(es.committed), vals, shapes[:len(vals)]))
    if vals:
        out.figures.append(Figure("buckling_modes.png", "buckling", _figure(model, base, vals, shapes, name, about)))
    return out


def _figure(model, base, lams, shapes, name, about):
    """The picture's data: per mode, the rods' node positions [m] of the base state and displaced
    along the mode (largest translation 10 % of the structure's size)."""
    L = model.Lref
    X = model.X0 + model.nodal(base[:model.n_q])[:, :2]
    modes = []
    for lam, phi in zip(lams, shapes):
        D = X + 0.1 * model.nodal(phi)[:, :2]
        modes.append({"load_factor": lam, "rods": [(D[nd] * L).tolist() for nd in model.rod_nodes]})
    return {"base": [(X[nd] * L).tolist() for nd in model.rod_nodes], "modes": modes,
            "title": f"{name}: buckling modes about the {about}"}


def _linear_path():
    from femslide.analysis.paths import Path
    return Path("linear")


def _fixed_error(meshes, lin, about, state, n, count, lam):
    """The relative error estimate on a fixed mesh: the change from the mesh with half as many
    elements, over 3 (O(h^2)); None when a rod has a single element."""
    half = {k: c // 2 for k, c in meshes.counts(n).items()}
    if any(h < 1 for h in half.values()) or lam.size == 0:
        return [None] * lam.size
    model = meshes(n, half)
    if about == "reference":
        lm = lin(n, half)
        y, es, _ = solve_level(lm, _linear_path(), None)
    else:
        lm = None
        y, es, _ = solve_level(model, state["path"], None)
    lh, _ = _eigen(model, lm, y, es, count)
    k = min(lh.size, lam.size)
    ratio = (max(meshes.counts(n).values()) / max(max(half.values()), 1)) ** 2
    return list(np.abs(lam[:k] - lh[:k]) / (ratio - 1.0) / np.abs(lam[:k])) + [None] * (lam.size - k)


def split(model, y, es, lin_model=None):
    """(K_E, K_G, G): the elastic and geometric parts of the tangent over the frame dofs and the
    joints' gradient, at the state (module docstring): the equilibrium y (``lin_model`` None) or the
    reference with the first-order state y of ``lin_model`` (sparse CSC, model units)."""
    n_q = model.n_q
    if lin_model is None:
        _, A, _ = model.system(y, es, 1.0)
        es.revert()
        x, alpha, z = y[:n_q], es.committed, y
        NM = corotational.element_terms(model.elements, x, alpha, tangent=False,
                                        free=getattr(model, "free_T", None))[2] \
            if model.elements is not None else None   # (a thermal load's free forces are stresses too)
    else:
        y0, e0 = model.zero_state()
        _, A, _ = model.system(y0, e0, 0.0)
        x, alpha, z = y0[:n_q], e0.committed, y0
        NM = lin_model.element_forces(y[:n_q], None)[0].T if model.elements is not None else None
    S = model.to_csc(A)
    KT, G = S[:n_q, :n_q], S[n_q:, :n_q]
    rows, cols, vals = [], [], []
    if model.elements is not None:
        Kg = corotational.geometric_terms(model.elements, x, alpha, NM)
        c = model.elements.conn
        ed = np.concatenate([3 * c[:, :1] + np.arange(3), 3 * c[:, 1:] + np.arange(3)], axis=1)
        rows.append(np.repeat(ed, 6, axis=1).ravel())
        cols.append(np.tile(ed, (1, 6)).ravel())
        vals.append(Kg.ravel())
    for link in model.constraints:
        d = link.dofs
        if not d.size:
            continue
        _, _, H = link.eval(z[d], model.multipliers(y, link))
        rows.append(np.repeat(d, d.size))
        cols.append(np.tile(d, d.size))
        vals.append(np.asarray(H).ravel())
    for t in model.terms:
        sh = getattr(t, "stress_hessian", None)
        if sh is None or not t.dofs.size:
            continue   # a term without a stress part: all of its stiffness is elastic
        d = t.dofs
        H = sh(z[d], 1.0) if lin_model is None else sh(z[d], 1.0, linear=y[d])
        rows.append(np.repeat(d, d.size))
        cols.append(np.tile(d, d.size))
        vals.append(np.asarray(H).ravel())
    KG = sp.csc_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n_q, n_q)) \
        if vals else sp.csc_matrix((n_q, n_q))
    KG = 0.5 * (KG + KG.T)
    KE = 0.5 * (KT + KT.T) - (KG if lin_model is None else 0.0)
    return sp.csc_matrix(KE), sp.csc_matrix(KG), sp.csc_matrix(G)


def _eigen(model, lin_model, y, es, count):
    """(lowest positive load factors ascending, their mode shapes (k, n_q)) at the state."""
    KE, KG, G = split(model, y, es, lin_model)
    n_q = model.n_q
    if n_q <= DENSE_LIMIT:
        from scipy.linalg import eig, eigh, null_space
        Gd = G.toarray()
        Z = null_space(Gd) if Gd.shape[0] else np.eye(n_q)
        if Z.shape[1] == 0:
            return np.zeros(0), np.zeros((0, n_q))
        Ke = Z.T @ KE.toarray() @ Z
        Kg = Z.T @ KG.toarray() @ Z
        Ke, Kg = 0.5 * (Ke + Ke.T), 0.5 * (Kg + Kg.T)
        try:   # K_E positive definite: -K_G phi = (1/lam) K_E phi, symmetric; the largest 1/lam
            m = Ke.shape[0]
            k = min(m, 2 * count + 4)
            nu, V = eigh(-Kg, Ke, subset_by_index=[m - k, m - 1])
            # (1/lam at the round-off level of the largest |1/lam| is no buckling: a rod in tension)
            # (the scale of 1/lam: the largest ratio of the two parts' diagonals)
            scale = max(float(np.max(np.abs(np.diag(Kg)) / np.maximum(np.abs(np.diag(Ke)), 1e-300))),
                        float(np.abs(nu).max()), 1e-300)
            with np.errstate(divide="ignore"):
                lam = np.where(nu > NOISE * scale, 1.0 / nu, np.inf)
        except np.linalg.LinAlgError:   # K_E not definite (a mechanism held by the loads): general form
            w, V = eig(Ke, -Kg)
            lam = np.where(np.isfinite(w) & (np.abs(w.imag) <= 1e-9 * np.abs(w)), w.real, np.inf)
            V = V.real
        keep = np.isfinite(lam) & (lam > 0)
        order = np.argsort(lam[keep])
        lam, V = lam[keep][order], V[:, keep][:, order]
        shapes = (Z @ V[:, :count]).T
    else:
        lam, shapes = _eigen_sparse(model, KE, KG, G, count)
    return lam[:count], _normalise(model, shapes)


def _eigen_sparse(model, KE, KG, G, count):
    """ARPACK on the constrained inverse of K_E (saddle-point LU) applied to -K_G: 1/lam largest."""
    import scipy.sparse.linalg as spla
    n_q, n_c = model.n_q, G.shape[0]
    S = sp.bmat([[KE, G.T], [G, None]]).tocsc() if n_c else KE.tocsc()
    lu = spla.splu(S, permc_spec="COLAMD")

    def op(x):
        b = np.zeros(n_q + n_c)
        b[:n_q] = -(KG @ x)
        return lu.solve(b)[:n_q]

    k = min(max(2 * count, count + 4), n_q - 2)
    Lop = spla.LinearOperator((n_q, n_q), matvec=op, dtype=float)
    try:
        nu, V = spla.eigs(Lop, k=k, which="LR", tol=1e-12, maxiter=50 * n_q)
    except spla.ArpackNoConvergence as exc:
        raise SolverFailure(f"buckling: the eigen-solver did not converge ({exc})") from None
    nu, V = nu.real, V.real
    keep = nu > NOISE * max(np.abs(nu).max(), 1e-300)
    lam = 1.0 / nu[keep]
    order = np.argsort(lam)
    return lam[order], V[:, keep][:, order].T


def _normalise(model, shapes):
    """Mode shapes scaled to a largest translation of 1 (or rotation, if nothing translates), the
    largest component positive."""
    shapes = np.array(shapes, float)
    for k in range(shapes.shape[0]):
        v = shapes[k]
        trans = np.ones(v.size, bool)
        trans[model.rotation_dofs()] = False
        big = float(np.abs(v[trans]).max()) if trans.any() else 0.0
        if big <= 1e-12 * float(np.abs(v).max()):
            big = float(np.abs(v).max())
        i = int(np.argmax(np.abs(v)))
        shapes[k] = v * math.copysign(1.0, v[i]) / big
    return shapes
