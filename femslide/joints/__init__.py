"""Joints as exact constraints: the joint kinds and their registry (pin, weld, slider, roller; kinds.py),
the links of a model, their springs, holds and Coulomb friction."""
