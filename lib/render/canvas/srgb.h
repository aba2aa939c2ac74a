/* srgb.h: linear light to 8-bit sRGB and back on the CPU: the physics
 * view's 3D pictures (scene_picture.c), canvas colours as light
 * (canvas.c, view.c) and textures read back for the canvas (graph.c).
 * The render graph itself encodes on the GPU (sRGB framebuffers). */
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

#endif
