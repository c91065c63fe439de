"""FE statics scenes beam-slider and beam-fixed against independent elastica references (issue 3 item 6).

Reference: ``validation/references.py`` - the rods as exact elasticas (massless, loaded at their ends),
integrated by a 30th-order Taylor method and shot with an exact (complex-step) Jacobian; principal
branch by continuation in EI from 1e12 N m^2 (equivalent to ramping gravity from zero).  It shares no
code with femslide's FE (the spring-hinge model only supplies the first starting guess).

Which reference: femslide's default EA = 1e6 EI is finite, and at EI <= 1e2 N m^2 its effect exceeds
SPEC section 3's "< 2e-7" (measured: up to 6.2e-6 in F1 at EI = 1e1, see ``test_EA_effect``).  The
default FE runs are therefore compared with the *extensible* elastica of the same EA (``EA_ratio``
= 1e6); the inextensible reference enters through ``test_EA_effect`` and the asymptotic tests.

Tolerances (each test repeats its own):
* phi, M_max, F1 (A1 Fx), N1 (A1 Fy), N2 (B1 Fy), slide: 1e-6 relative to max(|reference|, floor)
  with floors 1e-6 P, 1e-6 P a, 1e-6 rad, 1e-6 a;
* error_estimate / true relative error of M_max within [1/10, 10] where the true error > 1e-11;
* global statics N1 + N2 = P, F1 + F2 = 0 within 1e-9 P;
* d log M_max / d log EI within 0.01 of 1/3 over the last decade (1e9..1e10); measured log-log
  slopes of the relative error against the 1-term / 2-term asymptotes of SPEC section 3 within 0.05
  of -1/3 / -2/3 (1e8..1e10);
* FE beam-slider vs the spring hinge c = 3 EI/L, l1 = L: the M_max, phi and F1 differences shrink
  monotonically from EI = 1e1 to 1e5 and stay below 1e-7 from 1e6 on.
Run:  pytest -q validation/test_fe_statics.py
"""
from __future__ import annotations

import math
import pathlib
import sys

import numpy as np
import pytest

_HERE = pathlib.Path(__file__).resolve().parent
for _p in (str(_HERE.parent), str(_HERE)):
    if _p not in sys.path:
        sys.path.insert(0, _p)

import references as ref  # noqa: E402

import femslide  # noqa: E402
from femslide.scenes import hinge, series  # noqa: E402

GEOM = dict(a=1.0, b=0.5, d=0.2, l=3.0, m=1.0, g=9.81)
P = GEOM["m"] * GEOM["g"]
EIS = [1e1, 1e2, 1e3, 1e4, 1e6, 1e8, 1e10]
KINDS = {"slider": "beam-slider", "fixed": "beam-fixed"}
RTOL = 1e-6
QUANTITIES = ("phi", "M_max", "F1", "N1", "N2", "slide")
FLOOR = {"phi": 1e-6, "M_max": 1e-6 * P, "F1": 1e-6 * P, "N1": 1e-6 * P, "N2": 1e-6 * P, "slide": 1e-6}


def flat(r):
    rc = r["reactions"]
    return {"phi": r["phi"], "M_max": r["M_max"], "F1": rc["A1"]["Fx"], "N1": rc["A1"]["Fy"],
            "N2": rc["B1"]["Fy"], "F2": rc["B1"]["Fx"], "slide": r["slide"]}


def rel(x, y, q):
    return abs(x - y) / max(abs(y), FLOOR[q])


_FE: dict = {}


def fe(kind, EI, **kw):
    key = (kind, EI, tuple(sorted(kw.items())))
    if key not in _FE:
        _FE[key] = femslide.solve(KINDS[kind], EI=EI, **kw)
    return _FE[key]


def reference(kind, EI, EA_ratio=1e6):
    return ref.solve_structure(kind, EI, EA_ratio=EA_ratio)


CASES = [(k, EI) for k in KINDS for EI in EIS]
IDS = [f"{k}-EI{EI:.0e}" for k, EI in CASES]


@pytest.mark.parametrize("kind,EI", CASES, ids=IDS)
def test_converged(kind, EI):
    """Every default FE run converges (contract key ``converged``).

    Reference: SPEC section 7 contract (the accuracy itself is checked against the elastica in
    test_vs_elastica).  Tolerance: exact (``converged`` is True)."""
    assert fe(kind, EI)["converged"] is True


@pytest.mark.parametrize("kind,EI", CASES, ids=IDS)
def test_vs_elastica(kind, EI):
    """phi, M_max, F1, N1, N2, slide of the default FE run (EA = 1e6 EI) vs the extensible elastica
    with the same EA: 1e-6 relative to max(|ref|, floor)."""
    f, r = flat(fe(kind, EI)), flat(reference(kind, EI))
    errs = {q: rel(f[q], r[q], q) for q in QUANTITIES}
    bad = {q: e for q, e in errs.items() if not e <= RTOL}
    assert not bad, f"{kind} EI={EI:g}: relative differences {errs}"


@pytest.mark.parametrize("kind,EI", CASES, ids=IDS)
def test_error_estimate(kind, EI):
    """femslide's error_estimate (relative error of M_max) within a factor 10 of the true relative
    error against the extensible elastica, where the true error exceeds 1e-11."""
    res = fe(kind, EI)
    true = abs(res["M_max"] - reference(kind, EI)["M_max"]) / reference(kind, EI)["M_max"]
    est = res["error_estimate"]
    if true <= 1e-11:
        assert est <= 1e-9, f"true error {true:.1e} but estimate {est:.1e}"
        return
    ratio = est / true
    assert 0.1 <= ratio <= 10.0, f"{kind} EI={EI:g}: estimate {est:.2e}, true {true:.2e}, ratio {ratio:.3g}"


@pytest.mark.parametrize("kind,EI", CASES, ids=IDS)
def test_global_statics(kind, EI):
    """Global statics of the structure (SPEC section 1): N1 + N2 = P and F1 + F2 = 0 (no horizontal
    load).  Reference: exact equilibrium of the whole structure.  Tolerance: 1e-9 P."""
    f = flat(fe(kind, EI))
    assert abs(f["N1"] + f["N2"] - P) <= 1e-9 * P
    assert abs(f["F1"] + f["F2"]) <= 1e-9 * P


# SPEC section 3 claims EA/EI = 1e6 changes the results by < 2e-7; measured 3.3e-7 (F1, slider) at
# EI = 1e2 and 6.2e-6 (F1, slider), 3.1e-6 (F1, fixed) at EI = 1e1: the axial strain is ~P/EA.
_EA_XFAIL = pytest.mark.xfail(strict=True, reason="SPEC section 3 '< 2e-7' does not hold for EI <= 1e2 "
                                                  "(axial strain P/EA ~ 1e-6 at EI = 1e1)")
EA_CASES = [pytest.param(k, EI, marks=_EA_XFAIL) if (EI <= 1e2 and not (k == "fixed" and EI == 1e2))
            else (k, EI) for k, EI in CASES]


@pytest.mark.parametrize("kind,EI", EA_CASES, ids=IDS)
def test_EA_effect(kind, EI):
    """SPEC section 3: EA = 1e6 EI changes phi, M_max, F1, N1, N2, slide by < 2e-7 relative (extensible
    vs inextensible elastica; strict xfail where the claim is measured false)."""
    a, b = flat(reference(kind, EI, 1e6)), flat(reference(kind, EI, None))
    errs = {q: rel(a[q], b[q], q) for q in QUANTITIES}
    assert max(errs.values()) < 2e-7, errs


@pytest.mark.parametrize("ea_ratio", [1e8, 1e10, 1e12])
def test_fe_inextensible_limit(ea_ratio):
    """FE with EA = ea_ratio * EI against the inextensible elastica at EI = 1e4 and 1e8 (both scenes):
    1e-6 relative for phi, M_max, F1 (a nearly rigid axial direction must not spoil the bending
    answer; the EA effect itself is < 1e-9 here)."""
    for kind in KINDS:
        for EI in (1e4, 1e8):
            f, r = flat(fe(kind, EI, EA=ea_ratio * EI)), flat(reference(kind, EI, None))
            errs = {q: rel(f[q], r[q], q) for q in ("phi", "M_max", "F1")}
            assert max(errs.values()) <= RTOL, (kind, EI, errs)


# -- M_max(EI): slope and asymptotes (SPEC section 3) --------------------------------------------------

@pytest.mark.parametrize("kind", KINDS)
def test_slope_tends_to_one_third(kind):
    """Local slope d log M_max / d log EI of the FE results: within 0.01 of 1/3 over 1e9..1e10, and
    moving monotonically towards 1/3 over 1e4, 1e6, 1e8, 1e10."""
    M = {EI: fe(kind, EI)["M_max"] for EI in (1e4, 1e6, 1e8, 1e9, 1e10)}
    last = math.log(M[1e10] / M[1e9]) / math.log(10.0)
    assert abs(last - 1 / 3) <= 0.01, last
    s = [math.log(M[b] / M[a]) / math.log(b / a) for a, b in ((1e4, 1e6), (1e6, 1e8), (1e8, 1e10))]
    d = [abs(x - 1 / 3) for x in s]
    assert d[0] > d[1] > d[2], s


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("nterms,order", [(1, -1 / 3), (2, -2 / 3)])
def test_asymptote_error_decay(kind, nterms, order):
    """Relative error of M_max against the 1-term (2-term) asymptote of SPEC section 3
    (femslide.scenes.series.M_max_asymptote, L_r = l) decays like EI^-1/3 (EI^-2/3): the log-log slope of
    the FE errors over 1e8..1e10 within 0.05 of the exponent."""
    err = {}
    for EI in (1e8, 1e10):
        M = fe(kind, EI)["M_max"]
        err[EI] = abs(series.M_max_asymptote(nterms, EI, **GEOM) / M - 1.0)
    slope = math.log(err[1e10] / err[1e8]) / math.log(100.0)
    assert abs(slope - order) <= 0.05, slope


def test_slider_vs_hinge():
    """FE beam-slider vs the exact spring-hinge model (section 2) with c = 3 EI/L, l1 = L: relative
    differences of M_max, phi, F1 shrink monotonically over EI = 1e1..1e5 and are < 1e-7 at 1e6..1e10."""
    L = GEOM["l"]
    d = {}
    for EI in (1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e8, 1e10):
        f = flat(fe("slider", EI))
        h = hinge.solve_slider(**GEOM, c=3 * EI / L, l1=L)
        hf = flat(h)
        d[EI] = max(rel(f[q], hf[q], q) for q in ("M_max", "phi", "F1"))
    seq = [d[EI] for EI in (1e1, 1e2, 1e3, 1e4, 1e5)]
    assert all(x > y for x, y in zip(seq, seq[1:])), d
    assert all(d[EI] < 1e-7 for EI in (1e6, 1e8, 1e10)), d


# -- the reference itself ------------------------------------------------------------------------------

@pytest.mark.parametrize("kind", KINDS)
def test_reference_self_convergence(kind):
    """The Taylor shooting is converged: order 40 with steps 0.15/omega changes phi, M_max, slide, Q of
    the reference (order 30, 0.4/omega) by < 1e-13 relative at EI = 1e1, 1e3, 1e10."""
    for EI in (1e1, 1e3, 1e10):
        for ea in (None, 1e6):
            a = reference(kind, EI, ea)
            st = ref._Structure(kind, **GEOM, EA_ratio=ea)
            x0 = np.array([a["theta0"] - (0.5 * math.pi - a["phi"]), a["Q"] / P, a["phi"]])
            old = ref.H_OMEGA, ref.ORDER
            try:
                ref.H_OMEGA, ref.ORDER = 0.15, 40
                b = st.result(st.solve(EI / P, x0), EI / P)
            finally:
                ref.H_OMEGA, ref.ORDER = old
            for q in ("phi", "M_max", "slide", "Q"):
                assert abs(b[q] - a[q]) <= 1e-13 * abs(a[q]) + 1e-15, (EI, ea, q, a[q], b[q])


@pytest.mark.parametrize("kind", KINDS)
def test_reference_path_is_principal(kind):
    """The reference's continuation in EI (= ramping gravity, since only EI/(P a^2) and EA/P enter) is
    one smooth branch: phi grows monotonically as EI falls from 1e12 to 1e1 and the shooting Jacobian
    keeps its sign (no fold or bifurcation crossed), so it is the principal branch.
    Reference: the elastica shooting itself (references.py).  Tolerance: exact sign and monotonicity
    checks, no numeric threshold."""
    for ea in (None, 1e6):
        key = ref._key({**ref.DEFAULTS, **({"L": None} if kind == "slider" else {}), "EA_ratio": ea})
        path = ref._path(kind, key)
        st = ref._Structure(kind, **dict(key))
        ks = sorted(path, reverse=True)
        phis = [path[k][2] for k in ks]
        assert all(b > a for a, b in zip(phis, phis[1:]))
        dets = [np.linalg.det(st.jac(path[k], 10 ** (k / ref.N_PER_DECADE) / P)[1]) for k in ks]
        assert all(np.sign(x) == np.sign(dets[0]) for x in dets)


def test_reference_statics_and_hinge_limit():
    """Reference checks: the beam-slider elastica's moment balance about A1, 2a N2 = P x_G with
    x_G = (l + b) sin(phi) + (a + d) cos(phi) of the body turned by phi about A1 (1e-10 P a; the
    reference builds N1 + N2 = P and F1 + F2 = 0 in by construction, so those are not checked, and
    beam-fixed's x_G needs the rod shape); at EI = 1e8 the beam-slider elastica and the spring hinge
    c = 3EI/L, l1 = L agree to 1e-10 (both exact; they differ at O(EI^-1) relative)."""
    g = GEOM
    for EI in EIS:
        r = flat(reference("slider", EI, None))
        x_G = (g["l"] + g["b"]) * math.sin(r["phi"]) + (g["a"] + g["d"]) * math.cos(r["phi"])
        assert abs(2 * g["a"] * r["N2"] - P * x_G) <= 1e-10 * P * g["a"]
    r = flat(reference("slider", 1e8, None))
    h = flat(hinge.solve_slider(**GEOM, c=3e8 / GEOM["l"], l1=GEOM["l"]))
    assert max(rel(r[q], h[q], q) for q in ("M_max", "phi", "F1", "N2")) < 1e-10
