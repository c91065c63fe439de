"""Engineering analyses as users script them: load cases and combinations, first-order theory, elastic
supports and sections, buckling and arc-length continuation - declarations, structure files, the
command line, bad input (exit 2 naming the field and the allowed values), outputs and files; and the
model pieces behind them (load-case factors, the linearised model, the springs of an elastic support).
Numbers against references are in validation/ (test_linear_theory, test_buckling, test_arc_length)."""
from __future__ import annotations

import json
import os
import subprocess
import sys

import numpy as np
import pytest

import femslide
from femslide.analysis.static import scales
from femslide.app.structfile import dumps, load
from femslide.model.discrete import Model
from femslide.model.linear import LinearModel
from femslide.model.structure import Structure

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
INCLINED = os.path.join(ROOT, "meshes", "structures", "inclined-guide.toml")


def run(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "femslide", *args], capture_output=True, text=True, cwd=cwd)


def frame():
    s = Structure(gravity=(0.0, -9.81))
    s.rod("col", (0.0, 0.0), (0.0, 3.0), E=210e9, I=2.3e-5, A=5.4e-3, rhoA=40.0)
    s.rod("beam", (0.0, 3.0), (4.0, 3.0), EI=1e7, EA=1e9, rhoA=60.0)
    s.weld("base", "col.start", "ground", kr=4e6)
    s.weld("corner", "col.end", "beam.start")
    s.roller("far", "beam.end", "ground", axis=(1.0, 0.0), ky=5e7)
    s.distributed("snow", "beam", force=(0.0, -5e3), case="snow")
    s.force("wind", "col.end", force=(8e3, 0.0), case="wind")
    s.combination("ULS", {"dead": 1.35, "snow": 1.5, "wind": 0.9})
    s.combination("SLS", {"dead": 1.0, "snow": 1.0})
    return s


# -- declarations and their checks --------------------------------------------------------------------------
def test_cases_and_combinations_are_frozen():
    fs = frame().freeze()
    assert fs.cases == ("dead", "snow", "wind")
    assert [c.name for c in fs.combinations] == ["ULS", "SLS"]
    assert fs.combinations[0].factor_dict() == {"dead": 1.35, "snow": 1.5, "wind": 0.9}
    assert fs.rod("col").EI == pytest.approx(210e9 * 2.3e-5) and fs.rod("col").EA == pytest.approx(210e9 * 5.4e-3)


@pytest.mark.parametrize("change,match", [
    (lambda s: s.combination("bad", {"snw": 1.0}), "load case 'snw', which no load has; cases: dead, snow, wind"),
    (lambda s: s.combination("bad", {"snow": "x"}), "factor of snow"),
    (lambda s: s.combination("bad", {}), "factors is empty"),
    (lambda s: s.set("wind.case", ""), "case = ''"),
    (lambda s: s.rod("r2", (0, 0), (1, 0), E=2e11), "needs E .* and I"),
    (lambda s: s.rod("r2", (0, 0), (1, 0), EI=1.0, E=2e11, I=1e-5), "not both"),
    (lambda s: s.rod("r2", (0, 0), (1, 0), E=-2e11, I=1e-5), "E = -2"),
    (lambda s: s.set("corner.kx", 1e6), "only for a joint with b = \"ground\""),
    (lambda s: s.pin("p2", "beam.end", "ground", kx=0.0), "kx = 0.0 is out of range"),
    (lambda s: s.set("far.kx", 1e6), "allowed here: ky"),
    (lambda s: s.slider("s2", "beam.end", "ground", axis=(1.0, 1.0), kx=1e6), "allowed here: kr"),
    (lambda s: s.slider("s2", "beam.end", "ground", axis=(0.0, 1.0), kx=1e6, mu=0.2), "cannot carry friction"),
])
def test_bad_declarations_name_the_field(change, match):
    s = frame()
    change(s)
    with pytest.raises(femslide.BadInput, match=match):
        s.freeze()


def test_a_pin_takes_no_kr():
    s = frame()
    s.pin("p2", "beam.end", "ground", c=0.0)
    s.set("p2.kr", 1e5)
    with pytest.raises(femslide.BadInput, match="allowed here: kx, ky"):
        s.freeze()


def test_structure_file_round_trip(tmp_path):
    """dumps() writes cases, combinations, sections and springs; load() reads them back."""
    s = frame()
    f = tmp_path / "f.toml"
    f.write_text(dumps(s) + '\n[solve]\ntheory = "linear"\n')
    sf = load(str(f))
    fs = sf.structure.freeze()
    assert fs.cases == ("dead", "snow", "wind")
    assert [c.factor_dict() for c in fs.combinations] == [{"dead": 1.35, "snow": 1.5, "wind": 0.9},
                                                         {"dead": 1.0, "snow": 1.0}]
    assert fs.joints[0].kr == 4e6 and fs.joints[2].ky == 5e7
    assert sf.solve_table == {"theory": "linear"}


@pytest.mark.parametrize("text,match", [
    ('[solve]\npath = "riks"\n', "path = 'riks'; allowed: principal, arc-length"),
    ('[solve]\ntheory = "second-order"\n', "theory = 'second-order'; allowed: nonlinear, linear"),
    ('[solve]\nmethod = "x"\n', "unknown key 'method'; allowed: path, theory, plot"),
    ('[solve]\npath = "arc-length"\ntheory = "linear"\n', "needs theory = 'nonlinear'"),
    ('[[combination]]\nname = "c"\n', "missing field 'factors'"),
    ('[[combination]]\nname = "c"\nfactors = {dead = 1.0}\nextra = 1\n', "unknown field 'extra'"),
    ('[[combination]]\nname = "c"\nfactors = 1.0\n', "allowed: a table"),
])
def test_bad_solve_tables_exit_2(tmp_path, text, match):
    f = tmp_path / "f.toml"
    f.write_text(dumps(frame()) + "\n" + text)
    p = run("solve", str(f))
    assert p.returncode == 2, p.stderr
    assert match in p.stderr.replace("\n", " ")


def test_solve_options_on_the_command_line(tmp_path):
    f = tmp_path / "f.toml"
    f.write_text(dumps(frame()))
    assert run("solve", str(f), "--set", "solve.path=riks").returncode == 2
    p = run("solve", "beam-slider", "--path", "arc-length")
    assert p.returncode == 2 and "structure files" in p.stderr
    p = run("buckling", "beam-slider")
    assert p.returncode == 2 and "structure file" in p.stderr
    p = run("buckling", str(f), "--count", "0")
    assert p.returncode == 2 and "--count = 0" in p.stderr
    p = run("buckling", str(f), "--combination", "ULT")
    assert p.returncode == 2 and "combinations: ULS, SLS" in p.stderr


# -- the model: load-case factors, the linear model, elastic supports ------------------------------------------
def _model(s, factors=None, cls=Model, n=3):
    fs = s.freeze()
    L, F = scales(fs)
    return cls(fs, {r.name: n for r in fs.rods}, L, F, factors=factors)


def test_factors_scale_each_case():
    """A model of case factors equals the declared loads scaled by hand (residual and Jacobian at a
    random state); factors of 1 for every case equal the model without factors (bitwise)."""
    s = frame()
    all1 = _model(s, {"dead": 1.0, "snow": 1.0, "wind": 1.0})
    plain = _model(s)
    rng = np.random.default_rng(1)
    y = 1e-3 * rng.standard_normal(plain.n)
    r1, A1, _ = all1.system(y, all1.zero_state()[1], 0.7, dense=True)
    r0, A0, _ = plain.system(y, plain.zero_state()[1], 0.7, dense=True)
    assert np.array_equal(r1, r0) and np.array_equal(A1, A0)
    f = {"dead": 1.35, "snow": 1.5, "wind": 0.9}
    mf = _model(s, f)
    by_hand = frame()
    by_hand.gravity = (0.0, -9.81 * 1.35)
    by_hand.set("snow.force", (0.0, -5e3 * 1.5))
    by_hand.set("wind.force", (8e3 * 0.9, 0.0))
    mh = Model(by_hand.freeze(), {r: 3 for r in ("col", "beam")}, mf.Lref, mf.Fref)
    rf, Af, _ = mf.system(y, mf.zero_state()[1], 0.7, dense=True)
    rh, Ah, _ = mh.system(y, mh.zero_state()[1], 0.7, dense=True)
    assert np.allclose(rf, rh, rtol=1e-13, atol=1e-13) and np.allclose(Af, Ah, rtol=1e-13, atol=1e-13)


def test_linear_model_is_linear():
    """The linear model's residual is A0 y + lam f exactly (A0 its constant Jacobian) and Newton
    converges in one step."""
    m = _model(frame(), cls=LinearModel)
    y0, es = m.zero_state()
    r0, A0, _ = m.system(y0, es, 1.0, dense=True)
    y = np.random.default_rng(2).standard_normal(m.n)
    r, A, _ = m.system(y, es, 1.0, dense=True)
    assert np.array_equal(A, A0)
    assert np.allclose(r, r0 + A0 @ y, rtol=1e-12, atol=1e-12 * np.abs(A0).max())
    from femslide.analysis.newton import newton
    _, info = newton(m, y0, es, lam=1.0)
    assert info.converged and info.iterations == 1


def test_elastic_support_forces_are_the_energy_gradient():
    """The springs of an elastic support at a body point off the body's origin (a lever: nonlinear
    kinematics): force and Hessian equal finite differences of the energy (1e-6)."""
    s = Structure(gravity=(0.0, 0.0))
    s.rod("c", (0.0, 0.0), (0.0, 1.0), EI=1e3)
    s.body("b", mass=1.0, centroid=(0.5, 1.5), outline=[(0, 1), (1, 1), (1, 2), (0, 2)])
    s.weld("top", "c.end", "b")
    s.weld("base", "c.start", "ground")
    s.weld("spring", "b", "ground", at=(1.0, 2.0), kx=3.0, ky=5.0, kr=7.0)
    m = _model(s)
    t = m.supports["spring"]
    z = np.array([0.01, -0.02, 0.3])
    E, g, H, _ = t.eval(z)
    h = 1e-6
    for i in range(3):
        dz = np.zeros(3)
        dz[i] = h
        assert (t.eval(z + dz)[0] - t.eval(z - dz)[0]) / (2 * h) == pytest.approx(g[i], rel=1e-6, abs=1e-8)
        assert np.allclose((t.eval(z + dz)[1] - t.eval(z - dz)[1]) / (2 * h), H[:, i], rtol=1e-6, atol=1e-8)


# -- outputs -------------------------------------------------------------------------------------------------------
def test_combinations_output_files(tmp_path):
    f = tmp_path / "frame.toml"
    f.write_text(dumps(frame()))
    out = tmp_path / "out"
    p = run("solve", str(f), "--theory", "linear", "--json", "--out", str(out))
    assert p.returncode == 0, p.stderr
    r = json.loads(p.stdout)
    assert r["theory"] == "linear" and set(r["combinations"]) == {"ULS", "SLS"}
    assert r["envelope"]["rods"]["beam"]["M_max_combination"] == "ULS"
    for name in ("combinations.csv", "envelope_M.csv", "frame_ULS.vtu", "frame_SLS.vtu", "result.json"):
        assert (out / name).is_file(), name
    head = (out / "combinations.csv").read_text().splitlines()
    assert head[0].startswith("combination,M_max [N m],") and head[1].startswith("ULS,")
    env = (out / "envelope_M.csv").read_text().splitlines()
    assert env[0] == "rod,s [m],M_min [N m],M_max [N m],M ULS [N m],M SLS [N m]"


def test_a_failed_combination_keeps_the_others(tmp_path):
    """A combination past a limit point fails with its reason; the others are reported (exit 1)."""
    s = load(INCLINED).structure
    s.loads["W"] = None
    del s.loads["W"]
    s.combination("light", {"dead": 0.2})
    s.combination("heavy", {"dead": 1.0})
    r = femslide.solve(s)
    assert r["converged"] is False
    assert r["combinations"]["heavy"]["converged"] is False and "limit point" in r["combinations"]["heavy"]["reason"]
    assert r["combinations"]["light"]["converged"] is True
    assert "combination heavy" in r["reason"]
    assert set(r["envelope"]["rods"]["post"]) >= {"M_max", "M_max_combination"}


def test_arc_length_outputs(tmp_path):
    out = tmp_path / "o"
    p = run("solve", INCLINED, "--path", "arc-length", "--json", "--out", str(out))
    assert p.returncode == 0, p.stderr
    r = json.loads(p.stdout)
    assert [lp["kind"] for lp in r["limit_points"]] == ["maximum", "minimum"]
    lp = r["limit_points"][0]
    assert set(lp) >= {"load_factor", "error_estimate", "elements", "bodies", "rods", "joints", "reactions"}
    assert r["stable"] is True and r["path_plot"] == "bodies.head.y"
    lams = [pt["load_factor"] for pt in r["path"]]
    assert lams[0] == 0.0 and lams[-1] == 1.0 and max(lams[:-1]) < 1.0
    assert (out / "path.png").is_file()
    rows = (out / "path.csv").read_text().splitlines()
    assert rows[0].startswith("load_factor [-],M_max [N m],") and rows[0].endswith(",kind")
    assert len(rows) == len(r["path"]) + 1


def test_default_failure_json_names_the_limit_point():
    p = run("solve", INCLINED, "--json")
    assert p.returncode == 1
    r = json.loads(p.stdout)
    assert r["limit_point"]["kind"] == "maximum"
    assert r["limit_point"]["load_factor"] == pytest.approx(0.2322111, abs=1e-7)
    assert "limit point at load factor 0.2322111" in p.stderr


def test_python_api_options():
    s = load(INCLINED).structure
    r = femslide.solve(s, path="arc-length", plot="bodies.head.rotation")
    assert r["path_plot"] == "bodies.head.rotation" and r["bodies"]["head"]["rotation"] < -0.4
    with pytest.raises(femslide.BadInput, match="no such output of the path"):
        femslide.solve(s, path="arc-length", plot="bodies.head.z")
    with pytest.raises(femslide.BadInput, match="theory = 'first'"):
        femslide.solve(s, theory="first")
