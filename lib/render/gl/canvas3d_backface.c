/* canvas3d_backface.c: the back-face framebuffer of `!canvas3d`
 * translucency (see canvas3d_backface.h). One per renderer, remade only
 * when the picture's size changes. */
#include "canvas3d_backface.h"

#include <string.h>

#include <epoxy/gl.h>

/* last: it turns the library's names into calls through its table */
#include "gl_lib.h"

void c3d_backface_free(C3dBackface *b)
{
    if (b->fbo) glDeleteFramebuffers(1, &b->fbo);
    if (b->texture) glDeleteTextures(1, &b->texture);
    if (b->depth) glDeleteRenderbuffers(1, &b->depth);
    memset(b, 0, sizeof *b);
}

static bool make(C3dBackface *b, int w, int h)
{
    glGenTextures(1, &b->texture);
    glBindTexture(GL_TEXTURE_2D, b->texture);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA16F, w, h, 0, GL_RGBA, GL_FLOAT, NULL);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
    glBindTexture(GL_TEXTURE_2D, 0);
    glGenRenderbuffers(1, &b->depth);
    glBindRenderbuffer(GL_RENDERBUFFER, b->depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, w, h);
    glGenFramebuffers(1, &b->fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, b->fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, b->texture, 0);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, b->depth);
    b->w = w;
    b->h = h;
    return glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
}

bool c3d_backface_begin(C3dBackface *b, int w, int h)
{
    GLint prev = 0, vp[4];
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &prev);
    glGetIntegerv(GL_VIEWPORT, vp);
    if (b->fbo && (b->w != w || b->h != h)) c3d_backface_free(b);
    if (!b->fbo && !make(b, w, h)) {
        c3d_backface_free(b);
        glBindFramebuffer(GL_FRAMEBUFFER, (GLuint)prev);
        return false;
    }
    b->previous_fbo = prev;
    memcpy(b->previous_viewport, vp, sizeof vp);
    glBindFramebuffer(GL_FRAMEBUFFER, b->fbo);
    glViewport(0, 0, w, h);
    glDepthMask(GL_TRUE);
    glClearColor(0, 0, 0, 0);
    glClearDepth(1);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    return true;
}

void c3d_backface_end(C3dBackface *b)
{
    glBindFramebuffer(GL_FRAMEBUFFER, (GLuint)b->previous_fbo);
    glViewport(b->previous_viewport[0], b->previous_viewport[1], b->previous_viewport[2], b->previous_viewport[3]);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, b->texture);
}
