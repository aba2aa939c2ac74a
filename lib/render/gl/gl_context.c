/* gl_context.c: an EGL surfaceless OpenGL 3.3 core context and its
 * framebuffer (see gl_context.h).
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

#include "halffloat.h"
#include "halves.h"

#include <epoxy/egl.h>
#include <epoxy/gl.h>

/* last: it turns the library's names into calls through its table */
#include "gl_lib.h"

struct GlContext {
    EGLDisplay dpy;
    EGLContext ctx;
    bool tracked;            /* the display counts references: terminate it */
    int max_samples;         /* GL_MAX_SAMPLES */
    int w, h, samples;       /* the framebuffer's size and sample count (0: none yet) */
    int given;               /* the samples the driver gave for [samples] (it may give more) */
    GLuint fbo, color, depth;          /* the render pass target (multisampled or not) */
    GLuint resolve_fbo, resolve_color; /* single-sampled copy when samples > 0 */
    char renderer[128];
    uint16_t *half;          /* gl_target_read's half floats, cap_half of them */
    size_t cap_half;
    int f16c;                /* halves_fast_route(), asked once */
};

static bool has_ext(const char *list, const char *name)
{
    size_t n = strlen(name);
    for (const char *p = list; p && (p = strstr(p, name)); p += n)
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
    return false;
}

GlContext *gl_context_new(char *err, size_t errlen)
{
    if (!gl_lib_ready(err, errlen)) return NULL;
    const char *client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!client || !has_ext(client, "EGL_MESA_platform_surfaceless") ||
        !has_ext(client, "EGL_EXT_platform_base")) {
        snprintf(err, errlen, "EGL has no surfaceless platform (EGL_MESA_platform_surfaceless)");
        return NULL;
    }
    GlContext *gl = calloc(1, sizeof *gl);
    if (!gl) {
        snprintf(err, errlen, "out of memory");
        return NULL;
    }
    gl->tracked = has_ext(client, "EGL_KHR_display_reference");
    gl->f16c = halves_fast_route();
    const EGLint track[] = {EGL_TRACK_REFERENCES_KHR, EGL_TRUE, EGL_NONE};
    gl->dpy = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY,
                                       gl->tracked ? track : NULL);
    EGLint major, minor;
    if (gl->dpy == EGL_NO_DISPLAY || !eglInitialize(gl->dpy, &major, &minor)) {
        snprintf(err, errlen, "EGL cannot open the surfaceless display (error 0x%x)", (unsigned)eglGetError());
        free(gl);
        return NULL;
    }
    const char *exts = eglQueryString(gl->dpy, EGL_EXTENSIONS);
    if (!has_ext(exts, "EGL_KHR_surfaceless_context") || !has_ext(exts, "EGL_KHR_no_config_context") ||
        !eglBindAPI(EGL_OPENGL_API)) {
        snprintf(err, errlen, "EGL offers no surfaceless desktop OpenGL context");
        goto fail;
    }
    const EGLint attrs[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 3,
                            EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    gl->ctx = eglCreateContext(gl->dpy, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attrs);
    if (gl->ctx == EGL_NO_CONTEXT) {
        snprintf(err, errlen, "EGL cannot create an OpenGL 3.3 core context (error 0x%x)", (unsigned)eglGetError());
        goto fail;
    }
    if (!gl_context_use(gl)) {
        snprintf(err, errlen, "EGL cannot make the OpenGL context current (error 0x%x)", (unsigned)eglGetError());
        goto fail;
    }
    if (epoxy_gl_version() < 33) {
        snprintf(err, errlen, "OpenGL %d.%d is below 3.3", epoxy_gl_version() / 10, epoxy_gl_version() % 10);
        goto fail;
    }
    glGetIntegerv(GL_MAX_SAMPLES, &gl->max_samples);
    const char *name = (const char *)glGetString(GL_RENDERER);
    snprintf(gl->renderer, sizeof gl->renderer, "%s", name ? name : "?");
    return gl;
fail:
    gl_context_free(gl);
    return NULL;
}

bool gl_context_use(GlContext *gl)
{
    return eglMakeCurrent(gl->dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, gl->ctx) == EGL_TRUE;
}

void gl_context_done(GlContext *gl) { eglMakeCurrent(gl->dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT); }

const char *gl_context_renderer(const GlContext *gl) { return gl->renderer; }

static void drop_target(GlContext *gl)
{
    GLuint fbos[2] = {gl->fbo, gl->resolve_fbo};
    GLuint rbs[3] = {gl->color, gl->depth, gl->resolve_color};
    glDeleteFramebuffers(2, fbos);
    glDeleteRenderbuffers(3, rbs);
    gl->fbo = gl->resolve_fbo = gl->color = gl->depth = gl->resolve_color = 0;
    gl->w = gl->h = 0;
}

/* Flitter's sample count: none below 2, else the power of two at or below
 * [samples], at most the driver's maximum. */
static int sample_count(const GlContext *gl, int samples)
{
    if (samples < 2) return 0;
    int s = 1;
    while (s * 2 <= samples && s * 2 <= gl->max_samples) s *= 2;
    return s >= 2 ? s : 0;
}

bool gl_target_bind(GlContext *gl, int w, int h, int samples, int *used, char *err, size_t errlen)
{
    int s = sample_count(gl, samples);
    if (gl->fbo && (gl->w != w || gl->h != h || gl->samples != s)) drop_target(gl);
    if (!gl->fbo) {
        glGenFramebuffers(1, &gl->fbo);
        glBindFramebuffer(GL_FRAMEBUFFER, gl->fbo);
        glGenRenderbuffers(1, &gl->color);
        glBindRenderbuffer(GL_RENDERBUFFER, gl->color);
        glRenderbufferStorageMultisample(GL_RENDERBUFFER, s, GL_RGBA16F, w, h);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, gl->color);
        glGenRenderbuffers(1, &gl->depth);
        glBindRenderbuffer(GL_RENDERBUFFER, gl->depth);
        glRenderbufferStorageMultisample(GL_RENDERBUFFER, s, GL_DEPTH_COMPONENT24, w, h);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, gl->depth);
        bool ok = glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
        if (ok && s > 0) {
            glGenFramebuffers(1, &gl->resolve_fbo);
            glBindFramebuffer(GL_FRAMEBUFFER, gl->resolve_fbo);
            glGenRenderbuffers(1, &gl->resolve_color);
            glBindRenderbuffer(GL_RENDERBUFFER, gl->resolve_color);
            glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA16F, w, h);
            glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, gl->resolve_color);
            ok = glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
        }
        if (!ok) {
            snprintf(err, errlen, "OpenGL cannot make a %dx%d framebuffer with %d samples", w, h, s);
            drop_target(gl);
            glBindFramebuffer(GL_FRAMEBUFFER, 0);
            return false;
        }
        gl->w = w;
        gl->h = h;
        gl->samples = s;
        /* a driver may round a count up (llvmpipe gives 4 for 2): the
         * impostors' sample masks need the real one */
        GLint given = 0;
        glBindRenderbuffer(GL_RENDERBUFFER, gl->color);
        glGetRenderbufferParameteriv(GL_RENDERBUFFER, GL_RENDERBUFFER_SAMPLES, &given);
        gl->given = s > 0 && given > s ? (int)given : s;
    }
    if (used) *used = gl->given;
    glBindFramebuffer(GL_FRAMEBUFFER, gl->fbo);
    glViewport(0, 0, w, h);
    return true;
}

/* Rows of [rgba] (w x h RGBA floats) in the opposite order: GL's first row
 * is the bottom one. */
static void flip_rows(float *rgba, int w, int h)
{
    size_t row = (size_t)w * 4;
    float *tmp = malloc(row * sizeof *tmp);
    if (!tmp) return;
    for (int y = 0; y < h / 2; y++) {
        float *a = rgba + (size_t)y * row, *b = rgba + (size_t)(h - 1 - y) * row;
        memcpy(tmp, a, row * sizeof *tmp);
        memcpy(a, b, row * sizeof *tmp);
        memcpy(b, tmp, row * sizeof *tmp);
    }
    free(tmp);
}

/* The framebuffer's half floats of the columns x0 .. x1-1 of rows y0 ..
 * y1-1 (GL's, bottom-up), bottom row first, widened to floats top row
 * first, each other pixel of a row set to [outside] (rows_in_halves). */
typedef struct Widening {
    const uint16_t *half;
    float *rgba;
    int w, h;
    int x0, y0, x1, y1;
    const float *outside;
    int fast;                /* the F16C route (GlContext.f16c) */
} Widening;

static void fill_pixels(float *px, size_t n, const float *v)
{
    for (size_t i = 0; i < n; i++) memcpy(px + 4 * i, v, 4 * sizeof(float));
}

static void widen_rows(void *ctx, int y0, int y1, int part)
{
    (void)part;
    const Widening *j = ctx;
    size_t row = (size_t)j->w * 4, span = (size_t)(j->x1 - j->x0) * 4;
    for (int y = y0; y < y1; y++) {
        float *out = j->rgba + (size_t)y * row;
        int gy = j->h - 1 - y;   /* GL's row */
        if (gy < j->y0 || gy >= j->y1 || span == 0) {
            fill_pixels(out, (size_t)j->w, j->outside);
            continue;
        }
        fill_pixels(out, (size_t)j->x0, j->outside);
        halves_to_floats(j->half + (size_t)(gy - j->y0) * span, out + (size_t)j->x0 * 4, span, j->fast);
        fill_pixels(out + (size_t)j->x1 * 4, (size_t)(j->w - j->x1), j->outside);
    }
}

/* The pixel (x, y) of the bound framebuffer, resolved, as floats. */
static void read_pixel(GlContext *gl, int x, int y, float out[4])
{
    GLuint src = gl->fbo;
    if (gl->samples > 0) {
        glBindFramebuffer(GL_READ_FRAMEBUFFER, gl->fbo);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, gl->resolve_fbo);
        glBlitFramebuffer(x, y, x + 1, y + 1, x, y, x + 1, y + 1, GL_COLOR_BUFFER_BIT, GL_NEAREST);
        src = gl->resolve_fbo;
    }
    glBindFramebuffer(GL_READ_FRAMEBUFFER, src);
    glPixelStorei(GL_PACK_ALIGNMENT, 2);
    uint16_t half[4];
    glReadPixels(x, y, 1, 1, GL_RGBA, GL_HALF_FLOAT, half);
    for (int k = 0; k < 4; k++) out[k] = half_to_float(half[k]);
}

/* Resolve (when multisampled) and read back [rect] of the bound
 * framebuffer, the rest the value of one pixel outside it; [rect] NULL:
 * the whole framebuffer. */
static void read_rect(GlContext *gl, float *rgba, const int *rect)
{
    int w = gl->w, h = gl->h;
    float outside[4] = {0, 0, 0, 0};
    if (rect) {
        /* a pixel outside: a corner the rectangle leaves out */
        bool low = rect[0] > 0 || rect[1] > 0;
        read_pixel(gl, low ? 0 : w - 1, low ? 0 : h - 1, outside);
    }
    int x0 = rect ? rect[0] : 0, y0 = rect ? rect[1] : 0, x1 = rect ? rect[2] : w, y1 = rect ? rect[3] : h;
    int rw = x1 > x0 ? x1 - x0 : 0, rh = y1 > y0 ? y1 - y0 : 0;
    GLuint src = gl->fbo;
    if (gl->samples > 0 && rw && rh) {
        glBindFramebuffer(GL_READ_FRAMEBUFFER, gl->fbo);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, gl->resolve_fbo);
        glBlitFramebuffer(x0, y0, x1, y1, x0, y0, x1, y1, GL_COLOR_BUFFER_BIT, GL_NEAREST);
        src = gl->resolve_fbo;
    }
    glBindFramebuffer(GL_READ_FRAMEBUFFER, src);
    glPixelStorei(GL_PACK_ALIGNMENT, 2);
    size_t n = (size_t)rw * rh * 4;
    if (n > gl->cap_half) {
        uint16_t *more = realloc(gl->half, n * sizeof *more);
        if (!more) {   /* no room for the halves: GL converts the whole picture (the part
                          outside [rect] holds [outside] too: the same pixels) */
            if (gl->samples > 0 && rect) {
                glBindFramebuffer(GL_READ_FRAMEBUFFER, gl->fbo);
                glBindFramebuffer(GL_DRAW_FRAMEBUFFER, gl->resolve_fbo);
                glBlitFramebuffer(0, 0, w, h, 0, 0, w, h, GL_COLOR_BUFFER_BIT, GL_NEAREST);
                glBindFramebuffer(GL_READ_FRAMEBUFFER, gl->resolve_fbo);
            }
            glPixelStorei(GL_PACK_ALIGNMENT, 4);
            glReadPixels(0, 0, w, h, GL_RGBA, GL_FLOAT, rgba);
            glBindFramebuffer(GL_FRAMEBUFFER, gl->fbo);
            flip_rows(rgba, w, h);
            return;
        }
        gl->half = more;
        gl->cap_half = n;
    }
    /* the framebuffer's own format, copied as it is; widened here */
    if (n) glReadPixels(x0, y0, rw, rh, GL_RGBA, GL_HALF_FLOAT, gl->half);
    glBindFramebuffer(GL_FRAMEBUFFER, gl->fbo);
    Widening job = {gl->half, rgba, w, h, x0, y0, x0 + rw, y0 + rh, outside, gl->f16c};
    rows_in_halves(h, 64, widen_rows, &job);
}

void gl_target_read(GlContext *gl, float *rgba) { read_rect(gl, rgba, NULL); }

void gl_target_read_rect(GlContext *gl, float *rgba, const int rect[4]) { read_rect(gl, rgba, rect); }

void gl_context_free(GlContext *gl)
{
    if (!gl) return;
    if (gl->ctx != EGL_NO_CONTEXT && gl_context_use(gl)) drop_target(gl);
    eglMakeCurrent(gl->dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (gl->ctx != EGL_NO_CONTEXT) eglDestroyContext(gl->dpy, gl->ctx);
    if (gl->tracked) eglTerminate(gl->dpy);
    eglReleaseThread();
    free(gl->half);
    free(gl);
}
