"""Named results of a static state, in SI units: rods, bodies, joints and support reactions.

Conventions (counter-clockwise rotations and moments; forces in global x, y):

- rod arrays along the arc length s from the rod's ``start``: displacements (u, v), rotation theta,
  axial force N (tension > 0), shear force V and bending moment M = EI dtheta/ds (M > 0 where the rod
  turns counter-clockwise as s grows).  At a cut at s the part beyond the cut exerts on the part
  before it the force N t - V n and the moment +M (t the rod's tangent, n = t turned by +90 degrees);
  so dM/ds = V and, under a distributed load q per unit length, dN/ds = -q . t, dV/ds = -q . n;
- nodal values from equilibrium of the rod piece before the node (exact to the Newton residual,
  where the elements' own deformations, times a huge EA or EI, would carry round-off): the element
  end moments are those that balance the joint forces, springs and nodal loads on the nodes before
  them (in the deformed configuration), corrected by the fixed-end moments of a distributed load
  (exact for a linear beam); N and V are the force resultant G(s) of the same sums (statically
  G(s) = -(F_start + q s), F_start the joint forces and point loads on the rod's start node, q the
  distributed load; nodal inertia forces of a dynamic state included) projected on the nodal
  tangent.  ``M_max`` includes the interior extremum of the parabola a distributed load adds
  in an element;
- bodies: centroid position (x, y) now and rotation;
- joints: the force (Fx, Fy) and moment M that part b exerts on part a at the joint point (springs
  included), the slide (sliders, rollers: displacement of a's point along the axis from the
  reference) and the rotation of a relative to b (pins);
- reactions: the joints with the ground, as forces of the ground on the structure.

A model of first-order theory (``model.linear``, femslide.model.linear) has its results recovered
the same way on the reference geometry: equilibrium of the undeformed rod pieces, joint forces on
the reference gradients, springs linear in the displacements, slides and body positions to first
order.
"""
from __future__ import annotations

import numpy as np

from femslide.joints.base import at_joint_point


def rod_arrays(model, y, alpha, cuts=None, lam=1.0):
    """Per rod (by name): node arrays s, x, y, u, v, theta, N, V, M (SI) and the largest |M| along
    the rod including interior extrema (``M_max``).  ``cuts``: ``end_moments(model, y,
    resultant=True)`` of this state if already computed; ``lam``: the load factor of the state (an
    equilibrium on a load path; 1 = full load)."""
    L, F = model.Lref, model.Fref
    q = y[:model.n_q]
    U = model.nodal(q)
    out = {}
    if model.elements is None:
        return out
    es = model.elements
    X = model.X0 + U[:, :2]
    Xe = model.X0 if model.linear else X   # the geometry equilibrium is written on
    qb, Gmid = end_moments(model, y, Xe, resultant=True, lam=lam) if cuts is None else cuts
    D = Xe[es.conn[:, 1]] - Xe[es.conn[:, 0]]
    Ln = np.hypot(D[:, 0], D[:, 1])
    t = D / Ln[:, None]
    nrm = np.column_stack([-t[:, 1], t[:, 0]])
    L0 = es.L0
    qe = model.elem_q if lam == 1.0 else lam * model.elem_q
    qp = np.einsum("ij,ij->i", qe, nrm)
    fem = qp * L0 * L0 / 12.0
    Ms = -qb[:, 0] + fem
    Me = qb[:, 1] + fem
    # interior extremum of M(xi) = (1 - xi) Ms + xi Me - qp L0^2 xi (1 - xi) / 2
    loaded = qp != 0
    xi = np.full(qp.size, -1.0)
    xi[loaded] = 0.5 - (Me[loaded] - Ms[loaded]) / (qp[loaded] * L0[loaded] ** 2)
    xi = np.where((xi > 0) & (xi < 1), xi, 0.0)
    Mi = (1 - xi) * Ms + xi * Me - qp * L0 * L0 * xi * (1 - xi) / 2
    fs = model.structure
    for k, rod in enumerate(fs.rods):
        nodes = model.rod_nodes[k]
        el = np.nonzero(model.elem_rod == k)[0]
        ang = rod.angle + (0.0 if model.linear else U[nodes, 2])
        tn = np.column_stack([np.cos(ang), np.sin(ang)])
        nn = np.column_stack([-tn[:, 1], tn[:, 0]])
        M = np.zeros(nodes.size)
        M[:-1] += Ms[el]
        M[1:] += Me[el]
        M[1:-1] *= 0.5      # an interior node: the mean of its two elements (equal at equilibrium)
        s = np.concatenate([[0.0], np.cumsum(L0[el])])
        # the cut force at the nodes from the one at the element middles: node i carries half of
        # element i's distributed load, G(s_i) = G_mid,i + q L_i / 2 (and G_mid - q L / 2 at the end)
        hq = qe[el] * (0.5 * L0[el])[:, None]
        G = np.vstack([Gmid[el] + hq, Gmid[el[-1:]] - hq[-1:]])
        N = np.einsum("ij,ij->i", G, tn)
        V = -np.einsum("ij,ij->i", G, nn)
        Mside = np.concatenate([Ms[el], Me[el], Mi[el]])
        out[rod.name] = {
            "s": s * L, "x": X[nodes, 0] * L, "y": X[nodes, 1] * L,
            "u": U[nodes, 0] * L, "v": U[nodes, 1] * L, "theta": U[nodes, 2].copy(),
            "N": N * F, "V": V * F, "M": M * F * L,
            "M_max": float(np.abs(Mside).max()) * F * L,
            "N_max": float(np.abs(N).max()) * F,
            "V_max": float(np.abs(V).max()) * F,
        }
    return out


def moment_samples(model, y, alpha, k=8, cuts=None, lam=1.0):
    """Per rod: the bending moment [N m] at k points inside every element and at the nodes, on the
    continuous solution (the end moments from equilibrium plus the parabola of a distributed load, as
    :func:`rod_arrays`): {rod: (s [m], M [N m])}, for diagrams that show interior extrema."""
    if model.elements is None:
        return {}
    L, F = model.Lref, model.Fref
    es = model.elements
    X = model.X0 if model.linear else model.X0 + model.nodal(y[:model.n_q])[:, :2]
    qb, _ = end_moments(model, y, X, resultant=True, lam=lam) if cuts is None else cuts
    D = X[es.conn[:, 1]] - X[es.conn[:, 0]]
    t = D / np.hypot(D[:, 0], D[:, 1])[:, None]
    qp = np.einsum("ij,ij->i", lam * model.elem_q, np.column_stack([-t[:, 1], t[:, 0]]))
    L0 = es.L0
    fem = qp * L0 * L0 / 12.0
    Ms, Me = -qb[:, 0] + fem, qb[:, 1] + fem
    xi = np.linspace(0.0, 1.0, k + 2)[:-1]
    out = {}
    for r, rod in enumerate(model.structure.rods):
        el = np.nonzero(model.elem_rod == r)[0]
        s0 = np.concatenate([[0.0], np.cumsum(L0[el])])
        M = (1 - xi) * Ms[el, None] + xi * Me[el, None] - (qp[el] * L0[el] ** 2)[:, None] * xi * (1 - xi) / 2
        s = s0[:-1, None] + xi * L0[el, None]
        out[rod.name] = (np.append(s.ravel(), s0[-1]) * L, np.append(M.ravel(), Me[el[-1]]) * F * L)
    return out


def end_moments(model, y, X=None, resultant=False, lam=1.0):
    """End moments (n_elements, 2) [model units] of every element, in the sign of the elements' basic
    forces (M1 at the start node, M2 at the end; a beam's M(s) is -M1 at its start, +M2 at its end),
    from the equilibrium of the rod piece up to the element: at node i of a rod the element starting
    there balances the generalised forces g_j (loads, springs, joints: :meth:`Model.applied`) on the
    nodes j <= i,

        M1_i = -sum_{j<=i} [g_j^M + (x_j - x_i) x g_j^F],   M2_i = -M1_i - (x_i - x_{i+1}) x F1_i,

    with F1_i = -sum_{j<=i} g_j^F (x the current node positions, a x b = a_x b_y - a_y b_x).  Equal to
    the elements' own moments at equilibrium, but with the round-off of the forces instead of that of
    EI times a curvature from nearly equal rotations.

    With ``resultant``: also the force (n_elements, 2) that the part beyond each element's middle
    exerts on the part before it (G = N t - V n of the module docstring), sum_{j<=i} g_j^F: at the
    middle because node i carries half of element i's share of a distributed load."""
    if model.elements is None:
        return (np.zeros((0, 2)), np.zeros((0, 2))) if resultant else np.zeros((0, 2))
    if X is None:
        X = model.X0 if model.linear else model.X0 + model.nodal(y[:model.n_q])[:, :2]
    g = model.applied(y, lam)[:3 * model.n_nodes].reshape(-1, 3)
    first = model.node_first
    Xr = X - X[first]
    rows = g.copy()      # forces and moments about each rod's start node
    rows[:, 2] += Xr[:, 0] * g[:, 1] - Xr[:, 1] * g[:, 0]
    C = rows.cumsum(axis=0)
    C -= C[first] - rows[first]            # sums over each rod's own nodes only
    es = model.elements
    Ci, Xi = C[es.i], Xr[es.i]
    d = Xi - Xr[es.j]
    M = np.empty((es.size, 2))
    M[:, 0] = Xi[:, 0] * Ci[:, 1] - Xi[:, 1] * Ci[:, 0] - Ci[:, 2]
    M[:, 1] = d[:, 0] * Ci[:, 1] - d[:, 1] * Ci[:, 0] - M[:, 0]
    return (M, Ci[:, :2].copy()) if resultant else M


def element_cuts(model, y, alpha):
    """The (end moments, middle force) pair of :func:`end_moments` (``resultant=True``) taken from the
    elements' own basic forces instead of the equilibrium of the rod pieces: for a state that is not
    a static equilibrium of :meth:`Model.applied` - a time step of the dynamics (inertia, damping and
    friction forces act besides it), a displaced mode shape - where the equilibrium recovery would
    miss those forces.  M from the basic end moments, G = N t - V n at the element middle with N the
    basic axial force and V = (M1 + M2) / l the element shear (l the current chord)."""
    if model.elements is None:
        return np.zeros((0, 2)), np.zeros((0, 2))
    qb, _ = model.element_forces(y[:model.n_q], alpha)
    es = model.elements
    X = model.X0 if model.linear else model.X0 + model.nodal(y[:model.n_q])[:, :2]
    D = X[es.conn[:, 1]] - X[es.conn[:, 0]]
    ln = np.hypot(D[:, 0], D[:, 1])
    t = D / ln[:, None]
    V = (qb[:, 1] + qb[:, 2]) / ln
    G = qb[:, :1] * t - V[:, None] * np.column_stack([-t[:, 1], t[:, 0]])
    return qb[:, 1:].copy(), G


def largest_moment(model, y, alpha, cuts=None) -> float:
    """Largest |bending moment| [N m] over all rods (cheap when no rod carries a distributed load).
    ``cuts``: ``end_moments(model, y, resultant=True)`` of this state if already computed."""
    if model.elements is None:
        return 0.0
    if cuts is None:
        cuts = end_moments(model, y, resultant=True)
    if model.rods_loaded:
        return max(a["M_max"] for a in rod_arrays(model, y, alpha, cuts).values())
    return float(np.abs(cuts[0]).max()) * model.Fref * model.Lref


def joint_forces(model, y, name, lam=1.0):
    """(Fx, Fy, M) [model units] that b exerts on a at the joint point, springs (and the springs of
    an elastic support) included; ``lam`` the load factor of the state (a preload is ramped)."""
    link = model.joint[name]
    if link.ia is None:   # a is the ground: not allowed by the declaration layer
        raise ValueError(f"joint {name}: part a has no dofs")
    zq = y[link.dofs]
    z = [0.0] * zq.size if model.linear else zq.tolist()   # first order: the reference geometry
    gen = [0.0] * link.k   # the joint's generalised forces mu . G on its dofs (then its equations g)
    if link.size:
        gen = []
        link.assemble(z, model.multipliers(y, link).tolist(), gen, None)
    f = [-gen[i] for i in range(link.ia, link.ia + 3)]
    for spring in (model.spring.get(name), model.supports.get(name)):
        if spring is None:
            continue
        fs, jv, fv = [], ([] if model.linear else None), []
        spring.assemble(z, 0.0 if model.linear else lam, fs, jv, fv)
        if model.linear:   # the spring's force linear in the displacements: H0 z + f0 (preload)
            fs = (np.array(jv).reshape(link.k, link.k) @ zq + lam * np.array(fv)).tolist()
        f = [f[j] - fs[i] for j, i in enumerate(range(link.ia, link.ia + 3))]
    return at_joint_point(link, z, f)


def extract(model, y, alpha, arrays=None, lam=1.0) -> dict:
    """The named results of SPEC section 8 (SI units) of a converged state (at load factor ``lam``)."""
    L, F = model.Lref, model.Fref
    q = y[:model.n_q]
    arrays = rod_arrays(model, y, alpha, lam=lam) if arrays is None else arrays
    rods = {}
    for rod in model.structure.rods:
        a = arrays[rod.name]
        rods[rod.name] = {"M_max": a["M_max"], "N_max": a["N_max"], "V_max": a["V_max"],
                          "start": {"u": float(a["u"][0]), "v": float(a["v"][0]), "theta": float(a["theta"][0])},
                          "end": {"u": float(a["u"][-1]), "v": float(a["v"][-1]), "theta": float(a["theta"][-1])}}
    bodies = {}
    for b in model.structure.bodies:
        d = model.body_dof(b.name)
        if model.linear:   # to first order: the origin's displacement plus theta x (centroid - origin)
            X = model.body_X0[model.body_index[b.name]] * L
            th = float(q[d + 2])
            x = b.centroid[0] + q[d] * L - th * (b.centroid[1] - X[1])
            y_ = b.centroid[1] + q[d + 1] * L + th * (b.centroid[0] - X[0])
        else:
            x, y_ = model.body_point(b.name, q, b.centroid)
        bodies[b.name] = {"x": float(x), "y": float(y_), "rotation": float(q[d + 2])}
    joints, reactions = {}, {}
    for j in model.structure.joints:
        fx, fy, m = joint_forces(model, y, j.name, lam)
        out = {"Fx": fx * F, "Fy": fy * F, "M": m * F * L}
        link = model.joint[j.name]
        free = link.joint_kind.free   # the joint's free coordinate, if its kind reports one
        if free == "slide" and model.linear:   # to first order: the gradient at the reference
            s0, ds, _ = link.slide(np.zeros(link.k))
            out["slide"] = (float(s0) + float(ds @ q[link.dofs]) - model.slide0[j.name]) * L
        elif free == "slide":
            out["slide"] = (float(link.slide(q[link.dofs])[0]) - model.slide0[j.name]) * L
        elif free == "rotation":
            out["rotation"] = float(link.rotation(q[link.dofs])[0])
        joints[j.name] = out
        if j.b == "ground":
            reactions[j.name] = {"Fx": out["Fx"], "Fy": out["Fy"], "M": out["M"]}
    M_all = max((r["M_max"] for r in rods.values()), default=0.0)
    return {"M_max": M_all, "bodies": bodies, "rods": rods, "joints": joints, "reactions": reactions}


# -- flat views for the adaptive refinement ------------------------------------------------------------
KIND_OF = {"M_max": "moment", "M": "moment", "N_max": "force", "V_max": "force", "Fx": "force", "Fy": "force",
           "u": "length", "v": "length", "slide": "length", "x": "length", "y": "length",
           "theta": "angle", "rotation": "angle"}


def flatten(res: dict, structure):
    """(values, kinds) of every named number of a section-8 result in a fixed order; body positions
    enter as displacements (x - x0), so that relative changes measure the motion."""
    vals, kinds = [res["M_max"]], ["moment"]
    for r in structure.rods:
        d = res["rods"][r.name]
        for key in ("M_max", "N_max", "V_max"):
            vals.append(d[key])
            kinds.append(KIND_OF[key])
        for end in ("start", "end"):
            for key in ("u", "v", "theta"):
                vals.append(d[end][key])
                kinds.append(KIND_OF[key])
    for b in structure.bodies:
        d = res["bodies"][b.name]
        vals += [d["x"] - b.centroid[0], d["y"] - b.centroid[1], d["rotation"]]
        kinds += ["length", "length", "angle"]
    for j in structure.joints:
        d = res["joints"][j.name]
        for key in ("Fx", "Fy", "M", "slide", "rotation"):
            if key in d:
                vals.append(d[key])
                kinds.append(KIND_OF[key])
    return np.array(vals, float), kinds


def flatten_names(res: dict, structure) -> list[str]:
    """The dotted names of the values of :func:`flatten`, in its order (``rods.c0.M_max``,
    ``joints.T2.Fy``, ...)."""
    names = ["M_max"]
    for r in structure.rods:
        names += [f"rods.{r.name}.{k}" for k in ("M_max", "N_max", "V_max")]
        names += [f"rods.{r.name}.{end}.{k}" for end in ("start", "end") for k in ("u", "v", "theta")]
    for b in structure.bodies:
        names += [f"bodies.{b.name}.{k}" for k in ("x", "y", "rotation")]
    for j in structure.joints:
        names += [f"joints.{j.name}.{k}" for k in ("Fx", "Fy", "M", "slide", "rotation") if k in res["joints"][j.name]]
    return names


def unflatten(template: dict, vals, structure) -> dict:
    """The inverse of :func:`flatten` on a result of the same structure."""
    it = iter(np.asarray(vals, float).tolist())
    out = {"M_max": next(it), "bodies": {}, "rods": {}, "joints": {}, "reactions": {}}
    for r in structure.rods:
        d = {k: next(it) for k in ("M_max", "N_max", "V_max")}
        for end in ("start", "end"):
            d[end] = {k: next(it) for k in ("u", "v", "theta")}
        out["rods"][r.name] = d
    for b in structure.bodies:
        dx, dy, rot = next(it), next(it), next(it)
        out["bodies"][b.name] = {"x": b.centroid[0] + dx, "y": b.centroid[1] + dy, "rotation": rot}
    for j in structure.joints:
        tj = template["joints"][j.name]
        d = {k: next(it) for k in ("Fx", "Fy", "M", "slide", "rotation") if k in tj}
        out["joints"][j.name] = d
        if j.b == "ground":
            out["reactions"][j.name] = {k: d[k] for k in ("Fx", "Fy", "M")}
    return out
