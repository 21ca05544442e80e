/* The compiled core of the HNC-21T interpreter: runs of plain blocks, the file's line split
 * and the toolpath's summary figures.
 *
 * It does, bit for bit, what the Python code does in the states it accepts, and hands back
 * to Python (returning where it stopped) before anything else; so every alarm and warning is
 * still raised by the Python code, at the same line and column. The arithmetic is written
 * in the order of the Python expressions (built with -ffp-contract=off: no fused
 * multiply-add); math.hypot is called through Python (its algorithm is CPython's own, not
 * the C library's), atan2 and sin are the C library's functions that Python's math module
 * calls too.
 *
 * run_plain(interp, pc, end, steps, OTHER) -> (pc, steps)
 *     Executes statements pc, pc+1, ... while each is a plain block (at most one G00-G03,
 *     words X Z U W I K R F N, letters and numbers only, in the reader's syntax: what
 *     Interp._compile_plain accepts) that has not been compiled by the Python path, and while
 *     the machine state is simple: no dry run (cycle profile), no tool nose compensation
 *     being buffered, no chamfer/round pending, plain value types. A block stops the run
 *     (before any of its effects) when it would warn or alarm, would start a cycle, has
 *     I/K/R outside an arc, or when the step or move limit is reached.
 *     The moves are written straight into toolpath's column blocks.
 * split(text, line_limit) -> (lines, lineno, stext, kind, number) or None
 *     The per-line work of parser.load for an ASCII text whose lines need no comment
 *     blanking: None sends the whole text to the Python loader.
 * stats(moves) -> (xmin, zmin, xmax, zmax, feed_lengths, rapid_lengths, durations) or None
 *     Toolpath.summary's figures from the column blocks (None: a move keeps its values as
 *     given; the Python code then does it).
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <structmember.h>
#include <math.h>
#include <string.h>

/* ---- bound from hnc_cam.nc.toolpath (bind) --------------------------------------------- */
static PyTypeObject *MoveType = NULL;
static PyObject *BlockClass = NULL;
static PyObject *Local = NULL;      /* threading.local: .block */
static PyObject *Index = NULL;      /* tuple of ints 0.._BLOCK-1 */
static Py_ssize_t off_b = -1, off_k = -1;
static int NF = 12, NI = 6, BLOCK = 2048;
static int op_code[4];
static PyObject *op_str[4];
static PyObject *hypot_fn = NULL;

static PyObject *s_block, *s_used, *s_f, *s_i;
/* interp attributes */
static PyObject *a_src, *a_m, *a_dry, *a_comp_mode, *a_corner, *a_x, *a_z, *a_F, *a_motion,
    *a_absolute, *a_diam, *a_unit, *a_per_rev, *a_css, *a_s_rpm, *a_vc, *a_sdir, *a_coolant,
    *a_tool, *a_reg, *a_tdx, *a_tdz, *a_comp, *a_cyc_code, *a_blocks, *a_limit, *a_move_limit,
    *a_moves, *a_op, *a_compiled, *a_kind, *a_text, *a_lineno, *a_max_rpm, *a_rapid_x,
    *a_rapid_z;

#define TWO_PI (2.0 * 3.14159265358979311600)  /* 2.0 * math.pi */
#define LENGTH_LIMIT 99999.999

/* ---- numbers as Python computes them ---------------------------------------------------- */
static _Thread_local int hypot_err = 0;  /* per thread: runs in threads (a cluster worker) */

static double phypot(double a, double b)
{
    PyObject *args[2];
    args[0] = PyFloat_FromDouble(a);
    args[1] = PyFloat_FromDouble(b);
    PyObject *r = NULL;
    if (args[0] && args[1])
        r = PyObject_Vectorcall(hypot_fn, args, 2, NULL);
    Py_XDECREF(args[0]);
    Py_XDECREF(args[1]);
    if (r == NULL) {
        hypot_err = 1;
        return NAN;
    }
    double v = PyFloat_AsDouble(r);
    Py_DECREF(r);
    return v;
}

static double patan2(double y, double x)  /* CPython's m_atan2 for finite arguments */
{
    if (isnan(x) || isnan(y))
        return NAN;
    if (isinf(y) || isinf(x))
        return atan2(y, x);
    if (y == 0.0) {
        if (copysign(1.0, x) == 1.0)
            return y;
        return copysign(3.14159265358979311600, y);
    }
    return atan2(y, x);
}

static double pmod(double vx, double wx)  /* Python's float % */
{
    double mod = fmod(vx, wx);
    if (mod != 0.0) {
        if ((wx < 0) != (mod < 0))
            mod += wx;
    } else {
        mod = copysign(0.0, wx);
    }
    return mod;
}

/* a double from a Python float or small int; 0 = not such a value */
static int as_num(PyObject *o, double *v)
{
    if (PyFloat_CheckExact(o)) {
        *v = PyFloat_AS_DOUBLE(o);
        return 1;
    }
    if (PyLong_CheckExact(o)) {
        int ovf = 0;
        long long n = PyLong_AsLongLongAndOverflow(o, &ovf);
        if (ovf || n > (1LL << 52) || n < -(1LL << 52))
            return 0;
        *v = (double)n;
        return 1;
    }
    return 0;
}

static int as_i32(PyObject *o, long *v)
{
    if (!PyLong_CheckExact(o))
        return 0;
    int ovf = 0;
    long long n = PyLong_AsLongLongAndOverflow(o, &ovf);
    if (ovf || n > 2147483647LL || n < -2147483648LL)
        return 0;
    *v = (long)n;
    return 1;
}

/* ---- one plain block ---------------------------------------------------------------------- */
enum { WX, WZ, WU, WW, WI, WK, WR, WF, NW };

typedef struct {
    int g;          /* -1 none, else 0..3 */
    unsigned has;   /* bit per W* */
    double v[NW];
} Words;

static const double POW10[] = {1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11,
                               1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

static inline int is_ws(unsigned char c)  /* str.isspace() over ASCII */
{
    return c == ' ' || (c >= 9 && c <= 13) || (c >= 28 && c <= 31);
}

/* the number [-+]?(\d+\.?\d*|\.\d+) at s[*pos]; returns 0 when there is none, -1 on a
 * Python error; t0..t1 the number text (for N) */
static int read_number(const char *s, Py_ssize_t n, Py_ssize_t *pos, double *out,
                       Py_ssize_t *t0, Py_ssize_t *t1)
{
    Py_ssize_t p = *pos, start = p;
    int neg = 0;
    if (p < n && (s[p] == '-' || s[p] == '+')) {
        neg = s[p] == '-';
        p++;
    }
    Py_ssize_t d0 = p;
    unsigned long long m = 0;
    int sig = 0, frac = 0, big = 0, seen_digit = 0, dot = 0;
    while (p < n && s[p] >= '0' && s[p] <= '9') {
        seen_digit = 1;
        if (m || s[p] != '0') {
            if (sig < 18) m = m * 10 + (unsigned)(s[p] - '0'); else big = 1;
            sig++;
        }
        p++;
    }
    if (p < n && s[p] == '.') {
        if (!seen_digit) {  /* \.\d+ */
            if (!(p + 1 < n && s[p + 1] >= '0' && s[p + 1] <= '9'))
                return 0;
        }
        dot = 1;
        p++;
        while (p < n && s[p] >= '0' && s[p] <= '9') {
            seen_digit = 1;
            if (m || s[p] != '0') {
                if (sig < 18) m = m * 10 + (unsigned)(s[p] - '0'); else big = 1;
                sig++;
            }
            frac++;
            p++;
        }
    }
    (void)dot;
    if (!seen_digit)
        return 0;
    *t0 = start;
    *t1 = p;
    *pos = p;
    if (!big && m <= (1ULL << 53) && frac <= 22) {
        double v = (double)m / POW10[frac];
        *out = neg ? -v : v;
        return 1;
    }
    /* rare: Python's own conversion of the text */
    char buf[128];
    Py_ssize_t len = p - start;
    (void)d0;
    if (len >= (Py_ssize_t)sizeof(buf))
        return 2;  /* not handled here: the Python path reads it */
    memcpy(buf, s + start, (size_t)len);
    buf[len] = 0;
    double v = PyOS_string_to_double(buf, NULL, NULL);
    if (v == -1.0 && PyErr_Occurred()) {
        PyErr_Clear();
        return 2;
    }
    *out = v;
    return 1;
}

/* 1: a plain block (words filled), 0: not one (the Python path compiles it) */
static int parse_plain(const char *s, Py_ssize_t n, Words *w)
{
    Py_ssize_t p = 0;
    int have_n = 0;
    w->g = -1;
    w->has = 0;
    for (;;) {
        while (p < n && is_ws((unsigned char)s[p]))
            p++;
        if (p >= n)
            break;
        char L = s[p];
        if (L < 'A' || L > 'Z')
            return 0;
        p++;
        while (p < n && is_ws((unsigned char)s[p]))
            p++;
        double f;
        Py_ssize_t t0, t1;
        int r = read_number(s, n, &p, &f, &t0, &t1);
        if (r != 1)
            return 0;
        int k;
        switch (L) {
        case 'X': k = WX; break;
        case 'Z': k = WZ; break;
        case 'U': k = WU; break;
        case 'W': k = WW; break;
        case 'I': k = WI; break;
        case 'K': k = WK; break;
        case 'R': k = WR; break;
        case 'F': k = WF; break;
        case 'N': k = -1; break;
        case 'G': k = -2; break;
        default: return 0;
        }
        if (k >= 0) {
            if (w->has & (1u << k))
                return 0;
            if (f > LENGTH_LIMIT || f < -LENGTH_LIMIT || (k == WF && !(0 <= f && f <= 24000)))
                return 0;
            w->has |= 1u << k;
            w->v[k] = f;
        } else if (k == -1) {
            if (have_n || s[t0] == '+' || s[t0] == '-' || t1 - t0 > 10)
                return 0;
            for (Py_ssize_t q = t0; q < t1; q++)
                if (s[q] == '.')
                    return 0;
            if (f > 4294967295.0)
                return 0;
            have_n = 1;
        } else {
            if (w->g >= 0)
                return 0;
            if (f == 0.0 || f == 1.0 || f == 2.0 || f == 3.0)
                w->g = (int)f;
            else
                return 0;
        }
    }
    return w->g >= 0 || w->has || have_n;
}

/* ---- the machine state while a run lasts ------------------------------------------------ */
typedef struct {
    double x, z, F, unit, s_rpm, vc, tdx, tdz, max_rpm, rapid_x, rapid_z;
    int hasF, absolute, diam, per_rev, css, coolant, cyc_code_nz, op, op_changed, F_changed;
    long motion, sdir, tool, reg, comp;
    long long blocks, limit;
    Py_ssize_t move_limit;
    PyObject *moves;
    /* the column block being filled */
    PyObject *blk;
    Py_buffer fv, iv;
    int have_views;
    long used;
} St;

typedef struct {
    int kind;  /* 0 rapid, 1 line, 2 arc */
    double sx, sz, ex, ez, feed, cx, cz, spindle, duration;
    int feed_none, center_none, cw;  /* cw: 0 None, 1 False, 2 True */
} Mv;

static int release_block(St *st)
{
    int rc = 0;
    if (st->blk == NULL)
        return 0;
    PyObject *u = PyLong_FromLong(st->used);
    if (u == NULL || PyObject_SetAttr(st->blk, s_used, u) < 0)
        rc = -1;
    Py_XDECREF(u);
    if (st->have_views) {
        PyBuffer_Release(&st->fv);
        PyBuffer_Release(&st->iv);
        st->have_views = 0;
    }
    Py_CLEAR(st->blk);
    return rc;
}

static int acquire_block(St *st)
{
    PyObject *blk = PyObject_GetAttr(Local, s_block);
    if (blk == NULL) {
        if (!PyErr_ExceptionMatches(PyExc_AttributeError))
            return -1;
        PyErr_Clear();
    }
    long used = 0;
    if (blk != NULL && blk != Py_None) {
        PyObject *u = PyObject_GetAttr(blk, s_used);
        if (u == NULL) {
            Py_DECREF(blk);
            return -1;
        }
        used = PyLong_AsLong(u);
        Py_DECREF(u);
        if (used == -1 && PyErr_Occurred()) {
            Py_DECREF(blk);
            return -1;
        }
    }
    if (blk == NULL || blk == Py_None || used >= BLOCK || used < 0) {
        Py_XDECREF(blk);
        blk = PyObject_CallNoArgs(BlockClass);
        if (blk == NULL)
            return -1;
        if (PyObject_SetAttr(Local, s_block, blk) < 0) {
            Py_DECREF(blk);
            return -1;
        }
        used = 0;
    }
    PyObject *f = PyObject_GetAttr(blk, s_f);
    PyObject *i = f ? PyObject_GetAttr(blk, s_i) : NULL;
    if (i == NULL) {
        Py_XDECREF(f);
        Py_DECREF(blk);
        return -1;
    }
    int ok = PyObject_GetBuffer(f, &st->fv, PyBUF_WRITABLE | PyBUF_FORMAT) == 0;
    if (ok && PyObject_GetBuffer(i, &st->iv, PyBUF_WRITABLE | PyBUF_FORMAT) != 0) {
        PyBuffer_Release(&st->fv);
        ok = 0;
    }
    Py_DECREF(f);
    Py_DECREF(i);
    if (!ok) {
        Py_DECREF(blk);
        return -1;
    }
    if (st->fv.len < (Py_ssize_t)(8 * NF * BLOCK) || st->iv.len < (Py_ssize_t)(4 * NI * BLOCK)
        || st->fv.itemsize != 8 || st->iv.itemsize != 4) {
        PyBuffer_Release(&st->fv);
        PyBuffer_Release(&st->iv);
        Py_DECREF(blk);
        PyErr_SetString(PyExc_RuntimeError, "column block of an unexpected shape");
        return -1;
    }
    st->have_views = 1;
    st->blk = blk;
    st->used = used;
    return 0;
}

static int put_move(St *st, const Mv *m, long line)
{
    if (st->blk == NULL || st->used >= BLOCK) {
        if (release_block(st) < 0 || acquire_block(st) < 0)
            return -1;
    }
    long k = st->used;
    double *f = (double *)st->fv.buf + (Py_ssize_t)k * NF;
    int *iv = (int *)st->iv.buf + (Py_ssize_t)k * NI;
    f[0] = m->sx; f[1] = m->sz; f[2] = m->ex; f[3] = m->ez;
    f[4] = m->feed_none ? 0.0 : m->feed;
    f[5] = m->center_none ? 0.0 : m->cx;
    f[6] = m->center_none ? 0.0 : m->cz;
    f[7] = m->spindle; f[8] = m->duration;
    f[9] = 0.0; f[10] = 0.0; f[11] = 0.0;
    iv[0] = (int)line; iv[1] = (int)st->tool; iv[2] = (int)st->reg; iv[3] = (int)st->sdir;
    iv[4] = (int)st->comp;
    iv[5] = m->kind | (m->cw << 4) | (st->coolant ? 64 : 0) | (m->feed_none ? 128 : 0)
            | (m->center_none ? 256 : 0) | (op_code[st->op] << 9);
    PyObject *mv = MoveType->tp_alloc(MoveType, 0);
    if (mv == NULL)
        return -1;
    PyObject *kobj = PyTuple_GET_ITEM(Index, k);
    Py_INCREF(st->blk);
    Py_INCREF(kobj);
    *(PyObject **)((char *)mv + off_b) = st->blk;
    *(PyObject **)((char *)mv + off_k) = kobj;
    st->used = k + 1;
    int rc = PyList_Append(st->moves, mv);
    Py_DECREF(mv);
    return rc;
}

static double rpm_at(const St *st, double x)  /* Interp._rpm */
{
    if (st->sdir == 5)
        return 0.0;
    if (!st->css)
        return st->s_rpm;
    double r = fabs(x + st->tdx);
    double mx = st->max_rpm;
    if (r < 1e-9)
        return mx;
    double n = 1000.0 * st->vc / (TWO_PI * r);
    return n > mx ? mx : n;
}

/* Interp._css_time with x_at(u) = a + b * u (line: a = x0, b = x1 - x0) or
 * cx + r * sin(a0 + s * u) (arc) */
static double css_time(const St *st, double L, double f_rev, int arc, double p0, double p1,
                       double p2, double p3)
{
    const int n = 16;
    double acc = 0.0;
    for (int i = 0; i <= n; i++) {
        double u = (double)i / (double)n;
        double x = arc ? p0 + p1 * sin(p2 + p3 * u) : p0 + p1 * u;
        double rpm = rpm_at(st, x);
        if (rpm <= 0)
            return 0.0;
        double c = (i == 0 || i == n) ? 1.0 : (i % 2) ? 4.0 : 2.0;
        acc += c / rpm;
    }
    return L * acc / (double)(3 * n) / f_rev * 60.0;
}

/* feed and duration of a feed move (Interp._feed and the code after it with F=None);
 * 1 ok, 0 bail (the Python path warns or alarms) */
static int feed_of(const St *st, double rpm, double L, int arc, double p0, double p1, double p2,
                   double p3, double *feed, double *dur)
{
    double f;
    if (!st->hasF)
        return 0;  /* default feed with a warning */
    if (st->per_rev) {
        if (rpm <= 0)
            return 0;  /* warning */
        f = st->F * rpm;
    } else {
        if (st->F <= 0)
            return 0;  /* alarm */
        f = st->F;
    }
    if (f <= 0 && !st->per_rev)
        return 0;
    double t;
    if (f > 0 && rpm > 0 && st->css && st->per_rev)
        t = css_time(st, L, f / rpm, arc, p0, p1, p2, p3);
    else
        t = f > 0 ? L / f * 60.0 : 0.0;
    *feed = f;
    *dur = t;
    return 1;
}

static int arc_move(const St *st, double x0, double z0, double x1, double z1, double cx,
                    double cz, int cw, Mv *m)
{
    double r = phypot(x0 - cx, z0 - cz);
    double a0 = patan2(x0 - cx, z0 - cz);
    double a1 = patan2(x1 - cx, z1 - cz);
    double s = a1 - a0;
    if (cw) {
        while (s >= -1e-9) s -= TWO_PI;
        while (s < -TWO_PI) s += TWO_PI;
    } else {
        while (s <= 1e-9) s += TWO_PI;
        while (s > TWO_PI) s -= TWO_PI;
    }
    double L = fabs(s) * r;
    double rpm;
    if (st->sdir != 5)
        rpm = st->css ? rpm_at(st, cx + r * sin(a0 + s * 0.5)) : st->s_rpm;
    else
        rpm = 0.0;
    double f, t;
    if (!feed_of(st, rpm, L, 1, cx, r, a0, s, &f, &t))
        return 0;
    m->kind = 2;
    m->sx = x0 + st->tdx; m->sz = z0 + st->tdz;
    m->ex = x1 + st->tdx; m->ez = z1 + st->tdz;
    m->feed = f; m->feed_none = 0;
    m->cx = cx + st->tdx; m->cz = cz + st->tdz; m->center_none = 0;
    m->cw = cw ? 2 : 1;
    m->spindle = rpm;
    m->duration = t;
    return 1;
}

/* Interp._axis for a plain block */
static int axis(const St *st, const Words *w, int A, int inc, double cur, double scale, double *out)
{
    int hA = (w->has >> A) & 1, hI = (w->has >> inc) & 1;
    if (hA) {
        if (hI)
            return 0;  /* alarm: X and U in one block */
        *out = st->absolute ? w->v[A] * scale : cur + w->v[A] * scale;
        return 1;
    }
    *out = hI ? cur + w->v[inc] * scale : cur;
    return 1;
}

/* Execute one plain block: 1 done, 0 bail before any effect, -1 Python error */
static int exec_block(St *st, const Words *w, long line)
{
    const unsigned axes_bits = (1u << WX) | (1u << WZ) | (1u << WU) | (1u << WW);
    const unsigned extra_bits = (1u << WI) | (1u << WK) | (1u << WR);
    int axes = (w->has & axes_bits) != 0;
    int extra = (w->has & extra_bits) != 0;
    long motion = w->g >= 0 ? w->g : st->motion;
    double F = st->F;
    int hasF = st->hasF;
    if (w->has & (1u << WF)) {
        F = w->v[WF] * st->unit;
        hasF = 1;
    }
    if (!axes) {
        if (extra)
            return 0;
        st->F = F; st->hasF = hasF;
        if (w->has & (1u << WF)) st->F_changed = 1;
        if (w->g >= 0) { st->motion = w->g; st->cyc_code_nz = 0; }
        st->blocks++;
        return 1;
    }
    if (motion < 0 || motion > 3)
        return 0;  /* a cycle */
    if (extra && motion < 2)
        return 0;  /* C/R corner or a word without meaning */
    double u = st->unit;
    double x1, z1;
    if (!axis(st, w, WX, WU, st->x, st->diam ? 0.5 * u : u, &x1)
        || !axis(st, w, WZ, WW, st->z, u, &z1))
        return 0;
    double x0 = st->x, z0 = st->z;
    /* the block's new modal values, in effect for its own move */
    St nst = *st;
    nst.F = F; nst.hasF = hasF;
    Mv mv[2];
    int nmv = 0;
    Py_ssize_t have = PyList_GET_SIZE(st->moves);
    if (motion <= 1) {
        double dx = x1 - x0, dz = z1 - z0;
        if (!(-1e-9 < dx && dx < 1e-9 && -1e-9 < dz && dz < 1e-9)) {
            if (have >= st->move_limit)
                return 0;
            double tdx = st->tdx, tdz = st->tdz;
            if (motion == 0) {  /* _rapid_moves */
                double X0 = x0 + tdx, Z0 = z0 + tdz, X1 = x1 + tdx, Z1 = z1 + tdz;
                double tx = fabs(dx) / st->rapid_x;
                double tz = fabs(dz) / st->rapid_z;
                double rpm = st->sdir != 5 ? rpm_at(st, X1 - tdx) : 0.0;
                Mv *a = &mv[0];
                a->kind = 0; a->feed_none = 1; a->center_none = 1; a->cw = 0; a->feed = 0.0;
                a->cx = a->cz = 0.0; a->spindle = rpm;
                if (tx == 0.0 || tz == 0.0 || fabs(tx - tz) <= 1e-12 * (tx + tz)) {
                    a->sx = X0; a->sz = Z0; a->ex = X1; a->ez = Z1;
                    a->duration = (tx > tz ? tx : tz) * 60.0;
                    nmv = 1;
                } else {
                    double xm, zm, t1, t2;
                    if (tx < tz) {
                        xm = X1;
                        zm = Z0 + copysign(st->rapid_z * tx, dz);
                        t1 = tx; t2 = tz - tx;
                    } else {
                        zm = Z1;
                        xm = X0 + copysign(st->rapid_x * tz, dx);
                        t1 = tz; t2 = tx - tz;
                    }
                    mv[1] = *a;
                    a->sx = X0; a->sz = Z0; a->ex = xm; a->ez = zm; a->duration = t1 * 60.0;
                    mv[1].sx = xm; mv[1].sz = zm; mv[1].ex = X1; mv[1].ez = Z1;
                    mv[1].duration = t2 * 60.0;
                    nmv = 2;
                }
            } else {  /* _emit_line, feed */
                double L = phypot(dx, dz);
                if (hypot_err) return -1;
                double rpm = st->sdir != 5 ? rpm_at(st, (x0 + x1) * 0.5) : 0.0;
                double f, t;
                if (!feed_of(&nst, rpm, L, 0, x0, x1 - x0, 0.0, 0.0, &f, &t))
                    return 0;
                Mv *a = &mv[0];
                a->kind = 1;
                a->sx = x0 + tdx; a->sz = z0 + tdz; a->ex = x1 + tdx; a->ez = z1 + tdz;
                a->feed = f; a->feed_none = 0; a->center_none = 1; a->cx = a->cz = 0.0;
                a->cw = 0; a->spindle = rpm; a->duration = t;
                nmv = 1;
            }
        }
    } else {  /* _arc */
        int cw = motion == 2;
        double cx, cz;
        if (w->has & (1u << WR)) {
            double R = w->v[WR] * u;
            double chord = phypot(x1 - x0, z1 - z0);
            if (hypot_err) return -1;
            if (chord < 1e-9)
                return 0;
            double r = fabs(R);
            if (r == 0)
                return 0;
            if (r < chord / 2) {
                if (chord / 2 - r <= 1e-3)
                    R = copysign(chord / 2, R);
                else
                    return 0;
            }
            /* Arc.from_radius (c and left_normal's n are the same hypot as chord) */
            r = fabs(R);
            double dx = x1 - x0, dz = z1 - z0;
            double c = chord;
            double hh = r * r - pow(c / 2, 2.0);
            double h = sqrt(hh > 0.0 ? hh : 0.0);
            double mx = (x0 + x1) / 2, mz = (z0 + z1) / 2;
            double ln0 = dz / c, ln1 = -dx / c;
            double small_side = cw ? -1.0 : 1.0;
            double side = R > 0 ? small_side : -small_side;
            cx = mx + side * h * ln0;
            cz = mz + side * h * ln1;
        } else {
            int hI = (w->has >> WI) & 1, hK = (w->has >> WK) & 1;
            if (!hI && !hK)
                return 0;
            double I = (hI && w->v[WI] != 0.0) ? w->v[WI] : 0.0;
            double K = (hK && w->v[WK] != 0.0) ? w->v[WK] : 0.0;
            cx = x0 + I * u;
            cz = z0 + K * u;
            double r0 = phypot(x0 - cx, z0 - cz);
            if (hypot_err) return -1;
            if (r0 < 1e-9)
                return 0;
            double r1 = phypot(x1 - cx, z1 - cz);
            if (hypot_err) return -1;
            if (fabs(r1 - r0) > 0.01)
                return 0;
            double ch = phypot(x1 - x0, z1 - z0);
            if (hypot_err) return -1;
            if (ch < 1e-9) {  /* full circle: two half arcs */
                if (have >= st->move_limit || have + 1 >= st->move_limit)
                    return 0;
                double mx = 2 * cx - x0, mz = 2 * cz - z0;
                if (!arc_move(&nst, x0, z0, mx, mz, cx, cz, cw, &mv[0])
                    || !arc_move(&nst, mx, mz, x1, z1, cx, cz, cw, &mv[1]))
                    return hypot_err ? -1 : 0;
                nmv = 2;
                goto commit;
            }
        }
        if (have >= st->move_limit)
            return 0;
        if (!arc_move(&nst, x0, z0, x1, z1, cx, cz, cw, &mv[0]))
            return hypot_err ? -1 : 0;
        if (hypot_err) return -1;
        nmv = 1;
    }
commit:
    if (hypot_err)
        return -1;
    st->F = F; st->hasF = hasF;
    if (w->has & (1u << WF)) st->F_changed = 1;
    if (w->g >= 0) { st->motion = w->g; st->cyc_code_nz = 0; }
    st->blocks++;
    st->op = (int)motion;
    st->op_changed = 1;
    st->x = x1;
    st->z = z1;
    for (int j = 0; j < nmv; j++)
        if (put_move(st, &mv[j], line) < 0)
            return -1;
    return 1;
}

/* ---- reading and writing the interpreter's attributes ------------------------------------ */
static int get_num(PyObject *o, PyObject *name, double *v)  /* 1 ok, 0 not plain, -1 error */
{
    PyObject *a = PyObject_GetAttr(o, name);
    if (a == NULL)
        return -1;
    int r = as_num(a, v);
    Py_DECREF(a);
    return r;
}

static int get_i32(PyObject *o, PyObject *name, long *v)
{
    PyObject *a = PyObject_GetAttr(o, name);
    if (a == NULL)
        return -1;
    int r = as_i32(a, v);
    Py_DECREF(a);
    return r;
}

static int get_bool(PyObject *o, PyObject *name, int *v)
{
    PyObject *a = PyObject_GetAttr(o, name);
    if (a == NULL)
        return -1;
    int r = PyObject_IsTrue(a);
    Py_DECREF(a);
    if (r < 0)
        return -1;
    *v = r;
    return 1;
}

static int is_none(PyObject *o, PyObject *name)
{
    PyObject *a = PyObject_GetAttr(o, name);
    if (a == NULL)
        return -1;
    int r = a == Py_None;
    Py_DECREF(a);
    return r;
}

#define CHK(expr) do { int _r = (expr); if (_r < 0) goto error; if (_r == 0) goto plainless; } while (0)

static int load_state(PyObject *it, St *st)
{
    PyObject *m = NULL, *a = NULL;
    memset(st, 0, sizeof(*st));
    CHK(is_none(it, a_dry));
    a = PyObject_GetAttr(it, a_comp_mode);
    if (a == NULL) goto error;
    {
        int t = PyObject_IsTrue(a);
        Py_CLEAR(a);
        if (t < 0) goto error;
        if (t) goto plainless;
    }
    CHK(is_none(it, a_corner));
    CHK(get_num(it, a_x, &st->x));
    CHK(get_num(it, a_z, &st->z));
    a = PyObject_GetAttr(it, a_F);
    if (a == NULL) goto error;
    if (a == Py_None) {
        st->hasF = 0;
        st->F = 0.0;
    } else {
        if (!as_num(a, &st->F)) goto plainless;
        st->hasF = 1;
    }
    Py_CLEAR(a);
    CHK(get_i32(it, a_motion, &st->motion));
    CHK(get_bool(it, a_absolute, &st->absolute));
    CHK(get_bool(it, a_diam, &st->diam));
    CHK(get_num(it, a_unit, &st->unit));
    CHK(get_bool(it, a_per_rev, &st->per_rev));
    CHK(get_bool(it, a_css, &st->css));
    CHK(get_num(it, a_s_rpm, &st->s_rpm));
    CHK(get_num(it, a_vc, &st->vc));
    CHK(get_i32(it, a_sdir, &st->sdir));
    a = PyObject_GetAttr(it, a_coolant);
    if (a == NULL) goto error;
    if (!PyBool_Check(a)) goto plainless;
    st->coolant = a == Py_True;
    Py_CLEAR(a);
    CHK(get_i32(it, a_tool, &st->tool));
    CHK(get_i32(it, a_reg, &st->reg));
    CHK(get_num(it, a_tdx, &st->tdx));
    CHK(get_num(it, a_tdz, &st->tdz));
    CHK(get_i32(it, a_comp, &st->comp));
    {
        long cyc;
        CHK(get_i32(it, a_cyc_code, &cyc));
        st->cyc_code_nz = cyc != 0;
    }
    a = PyObject_GetAttr(it, a_blocks);
    if (a == NULL) goto error;
    if (!PyLong_CheckExact(a)) goto plainless;
    st->blocks = PyLong_AsLongLong(a);
    if (st->blocks == -1 && PyErr_Occurred()) goto error;
    Py_CLEAR(a);
    a = PyObject_GetAttr(it, a_limit);
    if (a == NULL) goto error;
    if (!PyLong_CheckExact(a)) goto plainless;
    st->limit = PyLong_AsLongLong(a);
    if (st->limit == -1 && PyErr_Occurred()) { PyErr_Clear(); goto plainless; }
    Py_CLEAR(a);
    a = PyObject_GetAttr(it, a_move_limit);
    if (a == NULL) goto error;
    if (!PyLong_CheckExact(a)) goto plainless;
    st->move_limit = PyLong_AsSsize_t(a);
    if (st->move_limit == -1 && PyErr_Occurred()) { PyErr_Clear(); goto plainless; }
    Py_CLEAR(a);
    m = PyObject_GetAttr(it, a_m);
    if (m == NULL) goto error;
    CHK(get_num(m, a_max_rpm, &st->max_rpm));
    CHK(get_num(m, a_rapid_x, &st->rapid_x));
    CHK(get_num(m, a_rapid_z, &st->rapid_z));
    Py_CLEAR(m);
    if (!(st->rapid_x > 0) || !(st->rapid_z > 0))
        goto plainless;
    st->moves = PyObject_GetAttr(it, a_moves);
    if (st->moves == NULL) goto error;
    if (!PyList_CheckExact(st->moves)) { Py_CLEAR(st->moves); goto plainless; }
    st->op = -1;
    return 1;
plainless:
    Py_XDECREF(a);
    Py_XDECREF(m);
    return 0;
error:
    Py_XDECREF(a);
    Py_XDECREF(m);
    return -1;
}

static int set_attr_d(PyObject *o, PyObject *name, double v)
{
    PyObject *f = PyFloat_FromDouble(v);
    if (f == NULL)
        return -1;
    int r = PyObject_SetAttr(o, name, f);
    Py_DECREF(f);
    return r;
}

static int store_state(PyObject *it, St *st)
{
    int rc = 0;
    if (set_attr_d(it, a_x, st->x) < 0 || set_attr_d(it, a_z, st->z) < 0)
        rc = -1;
    if (rc == 0 && st->F_changed && set_attr_d(it, a_F, st->F) < 0)
        rc = -1;
    if (rc == 0) {
        PyObject *v = PyLong_FromLong(st->motion);
        if (v == NULL || PyObject_SetAttr(it, a_motion, v) < 0) rc = -1;
        Py_XDECREF(v);
    }
    if (rc == 0 && !st->cyc_code_nz) {
        PyObject *v = PyLong_FromLong(0);
        if (v == NULL || PyObject_SetAttr(it, a_cyc_code, v) < 0) rc = -1;
        Py_XDECREF(v);
    }
    if (rc == 0) {
        PyObject *v = PyLong_FromLongLong(st->blocks);
        if (v == NULL || PyObject_SetAttr(it, a_blocks, v) < 0) rc = -1;
        Py_XDECREF(v);
    }
    if (rc == 0 && st->op_changed && PyObject_SetAttr(it, a_op, op_str[st->op]) < 0)
        rc = -1;
    return rc;
}

static PyObject *run_plain(PyObject *self, PyObject *args)
{
    PyObject *it, *OTHER;
    Py_ssize_t pc, end;
    long long steps;
    if (!PyArg_ParseTuple(args, "OnnLO", &it, &pc, &end, &steps, &OTHER))
        return NULL;
    if (MoveType == NULL) {
        PyErr_SetString(PyExc_RuntimeError, "_core.bind was not called");
        return NULL;
    }
    Py_ssize_t pc0 = pc;
    PyObject *src = NULL, *kind = NULL, *text = NULL, *lineno = NULL, *compiled = NULL;
    St st;
    int r = load_state(it, &st);
    if (r < 0)
        return NULL;
    if (r == 0)
        return Py_BuildValue("nL", pc, steps);
    src = PyObject_GetAttr(it, a_src);
    if (src == NULL) goto fail;
    kind = PyObject_GetAttr(src, a_kind);
    text = kind ? PyObject_GetAttr(src, a_text) : NULL;
    lineno = text ? PyObject_GetAttr(src, a_lineno) : NULL;
    compiled = lineno ? PyObject_GetAttr(it, a_compiled) : NULL;
    if (compiled == NULL) goto fail;
    if (!PyList_CheckExact(kind) || !PyList_CheckExact(text) || !PyList_CheckExact(lineno)
        || !PyList_CheckExact(compiled))
        goto done;
    hypot_err = 0;
    for (;;) {
        if (pc < 0 || pc >= end || pc >= PyList_GET_SIZE(kind) || pc >= PyList_GET_SIZE(text)
            || pc >= PyList_GET_SIZE(lineno) || pc >= PyList_GET_SIZE(compiled))
            break;
        if (PyList_GET_ITEM(kind, pc) != OTHER || PyList_GET_ITEM(compiled, pc) != Py_None)
            break;
        PyObject *t = PyList_GET_ITEM(text, pc);
        if (!PyUnicode_CheckExact(t) || !PyUnicode_IS_ASCII(t))
            break;
        PyObject *ln = PyList_GET_ITEM(lineno, pc);
        long line;
        if (!as_i32(ln, &line))
            break;
        Words w;
        if (!parse_plain((const char *)PyUnicode_DATA(t), PyUnicode_GET_LENGTH(t), &w))
            break;
        if (steps + 1 > st.limit)
            break;
        int e = exec_block(&st, &w, line);
        if (e < 0) goto fail;
        if (e == 0) break;
        steps++;
        pc++;
    }
done:
    if (pc != pc0 && store_state(it, &st) < 0) goto fail;
    if (release_block(&st) < 0) goto fail;
    Py_XDECREF(st.moves);
    Py_XDECREF(src); Py_XDECREF(kind); Py_XDECREF(text); Py_XDECREF(lineno);
    Py_XDECREF(compiled);
    return Py_BuildValue("nL", pc, steps);
fail:
    {
        PyObject *et, *ev, *tb;
        PyErr_Fetch(&et, &ev, &tb);
        release_block(&st);
        PyErr_Clear();
        PyErr_Restore(et, ev, tb);
    }
    Py_XDECREF(st.moves);
    Py_XDECREF(src); Py_XDECREF(kind); Py_XDECREF(text); Py_XDECREF(lineno);
    Py_XDECREF(compiled);
    if (!PyErr_Occurred())
        PyErr_SetString(PyExc_RuntimeError, "run_plain failed");
    return NULL;
}

/* ---- bind ----------------------------------------------------------------------------------- */
static Py_ssize_t slot_offset(PyObject *type, const char *name)
{
    PyObject *d = PyDict_GetItemString(((PyTypeObject *)type)->tp_dict, name);
    if (d == NULL || !PyObject_TypeCheck(d, &PyMemberDescr_Type)) {
        PyErr_Format(PyExc_TypeError, "Move has no slot %s", name);
        return -1;
    }
    PyMemberDef *md = ((PyMemberDescrObject *)d)->d_member;
    if (md->type != T_OBJECT_EX) {
        PyErr_Format(PyExc_TypeError, "Move.%s is not an object slot", name);
        return -1;
    }
    return md->offset;
}

static PyObject *bind(PyObject *self, PyObject *args)
{
    PyObject *move, *blockc, *local, *index, *ops, *hyp;
    int nf, ni, blk;
    if (!PyArg_ParseTuple(args, "OOOO!iiiOO", &move, &blockc, &local, &PyTuple_Type, &index,
                          &nf, &ni, &blk, &ops, &hyp))
        return NULL;
    if (!PyType_Check(move) || nf != 12 || ni != 6 || blk <= 0 || PyTuple_GET_SIZE(index) < blk
        || !PySequence_Check(ops) || PySequence_Size(ops) != 4) {
        PyErr_SetString(PyExc_ValueError, "bind: unexpected toolpath layout");
        return NULL;
    }
    Py_ssize_t ob = slot_offset(move, "_b"), ok = slot_offset(move, "_k");
    if (ob < 0 || ok < 0)
        return NULL;
    for (int j = 0; j < 4; j++) {
        PyObject *pair = PySequence_GetItem(ops, j);  /* (name, code) */
        if (pair == NULL)
            return NULL;
        PyObject *name;
        int code;
        if (!PyArg_ParseTuple(pair, "Ui", &name, &code)) {
            Py_DECREF(pair);
            return NULL;
        }
        Py_INCREF(name);
        Py_XSETREF(op_str[j], name);
        op_code[j] = code;
        Py_DECREF(pair);
    }
    Py_INCREF(move); Py_XSETREF(MoveType, (PyTypeObject *)move);
    Py_INCREF(blockc); Py_XSETREF(BlockClass, blockc);
    Py_INCREF(local); Py_XSETREF(Local, local);
    Py_INCREF(index); Py_XSETREF(Index, index);
    Py_INCREF(hyp); Py_XSETREF(hypot_fn, hyp);
    off_b = ob;
    off_k = ok;
    NF = nf; NI = ni; BLOCK = blk;
    Py_RETURN_NONE;
}

/* ---- split: parser.load's per-line work ------------------------------------------------- */
static int control_word(const char *s, Py_ssize_t n)  /* could parser._control see a keyword? */
{
    for (Py_ssize_t i = 0; i + 1 < n; i++) {
        if ((s[i] == 'I' && s[i + 1] == 'F') || (s[i] == 'W' && s[i + 1] == 'H')
            || (s[i] == 'E' && s[i + 1] == 'L') || (s[i] == 'D' && s[i + 1] == 'W'))
            return 1;
    }
    return 0;
}

static PyObject *split(PyObject *self, PyObject *args)
{
    PyObject *text;
    Py_ssize_t line_limit;  /* -1: none */
    PyObject *OTHER, *HDR, *control, *header;
    if (!PyArg_ParseTuple(args, "UnOOOO", &text, &line_limit, &OTHER, &HDR, &control, &header))
        return NULL;
    if (!PyUnicode_IS_ASCII(text))
        Py_RETURN_NONE;
    const char *s = (const char *)PyUnicode_DATA(text);
    Py_ssize_t n = PyUnicode_GET_LENGTH(text);
    /* whole-text screen: comments, NUL and long lines go to the Python loader */
    {
        Py_ssize_t start = 0;
        for (Py_ssize_t i = 0; i < n; i++) {
            char c = s[i];
            if (c == '(' || c == ';' || c == 0)
                Py_RETURN_NONE;
            if (c == '\n' || c == '\r') {
                if (line_limit >= 0 && i - start > line_limit)
                    Py_RETURN_NONE;
                if (c == '\r' && i + 1 < n && s[i + 1] == '\n')
                    i++;
                start = i + 1;
            }
        }
        if (line_limit >= 0 && n - start > line_limit)
            Py_RETURN_NONE;
    }
    PyObject *lines = PyList_New(0), *lineno = PyList_New(0), *stext = PyList_New(0),
             *kind = PyList_New(0), *number = PyList_New(0);
    char *buf = NULL;
    Py_ssize_t bufn = 0;
    if (!lines || !lineno || !stext || !kind || !number)
        goto fail;
    Py_ssize_t i = 0, lno = 0;
    while (i < n || (i == n && 0)) {
        Py_ssize_t a = i;
        while (i < n && s[i] != '\n' && s[i] != '\r')
            i++;
        Py_ssize_t b = i;  /* line is s[a:b] */
        if (i < n) {
            if (s[i] == '\r' && i + 1 < n && s[i + 1] == '\n')
                i += 2;
            else
                i += 1;
        }
        lno++;
        PyObject *raw = PyUnicode_FromStringAndSize(s + a, b - a);
        if (raw == NULL || PyList_Append(lines, raw) < 0) {
            Py_XDECREF(raw);
            goto fail;
        }
        /* cleaned: upper-cased, trailing blanks cut */
        Py_ssize_t e = b;
        while (e > a && is_ws((unsigned char)s[e - 1]))
            e--;
        Py_ssize_t len = e - a;
        int lower = 0;
        for (Py_ssize_t q = a; q < e; q++)
            if (s[q] >= 'a' && s[q] <= 'z') { lower = 1; break; }
        PyObject *st;
        if (!lower && e == b) {
            st = raw;
            Py_INCREF(st);
        } else {
            if (len > bufn) {
                char *nb = PyMem_Realloc(buf, (size_t)len + 1);
                if (nb == NULL) { Py_DECREF(raw); PyErr_NoMemory(); goto fail; }
                buf = nb;
                bufn = len;
            }
            for (Py_ssize_t q = 0; q < len; q++) {
                char c = s[a + q];
                buf[q] = (c >= 'a' && c <= 'z') ? (char)(c - 32) : c;
            }
            st = PyUnicode_FromStringAndSize(buf, len);
            if (st == NULL) { Py_DECREF(raw); goto fail; }
        }
        Py_DECREF(raw);
        if (len == 0) {
            Py_DECREF(st);
            continue;
        }
        const char *c = PyUnicode_DATA(st);
        Py_ssize_t j = 0;
        while (j < len && is_ws((unsigned char)c[j]))
            j++;
        PyObject *k = OTHER, *num = Py_None, *own = NULL;
        if (j < len && (c[j] == '%' || c[j] == 'O')) {
            PyObject *h = PyObject_CallOneArg(header, st);  /* (is header, number) */
            if (h == NULL) { Py_DECREF(st); goto fail; }
            if (!PyTuple_Check(h) || PyTuple_GET_SIZE(h) != 2) {
                Py_DECREF(h); Py_DECREF(st);
                PyErr_SetString(PyExc_TypeError, "header()");
                goto fail;
            }
            int t = PyObject_IsTrue(PyTuple_GET_ITEM(h, 0));
            if (t < 0) { Py_DECREF(h); Py_DECREF(st); goto fail; }
            if (t) {
                k = HDR;
                num = own = PyTuple_GET_ITEM(h, 1);
                Py_INCREF(own);
            }
            Py_DECREF(h);
        }
        PyObject *ctl = NULL;
        if (k == OTHER && control_word(c, len)) {
            ctl = PyObject_CallOneArg(control, st);
            if (ctl == NULL) { Py_DECREF(st); goto fail; }
            if (ctl != Py_None)
                k = ctl;
        }
        PyObject *lo = PyLong_FromSsize_t(lno);
        int bad = lo == NULL || PyList_Append(lineno, lo) < 0 || PyList_Append(stext, st) < 0
                  || PyList_Append(kind, k) < 0 || PyList_Append(number, num) < 0;
        Py_XDECREF(lo);
        Py_XDECREF(own);
        Py_XDECREF(ctl);
        Py_DECREF(st);
        if (bad)
            goto fail;
    }
    PyMem_Free(buf);
    return Py_BuildValue("(NNNNN)", lines, lineno, stext, kind, number);
fail:
    PyMem_Free(buf);
    Py_XDECREF(lines); Py_XDECREF(lineno); Py_XDECREF(stext); Py_XDECREF(kind);
    Py_XDECREF(number);
    return NULL;
}

/* ---- stats: Toolpath.summary's figures ---------------------------------------------------- */
static PyObject *stats(PyObject *self, PyObject *args)
{
    PyObject *moves, *arrays;  /* arrays: a callable making array('d') from bytes */
    if (!PyArg_ParseTuple(args, "O!O", &PyList_Type, &moves, &arrays))
        return NULL;
    if (MoveType == NULL)
        Py_RETURN_NONE;
    Py_ssize_t n = PyList_GET_SIZE(moves);
    for (Py_ssize_t j = 0; j < n; j++) {
        PyObject *m = PyList_GET_ITEM(moves, j);
        if (Py_TYPE(m) != MoveType)
            Py_RETURN_NONE;
        PyObject *b = *(PyObject **)((char *)m + off_b);
        PyObject *k = *(PyObject **)((char *)m + off_k);
        if (b == NULL || k == NULL || b == Py_None || !PyLong_CheckExact(k))
            Py_RETURN_NONE;
    }
    double *fl = PyMem_Malloc(sizeof(double) * (size_t)(n + 1));
    double *rl = PyMem_Malloc(sizeof(double) * (size_t)(n + 1));
    double *du = PyMem_Malloc(sizeof(double) * (size_t)(n + 1));
    Py_ssize_t nf = 0, nr = 0;
    double xmin = 0, zmin = 0, xmax = 0, zmax = 0;
    PyObject *cur = NULL;
    Py_buffer fv, iv;
    int views = 0, fallback = 0;
    hypot_err = 0;
    if (!fl || !rl || !du) {
        PyErr_NoMemory();
        goto fail;
    }
    for (Py_ssize_t j = 0; j < n; j++) {
        PyObject *m = PyList_GET_ITEM(moves, j);
        PyObject *b = *(PyObject **)((char *)m + off_b);
        long k = PyLong_AsLong(*(PyObject **)((char *)m + off_k));
        if (b != cur) {
            if (views) {
                PyBuffer_Release(&fv);
                PyBuffer_Release(&iv);
                views = 0;
            }
            PyObject *f = PyObject_GetAttr(b, s_f);
            PyObject *i = f ? PyObject_GetAttr(b, s_i) : NULL;
            int ok = i != NULL && PyObject_GetBuffer(f, &fv, PyBUF_SIMPLE) == 0;
            if (ok && PyObject_GetBuffer(i, &iv, PyBUF_SIMPLE) != 0) {
                PyBuffer_Release(&fv);
                ok = 0;
            }
            Py_XDECREF(f);
            Py_XDECREF(i);
            if (!ok) goto fail;
            views = 1;
            cur = b;
        }
        if (k < 0 || (Py_ssize_t)(k + 1) * NF * 8 > fv.len || (Py_ssize_t)(k + 1) * NI * 4 > iv.len) {
            PyErr_SetString(PyExc_IndexError, "move index out of its block");
            goto fail;
        }
        const double *f = (const double *)fv.buf + (Py_ssize_t)k * NF;
        const int *iw = (const int *)iv.buf + (Py_ssize_t)k * NI;
        int kind = iw[5] & 15;
        double sx = f[0], sz = f[1], ex = f[2], ez = f[3];
        double bx0, bz0, bx1, bz1, len = 0.0;
        if (kind == 2 && !(iw[5] & 256) && ((iw[5] >> 4) & 3) != 0) {
            double cx = f[5], cz = f[6];
            int cw = ((iw[5] >> 4) & 3) == 2;
            double r = phypot(cx - sx, cz - sz);  /* radius: dist(center, start) */
            double a0 = patan2(sx - cx, sz - cz), a1 = patan2(ex - cx, ez - cz);
            double s = a1 - a0;
            if (cw) {
                while (s >= -1e-9) s -= 2 * 3.14159265358979311600;
                while (s < -2 * 3.14159265358979311600) s += 2 * 3.14159265358979311600;
            } else {
                while (s <= 1e-9) s += 2 * 3.14159265358979311600;
                while (s > 2 * 3.14159265358979311600) s -= 2 * 3.14159265358979311600;
            }
            len = fabs(s) * r;
            double xs[6] = {sx, ex}, zs[6] = {sz, ez};
            int c = 2;
            const double angs[4] = {0.0, 3.14159265358979311600 / 2, 3.14159265358979311600,
                                    -3.14159265358979311600 / 2};
            const double px[4] = {cx, cx + r, cx, cx - r}, pz[4] = {cz + r, cz, cz - r, cz};
            for (int q = 0; q < 4; q++) {
                double d = angs[q] - a0;
                int in;
                if (s > 0) {
                    d = pmod(d, 2 * 3.14159265358979311600);
                    in = d <= s + 1e-12;
                } else {
                    d = pmod(-d, 2 * 3.14159265358979311600);
                    in = d <= -s + 1e-12;
                }
                if (in) {
                    xs[c] = px[q];
                    zs[c] = pz[q];
                    c++;
                }
            }
            bx0 = bx1 = xs[0];
            bz0 = bz1 = zs[0];
            for (int q = 1; q < c; q++) {
                if (xs[q] < bx0) bx0 = xs[q];
                if (xs[q] > bx1) bx1 = xs[q];
                if (zs[q] < bz0) bz0 = zs[q];
                if (zs[q] > bz1) bz1 = zs[q];
            }
        } else if (kind == 2 || kind > 4) {
            fallback = 1;  /* the Python code says what it makes of it */
            goto fail;
        } else {
            bx0 = ex < sx ? ex : sx;  /* min(start, end): the first unless the second is less */
            bz0 = ez < sz ? ez : sz;
            bx1 = ex > sx ? ex : sx;
            bz1 = ez > sz ? ez : sz;
            if (kind != 4)
                len = phypot(sx - ex, sz - ez);
        }
        if (hypot_err) goto fail;
        if (j == 0) {
            xmin = bx0; zmin = bz0; xmax = bx1; zmax = bz1;
        } else {
            if (bx0 < xmin) xmin = bx0;
            if (bz0 < zmin) zmin = bz0;
            if (bx1 > xmax) xmax = bx1;
            if (bz1 > zmax) zmax = bz1;
        }
        if (kind == 1 || kind == 2 || kind == 3)
            fl[nf++] = len;
        else if (kind == 0)
            rl[nr++] = len;
        du[j] = f[8];
    }
    if (views) {
        PyBuffer_Release(&fv);
        PyBuffer_Release(&iv);
        views = 0;
    }
    PyObject *bf = PyBytes_FromStringAndSize((const char *)fl, (Py_ssize_t)sizeof(double) * nf);
    PyObject *br = PyBytes_FromStringAndSize((const char *)rl, (Py_ssize_t)sizeof(double) * nr);
    PyObject *bd = PyBytes_FromStringAndSize((const char *)du, (Py_ssize_t)sizeof(double) * n);
    PyMem_Free(fl); PyMem_Free(rl); PyMem_Free(du);
    if (!bf || !br || !bd) {
        Py_XDECREF(bf); Py_XDECREF(br); Py_XDECREF(bd);
        return NULL;
    }
    PyObject *af = PyObject_CallOneArg(arrays, bf);
    PyObject *ar = af ? PyObject_CallOneArg(arrays, br) : NULL;
    PyObject *ad = ar ? PyObject_CallOneArg(arrays, bd) : NULL;
    Py_DECREF(bf); Py_DECREF(br); Py_DECREF(bd);
    if (ad == NULL) {
        Py_XDECREF(af); Py_XDECREF(ar);
        return NULL;
    }
    return Py_BuildValue("(ddddNNN)", xmin, zmin, xmax, zmax, af, ar, ad);
fail:
    if (views) {
        PyBuffer_Release(&fv);
        PyBuffer_Release(&iv);
    }
    PyMem_Free(fl); PyMem_Free(rl); PyMem_Free(du);
    if (fallback)
        Py_RETURN_NONE;
    return NULL;
}

static PyMethodDef methods[] = {
    {"bind", bind, METH_VARARGS, "bind(Move, _Block, local, index, NF, NI, BLOCK, ops, hypot)"},
    {"run_plain", run_plain, METH_VARARGS, "run_plain(interp, pc, end, steps, OTHER) -> (pc, steps)"},
    {"split", split, METH_VARARGS, "split(text, line_limit, OTHER, HDR, control, header)"},
    {"stats", stats, METH_VARARGS, "stats(moves, array_of_bytes)"},
    {NULL, NULL, 0, NULL}};

static struct PyModuleDef moddef = {PyModuleDef_HEAD_INIT, "_core",
                                    "The compiled core of the HNC-21T interpreter.", -1, methods};

#define INTERN(var, s) do { var = PyUnicode_InternFromString(s); if (var == NULL) return NULL; } while (0)

PyMODINIT_FUNC PyInit__core(void)
{
    INTERN(s_block, "block"); INTERN(s_used, "used"); INTERN(s_f, "f"); INTERN(s_i, "i");
    INTERN(a_src, "src"); INTERN(a_m, "m"); INTERN(a_dry, "dry"); INTERN(a_comp_mode, "comp_mode");
    INTERN(a_corner, "corner"); INTERN(a_x, "x"); INTERN(a_z, "z"); INTERN(a_F, "F");
    INTERN(a_motion, "motion"); INTERN(a_absolute, "absolute"); INTERN(a_diam, "diam");
    INTERN(a_unit, "unit"); INTERN(a_per_rev, "per_rev"); INTERN(a_css, "css");
    INTERN(a_s_rpm, "s_rpm"); INTERN(a_vc, "vc"); INTERN(a_sdir, "sdir");
    INTERN(a_coolant, "coolant"); INTERN(a_tool, "tool"); INTERN(a_reg, "reg");
    INTERN(a_tdx, "tdx"); INTERN(a_tdz, "tdz"); INTERN(a_comp, "comp");
    INTERN(a_cyc_code, "cyc_code"); INTERN(a_blocks, "blocks"); INTERN(a_limit, "limit");
    INTERN(a_move_limit, "move_limit"); INTERN(a_moves, "moves"); INTERN(a_op, "op");
    INTERN(a_compiled, "compiled"); INTERN(a_kind, "kind"); INTERN(a_text, "text");
    INTERN(a_lineno, "lineno"); INTERN(a_max_rpm, "max_rpm"); INTERN(a_rapid_x, "rapid_x");
    INTERN(a_rapid_z, "rapid_z");
    return PyModule_Create(&moddef);
}
