"""The solution path of declared structures: limit points, mechanisms, stable and unstable branches.

* Shallow two-bar (von Mises) truss: two rods pinned to the ground at (-1, 0) and (1, 0) and to each
  other at the apex (0, h), a dead load P down at the apex.  The rods stay straight (pinned ends, no
  transverse load), so the equilibrium is that of two bars: with the apex lowered by w,
  L(w) = sqrt(1 + (h - w)^2), N = EA (L0 - L)/L0 (compression), P = 2 N (h - w)/L.  Below the limit
  load (the maximum of P(w) on the first branch, found by scipy) femslide must give w within 1e-8
  relative; above it the run must fail (exit 1) saying "limit point" at a load factor within 1e-3
  of P_max/P (the step halving locates it to ~1e-6).
* A body hanging from a horizontal ground roller (gravity holds its rotation, nothing holds its
  sliding): a mechanism, exit 1 naming the body and the direction x.
* A pendulum (a body pinned above its centre of mass, no rods): gravity holds it; the solution is the
  undeformed state with the pin carrying the weight (exact).
"""
from __future__ import annotations

import math

import pytest
from scipy.optimize import brentq, minimize_scalar

import femslide
from femslide.errors import SolverFailure
from femslide.model.structure import Structure

H0, EA, EI = 0.1, 1e6, 1e5


def truss(P):
    s = Structure(gravity=(0.0, 0.0))
    s.rod("l", (-1.0, 0.0), (0.0, H0), EI=EI, EA=EA)
    s.rod("r", (1.0, 0.0), (0.0, H0), EI=EI, EA=EA)
    s.pin("A", "l.start", "ground")
    s.pin("B", "r.start", "ground")
    s.pin("apex", "l.end", "r.end")
    s.force("P", "l.end", force=(0.0, -P))
    return s


def bar_load(w):
    L0 = math.hypot(1.0, H0)
    L = math.hypot(1.0, H0 - w)
    return 2.0 * EA * (L0 - L) / L0 * (H0 - w) / L


def limit_load():
    res = minimize_scalar(lambda w: -bar_load(w), bounds=(0.0, H0), method="bounded",
                          options={"xatol": 1e-12})
    return -res.fun, res.x


@pytest.mark.parametrize("frac", [0.3, 0.8])
def test_truss_below_the_limit_load(frac):
    Pmax, wmax = limit_load()
    P = frac * Pmax
    w_ref = brentq(lambda w: bar_load(w) - P, 0.0, wmax, xtol=1e-15, rtol=1e-15)
    r = femslide.solve(truss(P))
    w = -r["rods"]["l"]["end"]["v"]
    assert w == pytest.approx(w_ref, rel=1e-8)
    assert r["rods"]["l"]["M_max"] <= 1e-8 * P   # the bars stay straight
    assert r["reactions"]["A"]["Fy"] == pytest.approx(P / 2, rel=1e-8)


def test_truss_above_the_limit_load_fails_at_the_limit_point():
    Pmax, _ = limit_load()
    P = 2.0 * Pmax
    with pytest.raises(SolverFailure) as exc:
        femslide.solve(truss(P))
    msg = exc.value.reason
    assert "limit point" in msg
    lam = float(msg.split("load factor ")[1].split(":")[0].split()[0])
    assert lam == pytest.approx(Pmax / P, rel=1e-3)


def test_hanging_body_on_a_roller_is_a_mechanism():
    s = Structure()
    s.body("cart", mass=2.0, centroid=(0.0, -0.5), outline=[(-0.5, -1), (0.5, -1), (0.5, 0), (-0.5, 0)])
    s.roller("track", "cart", "ground", at=(0.0, 0.0), axis=(1.0, 0.0))
    with pytest.raises(SolverFailure) as exc:
        femslide.solve(s)
    assert "mechanism" in exc.value.reason and "cart (x)" in exc.value.reason


def test_pendulum_is_held_by_gravity():
    s = Structure(gravity=(0.0, -9.81))
    s.body("bob", mass=3.0, centroid=(0.0, -1.0))
    s.pin("pivot", "bob", "ground", at=(0.0, 0.0))
    r = femslide.solve(s)
    assert r["bodies"]["bob"]["rotation"] == 0.0 or abs(r["bodies"]["bob"]["rotation"]) < 1e-14
    assert r["reactions"]["pivot"]["Fy"] == pytest.approx(3.0 * 9.81, rel=1e-12)
    assert abs(r["reactions"]["pivot"]["Fx"]) < 1e-12
