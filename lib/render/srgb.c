/* srgb.c: linear light to the window's 8-bit sRGB output (see srgb.h). */
#include "srgb.h"

#include <math.h>
#include <stddef.h>

void srgb_table_init(SrgbTable *t)
{
    for (int i = 0; i <= SRGB_STEPS; i++) {
        double x = (double)i / SRGB_STEPS;
        double s = x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1 / 2.4) - 0.055;
        t->enc[i] = (uint8_t)lround(s * 255);
    }
}

void srgb_encode_surface(const SrgbTable *t, const float *rgba, int w, int h, cairo_surface_t *pic)
{
    cairo_surface_flush(pic);
    unsigned char *data = cairo_image_surface_get_data(pic);
    int stride = cairo_image_surface_get_stride(pic);
    for (int y = 0; y < h; y++) {
        uint32_t *row = (uint32_t *)(void *)(data + (size_t)y * stride);
        const float *src = rgba + (size_t)y * w * 4;
        for (int x = 0; x < w; x++, src += 4) {
            unsigned v[3], a = 0;
            for (int k = 0; k < 3; k++) {
                float f = src[k];
                int idx = !(f > 0) ? 0 : f >= 1 ? SRGB_STEPS : (int)(f * SRGB_STEPS + 0.5f);
                v[k] = t->enc[idx];
                if (v[k] > a) a = v[k];
            }
            float fa = src[3];
            unsigned alpha = !(fa > 0) ? 0 : fa >= 1 ? 255 : (unsigned)lroundf(fa * 255);
            if (alpha > a) a = alpha;
            row[x] = (a << 24) | (v[0] << 16) | (v[1] << 8) | v[2];
        }
    }
    cairo_surface_mark_dirty(pic);
}
