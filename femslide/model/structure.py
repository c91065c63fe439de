"""Declaring a planar structure: rods, rigid bodies, joints and loads (the model layer's front end).

A :class:`Structure` is a plain, mutable declaration: every object has a unique name, coordinates
are global and in the reference (undeformed) configuration, units are SI (m, kg, s, N, N m, rad).
Rotations and moments are counter-clockwise positive.  :meth:`Structure.freeze` checks the whole
declaration and returns a :class:`Frozen` structure: immutable, with every name resolved to the
part it denotes; the solvers take only frozen structures.

    s = Structure(gravity=(0.0, -9.81))
    s.rod("col", start=(0, 0), end=(0, 3), EI=1e6)
    s.body("deck", mass=100.0, centroid=(1.0, 3.5), outline=[(0, 3), (2, 3), (2, 4), (0, 4)])
    s.pin("base", a="col.start", b="ground")
    s.weld("top", a="col.end", b="deck")
    s.force("wind", on="deck", force=(50.0, 0.0))
    frozen = s.freeze()

Parts and points:

- a rod is a flexible corotational Euler-Bernoulli beam from ``start`` to ``end``; its ends are the
  points ``"ROD.start"`` and ``"ROD.end"``.  ``EI`` [N m^2] and ``EA`` [N] are numbers or
  :class:`Table` (piecewise linear in the arc length s [m] from ``start``); EA defaults to
  1e6 m^-2 * EI (a nearly inextensible rod); ``rhoA`` [kg/m] gives self-weight (and mass in
  dynamics); ``elements`` fixes the mesh (absent: adaptive refinement with an error estimate);
- a body is rigid: ``mass`` [kg] at ``centroid``, ``inertia`` [kg m^2] about it, ``outline`` a
  polygon (pictures; default inertia of a uniform plate); a massless body is a rigid link;
- a joint connects part ``a`` (a rod end or a body) to part ``b`` (a rod end, a body or
  ``"ground"``) at the point ``at`` (default: the position of the rod end a, or of the rod end b);
  ``pin`` keeps the points together (rotational spring ``c`` [N m/rad] optional), ``weld`` the
  points and rotations, ``slider`` keeps a's point on the line through ``at`` along ``axis``
  (carried by b) and a's rotation equal to b's, ``roller`` the line only.  Sliders and rollers may
  carry a spring ``k`` [N/m] along the axis with a ``preload`` [N] (> 0 pushes a along +axis) and,
  in dynamics, Coulomb friction ``mu``/``mu0`` with bearings ``bearing`` [m] apart;
- loads: gravity (vector, on bodies and rod mass), ``force`` (a force [N] and moment [N m] on a body
  at ``at`` or on a rod end) and ``distributed`` (force per unit reference length [N/m], global
  components, on a whole rod).  All loads are dead loads, applied together with gravity.
"""
from __future__ import annotations

from collections.abc import Sequence
from dataclasses import fields, replace
from typing import Any

from femslide.errors import BadInput
from femslide.model.frozen import Frozen
from femslide.model.parts import _JOINT_FIELDS, GROUND, Body, Field, Joint, Load, Rod, Vec


class Structure:
    """A planar structure being declared: rods, rigid bodies, joints and loads (mutable).

    Every object has a unique name (a non-empty string without ``.``, not ``"ground"``);
    coordinates are global, in the reference (undeformed) configuration; units are SI (m, kg, s,
    N, N m, rad); rotations and moments are counter-clockwise positive.  Nothing is checked until
    :meth:`freeze` (which :func:`femslide.solve` calls): then an unknown name, a zero axis, a part
    connected to nothing or a value out of range raises :class:`femslide.BadInput` naming the
    object and the field.

    Parameters
    ----------
    gravity : (float, float), default (0.0, -9.81)
        Gravitational acceleration [m/s^2]; acts on bodies and on the rods' mass per length.

    Examples
    --------
    >>> s = femslide.Structure(gravity=(0.0, -9.81))
    >>> s.rod("col", start=(0, 0), end=(0, 3), EI=2e6)
    >>> s.body("deck", mass=500.0, centroid=(1.0, 3.5), outline=[(0, 3), (2, 3), (2, 4), (0, 4)])
    >>> s.pin("base", a="col.start", b="ground")
    >>> s.weld("top", a="col.end", b="deck")
    >>> s.roller("right", a="deck", b="ground", at=(2.0, 3.0), axis=(0.0, 1.0))
    >>> r = femslide.solve(s)
    """

    def __init__(self, gravity: Vec = (0.0, -9.81)) -> None:
        self.gravity = gravity
        self.rods: dict[str, Rod] = {}
        self.bodies: dict[str, Body] = {}
        self.joints: dict[str, Joint] = {}
        self.loads: dict[str, Load] = {}

    # -- declaring ----------------------------------------------------------------------------------
    def _name(self, name):
        if not isinstance(name, str) or not name or "." in name or name == GROUND:
            raise BadInput(f"name {name!r}: a non-empty string without '.', not {GROUND!r}")
        for kind in (self.rods, self.bodies, self.joints, self.loads):
            if name in kind:
                raise BadInput(f"name {name!r} is used twice; every rod, body, joint and load needs its own name")
        return name

    def rod(self, name: str, start: Vec, end: Vec, EI: Field, EA: Field | None = None, rhoA: Field = 0.0,
            elements: int | None = None) -> Rod:
        """Declare a flexible rod: a mesh of corotational Euler-Bernoulli beams from ``start`` to ``end``.

        Parameters
        ----------
        name : str
            Its name; its ends are the points ``"NAME.start"`` and ``"NAME.end"``.
        start, end : (float, float)
            End points [m].
        EI : float or Table
            Bending stiffness [N m^2], > 0: a number or a :class:`Table` piecewise linear in the
            arc length s [m] from ``start`` (covering the whole rod).
        EA : float or Table, optional
            Axial stiffness [N]; default 1e6 m^-2 * EI (a nearly inextensible rod).
        rhoA : float, default 0
            Mass per unit length [kg/m]: self-weight (and mass in dynamics).
        elements : int, optional
            A fixed number of elements; absent: the mesh is refined until the results are
            accurate to about 1e-7 and the result reports its ``error_estimate``.
        """
        r = Rod(self._name(name), tuple(start), tuple(end), EI, EA, rhoA, elements)
        self.rods[name] = r
        return r

    def body(self, name: str, mass: float = 0.0, centroid: Vec | None = None, inertia: float | None = None,
             outline: Sequence[Vec] | None = None) -> Body:
        """Declare a rigid body.

        Parameters
        ----------
        name : str
            Its name, used as a part of joints (``a="deck"``) and loads (``on="deck"``).
        mass : float, default 0
            Mass [kg] at the centroid; 0 makes a massless rigid link.
        centroid : (float, float), optional
            Centre of mass in the reference configuration [m]; default: the outline's centroid,
            else the point ``at`` of its first joint.
        inertia : float, optional
            Rotary inertia about the centroid [kg m^2]; default: a uniform plate of the outline.
        outline : list of (float, float), optional
            A polygon [m], for pictures and the default inertia.
        """
        b = Body(self._name(name), mass, None if centroid is None else tuple(centroid), inertia,
                 None if outline is None else tuple(tuple(p) for p in outline))
        self.bodies[name] = b
        return b

    def joint(self, name: str, type: str, a: str, b: str, **options: Any) -> Joint:
        """Declare a joint of any ``type``; :meth:`pin`, :meth:`weld`, :meth:`slider` and
        :meth:`roller` are the same with their options named.

        Parameters
        ----------
        name : str
            Its name.
        type : str
            A registered joint kind: ``"pin"``, ``"weld"``, ``"slider"``, ``"roller"`` or one added
            with :func:`femslide.joints.kinds.register`; it decides which options apply.
        a : str
            Part a: a rod end (``"ROD.start"``, ``"ROD.end"``) or a body.
        b : str
            Part b: a rod end, a body, or ``"ground"`` (then the joint is a support and its force
            is reported as a reaction).
        **options
            ``at``, ``axis``, ``c``, ``k``, ``preload``, ``mu``, ``mu0``, ``bearing`` as in the
            methods of each type.
        """
        unknown = set(options) - _JOINT_FIELDS
        if unknown:
            raise BadInput(f"joint {name}: unknown option(s) {', '.join(sorted(unknown))}")
        j = Joint(self._name(name), type, a, b, **{k: (tuple(v) if isinstance(v, (list, tuple)) else v)
                                                   for k, v in options.items()})
        self.joints[name] = j
        return j

    def pin(self, name: str, a: str, b: str, at: Vec | None = None, c: float = 0.0) -> Joint:
        """A pin: a's point and b's point stay together; rotations are free relative to each other.

        Parameters
        ----------
        name, a, b : str
            Its name and parts (see :meth:`joint`).
        at : (float, float), optional
            The joint point [m]; default: the position of the rod end a (or of the rod end b).
        c : float, default 0
            A rotational spring [N m/rad] between a and b (a spring hinge).
        """
        return self.joint(name, "pin", a, b, at=at, c=c)

    def weld(self, name: str, a: str, b: str, at: Vec | None = None) -> Joint:
        """A weld: a's point and rotation stay those of b.

        Parameters
        ----------
        name, a, b : str
            Its name and parts (see :meth:`joint`).
        at : (float, float), optional
            The joint point [m]; default: the position of the rod end a (or of the rod end b).
        """
        return self.joint(name, "weld", a, b, at=at)

    def slider(self, name: str, a: str, b: str, axis: Vec, at: Vec | None = None, k: float = 0.0,
               preload: float = 0.0, mu: float | None = None, mu0: float | None = None,
               bearing: float | None = None) -> Joint:
        """A slider (a sliding clamp, a prismatic joint): a's point stays on the line through ``at``
        along ``axis``, carried by b, and a's rotation equals b's; the slide along the line is free.

        Parameters
        ----------
        name, a, b : str
            Its name and parts (see :meth:`joint`); the guide is fixed to b.
        axis : (float, float)
            Direction of the guide in the reference configuration (nonzero; its length is ignored).
        at : (float, float), optional
            A point of the guide [m]; default: the position of the rod end a (or of the rod end b).
        k : float, default 0
            A linear spring along the guide [N/m].
        preload : float, default 0
            The spring's force at the reference position [N]; > 0 pushes a along +axis.
        mu, mu0 : float, optional
            Coulomb friction along the guide (kinetic, static >= kinetic; default mu0 = mu), for the
            dynamics; the statics treat sliders as frictionless.
        bearing : float, optional
            Distance [m] between the guide's two bearings, for friction's normal force.
        """
        return self.joint(name, "slider", a, b, at=at, axis=axis, k=k, preload=preload, mu=mu, mu0=mu0,
                          bearing=bearing)

    def roller(self, name: str, a: str, b: str, axis: Vec, at: Vec | None = None, k: float = 0.0,
               preload: float = 0.0, mu: float | None = None, mu0: float | None = None) -> Joint:
        """A roller: a's point stays on the line through ``at`` along ``axis``, carried by b; the
        rotation is free.

        Parameters
        ----------
        name, a, b : str
            Its name and parts (see :meth:`joint`).
        axis : (float, float)
            Direction of the line (nonzero).
        at : (float, float), optional
            A point of the line [m]; default: the position of the rod end a (or of the rod end b).
        k, preload, mu, mu0 : float, optional
            Spring, preload and friction along the line, as for :meth:`slider`.
        """
        return self.joint(name, "roller", a, b, at=at, axis=axis, k=k, preload=preload, mu=mu, mu0=mu0)

    def force(self, name: str, on: str, force: Vec = (0.0, 0.0), moment: float = 0.0,
              at: Vec | None = None) -> Load:
        """A dead force (and moment) on a body or a rod end, applied together with gravity.

        Parameters
        ----------
        name : str
            Its name.
        on : str
            A body or a rod end (``"ROD.start"``, ``"ROD.end"``).
        force : (float, float), default (0, 0)
            Force [N], global components.
        moment : float, default 0
            Moment [N m], counter-clockwise positive.
        at : (float, float), optional
            Point of application [m] on a body; default: its centroid (or the rod end).
        """
        ld = Load(self._name(name), "force", on, tuple(force), moment, None if at is None else tuple(at))
        self.loads[name] = ld
        return ld

    def distributed(self, name: str, on: str, force: Vec) -> Load:
        """A dead load distributed uniformly along a whole rod.

        Parameters
        ----------
        name : str
            Its name.
        on : str
            The rod's name.
        force : (float, float)
            Force per unit reference length [N/m], global components.
        """
        ld = Load(self._name(name), "distributed", on, tuple(force))
        self.loads[name] = ld
        return ld

    def set(self, path: str, value: Any) -> None:
        """Change one declared field by its dotted name.

        Parameters
        ----------
        path : str
            ``"NAME.FIELD"`` (``"right.EI"``, ``"wind.force"``, ``"clamp.k"``) or ``"gravity"``.
        value
            The new value (checked by :meth:`freeze`).

        Raises
        ------
        femslide.BadInput
            No part of that name, or no such field.
        """
        if path == "gravity":
            self.gravity = value
            return
        name, _, fld = path.partition(".")
        for kind in (self.rods, self.bodies, self.joints, self.loads):
            if name in kind:
                obj = kind[name]
                names = {f.name for f in fields(obj)} - {"name"}
                if fld not in names:
                    raise BadInput(f"{path}: {name} has no field {fld!r}; fields: {', '.join(sorted(names))}")
                kind[name] = replace(obj, **{fld: value})
                return
        raise BadInput(f"{path}: no rod, body, joint or load is named {name!r}")

    def copy(self) -> Structure:
        """An independent copy of the declaration (the declared objects themselves are immutable)."""
        s = Structure(self.gravity)
        s.rods, s.bodies, s.joints, s.loads = dict(self.rods), dict(self.bodies), dict(self.joints), dict(self.loads)
        return s

    def freeze(self) -> Frozen:
        """Check the whole declaration and return it frozen: immutable, every name resolved.

        Raises
        ------
        femslide.BadInput
            An unknown name, a zero axis, a part connected to nothing or a value out of range;
            the message names the object and the field.
        """
        return Frozen.from_structure(self)
