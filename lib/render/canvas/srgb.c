/* srgb.c: linear light to the window's 8-bit sRGB output (see srgb.h). */
#include "srgb.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "halves.h"

/* last: it turns the library's names into calls through its table */
#include "cairo_lib.h"

void srgb_table_init(SrgbTable *t)
{
    for (int i = 0; i <= SRGB_STEPS; i++) {
        double x = (double)i / SRGB_STEPS;
        double s = x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1 / 2.4) - 0.055;
        t->enc[i] = (uint8_t)lround(s * 255);
    }
}

double srgb_decode(double s)
{
    return s <= 0.04045 ? s / 12.92 : pow((s + 0.055) / 1.055, 2.4);
}

typedef float v4f __attribute__((vector_size(4 * sizeof(float))));
typedef int32_t v4i __attribute__((vector_size(4 * sizeof(int32_t))));

/* One pixel of premultiplied linear light [src] (RGBA) as the window's
 * output holds it: an ARGB32 word of encoded channels and an alpha of at
 * least each of them. A channel's step of enc is that of linear f clamped
 * to 0..1 (NaN to 0), (int)(f * SRGB_STEPS + 0.5f); the four are computed
 * as one vector (1 * SRGB_STEPS + 0.5 truncates to SRGB_STEPS, and 0.5 to
 * 0). */
static inline uint32_t encode_pixel(const SrgbTable *t, const float src[4])
{
    v4f f;
    memcpy(&f, src, sizeof f);
    const v4f one = {1, 1, 1, 1};
    v4i pos = f > 0, top = f >= 1;
    v4f c = (v4f)(((v4i)f & pos & ~top) | ((v4i)one & top));
    v4i ix = __builtin_convertvector(c * (float)SRGB_STEPS + 0.5f, v4i);
    unsigned v[3], a = 0;
    for (int k = 0; k < 3; k++) {
        v[k] = t->enc[ix[k]];
        if (v[k] > a) a = v[k];
    }
    float fa = src[3];
    unsigned alpha = !(fa > 0) ? 0 : fa >= 1 ? 255 : (unsigned)lroundf(fa * 255);
    if (alpha > a) a = alpha;
    return (a << 24) | (v[0] << 16) | (v[1] << 8) | v[2];
}

typedef struct Encoding {
    const SrgbTable *t;
    const float *rgba;
    int w, stride;
    unsigned char *data;
} Encoding;

static void encode_rows(void *ctx, int y0, int y1, int part)
{
    (void)part;
    const Encoding *e = ctx;
    for (int y = y0; y < y1; y++) {
        uint32_t *row = (uint32_t *)(void *)(e->data + (size_t)y * e->stride);
        const float *src = e->rgba + (size_t)y * e->w * 4;
        for (int x = 0; x < e->w; x++, src += 4) row[x] = encode_pixel(e->t, src);
    }
}

void srgb_encode_surface(const SrgbTable *t, const float *rgba, int w, int h, cairo_surface_t *pic)
{
    cairo_surface_flush(pic);
    Encoding e = {t, rgba, w, cairo_image_surface_get_stride(pic), cairo_image_surface_get_data(pic)};
    rows_in_halves(h, 64, encode_rows, &e);
    cairo_surface_mark_dirty(pic);
}
