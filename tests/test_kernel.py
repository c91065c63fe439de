"""The compiled assembly kernel (femslide/model/_assembly.c, femslide/model/fast.py) against its oracle,
the numpy path of Model.system, and the kernel's LU against numpy.linalg.

- residual, Jacobian (dense, LAPACK band, sparse), d r / d lam, the largest element force and the
  round-off estimate of the kernel equal the numpy path's *to the last bit* (the kernel sums in the
  numpy path's order; to 1e-13 of each array's largest value where numpy's arctan2 and hypot are not
  libm's, see ``_numpy_uses_libm``) at random states of structures that use every piece the kernel knows: rod
  elements, the four built-in joint kinds between rod nodes, bodies (with levers on either side) and
  the ground, a guide carried by a turning body, rotational and slide springs with preload, point
  forces off a body's centroid, distributed and nodal dead loads, displacement control, the residual
  alone; and with pieces it hands back to Python (a joint kind registered in Python, the holds of the
  dynamics) mixed in;
- the dense and band LU with partial pivoting (the kernel's factor/solve) against numpy.linalg.solve
  on random and structured systems (relative error <= 1e-12 on well-conditioned ones), a zero pivot is
  LinAlgError, and a band matrix solved twice reuses its factors;
- the switch: FEMSLIDE_KERNEL=numpy (and fast.forced(False)) gives the numpy path, and
  ``fast.status()`` says which runs.

Skipped when the extension is not built (then femslide runs on the numpy path, which the rest of the
suite tests).
"""
from __future__ import annotations

import numpy as np
import pytest

import femslide
from femslide.analysis import static
from femslide.elements import corotational
from femslide.joints.holds import BodyHold, DofHold, SlideHold
from femslide.joints.kind import JointKind
from femslide.joints.kinds import register, unregister
from femslide.model import discrete, fast
from femslide.model.discrete import Model
from femslide.model.linalg import BandMatrix, Banded, solve_linear
from femslide.model.patterns import PatternCache

pytestmark = pytest.mark.skipif(not fast.available(), reason="compiled kernel not built")

RNG = np.random.default_rng(20260311)


def _numpy_uses_libm():
    """Whether numpy's arctan2 and hypot (the chord's angle and length) return the C library's values
    here, as the kernel's atan2 and hypot do (the C library called through ctypes: Python's own
    math.hypot is not the C library's).  Where numpy dispatches them to its own SIMD code (seen with
    numpy 2.4 on a CPU with AVX-512: 1 of 6 arctan2 values differs by an ulp) the numpy path can no
    longer be the kernel's bit-for-bit oracle, and the two are compared to round-off instead
    (``_eq``); so too where the C library cannot be loaded."""
    import ctypes
    import ctypes.util
    try:
        libm = ctypes.CDLL(ctypes.util.find_library("m") or "libm.so.6")
        atan2, hypot = libm.atan2, libm.hypot
    except (OSError, AttributeError, TypeError):
        return False
    for f in (atan2, hypot):
        f.restype, f.argtypes = ctypes.c_double, [ctypes.c_double, ctypes.c_double]
    rng = np.random.default_rng(7)
    x, z = rng.standard_normal((2, 4096)) * 3.0
    return (np.array_equal(np.arctan2(x, z), [atan2(a, b) for a, b in zip(x, z)])
            and np.array_equal(np.hypot(x, z), [hypot(a, b) for a, b in zip(x, z)]))


BITWISE = _numpy_uses_libm()
ULPS = 1e-13   # where not bitwise: the largest difference, relative to the largest |value| of the array


def _eq(a, b):
    """a and b equal bit for bit where numpy's arctan2 and hypot are libm's (BITWISE), else to ULPS
    of the largest |value| (an ulp of a chord angle moves every sum that depends on it by an ulp)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    if BITWISE or a.shape != b.shape:
        return np.array_equal(a, b)
    return bool(np.all(np.abs(a - b) <= ULPS * max(float(np.abs(a).max(initial=0.0)), 1e-300)))


def frame():
    """Every piece the kernel evaluates: two flexible rods, two bodies, each built-in kind, levers on
    both sides of joints, a slider whose guide turns with a body, springs, point forces, loads."""
    s = femslide.Structure(gravity=(0.0, -9.81))
    s.rod("left", (0.0, 0.0), (0.0, 2.0), EI=3e4, EA=3e8, rhoA=2.0, elements=6)
    s.rod("right", (2.0, 0.0), (2.2, 2.0), EI=2e4, EA=2e8, elements=5)
    s.body("deck", mass=40.0, centroid=(1.0, 2.5), outline=[(0, 2), (2, 2), (2, 3), (0, 3)])
    s.body("arm", mass=5.0, centroid=(3.0, 1.0), inertia=0.7, outline=[(2.6, 0.8), (3.4, 0.8), (3.0, 1.4)])
    s.pin("A1", "left.start", "ground", c=500.0)
    s.weld("A", "left.end", "deck", at=(0.0, 2.0))
    s.roller("B1", "right.start", "ground", axis=(1.0, 0.0), k=3e3, preload=20.0)
    s.slider("clamp", "right.end", "deck", axis=(0.1, 1.0), at=(2.2, 2.0), k=800.0, preload=-15.0)
    s.pin("hinge", "arm", "deck", at=(2.5, 1.5), c=50.0)
    s.slider("guide", "arm", "ground", at=(3.0, 0.5), axis=(0.0, 1.0))
    s.force("wind", "deck", force=(300.0, -50.0), at=(0.2, 3.0), moment=40.0)
    s.force("push", "right.end", force=(-30.0, 10.0), moment=5.0)
    s.force("tip", "arm", force=(10.0, 20.0), at=(3.4, 0.8))
    s.distributed("q", "left", force=(25.0, -5.0))
    return s


def _model(structure, counts=None, finalize=True, extra=None):
    fs = structure.freeze()
    L, F = static.scales(fs)
    counts = counts or {r.name: r.elements or 4 for r in fs.rods}
    m = Model(fs, counts, L, F, PatternCache(), finalize=False)
    for c in extra(m) if extra else ():
        m.add_constraint(c)
    return m


def _state(m, scale=0.05):
    y = scale * RNG.standard_normal(m.n)
    y[:m.n_q] *= 0.5
    es = m.zero_state()[1]
    es.committed = 0.05 * RNG.standard_normal(es.committed.size)
    return y, es


def _on_both_paths(m, compute):
    """[compute() with m finalized for the numpy path, compute() with m finalized for the kernel] (each
    asserted to be the path it says)."""
    out = []
    for on in (False, True):
        with fast.forced(on):
            m.finalize()
            assert (m._pack is not None) == on
            out.append(compute())
    return out


def _both(m, y, es, **kw):
    """(numpy path, kernel) outputs of Model.system at the same state."""
    def system():
        e = es.copy()
        r, A, info = m.system(y, e, **kw)
        return r, A, dict(info) if A is None else {k: info[k] for k in ("fmax", "noise", "fl")}, e.trial
    return _on_both_paths(m, system)


def _dense(m, A, control=None):
    if isinstance(A, np.ndarray):
        return A
    if isinstance(A, BandMatrix):
        rows, cols, size, band, _, _ = m._topo.pattern(control)
        out = np.zeros((size, size))
        full = A.ab.T.ravel()
        out[rows, cols] = full[band.flat]
        return out
    return A.toarray()


def _same(m, a, b, control=None):
    (r0, A0, i0, t0), (r1, A1, i1, t1) = a, b
    assert _eq(r0, r1), np.abs(r0 - r1).max()
    assert _eq(t0, t1)
    if A0 is not None:
        assert type(A0) is type(A1)
        assert _eq(_dense(m, A0, control), _dense(m, A1, control))
        for k in ("fmax", "noise"):
            assert _eq(i0[k], i1[k]), (k, i0[k], i1[k])
        assert _eq(i0["fl"], i1["fl"])


@pytest.mark.parametrize("lam", [0.0, 0.37, 1.0])
def test_kernel_equals_the_numpy_path_on_a_frame_of_every_piece(lam):
    """Dense Jacobian (small model), residual alone, the residual without the elements (Model.applied)
    and displacement control: bit for bit."""
    m = _model(frame())
    m.finalize()
    assert not m._pack.python            # everything here is the kernel's
    assert m._pack.lint.shape[0] == 6 and m._pack.tint.shape[0] == 6
    for _ in range(3):
        y, es = _state(m)
        _same(m, *_both(m, y, es, lam=lam, dense=True))
        _same(m, *_both(m, y, es, lam=lam, jacobian=False))
        with fast.forced(False):
            m.finalize()
            g0 = m.applied(y, lam)
        with fast.forced(True):
            m.finalize()
            assert _eq(m.applied(y, lam), g0)   # the residual without the elements
        hold = DofHold(int(m.body_dof("deck")) + 2, 0.03)
        yc = np.concatenate([y, [lam]])
        _same(m, *_both(m, yc, es, control=hold), control=hold.dof)


@pytest.mark.parametrize("lam", [0.0, 0.37, 1.0])
def test_kernel_equals_the_numpy_path_with_thermal_loads(lam):
    """The frame of every piece with thermal loads (uniform dT and a gradient) on both rods: the free
    basic forces in the elements and their share of d r / d lam, bit for bit, also in displacement
    control."""
    s = frame()
    for rod, a in (("left", 1.2e-5), ("right", 1e-5)):
        s.set(f"{rod}.alpha", a)
        s.set(f"{rod}.depth", 0.2)
    s.thermal("heat", "left", dT=30.0, dT_gradient=8.0)
    s.thermal("cool", "right", dT=-20.0, case="winter")
    m = _model(s)
    m.finalize()
    assert m.free_T is not None and np.abs(m.free_T[0]).min() > 0 and np.abs(m.free_T[1]).max() > 0
    for _ in range(2):
        y, es = _state(m)
        _same(m, *_both(m, y, es, lam=lam, dense=True))
        _same(m, *_both(m, y, es, lam=lam, jacobian=False))
        hold = DofHold(int(m.body_dof("deck")) + 2, 0.03)
        yc = np.concatenate([y, [lam]])
        _same(m, *_both(m, yc, es, control=hold), control=hold.dof)


@pytest.mark.parametrize("thermal", [False, True])
def test_basic_forces_and_strain_energy_through_the_kernel(thermal):
    """Model.element_forces (a history's rows) and Model.potential (the energy balance) through the
    kernel's Assembler.basic against the numpy path (corotational.basic_forces, strain_energy): the
    basic forces and chord rotations bit for bit, the potential energy to 1e-14 of the largest of its
    terms (the kernel sums the elements' energies in order, numpy pairwise), on the frame of every piece
    at random states, with thermal loads (free forces: uniform dT and a gradient) and without."""
    s = frame()
    if thermal:
        for rod, a in (("left", 1.2e-5), ("right", 1e-5)):
            s.set(f"{rod}.alpha", a)
            s.set(f"{rod}.depth", 0.2)
        s.thermal("heat", "left", dT=30.0, dT_gradient=8.0)
    m = _model(s)
    m.finalize()
    for _ in range(3):
        y, es = _state(m)
        got = _on_both_paths(m, lambda y=y, es=es: (*m.element_forces(y[:m.n_q], es.committed),
                                                        m.potential(y, es.committed)))
        assert (m.free_T is not None) == thermal
        (NM0, a0, V0), (NM1, a1, V1) = got
        assert NM1.shape == NM0.shape == (es.committed.size, 3)
        assert _eq(NM0, NM1) and _eq(a0, a1)
        E = corotational.strain_energy(m.elements, m.nodal(y[:m.n_q]), es.committed, m.free_T)
        assert abs(E) > 1e-6 and abs(V1 - V0) <= 1e-14 * (abs(E) + abs(V0 - E))


@pytest.mark.parametrize("storage", ["dense", "band"])
def test_axial_forces_given_for_the_geometric_stiffness(storage):
    """Model.system(..., n_geometric=N_g) (a time step's first Newton matrix): the residual and the
    chord rotations are the model's own, and the tangent differs from the model's own by exactly the
    initial-stress matrix of the axial forces N_g - N (corotational.geometric_terms with basic forces
    (N_g - N, 0, 0), which is linear in them) to 1e-12 of the tangent's largest entry; the kernel equals
    the numpy path (as ``_same``: bit for bit where numpy's arctan2 and hypot are libm's)."""
    from femslide.model.linalg import BandMatrix as BM
    m = _model(frame(), None if storage == "dense" else {"left": 60, "right": 50})
    m.finalize()
    y, es = _state(m, 0.01)
    ne = es.committed.size
    NM0, _ = m.element_forces(y[:m.n_q], es.committed)
    Ng = NM0[:, 0] + 50.0 * RNG.standard_normal(ne) * np.abs(NM0[:, 0]).max()
    own = _both(m, y, es, lam=1.0, dense="coo")
    given = _both(m, y, es, lam=1.0, dense="coo", n_geometric=Ng)
    (r0, A0, i0, t0), (r1, A1, i1, t1) = given
    assert _eq(r0, r1) and _eq(t0, t1) and _eq(A0[2], A1[2]) and _eq(i0["noise"], i1["noise"])
    for (r0, A0, _, t0), (r1, A1, _, t1) in zip(own, given):
        assert np.array_equal(r0, r1) and np.array_equal(t0, t1)
        rows, cols, v0 = A0
        v1 = A1[2]
        G = corotational.geometric_terms(m.elements, m.nodal(y[:m.n_q]).reshape(-1), es.committed,
                                         np.stack([Ng - NM0[:, 0], np.zeros(ne), np.zeros(ne)]))
        # (the elements' 36 entries each come first in the pattern: Model.system's order)
        d = v1 - v0
        assert np.abs(d[:36 * ne] - G.ravel()).max() <= 1e-12 * np.abs(v0).max()
        assert not np.any(d[36 * ne:])
        assert np.abs(G).max() > 1e-6 * np.abs(v0).max()   # (the forces given change the tangent)
    # the stored matrix itself (dense, or the LAPACK band): the same change, scattered into it
    for on in (False, True):
        with fast.forced(on):
            m.finalize()
            _, A0, _ = m.system(y, es.copy(), 1.0)
            _, A1, _ = m.system(y, es.copy(), 1.0, n_geometric=Ng)
        assert isinstance(A1, BM) == (storage == "band")
        rows, cols = given[0][1][0], given[0][1][1]
        Gd = np.zeros((m.n, m.n))
        np.add.at(Gd, (rows[:36 * ne], cols[:36 * ne]), G.ravel())
        D0, D1 = _dense(m, A0), _dense(m, A1)
        assert np.abs((D1 - D0) - Gd).max() <= 1e-12 * np.abs(D0).max()


@pytest.mark.parametrize("storage", ["band", "sparse"])
def test_kernel_equals_the_numpy_path_in_band_and_sparse_storage(storage, monkeypatch):
    """A fine mesh (band storage), and the same frame forced into sparse storage."""
    if storage == "band":
        m = _model(frame(), {"left": 60, "right": 50})
    else:
        monkeypatch.setattr(discrete, "DENSE_LIMIT", 0)
        monkeypatch.setattr(discrete, "SPARSE_LIMIT", 0)
        m = _model(frame())
    m.finalize()
    y, es = _state(m, 0.01)
    a, b = _both(m, y, es, lam=0.8)
    kind = {"band": BandMatrix, "sparse": None}[storage]
    if kind is not None:
        assert isinstance(b[1], kind)
    else:
        assert not isinstance(b[1], (np.ndarray, BandMatrix))
    _same(m, a, b)
    hold = DofHold(m.body_dof("deck") + 1, 0.01)
    yc = np.concatenate([y, [0.8]])
    _same(m, *_both(m, yc, es, control=hold), control=hold.dof)


class Tie(JointKind):
    """A joint the kernel does not know (registered in Python): x_a = x_b, 1 equation."""

    name = "kerneltie"
    size = 1
    symbol = "marker"
    code = -1

    def equations(self, link, z):
        wx, wy, dw, d2w, tha, thb = link.w(z)
        row = [0.0] * link.k
        for i, dx, _ in dw:
            row[i] += dx
        hess = [(0, i, i, hx) for i, hx, _ in d2w]
        return [wx], [row], hess


def test_python_pieces_mixed_in_equal_the_numpy_path():
    """A Python-registered kind, a slide hold and a body hold next to the kernel's joints: the kernel
    takes their values from Python (Pack.python) and the sums stay the numpy path's to round-off
    (their order differs)."""
    register(Tie())
    try:
        s = frame()
        s.joint("tie", "kerneltie", "arm", "deck", at=(2.8, 1.9))

        def holds(m):
            return [SlideHold(m.joint["clamp"], 0.01, "lock", origin=m.slide0["clamp"]),
                    BodyHold(m.body_dof("arm"), (0.0, 0.0), ["u", "rot"], (0.6, 0.8))]
        m = _model(s, extra=holds)
        m.finalize()
        with fast.forced(True):
            m.finalize()
            assert m._pack.python and len(m._pack.py_cons) == 3
        for lam in (0.3, 1.0):
            y, es = _state(m)
            (r0, A0, i0, t0), (r1, A1, i1, t1) = _both(m, y, es, lam=lam, dense=True)
            scale = np.abs(r0).max()
            assert np.abs(r1 - r0).max() <= 1e-14 * scale
            assert np.abs(A1 - A0).max() <= 1e-14 * np.abs(A0).max()
            assert np.abs(i1["fl"] - i0["fl"]).max() <= 1e-14 * np.abs(i0["fl"]).max()
            assert _eq(t0, t1)
    finally:
        unregister("kerneltie")


def test_elastic_supports_next_to_python_constraints_equal_the_numpy_path():
    """Elastic supports (Python terms) on links that keep only some of their kind's equations
    (Python constraints): the kernel must place the Python terms' values before the constraints'
    (it crashed when a partial weld was packed as a whole one, and a weld with kr alone read its
    rows swapped: 'rod c ... is free to move')."""
    s = frame()
    s.rod("post", (4.0, 0.0), (4.0, 1.0), EI=1e4, EA=1e8, elements=3)
    s.weld("foot", "post.start", "ground", kr=2e3)
    s.pin("top", "post.end", "ground", kx=5e3)
    s.force("kick", "post.end", force=(0.0, -20.0))
    m = _model(s)
    m.finalize()
    with fast.forced(True):
        m.finalize()
        assert m._pack.python and len(m._pack.py_cons) == 2 and len(m._pack.py_terms) == 2
    for lam in (0.3, 1.0):
        y, es = _state(m)
        (r0, A0, i0, t0), (r1, A1, i1, t1) = _both(m, y, es, lam=lam, dense=True)
        assert np.abs(r1 - r0).max() <= 1e-14 * np.abs(r0).max()
        assert np.abs(A1 - A0).max() <= 1e-14 * np.abs(A0).max()


def test_solutions_through_kernel_and_numpy_agree():
    """The whole statics of the frame (adaptive meshes) through the kernel and the numpy path: every
    named result within 1e-10 of its group's scale (the LU's round-off differs, Newton's tolerance is
    1e-11)."""
    out = []
    for on in (False, True):
        with fast.forced(on):
            out.append(femslide.solve(frame(), elements=8))
    a, b = out
    for group in ("reactions", "joints"):
        for name, vals in a[group].items():
            scale = max(abs(v) for v in vals.values())
            for k, v in vals.items():
                assert abs(b[group][name][k] - v) <= 1e-10 * scale, (group, name, k)
    for name, rod in a["rods"].items():
        assert abs(b["rods"][name]["M_max"] - rod["M_max"]) <= 1e-10 * rod["M_max"]


@pytest.mark.parametrize("n", [1, 2, 7, 36, 120])
def test_dense_lu_against_numpy(n):
    """The kernel's dense LU (partial pivoting) on random systems, and on a saddle-point matrix with a
    zero block (pivoting needed): relative error <= 1e-12 (condition numbers below 1e4 here)."""
    A = RNG.standard_normal((n, n)) + n * np.eye(n)
    b = RNG.standard_normal(n)
    x = solve_linear(A, b)
    assert np.abs(x - np.linalg.solve(A, b)).max() <= 1e-12 * np.abs(x).max()
    if n >= 4:
        k = n // 3
        S = np.zeros((n, n))
        K = RNG.standard_normal((n - k, n - k))
        S[:n - k, :n - k] = K @ K.T + np.eye(n - k)
        G = RNG.standard_normal((k, n - k))
        S[n - k:, :n - k] = G
        S[:n - k, n - k:] = G.T
        x = solve_linear(S, b)
        assert np.abs(S @ x - b).max() <= 1e-11 * np.abs(b).max() * np.linalg.cond(S) ** 0.5


def test_singular_systems_are_linalg_errors():
    A = np.ones((4, 4))
    with pytest.raises(np.linalg.LinAlgError):
        solve_linear(A, np.ones(4))
    # tridiagonal pattern, rows 0 and 1 equal: (1, 1, 0, ...)
    rows, cols = np.nonzero(np.abs(np.subtract.outer(np.arange(6), np.arange(6))) <= 1)
    M = np.ones((6, 6))
    M[1, 2] = 0.0
    band = Banded(rows, cols, 6)
    with pytest.raises(np.linalg.LinAlgError):
        band.assemble(M[rows, cols]).solve(np.ones(6))


@pytest.mark.parametrize("kl, ku, n", [(1, 1, 5), (2, 5, 40), (7, 7, 800), (12, 3, 200)])
def test_band_lu_against_numpy(kl, ku, n):
    """The kernel's band LU (LAPACK's dgbtf2 with partial pivoting) on random band matrices whose
    diagonal does not dominate (rows get swapped), renumbered by Banded: residual at round-off and
    relative error <= 1e-14 x the condition number; a second solve reuses the factors and gives the
    same bits."""
    M = np.zeros((n, n))
    for i in range(n):
        j0, j1 = max(0, i - kl), min(n, i + ku + 1)
        M[i, j0:j1] = RNG.standard_normal(j1 - j0)
    M += 0.5 * np.eye(n)
    rows, cols = np.nonzero(M)
    band = Banded(rows, cols, n)
    B = band.assemble(M[rows, cols])
    b = RNG.standard_normal(n)
    x = B.solve(b)
    ref = np.linalg.solve(M, b)
    assert np.abs(M @ x - b).max() <= 1e-12 * np.abs(M).max() * np.abs(x).max() * n
    assert np.abs(x - ref).max() <= 1e-14 * np.linalg.cond(M) * np.abs(ref).max()
    assert np.array_equal(B.solve(b), x) and B._lu is not None


def test_environment_switch_and_status(monkeypatch):
    """FEMSLIDE_KERNEL=numpy: models finalized then assemble with numpy and solve with LAPACK; the
    status line says which runs."""
    assert fast.status() == "assembly: compiled kernel (femslide.model._assembly)"
    monkeypatch.setenv("FEMSLIDE_KERNEL", "numpy")
    assert not fast.enabled() and "numpy and LAPACK" in fast.status()
    m = _model(frame())
    m.finalize()
    assert m._pack is None
    with fast.forced(True):
        assert fast.enabled()
        m.finalize()
        assert m._pack is not None
    for value, on in (("NumPy", False), ("numpy", False), ("kernel", True), ("", True)):
        monkeypatch.setenv("FEMSLIDE_KERNEL", value)
        assert fast.enabled() is on, value
    monkeypatch.delenv("FEMSLIDE_KERNEL")
    assert fast.enabled()


def _solve_in_a_process(prefix, report):
    """The JSON list ``report`` (an expression over fast, linalg and r) printed by a fresh interpreter that
    runs ``prefix`` and then solves beam-slider at EI = 1e5 into r."""
    import json
    import subprocess
    import sys
    code = (prefix + "\nimport femslide, json\nfrom femslide.model import fast, linalg\n"
            "r = femslide.solve('beam-slider', EI=1e5)\nprint(json.dumps(" + report + "))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout.strip().splitlines()[-1])


def test_without_the_extension_femslide_runs_on_numpy():
    """A process in which the extension cannot be imported (as on a machine that built femslide without a
    compiler) solves on the numpy path, says so, and gets the kernel's answer to round-off."""
    status, M, phi = _solve_in_a_process("import sys; sys.modules['femslide.model._assembly'] = None",
                                         "[fast.status(), r['M_max'], r['phi']]")
    assert status.startswith("assembly: numpy and LAPACK (the compiled kernel is not available")
    r = femslide.solve("beam-slider", EI=1e5)
    assert abs(M / r["M_max"] - 1) <= 1e-11 and abs(phi / r["phi"] - 1) <= 1e-11


def test_a_kernel_built_from_another_source_is_not_used():
    """An extension whose VERSION is not the source's (an editable install not rebuilt after an update
    of _assembly.c: functions missing or doing other arithmetic) is not used: femslide solves on the
    numpy path, the status line says why and how to rebuild, and the answer is the kernel's to
    round-off."""
    from femslide.model import linalg
    assert femslide.model._assembly.VERSION == linalg.KERNEL_VERSION
    status, off, M = _solve_in_a_process("import femslide.model._assembly as a; a.VERSION = a.VERSION - 1",
                                         "[fast.status(), linalg._kernel is None, r['M_max']]")
    assert off and "built from another version" in status and "pip install -e ." in status
    assert abs(M / femslide.solve("beam-slider", EI=1e5)["M_max"] - 1) <= 1e-11


def test_rcm_ordering_equals_the_python_one():
    """The kernel's reverse Cuthill-McKee (Banded's ordering at any size, without scipy) gives the
    permutation of femslide.model.linalg.reverse_cuthill_mckee on random patterns and on a
    cantilever's Jacobian pattern."""
    from femslide.model import _assembly
    from femslide.model.linalg import reverse_cuthill_mckee
    pats = [(RNG.integers(0, 300, 2000), RNG.integers(0, 300, 2000), 300) for _ in range(3)]
    m = _model(frame(), {"left": 40, "right": 30})
    m.finalize()
    pats.append((m._topo.rows, m._topo.cols, m._topo.n))
    for rows, cols, size in pats:
        perm = np.empty(size, np.int64)
        _assembly.rcm(np.asarray(rows, np.int64), np.asarray(cols, np.int64), size, perm)
        assert np.array_equal(perm, reverse_cuthill_mckee(rows, cols, size))


@pytest.mark.parametrize("counts", [None, {"left": 60, "right": 50}])
def test_extra_terms_equal_adding_them_afterwards(counts):
    """Model.system(..., extra=(rows, values, positions, jvalues)) - a caller's terms added in the same
    pass, at Jacobian positions from Model.pattern_positions - equals adding them to the residual and
    the Jacobian afterwards (linalg.add_coo), dense and banded, kernel and numpy path; an
    entry outside the pattern is a ValueError."""
    from femslide.model.linalg import add_coo
    m = _model(frame(), counts)
    m.finalize()
    y, es = _state(m, 0.01)
    rows, cols = m._topo.rows[::7], m._topo.cols[::7]          # entries of the pattern, some repeated
    jv = RNG.standard_normal(rows.size)
    ri = np.arange(0, m.n_q, 3)
    rv = RNG.standard_normal(ri.size)
    for on in (False, True):
        with fast.forced(on):
            m.finalize()
            pos = m.pattern_positions(rows, cols)
            r0, A0, _ = m.system(y, es.copy(), 0.9)
            r0[ri] += rv
            A0 = add_coo(A0, (rows, cols, jv))
            r1, A1, _ = m.system(y, es.copy(), 0.9, extra=(ri, rv, pos, jv))
            assert np.abs(r1 - r0).max() <= 1e-15 * np.abs(r0).max()
            assert np.abs(_dense(m, A1) - _dense(m, A0)).max() <= 1e-15 * np.abs(_dense(m, A0)).max()
    with pytest.raises(ValueError, match="outside the Jacobian's pattern"):
        m.pattern_positions([0], [m.n - 1])


@pytest.mark.parametrize("theory", ["nonlinear", "linear"])
def test_elastic_support_holding_some_equations(theory):
    """A weld to the ground with a rotational spring kr holds two of its three equations: the kernel
    hands it to Python (it used to evaluate all three into the slots of two: a segfault) and the
    Python pieces' values land on their own rows (a Python term and a Python constraint together used
    to swap them).  Kernel against the numpy path (1e-12) and the closed form of the cantilever on a
    rotational spring, tip v = -(P L^3/(3 EI) + P L^2/kr) (1e-9)."""
    L, EI, P, kr = 2.5, 3e5, 4e3, 2e6
    s = femslide.Structure(gravity=(0.0, 0.0))
    s.rod("c", (0.0, 0.0), (L, 0.0), EI=EI, EA=4e9, elements=4)
    s.weld("root", "c.start", "ground", kr=kr)
    s.force("P", "c.end", force=(0.0, -P))
    m = _model(s)
    m.finalize()
    y, es = _state(m, 1e-3)
    (r0, A0, i0, _), (r1, A1, i1, _) = _both(m, y, es, lam=0.7, dense=True)
    assert np.abs(r0 - r1).max() <= 1e-12 * np.abs(r0).max()
    assert np.abs(A0 - A1).max() <= 1e-12 * np.abs(A0).max()
    r = femslide.solve(s, theory=theory)
    v = -(P * L**3 / (3 * EI) + P * L**2 / kr)
    assert abs(r["rods"]["c"]["end"]["v"] - v) <= (1e-9 if theory == "linear" else 1e-3) * abs(v)


@pytest.mark.parametrize("lam", [0.37, 1.0])
def test_rod_cuts_and_interior_moments_equal_the_numpy_path(lam):
    """The elements' end moments and middle forces from the equilibrium of the rod pieces
    (results.static.end_moments) and the largest moment at their interior extrema (_largest_inside):
    the kernel's ``cuts`` and ``inside`` equal the numpy path bit for bit at random states of the frame
    (two rods, each rod's cumulative sums restarted at its first node), with and without chord rotations."""
    from femslide.results import static as rs
    m = _model(frame())
    m.finalize()
    for _ in range(3):
        y, es = _state(m)

        def cuts(y=y, es=es):
            M, G = rs.end_moments(m, y, resultant=True, lam=lam)
            return M, G, rs._largest_inside(m, y, es.committed, (M, G)), rs._largest_inside(m, y, None, (M, G))
        (M0, G0, a0, b0), (M1, G1, a1, b1) = _on_both_paths(m, cuts)
        assert _eq(M0, M1) and _eq(G0, G1)
        assert a0 == a1 and b0 == b1 and a0 > 0.0


@pytest.mark.parametrize("coarse", [{"left": 3, "right": 2}, {"left": 6, "right": 5}])
def test_prolongation_equals_the_numpy_path(coarse):
    """A coarse state interpolated onto the meshes with twice the elements (analysis.refine.prolong:
    Hermite node positions, linear rotations, chord rotations continued): the kernel's ``prolong``
    equals the numpy path bit for bit on the frame's two rods, bodies and multipliers carried over."""
    from femslide.analysis.refine import prolong
    fs = frame().freeze()
    L, F = static.scales(fs)
    cache = PatternCache()
    mc = Model(fs, coarse, L, F, cache)
    mf = Model(fs, {k: 2 * n for k, n in coarse.items()}, L, F, cache)
    for _ in range(3):
        y, es = _state(mc)
        out = []
        for on in (False, True):
            with fast.forced(on):
                mc.finalize()
                mf.finalize()
                assert (mf._pack is not None) == on
                out.append(prolong(mc, y, es, mf))
        (y0, e0), (y1, e1) = out
        assert _eq(y0, y1) and _eq(e0.committed, e1.committed)
        assert np.abs(y1[:3 * mf.n_nodes]).max() > 0.0 and np.abs(e1.committed).max() > 0.0


def test_force_noise_of_a_level_equals_the_numpy_estimate():
    """The refinement's round-off level of the element forces (analysis.refine._force_noise) taken from
    the kernel's assembly equals the numpy estimate (elements.corotational.force_noise) bit for bit."""
    from femslide.analysis import refine
    from femslide.elements import corotational
    m = _model(frame())
    m.finalize()
    assert m._pack is not None
    for _ in range(3):
        y, es = _state(m)
        a = refine._force_noise(refine.Level(1, m, y, es))
        b = 4.0 * float(corotational.force_noise(m.elements, m.nodal(y[:m.n_q]), es.committed).max())
        assert a == b and a > 0.0


@pytest.mark.parametrize("n", [1, 2, 7, 36])
def test_determinant_sign_equals_numpys(n):
    """model.linalg.det_sign (the stability test's sign of det A, by the kernel's dense LU) against
    numpy's slogdet on random matrices with either sign, permuted ones and a singular one."""
    from femslide.model.linalg import det_sign
    seen = set()
    for _ in range(20):
        A = RNG.standard_normal((n, n))
        ref = float(np.linalg.slogdet(A)[0])
        assert det_sign(A) == ref
        seen.add(ref)
        P = A[RNG.permutation(n)]
        assert det_sign(P) == float(np.linalg.slogdet(P)[0])
    assert seen == ({1.0, -1.0} if n > 1 else seen)
    S = RNG.standard_normal((n, n))
    S[:, 0] = 0.0
    assert det_sign(S) == 0.0
    with fast.forced(False):
        assert det_sign(A) == float(np.linalg.slogdet(A)[0])
