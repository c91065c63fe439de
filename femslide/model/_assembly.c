/* The compiled assembly of femslide's models: residual and Jacobian of Model.system in one call.
 *
 * The same arithmetic as the numpy path of femslide.model.discrete.Model.system (which stays the
 * test oracle: tests/test_kernel.py compares the two to round-off): the corotational beam elements
 * (femslide.elements.corotational.element_terms), the built-in joint kinds pin, weld, slider and
 * roller (femslide.joints.kind: coincide, on_guide, same_rotation), the springs of joints
 * (femslide.joints.base.RotationalSpring, SlideSpring), forces at body points
 * (femslide.elements.loads.PointForce), the linear dead loads and a controlled dof (displacement
 * control).  Constraints and terms of other kinds (a kind registered in Python, the holds) are
 * evaluated in Python and handed over as (index, value) pairs.
 *
 * An Assembler is built once per model topology with the static data (index maps, element
 * constants, joint geometry) as contiguous arrays; each call takes the state and writes the residual
 * and the Jacobian in place: into a dense or LAPACK-band array through a map from the Jacobian's
 * pattern positions to storage positions, or as the pattern's values (for a sparse matrix).
 * Model units throughout (femslide.model.discrete).  Only the buffer protocol is used (no numpy C
 * API), so the build needs the Python headers and a C compiler only.  The bitwise agreement with the
 * numpy path needs each multiply and add rounded apart: setup.py builds with -ffp-contract=off (gcc
 * and clang fuse them into FMAs by default where the target has them: aarch64, Apple silicon).
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <float.h>
#include <math.h>
#include <string.h>
#ifdef __SSE2__
#include <emmintrin.h>
#endif

#if defined(_MSC_VER) && !defined(__cplusplus)
#define restrict __restrict   /* MSVC's C (without /std:c11) has no restrict keyword */
#endif

#define EPS 2.220446049250313e-16

/* -- buffers --------------------------------------------------------------------------------------- */

typedef struct {
    Py_buffer view;
    int held;
} Buf;

static int get_buf(PyObject *obj, Buf *b, int writable, const char *fmt, Py_ssize_t itemsize, const char *what)
{
    b->held = 0;
    if (obj == NULL || obj == Py_None)
        return 0;
    int flags = PyBUF_C_CONTIGUOUS | PyBUF_FORMAT | (writable ? PyBUF_WRITABLE : 0);
    if (PyObject_GetBuffer(obj, &b->view, flags) < 0)
        return -1;
    b->held = 1;
    if (b->view.itemsize != itemsize || b->view.format == NULL ||
        strchr(fmt, b->view.format[b->view.format[0] == '<' || b->view.format[0] == '=' ? 1 : 0]) == NULL) {
        PyErr_Format(PyExc_TypeError, "femslide kernel: %s has item format %s, expected one of %s", what,
                     b->view.format ? b->view.format : "?", fmt);
        PyBuffer_Release(&b->view);
        b->held = 0;
        return -1;
    }
    return 0;
}

static void release(Buf *b)
{
    if (b->held) {
        PyBuffer_Release(&b->view);
        b->held = 0;
    }
}

/* the array arguments o[0 .. n) of a kernel call as buffers b[0 .. n): kind[i] is 'd' a float64 array read,
 * 'w' a float64 array written, 'i' 8-byte indices, 'p' pivots (Py_ssize_t, np.intp), '-' no array (a scalar's
 * slot; o[i] is not read); what[i] names it in errors.  Every b[i] is set first, so that release_all(b, n)
 * is right after a failure too; None (or a NULL o[i]) gives an empty buffer, as get_buf does. */
static int get_all(PyObject *const *o, Buf *b, int n, const char *kind, const char *const *what)
{
    for (int i = 0; i < n; i++)
        b[i].held = 0;
    for (int i = 0; i < n; i++) {
        char k = kind[i];
        if (k == '-')
            continue;
        Py_ssize_t size = k == 'p' ? (Py_ssize_t)sizeof(Py_ssize_t) : 8;
        if (get_buf(o[i], &b[i], k == 'w', k == 'i' || k == 'p' ? "qlLn" : "d", size, what[i]) < 0)
            return -1;
    }
    return 0;
}

static void release_all(Buf *b, int n)
{
    for (int i = 0; i < n; i++)
        release(&b[i]);
}

#define DBL(b) ((double *)(b).view.buf)
#define IDX(b) ((long long *)(b).view.buf)
#define LEN(b) ((b).held ? (b).view.len / (b).view.itemsize : 0)

/* -- the Assembler type ------------------------------------------------------------------------------- */

enum { N_STATIC = 10 };

typedef struct {
    PyObject_HEAD
    Buf st[N_STATIC];
    Py_ssize_t n_q, ne, nl, nt, nlin, nload;
    double xmax;
    int thermal;   /* some element has free basic forces */
} Assembler;

/* static buffers, in the order of the constructor's arguments */
enum {
    S_EDOF,   /* int64 (ne, 6): dofs u1, v1, theta1, u2, v2, theta2 of every element */
    S_EDAT,   /* float64 (ne, 12): D0x, D0y, L0, beta0, k00, k11, k12, k21, k22, and the free (thermal) basic
                 forces at full load N_T, M1_T, M2_T (corotational.free_forces; zero without thermal loads) */
    S_LINT,   /* int64 (nl, 8): kind, dof of a (or -1), dof of b (or -1), lever a, lever b, first equation
                 row, first pattern position, linear */
    S_LDBL,   /* float64 (nl, 12): Xa, ra, Xb, rb, e0, n0 */
    S_TINT,   /* int64 (nt, 4): type (0 point force, 1 rotational spring, 2 slide spring), link row (springs)
                 or first dof (point force), first pattern position, 0 */
    S_TDBL,   /* float64 (nt, 5): point force rx, ry, Fx, Fy, M; rotational spring c; slide spring k, F0, s0 */
    S_LIND,   /* int64 (nlin,): dofs of the linear dead loads */
    S_LVAL,   /* float64 (nlin,): their values (model units) */
    S_LOADS,  /* int64 (nload,): the dofs of d r / d lam (the control column's rows) */
    S_SPARE
};

static void Assembler_dealloc(Assembler *self)
{
    for (int i = 0; i < N_STATIC; i++)
        release(&self->st[i]);
    Py_TYPE(self)->tp_free((PyObject *)self);
}

static int Assembler_init(Assembler *self, PyObject *args, PyObject *kwds)
{
    PyObject *o[9];
    Py_ssize_t n_q;
    double xmax;
    if (!PyArg_ParseTuple(args, "ndOOOOOOOOO", &n_q, &xmax, &o[0], &o[1], &o[2], &o[3], &o[4], &o[5], &o[6], &o[7],
                          &o[8]))
        return -1;
    static const char *names[9] = {"element dofs", "element data", "link integers", "link reals", "term integers",
                                   "term reals", "load dofs", "load values", "lam dofs"};
    static const int isint[9] = {1, 0, 1, 0, 1, 0, 1, 0, 1};
    for (int i = 0; i < N_STATIC; i++)
        release(&self->st[i]);
    for (int i = 0; i < 9; i++) {
        if (get_buf(o[i], &self->st[i], 0, isint[i] ? "qlL" : "d", 8, names[i]) < 0)
            return -1;
        if (!self->st[i].held) {
            PyErr_Format(PyExc_TypeError, "femslide kernel: %s missing", names[i]);
            return -1;
        }
    }
    self->n_q = n_q;
    self->xmax = xmax;
    self->ne = LEN(self->st[S_EDOF]) / 6;
    self->nl = LEN(self->st[S_LINT]) / 8;
    self->nt = LEN(self->st[S_TINT]) / 4;
    self->nlin = LEN(self->st[S_LIND]);
    self->nload = LEN(self->st[S_LOADS]);
    if (LEN(self->st[S_EDAT]) != 12 * self->ne || LEN(self->st[S_LDBL]) != 12 * self->nl ||
        LEN(self->st[S_TDBL]) != 5 * self->nt || LEN(self->st[S_LVAL]) != self->nlin) {
        PyErr_SetString(PyExc_ValueError, "femslide kernel: inconsistent static array sizes");
        return -1;
    }
    {   /* the element dofs index every state y (of n_q frame dofs and more): checked once here */
        const long long *ed = IDX(self->st[S_EDOF]);
        for (Py_ssize_t i = 0; i < 6 * self->ne; i++)
            if (ed[i] < 0 || ed[i] >= n_q) {
                PyErr_SetString(PyExc_IndexError, "femslide kernel: element dof out of range");
                return -1;
            }
    }
    self->thermal = 0;
    {
        const double *ed = DBL(self->st[S_EDAT]);
        for (Py_ssize_t e = 0; e < self->ne && !self->thermal; e++)
            self->thermal = ed[12 * e + 9] != 0.0 || ed[12 * e + 10] != 0.0 || ed[12 * e + 11] != 0.0;
    }
    return 0;
}

/* -- output: the Jacobian's pattern position p gets value v ----------------------------------------------- */

typedef struct {
    double *A;           /* dense or band storage (with flat), or NULL */
    const long long *flat;
    double *vals;        /* pattern values (sparse), or NULL */
} Out;

static inline void emit(const Out *o, Py_ssize_t p, double v)
{
    if (o->A)
        o->A[o->flat[p]] += v;
    else
        o->vals[p] = v;
}

/* -- joints (femslide.joints.base.Link, femslide.joints.kind) ---------------------------------------------- */

typedef struct {
    int k, ia, ib, lev_a, lev_b;
    int da, db;          /* global first dofs, -1 for the ground */
    const double *g;     /* Xa, ra, Xb, rb, e0, n0 */
} LinkGeo;

typedef struct {
    double wx, wy, tha, thb;
    int ndw, nd2;
    int dwi[6];
    double dwx[6], dwy[6];
    int d2i[2];
    double d2x[2], d2y[2];
} W;

static void link_geo(const long long *li, const double *ld, LinkGeo *L)
{
    L->da = (int)li[1];
    L->db = (int)li[2];
    L->lev_a = (int)li[3];
    L->lev_b = (int)li[4];
    L->ia = L->da >= 0 ? 0 : -1;
    L->ib = L->db >= 0 ? (L->da >= 0 ? 3 : 0) : -1;
    L->k = (L->da >= 0 ? 3 : 0) + (L->db >= 0 ? 3 : 0);
    L->g = ld;
}

/* (px, py, Rx, Ry, theta) of a carrier's joint point (femslide.joints.base._point) */
static void point(const double *z, int i, int lever, const double *X, const double *r, double *out)
{
    if (i < 0) {
        out[0] = X[0] + r[0];
        out[1] = X[1] + r[1];
        out[2] = out[3] = out[4] = 0.0;
        return;
    }
    double t = z[i + 2];
    if (!lever) {
        out[0] = X[0] + z[i];
        out[1] = X[1] + z[i + 1];
        out[2] = out[3] = 0.0;
        out[4] = t;
        return;
    }
    double co = cos(t), si = sin(t);
    double Rx = co * r[0] - si * r[1], Ry = si * r[0] + co * r[1];
    out[0] = X[0] + z[i] + Rx;
    out[1] = X[1] + z[i + 1] + Ry;
    out[2] = Rx;
    out[3] = Ry;
    out[4] = t;
}

/* w = p_a - p_b with its first and second derivatives over the joint's dofs (Link.w) */
static void link_w(const LinkGeo *L, const double *z, W *w)
{
    double a[5], b[5];
    const double *g = L->g;
    point(z, L->ia, L->lev_a, g + 0, g + 2, a);
    point(z, L->ib, L->lev_b, g + 4, g + 6, b);
    w->ndw = w->nd2 = 0;
    if (L->ia >= 0) {
        int i = L->ia;
        w->dwi[w->ndw] = i; w->dwx[w->ndw] = 1.0; w->dwy[w->ndw] = 0.0; w->ndw++;
        w->dwi[w->ndw] = i + 1; w->dwx[w->ndw] = 0.0; w->dwy[w->ndw] = 1.0; w->ndw++;
        if (L->lev_a) {
            w->dwi[w->ndw] = i + 2; w->dwx[w->ndw] = -a[3]; w->dwy[w->ndw] = a[2]; w->ndw++;
            w->d2i[w->nd2] = i + 2; w->d2x[w->nd2] = -a[2]; w->d2y[w->nd2] = -a[3]; w->nd2++;
        }
    }
    if (L->ib >= 0) {
        int i = L->ib;
        w->dwi[w->ndw] = i; w->dwx[w->ndw] = -1.0; w->dwy[w->ndw] = 0.0; w->ndw++;
        w->dwi[w->ndw] = i + 1; w->dwx[w->ndw] = 0.0; w->dwy[w->ndw] = -1.0; w->ndw++;
        if (L->lev_b) {
            w->dwi[w->ndw] = i + 2; w->dwx[w->ndw] = b[3]; w->dwy[w->ndw] = -b[2]; w->ndw++;
            w->d2i[w->nd2] = i + 2; w->d2x[w->nd2] = b[2]; w->d2y[w->nd2] = b[3]; w->nd2++;
        }
    }
    w->wx = a[0] - b[0];
    w->wy = a[1] - b[1];
    w->tha = a[4];
    w->thb = b[4];
}

/* the guide e and its normal n carried by b at b's rotation (Link.guide; the ground: e0, n0 exactly) */
static void guide(const LinkGeo *L, double thb, double *e, double *n)
{
    const double *e0 = L->g + 8, *n0 = L->g + 10;
    double co = cos(thb), si = sin(thb);
    e[0] = co * e0[0] - si * e0[1];
    e[1] = si * e0[0] + co * e0[1];
    n[0] = co * n0[0] - si * n0[1];
    n[1] = si * n0[0] + co * n0[1];
}

/* g (m), G (m x k, row-major, zeroed here) and the weighted Hessian sum_i mu_i H_i (k x k, added) of a
 * built-in kind: 0 pin (coincide), 1 weld (coincide, same rotation), 2 slider (on guide, same
 * rotation), 3 roller (on guide) */
static int link_equations(const LinkGeo *L, int kind, const double *z, const double *mu, double *g, double *G,
                          double *Hmu)
{
    W w;
    int k = L->k, m = 0;
    link_w(L, z, &w);
    memset(G, 0, sizeof(double) * 3 * 6);
    if (kind == 0 || kind == 1) {          /* coincide: w = 0 */
        double *gx = G, *gy = G + k;
        for (int q = 0; q < w.ndw; q++) {
            gx[w.dwi[q]] += w.dwx[q];
            gy[w.dwi[q]] += w.dwy[q];
        }
        g[0] = w.wx;
        g[1] = w.wy;
        if (Hmu)
            for (int q = 0; q < w.nd2; q++) {
                int i = w.d2i[q];
                Hmu[i * k + i] += mu[0] * w.d2x[q];
                Hmu[i * k + i] += mu[1] * w.d2y[q];
            }
        m = 2;
    } else {                               /* on guide: w . n = 0 */
        double e[2], n[2];
        double *row = G;
        guide(L, w.thb, e, n);
        for (int q = 0; q < w.ndw; q++)
            row[w.dwi[q]] += w.dwx[q] * n[0] + w.dwy[q] * n[1];
        if (Hmu)
            for (int q = 0; q < w.nd2; q++) {
                int i = w.d2i[q];
                Hmu[i * k + i] += mu[0] * (w.d2x[q] * n[0] + w.d2y[q] * n[1]);
            }
        if (L->ib >= 0) {
            int j = L->ib + 2;
            row[j] -= w.wx * e[0] + w.wy * e[1];
            if (Hmu) {
                for (int q = 0; q < w.ndw; q++) {
                    int i = w.dwi[q];
                    double v = -(w.dwx[q] * e[0] + w.dwy[q] * e[1]);
                    Hmu[i * k + j] += mu[0] * v;
                    Hmu[j * k + i] += mu[0] * v;
                }
                Hmu[j * k + j] += mu[0] * -(w.wx * n[0] + w.wy * n[1]);
            }
        }
        g[0] = w.wx * n[0] + w.wy * n[1];
        m = 1;
    }
    if (kind == 1 || kind == 2) {          /* same rotation: theta_a - theta_b = 0 */
        double *row = G + m * k;
        if (L->ia >= 0)
            row[L->ia + 2] = 1.0;
        if (L->ib >= 0)
            row[L->ib + 2] = -1.0;
        g[m] = w.tha - w.thb;
        m++;
    }
    return m;
}

/* the slide s = w . e, its gradient ds (k) and Hessian H (k x k, zeroed here) (Link._slide) */
static double link_slide(const LinkGeo *L, const double *z, double *ds, double *H)
{
    W w;
    double e[2], n[2];
    int k = L->k;
    link_w(L, z, &w);
    guide(L, w.thb, e, n);
    memset(ds, 0, sizeof(double) * 6);
    memset(H, 0, sizeof(double) * 36);
    for (int q = 0; q < w.ndw; q++)
        ds[w.dwi[q]] += w.dwx[q] * e[0] + w.dwy[q] * e[1];
    for (int q = 0; q < w.nd2; q++) {
        int i = w.d2i[q];
        H[i * k + i] += w.d2x[q] * e[0] + w.d2y[q] * e[1];
    }
    if (L->ib >= 0) {
        int j = L->ib + 2;
        ds[j] += w.wx * n[0] + w.wy * n[1];
        for (int q = 0; q < w.ndw; q++) {
            int i = w.dwi[q];
            double v = w.dwx[q] * n[0] + w.dwy[q] * n[1];
            H[i * k + j] += v;
            H[j * k + i] += v;
        }
        H[j * k + j] -= w.wx * e[0] + w.wy * e[1];
    }
    return w.wx * e[0] + w.wy * e[1];
}

static void gather(const LinkGeo *L, const double *x, double *z)
{
    if (L->da >= 0) {
        z[0] = x[L->da];
        z[1] = x[L->da + 1];
        z[2] = x[L->da + 2];
    }
    if (L->db >= 0) {
        int o = L->ia >= 0 ? 3 : 0;
        z[o] = x[L->db];
        z[o + 1] = x[L->db + 1];
        z[o + 2] = x[L->db + 2];
    }
}

static inline int gdof(const LinkGeo *L, int j)
{
    if (L->da >= 0)
        return j < 3 ? L->da + j : L->db + j - 3;
    return L->db + j;
}

/* -- the assembly ------------------------------------------------------------------------------------------ */

/* -- an element's corotational kinematics (corotational._kinematics): displacement differences (dx, dy),
 * deformed chord (Dx, Dy) and its length Ln, stretch ub, chord rotation al (continued from aref), end
 * rotations relative to the chord th1, th2; c the element's data row, d its dofs ------------------------ */

typedef struct {
    double dx, dy, Dx, Dy, Ln, ub, al, th1, th2;
} Kin;

static inline void kinematics(const double *y, const long long *d, const double *c, double aref, Kin *k)
{
    double D0x = c[0], D0y = c[1], L0 = c[2], beta0 = c[3];
    double u1 = y[d[0]], v1 = y[d[1]], t1 = y[d[2]], u2 = y[d[3]], v2 = y[d[4]], t2 = y[d[5]];
    double dx = u2 - u1, dy = v2 - v1;
    double Dx = D0x + dx, Dy = D0y + dy;
    double Ln = hypot(Dx, Dy);
    k->ub = ((D0x + Dx) * dx + (D0y + Dy) * dy) / (Ln + L0);
    double bref = beta0 + aref;
    double cb = cos(bref), sb = sin(bref);
    double al = aref + atan2(cb * Dy - sb * Dx, cb * Dx + sb * Dy);
    k->dx = dx, k->dy = dy, k->Dx = Dx, k->Dy = Dy, k->Ln = Ln, k->al = al;
    k->th1 = t1 - al, k->th2 = t2 - al;
}

static PyObject *Assembler_assemble(Assembler *self, PyObject *args)
{
    PyObject *oy, *oaref, *oaout, *or_, *oA, *oflat, *ovals, *ofl, *oxr, *oxrv, *oxj, *oxjv, *oxf, *oxfv;
    PyObject *ong = Py_None;
    double lam, target;
    Py_ssize_t ctrl;
    int with_elements = 1;
    /* ong: None, or the axial forces (ne) that the tangent's geometric part carries instead of the
     * elements' own (corotational.element_terms' n_geometric) */
    if (!PyArg_ParseTuple(args, "OOOdndOOOOOOOOOOO|pO", &oy, &oaref, &oaout, &lam, &ctrl, &target, &or_, &oA,
                          &oflat, &ovals, &ofl, &oxr, &oxrv, &oxj, &oxjv, &oxf, &oxfv, &with_elements, &ong))
        return NULL;
    Buf by, bar, bao, br, bA, bflat, bvals, bfl, bxr, bxrv, bxj, bxjv, bxf, bxfv, bng;
    Buf *all[] = {&by, &bar, &bao, &br, &bA, &bflat, &bvals, &bfl, &bxr, &bxrv, &bxj, &bxjv, &bxf, &bxfv, &bng};
    for (size_t i = 0; i < sizeof(all) / sizeof(all[0]); i++)
        all[i]->held = 0;
    PyObject *result = NULL;
    if (get_buf(oy, &by, 0, "d", 8, "y") < 0 || get_buf(oaref, &bar, 0, "d", 8, "alpha_ref") < 0 ||
        get_buf(oaout, &bao, 1, "d", 8, "alpha") < 0 || get_buf(or_, &br, 1, "d", 8, "r") < 0 ||
        get_buf(oA, &bA, 1, "d", 8, "A") < 0 || get_buf(oflat, &bflat, 0, "qlL", 8, "flat") < 0 ||
        get_buf(ovals, &bvals, 1, "d", 8, "vals") < 0 || get_buf(ofl, &bfl, 1, "d", 8, "fl") < 0 ||
        get_buf(oxr, &bxr, 0, "qlL", 8, "extra r index") < 0 || get_buf(oxrv, &bxrv, 0, "d", 8, "extra r") < 0 ||
        get_buf(oxj, &bxj, 0, "qlL", 8, "extra J position") < 0 || get_buf(oxjv, &bxjv, 0, "d", 8, "extra J") < 0 ||
        get_buf(oxf, &bxf, 0, "qlL", 8, "extra fl index") < 0 || get_buf(oxfv, &bxfv, 0, "d", 8, "extra fl") < 0 ||
        get_buf(ong, &bng, 0, "d", 8, "n_geometric") < 0)
        goto done;
    {
        const Py_ssize_t n_q = self->n_q, ne = with_elements ? self->ne : 0;
        if (bng.held && LEN(bng) != self->ne) {
            PyErr_SetString(PyExc_ValueError, "femslide kernel: n_geometric of the wrong size");
            goto done;
        }
        const double *ng = bng.held ? DBL(bng) : NULL;
        const double *y = DBL(by);
        double *r = DBL(br);
        Py_ssize_t nr = LEN(br);
        int jac = bA.held || bvals.held;
        if (jac && bA.held && !bflat.held) {
            PyErr_SetString(PyExc_ValueError, "femslide kernel: A without its flat map");
            goto done;
        }
        if (LEN(by) < n_q || (ne && (LEN(bar) != ne || LEN(bao) != ne)) || (bfl.held && LEN(bfl) != n_q)) {
            PyErr_SetString(PyExc_ValueError, "femslide kernel: state arrays of the wrong size");
            goto done;
        }
        Out out = {bA.held ? DBL(bA) : NULL, bflat.held ? IDX(bflat) : NULL, bvals.held ? DBL(bvals) : NULL};
        if (bA.held)
            memset(out.A, 0, bA.view.len);
        memset(r, 0, br.view.len);
        double *fl = bfl.held ? DBL(bfl) : NULL;
        if (fl)
            memset(fl, 0, bfl.view.len);
        const double *aref = bar.held ? DBL(bar) : NULL;
        double *alpha = bao.held ? DBL(bao) : NULL;
        const long long *edof = IDX(self->st[S_EDOF]);
        const double *edat = DBL(self->st[S_EDAT]);
        double fmax = 0.0, noise = 0.0, umag = 0.0;
        double *Fs = (double *)PyMem_Malloc(sizeof(double) * (6 * ne + 1));
        if (Fs == NULL) {
            PyErr_NoMemory();
            goto done;
        }
        /* a thermal load: its share -B^T S_T of d r / d lam, element by element (added after the loads', in
         * the order of the numpy path) */
        int therm = self->thermal && fl != NULL && ne > 0;
        double *FT = therm ? (double *)PyMem_Malloc(sizeof(double) * 6 * ne) : NULL;
        if (therm && FT == NULL) {
            PyMem_Free(Fs);
            PyErr_NoMemory();
            goto done;
        }
        /* elements (corotational.element_terms); the round-off estimate needs the largest translation of
         * the elements' nodes first */
        if (jac)
            for (Py_ssize_t e = 0; e < ne; e++) {
                const long long *d = edof + 6 * e;
                double a0 = fabs(y[d[0]]), a1 = fabs(y[d[1]]), a3 = fabs(y[d[3]]), a4 = fabs(y[d[4]]);
                if (a0 > umag) umag = a0;
                if (a1 > umag) umag = a1;
                if (a3 > umag) umag = a3;
                if (a4 > umag) umag = a4;
            }
        for (Py_ssize_t e = 0; e < ne; e++) {
            const long long *d = edof + 6 * e;
            const double *c = edat + 12 * e;
            double L0 = c[2];
            double k00 = c[4], k11 = c[5], k12 = c[6], k21 = c[7], k22 = c[8];
            Kin k;
            kinematics(y, d, c, aref[e], &k);
            double dx = k.dx, dy = k.dy, Dx = k.Dx, Dy = k.Dy, Ln = k.Ln, ub = k.ub, al = k.al;
            double th1 = k.th1, th2 = k.th2;
            alpha[e] = al;
            double N = k00 * ub;
            double M1 = k11 * th1 + k12 * th2, M2 = k21 * th1 + k22 * th2;
            if (self->thermal) {
                N -= lam * c[9];
                M1 -= lam * c[10];
                M2 -= lam * c[11];
            }
            double inv = 1.0 / Ln;
            double pc = Dx * inv, ps = Dy * inv;
            if (therm) {   /* corotational.free_nodal: B^T S_T */
                double mT = (c[10] + c[11]) * inv;
                double T3 = c[9] * pc + mT * ps, T4 = c[9] * ps - mT * pc;
                FT[e] = -T3;
                FT[ne + e] = -T4;
                FT[2 * ne + e] = c[10];
                FT[3 * ne + e] = T3;
                FT[4 * ne + e] = T4;
                FT[5 * ne + e] = c[11];
            }
            double m = (M1 + M2) * inv;
            double F3 = N * pc + m * ps, F4 = N * ps - m * pc;
            double F[6] = {-F3, -F4, M1, F3, F4, M2};
            for (int a = 0; a < 6; a++) {
                Fs[a * ne + e] = F[a];
                double af = fabs(F[a]);
                if (af > fmax) fmax = af;
            }
            if (!jac)
                continue;
            {   /* round-off level of the basic forces (corotational._noise) */
                double adx = fabs(dx), ady = fabs(dy);
                double dmag = adx > ady ? adx : ady;
                double iL0 = 1.0 / L0;
                double ang = fabs(th1) + fabs(th2) + fabs(al) + (2.0 * (self->xmax + umag)) * iL0;
                double nz = (EPS * (2.0 * k00)) * (umag + dmag) * (1.0 + dmag * iL0) +
                            (EPS * (k11 + fabs(k12))) * ang * (1.0 + 2.0 * inv);
                if (nz > noise) noise = nz;
            }
            double kappa = k11 + k12 + k21 + k22;
            double a_ww = (kappa + (ng ? ng[e] : N) * Ln) * inv * inv;
            double b_pw = m * inv;
            double cc = pc * pc, ss = ps * ps, cs = pc * ps;
            double b2 = 2.0 * b_pw * cs;
            double X00 = k00 * cc + a_ww * ss - b2;
            double X11 = k00 * ss + a_ww * cc + b2;
            double X01 = (k00 - a_ww) * cs + b_pw * (cc - ss);
            double r1 = (k11 + k12) * inv, r2 = (k21 + k22) * inv;
            double P3 = r1 * ps, P4 = r2 * ps, P5 = r1 * pc, P6 = r2 * pc;
            /* rows and columns u1 v1 th1 u2 v2 th2 */
            double K[36] = {
                X00, X01, -P3, -X00, -X01, -P4,
                X01, X11, P5, -X01, -X11, P6,
                -P3, P5, k11, P3, -P5, k12,
                -X00, -X01, P3, X00, X01, P4,
                -X01, -X11, -P5, X01, X11, -P6,
                -P4, P6, k21, P4, -P6, k22};
            Py_ssize_t p0 = 36 * e;
            for (int q = 0; q < 36; q++)
                emit(&out, p0 + q, K[q]);
        }
        /* the element forces into the residual force by force over the elements (the order of the numpy
         * path's bincount, so that the two agree to the last bit) */
        for (int a = 0; a < 6; a++)
            for (Py_ssize_t e = 0; e < ne; e++)
                r[edof[6 * e + a]] += Fs[a * ne + e];
        PyMem_Free(Fs);
        Fs = NULL;
        /* linear dead loads */
        const long long *lind = IDX(self->st[S_LIND]);
        const double *lval = DBL(self->st[S_LVAL]);
        for (Py_ssize_t i = 0; i < self->nlin; i++) {
            r[lind[i]] += lam * lval[i];
            if (fl)
                fl[lind[i]] += lval[i];
        }
        const long long *lint = IDX(self->st[S_LINT]);
        const double *ldbl = DBL(self->st[S_LDBL]);
        /* terms: forces at body points, rotational springs, slide springs */
        const long long *tint = IDX(self->st[S_TINT]);
        const double *tdbl = DBL(self->st[S_TDBL]);
        for (Py_ssize_t t = 0; t < self->nt; t++) {
            const long long *ti = tint + 4 * t;
            const double *td = tdbl + 5 * t;
            Py_ssize_t p0 = (Py_ssize_t)ti[2];
            if (ti[0] == 0) {      /* PointForce.assemble */
                int d0 = (int)ti[1];
                double th = y[d0 + 2];
                double co = cos(th), si = sin(th);
                double rx = td[0], ry = td[1], Fx = td[2], Fy = td[3], M = td[4];
                double Rx = co * rx - si * ry, Ry = si * rx + co * ry;
                double g0[3] = {-Fx, -Fy, -(Fx * -Ry + Fy * Rx) - M};
                for (int a = 0; a < 3; a++) {
                    r[d0 + a] += lam * g0[a];
                    if (fl)
                        fl[d0 + a] += g0[a];
                }
                if (jac) {
                    for (int q = 0; q < 8; q++)
                        emit(&out, p0 + q, 0.0);
                    emit(&out, p0 + 8, lam * (Fx * Rx + Fy * Ry));
                }
                continue;
            }
            LinkGeo L;
            Py_ssize_t li = (Py_ssize_t)ti[1];
            link_geo(lint + 8 * li, ldbl + 12 * li, &L);
            double z[6];
            gather(&L, y, z);
            int k = L.k;
            if (ti[0] == 1) {      /* RotationalSpring.assemble */
                double dd[6] = {0, 0, 0, 0, 0, 0}, th = 0.0;
                if (L.ia >= 0) { th += z[L.ia + 2]; dd[L.ia + 2] = 1.0; }
                if (L.ib >= 0) { th -= z[L.ib + 2]; dd[L.ib + 2] = -1.0; }
                double cval = td[0], ct = cval * th;
                for (int j = 0; j < k; j++)
                    r[gdof(&L, j)] += ct * dd[j];
                if (jac)
                    for (int i = 0; i < k; i++)
                        for (int j = 0; j < k; j++)
                            emit(&out, p0 + i * k + j, cval * (dd[i] * dd[j]));
            } else {               /* SlideSpring.assemble */
                double ds[6], H[36];
                double s = link_slide(&L, z, ds, H) - td[2];
                double kk = td[0], F0 = td[1];
                double f = kk * s - lam * F0;
                for (int j = 0; j < k; j++) {
                    r[gdof(&L, j)] += f * ds[j];
                    if (fl)
                        fl[gdof(&L, j)] += -F0 * ds[j];
                }
                if (jac)
                    for (int i = 0; i < k; i++)
                        for (int j = 0; j < k; j++)
                            emit(&out, p0 + i * k + j, kk * (ds[i] * ds[j]) + f * H[i * k + j]);
            }
        }
        /* joints: the multipliers' forces mu . G on the joint's dofs, the equations g on its rows; the
         * Jacobian blocks sum_i mu_i H_i (k x k), G (m x k) and G^T, in the pattern's order */
        for (Py_ssize_t l = 0; l < self->nl; l++) {
            const long long *li = lint + 8 * l;
            LinkGeo L;
            link_geo(li, ldbl + 12 * l, &L);
            int kind = (int)li[0];
            Py_ssize_t row0 = (Py_ssize_t)li[5], p0 = (Py_ssize_t)li[6];
            double z[6], g[3], G[18], Hmu[36];
            const double *mu = y + row0;
            int k = L.k;
            gather(&L, y, z);
            if (jac)
                memset(Hmu, 0, sizeof(Hmu));
            int m;
            if (li[7]) {
                /* a linear joint (no lever, pin or weld): g = G z + g(0) with the constant G, summed over
                 * G's nonzeros as Link.assemble does (the same rounding) */
                double z0[6] = {0, 0, 0, 0, 0, 0}, g0[3];
                m = link_equations(&L, kind, z0, mu, g0, G, NULL);
                for (int i = 0; i < m; i++) {
                    double gi = 0.0;
                    for (int j = 0; j < k; j++)
                        if (G[i * k + j] != 0.0)
                            gi += G[i * k + j] * z[j];
                    g[i] = gi + g0[i];
                }
            } else {
                m = link_equations(&L, kind, z, mu, g, G, jac ? Hmu : NULL);
            }
            for (int j = 0; j < k; j++) {
                double f = 0.0;
                for (int i = 0; i < m; i++)
                    f += mu[i] * G[i * k + j];
                r[gdof(&L, j)] += f;
            }
            for (int i = 0; i < m; i++)
                r[row0 + i] += g[i];
            if (!jac)
                continue;
            Py_ssize_t p = p0;
            for (int q = 0; q < k * k; q++)
                emit(&out, p++, Hmu[q]);
            for (int q = 0; q < m * k; q++)
                emit(&out, p++, G[q]);
            for (int q = 0; q < m * k; q++)
                emit(&out, p++, G[q]);
        }
        /* constraints and terms evaluated in Python */
        for (Py_ssize_t i = 0; i < LEN(bxr); i++)
            r[IDX(bxr)[i]] += DBL(bxrv)[i];
        if (fl)
            for (Py_ssize_t i = 0; i < LEN(bxf); i++)
                fl[IDX(bxf)[i]] += DBL(bxfv)[i];
        if (FT) {   /* minus the bincount of B^T S_T over the element dofs (numpy: its own sum, then subtracted) */
            double *acc = (double *)PyMem_Calloc((size_t)n_q, sizeof(double));
            if (acc == NULL) {
                PyMem_Free(FT);
                PyErr_NoMemory();
                goto done;
            }
            for (int a = 0; a < 6; a++)
                for (Py_ssize_t e = 0; e < ne; e++)
                    acc[edof[6 * e + a]] += FT[a * ne + e];
            for (Py_ssize_t i = 0; i < n_q; i++)
                fl[i] -= acc[i];
            PyMem_Free(acc);
            PyMem_Free(FT);
            FT = NULL;
        }
        if (jac)
            for (Py_ssize_t i = 0; i < LEN(bxj); i++)
                emit(&out, (Py_ssize_t)IDX(bxj)[i], DBL(bxjv)[i]);
        /* displacement control: the controlled dof's equation and the load factor's column */
        if (ctrl >= 0) {
            Py_ssize_t n = nr - 1;
            r[n] += y[ctrl] - target;
            if (jac) {
                Py_ssize_t p = (Py_ssize_t)(bflat.held ? LEN(bflat) : LEN(bvals)) - 1 - self->nload;
                if (!fl) {
                    PyErr_SetString(PyExc_ValueError, "femslide kernel: control needs fl");
                    goto done;
                }
                emit(&out, p++, 1.0);
                const long long *ld = IDX(self->st[S_LOADS]);
                for (Py_ssize_t i = 0; i < self->nload; i++)
                    emit(&out, p++, fl[ld[i]]);
            }
        }
        result = Py_BuildValue("dd", fmax, noise);
    }
done:
    for (size_t i = 0; i < sizeof(all) / sizeof(all[0]); i++)
        release(all[i]);
    return result;
}

/* basic(y, alpha_ref, NM, alpha) -> strain energy: the elements' basic forces (N, M1, M2) into NM (3, ne), their
 * chord rotations (continued from alpha_ref) into alpha (ne), and their strain energy: the kinematics of assemble()
 * without the nodal forces and tangents (femslide.elements.corotational.basic_forces and strain_energy, the free
 * (thermal) forces at full load; the forces bitwise as there, the energy summed in element order) */
static PyObject *Assembler_basic(Assembler *self, PyObject *args)
{
    PyObject *oy, *oaref, *onm, *oal;
    if (!PyArg_ParseTuple(args, "OOOO", &oy, &oaref, &onm, &oal))
        return NULL;
    Buf by, bar, bnm, bal;
    by.held = bar.held = bnm.held = bal.held = 0;
    PyObject *result = NULL;
    if (get_buf(oy, &by, 0, "d", 8, "y") < 0 || get_buf(oaref, &bar, 0, "d", 8, "alpha_ref") < 0 ||
        get_buf(onm, &bnm, 1, "d", 8, "NM") < 0 || get_buf(oal, &bal, 1, "d", 8, "alpha") < 0)
        goto done;
    {
        const Py_ssize_t ne = self->ne;
        if (LEN(by) < self->n_q || LEN(bar) != ne || LEN(bnm) != 3 * ne || LEN(bal) != ne) {
            PyErr_SetString(PyExc_ValueError, "femslide kernel: basic: arrays of the wrong size");
            goto done;
        }
        const double *y = DBL(by), *aref = DBL(bar);
        double *NM = DBL(bnm), *alpha = DBL(bal);
        const long long *edof = IDX(self->st[S_EDOF]);
        const double *edat = DBL(self->st[S_EDAT]);
        double E = 0.0, ET = 0.0;
        for (Py_ssize_t e = 0; e < ne; e++) {
            const long long *d = edof + 6 * e;
            const double *c = edat + 12 * e;
            double k00 = c[4], k11 = c[5], k12 = c[6], k21 = c[7], k22 = c[8];
            Kin k;
            kinematics(y, d, c, aref[e], &k);
            double ub = k.ub, th1 = k.th1, th2 = k.th2;
            alpha[e] = k.al;
            double N = k00 * ub;
            double M1 = k11 * th1 + k12 * th2, M2 = k21 * th1 + k22 * th2;
            if (self->thermal) {
                N -= c[9];
                M1 -= c[10];
                M2 -= c[11];
                ET += c[9] * ub + c[10] * th1 + c[11] * th2;
            }
            NM[e] = N;
            NM[ne + e] = M1;
            NM[2 * ne + e] = M2;
            E += k00 * (ub * ub) + k11 * (th1 * th1) + (k12 + k21) * th1 * th2 + k22 * (th2 * th2);
        }
        result = PyFloat_FromDouble(0.5 * E - ET);
    }
done:
    release(&by);
    release(&bar);
    release(&bnm);
    release(&bal);
    return result;
}

static PyMethodDef Assembler_methods[] = {
    {"basic", (PyCFunction)Assembler_basic, METH_VARARGS,
     "basic(y, alpha_ref, NM, alpha) -> strain energy: the elements' basic forces (N, M1, M2) into NM (3, ne) and "
     "their chord rotations into alpha"},
    {"assemble", (PyCFunction)Assembler_assemble, METH_VARARGS,
     "assemble(y, alpha_ref, alpha_out, lam, control_dof, target, r, A, flat, vals, fl, xr, xrv, xj, xjv, xf, xfv"
     "[, elements]) -> (fmax, noise): residual into r, Jacobian into A[flat[p]] (or vals[p]), trial chord rotations"
     " into alpha_out, d r / d lam into fl; None for what is not wanted; elements=False leaves the elements out"},
    {NULL, NULL, 0, NULL}};

static PyTypeObject AssemblerType = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "femslide.model._assembly.Assembler",
    .tp_basicsize = sizeof(Assembler),
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = "Assembler(n_q, xmax, element dofs, element data, link ints, link reals, term ints, term reals, "
              "load dofs, load values, lam dofs): the static data of one model topology",
    .tp_new = PyType_GenericNew,
    .tp_init = (initproc)Assembler_init,
    .tp_dealloc = (destructor)Assembler_dealloc,
    .tp_methods = Assembler_methods,
};


/* -- linear solves: LU with partial pivoting, dense (row-major) and band (LAPACK's band storage) -------------
 *
 * The Newton systems are small (dense, up to ~100 unknowns) or banded with a narrow band after
 * reverse Cuthill-McKee renumbering; LAPACK's dgesv / dgbsv cost more in the call than in the
 * arithmetic at these sizes, and dgbtf2 makes several BLAS calls per column.  These are the textbook
 * algorithms (Golub & Van Loan, 3.4 and 4.3; dgbtf2/dgbtrs for the band), written out. */

/* factor(A) in place: A (n x n, row-major) -> L\U, piv[k] = row swapped with k; returns 0 or k+1 at
 * the first exactly zero pivot (as LAPACK's info).  A row's update ri -= l rk runs over the nonzero
 * entries of the pivot row rk alone when they are fewer than half of it (a time step's coupled
 * matrix: 6 % nonzero, 12 % after fill-in): the same operations on the same entries in the same
 * order (a zero rk[j] leaves ri[j] as it is, but for the sign of a zero, unless l is NaN or infinite:
 * then the whole row), a fraction of the work.  The next column's pivot is searched while the rows
 * are updated (one pass down the column instead of two). */
static Py_ssize_t lu_dense(double *A, Py_ssize_t n, Py_ssize_t *piv)
{
    Py_ssize_t info = 0;
    Py_ssize_t *nz = n > 0 ? malloc(sizeof(Py_ssize_t) * (size_t)n) : NULL;   /* (NULL: every row dense) */
    Py_ssize_t next = -1;   /* the pivot of column k found while eliminating column k - 1 (-1: search) */
    for (Py_ssize_t k = 0; k < n; k++) {
        Py_ssize_t p = next;
        if (p < 0) {
            p = k;
            double big = fabs(A[k * n + k]);
            for (Py_ssize_t i = k + 1; i < n; i++) {
                double v = fabs(A[i * n + k]);
                if (v > big) { big = v; p = i; }
            }
        }
        next = -1;
        piv[k] = p;
        if (A[p * n + k] == 0.0) {
            if (!info) info = k + 1;
            continue;
        }
        if (p != k) {
            double *a = A + k * n, *b = A + p * n;
            for (Py_ssize_t j = 0; j < n; j++) { double t = a[j]; a[j] = b[j]; b[j] = t; }
        }
        double inv = 1.0 / A[k * n + k];
        const double *rk = A + k * n;
        Py_ssize_t m = -1;   /* the count of rk's nonzero entries beyond k (listed in nz), -1: dense */
        if (nz) {
            m = 0;
            for (Py_ssize_t j = k + 1; j < n; j++)
                if (rk[j] != 0.0)    /* (NaN included) */
                    nz[m++] = j;
            if (2 * m > n - k - 1)
                m = -1;
        }
        /* the rows in order, each's entry in column k + 1 final once it is updated: the next pivot is
         * searched on the way, as the search above would (the first of the largest) */
        Py_ssize_t q = k + 1;
        double big = -1.0;
        for (Py_ssize_t i = k + 1; i < n; i++) {
            double *ri = A + i * n;
            double l = ri[k] * inv;
            ri[k] = l;
            if (l != 0.0) {
                if (m < 0 || !isfinite(l))   /* (a NaN or infinite l: spread over the whole row, as always) */
                    for (Py_ssize_t j = k + 1; j < n; j++)
                        ri[j] -= l * rk[j];
                else
                    for (Py_ssize_t t = 0; t < m; t++) {
                        Py_ssize_t j = nz[t];
                        ri[j] -= l * rk[j];
                    }
            }
            if (k + 1 < n) {
                double v = fabs(ri[k + 1]);
                if (i == k + 1)
                    big = v;
                else if (v > big) { big = v; q = i; }
            }
        }
        if (k + 1 < n)
            next = q;
    }
    free(nz);
    return info;
}

static void lu_dense_solve(const double *LU, Py_ssize_t n, const Py_ssize_t *piv, double *b)
{
    for (Py_ssize_t k = 0; k < n; k++) {
        Py_ssize_t p = piv[k];
        if (p != k) { double t = b[k]; b[k] = b[p]; b[p] = t; }
    }
    /* forward: row i's s = b[i] - sum_j<i L[i, j] b[j], the terms in increasing j; four rows at a time
     * (four independent sums over the j < i they share, then the triangle), each row's terms in the same
     * order as one row at a time: the same rounding, without waiting for one sum's additions */
    Py_ssize_t i = 1;
    for (; i + 4 <= n; i += 4) {
        const double *r0 = LU + i * n, *r1 = r0 + n, *r2 = r1 + n, *r3 = r2 + n;
        double s0 = b[i], s1 = b[i + 1], s2 = b[i + 2], s3 = b[i + 3];
        for (Py_ssize_t j = 0; j < i; j++) {
            double bj = b[j];
            s0 -= r0[j] * bj;
            s1 -= r1[j] * bj;
            s2 -= r2[j] * bj;
            s3 -= r3[j] * bj;
        }
        b[i] = s0;
        s1 -= r1[i] * s0;
        b[i + 1] = s1;
        s2 -= r2[i] * s0;
        s2 -= r2[i + 1] * s1;
        b[i + 2] = s2;
        s3 -= r3[i] * s0;
        s3 -= r3[i + 1] * s1;
        s3 -= r3[i + 2] * s2;
        b[i + 3] = s3;
    }
    for (; i < n; i++) {
        const double *ri = LU + i * n;
        double s = b[i];
        for (Py_ssize_t j = 0; j < i; j++)
            s -= ri[j] * b[j];
        b[i] = s;
    }
    for (Py_ssize_t i = n - 1; i >= 0; i--) {
        const double *ri = LU + i * n;
        double s = b[i];
        for (Py_ssize_t j = i + 1; j < n; j++)
            s -= ri[j] * b[j];
        b[i] = s / ri[i];
    }
}

/* the band: AB column-major with leading dimension ld = 2 kl + ku + 1, A[i, j] at AB[j * ld + kl + ku + i - j]
 * (LAPACK's dgbtrf layout, the kl top rows are room for the fill-in); dgbtf2 */
static Py_ssize_t lu_band(double *AB, Py_ssize_t n, Py_ssize_t kl, Py_ssize_t ku, Py_ssize_t *piv)
{
    Py_ssize_t ld = 2 * kl + ku + 1, kv = ku + kl, info = 0;
    /* a column's update col -= l u runs over the nonzero multipliers alone when they are under half of
     * them (a time step's coupled band: 26 % nonzero after fill-in): the same operations on the same
     * entries in the same order (a zero l leaves the entry as it is, but for the sign of a zero) */
    Py_ssize_t *nz = kl > 0 ? malloc(sizeof(Py_ssize_t) * (size_t)kl) : NULL;
#define AB_(i, j) AB[(j) * ld + (i)]
    for (Py_ssize_t j = ku + 1; j < (kv < n ? kv : n); j++)
        for (Py_ssize_t i = kv - j; i < kl; i++)
            AB_(i, j) = 0.0;
    Py_ssize_t ju = 0;
    for (Py_ssize_t j = 0; j < n; j++) {
        if (j + kv < n)
            for (Py_ssize_t i = 0; i < kl; i++)
                AB_(i, j + kv) = 0.0;
        Py_ssize_t km = kl < n - 1 - j ? kl : n - 1 - j;
        Py_ssize_t jp = 0;
        double big = fabs(AB_(kv, j));
        for (Py_ssize_t i = 1; i <= km; i++) {
            double v = fabs(AB_(kv + i, j));
            if (v > big) { big = v; jp = i; }
        }
        piv[j] = jp + j;
        if (AB_(kv + jp, j) != 0.0) {
            Py_ssize_t t = j + ku + jp;
            if (t > n - 1) t = n - 1;
            if (t > ju) ju = t;
            if (jp != 0)      /* swap rows j and j + jp over the columns j .. ju */
                for (Py_ssize_t c = 0; c <= ju - j; c++) {
                    double *a = &AB[(j + c) * ld + kv + jp - c], *b = &AB[(j + c) * ld + kv - c];
                    double tmp = *a; *a = *b; *b = tmp;
                }
            if (km > 0) {
                double inv = 1.0 / AB_(kv, j);
                double *l = &AB_(kv + 1, j);
                Py_ssize_t m = nz ? 0 : -1;   /* the nonzero multipliers (listed in nz) or -1: all */
                for (Py_ssize_t i = 0; i < km; i++) {
                    l[i] *= inv;
                    if (m >= 0 && l[i] != 0.0)   /* (NaN included) */
                        nz[m++] = i + 1;
                }
                if (2 * m > km)
                    m = -1;
                for (Py_ssize_t c = 1; c <= ju - j; c++) {
                    double *col = &AB[(j + c) * ld + kv - c];   /* A[j, j + c] at col[0], A[j + i, j + c] at col[i] */
                    double u = col[0];
                    if (u == 0.0)
                        continue;
                    if (m < 0 || !isfinite(u))   /* (NaN or infinite: spread over the whole column, as always) */
                        for (Py_ssize_t i = 1; i <= km; i++)
                            col[i] -= l[i - 1] * u;
                    else
                        for (Py_ssize_t t = 0; t < m; t++) {
                            Py_ssize_t i = nz[t];
                            col[i] -= l[i - 1] * u;
                        }
                }
            }
        } else if (!info) {
            info = j + 1;
        }
    }
#undef AB_
    free(nz);
    return info;
}

static void lu_band_solve(const double *AB, Py_ssize_t n, Py_ssize_t kl, Py_ssize_t ku, const Py_ssize_t *piv,
                          double *b)
{
    Py_ssize_t ld = 2 * kl + ku + 1, kv = ku + kl;
    if (kl > 0)
        for (Py_ssize_t j = 0; j < n - 1; j++) {
            Py_ssize_t lm = kl < n - 1 - j ? kl : n - 1 - j;
            Py_ssize_t l = piv[j];
            if (l != j) { double t = b[l]; b[l] = b[j]; b[j] = t; }
            double bj = b[j];
            const double *col = AB + j * ld + kv + 1;
            for (Py_ssize_t i = 0; i < lm; i++)
                b[j + 1 + i] -= col[i] * bj;
        }
    for (Py_ssize_t j = n - 1; j >= 0; j--) {
        const double *col = AB + j * ld;
        b[j] /= col[kv];
        double t = b[j];
        Py_ssize_t i0 = j - kv > 0 ? j - kv : 0;
        for (Py_ssize_t i = i0; i < j; i++)
            b[i] -= t * col[kv + i - j];
    }
}

/* factor(M, piv) -> info: M is a dense (n x n, C order) or band ((n, 2 kl + ku + 1), C order: the
 * column-major band) array, factored in place; piv an intp array of n */
static PyObject *py_factor(PyObject *mod, PyObject *args)
{
    PyObject *om, *op;
    Py_ssize_t n, kl, ku;
    if (!PyArg_ParseTuple(args, "OOnnn", &om, &op, &n, &kl, &ku))
        return NULL;
    Buf bm, bp;
    if (get_buf(om, &bm, 1, "d", 8, "matrix") < 0)
        return NULL;
    if (get_buf(op, &bp, 1, "qlLn", (Py_ssize_t)sizeof(Py_ssize_t), "pivots") < 0) {
        release(&bm);
        return NULL;
    }
    Py_ssize_t info = -1;
    if (LEN(bp) != n || (kl < 0 ? LEN(bm) != n * n : LEN(bm) != n * (2 * kl + ku + 1)))
        PyErr_SetString(PyExc_ValueError, "femslide kernel: factor: wrong sizes");
    else {
        Py_BEGIN_ALLOW_THREADS
        info = kl < 0 ? lu_dense(DBL(bm), n, (Py_ssize_t *)bp.view.buf)
                      : lu_band(DBL(bm), n, kl, ku, (Py_ssize_t *)bp.view.buf);
        Py_END_ALLOW_THREADS
    }
    release(&bm);
    release(&bp);
    if (info < 0)
        return NULL;
    return PyLong_FromSsize_t(info);
}

/* solve(M, piv, b, kl, ku): b overwritten by the solution with the factors of factor() */
static PyObject *py_solve(PyObject *mod, PyObject *args)
{
    PyObject *om, *op, *ob;
    Py_ssize_t kl, ku;
    if (!PyArg_ParseTuple(args, "OOOnn", &om, &op, &ob, &kl, &ku))
        return NULL;
    Buf bm, bp, bb;
    bm.held = bp.held = bb.held = 0;
    PyObject *res = NULL;
    if (get_buf(om, &bm, 0, "d", 8, "factors") < 0 ||
        get_buf(op, &bp, 0, "qlLn", (Py_ssize_t)sizeof(Py_ssize_t), "pivots") < 0 ||
        get_buf(ob, &bb, 1, "d", 8, "right-hand side") < 0)
        goto out;
    {
        Py_ssize_t n = LEN(bp);
        if (LEN(bb) != n || (kl < 0 ? LEN(bm) != n * n : LEN(bm) != n * (2 * kl + ku + 1))) {
            PyErr_SetString(PyExc_ValueError, "femslide kernel: solve: wrong sizes");
            goto out;
        }
        if (kl < 0)
            lu_dense_solve(DBL(bm), n, (const Py_ssize_t *)bp.view.buf, DBL(bb));
        else
            lu_band_solve(DBL(bm), n, kl, ku, (const Py_ssize_t *)bp.view.buf, DBL(bb));
        Py_INCREF(Py_None);
        res = Py_None;
    }
out:
    release(&bm);
    release(&bp);
    release(&bb);
    return res;
}



/* solve_dense(A, x): x := A^-1 x for a dense (n x n, C order) A, which is left unchanged (LU in a
 * scratch copy): the Newton step of a small model in one call; returns the LU's info (0, or the first
 * zero pivot + 1) */
static PyObject *py_solve_dense(PyObject *mod, PyObject *args)
{
    PyObject *oa, *ox;
    if (!PyArg_ParseTuple(args, "OO", &oa, &ox))
        return NULL;
    Buf ba, bx;
    ba.held = bx.held = 0;
    PyObject *res = NULL;
    double *lu = NULL;
    Py_ssize_t *piv = NULL;
    if (get_buf(oa, &ba, 0, "d", 8, "matrix") < 0 || get_buf(ox, &bx, 1, "d", 8, "right-hand side") < 0)
        goto out;
    {
        Py_ssize_t n = LEN(bx);
        if (LEN(ba) != n * n) {
            PyErr_SetString(PyExc_ValueError, "femslide kernel: solve_dense: wrong sizes");
            goto out;
        }
        lu = PyMem_Malloc(sizeof(double) * (n * n + 1));
        piv = PyMem_Malloc(sizeof(Py_ssize_t) * (n + 1));
        if (!lu || !piv) {
            PyErr_NoMemory();
            goto out;
        }
        memcpy(lu, ba.view.buf, sizeof(double) * n * n);
        Py_ssize_t info = lu_dense(lu, n, piv);
        if (info == 0)
            lu_dense_solve(lu, n, piv, DBL(bx));
        res = PyLong_FromSsize_t(info);
    }
out:
    PyMem_Free(lu);
    PyMem_Free(piv);
    release(&ba);
    release(&bx);
    return res;
}


/* norms(v, k[, idx]) -> (max |v[:k]|, max |v[k:]|, max |v[idx]|): Newton's residual and step norms in
 * one pass (NaN propagates: a NaN anywhere gives NaN, as numpy's max does) */
static PyObject *py_norms(PyObject *mod, PyObject *args)
{
    PyObject *ov, *oi = Py_None;
    Py_ssize_t k;
    if (!PyArg_ParseTuple(args, "On|O", &ov, &k, &oi))
        return NULL;
    Buf bv, bi;
    bv.held = bi.held = 0;
    if (get_buf(ov, &bv, 0, "d", 8, "vector") < 0 || get_buf(oi, &bi, 0, "qlLn", 8, "indices") < 0) {
        release(&bv);
        return NULL;
    }
    const double *v = DBL(bv);
    Py_ssize_t n = LEN(bv);
    if (k > n) k = n;
    double a = 0.0, b = 0.0, c = 0.0;
    int nan = 0;
    for (Py_ssize_t i = 0; i < k; i++) {
        double x = fabs(v[i]);
        if (x > a) a = x;
        else if (x != x) nan = 1;
    }
    if (nan) a = NAN;
    nan = 0;
    for (Py_ssize_t i = k; i < n; i++) {
        double x = fabs(v[i]);
        if (x > b) b = x;
        else if (x != x) nan = 1;
    }
    if (nan) b = NAN;
    nan = 0;
    if (bi.held) {
        const long long *idx = IDX(bi);
        for (Py_ssize_t i = 0; i < LEN(bi); i++) {
            if (idx[i] < 0 || idx[i] >= n) {
                release(&bv);
                release(&bi);
                PyErr_SetString(PyExc_IndexError, "femslide kernel: norms: index out of range");
                return NULL;
            }
            double x = fabs(v[idx[i]]);
            if (x > c) c = x;
            else if (x != x) nan = 1;
        }
        if (nan) c = NAN;
    }
    release(&bv);
    release(&bi);
    return Py_BuildValue("ddd", a, b, c);
}

/* -- reverse Cuthill-McKee ordering (femslide.model.linalg.reverse_cuthill_mckee, the same permutation) ---------
 * of the symmetrised pattern (rows, cols) of a size x size matrix: breadth-first from a node of least
 * degree in each connected part (ties by index), neighbours by increasing degree (ties by index),
 * reversed. */
static int cmp_ll(const void *a, const void *b)
{
    long long x = *(const long long *)a, y = *(const long long *)b;
    return (x > y) - (x < y);
}

static PyObject *py_rcm(PyObject *mod, PyObject *args)
{
    PyObject *orow, *ocol, *operm;
    Py_ssize_t size;
    if (!PyArg_ParseTuple(args, "OOnO", &orow, &ocol, &size, &operm))
        return NULL;
    Buf br, bc, bp;
    br.held = bc.held = bp.held = 0;
    PyObject *res = NULL;
    long long *ptr = NULL, *adj = NULL, *deg = NULL, *order = NULL, *cnt = NULL, *key = NULL;
    char *seen = NULL;
    if (get_buf(orow, &br, 0, "qlL", 8, "rows") < 0 || get_buf(ocol, &bc, 0, "qlL", 8, "cols") < 0 ||
        get_buf(operm, &bp, 1, "qlL", 8, "perm") < 0)
        goto out;
    {
        Py_ssize_t m = LEN(br);
        const long long *R = IDX(br), *C = IDX(bc);
        long long *perm = IDX(bp);
        if (LEN(bc) != m || LEN(bp) != size) {
            PyErr_SetString(PyExc_ValueError, "femslide kernel: rcm: wrong sizes");
            goto out;
        }
        ptr = PyMem_Calloc(size + 1, sizeof(long long));
        adj = PyMem_Malloc(sizeof(long long) * (2 * m + 1));
        deg = PyMem_Calloc(size + 1, sizeof(long long));
        order = PyMem_Malloc(sizeof(long long) * (size + 1));
        key = PyMem_Malloc(sizeof(long long) * (2 * m + 1));
        seen = PyMem_Calloc(size + 1, 1);
        if (!ptr || !adj || !deg || !order || !key || !seen) {
            PyErr_NoMemory();
            goto out;
        }
        for (Py_ssize_t i = 0; i < m; i++) {
            if (R[i] < 0 || R[i] >= size || C[i] < 0 || C[i] >= size) {
                PyErr_SetString(PyExc_ValueError, "femslide kernel: rcm: index out of range");
                goto out;
            }
            if (R[i] != C[i]) {
                ptr[R[i] + 1]++;
                ptr[C[i] + 1]++;
            }
        }
        for (Py_ssize_t i = 0; i < size; i++)
            ptr[i + 1] += ptr[i];
        {
            long long *fill = deg;   /* (reused as a cursor, zeroed again below) */
            for (Py_ssize_t i = 0; i < m; i++)
                if (R[i] != C[i]) {
                    adj[ptr[R[i]] + fill[R[i]]++] = C[i];
                    adj[ptr[C[i]] + fill[C[i]]++] = R[i];
                }
        }
        /* each node's neighbours sorted and made distinct; degree = their count */
        for (Py_ssize_t v = 0; v < size; v++) {
            long long a = ptr[v], n = ptr[v + 1] - a;
            qsort(adj + a, (size_t)n, sizeof(long long), cmp_ll);
            long long k = 0;
            for (long long j = 0; j < n; j++)
                if (k == 0 || adj[a + j] != adj[a + k - 1])
                    adj[a + k++] = adj[a + j];
            deg[v] = k;
        }
        /* neighbours by (degree, index): sort keys degree * size + index */
        for (Py_ssize_t v = 0; v < size; v++) {
            long long a = ptr[v], n = deg[v];
            for (long long j = 0; j < n; j++)
                key[j] = deg[adj[a + j]] * (long long)size + adj[a + j];
            qsort(key, (size_t)n, sizeof(long long), cmp_ll);
            for (long long j = 0; j < n; j++)
                adj[a + j] = key[j] % size;
        }
        /* start candidates by (degree, index): a counting sort on the degree (stable) */
        long long dmax = 0;
        for (Py_ssize_t v = 0; v < size; v++)
            if (deg[v] > dmax) dmax = deg[v];
        cnt = PyMem_Calloc(dmax + 2, sizeof(long long));
        if (!cnt) {
            PyErr_NoMemory();
            goto out;
        }
        for (Py_ssize_t v = 0; v < size; v++)
            cnt[deg[v] + 1]++;
        for (long long d = 0; d <= dmax; d++)
            cnt[d + 1] += cnt[d];
        for (Py_ssize_t v = 0; v < size; v++)
            order[cnt[deg[v]]++] = v;
        Py_ssize_t head = 0, tail = 0;
        for (Py_ssize_t q = 0; q < size; q++) {
            long long s0 = order[q];
            if (seen[s0])
                continue;
            seen[s0] = 1;
            perm[tail++] = s0;
            while (head < tail) {
                long long v = perm[head++];
                for (long long j = ptr[v]; j < ptr[v] + deg[v]; j++) {
                    long long w = adj[j];
                    if (!seen[w]) {
                        seen[w] = 1;
                        perm[tail++] = w;
                    }
                }
            }
        }
        for (Py_ssize_t i = 0; i < size / 2; i++) {
            long long t = perm[i];
            perm[i] = perm[size - 1 - i];
            perm[size - 1 - i] = t;
        }
        Py_INCREF(Py_None);
        res = Py_None;
    }
out:
    PyMem_Free(ptr);
    PyMem_Free(adj);
    PyMem_Free(deg);
    PyMem_Free(order);
    PyMem_Free(key);
    PyMem_Free(cnt);
    PyMem_Free(seen);
    release(&br);
    release(&bc);
    release(&bp);
    return res;
}

/* -- equilibration ------------------------------------------------------------------------------------ */

/* 2^-e with x = m 2^e, 0.5 <= m < 1; 1 for x <= 0, infinite or NaN (linalg._pow2) */
static double pow2_scale(double x)
{
    if (!(x > 0.0) || isinf(x))
        return 1.0;
    int e;
    frexp(x, &e);
    return ldexp(1.0, -e);
}

/* the scale of a row or column from its largest magnitude m and chk, the sum of (a - a) over its entries
 * (NaN when one of them is infinite or NaN: numpy's max is then inf or NaN, and _pow2 gives 1; the rows'
 * own loops flag that with an integer, which vectorises) */
static inline double scale_of(double m, double chk)
{
    return chk == 0.0 ? pow2_scale(m) : 1.0;
}

/* the largest |x[i]| of n values (max is exact in any order: SSE2's maxpd, two lanes twice); *bad set when
 * one of them is infinite or NaN */
static double absmax(const double *x, Py_ssize_t n, int *bad)
{
    Py_ssize_t i = 0;
    double m = 0.0;
    int b = 0;
#ifdef __SSE2__
    const __m128d sign = _mm_set1_pd(-0.0), big = _mm_set1_pd(DBL_MAX);
    __m128d m0 = _mm_setzero_pd(), m1 = _mm_setzero_pd(), b0 = _mm_setzero_pd();
    for (; i + 4 <= n; i += 4) {
        __m128d a0 = _mm_andnot_pd(sign, _mm_loadu_pd(x + i)), a1 = _mm_andnot_pd(sign, _mm_loadu_pd(x + i + 2));
        m0 = _mm_max_pd(a0, m0);     /* (a NaN a gives m0: flagged below) */
        m1 = _mm_max_pd(a1, m1);
        b0 = _mm_or_pd(b0, _mm_or_pd(_mm_cmpnle_pd(a0, big), _mm_cmpnle_pd(a1, big)));
    }
    double t[2];
    _mm_storeu_pd(t, _mm_max_pd(m0, m1));
    m = t[0] > t[1] ? t[0] : t[1];
    b = _mm_movemask_pd(b0) != 0;
#endif
    for (; i < n; i++) {
        double a = fabs(x[i]);
        m = a > m ? a : m;
        b |= !(a <= DBL_MAX);
    }
    *bad = b;
    return m;
}

/* the positions of a dense matrix's nonzero entries (equilibrate; under the GIL: one buffer kept and grown),
 * NULL beyond 4M entries or without memory (then the entries are all scanned) */
static int *eq_buf = NULL;
static Py_ssize_t eq_cap = 0;

static int *eq_positions(Py_ssize_t total)
{
    if (total <= 0 || total > 4194304)
        return NULL;
    if (total > eq_cap) {
        int *b = PyMem_Realloc(eq_buf, sizeof(int) * (size_t)total);
        if (!b)
            return NULL;
        eq_buf = b;
        eq_cap = total;
    }
    return eq_buf;
}

/* the positions of the nonzero entries of x[0..n) (NaN included) written to nz from t0 on; returns the end */
static Py_ssize_t list_nonzero(const double *x, Py_ssize_t n, int *nz, Py_ssize_t t0)
{
    Py_ssize_t i = 0, u = t0;
#ifdef __SSE2__
    const __m128d zero = _mm_setzero_pd();
    for (; i + 4 <= n; i += 4) {
        int mask = _mm_movemask_pd(_mm_cmpneq_pd(_mm_loadu_pd(x + i), zero))
                   | (_mm_movemask_pd(_mm_cmpneq_pd(_mm_loadu_pd(x + i + 2), zero)) << 2);
        while (mask) {
            nz[u++] = (int)(i + __builtin_ctz(mask));
            mask &= mask - 1;
        }
    }
#endif
    for (; i < n; i++)
        if (x[i] != 0.0)
            nz[u++] = (int)i;
    return u;
}

/* the largest |x[i]| of n values, and the positions of the nonzero ones (NaN included) written to nz from
 * t0 on (*t1: the end); *bad set when one of them is infinite or NaN */
static double absmax_nonzero(const double *x, Py_ssize_t n, int *nz, Py_ssize_t t0, Py_ssize_t *t1, int *bad)
{
    Py_ssize_t u = list_nonzero(x, n, nz, t0);
    double m = 0.0;
    int b = 0;
    for (Py_ssize_t v = t0; v < u; v++) {
        double a = fabs(x[nz[v]]);
        m = a > m ? a : m;
        b |= !(a <= DBL_MAX);
    }
    *t1 = u;
    *bad = b;
    return m;
}

/* row *= r, and the columns' largest magnitudes cm and inf/NaN checks ck updated with it (dense equilibrate) */
static void scale_row(double *restrict row, double r, double *restrict cm, double *restrict ck, Py_ssize_t n)
{
    for (Py_ssize_t j = 0; j < n; j++) {
        double a = fabs(row[j] *= r);
        cm[j] = a > cm[j] ? a : cm[j];
        ck[j] += a - a;
    }
}

/* equilibrate(M, kl, ku, rs, cs): linalg._equilibrate in one call (the same scales, the same scaled M:
 * powers of 2, no round-off): M dense (n, n) C order (kl < 0) or the kernel's band layout (n, 2 kl + ku + 1),
 * M[j, kl + ku + i - j] = A[i, j]; rs, cs (n,) receive the row and column scales */
static PyObject *py_equilibrate(PyObject *mod, PyObject *args)
{
    PyObject *om, *ors, *ocs;
    Py_ssize_t kl, ku;
    if (!PyArg_ParseTuple(args, "OnnOO", &om, &kl, &ku, &ors, &ocs))
        return NULL;
    Buf bm, br, bc;
    bm.held = br.held = bc.held = 0;
    PyObject *res = NULL;
    double *chk = NULL;
    Py_ssize_t *row0 = NULL;
    if (get_buf(om, &bm, 1, "d", 8, "matrix") < 0 || get_buf(ors, &br, 1, "d", 8, "row scales") < 0 ||
        get_buf(ocs, &bc, 1, "d", 8, "column scales") < 0)
        goto out;
    {
        Py_ssize_t n = LEN(br), nrow = kl < 0 ? n : 2 * kl + ku + 1;
        if (LEN(bc) != n || LEN(bm) != n * nrow) {
            PyErr_SetString(PyExc_ValueError, "femslide kernel: equilibrate: wrong sizes");
            goto out;
        }
        chk = PyMem_Malloc(sizeof(double) * (n + 1));
        if (!chk) {
            PyErr_NoMemory();
            goto out;
        }
        double *M = DBL(bm), *rs = DBL(br), *cs = DBL(bc);
        int *nz = eq_positions(n * nrow);
        row0 = nz ? PyMem_Malloc(sizeof(Py_ssize_t) * (n + 1)) : NULL;
        if (nz && row0 && kl >= 0) {
            /* the band's columns' nonzero entries listed once (a time step's coupled band: 9 %): the
             * same scales and the same scaled band as below, from them alone */
            Py_ssize_t d = kl + ku;
            for (Py_ssize_t i = 0; i < n; i++)
                rs[i] = chk[i] = 0.0;
            row0[0] = 0;
            for (Py_ssize_t j = 0; j < n; j++) {
                const double *mj = M + j * nrow;
                row0[j + 1] = list_nonzero(mj, nrow, nz, row0[j]);
                Py_ssize_t c0 = d - j > 0 ? d - j : 0, c1 = n + d - j < nrow ? n + d - j : nrow;
                for (Py_ssize_t u = row0[j]; u < row0[j + 1]; u++) {
                    Py_ssize_t c = nz[u];
                    if (c < c0 || c >= c1)
                        continue;
                    double a = fabs(mj[c]);
                    Py_ssize_t i = j + c - d;
                    rs[i] = a > rs[i] ? a : rs[i];
                    chk[i] += a - a;
                }
            }
            for (Py_ssize_t i = 0; i < n; i++)
                rs[i] = scale_of(rs[i], chk[i]);
            for (Py_ssize_t j = 0; j < n; j++) {
                double *mj = M + j * nrow;
                Py_ssize_t c0 = d - j > 0 ? d - j : 0, c1 = n + d - j < nrow ? n + d - j : nrow;
                double m = 0.0;
                int bad = 0;
                for (Py_ssize_t u = row0[j]; u < row0[j + 1]; u++) {
                    Py_ssize_t c = nz[u];
                    if (c >= c0 && c < c1)
                        mj[c] *= rs[j + c - d];
                    double a = fabs(mj[c]);
                    m = a > m ? a : m;
                    bad |= !(a <= DBL_MAX);
                }
                double sc = bad ? 1.0 : pow2_scale(m);
                for (Py_ssize_t u = row0[j]; u < row0[j + 1]; u++)
                    mj[nz[u]] *= sc;
                cs[j] = sc;
            }
        } else if (nz && row0) {
            /* the dense matrix's nonzero entries listed once (a time step's coupled matrix: 6 %), the
             * scales from them and only they scaled: the same scales and the same scaled matrix (a zero
             * entry neither raises a maximum nor changes when scaled by a power of 2) */
            double *cm = cs, *ck = chk;
            row0[0] = 0;
            for (Py_ssize_t i = 0; i < n; i++) {
                int bad;
                double m = absmax_nonzero(M + i * n, n, nz, row0[i], &row0[i + 1], &bad);
                rs[i] = bad ? 1.0 : pow2_scale(m);
            }
            for (Py_ssize_t j = 0; j < n; j++)
                cm[j] = ck[j] = 0.0;
            for (Py_ssize_t i = 0; i < n; i++) {
                double *ri = M + i * n, r = rs[i];
                for (Py_ssize_t u = row0[i]; u < row0[i + 1]; u++) {
                    int j = nz[u];
                    double a = fabs(ri[j] *= r);
                    cm[j] = a > cm[j] ? a : cm[j];
                    ck[j] += a - a;
                }
            }
            for (Py_ssize_t j = 0; j < n; j++)
                cs[j] = scale_of(cm[j], ck[j]);
            for (Py_ssize_t i = 0; i < n; i++) {
                double *ri = M + i * n;
                for (Py_ssize_t u = row0[i]; u < row0[i + 1]; u++)
                    ri[nz[u]] *= cs[nz[u]];
            }
        } else if (kl < 0) {
            for (Py_ssize_t i = 0; i < n; i++) {
                int bad;
                double m = absmax(M + i * n, n, &bad);
                rs[i] = bad ? 1.0 : pow2_scale(m);
            }
            for (Py_ssize_t j = 0; j < n; j++)
                cs[j] = chk[j] = 0.0;
            for (Py_ssize_t i = 0; i < n; i++)
                scale_row(M + i * n, rs[i], cs, chk, n);
            for (Py_ssize_t j = 0; j < n; j++)
                cs[j] = scale_of(cs[j], chk[j]);
            for (Py_ssize_t i = 0; i < n; i++) {
                double *restrict ri = M + i * n;
                const double *restrict c = cs;
                for (Py_ssize_t j = 0; j < n; j++)
                    ri[j] *= c[j];
            }
        } else {
            Py_ssize_t d = kl + ku;
            for (Py_ssize_t i = 0; i < n; i++)
                rs[i] = chk[i] = 0.0;
            /* M[j, c] is A[j + c - d, j]: the rows' largest entries (the places outside A excluded) */
            for (Py_ssize_t j = 0; j < n; j++) {
                const double *mj = M + j * nrow;
                Py_ssize_t c0 = d - j > 0 ? d - j : 0, c1 = n + d - j < nrow ? n + d - j : nrow;
                for (Py_ssize_t c = c0; c < c1; c++) {
                    double a = fabs(mj[c]);
                    Py_ssize_t i = j + c - d;
                    rs[i] = a > rs[i] ? a : rs[i];
                    chk[i] += a - a;
                }
            }
            for (Py_ssize_t i = 0; i < n; i++)
                rs[i] = scale_of(rs[i], chk[i]);
            for (Py_ssize_t j = 0; j < n; j++) {
                double *mj = M + j * nrow;
                int bad;
                Py_ssize_t c0 = d - j > 0 ? d - j : 0, c1 = n + d - j < nrow ? n + d - j : nrow;
                for (Py_ssize_t c = c0; c < c1; c++)
                    mj[c] *= rs[j + c - d];
                double m = absmax(mj, nrow, &bad);
                double sc = bad ? 1.0 : pow2_scale(m);
                for (Py_ssize_t c = 0; c < nrow; c++)
                    mj[c] *= sc;
                cs[j] = sc;
            }
        }
        Py_INCREF(Py_None);
        res = Py_None;
    }
out:
    PyMem_Free(chk);
    PyMem_Free(row0);
    release(&bm);
    release(&br);
    release(&bc);
    return res;
}

/* -- the inertia of k states ----------------------------------------------------------------------------- */

/* inertia(Q, V, ACC, G, node_dofs, node_vals, body_d, body_data, F, base, mass, vel):
 * femslide.model.mass.Masses.inertia_parts in one call, the same arithmetic in the same order (bitwise the
 * same results on a machine without fused multiply-add): Q, V, ACC (k, n_q); G (k, 2) base accelerations or
 * None; node_dofs (nn,) int64 and node_vals (nn,) the lumped masses (the first half x dofs, then y);
 * body_d (nb,) int64 the bodies' first dofs, body_data (nb, 4): m, J, rho0_x, rho0_y; outputs F (k, n_q)
 * (overwritten), base, mass, vel (k, nn + 9 nb) */
static PyObject *py_inertia(PyObject *mod, PyObject *args)
{
    PyObject *o[12];
    if (!PyArg_ParseTuple(args, "OOOOOOOOOOOO", &o[0], &o[1], &o[2], &o[3], &o[4], &o[5], &o[6], &o[7], &o[8],
                          &o[9], &o[10], &o[11]))
        return NULL;
    static const char *what[12] = {"Q", "V", "ACC", "ground", "node dofs", "node masses", "body dofs",
                                   "body data", "F", "base", "mass", "vel"};
    Buf b[12];
    PyObject *res = NULL;
    if (get_all(o, b, 12, "ddddididwwww", what) < 0)
        goto out;
    {
        Py_ssize_t nn = LEN(b[5]), nb = LEN(b[6]), nnz = nn + 9 * nb, nF = LEN(b[8]);
        Py_ssize_t k = nnz > 0 ? LEN(b[9]) / nnz : 0;
        Py_ssize_t nq = k > 0 ? nF / k : 0;
        if (k <= 0 || nq * k != nF || LEN(b[0]) != nF || LEN(b[1]) != nF || LEN(b[2]) != nF ||
            (b[3].held && LEN(b[3]) != 2 * k) || LEN(b[4]) != nn || LEN(b[7]) != 4 * nb || LEN(b[9]) != k * nnz ||
            LEN(b[10]) != k * nnz || LEN(b[11]) != k * nnz) {
            PyErr_SetString(PyExc_ValueError, "femslide kernel: inertia: wrong sizes");
            goto out;
        }
        const long long *nd = IDX(b[4]), *bd = IDX(b[6]);
        for (Py_ssize_t i = 0; i < nn; i++)
            if (nd[i] < 0 || nd[i] >= nq) {
                PyErr_SetString(PyExc_IndexError, "femslide kernel: inertia: node dof out of range");
                goto out;
            }
        for (Py_ssize_t i = 0; i < nb; i++)
            if (bd[i] < 0 || bd[i] + 2 >= nq) {
                PyErr_SetString(PyExc_IndexError, "femslide kernel: inertia: body dof out of range");
                goto out;
            }
        const double *nv = DBL(b[5]), *bdat = DBL(b[7]), *G = b[3].held ? DBL(b[3]) : NULL;
        Py_ssize_t half = nn / 2;
        for (Py_ssize_t s = 0; s < k; s++) {
            const double *q = DBL(b[0]) + s * nq, *v = DBL(b[1]) + s * nq, *acc = DBL(b[2]) + s * nq;
            double *F = DBL(b[8]) + s * nq, *bs = DBL(b[9]) + s * nnz, *ms = DBL(b[10]) + s * nnz,
                   *vs = DBL(b[11]) + s * nnz;
            double gx = G ? G[2 * s] : 0.0, gy = G ? G[2 * s + 1] : 0.0;
            for (Py_ssize_t i = 0; i < nq; i++)
                F[i] = 0.0;
            for (Py_ssize_t i = 0; i < nn; i++) {
                F[nd[i]] = nv[i] * acc[nd[i]];
                if (G)
                    F[nd[i]] += nv[i] * (i < half ? gx : gy);
                bs[i] = 0.0;
                ms[i] = nv[i];
                vs[i] = 0.0;
            }
            for (Py_ssize_t j = 0; j < nb; j++) {
                Py_ssize_t d = bd[j], o = nn + 9 * j;
                double m = bdat[4 * j], J = bdat[4 * j + 1], rx = bdat[4 * j + 2], ry = bdat[4 * j + 3];
                double th = q[d + 2], c = cos(th), sn = sin(th);
                double px = c * rx - sn * ry, py = sn * rx + c * ry;
                double ux = acc[d] + gx, uy = acc[d + 1] + gy, tdd = acc[d + 2];
                double td = v[d + 2], td2 = td * td;
                double ax = ux - tdd * py - td2 * px;
                double ay = uy + tdd * px - td2 * py;
                F[d] += m * ax;
                F[d + 1] += m * ay;
                F[d + 2] += J * tdd + m * (px * ay - py * ax);
                double b2 = m * (td2 * py - tdd * px), b5 = m * (-(tdd * py) - td2 * px);
                double b8 = -(m * (px * ux + py * uy));
                for (int e = 0; e < 9; e++)
                    bs[o + e] = vs[o + e] = 0.0;
                bs[o + 2] = b2;
                bs[o + 5] = b5;
                bs[o + 8] = b8;
                ms[o] = ms[o + 4] = m;
                ms[o + 1] = ms[o + 3] = 0.0;
                ms[o + 2] = ((-m) * py + b2) - b2;
                ms[o + 5] = (m * px + b5) - b5;
                ms[o + 6] = (-m) * py;
                ms[o + 7] = m * px;
                ms[o + 8] = ((J + m * (px * px + py * py)) + b8) - b8;
                vs[o + 2] = m * ((-2.0 * td) * px - tdd * px + td2 * py) - b2;
                vs[o + 5] = m * ((-2.0 * td) * py - tdd * py - td2 * px) - b5;
            }
        }
        Py_INCREF(Py_None);
        res = Py_None;
    }
out:
    release_all(b, 12);
    return res;
}

/* -- the coupled matrix of a Radau step ------------------------------------------------------------------ */

/* coupled(out, flat, parts, mass, vel, w2, w1, cblocks): femslide.analysis.radau's coupled Newton matrix written
 * into its storage out (dense (n, n) or the band's (n, 2 kl + ku + 1), zeroed here) through the pattern's
 * flat map: the values in the pattern's order are the 1-d arrays of the list parts (the stages' model,
 * inertia and friction entries), then for the blocks (i, j) of the stages, w2[i, j] mass[i] + w1[i, j] vel[i]
 * (mass, vel (3, k)) followed by cblocks[i, j] ((3, 3, kc) or None); each value added at its place in
 * that order (numpy's bincount: the same sums) */
static PyObject *py_coupled(PyObject *mod, PyObject *args)
{
    PyObject *oout, *oflat, *oparts, *omass, *ovel, *ow2, *ow1, *oc;
    if (!PyArg_ParseTuple(args, "OOOOOOOO", &oout, &oflat, &oparts, &omass, &ovel, &ow2, &ow1, &oc))
        return NULL;
    PyObject *seq = PySequence_Fast(oparts, "femslide kernel: coupled: parts must be a sequence");
    if (!seq)
        return NULL;
    Buf bo, bf, bm, bv, b2, b1, bc;
    bo.held = bf.held = bm.held = bv.held = b2.held = b1.held = bc.held = 0;
    PyObject *res = NULL;
    if (get_buf(oout, &bo, 1, "d", 8, "storage") < 0 || get_buf(oflat, &bf, 0, "qlLn", 8, "flat") < 0 ||
        get_buf(omass, &bm, 0, "d", 8, "mass") < 0 || get_buf(ovel, &bv, 0, "d", 8, "vel") < 0 ||
        get_buf(ow2, &b2, 0, "d", 8, "w2") < 0 || get_buf(ow1, &b1, 0, "d", 8, "w1") < 0 ||
        get_buf(oc, &bc, 0, "d", 8, "cblocks") < 0)
        goto out;
    {
        Py_ssize_t np_ = PySequence_Fast_GET_SIZE(seq), k = LEN(bm) / 3, kc = LEN(bc) / 9, len = LEN(bo);
        if (LEN(bm) != 3 * k || LEN(bv) != 3 * k || LEN(b2) != 9 || LEN(b1) != 9 || LEN(bc) != 9 * kc) {
            PyErr_SetString(PyExc_ValueError, "femslide kernel: coupled: wrong sizes");
            goto out;
        }
        double *A = DBL(bo);
        const long long *flat = IDX(bf);
        Py_ssize_t nf = LEN(bf), p = 0;
        memset(A, 0, bo.view.len);
        for (Py_ssize_t q = 0; q < np_; q++) {
            Buf bp;
            if (get_buf(PySequence_Fast_GET_ITEM(seq, q), &bp, 0, "d", 8, "part") < 0)
                goto out;
            Py_ssize_t m = LEN(bp);
            const double *v = DBL(bp);
            if (p + m > nf) {
                release(&bp);
                PyErr_SetString(PyExc_ValueError, "femslide kernel: coupled: more values than the pattern");
                goto out;
            }
            for (Py_ssize_t e = 0; e < m; e++, p++) {
                long long f = flat[p];
                if (f < 0 || f >= len) {
                    release(&bp);
                    PyErr_SetString(PyExc_IndexError, "femslide kernel: coupled: flat map out of range");
                    goto out;
                }
                A[f] += v[e];
            }
            release(&bp);
        }
        if (p + 9 * (k + kc) != nf) {
            PyErr_SetString(PyExc_ValueError, "femslide kernel: coupled: the values do not fill the pattern");
            goto out;
        }
        for (Py_ssize_t e = p; e < nf; e++)
            if (flat[e] < 0 || flat[e] >= len) {
                PyErr_SetString(PyExc_IndexError, "femslide kernel: coupled: flat map out of range");
                goto out;
            }
        const double *M = DBL(bm), *V = DBL(bv), *w2 = DBL(b2), *w1 = DBL(b1), *C = bc.held ? DBL(bc) : NULL;
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) {
                double a = w2[3 * i + j], b = w1[3 * i + j];
                const double *mi = M + i * k, *vi = V + i * k;
                for (Py_ssize_t e = 0; e < k; e++, p++)
                    A[flat[p]] += a * mi[e] + b * vi[e];
                if (C) {
                    const double *cij = C + (3 * i + j) * kc;
                    for (Py_ssize_t e = 0; e < kc; e++, p++)
                        A[flat[p]] += cij[e];
                }
            }
        Py_INCREF(Py_None);
        res = Py_None;
    }
out:
    Py_DECREF(seq);
    release(&bo);
    release(&bf);
    release(&bm);
    release(&bv);
    release(&b2);
    release(&b1);
    release(&bc);
    return res;
}

/* 0, or -1 with IndexError when a COO entry (rows[e], cols[e]) lies outside an m x m matrix */
static int check_coo(const long long *rows, const long long *cols, Py_ssize_t k, Py_ssize_t m, const char *who)
{
    for (Py_ssize_t e = 0; e < k; e++)
        if (rows[e] < 0 || rows[e] >= m || cols[e] < 0 || cols[e] >= m) {
            PyErr_Format(PyExc_IndexError, "femslide kernel: %s: index out of range", who);
            return -1;
        }
    return 0;
}

/* the right-hand side of coupled_rhs (below) with its index checks done; acc: 2 * 3 nq zeros (scratch) */
static void rhs_core(const double *r, const double *wrq, double h, const long long *cr, const long long *cc,
                     const double *cv, Py_ssize_t kc, const long long *mr, const long long *mc, const double *mv,
                     Py_ssize_t km, Py_ssize_t nq, Py_ssize_t nc, double *acc, double *rhs)
{
    Py_ssize_t m3 = 3 * nq;
    const double *rq = r + m3;
    double *cp = acc, *mp = acc + m3, hh = h * h;
    for (Py_ssize_t e = 0; e < kc; e++)
        cp[cr[e]] += cv[e] * rq[cc[e]];
    for (Py_ssize_t e = 0; e < km; e++)
        mp[mr[e]] += mv[e] * wrq[mc[e]];
    for (int i = 0; i < 3; i++) {
        double *ri = rhs + i * (nq + nc);
        for (Py_ssize_t d = 0; d < nq; d++) {
            Py_ssize_t p = i * nq + d;
            ri[d] = r[p] + cp[p] / h + mp[p] / hh;
        }
        for (Py_ssize_t c = 0; c < nc; c++)
            ri[nq + c] = r[2 * m3 + i * nc + c];
    }
}

/* coupled_rhs(r, wrq, h, cr, cc, cv, mr, mc, mv, nq, rhs): the right-hand side of femslide.analysis.radau's
 * coupled Newton system for the stacked residual r = [Rv (3 nq), Rq (3 nq), Rm (3 nc)] with the velocity
 * corrections eliminated: rhs (3, nq + nc) with rhs[i, :nq] = Rv_i + (C Rq)_i / h + (M wrq)_i / h^2 and
 * rhs[i, nq:] = Rm_i, the products over the COO entries (cr, cc, cv), (mr, mc, mv) of the three stages
 * stacked (rows and columns in 0 .. 3 nq), each row's terms summed in their order (numpy's bincount) */
static PyObject *py_coupled_rhs(PyObject *mod, PyObject *args)
{
    PyObject *o[11];
    double h;
    Py_ssize_t nq;
    if (!PyArg_ParseTuple(args, "OOdOOOOOOnO", &o[0], &o[1], &h, &o[3], &o[4], &o[5], &o[6], &o[7], &o[8], &nq,
                          &o[10]))
        return NULL;
    o[2] = o[9] = NULL;
    static const char *what[11] = {"r", "wrq", "", "cr", "cc", "cv", "mr", "mc", "mv", "", "rhs"};
    Buf b[11];
    PyObject *res = NULL;
    double *acc = NULL;
    if (get_all(o, b, 11, "dd-iidiid-w", what) < 0)
        goto out;
    {
        Py_ssize_t m3 = 3 * nq, n = LEN(b[0]), nc3 = n - 2 * m3, nc = nc3 / 3, kc = LEN(b[3]), km = LEN(b[6]);
        if (nq < 0 || nc3 < 0 || nc * 3 != nc3 || LEN(b[1]) != m3 || LEN(b[4]) != kc || LEN(b[5]) != kc ||
            LEN(b[7]) != km || LEN(b[8]) != km || LEN(b[10]) != 3 * (nq + nc)) {
            PyErr_SetString(PyExc_ValueError, "femslide kernel: coupled_rhs: wrong sizes");
            goto out;
        }
        const long long *cr = IDX(b[3]), *cc = IDX(b[4]), *mr = IDX(b[6]), *mc = IDX(b[7]);
        if (check_coo(cr, cc, kc, m3, "coupled_rhs") < 0 || check_coo(mr, mc, km, m3, "coupled_rhs") < 0)
            goto out;
        acc = PyMem_Calloc(2 * m3 + 1, sizeof(double));
        if (!acc) {
            PyErr_NoMemory();
            goto out;
        }
        rhs_core(DBL(b[0]), DBL(b[1]), h, cr, cc, DBL(b[5]), kc, mr, mc, DBL(b[8]), km, nq, nc, acc, DBL(b[10]));
        Py_INCREF(Py_None);
        res = Py_None;
    }
out:
    PyMem_Free(acc);
    release_all(b, 11);
    return res;
}

/* out_i = w_i0 z_0 + w_i1 z_1 + w_i2 z_2 for the three rows z (3, m) of W z, w (3, 3): the sums in that
 * order (femslide.analysis.radau._w_times, numpy's path) */
static void w_times(const double *w, const double *z, Py_ssize_t m, double *out)
{
    for (int i = 0; i < 3; i++) {
        double a = w[3 * i], b = w[3 * i + 1], c = w[3 * i + 2];
        double *o = out + i * m;
        for (Py_ssize_t d = 0; d < m; d++)
            o[d] = (a * z[d] + b * z[m + d]) + c * z[2 * m + d];
    }
}

/* stages(Y, qn, v, w, h, Q, Ys, V, ACC): the stage states of femslide.analysis.radau.RadauSystem.system from
 * its unknowns Y = [ZQ (3, nq), ZV (3, nq), MU (3, nc)]: Q_i = qn + ZQ_i, Ys_i = [Q_i, MU_i] (3, nq + nc),
 * V_i = v + ZV_i, ACC = (w ZV) / h (w (3, 3) = A^-1: _w_times' sums); nq = len(qn), nc from Y's size */
static PyObject *py_stages(PyObject *mod, PyObject *args)
{
    PyObject *o[9];
    double h;
    if (!PyArg_ParseTuple(args, "OOOOdOOOO", &o[0], &o[1], &o[2], &o[3], &h, &o[5], &o[6], &o[7], &o[8]))
        return NULL;
    o[4] = NULL;
    static const char *what[9] = {"Y", "qn", "v", "w", "", "Q", "Ys", "V", "ACC"};
    Buf b[9];
    PyObject *res = NULL;
    if (get_all(o, b, 9, "dddd-wwww", what) < 0)
        goto out;
    {
        Py_ssize_t nq = LEN(b[1]), m3 = 3 * nq, nc3 = LEN(b[0]) - 2 * m3, nc = nc3 / 3;
        if (nc3 < 0 || 3 * nc != nc3 || LEN(b[2]) != nq || LEN(b[3]) != 9 || LEN(b[5]) != m3 ||
            LEN(b[6]) != 3 * (nq + nc) || LEN(b[7]) != m3 || LEN(b[8]) != m3) {
            PyErr_SetString(PyExc_ValueError, "femslide kernel: stages: wrong sizes");
            goto out;
        }
        const double *Y = DBL(b[0]), *qn = DBL(b[1]), *v = DBL(b[2]);
        double *Q = DBL(b[5]), *Ys = DBL(b[6]), *V = DBL(b[7]), *ACC = DBL(b[8]);
        for (int i = 0; i < 3; i++) {
            const double *zq = Y + i * nq, *zv = Y + m3 + i * nq, *mu = Y + 2 * m3 + i * nc;
            double *q = Q + i * nq, *ys = Ys + i * (nq + nc), *vi = V + i * nq;
            for (Py_ssize_t d = 0; d < nq; d++) {
                q[d] = qn[d] + zq[d];
                ys[d] = q[d];
                vi[d] = v[d] + zv[d];
            }
            for (Py_ssize_t c = 0; c < nc; c++)
                ys[nq + c] = mu[c];
        }
        w_times(DBL(b[3]), Y + m3, nq, ACC);
        for (Py_ssize_t d = 0; d < m3; d++)
            ACC[d] /= h;
        Py_INCREF(Py_None);
        res = Py_None;
    }
out:
    release_all(b, 9);
    return res;
}

/* stage_rows(parts, F, Y, V, w, h, r): the stacked stage residual of femslide.analysis.radau.RadauSystem.system,
 * r = [forces (3, nq), h x kinematics (3, nq), constraints (3, nc)], from the stages' model residuals parts
 * (3 arrays of nq + nc), their inertia F (3, nq), the unknowns Y = [ZQ, ZV, MU] and the stage velocities V:
 * forces_i = part_i[:nq] + F_i, kinematics = w ZQ - h V (_w_times' sums), constraints_i = part_i[nq:] */
static PyObject *py_stage_rows(PyObject *mod, PyObject *args)
{
    PyObject *oparts, *o[7];
    double h;
    if (!PyArg_ParseTuple(args, "OOOOOdO", &oparts, &o[1], &o[2], &o[3], &o[4], &h, &o[6]))
        return NULL;
    PyObject *seq = PySequence_Fast(oparts, "femslide kernel: stage_rows: parts must be a sequence");
    if (!seq)
        return NULL;
    static const char *what[7] = {"", "F", "Y", "V", "w", "", "r"};
    Buf b[7], bp[3];
    for (int i = 0; i < 3; i++)
        bp[i].held = 0;
    PyObject *res = NULL;
    if (get_all(o, b, 7, "-dddd-w", what) < 0)
        goto out;
    if (PySequence_Fast_GET_SIZE(seq) != 3) {
        PyErr_SetString(PyExc_ValueError, "femslide kernel: stage_rows: three parts expected");
        goto out;
    }
    for (int i = 0; i < 3; i++)
        if (get_buf(PySequence_Fast_GET_ITEM(seq, i), &bp[i], 0, "d", 8, "part") < 0)
            goto out;
    {
        Py_ssize_t m3 = LEN(b[1]), nq = m3 / 3, n = LEN(b[6]), nc3 = n - 2 * m3, nc = nc3 / 3;
        int bad = 3 * nq != m3 || nc3 < 0 || 3 * nc != nc3 || LEN(b[2]) != n || LEN(b[3]) != m3 || LEN(b[4]) != 9;
        for (int i = 0; i < 3; i++)
            bad |= LEN(bp[i]) != nq + nc;
        if (bad) {
            PyErr_SetString(PyExc_ValueError, "femslide kernel: stage_rows: wrong sizes");
            goto out;
        }
        const double *F = DBL(b[1]), *Y = DBL(b[2]), *V = DBL(b[3]);
        double *r = DBL(b[6]);
        for (int i = 0; i < 3; i++) {
            const double *p = DBL(bp[i]), *f = F + i * nq;
            double *rf = r + i * nq, *rc = r + 2 * m3 + i * nc;
            for (Py_ssize_t d = 0; d < nq; d++)
                rf[d] = p[d] + f[d];
            for (Py_ssize_t c = 0; c < nc; c++)
                rc[c] = p[nq + c];
        }
        double *rk = r + m3;
        w_times(DBL(b[4]), Y, nq, rk);
        for (Py_ssize_t d = 0; d < m3; d++)
            rk[d] -= h * V[d];
        Py_INCREF(Py_None);
        res = Py_None;
    }
out:
    Py_DECREF(seq);
    release_all(b, 7);
    release_all(bp, 3);
    return res;
}

/* coupled_solve(r, h, w, cr, cc, cv, mr, mc, mv, lu, piv, kl, ku, perm, rs, cs, out): femslide.analysis.radau.
 * CoupledMatrix.solve in one call: the Newton correction out (the stacked unknowns [dQ (3, nq), dV (3, nq),
 * dMU (3, nc)]) for the stacked residual r with the coupled matrix's factors (factor(): lu, piv, kl, ku;
 * kl < 0 dense) and its scales rs, cs (equilibrate()), perm the band's ordering (None: dense): wrq = w Rq,
 * rhs as coupled_rhs, x = cs * LU^-1 (rs * rhs[perm]) placed back at perm, dQ and dMU its rows and
 * dV = (w dQ - Rq) / h (_w_times' sums); nq and nc from the sizes: len(r) = 6 nq + 3 nc, len(rs) = 3 (nq + nc) */
static PyObject *py_coupled_solve(PyObject *mod, PyObject *args)
{
    PyObject *o[17];
    double h;
    Py_ssize_t kl, ku;
    if (!PyArg_ParseTuple(args, "OdOOOOOOOOOnnOOOO", &o[0], &h, &o[2], &o[3], &o[4], &o[5], &o[6], &o[7], &o[8],
                          &o[9], &o[10], &kl, &ku, &o[13], &o[14], &o[15], &o[16]))
        return NULL;
    o[1] = o[11] = o[12] = NULL;
    static const char *what[17] = {"r", "", "w", "cr", "cc", "cv", "mr", "mc", "mv", "factors", "pivots", "", "",
                                   "perm", "rs", "cs", "out"};
    Buf b[17];
    PyObject *res = NULL;
    double *work = NULL;
    if (get_all(o, b, 17, "d-diidiiddp--iddw", what) < 0)
        goto out;
    {
        Py_ssize_t n = LEN(b[0]), N = LEN(b[14]), kc = LEN(b[3]), km = LEN(b[6]);
        /* n = 6 nq + 3 nc, N = 3 (nq + nc): nq = (n - N) / 3 */
        Py_ssize_t nq = (n - N) / 3, nc = N / 3 - nq, m3 = 3 * nq;
        if (nq < 0 || nc < 0 || 3 * nq != n - N || 3 * (nq + nc) != N || LEN(b[2]) != 9 || LEN(b[4]) != kc ||
            LEN(b[5]) != kc || LEN(b[7]) != km || LEN(b[8]) != km || LEN(b[10]) != N || LEN(b[15]) != N ||
            LEN(b[16]) != n || (b[13].held && LEN(b[13]) != N) || (kl < 0) != !b[13].held ||
            (kl < 0 ? LEN(b[9]) != N * N : (ku < 0 || LEN(b[9]) != N * (2 * kl + ku + 1)))) {
            PyErr_SetString(PyExc_ValueError, "femslide kernel: coupled_solve: wrong sizes");
            goto out;
        }
        const long long *cr = IDX(b[3]), *cc = IDX(b[4]), *mr = IDX(b[6]), *mc = IDX(b[7]);
        if (check_coo(cr, cc, kc, m3, "coupled_solve") < 0 || check_coo(mr, mc, km, m3, "coupled_solve") < 0)
            goto out;
        const long long *perm = b[13].held ? IDX(b[13]) : NULL;
        const Py_ssize_t *piv = (const Py_ssize_t *)b[10].view.buf;
        if (perm)
            for (Py_ssize_t i = 0; i < N; i++)
                if (perm[i] < 0 || perm[i] >= N) {
                    PyErr_SetString(PyExc_IndexError, "femslide kernel: coupled_solve: perm out of range");
                    goto out;
                }
        for (Py_ssize_t i = 0; i < N; i++)
            if (piv[i] < 0 || piv[i] >= N) {
                PyErr_SetString(PyExc_IndexError, "femslide kernel: coupled_solve: pivot out of range");
                goto out;
            }
        /* scratch: wrq (m3), the products (2 m3), rhs (N), x (N), w dQ (m3) */
        work = PyMem_Calloc(4 * m3 + 2 * N + 1, sizeof(double));
        if (!work) {
            PyErr_NoMemory();
            goto out;
        }
        double *wrq = work, *acc = work + m3, *rhs = work + 3 * m3, *x = rhs + N, *wdq = x + N;
        const double *r = DBL(b[0]), *w = DBL(b[2]), *rs = DBL(b[14]), *cs = DBL(b[15]), *rq = r + m3;
        double *outv = DBL(b[16]);
        w_times(w, rq, nq, wrq);
        rhs_core(r, wrq, h, cr, cc, DBL(b[5]), kc, mr, mc, DBL(b[8]), km, nq, nc, acc, rhs);
        for (Py_ssize_t i = 0; i < N; i++)
            x[i] = rs[i] * rhs[perm ? perm[i] : i];
        if (kl < 0)
            lu_dense_solve(DBL(b[9]), N, piv, x);
        else
            lu_band_solve(DBL(b[9]), N, kl, ku, piv, x);
        /* x back in the stacked order: rhs := the solution */
        for (Py_ssize_t i = 0; i < N; i++)
            rhs[perm ? perm[i] : i] = cs[i] * x[i];
        for (int i = 0; i < 3; i++) {
            const double *xi = rhs + i * (nq + nc);
            for (Py_ssize_t d = 0; d < nq; d++)
                outv[i * nq + d] = xi[d];
            for (Py_ssize_t c = 0; c < nc; c++)
                outv[2 * m3 + i * nc + c] = xi[nq + c];
        }
        w_times(w, outv, nq, wdq);
        for (Py_ssize_t d = 0; d < m3; d++)
            outv[m3 + d] = (wdq[d] - rq[d]) / h;
        Py_INCREF(Py_None);
        res = Py_None;
    }
out:
    PyMem_Free(work);
    release_all(b, 17);
    return res;
}

/* error_rhs(Y, e, h, acc, v, lam, mr, mc, mv, cr, cc, cv, b, rq): the right-hand side of RADAU5's error estimate
 * (femslide.analysis.radau.RadauSystem.error): with ZQ, ZV the first two blocks (3, nq) of the step's unknowns Y,
 * zq = (e ZQ) / h and zv = (e ZV) / h (e (3,), summed in order), rq := v + zq (nq) and b (nq + nc) := [(M (acc + zv) +
 * C rq) + lam M rq, 0], the products over the COO entries (mr, mc, mv) and (cr, cc, cv) (rows and columns below nq),
 * each row's terms summed in their order (numpy's bincount) */
static PyObject *py_error_rhs(PyObject *mod, PyObject *args)
{
    PyObject *o[14];
    double h, lam;
    if (!PyArg_ParseTuple(args, "OOdOOdOOOOOOOO", &o[0], &o[1], &h, &o[3], &o[4], &lam, &o[6], &o[7], &o[8], &o[9],
                          &o[10], &o[11], &o[12], &o[13]))
        return NULL;
    o[2] = o[5] = NULL;
    static const char *what[14] = {"Y", "e", "", "acc", "v", "", "mr", "mc", "mv", "cr", "cc", "cv", "b", "rq"};
    Buf b[14];
    PyObject *res = NULL;
    double *x = NULL;
    if (get_all(o, b, 14, "dd-dd-iidiidww", what) < 0)
        goto out;
    {
        Py_ssize_t nq = LEN(b[4]), nb = LEN(b[12]), km = LEN(b[6]), kc = LEN(b[9]);
        if (LEN(b[0]) < 6 * nq || LEN(b[1]) != 3 || LEN(b[3]) != nq || nb < nq || LEN(b[13]) != nq ||
            LEN(b[7]) != km || LEN(b[8]) != km || LEN(b[10]) != kc || LEN(b[11]) != kc) {
            PyErr_SetString(PyExc_ValueError, "femslide kernel: error_rhs: wrong sizes");
            goto out;
        }
        const long long *mr = IDX(b[6]), *mc = IDX(b[7]), *cr = IDX(b[9]), *cc = IDX(b[10]);
        if (check_coo(mr, mc, km, nq, "error_rhs") < 0 || check_coo(cr, cc, kc, nq, "error_rhs") < 0)
            goto out;
        x = PyMem_Calloc(3 * nq + 1, sizeof(double));
        if (!x) {
            PyErr_NoMemory();
            goto out;
        }
        const double *Y = DBL(b[0]), *e = DBL(b[1]), *acc = DBL(b[3]), *v = DBL(b[4]), *mv = DBL(b[8]),
                     *cv = DBL(b[11]);
        double *bb = DBL(b[12]), *rq = DBL(b[13]), *p2 = x + nq, *p3 = x + 2 * nq;
        for (Py_ssize_t d = 0; d < nq; d++) {
            double zq = ((e[0] * Y[d] + e[1] * Y[nq + d]) + e[2] * Y[2 * nq + d]) / h;
            double zv = ((e[0] * Y[3 * nq + d] + e[1] * Y[4 * nq + d]) + e[2] * Y[5 * nq + d]) / h;
            rq[d] = v[d] + zq;
            x[d] = acc[d] + zv;
        }
        for (Py_ssize_t i = 0; i < nb; i++)
            bb[i] = 0.0;
        for (Py_ssize_t k = 0; k < km; k++) {
            bb[mr[k]] += mv[k] * x[mc[k]];
            p3[mr[k]] += mv[k] * rq[mc[k]];
        }
        for (Py_ssize_t k = 0; k < kc; k++)
            p2[cr[k]] += cv[k] * rq[cc[k]];
        for (Py_ssize_t d = 0; d < nq; d++)
            bb[d] = (bb[d] + p2[d]) + lam * p3[d];
        Py_INCREF(Py_None);
        res = Py_None;
    }
out:
    PyMem_Free(x);
    release_all(b, 14);
    return res;
}

/* -- the elements' end moments from the equilibrium of rod pieces, and their interior extrema ----------
 * (femslide.results.static.end_moments and _largest_inside, the same arithmetic in the same order:
 * numpy's cumsum is the sequential sum) */

/* cuts(X, g, first, ei, ej, M, G): M (n_el, 2) := the end moments, G (n_el, 2) := the middle forces of
 * femslide.results.static.end_moments (``resultant``); X (n_nodes, 2) the current node positions, g
 * (n_nodes, 3) the applied generalised forces, first (n_nodes) each node's rod start node */
static PyObject *py_cuts(PyObject *mod, PyObject *args)
{
    PyObject *ox, *og, *of, *oi, *oj, *om, *oG;
    if (!PyArg_ParseTuple(args, "OOOOOOO", &ox, &og, &of, &oi, &oj, &om, &oG))
        return NULL;
    Buf bx, bg, bf, bi, bj, bm, bG;
    bx.held = bg.held = bf.held = bi.held = bj.held = bm.held = bG.held = 0;
    PyObject *res = NULL;
    double *S = NULL;
    if (get_buf(ox, &bx, 0, "d", 8, "X") < 0 || get_buf(og, &bg, 0, "d", 8, "g") < 0 ||
        get_buf(of, &bf, 0, "qlLn", 8, "first") < 0 || get_buf(oi, &bi, 0, "qlLn", 8, "ei") < 0 ||
        get_buf(oj, &bj, 0, "qlLn", 8, "ej") < 0 || get_buf(om, &bm, 1, "d", 8, "M") < 0 ||
        get_buf(oG, &bG, 1, "d", 8, "G") < 0)
        goto out;
    {
        Py_ssize_t nn = LEN(bf), ne = LEN(bi);
        if (LEN(bx) != 2 * nn || LEN(bg) < 3 * nn || LEN(bj) != ne || LEN(bm) != 2 * ne || LEN(bG) != 2 * ne) {
            PyErr_SetString(PyExc_ValueError, "femslide kernel: cuts: wrong sizes");
            goto out;
        }
        const double *X = DBL(bx), *g = DBL(bg);
        const long long *first = IDX(bf), *I = IDX(bi), *J = IDX(bj);
        double *M = DBL(bm), *G = DBL(bG);
        S = PyMem_Malloc(sizeof(double) * (6 * nn + 1));   /* cumulative sums, then the rows */
        if (!S) {
            PyErr_NoMemory();
            goto out;
        }
        double *R = S + 3 * nn;
        double c0 = 0.0, c1 = 0.0, c2 = 0.0;
        for (Py_ssize_t k = 0; k < nn; k++) {
            long long f = first[k];
            if (f < 0 || f >= nn) {
                PyErr_SetString(PyExc_IndexError, "femslide kernel: cuts: node index out of range");
                goto out;
            }
            double xr = X[2 * k] - X[2 * f], yr = X[2 * k + 1] - X[2 * f + 1];
            R[3 * k] = g[3 * k];
            R[3 * k + 1] = g[3 * k + 1];
            R[3 * k + 2] = g[3 * k + 2] + (xr * g[3 * k + 1] - yr * g[3 * k]);
            c0 += R[3 * k];
            c1 += R[3 * k + 1];
            c2 += R[3 * k + 2];
            S[3 * k] = c0;
            S[3 * k + 1] = c1;
            S[3 * k + 2] = c2;
        }
        for (Py_ssize_t e = 0; e < ne; e++) {
            long long i = I[e], j = J[e];
            if (i < 0 || i >= nn || j < 0 || j >= nn) {
                PyErr_SetString(PyExc_IndexError, "femslide kernel: cuts: node index out of range");
                goto out;
            }
            long long f = first[i];
            double C0 = S[3 * i] - (S[3 * f] - R[3 * f]);
            double C1 = S[3 * i + 1] - (S[3 * f + 1] - R[3 * f + 1]);
            double C2 = S[3 * i + 2] - (S[3 * f + 2] - R[3 * f + 2]);
            double xi = X[2 * i] - X[2 * f], yi = X[2 * i + 1] - X[2 * f + 1];
            long long fj = first[j];
            if (fj < 0 || fj >= nn) {
                PyErr_SetString(PyExc_IndexError, "femslide kernel: cuts: node index out of range");
                goto out;
            }
            double xj = X[2 * j] - X[2 * fj], yj = X[2 * j + 1] - X[2 * fj + 1];
            double dx = xi - xj, dy = yi - yj;
            double m0 = xi * C1 - yi * C0 - C2;
            M[2 * e] = m0;
            M[2 * e + 1] = dx * C1 - dy * C0 - m0;
            G[2 * e] = C0;
            G[2 * e + 1] = C1;
        }
        Py_INCREF(Py_None);
        res = Py_None;
    }
out:
    PyMem_Free(S);
    release(&bx);
    release(&bg);
    release(&bf);
    release(&bi);
    release(&bj);
    release(&bm);
    release(&bG);
    return res;
}

/* inside(X, U, ei, ej, beta0, alpha, M, G) -> max |M| at the ends and interior extrema of the elements'
 * cubic moments (femslide.results.static._largest_inside; alpha None: zero); NaN if any is NaN */
static PyObject *py_inside(PyObject *mod, PyObject *args)
{
    PyObject *ox, *ou, *oi, *oj, *ob, *oa, *om, *oG;
    if (!PyArg_ParseTuple(args, "OOOOOOOO", &ox, &ou, &oi, &oj, &ob, &oa, &om, &oG))
        return NULL;
    Buf bx, bu, bi, bj, bb, ba, bm, bG;
    bx.held = bu.held = bi.held = bj.held = bb.held = ba.held = bm.held = bG.held = 0;
    PyObject *res = NULL;
    if (get_buf(ox, &bx, 0, "d", 8, "X") < 0 || get_buf(ou, &bu, 0, "d", 8, "U") < 0 ||
        get_buf(oi, &bi, 0, "qlLn", 8, "ei") < 0 || get_buf(oj, &bj, 0, "qlLn", 8, "ej") < 0 ||
        get_buf(ob, &bb, 0, "d", 8, "beta0") < 0 || get_buf(oa, &ba, 0, "d", 8, "alpha") < 0 ||
        get_buf(om, &bm, 0, "d", 8, "M") < 0 || get_buf(oG, &bG, 0, "d", 8, "G") < 0)
        goto out;
    {
        Py_ssize_t nn = LEN(bx) / 2, ne = LEN(bi);
        if (LEN(bu) < 3 * nn || LEN(bj) != ne || LEN(bb) != ne || (ba.held && LEN(ba) != ne) ||
            LEN(bm) != 2 * ne || LEN(bG) != 2 * ne) {
            PyErr_SetString(PyExc_ValueError, "femslide kernel: inside: wrong sizes");
            goto out;
        }
        const double *X = DBL(bx), *U = DBL(bu), *b0 = DBL(bb), *al = ba.held ? DBL(ba) : NULL;
        const double *M = DBL(bm), *G = DBL(bG);
        const long long *I = IDX(bi), *J = IDX(bj);
        double top = 0.0;
        int nan = 0;
        for (Py_ssize_t e = 0; e < ne; e++) {
            long long i = I[e], j = J[e];
            if (i < 0 || i >= nn || j < 0 || j >= nn) {
                PyErr_SetString(PyExc_IndexError, "femslide kernel: inside: node index out of range");
                goto out;
            }
            double Dx = X[2 * j] - X[2 * i], Dy = X[2 * j + 1] - X[2 * i + 1];
            double ref = al ? b0[e] + al[e] : b0[e];
            double cr = cos(ref), sr = sin(ref);
            double chord = ref + atan2(cr * Dy - sr * Dx, cr * Dx + sr * Dy) - b0[e];
            double t1 = U[3 * i + 2] - chord, t2 = U[3 * j + 2] - chord;
            double W = G[2 * e] * Dx + G[2 * e + 1] * Dy;
            double Ms = -M[2 * e];
            double a1 = (M[2 * e + 1] - Ms) + W * t1;
            double a2 = -W * (2.0 * t1 + t2);
            double a3 = W * (t1 + t2);
            double A = 3.0 * a3, B = 2.0 * a2;
            double disc = B * B - 4.0 * A * a1;
            double q = -0.5 * (B + copysign(sqrt(disc > 0.0 ? disc : 0.0), B));
            double r[2];
            r[0] = A != 0.0 ? q / A : 0.0;
            r[1] = q != 0.0 ? a1 / q : 0.0;
            for (int k = 0; k < 2; k++) {
                double x = r[k];
                if (x <= 0.0 || x >= 1.0 || disc < 0.0)
                    x = 0.0;
                double v = fabs(Ms + x * (a1 + x * (a2 + x * a3)));
                if (v > top)
                    top = v;
                else if (v != v)
                    nan = 1;
            }
        }
        res = PyFloat_FromDouble(nan ? NAN : top);
    }
out:
    release(&bx);
    release(&bu);
    release(&bi);
    release(&bj);
    release(&bb);
    release(&ba);
    release(&bm);
    release(&bG);
    return res;
}

/* prolong(a, b, nf, t, H, bet, X0c, yc, X0f, yf, ia, ib, ef, ec, beta0c, alpha, beta0f, af): the
 * interpolation of femslide.analysis.refine.prolong, the same arithmetic in the same order, over the
 * fine nodes of all rods (flattened plan: coarse end nodes a, b of each fine node's coarse element, the
 * fine node nf, its parameter t and Hermite weights H (4, n), the rod's chord angle bet) and the fine
 * elements ef (their nodes ia, ib, the coarse element ec at their middle): yf[:3 n_fine_nodes] := the
 * fine nodal dofs, af[ef] := the fine elements' chord rotations */
static PyObject *py_prolong(PyObject *mod, PyObject *args)
{
    PyObject *o[18];
    if (!PyArg_ParseTuple(args, "OOOOOOOOOOOOOOOOOO", &o[0], &o[1], &o[2], &o[3], &o[4], &o[5], &o[6], &o[7],
                          &o[8], &o[9], &o[10], &o[11], &o[12], &o[13], &o[14], &o[15], &o[16], &o[17]))
        return NULL;
    static const char *what[18] = {"a", "b", "nf", "t", "H", "bet", "X0c", "yc", "X0f", "yf", "ia", "ib", "ef",
                                   "ec", "beta0c", "alpha", "beta0f", "af"};
    Buf B[18];
    PyObject *res = NULL;
    if (get_all(o, B, 18, "iiiddddddwiiiidddw", what) < 0)
        goto out;
    {
        const long long *A = IDX(B[0]), *Bn = IDX(B[1]), *NF = IDX(B[2]);
        const double *t = DBL(B[3]), *H = DBL(B[4]), *bet = DBL(B[5]), *X0c = DBL(B[6]), *yc = DBL(B[7]);
        const double *X0f = DBL(B[8]);
        double *yf = DBL(B[9]);
        const long long *IA = IDX(B[10]), *IB = IDX(B[11]), *EF = IDX(B[12]), *EC = IDX(B[13]);
        const double *b0c = DBL(B[14]), *al = DBL(B[15]), *b0f = DBL(B[16]);
        double *af = DBL(B[17]);
        Py_ssize_t n = LEN(B[0]), ne = LEN(B[10]), ncn = LEN(B[6]) / 2, nfn = LEN(B[8]) / 2;
        Py_ssize_t nec = LEN(B[14]), nef = LEN(B[16]);
        if (LEN(B[1]) != n || LEN(B[2]) != n || LEN(B[3]) != n || LEN(B[4]) != 4 * n || LEN(B[5]) != n ||
            LEN(B[7]) < 3 * ncn || LEN(B[9]) < 3 * nfn || LEN(B[11]) != ne || LEN(B[12]) != ne ||
            LEN(B[13]) != ne || LEN(B[15]) != nec || LEN(B[17]) != nef) {
            PyErr_SetString(PyExc_ValueError, "femslide kernel: prolong: wrong sizes");
            goto out;
        }
        const double *H0 = H, *H1 = H + n, *H2 = H + 2 * n, *H3 = H + 3 * n;
        for (Py_ssize_t m = 0; m < n; m++) {
            long long a = A[m], b = Bn[m], f = NF[m];
            if (a < 0 || a >= ncn || b < 0 || b >= ncn || f < 0 || f >= nfn) {
                PyErr_SetString(PyExc_IndexError, "femslide kernel: prolong: node index out of range");
                goto out;
            }
            double Pax = X0c[2 * a] + yc[3 * a], Pay = X0c[2 * a + 1] + yc[3 * a + 1];
            double Pbx = X0c[2 * b] + yc[3 * b], Pby = X0c[2 * b + 1] + yc[3 * b + 1];
            double ga = bet[m] + yc[3 * a + 2], gb = bet[m] + yc[3 * b + 2];
            double Tax = cos(ga), Tay = sin(ga), Tbx = cos(gb), Tby = sin(gb);
            double px = H0[m] * Pax + H1[m] * Tax + H2[m] * Pbx + H3[m] * Tbx;
            double py = H0[m] * Pay + H1[m] * Tay + H2[m] * Pby + H3[m] * Tby;
            yf[3 * f] = px - X0f[2 * f];
            yf[3 * f + 1] = py - X0f[2 * f + 1];
            yf[3 * f + 2] = (1 - t[m]) * yc[3 * a + 2] + t[m] * yc[3 * b + 2];
        }
        for (Py_ssize_t e = 0; e < ne; e++) {
            long long i = IA[e], j = IB[e], ef = EF[e], ec = EC[e];
            if (i < 0 || i >= nfn || j < 0 || j >= nfn || ef < 0 || ef >= nef || ec < 0 || ec >= nec) {
                PyErr_SetString(PyExc_IndexError, "femslide kernel: prolong: element index out of range");
                goto out;
            }
            double Dx = (X0f[2 * j] + yf[3 * j]) - (X0f[2 * i] + yf[3 * i]);
            double Dy = (X0f[2 * j + 1] + yf[3 * j + 1]) - (X0f[2 * i + 1] + yf[3 * i + 1]);
            double ref = b0c[ec] + al[ec];
            double cr = cos(ref), sr = sin(ref);
            af[ef] = (ref + atan2(cr * Dy - sr * Dx, cr * Dx + sr * Dy)) - b0f[ef];
        }
        Py_INCREF(Py_None);
        res = Py_None;
    }
out:
    release_all(B, 18);
    return res;
}

static PyMethodDef module_methods[] = {
    {"prolong", py_prolong, METH_VARARGS,
     "prolong(a, b, nf, t, H, bet, X0c, yc, X0f, yf, ia, ib, ef, ec, beta0c, alpha, beta0f, af): the nodal "
     "dofs and chord rotations of femslide.analysis.refine.prolong (outputs yf, af written in place)"},
    {"cuts", py_cuts, METH_VARARGS,
     "cuts(X, g, first, ei, ej, M, G): M, G := the end moments and middle forces of the elements from the "
     "equilibrium of the rod pieces (femslide.results.static.end_moments)"},
    {"inside", py_inside, METH_VARARGS,
     "inside(X, U, ei, ej, beta0, alpha, M, G) -> max |M| at the elements' ends and interior extrema "
     "(femslide.results.static._largest_inside)"},
    {"stages", py_stages, METH_VARARGS,
     "stages(Y, qn, v, w, h, Q, Ys, V, ACC): a Radau step's stage states from its unknowns "
     "(femslide.analysis.radau.RadauSystem.system; outputs written in place)"},
    {"stage_rows", py_stage_rows, METH_VARARGS,
     "stage_rows(parts, F, Y, V, w, h, r): a Radau step's stacked stage residual from the stages' model "
     "residuals and inertia (femslide.analysis.radau.RadauSystem.system)"},
    {"error_rhs", py_error_rhs, METH_VARARGS,
     "error_rhs(Y, e, h, acc, v, lam, mr, mc, mv, cr, cc, cv, b, rq): the right-hand side of a Radau step's "
     "error estimate (femslide.analysis.radau.RadauSystem.error; b and rq written in place)"},
    {"coupled_solve", py_coupled_solve, METH_VARARGS,
     "coupled_solve(r, h, w, cr, cc, cv, mr, mc, mv, lu, piv, kl, ku, perm, rs, cs, out): the Newton correction "
     "of a Radau step from its coupled matrix's factors (femslide.analysis.radau.CoupledMatrix.solve)"},
    {"coupled_rhs", py_coupled_rhs, METH_VARARGS,
     "coupled_rhs(r, wrq, h, cr, cc, cv, mr, mc, mv, nq, rhs): the right-hand side of a Radau step's coupled "
     "Newton system (femslide.analysis.radau.CoupledMatrix.solve)"},
    {"coupled", py_coupled, METH_VARARGS,
     "coupled(out, flat, parts, mass, vel, w2, w1, cblocks): a Radau step's coupled Newton matrix written into "
     "its storage (femslide.analysis.radau)"},
    {"inertia", py_inertia, METH_VARARGS,
     "inertia(Q, V, ACC, G, node_dofs, node_vals, body_d, body_data, F, base, mass, vel): "
     "femslide.model.mass.Masses.inertia_parts (outputs written in place)"},
    {"equilibrate", py_equilibrate, METH_VARARGS,
     "equilibrate(M, kl, ku, rs, cs): M scaled in place to rows and columns of largest magnitude about 1 "
     "(powers of 2), rs and cs := the scales (kl < 0: M dense (n, n), else the column-major band)"},
    {"factor", py_factor, METH_VARARGS,
     "factor(M, piv, n, kl, ku) -> info: LU with partial pivoting in place; kl < 0: M dense (n, n), else M the "
     "column-major band with kl sub- and ku superdiagonals ((n, 2 kl + ku + 1) C order); info > 0: zero pivot"},
    {"solve", py_solve, METH_VARARGS, "solve(factors, piv, b, kl, ku): b := the solution, with factor()'s factors"},
    {"solve_dense", py_solve_dense, METH_VARARGS,
     "solve_dense(A, x) -> info: x := A^-1 x (A dense, unchanged); info > 0: zero pivot, x unchanged"},
    {"norms", py_norms, METH_VARARGS,
     "norms(v, k[, idx]) -> (max |v[:k]|, max |v[k:]|, max |v[idx]|) (0 for an empty part, NaN if a NaN)"},
    {"rcm", py_rcm, METH_VARARGS,
     "rcm(rows, cols, size, perm): perm := the reverse Cuthill-McKee ordering of the symmetrised pattern"},
    {NULL, NULL, 0, NULL}};

static struct PyModuleDef moduledef = {PyModuleDef_HEAD_INIT, "_assembly",
                                       "The compiled assembly of femslide's models (see _assembly.c).", -1,
                                       module_methods};

PyMODINIT_FUNC PyInit__assembly(void)
{
    if (PyType_Ready(&AssemblerType) < 0)
        return NULL;
    PyObject *m = PyModule_Create(&moduledef);
    if (m == NULL)
        return NULL;
    Py_INCREF(&AssemblerType);
    if (PyModule_AddObject(m, "Assembler", (PyObject *)&AssemblerType) < 0) {
        Py_DECREF(&AssemblerType);
        Py_DECREF(m);
        return NULL;
    }
    PyModule_AddIntConstant(m, "VERSION", 4);   /* femslide.model.linalg.KERNEL_VERSION: raise both with a change */
    return m;
}
