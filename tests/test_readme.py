"""The README's own structure runs as written (issue 25: its TOML example left four tables to the
reader, and its first structure was the paper's near-mechanism, which swayed 22.6 degrees with a support
pulled down, reported as plain converged).

The Python block and the TOML block of "Your own structure" are taken from README.md and run as they
are: they declare the same portal frame (results equal to 1e-12), the values quoted in the Python
block's comments are the results (to their printed digits), the frame stands on its supports (no
notes), and - the independent reference - the reactions balance the loads: sum of Fy = roof load
8 kN/m x 6 m + the beam's weight 60 kg/m x 6 m x 9.81 m/s^2, sum of Fx = -6 kN (1e-9).
"""
from __future__ import annotations

import pathlib
import re

import pytest

import femslide

ROOT = pathlib.Path(__file__).resolve().parents[1]


def block(section, lang):
    text = (ROOT / "README.md").read_text()
    i = text.index(section)
    m = re.compile(rf"```{lang}\n(.*?)```", re.S).search(text, i)
    return m.group(1)


@pytest.fixture(scope="module")
def python_run():
    pytest.importorskip("matplotlib")
    import matplotlib
    matplotlib.use("Agg")
    code = block("### In Python", "python")
    ns = {}
    exec(compile(code, "README.md", "exec"), ns)   # noqa: S102 - the README's own example
    return code, ns["r"]


def test_python_block_runs_and_its_comments_are_its_results(python_run):
    code, r = python_run
    assert r["converged"] and r["notes"] == []
    quoted = re.search(r"r\[\"reactions\"\]\[\"A\"\]\s+# \{'Fx': ([-\d.]+), 'Fy': ([-\d.]+), 'M': ([-\d.]+)\}", code)
    A = r["reactions"]["A"]
    for got, key in zip(quoted.groups(), ("Fx", "Fy", "M")):
        assert A[key] == pytest.approx(float(got), abs=0.051)
    M = float(re.search(r"# ([\d.]+) N m, largest", code).group(1))
    assert r["rods"]["beam"]["M_max"] == pytest.approx(M, abs=0.051)
    bearing = re.search(r"'M': ([-\d.]+), 'slide'", code)
    assert r["joints"]["bearing"]["M"] == pytest.approx(float(bearing.group(1)), abs=0.051)


def test_reactions_balance_the_loads(python_run):
    _, r = python_run
    R = r["reactions"]
    assert R["A"]["Fy"] + R["B"]["Fy"] == pytest.approx(8000.0 * 6 + 60.0 * 6 * 9.81, rel=1e-9)
    assert R["A"]["Fx"] + R["B"]["Fx"] == pytest.approx(-6000.0, rel=1e-9)


def test_toml_block_runs_as_written_and_is_the_same_frame(python_run, tmp_path):
    _, r = python_run
    f = tmp_path / "frame.toml"
    f.write_text(block("### In a TOML structure file", "toml"))
    t = femslide.solve(str(f))
    for name in ("A", "B"):
        for key in ("Fx", "Fy", "M"):
            assert t["reactions"][name][key] == pytest.approx(r["reactions"][name][key], rel=1e-12, abs=1e-6)
    assert t["M_max"] == pytest.approx(r["M_max"], rel=1e-12)


def test_simulate_table_of_the_readme_is_accepted(tmp_path):
    """The [simulate] block appended to frame.toml is a valid table (checked, not run: 3 s of shaking)."""
    from femslide.app.structfile import load
    f = tmp_path / "frame.toml"
    f.write_text(block("### In a TOML structure file", "toml") + "\n" + block("### Dynamics of your structure", "toml"))
    target = load(str(f)).for_simulate()
    target.resolve({})
