"""Every script in examples/ runs (in a subprocess, as a user runs it) and writes its outputs into
the folder given as its first argument."""
from __future__ import annotations

import os
import pathlib
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]
EXAMPLES = sorted((ROOT / "examples").glob("*.py"))

# files some examples must write (every example must write at least one file)
EXPECTED = {
    "paper_ei_sweep.py": ["ei_sweep.csv", "M_max_vs_EI.png"],
    "friction_hysteresis.py": ["history.csv", "hysteresis.png", "run/result.json", "run/history.csv"],
    "load_combinations.py": ["combinations.csv", "envelope_M.csv", "envelope_M.png", "structure_SLS.vtu"],
    "column_buckling.py": ["buckling_modes.png", "structure_buckling.pvd", "structure_buckling_0000.vtu"],
    "snap_through.py": ["path.csv", "path.png", "snapped-M.png", "structure.vtu"],
    "seismic_isolation.py": ["comparison.csv", "comparison.png", "records.png", "record_1.csv"],
    "thermal_friction_deck.py": ["columns_M.png", "friction/steps.csv", "friction/hysteresis_C.png"],
}


def test_examples_exist():
    assert {p.name for p in EXAMPLES} >= set(EXPECTED)


@pytest.mark.parametrize("script", EXAMPLES, ids=[p.name for p in EXAMPLES])
def test_example_runs_and_writes_its_outputs(script, tmp_path):
    pytest.importorskip("matplotlib")
    pytest.importorskip("pandas")
    out = tmp_path / "out"
    env = {**os.environ, "MPLBACKEND": "Agg", "FEMSLIDE_EXAMPLE_SIZE": "small",   # (examples with a small size)
           "PYTHONPATH": str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", "")}
    r = subprocess.run([sys.executable, str(script), str(out)], capture_output=True, text=True,
                       cwd=tmp_path, env=env, timeout=300)
    assert r.returncode == 0, r.stderr[-3000:]
    written = [p for p in out.rglob("*") if p.is_file()]
    assert written, f"{script.name} wrote nothing into {out}"
    for name in EXPECTED.get(script.name, []):
        f = out / name
        assert f.is_file() and f.stat().st_size > 0, f"{script.name}: {name} missing or empty"
    for png in out.rglob("*.png"):
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", png
    if script.name == "paper_ei_sweep.py":
        import pandas as pd
        df = pd.read_csv(out / "ei_sweep.csv")
        assert len(df) == 9 and df["converged"].all() and {"EI", "M_max", "reactions.B1.Fx"} <= set(df)
    if script.name == "seismic_isolation.py":   # the sliders cut the column moments, drifts, floor accelerations
        import pandas as pd
        df = pd.read_csv(out / "comparison.csv")
        fixed, iso = df[df["frame"] == "fixed base"], df[df["frame"] == "isolated"]
        assert len(fixed) == len(iso) == 2
        for key in ("column foot M [kN m]", "drift 1 [mm]", "floor2 abs. acc. [m/s^2]"):
            assert (iso[key].to_numpy() < fixed[key].to_numpy()).all(), key
        assert (iso["slip events"] > 0).all() and (iso["residual slide [mm]"].abs() > 0).all()
