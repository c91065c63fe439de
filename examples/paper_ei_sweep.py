"""The paper's structure and its EI sweep: a DataFrame and a log-log plot of M_max against EI.

The built-in scene ``beam-slider`` is the structure of Dosaev (2023): a rigid body (2a x 2b, mass m)
on two rods of length l pinned to the ground at A1 = (0, 0) and B1 = (2a, 0); the left rod is rigid,
the right one a flexible beam (bending stiffness EI) whose top end slides in a clamp fixed to the
body.  Gravity tilts the body by phi (> 0 towards B1) and bends the sliding rod; its largest bending
moment M_max grows like EI^(1/3): with the rod's equivalent spring-hinge stiffness c = 3 EI / l,
M_max ~ c^(1/3).  The leading term of the asymptote (and its second term) is

    M_max = (3 EI / (4 a))^(1/3) (P (a + d))^(2/3) + P (l + b) l / (3 a),      P = m g.

Run::

    python examples/paper_ei_sweep.py [OUTPUT_FOLDER]

It writes ``ei_sweep.csv`` (one row per EI: the varied EI, converged, M_max, phi, slide, the
reactions ``reactions.A1.Fx`` ... in N, iterations, error_estimate, wall_time_s) and
``M_max_vs_EI.png`` into OUTPUT_FOLDER (default: a new temporary folder), and prints the table.
SI units throughout.  Takes a few seconds.
"""
from __future__ import annotations

import os
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import femslide  # noqa: E402
from femslide.scenes.series import M_max_asymptote  # noqa: E402

out = sys.argv[1] if len(sys.argv) > 1 else tempfile.mkdtemp(prefix="femslide-ei-sweep-")
os.makedirs(out, exist_ok=True)

# the scene's parameters (its defaults; any of them can be changed like EI)
a, b, d, l, m, g = 1.0, 0.5, 0.2, 3.0, 1.0, 9.81  # noqa: E741  (the paper's names)
fixed = dict(a=a, b=b, d=d, l=l, m=m, g=g)

# one solve per EI, each from scratch; jobs=2 would run them in two processes with the same rows
EI = np.logspace(2, 10, 9)                       # N m^2
df = femslide.sweep("beam-slider", EI=EI, fixed=fixed, quiet=True)
df.to_csv(os.path.join(out, "ei_sweep.csv"), index=False)
print(df[["EI", "converged", "M_max", "phi", "slide", "reactions.B1.Fx", "error_estimate"]]
      .to_string(index=False, float_format="%.6g"))

# the asymptotes: one term (the c^(1/3) law) and two terms
EI_fine = np.geomspace(EI.min(), EI.max(), 200)
one_term = M_max_asymptote(1, EI_fine, **fixed)     # (3 EI/(4a))^(1/3) (P (a+d))^(2/3)
two_terms = M_max_asymptote(2, EI_fine, **fixed)    # + P (l+b) l/(3a)

ok = df[df["converged"]]
slope = np.diff(np.log(ok["M_max"].to_numpy())) / np.diff(np.log(ok["EI"].to_numpy()))
print(f"local slope d log M_max / d log EI: {slope[0]:.3f} (EI = 1e2 .. 1e3) -> {slope[-1]:.4f} "
      f"(EI = 1e9 .. 1e10); the asymptote's 1/3 = {1 / 3:.4f}")
last = ok.iloc[-1]
ref = M_max_asymptote(2, last["EI"], **fixed)
print(f"EI = {last['EI']:.3g} N m^2: M_max = {last['M_max']:.6g} N m, two-term asymptote {ref:.6g} N m "
      f"(relative difference {abs(last['M_max'] - ref) / ref:.2e})")

fig, ax = plt.subplots(figsize=(6.4, 4.6))
ax.loglog(ok["EI"], ok["M_max"], "o", color="C0", label="femslide (beam-slider)")
ax.loglog(EI_fine, one_term, "--", color="C1", label=r"$(3EI/4a)^{1/3}(P(a+d))^{2/3} \propto c^{1/3}$")
ax.loglog(EI_fine, two_terms, ":", color="C2", label="two-term asymptote")
ax.set_xlabel("EI [N m$^2$]")
ax.set_ylabel("M_max [N m]")
ax.set_title("Sliding rod of the paper's structure: largest bending moment")
ax.grid(True, which="both", alpha=0.3)
ax.legend(fontsize=8)
fig.tight_layout()
png = os.path.join(out, "M_max_vs_EI.png")
fig.savefig(png, dpi=100)
print(f"wrote {os.path.join(out, 'ei_sweep.csv')} and {png}")
