"""femslide.results.compare: the differences of two runs' histories, peaks and events."""
import numpy as np
import pytest

from femslide.results.compare import event_difference, history_difference, interpolate, peak_difference


def test_interpolation_is_exact_for_quintics_and_keeps_to_its_segment():
    """Local Lagrange interpolation through six samples reproduces a quintic to round-off on an
    uneven grid; across a break (a jump) each side uses only its own samples; a time that is a
    sample takes the sample."""
    rng = np.random.default_rng(3)
    ta = np.sort(rng.uniform(0.0, 2.0, 40))
    ta[0], ta[-1] = 0.0, 2.0
    p = np.poly1d([0.3, -1.0, 0.5, 2.0, -0.7, 1.1])
    tb = np.linspace(0.0, 2.0, 57)
    xi = interpolate(ta, p(ta)[:, None], tb)[:, 0]
    assert np.abs(xi - p(tb)).max() < 1e-11
    # a step of 1 at the break tb = 1.0 (the sample at the break belongs to the segment after it)
    brk = 1.0
    ta2 = np.sort(np.concatenate([ta, [brk]]))
    xa = p(ta2) + (ta2 >= brk)
    xi2 = interpolate(ta2, xa[:, None], tb, breaks=[brk])[:, 0]
    assert np.abs(xi2 - (p(tb) + (tb >= brk))).max() < 1e-10
    assert interpolate(ta, p(ta)[:, None], [ta[7]])[0, 0] == p(ta)[7]


def test_history_difference_is_relative_and_skips_windows():
    """The largest difference per column relative to the column's largest value (positions from an
    offset), outside the windows; a zero column gives 0."""
    t = np.linspace(0.0, 1.0, 101)
    Xa = np.column_stack([np.sin(t), 10.0 + 0.01 * t, np.zeros_like(t)])
    Xb = Xa.copy()
    Xb[:, 0] += 1e-6
    Xb[50, 1] += 1.0               # inside a window: left out
    rel = history_difference(t, Xa, t, Xb, windows=[(0.495, 0.505)], offsets=[0.0, 10.0, 0.0])
    assert rel[0] == pytest.approx(1e-6 / np.sin(1.0), rel=1e-9)
    assert rel[1] == 0.0 and rel[2] == 0.0


def test_peak_and_event_differences():
    a = {"reactions": {"A": {"Fx": 2.0, "M": 0.0}}, "joints": {"s": {"slide_min": -1.0}}}
    b = {"reactions": {"A": {"Fx": 2.002, "M": 0.0}}, "joints": {"s": {"slide_min": -1.1}}}
    d = peak_difference(a, b)
    assert d["reactions.A.Fx"] == pytest.approx(1e-3) and d["reactions.A.M"] == 0.0
    assert d["joints.s.slide_min"] == pytest.approx(0.1)
    ea = {"j": [{"t": 0.0, "kind": "stick"}, {"t": 1.0, "kind": "slip+"}]}
    assert event_difference(ea, {"j": [{"t": 0.0, "kind": "stick"}, {"t": 1.001, "kind": "slip+"}]}) == \
        (True, pytest.approx(1e-3))
    assert event_difference(ea, {"j": [{"t": 0.0, "kind": "stick"}]})[0] is False


def test_untrustworthy_runs_fail():
    """A completed run whose energy balance is far beyond its tolerance, or whose friction events fall
    on most of its steps, is a SolverFailure naming the reason (the chatter of issue 22 returned
    converged with energy_balance 1.01 and 947 events)."""
    import pytest

    from femslide.analysis.accuracy import check_trust
    from femslide.errors import SolverFailure
    ok = {"energy_balance": 1e-7, "events": {"iso": [{"t": 0.0, "kind": "stick"}] * 130}, "steps": 2000}
    check_trust(ok, 1e-6)
    with pytest.raises(SolverFailure, match="energy balance 1.01"):
        check_trust({**ok, "energy_balance": 1.01}, 1e-4)
    check_trust({**ok, "energy_balance": 5e-3}, 1e-6)        # below the floor 1e-2
    with pytest.raises(SolverFailure, match="chatter"):
        check_trust({**ok, "events": {"iso": [{"t": 0.0, "kind": "slip+"}] * 948}, "steps": 1500}, 1e-4)
