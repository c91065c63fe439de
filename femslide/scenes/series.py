"""Asymptotic series of the spring-hinge models in epsilon = c^(-1/3) (SPEC section 2, corrected).

phi = a1 eps + a2 eps^2 + a3 eps^3 and the hinge moment T = c chi(phi) expanded to the same order:
with chi = kappa (phi^2 - phi^4/12) + O(phi^6) (kappa = a/l1 for sections 2 and 4, -2a/l for
section 3),
    T = kappa [a1^2 eps^-1 + 2 a1 a2 + (a2^2 + 2 a1 a3 - a1^4/12) eps] + O(eps^2).
The relative errors of the 1-, 2- and 3-term T decay like c^(-1/3), c^(-2/3), c^(-1).

``printed_*`` are the paper's formulas as printed, kept for the errata tests (SPEC section 6).
Section 4's a3 is not given in SPEC, so its series stop at two terms.
"""
from __future__ import annotations

import math


def _coeffs(model, a, b, d, l, l1, m, g, k=0.0, **_):
    P = m * g
    if model == "slider":
        a1 = math.copysign(abs(P * (a + d) * l1 ** 2 / (2 * a * a)) ** (1 / 3), a + d)
        a2 = P * (l + b) * l1 ** 2 / (6 * a * a * a1)
        a3 = -P * (a + d) * l1 ** 2 / (24 * a * a)
        return a1, a2, a3, a / l1
    if model == "spring":
        a1 = math.copysign(abs(P * (a + d) * l1 ** 2 / (2 * a * a)) ** (1 / 3), a + d)
        a2 = l1 ** 2 * (P * (l + b) - 4 * k * a * a) / (6 * a * a * a1)
        return a1, a2, None, a / l1
    if model == "fixed":
        a1 = math.copysign(abs(P * (a + d) * l ** 2 / (8 * a * a)) ** (1 / 3), a + d)
        a2 = P * (l + b) * l ** 2 / (24 * a * a * a1)
        a3 = -P * (13 * a + d) * l ** 2 / (96 * a * a)
        return a1, a2, a3, -2 * a / l
    raise ValueError(f"model must be 'slider', 'spring' or 'fixed', got {model!r}")


def phi_series(model: str, nterms: int, c: float, **p) -> float:
    """phi [rad] from the corrected series with ``nterms`` (1..3) terms."""
    a1, a2, a3, _ = _coeffs(model, **p)
    terms = [a1, a2, a3][:nterms]
    if None in terms:
        raise ValueError(f"{nterms}-term series not available for model {model!r}")
    eps = c ** (-1.0 / 3.0)
    return sum(t * eps ** (i + 1) for i, t in enumerate(terms))


def T_series(model: str, nterms: int, c: float, **p) -> float:
    """Signed hinge moment T [N m] from the corrected series with ``nterms`` (1..3) terms."""
    a1, a2, a3, kappa = _coeffs(model, **p)
    eps = c ** (-1.0 / 3.0)
    out = a1 * a1 / eps
    if nterms >= 2:
        out += 2 * a1 * a2
    if nterms >= 3:
        if a3 is None:
            raise ValueError(f"3-term series not available for model {model!r}")
        out += (a2 * a2 + 2 * a1 * a3 - a1 ** 4 / 12) * eps
    return kappa * out


def printed_T_2_9(c, a, b, d, l, l1, m, g, **_):
    """Paper eq. (2.9) as printed (wrong power of c, l instead of l + b)."""
    P = m * g
    return 0.5 * (2 * l1 / a) ** (1 / 3) * (P * P * (a + d) ** 2 / c) ** (1 / 3) + P * l * l1 / (3 * a)


def printed_T_4_4(c, a, b, d, l, l1, m, g, k, **_):
    """Paper eq. (4.4) as printed (l for l1 in the leading term, spurious (l1 + 1) terms)."""
    P = m * g
    return (0.5 * (2 * l * c / a) ** (1 / 3) * (P * (a + d)) ** (2 / 3)
            + (P * l1 ** 2 - 2 * k * (l1 + 1) ** 2 * a * a) / (3 * a * l1))


def M_max_asymptote(nterms: int, EI: float, a, b, d, l, m, g, L_r=None, **_):
    """Beam-equivalent asymptote of M_max [N m] (SPEC section 3): 1 or 2 terms.

    M_max = (3 EI/(4a))^(1/3) (P(a+d))^(2/3) + P (l+b) L_r/(3a); L_r is the flexible rod's length.
    """
    P = m * g
    L_r = l if L_r is None else L_r
    out = (3 * EI / (4 * a)) ** (1 / 3) * (P * abs(a + d)) ** (2 / 3)
    if nterms >= 2:
        out += P * (l + b) * L_r / (3 * a)
    return out
