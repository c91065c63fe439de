"""Property tests of parameter parsing (femslide.scenes.params): every finite in-range value is accepted and
round-trips exactly (as a number and as the text a user types), every out-of-range, NaN, infinite or
non-numeric value is rejected with BadInput naming the parameter and its allowed range.
"""
from __future__ import annotations

import math
import pathlib
import sys

import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

_ROOT = pathlib.Path(__file__).resolve().parents[1]
if str(_ROOT) not in sys.path:
    sys.path.insert(0, str(_ROOT))

from femslide.errors import BadInput  # noqa: E402
from femslide.scenes.catalog import get as get_scene  # noqa: E402
from femslide.scenes.params import PARAMS, ParamSet, parse_assignments  # noqa: E402

FLOATS = sorted(n for n, p in PARAMS.items() if p.kind == "float")
INTS = sorted(n for n, p in PARAMS.items() if p.kind == "int")
NUMERIC = FLOATS + INTS
SETTINGS = settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def in_range(p):
    """Finite floats inside p's allowed range (open bounds excluded)."""
    lo = p.lo if math.isfinite(p.lo) else None
    hi = p.hi if math.isfinite(p.hi) else None
    return st.floats(min_value=lo, max_value=hi, exclude_min=p.lo_open and lo is not None,
                     exclude_max=p.hi_open and hi is not None, allow_nan=False, allow_infinity=False)


def out_of_range(p):
    """Finite floats outside p's range (an open bound itself included)."""
    parts = []
    if math.isfinite(p.lo):
        parts.append(st.floats(max_value=p.lo, exclude_max=not p.lo_open, allow_nan=False,
                               allow_infinity=False))
    if math.isfinite(p.hi):
        parts.append(st.floats(min_value=p.hi, exclude_min=not p.hi_open, allow_nan=False,
                               allow_infinity=False))
    return st.one_of(parts) if parts else st.nothing()


def assert_names(exc_info, name):
    msg = str(exc_info.value)
    assert f"parameter {name}" in msg, msg
    assert "allowed" in msg, msg


def texts_of(x):
    """Ways a user may type the number x."""
    return [repr(x), f"{x:.17g}", f"  {x!r} ", f"{x:.17e}"]


@pytest.mark.parametrize("name", FLOATS)
@SETTINGS
@given(data=st.data())
def test_in_range_float_accepted_and_round_trips(name, data):
    p = PARAMS[name]
    x = data.draw(in_range(p))
    assert p.check(x) == x and isinstance(p.check(x), float)
    for text in texts_of(x):
        y = p.check(text)
        assert y == x and math.copysign(1.0, y) == math.copysign(1.0, x), (text, y)


def _has_integers(name):
    p = PARAMS[name]
    return not (math.isfinite(p.lo) and math.isfinite(p.hi) and math.ceil(p.lo) > math.floor(p.hi))


@pytest.mark.parametrize("name", [n for n in FLOATS if _has_integers(n)])   # (tolerance: none in 1e-12..1e-2)
@SETTINGS
@given(data=st.data())
def test_in_range_integers_accepted(name, data):
    """Python ints in range are numbers too (keyword arguments of femslide.solve)."""
    p = PARAMS[name]
    lo = math.ceil(p.lo) if math.isfinite(p.lo) else -10 ** 12
    hi = math.floor(p.hi) if math.isfinite(p.hi) else 10 ** 12
    i = data.draw(st.integers(min_value=lo, max_value=hi))
    assume(not (p.lo_open and i == p.lo) and not (p.hi_open and i == p.hi))
    assert p.check(i) == float(i)
    assert p.check(str(i)) == float(i)


@pytest.mark.parametrize("name", [n for n in NUMERIC if math.isfinite(PARAMS[n].lo) or math.isfinite(PARAMS[n].hi)])
@SETTINGS
@given(data=st.data())
def test_out_of_range_rejected_naming_the_parameter(name, data):
    p = PARAMS[name]
    x = data.draw(out_of_range(p))
    for value in (x, repr(x)):
        with pytest.raises(BadInput) as exc:
            p.check(value)
        assert_names(exc, name)


@pytest.mark.parametrize("name", NUMERIC)
@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf, "nan", "NaN", "inf", "-inf", "Infinity",
                                   "1e400", "-1e400", 10 ** 400, -(10 ** 400)],
                         ids=lambda v: ("int" + ("-" if v < 0 else "+") + "1e400") if isinstance(v, int)
                         else repr(v))
def test_nan_inf_and_overflow_rejected(name, value):
    with pytest.raises(BadInput) as exc:
        PARAMS[name].check(value)
    assert_names(exc, name)


@pytest.mark.parametrize("name", NUMERIC)
@SETTINGS
@given(text=st.text(max_size=12))
def test_non_numbers_rejected(name, text):
    try:
        float(text.strip())    # surrounding whitespace (str.strip's notion) is allowed
        assume(False)          # a number after all: covered elsewhere
    except ValueError:
        pass
    with pytest.raises(BadInput) as exc:
        PARAMS[name].check(text)
    assert_names(exc, name)


@pytest.mark.parametrize("name", NUMERIC)
@pytest.mark.parametrize("value", [True, False, None, [1.0], {"x": 1}, object()], ids=repr)
def test_non_scalars_rejected(name, value):
    with pytest.raises(BadInput) as exc:
        PARAMS[name].check(value)
    assert f"parameter {name}" in str(exc.value)


@pytest.mark.parametrize("name", INTS)
@SETTINGS
@given(data=st.data())
def test_int_parameters(name, data):
    p = PARAMS[name]
    i = data.draw(st.integers(min_value=int(p.lo), max_value=int(p.hi)))
    for value in (i, float(i), str(i), f"{float(i)!r}"):
        got = p.check(value)
        assert got == i and type(got) is int
    frac = data.draw(st.floats(min_value=p.lo, max_value=p.hi, allow_nan=False).filter(
        lambda v: v != int(v)))
    with pytest.raises(BadInput) as exc:
        p.check(frac)
    assert_names(exc, name)


# ----------------------------------------------------------------------- through a scene's ParamSet

SCENE_PARAMS = [("hinge-slider", n) for n in ("a", "b", "d", "m", "g", "c")] + \
    [("hinge-extra-mass", n) for n in ("dm", "m1", "l2")]


@pytest.mark.parametrize("scene,name", SCENE_PARAMS)
@SETTINGS
@given(data=st.data())
def test_scene_resolve_round_trip(scene, name, data):
    """``--set NAME=VALUE`` text through parse_assignments and the scene's ParamSet gives back the
    number; every other parameter keeps its default."""
    s = get_scene(scene)
    x = data.draw(in_range(PARAMS[name]))
    values = s.resolve(parse_assignments([f"{name}={x!r}"]))
    assert values[name] == x
    defaults = {p.name: p.default for p in s.params.params()}
    assert all(values[k] == v for k, v in defaults.items() if k != name)


@pytest.mark.parametrize("scene,name", [(s, n) for s, n in SCENE_PARAMS
                                        if math.isfinite(PARAMS[n].lo) or math.isfinite(PARAMS[n].hi)])
@SETTINGS
@given(data=st.data())
def test_scene_resolve_rejects_out_of_range(scene, name, data):
    s = get_scene(scene)
    p = PARAMS[name]
    x = data.draw(out_of_range(p))
    with pytest.raises(BadInput) as exc:
        s.resolve(parse_assignments([f"{name}={x!r}"]))
    assert_names(exc, name)


@SETTINGS
@given(name=st.text(alphabet="abcdefghijklmnopqrstuvwxyz_0123456789", min_size=1, max_size=10))
def test_unknown_names_rejected_naming_them(name):
    s = get_scene("hinge-slider")
    assume(name not in s.params.names)
    with pytest.raises(BadInput) as exc:
        s.resolve({name: "1"})
    assert repr(name) in str(exc.value) and "allowed" in str(exc.value)


@SETTINGS
@given(l=st.floats(min_value=1e-3, max_value=1e3), ratio=st.floats(min_value=1.0, max_value=1e3,
                                                                    exclude_min=True))
def test_l1_beyond_the_rod_rejected(l, ratio):
    """l1 must lie on the rod (SPEC: hinge at height l1 on a rod of length l): l1 > l is rejected
    naming l1."""
    l1 = l * ratio
    assume(l1 > l and math.isfinite(l1))
    for scene in ("hinge-slider", "hinge-spring", "hinge-extra-mass"):
        with pytest.raises(BadInput) as exc:
            get_scene(scene).resolve({"l": repr(l), "l1": repr(l1)})
        assert "l1" in str(exc.value)


def test_paramset_defaults_are_themselves_valid():
    """Every declared default passes its own check (a default outside its range would make the
    scene unusable without --set)."""
    for p in PARAMS.values():
        if p.default is not None and p.kind != "path":
            assert p.check(p.default) == p.default, p.name
    ps = ParamSet(("a", "c"), defaults={"c": 5.0})
    assert ps.resolve({}) == {"a": 1.0, "c": 5.0}
