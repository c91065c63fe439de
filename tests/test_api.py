"""The Python API's result object and femslide.sweep (femslide/app/run.py, femslide/__init__.py).

Every value checked here is compared with an independent reference: equilibrium of a cut rod (the
nodal N, V, M against the load carried by the part beyond the cut), the closed-form free vibration of
the Coulomb oscillator, the files a run writes, and single solves for the rows of a sweep.
"""
from __future__ import annotations

import json
import math

import numpy as np
import pytest

import femslide
from femslide import BadInput

pd = pytest.importorskip("pandas")

P = 2.0e3       # N, tip load of the cantilever
L = 2.0         # m


def cantilever(P=P, EI=1e5, elements=8):
    s = femslide.Structure(gravity=(0.0, 0.0))
    s.rod("arm", start=(0.0, 0.0), end=(L, 0.0), EI=EI, elements=elements)
    s.weld("base", a="arm.start", b="ground")
    s.force("tip", on="arm.end", force=(0.0, -P))
    return s


@pytest.fixture(scope="module")
def cant():
    return femslide.solve(cantilever())


@pytest.fixture(scope="module")
def slider():
    return femslide.solve("beam-slider", EI=1e6)


@pytest.fixture(scope="module")
def sdof_free():
    return femslide.simulate("sdof-free")


def private_keys(obj, path=""):
    out = []
    if isinstance(obj, dict):
        for k, v in obj.items():
            if str(k).startswith("_"):
                out.append(path + str(k))
            out += private_keys(v, f"{path}{k}.")
    elif isinstance(obj, (list, tuple)):
        for v in obj:
            out += private_keys(v, path)
    return out


# -- the dict -----------------------------------------------------------------------------------------

def test_results_are_dicts_without_private_keys(cant, slider, sdof_free):
    hinge = femslide.solve("hinge-slider")
    for r in (cant, slider, sdof_free, hinge):
        assert isinstance(r, femslide.Result) and isinstance(r, dict)
        assert private_keys(r) == []
        assert r["converged"] is True
    assert slider["M_max"] == pytest.approx(504.9376, rel=1e-6)
    assert cant["rods"]["arm"]["M_max"] == cant["M_max"]


# -- rods, joints, bodies by name --------------------------------------------------------------------------

def test_rod_arrays_satisfy_equilibrium_of_every_cut(cant):
    """At a cut at s the part beyond carries only the tip load (0, -P) at the deformed tip, so
    N t - V n = (0, -P) and M = -P (x_tip - x(s)) (moments counter-clockwise).  Exact for any
    mesh at equilibrium: tolerance 1e-9 P (L) for Newton's residual."""
    a = cant.rod("arm")
    assert set("s x y u v theta N V M".split()) <= set(a)
    th = a["theta"]  # the rod starts along +x: the tangent angle is theta
    t = np.column_stack([np.cos(th), np.sin(th)])
    n = np.column_stack([-t[:, 1], t[:, 0]])
    force = a["N"][:, None] * t - a["V"][:, None] * n
    assert np.allclose(force, [0.0, -P], rtol=0, atol=1e-9 * P)
    assert np.allclose(a["M"], -P * (a["x"][-1] - a["x"]), rtol=0, atol=1e-9 * P * L)
    assert np.allclose(a["s"], np.linspace(0, L, 9), rtol=0, atol=1e-15)
    assert a["x"] == pytest.approx(a["s"] + a["u"], abs=1e-14)
    a["M"][:] = 0.0          # a copy: the result does not change
    assert cant.rod("arm")["M"][0] != 0.0


def test_joint_and_body_by_name(cant, slider):
    """The base reaction balances the tip load: (0, P) and moment P x_tip (independent of EI)."""
    base = cant.joint("base")
    x_tip = cant.rod("arm")["x"][-1]
    assert base["Fx"] == pytest.approx(0.0, abs=1e-9 * P)
    assert base["Fy"] == pytest.approx(P, rel=1e-12)
    assert base["M"] == pytest.approx(P * x_tip, rel=1e-9)
    assert base == cant["reactions"]["base"]
    # a paper scene: the declared names of its structure
    assert slider.parts() == {"rods": ["right"], "bodies": ["deck"], "joints": ["A1", "B1", "clamp"]}
    assert slider.joint("B1")["Fx"] == pytest.approx(slider["reactions"]["B1"]["Fx"], rel=1e-12)
    assert slider.joint("clamp")["slide"] == pytest.approx(slider["slide"], rel=1e-12)
    assert slider.body("deck")["rotation"] == pytest.approx(-slider["phi"], rel=1e-12)  # paper: clockwise
    with pytest.raises(BadInput, match="no joint named 'C'.*A1, B1, clamp"):
        slider.joint("C")
    with pytest.raises(BadInput, match="no rod named"):
        slider.rod("left")
    with pytest.raises(BadInput, match="no rods, joints or bodies"):
        femslide.solve("hinge-slider").rod("right")


def test_statics_dataframe_has_one_row_per_rod_node(slider):
    df = slider.to_dataframe()
    a = slider.rod("right")
    assert list(df.columns) == ["rod", "node", "s", "x", "y", "u", "v", "theta", "N", "V", "M"]
    assert len(df) == a["s"].size and (df["rod"] == "right").all()
    assert np.array_equal(df["M"].to_numpy(), a["M"]) and np.array_equal(df["node"], np.arange(len(df)))
    assert df.attrs["units"]["M"] == "N m"
    both = femslide.solve("beam-both", EI=1e6).to_dataframe()
    assert set(both["rod"]) == {"left", "right"}


# -- time histories ----------------------------------------------------------------------------------------

def test_sdof_history_matches_the_closed_form_first_swing(sdof_free):
    """sdof-free (m = 1 kg, k = 200 N/m, mu = 0.2, w0 = 0.07 m) slides back from rest at w0 with
    w' < 0, so f = -mu m g and w(t) = fk/k + (w0 - fk/k) cos(omega t) until t = pi/omega; the
    history must equal it (tolerance 1e-12 m: the exact integrator's round-off)."""
    h = sdof_free.history
    assert list(h)[:4] == ["t", "w", "v", "state"] and {"F", "f"} <= set(h)
    assert all(v.shape == h["t"].shape for v in h.values())
    assert np.all(np.diff(h["t"]) > 0) and h["t"][-1] == pytest.approx(2.0)
    k, m, fk = 200.0, 1.0, 0.2 * 9.81
    om = math.sqrt(k / m)
    first = (h["t"] > 0) & (h["t"] < math.pi / om * (1 - 1e-9))
    t = h["t"][first]
    w_ref = fk / k + (0.07 - fk / k) * np.cos(om * t)
    assert np.allclose(h["w"][first], w_ref, rtol=0, atol=1e-12)
    assert np.allclose(h["v"][first], -(0.07 - fk / k) * om * np.sin(om * t), rtol=0, atol=1e-10)
    assert np.all(h["state"][first] == -1) and np.allclose(h["f"][first], -fk, rtol=1e-15)
    # stuck samples: static friction holds the spring (F = 0 here)
    stuck = h["state"] == 0
    assert stuck.any() and np.allclose(h["f"][stuck], -k * h["w"][stuck], rtol=1e-12)
    assert np.all(np.abs(h["f"][stuck]) <= 0.24 * 9.81)
    df = sdof_free.to_dataframe()
    assert list(df.columns) == list(h) and len(df) == h["t"].size and df.attrs["units"]["f"] == "N"


def test_history_equals_the_written_csv(sdof_free, tmp_path):
    files = sdof_free.write(tmp_path / "run")
    assert [p.split("/")[-1] for p in files] == ["history.csv", "turning_points.csv", "result.json"]
    csv = np.loadtxt(tmp_path / "run" / "history.csv", delimiter=",", skiprows=1)
    h = sdof_free.history
    assert np.array_equal(csv[:, 0], h["t"]) and np.array_equal(csv[:, 1], h["w"])
    saved = json.loads((tmp_path / "run" / "result.json").read_text())
    assert saved["w_max"] == sdof_free["w_max"] and "history" not in saved


def test_structure_dynamics_history():
    """beam-oscillation: the history starts at rest at phi0 and its |F2| peaks at the reported
    F2_max (refined between samples, so at least the largest sample, and within 1 % of it)."""
    r = femslide.simulate("beam-oscillation", t_end=0.3)
    h = r.history
    assert list(h) == ["t", "phi", "phi_dot", "slide", "stuck", "F_ax", "N", "F1", "N1", "F2", "N2"]
    assert h["t"][0] == 0.0 and h["phi"][0] == pytest.approx(0.01, rel=1e-12) and h["phi_dot"][0] == 0.0
    peak = np.abs(h["F2"]).max()
    assert peak <= r["F2_max"] * (1 + 1e-12) and peak >= 0.99 * r["F2_max"]
    assert r.to_dataframe().shape == (h["t"].size, 11)


def test_statics_have_no_history(slider):
    assert slider.history is None


# -- flat values, files ----------------------------------------------------------------------------------

def test_flat_uses_dotted_names(cant, sdof_free):
    f = cant.flat()
    assert f["reactions.base.Fy"] == cant["reactions"]["base"]["Fy"]
    assert f["rods.arm.end.v"] == cant["rods"]["arm"]["end"]["v"]
    assert all(not isinstance(v, (dict, list)) for v in f.values())
    g = sdof_free.flat()
    assert "turning_points" not in g and g["w_max"] == sdof_free["w_max"]
    one = femslide.solve("hinge-fixed").to_dataframe()
    assert len(one) == 1 and one.loc[0, "reactions.B1.Fx"] == pytest.approx(
        femslide.solve("hinge-fixed")["reactions"]["B1"]["Fx"], rel=1e-12)


def test_write_statics_and_bad_folder(cant, tmp_path):
    files = cant.write(str(tmp_path / "o"))
    names = sorted(p.split("/")[-1] for p in files)
    assert names == ["result.json", "structure.json", "structure.vtu"]
    saved = json.loads((tmp_path / "o" / "result.json").read_text())
    assert saved["rods"]["arm"]["M_max"] == cant["M_max"]
    (tmp_path / "file").write_text("x")
    with pytest.raises(BadInput, match="out_dir"):
        cant.write(tmp_path / "file" / "sub")


# -- femslide.sweep ---------------------------------------------------------------------------------------

def test_sweep_rows_equal_single_solves():
    df = femslide.sweep("beam-slider", EI=[1e4, 1e8], quiet=True)
    assert isinstance(df, pd.DataFrame)
    assert list(df.columns[:4]) == ["EI", "converged", "status", "reason"]
    assert (df["status"] == "converged").all()
    assert df["EI"].tolist() == [1e4, 1e8] and df["converged"].all() and df["reason"].isna().all()
    assert not [c for c in df.columns if c.startswith("_") or "._" in c]
    for i, EI in enumerate([1e4, 1e8]):
        one = femslide.solve("beam-slider", EI=EI).flat()
        for k, v in one.items():
            if k not in ("wall_time_s", "import_time_s", "error_estimate", "converged"):
                assert df.loc[i, k] == v, k


def test_sweep_grid_fixed_and_failures():
    df = femslide.sweep("hinge-fixed", c=[1.0, 1e6, 1e8], fixed={"d": 0.1}, quiet=True)
    assert df["converged"].tolist() == [False, True, True]
    assert isinstance(df.loc[0, "reason"], str) and math.isnan(df.loc[0, "M_max"])
    assert df.loc[2, "M_max"] == femslide.solve("hinge-fixed", c=1e8, d=0.1)["M_max"]
    grid = femslide.sweep("hinge-slider", c=[1e6, 1e8], l1=range(1, 4), quiet=True)
    assert list(zip(grid["c"], grid["l1"])) == [(c, l1) for c in (1e6, 1e8) for l1 in (1, 2, 3)]
    assert grid.loc[4, "phi"] == femslide.solve("hinge-slider", c=1e8, l1=2)["phi"]
    assert grid.attrs["varied"] == ["c", "l1"]


def test_sweep_of_a_structure_in_processes_equals_in_process():
    """A declared structure goes to the worker processes as a structure file: same rows."""
    s = cantilever()
    kw = {"arm.EI": np.array([1e4, 1e5]), "tip.force": [[0.0, -P], [P, 0.0]]}
    one = femslide.sweep(s, **kw, quiet=True)
    two = femslide.sweep(s, **kw, jobs=2, quiet=True)
    assert len(one) == 4 and one["converged"].all()
    cols = [c for c in one.columns if c not in ("wall_time_s", "import_time_s")]
    pd.testing.assert_frame_equal(one[cols], two[cols])
    # row 0 (EI = 1e4, load (0, -P)): the base moment balances the load at the deformed tip
    assert one.loc[0, "reactions.base.M"] == pytest.approx(P * (L + one.loc[0, "rods.arm.end.u"]), rel=1e-9)
    assert one.loc[0, "rods.arm.end.v"] < -0.1     # a large deflection, so u matters


def test_sweep_of_a_simulation():
    df = femslide.sweep("sdof-free", mu=[0.1, 0.2], fixed={"mu0": 0.25}, quiet=True)
    assert df["converged"].all() and "stop.t" in df.columns and "turning_points" not in df.columns
    assert df.loc[1, "w_max"] == femslide.simulate("sdof-free", mu=0.2, mu0=0.25)["w_max"]


@pytest.mark.parametrize("args, kwargs, match", [
    (("hinge-fixed",), {"c": 1e6}, "not a list of values"),
    (("hinge-fixed",), {"c": []}, "has no values"),
    (("hinge-fixed",), {"c": "1e6"}, "not a list of values"),
    (("hinge-fixed",), {}, "no varied parameter"),
    (("hinge-fixed",), {"c": [1e6], "fixed": {"c": 1.0}}, "both fixed and varied"),
    (("hinge-fixed",), {"c": [1e6], "jobs": 0}, "jobs"),
    (("hinge-fixed",), {"zz": [1.0]}, "unknown parameter 'zz'"),
    (("hinge-fixed",), {"c": [1e6, -1.0]}, "parameter c"),
    ((3.0,), {"c": [1e6]}, "allowed: a built-in scene name"),
])
def test_sweep_bad_input(args, kwargs, match):
    with pytest.raises(BadInput, match=match):
        femslide.sweep(*args, **kwargs)


def test_sweep_status_tells_bad_input_from_failure():
    """A value rejected only when its case runs (the one-mass oscillator's work bound on t_end) is a
    row with status "bad-input", not a solver failure; the other cases run."""
    df = femslide.sweep("sdof-harmonic", t_end=[10.0, 1e7], quiet=True)
    assert df["status"].tolist() == ["converged", "bad-input"]
    assert df["converged"].tolist() == [True, False] and "t_end" in df.loc[1, "reason"]
