"""Files of an FE simulation: history.csv, the PVD series of VTU frames and the hysteresis plots.
"""
from __future__ import annotations

import os

import numpy as np

from femslide.analysis import transient  # noqa: F401  (sets the BLAS threads before numpy is imported)


def _hysteresis(out_dir, name, cols, H, joints):
    """A PNG per friction joint: its friction force against its slide (the hysteresis loop);
    nothing without matplotlib."""
    if not joints:
        return []
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return []
    files = []
    for n in joints:
        fig, ax = plt.subplots(figsize=(5, 4))
        ax.plot(H[:, cols.index(f"joints.{n}.slide")], H[:, cols.index(f"joints.{n}.friction")], lw=0.8)
        ax.set_xlabel(f"slide of {n} [m]")
        ax.set_ylabel("friction force on a along the axis [N]")
        ax.set_title(f"{name}: {n}")
        ax.grid(True, alpha=0.3)
        fig.tight_layout()
        path = os.path.join(out_dir, f"hysteresis_{n}.png")
        fig.savefig(path, dpi=100)
        plt.close(fig)
        files.append(path)
    return files


def _write(out_dir, name, cols, H, frames, model):
    """history.csv and the PVD series of VTU frames (about FRAMES, evenly spread in time), each frame
    with its time and the history's values at that time as field data (femslide.output.vtu.write_series)."""
    from femslide.output.vtu import mesh_data, write_series
    from femslide.results.static import element_cuts
    os.makedirs(out_dir, exist_ok=True)
    files = []
    path = os.path.join(out_dir, "history.csv")
    np.savetxt(path, H, delimiter=",", header=",".join(cols), comments="")
    files.append(path)
    if frames:
        def series():
            for t, i, y, alpha in frames:
                # (a time step is no static equilibrium of the model's own forces: the rods' cut
                # forces and moments from the elements, not from the equilibrium recovery)
                points, cells, pdata, cdata = mesh_data(model, y, alpha, cuts=element_cuts(model, y, alpha))
                yield t, points, cells, pdata, cdata, {c: H[i, j] for j, c in enumerate(cols) if j > 0}
        files += write_series(series(), out_dir, name)
    return files
