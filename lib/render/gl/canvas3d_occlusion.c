/* canvas3d_occlusion.c: the occluders' framebuffer of `!canvas3d` (see
 * canvas3d_occlusion.h). */
#include "canvas3d_occlusion.h"

#include <string.h>

#include <epoxy/gl.h>

/* last: it turns the library's names into calls through its table */
#include "gl_lib.h"

void c3d_occlusion_free(C3dOcclusion *o)
{
    if (o->fbo) glDeleteFramebuffers(1, &o->fbo);
    if (o->depth) glDeleteTextures(1, &o->depth);
    memset(o, 0, sizeof *o);
}

/* The texture target of [samples] samples. */
static GLenum target_of(int samples) { return samples > 1 ? GL_TEXTURE_2D_MULTISAMPLE : GL_TEXTURE_2D; }

static bool make(C3dOcclusion *o, int w, int h, int samples)
{
    GLenum target = target_of(samples);
    glGenTextures(1, &o->depth);
    glBindTexture(target, o->depth);
    if (samples > 1) {
        /* fixed sample locations, as the picture's renderbuffers have */
        glTexImage2DMultisample(GL_TEXTURE_2D_MULTISAMPLE, samples, GL_DEPTH_COMPONENT24, w, h, GL_TRUE);
    } else {
        /* complete without mipmaps (texelFetch reads level 0), no comparison */
        glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT24, w, h, 0, GL_DEPTH_COMPONENT, GL_UNSIGNED_INT, NULL);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_NONE);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
    }
    glBindTexture(target, 0);
    glGenFramebuffers(1, &o->fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, o->fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, target, o->depth, 0);
    glDrawBuffer(GL_NONE);
    glReadBuffer(GL_NONE);
    o->w = w;
    o->h = h;
    o->samples = samples;
    return glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
}

bool c3d_occlusion_begin(C3dOcclusion *o, int w, int h, int samples)
{
    GLint prev = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &prev);
    if (o->fbo && (o->w != w || o->h != h || o->samples != samples)) c3d_occlusion_free(o);
    if (!o->fbo && !make(o, w, h, samples)) {
        c3d_occlusion_free(o);
        glBindFramebuffer(GL_FRAMEBUFFER, (GLuint)prev);
        return false;
    }
    o->previous_fbo = prev;
    glBindFramebuffer(GL_FRAMEBUFFER, o->fbo);
    glDepthMask(GL_TRUE);
    glClearDepth(1);
    glClear(GL_DEPTH_BUFFER_BIT);
    return true;
}

void c3d_occlusion_end(C3dOcclusion *o)
{
    glBindFramebuffer(GL_FRAMEBUFFER, (GLuint)o->previous_fbo);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(target_of(o->samples), o->depth);
    glActiveTexture(GL_TEXTURE0);
}

void c3d_occlusion_unbind(void)
{
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D_MULTISAMPLE, 0);
    glBindTexture(GL_TEXTURE_2D, 0);
    glActiveTexture(GL_TEXTURE0);
}
