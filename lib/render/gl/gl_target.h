/* gl_target.h: render targets, the framebuffers every render pass draws
 * into, and the pool that reuses them across passes and frames.
 *
 * A target is a W x H texture of one colour format (Flitter docs/
 * windows.md, "Common attributes", colorbits=: 8 is RGBA8, or SRGB8_ALPHA8
 * with [srgb]: written through GL's sRGB encoding and read back as linear
 * light; 16 is RGBA16F, the default; 32 is RGBA32F), with a depth buffer
 * when asked, drawn into through its own framebuffer, or through a
 * multisampled one resolved into the texture by target_finish when
 * [samples] asks (Flitter canvas3d.pyx, Camera.derive: below 2 none, else
 * the power of two at or below it, at most GL_MAX_SAMPLES).
 *
 * The pool keeps released targets by size and format (Flitter target.py,
 * RenderTarget.get/release) and deletes those unused for a while
 * (target_pool_expire). Every target's bytes (colour, multisampled colour
 * and depth) are charged to the runtime's memory budget while it exists,
 * in the pool too. All calls need the pool's context current.
 */
#ifndef FL_RENDER_GL_TARGET_H
#define FL_RENDER_GL_TARGET_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <epoxy/gl.h>

#include "gl_context.h"
#include "mem.h"

/* The texture unit targets are made on (no pass samples from it: passes
 * bind their inputs below it). */
#define GL_TARGET_SCRATCH_UNIT 31

typedef struct GlTarget {
    int w, h;               /* pixels */
    int colorbits;          /* 8, 16 or 32 */
    bool srgb;              /* 8 bits stored as sRGB */
    bool depth;             /* with a depth buffer */
    int samples;            /* multisampling asked for (0: none), after Flitter's rounding */
    int given;              /* the samples the driver gave (it may give more) */
    GLuint tex;             /* the texture its picture ends up in */
    GLuint fbo;             /* the framebuffer drawn into */
    GLuint tex_fbo;         /* the framebuffer of [tex] (== fbo when not multisampled) */
    GLuint color_rb, depth_rb;
    size_t bytes;           /* charged to the budget */
    double released;        /* when it went back to the pool (monotonic seconds) */
    struct GlTarget *next;  /* in the pool */
} GlTarget;

typedef struct TargetPool TargetPool;

/* A pool on context [gl] charging [budget] (may be NULL: none). */
TargetPool *target_pool_new(GlContext *gl, MemBudget *budget);
/* A target of [w] x [h] pixels of [colorbits] (8, 16 or 32; anything
 * else is taken as 16), sRGB-encoded when [srgb] and 8 bits, with a depth
 * buffer when [depth], multisampled by [samples] (rounded as above): a
 * released one of the same kind if any, else a new one. Its contents are
 * undefined until cleared.
 *   errors: NULL with one line in [err] when a side is outside
 *           1..gl_context_max_size ("... is beyond this OpenGL's limit of
 *           N pixels"), the memory budget refuses its bytes, or GL cannot
 *           complete its framebuffer. */
GlTarget *target_get(TargetPool *p, int w, int h, int colorbits, bool srgb, bool depth, int samples, Buf *err);
/* Give [t] back to the pool (NULL is a no-op). */
void target_release(TargetPool *p, GlTarget *t);
/* Delete pooled targets released more than [age] seconds before [now]. */
void target_pool_expire(TargetPool *p, double now, double age);
/* Delete every pooled target and the pool (NULL is a no-op); targets not
 * released are the caller's to release first. */
void target_pool_free(TargetPool *p);

/* Bind [t]'s framebuffer for drawing, the viewport over all of it, GL's
 * sRGB encoding on for an sRGB target. */
void target_bind(GlTarget *t);
/* Clear the bound [t] to [rgba] (and its depth to 1). */
void target_clear(GlTarget *t, const float rgba[4]);
/* After drawing: resolve the samples into the texture and turn the sRGB
 * encoding off again. */
void target_finish(GlTarget *t);
/* Read [t]'s texture back as 8-bit words 0xAARRGGBB (native-endian
 * uint32_t), top row first, rows [stride] bytes apart (a multiple of 4,
 * at least w*4) in [px] (an sRGB target gives its sRGB bytes; another is
 * clamped to 0..1 and scaled to 0..255 by GL). */
void target_read_argb(GlTarget *t, uint32_t *px, size_t stride);
/* Read [t]'s texture back as float RGBA, top row first, w*h*4 floats. */
void target_readf(GlTarget *t, float *out);

/* Monotonic seconds, for release times. */
double target_now(void);

#endif
