"""Built-in scenes as data: the parameters each accepts, its defaults, its rules and its runner.

A scene's ``kind`` says what machinery it runs on: "hinge" (the exact spring-hinge models, pure
Python), "fe-statics" (the paper's structures and the cantilevers as FE declarations),
"oscillator" (the exact one-mass friction oscillator) and "fe-dynamics" (the paper's section 5.2
structure in time, on the FE transient).  Its runner is a function that imports that machinery when called, so listing
scenes or solving a spring-hinge scene never imports the FE machinery (or numpy); ``machinery``
imports it beforehand, so that a run's ``import_time_s`` and ``wall_time_s`` are measured apart.
A runner has the signature ``run(values: dict) -> result: dict``: ``values`` are validated
parameters (plus private keys starting with ``_``, e.g. ``_quiet`` to switch off progress bars,
``_progress`` a callable t -> None that the FE dynamics calls as simulated time advances),
``result`` the JSON object of the contract (SPEC section 7); private result keys are not printed.
Runners raise :class:`~femslide.errors.SolverFailure` when they do not converge.  Every run starts
from scratch, so a case gives the same numbers whether it is solved alone or in a sweep.
"""
from __future__ import annotations

import math
from collections.abc import Callable

from femslide.errors import BadInput, SolverFailure
from femslide.records import dataclass
from femslide.results.outcome import Outcome
from femslide.scenes.params import ParamSet, rule_l1_le_l, rule_l1_lt_l, rule_mu0_ge_mu

GEOMETRY = ("a", "b", "d", "l", "m", "g")
FE = GEOMETRY + ("EI", "EA", "n_elements")


def rule_L_le_l(v):
    if v.get("L") is not None and v["L"] > v["l"]:
        return (f"parameter L = {v['L']:g} m (free length of the flexible sliding rod) exceeds l = {v['l']:g} m; "
                f"allowed: 0 < L <= l")
    return None


@dataclass(frozen=True)
class Scene:
    name: str
    command: str  # "solve" or "simulate"
    model: str
    params: ParamSet
    kind: str     # "hinge", "fe-statics", "oscillator" or "fe-dynamics"
    runner: Callable[[dict], dict]

    def resolve(self, given: dict) -> dict:
        return self.params.resolve(given, scene=self.name)

    def prepare(self):
        """Import the machinery the scene needs (numpy, the FE modules, LAPACK).  Separate from
        :meth:`run` so that a run's ``wall_time_s`` measures the solve and ``import_time_s`` the
        imports."""
        MACHINERY[self.kind]()

    def run(self, values: dict) -> dict:
        out = self.runner(values)
        res = out.values if isinstance(out, Outcome) else out
        bad = _non_finite(res)
        if bad and res.get("converged", True):
            raise SolverFailure(f"the result is not finite ({bad} = {_at(res, bad)}); not reported as "
                                f"converged")
        return out


def _non_finite(obj, path=""):
    """Dotted path of the first NaN or inf float in a result (private ``_`` keys skipped), or ''."""
    if type(obj) is float:   # (the common leaf first)
        return "" if math.isfinite(obj) else path
    if isinstance(obj, dict):
        for k, v in obj.items():
            if (type(v) is float and math.isfinite(v)) or str(k).startswith("_"):   # (no path built)
                continue
            bad = _non_finite(v, f"{path}.{k}" if path else str(k))
            if bad:
                return bad
        return ""
    if isinstance(obj, (list, tuple)):
        for i, v in enumerate(obj):
            bad = _non_finite(v, f"{path}[{i}]")
            if bad:
                return bad
        return ""
    if isinstance(obj, (bool, str)) or obj is None:
        return ""
    try:
        return "" if math.isfinite(float(obj)) else path
    except (TypeError, ValueError, OverflowError):
        return ""


def _at(res, path):
    import re
    obj = res
    for part in re.findall(r"[^.\[\]]+|\[\d+\]", path):
        obj = obj[int(part[1:-1])] if part.startswith("[") else obj[part]
    return obj


# -- runners: each imports its machinery when called ----------------------------------------------

def _hinge(model):
    def run(v):
        from femslide.scenes import hinge
        return {"slider": hinge.solve_slider, "fixed": hinge.solve_fixed,
                "extra-mass": hinge.solve_extra_mass}[model](**v)
    return run


def _fe_statics(scene):
    def run(v):
        from femslide.scenes import paper
        return paper.run(scene, v)
    return run


def _oscillator(v):
    from femslide.scenes import sdof
    return sdof.run(v)


def _fe_dynamics(which):
    def run(v):
        from femslide.scenes import beam_dynamics
        return beam_dynamics.run(v, friction=which == "friction", progress=v.get("_progress"))
    return run


def _load_fe():
    from femslide.analysis import static  # noqa: F401
    from femslide.model.linalg import load_lapack
    load_lapack()


def _load_oscillator():
    from femslide.scenes import sdof  # noqa: F401


def _load_fe_dynamics():
    _load_fe()
    from femslide.analysis import simulate  # noqa: F401
    from femslide.scenes import beam_dynamics  # noqa: F401


def _load_nothing():
    from femslide.scenes import hinge  # noqa: F401


MACHINERY = {"hinge": _load_nothing, "fe-statics": _load_fe, "oscillator": _load_oscillator,
             "fe-dynamics": _load_fe_dynamics}


SCENES: dict[str, Scene] = {s.name: s for s in [
    Scene("hinge-slider", "solve", "section 2: rigid fixed rod; sliding rod with a spring hinge at height l1",
          ParamSet(GEOMETRY + ("l1", "c"), rules=(rule_l1_le_l,)), "hinge", _hinge("slider")),
    Scene("hinge-fixed", "solve", "section 3: fixed rod with a spring hinge at l/2; rigid sliding rod",
          ParamSet(GEOMETRY + ("c",)), "hinge", _hinge("fixed")),
    Scene("hinge-spring", "solve", "section 4: section 2 plus a linear spring k between rod and guide",
          ParamSet(GEOMETRY + ("l1", "c", "k"), rules=(rule_l1_le_l,)), "hinge", _hinge("slider")),
    Scene("hinge-extra-mass", "solve",
          "section 5.1: preloaded slider spring, telescopic rod piece (m1, l2), extra mass dm on the body",
          ParamSet(GEOMETRY + ("l1", "c", "k", "dm", "m1", "l2"), defaults={"dm": 1e-3},
                   rules=(rule_l1_lt_l,)), "hinge", _hinge("extra-mass")),
    # -- FE statics scenes (declarations in femslide/scenes/paper.py) --
    Scene("beam-slider", "solve", "right rod a flexible FE beam (free length L) in the sliding clamp, left rod rigid",
          ParamSet(FE + ("L",), defaults={"L": None}, rules=(rule_L_le_l,)), "fe-statics", _fe_statics("beam-slider")),
    Scene("beam-fixed", "solve", "left rod a flexible FE beam welded at A, right rod rigid in the sliding clamp",
          ParamSet(FE), "fe-statics", _fe_statics("beam-fixed")),
    Scene("beam-both", "solve", "both rods flexible FE beams (left welded at A, right in the sliding clamp)",
          ParamSet(FE), "fe-statics", _fe_statics("beam-both")),
    Scene("beam-spring", "solve", "beam-slider with a linear spring k along the guide (at rest in the vertical state)",
          ParamSet(FE + ("L", "k"), defaults={"L": None}, rules=(rule_L_le_l,)),
          "fe-statics", _fe_statics("beam-spring")),
    Scene("beam-extra-mass", "solve",
          "FE section 5.1: preloaded slider spring, flexible rod of length L under a rigid telescopic piece "
          "(m1, l2), extra mass dm",
          ParamSet(FE + ("L", "k", "dm", "m1", "l2"), defaults={"L": 1.5, "dm": 1e-3}, rules=(rule_L_le_l,)),
          "fe-statics", _fe_statics("beam-extra-mass")),
    Scene("cantilever-moment", "solve", "clamped rod under an end moment m_ratio * 2 pi EI/L (1: full circle)",
          ParamSet(("L", "EI", "EA", "n_elements", "m_ratio"), defaults={"EI": 1.0}),
          "fe-statics", _fe_statics("cantilever-moment")),
    Scene("cantilever-load", "solve", "clamped rod under a transverse dead tip load p_ratio * EI/L^2 (+y)",
          ParamSet(("L", "EI", "EA", "n_elements", "p_ratio"), defaults={"EI": 1.0}),
          "fe-statics", _fe_statics("cantilever-load")),
    # -- one-mass dynamic scenes (femslide/scenes/sdof.py) --
    Scene("sdof-free", "simulate",
          "paper 003 ex. 1: free vibration of a mass on a spring with Coulomb friction (mu, mu0), exact",
          ParamSet(("m", "k", "g", "mu", "mu0", "c_v", "w0", "t_end"),
                   defaults={"m": 1.0, "k": 200.0, "g": 9.81, "mu": 0.2, "mu0": 0.24, "c_v": 0.0,
                             "w0": 0.07, "t_end": 2.0},
                   rules=(rule_mu0_ge_mu,)), "oscillator", _oscillator),
    Scene("sdof-decay", "simulate",
          "paper 003 ex. 2: decaying oscillation under constant friction (N = m g = 20 N), exact",
          ParamSet(("m", "k", "g", "mu", "mu0", "c_v", "w0", "t_end"),
                   defaults={"m": 20.0 / 9.81, "k": 1000.0, "g": 9.81, "mu": 0.15, "mu0": 0.18,
                             "c_v": 0.0, "w0": 0.08, "t_end": 3.0},
                   rules=(rule_mu0_ge_mu,)), "oscillator", _oscillator),
    Scene("sdof-harmonic", "simulate",
          "paper 003 ex. 3: ex. 2 from rest under F = P0 sin(theta t) - m ag sin(theta t) - m a_rec(t); "
          "P0 defaults to 10 N, or to 0 when ag or record is given",
          ParamSet(("m", "k", "g", "mu", "mu0", "c_v", "w0", "P0", "theta_ratio", "ag", "record",
                    "t_end"),
                   defaults={"m": 20.0 / 9.81, "k": 1000.0, "g": 9.81, "mu": 0.15, "mu0": 0.18,
                             "c_v": 0.0, "w0": 0.0, "P0": None, "theta_ratio": 0.5, "ag": 0.0,
                             "record": None, "t_end": 30.0},
                   rules=(rule_mu0_ge_mu,)), "oscillator", _oscillator),
    # -- structure dynamic scenes (femslide/scenes/beam_dynamics.py, on the FE transient) --
    Scene("beam-oscillation", "simulate",
          "FE section 5.2 on the FE transient: beam-extra-mass at dm = 0 (massless rod; deck and piece m1 carry "
          "the inertia) released from rest at phi0; w = phi; c_v a dashpot on phi.  At the default tolerance "
          "1e-6 (measured at the defaults) within 1e-4 s and 5e-8 rad (turning points), 1e-5 (F2_max) and "
          "4e-6 (w_max) of the reduced 1-DOF model; energy_balance 4e-5",
          ParamSet(FE + ("L", "k", "m1", "l2", "c_v", "phi0", "t_end", "tolerance"),
                   defaults={"L": 1.5, "n_elements": 8, "t_end": 3.0}, rules=(rule_L_le_l,),
                   units={"c_v": "N m s/rad"}),
          "fe-dynamics", _fe_dynamics("oscillation")),
    Scene("beam-friction", "simulate",
          "beam-oscillation with Coulomb friction (mu, mu0) in the sliding clamp (N = |clamp transverse force|), "
          "m1 = 0, ground acceleration ag sin(theta t) (+ record), theta = theta_ratio * omega (frictionless).  "
          "At the default tolerance 1e-6 (measured at the defaults) within 8e-5 s and 2.5e-6 rad (turning "
          "points), 4e-4 (F2_max) and 2e-4 (w_max) of the reduced 1-DOF model; energy_balance 1.1e-4",
          ParamSet(FE + ("L", "k", "mu", "mu0", "c_v", "phi0", "ag", "theta_ratio", "record", "t_end", "tolerance"),
                   defaults={"L": 1.5, "n_elements": 8, "EI": 1e4, "EA": 1e6, "mu": 0.2, "mu0": 0.24,
                             "phi0": 0.0, "ag": 1.0, "theta_ratio": 1.0, "record": None, "t_end": 3.0},
                   rules=(rule_L_le_l, rule_mu0_ge_mu), units={"c_v": "N m s/rad"}),
          "fe-dynamics", _fe_dynamics("friction")),
]}


def get(name: str) -> Scene:
    try:
        return SCENES[name]
    except KeyError:
        raise BadInput(f"unknown scene {name!r}; built-in scenes: {', '.join(SCENES)}") from None
