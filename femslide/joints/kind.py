"""A joint kind: everything one type of joint ("pin", "weld", ...) means, declared in one class.

A joint connects a point of part a to a point of part b (:mod:`femslide.joints.base`: frames,
carriers, w = p_a - p_b, the guide direction e = R(theta_b) e0 carried by b and n = e turned by +90
degrees; model units).  A :class:`JointKind` tells the rest of the package all it needs about one
type, so that a new type is one new module (a subclass, like :mod:`femslide.joints.pin`) and one
line in :mod:`femslide.joints.kinds`, or a :func:`femslide.joints.kinds.register` call:

- ``name``: the type of declarations (``s.joint(name, "pin", a, b)``, ``type = "pin"`` in a file);
- ``size``: its number of equations (and Lagrange multipliers);
- :meth:`JointKind.equations`: the equations g(z) = 0 with their gradient and Hessians, built from
  the shared pieces :func:`coincide` (w = 0: 2 equations), :func:`on_guide` (w . n = 0: 1) and
  :func:`same_rotation` (theta_a - theta_b = 0: 1);
- ``accepts``: the optional fields of a declaration it takes, from :data:`OPTIONAL_FIELDS`:
  "axis" (then required: the guide direction carried by b; a rod end a may start anywhere on the
  guide line), "c" (a rotational spring [N m/rad] on theta_a - theta_b), "k" and "preload" (a spring
  [N/m] along the guide with its force [N] at the reference position), "mu" and "mu0" (Coulomb
  friction along the guide, dynamics only), "bearing" (distance [m] of the guide's two bearings,
  for friction's normal force), "unilateral" and "restitution" (a contact on the +n side of the
  guide: it holds only while it presses - its first multiplier Q <= 0, the force -Q n on a -, lifts
  off and lands; a kind that accepts it has :func:`on_guide` as its first equation, the gap w . n).
  The declaration's checks (:mod:`femslide.model.frozen`) reject the
  others;
- ``free``: the free relative coordinate reported in the results as ``joints.NAME.<free>``:
  "slide" (s = w . e from the reference position [m]; springs k, friction and held starts act on
  it), "rotation" (theta_a - theta_b [rad], counter-clockwise positive; a spring c acts on it) or
  None;
- ``linear``: its equations are linear in the dofs when neither side has a lever (a rod node or
  the ground on both sides): the model evaluates them once (constant gradient, no Hessian);
- ``stuck``: the name of the kind it becomes when friction sticks its slide (the statics of the
  stuck state: a slider becomes a weld, a roller a pin);
- ``pivot``: a body joined to the ground by it turns about the joint point; a body's frame origin
  is the point of its first pivot to the ground (that joint is then linear), else its centroid;
- :meth:`JointKind.normal_force`: friction's normal force from the joint's multipliers;
- ``symbol``: the picture of the joint (:mod:`femslide.output.diagrams` draws "hinge", "clamp",
  "sleeve" and "roller"; any other name is drawn as a plain marker);
- ``springs``: which of its equations an elastic support (a joint with the ground carrying ``kx``,
  ``ky``, ``kr``) may turn into springs, by name: "kx", "ky" (the x and y components of w = 0),
  "kn" (w . n = 0 across a guide: a declaration's kx for a guide along y, ky for one along x),
  "kr" (theta_a - theta_b = 0) -> the index of that equation in :meth:`JointKind.equations`; an
  equation so turned is replaced by the energy (k/2) g^2 (femslide.joints.base.ElasticSupport);
- ``code``: its integer in the VTU field data ``joint_type`` (0 pin, 1 weld, 2 slider, 3 roller, as
  in files written before the type names were; -1 for every other kind: files name all kinds in
  ``joint_type_names``).

Sign of the multipliers (as everywhere): the equations are stationarity of U + V + mu . g, so the
generalised force of the joint on a is -G_a^T mu.

This module is pure Python (``math`` only): the declaration layer imports it without numpy.
"""
from __future__ import annotations

import math

#: the optional fields of a joint declaration that a kind may accept (besides name, type, a, b, at)
OPTIONAL_FIELDS = frozenset(("axis", "c", "k", "preload", "mu", "mu0", "bearing", "unilateral", "restitution"))


class JointKind:
    """One type of joint (see the module docstring).  Subclasses set the class attributes and
    write :meth:`equations`; instances are registered in :mod:`femslide.joints.kinds`."""

    name: str = ""
    size: int = 0
    accepts: frozenset = frozenset()
    free: str | None = None
    linear: bool = False
    stuck: str | None = None
    pivot: bool = False
    symbol: str = "marker"
    code: int = -1
    springs: dict = {}

    @property
    def guide(self) -> bool:
        """Whether it has a guide line (it accepts, and needs, an ``axis``)."""
        return "axis" in self.accepts

    def equations(self, link, z):
        """The equations of ``link`` (a :class:`femslide.joints.base.Link` of this kind) at its dofs
        ``z`` (a list of Python floats, a's dofs then b's, model units): (g, G, hess) with g the
        ``size`` values, G their gradient rows (``size`` lists of ``link.k`` floats) and hess the
        nonzero second derivatives as (equation, dof, dof, value).  Called per joint per Newton
        iteration: scalar arithmetic, no numpy."""
        raise NotImplementedError(f"joint kind {self.name!r} defines no equations")

    def normal_force(self, mu, h):
        """(N, dN/dmu) of friction in the joint: the normal force N >= 0 [model units] from its
        multipliers ``mu`` (a list) and the derivatives (a list of ``size``); ``h`` the bearing
        distance in model units (None without one).  Default: N = |Q|, Q the first multiplier (the
        transverse force of a guide, :func:`on_guide` first)."""
        Q = mu[0]
        dN = [0.0] * len(mu)
        dN[0] = math.copysign(1.0, Q)
        return abs(Q), dN

    def __repr__(self):
        return f"<joint kind {self.name!r}>"


# -- shared pieces of equations ---------------------------------------------------------------------
# Each appends its equations to g, their gradient rows to G and their second derivatives (equation
# index counted from len(g)) to hess; ``w`` is link.w(z): (wx, wy, dw, d2w, theta_a, theta_b).

def coincide(link, w, g, G, hess):
    """a's point on b's point: w = 0 (2 equations, x then y)."""
    wx, wy, dw, d2w = w[0], w[1], w[2], w[3]
    k, r = link.k, len(g)
    gx, gy = [0.0] * k, [0.0] * k
    for i, dx, dy in dw:
        gx[i] += dx
        gy[i] += dy
    g += [wx, wy]
    G += [gx, gy]
    for i, hx, hy in d2w:
        hess += [(r, i, i, hx), (r + 1, i, i, hy)]


def on_guide(link, w, g, G, hess):
    """a's point on the guide line carried by b: w . n = 0 (1 equation; n = R(theta_b) n0)."""
    wx, wy, dw, d2w, thb = w[0], w[1], w[2], w[3], w[5]
    k, ib, r = link.k, link.ib, len(g)
    ex, ey, nx, ny = link.guide(thb)
    row = [0.0] * k
    for i, dx, dy in dw:
        row[i] += dx * nx + dy * ny
    for i, hx, hy in d2w:
        hess.append((r, i, i, hx * nx + hy * ny))
    if ib is not None:
        j = ib + 2
        row[j] -= wx * ex + wy * ey           # w . dn/dthb, dn/dthb = -e
        for i, dx, dy in dw:                  # 2 sym(dw . dn/dthb) (x) delta_b
            v = -(dx * ex + dy * ey)
            hess += [(r, i, j, v), (r, j, i, v)]
        hess.append((r, j, j, -(wx * nx + wy * ny)))  # w . d2n/dthb2, d2n = -n
    g.append(wx * nx + wy * ny)
    G.append(row)


def same_rotation(link, w, g, G):
    """a turns with b: theta_a - theta_b = 0 (1 equation, linear)."""
    row = [0.0] * link.k
    if link.ia is not None:
        row[link.ia + 2] = 1.0
    if link.ib is not None:
        row[link.ib + 2] = -1.0
    g.append(w[4] - w[5])
    G.append(row)
