/* test_bloom_literal.c: the !bloom passes and the sRGB encoding
 * (lib/render/bloom.c, srgb.c), whose fast routes compute a pixel as one
 * vector, against the literal route written here one float at a time from
 * bloom.h's description (bilinear taps clamped at the edges, adjust,
 * Gaussian x then y with clamped edges, bilinear back up, lighten, alpha),
 * bit for bit, on random pictures with special values (zeros of both
 * signs, NaN, infinities, values above 1, alpha 0), odd and tiny sizes,
 * downsample 1 to 3, radii 0 to 9 and with shadows and highlights (the
 * scalar adjust) as well as without (the vector one). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include <cairo.h>

#include "bloom.h"
#include "cairo_lib.h"
#include "srgb.h"

/* {===== the literal route */

static void lit_taps(int *ix, float *fx, int to, int from)
{
    for (int i = 0; i < to; i++) {
        double u = (i + 0.5) * from / to - 0.5;
        double f0 = floor(u);
        int x0 = (int)f0;
        double f = u - f0;
        if (x0 < 0) x0 = 0, f = 0;
        if (x0 >= from - 1) x0 = from - 1, f = 0;
        ix[i] = x0;
        fx[i] = (float)f;
    }
}

/* channel k of the bilinear sample of picture [m] (w x h) at taps */
static float lit_sample(const float *m, int w, int h, int x0, float wx, int y0, float wy, int k)
{
    int x1 = x0 + 1 < w ? x0 + 1 : x0, y1 = y0 + 1 < h ? y0 + 1 : y0;
    const float *r0 = m + (size_t)y0 * w * 4, *r1 = m + (size_t)y1 * w * 4;
    float top = r0[x0 * 4 + k] + (r0[x1 * 4 + k] - r0[x0 * 4 + k]) * wx;
    float bot = r1[x0 * 4 + k] + (r1[x1 * 4 + k] - r1[x0 * 4 + k]) * wx;
    return top + (bot - top) * wy;
}

static void lit_adjust(float *px, const BloomParams *p, float gain, float offset)
{
    float a = px[3];
    float c[3];
    for (int k = 0; k < 3; k++) c[k] = (a > 0 ? px[k] / a : 0) * gain + offset;
    if (p->shadows != 0 || p->highlights != 0) {
        double l = 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
        double s = 4 * (0.25 - l), h = 2 * (l - 0.5);
        s = s < 0 ? 0 : s > 1 ? 1 : s;
        h = h < 0 ? 0 : h > 1 ? 1 : h;
        double m = pow(2.0, p->shadows * s) * pow(2.0, p->highlights * h);
        for (int k = 0; k < 3; k++) c[k] = (float)(c[k] * m);
    }
    for (int k = 0; k < 3; k++) px[k] = c[k] * a;
}

static void lit_gaussian(float *wt, int r, double sigma)
{
    double sum = 1;
    for (int i = 1; i <= r; i++) sum += 2 * (sigma > 0 ? exp(-0.5 * i * i / (sigma * sigma)) : 0);
    wt[0] = (float)(1 / sum);
    for (int i = 1; i <= r; i++) wt[i] = (float)((sigma > 0 ? exp(-0.5 * i * i / (sigma * sigma)) : 0) / sum);
}

static int clampi(int v, int lo, int hi)
{
    return v < lo ? lo : v > hi ? hi : v;
}

static void lit_bloom(const BloomParams *p, float *rgba, int w, int h)
{
    int ds = p->downsample < 1 ? 1 : p->downsample;
    int sw = w / ds, sh = h / ds;
    if (sw < 1) sw = 1;
    if (sh < 1) sh = 1;
    float *small = calloc((size_t)sw * sh * 4, sizeof(float));
    float *tmp = calloc((size_t)sw * sh * 4, sizeof(float));
    int *ix = calloc((size_t)w + h, sizeof(int)), *iy;
    float *fx = calloc((size_t)w + h, sizeof(float)), *fy;
    float gain = (float)(pow(2.0, p->exposure) * p->contrast);
    float offset = (float)(p->brightness + (1 - p->contrast) / 2);
    iy = ix + sw, fy = fx + sw;
    lit_taps(ix, fx, sw, w);
    lit_taps(iy, fy, sh, h);
    for (int y = 0; y < sh; y++)
        for (int x = 0; x < sw; x++) {
            float *o = small + ((size_t)y * sw + x) * 4;
            for (int k = 0; k < 4; k++) o[k] = lit_sample(rgba, w, h, ix[x], fx[x], iy[y], fy[y], k);
            lit_adjust(o, p, gain, offset);
        }
    int rx = clampi(p->radius[0] / ds, 0, 4096), ry = clampi(p->radius[1] / ds, 0, 4096);
    float wt[4097];
    lit_gaussian(wt, rx, rx * p->sigma[0]);
    for (int y = 0; y < sh; y++)
        for (int x = 0; x < sw; x++)
            for (int k = 0; k < 4; k++) {
                float acc = small[((size_t)y * sw + x) * 4 + k] * wt[0];
                for (int i = 1; i <= rx; i++)
                    acc += (small[((size_t)y * sw + clampi(x - i, 0, sw - 1)) * 4 + k] +
                            small[((size_t)y * sw + clampi(x + i, 0, sw - 1)) * 4 + k]) * wt[i];
                tmp[((size_t)y * sw + x) * 4 + k] = acc;
            }
    lit_gaussian(wt, ry, ry * p->sigma[1]);
    for (int y = 0; y < sh; y++)
        for (int x = 0; x < sw; x++)
            for (int k = 0; k < 4; k++) {
                float acc = tmp[((size_t)y * sw + x) * 4 + k] * wt[0];
                for (int i = 1; i <= ry; i++)
                    acc += (tmp[((size_t)clampi(y - i, 0, sh - 1) * sw + x) * 4 + k] +
                            tmp[((size_t)clampi(y + i, 0, sh - 1) * sw + x) * 4 + k]) * wt[i];
                small[((size_t)y * sw + x) * 4 + k] = acc;
            }
    iy = ix + w, fy = fx + w;
    lit_taps(ix, fx, w, sw);
    lit_taps(iy, fy, h, sh);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            for (int k = 0; k < 4; k++) {
                float l = lit_sample(small, sw, sh, ix[x], fx[x], iy[y], fy[y], k);
                float *o = rgba + ((size_t)y * w + x) * 4 + k;
                *o = (*o > l ? *o : l) * (float)p->alpha;
            }
    free(small);
    free(tmp);
    free(ix);
    free(fx);
}

/* }===== */

static uint64_t rng = 0x9e3779b97f4a7c15u;

static uint64_t next(void)
{
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return rng;
}

/* A picture of premultiplied light with some special values. */
static void random_picture(float *px, size_t n)
{
    static const float special[] = {0.0f, -0.0f, NAN, INFINITY, -INFINITY, 1.0f, 4.0f, -0.5f, 1e-30f};
    for (size_t i = 0; i < n; i++) {
        float a = (next() % 8 == 0) ? 0.0f : (float)(next() % 1001) / 1000.0f;
        for (int k = 0; k < 3; k++) {
            uint64_t r = next();
            px[i * 4 + k] = r % 50 == 0 ? special[(r >> 8) % 9] : (float)((r >> 16) % 3000) / 1000.0f * a;
        }
        px[i * 4 + 3] = a;
    }
}

/* Bit for bit, except that any NaN equals any NaN (which operand's NaN an
 * operation passes on is the compiler's choice of operand order, in either
 * route; every NaN encodes alike). */
static void assert_same_bits(const float *a, const float *b, size_t n, const char *what)
{
    if (memcmp(a, b, n * sizeof(float)) != 0) {
        for (size_t i = 0; i < n; i++)
            if (!(isnan(a[i]) && isnan(b[i])) && memcmp(a + i, b + i, sizeof(float)) != 0)
                fail_msg("%s: float %zu (pixel %zu channel %zu) is %a, the literal route's %a", what, i,
                         i / 4, i % 4, (double)a[i], (double)b[i]);
    }
}

static void passes_as_literal(void **st)
{
    (void)st;
    /* sizes: odd, tiny, over the two-thread split (64 rows) */
    static const int sizes[][2] = {{1, 1}, {2, 3}, {7, 5}, {33, 17}, {65, 130}, {131, 67}, {200, 129}};
    Bloom *b = bloom_new();
    for (size_t s = 0; s < sizeof sizes / sizeof *sizes; s++)
        for (int round = 0; round < 6; round++) {
            int w = sizes[s][0], h = sizes[s][1];
            size_t n = (size_t)w * h * 4;
            float *fast = malloc(n * sizeof(float)), *lit = malloc(n * sizeof(float));
            random_picture(fast, (size_t)w * h);
            memcpy(lit, fast, n * sizeof(float));
            BloomParams p = {.radius = {(int)(next() % 20), (int)(next() % 20)},
                             .sigma = {0.3, 0.1 + (double)(next() % 10) / 10},
                             .exposure = -1 + (double)(next() % 5) / 2, .contrast = 0.5 + (double)(next() % 4) / 2,
                             .brightness = (double)(next() % 3) / 10, .alpha = 1 - (double)(next() % 3) / 4,
                             .downsample = 1 + (int)(next() % 3)};
            if (round % 3 == 2) {
                p.shadows = 0.5;
                p.highlights = -1;
            }
            bloom_apply(b, &p, fast, w, h);
            lit_bloom(&p, lit, w, h);
            char what[128];
            snprintf(what, sizeof what, "%dx%d radius %d;%d downsample %d shadows %g", w, h, p.radius[0],
                     p.radius[1], p.downsample, p.shadows);
            assert_same_bits(fast, lit, n, what);
            free(fast);
            free(lit);
        }
    bloom_free(b);
}

/* The literal encoding of one pixel (srgb.h): each channel clamped to
 * 0..1 (NaN to 0), its step enc[(int)(f * SRGB_STEPS + 0.5)], alpha at
 * least each channel's code. */
static uint32_t lit_encode(const SrgbTable *t, const float *src)
{
    unsigned v[3], a = 0;
    for (int k = 0; k < 3; k++) {
        float f = src[k];
        int i = !(f > 0) ? 0 : f >= 1 ? SRGB_STEPS : (int)(f * SRGB_STEPS + 0.5f);
        v[k] = t->enc[i];
        if (v[k] > a) a = v[k];
    }
    float fa = src[3];
    unsigned alpha = !(fa > 0) ? 0 : fa >= 1 ? 255 : (unsigned)lroundf(fa * 255);
    if (alpha > a) a = alpha;
    return (a << 24) | (v[0] << 16) | (v[1] << 8) | v[2];
}

static void encoding_as_literal(void **st)
{
    (void)st;
    enum { W = 97, H = 70 };
    static SrgbTable t;
    char why[256];
    assert_true(cairo_lib_ready(why, sizeof why));
    srgb_table_init(&t);
    static float px[W * H * 4];
    random_picture(px, W * H);
    /* every step boundary's neighbours too */
    for (int i = 0; i < 3 * 4096 && i < W * H * 4; i += 4) {
        float f = ((float)(i / 4) + 0.5f) / SRGB_STEPS;
        px[i] = nextafterf(f, 0);
        px[i + 1] = f;
        px[i + 2] = nextafterf(f, 2);
    }
    cairo_surface_t *pic = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, W, H);
    assert_int_equal(cairo_surface_status(pic), CAIRO_STATUS_SUCCESS);
    srgb_encode_surface(&t, px, W, H, pic);
    cairo_surface_flush(pic);
    const unsigned char *data = cairo_image_surface_get_data(pic);
    int stride = cairo_image_surface_get_stride(pic);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            uint32_t got;
            memcpy(&got, data + (size_t)y * stride + (size_t)x * 4, 4);
            uint32_t want = lit_encode(&t, px + ((size_t)y * W + x) * 4);
            if (got != want)
                fail_msg("pixel %d,%d: %08x, the literal encoding %08x", x, y, got, want);
        }
    cairo_surface_destroy(pic);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(passes_as_literal),
        cmocka_unit_test(encoding_as_literal),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
