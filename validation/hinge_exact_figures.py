"""Print the figures behind validation/test_hinge_exact.py: the largest relative differences between
femslide's hinge scenes and the independent exact solution, and the largest statics-closure residuals.

    python validation/hinge_exact_figures.py
"""
from __future__ import annotations

import pathlib
import sys

_HERE = pathlib.Path(__file__).resolve().parent
for _p in (str(_HERE.parent), str(_HERE)):
    if _p not in sys.path:
        sys.path.insert(0, _p)

import hinge_reference as ref  # noqa: E402
import test_hinge_exact as t  # noqa: E402


def main():
    worst = {}
    n = 0
    cases = [(m, {"c": c}) for m in ("slider", "fixed", "spring") for c in t.C_VALUES]
    cases += [("extra", {"c": c, "dm": f(c)}) for f in t.REGIMES.values() for c in t.C_EXTRA]
    cases += [(m, {"c": c, "d": d, **({"dm": 1e-3} if m == "extra" else {})})
              for m in ("slider", "fixed", "spring", "extra") for d in (-1.3, -2.0) for c in (1e3, 1e6, 1e10)]
    for model, kw in cases:
        r = ref.solve(model, **kw)
        fem = t._fem(model, **kw)
        got = {"phi": fem["phi"], "T": fem["T"], "F2": fem["reactions"]["B1"]["Fx"],
               "psi": fem["psi"], "slide": fem["slide"], "N2": fem["reactions"]["B1"]["Fy"]}
        want = {"phi": r.phi, "T": r.T, "F2": r.F2, "psi": r.psi, "slide": r.slide, "N2": r.N2}
        for key in got:
            d = abs(float(got[key] / want[key] - 1))
            if d > worst.get(key, (0, None))[0]:
                worst[key] = (d, (model, kw))
        n += 1
    print(f"femslide vs independent exact solution, {n} cases (c = 1e2 .. 1e12, regimes of 5.1, phi < 0):")
    for key, (d, case) in worst.items():
        print(f"  max rel. diff {key:6}: {d:.2e}   at {case}")
    resid, n = {}, 0
    for model, p in t._closure_cases():
        fem = t._fem(model, **p)
        for name, v in t._free_body_residuals(model, fem, p).items():
            if abs(v) >= resid.get(name, (0, None))[0]:
                resid[name] = (abs(v), (model, p["c"], p.get("dm", 0.0)))
        n += 1
    print(f"statics closure of femslide solutions, {n} cases (force eq. / P, moment eq. / (P a)):")
    for name, (v, case) in sorted(resid.items()):
        print(f"  max |{name}|: {v:.2e}   at {case}")


if __name__ == "__main__":
    main()
