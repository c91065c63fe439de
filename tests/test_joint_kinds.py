"""Joint kinds as classes in a registry (femslide/joints/kind.py, kinds.py): a new kind of joint is
one class, registered, and every layer above (declaration checks, model, results, VTU, pictures)
works with it without a change.

- two toy kinds defined here and registered for the test only: ``toyclamp`` (a weld written again
  with equations of its own) and ``xtie`` (a new joint: the x coordinates of the two points equal,
  1 equation).  A frame with toy clamps (rod node to the ground, rod node to rod node, a body with a
  lever) solves to the numbers of the same frame with built-in welds, and a cantilever whose tip is
  x-tied to the ground (a structure file) to those of the tip on a roller guided along y (the same
  constraint, written as w . n = 0), both to 1e-12 relative;
- the toy kinds' equations against central differences of their own g (gradient and Hessian, steps
  1e-6, tolerance 1e-7, as for the built-in kinds in tests/test_elements.py, which runs every
  built-in kind through the same check); every registered kind declared ``linear`` has a constant
  gradient and no Hessian between rod nodes and the ground;
- the registry: an unknown type is BadInput listing the registered kinds (the toy kinds too while
  registered), the declaration's field checks come from the kind, malformed kinds are refused;
- VTU: a toy kind is written with ``joint_type`` -1 and its name in ``joint_type_names``, read back
  by the pictures with a plain marker (also once unregistered); files without ``joint_type_names``
  (written before it) still read their built-in types from ``joint_type``.
"""
from __future__ import annotations

import re

import numpy as np
import pytest

import femslide
from femslide.errors import BadInput
from femslide.joints.base import Carrier, Link
from femslide.joints.kind import JointKind
from femslide.joints.kinds import BUILTIN, KINDS, kind_of, problems, register, unregister
from femslide.model.structure import Structure

RNG = np.random.default_rng(20260302)
NODE = Carrier(0, (0.2, 1.9), (0.0, 0.0))
BODY = Carrier(3, (0.3, 2.0), (0.4, -0.3))
GROUND = Carrier(None, (0.0, 0.0), (0.25, 1.7))
PAIRS = ((NODE, GROUND), (BODY, GROUND), (NODE, BODY), (BODY, NODE),
         (Carrier(0, (0.1, 0.2), (-0.3, 0.5)), Carrier(3, (1.0, 0.4), (0.2, 0.1))))


class ToyClamp(JointKind):
    """A weld with its own equations: w = 0 and theta_a - theta_b = 0, written out here."""

    name = "toyclamp"
    size = 3
    linear = True
    symbol = "clamp"

    def equations(self, link, z):
        wx, wy, dw, d2w, tha, thb = link.w(z)
        rows = [[0.0] * link.k for _ in range(3)]
        for i, dx, dy in dw:
            rows[0][i] += dx
            rows[1][i] += dy
        if link.ia is not None:
            rows[2][link.ia + 2] = 1.0
        if link.ib is not None:
            rows[2][link.ib + 2] = -1.0
        hess = [(e, i, i, h) for i, hx, hy in d2w for e, h in ((0, hx), (1, hy))]
        return [wx, wy, tha - thb], rows, hess


class XTie(JointKind):
    """A new joint: a's point keeps b's x coordinate (g = w_x, 1 equation); y and the rotations are
    free.  Its multiplier is minus its force on a along x."""

    name = "xtie"
    size = 1
    linear = True

    def equations(self, link, z):
        wx, _, dw, d2w, _, _ = link.w(z)
        row = [0.0] * link.k
        for i, dx, _ in dw:
            row[i] += dx
        return [wx], [row], [(0, i, i, hx) for i, hx, _ in d2w]


@pytest.fixture
def toys():
    """The toy kinds, registered for one test and removed afterwards."""
    kinds = [register(ToyClamp()), register(XTie())]
    try:
        yield kinds
    finally:
        for k in kinds:
            unregister(k.name)
    assert "toyclamp" not in KINDS and "xtie" not in KINDS


def _numbers(r):
    """The named results of a statics run (SI units), dotted names to floats."""
    return {k: v for k, v in r.flat().items()
            if k.split(".")[0] in ("M_max", "rods", "bodies", "joints", "reactions")}


GROUPS = {"u": "m", "v": "m", "x": "m", "y": "m", "slide": "m", "theta": "rad", "rotation": "rad", "Fx": "N",
          "Fy": "N", "N_max": "N", "V_max": "N"}   # the rest: N m


def _same(r, ref, rtol=1e-12):
    """The results that both runs name agree to rtol relative (of the largest value of the same unit
    where the value itself is nearly zero)."""
    a, b = _numbers(r), _numbers(ref)
    common = sorted(set(a) & set(b))
    assert len(common) > 12
    unit = {k: GROUPS.get(k.rsplit(".", 1)[-1], "N m") for k in common}
    big = {u: max(abs(b[k]) for k in common if unit[k] == u) for u in set(unit.values())}
    bad = [(k, a[k], b[k]) for k in common if abs(a[k] - b[k]) > rtol * max(abs(b[k]), big[unit[k]])]
    assert not bad, bad[:5]
    return common


# -- (1) a toy kind in a declared structure ----------------------------------------------------------

def _frame(kind):
    """A column clamped to the ground, an arm clamped on its top, a box clamped on the arm's end
    off its centroid (a lever), all joints of ``kind``; gravity and a push on the box."""
    s = Structure(gravity=(0.0, -9.81))
    s.rod("col", (0.0, 0.0), (0.0, 2.0), EI=3e3, EA=3e6, rhoA=2.0, elements=8)
    s.rod("arm", (0.0, 2.0), (1.5, 2.5), EI=2e3, elements=6)
    s.body("box", mass=20.0, centroid=(1.8, 2.9), outline=[(1.4, 2.4), (2.2, 2.4), (2.2, 3.4), (1.4, 3.4)])
    s.joint("base", kind, "col.start", "ground")
    s.joint("knee", kind, "arm.start", "col.end")
    s.joint("top", kind, "box", "arm.end")
    s.force("push", "box", force=(400.0, -100.0), moment=30.0, at=(2.2, 3.4))
    return s


def test_toy_clamp_frame_solves_as_the_same_frame_with_welds(toys):
    r = femslide.solve(_frame("toyclamp"))
    ref = femslide.solve(_frame("weld"))
    keys = _same(r, ref)
    assert "reactions.base.M" in keys and "joints.top.M" in keys and "bodies.box.rotation" in keys
    assert abs(ref["bodies"]["box"]["rotation"]) > 1e-3        # a visibly deformed state
    # the links of the model carry the toy kind; its joints between rod nodes and the ground take
    # the linear path, the one with the box's lever does not
    links = r.solution.level.model.joint
    assert links["base"].joint_kind is toys[0] and links["base"].linear and not links["top"].linear


XTIE_FILE = """
description = "a cantilever whose tip keeps its x (a toy joint kind)"
gravity = [0.0, 0.0]

[[rod]]
name = "beam"
start = [0.0, 0.0]
end = [2.0, 0.0]
EI = 50.0
elements = 12

[[joint]]
name = "root"
type = "weld"
a = "beam.start"
b = "ground"

[[joint]]
name = "tip"
type = "xtie"
a = "beam.end"
b = "ground"

[[load]]
name = "P"
type = "force"
on = "beam.end"
force = [0.0, -60.0]
"""


def test_xtie_from_a_structure_file_equals_a_roller_guided_along_y(toys, tmp_path):
    f = tmp_path / "xtie.toml"
    f.write_text(XTIE_FILE)
    r = femslide.solve(str(f))
    s = Structure(gravity=(0.0, 0.0))
    s.rod("beam", (0.0, 0.0), (2.0, 0.0), EI=50.0, elements=12)
    s.weld("root", "beam.start", "ground")
    s.roller("tip", "beam.end", "ground", axis=(0.0, 1.0))
    s.force("P", "beam.end", force=(0.0, -60.0))
    ref = femslide.solve(s)
    _same(r, ref)
    # geometrically nonlinear: the tie holds the tip's x against a membrane force far above the load
    assert ref["rods"]["beam"]["end"]["v"] < -0.02 and r["reactions"]["tip"]["Fx"] > 50 * 60.0
    assert r["rods"]["beam"]["end"]["u"] == pytest.approx(0.0, abs=1e-12)
    assert "slide" not in r["joints"]["tip"] and "rotation" not in r["joints"]["tip"]   # free = None


# -- (2) equations against finite differences -------------------------------------------------------

def _fd_check(link):
    k = link.k
    z = RNG.normal(0, 0.4, k)
    g, G, H = link.eval(z)
    assert g.shape == (link.size,) and G.shape == (link.size, k)
    h = 1e-6
    for j in range(k):
        zp, zm = z.copy(), z.copy()
        zp[j] += h
        zm[j] -= h
        gp, Gp, _ = link.eval(zp)
        gm, Gm, _ = link.eval(zm)
        assert np.allclose(G[:, j], (gp - gm) / (2 * h), atol=1e-7, rtol=0)
        assert np.allclose(H[:, :, j], (Gp - Gm) / (2 * h), atol=1e-7, rtol=0)
    mu = RNG.normal(0, 1.0, link.size)
    rv, jv = [], []
    link.assemble(z.tolist(), mu.tolist(), rv, jv)
    _, Gm, Hmu = link.eval(z, mu)
    assert np.allclose(rv, np.concatenate([mu @ Gm, g]), rtol=0, atol=1e-14)
    assert np.allclose(jv, np.concatenate([Hmu.ravel(), Gm.ravel(), Gm.ravel()]), rtol=0, atol=1e-14)


@pytest.mark.parametrize("pair", range(len(PAIRS)))
@pytest.mark.parametrize("kind", ["toyclamp", "xtie"])
def test_toy_equations_against_finite_differences(toys, kind, pair):
    a, b = PAIRS[pair]
    _fd_check(Link("j", kind, a, b))


def test_toy_clamp_equations_are_the_welds():
    for a, b in PAIRS:
        weld = Link("w", "weld", a, b)
        toy = Link("t", ToyClamp(), a, b)   # a kind need not be registered to build a link
        z = RNG.normal(0, 0.4, weld.k).tolist()
        assert toy.joint_kind.equations(toy, z) == weld.joint_kind.equations(weld, z)


@pytest.mark.parametrize("kind", sorted(k.name for k in BUILTIN) + ["toyclamp", "xtie"])
def test_linear_kinds_have_a_constant_gradient_between_nodes_and_the_ground(toys, kind):
    node2 = Carrier(3, (1.0, 0.4), (0.0, 0.0))
    for a, b in ((NODE, GROUND), (NODE, node2), (node2, NODE)):
        link = Link("j", kind, a, b, axis=(0.6, 0.8))
        z1, z2 = RNG.normal(0, 0.7, link.k), RNG.normal(0, 0.7, link.k)
        g1, G1, H1 = link.eval(z1)
        g2, G2, H2 = link.eval(z2)
        assert link.linear == link.joint_kind.linear
        if link.linear:
            assert np.array_equal(G1, G2) and not H1.any() and not H2.any()
            assert np.allclose(g2 - g1, G1 @ (z2 - z1), rtol=0, atol=1e-14)


# -- (3) the registry and the declaration's checks ----------------------------------------------------

def _one_joint(kind, **options):
    s = Structure(gravity=(0.0, 0.0))
    s.rod("beam", (0.0, 0.0), (2.0, 0.0), EI=50.0)
    s.weld("root", "beam.start", "ground")
    s.joint("j", kind, "beam.end", "ground", **options)
    return s


def test_unknown_type_is_bad_input_listing_the_registered_kinds(toys):
    with pytest.raises(BadInput, match=r"joint j: type 'hinge'; allowed: pin, weld, slider, roller, toyclamp, xtie"):
        _one_joint("hinge").freeze()
    with pytest.raises(BadInput, match=r"type 'hinge'; allowed: pin, weld, slider, roller, toyclamp, xtie$"):
        kind_of("hinge")


def test_unknown_type_without_toys():
    with pytest.raises(BadInput, match=r"joint j: type 'xtie'; allowed: pin, weld, slider, roller$"):
        _one_joint("xtie").freeze()
    with pytest.raises(BadInput, match=r"type None"):
        kind_of(None)


@pytest.mark.parametrize("options,needle", [
    ({"c": 1.0}, "a rotational spring c is for pins, not a xtie"),
    ({"axis": (0.0, 1.0)}, "axis is for sliders and rollers, not a xtie"),
    ({"k": 2.0}, "k and preload are for sliders and rollers, not a xtie"),
    ({"mu": 0.3}, r"friction \(mu, mu0\) is for sliders and rollers, not a xtie"),
    ({"bearing": 0.1}, "bearing is for sliders"),
])
def test_field_checks_come_from_the_kind(toys, options, needle):
    with pytest.raises(BadInput, match=needle):
        _one_joint("xtie", **options).freeze()
    _one_joint("xtie").freeze()


def test_malformed_kinds_are_refused_and_built_ins_stay():
    for k in BUILTIN:
        assert problems(k) == [] and KINDS[k.name] is k

    class Slide(JointKind):
        name, size, free = "badslide", 1, "slide"

    class Friction(JointKind):
        name, size, free, accepts = "badfriction", 1, "slide", frozenset(("axis", "mu", "mu0"))

    class Pin2(JointKind):
        name, size = "pin", 2

    for bad, needle in ((Slide(), "a slide needs a guide"), (Friction(), "stuck"), (Pin2(), "name 'pin'")):
        with pytest.raises(ValueError, match=needle):
            register(bad)
        assert KINDS.get(bad.name) is not bad
    with pytest.raises(TypeError):
        register("pin")
    with pytest.raises(ValueError, match="built in"):
        unregister("pin")


# -- VTU and pictures ----------------------------------------------------------------------------------

def test_vtu_names_a_toy_kind_and_pictures_draw_a_marker(toys, tmp_path):
    from femslide.output.diagrams import frame_data, shapes
    from femslide.output.vtu import text, write_static

    s = _one_joint("xtie")
    s.force("P", "beam.end", force=(0.0, -1.0))
    r = femslide.solve(s)
    path, _ = write_static(r.solution, str(tmp_path), "tie")
    from femslide.output.vtu import read
    fd = read(path).field_data
    assert fd["joint_type"].ravel().tolist() == [1, -1]
    assert text(fd, "joint_type_names").split("\n") == ["weld", "xtie"]

    def marker(fr):
        j = next(j for j in fr["joints"] if j["name"] == "j")
        assert j["type"] == "xtie"
        polys = [p for kind, p, _ in shapes(fr) if kind == "poly" and len(p) == 4]
        return j, [p for p in polys if np.allclose(p.mean(axis=0), j["X"])]

    j, found = marker(frame_data(path))
    assert j["symbol"] == "marker" and len(found) == 1
    unregister("xtie")
    try:
        j, found = marker(frame_data(path))      # a type this process does not know
        assert j["symbol"] is None and len(found) == 1
    finally:
        register(toys[1])


def test_vtu_without_type_names_reads_the_codes(tmp_path):
    from femslide.output.diagrams import frame_data

    s = Structure(gravity=(0.0, 0.0))
    s.rod("beam", (0.0, 0.0), (2.0, 0.0), EI=50.0, elements=4)
    s.pin("a", "beam.start", "ground")
    s.roller("b", "beam.end", "ground", axis=(1.0, 0.0))
    s.force("P", "beam.end", force=(0.0, -1.0), moment=0.5)
    r = femslide.solve(s)
    from femslide.output.vtu import write_static
    path, _ = write_static(r.solution, str(tmp_path), "old")
    new = frame_data(path)
    text = open(path).read()
    old = re.sub(r'<Array [^>]*Name="joint_type_names"[^>]*>[^<]*</Array>\n', "", text)
    assert old != text
    open(path, "w").write(old)
    fr = frame_data(path)
    assert [(j["type"], j["symbol"]) for j in fr["joints"]] == [("pin", "hinge"), ("roller", "roller")]
    assert [(j["type"], j["symbol"]) for j in new["joints"]] == [("pin", "hinge"), ("roller", "roller")]
