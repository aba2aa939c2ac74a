/* bloom.h: Flitter's `!bloom` window effect, computed on the CPU in float.
 *
 * Behaviour from Flitter's documentation (docs/shaders.md, "!bloom") and
 * its filter (render/window/shaders.py, Bloom; glsl/bloom.frag and
 * filter_functions.glsl): the children, composited in linear light, are
 *   1. resampled to a framebuffer `downsample` (default 2) times smaller
 *      (integer division of each side; bilinear, clamped at the edges),
 *      un-premultiplied, adjusted as !adjust does (exposure, default -1,
 *      then contrast, brightness, shadows, highlights) and premultiplied;
 *   2. blurred horizontally then vertically, at the smaller size, with a
 *      normalised 1D Gaussian of r = radius/downsample taps each side
 *      (integer division) and a standard deviation of r * sigma (sigma
 *      default 0.3), edges clamped;
 *   3. brought back to full size (bilinear) and combined with the
 *      original by the *lighten* blend (the larger of each premultiplied
 *      component, alpha included), times the node's `alpha` (default 1).
 * radius and sigma take one number or two (x;y); radius is truncated to
 * an integer as Flitter's integer uniform is. Values above 1 (HDR light
 * from !canvas3d) are kept until the window encodes the result.
 */
#ifndef FL_RENDER_BLOOM_H
#define FL_RENDER_BLOOM_H

#include <cairo.h>

#include "node.h"

/* The attributes of one !bloom node (Flitter shaders.py, Bloom.render). */
typedef struct BloomParams {
    int radius[2];        /* pixels at full size, x and y; default 0 */
    double sigma[2];      /* the Gaussian's sigma as a multiple of the radius; 0.3 */
    double exposure;      /* stops; -1 */
    double contrast;      /* 1 */
    double brightness;    /* 0 */
    double shadows;       /* stops at luminance 0 fading to none at 0.25; 0 */
    double highlights;    /* stops at luminance 1 fading to none at 0.5; 0 */
    double alpha;         /* the result's opacity; 1 */
    int downsample;       /* the blur's framebuffer scale-down, at least 1; 2 */
} BloomParams;

/* Scratch framebuffers reused from frame to frame (one per renderer). */
typedef struct Bloom Bloom;

/* Read [n]'s !bloom attributes into [p], with Flitter's defaults for
 * those absent or malformed (a wrong count or a non-number is ignored). */
void bloom_params(const Node *n, BloomParams *p);
/* An empty set of scratch framebuffers. */
Bloom *bloom_new(void);
/* Apply the bloom [p] in place to [rgba]: [w] x [h] pixels of linear,
 * premultiplied RGBA floats, top row first. Each pass of 64 rows or more
 * is split between two threads (halves.h), row by row as one thread
 * would compute it.
 *   errors: none; a size under 1 does nothing. */
void bloom_apply(Bloom *b, const BloomParams *p, float *rgba, int w, int h);
/* Milliseconds spent in bloom_apply so far and its call count. */
double bloom_time_ms(const Bloom *b, long *calls);
/* Free [b] (NULL is a no-op). */
void bloom_free(Bloom *b);

/* The linear light of [pic] (an ARGB32 cairo image surface: premultiplied,
 * sRGB-encoded 8-bit) into [rgba] (w x h x 4 floats, premultiplied), as
 * an sRGB texture is read by GL: each channel un-premultiplied, decoded,
 * premultiplied again. */
void bloom_decode(cairo_surface_t *pic, float *rgba);
/* The linear light of [lin] (an ARGB32 cairo image surface whose
 * premultiplied 8-bit values are linear: a `!canvas linear=true`, as
 * Flitter's 8-bit linear canvas texture is read) into [rgba]: each value
 * over 255, premultiplied as it is. */
void bloom_decode_linear(cairo_surface_t *lin, float *rgba);
/* Paint linear light [rgba] over linear light [dst] (both premultiplied,
 * [n] pixels): the `over` blend. */
void bloom_over(float *dst, const float *rgba, size_t n);
/* Encode linear light [rgba] into [pic] (ARGB32 of the same size),
 * replacing its pixels as the window's output does (srgb_encode_surface,
 * with [b]'s table). */
void bloom_encode(Bloom *b, const float *rgba, cairo_surface_t *pic);

#endif
