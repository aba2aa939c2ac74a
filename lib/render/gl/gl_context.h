/* gl_context.h: the OpenGL 3.3 core context the render graph draws with.
 *
 * Either the library's own (gl_context_new): an EGL context on Mesa's
 * surfaceless platform (EGL_MESA_platform_surfaceless), which needs no
 * display server and no GPU (without one Mesa draws with llvmpipe), made
 * current on the calling thread by gl_context_use before each use and
 * released after it, so that a runtime may move between threads; or a
 * host's (gl_context_host): whatever context is current on the calling
 * thread when it is made (a front end's window context, SDL's), which the
 * host keeps current whenever it calls the library. GL entry points come
 * from libepoxy (gl_lib.h). Each GlContext is independent: two renderers,
 * or two runtimes, in one process own one each.
 */
#ifndef FL_RENDER_GL_CONTEXT_H
#define FL_RENDER_GL_CONTEXT_H

#include <stdbool.h>
#include <stddef.h>

#include "buf.h"

typedef struct GlContext GlContext;

/* A context of the library's own (current on the calling thread when it
 * returns).
 *   errors: NULL with one line in [err] (no libepoxy or EGL, no
 *           surfaceless platform, no OpenGL 3.3 core); nothing is left
 *           allocated. */
GlContext *gl_context_new(Buf *err);
/* The context current on the calling thread, as the host's: the library
 * draws with it whenever it is called on a thread where it is current,
 * and never makes any context current or releases it.
 *   errors: NULL with one line in [err] (no libepoxy, no context current,
 *           OpenGL below 3.3). */
GlContext *gl_context_host(Buf *err);
/* Make [gl] current on the calling thread (a host's context: it is
 * assumed to be); false when EGL refuses. */
bool gl_context_use(GlContext *gl);
/* After drawing: release the library's own context from the calling
 * thread (a host's is left as it is). */
void gl_context_done(GlContext *gl);
/* GL_MAX_SAMPLES. */
int gl_context_max_samples(const GlContext *gl);
/* The largest side of a framebuffer the driver takes: the least of
 * GL_MAX_TEXTURE_SIZE, GL_MAX_RENDERBUFFER_SIZE and GL_MAX_VIEWPORT_DIMS. */
int gl_context_max_size(const GlContext *gl);
/* Release the context (NULL is a no-op): the library's own is destroyed,
 * a host's only forgotten (the host destroys it). Objects made on it must
 * have been deleted before, with the context current. */
void gl_context_free(GlContext *gl);

#endif
