/* gl_target.c: render targets and their pool (see gl_target.h). */
#include "gl_target.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* last: it turns the library's names into calls through its table */
#include "gl_lib.h"

struct TargetPool {
    GlContext *gl;
    MemBudget *budget;
    GlTarget *free;          /* released targets, most recent first */
};

double target_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
}

TargetPool *target_pool_new(GlContext *gl, MemBudget *budget)
{
    TargetPool *p = mem_calloc(1, sizeof *p);
    p->gl = gl;
    p->budget = budget;
    return p;
}

static void formats(int colorbits, bool srgb, GLenum *internal, GLenum *type, int *bpp)
{
    switch (colorbits) {
    case 8:
        *internal = srgb ? GL_SRGB8_ALPHA8 : GL_RGBA8;
        *type = GL_UNSIGNED_BYTE;
        *bpp = 4;
        break;
    case 32:
        *internal = GL_RGBA32F;
        *type = GL_FLOAT;
        *bpp = 16;
        break;
    default:
        *internal = GL_RGBA16F;
        *type = GL_HALF_FLOAT;
        *bpp = 8;
        break;
    }
}

/* Flitter's sample count: none below 2, else the power of two at or below
 * [samples], at most the driver's maximum. */
static int sample_count(const TargetPool *p, int samples)
{
    if (samples < 2) return 0;
    int max = gl_context_max_samples(p->gl), s = 1;
    while (s * 2 <= samples && s * 2 <= max) s *= 2;
    return s >= 2 ? s : 0;
}

static void destroy(TargetPool *p, GlTarget *t)
{
    GLuint fbos[2] = {t->fbo, t->tex_fbo != t->fbo ? t->tex_fbo : 0};
    GLuint rbs[2] = {t->color_rb, t->depth_rb};
    glDeleteFramebuffers(2, fbos);
    glDeleteRenderbuffers(2, rbs);
    glDeleteTextures(1, &t->tex);
    mem_budget_release(p->budget, t->bytes);
    free(t);
}

static bool complete(GLuint fbo)
{
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    return glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
}

GlTarget *target_get(TargetPool *p, int w, int h, int colorbits, bool srgb, bool depth, int samples, Buf *err)
{
    if (colorbits != 8 && colorbits != 32) colorbits = 16;
    if (colorbits != 8) srgb = false;
    samples = sample_count(p, samples);
    for (GlTarget **at = &p->free; *at; at = &(*at)->next) {
        GlTarget *t = *at;
        if (t->w == w && t->h == h && t->colorbits == colorbits && t->srgb == srgb && t->depth == depth &&
            t->samples == samples) {
            *at = t->next;
            t->next = NULL;
            return t;
        }
    }
    int max = gl_context_max_size(p->gl);
    if (w < 1 || h < 1 || w > max || h > max) {
        buf_printf(err, "a %dx%d framebuffer is beyond this OpenGL's limit of %d pixels a side\n", w, h, max);
        return NULL;
    }
    GLenum internal, type;
    int bpp;
    formats(colorbits, srgb, &internal, &type, &bpp);
    size_t npix = (size_t)w * (size_t)h;
    size_t bytes = npix * (size_t)bpp * (size_t)(1 + samples) + (depth ? npix * 4 * (size_t)(samples ? samples : 1) : 0);
    if (!mem_budget_reserve(p->budget, bytes)) {
        buf_printf(err, "a %dx%d framebuffer (%zu MB) is past the memory budget (--max-memory)\n", w, h,
                 bytes >> 20);
        return NULL;
    }
    GlTarget *t = mem_calloc(1, sizeof *t);
    *t = (GlTarget){.w = w, .h = h, .colorbits = colorbits, .srgb = srgb, .depth = depth, .samples = samples,
                    .given = samples, .bytes = bytes};
    /* on a unit no pass samples from: a program pass may be drawing with
     * its inputs bound while it asks for its next target */
    GLint unit = 0;
    glGetIntegerv(GL_ACTIVE_TEXTURE, &unit);
    glActiveTexture(GL_TEXTURE0 + GL_TARGET_SCRATCH_UNIT);
    glGenTextures(1, &t->tex);
    glBindTexture(GL_TEXTURE_2D, t->tex);
    glTexImage2D(GL_TEXTURE_2D, 0, (GLint)internal, w, h, 0, GL_RGBA, type, NULL);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glBindTexture(GL_TEXTURE_2D, 0);
    glActiveTexture((GLenum)unit);
    glGenFramebuffers(1, &t->tex_fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, t->tex_fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, t->tex, 0);
    bool ok = true;
    if (samples) {
        ok = complete(t->tex_fbo);
        glGenFramebuffers(1, &t->fbo);
        glBindFramebuffer(GL_FRAMEBUFFER, t->fbo);
        glGenRenderbuffers(1, &t->color_rb);
        glBindRenderbuffer(GL_RENDERBUFFER, t->color_rb);
        glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, internal, w, h);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, t->color_rb);
        /* a driver may round a count up (llvmpipe gives 4 for 2) */
        GLint given = 0;
        glGetRenderbufferParameteriv(GL_RENDERBUFFER, GL_RENDERBUFFER_SAMPLES, &given);
        if (given > samples) t->given = given;
    } else {
        t->fbo = t->tex_fbo;
    }
    if (depth) {
        glBindFramebuffer(GL_FRAMEBUFFER, t->fbo);
        glGenRenderbuffers(1, &t->depth_rb);
        glBindRenderbuffer(GL_RENDERBUFFER, t->depth_rb);
        glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_DEPTH_COMPONENT24, w, h);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, t->depth_rb);
    }
    glBindRenderbuffer(GL_RENDERBUFFER, 0);
    ok = ok && complete(t->fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (!ok) {
        buf_printf(err, "OpenGL cannot make a %dx%d %d-bit framebuffer%s with %d samples\n", w, h, colorbits,
                 depth ? " with depth" : "", samples);
        destroy(p, t);
        return NULL;
    }
    return t;
}

void target_release(TargetPool *p, GlTarget *t)
{
    if (!t) return;
    t->released = target_now();
    t->next = p->free;
    p->free = t;
}

void target_pool_expire(TargetPool *p, double now, double age)
{
    for (GlTarget **at = &p->free; *at;) {
        GlTarget *t = *at;
        if (t->released < now - age) {
            *at = t->next;
            destroy(p, t);
        } else {
            at = &t->next;
        }
    }
}

void target_pool_free(TargetPool *p)
{
    if (!p) return;
    while (p->free) {
        GlTarget *t = p->free;
        p->free = t->next;
        destroy(p, t);
    }
    free(p);
}

void target_bind(GlTarget *t)
{
    glBindFramebuffer(GL_FRAMEBUFFER, t->fbo);
    glViewport(0, 0, t->w, t->h);
    if (t->srgb) glEnable(GL_FRAMEBUFFER_SRGB);
    else glDisable(GL_FRAMEBUFFER_SRGB);
}

void target_clear(GlTarget *t, const float rgba[4])
{
    glClearColor(rgba[0], rgba[1], rgba[2], rgba[3]);
    glClearDepth(1);
    if (t->depth) glDepthMask(GL_TRUE);
    glClear(GL_COLOR_BUFFER_BIT | (t->depth ? GL_DEPTH_BUFFER_BIT : 0));
}

void target_finish(GlTarget *t)
{
    if (t->fbo != t->tex_fbo) {
        glBindFramebuffer(GL_READ_FRAMEBUFFER, t->fbo);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, t->tex_fbo);
        glBlitFramebuffer(0, 0, t->w, t->h, 0, 0, t->w, t->h, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    }
    glDisable(GL_FRAMEBUFFER_SRGB);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

/* Rows of [px] (h rows of [row] bytes) in the opposite order: GL's first
 * row is the bottom one. */
/* Turn [h] rows of [row] bytes, [stride] apart, upside down. */
static void flip(void *px, size_t stride, size_t row, int h)
{
    unsigned char *p = px, *tmp = mem_alloc(row);
    for (int y = 0; y < h / 2; y++) {
        unsigned char *a = p + (size_t)y * stride, *b = p + (size_t)(h - 1 - y) * stride;
        memcpy(tmp, a, row);
        memcpy(a, b, row);
        memcpy(b, tmp, row);
    }
    free(tmp);
}

void target_read_argb(GlTarget *t, uint32_t *px, size_t stride)
{
    glBindFramebuffer(GL_READ_FRAMEBUFFER, t->tex_fbo);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glPixelStorei(GL_PACK_ROW_LENGTH, (GLint)(stride / 4));
    glReadPixels(0, 0, t->w, t->h, GL_BGRA, GL_UNSIGNED_INT_8_8_8_8_REV, px);
    glPixelStorei(GL_PACK_ROW_LENGTH, 0);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    flip(px, stride, (size_t)t->w * 4, t->h);
}

void target_readf(GlTarget *t, float *out)
{
    glBindFramebuffer(GL_READ_FRAMEBUFFER, t->tex_fbo);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(0, 0, t->w, t->h, GL_RGBA, GL_FLOAT, out);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    flip(out, (size_t)t->w * 16, (size_t)t->w * 16, t->h);
}
