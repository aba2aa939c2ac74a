/* window_gl.c: the live window's OpenGL contexts, the frame loop's copy of
 * each picture and the display's drawing of it (see window_gl.h). GL
 * entry points come from libepoxy, which the window module links (the
 * library opens the same libepoxy with dlopen). */
#include "window_gl.h"

#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <epoxy/gl.h>

struct WinGl {
    SDL_Window *display_window, *frame_window;   /* hidden: each context's own drawable */
    SDL_GLContext display, frame;
    /* the display's objects */
    GLuint program, program_pixels;   /* light, clamped over black (shared); sRGB pixels as they are */
    GLint u_tex, u_tex_pixels;
    GLuint vao, vbo;
    GLuint pixels_tex;                /* the CPU pictures' texture */
    int pixels_w, pixels_h;
    GLuint fbo_read;                  /* the display's framebuffer of a picture's texture */
    GLuint nearest;                   /* a sampler of nearest texels (shared: the frame loop's copy) */
    /* the display's copy of a picture as a textured quad (0: blits) */
    GLuint program_copy;              /* its texels as they are */
    GLint u_tex_copy;
    GLuint raw_nearest, raw_linear;   /* samplers that leave sRGB texels encoded */
    /* the frame loop's objects */
    GLuint fbo_dst, frame_vao, frame_vbo;
    /* a renderer on the CPU: the two contexts take turns (wingl_lock) */
    bool serial;
    pthread_mutex_t turn;
    atomic_uintptr_t turn_owner;      /* the thread holding the turn (its pthread_t), or 0 */
};

static const char vertex_source[] =
    "#version 330 core\n"
    "in vec2 position;\n"
    "out vec2 coord;\n"
    "void main() {\n"
    "    coord = 0.5 * position + 0.5;\n"
    "    gl_Position = vec4(position, 0.0, 1.0);\n"
    "}\n";

/* Flitter's window: the light clamped, over black, opaque (written into
 * an sRGB texture with GL_FRAMEBUFFER_SRGB on: the GL encodes it). */
static const char fragment_linear[] =
    "#version 330 core\n"
    "in vec2 coord;\n"
    "out vec4 color;\n"
    "uniform sampler2D picture;\n"
    "void main() {\n"
    "    color = vec4(clamp(texture(picture, coord).rgb, 0.0, 1.0), 1.0);\n"
    "}\n";

/* A picture's sRGB bytes as they are (sampled without decoding). */
static const char fragment_copy[] =
    "#version 330 core\n"
    "in vec2 coord;\n"
    "out vec4 color;\n"
    "uniform sampler2D picture;\n"
    "void main() {\n"
    "    color = texture(picture, coord);\n"
    "}\n";

/* A CPU picture (rows top first, so read upside down), as it is. */
static const char fragment_pixels[] =
    "#version 330 core\n"
    "in vec2 coord;\n"
    "out vec4 color;\n"
    "uniform sampler2D picture;\n"
    "void main() {\n"
    "    color = texture(picture, vec2(coord.x, 1.0 - coord.y));\n"
    "}\n";

static GLuint link_program(const char *fsrc, char *why, size_t cap)
{
    const char *srcs[2] = {vertex_source, fsrc};
    GLenum types[2] = {GL_VERTEX_SHADER, GL_FRAGMENT_SHADER};
    GLuint prog = glCreateProgram(), sh[2];
    for (int i = 0; i < 2; i++) {
        sh[i] = glCreateShader(types[i]);
        glShaderSource(sh[i], 1, &srcs[i], NULL);
        glCompileShader(sh[i]);
        GLint ok = 0;
        glGetShaderiv(sh[i], GL_COMPILE_STATUS, &ok);
        if (!ok) {
            char log[512] = "";
            glGetShaderInfoLog(sh[i], sizeof log, NULL, log);
            snprintf(why, cap, "the window's shader does not compile: %s", log);
        }
        glAttachShader(prog, sh[i]);
    }
    glBindAttribLocation(prog, 0, "position");
    glLinkProgram(prog);
    glDeleteShader(sh[0]);
    glDeleteShader(sh[1]);
    GLint ok = 0;
    glGetProgramiv(prog, GL_LINK_STATUS, &ok);
    if (!ok) {
        if (!why[0]) snprintf(why, cap, "the window's shader does not link");
        glDeleteProgram(prog);
        return 0;
    }
    return prog;
}

/* A vertex array of the whole-viewport quad (attribute 0, a triangle
 * strip of 4 corners) in the current context, into [vao] and [vbo]. */
static void make_quad(GLuint *vao, GLuint *vbo)
{
    static const float quad[8] = {-1, -1, 1, -1, -1, 1, 1, 1};
    glGenVertexArrays(1, vao);
    glBindVertexArray(*vao);
    glGenBuffers(1, vbo);
    glBindBuffer(GL_ARRAY_BUFFER, *vbo);
    glBufferData(GL_ARRAY_BUFFER, sizeof quad, quad, GL_STATIC_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, NULL);
    glBindVertexArray(0);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
}

WinGl *wingl_start(char *why, size_t cap)
{
    why[0] = '\0';
    SDL_GL_SetAttribute(SDL_GL_CONTEXT_MAJOR_VERSION, 3);
    SDL_GL_SetAttribute(SDL_GL_CONTEXT_MINOR_VERSION, 3);
    SDL_GL_SetAttribute(SDL_GL_CONTEXT_PROFILE_MASK, SDL_GL_CONTEXT_PROFILE_CORE);
    SDL_GL_SetAttribute(SDL_GL_DOUBLEBUFFER, 1);
    SDL_GL_SetAttribute(SDL_GL_FRAMEBUFFER_SRGB_CAPABLE, 0);
    SDL_GL_SetAttribute(SDL_GL_SHARE_WITH_CURRENT_CONTEXT, 0);
    WinGl *g = calloc(1, sizeof *g);
    if (!g) {
        snprintf(why, cap, "out of memory");
        return NULL;
    }
    pthread_mutex_init(&g->turn, NULL);
    Uint32 hidden = SDL_WINDOW_OPENGL | SDL_WINDOW_HIDDEN;
    g->display_window = SDL_CreateWindow("flitter", 0, 0, 1, 1, hidden);
    g->frame_window = g->display_window ? SDL_CreateWindow("flitter", 0, 0, 1, 1, hidden) : NULL;
    if (!g->frame_window) goto fail;
    g->display = SDL_GL_CreateContext(g->display_window);
    if (!g->display) goto fail;
    SDL_GL_SetAttribute(SDL_GL_SHARE_WITH_CURRENT_CONTEXT, 1);
    g->frame = SDL_GL_CreateContext(g->frame_window);
    SDL_GL_SetAttribute(SDL_GL_SHARE_WITH_CURRENT_CONTEXT, 0);
    if (!g->frame) goto fail;
    /* the frame loop's context stays free for its thread; the display's
     * is current here from now on */
    if (SDL_GL_MakeCurrent(g->display_window, g->display) != 0) goto fail;
    if (epoxy_gl_version() < 33) {
        snprintf(why, cap, "OpenGL %d.%d is below 3.3", epoxy_gl_version() / 10, epoxy_gl_version() % 10);
        goto fail_quiet;
    }
    /* Mesa's CPU renderers (llvmpipe 22.3 seen crashing inside a draw
     * while the other context of the share group drew on its thread) */
    const char *renderer = (const char *)glGetString(GL_RENDERER);
    g->serial = renderer && (strstr(renderer, "llvmpipe") || strstr(renderer, "softpipe"));
    g->program = link_program(fragment_linear, why, cap);
    g->program_pixels = g->program ? link_program(fragment_pixels, why, cap) : 0;
    if (!g->program_pixels) goto fail_quiet;
    g->u_tex = glGetUniformLocation(g->program, "picture");
    g->u_tex_pixels = glGetUniformLocation(g->program_pixels, "picture");
    make_quad(&g->vao, &g->vbo);
    glGenTextures(1, &g->pixels_tex);
    glGenFramebuffers(1, &g->fbo_read);
    glGenSamplers(1, &g->nearest);
    glSamplerParameteri(g->nearest, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glSamplerParameteri(g->nearest, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glSamplerParameteri(g->nearest, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glSamplerParameteri(g->nearest, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    /* where texels can be sampled as they are stored (EXT_texture_sRGB_
     * decode), the display scales a picture into the window with a
     * textured quad: on llvmpipe 22.3 a 540x540 picture filtered into a
     * 1080x1080 window takes 4.6-5.2 ms so, against 6.7-7.2 ms with
     * glBlitFramebuffer (bench/PROFILE.md, issue 58, presenting) */
    if (epoxy_has_gl_extension("GL_EXT_texture_sRGB_decode")) {
        char ignored[8];
        g->program_copy = link_program(fragment_copy, ignored, sizeof ignored);
        g->u_tex_copy = g->program_copy ? glGetUniformLocation(g->program_copy, "picture") : -1;
        GLuint raw[2];
        glGenSamplers(2, raw);
        for (int i = 0; i < 2; i++) {
            GLint filter = i ? GL_LINEAR : GL_NEAREST;
            glSamplerParameteri(raw[i], GL_TEXTURE_MIN_FILTER, filter);
            glSamplerParameteri(raw[i], GL_TEXTURE_MAG_FILTER, filter);
            glSamplerParameteri(raw[i], GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
            glSamplerParameteri(raw[i], GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
            glSamplerParameteri(raw[i], GL_TEXTURE_SRGB_DECODE_EXT, GL_SKIP_DECODE_EXT);
        }
        g->raw_nearest = raw[0];
        g->raw_linear = raw[1];
    }
    return g;
fail:
    snprintf(why, cap, "no OpenGL 3.3 core windows: %s", SDL_GetError());
fail_quiet:
    wingl_stop(g);
    return NULL;
}

void wingl_stop(WinGl *g)
{
    if (!g) return;
    if (g->display && SDL_GL_MakeCurrent(g->display_window, g->display) == 0) {
        if (g->program) glDeleteProgram(g->program);
        if (g->program_pixels) glDeleteProgram(g->program_pixels);
        if (g->vao) glDeleteVertexArrays(1, &g->vao);
        if (g->vbo) glDeleteBuffers(1, &g->vbo);
        if (g->pixels_tex) glDeleteTextures(1, &g->pixels_tex);
        if (g->fbo_read) glDeleteFramebuffers(1, &g->fbo_read);
        if (g->nearest) glDeleteSamplers(1, &g->nearest);
        if (g->program_copy) glDeleteProgram(g->program_copy);
        if (g->raw_nearest) glDeleteSamplers(1, &g->raw_nearest);
        if (g->raw_linear) glDeleteSamplers(1, &g->raw_linear);
        SDL_GL_MakeCurrent(g->display_window, NULL);
    }
    if (g->frame) SDL_GL_DeleteContext(g->frame);
    if (g->display) SDL_GL_DeleteContext(g->display);
    if (g->frame_window) SDL_DestroyWindow(g->frame_window);
    if (g->display_window) SDL_DestroyWindow(g->display_window);
    pthread_mutex_destroy(&g->turn);
    free(g);
}

bool wingl_software(const WinGl *g) { return g && g->serial; }

void wingl_windows(const WinGl *g, SDL_Window **display, SDL_Window **frame)
{
    *display = g ? g->display_window : NULL;
    *frame = g ? g->frame_window : NULL;
}

void wingl_lock(WinGl *g)
{
    if (!g || !g->serial) return;
    pthread_mutex_lock(&g->turn);
    atomic_store(&g->turn_owner, (uintptr_t)pthread_self());
}

void wingl_unlock(WinGl *g)
{
    if (!g || !g->serial) return;
    atomic_store(&g->turn_owner, 0);
    pthread_mutex_unlock(&g->turn);
}

void wingl_give_up_turn(WinGl *g)
{
    if (g && g->serial && atomic_load(&g->turn_owner) == (uintptr_t)pthread_self()) wingl_unlock(g);
}

/* {===== the frame loop's side */

bool wingl_frame_enter(WinGl *g)
{
    if (SDL_GL_MakeCurrent(g->frame_window, g->frame) != 0) return false;
    if (!g->fbo_dst) {   /* (framebuffers and vertex arrays are not shared) */
        glGenFramebuffers(1, &g->fbo_dst);
        make_quad(&g->frame_vao, &g->frame_vbo);
    }
    return true;
}

void wingl_frame_leave(WinGl *g) { SDL_GL_MakeCurrent(g->frame_window, NULL); }

bool wingl_frame_copy(WinGl *g, WinGlPicture *p, unsigned src, int w, int h)
{
    if (p->done) {
        /* the display may still be reading this texture */
        glWaitSync(p->done, 0, GL_TIMEOUT_IGNORED);
        glDeleteSync(p->done);
        p->done = NULL;
    }
    if (p->ready) {
        glDeleteSync(p->ready);
        p->ready = NULL;
    }
    if (!p->tex || p->w != w || p->h != h) {
        if (!p->tex) glGenTextures(1, &p->tex);
        glBindTexture(GL_TEXTURE_2D, p->tex);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_SRGB8_ALPHA8, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        glBindTexture(GL_TEXTURE_2D, 0);
        p->w = w;
        p->h = h;
    }
    /* the picture as the window shows it: clamped, over black, encoded
     * to sRGB by the GL as it is written (the display then only copies
     * it: a blit, no shader) */
    glBindFramebuffer(GL_FRAMEBUFFER, g->fbo_dst);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, p->tex, 0);
    bool ok = glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
    if (ok) {
        glViewport(0, 0, w, h);
        glDisable(GL_BLEND);
        glDisable(GL_DEPTH_TEST);
        glEnable(GL_FRAMEBUFFER_SRGB);
        glUseProgram(g->program);
        glActiveTexture(GL_TEXTURE0);
        glBindTexture(GL_TEXTURE_2D, src);
        glBindSampler(0, g->nearest);   /* texel for texel */
        glUniform1i(g->u_tex, 0);
        glBindVertexArray(g->frame_vao);
        glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
        glBindVertexArray(0);
        glBindSampler(0, 0);
        glBindTexture(GL_TEXTURE_2D, 0);
        glUseProgram(0);
        glDisable(GL_FRAMEBUFFER_SRGB);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    p->ready = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
    glFlush();
    return ok;
}

void wingl_picture_free(WinGlPicture *p)
{
    if (p->ready) glDeleteSync(p->ready);
    if (p->done) glDeleteSync(p->done);
    if (p->tex) glDeleteTextures(1, &p->tex);
    memset(p, 0, sizeof *p);
}

/* }===== */

/* {===== the display's side */

bool wingl_use(WinGl *g, SDL_Window *w) { return SDL_GL_MakeCurrent(w, g->display) == 0; }

void wingl_output_size(SDL_Window *w, int *width, int *height) { SDL_GL_GetDrawableSize(w, width, height); }

void wingl_clear(int W, int H)
{
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, W, H);
    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
}

/* Draw the quad over the window rectangle x, y, w, h (top-left origin). */
static void quad(WinGl *g, int x, int y, int w, int h, int H)
{
    glViewport(x, H - y - h, w, h);
    glBindVertexArray(g->vao);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    glBindVertexArray(0);
}

void wingl_draw_picture(WinGl *g, WinGlPicture *p, bool fenced, int x, int y, int w, int h, int W, int H)
{
    (void)W;
    if (!p->tex) return;
    if (fenced && p->ready) glWaitSync(p->ready, 0, GL_TIMEOUT_IGNORED);
    /* a copy of the sRGB bytes as they are (GL_FRAMEBUFFER_SRGB off: no
     * decoding or encoding), scaled into the letterbox */
    glDisable(GL_FRAMEBUFFER_SRGB);
    if (g->program_copy) {
        /* texel for texel at the picture's own size, else filtered */
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        glDisable(GL_BLEND);
        glUseProgram(g->program_copy);
        glActiveTexture(GL_TEXTURE0);
        glBindTexture(GL_TEXTURE_2D, p->tex);
        glBindSampler(0, w == p->w && h == p->h ? g->raw_nearest : g->raw_linear);
        glUniform1i(g->u_tex_copy, 0);
        quad(g, x, y, w, h, H);
        glBindSampler(0, 0);
        glBindTexture(GL_TEXTURE_2D, 0);
        glUseProgram(0);
    } else {
        glBindFramebuffer(GL_READ_FRAMEBUFFER, g->fbo_read);
        glFramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, p->tex, 0);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
        if (glCheckFramebufferStatus(GL_READ_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE)
            glBlitFramebuffer(0, 0, p->w, p->h, x, H - y - h, x + w, H - y, GL_COLOR_BUFFER_BIT,
                              w == p->w && h == p->h ? GL_NEAREST : GL_LINEAR);
        glFramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, 0, 0);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
    }
    if (!fenced) return;
    if (p->done) glDeleteSync(p->done);
    p->done = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
    glFlush();
}

void wingl_draw_pixels(WinGl *g, const uint32_t *pixels, int pw, int ph, int x, int y, int w, int h, int W, int H,
                       bool straight)
{
    (void)W;
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, g->pixels_tex);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    if (pw != g->pixels_w || ph != g->pixels_h) {
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, pw, ph, 0, GL_BGRA, GL_UNSIGNED_INT_8_8_8_8_REV, pixels);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        g->pixels_w = pw;
        g->pixels_h = ph;
    } else {
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, pw, ph, GL_BGRA, GL_UNSIGNED_INT_8_8_8_8_REV, pixels);
    }
    if (!straight) {
        /* replacing what is there: a copy, rows turned over (the CPU's
         * top row first), scaled into the rectangle (no shader) */
        glBindTexture(GL_TEXTURE_2D, 0);
        glDisable(GL_FRAMEBUFFER_SRGB);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, g->fbo_read);
        glFramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, g->pixels_tex, 0);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
        if (glCheckFramebufferStatus(GL_READ_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE)
            glBlitFramebuffer(0, 0, pw, ph, x, H - y, x + w, H - y - h, GL_COLOR_BUFFER_BIT,
                              w == pw && h == ph ? GL_NEAREST : GL_LINEAR);
        glFramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, 0, 0);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        return;
    }
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glUseProgram(g->program_pixels);
    glUniform1i(g->u_tex_pixels, 0);
    quad(g, x, y, w, h, H);
    glDisable(GL_BLEND);
    glBindTexture(GL_TEXTURE_2D, 0);
    glUseProgram(0);
}

/* }===== */
