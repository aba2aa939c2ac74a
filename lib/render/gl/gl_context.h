/* gl_context.h: an offscreen OpenGL 3.3 core context and its framebuffer.
 *
 * The context is made through EGL on Mesa's surfaceless platform
 * (EGL_MESA_platform_surfaceless), so it needs no display server and no
 * GPU: without one Mesa draws with llvmpipe. GL entry points come from
 * libepoxy. Each GlContext is its own EGL context (no process-wide
 * state: two renderers, or two runtimes, in one process each own one);
 * gl_context_use makes it current on the calling thread before drawing.
 *
 * The framebuffer is a render pass target of W x H pixels: a half-float
 * RGBA colour buffer (values above 1 are kept, as Flitter's 16-bit
 * default `colorbits`) and a 24-bit depth buffer, multisampled when
 * `samples` asks (Flitter render/window/canvas3d.pyx, Camera.derive:
 * samples below 2 are none, others rounded down to a power of two and
 * capped at GL_MAX_SAMPLES); gl_target_read resolves it and reads it back.
 */
#ifndef FL_RENDER_GL_CONTEXT_H
#define FL_RENDER_GL_CONTEXT_H

#include <stdbool.h>
#include <stddef.h>

typedef struct GlContext GlContext;

/* A new context (current on the calling thread when it returns).
 *   errors: NULL with one line in [err] (no EGL, no surfaceless platform,
 *           no OpenGL 3.3 core); nothing is left allocated. */
GlContext *gl_context_new(char *err, size_t errlen);
/* Make [gl] current on the calling thread; false when EGL refuses. */
bool gl_context_use(GlContext *gl);
/* Make no context current on the calling thread (after a draw, so that
 * the context may be used from another thread next time). */
void gl_context_done(GlContext *gl);
/* Bind a framebuffer of [w] x [h] pixels (1..16384) with [samples]
 * multisampling (the count actually used, after rounding and capping and
 * as the driver gave it, which may be more than asked, is returned
 * through [used] when not NULL), reallocating its buffers only
 * when the size or sample count changed; sets the viewport.
 *   errors: false with a message in [err] when the framebuffer is
 *           incomplete (e.g. too large for the driver). */
bool gl_target_bind(GlContext *gl, int w, int h, int samples, int *used, char *err, size_t errlen);
/* Resolve the bound framebuffer and read its pixels into [rgba]: w*h*4
 * floats, linear premultiplied RGBA, the top row first (GL's rows are
 * bottom-up; this flips them). The framebuffer's half floats are read as
 * they are and widened exactly on two threads (halffloat.h, halves.h);
 * when no buffer for them can be had, GL converts to floats itself. */
void gl_target_read(GlContext *gl, float *rgba);
/* gl_target_read for a framebuffer whose pixels outside the rectangle
 * [rect] (x0, y0, x1, y1: GL window pixels, bottom-up, x0 <= x < x1, y0 <=
 * y < y1, within the framebuffer, not all of it) all hold one colour,
 * the clear colour: only the rectangle and one pixel outside it are
 * resolved and read back, and every other pixel of [rgba] takes that
 * pixel's value (the clear colour as the driver stored it, whatever its
 * rounding). The result is the whole read's, bit for bit, when that
 * promise holds. An empty rectangle reads that one pixel. */
void gl_target_read_rect(GlContext *gl, float *rgba, const int rect[4]);
/* The renderer string of the driver (e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"). */
const char *gl_context_renderer(const GlContext *gl);
/* Release the framebuffer and the context (NULL is a no-op). */
void gl_context_free(GlContext *gl);

#endif
