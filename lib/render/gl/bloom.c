/* bloom.c: Flitter's !bloom window effect on the CPU (see bloom.h). */
#include "bloom.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "canvas.h"
#include "halves.h"
#include "mem.h"
#include "srgb.h"

/* last: it turns the library's names into calls through its table */
#include "cairo_lib.h"

struct Bloom {
    float *small, *tmp;       /* two framebuffers at the blur's size */
    size_t cap_small;
    int *ix; float *fx;       /* bilinear taps along one axis: index, weight of index+1 */
    size_t cap_taps;
    SrgbTable srgb;           /* the output encoding, made once */
    double ms_total;
    long calls;
};

/* Four floats (one RGBA pixel) as one vector value (GCC/clang vector
 * extensions): each lane takes the scalar code's operations in its order,
 * so a result is the scalar one bit for bit (the build contracts nothing
 * into FMA). */
typedef float v4f __attribute__((vector_size(4 * sizeof(float))));
typedef int32_t v4i __attribute__((vector_size(4 * sizeof(int32_t))));

static inline v4f ld4(const float *p)
{
    v4f v;
    memcpy(&v, p, sizeof v);
    return v;
}

static inline void st4(float *p, v4f v)
{
    memcpy(p, &v, sizeof v);
}

/* Per lane a > b ? a : b. */
static inline v4f max4(v4f a, v4f b)
{
    v4i m = a > b;
    return (v4f)(((v4i)a & m) | ((v4i)b & ~m));
}

void bloom_params(const Node *n, BloomParams *p)
{
    /* Flitter shaders.py, Bloom.render, and ProgramNode.render (downsample) */
    *p = (BloomParams){.sigma = {0.3, 0.3}, .exposure = -1, .contrast = 1, .alpha = 1, .downsample = 2};
    double v[2];
    if (canvas_attr_nums(n, "radius", 2, v))
        for (int k = 0; k < 2; k++) p->radius[k] = !(fabs(v[k]) < 1e6) ? 0 : (int)v[k];   /* truncated */
    if (canvas_attr_nums(n, "sigma", 2, v)) p->sigma[0] = v[0], p->sigma[1] = v[1];
    if (canvas_attr_nums(n, "exposure", 1, v)) p->exposure = v[0];
    if (canvas_attr_nums(n, "contrast", 1, v)) p->contrast = v[0];
    if (canvas_attr_nums(n, "brightness", 1, v)) p->brightness = v[0];
    if (canvas_attr_nums(n, "shadows", 1, v)) p->shadows = v[0];
    if (canvas_attr_nums(n, "highlights", 1, v)) p->highlights = v[0];
    if (canvas_attr_nums(n, "alpha", 1, v)) p->alpha = v[0];
    if (canvas_attr_nums(n, "downsample", 1, v)) p->downsample = v[0] >= 1 && v[0] < 1e6 ? (int)v[0] : 1;
}

Bloom *bloom_new(void)
{
    Bloom *b = mem_calloc(1, sizeof(Bloom));
    srgb_table_init(&b->srgb);
    return b;
}

double bloom_time_ms(const Bloom *b, long *calls)
{
    if (calls) *calls = b->calls;
    return b->ms_total;
}

void bloom_free(Bloom *b)
{
    if (!b) return;
    free(b->small);
    free(b->tmp);
    free(b->ix);
    free(b->fx);
    free(b);
}

/* Bilinear taps for sampling a side of [from] pixels at the pixel centres
 * of a side of [to] pixels (GL's linear filter, clamped to the edge):
 * ix[i] and ix[i]+1 (clamped) weighted 1-fx[i] and fx[i]. */
static void taps(int *ix, float *fx, int to, int from)
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

/* Room in b->ix and b->fx for [need] taps. */
static void grow_taps(Bloom *b, size_t need)
{
    if (need <= b->cap_taps) return;
    b->cap_taps = need;
    free(b->ix);
    free(b->fx);
    b->ix = mem_alloc(need * sizeof *b->ix);
    b->fx = mem_alloc(need * sizeof *b->fx);
}

/* Flitter filter_functions.glsl, filter_adjust, on un-premultiplied
 * light; [gain] is 2^exposure * contrast, [offset] brightness + (1 -
 * contrast)/2. */
static void adjust(float *px, const BloomParams *p, float gain, float offset)
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

/* The normalised weights of a 1D Gaussian of [r] taps each side and
 * standard deviation [sigma] pixels into wt[0..r] (Flitter
 * filter_functions.glsl, filter_blur: weight exp(-i^2 / 2 sigma^2), the
 * centre 1 even when sigma is 0). */
static void gaussian(float *wt, int r, double sigma)
{
    double sum = 1;
    for (int i = 1; i <= r; i++) sum += 2 * (sigma > 0 ? exp(-0.5 * i * i / (sigma * sigma)) : 0);
    wt[0] = (float)(1 / sum);
    for (int i = 1; i <= r; i++) wt[i] = (float)((sigma > 0 ? exp(-0.5 * i * i / (sigma * sigma)) : 0) / sum);
}

/* One output row of the x pass: o[x] = sum over i of wt[|i|] * mid[x + i*step]
 * for [w] pixels, |i| <= [r], summed as mid[x]*wt[0] + (mid[x-step] +
 * mid[x+step])*wt[1] + ... in that order; [mid] is padded by r pixels each
 * side. */
static void weigh_rows(float *restrict o, const float *restrict mid, int w, const float *wt, int r, int step)
{
    for (size_t p = 0; p < (size_t)w * 4; p += 4) {
        v4f acc = ld4(mid + p) * wt[0];
        for (int i = 1; i <= r; i++)
            acc = acc + (ld4(mid + p - (size_t)i * step) + ld4(mid + p + (size_t)i * step)) * wt[i];
        st4(o + p, acc);
    }
}

/* The passes of one bloom_apply, by rows (rows_in_halves). */
typedef struct Passes {
    const BloomParams *p;
    float *rgba;                 /* the picture, w x h */
    int w, h, sw, sh;            /* the picture's size and the blur's */
    float *small, *tmp;          /* sw x sh */
    const int *ix, *iy;          /* bilinear taps: down (to sw, sh) or up (to w, h) */
    const float *fx, *fy;
    float gain, offset, alpha;
    const float *wt;             /* the Gaussian's weights, r + 1 */
    int r;
    float *scratch[2];           /* per thread: a padded row, or two full-size rows */
} Passes;

/* Pass 1, rows y0..y1-1 of the small framebuffer: the picture resampled
 * (bilinear taps), then adjusted. */
static void down_rows(void *ctx, int y0, int y1, int part)
{
    (void)part;
    const Passes *q = ctx;
    int sw = q->w, sh = q->h, dw = q->sw;
    for (int y = y0; y < y1; y++) {
        const float *r0 = q->rgba + (size_t)q->iy[y] * sw * 4;
        const float *r1 = q->iy[y] + 1 < sh ? r0 + (size_t)sw * 4 : r0;
        float wy = q->fy[y];
        float *out = q->small + (size_t)y * dw * 4;
        int x = 0;
        if (q->p->shadows == 0 && q->p->highlights == 0) {
            /* a pixel a vector: the lanes of adjust() without its
             * shadows and highlights */
            const float gain = q->gain, offset = q->offset;
            for (; x < dw; x++, out += 4) {
                int x0 = q->ix[x] * 4, x1 = q->ix[x] + 1 < sw ? x0 + 4 : x0;
                float wx = q->fx[x];
                v4f t0 = ld4(r0 + x0), u0 = ld4(r1 + x0);
                v4f top = t0 + (ld4(r0 + x1) - t0) * wx, bot = u0 + (ld4(r1 + x1) - u0) * wx;
                v4f px = top + (bot - top) * wy;
                v4f a = __builtin_shufflevector(px, px, 3, 3, 3, 3);
                v4f c = (v4f)((v4i)(px / a) & (a > 0)) * gain + offset;
                st4(out, __builtin_shufflevector(c * a, px, 0, 1, 2, 7));
            }
        }
        for (; x < dw; x++, out += 4) {
            int x0 = q->ix[x] * 4, x1 = q->ix[x] + 1 < sw ? x0 + 4 : x0;
            float wx = q->fx[x];
            for (int k = 0; k < 4; k++) {
                float top = r0[x0 + k] + (r0[x1 + k] - r0[x0 + k]) * wx;
                float bot = r1[x0 + k] + (r1[x1 + k] - r1[x0 + k]) * wx;
                out[k] = top + (bot - top) * wy;
            }
            adjust(out, q->p, q->gain, q->offset);
        }
    }
}

/* Pass 2, the Gaussian along x: small to tmp, edges clamped, each row
 * through the thread's padded row (w + 2r pixels). */
static void blur_x_rows(void *ctx, int y0, int y1, int part)
{
    const Passes *q = ctx;
    int w = q->sw, r = q->r;
    float *pad = q->scratch[part];
    for (int y = y0; y < y1; y++) {
        const float *row = q->small + (size_t)y * w * 4;
        for (int x = -r; x < w + r; x++) {
            int c = x < 0 ? 0 : x >= w ? w - 1 : x;
            memcpy(pad + (size_t)(x + r) * 4, row + (size_t)c * 4, 4 * sizeof(float));
        }
        weigh_rows(q->tmp + (size_t)y * w * 4, pad + (size_t)r * 4, w, q->wt, r, 4);
    }
}

/* Pass 3, the Gaussian along y: tmp to small, edges clamped. */
static void blur_y_rows(void *ctx, int y0, int y1, int part)
{
    (void)part;
    const Passes *q = ctx;
    int h = q->sh, r = q->r;
    size_t n = (size_t)q->sw * 4;
    for (int y = y0; y < y1; y++) {
        float *restrict o = q->small + (size_t)y * n;
        const float *mid = q->tmp + (size_t)y * n;
        /* the sum of weigh_rows, in its order, row by row into o */
        size_t j;
        for (j = 0; j < n; j += 4) st4(o + j, ld4(mid + j) * q->wt[0]);
        for (int i = 1; i <= r; i++) {
            int a = y - i < 0 ? 0 : y - i, b = y + i >= h ? h - 1 : y + i;
            const float *ra = q->tmp + (size_t)a * n, *rb = q->tmp + (size_t)b * n;
            float g = q->wt[i];
            for (j = 0; j < n; j += 4) st4(o + j, ld4(o + j) + (ld4(ra + j) + ld4(rb + j)) * g);
        }
    }
}

/* Row [sy] of the small framebuffer resampled along x to the picture's
 * width (bilinear taps ix, fx): out[x] = m[x0] + (m[x1] - m[x0]) * fx[x],
 * per channel. */
static void widen_row(const Passes *q, int sy, float *restrict out)
{
    const float *m = q->small + (size_t)sy * q->sw * 4;
    int sw = q->sw;
    for (int x = 0; x < q->w; x++) {
        int x0 = q->ix[x] * 4, x1 = q->ix[x] + 1 < sw ? x0 + 4 : x0;
        float wx = q->fx[x];
        for (int k = 0; k < 4; k++) out[x * 4 + k] = m[x0 + k] + (m[x1 + k] - m[x0 + k]) * wx;
    }
}

/* Pass 4, rows y0..y1-1 of the picture: the blur brought back to full size
 * (bilinear taps: the two small rows around the picture row, each widened
 * along x, then weighed along y), lighten with the original, times alpha.
 * A thread's rows are consecutive and their small rows never go down, so
 * each small row is widened once per thread, into the thread's scratch
 * (two rows of the picture's width). */
static void up_rows(void *ctx, int y0, int y1, int part)
{
    const Passes *q = ctx;
    int sh = q->sh;
    size_t row = (size_t)q->w * 4;
    float *wide[2] = {q->scratch[part], q->scratch[part] + row};
    int held[2] = {-1, -1};          /* the small row in wide[0], wide[1] */
    for (int y = y0; y < y1; y++) {
        int s0 = q->iy[y], s1 = s0 + 1 < sh ? s0 + 1 : s0;
        int t = held[0] == s0 ? 0 : held[1] == s0 ? 1 : -1;
        if (t < 0) {
            t = held[0] == s1 ? 1 : 0;        /* keep s1 if it is held */
            widen_row(q, s0, wide[t]);
            held[t] = s0;
        }
        int u = held[t] == s1 ? t : held[1 - t] == s1 ? 1 - t : -1;
        if (u < 0) {
            u = 1 - t;
            widen_row(q, s1, wide[u]);
            held[u] = s1;
        }
        const float *top = wide[t], *bot = wide[u];
        float wy = q->fy[y], alpha = q->alpha;
        float *restrict o = q->rgba + (size_t)y * row;
        size_t i = 0;
        for (; i + 4 <= row; i += 4) {
            v4f t = ld4(top + i), l = t + (ld4(bot + i) - t) * wy;
            st4(o + i, max4(ld4(o + i), l) * alpha);
        }
        for (; i < row; i++) {
            float l = top[i] + (bot[i] - top[i]) * wy;
            o[i] = (o[i] > l ? o[i] : l) * alpha;
        }
    }
}

/* Rows a thread must have before a pass is split between two. */
#define SPLIT_ROWS 64

void bloom_apply(Bloom *b, const BloomParams *p, float *rgba, int w, int h)
{
    if (w < 1 || h < 1) return;
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    int ds = p->downsample < 1 ? 1 : p->downsample;
    /* Flitter: RenderTarget of width//downsample x height//downsample */
    int sw = w / ds, sh = h / ds;
    if (sw < 1) sw = 1;
    if (sh < 1) sh = 1;
    size_t n = (size_t)sw * sh * 4;
    if (n > b->cap_small) {
        b->cap_small = n;
        free(b->small);
        free(b->tmp);
        b->small = mem_alloc(n * sizeof(float));
        b->tmp = mem_alloc(n * sizeof(float));
    }
    Passes q = {.p = p, .rgba = rgba, .w = w, .h = h, .sw = sw, .sh = sh, .small = b->small, .tmp = b->tmp,
                .alpha = (float)p->alpha};
    /* pass 1: down-sample and darken */
    grow_taps(b, (size_t)w + h);
    int *ix = b->ix, *iy = b->ix + sw;
    float *fx = b->fx, *fy = b->fx + sw;
    taps(ix, fx, sw, w);
    taps(iy, fy, sh, h);
    q.ix = ix, q.iy = iy, q.fx = fx, q.fy = fy;
    q.gain = (float)(pow(2.0, p->exposure) * p->contrast);
    q.offset = (float)(p->brightness + (1 - p->contrast) / 2);
    rows_in_halves(sh, SPLIT_ROWS, down_rows, &q);
    /* passes 2 and 3: the Gaussian, x then y, at the small size */
    int rx = p->radius[0] / ds, ry = p->radius[1] / ds;
    if (rx < 0) rx = 0;
    if (ry < 0) ry = 0;
    /* a radius over 4096 pixels at the blur's size is taken as 4096 (a
     * bound on the work for absurd values; Flitter would loop on) */
    if (rx > 4096) rx = 4096;
    if (ry > 4096) ry = 4096;
    float *wt = mem_alloc(((size_t)(rx > ry ? rx : ry) + 1) * sizeof *wt);
    size_t pad = ((size_t)sw + 2 * (size_t)rx) * 4, row = (size_t)w * 4 * 2;
    size_t scratch = pad > row ? pad : row;
    q.scratch[0] = mem_alloc(2 * scratch * sizeof(float));
    q.scratch[1] = q.scratch[0] + scratch;
    q.wt = wt;
    gaussian(wt, rx, rx * p->sigma[0]);
    q.r = rx;
    rows_in_halves(sh, SPLIT_ROWS, blur_x_rows, &q);
    gaussian(wt, ry, ry * p->sigma[1]);
    q.r = ry;
    rows_in_halves(sh, SPLIT_ROWS, blur_y_rows, &q);
    /* pass 4: back to full size, lighten with the original, times alpha */
    ix = b->ix, iy = b->ix + w;
    fx = b->fx, fy = b->fx + w;
    taps(ix, fx, w, sw);
    taps(iy, fy, h, sh);
    q.ix = ix, q.iy = iy, q.fx = fx, q.fy = fy;
    rows_in_halves(h, SPLIT_ROWS, up_rows, &q);
    free(wt);
    free(q.scratch[0]);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    b->ms_total += (double)(t1.tv_sec - t0.tv_sec) * 1e3 + (double)(t1.tv_nsec - t0.tv_nsec) / 1e6;
    b->calls++;
}

/* {===== linear light to and from the window's 8-bit pictures */

void bloom_decode(cairo_surface_t *pic, float *rgba)
{
    float lin[256];
    for (int i = 0; i < 256; i++) lin[i] = (float)srgb_decode(i / 255.0);
    cairo_surface_flush(pic);
    const unsigned char *data = cairo_image_surface_get_data(pic);
    int w = cairo_image_surface_get_width(pic), h = cairo_image_surface_get_height(pic);
    int stride = cairo_image_surface_get_stride(pic);
    for (int y = 0; y < h; y++) {
        const uint32_t *src = (const uint32_t *)(const void *)(data + (size_t)y * stride);
        float *o = rgba + (size_t)y * w * 4;
        for (int x = 0; x < w; x++, o += 4) {
            uint32_t p = src[x];
            unsigned a = p >> 24;
            if (a == 0) {
                o[0] = o[1] = o[2] = o[3] = 0;
                continue;
            }
            float fa = a / 255.0f;
            for (int k = 0; k < 3; k++) {
                unsigned v = (p >> (16 - 8 * k)) & 0xff;
                /* un-premultiplied 8-bit value, as the texture would hold it */
                unsigned u = a == 255 ? v : (v * 255 + a / 2) / a;
                if (u > 255) u = 255;
                o[k] = lin[u] * fa;
            }
            o[3] = fa;
        }
    }
}

void bloom_decode_linear(cairo_surface_t *lin, float *rgba)
{
    cairo_surface_flush(lin);
    const unsigned char *data = cairo_image_surface_get_data(lin);
    int w = cairo_image_surface_get_width(lin), h = cairo_image_surface_get_height(lin);
    int stride = cairo_image_surface_get_stride(lin);
    for (int y = 0; y < h; y++) {
        const uint32_t *src = (const uint32_t *)(const void *)(data + (size_t)y * stride);
        float *o = rgba + (size_t)y * w * 4;
        for (int x = 0; x < w; x++, o += 4) {
            uint32_t p = src[x];
            for (int k = 0; k < 3; k++) o[k] = (float)((p >> (16 - 8 * k)) & 0xff) / 255.0f;
            o[3] = (float)(p >> 24) / 255.0f;
        }
    }
}

void bloom_over(float *dst, const float *rgba, size_t n)
{
    for (size_t i = 0; i < n; i++, dst += 4, rgba += 4) {
        float keep = 1 - rgba[3];
        for (int k = 0; k < 4; k++) dst[k] = rgba[k] + dst[k] * keep;
    }
}

void bloom_encode(Bloom *b, const float *rgba, cairo_surface_t *pic)
{
    srgb_encode_surface(&b->srgb, rgba, cairo_image_surface_get_width(pic),
                        cairo_image_surface_get_height(pic), pic);
}

/* }===== */
