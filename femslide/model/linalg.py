"""Linear algebra of the model's Newton systems: dense, banded and sparse solves.

The Jacobians of :meth:`femslide.model.discrete.Model.system` are saddle-point matrices
[[K, G^T], [G, 0]].  Rod meshes make K block-tridiagonal; joints add a few entries near the rod ends.
Small systems are solved dense, larger ones with a narrow band after reverse Cuthill-McKee
renumbering in LAPACK's band storage (O(n) per solve), wide-band ones by sparse LU (SuperLU).  The
dense and band LU with partial pivoting come with the compiled kernel (femslide.model._assembly:
LAPACK's own algorithms, dgetf2 and dgbtf2, without the cost of calling LAPACK through its Python
wrappers, which at these sizes is most of the solve); without the kernel they are LAPACK's dgesv
and dgbsv, loaded from scipy's compiled wrappers without importing ``scipy.linalg`` (whose import
costs ten times a small solve).  A band matrix keeps its factors: a second right-hand side costs a
solve, not a factorisation.  The dense symmetric eigenproblems and null spaces of the natural modes
(:func:`eigh`, :func:`null_space`) call LAPACK the same way, as scipy.linalg would, and the set
operations (:func:`distinct`, :func:`member`, :func:`complement`) are numpy's without numpy.ma: a
time history without damping or friction imports no scipy module.
"""
from __future__ import annotations

import numpy as np

import contextlib
import math
import os
import sys

KERNEL_VERSION = 4   # the source's (_assembly.c's VERSION): a kernel built from another is not used

try:
    from femslide.model import _assembly as _kernel
    KERNEL_ERROR = ""
except ImportError as exc:   # not built or not loadable: LAPACK and the numpy assembly (fast.status says so)
    _kernel = None
    KERNEL_ERROR = str(exc) or type(exc).__name__
if _kernel is not None and getattr(_kernel, "VERSION", None) != KERNEL_VERSION:
    # (an editable install whose extension was not rebuilt after an update of _assembly.c: its functions
    # may be missing or do other arithmetic; the numpy path gives the right answers)
    KERNEL_ERROR = (f"built from another version of femslide/model/_assembly.c (kernel version "
                    f"{getattr(_kernel, 'VERSION', None)}, this source {KERNEL_VERSION}): rebuild it with "
                    f"pip install -e . (or reinstall femslide)")
    _kernel = None

_FORCED: list = []

# os.environ.get of an unset variable raises and catches a KeyError (~1 us): at every dense solve that
# was 4 % of a sweep.  The environment's own mapping is read instead where os.environ has one.
_ENV_NAME = "FEMSLIDE_KERNEL"
try:
    _ENV_KEY = os.environ.encodekey(_ENV_NAME)
except AttributeError:   # (another os.environ: the public interface)
    _ENV_KEY = None


def _kernel_env():
    """The value of FEMSLIDE_KERNEL, or None when it is not set."""
    env = os.environ
    data = getattr(env, "_data", None) if _ENV_KEY is not None else None
    if type(data) is not dict:
        return env.get(_ENV_NAME)
    v = data.get(_ENV_KEY)
    return None if v is None else env.decodevalue(v)


def kernel_available() -> bool:
    """Whether the compiled kernel (femslide.model._assembly) is built and importable."""
    return _kernel is not None


def kernel_enabled() -> bool:
    """Whether the compiled kernel (assembly and LU) is used now: built, not switched off by the
    environment variable ``FEMSLIDE_KERNEL=numpy`` nor inside :func:`kernel_forced` (False)."""
    if _kernel is None:
        return False
    if _FORCED:
        return _FORCED[-1]
    env = _kernel_env()
    return env is None or env.lower() != "numpy"


def model_kernel(model, name):
    """The compiled kernel's function ``name`` for work on ``model`` when the model was finalized with
    the kernel (its ``_pack``; a model keeps the assembly it was finalized with), else None: the
    caller's numpy path.  (No look-up of the environment: it runs at every refinement level.)"""
    return getattr(_kernel, name, None) if getattr(model, "_pack", None) is not None else None


def kernel_function(name):
    """The compiled kernel's function ``name`` when the kernel is used now (:func:`kernel_enabled`) and
    has it (a kernel built from an older source may not), else None: the caller's numpy path."""
    return getattr(_kernel, name, None) if kernel_enabled() else None


@contextlib.contextmanager
def kernel_forced(on: bool):
    """Within the block the compiled kernel is used (``on``, if built) or not, whatever the
    environment says: the tests' switch between the kernel and its numpy/LAPACK oracle.  A model
    keeps the assembly it was finalized with."""
    _FORCED.append(bool(on))
    try:
        yield
    finally:
        _FORCED.pop()

RCM_LOCAL_LIMIT = 5000  # unknowns; up to it the banded ordering is computed without scipy


class Banded:
    """A static sparsity pattern renumbered by reverse Cuthill-McKee and stored as a LAPACK band.

    Rod meshes give block-tridiagonal tangents; joints and the bordered control add a few entries
    near the rod ends.  After renumbering, the saddle-point system is solved by banded LU with
    partial pivoting (dgbsv) in O(n) per Newton iteration, without building a sparse matrix.
    """

    def __init__(self, rows, cols, size):
        if kernel_enabled():   # the kernel's RCM: the same permutation, any size, without scipy
            perm = np.empty(size, np.int64)
            _kernel.rcm(np.ascontiguousarray(rows, np.int64), np.ascontiguousarray(cols, np.int64), size, perm)
            perm = perm.astype(np.intp, copy=False)
        elif size <= RCM_LOCAL_LIMIT:
            perm = reverse_cuthill_mckee(rows, cols, size)
        else:   # large: scipy's compiled RCM (its import is small against the solve)
            import scipy.sparse as sp
            from scipy.sparse.csgraph import reverse_cuthill_mckee as rcm
            pat = sp.coo_matrix((np.ones(rows.size), (rows, cols)), shape=(size, size)).tocsr()
            perm = rcm((pat + pat.T).tocsr(), symmetric_mode=True).astype(np.intp)
        inv = np.empty_like(perm)
        inv[perm] = np.arange(size)
        pr, pc = inv[rows], inv[cols]
        self.kl = int(max(0, (pr - pc).max()))
        self.ku = int(max(0, (pc - pr).max()))
        self.size = size
        self.perm, self.inv = perm, inv   # inv: position of each unknown in the band
        nrow = 2 * self.kl + self.ku + 1
        self.shape = (nrow, size)
        # column-major (LAPACK's layout, so that no wrapper copies it): A[i, j] at ab[kl + ku + i - j, j],
        # stored at flat position j * nrow + kl + ku + i - j of an array (size, nrow) in C order
        self.flat = pc * nrow + (self.kl + self.ku + pr - pc)

    def empty(self):
        """Storage for a matrix of this pattern: (the band array (nrow, size), Fortran order; the
        (size, nrow) C-order array behind it, which the kernel fills through ``flat``)."""
        raw = np.empty((self.size, self.shape[0]))
        return raw.T, raw

    def assemble(self, vals):
        ab = np.bincount(self.flat, weights=vals, minlength=self.shape[0] * self.size)
        return BandMatrix(self, ab.reshape(self.size, self.shape[0]).T)


def distinct(a, first=False):
    """Sorted distinct values of an array, flattened (np.unique's result for finite values; np.unique
    itself imports numpy.ma on its first call: 35 ms without bytecode, ~17 ms with, and ~3 MB); with
    ``first``, also the index of each value's first occurrence (np.unique's ``return_index``)."""
    a = np.asarray(a).ravel()
    order = np.argsort(a, kind="stable")
    a = a[order]
    keep = np.concatenate(([True], a[1:] != a[:-1])) if a.size else np.zeros(0, dtype=bool)
    return (a[keep], order[keep]) if first else a[keep]


def member(a, values):
    """Whether each entry of a is among ``values`` (np.isin, without its import of numpy.ma)."""
    v = distinct(values)
    a = np.asarray(a)
    if not v.size:
        return np.zeros(a.shape, dtype=bool)
    i = np.minimum(np.searchsorted(v, a), v.size - 1)
    return v[i] == a


def complement(n, idx):
    """The indices 0 .. n-1 not in ``idx``, ascending (np.setdiff1d(np.arange(n), idx))."""
    keep = np.ones(n, dtype=bool)
    keep[np.asarray(idx, dtype=np.intp)] = False
    return np.nonzero(keep)[0]


def coo_mv(rows, cols, vals, x, n):
    """(rows, cols, vals) @ x for a COO matrix of n rows (duplicates summed): one bincount."""
    return np.bincount(rows, weights=vals * x[cols], minlength=n)


class Coo:
    """A square sparse matrix as COO triplets ``row``, ``col``, ``data`` (duplicates summed in the
    order given, zeros dropped, entries in row-major order) of ``shape`` (n, n), without scipy: a time
    history's damping matrix C (model units).  ``C @ v`` (v a vector) is one bincount (:func:`coo_mv`);
    ``C + D``, ``a * C`` and ``C.T`` give new matrices.  :meth:`of` takes one of these, a square scipy sparse matrix
    (anything with ``tocoo``) or None.  Indices outside 0 .. n-1 are a ValueError."""

    __slots__ = ("row", "col", "data", "shape")

    def __init__(self, row, col, data, n):
        row, col = np.asarray(row, dtype=np.intp).ravel(), np.asarray(col, dtype=np.intp).ravel()
        data = np.asarray(data, dtype=float).ravel()
        if not (row.size == col.size == data.size):
            raise ValueError(f"Coo: row, col and data differ in length ({row.size}, {col.size}, {data.size})")
        if row.size and (min(row.min(), col.min()) < 0 or max(row.max(), col.max()) >= n):
            raise ValueError(f"Coo: an index outside 0 .. {n - 1}")
        key = row * n + col
        u = distinct(key)
        vals = np.bincount(np.searchsorted(u, key), weights=data, minlength=u.size) if u.size else np.zeros(0)
        keep = vals != 0.0
        self.data, u = vals[keep], u[keep]
        self.row, self.col, self.shape = u // n, u % n, (n, n)

    @classmethod
    def of(cls, C):
        """C as a Coo (None stays None)."""
        if C is None or isinstance(C, cls):
            return C
        c = C.tocoo()
        if c.shape[0] != c.shape[1]:
            raise ValueError(f"Coo: a square matrix is needed, not {c.shape}")
        return cls(c.row, c.col, c.data, c.shape[0])

    def __matmul__(self, x):
        return coo_mv(self.row, self.col, self.data, np.asarray(x, float), self.shape[0])

    @property
    def T(self):
        return Coo(self.col, self.row, self.data, self.shape[0])

    def __add__(self, other):
        other = Coo.of(other)
        if other.shape != self.shape:
            raise ValueError(f"Coo: shapes {self.shape} and {other.shape} differ")
        return Coo(np.concatenate([self.row, other.row]), np.concatenate([self.col, other.col]),
                   np.concatenate([self.data, other.data]), self.shape[0])

    def __rmul__(self, a):
        return Coo(self.row, self.col, float(a) * self.data, self.shape[0])

    def toarray(self):
        A = np.zeros(self.shape)
        A[self.row, self.col] = self.data
        return A


def reverse_cuthill_mckee(rows, cols, size):
    """Reverse Cuthill-McKee ordering of the symmetrised pattern (rows, cols) of a size x size matrix:
    breadth-first from a node of least degree in each connected part, neighbours by increasing
    degree, reversed.  numpy and one Python pass over the edges (a few ms per 1e4 unknowns), so that
    banded models need not import scipy.sparse."""
    r = np.concatenate([rows, cols])
    c = np.concatenate([cols, rows])
    key = distinct(r * size + c)
    r, c = key // size, key % size
    off = r != c
    r, c = r[off], c[off]
    ptr = np.searchsorted(r, np.arange(size + 1)).tolist()
    deg = np.diff(ptr)
    nbrs = c[np.lexsort((c, deg[c], r))].tolist()
    seen = bytearray(size)
    perm = []
    for s in np.argsort(deg, kind="stable").tolist():
        if seen[s]:
            continue
        seen[s] = 1
        perm.append(s)
        i = len(perm) - 1
        while i < len(perm):
            v = perm[i]
            i += 1
            for w in nbrs[ptr[v]:ptr[v + 1]]:
                if not seen[w]:
                    seen[w] = 1
                    perm.append(w)
    return np.array(perm[::-1], np.intp)


_FLAPACK = []


def _lapack(name):
    """A LAPACK routine (dgesv, dgbsv) from scipy's compiled LAPACK wrappers, loaded as that one
    extension module (a few ms) rather than through ``scipy.linalg``, whose import chain costs ten
    times a whole small solve; the regular import when scipy's layout differs.  (numpy's own
    ``linalg.solve`` needs no scipy but is twice as slow on these small systems.)"""
    if not _FLAPACK:
        try:
            import importlib.machinery
            import importlib.util
            import os
            spec = importlib.util.find_spec("scipy")
            d = os.path.join(os.path.dirname(spec.origin), "linalg")
            fname = next(f for f in os.listdir(d) if f.startswith("_flapack.")
                         and f.endswith(tuple(importlib.machinery.EXTENSION_SUFFIXES)))
            sp_ = importlib.util.spec_from_file_location("scipy.linalg._flapack", os.path.join(d, fname))
            mod = importlib.util.module_from_spec(sp_)
            sp_.loader.exec_module(mod)
            mod.dgesv, mod.dgbtrf, mod.dgbtrs   # noqa: B018 - all present, else the fallback
            _FLAPACK.append(mod)
            _OPENBLAS_SEEN[0] = -1   # (it brought scipy's OpenBLAS: one_blas_thread scans the libraries again)
        except Exception:  # noqa: BLE001 - any surprise: the documented import
            from scipy.linalg import lapack
            _FLAPACK.append(lapack)
            _OPENBLAS_SEEN[0] = -1
    return getattr(_FLAPACK[0], name)


_OPENBLAS: dict = {}   # {library path: (set_num_threads, get_num_threads) or None}
_OPENBLAS_SEEN = [-1, []]   # [len(sys.modules) at the last scan, its controls]


def _openblas_controls():
    """(set_num_threads, get_num_threads) of every OpenBLAS library loaded in the process (numpy's
    and scipy's wheels each bring one), from /proc/self/maps; empty where that fails (not Linux,
    another BLAS): then nothing is changed.  The maps are read again only when modules were imported
    since the last scan (a library comes with an extension module; reading them is ~1 ms)."""
    seen = len(sys.modules)
    if _OPENBLAS_SEEN[0] == seen:
        return _OPENBLAS_SEEN[1]
    try:
        import ctypes
        with open("/proc/self/maps") as f:   # (the path: the sixth field, which may hold spaces)
            paths = sorted({parts[5].strip() for parts in (ln.split(None, 5) for ln in f)
                            if len(parts) == 6 and "openblas" in parts[5].lower() and ".so" in parts[5]})
        for path in paths:
            if path in _OPENBLAS:
                continue
            _OPENBLAS[path] = None
            try:
                lib = ctypes.CDLL(path)
            except OSError:   # (a library replaced on disk since: its entry reads "(deleted)")
                continue
            for pre, suf in (("scipy_openblas", "64_"), ("scipy_openblas", ""), ("openblas", "64_"),
                             ("openblas", "")):
                set_ = getattr(lib, f"{pre}_set_num_threads{suf}", None)
                get = getattr(lib, f"{pre}_get_num_threads{suf}", None)
                if set_ is not None and get is not None:
                    set_.argtypes, set_.restype, get.argtypes, get.restype = [ctypes.c_int], None, [], ctypes.c_int
                    _OPENBLAS[path] = (set_, get)
                    break
        found = [_OPENBLAS[p] for p in paths if _OPENBLAS[p] is not None]
    except Exception:  # noqa: BLE001 - any surprise: the BLAS is left as it is
        found = []
    _OPENBLAS_SEEN[:] = [seen, found]
    return found


@contextlib.contextmanager
def one_blas_thread():
    """Run the block with OpenBLAS on one thread (restored after): the dense eigenproblems and
    products of a few hundred unknowns (natural modes) take 1-2 ms single-threaded, but a threaded
    BLAS whose threads wait for a busy core spends 10-100x that (a 32-element cantilever's modes:
    ~200 ms on a loaded 2-core machine, 3 ms on one thread).  The libraries loaded when the block
    starts are set (import scipy.linalg before it for scipy's)."""
    ctl = _openblas_controls()
    old = [get() for _, get in ctl]
    for set_, _ in ctl:
        set_(1)
    try:
        yield
    finally:
        for (set_, _), n in zip(ctl, old):
            set_(n)


def load_lapack(always=False):
    """Load the compiled LAPACK routines now (a few ms, the first time in a process) if the solves
    need them (not with the compiled kernel, whose LU is its own; ``always``: the eigenproblems and
    null spaces of :func:`eigh` and :func:`null_space` do): the FE modules call it when imported, so
    that a timed solve does not pay for it (``import_time_s``), and the natural modes before
    :func:`one_blas_thread`, so that the OpenBLAS library loaded with them is set too."""
    if always or not kernel_enabled():
        _lapack("dgesv")


class BandMatrix:
    """A banded Jacobian: ``ab`` (nrow, size) in LAPACK's band storage (Fortran order) on the
    renumbered unknowns of ``pattern``; its LU factors are computed by the first solve and kept for
    the next ones.  With the compiled kernel the factors overwrite ``ab`` (a Jacobian is assembled to
    be solved; a fine mesh's band is megabytes): add to it before the first solve, not after."""

    def __init__(self, pattern, ab):
        self.pattern, self.ab = pattern, ab
        self._lu = self._kern = None

    def solve(self, b):
        p = self.pattern
        rhs = np.array(b, float)[p.perm]
        if self._lu is None:
            self._kern = kernel_enabled()
        if self._kern:
            if self._lu is None:
                lu = self.ab.T                  # (size, nrow) C order: the column-major band, factored in place
                piv = np.empty(p.size, np.intp)
                info = _kernel.factor(lu, piv, p.size, p.kl, p.ku)
                if info != 0:
                    raise np.linalg.LinAlgError(f"singular matrix (zero pivot {info} of the band LU)")
                self._lu = (lu, piv)
            _kernel.solve(self._lu[0], self._lu[1], rhs, p.kl, p.ku)
            x = rhs
        else:
            if self._lu is None:
                lu, piv, info = _lapack("dgbtrf")(self.ab, p.kl, p.ku, overwrite_ab=0)
                if info != 0:
                    raise np.linalg.LinAlgError(f"singular matrix (LAPACK gbtrf info {info})")
                self._lu = (lu, piv)
            x, info = _lapack("dgbtrs")(self._lu[0], p.kl, p.ku, rhs, self._lu[1], overwrite_b=1)
            if info != 0:
                raise ValueError(f"LAPACK gbtrs info {info}")
        out = np.empty_like(x)
        out[p.perm] = x
        return out



def add_coo(A, *parts):
    """A + the COO entries ``parts`` = (rows, cols, vals), ... (which must lie in A's pattern), for A
    dense, banded (:class:`BandMatrix`) or sparse (one sparse sum for all parts)."""
    if isinstance(A, np.ndarray):
        for rows, cols, vals in parts:
            np.add.at(A, (rows, cols), vals)
        return A
    if isinstance(A, BandMatrix):
        p = A.pattern
        for rows, cols, vals in parts:
            pr, pc = p.inv[rows], p.inv[cols]
            np.add.at(A.ab, (p.kl + p.ku + pr - pc, pc), vals)
        return A
    import scipy.sparse as sp
    rows, cols, vals = (np.concatenate(x) for x in zip(*parts))
    return (A + sp.csc_matrix((vals, (rows, cols)), shape=A.shape)).tocsc()


def norms(v, k, idx=None):
    """(max |v[:k]|, max |v[k:]|, max |v[idx]|) as floats, 0.0 for an empty part and NaN when a part
    holds a NaN (Newton's residual and step norms: one kernel call, or numpy without the kernel)."""
    if _kernel is not None and v.dtype == np.float64 and v.flags.c_contiguous:
        return _kernel.norms(v, k, idx)
    a = np.abs(v)
    return (float(a[:k].max()) if k else 0.0, float(a[k:].max()) if a.size > k else 0.0,
            float(a[idx].max()) if idx is not None and len(idx) else 0.0)


def to_csc(A, rows, cols):
    """A Jacobian of :meth:`femslide.model.discrete.Model.system` (dense, banded or sparse) as a scipy CSC
    matrix; ``rows``, ``cols``: its pattern (a band's entries, each position once)."""
    import scipy.sparse as sp
    if isinstance(A, BandMatrix):
        flat, idx = distinct(A.pattern.flat, first=True)
        # (ab is the Fortran-ordered band, Banded: flat indexes its transpose)
        return sp.csc_matrix((A.ab.T.ravel()[flat], (rows[idx], cols[idx])), shape=(A.pattern.size,) * 2)
    return sp.csc_matrix(A)


def largest_abs(a) -> float:
    """max |a| over every entry of a non-empty array, as a float (NaN if one is NaN): one kernel pass
    (:func:`norms`) for a C-ordered float array, without numpy's ``max`` wrappers (a refinement level
    takes several).  Like :func:`norms`, it uses the kernel whenever it is built (FEMSLIDE_KERNEL does
    not switch it: the same float either way, tests/test_model_numerics.py)."""
    if _kernel is not None and a.dtype == np.float64 and a.flags.c_contiguous and a.size:
        return _kernel.norms(a.reshape(-1), a.size)[0]
    return float(np.abs(a).max())


def solve_linear(A, b):
    """Solve A x = b for the dense, banded or sparse Jacobian of :meth:`Model.system`.

    Dense and banded systems go to the kernel's LU (or LAPACK's dgesv and dgbtrf/dgbtrs, loaded by
    :func:`_lapack` without importing scipy.linalg), sparse ones to scipy's SuperLU.  A is not
    modified."""
    if isinstance(A, BandMatrix) or (not isinstance(A, np.ndarray) and hasattr(A, "solve")):
        return A.solve(b)   # (a band, or an operator that solves itself: femslide.analysis.radau)
    if isinstance(A, np.ndarray):
        if A.flags.c_contiguous and A.dtype == np.float64 and kernel_enabled():
            x = np.array(b, float)
            info = _kernel.solve_dense(A, x)
            if info != 0:
                raise np.linalg.LinAlgError(f"singular matrix (zero pivot {info} of the dense LU)")
            return x
        _, _, x, info = _lapack("dgesv")(A, b, overwrite_a=0, overwrite_b=0)
        if info != 0:
            raise np.linalg.LinAlgError(f"singular matrix (LAPACK gesv info {info})")
        return x
    import scipy.sparse.linalg as spla
    return spla.splu(A, permc_spec="COLAMD").solve(b)


def det_sign(A) -> float:
    """The sign of det A (dense, C order): 1.0, -1.0, 0.0 (a zero pivot) or NaN (a non-finite
    factor) - the stability test's (femslide.analysis.paths.check_stable).  The kernel's dense LU with
    partial pivoting (numpy's slogdet without the kernel): the product of the pivots' signs and of
    the row exchanges'."""
    if not (_kernel is not None and isinstance(A, np.ndarray) and A.dtype == np.float64 and kernel_enabled()):
        return float(np.linalg.slogdet(A)[0])
    n = A.shape[0]
    lu = np.array(A, float, order="C")
    piv = np.empty(n, np.intp)
    if _kernel.factor(lu, piv, n, -1, -1):
        return 0.0
    # (Python floats, without numpy's per-call cost: at most DENSE_CHECK pivots, negligible beside the LU)
    odd = 0
    for x in lu.ravel()[::n + 1].tolist():
        if not math.isfinite(x):
            return math.nan
        odd += x < 0.0
    odd += sum(p != i for i, p in enumerate(piv.tolist()))
    return -1.0 if odd % 2 else 1.0


def null_space(A):
    """An orthonormal basis (n, n - rank) of the null space of the dense (m, n) matrix A: the right
    singular vectors (LAPACK dgesdd) beyond the singular values above max(m, n) eps times the largest,
    as scipy.linalg.null_space computes it, without importing scipy.linalg (its import was a third of a
    short simulate's time)."""
    A = np.asarray(A, dtype=float)
    if A.size == 0:   # (no equations: the whole space; LAPACK refuses empty matrices)
        return np.eye(A.shape[1])
    if not np.all(np.isfinite(A)):
        raise ValueError("null_space: the matrix holds NaN or inf")
    u, s, vt, info = _lapack("dgesdd")(A, compute_uv=1, full_matrices=1)
    if info != 0:
        raise np.linalg.LinAlgError(f"SVD did not converge (LAPACK gesdd info {info})")
    tol = float(np.amax(s, initial=0.0)) * np.finfo(float).eps * max(A.shape)
    return vt[int(np.sum(s > tol)):, :].T.copy()


def eigh(A, B=None):
    """(w ascending, V) of the dense symmetric eigenproblem A v = w v, or A v = w B v with B positive
    definite (V^T B V = I), from the lower triangles: scipy.linalg.eigh's default drivers (LAPACK
    dsyevr, dsygvd) called as it calls them, without importing scipy.linalg.  LinAlgError where B is
    not positive definite or the algorithm fails."""
    A = np.asarray(A, dtype=float)
    n = A.shape[0]
    if n == 0:
        return np.zeros(0), np.zeros((0, 0))
    if not (np.all(np.isfinite(A)) and (B is None or np.all(np.isfinite(B)))):
        raise ValueError("eigh: the matrices hold NaN or inf")   # (as scipy's check_finite)
    if B is None:
        lw = _lapack("dsyevr_lwork")(n, lower=1)
        if lw[-1] != 0:
            raise np.linalg.LinAlgError(f"LAPACK dsyevr workspace query info {lw[-1]}")
        w, v, _, _, info = _lapack("dsyevr")(A, compute_v=1, lower=1, lwork=int(lw[0]), liwork=int(lw[1]))
    else:
        w, v, info = _lapack("dsygvd")(A, np.asarray(B, dtype=float), itype=1, jobz="V", uplo="L")
    if info > n:
        raise np.linalg.LinAlgError(f"the leading minor of order {info - n} of B is not positive definite")
    if info != 0:
        raise np.linalg.LinAlgError(f"the symmetric eigenproblem failed (LAPACK info {info})")
    return w, v


def lu_factor(A):
    """LU factors of a dense square matrix (LAPACK dgetrf, loaded as :func:`solve_linear` loads its
    routines); LinAlgError when A is singular.  A is not modified."""
    lu, piv, info = _lapack("dgetrf")(A, overwrite_a=0)
    if info != 0:
        raise np.linalg.LinAlgError(f"singular matrix (LAPACK getrf info {info})")
    return lu, piv


def lu_solve(factors, b):
    """x with A x = b from :func:`lu_factor`'s factors of A (LAPACK dgetrs)."""
    x, info = _lapack("dgetrs")(factors[0], factors[1], b)
    if info != 0:
        raise ValueError(f"LAPACK getrs info {info}")
    return x


def _pow2(x):
    """2^-e with x = m 2^e, 0.5 <= m < 1 (1 where x is 0): a scale without round-off."""
    _, e = np.frexp(x)
    return np.where(x > 0.0, np.ldexp(1.0, -e), 1.0)


def _equilibrate(M, kl=None, ku=None, kern=None):
    """Scale M in place to rows and columns of largest magnitude about 1 (powers of 2: no round-off);
    returns (row scales, column scales): the solution of A x = b is cs * the solution of the scaled
    system with rs * b.  M is A itself (dense, kl None) or its band in the kernel's layout, (n, 2 kl
    + ku + 1) with M[j, kl + ku + i - j] = A[i, j] (places outside A hold zeros).  A time step's
    matrix holds M / h^2 beside the constraints' O(1) rows (at a located step of 1e-9 s: 1e16 against
    1; its LU without scaling gave solutions 4e-6 apart between two correct LU codes; scaled: 58 for
    the condition number).  With the compiled kernel, one call does the same (the same scales and
    scaled M: its Python loop over the band's diagonals was a fifth of a time step); ``kern``: the
    caller's :func:`kernel_enabled` (None: asked here)."""
    if kern is None:
        kern = kernel_enabled()
    if kern and M.dtype == np.float64 and M.flags.c_contiguous and hasattr(_kernel, "equilibrate"):
        rs, cs = np.empty(M.shape[0]), np.empty(M.shape[0])
        _kernel.equilibrate(M, -1 if kl is None else kl, 0 if ku is None else ku, rs, cs)
        return rs, cs
    if kl is None:
        rs = _pow2(np.abs(M).max(axis=1))
        M *= rs[:, None]
        cs = _pow2(np.abs(M).max(axis=0))
        M *= cs[None, :]
        return rs, cs
    n, nrow = M.shape
    a = np.abs(M)
    rmax = np.zeros(n)
    spans = []
    for c in range(nrow):
        off = c - kl - ku                      # the row of M[j, c] is j + off
        j0, j1 = max(0, -off), min(n, n - off)
        if j1 > j0:
            spans.append((c, j0, j1, off))
            np.maximum(rmax[j0 + off:j1 + off], a[j0:j1, c], out=rmax[j0 + off:j1 + off])
    rs = _pow2(rmax)
    for c, j0, j1, off in spans:
        M[j0:j1, c] *= rs[j0 + off:j1 + off]
    cs = _pow2(np.abs(M).max(axis=1))
    M *= cs[:, None]
    return rs, cs


class Factorized:
    """An LU factorisation of a dense, banded or sparse Jacobian of :meth:`Model.system` (real or
    complex) kept for several solves: ``solve(b)``.  LinAlgError when the matrix is singular.
    ``overwrite``: A's storage may be scaled and factorised in place (A is not used afterwards)."""

    def __init__(self, A, overwrite=False):
        self.band = self.dense = self.sparse = self.kern = None
        self.rs = self.cs = None
        kern = kernel_enabled()
        if isinstance(A, BandMatrix):
            p = A.pattern
            self.pattern, kl, ku = p, p.kl, p.ku
            ab = A.ab if overwrite and A.ab.flags.f_contiguous else np.array(A.ab, order="F")
            lu = ab.T                               # (its columns: C order, the kernel's layout)
            self.rs, self.cs = _equilibrate(lu, kl, ku, kern)
        elif isinstance(A, np.ndarray):
            lu, kl, ku = (A if overwrite and A.flags.c_contiguous else np.array(A, order="C")), -1, 0
            self.rs, self.cs = _equilibrate(lu, None, None, kern)
        if self.rs is not None and kern and lu.dtype.kind != "c":
            # the kernel's LU (single-threaded C: a threaded BLAS on a small matrix of a busy machine
            # spends 10-100x its time waiting for its threads)
            lu = np.ascontiguousarray(lu, dtype=float)
            piv = np.empty(lu.shape[0], np.intp)
            info = _kernel.factor(lu, piv, lu.shape[0], kl, ku)
            if info != 0:
                raise np.linalg.LinAlgError(f"singular matrix (zero pivot {info} of the LU)")
            self.kern = (lu, piv, kl, ku)
        elif isinstance(A, BandMatrix):
            pre = "z" if np.iscomplexobj(ab) else "d"
            lu, piv, info = _lapack(pre + "gbtrf")(ab, kl, ku, overwrite_ab=1)
            if info != 0:
                raise np.linalg.LinAlgError(f"singular matrix (LAPACK gbtrf info {info})")
            self.band, self.piv, self._trs = lu, piv, _lapack(pre + "gbtrs")
        elif isinstance(A, np.ndarray):
            pre = "z" if np.iscomplexobj(lu) else "d"
            lu, piv, info = _lapack(pre + "getrf")(lu, overwrite_a=1)
            if info != 0:
                raise np.linalg.LinAlgError(f"singular matrix (LAPACK getrf info {info})")
            self.dense, self.piv, self._trs = lu, piv, _lapack(pre + "getrs")
        else:
            import scipy.sparse.linalg as spla
            try:
                self.sparse = spla.splu(A.tocsc(), permc_spec="COLAMD")
            except RuntimeError as exc:   # SuperLU: "Factor is exactly singular"
                raise np.linalg.LinAlgError(f"singular matrix ({exc})") from None

    def solve(self, b):
        if self.kern is not None:
            lu, piv, kl, ku = self.kern
            if kl < 0:
                x = self.rs * np.asarray(b, dtype=float)
                _kernel.solve(lu, piv, x, kl, ku)
                return self.cs * x
            p = self.pattern
            x = self.rs * np.asarray(b, dtype=float)[p.perm]
            _kernel.solve(lu, piv, x, kl, ku)
            out = np.empty_like(x)
            out[p.perm] = self.cs * x
            return out
        if self.sparse is not None:
            return self.sparse.solve(b)
        if self.dense is not None:
            x, info = self._trs(self.dense, self.piv, self.rs * b)
            x = self.cs * x
        else:
            p = self.pattern
            x, info = self._trs(self.band, p.kl, p.ku, self.rs * b[p.perm], self.piv)
            out = np.empty_like(x)
            out[p.perm] = self.cs * x
            x = out
        if info != 0:
            raise np.linalg.LinAlgError(f"LAPACK trs info {info}")
        return x


class Assembler:
    """A static sparsity pattern (rows, cols; duplicates summed) of a size x size matrix, stored as the
    model's Jacobians are: dense for small systems, as a band after reverse Cuthill-McKee renumbering
    when the band is narrow (its width kl + ku below ``band_share`` of the size), else dense up to
    ``sparse_limit`` unknowns and sparse above;
    ``assemble(values)`` gives the matrix (values in the pattern's order), which
    :class:`Factorized` factorises."""

    def __init__(self, rows, cols, size, dense_limit=100, sparse_limit=600, band_share=0.25):
        self.rows, self.cols, self.size = rows, cols, size
        self.band, self.sparse = None, False
        if size > dense_limit:
            self.band = Banded(rows, cols, size)
            if self.band.kl + self.band.ku >= int(size * band_share):
                self.band, self.sparse = None, size > sparse_limit
        self.flat = rows * size + cols if self.band is None and not self.sparse else None

    def target(self):
        """(storage, flat map, matrix) for a caller that writes the values itself (a kernel adding each
        value at storage.flat[flat[p]], as :meth:`assemble` sums them): the dense array, or the band's
        (size, nrow) C-order array and its :class:`BandMatrix`; None for a sparse pattern."""
        if self.sparse:
            return None
        if self.band is not None:
            ab, raw = self.band.empty()
            return raw, self.band.flat, BandMatrix(self.band, ab)
        A = np.empty((self.size, self.size))
        return A, self.flat, A

    def assemble(self, vals):
        if self.band is not None:
            return self.band.assemble(vals)
        if self.sparse:
            import scipy.sparse as sp
            return sp.csc_matrix((vals, (self.rows, self.cols)), shape=(self.size, self.size))
        n = self.size
        return np.bincount(self.flat, weights=vals, minlength=n * n).reshape(n, n)

