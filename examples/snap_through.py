"""A structure that snaps: its limit point, and arc-length continuation through it.

``meshes/structures/inclined-guide.toml``: a rod (the arm, clamped at B) runs in an inclined guide
carried by a body (the head) that sits on a second rod (the post, pinned at A).  The two shallow rods
form an arch under the head's weight: the load path reaches a maximum (a limit point) at load factor
0.2322 of the weight and snaps to a state where the head hangs below the supports.

The default solve follows the principal branch and stops there: exit 1, naming the limit point and
its load factor (refined with the mesh).  With ``path="arc-length"`` femslide follows the path
through the limit point and its minimum to the first equilibrium at full load, reports both limit
points and the traced path, and writes ``path.png`` (the load factor against the head's height),
``path.csv`` and the final state into the folder given as the first argument; the script also draws
the bending moment of the state after the snap (``snapped-M.png``).

    python examples/snap_through.py out/
"""
import sys
import tempfile
from pathlib import Path

import matplotlib

matplotlib.use("Agg")   # files only, no window
import matplotlib.pyplot as plt  # noqa: E402

import femslide  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


def main(out: Path) -> None:
    out.mkdir(parents=True, exist_ok=True)
    s = femslide.load(str(ROOT / "meshes" / "structures" / "inclined-guide.toml"))
    try:
        femslide.solve(s)
    except femslide.SolverFailure as exc:
        print("principal branch:", exc.reason)
    r = femslide.solve(s, path="arc-length")
    for lp in r["limit_points"]:
        print(f"{lp['kind']:8s} of the load factor: {lp['load_factor']:.7f} "
              f"(estimated error {lp['error_estimate']:.0e}), head at y = {lp['bodies']['head']['y']:.4f} m")
    head = r["bodies"]["head"]
    print(f"after the snap at full load: head at ({head['x']:.4f}, {head['y']:.4f}) m, "
          f"turned {head['rotation']:.4f} rad; stable: {r['stable']}")
    for path in r.write(out):
        print(path)
    ax = femslide.plot(r, diagram="M")
    ax.figure.savefig(out / "snapped-M.png", dpi=110, bbox_inches="tight")
    plt.close(ax.figure)
    print(out / "snapped-M.png")


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path(tempfile.mkdtemp(prefix="femslide-snap-")))
