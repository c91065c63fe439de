"""The registry of joint kinds: the joint types a declaration may name, and what each one means.

``KINDS`` maps a type name to its :class:`femslide.joints.kind.JointKind`.  The built-in kinds are
the pin, weld, slider and roller (one module each); a new built-in kind is one module with its
subclass plus one entry in ``BUILTIN`` below, and a program or a test may add its own at run time::

    from femslide.joints.kinds import register, unregister
    register(MyKind())        # then s.joint("j", "mykind", a, b) in any structure
    ...
    unregister("mykind")

Every other module asks the kind (``kind_of(joint.type)`` or a link's ``joint_kind``), never
compares type names.  Pure Python, like the kinds themselves.
"""
from __future__ import annotations

from femslide.errors import BadInput
from femslide.joints.kind import OPTIONAL_FIELDS, JointKind
from femslide.joints.pin import Pin
from femslide.joints.roller import Roller
from femslide.joints.slider import Slider
from femslide.joints.weld import Weld

#: the built-in kinds, in the order of their ``code`` (the VTU field data ``joint_type``)
BUILTIN = (Pin(), Weld(), Slider(), Roller())

#: type name -> kind, the built-in kinds first
KINDS: dict[str, JointKind] = {k.name: k for k in BUILTIN}


def kind_of(name, what: str | None = None) -> JointKind:
    """The kind of the joint type ``name``; :class:`BadInput` naming the registered types otherwise
    (``what`` prefixes the message, e.g. "joint j1")."""
    kind = KINDS.get(name) if isinstance(name, str) else None
    if kind is None:
        raise BadInput(f"{what + ': ' if what else ''}type {name!r}; allowed: {', '.join(KINDS)}")
    return kind


def register(kind: JointKind) -> JointKind:
    """Add a kind to the registry (its ``name`` must be new) after checking that its declaration
    hangs together; returns it.  TypeError / ValueError on a malformed kind (a programming error)."""
    if not isinstance(kind, JointKind):
        raise TypeError(f"{kind!r} is not a JointKind instance")
    name = kind.name
    if not isinstance(name, str) or not name or name in KINDS:
        raise ValueError(f"joint kind name {name!r}: give a new, non-empty name (registered: {', '.join(KINDS)})")
    bad = []
    if not isinstance(kind.size, int) or kind.size < 1:
        bad.append(f"size = {kind.size!r} (a positive number of equations)")
    if not set(kind.accepts) <= OPTIONAL_FIELDS:
        bad.append(f"accepts {sorted(set(kind.accepts) - OPTIONAL_FIELDS)} (allowed: {sorted(OPTIONAL_FIELDS)})")
    if not isinstance(kind.code, int) or (kind.code != -1 and any(k.code == kind.code for k in KINDS.values())):
        bad.append(f"code = {kind.code!r} (-1, or an integer no other kind has)")
    if kind.free not in (None, "slide", "rotation"):
        bad.append(f"free = {kind.free!r} (None, 'slide' or 'rotation')")
    if kind.free == "slide" and not kind.guide:
        bad.append("a slide needs a guide: accept 'axis'")
    if "c" in kind.accepts and kind.free != "rotation":
        bad.append("a rotational spring c needs free = 'rotation'")
    for pair in (("k", "preload"), ("mu", "mu0")):
        if any(f in kind.accepts for f in pair) and (kind.free != "slide" or not set(pair) <= kind.accepts):
            bad.append(f"{' and '.join(pair)} go together and need free = 'slide'")
    if "mu" in kind.accepts and not kind.stuck:
        bad.append("friction needs the kind it becomes when stuck (stuck)")
    if "bearing" in kind.accepts and "mu" not in kind.accepts:
        bad.append("a bearing is for friction: accept 'mu' and 'mu0'")
    if bad:
        raise ValueError(f"joint kind {name!r}: " + "; ".join(bad))
    KINDS[name] = kind
    return kind


def unregister(name: str) -> None:
    """Remove a kind added by :func:`register` (the built-in kinds stay)."""
    if any(k.name == name for k in BUILTIN):
        raise ValueError(f"joint kind {name!r} is built in")
    KINDS.pop(name, None)


def name_of_code(code: int) -> str | None:
    """The type name of a ``joint_type`` integer of a VTU file (None for -1 or an unknown code)."""
    return next((k.name for k in KINDS.values() if k.code == code and code >= 0), None)


def listed(test, last: str = "and", plural: bool = False) -> str:
    """The names of the registered kinds that pass ``test`` for messages: "sliders and rollers"
    (``plural``), "slider or roller" (``last="or"``); "no kind" when none does."""
    names = [k.name + ("s" if plural else "") for k in KINDS.values() if test(k)]
    if not names:
        return "no kind"
    return names[0] if len(names) == 1 else f"{', '.join(names[:-1])} {last} {names[-1]}"
