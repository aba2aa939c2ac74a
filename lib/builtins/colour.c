/* colour.c: the colour built-ins hsl, hsv, colortemp, oklab and oklch
 * (LANGUAGE.md §5.10), exported as bi_colour_table.
 *
 * Every operation is written out in the reference's evaluation order so the
 * results are bit-identical: hue sectors from `hsl`, the CIE daylight-locus
 * polynomials of `colortemp` (with `T³` as `T*(T*T)` and `c*x*x²` as
 * `(c*x)*x²`), and the OKLab matrices, whose inverses are computed with the
 * 3×3 adjugate formula of `inverse()` on each call (a handful of operations;
 * no mutable global state). Matrices are stored column-major like the
 * reference: element (row k, column c) is m[k + 3*c].
 */
#include <math.h>
#include <stdbool.h>
#include <stdint.h>

#include "builtins.h"
#include "matrix.h"
#include "turns.h"

/* "C max(a,b)" and "C min(a,b)" of LANGUAGE.md §5.2. */
static double cmax(double a, double b) { return (b > a) ? b : a; }
static double cmin(double a, double b) { return (b < a) ? b : a; }

/* ------------------------------------------------------------------ */
/* HSL / HSV                                                           */
/* ------------------------------------------------------------------ */

/* A number congruent to t modulo 6 in (-6, 6), exactly, without the libm
 * call for |t| < 2^48: where it differs from fmod(t, 6) (by 6, or in the
 * sign of a zero), hue_to_rgb's `t < 0: t += 6` makes the two the same
 * number. For |t| < 6 that is t itself; below 12, t - 6 or t + 6
 * (Sterbenz: the difference is representable). Beyond, t - 6k for k the
 * quotient t / 6 truncated, which its rounding may make one too large in
 * magnitude: 6k is exact (an integer below 2^51), and so is t - 6k, a
 * difference that is a multiple of t's last place and smaller than t.
 * Larger, infinite or NaN t go to fmod. Hues that grow with the beat
 * (`hsv(beat/10;1;1)`) pass 12 within minutes. */
static inline __attribute__((always_inline)) double mod6(double t)
{
    if (t > -6 && t < 6)
        return t;
    if (t >= 6 && t < 12)
        return t - 6;
    if (t < -6 && t > -12)
        return t + 6;
    if (t > -0x1p48 && t < 0x1p48)
        return t - 6 * (double)(int64_t)(t / 6);
    return fmod(t, 6);
}

/* One channel of hsl_rgb: each case's formula as the reference computes
 * it, both slopes computed and the case's value chosen (no branch on the
 * hue to mispredict: a loop kernel's lanes have many hues) */
static inline __attribute__((always_inline)) double hue_to_rgb(double m1, double m2, double t)
{
    t = mod6(t);
    if (t < 0)
        t += 6;
    const double up = m1 + (m2 - m1) * t, down = m1 + (m2 - m1) * (4 - t);
    return t < 1 ? up : t < 3 ? m2 : t < 4 ? down : m1;
}

/* RGB of hue [h], saturation [s], lightness [l] (already clamped) into
 * out[0..3). */
static inline __attribute__((always_inline)) void hsl_rgb(double h, double s, double l, double *out)
{
    double m2 = (l <= 0.5) ? l * (s + 1) : l + s - l * s;
    double m1 = l * 2 - m2;
    h *= 6;
    out[0] = hue_to_rgb(m1, m2, h + 2);
    out[1] = hue_to_rgb(m1, m2, h);
    out[2] = hue_to_rgb(m1, m2, h - 2);
}

/* hsl of the [n] numbers [x] into out[0..3); false when its result is
 * null (not three numbers). */
static bool hsl_nums(const double *x, uint32_t n, double *out)
{
    if (n != 3)
        return false;
    double s = cmin(cmax(0, x[1]), 1);
    double l = cmin(cmax(0, x[2]), 1);
    hsl_rgb(x[0], s, l, out);
    return true;
}

/* hsv of the [n] numbers [x] into out[0..3); false when its result is
 * null (not one to three numbers). */
static bool hsv_nums(const double *x, uint32_t n, double *out)
{
    if (n < 1 || n > 3)
        return false;
    double h = x[0];
    double s = n > 1 ? x[1] : 1;
    double v = n == 3 ? x[2] : 1;
    s = cmin(cmax(0, s), 1);
    v = cmin(cmax(0, v), 1);
    double l = v * (1 - s / 2);
    double s2 = (l == 0 || l == 1) ? 0 : (v - l) / cmin(l, 1 - l);
    hsl_rgb(h, s2, l, out);
    return true;
}

/* A builtin of one numeric argument whose result is three numbers. */
static inline __attribute__((always_inline)) Vec *rgb_of(const Vec *c, bool (*f)(const double *, uint32_t, double *))
{
    double rgb[3];
    if (!vec_is_num(c) || !f(vec_cnums(c), c->len, rgb))
        return NULL;
    Vec *v = vec_new_num(3);
    double *d = vec_nums(v);
    d[0] = rgb[0];
    d[1] = rgb[1];
    d[2] = rgb[2];
    return v;
}

static Vec *bi_hsl(Eval *ev, const Builtin *bi, int nargs, Vec *const *args)
{
    (void)ev; (void)bi; (void)nargs;
    return rgb_of(args[0], hsl_nums);
}

static Vec *bi_hsv(Eval *ev, const Builtin *bi, int nargs, Vec *const *args)
{
    (void)ev; (void)bi; (void)nargs;
    return rgb_of(args[0], hsv_nums);
}

static uint32_t three(uint32_t n)
{
    (void)n;
    return 3;
}

static const BiVecKernel vec_kernels[] = {
    {bi_hsl, three, hsl_nums},
    {bi_hsv, three, hsv_nums},
};

int bi_vec_kernel_index(const Builtin *bi)
{
    for (size_t i = 0; i < sizeof vec_kernels / sizeof vec_kernels[0]; i++)
        if (vec_kernels[i].fn == bi->fn) return (int)i;
    return -1;
}

const BiVecKernel *bi_vec_kernel_at(int i)
{
    return i >= 0 && (size_t)i < sizeof vec_kernels / sizeof vec_kernels[0] ? &vec_kernels[i] : NULL;
}

const BiVecKernel *bi_vec_kernel(const Builtin *bi)
{
    return bi_vec_kernel_at(bi_vec_kernel_index(bi));
}

/* ------------------------------------------------------------------ */
/* Colour temperature                                                  */
/* ------------------------------------------------------------------ */

static Vec *bi_colortemp(Eval *ev, const Builtin *bi, int nargs, Vec *const *args)
{
    (void)ev; (void)bi;
    const Vec *t = args[0];
    if (!vec_is_num(t))
        return NULL;
    bool norm = nargs > 1 && vec_truthy(args[1]);
    uint32_t n = t->len;
    if (n > UINT32_MAX / 3)
        return NULL;
    const double *tv = vec_cnums(t);
    Vec *rgb = vec_new_num(3 * n);
    double *out = vec_nums(rgb);
    for (uint32_t i = 0; i < n; i++) {
        double T = cmin(cmax(1667, tv[i]), 25000);
        double T2 = T * T;
        double x, y;
        if (T < 4000)
            x = -0.2661239e9 / (T * T2) - 0.2343589e6 / T2 + 0.8776956e3 / T + 0.179910;
        else
            x = -3.0258469e9 / (T * T2) + 2.1070379e6 / T2 + 0.2226347e3 / T + 0.240390;
        double x2 = x * x;
        if (T < 2222)
            y = -1.1063814 * x * x2 - 1.34811020 * x2 + 2.18555832 * x - 0.20219683;
        else if (T < 4000)
            y = -0.9549476 * x * x2 - 1.37418593 * x2 + 2.09137015 * x - 0.16748867;
        else
            y = 3.0817580 * x * x2 - 5.87338670 * x2 + 3.75112997 * x - 0.37001483;
        double Y = norm ? 1 : pow(cmax(0, tv[i]) / 6503.5, 4);
        double X = Y * x / y;
        double Z = Y * (1 - x - y) / y;
        out[3 * i] = cmax(0, 3.2406255 * X - 1.537208 * Y - 0.4986286 * Z);
        out[3 * i + 1] = cmax(0, -0.9689307 * X + 1.8757561 * Y + 0.0415175 * Z);
        out[3 * i + 2] = cmax(0, 0.0557101 * X - 0.2040211 * Y + 1.0569959 * Z);
    }
    return rgb;
}

/* ------------------------------------------------------------------ */
/* OKLab / OKLCh                                                       */
/* ------------------------------------------------------------------ */

/* Column-major matrices of LANGUAGE.md §5.10. */
static const double OKLAB_M1[9] = {
    0.8189330101, 0.0329845436, 0.0482003018,
    0.3618667424, 0.9293118715, 0.2643662691,
    -0.1288597137, 0.0361456387, 0.6338517070,
};
static const double OKLAB_M2[9] = {
    0.2104542553, 1.9779984951, 0.0259040371,
    0.7936177850, -2.4285922050, 0.7827717662,
    -0.0040720468, 0.4505937099, -0.8086757660,
};
static const double XYZ_TO_SRGB[9] = {
    3.2406, -0.9689, 0.0557,
    -1.5372, 1.8758, -0.2040,
    -0.4986, 0.0415, 1.0570,
};

/* r = m · v (column order summation). [r] must not alias [v]. */
static void mat3_vmul(const double m[9], const double v[3], double r[3])
{
    for (int k = 0; k < 3; k++)
        r[k] = m[k] * v[0] + m[k + 3] * v[1] + m[k + 6] * v[2];
}

/* sRGB of OKLab (L, a, b). */
static Vec *oklab_to_rgb(const double lab[3])
{
    double m1_inv[9], m2_inv[9], lms[3], xyz[3];
    mat3_inverse(OKLAB_M1, m1_inv);
    mat3_inverse(OKLAB_M2, m2_inv);
    mat3_vmul(m2_inv, lab, lms);
    for (int k = 0; k < 3; k++)
        lms[k] = pow(lms[k], 3);
    mat3_vmul(m1_inv, lms, xyz);
    Vec *rgb = vec_new_num(3);
    mat3_vmul(XYZ_TO_SRGB, xyz, vec_nums(rgb));
    return rgb;
}

static Vec *bi_oklab(Eval *ev, const Builtin *bi, int nargs, Vec *const *args)
{
    (void)ev; (void)bi; (void)nargs;
    const Vec *c = args[0];
    if (!vec_is_num(c) || c->len != 3)
        return NULL;
    return oklab_to_rgb(vec_cnums(c));
}

static Vec *bi_oklch(Eval *ev, const Builtin *bi, int nargs, Vec *const *args)
{
    (void)ev; (void)bi; (void)nargs;
    const Vec *c = args[0];
    if (!vec_is_num(c) || c->len != 3)
        return NULL;
    const double *x = vec_cnums(c);
    double lab[3] = {x[0], x[1] * cos_t(x[2]), x[1] * sin_t(x[2])};
    return oklab_to_rgb(lab);
}

const Builtin bi_colour_table[] = {
    {"hsl", "hsl", 1, 1, {"color"}, bi_hsl, 0},
    {"hsv", "hsv", 1, 1, {"color"}, bi_hsv, 0},
    {"colortemp", "colortemp", 1, 2, {"t", "normalize"}, bi_colortemp, 0},
    {"oklab", "oklab", 1, 1, {"lab"}, bi_oklab, 0},
    {"oklch", "oklch", 1, 1, {"lch"}, bi_oklch, 0},
    {NULL, NULL, 0, 0, {NULL}, NULL, 0},
};
