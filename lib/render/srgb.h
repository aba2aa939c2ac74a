/* srgb.h: linear light to the window's 8-bit sRGB output, shared by
 * !canvas3d (canvas3d.c) and !bloom (bloom.c). */
#ifndef FL_SRGB_H
#define FL_SRGB_H

#include <cairo.h>
#include <stdint.h>

/* Steps of the encoding table over linear 0..1. */
#define SRGB_STEPS 16384

/* The sRGB transfer function tabulated: enc[i] is the 0..255 code of
 * linear i / SRGB_STEPS (IEC 61966-2-1). Made once per renderer. */
typedef struct SrgbTable {
    uint8_t enc[SRGB_STEPS + 1];
} SrgbTable;

/* Fill [t]. */
void srgb_table_init(SrgbTable *t);

/* Encode [w] x [h] pixels of premultiplied linear light [rgba] (floats,
 * rows of w*4) into the ARGB32 surface [pic] (at least w x h), replacing
 * its pixels as the window's output does: each channel clamped to 0..1
 * and sRGB-encoded through [t], with an alpha of at least each encoded
 * channel, so that painted over black it gives Flitter's window output
 * exactly (Flitter render/window: the sRGB framebuffer). */
void srgb_encode_surface(const SrgbTable *t, const float *rgba, int w, int h, cairo_surface_t *pic);

#endif
