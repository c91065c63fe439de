"""Mesh convergence of cantilever-load (p_ratio = 1, L = 1, EI = 1, default EA = 1e6 EI) on fixed meshes
n_elements = 1, 2, 4, ..., 1024, plus femslide's adaptive (Richardson) run.

For every mesh: tip u, v, theta and M_max, the true relative error of M_max and the largest tip error
(|du|, |dv| in units of L, |dtheta|/theta) against the exact elastica of the same model (extensible,
EA = 1e6 EI: ``references.cantilever_load_shooting``), the distance to the inextensible elliptic-
integral elastica (floors at the EA effect ~2.6e-7), femslide's error_estimate, and the wall time.
Prints the table and writes validation/cantilever_convergence.csv and .png (error vs run time).
Run:  python validation/cantilever_convergence.py
"""
from __future__ import annotations

import csv
import pathlib
import sys
import time

_HERE = pathlib.Path(__file__).resolve().parent
for _p in (str(_HERE.parent), str(_HERE)):
    if _p not in sys.path:
        sys.path.insert(0, _p)

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402
import references as ref  # noqa: E402

import femslide  # noqa: E402

P_RATIO = 1.0
NS = [2 ** k for k in range(11)]


def tip_error(tip, exact):
    return max(abs(tip["u"] - exact["u"]), abs(tip["v"] - exact["v"]),
               abs(tip["theta"] - exact["theta"]) / abs(exact["theta"]))


def run(n):
    kw = {} if n is None else {"n_elements": n}
    best = None
    for _ in range(3):   # best of 3 wall times (the first call also pays imports)
        t0 = time.perf_counter()
        r = femslide.solve("cantilever-load", p_ratio=P_RATIO, **kw)
        dt = time.perf_counter() - t0
        best = dt if best is None else min(best, dt)
    return r, best


def main():
    exact = ref.cantilever_load_shooting(P_RATIO, EA=1e6)
    inext = ref.cantilever_load(P_RATIO)
    femslide.solve("cantilever-load", p_ratio=P_RATIO, n_elements=2)   # warm-up (imports)
    rows = []
    for n in NS + [None]:
        r, dt = run(n)
        tip = r["tip"]
        rows.append({
            "n_elements": n if n is not None
            else f"adaptive({r.solution.level.model.elements.size if r.solution else '?'})",
            "u": tip["u"], "v": tip["v"], "theta": tip["theta"], "M_max": r["M_max"],
            "err_M_true": abs(r["M_max"] / exact["M_max"] - 1.0),
            "err_tip_true": tip_error(tip, exact),
            "err_tip_vs_inextensible": tip_error(tip, inext),
            "error_estimate": r["error_estimate"],
            "wall_time_s": dt,
        })
    keys = list(rows[0])
    print(f"cantilever-load p_ratio={P_RATIO}: exact (EA=1e6 EI) u={exact['u']:.15g} v={exact['v']:.15g} "
          f"theta={exact['theta']:.15g} M_max={exact['M_max']:.15g}")
    print(f"{'n':>14} {'u':>19} {'v':>19} {'theta':>19} {'errM':>9} {'errtip':>9} {'vs inext':>9} "
          f"{'estimate':>9} {'ratio':>7} {'time[s]':>9}")
    for w in rows:
        est = w["error_estimate"]
        ratio = est / w["err_M_true"] if (est is not None and w["err_M_true"] > 0) else float("nan")
        print(f"{str(w['n_elements']):>14} {w['u']:19.15f} {w['v']:19.15f} {w['theta']:19.15f} "
              f"{w['err_M_true']:9.2e} {w['err_tip_true']:9.2e} {w['err_tip_vs_inextensible']:9.2e} "
              f"{(est if est is not None else float('nan')):9.2e} {ratio:7.3g} {w['wall_time_s']:9.4f}")
    with open(_HERE / "cantilever_convergence.csv", "w", newline="") as fh:
        wr = csv.DictWriter(fh, fieldnames=keys)
        wr.writeheader()
        for w in rows:
            wr.writerow({k: (repr(v) if isinstance(v, float) else v) for k, v in w.items()})
    fixed = [w for w in rows if isinstance(w["n_elements"], int)]
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.5))
    t = [w["wall_time_s"] for w in fixed]
    ax[0].loglog(t, [w["err_M_true"] for w in fixed], "o-", label="M_max: true error")
    ax[0].loglog(t, [w["err_tip_true"] for w in fixed], "s-", mfc="none", label="tip: true error")
    ax[0].loglog(t, [w["error_estimate"] or float("nan") for w in fixed], "^--", mfc="none",
                 label="femslide error_estimate (N vs N/2)")
    ad = rows[-1]
    ax[0].loglog([ad["wall_time_s"]], [ad["err_M_true"]], "r*", ms=12, label=f"{ad['n_elements']}: M_max")
    ax[0].loglog([ad["wall_time_s"]], [ad["err_tip_true"]], "m*", ms=9, label="adaptive: tip")
    for w in fixed:
        ax[0].annotate(str(w["n_elements"]), (w["wall_time_s"], w["err_M_true"]), fontsize=7)
    ax[0].xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
    ax[0].set_xlabel("wall time [s]")
    ax[0].set_ylabel("relative error")
    ax[0].set_title("cantilever-load p_ratio=1: error vs run time")
    ax[0].grid(True, which="both", lw=0.3)
    ax[0].legend(fontsize=7)
    h = [1.0 / w["n_elements"] for w in fixed]
    ax[1].loglog(h, [w["err_M_true"] for w in fixed], "o-", label="M_max: true error")
    ax[1].loglog(h, [w["err_tip_true"] for w in fixed], "s-", mfc="none", label="tip: true error")
    ax[1].loglog(h, [w["err_tip_vs_inextensible"] for w in fixed], "x:", label="tip vs inextensible elastica")
    ax[1].loglog(h, [0.1 * x * x for x in h], "k--", lw=0.8, label="~h$^2$")
    ax[1].set_xlabel("h = L / n_elements")
    ax[1].set_ylabel("relative error")
    ax[1].set_title("mesh convergence")
    ax[1].grid(True, which="both", lw=0.3)
    ax[1].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(_HERE / "cantilever_convergence.png", dpi=130)
    print(f"wrote {_HERE / 'cantilever_convergence.csv'} and {_HERE / 'cantilever_convergence.png'}")


if __name__ == "__main__":
    main()
