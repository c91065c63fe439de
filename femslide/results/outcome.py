"""What a run produced, as plain data: the contract's values and the data behind its files.

Every runner (a built-in scene, a structure file's solve, simulate or modes) returns an
:class:`Outcome`; nothing in it writes files.  The application turns it into a
:class:`femslide.app.result.Result` and, when asked to, hands it to the writers of
femslide.output.files: a static VTU of a converged solution, CSV tables, a PVD series of VTU frames,
mode-shape VTUs and plots.  Units are SI everywhere except in the states (``y``, ``alpha``) of a
discrete model, which are in the model's units (femslide.model.discrete).
"""
from __future__ import annotations

from collections.abc import Callable

from femslide.records import dataclass, field


def dotted(obj: dict, prefix: str = "") -> dict:
    """Nested dicts to one dict with dotted keys (``{"reactions": {"A1": {"Fx": 1.0}}}`` ->
    ``{"reactions.A1.Fx": 1.0}``); lists are left out.  The one naming of flattened values
    everywhere: a result's :meth:`~femslide.app.result.Result.flat`, a sweep's columns, the command
    line's text output, the field data of every VTU and the columns of a time history."""
    out = {}
    for k, v in obj.items():
        if isinstance(v, dict):
            out.update(dotted(v, f"{prefix}{k}."))
        elif not isinstance(v, (list, tuple)):
            out[f"{prefix}{k}"] = v
    return out


@dataclass
class Table:
    """A CSV file: ``header`` (one name with its unit per column), ``columns`` of equal length and
    their number formats (one format string, or one per column)."""

    file: str
    header: list
    columns: list
    fmt: str | list = "%.17g"


@dataclass
class Frames:
    """States of a discrete model at times, for a PVD series of VTU frames: ``states`` holds
    (t [s], y, alpha, values) with ``values`` the run's global values at t (field data).  States of a
    motion are no static equilibria: their cut forces come from the elements."""

    model: object
    states: list


@dataclass
class ModeShapes:
    """Natural modes about a static state (y, alpha) of a discrete model: frequencies [Hz] and shapes
    over the frame dofs (model units, largest translation 1)."""

    model: object
    y: object
    alpha: object
    frequencies: list
    shapes: object


@dataclass
class Buckling:
    """Buckling modes about a state (y, alpha) of a discrete model: load factors and shapes over the
    frame dofs (model units, largest translation 1)."""

    model: object
    y: object
    alpha: object
    load_factors: list
    shapes: object


@dataclass
class Loop:
    """A friction joint's hysteresis loop: its slide [m] against the friction force on a along the
    axis [N]."""

    joint: str
    slide: object
    force: object


@dataclass
class Figure:
    """A picture to draw into ``file`` (PNG, with matplotlib; nothing without it): ``kind`` names the
    drawing (femslide.output.plots: "envelope" the bending-moment envelope of load combinations,
    "path" a traced load path), ``data`` what it draws."""

    file: str
    kind: str
    data: dict


@dataclass
class Outcome:
    """The result of one run (see the module docstring).

    ``values``: the JSON object of the contract (SI units); ``name``: the base name of its files;
    ``solution``: the converged static solution (femslide.analysis.static.Solution) of an FE statics
    run, ``static_values`` extra global values for its VTU; ``history``: the time history
    {column: array} (``t`` first) or a function computing it when first asked for; ``tables``: the
    CSV files, or a function computing them; ``frames``, ``modes``, ``loops``: a PVD series, mode
    shapes and hysteresis loops to write; ``solutions``: more static solutions, each written as its
    own VTU ``NAME_<key>.vtu`` (the combinations of a structure); ``figures``: pictures to draw."""

    values: dict
    name: str = "structure"
    solution: object = None
    static_values: dict | None = None
    history: dict | Callable | None = None
    tables: list | Callable = field(default_factory=list)
    frames: Frames | None = None
    modes: ModeShapes | None = None
    loops: list = field(default_factory=list)
    solutions: dict = field(default_factory=dict)
    figures: list = field(default_factory=list)
    buckling: Buckling | None = None

    def __getitem__(self, key):
        """A value of the contract: ``outcome["peaks"]`` is ``outcome.values["peaks"]``."""
        return self.values[key]

    def get_history(self) -> dict | None:
        """The time history, computed now if it is a function."""
        return self.history() if callable(self.history) else self.history

    def get_tables(self) -> list:
        """The CSV tables, computed now if they are a function."""
        return self.tables() if callable(self.tables) else list(self.tables)
