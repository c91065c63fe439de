"""The rocking-block reference (validation/rocking_reference.py) against what is known of it in closed
form: the angular velocity at the first impact by energy conservation (1e-10), Housner's ratio
1 - 3/2 sin^2(alpha) between the angular velocities after and before each impact (exact), the
amplitude after an impact reached by the next swing's quarter (energy, 1e-10), and for a slender block
at a small tilt the linearised impact time acosh(1 / (1 - theta0 / alpha)) / p, p^2 = 3 g / (4 R)
(within the linearisation's error: 2e-3 relative at alpha = 0.05)."""
import math
import os
import sys

import pytest

sys.path.insert(0, os.path.dirname(__file__))
from rocking_reference import housner, release_energy_check  # noqa: E402


def test_first_impact_velocity_by_energy():
    b, h, th0 = 0.2, 0.6, 0.1
    imp = housner(b, h, th0, 1)[0]
    assert abs(imp["w_minus"]) == pytest.approx(release_energy_check(b, h, th0), rel=1e-10)


def test_housner_ratio_and_amplitudes():
    b, h, th0 = 0.2, 0.6, 0.12
    alpha = math.atan2(b, h)
    r = 1 - 1.5 * math.sin(alpha) ** 2
    imps = housner(b, h, th0, 4)
    for a, nxt in zip(imps, imps[1:]):
        assert a["w_plus"] == pytest.approx(r * a["w_minus"], rel=1e-15)
        # the next impact comes with the speed the amplitude's energy gives (conservative between)
        assert abs(nxt["w_minus"]) == pytest.approx(release_energy_check(b, h, a["amplitude"]), rel=1e-10)
        assert nxt["t"] > a["t"]


def test_slender_block_small_tilt_against_the_linearised_time():
    b, h = 0.05, 1.0
    alpha = math.atan2(b, h)
    th0 = 0.2 * alpha
    R = math.hypot(b, h)
    p = math.sqrt(3 * 9.81 / (4 * R))
    t_lin = math.acosh(1 / (1 - th0 / alpha)) / p
    assert housner(b, h, th0, 1)[0]["t"] == pytest.approx(t_lin, rel=2e-3)
