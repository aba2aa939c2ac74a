/* window_sdl.c: an SDL window that shows a frame's picture: a streaming
 * ARGB8888 texture the size of the picture (which fl_draw_window fills in
 * place), copied scaled into the largest rectangle of the same aspect
 * ratio centred in the renderer's output (letterbox: black bars), with an
 * optional overlay texture at the output's own resolution on top. The
 * picture is premultiplied; it is copied without blending, which is the
 * picture over black, as !record writes it. Sizes are pixels of the
 * renderer output (SDL_GetRendererOutputSize), which a HiDPI display makes
 * larger than the window's size in points (SDL mouse coordinates). */
#include "window_sdl.h"

#include "window_lost.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* The rectangle of aspect [pw]:[ph] that fills [W] x [H], centred. */
static SDL_Rect fit(int pw, int ph, int W, int H)
{
    SDL_Rect r = {0, 0, W, H};
    if (pw <= 0 || ph <= 0 || W <= 0 || H <= 0) return r;
    if ((double)W / H > (double)pw / ph) {
        r.w = (int)((double)H * pw / ph + 0.5);
        r.x = (W - r.w) / 2;
    } else {
        r.h = (int)((double)W * ph / pw + 0.5);
        r.y = (H - r.h) / 2;
    }
    return r;
}

/* Shrink [w] x [h] by 2/3 steps until it fits 95% of display [screen]. */
static void fit_display(int screen, int *w, int *h)
{
    SDL_Rect b;
    if (SDL_GetDisplayUsableBounds(screen, &b) != 0) return;
    while ((*w > b.w * 0.95 || *h > b.h * 0.95) && *w > 1 && *h > 1) {
        *w = *w * 2 / 3;
        *h = *h * 2 / 3;
    }
}

/* Whether [r] is an OpenGL renderer whose GL is a software rasteriser
 * (Mesa's llvmpipe or softpipe, as under Xvfb without a GPU). False when
 * the user chose a renderer with SDL_RENDER_DRIVER, which is left alone. */
static bool software_gl(SDL_Renderer *r)
{
    if (SDL_GetHint(SDL_HINT_RENDER_DRIVER)) return false;
    SDL_RendererInfo info;
    if (SDL_GetRendererInfo(r, &info) != 0 || strncmp(info.name, "opengl", 6) != 0) return false;
    typedef const unsigned char *(*GetString)(unsigned);
    GetString get = (GetString)(uintptr_t)SDL_GL_GetProcAddress("glGetString");
    if (!get || !SDL_GL_GetCurrentContext()) return false;
    const char *name = (const char *)get(0x1F01 /* GL_RENDERER */);
    return name && (strstr(name, "llvmpipe") || strstr(name, "softpipe") ||
                    strstr(name, "Software Rasterizer"));
}

int winview_start(char *why, size_t cap)
{
    const char *x = getenv("DISPLAY"), *w = getenv("WAYLAND_DISPLAY");
    if (!(x && *x) && !(w && *w)) {   /* (set but empty: none) */
        snprintf(why, cap, "no display (DISPLAY and WAYLAND_DISPLAY are not set or empty)");
        return -1;
    }
    SDL_SetHint(SDL_HINT_NO_SIGNAL_HANDLERS, "1");   /* Ctrl-C and SIGTERM are the caller's */
    SDL_SetHint(SDL_HINT_RENDER_SCALE_QUALITY, "1");
    SDL_SetHint(SDL_HINT_VIDEO_MINIMIZE_ON_FOCUS_LOSS, "0");
    if (SDL_Init(SDL_INIT_VIDEO) != 0) {
        snprintf(why, cap, "cannot open the display: %s", SDL_GetError());
        return -1;
    }
    return 0;
}

/* An OpenGL window: drawn by the display's context of [gl]. */
static int open_gl(WinView *v, bool vsync)
{
    wingl_lock(v->gl);
    bool ok = wingl_use(v->gl, v->window);
    if (ok) {
        SDL_GL_SetSwapInterval(vsync ? 1 : 0);
        int W, H;
        wingl_output_size(v->window, &W, &H);
        wingl_clear(W, H);
        SDL_GL_SwapWindow(v->window);
    }
    wingl_unlock(v->gl);
    return ok ? 0 : -1;
}

int winview_open(WinView *v, const char *title, int w, int h, const WinOptions *o,
                 bool fullscreen, bool vsync, WinGl *gl)
{
    *v = (WinView){0};
    int screen = o->screen >= 0 && o->screen < SDL_GetNumVideoDisplays() ? o->screen : 0;
    int ww = w, wh = h;
    fit_display(screen, &ww, &wh);
    Uint32 flags = SDL_WINDOW_RESIZABLE | SDL_WINDOW_ALLOW_HIGHDPI | (gl ? SDL_WINDOW_OPENGL : 0);
    if (fullscreen) flags |= SDL_WINDOW_FULLSCREEN_DESKTOP;
    v->window = SDL_CreateWindow(title, SDL_WINDOWPOS_CENTERED_DISPLAY(screen),
                                 SDL_WINDOWPOS_CENTERED_DISPLAY(screen), ww, wh, flags);
    if (!v->window) return -1;
    v->id = SDL_GetWindowID(v->window);
    v->want_w = w;
    v->want_h = h;
    v->fullscreen = fullscreen;
    v->vsync = vsync;
    snprintf(v->title, sizeof v->title, "%s", title);
    if (gl) {
        v->gl = gl;
        if (open_gl(v, vsync) != 0) {
            SDL_DestroyWindow(v->window);
            *v = (WinView){0};
            return -1;
        }
        return 0;
    }
    Uint32 rflags = vsync ? SDL_RENDERER_PRESENTVSYNC : 0;
    v->renderer = SDL_CreateRenderer(v->window, -1, SDL_RENDERER_ACCELERATED | rflags);
    if (v->renderer && software_gl(v->renderer)) {
        /* a GL rasterised on the CPU (Xvfb, no GPU): SDL's own software
         * renderer copies the picture instead of texturing a quad with it,
         * which costs far less CPU and leaves the cores to the frame;
         * and its window surface is then plain X11 memory (XShm), not a
         * texture of that same GL, which SDL would otherwise use for it
         * (SDL_HINT_FRAMEBUFFER_ACCELERATION; presenting a frame is then
         * far cheaper: bench/PROFILE.md, "src/window_sdl.c: SDL's
         * software renderer under a CPU GL"; the user's
         * SDL_FRAMEBUFFER_ACCELERATION still wins) */
        SDL_DestroyRenderer(v->renderer);
        v->renderer = NULL;
        SDL_SetHintWithPriority(SDL_HINT_FRAMEBUFFER_ACCELERATION, "0", SDL_HINT_DEFAULT);
    }
    if (!v->renderer) v->renderer = SDL_CreateRenderer(v->window, -1, SDL_RENDERER_SOFTWARE | rflags);
    if (!v->renderer) {
        SDL_DestroyWindow(v->window);
        *v = (WinView){0};
        return -1;
    }
    v->id = SDL_GetWindowID(v->window);
    v->want_w = w;
    v->want_h = h;
    v->fullscreen = fullscreen;
    v->vsync = vsync;
    snprintf(v->title, sizeof v->title, "%s", title);
    SDL_SetRenderDrawColor(v->renderer, 0, 0, 0, 255);
    SDL_RenderClear(v->renderer);
    SDL_RenderPresent(v->renderer);
    return 0;
}

void winview_close(WinView *v)
{
    free(v->px);
    free(v->ov);
    if (v->picture) SDL_DestroyTexture(v->picture);
    if (v->overlay) SDL_DestroyTexture(v->overlay);
    if (v->renderer) SDL_DestroyRenderer(v->renderer);
    wingl_lock(v->gl);   /* (the display's context may be current with it) */
    if (v->window) SDL_DestroyWindow(v->window);
    wingl_unlock(v->gl);
    *v = (WinView){0};
}

void winview_update(WinView *v, const char *title, int w, int h, bool fullscreen, bool vsync)
{
    if (strncmp(title, v->title, sizeof v->title - 1) != 0) {
        snprintf(v->title, sizeof v->title, "%s", title);
        SDL_SetWindowTitle(v->window, v->title);
    }
    if ((int)fullscreen != v->fullscreen) {
        SDL_SetWindowFullscreen(v->window, fullscreen ? SDL_WINDOW_FULLSCREEN_DESKTOP : 0);
        v->fullscreen = fullscreen;
    }
    if ((w != v->want_w || h != v->want_h) && !v->fullscreen) {
        int ww = w, wh = h;
        fit_display(SDL_GetWindowDisplayIndex(v->window), &ww, &wh);
        SDL_SetWindowSize(v->window, ww, wh);
        v->want_w = w;
        v->want_h = h;
    }
    if ((int)vsync != v->vsync) {
        if (v->gl) {
            wingl_lock(v->gl);
            if (wingl_use(v->gl, v->window)) SDL_GL_SetSwapInterval(vsync ? 1 : 0);
            wingl_unlock(v->gl);
        } else {
            SDL_RenderSetVSync(v->renderer, vsync);
        }
        v->vsync = vsync;
    }
}

void winview_output_size(const WinView *v, int *w, int *h)
{
    if (v->gl) wingl_output_size(v->window, w, h);
    else if (SDL_GetRendererOutputSize(v->renderer, w, h) != 0) SDL_GetWindowSize(v->window, w, h);
}

/* Room for [n] words at *[buf] (of *[cap]); false when there is none. */
static bool room(uint32_t **buf, size_t *cap, size_t n)
{
    if (n <= *cap) return true;
    uint32_t *more = realloc(*buf, n * sizeof *more);
    if (!more) return false;
    *buf = more;
    *cap = n;
    return true;
}

void winview_show_texture(WinView *v, WinGlPicture *p)
{
    v->shown = p;
    v->glpic = (WinGlPicture){.tex = p->tex, .w = p->w, .h = p->h};
    v->gl_texture = true;
    v->pic_w = p->w;
    v->pic_h = p->h;
}

/* (Re)make the picture texture at [w] x [h] pixels; -1 on failure. */
static int picture_texture(WinView *v, int w, int h)
{
    if (!v->picture || w != v->pic_w || h != v->pic_h) {
        if (v->picture) SDL_DestroyTexture(v->picture);
        v->picture = SDL_CreateTexture(v->renderer, SDL_PIXELFORMAT_ARGB8888,
                                       SDL_TEXTUREACCESS_STREAMING, w, h);
        v->pic_w = v->picture ? w : 0;
        v->pic_h = v->picture ? h : 0;
        if (!v->picture) return -1;
        SDL_SetTextureBlendMode(v->picture, SDL_BLENDMODE_NONE);
    }
    return 0;
}

int winview_upload(WinView *v, const uint32_t *px, int w, int h)
{
    if (v->gl) {
        if (!room(&v->px, &v->pxcap, (size_t)w * (size_t)h)) return -1;
        memcpy(v->px, px, (size_t)w * (size_t)h * 4);
        v->gl_texture = false;
        v->pic_w = w;
        v->pic_h = h;
        return 0;
    }
    if (picture_texture(v, w, h) != 0) return -1;
    return SDL_UpdateTexture(v->picture, NULL, px, w * 4) == 0 ? 0 : -1;
}

uint32_t *winview_lock(WinView *v, int w, int h, int *pitch)
{
    if (picture_texture(v, w, h) != 0) return NULL;
    void *pixels;
    if (SDL_LockTexture(v->picture, NULL, &pixels, pitch) != 0) return NULL;
    /* the picture may be drawn with the library's own EGL context
     * (!canvas3d): a thread cannot have a GLX and an EGL context current
     * at once (libglvnd refuses with EGL_BAD_ACCESS), so SDL's is released
     * here; SDL's renderer makes it current again when next used */
    if (SDL_GL_GetCurrentContext()) SDL_GL_MakeCurrent(v->window, NULL);
    return pixels;
}

void winview_unlock(WinView *v) { SDL_UnlockTexture(v->picture); }

uint32_t *winview_overlay_lock(WinView *v, int *w, int *h, int *pitch)
{
    winview_output_size(v, w, h);
    if (v->gl) {
        if (*w < 1 || *h < 1 || !room(&v->ov, &v->ovcap, (size_t)*w * (size_t)*h)) return NULL;
        v->ov_w = *w;
        v->ov_h = *h;
        *pitch = *w * 4;
        return v->ov;
    }
    if (!v->overlay || *w != v->ov_w || *h != v->ov_h) {
        if (v->overlay) SDL_DestroyTexture(v->overlay);
        v->overlay = SDL_CreateTexture(v->renderer, SDL_PIXELFORMAT_ARGB8888,
                                       SDL_TEXTUREACCESS_STREAMING, *w, *h);
        v->ov_w = v->overlay ? *w : 0;
        v->ov_h = v->overlay ? *h : 0;
        if (!v->overlay) return NULL;
        SDL_SetTextureBlendMode(v->overlay, SDL_BLENDMODE_BLEND);
    }
    void *pixels;
    if (SDL_LockTexture(v->overlay, NULL, &pixels, pitch) != 0) return NULL;
    return pixels;
}

void winview_overlay_done(WinView *v, bool shown)
{
    if (!v->gl) SDL_UnlockTexture(v->overlay);
    v->has_overlay = shown;
}

/* winview_present for an OpenGL window. */
static void present_gl(WinView *v)
{
    int W, H;
    winview_output_size(v, &W, &H);
    wingl_lock(v->gl);
    if (!wingl_use(v->gl, v->window)) {
        wingl_unlock(v->gl);
        return;
    }
    /* Mesa's software GLX reads the window's size back at the first draw
     * after a swap (the clear), from a request that leaves it
     * uninitialised when another client has destroyed the window (seen:
     * a clear of 6.7 s): the window is asked for first, and with a renderer
     * on the CPU the server is held (XGrabServer) from that question to
     * the end of the clear, so that no destroy can come between */
    bool held = v->lost && wingl_software(v->gl) && winlost_hold_server(v->lost, true);
    if (v->lost && !winlost_window_exists(v->lost, v->window)) {
        if (held) winlost_hold_server(v->lost, false);
        v->gone = true;
        wingl_unlock(v->gl);
        return;
    }
    wingl_clear(W, H);
    if (held) winlost_hold_server(v->lost, false);
    SDL_Rect r = fit(v->pic_w, v->pic_h, W, H);
    if (v->gl_texture) {
        /* the set's own picture, fenced for the frame loop; later presents
         * (exposed, resized) draw the texture as it is then */
        wingl_draw_picture(v->gl, v->shown ? v->shown : &v->glpic, v->shown != NULL, r.x, r.y, r.w, r.h, W, H);
        v->shown = NULL;
    } else if (v->pic_w > 0 && v->px) {
        wingl_draw_pixels(v->gl, v->px, v->pic_w, v->pic_h, r.x, r.y, r.w, r.h, W, H, false);
    }
    if (v->has_overlay && v->ov && v->ov_w == W && v->ov_h == H)
        wingl_draw_pixels(v->gl, v->ov, W, H, 0, 0, W, H, W, H, true);
    SDL_GL_SwapWindow(v->window);
    wingl_unlock(v->gl);
}

void winview_present(WinView *v)
{
    if (v->gl) {
        present_gl(v);
        return;
    }
    int W, H;
    winview_output_size(v, &W, &H);
    SDL_SetRenderDrawColor(v->renderer, 0, 0, 0, 255);
    SDL_RenderClear(v->renderer);
    if (v->picture) {
        SDL_Rect r = fit(v->pic_w, v->pic_h, W, H);
        SDL_RenderCopy(v->renderer, v->picture, NULL, &r);
    }
    if (v->has_overlay && v->overlay && v->ov_w == W && v->ov_h == H)
        SDL_RenderCopy(v->renderer, v->overlay, NULL, NULL);
    SDL_RenderPresent(v->renderer);
}

bool winview_pointer(const WinView *v, int x, int y, double *fx, double *fy)
{
    int W, H;
    SDL_GetWindowSize(v->window, &W, &H);
    SDL_Rect r = fit(v->pic_w ? v->pic_w : W, v->pic_h ? v->pic_h : H, W, H);
    if (r.w <= 0 || r.h <= 0) return false;
    *fx = (double)(x - r.x) / r.w;
    *fy = (double)(y - r.y) / r.h;
    return *fx >= 0 && *fx <= 1 && *fy >= 0 && *fy <= 1;
}
