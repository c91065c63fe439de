"""Linear buckling (``femslide buckling``) against the Euler loads of columns.

References (exact, inextensible Euler-Bernoulli columns) and tolerances:

* cantilever (clamped, free end) under an end load P: P_cr = pi^2 EI / (4 L^2), the higher modes
  (2k - 1)^2 P_cr;
* pinned-roller (pin, roller along the axis) under an end load: P_cr = pi^2 EI / L^2, modes k^2 P_cr;
* clamped-pinned (a propped column): P_cr = (kL)^2 EI / L^2 with tan(kL) = kL (kL = 4.4934...,
  root by scipy's brentq);

each within 1e-4 at default settings (adaptive meshes), about the loaded equilibrium (default) and
about the reference state.  The default axial stiffness EA = 1e6 m^-2 EI makes the prebuckling
shortening P/EA ~ 1e-6 (the loaded-equilibrium value differs from Euler's by that much).  Convergence
with the mesh: on fixed meshes of 4, 8, 16, 32 elements the error of the lowest load factor falls like
h^2 (ratio 4 +- 10 % per doubling), and the reported error estimate is within a factor 3 of the true
error (the estimate comparing each mesh with its half, over 3); the adaptive default's estimate is at
least 1/3 of its true error and below 1e-6.
"""
from __future__ import annotations

import json
import math
import os
import subprocess
import sys

import pytest
from scipy.optimize import brentq

from femslide.analysis.buckling import buckling
from femslide.model.structure import Structure

EI, L, P = 2.4e5, 3.0, 1e4


def column(support="cantilever", elements=None, EA=None):
    s = Structure(gravity=(0.0, 0.0))
    kw = {"elements": elements} if elements else {}
    if EA:
        kw["EA"] = EA
    if support == "cantilever":
        s.rod("c", (0.0, 0.0), (0.0, L), EI=EI, **kw)
        s.weld("base", "c.start", "ground")
        s.force("P", "c.end", force=(0.0, -P))
    else:
        s.rod("c", (0.0, 0.0), (L, 0.0), EI=EI, **kw)
        if support == "pinned-roller":
            s.pin("A", "c.start", "ground")
        else:
            s.weld("A", "c.start", "ground")
        s.roller("B", "c.end", "ground", axis=(1.0, 0.0))
        s.force("P", "c.end", force=(-P, 0.0))
    return s


def euler(support):
    if support == "cantilever":
        return math.pi**2 * EI / (4 * L**2), [1, 9, 25]
    if support == "pinned-roller":
        return math.pi**2 * EI / L**2, [1, 4, 9]
    kl = brentq(lambda x: math.tan(x) - x, 4.4, 4.6, xtol=1e-15)
    return kl**2 * EI / L**2, [1]


@pytest.mark.parametrize("support", ["cantilever", "pinned-roller", "clamped-pinned"])
@pytest.mark.parametrize("about", ["equilibrium", "reference"])
def test_euler_loads(support, about):
    """The lowest load factors times P equal the Euler loads within 1e-4 at default settings."""
    Pcr, ratios = euler(support)
    out = buckling(column(support).freeze(), count=len(ratios), about=about)
    lam = out.values["load_factors"]
    assert len(lam) == len(ratios)
    for got, k in zip(lam, ratios):
        assert got * P == pytest.approx(k * Pcr, rel=1e-4)
    assert out.values["error_estimate"] <= 1e-6
    assert abs(lam[0] * P / Pcr - 1.0) <= 1e-6   # the lowest one far better than asked


def test_buckling_converges_like_h2_with_an_honest_estimate():
    """Fixed meshes of 4 .. 32 elements: the error of the lowest load factor (about the reference,
    EA large so that the inextensible Euler load is the limit) falls by 4 per doubling (+-10 %) and
    the estimate against the half mesh is within a factor 3 of the true error."""
    Pcr, _ = euler("pinned-roller")
    errs = []
    for n in (4, 8, 16, 32):
        v = buckling(column("pinned-roller", elements=n, EA=1e6 * EI * 1e4).freeze(), count=1,
                     about="reference").values
        err = abs(v["load_factors"][0] * P / Pcr - 1.0)
        errs.append(err)
        assert err / 3.0 <= v["error_estimate"] <= 3.0 * err
    for a, b in zip(errs, errs[1:]):
        assert 3.6 <= a / b <= 4.4


def test_adaptive_estimate_is_honest():
    """The adaptive default's estimate is not smaller than a third of its true error."""
    Pcr, _ = euler("cantilever")
    v = buckling(column("cantilever", EA=1e6 * EI * 1e4).freeze(), count=1, about="reference").values
    err = abs(v["load_factors"][0] * P / Pcr - 1.0)
    assert v["error_estimate"] >= err / 3.0
    assert v["error_estimate"] <= 1e-6


def test_tension_does_not_buckle():
    """A rod in tension has no positive buckling load factor (a note says why)."""
    s = Structure(gravity=(0.0, 0.0))
    s.rod("c", (0.0, 0.0), (0.0, L), EI=EI)
    s.weld("base", "c.start", "ground")
    s.force("P", "c.end", force=(0.0, P))
    v = buckling(s.freeze(), count=2).values
    assert v["load_factors"] == [] and "tension" in v["note"]


def test_buckling_command_line(tmp_path):
    """`femslide buckling FILE --json --out DIR`: the load factors, a PVD series with the mode number as
    its time and each mode's load factor in its frame."""
    from femslide.app.structfile import dumps
    from femslide.output import vtu
    f = tmp_path / "column.toml"
    f.write_text(dumps(column("cantilever")))
    out = tmp_path / "out"
    p = subprocess.run([sys.executable, "-m", "femslide", "buckling", str(f), "--json", "--count", "2",
                        "--out", str(out)], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    r = json.loads(p.stdout)
    Pcr, _ = euler("cantilever")
    assert r["load_factors"][0] * P == pytest.approx(Pcr, rel=1e-4)
    assert os.path.isfile(out / "column_buckling.pvd")
    m = vtu.read(str(out / "column_buckling_0001.vtu"))   # text field data: meshio alone cannot read it
    assert float(m.field_data["load_factor"].ravel()[0]) == pytest.approx(r["load_factors"][1])
    assert int(m.field_data["mode"].ravel()[0]) == 2
