"""Reference values of the paper's structure in time, from the reduced 1-degree-of-freedom model
(validation/reduced_dynamics.py: the massless rod's statics at every body rotation, DOP853 at rtol 1e-11,
energy balance ~1e-11) - a formulation independent of the FE transient (femslide/analysis/transient.py)
on which the scenes beam-oscillation and beam-friction and the structure files run, and which the
validation compares against them.  Regenerate with (default parameters, from the repository root)::

    python -c "import sys; sys.path.insert(0, 'validation'); from reduced_dynamics import *; \
    from femslide.scenes.catalog import get; print(run_friction(get('beam-friction').resolve({})))"

(and run_oscillation for beam-oscillation); the OpenSees Newmark transient of
validation/opensees_models.py agrees with OSCILLATION_F2 to 5e-9.  Both runs start at rest from
phi = phi0 (0.01, 0) held, as the scenes do.
"""

# beam-oscillation (section 5.2, released from phi = 0.01 rad): peak |F2| [N]
OSCILLATION_F2 = 88.92548492288407

# beam-friction (friction in the sliding clamp, ground acceleration at the frictionless frequency)
FRICTION_STICK = [0.5980783557781205, 1.1999410820655922, 1.808435723775855, 2.420973032106233]  # ends of slip [s]
FRICTION_F2 = 15.735132504141756                                  # peak |F2| [N]
FRICTION_SLIDE = (-0.08479172708081142, 0.08018954611890944)      # slide range [m]
FRICTION_OMEGA = 5.090891795846383                                # frictionless small-oscillation omega [rad/s]
FRICTION_JUMP = 4.688917117104702e-06                             # energy released by the slide's jumps [J]
FRICTION_WORK = (0.3886431132621047 + FRICTION_JUMP, 0.7568608325916912)  # dissipated (friction + jumps), work in [J]
