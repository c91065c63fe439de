"""The built-in scenes: the paper's structures as declarations, the spring-hinge models, the exact
one-mass oscillator."""
