"""The model layer: declaring a structure, freezing it, and its discretisation (dofs, assembly,
masses, linear algebra)."""
