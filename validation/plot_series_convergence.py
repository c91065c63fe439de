"""Plot the relative errors of the corrected series and of the printed (2.9), (4.4) against the exact
spring-hinge models (SPEC sections 2 and 6) and print the fitted log-log slopes.

    python validation/plot_series_convergence.py
writes validation/series_convergence.png.  The exact reference is validation/hinge_reference.py
(independent 50-digit solution); the series are femslide.scenes.series in double precision.
"""
from __future__ import annotations

import pathlib
import sys

_HERE = pathlib.Path(__file__).resolve().parent
for _p in (str(_HERE.parent), str(_HERE)):
    if _p not in sys.path:
        sys.path.insert(0, _p)

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import test_series_errata as t  # noqa: E402  (same reference, ranges and fit as the tests)

from femslide.scenes import series  # noqa: E402


def main(out=_HERE / "series_convergence.png"):
    fig, axes = plt.subplots(1, 3, figsize=(16, 5.2), sharey=True)
    titles = {"slider": "section 2 (hinge-slider)", "fixed": "section 3 (hinge-fixed)",
              "spring": "section 4 (hinge-spring, k = 100)"}
    print(f"{'model':8} {'qty':4} {'series':16} {'c-range':16} {'slope':>8} {'theory':>8}")
    for ax, model in zip(axes, ("slider", "fixed", "spring")):
        hi = 1e20 if model == "spring" else 1e14
        cs = t._grid(1e2, hi, per_decade=3)
        for quantity, style in (("T", "-"), ("phi", "--")):
            for n in range(1, t.NTERMS[model] + 1):
                fn = t.corrected(model, quantity, n)
                errs = [max(t.rel_err(model, quantity, fn, c), 1e-17) for c in cs]
                ax.loglog(cs, errs, style, marker="o", ms=2.5, label=f"{quantity}, {n} term{'s' * (n > 1)}")
                lo, top = t.RANGES[(model, quantity)]
                fit_cs = t._grid(lo, top)
                slope = t.fitted_slope(fit_cs, [t.rel_err(model, quantity, fn, c) for c in fit_cs])
                print(f"{model:8} {quantity:4} {str(n) + '-term corrected':16} {lo:.0e}-{top:.0e}  "
                      f"{slope:8.4f} {-n / 3:8.4f}")
        p = t.params(model)
        printed = {"slider": ("printed (2.9)", lambda c: series.printed_T_2_9(c, **p)),
                   "spring": ("printed (4.4)", lambda c: series.printed_T_4_4(c, **p))}.get(model)
        if printed:
            label, fn = printed
            errs = [t.rel_err(model, "T", fn, c) for c in cs]
            ax.loglog(cs, errs, "k:", lw=2, label=f"T, {label}")
            lo, top = t.RANGES[(model, "T")]
            fit_cs = t._grid(lo, top)
            slope = t.fitted_slope(fit_cs, [t.rel_err(model, "T", fn, c) for c in fit_cs])
            print(f"{model:8} T    {label:16} {lo:.0e}-{top:.0e}  {slope:8.4f}   (no decay; "
                  f"error at {top:.0e}: {t.rel_err(model, 'T', fn, top):.4f})")
        for n in range(1, t.NTERMS[model] + 1):  # reference slopes c^(-n/3) through the 1e12 value
            c0 = 1e12
            e0 = t.rel_err(model, "T", t.corrected(model, "T", n), c0)
            ax.loglog([1e6, hi], [e0 * (x / c0) ** (-n / 3) for x in (1e6, hi)], color="0.75", lw=0.8)
        ax.set_title(titles[model])
        ax.set_xlabel("hinge stiffness c [N m/rad]")
        ax.grid(True, which="major", alpha=0.3)
        ax.set_ylim(1e-17, 10)
        ax.legend(fontsize=7, loc="lower left")
    axes[0].set_ylabel("relative error vs exact model")
    fig.suptitle("Spring-hinge series vs exact solution (grey: slopes -1/3, -2/3, -1)")
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
