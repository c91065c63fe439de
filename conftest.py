"""pytest configuration for tests/ and validation/: one BLAS thread, as the command line runs (the
solvers factorise many small matrices, where OpenBLAS threads only cost), set before numpy loads."""
import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
