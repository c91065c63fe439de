"""The Newton start of the structure scenes (femslide.predictor): the deformed spring-hinge mechanism.

Checked against what it promises: no axial strain, the rotational locks and rigid joints satisfied
exactly, the sliding clamp's transverse lock up to the O(h^2) of laying the elements end to end, and a
start good enough for a controlled Newton solve to converge in a handful of iterations.
"""
import numpy as np
import pytest

from femslide import corotational
from femslide.newton import newton
from femslide.predictor import mechanism_state
from femslide.scenes import SCENES
import femslide.statics as st

CASES = [("beam-slider", st.build_slider), ("beam-fixed", st.build_fixed),
         ("beam-both", st.build_both), ("beam-spring", st.build_spring)]


def _built(scene, build, n, EI=1e4):
    v = SCENES[scene].resolve({"EI": EI, "n_elements": n})
    return build(v, n)


@pytest.mark.parametrize("scene,build", CASES)
@pytest.mark.parametrize("phi", [0.01, 0.3, 1.0])
def test_state_is_a_strain_free_mechanism(scene, build, phi):
    bt = _built(scene, build, 8)
    m = bt.model
    y, alpha = mechanism_state(bt, phi)
    q = y[:m.n_q]
    assert q[m.body.dof0 + 2] == pytest.approx(-phi, abs=1e-15)
    _, _, u_bar, a2, _, _ = corotational.basic_deformations(m.elements, m.nodal(q), alpha)
    assert np.abs(u_bar).max() <= 1e-13          # elements laid end to end with their lengths
    assert np.abs(a2 - alpha).max() <= 1e-12       # alpha is the chord rotation of the state
    for c in m.constraints:
        g = c.eval(q[c.dofs])[0]
        if type(c).__name__ == "SlidingClamp":
            assert abs(g[1]) <= 1e-14                    # the top turns with the body
            assert abs(g[0]) <= 0.02 * phi * phi + 1e-14   # on the guide up to O(h^2)
        elif type(c).__name__ == "Weld":
            assert abs(g[2]) <= 1e-14
            assert np.abs(g[:2]).max() <= 0.02 * phi * phi + 1e-14
        else:  # ground pins, body pin, guide line: exact
            assert np.abs(g).max() <= 1e-12


@pytest.mark.parametrize("scene,build", CASES)
def test_controlled_newton_from_the_prediction_is_short(scene, build):
    """At the equilibrium's own rotation the prediction is within Newton's quadratic range."""
    bt = _built(scene, build, 8)
    m = bt.model
    th = m.body.dof0 + 2
    y_eq, *_ = st._solve_structure(bt)
    phi = -y_eq[th] * bt.phi_dir
    y, alpha = mechanism_state(bt, phi)
    z = np.concatenate([y, [1.0]])
    _, info = newton(m, z, alpha, control=(th, -bt.phi_dir * phi))
    assert info.converged and info.iterations <= 6, info


def test_guide_out_of_reach_gives_no_state():
    bt = _built("beam-fixed", st.build_fixed, 4)
    assert mechanism_state(bt, 3.0) is None
