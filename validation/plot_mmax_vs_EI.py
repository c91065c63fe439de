"""M_max vs EI (log-log) for beam-slider and beam-fixed, EI = 1e1 .. 1e12 N m^2, with the 1-term and
2-term asymptotes of SPEC section 3 and the independent elastica reference (validation/references.py).

Writes validation/mmax_vs_EI.png and prints the table (FE, reference, asymptotes, local slope).
Run:  python validation/plot_mmax_vs_EI.py
"""
from __future__ import annotations

import math
import pathlib
import sys

_HERE = pathlib.Path(__file__).resolve().parent
for _p in (str(_HERE.parent), str(_HERE)):
    if _p not in sys.path:
        sys.path.insert(0, _p)

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import references as ref  # noqa: E402

import femslide  # noqa: E402
from femslide.scenes import series  # noqa: E402

GEOM = dict(a=1.0, b=0.5, d=0.2, l=3.0, m=1.0, g=9.81)
EIS = [10.0 ** (k / 2) for k in range(2, 25)]   # 1e1 .. 1e12, half decades


def main():
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.5))
    EIa = np.logspace(1, 12, 200)
    a1 = [series.M_max_asymptote(1, x, **GEOM) for x in EIa]
    a2 = [series.M_max_asymptote(2, x, **GEOM) for x in EIa]
    for kind, scene in (("slider", "beam-slider"), ("fixed", "beam-fixed")):
        fe, rf = [], []
        print(f"{scene}:  EI  M_max(FE)  M_max(elastica, EA=1e6 EI)  rel.diff  1-term  2-term  slope")
        for EI in EIS:
            try:
                M = femslide.solve(scene, EI=EI)["M_max"]
            except femslide.SolverFailure as exc:
                print(f"  EI={EI:.3g}: FE failed: {exc}")
                M = math.nan
            R = ref.solve_structure(kind, EI, EA_ratio=1e6)["M_max"]
            fe.append(M)
            rf.append(R)
        fe, rf = np.array(fe), np.array(rf)
        slope = np.gradient(np.log(fe), np.log(EIS))
        for EI, M, R, s in zip(EIS, fe, rf, slope):
            print(f"  {EI:9.3g} {M:16.10g} {R:16.10g} {abs(M / R - 1):9.2e} "
                  f"{series.M_max_asymptote(1, EI, **GEOM):12.6g} {series.M_max_asymptote(2, EI, **GEOM):12.6g} "
                  f"{s:7.4f}")
        mk = "o" if kind == "slider" else "s"
        ax[0].loglog(EIS, fe, mk, mfc="none", label=f"{scene} (FE)")
        ax[0].loglog(EIS, rf, "-", lw=0.8, label=f"{scene} (elastica)")
        e1 = np.abs(np.array([series.M_max_asymptote(1, x, **GEOM) for x in EIS]) / fe - 1)
        e2 = np.abs(np.array([series.M_max_asymptote(2, x, **GEOM) for x in EIS]) / fe - 1)
        ax[1].loglog(EIS, e1, mk + "-", mfc="none", label=f"{scene}: 1-term")
        ax[1].loglog(EIS, e2, mk + "--", mfc="none", label=f"{scene}: 2-term")
    ax[0].loglog(EIa, a1, "k:", label="1-term asymptote")
    ax[0].loglog(EIa, a2, "k--", lw=0.8, label="2-term asymptote")
    ax[0].set_xlabel("EI [N m$^2$]")
    ax[0].set_ylabel("M_max [N m]")
    ax[0].set_title("M_max vs EI (a=1, b=0.5, d=0.2, l=3, m=1)")
    ax[0].legend(fontsize=7)
    ax[0].grid(True, which="both", lw=0.3)
    ax[1].loglog(EIa, 3.0 * EIa ** (-1 / 3), "k:", lw=0.8, label="~EI$^{-1/3}$")
    ax[1].loglog(EIa, 30.0 * EIa ** (-2 / 3), "k--", lw=0.8, label="~EI$^{-2/3}$")
    ax[1].set_xlabel("EI [N m$^2$]")
    ax[1].set_ylabel("relative error of the asymptote")
    ax[1].set_title("asymptote error (FE M_max as truth)")
    ax[1].legend(fontsize=7)
    ax[1].grid(True, which="both", lw=0.3)
    fig.tight_layout()
    out = _HERE / "mmax_vs_EI.png"
    fig.savefig(out, dpi=130)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
