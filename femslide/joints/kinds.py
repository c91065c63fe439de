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
    hangs together (:func:`problems`); returns it.  TypeError / ValueError on a malformed kind (a
    programming error, not bad input)."""
    if not isinstance(kind, JointKind):
        raise TypeError(f"{kind!r} is not a JointKind instance")
    bad = problems(kind)
    if bad:
        raise ValueError(f"joint kind {kind.name!r}: " + "; ".join(bad))
    KINDS[kind.name] = kind
    return kind


def problems(kind: JointKind) -> list[str]:
    """What is wrong with a kind's declaration, against the registered kinds ([] when nothing is):
    its name and code must be its own, its accepted fields known and consistent with its free
    coordinate (a slide needs a guide; springs and friction act on the free coordinate; friction
    needs the kind it becomes when stuck)."""
    name, acc = kind.name, set(kind.accepts)
    bad = []
    others = [k for k in KINDS.values() if k is not kind]
    if not isinstance(name, str) or not name or any(k.name == name for k in others):
        bad.append(f"name {name!r} (a new, non-empty name; registered: {', '.join(KINDS)})")
    if not isinstance(kind.code, int) or (kind.code != -1 and any(k.code == kind.code for k in others)):
        bad.append(f"code = {kind.code!r} (-1, or an integer no other kind has)")
    if not isinstance(kind.size, int) or kind.size < 1:
        bad.append(f"size = {kind.size!r} (a positive number of equations)")
    if not acc <= OPTIONAL_FIELDS:
        bad.append(f"accepts {sorted(acc - OPTIONAL_FIELDS)} (allowed: {', '.join(sorted(OPTIONAL_FIELDS))})")
    if kind.free not in (None, "slide", "rotation"):
        bad.append(f"free = {kind.free!r} (None, 'slide' or 'rotation')")
    if kind.free == "slide" and "axis" not in acc:
        bad.append("a slide needs a guide: accept 'axis'")
    if "c" in acc and kind.free != "rotation":
        bad.append("a rotational spring c needs free = 'rotation'")
    for pair in (("k", "preload"), ("mu", "mu0")):
        if acc & set(pair) and (kind.free != "slide" or not set(pair) <= acc):
            bad.append(f"{' and '.join(pair)} go together and need free = 'slide'")
    if "mu" in acc and not kind.stuck:
        bad.append("friction needs the name of the kind it becomes when stuck (stuck)")
    if acc & {"unilateral", "restitution"} and (not kind.guide or not {"unilateral", "restitution"} <= acc):
        bad.append("unilateral and restitution go together and need a guide (accept 'axis')")
    if "bearing" in acc and "mu" not in acc:
        bad.append("a bearing is for friction: accept 'mu' and 'mu0'")
    return bad


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
