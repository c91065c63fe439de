"""Regression tests of issue 12: never exit 0 with a wrong, NaN or unconverged answer; bounded time
and memory; output paths checked before any work; unreadable inputs named.

Each test runs the command line as a user does (``python -m femslide ...`` in a subprocess, or
``femslide.app.cli.main`` in process where that is enough) and checks the exit status (0 converged, 1
failed with a reason, 2 bad input naming the parameter or file), the message, and - where a run
converges - the answer against an independent reference.  Every case here misbehaved before the
fix (noted per test).
"""
from __future__ import annotations

import contextlib
import io
import json
import os
import pathlib
import subprocess
import sys
import time

import pytest

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent
for _p in (str(ROOT), str(HERE)):
    if _p not in sys.path:
        sys.path.insert(0, _p)

from femslide.app.cli import main  # noqa: E402


def run(*args, timeout=120):
    """``python -m femslide ARGS``: (exit status, stdout, stderr, wall time)."""
    env = dict(os.environ)
    env["PYTHONPATH"] = str(ROOT) + os.pathsep + env.get("PYTHONPATH", "")
    env.pop("FEMSLIDE_DEBUG", None)
    t0 = time.perf_counter()
    p = subprocess.run([sys.executable, "-m", "femslide", *args], capture_output=True, text=True,
                       cwd=ROOT, env=env, timeout=timeout)
    return p.returncode, p.stdout, p.stderr, time.perf_counter() - t0


def cli(*argv):
    """``femslide.app.cli.main`` in process: (exit status, stdout, stderr)."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main([str(a) for a in argv])
    return code, out.getvalue(), err.getvalue()


def clean_error(code, err, *names):
    """Exit 2 or 1 with one femslide message naming ``names``; no traceback, no internal error."""
    assert "Traceback" not in err and "internal error" not in err, err
    assert "RuntimeWarning" not in err, err
    for n in names:
        assert n in err, (n, err)


# -- output paths: checked before any work ---------------------------------------------------------------
# Before: the whole solve or sweep ran, then "internal error" (exit 1).

SLOW_SWEEP = ("sweep", "sdof-harmonic", "--vary", "t_end=20000,20001", "--quiet")


@pytest.mark.parametrize("make, args, option", [
    (lambda d: (d / "afile").write_text("x") and d / "afile", ("simulate", "sdof-harmonic", "--set", "t_end=20000"),
     "--out"),
    (lambda d: d / "afile" / "sub", ("simulate", "sdof-harmonic", "--set", "t_end=20000"), "--out"),
    (lambda d: "/proc/femslide-out", ("solve", "beam-slider"), "--out"),
    (lambda d: "/proc/femslide-out", SLOW_SWEEP, "--out"),
])
def test_out_path_is_checked_before_the_work(tmp_path, make, args, option):
    (tmp_path / "afile").write_text("x")
    path = make(tmp_path)
    code, out, err, dt = run(*args, option, str(path))
    assert code == 2, err
    clean_error(code, err, option, str(path))
    assert dt < 10  # rejected at once: the run itself takes longer


@pytest.mark.parametrize("plot", ["x.xyz", "/proc/femslide/x.png"])
def test_plot_path_is_checked_before_the_sweep(tmp_path, plot):
    path = plot if plot.startswith("/") else str(tmp_path / plot)
    code, out, err, dt = run(*SLOW_SWEEP, "--plot", path)
    assert code == 2
    clean_error(code, err, "--plot", path)
    assert dt < 10


def test_screenshot_path_and_corrupt_vtu(tmp_path):
    bad = tmp_path / "corrupt.vtu"
    bad.write_text("<VTKFile> this is not a VTU")
    code, _, err, _ = run("show", str(bad), "--screenshot", str(tmp_path / "x.png"))
    assert code == 2
    clean_error(code, err, str(bad))
    good = tmp_path / "res"
    assert run("solve", "beam-slider", "--set", "n_elements=4", "--out", str(good))[0] == 0
    vtu = next(good.glob("*.vtu"))
    code, _, err, _ = run("show", str(vtu), "--screenshot", "/proc/femslide/x.png")
    assert code == 2
    clean_error(code, err, "--screenshot", "/proc/femslide/x.png")


def test_scene_file_with_a_corrupt_mesh_names_the_file(tmp_path):
    """Before: exit 1 with meshio's bare 'Couldn't read file' (meshio calls sys.exit)."""
    (tmp_path / "bad.vtu").write_text("garbage")
    scene = tmp_path / "s.toml"
    scene.write_text('scene = "beam-slider"\nmesh = "bad.vtu"\n')
    code, _, err, _ = run("solve", str(scene))
    assert code == 2
    clean_error(code, err, "bad.vtu", str(scene))


# -- sweeps: one sweep per folder, case files never overwritten --------------------------------------------

def test_second_sweep_with_other_parameters_is_refused(tmp_path):
    """Before: the second sweep restarted at case 0 and overwrote the first sweep's case files."""
    code, out, err = cli("sweep", "beam-slider", "--vary", "EI=1e6,1e8", "--set", "n_elements=4",
                         "--json", "--quiet", "--out", tmp_path)
    assert code == 0, err
    first = json.loads(out)
    before = {p: p.read_bytes() for p in tmp_path.rglob("*") if p.is_file()}
    for extra in (("--set", "n_elements=8"), ("--set", "n_elements=4", "--set", "d=0.1")):
        for resume in ((), ("--resume",)):
            code, out, err = cli("sweep", "beam-slider", "--vary", "EI=1e6,1e8", *extra, "--json",
                                 "--quiet", "--out", tmp_path, *resume)
            assert code == 2 and "another sweep" in err and str(tmp_path) in err, err
    other_scene = cli("sweep", "beam-fixed", "--vary", "EI=1e6", "--set", "n_elements=4", "--quiet",
                      "--out", tmp_path)
    assert other_scene[0] == 2 and "scene beam-slider, not beam-fixed" in other_scene[2]
    after = {p: p.read_bytes() for p in tmp_path.rglob("*") if p.is_file()}
    assert after == before  # nothing written, nothing overwritten
    # the same sweep with one more value: resumed; the new case gets a new folder, rows point at
    # their own files
    code, out, err = cli("sweep", "beam-slider", "--vary", "EI=1e7,1e6,1e8", "--set", "n_elements=4",
                         "--json", "--quiet", "--out", tmp_path, "--resume")
    assert code == 0, err
    rows = json.loads(out)
    assert rows[1] == first[0] and rows[2] == first[1]
    recs = [json.loads(x) for x in (tmp_path / "sweep.jsonl").read_text().splitlines()]
    assert [r["case"] for r in recs] == [0, 1, 2] and recs[2]["params"]["EI"] == 1e7
    assert all(r["version"] and r["varied"] == "EI" for r in recs)
    for r in recs:
        assert all(f"case_{r['case']:03d}" in f for f in r["files"]), r["files"]
    after2 = {p: p.read_bytes() for p in tmp_path.rglob("*") if p.is_file() and "case_002" not in str(p)}
    assert {p: b for p, b in after2.items() if p.name != "sweep.jsonl"} == \
        {p: b for p, b in before.items() if p.name != "sweep.jsonl"}


def test_resume_key_includes_the_version(tmp_path):
    code, out, err = cli("sweep", "hinge-slider", "--vary", "c=1e6,1e7", "--json", "--quiet", "--out", tmp_path)
    assert code == 0
    path = tmp_path / "sweep.jsonl"
    recs = [json.loads(x) for x in path.read_text().splitlines()]
    path.write_text("".join(json.dumps({**r, "version": "0.0.1"}) + "\n" for r in recs))
    code, out, err = cli("sweep", "hinge-slider", "--vary", "c=1e6,1e7", "--json", "--quiet", "--out",
                         tmp_path, "--resume")
    assert code == 2 and "femslide 0.0.1" in err


# -- the one-mass oscillator: numbers and work bounded, answers checked ------------------------------

def test_record_of_huge_accelerations_is_bad_input(tmp_path):
    """Before: exit 0, converged true, the history all NaN (m a overflowed to inf)."""
    rec = tmp_path / "huge.csv"
    rec.write_text("t,a\n0,1e308\n1,-1e308\n2,1e308\n")
    code, out, err, _ = run("simulate", "sdof-harmonic", "--set", f"record={rec}", "--json", "--quiet")
    assert code == 2
    clean_error(code, err, "record")


@pytest.mark.parametrize("args, name", [
    (("sdof-free", "w0=1e308"), "w0"),                   # before: internal error: OverflowError
    (("sdof-harmonic", "P0=1e300"), "P0"),
    (("sdof-harmonic", "ag=1e308"), "ag"),
    (("sdof-free", "k=1e300", "m=1e-300"), "k, m"),
])
def test_overflowing_magnitudes_are_bad_input(args, name):
    scene, *sets = args
    code, out, err, _ = run("simulate", scene, *[x for s in sets for x in ("--set", s)], "--quiet")
    assert code == 2
    clean_error(code, err, name, "allowed")


def _limited(cmd, mem_bytes=2 * 2**30, timeout=120):
    """Run python -m femslide in a subprocess with an address-space limit."""
    import resource

    def limit():
        resource.setrlimit(resource.RLIMIT_AS, (mem_bytes, mem_bytes))
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    t0 = time.perf_counter()
    p = subprocess.run([sys.executable, "-m", "femslide", *cmd], capture_output=True, text=True, cwd=ROOT,
                       env=env, timeout=timeout, preexec_fn=limit)
    return p.returncode, p.stdout, p.stderr, time.perf_counter() - t0


@pytest.mark.parametrize("c_v", [1e9, 1e12])
def test_stiff_damping_in_bounded_memory_against_scipy(tmp_path, c_v):
    """Before: c_v = 1e9 allocated 2.5 GiB (15 GB with the history), 1e12 asked for 2.4 TiB.
    Now O(1) memory; the creeping motion agrees with scipy's Radau (rtol 1e-12) to 1e-12 m."""
    import numpy as np
    import sdof_reference as sref
    out = tmp_path / "o"
    code, stdout, err, dt = _limited(["simulate", "sdof-free", "--set", f"c_v={c_v}", "--set", "t_end=1e4",
                                      "--json", "--quiet", "--out", str(out)])
    assert code == 0, err
    res = json.loads(stdout)
    assert res["converged"] and res["energy_balance"] < 1e-9 and res["turning_points"] == []
    hist = np.loadtxt(out / "history.csv", delimiter=",", skiprows=1)
    iv = sref.ivp_simulate(1.0, 200.0, c_v, 0.2, 0.24, 9.81, 0.07, t_end=2.0, rtol=1e-12, atol=1e-16,
                           method="Radau")
    sel = hist[:, 0] <= 2.0
    ref = sref.ivp_eval(iv, hist[sel, 0])
    assert np.max(np.abs(hist[sel, 1] - ref)) < 1e-12


def test_long_t_end_is_capped_with_the_usable_range():
    """Before: sdof-harmonic t_end = 1e7 ran for tens of minutes.  Now exit 2 at once, naming t_end
    and the largest usable value, which then runs."""
    code, out, err, dt = run("simulate", "sdof-harmonic", "--set", "t_end=1e7", "--quiet")
    assert code == 2 and dt < 10
    clean_error(code, err, "t_end", "allowed: t_end <=")
    # an unforced run that stops may be as long as the range allows
    code, out, err, dt = run("simulate", "sdof-free", "--set", "t_end=1e7", "--json", "--quiet")
    assert code == 0 and json.loads(out)["stop"] is not None and dt < 30


@pytest.mark.slow
def test_largest_usable_t_end_runs_within_two_minutes(tmp_path):
    import re
    code, out, err, _ = run("simulate", "sdof-harmonic", "--set", "theta_ratio=3", "--set", "t_end=1e7", "--quiet")
    t_max = float(re.search(r"t_end <= ([0-9.e+]+) s", err).group(1))
    code, out, err, dt = run("simulate", "sdof-harmonic", "--set", "theta_ratio=3", "--set", f"t_end={t_max}",
                             "--json", "--quiet", "--out", str(tmp_path / "o"), timeout=180)
    assert code == 0, err
    assert dt < 120 and json.loads(out)["energy_balance"] < 1e-8


def test_frictionless_grazing_zero_restarts_the_right_way():
    """theta = omega/2 without friction: v and a vanish together once per forcing period.  Before,
    round-off started a segment the wrong way at t ~ 6367 s and w was off by 1.4e-3 m from then on.
    Reference: the closed form w = B (sin(theta t) - r sin(omega t))."""
    import numpy as np

    from femslide.scenes import sdof
    from femslide.scenes.catalog import get
    v = get("sdof-harmonic").resolve({"mu": 0, "mu0": 0, "t_end": 7000})
    osc, w0, t_end = sdof.build(v)
    sol = osc.run(w0, t_end)
    om, th = osc.omega, osc.F.theta
    r = th / om
    B = 10.0 / (osc.k * (1 - r * r))
    t = np.linspace(6000.0, 7000.0, 200001)
    w, _, _ = sol.eval(t)
    assert np.max(np.abs(w - B * (np.sin(th * t) - r * np.sin(om * t)))) < 1e-8
    assert sol.energy_balance() < 1e-9


def test_energy_balance_does_not_drift_on_long_forced_runs():
    """Before: the forcing phase theta t recomputed at the quadrature nodes made the balance drift as
    t_end^2 (4.3e-6 at t_end = 1e4 s, theta = 3 omega; 9000 s is the usable maximum now)."""
    from femslide.scenes import sdof
    from femslide.scenes.catalog import get
    osc, w0, t_end = sdof.build(get("sdof-harmonic").resolve({"theta_ratio": 3, "t_end": 9000}))
    assert osc.run(w0, t_end).energy_balance() < 1e-8


# -- FE inputs beyond the verified range ---------------------------------------------------------------

@pytest.mark.parametrize("cmd, sets, name", [
    ("solve", ("EI=1e308",), "EA"),                        # before: numpy RuntimeWarnings, exit 1
    ("solve", ("EI=1e308", "EA=1e300"), "EI"),
    ("solve", ("EA=1e21",), "EA"),                          # before: exit 0, moment balance off 8e-6
    ("solve", ("m=1e-300",), "EI"),
])
def test_fe_stiffness_outside_the_verified_range(cmd, sets, name):
    code, out, err, _ = run(cmd, "beam-slider", *[x for s in sets for x in ("--set", s)], "--quiet")
    assert code == 2
    clean_error(code, err, f"parameter {name}", "allowed")


# -- FE dynamics: bounded time -----------------------------------------------------------------------

def test_beam_oscillation_long_t_end_is_capped():
    """Before: t_end = 1e4 s ran for hours without output.  Now (issue 24: only absurd runs, estimated
    beyond 24 h of work, are refused) t_end = 1e6 s is exit 2 within seconds naming t_end and the
    usable range (derived from the measured cost per period: femslide.analysis.simulate.check_work)."""
    code, out, err, dt = run("simulate", "beam-oscillation", "--set", "t_end=1e6", "--quiet")
    assert code == 2 and dt < 20
    clean_error(code, err, "t_end", "allowed: t_end <=", "per period")


# -- beam-friction: the stick test ----------------------------------------------------------------------
# On the FE transient (issue 21) at tolerance 1e-8, where its turning points agree with the independent
# model validation/friction_reference.py to ~1e-7 rad and ~4e-6 s (at the default 1e-6: ~3e-6 rad, 8e-5 s).

TIGHT = "tolerance=1e-8"


def _friction(tmp_path, *sets, t_end):
    import numpy as np
    out = tmp_path / "o"
    args = [x for s in (TIGHT,) + sets for x in ("--set", s)]
    code, stdout, err, _ = run("simulate", "beam-friction", *args, "--set", f"t_end={t_end}", "--json",
                               "--quiet", "--out", str(out), timeout=300)
    assert code == 0, err
    H = np.loadtxt(out / "history.csv", delimiter=",", skiprows=1)
    return json.loads(stdout), H


def _coulomb(H, mu0):
    """Largest |F_ax| / (mu0 N) over the stuck samples of history.csv (columns t .. stuck, F_ax, N)."""
    import numpy as np
    stuck = H[:, 5] == 1
    if not stuck.any():
        return 0.0
    F, N = np.abs(H[stuck, 6]), H[stuck, 7]
    return float(np.max(F / np.maximum(mu0 * N, 1e-300)))


def test_friction_mu0_zero_never_sticks(tmp_path):
    """Before: with mu = mu0 = 0 the slide stayed locked for the whole run (converged true).
    Reference: the frictionless structure, independent model (elastica + scipy): turning points
    within 1e-6 rad (measured 8.6e-8)."""
    import friction_reference as fr
    res, H = _friction(tmp_path, "mu=0", "mu0=0", t_end=1.3)
    assert res["stuck_time"] == 0 and res["energy"]["dissipated"] == 0 and not res["events"]
    slide = res["peaks"]["joints"]["clamp"]
    assert slide["slide_max"] - slide["slide_min"] > 1e-2
    ref = fr.simulate(mu=0.0, mu0=0.0, t_end=1.3)
    got = [(q["t"], q["w"]) for q in res["turning_points"] if abs(q["w"]) > 1e-4]
    big = [(t, w) for t, w in ref["turning"] if abs(w) > 1e-4]
    assert len(got) == len(big) >= 2
    assert max(abs(a[1] - b[1]) for a, b in zip(got, big)) < 1e-6


def test_friction_mu_equal_mu0_obeys_coulomb(tmp_path):
    """Before: with mu = mu0 = 0.05 the guide force inside stuck phases reached 57 mu0 N.  Energy
    balance at tolerance 1e-8 within 1e-5 (measured 4.4e-6)."""
    res, H = _friction(tmp_path, "mu=0.05", "mu0=0.05", t_end=1.3)
    assert _coulomb(H, 0.05) <= 1 + 1e-6
    assert res["stuck_force_ratio_max"] <= 1 + 1e-6 and res["energy_balance"] < 1e-5


def test_friction_slips_where_the_independent_model_slips(tmp_path):
    """mu = 0.1, mu0 = 0.15, ag = 2, theta_ratio = 0.6.  Before: locked for the whole run (a round-off
    change flipped it), while an independent model slips to 0.039 rad.  In the vertical state
    N = 0: the clamp holds only if |dF_ax/dphi| <= mu0 |dN/dphi|, which fails here by far.
    Reference: validation/friction_reference.py (extensible elastica by shooting, scipy events):
    stuck time within 1e-4 s, turning points within 1e-6 rad and 1e-5 s (measured 1.6e-6 s, 1.2e-7
    rad, 2.6e-6 s)."""
    import friction_reference as fr
    sets = dict(mu=0.1, mu0=0.15, ag=2.0, theta_ratio=0.6)
    res, H = _friction(tmp_path, *[f"{k}={v}" for k, v in sets.items()], t_end=1.6)
    ref = fr.simulate(t_end=1.6, **sets)
    assert res["stuck_time"] < 0.05 and abs(res["stuck_time"] - fr.stuck_time(ref)) < 1e-4
    got = [(q["t"], q["w"]) for q in res["turning_points"] if abs(q["w"]) > 1e-4]
    big = [(t, w) for t, w in ref["turning"] if abs(w) > 1e-4]
    assert len(got) == len(big) == 2
    assert abs(got[-1][1] - 0.0387268) < 1e-6          # the peak the issue quotes as 0.039 rad
    assert max(abs(a[1] - b[1]) for a, b in zip(got, big)) < 1e-6
    assert max(abs(a[0] - b[0]) for a, b in zip(got, big)) < 1e-5
    assert _coulomb(H, 0.15) <= 1 + 1e-6


@pytest.mark.slow
@pytest.mark.parametrize("sets, tol", [(dict(), 1e-6), (dict(mu=0.2, mu0=0.24, ag=2.0, theta_ratio=0.5), 1e-6),
                                       (dict(mu=0.5, mu0=0.6, ag=3.0), 1e-5)])
def test_friction_against_the_independent_model(tmp_path, sets, tol):
    """Turning points (|phi| > 1e-4) of the independent model within tol rad at tolerance 1e-8
    (measured 1.5e-7, 4.7e-8 and 4.1e-6 rad: the last with long stuck phases and 15 turning points);
    Coulomb's law on every stuck step."""
    import friction_reference as fr
    res, H = _friction(tmp_path, *[f"{k}={v}" for k, v in sets.items()], t_end=2.5)
    ref = fr.simulate(t_end=2.5, **sets)
    got = [(q["t"], q["w"]) for q in res["turning_points"] if abs(q["w"]) > 1e-4]
    big = [(t, w) for t, w in ref["turning"] if abs(w) > 1e-4]
    assert len(got) == len(big)
    assert max(abs(a[1] - b[1]) for a, b in zip(got, big)) < tol
    assert _coulomb(H, sets.get("mu0", 0.24)) <= 1 + 1e-6


# -- error estimates at the defaults -----------------------------------------------------------------------
# Before: `femslide solve beam-extra-mass` reported converged with error_estimate 3.1e-6 (round-off of the
# elements' end moments, ~1e-4 P a here) and M_max off by 2.2e-6 from the fine-mesh limit.

FE_SCENES = ("beam-slider", "beam-fixed", "beam-both", "beam-spring", "beam-extra-mass",
             "cantilever-moment", "cantilever-load")


@pytest.mark.parametrize("scene", FE_SCENES)
def test_default_runs_meet_the_error_target_and_the_estimate_is_honest(scene):
    """At the defaults every FE scene converges with error_estimate <= 1e-6 (the contract's target),
    and its M_max lies within max(2 x estimate, 1e-8) (relative) of the fine-mesh limit estimated
    from fixed 32- and 64-element meshes (Richardson, h^2).  This checks the honesty of the adaptive
    run's estimate against another route through the same model (not the model itself: the
    independent references are in test_fe_statics, test_large_rotation and test_linear_frames)."""
    code, out, err = cli("solve", scene, "--json")
    assert code == 0, err
    r = json.loads(out)
    assert r["converged"] and r["error_estimate"] <= 1e-6, r["error_estimate"]
    fixed = []
    for n in (32, 64):
        c, o, e = cli("solve", scene, "--json", "--set", f"n_elements={n}")
        assert c == 0, e
        fixed.append(json.loads(o)["M_max"])
    ref = (4.0 * fixed[1] - fixed[0]) / 3.0
    # (beam-extra-mass's fixed-mesh M_max carries round-off of ~5e-7 of itself - the elements' end
    # moments, ~1e-4 P a, against M_max ~ 1e-3 P a -: 32 elements give 1.40086151e-3 through the
    # compiled kernel and 1.40086202e-3 through numpy, so its Richardson reference is that uncertain)
    floor = 1e-6 if scene == "beam-extra-mass" else 1e-8
    assert abs(r["M_max"] - ref) <= max(2.0 * r["error_estimate"], floor) * abs(ref), (r["M_max"], ref)
