"""Independent reference for uplift (issue 24, SPEC 9.4): Housner's rocking rigid block.

A rigid rectangular block (half-width b, half-height h, mass m, inertia J about its centroid) stands on
rigid ground with friction high enough that it never slides; released from a tilt theta0 (about one
bottom corner, at rest) it rocks: between impacts it turns about one corner O (R = sqrt(b^2 + h^2),
alpha = atan(b / h), I_O = J + m R^2)

    I_O theta'' = -m g R sin(alpha sgn(theta) - theta)          (Housner 1963, exact, nonlinear)

and when theta reaches 0 the other corner lands: a perfectly plastic impact there (no bounce, no
slip) and the first corner lifts at once.  The angular momentum about the landing corner is kept:

    theta'+ = r theta'-,   r = 1 - 2 m R^2 sin^2(alpha) / I_O   (= 1 - 3/2 sin^2(alpha) for J = m R^2 / 3,
                                                                  the uniform rectangle)

The motion between impacts is integrated here with scipy's solve_ivp (DOP853, rtol 1e-13) and each
impact located as an event (theta = 0); the amplitude after each impact follows in closed form from
energy conservation, I_O w^2 / 2 = m g R (cos(alpha - theta_max) - cos(alpha)) (the centroid's
rise).  Nothing of femslide is used.  :func:`housner` returns the impacts; run as a script it
prints them for a sample block.
"""
from __future__ import annotations

import math

from scipy.integrate import solve_ivp


def housner(b, h, theta0, n_impacts=5, m=1.0, J=None, g=9.81, rtol=1e-13, atol=1e-15):
    """The first ``n_impacts`` impacts of the block released at rest from theta0 (0 < |theta0| < alpha,
    rad; its sign picks the corner it starts on): a list of dicts {t [s], w_minus, w_plus [rad/s]
    (before and after), amplitude [rad] (the largest |theta| of the swing after it)}."""
    R = math.hypot(b, h)
    alpha = math.atan2(b, h)
    J = m * R * R / 3.0 if J is None else J
    I_O = J + m * R * R
    if not 0.0 < abs(theta0) < alpha:
        raise ValueError(f"theta0 = {theta0}: the block must start tilted and stable, 0 < |theta0| < {alpha}")
    r = 1.0 - 2.0 * m * R * R * math.sin(alpha) ** 2 / I_O
    k = m * g * R / I_O

    def rhs(t, z, side):
        return [z[1], -k * math.sin(alpha * side - z[0])]

    def hit(t, z, side):
        return z[0]
    hit.terminal = True

    t, z, side = 0.0, [theta0, 0.0], (1.0 if theta0 > 0 else -1.0)
    out = []
    for _ in range(n_impacts):
        hit.direction = -side
        sol = solve_ivp(rhs, (t, t + 1e3), z, method="DOP853", events=hit, args=(side,), rtol=rtol, atol=atol)
        if not sol.t_events[0].size:
            raise RuntimeError("no impact found")
        t = float(sol.t_events[0][0])
        w_minus = float(sol.y_events[0][0][1])
        w_plus = r * w_minus
        side = -side
        # the swing after: energy conservation about the new corner
        c = math.cos(alpha) + I_O * w_plus * w_plus / (2.0 * m * g * R)
        amp = alpha - math.acos(c) if c < 1.0 else float("nan")   # (c >= 1: it overturns)
        out.append({"t": t, "w_minus": w_minus, "w_plus": w_plus, "amplitude": amp})
        z = [0.0, w_plus]
    return out


def bouncing_bar(m, J, d, beta, theta0, e, n_impacts=5, g=9.81, rtol=1e-13, atol=1e-15):
    """The first ``n_impacts`` impacts of a rigid bar pinned to the ground at one end, released at
    rest from theta0 > 0 (rad, counter-clockwise) onto a contact under its other end (at theta = 0)
    with restitution e: between impacts I_P theta'' = -m g d cos(theta + beta) (I_P = J + m d^2 its
    inertia about the pin, d the pin-to-centroid distance, beta that line's angle above the bar's
    bottom edge), at an impact theta'+ = -e theta'- (the contact's normal velocity reverses times e;
    the pin takes the rest of the impulse).  A list of dicts {t [s], w_minus, w_plus [rad/s]}."""
    I_P = J + m * d * d

    def rhs(t, z):
        return [z[1], -m * g * d * math.cos(z[0] + beta) / I_P]

    def hit(t, z):
        return z[0]
    hit.terminal, hit.direction = True, -1

    t, z, out = 0.0, [theta0, 0.0], []
    for _ in range(n_impacts):
        sol = solve_ivp(rhs, (t, t + 1e3), z, method="DOP853", events=hit, rtol=rtol, atol=atol, first_step=1e-6)
        if not sol.t_events[0].size:
            raise RuntimeError("no impact found")
        t = float(sol.t_events[0][0])
        w_minus = float(sol.y_events[0][0][1])
        out.append({"t": t, "w_minus": w_minus, "w_plus": -e * w_minus})
        z = [0.0, -e * w_minus]
    return out


def release_energy_check(b, h, theta0, m=1.0, J=None, g=9.81):
    """The angular velocity at the first impact from energy conservation alone (no integration):
    |w| = sqrt(2 m g R (cos(alpha - theta0) - cos(alpha)) / I_O)."""
    R = math.hypot(b, h)
    alpha = math.atan2(b, h)
    J = m * R * R / 3.0 if J is None else J
    I_O = J + m * R * R
    return math.sqrt(2.0 * m * g * R * (math.cos(alpha - abs(theta0)) - math.cos(alpha)) / I_O)


if __name__ == "__main__":
    b, h, th0 = 0.2, 0.6, 0.1
    for k, imp in enumerate(housner(b, h, th0, 6)):
        print(f"impact {k + 1}: t = {imp['t']:.12f} s, w- = {imp['w_minus']:+.12f}, w+ = {imp['w_plus']:+.12f} "
              f"rad/s, amplitude after = {imp['amplitude']:.12f} rad")
    print("energy check of the first impact:", release_energy_check(b, h, th0))
    print("r = 1 - 3/2 sin^2(alpha) =", 1 - 1.5 * math.sin(math.atan2(b, h)) ** 2)
