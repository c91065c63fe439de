"""Element kernels: the corotational beam, scikit-fem forms for varying EI and EA, and loads on elements."""
