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
  components, on a whole rod).  All loads are dead loads; each belongs to a load ``case`` (default
  ``"dead"``, the case of gravity).  Without combinations every case is applied at once; a
  :meth:`Structure.combination` gives a factor per case and is solved as its own equilibrium.
- elastic supports: a joint with the ground may carry springs ``kx``, ``ky`` [N/m] and ``kr``
  [N m/rad] instead of its rigid constraints in those directions.
"""
from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from femslide.errors import BadInput
from femslide.model.frozen import Frozen
from femslide.model.parts import _JOINT_FIELDS, DEAD, GROUND, Body, Combination, Field, Joint, Load, Rod, Vec
from femslide.records import fields, replace


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
        self.combinations: dict[str, Combination] = {}
        self.steps: list[Combination] = []

    # -- declaring ----------------------------------------------------------------------------------
    def _name(self, name):
        if not isinstance(name, str) or not name or "." in name or name == GROUND:
            raise BadInput(f"name {name!r}: a non-empty string without '.', not {GROUND!r}")
        for kind in (self.rods, self.bodies, self.joints, self.loads, self.combinations):
            if name in kind:
                raise BadInput(f"name {name!r} is used twice; every rod, body, joint, load and combination "
                               f"needs its own name")
        return name

    def rod(self, name: str, start: Vec, end: Vec, EI: Field | None = None, EA: Field | None = None,
            rhoA: Field = 0.0, elements: int | None = None, E: float | None = None, I: float | None = None,  # noqa: E741
            A: float | None = None, alpha: float = 0.0, depth: float | None = None) -> Rod:
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
        E, I, A : float, optional
            The section instead of EI and EA: Young's modulus [Pa], second moment of area [m^4]
            and area [m^2]; EI = E I and EA = E A (without A: the default EA above).
        alpha : float, default 0
            Thermal expansion coefficient [1/K], >= 0 (for thermal loads).
        depth : float, optional
            Section depth [m], > 0: needed by a thermal load with a gradient ``dT_gradient``.
        """
        r = Rod(self._name(name), tuple(start), tuple(end), EI, EA, rhoA, elements, E, I, A, alpha, depth)
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
            ``at``, ``axis``, ``c``, ``k``, ``preload``, ``mu``, ``mu0``, ``bearing``, ``unilateral``,
            ``restitution`` as in the
            methods of each type; on a joint with the ground also ``kx``, ``ky`` [N/m] and ``kr``
            [N m/rad]: elastic springs instead of its rigid constraints in x, y and rotation (a pin
            or weld takes kx and ky, a weld or slider kr, a slider or roller the k across its guide
            when the guide is along y (kx) or x (ky)); and a prescribed support motion
            ``displacement = (dx, dy)`` [m] (any kind: its ground point moves; a guide along it
            passes the motion across the guide only) and ``rotation`` [rad] (weld, slider: the
            held rotation), ramped with the loads of case "dead" (a settlement).
        """
        unknown = set(options) - _JOINT_FIELDS
        if unknown:
            raise BadInput(f"joint {name}: unknown option(s) {', '.join(sorted(unknown))}")
        j = Joint(self._name(name), type, a, b, **{k: (tuple(v) if isinstance(v, (list, tuple)) else v)
                                                   for k, v in options.items()})
        self.joints[name] = j
        return j

    def pin(self, name: str, a: str, b: str, at: Vec | None = None, c: float = 0.0, kx: float | None = None,
            ky: float | None = None, displacement: Vec | None = None) -> Joint:
        """A pin: a's point and b's point stay together; rotations are free relative to each other.

        Parameters
        ----------
        name, a, b : str
            Its name and parts (see :meth:`joint`).
        at : (float, float), optional
            The joint point [m]; default: the position of the rod end a (or of the rod end b).
        c : float, default 0
            A rotational spring [N m/rad] between a and b (a spring hinge).
        kx, ky : float, optional
            With b = "ground": an elastic support, springs [N/m] in x and y instead of the rigid
            constraints there (default: rigid).
        displacement : (float, float), optional
            With b = "ground": the support moves by (dx, dy) [m] (a settlement), ramped with the
            loads of case "dead".
        """
        return self.joint(name, "pin", a, b, at=at, c=c, kx=kx, ky=ky, displacement=displacement)

    def weld(self, name: str, a: str, b: str, at: Vec | None = None, kx: float | None = None,
             ky: float | None = None, kr: float | None = None, displacement: Vec | None = None,
             rotation: float | None = None) -> Joint:
        """A weld: a's point and rotation stay those of b.

        Parameters
        ----------
        name, a, b : str
            Its name and parts (see :meth:`joint`).
        at : (float, float), optional
            The joint point [m]; default: the position of the rod end a (or of the rod end b).
        kx, ky : float, optional
            With b = "ground": an elastic support, springs [N/m] in x and y instead of the rigid
            constraints there (default: rigid).
        kr : float, optional
            With b = "ground": a rotational spring [N m/rad] instead of the rigid rotation (a
            cantilever on an elastic foundation; default: rigid).
        displacement : (float, float), optional
            With b = "ground": the support moves by (dx, dy) [m] (a settlement), ramped with the
            loads of case "dead".
        rotation : float, optional
            With b = "ground": the support turns by this much [rad] (counter-clockwise), ramped
            likewise.
        """
        return self.joint(name, "weld", a, b, at=at, kx=kx, ky=ky, kr=kr, displacement=displacement,
                          rotation=rotation)

    def slider(self, name: str, a: str, b: str, axis: Vec, at: Vec | None = None, k: float = 0.0,
               preload: float = 0.0, mu: float | None = None, mu0: float | None = None,
               bearing: float | None = None, kx: float | None = None, ky: float | None = None,
               kr: float | None = None, unilateral: bool = False, restitution: float | None = None) -> Joint:
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
        kx, ky, kr : float, optional
            With b = "ground": springs [N/m, N m/rad] instead of the rigid constraint across a guide
            along y (kx) or along x (ky), and of the rigid rotation (kr).
        unilateral : bool, default False
            A contact instead of a two-sided guide: a's point rests on the +n side of the guide (n =
            ``axis`` turned by +90 degrees: above a guide along +x) and the joint holds only while
            it presses; when it would pull, a lifts off (in statics the joint is released, in
            dynamics a located "lift" event) and lands again when its gap closes ("land").
        restitution : float, optional
            With ``unilateral``: the landing's coefficient of restitution in [0, 1] (the normal
            rebound velocity over the approach velocity); default 0, a plastic landing.
        """
        return self.joint(name, "slider", a, b, at=at, axis=axis, k=k, preload=preload, mu=mu, mu0=mu0,
                          bearing=bearing, kx=kx, ky=ky, kr=kr, unilateral=unilateral, restitution=restitution)

    def roller(self, name: str, a: str, b: str, axis: Vec, at: Vec | None = None, k: float = 0.0,
               preload: float = 0.0, mu: float | None = None, mu0: float | None = None,
               kx: float | None = None, ky: float | None = None, unilateral: bool = False,
               restitution: float | None = None) -> Joint:
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
        kx, ky : float, optional
            With b = "ground": a spring [N/m] instead of the rigid constraint across a line along y
            (kx) or along x (ky).
        unilateral, restitution : optional
            A contact that lifts off and lands, as for :meth:`slider` (a rocking block's corners).
        """
        return self.joint(name, "roller", a, b, at=at, axis=axis, k=k, preload=preload, mu=mu, mu0=mu0,
                          kx=kx, ky=ky, unilateral=unilateral, restitution=restitution)

    def force(self, name: str, on: str, force: Vec = (0.0, 0.0), moment: float = 0.0,
              at: Vec | None = None, case: str = DEAD, s: float | None = None) -> Load:
        """A dead force (and moment) on a body, a rod end or a point inside a rod, applied together
        with gravity.

        Parameters
        ----------
        name : str
            Its name.
        on : str
            A body, a rod end (``"ROD.start"``, ``"ROD.end"``) or a rod (``"ROD"``, with ``s``).
        force : (float, float), default (0, 0)
            Force [N], global components.
        moment : float, default 0
            Moment [N m], counter-clockwise positive.
        at : (float, float), optional
            Point of application [m] on a body; default: its centroid (or the rod end).
        case : str, default "dead"
            Its load case (gravity is case "dead"); combinations give factors per case.
        s : float, optional
            With ``on`` a rod: the arc length [m] from the rod's start, in [0, length]; every mesh
            has a node there.
        """
        ld = Load(self._name(name), "force", on, tuple(force), moment, None if at is None else tuple(at), case,
                  s=s)
        self.loads[name] = ld
        return ld

    def distributed(self, name: str, on: str, force: Vec, case: str = DEAD, force_end: Vec | None = None,
                    frame: str = "global") -> Load:
        """A dead load distributed along a whole rod, uniform or varying linearly in the arc length.

        Parameters
        ----------
        name : str
            Its name.
        on : str
            The rod's name.
        force : (float, float)
            Force per unit reference length [N/m] at the rod's start (everywhere without
            ``force_end``).
        case : str, default "dead"
            Its load case.
        force_end : (float, float), optional
            Force per unit length [N/m] at the rod's end: the load varies linearly between.
        frame : {"global", "rod"}, default "global"
            The components' axes: global x, y, or the rod's reference tangent (start to end) and
            normal (the tangent turned by +90 degrees).  Dead loads either way: they do not turn
            with the rod.
        """
        ld = Load(self._name(name), "distributed", on, tuple(force), case=case,
                  force_end=None if force_end is None else tuple(force_end), frame=frame)
        self.loads[name] = ld
        return ld

    def thermal(self, name: str, on: str, dT: float = 0.0, dT_gradient: float = 0.0, case: str = DEAD) -> Load:
        """A temperature change of a whole rod (it needs ``alpha``; a gradient also ``depth``).

        The rod's free strain is alpha dT and its free curvature kappa_T = -alpha dT_gradient / depth
        (it bends away from its hotter face); its forces are N = EA (stretch - alpha dT) and
        M = EI (dtheta/ds - kappa_T).  Ramped with the other loads; a case factor scales dT and
        dT_gradient.

        Parameters
        ----------
        name : str
            Its name.
        on : str
            The rod's name.
        dT : float, default 0
            Uniform temperature change [K] (> 0 heats, the rod lengthens).
        dT_gradient : float, default 0
            Temperature of the rod's +n face minus its -n face [K] (n = the rod's reference tangent
            turned by +90 degrees).
        case : str, default "dead"
            Its load case.
        """
        ld = Load(self._name(name), "thermal", on, case=case, dT=dT, dT_gradient=dT_gradient)
        self.loads[name] = ld
        return ld

    def step(self, factors: dict, name: str | None = None) -> Combination:
        """Append a state to the load history (SPEC section 10): the structure is brought from the
        previous step's load state (the unloaded one for the first) to this one by ramping every
        case's factor linearly, quasi-statically.  With steps, sliders and rollers with ``mu`` carry
        Coulomb friction in statics (stuck or slipping, path-dependent) and :func:`femslide.solve`
        reports every step's result.

        Parameters
        ----------
        factors : dict
            {case: factor} of this state; cases not named have factor 0 (gravity is case "dead").
        name : str, optional
            Its name in the results (default "stepN").
        """
        if not isinstance(factors, dict):
            raise BadInput(f"step {name or len(self.steps) + 1}: factors = {factors!r}; allowed: a table "
                           f"{{case = factor, ...}}")
        st = Combination(name or "", tuple(factors.items()))
        self.steps.append(st)
        return st

    def combination(self, name: str, factors: dict) -> Combination:
        """A load combination: a factor per load case, e.g. ``{"dead": 1.35, "wind": 1.5}`` (cases
        not named have factor 0).  With combinations declared, :func:`femslide.solve` solves each
        one as its own equilibrium and reports them with their envelope.

        Parameters
        ----------
        name : str
            Its name.
        factors : dict
            {case: factor}; every case must be the case of some load, or "dead" (gravity).
        """
        if not isinstance(factors, dict):
            raise BadInput(f"combination {name}: factors = {factors!r}; allowed: a table {{case = factor, ...}}")
        c = Combination(self._name(name), tuple(factors.items()))
        self.combinations[name] = c
        return c

    def set(self, path: str, value: Any) -> None:
        """Change one declared field by its dotted name.

        Parameters
        ----------
        path : str
            ``"NAME.FIELD"`` (``"right.EI"``, ``"wind.force"``, ``"clamp.k"``, ``"ULS.factors"``) or
            ``"gravity"``.
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
        for kind in (self.rods, self.bodies, self.joints, self.loads, self.combinations):
            if name in kind:
                obj = kind[name]
                names = {f.name for f in fields(obj)} - {"name"}
                if fld not in names:
                    raise BadInput(f"{path}: {name} has no field {fld!r}; fields: {', '.join(sorted(names))}")
                if isinstance(obj, Combination):
                    if not isinstance(value, dict):
                        raise BadInput(f"{path} = {value!r}; allowed: a table {{case = factor, ...}}")
                    value = tuple(value.items())
                kind[name] = replace(obj, **{fld: value})
                return
        raise BadInput(f"{path}: no rod, body, joint, load or combination is named {name!r}")

    def copy(self) -> Structure:
        """An independent copy of the declaration (the declared objects themselves are immutable)."""
        s = Structure(self.gravity)
        s.rods, s.bodies, s.joints, s.loads = dict(self.rods), dict(self.bodies), dict(self.joints), dict(self.loads)
        s.combinations = dict(self.combinations)
        s.steps = list(self.steps)
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
