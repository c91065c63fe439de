"""The Newton start of the structure scenes (femslide.scenes.predictor): the deformed spring-hinge mechanism.

Checked against what it promises: no axial strain, the rotational locks and rigid joints satisfied
exactly, the sliding clamp's transverse lock up to the O(h^2) of laying the elements end to end, and a
start good enough for a controlled Newton solve to converge in a handful of iterations.
"""
import numpy as np
import pytest

from femslide.analysis import static
from femslide.analysis.newton import newton
from femslide.elements import corotational
from femslide.joints.holds import DofHold
from femslide.model.discrete import Model
from femslide.scenes import paper
from femslide.scenes.catalog import SCENES
from femslide.scenes.predictor import mechanism_state

CASES = ["beam-slider", "beam-fixed", "beam-both", "beam-spring"]


def _model(scene, n, EI=1e4):
    v = SCENES[scene].resolve({"EI": EI, "n_elements": n})
    fs = paper.declare(scene, v).freeze()
    return Model(fs, {r.name: n for r in fs.rods}, *paper.units(scene, v)), v


@pytest.mark.parametrize("scene", CASES)
@pytest.mark.parametrize("phi", [0.01, 0.3, 1.0])
def test_state_is_a_strain_free_mechanism(scene, phi):
    m, _ = _model(scene, 8)
    y, elements = mechanism_state(m, -phi)
    alpha = elements.committed
    q = y[:m.n_q]
    assert q[m.body_dof("deck") + 2] == pytest.approx(-phi, abs=1e-15)
    _, _, u_bar, a2, _, _ = corotational.basic_deformations(m.elements, m.nodal(q), alpha)
    assert np.abs(u_bar).max() <= 1e-13          # elements laid end to end with their lengths
    assert np.abs(a2 - alpha).max() <= 1e-12       # alpha is the chord rotation of the state
    for c in m.constraints:
        g = c.eval(q[c.dofs])[0]
        flex = c.ia is not None and c.dofs[0] < 3 * m.n_nodes   # a rod end on side a
        if c.kind == "slider" and flex:
            assert abs(g[1]) <= 1e-14                    # the top turns with the body
            assert abs(g[0]) <= 0.02 * phi * phi + 1e-14   # on the guide up to O(h^2)
        elif c.kind == "weld" and flex:
            assert abs(g[2]) <= 1e-14
            assert np.abs(g[:2]).max() <= 0.02 * phi * phi + 1e-14
        else:  # ground pins, rigid rods: exact
            assert np.abs(g).max() <= 1e-12


@pytest.mark.parametrize("scene", CASES)
def test_controlled_newton_from_the_prediction_is_short(scene):
    """At the equilibrium's own rotation the prediction is within Newton's quadratic range."""
    m, v = _model(scene, 8)
    th = m.body_dof("deck") + 2
    path = paper.path(scene, v)
    y_eq, _, _ = static.solve_level(m, path)
    y, elements = mechanism_state(m, y_eq[th])
    z = np.concatenate([y, [1.0]])
    _, info = newton(m, z, elements, control=DofHold(th, y_eq[th]))
    assert info.converged and info.iterations <= 6, info


def test_guide_out_of_reach_gives_no_state():
    m, _ = _model("beam-fixed", 4)
    assert mechanism_state(m, -3.0) is None
