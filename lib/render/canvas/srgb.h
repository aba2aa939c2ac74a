/* srgb.h: linear light to the window's 8-bit sRGB output and back, shared
 * by !canvas3d (canvas3d.c), !bloom (bloom.c) and linear canvases
 * (window.c, canvas.c). */
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
    uint8_t enc8[256];   /* the code of linear v/255, as enc gives it */
} SrgbTable;

/* Fill [t]. */
void srgb_table_init(SrgbTable *t);

/* The linear light of sRGB-encoded [s] in 0..1 (IEC 61966-2-1). */
double srgb_decode(double s);

/* Encode [w] x [h] pixels of premultiplied linear light [rgba] (floats,
 * rows of w*4) into the ARGB32 surface [pic] (at least w x h), replacing
 * its pixels as the window's output does: each channel clamped to 0..1
 * and sRGB-encoded through [t], with an alpha of at least each encoded
 * channel, so that painted over black it gives Flitter's window output
 * exactly (Flitter render/window: the sRGB framebuffer). Pictures of 64
 * rows or more are encoded by two threads, half the rows each
 * (halves.h). */
void srgb_encode_surface(const SrgbTable *t, const float *rgba, int w, int h, cairo_surface_t *pic);

/* Encode the ARGB32 surface [lin], whose premultiplied 8-bit values are
 * linear light (a `!canvas linear=true` drawn by cairo; Flitter
 * render/window/canvas.pyx, Canvas.create: an 8-bit linear-sRGB surface),
 * into the ARGB32 surface [pic] of the same size (which may be [lin]
 * itself), as srgb_encode_surface encodes each pixel: channel v to
 * enc(v/255), alpha at least each encoded channel.
 *   errors: none; nothing is done when the sizes differ. */
void srgb_encode_linear8(const SrgbTable *t, cairo_surface_t *lin, cairo_surface_t *pic);

#endif
