"""The compiled assembly of a model (the C extension ``femslide.model._assembly``) and its fallback.

:meth:`femslide.model.discrete.Model.system` evaluates every element, joint, spring and load and
writes the residual and the Jacobian (dense, LAPACK band or sparse values) in one call of the
compiled kernel, with index maps built once per model: the static data of the elements (their dofs,
chords, stiffnesses), of the joints of the built-in kinds (pin, weld, slider, roller: their carriers,
guides and equation rows) and of the terms (forces at body points, rotational and slide springs)
are packed here as contiguous arrays.  Constraints and terms the kernel does not know - a joint kind
registered in Python, the holds of displacement control and of the dynamics - are evaluated in Python
(their ``assemble``/``eval``) and handed to the kernel as (index, value) pairs.

The numpy path of ``Model.system`` stays the reference: it is used when the extension is not built
(a machine without a C compiler installing from source; :func:`status` says so, as does ``femslide
--version``), when ``FEMSLIDE_KERNEL=numpy`` is set, or inside :func:`forced`; the tests compare the
two to round-off (tests/test_kernel.py).
"""
from __future__ import annotations

import numpy as np

from femslide.elements.loads import PointForce
from femslide.joints.base import Link, RotationalSpring, SlideSpring
from femslide.joints.pin import Pin
from femslide.joints.roller import Roller
from femslide.joints.slider import Slider
from femslide.joints.weld import Weld
from femslide.model import linalg
from femslide.model.linalg import BandMatrix

_BUILTIN = {Pin: 0, Weld: 1, Slider: 2, Roller: 3}   # the kinds the kernel evaluates, by class (not subclasses)

available = linalg.kernel_available
enabled = linalg.kernel_enabled
forced = linalg.kernel_forced


def status() -> str:
    """One line for ``femslide --version``: which assembly and linear solver run."""
    if not available():
        return f"assembly: numpy and LAPACK (the compiled kernel is not available: {linalg.KERNEL_ERROR})"
    if not enabled():
        return "assembly: numpy and LAPACK (compiled kernel switched off: FEMSLIDE_KERNEL=numpy)"
    return "assembly: compiled kernel (femslide.model._assembly)"


def _kind_code(link) -> int | None:
    """The kernel's code of a link of a built-in kind, None for anything else."""
    if type(link) is not Link or link.keep is not None:
        return None   # (a link holding only some of its kind's equations - an elastic support's - is Python's)
    return _BUILTIN.get(type(link.joint_kind))


class Pack:
    """What a finalized model's kernel needs besides the elements: the joints and terms it evaluates,
    packed as arrays, and the Python-evaluated rest with the positions of their values (residual
    rows, Jacobian pattern positions, d r / d lam rows).  Built by :meth:`Model.finalize`; shared by
    the models of one plan and mesh (the cases of a sweep), which differ only in their elements'
    stiffness."""

    def __init__(self, model, topo, con_dofs, term_dofs, lin_dofs):
        n_q = model.n_q
        ne = model.elements.size if model.elements is not None else 0
        # pattern positions of the blocks: the elements' 36 each, the terms' k x k, the constraints'
        # k x k + 2 m k (femslide.model.discrete._Topology)
        p = 36 * ne
        term_p, con_p = [], []
        for d in term_dofs:
            term_p.append(p)
            p += d.size * d.size
        for c, d in zip(model.constraints, con_dofs):
            con_p.append(p)
            p += d.size * d.size + 2 * c.size * d.size
        self.nnz = p
        lint, ldbl, lrow = [], [], {}
        self.py_terms, self.py_cons = [], []        # evaluators of the Python-evaluated ones
        xr, xj, xf = [], [], []                      # their residual rows, pattern positions, fl rows
        cr, cj = [], []                              # (the constraints' rows and positions, after the terms')
        for c, d, ev, mu, p0 in zip(model.constraints, con_dofs, model._con_evals, topo.con_mu, con_p):
            k, m = d.size, c.size
            row0 = n_q + mu.start
            code = _kind_code(c)
            if code is not None:
                a, b = c.a, c.b
                lrow[id(c)] = len(lint)
                lint.append([code, -1 if a.dof0 is None else a.dof0, -1 if b.dof0 is None else b.dof0,
                             int(c.lever_a), int(c.lever_b), row0, p0, int(c.linear)])
                ldbl.append([*a.X, *a.r, *b.X, *b.r, *c.e0, *c.n0])
            else:
                self.py_cons.append(ev)
                cr += [d, np.arange(row0, row0 + m)]
                cj.append(np.arange(p0, p0 + k * k + 2 * m * k))
        tint, tdbl = [], []
        for t, d, ev, p0 in zip(model.terms, term_dofs, model._term_evals, term_p):
            k = d.size
            link = getattr(t, "link", None)
            if type(t) is PointForce:
                tint.append([0, int(d[0]), p0, 0])
                tdbl.append([t.r[0], t.r[1], t.F[0], t.F[1], t.M])
            elif type(t) is RotationalSpring and id(link) in lrow:
                tint.append([1, lrow[id(link)], p0, 0])
                tdbl.append([t.c, 0.0, 0.0, 0.0, 0.0])
            elif type(t) is SlideSpring and id(link) in lrow:
                tint.append([2, lrow[id(link)], p0, 0])
                tdbl.append([t.k, t.F0, t.s0, 0.0, 0.0])
            else:
                self.py_terms.append(ev)
                xr.append(d)
                xj.append(np.arange(p0, p0 + k * k))
                xf.append(d)
        # (system() evaluates the Python terms first, then the Python constraints)
        xr, xj = xr + cr, xj + cj
        ip = np.intp
        self.lint = np.array(lint, np.int64).reshape(-1, 8)
        self.ldbl = np.array(ldbl, float).reshape(-1, 12)
        self.tint = np.array(tint, np.int64).reshape(-1, 4)
        self.tdbl = np.array(tdbl, float).reshape(-1, 5)
        self.lin_dofs = np.asarray(lin_dofs, np.int64)
        self.lin_vals = np.ascontiguousarray(model._p_sel, float)
        self.load_dofs = np.asarray(topo.load_dofs, np.int64)
        self.xr = np.concatenate([np.zeros(0, ip), *xr]).astype(np.int64)
        self.xj = np.concatenate([np.zeros(0, ip), *xj]).astype(np.int64)
        self.xf = np.concatenate([np.zeros(0, ip), *xf]).astype(np.int64)
        self.python = bool(self.py_terms or self.py_cons)


def _geometry(es):
    """The elements' dofs (n, 6) and the kernel's element data (n, 12) with their geometric columns
    (D0x, D0y, L0, beta0) filled and the others zero, built once per element geometry (kept on the
    geometry's arrays' owner: the models of one mesh share ``conn``; the cases of a sweep over
    stiffnesses)."""
    cached = _GEOMETRY.get(id(es.conn))
    if cached is not None and cached[0] is es.conn:
        return cached[1], cached[2]
    c = es.conn
    edof = np.empty((es.size, 6), np.int64)
    edof[:, 0:3] = 3 * c[:, :1] + np.arange(3)
    edof[:, 3:6] = 3 * c[:, 1:] + np.arange(3)
    geo = np.zeros((es.size, 12))   # the kernel's element data with the geometric columns filled
    geo[:, 0], geo[:, 1], geo[:, 2], geo[:, 3] = es.D0[:, 0], es.D0[:, 1], es.L0, es.beta0
    if len(_GEOMETRY) >= 64:
        _GEOMETRY.clear()
    _GEOMETRY[id(c)] = (c, edof, geo)
    return edof, geo


_GEOMETRY: dict = {}
_KB = np.array([0, 4, 5, 7, 8])     # kb[0, 0], kb[1, 1], kb[1, 2], kb[2, 1], kb[2, 2] of the flat (n, 9)


def assembler(model, pack: Pack):
    """The kernel's Assembler of a model: the shared pack and the model's own elements."""
    es = model.elements
    if es is not None:
        edof, geo = _geometry(es)
        edat = geo.copy()
        edat[:, 4:9] = es.kb.reshape(-1, 9)[:, _KB]
        free = getattr(model, "free_T", None)
        if free is not None:
            edat[:, 9:] = free.T
        xmax = float(es.xmax)
    else:
        edof, edat, xmax = np.zeros((0, 6), np.int64), np.zeros((0, 12)), 1.0
    return linalg._kernel.Assembler(model.n_q, xmax, edof, edat, pack.lint, pack.ldbl, pack.tint,
                                    pack.tdbl, pack.lin_dofs, pack.lin_vals, pack.load_dofs)


def system(model, kern, y, elements, lam, control, jacobian, dense, info, extra=None, n_geometric=None):
    """:meth:`femslide.model.discrete.Model.system` through the kernel ``kern`` (an Assembler of
    :func:`assembler`): (r, A, info) with the same meaning; ``info`` the model's _Info to fill;
    ``extra`` the caller's (rows, values, positions, jvalues), added by the kernel with the
    Python-evaluated pieces; ``n_geometric`` as Model.system's."""
    pack = model._pack
    topo = model._topo
    n_q = model.n_q
    if control is not None:
        lam = float(y[-1])
        info["lam"] = lam
        dof, target = control.dof, control.target
        size = model.n + 1
    else:
        dof, target = -1, 0.0
        size = model.n
    xr = xrv = xj = xjv = xf = xfv = None
    if pack.python:
        z = y[:n_q][topo.jt_dofs].tolist()
        mu = y[n_q:n_q + model.n_c].tolist()
        rv, fv = [], []
        jv = [] if jacobian else None
        for ev, a, b in pack.py_terms:
            ev(z[a:b], lam, rv, jv, fv)
        for ev, a, b, ma, mb in pack.py_cons:
            ev(z[a:b], mu[ma:mb], rv, jv)
        xr, xrv, xf, xfv = pack.xr, np.array(rv, float), pack.xf, np.array(fv, float)
        if jacobian:
            xj, xjv = pack.xj, np.array(jv, float)
    if extra is not None:
        er, erv, ej, ejv = (None if a is None else np.ascontiguousarray(a, np.int64 if i % 2 == 0 else float)
                            for i, a in enumerate(extra))
        if er is not None:
            xr = er if xr is None else np.concatenate([xr, er])
            xrv = erv if xrv is None else np.concatenate([xrv, erv])
        if ej is not None and jacobian:
            xj = ej if xj is None else np.concatenate([xj, ej])
            xjv = ejv if xjv is None else np.concatenate([xjv, ejv])
    ne = elements.committed.size
    alpha = np.empty(ne)
    r = np.empty(size)
    fl = np.empty(n_q)
    A = flat = vals = None
    out = None
    if jacobian:
        rows, cols, size_, band, sparse, pflat = topo.pattern(None if control is None else control.dof)
        if dense == "coo":    # the entries in the pattern's order (femslide.analysis.radau's stages)
            vals = np.empty(rows.size)
        elif dense or (band is None and not sparse):
            flat = topo.dense_flat(None if control is None else control.dof) if pflat is None else pflat
            A = out = np.empty((size, size))
        elif band is not None:
            flat = band.flat
            ab, A = band.empty()
            out = BandMatrix(band, ab)
        else:
            vals = np.empty(rows.size)
    ng = None if n_geometric is None else np.ascontiguousarray(n_geometric, dtype=float)
    fmax, noise = kern.assemble(y, elements.committed, alpha, lam, dof, target, r, A, flat, vals, fl,
                                xr, xrv, xj, xjv, xf, xfv, True, ng)
    if dense == "coo" and vals is not None:
        out = (rows, cols, vals)
    elif vals is not None:
        import scipy.sparse as sp
        out = sp.csc_matrix((vals, (rows, cols)), shape=(size, size))
    elements.trial = alpha
    info["fmax"] = fmax
    info["noise"] = 4.0 * noise if jacobian and ne else 0.0
    info["fl"] = fl
    return r, out, info


def basic(kern, q, alpha_ref):
    """(NM (ne, 3), alpha (ne,), strain energy) through the kernel ``kern``: the elements' basic forces
    (N, M1, M2), chord rotations and strain energy at the frame dofs q (model units; the free forces of
    a thermal load at full load), as :meth:`femslide.model.discrete.Model.element_forces` and
    :func:`femslide.elements.corotational.strain_energy` give them."""
    ne = np.size(alpha_ref)
    NM, alpha = np.empty((3, ne)), np.empty(ne)
    energy = kern.basic(np.ascontiguousarray(q, dtype=float), np.ascontiguousarray(alpha_ref, dtype=float), NM, alpha)
    return NM.T, alpha, energy


def applied(model, kern, y, lam):
    """:meth:`femslide.model.discrete.Model.applied` through the kernel: the residual without the
    elements, over the frame dofs."""
    pack = model._pack
    xr = xrv = None
    if pack.python:
        n_q = model.n_q
        z = y[:n_q][model._topo.jt_dofs].tolist()
        mu = y[n_q:n_q + model.n_c].tolist()
        rv, fv = [], []
        for ev, a, b in pack.py_terms:
            ev(z[a:b], lam, rv, None, fv)
        for ev, a, b, ma, mb in pack.py_cons:
            ev(z[a:b], mu[ma:mb], rv, None)
        xr, xrv = pack.xr, np.array(rv, float)
    r = np.empty(model.n)
    kern.assemble(y, None, None, float(lam), -1, 0.0, r, None, None, None, None, xr, xrv, None, None, None, None, False)
    return r[:model.n_q]
