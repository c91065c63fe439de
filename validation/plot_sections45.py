"""Plots for paper sections 4 and 5.1 with FE rods (issue 5); prints the measured exponents.

    python validation/plot_sections45.py

Writes validation/F2_vs_dm.png (|F2| against dm for several EI, log-log, beam-extra-mass) and
validation/beam_spring_vs_hinge.png (relative difference of beam-spring M_max and hinge-spring |T| at
c = 3 EI / L, l1 = L, against EI), and validation/sections45_exponents.csv.
"""
from __future__ import annotations

import csv
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))

import femslide  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
L_EXTRA, L_SPRING = 1.5, 3.0


def main():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = []
    fig, ax = plt.subplots(figsize=(6.4, 4.8))
    for EI in (1e4, 1e5, 1e6, 1e7):
        c = 3 * EI / L_EXTRA
        dms = np.logspace(np.log10(1.0 / c), -1, 13)
        F2 = [abs(femslide.solve("beam-extra-mass", EI=EI, dm=dm)["reactions"]["B1"]["Fx"]) for dm in dms]
        ax.loglog(dms, F2, "o-", ms=3, label=f"EI = {EI:.0e} N m$^2$ (c = {c:.1e})")
        for _lab, p in (("c^-1", -1.0), ("c^-0.5", -0.5), ("c^-0.2", -0.2)):
            ax.axvline(c ** p, color="0.85", lw=0.5)
    ax.set_xlabel("extra mass dm [kg]")
    ax.set_ylabel("|F2| [N]")
    ax.set_title("beam-extra-mass: |F2| vs dm (dips: F2 changes sign)", fontsize=10)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(HERE, "F2_vs_dm.png"), dpi=110)

    print("regime exponents of |F2| against c = 3EI/L (local slopes between successive EI):")
    EIs = [1e3, 1e4, 1e5, 1e6, 1e7]
    cs = np.array([3 * EI / L_EXTRA for EI in EIs])
    for lab, f in (("dm = 10/c", lambda c: 10 / c), ("dm = c^-0.5", lambda c: c ** -0.5),
                   ("dm = c^-0.2", lambda c: c ** -0.2)):
        F = np.array([abs(femslide.solve("beam-extra-mass", EI=EI, dm=f(c))["reactions"]["B1"]["Fx"])
                      for EI, c in zip(EIs, cs)])
        s = np.diff(np.log(F)) / np.diff(np.log(cs))
        print(f"  {lab:12s} " + "  ".join(f"{x:+.3f}" for x in s))
        rows.append({"regime": lab, **{f"slope_EI{EIs[i]:.0e}-{EIs[i + 1]:.0e}": s[i] for i in range(len(s))}})

    EIs = [1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10]
    diff = []
    for EI in EIs:
        fe = femslide.solve("beam-spring", EI=EI)
        hs = femslide.solve("hinge-spring", c=3 * EI / L_SPRING, l1=L_SPRING)
        diff.append(abs(fe["M_max"] - abs(hs["T"])) / abs(hs["T"]))
    print("beam-spring vs hinge-spring, relative difference of M_max and |T|:")
    print("  " + "  ".join(f"{EI:.0e}: {d:.1e}" for EI, d in zip(EIs, diff)))
    fig, ax = plt.subplots(figsize=(6.4, 4.8))
    ax.loglog(EIs, diff, "o-")
    ax.axhline(1e-6, color="r", lw=0.8, ls="--", label="1e-6")
    ax.set_xlabel("EI [N m$^2$]")
    ax.set_ylabel("|M_max(FE) - |T|(hinge)| / |T|")
    ax.set_title("beam-spring vs hinge-spring (c = 3EI/L, l1 = L)")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(HERE, "beam_spring_vs_hinge.png"), dpi=110)
    keys = sorted({k for r in rows for k in r}, key=lambda k: (k != "regime", k))
    with open(os.path.join(HERE, "sections45_exponents.csv"), "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=keys)
        w.writeheader()
        w.writerows(rows)
    print("written F2_vs_dm.png, beam_spring_vs_hinge.png, sections45_exponents.csv")


if __name__ == "__main__":
    main()
