"""A deck on two columns through a summer-winter temperature cycle: the forces friction locks in.

A 40 m concrete deck rests on two 8 m columns.  At the left column it is pinned to the column top; at
the right column it sits on a sliding bearing (a roller along the deck: free to turn) with friction: kinetic
coefficient mu = 0.03, static mu0 = 0.05 (PTFE on steel).  The deck's self-weight presses the
bearing.  The deck is built at 0 K, warms by 25 K in summer, cools by 20 K below the building
temperature in winter, and comes back - twice.  Each state is a ``[[step]]`` of the load history
(load case "thermal" with its factor), solved quasi-statically with Coulomb friction in the bearing:
stuck while its force stays below mu0 N, slipping at mu N against the slide otherwise.

The same deck is solved with a frictionless bearing (the columns carry nothing from temperature) and
with the bearing fixed (a pin: the deck cannot expand freely and pushes both columns).  The script
prints the columns' root moments at every step of the three cases and the bearing's state, and
writes into the folder given as its first argument (default: a new temporary folder)
``columns_M.png`` (root moments of both columns along the history, the three cases), the
history's ``steps.csv`` and the bearing's hysteresis loop ``hysteresis_bearing.png``.

    python examples/thermal_friction_deck.py out/
"""
import sys
import tempfile
from pathlib import Path

import femslide

H, SPAN = 8.0, 40.0                  # m
TEMPS = [0.0, 25.0, 0.0, -20.0, 0.0, 25.0, 0.0, -20.0, 0.0]   # K, the load history's steps


def deck(bearing: str) -> femslide.Structure:
    """``bearing``: "friction", "free" (frictionless) or "fixed" (a pin)."""
    s = femslide.Structure(gravity=(0.0, -9.81))
    column = dict(E=33e9, I=0.13, A=1.13)                     # a 1.2 m round concrete column
    s.rod("left", (0.0, 0.0), (0.0, H), **column)
    s.rod("right", (SPAN, 0.0), (SPAN, H), **column)
    s.rod("deck", (0.0, H), (SPAN, H), E=33e9, I=0.9, A=4.2, rhoA=10500.0, alpha=1.0e-5, depth=1.6)
    s.weld("A", "left.start", "ground")
    s.weld("D", "right.start", "ground")
    s.pin("B", "deck.start", "left.end")
    if bearing == "fixed":
        s.pin("C", "deck.end", "right.end")
    else:
        friction = dict(mu=0.03, mu0=0.05) if bearing == "friction" else {}
        s.roller("C", "deck.end", "right.end", axis=(1.0, 0.0), **friction)
    s.thermal("temperature", "deck", dT=1.0, case="thermal")
    for i, t in enumerate(TEMPS):
        s.step({"dead": 1.0, "thermal": t}, name=f"{i}: {t:+.0f} K")
    return s


def main(out: Path) -> None:
    out.mkdir(parents=True, exist_ok=True)
    runs = {case: femslide.solve(deck(case), theory="linear") for case in ("friction", "free", "fixed")}
    print("root moments of the columns [kN m] (first-order theory)")
    print(f"{'step':>10s} " + " ".join(f"{c + ' ' + col:>16s}" for c in runs for col in ("left", "right")))
    for i, name in enumerate(st["name"] for st in runs["friction"]["steps"]):
        row = [runs[c]["steps"][i]["reactions"][col]["M"] / 1e3 for c in runs for col in ("A", "D")]
        state = runs["friction"]["steps"][i]["friction"]["C"]
        print(f"{name:>10s} " + " ".join(f"{v:16.1f}" for v in row)
              + f"   bearing {state['state']}, slide {state['slide'] * 1e3:6.2f} mm,"
              f" force {state['force'] / 1e3:7.1f} kN")
    f = runs["friction"]
    print("friction events:", ", ".join(f"{e['kind']} in step {e['step']} at t = {e['load_parameter']:.3f}"
                                        for e in f["events"]))
    for path in f.write(out / "friction"):
        print(path)
    _plot(runs, out / "columns_M.png")
    print(out / "columns_M.png")


def _plot(runs, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(8, 4.2))
    x = range(len(TEMPS))
    styles = {"friction": "-o", "free": ":s", "fixed": "--^"}
    for case, r in runs.items():
        for col, sup, colour in (("left", "A", "tab:blue"), ("right", "D", "tab:red")):
            ax.plot(x, [st["reactions"][sup]["M"] / 1e3 for st in r["steps"]], styles[case], color=colour,
                    label=f"{col} column, {case} bearing", ms=4)
    ax.set_xticks(list(x), [f"{t:+.0f} K" for t in TEMPS])
    ax.set_xlabel("deck temperature along the history (steps)")
    ax.set_ylabel("root moment of the column [kN m]")
    ax.set_title("Deck on two columns: moments locked in by the bearing's friction")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, ncol=3, loc="lower left")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path(tempfile.mkdtemp(prefix="femslide-deck-")))
