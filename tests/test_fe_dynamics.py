"""FE dynamics of declared structures: masses, modes, the implicit integrator, simulate."""
import math

import numpy as np
import pytest

import femslide
from femslide import static
from femslide.mass import Masses
from femslide.modes import modes

BETA_L = np.array([1.8751040687119611, 4.694091132974175, 7.854757438237613])  # cantilever roots


def _solved(s):
    sol = static.solve(s.freeze())
    return sol.level.model, sol.level.y, sol.level.alpha


def _cantilever(n, rhoA=2.0, L=1.5, EI=2.0, tip=None, gravity=(0.0, 0.0)):
    s = femslide.Structure(gravity=gravity)
    s.rod("c", (0.0, 0.0), (L, 0.0), EI=EI, EA=1e6 * EI, rhoA=rhoA, elements=n)
    s.weld("clamp", "c.start", "ground")
    if tip is not None:
        s.body("tip", mass=tip, centroid=(L, 0.0), inertia=0.0)
        s.weld("w", "tip", "c.end", at=(L, 0.0))
    return s


def test_lumped_masses_carry_the_rod_and_body_mass():
    """Row-sum lumping: the nodal masses add up to rhoA L exactly; the body's 3x3 block about a
    frame origin off the centroid is [[m, 0, -m ry], [0, m, m rx], [., ., J + m |r|^2]]."""
    s = _cantilever(5, rhoA=3.0, L=2.0)
    s.body("deck", mass=4.0, centroid=(2.0, 1.0), inertia=0.5)
    s.pin("p", "deck", "ground", at=(3.0, 1.0))
    s.weld("w", "c.end", "deck")
    model, y, _ = _solved(s)
    ms = Masses(model)
    assert ms.node_m.sum() / ms.unit_m == pytest.approx(6.0, rel=1e-14)
    assert ms.node_m[0] == pytest.approx(ms.node_m[1] / 2, rel=1e-14)
    M = ms.dense(np.zeros(model.n_q))
    d = model.body_dof("deck")
    B = M[d:d + 3, d:d + 3]
    rx, ry = (2.0 - 3.0) / model.Lref, 0.0
    m, J = 4.0 * ms.unit_m, 0.5 * ms.unit_J
    assert np.allclose(B, [[m, 0, -m * ry], [0, m, m * rx], [-m * ry, m * rx, J + m * rx * rx]], rtol=1e-14)
    assert ms.total_mass == pytest.approx(10.0)


def test_tip_mass_on_a_massless_cantilever():
    """Massless cantilever (EI = 2, L = 1.5) with a tip body M = 3 (J = 0): the only finite frequency
    transverse frequency is sqrt(3 EI / (M L^3)) / (2 pi) (cubic beams are exact for the tip
    stiffness), the axial one sqrt(EA / (M L)) / (2 pi); both within 1e-6, and no others."""
    model, y, a = _solved(_cantilever(4, rhoA=0.0, tip=3.0))
    f, shapes = modes(model, y, a, Masses(model), 3)
    assert f.size == 2
    assert f[0] == pytest.approx(math.sqrt(3 * 2.0 / (3.0 * 1.5 ** 3)) / (2 * math.pi), rel=1e-6)
    assert f[1] == pytest.approx(math.sqrt(2e6 / (3.0 * 1.5)) / (2 * math.pi), rel=1e-6)
    assert abs(shapes[0][model.body_dof("tip") + 1]) == pytest.approx(1.0)


def test_cantilever_rod_modes_converge_at_second_order():
    """Uniform cantilever (rhoA = 2, EI = 2, L = 1.5) against Euler-Bernoulli's
    f_k = (beta_k L)^2 / (2 pi L^2) sqrt(EI / rhoA): three lowest within 1e-3 at 64 elements, and the
    error falls by 4 (3.6 .. 4.4) per mesh doubling (lumped masses: second order)."""
    ref = BETA_L ** 2 / 1.5 ** 2 * math.sqrt(2.0 / 2.0) / (2 * math.pi)
    errs = []
    for n in (16, 32, 64):
        model, y, a = _solved(_cantilever(n))
        f, _ = modes(model, y, a, Masses(model), 3)
        errs.append(np.abs(f / ref - 1.0))
    assert np.all(errs[-1] < 1e-3)
    for e1, e2 in zip(errs, errs[1:]):
        assert np.all((e1 / e2 > 3.6) & (e1 / e2 < 4.4))
