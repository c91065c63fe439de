"""The paper's spring-hinge models (SPEC section 2), solved exactly: no series, no linearisation.

A rod is split by a hinge carrying a spiral spring of stiffness c [N m/rad]; the lower piece turns
by psi, the upper piece (locked to the body) by phi, both from the vertical, positive clockwise
(towards B1).  The hinge moment is T = c (psi - phi) [N m].  Each model reduces to one unknown phi
with the kinematic constraint giving chi = psi - phi; the equilibrium is the first root of
dPi/dphi met when phi grows from 0 towards the side the load pushes (the principal branch, the
state reached by ramping gravity from zero).

Reactions (N1, F1) at A1 and (N2, F2) at B1 are forces by the ground on the structure [N], F
horizontal (+x), N vertical (+y).  The slide s [m] is the advance of the rod's top end past its
initial position along the guide direction e = (sin phi, cos phi).

Pure Python (``math`` only): a spring-hinge solve as a whole process takes well under 0.1 s.
"""
from __future__ import annotations

import math

from femslide.analysis.events import NoRoot, first_crossing
from femslide.errors import BadInput, SolverFailure
from femslide.records import dataclass


class NoEquilibrium(SolverFailure):
    """The principal branch has no equilibrium in the admissible range (exit status 1)."""


@dataclass(frozen=True)
class Kinematics:
    """chi = psi - phi as a function of phi: sin chi = s0 * sin^2(phi/2) (``s0`` signed)."""

    s0: float  # sec. 2/4/5: 4a/l1 ; sec. 3: -8a/l

    def phi_max(self) -> float:
        # |sin chi| <= 1  <=>  sin^2(phi/2) <= 1/|s0|
        r = 1.0 / abs(self.s0)
        return math.pi if r >= 1.0 else 2.0 * math.asin(math.sqrt(r))

    def chi(self, phi: float) -> tuple[float, float]:
        """(chi, dchi/dphi); 1 - cos phi is written 2 sin^2(phi/2) to keep precision at tiny phi."""
        sh = math.sin(0.5 * phi)
        u = self.s0 * sh * sh
        u = max(-1.0, min(1.0, u))
        cchi = math.sqrt(max(0.0, (1.0 - u) * (1.0 + u)))
        du = 0.5 * self.s0 * math.sin(phi)
        dchi = du / cchi if cchi > 0.0 else math.copysign(math.inf, du)
        return math.asin(u), dchi


def _solve_branch(dpi, kin: Kinematics, phi_guess: float, d2pi0: float) -> tuple[float, int]:
    """Principal equilibrium of dPi/dphi = ``dpi(phi)``.

    ``d2pi0`` is the stiffness at phi = 0 (used only when phi = 0 is itself an equilibrium).
    """
    g0 = dpi(0.0)
    if g0 == 0.0 and d2pi0 > 0.0:
        return 0.0, 1
    sign = 1.0 if g0 <= 0.0 else -1.0  # the load pushes towards -g0
    g = (lambda x: sign * dpi(sign * x))
    x_max = kin.phi_max()
    start = min(0.5 * abs(phi_guess), 1e-3) if phi_guess else 1e-3
    start = max(start, 1e-300)
    # the scan must start below the root: shrink until g < 0 there
    n = 0
    while g(start) >= 0.0 and start > 1e-300:
        start *= 1e-3
        n += 1
    try:
        x, k = first_crossing(g, start, x_max)
    except NoRoot as exc:
        raise NoEquilibrium(f"no equilibrium on the principal branch: {exc} "
                            f"(rotation limit of the hinge geometry {x_max:g} rad)") from None
    return sign * x, n + k


def _result(phi, chi, T, N1, F1, N2, F2, slide, evals):
    return {
        "converged": True,
        "phi": phi,
        "psi": phi + chi,
        "slide": slide,
        "T": T,
        "M_max": abs(T),
        "reactions": {"A1": {"Fx": F1, "Fy": N1}, "B1": {"Fx": F2, "Fy": N2}},
        "iterations": evals,
        "error_estimate": 0.0,
    }


def _series_guess(P, a, d, lc, c, factor):
    """Leading-order phi = (P (a+d) lc^2 / (factor a^2 c))^(1/3), signed (start of the scan)."""
    x = P * abs(a + d) * lc * lc / (factor * a * a * c)
    return math.copysign(x ** (1.0 / 3.0), a + d) if x > 0 else 0.0


def solve_slider(a, b, d, l, l1, m, g, c, k=0.0, **_):
    """Sections 2 and 4: rigid fixed rod, right rod with hinge B3 at height l1 (spring k if > 0)."""
    P = m * g
    kin = Kinematics(4.0 * a / l1)

    def dpi(phi):
        chi, dchi = kin.chi(phi)
        out = -P * ((l + b) * math.sin(phi) + (a + d) * math.cos(phi)) + c * chi * dchi
        if k:
            delta = 2 * a * math.sin(phi) - 2 * l1 * math.sin(0.5 * chi) ** 2
            ddelta = 2 * a * math.cos(phi) - l1 * math.sin(chi) * dchi
            out += k * delta * ddelta
        return out

    d2 = -P * (l + b) + 4 * a * a * k
    phi, n = _solve_branch(dpi, kin, _series_guess(P, a, d, l1, c, 2.0), d2)
    return _slider_reactions(phi, kin, a, b, d, l, l1, P, c, n, m1=0.0, l2=0.0, g=g)


def _slider_reactions(phi, kin, a, b, d, l, l1, W, c, n, m1, l2, g):
    chi, _ = kin.chi(phi)
    psi = phi + chi
    T = c * chi
    x_G = (l + b) * math.sin(phi) + (a + d) * math.cos(phi)
    x_G1 = 2 * a + l1 * math.sin(psi) + 0.5 * l2 * math.sin(phi)
    N2 = (W * x_G + m1 * g * x_G1) / (2 * a)
    F2 = (N2 * l1 * math.sin(psi) - T) / (l1 * math.cos(psi))
    N1 = W + m1 * g - N2
    slide = 2 * a * math.sin(phi) - 2 * l1 * math.sin(0.5 * chi) ** 2
    return _result(phi, chi, T, N1, -F2, N2, F2, slide, n)


def solve_fixed(a, b, d, l, m, g, c, **_):
    """Section 3: left rod with hinge A2 at l/2, right rod rigid in the sliding clamp."""
    P = m * g
    kin = Kinematics(-8.0 * a / l)

    def dpi(phi):
        chi, dchi = kin.chi(phi)
        psi = phi + chi
        return (P * (-(0.5 * l) * math.sin(psi) * (1.0 + dchi) - (0.5 * l + b) * math.sin(phi)
                     - (a + d) * math.cos(phi)) + c * chi * dchi)

    phi, n = _solve_branch(dpi, kin, _series_guess(P, a, d, l, c, 8.0), -P * (l + b))
    chi, _ = kin.chi(phi)
    psi = phi + chi
    T = c * chi
    x_G = 0.5 * l * math.sin(psi) + (0.5 * l + b) * math.sin(phi) + (a + d) * math.cos(phi)
    N2 = P * x_G / (2 * a)
    # the rigid right rod is loaded only at its ends: the ground force is normal to the guide
    F2 = -N2 * math.cos(phi) / math.sin(phi) if phi != 0.0 else 0.0
    slide = 2 * a * math.sin(phi) + l * math.sin(0.5 * chi) ** 2
    return _result(phi, chi, T, P - N2, -F2, N2, F2, slide, n)


def k_crit(a, b, l, l1, m, g, m1, l2, **_):
    """Section 5.1: below this slider-spring stiffness [N/m] the vertical state is unstable."""
    return (m * g * (l + b) + m1 * g * (l1 + 0.5 * l2)) / (4 * a * a)


def solve_extra_mass(a, b, d, l, l1, m, g, c, k, dm, m1, l2, **_):
    """Section 5.1: slider spring preloaded so that phi = 0 at dm = 0; telescopic piece m1, l2."""
    kc = k_crit(a, b, l, l1, m, g, m1, l2)
    if not k > kc:
        raise BadInput(f"parameter k = {k:g} N/m is not above k_crit = {kc:.6g} N/m: the vertical "
                       f"state is unstable even at dm = 0; allowed: k > {kc:.6g}")
    P = m * g
    W = (m + dm) * g
    F_el = P * (a + d) / (2 * a)
    kin = Kinematics(4.0 * a / l1)

    def dpi(phi):
        chi, dchi = kin.chi(phi)
        psi = phi + chi
        sc = math.sin(chi)
        delta = 2 * a * math.sin(phi) - 2 * l1 * math.sin(0.5 * chi) ** 2
        ddelta = 2 * a * math.cos(phi) - l1 * sc * dchi
        # -(m+dm) g (a+d) cos(phi) + F_el 2a cos(phi) = -dm g (a+d) cos(phi): cancelled by hand
        return (-W * (l + b) * math.sin(phi) - dm * g * (a + d) * math.cos(phi)
                - F_el * l1 * sc * dchi + k * delta * ddelta
                - m1 * g * (l1 * math.sin(psi) * (1.0 + dchi) + 0.5 * l2 * math.sin(phi))
                + c * chi * dchi)

    d2 = 4 * a * a * k - W * (l + b) - m1 * g * (l1 + 0.5 * l2)
    # leading-order guess: linear when the spring dominates
    guess = dm * g * (a + d) / d2 if d2 > 0 else 0.0
    phi, n = _solve_branch(dpi, kin, guess, d2)
    return _slider_reactions(phi, kin, a, b, d, l, l1, W, c, n, m1=m1, l2=l2, g=g)
