"""Element, joint and assembly kernels against closed forms and finite differences (issue 3 item 1).

- basic stiffness from the scikit-fem forms against the closed forms: EA/L and EI/L [[4, 2], [2, 4]]
  for constant stiffness; for EI(s) = E0 + E1 s and EA(s) linear the exact integrals
  k11 = (4 EI_m - E1 L)/L, k22 = (4 EI_m + E1 L)/L, k12 = 2 EI_m/L, k00 = EA_m/L (EI_m, EA_m: the
  values at the element middle); tolerance 1e-12 relative;
- corotational element: internal force = gradient of the strain energy and tangent = Jacobian of the
  internal force, by central differences (step 1e-6; tolerance 1e-6 of the largest entry), at large
  deformed states, chords turned past pi included; zero force under a rigid motion of 3.5 rad;
- joints (every type between every pair of carriers: rod node, body point, ground; inclined axes),
  springs and loads: gradients and Hessians by central differences (tolerance 1e-7);
- the assembled Jacobian of every structure scene and of a general frame with every joint type, in
  load and in displacement control, by central differences of the assembled residual (tolerance 1e-6
  of its largest entry).
"""
import math

import numpy as np
import pytest

from femslide.elements import corotational
from femslide.elements.forms import basic_stiffness
from femslide.elements.loads import PointForce
from femslide.joints.base import Carrier, Link, RotationalSpring, SlideSpring
from femslide.joints.kinds import BUILTIN
from femslide.model.discrete import Model
from femslide.joints.holds import DofHold
from femslide.model.state import ElementState
from femslide.model.structure import Structure
from femslide.scenes import paper
from femslide.scenes.catalog import SCENES

RNG = np.random.default_rng(20261121)


def test_basic_stiffness_constant_is_the_closed_form():
    L0 = np.array([0.5, 1.0, 2.5])
    kb = basic_stiffness(L0, np.array([0.0, 0.5, 1.5]), 7.0, 3e5)
    for k, L in zip(kb, L0):
        ref = np.array([[3e5 / L, 0, 0], [0, 4 * 7.0 / L, 2 * 7.0 / L], [0, 2 * 7.0 / L, 4 * 7.0 / L]])
        assert np.allclose(k, ref, rtol=1e-12, atol=0)


def test_basic_stiffness_linear_EI_EA_is_exact():
    E0, E1, A0, A1 = 3.0, 2.0, 1e4, -3e3
    L0 = np.array([0.4, 0.7, 1.1])
    s0 = np.concatenate([[0.0], np.cumsum(L0)[:-1]])
    kb = basic_stiffness(L0, s0, lambda s: E0 + E1 * s, lambda s: A0 + A1 * s)
    for k, L, s in zip(kb, L0, s0):
        EIm, EAm = E0 + E1 * (s + L / 2), A0 + A1 * (s + L / 2)
        ref = np.array([[EAm / L, 0, 0],
                        [0, (4 * EIm - E1 * L) / L, 2 * EIm / L],
                        [0, 2 * EIm / L, (4 * EIm + E1 * L) / L]])
        assert np.allclose(k, ref, rtol=1e-12, atol=1e-12 * np.abs(ref).max())


def _elements(n=3, turn=0.0):
    """n elements of assorted lengths and directions; EA/EI = 1e3 so that both terms matter."""
    X = np.cumsum(np.vstack([[0.0, 0.0], RNG.uniform(0.3, 1.0, (n, 2)) * [1, 1]]), axis=0)
    conn = np.stack([np.arange(n), np.arange(1, n + 1)], axis=1)
    D0 = X[1:] - X[:-1]
    L0 = np.hypot(*D0.T)
    kb = basic_stiffness(L0, np.zeros(n), 2.0, 2e3)
    es = corotational.ElementSet(conn, D0, L0, np.arctan2(D0[:, 1], D0[:, 0]), kb, float(np.abs(X).max()))
    return es, X


def _rigid(X, ang, shift=(0.3, -0.2)):
    c, s = math.cos(ang), math.sin(ang)
    Xr = X @ np.array([[c, s], [-s, c]]) + shift
    U = np.zeros((X.shape[0], 3))
    U[:, :2] = Xr - X
    U[:, 2] = ang
    return U


def test_rigid_motion_past_pi_gives_no_force():
    es, X = _elements()
    U = _rigid(X, 3.5)
    alpha_ref = np.full(es.size, 3.4)   # continued from a neighbouring state, not wrapped to (-pi, pi]
    f, K, q, alpha, _ = corotational.evaluate(es, U, alpha_ref)
    assert np.allclose(alpha, 3.5, atol=1e-13, rtol=0)
    assert np.abs(q).max() <= 1e-9 and np.abs(f).max() <= 1e-9


@pytest.mark.parametrize("turn", [0.0, 1.2, 3.5, -4.0])
def test_force_is_energy_gradient_and_tangent_its_jacobian(turn):
    es, X = _elements()
    U = _rigid(X, turn) + RNG.normal(0, 0.05, (X.shape[0], 3))
    alpha_ref = np.full(es.size, turn)
    f, K, _, _, _ = corotational.evaluate(es, U, alpha_ref)
    nd = U.size
    h = 1e-6
    F = np.zeros(nd)
    J = np.zeros((nd, nd))
    for k in range(nd):
        Up, Um = U.copy(), U.copy()
        Up.flat[k] += h
        Um.flat[k] -= h
        F[k] = (corotational.strain_energy(es, Up, alpha_ref) - corotational.strain_energy(es, Um, alpha_ref)) / (2 * h)
        fp = corotational.evaluate(es, Up, alpha_ref)[0]
        fm = corotational.evaluate(es, Um, alpha_ref)[0]
        J[:, k] = _assemble_f(es, fp - fm, nd) / (2 * h)
    assert np.abs(_assemble_f(es, f, nd) - F).max() <= 1e-6 * np.abs(F).max()
    assert np.abs(_assemble_K(es, K, nd) - J).max() <= 1e-6 * np.abs(J).max()


def _edofs(es):
    c = es.conn
    return np.concatenate([3 * c[:, :1] + np.arange(3), 3 * c[:, 1:] + np.arange(3)], axis=1)


def _assemble_f(es, f, nd):
    return np.bincount(_edofs(es).ravel(), weights=f.ravel(), minlength=nd)


def _assemble_K(es, K, nd):
    ed = _edofs(es)
    A = np.zeros((nd, nd))
    for e in range(es.size):
        A[np.ix_(ed[e], ed[e])] += K[e]
    return A


NODE = Carrier(0, (0.2, 1.9), (0.0, 0.0))
BODY = Carrier(3, (0.3, 2.0), (0.4, -0.3))
GROUND = Carrier(None, (0.0, 0.0), (0.25, 1.7))


def _joint_cases():
    cases = []
    for kind in (k.name for k in BUILTIN):   # every built-in kind's equations
        for a, b in ((NODE, GROUND), (BODY, GROUND), (NODE, BODY), (BODY, NODE),
                     (Carrier(0, (0.1, 0.2), (-0.3, 0.5)), Carrier(3, (1.0, 0.4), (0.2, 0.1)))):
            link = Link(kind, kind, a, b, axis=(0.6, 0.8))
            cases.append((link, link.k))
    return cases


def _id(x):
    return f"{x.kind}-{x.ia}-{x.ib}" if isinstance(x, Link) else (type(x).__name__ if not isinstance(x, int) else "")


@pytest.mark.parametrize("joint,k", _joint_cases(), ids=_id)
def test_joint_gradient_and_hessian(joint, k):
    z = RNG.normal(0, 0.4, k)
    g, G, H = joint.eval(z)
    mu = RNG.normal(0, 1.0, g.size)
    assert np.allclose(joint.eval(z, mu)[2], np.einsum("i,ijk->jk", mu, H), atol=1e-14)
    h = 1e-6
    for j in range(k):
        zp, zm = z.copy(), z.copy()
        zp[j] += h
        zm[j] -= h
        gp, Gp, _ = joint.eval(zp)
        gm, Gm, _ = joint.eval(zm)
        assert np.allclose(G[:, j], (gp - gm) / (2 * h), atol=1e-7, rtol=0)
        assert np.allclose(H[:, :, j], (Gp - Gm) / (2 * h), atol=1e-7, rtol=0)
    # the model assembles through assemble(): the same numbers as eval() - mu . G, g, then the
    # Jacobian entries sum mu_i H_i, G and G again
    rv, jv = [], []
    joint.assemble(z.tolist(), mu.tolist(), rv, jv)
    _, Gm, Hmu = joint.eval(z, mu)
    assert np.allclose(rv, np.concatenate([mu @ Gm, g]), rtol=0, atol=1e-14)
    assert np.allclose(jv, np.concatenate([Hmu.ravel(), Gm.ravel(), Gm.ravel()]), rtol=0, atol=1e-14)


@pytest.mark.parametrize("joint,k", [c for c in _joint_cases() if c[0].joint_kind.free == "slide"], ids=_id)
def test_slide_gradient_and_hessian(joint, k):
    z = RNG.normal(0, 0.4, k)
    s, ds, H = joint.slide(z)
    h = 1e-6
    for j in range(k):
        zp, zm = z.copy(), z.copy()
        zp[j] += h
        zm[j] -= h
        sp, dsp, _ = joint.slide(zp)
        sm, dsm, _ = joint.slide(zm)
        assert abs(ds[j] - (sp - sm) / (2 * h)) <= 1e-7
        assert np.allclose(H[:, j], (dsp - dsm) / (2 * h), atol=1e-7, rtol=0)


def _term_cases():
    slider = Link("s", "slider", NODE, BODY, axis=(0.6, 0.8))
    pin = Link("p", "pin", BODY, NODE)
    return [
        (PointForce(np.arange(3), (1.2, 0.4), (0.3, -1.3), 0.2), 3),
        (SlideSpring(slider, 3.0, 0.8, 0.1), 6),
        (RotationalSpring(pin, 2.5), 6),
    ]


@pytest.mark.parametrize("term,k", _term_cases(), ids=_id)
@pytest.mark.parametrize("lam", [0.3, 1.0])
def test_load_gradient_and_hessian(term, k, lam):
    z = RNG.normal(0, 0.4, k)
    _, g, H, g0 = term.eval(z, lam)
    h = 1e-6
    for j in range(k):
        zp, zm = z.copy(), z.copy()
        zp[j] += h
        zm[j] -= h
        Ep, gp, _, _ = term.eval(zp, lam)
        Em, gm, _, _ = term.eval(zm, lam)
        assert abs(g[j] - (Ep - Em) / (2 * h)) <= 1e-7
        assert np.allclose(H[:, j], (gp - gm) / (2 * h), atol=1e-7, rtol=0)
    # d gradient / d lam
    lp = term.eval(z, lam + h)[1]
    lm = term.eval(z, lam - h)[1]
    assert np.allclose(g0, (lp - lm) / (2 * h), atol=1e-7, rtol=0)
    # the model assembles through assemble(): the same numbers as eval()
    rv, jv, fv = [], [], []
    term.assemble(z.tolist(), lam, rv, jv, fv)
    assert np.allclose(rv, g, rtol=0, atol=1e-14) and np.allclose(fv, g0, rtol=0, atol=1e-14)
    assert np.allclose(np.reshape(jv, H.shape), H, rtol=0, atol=1e-14)


def _dense(A):
    if isinstance(A, np.ndarray):
        return A
    if hasattr(A, "toarray"):
        return A.toarray()
    raise TypeError(type(A))


def _frame():
    """A frame with every joint type, springs, an inclined guide, point, end and distributed loads."""
    s = Structure(gravity=(0.3, -9.81))
    s.rod("c1", (0, 0), (0, 3), EI=30.0, EA=3e3, rhoA=0.4)
    s.rod("c2", (4, 0), (4, 3), EI={"s": [0, 3], "value": [40.0, 20.0]}, EA=5e3)
    s.rod("beam", (0, 3), (4, 3), EI=50.0, EA=4e3)
    s.body("deck", mass=2.0, centroid=(2, 4), outline=[(0, 3.5), (4, 3.5), (4, 4.5), (0, 4.5)])
    s.pin("base1", "c1.start", "ground", c=5.0)
    s.roller("base2", "c2.start", "ground", axis=(1.0, 0.2), k=7.0, preload=0.5)
    s.weld("k1", "c1.end", "beam.start")
    s.pin("k2", "c2.end", "beam.end")
    s.slider("guide", "deck", "beam.end", axis=(0.0, 1.0), at=(4, 3), k=3.0)
    s.pin("tie", "deck", "c1.end", at=(0, 3))
    s.force("wind", "deck", force=(1.0, 0.5), moment=0.3, at=(0, 4.5))
    s.force("tip", "c2.end", force=(0.2, 0.0))
    s.distributed("snow", "beam", force=(0.0, -0.7))
    return s.freeze()


def _scene_model(scene):
    v = SCENES[scene].resolve({"EI": 30.0, "EA": 3e3, "n_elements": 3})
    fs = paper.declare(scene, v).freeze()
    return Model(fs, {r.name: 3 for r in fs.rods}, *paper.units(scene, v))


@pytest.mark.parametrize("scene", ["beam-slider", "beam-fixed", "beam-both", "beam-spring", "beam-extra-mass", "frame"])
@pytest.mark.parametrize("control", [False, True])
def test_assembled_jacobian(scene, control):
    m = Model(_frame(), {"c1": 3, "c2": 2, "beam": 3}, 4.0, 10.0) if scene == "frame" else _scene_model(scene)
    y = RNG.normal(0, 0.02, m.n)
    y[m.n_q:] = RNG.normal(0, 1.0, m.n_c)
    alpha_ref = ElementState.zero(m.elements.size)
    ctl = None
    if control:
        y = np.concatenate([y, [0.8]])
        ctl = DofHold(m.body_dof("deck") + 2, -0.01)
    r, A, _ = m.system(y, alpha_ref, 0.8, ctl)
    A = _dense(A)
    h = 1e-6
    J = np.zeros_like(A)
    for k in range(y.size):
        yp, ym = y.copy(), y.copy()
        yp[k] += h
        ym[k] -= h
        J[:, k] = (m.system(yp, alpha_ref, 0.8, ctl)[0] - m.system(ym, alpha_ref, 0.8, ctl)[0]) / (2 * h)
    assert np.abs(A - J).max() <= 1e-6 * np.abs(J).max()
