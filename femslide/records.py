"""Record classes: the part of :mod:`dataclasses` femslide uses, at a fraction of its import cost.

``@dataclass`` / ``@dataclass(frozen=True)`` make a class of annotated fields a record as the
standard library's decorator does - an ``__init__`` taking the fields in order (defaults, ``field(
default_factory=...)``, ``__post_init__``), ``__repr__``, ``__eq__`` over the compared fields; frozen
records refuse assignment (:class:`FrozenInstanceError`) and hash their compared fields, other
records are unhashable - and :func:`fields` and :func:`replace` work on them.  Methods the class
defines itself are kept.  ``dataclasses.fields``, ``replace``, ``asdict`` and ``is_dataclass`` work
on records too (their ``__dataclass_fields__`` are made when first asked for).  Not supported
(femslide does not use them): inheritance between records, ``ClassVar``/``InitVar`` fields,
``init=False`` fields, keyword-only fields, ordering, slots.

Why: the standard decorator compiles five or six methods per class from generated source and
inspects the class, about 0.5-1 ms a class, and importing :mod:`dataclasses` imports :mod:`inspect`;
with some thirty records on the path of ``femslide sweep`` that was 34 ms of a 185 ms process
(measured with bytecode), more than the sweep's nine solves.  Here one small ``__init__`` is
compiled per class and the other methods are shared functions.
"""
from __future__ import annotations

from operator import attrgetter

__all__ = ["dataclass", "field", "fields", "replace", "FrozenInstanceError", "MISSING"]


class _Missing:
    __slots__ = ()

    def __repr__(self):
        return "MISSING"


MISSING = _Missing()   # a field without a default


class FrozenInstanceError(AttributeError):
    """Assignment to a field of a frozen record."""


class Field:
    """A record's field: ``name``, ``default`` (MISSING: none), ``default_factory`` (MISSING: none),
    ``compare`` (in ``__eq__`` and the hash), ``repr`` (in ``__repr__``)."""

    __slots__ = ("name", "default", "default_factory", "compare", "repr")

    def __init__(self, default=MISSING, default_factory=MISSING, compare=True, repr=True):
        if default is not MISSING and default_factory is not MISSING:
            raise ValueError("cannot specify both default and default_factory")
        self.name = None
        self.default, self.default_factory, self.compare, self.repr = default, default_factory, compare, repr

    def __repr__(self):
        return f"Field(name={self.name!r}, default={self.default!r}, default_factory={self.default_factory!r})"


def field(*, default=MISSING, default_factory=MISSING, compare=True, repr=True) -> Field:
    """A field with a default or a ``default_factory`` (called for every new record), and whether it
    is compared (``__eq__``, hash) and shown (``__repr__``)."""
    return Field(default, default_factory, compare, repr)


def fields(obj) -> tuple:
    """The fields of a record class or record, in order."""
    try:
        return tuple(obj.__record_fields__)
    except AttributeError:
        raise TypeError("must be called with a record class or instance") from None


def replace(obj, **changes):
    """A new record of obj's class with the fields ``changes`` replaced (``__post_init__`` runs)."""
    for f in fields(obj):
        if f.name not in changes:
            changes[f.name] = getattr(obj, f.name)
    return obj.__class__(**changes)


class _DataclassFields:
    """A record's ``__dataclass_fields__``, made when first asked for (importing :mod:`dataclasses`
    then, not before): ``dataclasses.fields``, ``replace``, ``asdict`` and ``is_dataclass`` work on
    records as on the standard library's dataclasses."""

    def __get__(self, obj, cls):
        made = cls.__dict__.get("_record_dataclass_fields")
        if made is None:
            import dataclasses
            made = {}
            for f in cls.__record_fields__:
                kw = {"repr": f.repr, "compare": f.compare}
                if f.default_factory is not MISSING:
                    kw["default_factory"] = f.default_factory
                elif f.default is not MISSING:
                    kw["default"] = f.default
                df = dataclasses.field(**kw)
                df.name, df.type = f.name, cls.__dict__.get("__annotations__", {}).get(f.name)
                df._field_type = dataclasses._FIELD
                made[f.name] = df
            cls._record_dataclass_fields = made
        return made


def _repr(self):
    parts = ", ".join(f"{f.name}={getattr(self, f.name)!r}" for f in self.__record_fields__ if f.repr)
    return f"{type(self).__qualname__}({parts})"


def _eq(self, other):
    if other.__class__ is self.__class__:
        key = self.__record_key__
        return key(self) == key(other)
    return NotImplemented


def _hash(self):
    return hash(self.__record_key__(self))


def _key(names):
    """The tuple of the compared fields' values of a record (a C-level attrgetter)."""
    if len(names) == 1:
        get = attrgetter(names[0])
        return lambda obj: (get(obj),)
    return attrgetter(*names) if names else (lambda obj: ())


def _frozen_setattr(self, name, value):
    if name in self.__record_names__:
        raise FrozenInstanceError(f"cannot assign to field {name!r}")
    object.__setattr__(self, name, value)


def _frozen_delattr(self, name):
    if name in self.__record_names__:
        raise FrozenInstanceError(f"cannot delete field {name!r}")
    object.__delattr__(self, name)


def _process(cls, frozen: bool):
    ns = cls.__dict__
    flds = []
    for name in ns.get("__annotations__", {}):
        value = ns.get(name, MISSING)
        if isinstance(value, Field):
            f = value
            if f.default is MISSING:
                delattr(cls, name)          # (a factory: no class attribute, as dataclasses does)
            else:
                setattr(cls, name, f.default)
        else:
            f = Field(value)
        f.name = name
        flds.append(f)
    # __init__: one small function compiled for the class (the fields as its parameters)
    glob = {"_MISSING": MISSING, "_set": object.__setattr__}
    params, body = [], []
    for f in flds:
        n = f.name
        if f.default_factory is not MISSING:
            glob[f"_f_{n}"] = f.default_factory
            params.append(f"{n}=_MISSING")
            value = f"_f_{n}() if {n} is _MISSING else {n}"
        elif f.default is not MISSING:
            glob[f"_d_{n}"] = f.default
            params.append(f"{n}=_d_{n}")
            value = n
        else:
            params.append(n)
            value = n
        body.append(f"    _set(self, {n!r}, {value})" if frozen else f"    self.{n} = {value}")
    if "__post_init__" in ns:
        body.append("    self.__post_init__()")
    src = f"def __init__(self, {', '.join(params)}):\n" + ("\n".join(body) or "    pass") + "\n"
    if not params:
        src = src.replace("(self, )", "(self)")
    loc = {}
    exec(src, glob, loc)   # noqa: S102 - source built above from the class's own field names
    init = loc["__init__"]
    init.__qualname__ = f"{cls.__qualname__}.__init__"
    init.__module__ = cls.__module__
    ann = ns.get("__annotations__", {})
    init.__annotations__ = {**{f.name: ann[f.name] for f in flds}, "return": "None"}   # (as dataclasses' __init__)
    cls.__record_fields__ = tuple(flds)
    cls.__record_names__ = frozenset(f.name for f in flds)
    cls.__record_key__ = staticmethod(_key(tuple(f.name for f in flds if f.compare)))
    cls.__dataclass_fields__ = _DataclassFields()
    own = {"__init__": init, "__repr__": _repr, "__eq__": _eq}
    if frozen:
        own.update(__setattr__=_frozen_setattr, __delattr__=_frozen_delattr)
    for k, v in own.items():
        if k not in ns:
            setattr(cls, k, v)
    if "__hash__" not in ns or (ns["__hash__"] is None and "__eq__" in ns):
        cls.__hash__ = _hash if frozen else None   # (dataclasses: eq without frozen is unhashable)
    return cls


def dataclass(cls=None, *, frozen: bool = False):
    """Make ``cls`` a record (the module docstring): ``@dataclass`` or ``@dataclass(frozen=True)``."""
    if cls is None:
        return lambda c: _process(c, frozen)
    return _process(cls, frozen)
