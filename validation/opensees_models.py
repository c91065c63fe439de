"""OpenSees (openseespy) models of femslide's scenes, for benchmarks and cross-checks.

Imported only where openseespy is wanted (it needs Debian's libblas3 and liblapack3).
"""
from __future__ import annotations

import math
import os
import time


def opensees_slider(v, phi, n=32, steps=None, penalty=1e6):
    """beam-slider in OpenSees (nondimensional: lengths by a, forces by P), driven by displacement
    control of the body rotation to femslide's equilibrium phi; returns (seconds of the analysis,
    load factor at phi, M_max [N m], status, seconds of model building and analysis).

    OpenSees has no rotating prismatic joint, so the sliding clamp is a corotational beam from a body
    point C on the guide line to the rod top S that is stiff in bending (penalty x the rod's EI) and
    has almost no axial stiffness: its chord, and so S, stays on the guide line through C, S turns
    with the body, and the slide is free up to the penalty.  The rigid body (with the rigid left rod)
    is two stiff corotational beams from the ground pin A1 to C and to the centre of mass G.  The
    work is less than femslide's: OpenSees is told phi and only finds the load factor holding it.
    """
    import openseespy.opensees as ops
    a, P = v["a"], v["m"] * v["g"]
    l, b, d, L = v["l"] / a, v["b"] / a, v["d"] / a, (v.get("L") or v["l"]) / a
    EI, EA = v["EI"] / (P * a * a), v["EA"] / P
    stiff = penalty * max(EI, 1.0)
    t_build = time.perf_counter()
    ops.wipe()
    ops.logFile(os.devnull, "-noEcho")  # its failures are counted, not printed
    ops.model("basic", "-ndm", 2, "-ndf", 3)
    ops.node(1, 0.0, 0.0)                 # A1: the body's ground pin (body rotation = its dof 3)
    ops.node(2, 1.0 + d, l + b)           # G
    ops.node(3, 2.0, L + 1.0)             # C: body point on the guide line, above the rod top
    for i in range(n + 1):                # the flexible rod B1 -> S
        ops.node(10 + i, 2.0, L * i / n)
    ops.fix(1, 1, 1, 0)
    ops.fix(10, 1, 1, 0)
    ops.geomTransf("Corotational", 1)
    for i in range(n):
        ops.element("elasticBeamColumn", 100 + i, 10 + i, 11 + i, EA, 1.0, EI, 1)
    ops.element("elasticBeamColumn", 1, 1, 2, stiff * EA / max(EI, 1.0), 1.0, stiff, 1)   # rigid body
    ops.element("elasticBeamColumn", 2, 1, 3, stiff * EA / max(EI, 1.0), 1.0, stiff, 1)
    ops.element("elasticBeamColumn", 3, 3, 10 + n, 1e-6, 1.0, stiff, 1)                  # the clamp
    ops.timeSeries("Linear", 1)
    ops.pattern("Plain", 1, 1)
    ops.load(2, 0.0, -1.0, 0.0)
    ops.system("BandGeneral")
    ops.numberer("RCM")
    ops.constraints("Plain")
    ops.test("NormDispIncr", 1e-12, 50, 0)
    ops.algorithm("Newton")
    steps = steps or max(1, math.ceil(abs(phi) / 0.1))
    ops.integrator("DisplacementControl", 1, 3, -phi / steps)
    ops.analysis("Static")
    t0 = time.perf_counter()
    ok = ops.analyze(steps)
    dt = time.perf_counter() - t0
    dt_all = time.perf_counter() - t_build
    lam = ops.getLoadFactor(1)
    M = max(abs(ops.eleForce(100 + i)[2]) for i in range(n))
    M = max(M, abs(ops.eleForce(100 + n - 1)[5]))
    return dt, lam, M * P * a, ok, dt_all
