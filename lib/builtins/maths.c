/* maths.c: the mathematical built-ins (LANGUAGE.md §5.4), quaternions
 * (§5.5), waveforms (§5.6) and easing (§5.7), built on the turn functions
 * sin_t/cos_t of turns.h (§5.2).
 *
 * Every function here is pure: it reads its argument vectors (borrowed) and
 * returns a new numeric vector, or NULL (null) when an argument is not the
 * numeric shape it needs; such "wrong shape" cases are silent, as in the
 * reference. Floating-point expressions are written in the reference's
 * evaluation order (left to right, no contraction; the build sets
 * -ffp-contract=off), because the results must be bit-identical.
 * Angles are in turns throughout. Matrices are column-major.
 */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "config.h"
#include "builtins.h"
#include "matrix.h"
#include "mem.h"
#include "turns.h"

/* The parameter list every builtin shares (BuiltinFn in builtins.h). */
#define PI 3.141592653589793

/* {====================================================================
 * Helpers
 * ===================================================================== */

/* A numeric vector of [n] elements, or NULL when n == 0. */
static Vec *new_nums(uint64_t n)
{
    return n ? vec_new_num((uint32_t)n) : NULL;
}

/* [xs] with [f] applied to each element; null unless [xs] is numeric. */
static Vec *map1(const Vec *xs, double (*f)(double))
{
    if (!vec_is_num(xs))
        return NULL;
    Vec *r = vec_new_num(xs->len);
    const double *x = vec_cnums(xs);
    double *y = vec_nums(r);
    for (uint32_t i = 0; i < xs->len; i++)
        y[i] = f(x[i]);
    return r;
}

/* The longest length of numeric vectors a, b and c. */
static uint32_t max3(const Vec *a, const Vec *b, const Vec *c)
{
    uint32_t n = a->len;
    if (b->len > n)
        n = b->len;
    if (c->len > n)
        n = c->len;
    return n;
}

/* C conversion double -> int64_t as the reference's x86 build performs it:
 * out-of-range values and NaN give INT64_MIN (never undefined behaviour). */
static int64_t to_i64(double x)
{
    if (x >= -9223372036854775808.0 && x < 9223372036854775808.0)
        return (int64_t)x;
    return INT64_MIN;
}

/* }==================================================================== */

/* {====================================================================
 * Element-wise functions (§5.4)
 * ===================================================================== */

static double f_fract(double x) { return x - floor(x); }
static double f_sinv(double x) { return sin_t(x); }
static double f_cosv(double x) { return cos_t(x); }
static double f_tanv(double x) { return tan(x * TAU); }
static double f_asinv(double x) { return asin(x) / TAU; }
static double f_acosv(double x) { return acos(x) / TAU; }

static Vec *bi_absv(BI_PARAMS) { return map1(args[0], fabs); }
static Vec *bi_floorv(BI_PARAMS) { return map1(args[0], floor); }
static Vec *bi_ceilv(BI_PARAMS) { return map1(args[0], ceil); }
static Vec *bi_fract(BI_PARAMS) { return map1(args[0], f_fract); }
static Vec *bi_sqrtv(BI_PARAMS) { return map1(args[0], sqrt); }
static Vec *bi_expv(BI_PARAMS) { return map1(args[0], exp); }
static Vec *bi_logv(BI_PARAMS) { return map1(args[0], log); }
static Vec *bi_log2v(BI_PARAMS) { return map1(args[0], log2); }
static Vec *bi_log10v(BI_PARAMS) { return map1(args[0], log10); }
static Vec *bi_sinv(BI_PARAMS) { return map1(args[0], f_sinv); }
static Vec *bi_cosv(BI_PARAMS) { return map1(args[0], f_cosv); }
static Vec *bi_tanv(BI_PARAMS) { return map1(args[0], f_tanv); }
static Vec *bi_asinv(BI_PARAMS) { return map1(args[0], f_asinv); }
static Vec *bi_acosv(BI_PARAMS) { return map1(args[0], f_acosv); }

/* round(xs, ys=0): p = 10**d as a wrapping 64-bit integer power (0 for
 * d < 0, the reference's quirk), then round(x * p) / p. */
static Vec *bi_roundv(BI_PARAMS)
{
    const Vec *xs = args[0];
    if (nargs > 1 && !vec_is_scalar(args[1]))
        return NULL;
    int64_t d = nargs > 1 ? to_i64(floor(vec_scalar(args[1]))) : 0;
    if (!vec_is_num(xs))
        return NULL;
    uint64_t p = 0;
    if (d >= 0) {
        uint64_t b = 10;
        p = 1;
        for (uint64_t e = (uint64_t)d; e; e >>= 1, b *= b)
            if (e & 1)
                p *= b;
    }
    double exponent = (double)(int64_t)p;
    Vec *r = vec_new_num(xs->len);
    const double *x = vec_cnums(xs);
    double *y = vec_nums(r);
    for (uint32_t i = 0; i < xs->len; i++)
        y[i] = round(x[i] * exponent) / exponent;
    return r;
}

static Vec *bi_polar(BI_PARAMS)
{
    const Vec *th = args[0];
    if (!vec_is_num(th))
        return NULL;
    if (2 * (uint64_t)th->len > MAX_RESULT)
        return bi_error(ev, bi, "result too long");
    if (!mem_fits(sizeof(Vec) + 2 * (size_t)th->len * sizeof(double)) && mem_take_refusal())
        return bi_error(ev, bi, "out of memory");
    Vec *r = vec_new_num(2 * th->len);
    const double *t = vec_cnums(th);
    double *y = vec_nums(r);
    for (uint32_t i = 0; i < th->len; i++)
        sincos_t(t[i], &y[2 * i + 1], &y[2 * i]);   /* cos_t, sin_t */
    return r;
}

/* angle(xy) / length(xy) over pairs, or angle(xs, ys) / length(xs, ys)
 * broadcast; [f] combines one (x, y). */
static Vec *pairwise(int nargs, Vec *const *args, double (*f)(double, double))
{
    const Vec *xy = args[0], *ys = nargs > 1 ? args[1] : NULL;
    if (!vec_is_num(xy) || (nargs > 1 && !vec_is_num(ys)))
        return NULL;
    const double *a = vec_cnums(xy);
    if (nargs == 1) {
        uint32_t n = xy->len / 2;
        Vec *r = new_nums(n);
        for (uint32_t i = 0; i < n; i++)
            vec_nums(r)[i] = f(a[2 * i], a[2 * i + 1]);
        return r;
    }
    const double *b = vec_cnums(ys);
    uint32_t n = xy->len > ys->len ? xy->len : ys->len;
    Vec *r = vec_new_num(n);
    /* (the wrapped indices counted, not divided, here and below) */
    for (uint32_t i = 0, ia = 0, ib = 0; i < n; i++) {
        vec_nums(r)[i] = f(a[ia], b[ib]);
        if (++ia == xy->len) ia = 0;
        if (++ib == ys->len) ib = 0;
    }
    return r;
}

static double f_angle(double x, double y) { return atan2(y, x) / TAU; }
static double f_length(double x, double y) { return sqrt(x * x + y * y); }

static Vec *bi_angle(BI_PARAMS) { return pairwise(nargs, args, f_angle); }
static Vec *bi_length(BI_PARAMS) { return pairwise(nargs, args, f_length); }

double bi_hypot_nums(const double *x, uint32_t n)
{
    double y = 0;
    for (uint32_t i = 0; i < n; i++)
        y += x[i] * x[i];
    return sqrt(y);
}

static Vec *bi_hypot(BI_PARAMS)
{
    if (nargs == 0)
        return NULL;
    if (nargs == 1) {
        if (!vec_is_num(args[0]))
            return NULL;
        return vec_num1(bi_hypot_nums(vec_cnums(args[0]), args[0]->len));
    }
    uint32_t n = 0;
    for (int k = 0; k < nargs; k++) {
        if (!vec_is_num(args[k]))
            return NULL;
        if (args[k]->len > n)
            n = args[k]->len;
    }
    Vec *r = vec_new_num(n);
    for (uint32_t i = 0; i < n; i++) {
        double y = 0;
        for (int k = 0; k < nargs; k++) {
            uint32_t len = args[k]->len;
            double x = vec_cnums(args[k])[len == n ? i : len == 1 ? 0 : i % len];
            y += x * x;
        }
        vec_nums(r)[i] = sqrt(y);
    }
    return r;
}

/* normalize of [n] doubles into a new vector; NULL when the squared sum
 * is 0 (the reference's Vector.normalize). */
static Vec *normalize_nums(const double *x, uint32_t n)
{
    double y = 0;
    for (uint32_t i = 0; i < n; i++)
        y += x[i] * x[i];
    if (y == 0 || n == 0)
        return NULL;
    y = sqrt(y);
    Vec *r = vec_new_num(n);
    for (uint32_t i = 0; i < n; i++)
        vec_nums(r)[i] = x[i] / y;
    return r;
}

static Vec *bi_normalize(BI_PARAMS)
{
    if (!vec_is_num(args[0]))
        return NULL;
    return normalize_nums(vec_cnums(args[0]), args[0]->len);
}

/* Σ xs[i mod n] * ys[i mod m] over max(n, m), left to right. */
static double dot_nums(const double *x, uint32_t n, const double *y, uint32_t m)
{
    uint32_t len = n > m ? n : m;
    double s = 0;
    for (uint32_t i = 0, ix = 0, iy = 0; i < len; i++) {
        s += x[ix] * y[iy];
        if (++ix == n) ix = 0;
        if (++iy == m) iy = 0;
    }
    return s;
}

static Vec *bi_dot(BI_PARAMS)
{
    const Vec *a = args[0], *b = args[1];
    if (!vec_is_num(a) || !vec_is_num(b))
        return NULL;
    return vec_num1(dot_nums(vec_cnums(a), a->len, vec_cnums(b), b->len));
}

static void cross3(const double *a, const double *b, double *r)
{
    r[0] = a[1] * b[2] - a[2] * b[1];
    r[1] = a[2] * b[0] - a[0] * b[2];
    r[2] = a[0] * b[1] - a[1] * b[0];
}

static Vec *bi_cross(BI_PARAMS)
{
    const Vec *a = args[0], *b = args[1];
    if (!vec_is_num(a) || a->len != 3 || !vec_is_num(b) || b->len != 3)
        return NULL;
    Vec *r = vec_new_num(3);
    cross3(vec_cnums(a), vec_cnums(b), vec_nums(r));
    return r;
}

/* clamp(xs, lo, hi)'s numbers: out[0..n) from the [nx], [nl], [nh]
 * numbers of xs, lo and hi, each repeated (n their largest count):
 * d = C max(lo, d) = (d > lo ? d : lo), then C min(d, hi) = (hi < d ? hi : d). */
static void clamp_nums(const double *xs, uint32_t nx, const double *lo, uint32_t nl, const double *hi,
                       uint32_t nh, double *out, uint32_t n)
{
    for (uint32_t i = 0, ix = 0, il = 0, ih = 0; i < n; i++) {
        out[i] = bi_clamp_num(xs[ix], lo[il], hi[ih]);
        if (++ix == nx) ix = 0;
        if (++il == nl) il = 0;
        if (++ih == nh) ih = 0;
    }
}

static Vec *bi_clamp(BI_PARAMS)
{
    const Vec *xs = args[0], *lo = args[1], *hi = args[2];
    if (!vec_is_num(xs) || !vec_is_num(lo) || !vec_is_num(hi))
        return NULL;
    uint32_t n = max3(xs, lo, hi);
    Vec *r = vec_new_num(n);
    clamp_nums(vec_cnums(xs), xs->len, vec_cnums(lo), lo->len, vec_cnums(hi), hi->len, vec_nums(r), n);
    return r;
}

/* map's numbers: out[0..n) = (1 - x)*y + x*z of the [nx], [ny], [nz]
 * numbers of xs, ys and zs, each repeated (n their largest count). */
static void map_nums(const double *xs, uint32_t nx, const double *ys, uint32_t ny, const double *zs,
                     uint32_t nz, double *out, uint32_t n)
{
    for (uint32_t i = 0, ix = 0, iy = 0, iz = 0; i < n; i++) {
        out[i] = bi_map_num(xs[ix], ys[iy], zs[iz]);
        if (++ix == nx) ix = 0;
        if (++iy == ny) iy = 0;
        if (++iz == nz) iz = 0;
    }
}

static Vec *bi_mapv(BI_PARAMS)
{
    const Vec *xs = args[0], *ys = args[1], *zs = args[2];
    if (!vec_is_num(xs) || !vec_is_num(ys) || !vec_is_num(zs))
        return NULL;
    uint32_t n = max3(xs, ys, zs);
    Vec *r = vec_new_num(n);
    map_nums(vec_cnums(xs), xs->len, vec_cnums(ys), ys->len, vec_cnums(zs), zs->len, vec_nums(r), n);
    return r;
}

/* }==================================================================== */

/* {====================================================================
 * Matrices: inverse, point_towards (§5.4)
 * ===================================================================== */

void mat3_inverse(const double m[9], double r[9])
{
    double s0 = m[0] * (m[4] * m[8] - m[7] * m[5]);
    double s1 = m[3] * (m[7] * m[2] - m[1] * m[8]);
    double s2 = m[6] * (m[1] * m[5] - m[4] * m[2]);
    double invdet = 1 / (s0 + s1 + s2);
    r[0] = (m[4] * m[8] - m[5] * m[7]) * invdet;
    r[1] = (m[2] * m[7] - m[1] * m[8]) * invdet;
    r[2] = (m[1] * m[5] - m[2] * m[4]) * invdet;
    r[3] = (m[5] * m[6] - m[3] * m[8]) * invdet;
    r[4] = (m[0] * m[8] - m[2] * m[6]) * invdet;
    r[5] = (m[2] * m[3] - m[0] * m[5]) * invdet;
    r[6] = (m[3] * m[7] - m[4] * m[6]) * invdet;
    r[7] = (m[1] * m[6] - m[0] * m[7]) * invdet;
    r[8] = (m[0] * m[4] - m[1] * m[3]) * invdet;
}

/* 4×4 inverse by 2×2 sub-determinants, in the reference's term order. */
static void inverse44(const double *m, double *r)
{
    double s0 = m[0] * m[5] - m[4] * m[1];
    double s1 = m[0] * m[6] - m[4] * m[2];
    double s2 = m[0] * m[7] - m[4] * m[3];
    double s3 = m[1] * m[6] - m[5] * m[2];
    double s4 = m[1] * m[7] - m[5] * m[3];
    double s5 = m[2] * m[7] - m[6] * m[3];
    double c5 = m[10] * m[15] - m[14] * m[11];
    double c4 = m[9] * m[15] - m[13] * m[11];
    double c3 = m[9] * m[14] - m[13] * m[10];
    double c2 = m[8] * m[15] - m[12] * m[11];
    double c1 = m[8] * m[14] - m[12] * m[10];
    double c0 = m[8] * m[13] - m[12] * m[9];
    double invdet = 1 / (s0 * c5 - s1 * c4 + s2 * c3 + s3 * c2 - s4 * c1 + s5 * c0);
    r[0] = (m[5] * c5 - m[6] * c4 + m[7] * c3) * invdet;
    r[1] = (-m[1] * c5 + m[2] * c4 - m[3] * c3) * invdet;
    r[2] = (m[13] * s5 - m[14] * s4 + m[15] * s3) * invdet;
    r[3] = (-m[9] * s5 + m[10] * s4 - m[11] * s3) * invdet;
    r[4] = (-m[4] * c5 + m[6] * c2 - m[7] * c1) * invdet;
    r[5] = (m[0] * c5 - m[2] * c2 + m[3] * c1) * invdet;
    r[6] = (-m[12] * s5 + m[14] * s2 - m[15] * s1) * invdet;
    r[7] = (m[8] * s5 - m[10] * s2 + m[11] * s1) * invdet;
    r[8] = (m[4] * c4 - m[5] * c2 + m[7] * c0) * invdet;
    r[9] = (-m[0] * c4 + m[1] * c2 - m[3] * c0) * invdet;
    r[10] = (m[12] * s4 - m[13] * s2 + m[15] * s0) * invdet;
    r[11] = (-m[8] * s4 + m[9] * s2 - m[11] * s0) * invdet;
    r[12] = (-m[4] * c3 + m[5] * c1 - m[6] * c0) * invdet;
    r[13] = (m[0] * c3 - m[1] * c1 + m[2] * c0) * invdet;
    r[14] = (-m[12] * s3 + m[13] * s1 - m[14] * s0) * invdet;
    r[15] = (m[8] * s3 - m[9] * s1 + m[10] * s0) * invdet;
}

/* r = a × b for column-major 4×4 matrices, each sum left to right. */
static void mmul44(const double *a, const double *b, double *r)
{
    for (int c = 0; c < 4; c++)
        for (int row = 0; row < 4; row++)
            r[c * 4 + row] = a[row] * b[c * 4] + a[4 + row] * b[c * 4 + 1]
                             + a[8 + row] * b[c * 4 + 2] + a[12 + row] * b[c * 4 + 3];
}

static Vec *bi_inverse(BI_PARAMS)
{
    const Vec *m = args[0];
    if (!vec_is_num(m) || (m->len != 9 && m->len != 16))
        return NULL;
    Vec *r = vec_new_num(m->len);
    if (m->len == 9)
        mat3_inverse(vec_cnums(m), vec_nums(r));
    else
        inverse44(vec_cnums(m), vec_nums(r));
    return r;
}

/* Broadcast a[i mod na] OP b[i mod nb] into out (capacity cap); returns
 * the length, 0 when either side is empty. op: '-' or '*'. */
static uint32_t bcast(char op, const double *a, uint32_t na, const double *b, uint32_t nb,
                      double *out, uint32_t cap)
{
    if (na == 0 || nb == 0)
        return 0;
    uint32_t n = na > nb ? na : nb;
    if (n > cap)
        return 0;
    for (uint32_t i = 0; i < n; i++)
        out[i] = op == '-' ? a[i % na] - b[i % nb] : a[i % na] * b[i % nb];
    return n;
}

/* point_towards(direction, up): the reference's look-at matrix from the
 * origin (z = normalize(0 - direction), y = normalize(up - z (up·z)),
 * x = y × z), multiplied by a translation by -0, then inverted. Every
 * intermediate is computed with the reference's broadcasting vector
 * operations, so only lengths of 3 lead to a result. */
static Vec *bi_point_towards(BI_PARAMS)
{
    const Vec *dir = args[0], *up = args[1];
    if (!vec_is_num(dir) || !vec_is_num(up) || dir->len > 3 || up->len > 3)
        return NULL; /* any longer input makes z or y longer than 3 */
    static const double origin[3] = {0, 0, 0};
    double z[3], zn[3], t[3], y[3], yn[3], x[3];
    uint32_t nz = bcast('-', origin, 3, vec_cnums(dir), dir->len, z, 3);
    Vec *zv = normalize_nums(z, nz);
    if (!zv)
        return NULL;
    memcpy(zn, vec_cnums(zv), sizeof zn);
    vec_release(zv);
    double d = dot_nums(vec_cnums(up), up->len, zn, 3);
    bcast('*', zn, 3, &d, 1, t, 3);
    uint32_t ny = bcast('-', vec_cnums(up), up->len, t, 3, y, 3);
    Vec *yv = normalize_nums(y, ny);
    if (!yv)
        return NULL;
    memcpy(yn, vec_cnums(yv), sizeof yn);
    vec_release(yv);
    cross3(yn, zn, x);
    double look[16] = {x[0], yn[0], zn[0], 0, x[1], yn[1], zn[1], 0,
                       x[2], yn[2], zn[2], 0, 0, 0, 0, 1};
    double trans[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -0.0, -0.0, -0.0, 1};
    double m[16];
    mmul44(look, trans, m);
    Vec *r = vec_new_num(16);
    inverse44(m, vec_nums(r));
    return r;
}

/* }==================================================================== */

/* {====================================================================
 * Quaternions (§5.5), w;x;y;z
 * ===================================================================== */

/* Hamilton product r = a ⊗ b. */
static void qmul4(const double *a, const double *b, double *r)
{
    double aw = a[0], ax = a[1], ay = a[2], az = a[3];
    double bw = b[0], bx = b[1], by = b[2], bz = b[3];
    r[0] = aw * bw - ax * bx - ay * by - az * bz;
    r[1] = aw * bx + ax * bw + ay * bz - az * by;
    r[2] = aw * by + ay * bw + az * bx - ax * bz;
    r[3] = aw * bz + az * bw + ax * by - ay * bx;
}

static Vec *bi_quaternion(BI_PARAMS)
{
    const Vec *axis = args[0], *angle = args[1];
    if (!vec_is_num(axis) || axis->len != 3 || !vec_is_scalar(angle))
        return NULL;
    const double *a = vec_cnums(axis);
    double x = a[0], y = a[1], z = a[2];
    double h = vec_scalar(angle) / 2;
    double k = sin_t(h) / sqrt(x * x + y * y + z * z);
    Vec *r = vec_new_num(4);
    double *q = vec_nums(r);
    q[0] = cos_t(h);
    q[1] = k * x;
    q[2] = k * y;
    q[3] = k * z;
    return r;
}

static Vec *bi_qmul(BI_PARAMS)
{
    const Vec *a = args[0], *b = args[1];
    if (!vec_is_num(a) || a->len != 4 || !vec_is_num(b) || (b->len != 3 && b->len != 4))
        return NULL;
    const double *p = vec_cnums(a), *v = vec_cnums(b);
    if (b->len == 4) {
        Vec *r = vec_new_num(4);
        qmul4(p, v, vec_nums(r));
        return r;
    }
    /* rotate the 3-vector v by p: (p ⊗ v) ⊗ p⁻¹ */
    double x = v[0], y = v[1], z = v[2];
    double aw = p[0], ax = p[1], ay = p[2], az = p[3];
    double bw = -ax * x - ay * y - az * z;
    double bx = aw * x + ay * z - az * y;
    double by = aw * y + az * x - ax * z;
    double bz = aw * z + ax * y - ay * x;
    double s = 1 / (ax * ax + ay * ay + az * az + aw * aw);
    aw *= s;
    ax *= -s;
    ay *= -s;
    az *= -s;
    Vec *r = vec_new_num(3);
    double *o = vec_nums(r);
    o[0] = bw * ax + bx * aw + by * az - bz * ay;
    o[1] = bw * ay + by * aw + bz * ax - bx * az;
    o[2] = bw * az + bz * aw + bx * ay - by * ax;
    return r;
}

static Vec *bi_qbetween(BI_PARAMS)
{
    const Vec *av = args[0], *bv = args[1];
    if (!vec_is_num(av) || av->len != 3 || !vec_is_num(bv) || bv->len != 3)
        return NULL;
    const double *a = vec_cnums(av), *b = vec_cnums(bv);
    double ax = a[0], ay = a[1], az = a[2];
    double s = 1 / sqrt(ax * ax + ay * ay + az * az);
    ax *= s;
    ay *= s;
    az *= s;
    double bx = b[0], by = b[1], bz = b[2];
    s = 1 / sqrt(bx * bx + by * by + bz * bz);
    bx *= s;
    by *= s;
    bz *= s;
    double cth = ax * bx + ay * by + az * bz;
    Vec *r = vec_new_num(4);
    double *q = vec_nums(r);
    s = sqrt((1 + cth) * 2);
    if (s != 0) {
        double x = ay * bz - az * by;
        double y = az * bx - ax * bz;
        double z = ax * by - ay * bx;
        double k = 1 / s;
        q[0] = s / 2;
        q[1] = x * k;
        q[2] = y * k;
        q[3] = z * k;
    } else {
        double x, y, z;
        if (ax != 0 || ay != 0) {
            x = -ay;
            y = ax;
            z = 0;
        } else {
            x = 0;
            y = -az;
            z = ay;
        }
        s = 1 / sqrt(x * x + y * y + z * z);
        q[0] = 0;
        q[1] = x * s;
        q[2] = y * s;
        q[3] = z * s;
    }
    return r;
}

/* slerp(t, p, q) = ((q ⊗ p⁻¹)^t) ⊗ p, the power taken through C acos,
 * sin and cos in radians. */
static Vec *bi_slerp(BI_PARAMS)
{
    const Vec *tv = args[0], *pv = args[1], *qv = args[2];
    if (!vec_is_scalar(tv) || !vec_is_num(pv) || pv->len != 4 || !vec_is_num(qv) || qv->len != 4)
        return NULL;
    const double *p = vec_cnums(pv);
    double aw = p[0], ax = p[1], ay = p[2], az = p[3];
    double s = 1 / (ax * ax + ay * ay + az * az + aw * aw);
    double inv[4] = {aw * s, -ax * s, -ay * s, -az * s};
    double r[4], e[4];
    qmul4(vec_cnums(qv), inv, r);
    double th = acos(r[0]), sth = sin(th);
    th *= vec_scalar(tv);
    sth = sth != 0 ? sin(th) / sth : 0;
    e[1] = r[1] * sth;
    e[2] = r[2] * sth;
    e[3] = r[3] * sth;
    e[0] = cos(th);
    Vec *out = vec_new_num(4);
    qmul4(e, p, vec_nums(out));
    return out;
}

/* }==================================================================== */

/* {====================================================================
 * Waveforms (§5.6) and easing (§5.7)
 * ===================================================================== */

static double f_sine(double x) { return (1 - cos_t(x)) / 2; }
static double f_bounce(double x) { return sin(PI * (x - floor(x))); }
static double f_sawtooth(double x) { return x - floor(x); }
static double f_triangle(double x) { return 1 - fabs((x - floor(x)) * 2 - 1); }

static double f_square(double x)
{
    x -= floor(x);
    return x < 0.5 ? 0 : 1;
}

static double f_sharkfin(double x)
{
    x -= floor(x);
    return x < 0.5 ? sin(PI * x) : 1 - sin(PI * (x - 0.5));
}

static double f_linear(double x)
{
    if (x < 0)
        return 0;
    if (x > 1)
        return 1;
    return x;
}

static double f_quad(double x)
{
    if (x < 0)
        return 0;
    if (x > 1)
        return 1;
    if (x < 0.5) {
        double a = x * 2;
        return a * a / 2;
    }
    double a = (1 - x) * 2;
    return 1 - a * a / 2;
}

static double f_cubic(double x)
{
    if (x < 0)
        return 0;
    if (x > 1)
        return 1;
    if (x < 0.5) {
        double a = x * 2;
        return a * a * a / 2;
    }
    double a = (1 - x) * 2;
    return 1 - a * a * a / 2;
}

static double f_snap(double x)
{
    if (x < 0)
        x = 0;
    else if (x > 1)
        x = 1;
    return x < 0.5 ? sqrt(x * 2) / 2 : 1 - sqrt((1 - x) * 2) / 2;
}

static Vec *bi_sine(BI_PARAMS) { return map1(args[0], f_sine); }
static Vec *bi_bounce(BI_PARAMS) { return map1(args[0], f_bounce); }
static Vec *bi_sawtooth(BI_PARAMS) { return map1(args[0], f_sawtooth); }
static Vec *bi_triangle(BI_PARAMS) { return map1(args[0], f_triangle); }
static Vec *bi_square(BI_PARAMS) { return map1(args[0], f_square); }
static Vec *bi_sharkfin(BI_PARAMS) { return map1(args[0], f_sharkfin); }
static Vec *bi_linear(BI_PARAMS) { return map1(args[0], f_linear); }
static Vec *bi_quad(BI_PARAMS) { return map1(args[0], f_quad); }
static Vec *bi_cubic(BI_PARAMS) { return map1(args[0], f_cubic); }
static Vec *bi_snap(BI_PARAMS) { return map1(args[0], f_snap); }

/* impulse(xs, cs=0.25): attack to 1 over [0, c), cubic decay after. */
static Vec *bi_impulse(BI_PARAMS)
{
    const Vec *xs = args[0], *cs = nargs > 1 ? args[1] : NULL;
    if (!vec_is_num(xs) || (nargs > 1 && !vec_is_num(cs)))
        return NULL;
    Vec *r = vec_new_num(xs->len);
    for (uint32_t i = 0; i < xs->len; i++) {
        double x = vec_cnums(xs)[i];
        x -= floor(x);
        double c = cs ? vec_cnums(cs)[i % cs->len] : 0.25;
        double y, yy;
        if (x < c) {
            y = 1 - x / c;
            yy = y * y;
            y = 1 - yy * y;
        } else {
            y = 1 - (x - c) / (1 - c);
            yy = y * y;
            y = yy * y;
        }
        vec_nums(r)[i] = y;
    }
    return r;
}

/* }==================================================================== */

/* The element kernel of every builtin above that is map1(args[0], f): the
 * same f, for callers holding a single number (bi_kernel). */
static const struct {
    BuiltinFn fn;
    double (*kernel)(double);
} kernels[] = {
    {bi_absv, fabs},
    {bi_floorv, floor},
    {bi_ceilv, ceil},
    {bi_fract, f_fract},
    {bi_sqrtv, sqrt},
    {bi_expv, exp},
    {bi_logv, log},
    {bi_log2v, log2},
    {bi_log10v, log10},
    {bi_sinv, f_sinv},
    {bi_cosv, f_cosv},
    {bi_tanv, f_tanv},
    {bi_asinv, f_asinv},
    {bi_acosv, f_acosv},
    {bi_sine, f_sine},
    {bi_bounce, f_bounce},
    {bi_sawtooth, f_sawtooth},
    {bi_triangle, f_triangle},
    {bi_square, f_square},
    {bi_sharkfin, f_sharkfin},
    {bi_linear, f_linear},
    {bi_quad, f_quad},
    {bi_cubic, f_cubic},
    {bi_snap, f_snap},
};

bool bi_is_hypot(const Builtin *bi) { return bi && bi->fn == bi_hypot; }

BiKernel bi_kernel(const Builtin *bi)
{
    for (size_t i = 0; i < sizeof kernels / sizeof kernels[0]; i++)
        if (kernels[i].fn == bi->fn) return kernels[i].kernel;
    return NULL;
}

/* bi_nums_route_id's numbers: hypot; an element kernel (ROUTE_KERNEL +
 * its index in kernels[]); a numeric kernel (ROUTE_VEC + its index,
 * bi_vec_kernel_index) */
#define ROUTE_HYPOT 1
#define ROUTE_KERNEL 2
#define ROUTE_VEC 128
_Static_assert(ROUTE_KERNEL + sizeof kernels / sizeof kernels[0] <= ROUTE_VEC, "route numbers apart");

uint16_t bi_nums_route_id(const Builtin *bi)
{
    if (!bi)
        return 0;
    if (bi->fn == bi_hypot)
        return ROUTE_HYPOT;
    for (size_t i = 0; i < sizeof kernels / sizeof kernels[0]; i++)
        if (kernels[i].fn == bi->fn)
            return (uint16_t)(ROUTE_KERNEL + i);
    int v = bi_vec_kernel_index(bi);
    return v >= 0 ? (uint16_t)(ROUTE_VEC + v) : 0;
}

bool bi_nums_route(const Builtin *bi)
{
    return bi_nums_route_id(bi) != 0;
}

bool bi_call_nums_id(uint16_t id, const double *x, uint32_t n, double *out, uint32_t *nout)
{
    if (n < 1 || n > BI_NUMS_MAX || !id)
        return false;
    if (id == ROUTE_HYPOT) {
        out[0] = bi_hypot_nums(x, n);
        *nout = 1;
        return true;
    }
    if (id < ROUTE_VEC) {
        BiKernel k = kernels[id - ROUTE_KERNEL].kernel;
        for (uint32_t i = 0; i < n; i++)
            out[i] = k(x[i]);
        *nout = n;
        return true;
    }
    const BiVecKernel *vk = bi_vec_kernel_at(id - ROUTE_VEC);
    if (!vk || !vk->run(x, n, out))
        return false;
    *nout = vk->nout(n);
    return true;
}

bool bi_call_nums(const Builtin *bi, const double *x, uint32_t n, double *out, uint32_t *nout)
{
    return bi_call_nums_id(bi_nums_route_id(bi), x, n, out, nout);
}

/* A call of map or clamp with their three arguments. */
static bool map_or_clamp(const Builtin *bi, uint32_t nargs)
{
    return nargs == 3 && (bi->fn == bi_mapv || bi->fn == bi_clamp);
}

int bi_map_or_clamp(const Builtin *bi)
{
    return !bi ? 0 : bi->fn == bi_mapv ? BI_MAP : bi->fn == bi_clamp ? BI_CLAMP : 0;
}

bool bi_args_route(const Builtin *bi, uint32_t nargs)
{
    return map_or_clamp(bi, nargs) || bi_noise_route(bi, nargs);
}

bool bi_call_nums_args(Eval *ev, const Builtin *bi, const double *const *x, const uint32_t *n, uint32_t nargs,
                       double *out, uint32_t *nout)
{
    if (map_or_clamp(bi, nargs)) {
        uint32_t m = n[0] > n[1] ? n[0] : n[1];
        if (n[2] > m)
            m = n[2];
        if (!n[0] || !n[1] || !n[2] || m > BI_NUMS_MAX)
            return false;
        (bi->fn == bi_mapv ? map_nums : clamp_nums)(x[0], n[0], x[1], n[1], x[2], n[2], out, m);
        *nout = m;
        return true;
    }
    return bi_noise_nums(ev, bi, x, n, nargs, out, nout);
}

BiKernelPair bi_kernel_pair(BiKernel a, BiKernel *b)
{
    if (a != f_sinv) return NULL;
    *b = f_cosv;
    return sincos_t;
}

/* The maths family, grouped as §5.4-§5.7 list them. Keyword names are
 * the reference's parameter names. */
const Builtin bi_maths_table[] = {
    {"abs", "absv", 1, 1, {"xs"}, bi_absv, 0},
    {"floor", "floorv", 1, 1, {"xs"}, bi_floorv, 0},
    {"ceil", "ceilv", 1, 1, {"xs"}, bi_ceilv, 0},
    {"fract", "fract", 1, 1, {"xs"}, bi_fract, 0},
    {"round", "roundv", 1, 2, {"xs", "ys"}, bi_roundv, 0},
    {"sqrt", "sqrtv", 1, 1, {"xs"}, bi_sqrtv, 0},
    {"exp", "expv", 1, 1, {"xs"}, bi_expv, 0},
    {"log", "logv", 1, 1, {"xs"}, bi_logv, 0},
    {"log2", "log2v", 1, 1, {"xs"}, bi_log2v, 0},
    {"log10", "log10v", 1, 1, {"xs"}, bi_log10v, 0},
    {"sin", "sinv", 1, 1, {"theta"}, bi_sinv, 0},
    {"cos", "cosv", 1, 1, {"theta"}, bi_cosv, 0},
    {"tan", "tanv", 1, 1, {"theta"}, bi_tanv, 0},
    {"asin", "asinv", 1, 1, {"ys"}, bi_asinv, 0},
    {"acos", "acosv", 1, 1, {"ys"}, bi_acosv, 0},
    {"polar", "polar", 1, 1, {"theta"}, bi_polar, 0},
    {"angle", "angle", 1, 2, {"xy", "ys"}, bi_angle, 0},
    {"length", "length", 1, 2, {"xy", "ys"}, bi_length, 0},
    {"hypot", "hypot", 0, BI_VARIADIC, {NULL}, bi_hypot, 0},
    {"normalize", "normalize", 1, 1, {"xs"}, bi_normalize, 0},
    {"dot", "dot", 2, 2, {"xs", "ys"}, bi_dot, 0},
    {"cross", "cross", 2, 2, {"xs", "ys"}, bi_cross, 0},
    {"clamp", "clamp", 3, 3, {"xs", "ys", "zs"}, bi_clamp, 0},
    {"map", "mapv", 3, 3, {"xs", "ys", "zs"}, bi_mapv, 0},
    {"inverse", "inverse", 1, 1, {"matrix"}, bi_inverse, 0},
    {"point_towards", "point_towards", 2, 2, {"direction", "up"}, bi_point_towards, 0},
    {"quaternion", "quaternion", 2, 2, {"axis", "angle"}, bi_quaternion, 0},
    {"qmul", "qmul", 2, 2, {"a", "b"}, bi_qmul, 0},
    {"qbetween", "qbetween", 2, 2, {"a", "b"}, bi_qbetween, 0},
    {"slerp", "slerp", 3, 3, {"t", "a", "b"}, bi_slerp, 0},
    {"sine", "sine", 1, 1, {"xs"}, bi_sine, 0},
    {"bounce", "bounce", 1, 1, {"xs"}, bi_bounce, 0},
    {"sawtooth", "sawtooth", 1, 1, {"xs"}, bi_sawtooth, 0},
    {"triangle", "triangle", 1, 1, {"xs"}, bi_triangle, 0},
    {"square", "square", 1, 1, {"xs"}, bi_square, 0},
    {"sharkfin", "sharkfin", 1, 1, {"xs"}, bi_sharkfin, 0},
    {"impulse", "impulse", 1, 2, {"xs", "cs"}, bi_impulse, 0},
    {"linear", "linear", 1, 1, {"xs"}, bi_linear, 0},
    {"quad", "quad", 1, 1, {"xs"}, bi_quad, 0},
    {"cubic", "cubic", 1, 1, {"xs"}, bi_cubic, 0},
    {"snap", "snap", 1, 1, {"xs"}, bi_snap, 0},
    {NULL, NULL, 0, 0, {NULL}, NULL, 0},
};
