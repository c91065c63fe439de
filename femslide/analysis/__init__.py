"""Analyses: Newton, path following, adaptive refinement, statics, excitation, time integration, modes."""
