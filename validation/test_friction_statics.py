"""Friction in statics under load histories (SPEC section 10, ``[[step]]``) against the exact
one-dimensional references of validation/friction_statics_reference.py.

References and tolerances:

* a rod welded at one end, its other end on a frictional ground slider under a vertical load W,
  heated and cooled back (and through a second cycle): at every step the slider's state, its
  friction force (mu0 N while stuck at most, mu N slipping, against the slide) and the slide equal
  the exact event-by-event solution of a spring k = EA/L with Coulomb friction (1e-6 of mu N and of
  the largest slide); after the cycle the residual slide (mu N L / EA per reversal) and the locked-in
  tension N = mu W (1e-6);
* a deck (a stiff rod) pinned to the top of a column (a cantilever, stiffness 3 EI / H^3) and resting
  on a frictional sliding bearing, through temperature cycles (+25 K stays stuck, +60 K and -50 K
  slip): the bearing's state and force and the column's root moment against the spring-friction
  reference with k = (H^3 / (3 EI) + Ld / EA)^-1 (1e-6 of mu0 N in first-order theory, measured
  2e-11; 1e-4 in the exact theory, measured 1.1e-5: the column's deflection of H/270 adds its
  second-order terms);
* a rod on two frictional sliders on an incline (tan beta < mu) under repeated thermal cycles: the
  rod walks downhill by the same amount every cycle (thermal ratcheting); both ends' slides and
  forces at every step against the exact reference (1e-6), and the walk per cycle;
* the breakaway's load parameter inside the step: alpha dT at the switch gives |N| = mu0 W (1e-9).
"""
from __future__ import annotations

import math

import friction_statics_reference as ref
import pytest

import femslide
from femslide.model.structure import Structure

TOL = 1e-6


def rod_on_slider(L=10.0, EA=1e9, alpha=1.2e-5, W=1e4, mu=0.3, mu0=0.4, temps=(0.0, 20.0, 0.0)):
    s = Structure(gravity=(0.0, 0.0))
    s.rod("r", (0.0, 0.0), (L, 0.0), EI=1e6, EA=EA, alpha=alpha)
    s.weld("A", "r.start", "ground")
    s.slider("B", "r.end", "ground", axis=(1.0, 0.0), mu=mu, mu0=mu0)
    s.force("W", "r.end", force=(0.0, -W))
    s.thermal("T", "r", dT=1.0, case="heat")
    for t in temps:
        s.step({"dead": 1.0, "heat": t})
    return s


@pytest.mark.parametrize("theory", ["nonlinear", "linear"])
def test_rod_on_a_frictional_slider_thermal_cycle(theory):
    L, EA, alpha, W, mu, mu0 = 10.0, 1e9, 1.2e-5, 1e4, 0.3, 0.4
    temps = (0.0, 20.0, 0.0, 35.0, -10.0, 0.0)
    r = femslide.solve(rod_on_slider(L, EA, alpha, W, mu, mu0, temps), theory=theory)
    exact = ref.one_slider(EA / L, W, mu, mu0, [alpha * t * L for t in temps])
    smax = max(abs(x["slide"]) for x in exact)
    for st, ex in zip(r["steps"], exact):
        f = st["friction"]["B"]
        assert f["state"] == ex["state"], (st["name"], f, ex)
        assert abs(f["force"] - ex["force"]) <= TOL * mu * W, (st["name"], f, ex)
        assert abs(f["slide"] - ex["slide"]) <= TOL * smax, (st["name"], f, ex)
        assert abs(f["normal"] - W) <= TOL * W
        # Coulomb's law: |F| <= mu0 N stuck, = mu N slipping
        assert abs(f["force"]) <= mu0 * W * (1 + 1e-12)
        if f["state"] == "slipping":
            assert abs(abs(f["force"]) - mu * W) <= TOL * mu * W
        # the rod's axial force is the friction force (nothing else acts along it)
        assert abs(st["rods"]["r"]["N_max"] - abs(ex["force"])) <= TOL * mu * W
    # after heating by 20 K and cooling back: residual slide mu W L / EA, locked-in tension mu W
    back = r["steps"][2]
    assert abs(back["friction"]["B"]["slide"] - mu * W * L / EA) <= TOL * mu * W * L / EA
    assert abs(back["reactions"]["A"]["Fx"] + mu * W) <= TOL * mu * W   # the rod is in tension mu W
    # the first breakaway inside step 2: alpha dT EA = mu0 W
    ev = r["events"][0]
    assert ev["step"] == "step2" and ev["kind"] == "slip+"
    assert abs(ev["load_parameter"] * 20.0 * alpha * EA - mu0 * W) <= 1e-9 * mu0 * W


@pytest.mark.parametrize("theory,tol", [("linear", TOL), ("nonlinear", 1e-4)])
def test_deck_on_a_column_and_a_sliding_bearing(theory, tol):
    H, Ld, EI, EA, alpha, W, mu, mu0 = 6.0, 30.0, 2e8, 4e10, 1.2e-5, 5e5, 0.05, 0.08
    s = Structure(gravity=(0.0, 0.0))
    s.rod("col", (0.0, 0.0), (0.0, H), EI=EI, EA=1e12)
    s.rod("deck", (0.0, H), (Ld, H), EI=1e10, EA=EA, alpha=alpha)
    s.weld("base", "col.start", "ground")
    s.pin("top", "deck.start", "col.end")
    s.slider("bearing", "deck.end", "ground", axis=(1.0, 0.0), mu=mu, mu0=mu0)
    s.force("W", "deck.end", force=(0.0, -W))
    s.thermal("T", "deck", dT=1.0, case="thermal")
    temps = (0.0, 25.0, 60.0, 0.0, -50.0, 60.0, 0.0)   # 25 K stays stuck (P = 24.9 kN < mu0 W = 40 kN)
    for i, t in enumerate(temps):
        s.step({"dead": 1.0, "thermal": t}, name=f"{i}: T{t:+g}")
    r = femslide.solve(s, theory=theory)
    k = 1.0 / (H ** 3 / (3 * EI) + Ld / EA)
    # the column and the deck in series are the spring between the column's base and the bearing:
    # P = k (s - e), s the bearing's slide, e the deck's free elongation
    exact = ref.one_slider(k, W, mu, mu0, [alpha * t * Ld for t in temps])
    for st, ex in zip(r["steps"], exact):
        f = st["friction"]["bearing"]
        assert f["state"] == ex["state"], (st["name"], f, ex)
        assert abs(f["force"] - ex["force"]) <= tol * mu0 * W, (st["name"], f, ex)
        # the column carries the friction force as its shear: root moment P H
        assert abs(abs(st["reactions"]["base"]["M"]) - abs(ex["force"]) * H) <= tol * mu0 * W * H
    assert [st["friction"]["bearing"]["state"] for st in r["steps"]].count("slipping") >= 3


def test_thermal_ratcheting_on_an_incline():
    L, EA, alpha, W, mu, mu0 = 8.0, 2e8, 1.2e-5, 2e4, 0.3, 0.35
    beta = math.atan(0.15)
    c, sn = math.cos(beta), math.sin(beta)
    s = Structure(gravity=(0.0, 0.0))
    s.rod("r", (0.0, 0.0), (L * c, L * sn), EI=1e7, EA=EA, alpha=alpha)
    s.slider("low", "r.start", "ground", axis=(c, sn), mu=mu, mu0=mu0)
    s.slider("up", "r.end", "ground", axis=(c, sn), mu=mu, mu0=mu0)
    s.force("W1", "r.start", force=(0.0, -W))
    s.force("W2", "r.end", force=(0.0, -W))
    s.thermal("T", "r", dT=1.0, case="heat")
    temps = [0.0] + [40.0, 0.0] * 3
    for t in temps:
        s.step({"dead": 1.0, "heat": t})
    r = femslide.solve(s)
    N, T = W * c, W * sn
    exact = ref.incline_two_sliders(EA / L, N, T, mu, mu0, [alpha * t * L for t in temps])
    scale = max(max(abs(x["s1"]), abs(x["s2"])) for x in exact)
    for st, ex in zip(r["steps"], exact):
        lo, up = st["friction"]["low"], st["friction"]["up"]
        assert abs(lo["slide"] - ex["s1"]) <= TOL * scale, (st["name"], lo, up, ex)
        assert abs(up["slide"] - ex["s2"]) <= TOL * scale, (st["name"], lo, up, ex)
        assert abs(lo["force"] - ex["F1"]) <= TOL * mu0 * N
        assert abs(up["force"] - ex["F2"]) <= TOL * mu0 * N
    # the walk per cycle (after the first) is the same and downhill
    mid = [0.5 * (st["friction"]["low"]["slide"] + st["friction"]["up"]["slide"]) for st in r["steps"][2::2]]
    walks = [b - a for a, b in zip(mid, mid[1:])]
    assert all(w < -1e-4 for w in walks) and abs(walks[1] - walks[0]) <= TOL * abs(walks[0])
