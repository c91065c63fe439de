"""The errata of SPEC section 6, reproduced numerically: corrected series converge at their order,
the paper's printed formulas do not.

Reference ("exact"): validation/hinge_reference.py, the independent 50-digit solution of the full
spring-hinge models (no series), so that errors down to 1e-15 and c up to 1e22 are measured without
roundoff in the reference.  femslide.scenes.series is evaluated in double precision, as users get it.

Orders (SPEC section 2, epsilon = c^(-1/3)): relative errors of the 1-, 2-, 3-term phi and T decay like
c^(-1/3), c^(-2/3), c^(-1).  Measured log-log slopes (least squares over the stated c-range) must be
within 0.02 of those.  Ranges: sections 2 and 3 (c = 1e6 .. 1e12); section 4 at k = 100 only where
its asymptotic regime holds - its second coefficient a2 = l1^2 [P(l+b) - 4ka^2]/(6a^2 a1) is -58
(against 2.4 for a1), so the next terms dominate until c ~ 1e11 for T and c ~ 1e16 for phi (the
local slope of the 2-term phi error is -1.1 at c = 1e6 .. 1e12, and the error changes sign near
c = 1e13); those ranges are c = 1e11 .. 1e16 for T and 1e16 .. 1e20 for phi (above 1e20 the 2-term
phi error, 5e-14, meets double roundoff).
"""
from __future__ import annotations

import math
import pathlib
import sys
from functools import lru_cache

import pytest

_HERE = pathlib.Path(__file__).resolve().parent
for _p in (str(_HERE.parent), str(_HERE)):
    if _p not in sys.path:
        sys.path.insert(0, _p)

import hinge_reference as ref  # noqa: E402

from femslide.scenes import series  # noqa: E402

GEOM = dict(a=1.0, b=0.5, d=0.2, l=3.0, l1=1.5, m=1.0, g=9.81)
K = 100.0
SLOPE_TOL = 0.02


def _grid(lo, hi, per_decade=2):
    n = int(round((math.log10(hi) - math.log10(lo)) * per_decade))
    return [10.0 ** (math.log10(lo) + i / per_decade) for i in range(n + 1)]


@lru_cache(maxsize=None)
def exact_mp(model, c):
    r = ref.solve(model, c, **({"k": K} if model == "spring" else {}))
    return r.phi, r.T


def exact(model, c):
    return tuple(float(x) for x in exact_mp(model, c))


def params(model):
    return dict(GEOM, k=K) if model == "spring" else dict(GEOM)


def rel_err(model, quantity, value_fn, c):
    phi, T = exact(model, c)
    want = phi if quantity == "phi" else T
    return abs(value_fn(c) / want - 1.0)


def fitted_slope(cs, errs):
    x = [math.log(c) for c in cs]
    y = [math.log(e) for e in errs]
    mx, my = sum(x) / len(x), sum(y) / len(y)
    return sum((a - mx) * (b - my) for a, b in zip(x, y)) / sum((a - mx) ** 2 for a in x)


# c-ranges where each corrected series is in its asymptotic regime (see the module docstring)
RANGES = {
    ("slider", "phi"): (1e6, 1e12), ("slider", "T"): (1e6, 1e12),
    ("fixed", "phi"): (1e6, 1e12), ("fixed", "T"): (1e6, 1e12),
    ("spring", "phi"): (1e16, 1e20), ("spring", "T"): (1e11, 1e16),
}
NTERMS = {"slider": 3, "fixed": 3, "spring": 2}
CASES = [(m, q, n) for m in ("slider", "fixed", "spring") for q in ("phi", "T")
         for n in range(1, NTERMS[m] + 1)]


def corrected(model, quantity, n):
    f = series.phi_series if quantity == "phi" else series.T_series
    p = params(model)
    return lambda c: f(model, n, c, **p)


@pytest.mark.parametrize("model,quantity,n", CASES, ids=[f"{m}-{q}-{n}term" for m, q, n in CASES])
def test_corrected_series_converge_at_their_order(model, quantity, n):
    """Corrected series of SPEC section 2 (sections 2, 3: 3 terms; section 4: 2 terms).

    Reference: independent exact solution (hinge_reference).  Expected slope of the relative error
    vs c on log-log axes: -n/3.  Tolerance: 0.02 on the least-squares slope over the stated range;
    also the error must actually be small at the top of the range (< 1e-2 * c_top^(-n/3 + 1/3)).
    """
    lo, hi = RANGES[(model, quantity)]
    cs = _grid(lo, hi)
    fn = corrected(model, quantity, n)
    errs = [rel_err(model, quantity, fn, c) for c in cs]
    slope = fitted_slope(cs, errs)
    assert abs(slope + n / 3.0) < SLOPE_TOL, (model, quantity, n, slope, errs)
    assert errs[-1] < 1e-2 * hi ** (-(n - 1) / 3.0)


# --------------------------------------------------------------------------- the paper's print

def T_2_9_power_fixed_only(c, a, b, d, l, l1, m, g, **_):
    """(2.9) with c^(+1/3) but still l instead of l + b in the second term."""
    P = m * g
    return 0.5 * (2 * l1 / a) ** (1 / 3) * (P * P * (a + d) ** 2 * c) ** (1 / 3) + P * l * l1 / (3 * a)


def printed_a3(model, a, b, d, l, l1, m, g, **_):
    """a3 as printed in (2.7) (section 2) or (3.5) (section 3): without the c phi^5 term."""
    P = m * g
    if model == "slider":
        a1 = (0.5 * P * (a + d) * (l1 / a) ** 2) ** (1 / 3)
        a2 = P * (l + b) / (6 * a1) * (l1 / a) ** 2
        return a1, a2, (P * (2 * (l + b) * a2 - (a + d) * a1 ** 2) / (12 * a1) * (l1 / a) ** 2 - a2 ** 2) / a1
    a1 = (P / 8 * (a + d) * (l / a) ** 2) ** (1 / 3)
    a2 = P / 24 * (l + b) / a1 * (l / a) ** 2
    return a1, a2, (P / (48 * a1) * (l / a) ** 2 * (2 * l * a2 - (7 * a + d) * a1 ** 2 + 2 * b * a2)
                    - a2 ** 2) / a1


def test_printed_2_9_does_not_converge():
    """Paper (2.9) as printed (c^(-1/3) and l): T -> P l l1/(3a), finite, while the exact T grows like
    c^(1/3), so its relative error tends to 1, not 0 (SPEC section 6).

    Reference: exact solution.  Checks: error > 0.99 at c = 1e12 and non-decreasing over 1e6..1e12.
    """
    p = params("slider")
    cs = _grid(1e6, 1e12)
    errs = [rel_err("slider", "T", lambda c: series.printed_T_2_9(c, **p), c) for c in cs]
    assert errs[-1] > 0.99
    assert all(e2 >= e1 for e1, e2 in zip(errs, errs[1:]))
    assert fitted_slope(cs, errs) > -0.01


def test_2_9_needs_l_plus_b_too():
    """(2.9) with only the power of c corrected (l kept for l + b) converges one order too slowly: its
    relative error decays like c^(-1/3) (an O(1) error P b l1/(3a) in T), not c^(-2/3).

    Reference: exact solution; slope -1/3 +- 0.02 over c = 1e6 .. 1e12, and the corrected 2-term
    series beats it by > 100x at c = 1e12.
    """
    p = params("slider")
    cs = _grid(1e6, 1e12)
    errs = [rel_err("slider", "T", lambda c: T_2_9_power_fixed_only(c, **p), c) for c in cs]
    assert abs(fitted_slope(cs, errs) + 1 / 3) < SLOPE_TOL
    good = rel_err("slider", "T", corrected("slider", "T", 2), 1e12)
    assert good * 100 < errs[-1]


def test_printed_4_4_does_not_converge():
    """Paper (4.4) as printed (l for l1 in the leading term, spurious (l1 + 1) terms): its leading term
    is (l/l1)^(1/3) times the right one, so the relative error tends to (l/l1)^(1/3) - 1 = 0.2599
    (l = 3, l1 = 1.5), not 0 (SPEC section 6).

    Reference: exact solution (k = 100).  Checks: |slope| < 0.02 over c = 1e11 .. 1e16 and the error
    within 0.005 of 2^(1/3) - 1 at c = 1e16.
    """
    p = params("spring")
    cs = _grid(1e11, 1e16)
    errs = [rel_err("spring", "T", lambda c: series.printed_T_4_4(c, **p), c) for c in cs]
    assert abs(fitted_slope(cs, errs)) < 0.02
    assert errs[-1] == pytest.approx((p["l"] / p["l1"]) ** (1 / 3) - 1, abs=5e-3)


@pytest.mark.parametrize("model", ["slider", "fixed"])
def test_printed_a3_stalls_at_second_order(model):
    """(2.7), (3.5): the printed a3 misses the c phi^5 term of the equilibrium equation, so the 3-term
    phi series with it converges only like the 2-term one: relative error ~ c^(-2/3), not c^(-1).

    Reference: exact solution; slope -2/3 +- 0.02 over c = 1e8 .. 1e12 for the printed a3, while the
    corrected a3 (femslide.scenes.series) reaches -1 (test_corrected_series_converge_at_their_order).
    """
    p = params(model)
    a1, a2, a3 = printed_a3(model, **p)
    ref_a1, ref_a2, ref_a3, _ = series._coeffs(model, **p)
    assert a1 == pytest.approx(ref_a1, rel=1e-14) and a2 == pytest.approx(ref_a2, rel=1e-14)
    assert abs(a3 - ref_a3) > 0.05 * abs(ref_a3)   # -13.24 vs -12.14 (sec. 3), 0.74 vs -1.10 (sec. 2)
    cs = _grid(1e8, 1e12)
    fn = (lambda c: a1 * c ** (-1 / 3) + a2 * c ** (-2 / 3) + a3 / c)
    errs = [rel_err(model, "phi", fn, c) for c in cs]
    assert abs(fitted_slope(cs, errs) + 2 / 3) < SLOPE_TOL


def test_section4_third_coefficient():
    """Section 4's a3 (not in SPEC): re-deriving the expansion of dPi/dphi = 0 (the c phi^5 term
    included) gives a3 = -P (a+d) l1^2 / (24 a^2), the same as section 2 - the k-terms cancel at
    that order.  With it the 3-term phi error decays like c^(-1).

    Reference: exact solution.  Errors of 1e-17 .. 1e-21 are below double precision, so this series
    is summed in mpmath (50 digits) from the SPEC formulas for a1, a2 (k = 100).  Tolerance: slope
    -1 +- 0.02 over c = 1e17 .. 1e21 (where the regime holds, see the module docstring).
    """
    import mpmath as mp
    with mp.workdps(50):
        p = {key: mp.mpf(v) for key, v in params("spring").items()}
        P = p["m"] * p["g"]
        a, d, l1 = p["a"], p["d"], p["l1"]
        a1 = mp.cbrt(P * (a + d) * l1 ** 2 / (2 * a * a))
        a2 = l1 ** 2 * (P * (p["l"] + p["b"]) - 4 * p["k"] * a * a) / (6 * a * a * a1)
        a3 = -P * (a + d) * l1 ** 2 / (24 * a * a)
        cs = _grid(1e17, 1e21)
        errs = []
        for c in cs:
            eps = mp.cbrt(1 / mp.mpf(c))
            errs.append(float(abs((a1 * eps + a2 * eps ** 2 + a3 * eps ** 3) / exact_mp("spring", c)[0] - 1)))
            two = float(abs((a1 * eps + a2 * eps ** 2) / exact_mp("spring", c)[0] - 1))
            assert errs[-1] < two
    assert abs(fitted_slope(cs, errs) + 1.0) < SLOPE_TOL, errs
