"""femslide.records: the record classes behave as the standard library's dataclasses do for what
femslide uses (constructor, defaults, factories, __post_init__, equality, hashing, frozen fields,
repr, fields, replace), dataclasses' own functions work on them, and the command line imports no
dataclasses."""
from __future__ import annotations

import dataclasses
import pickle
import subprocess
import sys

import pytest

from femslide.records import FrozenInstanceError, dataclass, field, fields, replace


@dataclass(frozen=True)
class Point:
    """A frozen record."""

    x: float
    y: float = 0.0
    tags: tuple = ()
    cache: dict = field(default_factory=dict, compare=False, repr=False)


@dataclass
class Bag:
    name: str
    items: list = field(default_factory=list)

    def __post_init__(self):
        self.size = len(self.items)


@dataclasses.dataclass(frozen=True)
class StdPoint:
    """The standard library's twin of Point, the reference."""

    x: float
    y: float = 0.0
    tags: tuple = ()
    cache: dict = dataclasses.field(default_factory=dict, compare=False, repr=False)


def test_records_behave_as_dataclasses():
    p, q = Point(1.0, tags=("a",)), StdPoint(1.0, tags=("a",))
    assert repr(p) == repr(q).replace("StdPoint", "Point")
    assert p == Point(1.0, 0.0, ("a",), {"other": 1}) and p != Point(2.0)
    assert hash(p) == hash(q) == hash((1.0, 0.0, ("a",)))
    assert p.cache == {} and p.cache is not Point(1.0).cache          # a new dict per record
    with pytest.raises(FrozenInstanceError):
        p.x = 3.0
    with pytest.raises(AttributeError):
        del p.y
    assert Point.y == 0.0 and not hasattr(Point, "cache")
    with pytest.raises(TypeError):
        Point()                                                        # x has no default
    b = Bag("b", [1, 2])
    b.name = "c"                                                       # not frozen
    assert b.size == 2 and Bag("e").items == [] and Bag.__hash__ is None
    assert [f.name for f in fields(Point)] == ["x", "y", "tags", "cache"]
    r = replace(p, y=5.0)
    assert (r.x, r.y, r.tags) == (1.0, 5.0, ("a",)) and p.y == 0.0
    assert pickle.loads(pickle.dumps(p)) == p


def test_dataclasses_functions_work_on_records():
    p = Point(1.0, 2.0)
    assert dataclasses.is_dataclass(p) and dataclasses.is_dataclass(Point)
    assert [f.name for f in dataclasses.fields(p)] == [f.name for f in dataclasses.fields(StdPoint)]
    assert dataclasses.replace(p, x=4.0) == Point(4.0, 2.0)
    assert dataclasses.asdict(p) == dataclasses.asdict(StdPoint(1.0, 2.0))


def test_the_command_line_imports_no_dataclasses():
    out = subprocess.run([sys.executable, "-c", "import sys, femslide.app.cli, femslide.analysis.static, "
                          "femslide.scenes.paper; print('dataclasses' in sys.modules)"],
                         capture_output=True, text=True, check=True).stdout
    assert out.strip() == "False"
