"""Joints as exact constraints (pin, weld, slider, roller), their springs, holds and Coulomb friction."""
