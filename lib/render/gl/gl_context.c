/* gl_context.c: the library's EGL surfaceless OpenGL 3.3 core context, or
 * a host's current one (see gl_context.h).
 *
 * The EGL display of the surfaceless platform is one per process in EGL's
 * model; when EGL_KHR_display_reference is offered it is opened with
 * EGL_TRACK_REFERENCES_KHR so that each context's eglInitialize is paired
 * with its own eglTerminate, otherwise it is never terminated (a second
 * context may still use it). */
#include "gl_context.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <epoxy/egl.h>
#include <epoxy/gl.h>

/* last: it turns the library's names into calls through its table */
#include "gl_lib.h"

struct GlContext {
    bool host;               /* the host's context: never made current or destroyed here */
    EGLDisplay dpy;
    EGLContext ctx;
    bool tracked;            /* the display counts references: terminate it */
    int max_samples;         /* GL_MAX_SAMPLES */
    int max_size;            /* the largest framebuffer side */
    char renderer[128];
};

static bool has_ext(const char *list, const char *name)
{
    size_t n = strlen(name);
    for (const char *p = list; p && (p = strstr(p, name)); p += n)
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
    return false;
}

/* Read the limits and the renderer of the current context; false with a
 * message when it is below OpenGL 3.3. */
static bool describe(GlContext *gl, Buf *err)
{
    if (epoxy_gl_version() < 33) {
        buf_printf(err, "OpenGL %d.%d is below 3.3\n", epoxy_gl_version() / 10, epoxy_gl_version() % 10);
        return false;
    }
    GLint samples = 0, tex = 0, rb = 0, vp[2] = {0, 0};
    glGetIntegerv(GL_MAX_SAMPLES, &samples);
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &tex);
    glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &rb);
    glGetIntegerv(GL_MAX_VIEWPORT_DIMS, vp);
    gl->max_samples = samples;
    int m = tex;
    if (rb < m) m = rb;
    if (vp[0] < m) m = vp[0];
    if (vp[1] < m) m = vp[1];
    gl->max_size = m > 0 ? m : 1;
    const char *name = (const char *)glGetString(GL_RENDERER);
    snprintf(gl->renderer, sizeof gl->renderer, "%s", name ? name : "?");
    return true;
}

GlContext *gl_context_new(Buf *err)
{
    if (!gl_lib_ready(err)) return NULL;
    const char *client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!client || !has_ext(client, "EGL_MESA_platform_surfaceless") ||
        !has_ext(client, "EGL_EXT_platform_base")) {
        buf_printf(err, "EGL has no surfaceless platform (EGL_MESA_platform_surfaceless)\n");
        return NULL;
    }
    GlContext *gl = calloc(1, sizeof *gl);
    if (!gl) {
        buf_printf(err, "out of memory\n");
        return NULL;
    }
    gl->tracked = has_ext(client, "EGL_KHR_display_reference");
    const EGLint track[] = {EGL_TRACK_REFERENCES_KHR, EGL_TRUE, EGL_NONE};
    gl->dpy = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY,
                                       gl->tracked ? track : NULL);
    EGLint major, minor;
    if (gl->dpy == EGL_NO_DISPLAY || !eglInitialize(gl->dpy, &major, &minor)) {
        buf_printf(err, "EGL cannot open the surfaceless display (error 0x%x)\n", (unsigned)eglGetError());
        free(gl);
        return NULL;
    }
    const char *exts = eglQueryString(gl->dpy, EGL_EXTENSIONS);
    if (!has_ext(exts, "EGL_KHR_surfaceless_context") || !has_ext(exts, "EGL_KHR_no_config_context") ||
        !eglBindAPI(EGL_OPENGL_API)) {
        buf_printf(err, "EGL offers no surfaceless desktop OpenGL context\n");
        goto fail;
    }
    const EGLint attrs[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 3,
                            EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    gl->ctx = eglCreateContext(gl->dpy, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attrs);
    if (gl->ctx == EGL_NO_CONTEXT) {
        buf_printf(err, "EGL cannot create an OpenGL 3.3 core context (error 0x%x)\n", (unsigned)eglGetError());
        goto fail;
    }
    if (!gl_context_use(gl)) {
        buf_printf(err, "EGL cannot make the OpenGL context current (error 0x%x)\n", (unsigned)eglGetError());
        goto fail;
    }
    if (!describe(gl, err)) goto fail;
    return gl;
fail:
    gl_context_free(gl);
    return NULL;
}

GlContext *gl_context_host(Buf *err)
{
    if (!gl_lib_ready(err)) return NULL;
    /* with no context current, glGetString gives NULL and epoxy a version of 0 */
    if (epoxy_gl_version() == 0) {
        buf_printf(err, "no OpenGL context is current on this thread\n");
        return NULL;
    }
    GlContext *gl = calloc(1, sizeof *gl);
    if (!gl) {
        buf_printf(err, "out of memory\n");
        return NULL;
    }
    gl->host = true;
    if (!describe(gl, err)) {
        free(gl);
        return NULL;
    }
    return gl;
}

bool gl_context_use(GlContext *gl)
{
    if (gl->host) return true;
    return eglMakeCurrent(gl->dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, gl->ctx) == EGL_TRUE;
}

void gl_context_done(GlContext *gl)
{
    if (!gl->host) eglMakeCurrent(gl->dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
}

int gl_context_max_samples(const GlContext *gl) { return gl->max_samples; }

int gl_context_max_size(const GlContext *gl) { return gl->max_size; }

void gl_context_free(GlContext *gl)
{
    if (!gl) return;
    if (!gl->host) {
        eglMakeCurrent(gl->dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        if (gl->ctx != EGL_NO_CONTEXT) eglDestroyContext(gl->dpy, gl->ctx);
        if (gl->tracked) eglTerminate(gl->dpy);
        eglReleaseThread();
    }
    free(gl);
}
