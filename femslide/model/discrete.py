"""The discretised model of a frozen structure: meshed rods, frames, joints, loads and assembly.

Every part moves as a frame with three dofs (u, v, theta): the nodes of the rod meshes first, then
the rigid bodies (displacement of the body's origin - its pin to the ground if it has one, else
its centroid - and rotation); the ground has none.  Unknowns are
y = [q, mu] (+ lam in displacement control): q the frame dofs, mu the joint multipliers.  The
equations are the stationarity of the Lagrangian  U_rods(q) + U_springs(q) + lam V_loads(q) +
sum mu_i g_i(q):

    R(q) + lam f(q) + G(q)^T mu = 0,    g(q) = 0,

solved by Newton with the consistent tangent [[K + lam K_V + sum mu_i H_i, G^T], [G, 0]].  In
displacement control one dof is prescribed and lam is the extra unknown.

The model is nondimensional: lengths by ``Lref`` [m], forces by ``Fref`` [N] (moments by Fref Lref),
so that EI/(P a^2) from 1 to 1e12 needs no tuning; :mod:`femslide.results.static` scales back to SI.
"""
from __future__ import annotations

import copy
import math

import numpy as np

from femslide.elements import corotational
from femslide.elements.forms import element_stiffness
from femslide.elements.loads import PointForce, distributed_nodal_loads
from femslide.joints.base import Carrier, ElasticSupport, Link, RotationalSpring, SlideSpring
from femslide.joints.kinds import kind_of
from femslide.model import fast
from femslide.model.frozen import Frozen, support_springs
from femslide.model.linalg import Banded, distinct, to_csc
from femslide.model.state import ElementState
from femslide.model.parts import DEAD, Table
from femslide.model.patterns import PatternCache
from femslide.model.mesh import _Mesh, rod_fractions  # noqa: F401 - rod_fractions: part of this module's interface

DENSE_LIMIT = 100  # unknowns; above it a banded LU is faster when the band is narrow
SPARSE_LIMIT = 600  # unknowns; above it a wide-band system goes to sparse LU


def _tile(d, k):
    """np.tile(d, k) of a 1-d array (one C call instead of numpy's Python-level tile)."""
    return d[None, :].repeat(k, axis=0).ravel()


class _Topology:
    """Dof layout of a finalized model and the scatter patterns of its Jacobian (static; shared by
    models of the same topology through a :class:`PatternCache`)."""

    def __init__(self, model, con_dofs, term_dofs, lin_dofs, free_dofs=None):
        n_q = model.n_q
        sizes = [c.size for c in model.constraints]
        self.c_off = np.concatenate([[0], np.cumsum(sizes)]).astype(int)
        self.n_c = int(self.c_off[-1])
        self.n = n_q + self.n_c
        rows, cols = [], []
        self.ebinT = None
        if model.elements is not None:
            c = model.elements.conn
            ed = np.concatenate([3 * c[:, :1] + np.arange(3), 3 * c[:, 1:] + np.arange(3)], axis=1)
            self.ebinT = ed.T.ravel()  # matches the (6, n_elements) layout of the element forces
            rows.append(np.repeat(ed, 6, axis=1).ravel())
            cols.append(ed[:, None, :].repeat(6, axis=1).ravel())      # (np.tile(ed, (1, 6)))
        for d in term_dofs:
            rows.append(np.repeat(d, d.size))
            cols.append(_tile(d, d.size))
        for i, d in enumerate(con_dofs):
            o, m = n_q + self.c_off[i], sizes[i]
            rows += [np.repeat(d, d.size), np.repeat(np.arange(o, o + m), d.size), _tile(d, m)]
            cols += [_tile(d, d.size), _tile(d, m), np.repeat(np.arange(o, o + m), d.size)]
        self.rows = np.concatenate(rows).astype(np.intp)
        self.cols = np.concatenate(cols).astype(np.intp)
        self.con_mu = [slice(self.c_off[i], self.c_off[i + 1]) for i in range(len(sizes))]
        # loads act on few dofs: d r / d lam is sparse with a static pattern
        # (a thermal load's free forces act through the elements: their dofs too)
        self.load_dofs = distinct(np.concatenate([*term_dofs, lin_dofs, *([] if free_dofs is None else [free_dofs])]
                                                )).astype(np.intp)
        self.patterns = {}
        # the residual is one bincount of the element forces, the loads, the terms' forces and the joints'
        # forces and equations (Model.system), in this order; d r / d lam one of the loads and the terms' parts
        ip = np.intp
        con_rows = [np.arange(n_q + self.c_off[i], n_q + self.c_off[i + 1]) for i in range(len(sizes))]
        parts = [self.ebinT if self.ebinT is not None else np.zeros(0, ip), lin_dofs, *term_dofs]
        for d, g in zip(con_dofs, con_rows):
            parts += [d, g]
        self.rbins = np.concatenate(parts).astype(ip)
        self.rbins_control = np.concatenate([self.rbins, [self.n]]).astype(ip)
        self.rbins_applied = self.rbins[parts[0].size:]
        self.fbins = np.concatenate([lin_dofs, *term_dofs]).astype(ip)
        # the dofs of the terms and joints, gathered in one call (their slices: Model.finalize)
        self.jt_dofs = np.concatenate([np.zeros(0, ip), *term_dofs, *con_dofs]).astype(ip)

    def pattern(self, control):
        key = None if control is None else int(control)
        if key in self.patterns:
            return self.patterns[key]
        if control is None:
            rows, cols, size = self.rows, self.cols, self.n
        else:
            j = self.n
            ld = self.load_dofs
            rows = np.concatenate([self.rows, [j], ld])
            cols = np.concatenate([self.cols, [key], np.full(ld.size, j)])
            size = self.n + 1
        # storage: dense (band None) for small systems, banded when the renumbered band is narrow,
        # else dense up to SPARSE_LIMIT unknowns and sparse above
        band, sparse = None, False
        if size > DENSE_LIMIT:
            band = Banded(rows, cols, size)
            if band.kl + band.ku >= size // 4:
                band, sparse = None, size > SPARSE_LIMIT
        flat = rows * size + cols if band is None and not sparse else None
        self.patterns[key] = (rows, cols, size, band, sparse, flat)
        return self.patterns[key]

    def dense_flat(self, control):
        """Positions in a dense array of the pattern's entries (for ``dense=True`` on a banded or
        sparse pattern), built when first asked for."""
        key = ("dense", None if control is None else int(control))
        if key not in self.patterns:
            rows, cols, size, _, _, _ = self.pattern(control)
            self.patterns[key] = rows * size + cols
        return self.patterns[key]


def _scaled(x, f, L):
    """A stiffness in model units: values times f; a table's arc lengths divided by L."""
    return Table(tuple(v / L for v in x.s), tuple(v * f for v in x.value)) if isinstance(x, Table) else x * f


class _RodPlan:
    __slots__ = ("name", "S", "E", "length", "EI", "EA", "q", "q_end", "loaded", "strain", "curvature", "breaks")


class _JointPlan:
    # kind: a JointKind; motion: a prescribed support motion (dx, dy, rotation) or None
    # lifted: a unilateral contact released by the statics (no equations; its spring along the guide stays)
    __slots__ = ("name", "kind", "ra", "rb", "at", "axis", "k", "preload", "c", "springs", "motion", "lifted")


def _factor_of(factors):
    """The load factor of a case: None (the loads used as declared) without ``factors``, else the
    case's factor (0 for a case not named)."""
    if factors is None:
        return lambda case: None
    return lambda case: float(factors.get(case, 0.0))


def _times(f, x):
    """x times the factor f (None: x itself, untouched)."""
    return x if f is None else f * x


class _Plan:
    """What a frozen structure's models share whatever their meshes, in model units.

    ``factors``: {case: factor} of the load cases (a combination, a step of a load history), None
    for every load at its declared value; a case not named has factor 0.  Gravity and the slider
    springs' preloads are case "dead"."""

    def __init__(self, fs: Frozen, L: float, F: float, factors: dict | None = None):
        rods = fs.rods
        fac = _factor_of(factors)
        dead = fac(DEAD)
        body_w, rod_w = fs.weights()
        if dead is not None:
            body_w = {k: (dead * v[0], dead * v[1]) for k, v in body_w.items()}
            rod_w = {k: (dead * v[0], dead * v[1]) for k, v in rod_w.items()}
        dist = {r.name: np.zeros(2) for r in rods}
        dist_end = {r.name: np.zeros(2) for r in rods}
        therm = {r.name: [0.0, 0.0] for r in rods}   # free strain alpha dT, free curvature [1/m]
        breaks = {r.name: set() for r in rods}
        for ld in fs.loads:
            if ld.type == "force" and ld.s is not None:
                rod = fs.rod(ld.on)
                f = ld.s / rod.length
                if 0.0 < f < 1.0:
                    breaks[ld.on].add(f)
            if ld.type == "distributed":
                f = fac(ld.case)
                q0 = np.asarray(ld.force, float)
                q1 = q0 if ld.force_end is None else np.asarray(ld.force_end, float)
                if ld.frame == "rod":   # components along the rod's reference tangent and normal
                    rod = fs.rod(ld.on)
                    c, s = math.cos(rod.angle), math.sin(rod.angle)
                    q0 = np.array([c * q0[0] - s * q0[1], s * q0[0] + c * q0[1]])
                    q1 = np.array([c * q1[0] - s * q1[1], s * q1[0] + c * q1[1]])
                dist[ld.on] += _times(f, q0)
                dist_end[ld.on] += _times(f, q1)
            elif ld.type == "thermal":
                rod = fs.rod(ld.on)
                f = fac(ld.case)
                f = 1.0 if f is None else f
                therm[ld.on][0] += f * rod.alpha * ld.dT
                if ld.dT_gradient:
                    therm[ld.on][1] -= f * rod.alpha * ld.dT_gradient / rod.depth
        self.rods = []
        self.rod_index = {}
        self.geometry = tuple((r.start, r.end, tuple(sorted(breaks[r.name]))) for r in rods) + (L,)
        for k, rod in enumerate(rods):
            rp = _RodPlan()
            rp.name = rod.name
            rp.S, rp.E = np.asarray(rod.start, float) / L, np.asarray(rod.end, float) / L
            rp.length = rod.length / L
            rp.EI, rp.EA = _scaled(rod.EI, 1.0 / (F * L * L), L), _scaled(rod.EA, 1.0 / F, L)
            rp.q = (dist[rod.name] + np.asarray(rod_w[rod.name])) * (L / F)
            rp.q_end = (dist_end[rod.name] + np.asarray(rod_w[rod.name])) * (L / F)
            rp.loaded = bool(rp.q.any() or rp.q_end.any())
            rp.breaks = tuple(sorted(breaks[rod.name]))
            rp.strain, rp.curvature = therm[rod.name][0], therm[rod.name][1] * L
            self.rods.append(rp)
            self.rod_index[rod.name] = k
        self.body_index = {b.name: i for i, b in enumerate(fs.bodies)}
        self.body_X0 = np.array([body_origin(fs, b) for b in fs.bodies], float).reshape(-1, 2) / L
        bp = np.zeros((len(fs.bodies), 3))
        self.node_loads, self.point_forces = [], []
        for b in fs.bodies:
            Fx, Fy = body_w[b.name]
            i = self.body_index[b.name]
            r = np.asarray(b.centroid, float) / L - self.body_X0[i]
            if np.abs(r).max() <= 1e-14:
                bp[i, :2] -= (Fx / F, Fy / F)
            elif Fx or Fy:
                self.point_forces.append((b.name, (float(r[0]), float(r[1])), (Fx / F, Fy / F), 0.0, "weight"))
        for ld in fs.loads:
            if ld.type != "force":
                continue
            ref, _ = fs.refs[ld.name]
            vec = _times(fac(ld.case), np.array([ld.force[0] / F, ld.force[1] / F, ld.moment / (F * L)]))
            if ref.kind == "rod_end":   # (rod, fraction of its length, load)
                self.node_loads.append((ref.name, 0.0 if ref.end == 0 else 1.0, -vec))
                continue
            if ref.kind == "rod":        # a load inside a rod, at arc length s (a node of every mesh)
                self.node_loads.append((ref.name, ld.s / fs.rod(ref.name).length, -vec))
                continue
            i = self.body_index[ref.name]
            r = np.asarray(ld.at, float) / L - self.body_X0[i]
            if np.abs(r).max() <= 1e-14:
                bp[i] -= vec
            else:
                self.point_forces.append((ref.name, (float(r[0]), float(r[1])), (float(vec[0]), float(vec[1])),
                                          float(vec[2]), ld.name))
        self.body_p = bp.ravel()
        self.joints = []
        for j in fs.joints:
            jp = _JointPlan()
            jp.name, jp.kind, jp.axis = j.name, kind_of(j.type), j.axis
            jp.ra, jp.rb = fs.refs[j.name]
            jp.lifted = bool(j.lifted)
            jp.at = (j.at[0] / L, j.at[1] / L)
            jp.k, jp.preload, jp.c = j.k * L / F, _times(dead, j.preload / F), j.c / (F * L)
            # elastic support springs: (equation index, stiffness in model units: k L / F, kr / (F L))
            jp.springs = tuple((i, k / (F * L) if rot else k * L / F) for i, k, rot in support_springs(j, jp.kind))
            # a prescribed support motion (model units), of case "dead": (dx, dy, rotation) or None
            jp.motion = None
            if j.displacement is not None or j.rotation is not None:
                f = 1.0 if dead is None else dead
                d = j.displacement or (0.0, 0.0)
                jp.motion = (f * d[0] / L, f * d[1] / L, f * (j.rotation or 0.0))
            self.joints.append(jp)
        # everything a model's frames, joints, springs and loads depend on, not the rods' stiffness:
        # models of one key and mesh share them (the cases of a sweep over EI, Model._share)
        self.thermal = any(rp.strain or rp.curvature for rp in self.rods)
        self.key = (L, F, self.geometry, tuple((rp.name, tuple(rp.q.tolist()), tuple(rp.q_end.tolist()), rp.strain,
                                                rp.curvature) for rp in self.rods),
                    tuple(self.body_index), self.body_X0.tobytes(), self.body_p.tobytes(),
                    tuple((r, e, tuple(v.tolist())) for r, e, v in self.node_loads), tuple(self.point_forces),
                    tuple((j.name, j.kind, j.ra, j.rb, j.at, j.axis, j.k, j.preload, j.c, j.springs, j.motion,
                           j.lifted) for j in self.joints))
        self._ids = self._base = None   # (the plan this one was restiffened from: same geometry and key)

    def restiffened(self, fs: Frozen, L: float, F: float) -> "_Plan":
        """This plan for ``fs``, a structure that differs from this plan's only in the rods' EI and EA
        (Frozen.with_stiffness): a copy with the rods' stiffness in model units replaced (the key,
        which leaves the stiffness out, stays)."""
        new = copy.copy(self)
        new._base = self._base or self
        new.rods = []
        for rp, rod in zip(self.rods, fs.rods):
            rq = _RodPlan()
            for k in _RodPlan.__slots__:
                setattr(rq, k, getattr(rp, k))
            rq.EI, rq.EA = _scaled(rod.EI, 1.0 / (F * L * L), L), _scaled(rod.EA, 1.0 / F, L)
            new.rods.append(rq)
        return new

    def ids(self, cache: PatternCache) -> tuple:
        """(geometry, key) as ``cache``'s small integers (PatternCache.key_id), computed once per cache."""
        held = self._ids
        if held is None or held[0] is not cache:
            ids = self._base.ids(cache) if self._base is not None else \
                (cache.key_id(("geometry", self.geometry)), cache.key_id(("plan", self.key)))
            held = self._ids = (cache, *ids)
        return held[1], held[2]


def body_origin(fs: Frozen, body) -> tuple:
    """Reference point [m] of a body's frame: the point of its first pivot to the ground (a pin: the
    body then turns about its frame origin and that joint is a linear constraint), else its centroid."""
    for j in fs.joints:
        ra, rb = fs.refs[j.name]
        if rb.kind == "ground" and ra.kind == "body" and ra.name == body.name and kind_of(j.type).pivot:
            return tuple(j.at)
    return tuple(body.centroid)


def _plan(fs: Frozen, L: float, F: float, factors: dict | None = None) -> _Plan:
    """The structure's plan for these model units and load-case factors (kept on the frozen
    structure)."""
    key = ("plan", L, F) if factors is None else ("plan", L, F, tuple(sorted(factors.items())))
    plan = fs.derived.get(key)
    if plan is None:
        parent = fs.derived.get("stiffness_of")   # (Frozen.with_stiffness: the same but for the rods' stiffness)
        plan = fs.derived[key] = _plan(parent, L, F, factors).restiffened(fs, L, F) if parent is not None \
            else _Plan(fs, L, F, factors)
    return plan


class Model:
    """A frozen structure meshed with ``elements[rod]`` elements per rod, in model units.

    Built complete (joints, springs, loads) and finalized; callers that add constraints or terms
    of their own (the dynamics) pass ``finalize=False`` and call :meth:`finalize` themselves.

    ``factors``: {load case: factor} (a combination, a step of a load history; a case not named has
    factor 0), or None: every load as declared.  The load factor ``lam`` of :meth:`system` scales
    the loads so combined.  (A load history that ramps from one set of factors f0 to the next f1
    builds the model of the difference f1 - f0 and holds the loads of f0 with a constant term, or
    builds the model of f0 + lam (f1 - f0) for each lam: the cases' loads are linear in the factors.)
    """

    linear = False   # geometrically exact (corotational); femslide.model.linear.LinearModel: first order
    theory = "nonlinear"

    def __init__(self, structure: Frozen, elements: dict, Lref: float, Fref: float,
                 cache: PatternCache | None = None, finalize: bool = True, factors: dict | None = None):
        self.structure, self.Lref, self.Fref = structure, Lref, Fref
        self.cache = cache or PatternCache()
        self.factors = factors
        plan = _plan(structure, Lref, Fref, factors)
        self.rod_index = plan.rod_index
        counts = tuple(int(elements[rp.name]) for rp in plan.rods)
        gid, kid = plan.ids(self.cache)
        mesh = self.cache.mesh((gid, counts), lambda: _Mesh(plan, counts))
        counts = mesh.counts if plan.rods else counts   # a rod with loads inside: its pieces' elements
        self.X0, self.rod_nodes, self.n_nodes = mesh.X0, mesh.rod_nodes, mesh.n_nodes
        self.node_first = mesh.node_first
        self.mesh = mesh
        off = mesh.n_nodes
        if mesh.conn is not None:
            kbs = [element_stiffness(mesh.L0[e], mesh.s0[e], rp.EI, rp.EA)
                   for rp, e in zip(plan.rods, mesh.rod_elements)]
            self.elements = mesh.element_set().with_stiffness(kbs[0] if len(kbs) == 1 else np.concatenate(kbs))
            self.elem_rod = mesh.elem_rod
        else:
            self.elements = None
            self.elem_rod = np.zeros(0, np.intp)
        # a thermal load: the elements' free basic forces at full load (femslide.elements.corotational
        # .free_forces), ramped with the load factor like every load
        self.free_T = None
        if plan.thermal and self.elements is not None:
            counts_a = np.array(counts)
            strain = np.repeat([rp.strain for rp in plan.rods], counts_a)
            curv = np.repeat([rp.curvature for rp in plan.rods], counts_a)
            self.free_T = corotational.free_forces(self.elements, strain, curv)
        if finalize:
            shared = self.cache.frames((kid, counts))
            if shared is not None:
                self._share(shared)
                return
        self.rods_loaded = any(rp.loaded for rp in plan.rods)   # a distributed load on some rod
        # distributed loads linear in s: their values at each element's start and end (model units) and
        # the mean (elem_q)
        self.elem_q1, self.elem_q2 = np.zeros((0, 2)), np.zeros((0, 2))
        if mesh.conn is not None:
            q1, q2 = [], []
            for rp, t in zip(plan.rods, mesh.rod_t):
                qn = rp.q[None, :] + t[:, None] * (rp.q_end - rp.q)[None, :]
                q1.append(qn[:-1])
                q2.append(qn[1:])
            self.elem_q1, self.elem_q2 = np.concatenate(q1), np.concatenate(q2)
        self.elem_q = 0.5 * (self.elem_q1 + self.elem_q2) if mesh.conn is not None else np.zeros((0, 2))
        p_lin = [-distributed_nodal_loads(self.X0[nodes], rp.q, rp.q_end if rp.q_end is not None else None)
                 if rp.loaded else None for rp, nodes in zip(plan.rods, self.rod_nodes)]
        # bodies: frames after the nodes, at their origins (a ground pin, else the centroid)
        self.body_index = plan.body_index
        self.body_X0 = plan.body_X0
        nb3 = 3 * off
        self.n_q = nb3 + plan.body_p.size
        p = np.zeros(self.n_q)
        for pl, nodes in zip(p_lin, self.rod_nodes):
            if pl is not None:
                p[3 * nodes[0]:3 * nodes[-1] + 3] = pl.ravel()
        p[nb3:] = plan.body_p
        for rod, frac, vec in plan.node_loads:
            k = self.rod_index[rod]
            t = mesh.rod_t[k]
            i = int(np.searchsorted(t, frac))
            if i >= t.size or t[i] != frac:   # not a node: the plan's breaks and the mesh disagree
                raise AssertionError(f"load at s/L = {frac} on rod {rod} is not at a node")
            d = 3 * int(self.rod_nodes[k][i])
            p[d:d + 3] += vec
        self.p_lin = p
        self.constraints, self.terms = [], []
        self.joint, self.spring, self.slide0, self.supports = {}, {}, {}, {}
        self.motion = []    # (link, offsets of its equations at full load): prescribed support motion
        for jp in plan.joints:
            # an elastic support holds only the equations its springs do not replace
            keep = [i for i in range(jp.kind.size) if i not in dict(jp.springs)] if jp.springs else None
            if jp.lifted:   # a contact the statics released: no equations (its multipliers read 0)
                keep = []
            link = Link(jp.name, jp.kind, self._carrier(jp.ra, jp.at), self._carrier(jp.rb, jp.at), jp.axis, keep)
            self.joint[jp.name] = link
            if link.size:
                self.add_constraint(link)
            if jp.motion is not None:
                self.motion.append((link, _motion_offsets(link, jp, self._carrier)))
            if jp.springs:
                self.supports[jp.name] = self.add_term(ElasticSupport(link, jp.springs, jp.name))
            if jp.kind.free == "slide":
                # reference slide: a's point (a rod end may sit anywhere on the line) past ``at``
                pa = (link.a.X[0] + link.a.r[0] - jp.at[0], link.a.X[1] + link.a.r[1] - jp.at[1])
                self.slide0[jp.name] = s0 = pa[0] * jp.axis[0] + pa[1] * jp.axis[1]
                if jp.k or jp.preload:
                    self.spring[jp.name] = self.add_term(SlideSpring(link, jp.k, jp.preload, s0, jp.name))
            elif jp.c:   # a kind with a free rotation (Frozen checks that it takes c)
                self.spring[jp.name] = self.add_term(RotationalSpring(link, jp.c, jp.name))
        for body, r, Fv, M, name in plan.point_forces:
            d = self.body_dof(body)
            self.add_term(PointForce(np.arange(d, d + 3), r, Fv, M, name))
        if finalize:
            self.finalize()
            self.cache.frames((kid, counts), self)

    _kern = None   # the compiled assembler of this model (femslide.model.fast), made at its first evaluation
    _pack = None

    _OWN = frozenset(("structure", "Lref", "Fref", "cache", "factors", "rod_index", "X0", "rod_nodes", "n_nodes",
                      "node_first", "mesh", "elements", "elem_rod", "last_tangent", "_kern", "free_T"))

    def _share(self, other: "Model"):
        """Take the frames, joints, terms, loads and dof layout of a finalized model of the same
        plan key and mesh (they do not depend on the rods' stiffness): the joints, terms and
        (read-only) arrays are shared, the lists and dicts copied."""
        d, own = self.__dict__, self._OWN
        # (by exact type: every container of a model is a plain list or dict; a subclass would be shared)
        for k, v in other.__dict__.items():
            if k not in own:
                t = type(v)
                d[k] = v.copy() if t is list or t is dict else v

    # -- layout -----------------------------------------------------------------------------------
    def node(self, rod: str, i: int) -> int:
        """Model index of node i (negative counts from the end) of the named rod."""
        return int(self.rod_nodes[self.rod_index[rod]][i])

    def node_at(self, rod: str, s: float) -> int:
        """Model index of the node of the named rod at the arc length s [m] (a rod end or the point of
        a load inside the rod: every mesh has a node there); ValueError if no node is there."""
        k = self.rod_index[rod]
        t = self.mesh.rod_t[k]
        frac = s / self.structure.rod(rod).length
        i = int(np.searchsorted(t, frac))
        for j in (i - 1, i):
            if 0 <= j < t.size and abs(t[j] - frac) <= 1e-12:
                return int(self.rod_nodes[k][j])
        raise ValueError(f"rod {rod} has no node at s = {s} m")

    def body_dof(self, body: str) -> int:
        """First dof (u) of the named body's frame."""
        return 3 * (self.n_nodes + self.body_index[body])

    def _carrier(self, ref, at):
        if ref.kind == "ground":
            return Carrier(None, (0.0, 0.0), at)
        if ref.kind == "rod_end":   # the joint point on a rod end is the end node itself
            nd = self.node(ref.name, ref.end)
            X = self.X0[nd]
            return Carrier(3 * nd, (float(X[0]), float(X[1])), (0.0, 0.0))
        X = self.body_X0[self.body_index[ref.name]]
        return Carrier(self.body_dof(ref.name), (float(X[0]), float(X[1])),
                       (at[0] - float(X[0]), at[1] - float(X[1])))

    def body_point(self, name: str, q, p):
        """Current position [m] of the body point whose reference position is p [m]."""
        d = self.body_dof(name)
        X = self.body_X0[self.body_index[name]] * self.Lref
        u, v, th = q[d] * self.Lref, q[d + 1] * self.Lref, q[d + 2]
        c, s = np.cos(th), np.sin(th)
        r = np.asarray(p, float) - X
        return np.column_stack([X[0] + u + c * r[..., 0] - s * r[..., 1], X[1] + v + s * r[..., 0] + c * r[..., 1]]) \
            if r.ndim == 2 else np.array([X[0] + u + c * r[0] - s * r[1], X[1] + v + s * r[0] + c * r[1]])

    def add_constraint(self, c):
        self.constraints.append(c)
        return c

    def add_term(self, t):
        self.terms.append(t)
        return t

    def finalize(self):
        """Fix the dof layout and the scatter pattern of the Jacobian."""
        con_dofs = [c.dofs for c in self.constraints]
        term_dofs = [t.dofs for t in self.terms]
        lin_dofs = np.nonzero(self.p_lin)[0].astype(np.intp)
        key = (self.n_q, self.elements.conn.tobytes() if self.elements is not None else b"",
               tuple((c.size, d.tobytes()) for c, d in zip(self.constraints, con_dofs)),
               tuple(d.tobytes() for d in term_dofs), lin_dofs.tobytes(), self.free_T is not None)
        free_dofs = None
        if self.free_T is not None:
            c = self.elements.conn
            free_dofs = (3 * c[:, :, None] + np.arange(3)).ravel()
        topo = self.cache.topology(key, lambda: _Topology(self, con_dofs, term_dofs, lin_dofs, free_dofs))
        self._topo = topo
        self.c_off, self.n_c, self.n = topo.c_off, topo.n_c, topo.n
        self._load_dofs, self._term_dofs = topo.load_dofs, term_dofs
        self._p_sel = self.p_lin[lin_dofs]
        # (assemble, slice of the gathered dofs[, slice of the multipliers]) per term and joint
        o = 0
        self._term_evals, self._con_evals = [], []
        for t, d in zip(self.terms, term_dofs):
            self._term_evals.append((getattr(t, "assemble", None) or _term_assembler(t), o, o + d.size))
            o += d.size
        for c, d, ci in zip(self.constraints, con_dofs, topo.con_mu):
            self._con_evals.append((getattr(c, "assemble", None) or _constraint_assembler(c), o, o + d.size,
                                    ci.start, ci.stop))
            o += d.size
        rot = np.arange(2, self.n_q, 3)
        self._rot = rot.astype(np.intp)
        # the compiled assembly (femslide.model.fast): its index maps and joint data now, the elements'
        # part with the first evaluation (models sharing these differ in their stiffness)
        self._pack = fast.Pack(self, topo, con_dofs, term_dofs, lin_dofs) if fast.enabled() else None
        # prescribed support motion: lam times these values added to the joints' equations' rows
        rows, vals = [], []
        for link, off in getattr(self, "motion", ()):
            i = self.constraints.index(link)
            rows += range(self.n_q + self.c_off[i], self.n_q + self.c_off[i] + link.size)
            vals += off
        self._motion_rows, self._motion_vals = np.array(rows, np.intp), np.array(vals, float)
        self._kern = None
        return self

    def _pattern(self, control):
        return self._topo.pattern(control)

    def to_csc(self, A, control=None):
        """A Jacobian of :meth:`system` as a scipy CSC matrix (``control``: its DofHold, or None)."""
        return to_csc(A, *self._pattern(None if control is None else control.dof)[:2])

    def rotation_dofs(self):
        """Indices of the rotational dofs (node and body rotations) among the unknowns."""
        return self._rot

    def pattern_positions(self, rows, cols, control=None):
        """Positions in the Jacobian's pattern (the order of :meth:`system`'s values) of the entries
        (rows, cols): where ``system(..., extra=...)`` adds a caller's Jacobian values (a time step's
        mass and damping matrices, whose entries lie in the pattern).  ValueError for an entry outside
        the pattern.  ``control``: the controlled dof of the pattern, or None."""
        prow, pcol, size, _, _, _ = self._pattern(control)
        keys = prow.astype(np.int64) * size + pcol
        order = np.argsort(keys, kind="stable")
        want = np.asarray(rows, np.int64) * size + np.asarray(cols, np.int64)
        at = np.searchsorted(keys[order], want)
        bad = (at >= keys.size) | (keys[order][np.minimum(at, keys.size - 1)] != want)
        if bad.any():
            i = int(np.nonzero(bad)[0][0])
            raise ValueError(f"entry ({int(np.asarray(rows)[i])}, {int(np.asarray(cols)[i])}) is outside the "
                             f"Jacobian's pattern")
        return order[at].astype(np.intp)

    def multipliers(self, y, link):
        if link.size == 0:   # an elastic support with every constraint turned into a spring
            return y[:0]
        i = self.constraints.index(link)
        return y[self.n_q + self.c_off[i]:self.n_q + self.c_off[i + 1]]

    def zero_state(self):
        """The undeformed state: y = 0 and the elements' undeformed history."""
        ne = self.elements.size if self.elements is not None else 0
        return np.zeros(self.n), ElementState.zero(ne)

    # -- evaluation ---------------------------------------------------------------------------------
    def nodal(self, q):
        return q[: 3 * self.n_nodes].reshape(-1, 3)

    def _assembler(self):
        """The compiled kernel's Assembler of this model (built at the first call; a model with ``_pack``)."""
        if self._kern is None:
            self._kern = fast.assembler(self, self._pack)
        return self._kern

    def element_forces(self, q, alpha_ref):
        """Basic forces (N, M1, M2) of every element and the chord rotations alpha."""
        if self.elements is None:
            return np.zeros((0, 3)), np.zeros(0)
        if self._pack is not None:   # (the same arithmetic in C)
            return fast.basic(self._assembler(), q, alpha_ref)[:2]
        NM, alpha = corotational.basic_forces(self.elements, self.nodal(q).reshape(-1), alpha_ref, self.free_T)
        return NM.T, alpha

    def potential(self, y, alpha_ref, skip=None):
        """Potential energy at y (model units): the rods' strain energy, the springs' energy and the
        dead loads' potential (gravity included); the term ``skip`` (an extra term of a caller)
        left out."""
        q = y[:self.n_q]
        if self.elements is None:
            V = 0.0
        elif self._pack is not None:   # (the kernel's sum in element order)
            V = fast.basic(self._assembler(), q, alpha_ref)[2]
        else:
            V = corotational.strain_energy(self.elements, self.nodal(q), alpha_ref, self.free_T)
        V += float(np.dot(self.p_lin, q))
        for t, d in zip(self.terms, self._term_dofs):
            if t is not skip:   # (a term's energy alone, where it has it: its eval forms the Hessian too)
                V += float(t.energy(q[d], 1.0) if hasattr(t, "energy") else t.eval(q[d], 1.0)[0])
        return V

    def applied(self, y, lam=1.0):
        """The generalised forces on the frames from everything but the rod elements - loads (times
        ``lam``), springs and joint multipliers - in the residual's sign (minus the force on the
        frame), model units.  At equilibrium the elements' internal forces balance them; results
        recover cut forces and moments along rods from them (exact to the residual)."""
        if self._pack is not None:
            return fast.applied(self, self._assembler(), y, lam)
        rv, _ = self._joint_terms(y, lam, None)
        # the residual's bincount without the elements (the joints' equations land beyond n_q)
        return np.bincount(self._topo.rbins_applied, weights=np.concatenate([lam * self._p_sel, rv]),
                           minlength=self.n)[:self.n_q]

    def _joint_terms(self, y, lam, jv):
        """The terms' (springs, point loads) and joints' shares of the equations at y, as Python
        floats in the residual's order: (rv, fv) - their residual entries and the terms' d force /
        d lam - with their Jacobian entries appended to ``jv`` unless it is None."""
        n_q = self.n_q
        z = y[:n_q][self._topo.jt_dofs].tolist()
        mu = y[n_q:n_q + self.n_c].tolist()
        rv, fv = [], []
        for ev, a, b in self._term_evals:
            ev(z[a:b], lam, rv, jv, fv)
        for ev, a, b, ma, mb in self._con_evals:
            ev(z[a:b], mu[ma:mb], rv, jv)
        return rv, fv

    def system(self, y, elements, lam=1.0, control=None, jacobian=True, dense=False, extra=None, n_geometric=None):
        """Residual and Jacobian of the equations at y.

        ``elements``: the elements' history (femslide.model.state.ElementState): the chord rotations
        are continued from its committed ones, and the rotations at y become its trial ones.

        ``control``: None (load ``lam`` given) or a femslide.joints.holds.DofHold: its dof is held at
        its target and lam is the last unknown y[-1] (displacement control).  Returns (r, A, info)
        with A dense, banded or sparse CSC (:func:`solve_linear` solves any of them; ``dense=True``
        asks for a dense array whatever the size; ``dense="coo"`` for its entries (rows, cols,
        values) in the pattern's order, duplicates to be summed), or None with ``jacobian=False``
        (then info["noise"] is not estimated either).

        ``extra``: terms of the caller added in the same pass, ``(rows, values, positions, jvalues)``:
        ``values`` added to the residual entries ``rows`` and ``jvalues`` to the Jacobian entries at
        ``positions`` of its pattern (:meth:`pattern_positions`; a time step's inertia and damping);
        None entries for parts not given.  ``n_geometric``: the elements' axial forces in the tangent's
        geometric part, or None (their own; corotational.element_terms).

        With the compiled kernel (femslide.model.fast) one call evaluates everything and writes the
        residual and the Jacobian in place.  The numpy path (the kernel's oracle): one evaluation of
        all elements (:func:`femslide.elements.corotational.element_terms`), the terms and joints in
        Python floats (few numbers each, where numpy's per-call cost would dominate), one bincount
        for the residual and one for a dense Jacobian.
        """
        if self._pack is not None:
            out = fast.system(self, self._assembler(), y, elements, lam, control, jacobian, dense, _Info(lam=lam),
                              extra, n_geometric)
            if self._motion_rows.size:
                out[0][self._motion_rows] += out[2]["lam"] * self._motion_vals
            return out
        n_q, topo = self.n_q, self._topo
        q = y[:n_q]
        if control is not None:
            lam = y[-1]
        size = self.n + (1 if control is not None else 0)
        jv = [] if jacobian else None
        rv, fv = self._joint_terms(y, lam, jv)
        fmax = 0.0
        alpha_ref = elements.committed
        alpha = alpha_ref
        parts = []
        info = _Info(lam=lam)
        if self.elements is not None:
            free = None if self.free_T is None else lam * self.free_T
            F, K, _, alpha, noise = corotational.element_terms(self.elements, q, alpha_ref, jacobian, free, n_geometric)
            parts.append(F.ravel())
            fmax = float(np.abs(F).max())
            if jacobian:
                info.later("noise", lambda: 4.0 * float(noise().max()))
        if self._p_sel.size:
            parts.append(lam * self._p_sel)
        qc = q.copy() if self.free_T is not None else None

        def fl():
            out = np.bincount(topo.fbins, weights=np.concatenate([self._p_sel, fv]), minlength=n_q) \
                if topo.fbins.size else np.zeros(n_q)
            if self.free_T is not None:   # d (element forces) / d lam = -B^T S_T
                fT = corotational.free_nodal(self.elements, qc, alpha_ref, self.free_T)
                out -= np.bincount(topo.ebinT, fT.ravel(), minlength=n_q)
            return out
        info.later("fl", fl)
        if control is not None:
            dof, value = control.dof, control.target
            rv.append(float(q[dof]) - value)
        parts.append(rv)
        r = np.bincount(topo.rbins if control is None else topo.rbins_control, weights=np.concatenate(parts),
                        minlength=size)
        if extra is not None and extra[0] is not None:
            np.add.at(r, extra[0], extra[1])
        if self._motion_rows.size:
            r[self._motion_rows] += lam * self._motion_vals
        info["fmax"] = fmax
        elements.trial = alpha
        if not jacobian or self.elements is None:
            info["noise"] = 0.0
        if not jacobian:
            return r, None, info
        if control is not None:
            jv.append(1.0)
            jv += info["fl"][self._load_dofs].tolist()
        rows, cols, size, band, sparse, flat = self._pattern(None if control is None else control.dof)
        vals = np.concatenate([K.ravel(), jv]) if self.elements is not None else np.array(jv)
        if extra is not None and extra[2] is not None:
            np.add.at(vals, extra[2], extra[3])
        if dense == "coo":   # the entries themselves, in the pattern's order (duplicates to be summed)
            return r, (rows, cols, vals), info
        if band is not None and not dense:
            A = band.assemble(vals)
        elif sparse and not dense:
            import scipy.sparse as sp
            A = sp.csc_matrix((vals, (rows, cols)), shape=(size, size))
        else:
            flat = rows * size + cols if flat is None else flat
            A = np.bincount(flat, weights=vals, minlength=size * size).reshape(size, size)
        return r, A, info


def _motion_offsets(link, jp, carrier):
    """The change of a ground joint's equations g at the reference state when its ground point moves
    by (dx, dy) and its held rotation by r (jp.motion, model units): g is linear in the ground point
    (every kind's equations with a fixed b), so this is the exact offset of g per unit load factor."""
    dx, dy, rot = jp.motion
    z0 = [0.0] * link.k
    g0 = link._parts(z0)[0]
    b = link.b
    moved = Link(link.name, link.joint_kind, link.a, Carrier(None, (b.X[0] + dx, b.X[1] + dy), b.r), jp.axis)
    off = [x1 - x0 for x0, x1 in zip(g0, moved._parts(z0)[0])]
    if rot:
        off[link.joint_kind.springs["kr"]] -= rot
    return off


class _Info(dict):
    """The info of :meth:`Model.system`: "fmax" (largest element force), "noise" (round-off level of
    the element forces, with the Jacobian), "fl" (d r / d lam over the frame dofs), "lam";
    "noise" and "fl" are computed when first read (from copies of the evaluated state)."""

    def later(self, key, compute):
        self.__dict__[key] = compute

    def __missing__(self, key):
        compute = self.__dict__.pop(key, None)
        if compute is None:
            raise KeyError(key)
        self[key] = value = compute()
        return value


def _term_assembler(t):
    """The assembly function (see femslide.elements.loads.PointForce.assemble) of a term that has only
    ``eval(z, lam) -> (energy, force, Hessian, d force / d lam)``."""
    def assemble(z, lam, rv, jv, fv):
        _, g, H, g0 = t.eval(np.array(z), lam)
        rv += g.tolist()
        if jv is not None:
            jv += np.ravel(H).tolist()
        fv += g0.tolist()
    return assemble


def _constraint_assembler(c):
    """The assembly function (see femslide.joints.base.Link.assemble) of a constraint that has only
    ``eval(z, mu) -> (g, G, sum_i mu_i H_i)``."""
    def assemble(z, mu, rv, jv):
        mu = np.array(mu)
        g, G, Hmu = c.eval(np.array(z), mu)
        rv += (mu @ G).tolist()
        rv += np.ravel(g).tolist()
        if jv is not None:
            Gl = np.ravel(G).tolist()
            jv += np.ravel(Hmu).tolist()
            jv += Gl
            jv += Gl
    return assemble
