"""Unit tests of the model's numerical building blocks added for round-off and start-up: the bending
moments recovered from the equilibrium of the rod piece, the numpy reverse Cuthill-McKee ordering and
the banded solver loaded without scipy.linalg."""
from __future__ import annotations

import subprocess
import sys
import warnings

import numpy as np
import pytest

import femslide
from femslide.model.linalg import reverse_cuthill_mckee
from femslide.model.structure import Structure
from femslide.results.static import end_moments


def _portal():
    """Portal frame: a spring pin, a reversed rod, a distributed load, a point moment, a slider."""
    s = Structure(gravity=(0.0, -9.81))
    s.rod("left", (0, 0), (0, 3), EI=2e6, rhoA=10.0)
    s.rod("beam", (4, 3), (0, 3), EI=5e6, elements=8)          # declared right to left
    s.rod("right", (4, 0), (4, 3), EI=2e6)
    s.pin("A", "left.start", "ground", c=1e5)
    s.pin("B", "right.start", "ground")
    s.weld("C", "left.end", "beam.end")
    s.slider("D", "right.end", "beam.start", axis=(0, 1))
    s.distributed("snow", "beam", force=(0.0, -2000.0))
    s.force("push", "left.end", force=(500.0, 0.0), moment=300.0)
    return s


@pytest.mark.parametrize("make", [_portal])
def test_equilibrium_moments_equal_the_elements_own_at_equilibrium(make):
    """At a converged state the moments from the rod piece's equilibrium equal the elements' own end
    moments (EI times the deformation) to the Newton residual (1e-8 of the largest moment)."""
    r = femslide.solve(make())
    sol = r.solution
    m, y, alpha = sol.model, sol.level.y, sol.level.alpha
    qb, _ = m.element_forces(y[:m.n_q], alpha)
    eq = end_moments(m, y)
    assert np.allclose(eq, qb[:, 1:], rtol=0, atol=1e-8 * np.abs(qb[:, 1:]).max())
    # and the cut force at the element middles against the elements' axial force along the chord
    # (1e-6: the elements' N = EA times a stretch carries round-off ~ eps EA |u|, the reason for the
    # equilibrium recovery)
    _, G = end_moments(m, y, resultant=True)
    X = m.X0 + m.nodal(y[:m.n_q])[:, :2]
    D = X[m.elements.conn[:, 1]] - X[m.elements.conn[:, 0]]
    t = D / np.hypot(D[:, 0], D[:, 1])[:, None]
    assert np.allclose((G * t).sum(axis=1), qb[:, 0], rtol=0, atol=1e-6 * np.abs(qb[:, 0]).max())


def _band(perm, rows, cols):
    inv = np.empty_like(perm)
    inv[perm] = np.arange(perm.size)
    return int(np.abs(inv[rows] - inv[cols]).max())


def test_reverse_cuthill_mckee_is_a_permutation_and_narrows_a_scrambled_chain():
    """A chain of 200 nodes, numbered at random: the ordering is a permutation of all nodes (also
    with several connected parts) and brings the band back to 1, as for the chain's own order."""
    rng = np.random.default_rng(1)
    n = 200
    lab = rng.permutation(n)
    rows, cols = lab[:-1], lab[1:]
    perm = reverse_cuthill_mckee(rows, cols, n)
    assert sorted(perm.tolist()) == list(range(n))
    assert _band(np.arange(n), rows, cols) > 10 and _band(perm, rows, cols) == 1
    # two parts and an isolated node
    rows2 = np.concatenate([rows[:80], rows[100:]])
    cols2 = np.concatenate([cols[:80], cols[100:]])
    perm2 = reverse_cuthill_mckee(rows2, cols2, n)
    assert sorted(perm2.tolist()) == list(range(n))


def test_banded_model_solves_without_scipy_linalg_and_scipy_still_imports_after():
    """A banded model (a 200-element cantilever) solved in a fresh process imports neither
    scipy.linalg nor scipy.sparse; importing scipy.linalg afterwards works and its dgbsv gives the
    same solve."""
    code = """
import sys, numpy as np, femslide
from femslide.model.structure import Structure
s = Structure(gravity=(0.0, 0.0))
s.rod("c", (0, 0), (2, 0), EI=1.0, elements=200)
s.weld("w", "c.start", "ground")
s.force("tip", "c.end", force=(0.0, -0.1))
r = femslide.solve(s)
loaded = sorted(k for k in sys.modules
                if k.startswith(("scipy.linalg", "scipy.sparse")) and k != "scipy.linalg._flapack")
print("LOADED", loaded)
import scipy.linalg
from scipy.linalg.lapack import dgbsv
ab = np.array([[0.0, 1.0, 1.0], [2.0, 2.0, 2.0], [1.0, 1.0, 0.0]])
_, _, x, info = dgbsv(1, 1, np.vstack([np.zeros(3), ab]), np.array([3.0, 4.0, 3.0]))
print("OK", info, np.allclose(x, 1.0), r["rods"]["c"]["M_max"])
"""
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr
    assert "LOADED []" in p.stdout, p.stdout
    ok = [ln for ln in p.stdout.splitlines() if ln.startswith("OK")][0].split()
    assert ok[1] == "0" and ok[2] == "True"


@pytest.mark.parametrize("P,eps,Mt", [(2e4, 0.004, 2.0e4), (1e4, 0.002, 1.5e4), (3e4, 0.01, 3e4)])
def test_closed_form_moment_peaks_match_the_search(P, eps, Mt):
    """The moment inside an element is a cubic in xi: largest_moment's closed form (the roots of M')
    and _Inside.moment_peak give the largest |M| and its position that the sampled golden-section
    search (_Inside.peak) finds, to 1e-12, on a compressed column whose peak lies inside its first
    element (interior excess over the nodes 2e-7 and 2e-6 in the first two cases)."""
    from femslide.results.static import _Inside, largest_moment
    s = Structure(gravity=(0.0, 0.0))
    s.rod("c", (0.0, 0.0), (3.0, 0.0), EI=1e5, EA=1e11, elements=4)
    s.weld("root", "c.start", "ground")
    s.force("tip", "c.end", force=(-P, -eps * P), moment=Mt)
    lv = femslide.solve(s).solution.level
    m = lv.model
    ins = _Inside(m, lv.y, lv.alpha, lv.cuts, 1.0)
    e = np.arange(m.elements.size)
    v_search, xi_search = ins.peak(ins.moment, e)
    v_closed, xi_closed = ins.moment_peak(e)
    assert np.allclose(v_closed, v_search, rtol=1e-12, atol=0.0)
    assert np.allclose(xi_closed, xi_search, rtol=0.0, atol=1e-6)   # a flat peak: its position to sqrt(eps)
    top = max(np.abs(v_search).max(), np.abs(lv.cuts[0]).max()) * m.Fref * m.Lref
    assert abs(largest_moment(m, lv.y, lv.alpha, lv.cuts) / top - 1.0) <= 1e-12


def test_batched_peaks_equal_the_fit_of_each_candidate():
    """results.history._peaks (every column's peak candidates fitted in one batched solve) gives
    what fitting each candidate's window with numpy.polyfit one by one gives (_refine, the loop
    written out here), to 1e-12 relative, on random sampled histories with uneven steps, repeated
    sample times (an event's two rows) and breaks."""
    from femslide.results.history import _peaks, _refine
    rng = np.random.default_rng(5)
    for trial in range(40):
        n = int(rng.integers(3, 200))
        t = np.cumsum(rng.uniform(1e-3, 0.05, n))
        if trial % 3 == 0:   # an event's two rows at one time
            k = int(rng.integers(1, n - 1))
            t[k:] -= t[k] - t[k - 1]
        X = np.column_stack([np.abs(np.sin(2 * np.pi * rng.uniform(0.3, 9.0) * t + rng.uniform(0, 6)))
                             for _ in range(int(rng.integers(1, 6)))])
        brk = [float(t[int(rng.integers(0, n))])] if trial % 4 == 0 else []
        with np.errstate(all="ignore"), warnings.catch_warnings():
            warnings.simplefilter("ignore")   # (polyfit's RankWarning on a window with repeated times)
            got = _peaks(t, X, breaks=brk)
        for j in range(X.shape[1]):
            x = X[:, j]
            best = float(x.max())
            inner = np.nonzero((x[1:-1] > x[:-2]) & (x[1:-1] >= x[2:]))[0] + 1
            for i in inner[np.argsort(-x[inner])][:16]:
                lo, hi = t[max(0, i - 2)], t[min(n - 1, i + 2)]
                if any(lo <= b <= hi for b in brk):
                    continue
                with np.errstate(all="ignore"), warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    best = max(best, _refine(t, x, int(i)))
            assert got[j] == pytest.approx(best, rel=1e-12)


class _Cubic:
    """r(y) = y^3 + y - b, component by component (a nonlinear system in Newton's interface, with a
    count of its Jacobian evaluations)."""

    def __init__(self, b):
        self.b, self.n_q, self.jacobians = np.asarray(b, float), len(b), 0

    def rotation_dofs(self):
        return np.zeros(0, dtype=np.intp)

    def system(self, y, elements, lam=1.0, control=None, jacobian=True, dense=False):
        r = y ** 3 + y - self.b
        if not jacobian:
            return r, None, {"fmax": 0.0, "noise": 0.0}
        self.jacobians += 1
        return r, np.diag(3.0 * y * y + 1.0), {"fmax": 0.0, "noise": 0.0}


@pytest.mark.parametrize("start", [0.9, 0.0, 3.0])
def test_newton_reuse_takes_chord_steps_to_the_same_root(start):
    """newton(..., reuse=0.1) keeps the last matrix while each residual is cut 10x or more, and
    assembles it afresh where it is not: from near the root (start 0.9 for roots near 1) it reaches
    the root of y^3 + y = b (to 1e-12, the roots found by numpy's polynomial solver) with fewer
    Jacobians than full Newton; from far off (0 and 3) it refreshes, converges all the same, and
    never assembles more Jacobians than full Newton's evaluations."""
    from femslide.analysis.newton import newton
    from femslide.model.state import ElementState
    b = np.array([2.0, 2.3, 1.7])
    exact = np.array([next(float(z.real) for z in np.roots([1.0, 0.0, 1.0, -bi]) if abs(z.imag) < 1e-12)
                      for bi in b])
    full, chord = _Cubic(b), _Cubic(b)
    y0 = np.full(3, start)
    y_f, info_f = newton(full, y0, ElementState(np.zeros(0)), tol=1e-13, maxit=40)
    y_c, info_c = newton(chord, y0, ElementState(np.zeros(0)), tol=1e-13, maxit=40, reuse=0.1)
    assert info_f.converged and info_c.converged
    assert np.abs(y_c - exact).max() <= 1e-12 and np.abs(y_f - exact).max() <= 1e-12
    assert chord.jacobians <= full.jacobians
    if start == 0.9:
        assert chord.jacobians < full.jacobians and info_c.iterations >= chord.jacobians


def test_history_centroids_are_the_models_body_points(monkeypatch):
    """A simulate history's bodies.NAME.x and .y (written with Model.body_point's formula in Python
    floats, femslide/analysis/simulate.py) equal Model.body_point of the same state to the last bit,
    at every recorded step of section 5.2's structure (the deck's frame origin is the pin at A1, away
    from its centroid; the piece's is its centroid)."""
    import femslide.analysis.transient as transient
    seen = []
    plain = transient.integrate

    def keep(model, *args, **kw):
        observe = kw["observe"]

        def watched(t, y, alpha, v, acc):
            row = observe(t, y, alpha, v, acc)
            seen.append((model, y.copy(), row))
            return row
        kw["observe"] = watched
        return plain(model, *args, **kw)
    monkeypatch.setattr(transient, "integrate", keep)
    r = femslide.simulate("meshes/structures/beam-oscillation.toml", t_end=0.3, tolerance=1e-4,
                          error_estimate=False)
    cols = list(r.history)
    assert len(seen) > 10
    for model, y, row in seen:
        fs = model.structure
        for b in fs.bodies:
            x, yy = model.body_point(b.name, y[:model.n_q], b.centroid)
            assert row[cols.index(f"bodies.{b.name}.x")] == float(x)
            assert row[cols.index(f"bodies.{b.name}.y")] == float(yy)


def test_an_event_located_inside_a_step_is_not_put_at_its_start_by_a_shortest_trial():
    """events.locate_step: an event function that falls linearly from f0 > 0 at the step's start to
    zero at 0.3 h (exact root) is located there to 1e-9 h, also where a trial as short as the
    resolution of event times would give a garbage value (a step of 2.5e-8 s on a structure with
    massless parts gave a friction margin of -2 for a true +3e-4 N: the event was placed at x_min,
    1.6e-4 s early); no trial is shorter than x_min; an event within x_min of the start is placed at
    x_min."""
    from femslide.analysis.events import locate_step
    h, x_min, root = 5e-4, 2.5e-8, 1.5e-4
    tried = []

    def attempt(x):
        tried.append(x)
        return x

    def f(c):   # the event function at a trial's end; garbage on trials shorter than 4 x_min
        return -2.0 if c < 4 * x_min else (root - c) / h

    x, c = locate_step(attempt, f, root / h, h, h, x_min=x_min)
    assert abs(x - root) <= 1e-9 * h and c == x and f(c) <= 0.0
    assert min(tried) >= x_min
    x, _ = locate_step(attempt, lambda c: (1e-8 - c) / h, 1e-8 / h, h, h, x_min=x_min)   # (root below x_min)
    assert x == x_min


def test_largest_abs_is_numpys_largest_magnitude():
    """linalg.largest_abs (one kernel pass where the array allows it) gives float(np.abs(a).max()):
    the same float on C-ordered, strided and integer arrays, NaN where one entry is NaN, inf where one
    is infinite."""
    from femslide.model.linalg import largest_abs
    rng = np.random.default_rng(3)
    for a in (rng.standard_normal(7), rng.standard_normal((5, 2)), rng.standard_normal((6, 4))[:, 1],
              np.arange(-5, 3), np.array([-0.0]), np.array([1e308, -1e308])):
        assert largest_abs(a) == float(np.abs(a).max())
    assert np.isnan(largest_abs(np.array([1.0, np.nan, 3.0])))
    assert largest_abs(np.array([1.0, -np.inf])) == np.inf


def test_dense_eigenproblems_and_null_spaces_are_scipys_without_scipy_linalg():
    """linalg.eigh (one matrix, or a pair with B positive definite) and linalg.null_space call LAPACK
    as scipy.linalg.eigh and scipy.linalg.null_space do (dsyevr, dsygvd, dgesdd through the compiled
    wrappers, without importing scipy.linalg): the same arrays, bit for bit, on random symmetric
    problems of 1 to 90 unknowns and on rank-deficient constraint gradients (G with a row the sum of
    two others, and G = 0: the whole space); the basis is orthonormal and G Z = 0 to round-off; B not
    positive definite raises LinAlgError, as scipy's does."""
    import scipy.linalg as sl
    from femslide.model.linalg import eigh, null_space
    rng = np.random.default_rng(11)
    for n in (1, 4, 30, 90):
        X, Y = rng.standard_normal((n, n)), rng.standard_normal((n, n))
        A, B = X + X.T, Y @ Y.T + n * np.eye(n)
        for got, ref in ((eigh(A), sl.eigh(A)), (eigh(A, B), sl.eigh(A, B))):
            assert np.array_equal(got[0], ref[0]) and np.array_equal(got[1], ref[1])
        w, V = eigh(A, B)
        assert np.allclose(V.T @ B @ V, np.eye(n), atol=1e-12) and np.all(np.diff(w) >= 0.0)
    with pytest.raises(np.linalg.LinAlgError):
        eigh(A, -B)
    for m, n in ((3, 10), (5, 5), (12, 40), (2, 6)):
        G = rng.standard_normal((m, n)) if m != 2 else np.zeros((m, n))
        if m > 2:
            G[2] = G[0] + G[1]
        Z = null_space(G)
        assert np.array_equal(Z, sl.null_space(G))
        rank = 0 if m == 2 else min(m, n) - 1   # (G = 0, or one dependent row)
        assert Z.shape == (n, n - rank)
        assert np.abs(G @ Z).max(initial=0.0) <= 1e-13 and np.allclose(Z.T @ Z, np.eye(Z.shape[1]), atol=1e-13)


def test_set_operations_are_numpys_without_numpy_ma():
    """linalg.distinct (with ``first``), member and complement give np.unique (with return_index),
    np.isin and np.setdiff1d(np.arange(n), idx) exactly, on random integer arrays with repeats (empty
    ones too) and on floats with a repeat."""
    from femslide.model.linalg import complement, distinct, member
    rng = np.random.default_rng(2)
    for _ in range(300):
        a = rng.integers(0, 20, rng.integers(0, 30))
        v = rng.integers(0, 20, rng.integers(0, 6))
        u, i = np.unique(a, return_index=True)
        d, j = distinct(a, first=True)
        assert np.array_equal(u, d) and np.array_equal(i, j) and np.array_equal(distinct(a), u)
        assert np.array_equal(member(a, v), np.isin(a, v))
        assert np.array_equal(complement(20, v), np.setdiff1d(np.arange(20), v))
    f = rng.standard_normal(10)
    f[3] = f[7]
    assert np.array_equal(distinct(f), np.unique(f))


def test_a_joints_slide_value_is_the_slide_of_its_gradient_evaluation():
    """Link.slide_value (the slide alone: history rows, watched results) is bit for bit the slide that
    Link.slide computes with its gradient and Hessian, on random states of a sliding clamp whose guide
    a turning body carries (its joint point off the body's frame origin: a lever)."""
    from femslide.model.discrete import Model
    s = Structure(gravity=(0.0, -9.81))
    s.body("deck", mass=100.0, outline=[(-1.0, 0.0), (1.0, 0.0), (1.0, 0.2), (-1.0, 0.2)])
    s.rod("post", (0.6, -2.0), (0.6, 0.0), EI=1e5, EA=1e8)
    s.pin("A", "deck", "ground", at=(-0.6, 0.0))
    s.pin("B", "post.start", "ground")
    s.slider("clamp", "post.end", "deck", axis=(0.0, 1.0))
    fs = s.freeze()
    m = Model(fs, {"post": 4}, 1.0, 1.0)
    link = m.joint["clamp"]
    assert link.lever_b
    rng = np.random.default_rng(5)
    for _ in range(200):
        z = rng.standard_normal(link.dofs.size)
        assert link.slide_value(z) == link.slide(z)[0]


def test_coo_matrix_equals_scipys():
    """femslide.model.linalg.Coo (a time history's damping matrix, without scipy) against scipy.sparse
    as the reference: duplicates summed, C @ v, C + D, a * C and Coo.of(scipy matrix) give scipy's
    dense matrices and products to 1e-15 of their largest value, C.T its transpose; an empty matrix is
    zero."""
    import scipy.sparse as sp

    from femslide.model.linalg import Coo
    rng = np.random.default_rng(3)
    n = 17
    r, c = rng.integers(0, n, (2, 80))   # (with repeated positions)
    v = rng.standard_normal(80)
    C, S = Coo(r, c, v, n), sp.coo_matrix((v, (r, c)), shape=(n, n))
    assert C.row.size < 80 and np.all(np.diff(C.row * n + C.col) > 0)   # (summed, row-major)
    x = rng.standard_normal(n)
    assert np.abs(C.toarray() - S.toarray()).max() <= 1e-15 * np.abs(S.toarray()).max()
    assert np.abs(C @ x - S @ x).max() <= 1e-15 * np.abs(S @ x).max() * n
    r2, c2 = rng.integers(0, n, (2, 30))
    v2 = rng.standard_normal(30)
    D, SD = Coo(r2, c2, v2, n), sp.coo_matrix((v2, (r2, c2)), shape=(n, n))
    ref = (0.3 * S + SD).toarray()
    assert np.abs((0.3 * C + D).toarray() - ref).max() <= 1e-15 * np.abs(ref).max() * 4
    assert np.abs(Coo.of(S.tocsr()).toarray() - S.toarray()).max() <= 1e-15 * np.abs(S.toarray()).max()
    assert np.array_equal(C.T.toarray(), S.T.toarray())
    assert Coo.of(None) is None and Coo.of(C) is C
    E = Coo([], [], [], n)
    assert E.data.size == 0 and not np.any(E @ x) and (E + C).toarray().tolist() == C.toarray().tolist()


def test_coo_keeps_its_indices_in_range_and_drops_zeros():
    """Coo refuses indices outside 0 .. n-1 and a non-square scipy matrix (a ValueError naming the
    range or the shape), and drops zeros: explicit zeros of a scipy matrix and sums that cancel."""
    import scipy.sparse as sp

    from femslide.model.linalg import Coo
    with pytest.raises(ValueError, match="outside 0 .. 1"):
        Coo([2], [0], [1.0], 2)
    with pytest.raises(ValueError, match="square"):
        Coo.of(sp.coo_matrix(np.ones((2, 3))))
    S = sp.coo_matrix(([1.0, 0.0, 2.0, -2.0], ([0, 1, 2, 2], [0, 1, 1, 1])), shape=(3, 3))
    C = Coo.of(S)
    assert C.row.tolist() == [0] and C.col.tolist() == [0] and C.data.tolist() == [1.0]


@pytest.mark.parametrize("n_el", [3, 60])
def test_rayleigh_damping_is_alpha_m_plus_beta_k0(n_el):
    """simulate.rayleigh_damping against its definition, C = alpha M + beta (K + K^T) / 2 with M the
    dense mass matrix and K the stiffness block of the dense tangent (Model.system(dense=True)) at a
    random state of a mast with a rotational spring at its foot and a body welded on top: to 1e-14
    of C's largest entry, for a dense (3 elements) and a banded (60 elements) model; alpha or beta
    zero leaves the other term alone.  (This tangent is symmetric, as the corotational elements', the
    springs' and the joints' are: the symmetric part is what a non-symmetric one would contribute.)"""
    from femslide.analysis import static
    from femslide.analysis.simulate import rayleigh_damping
    from femslide.model.discrete import Model
    from femslide.model.linalg import BandMatrix
    from femslide.model.mass import Masses
    s = Structure(gravity=(0.0, -9.81))
    s.rod("mast", (0.0, 0.0), (0.3, 2.0), EI=2e4, EA=2e8, rhoA=3.0, elements=n_el)
    s.body("top", mass=50.0, centroid=(0.3, 2.2), inertia=4.0)
    s.weld("head", "top", "mast.end")
    s.pin("foot", "mast.start", "ground", c=300.0)
    fs = s.freeze()
    model = Model(fs, {"mast": n_el}, *static.scales(fs))
    masses = Masses(model)
    rng = np.random.default_rng(11)
    y = 0.02 * rng.standard_normal(model.n)
    es = model.zero_state()[1]
    es.committed = 0.02 * rng.standard_normal(es.committed.size)
    _, A, _ = model.system(y, es.copy(), 1.0)
    assert isinstance(A, BandMatrix) == (n_el == 60)
    _, A, _ = model.system(y, es.copy(), 1.0, dense=True)
    K = A[:model.n_q, :model.n_q]
    M = masses.dense(y[:model.n_q])
    for alpha, beta in ((0.4, 2e-3), (0.0, 1e-3), (0.7, 0.0)):
        ref = alpha * M + beta * 0.5 * (K + K.T)
        C = rayleigh_damping(model, masses, y, es.copy(), alpha, beta).toarray()
        assert np.abs(C - ref).max() <= 1e-14 * np.abs(ref).max(), (alpha, beta)
