/* window_sdl.h: one SDL window showing a picture, letterboxed, with an
 * overlay on top. */
#ifndef FL_WINDOW_SDL_H
#define FL_WINDOW_SDL_H

#include <stdbool.h>
#include <stdint.h>

#include <SDL.h>

#include "window_gl.h"

/* How windows open (the command line's defaults; a !window's own
 * fullscreen= and vsync= override them). */
typedef struct WinOptions {
    int screen;          /* display index (--screen N), from 0 */
    bool fullscreen;     /* --fullscreen */
    bool vsync;          /* --vsync */
} WinOptions;

struct WinLost;

typedef struct WinView {
    SDL_Window *window;
    struct WinLost *lost;    /* set by the caller after winview_open: asked whether the window
                                still exists before OpenGL draws into it (window_lost.h), or NULL */
    bool gone;               /* a present found the window destroyed (by another X client) */
    WinGl *gl;               /* shown through OpenGL (window_gl.h), or NULL: through [renderer] */
    SDL_Renderer *renderer;
    Uint32 id;               /* SDL_GetWindowID, to route events */
    SDL_Texture *picture;    /* streaming ARGB8888, pic_w x pic_h pixels */
    int pic_w, pic_h;        /* the picture's size in pixels */
    int want_w, want_h;      /* the size the window was last asked for */
    SDL_Texture *overlay;    /* ARGB8888, straight alpha, ov_w x ov_h (output pixels) */
    int ov_w, ov_h;
    bool has_overlay;        /* the overlay texture holds something to show */
    /* with [gl]: the picture to present, a texture of the picture sets
     * (glpic, a copy of its name and size) or CPU pixels (px, pic_w x
     * pic_h), and the overlay's pixels */
    WinGlPicture glpic;
    WinGlPicture *shown;     /* the set's picture to fence at the next present, or NULL */
    bool gl_texture;         /* the picture is glpic (else px, when pic_w > 0) */
    uint32_t *px, *ov;
    size_t pxcap, ovcap;
    int fullscreen;          /* 1 fullscreen now, 0 not */
    int vsync;               /* 1 presenting with vsync, 0 not */
    char title[256];         /* the title shown */
} WinView;

/* Start SDL's video for windows: the hints every front end wants (SDL
 * leaves SIGINT/SIGTERM to the caller, smooth scaling, no minimising on
 * focus loss), then SDL_Init(SDL_INIT_VIDEO); end with SDL_Quit().
 *   errors: -1 with the reason in [why] ([cap] bytes) when neither DISPLAY
 *           nor WAYLAND_DISPLAY is set or SDL cannot open the display
 *           (nothing started); else 0. */
int winview_start(char *why, size_t cap);

/* Open a resizable, HiDPI-aware window [title] for a picture of [w] x [h]
 * pixels on display o->screen (centred; shrunk by 2/3 steps until it fits
 * 95% of the display, as Flitter does), fullscreen (desktop mode) when
 * [fullscreen], presenting with vsync when [vsync]: an OpenGL window
 * drawn with the display's context of [gl] when not NULL, else with an
 * accelerated SDL renderer (else SDL's software one).
 *   errors: -1 with SDL_GetError() text left in SDL, nothing left open;
 *           else 0.
 *   source: Flitter render/window/__init__.py Window.create (sizing,
 *           centring, aspect ratio). */
int winview_open(WinView *v, const char *title, int w, int h, const WinOptions *o,
                 bool fullscreen, bool vsync, WinGl *gl);
/* Close [v]'s window and free its textures (a closed WinView is a no-op). */
void winview_close(WinView *v);

/* Follow a window node's attributes after a frame: [title], the picture
 * size [w] x [h] (the window is resized to it when it changes, like
 * Flitter's), [fullscreen] and [vsync] (1/0). */
void winview_update(WinView *v, const char *title, int w, int h, bool fullscreen, bool vsync);

/* The renderer's output size in pixels (HiDPI: more than the window's
 * size in points). */
void winview_output_size(const WinView *v, int *w, int *h);

/* Lock the picture texture, (re)made at [w] x [h] pixels, for writing:
 * returns its pixels (0xAARRGGBB words) and their row pitch in *[pitch]
 * bytes, or NULL (SDL error) when it cannot be made. SDL's OpenGL
 * context, if any, is no longer current on the calling thread after it,
 * so that the picture can be drawn with another (EGL) context. */
uint32_t *winview_lock(WinView *v, int w, int h, int *pitch);
/* Unlock the picture after winview_lock. */
void winview_unlock(WinView *v);

/* Copy the picture [px] ([w] x [h] 0xAARRGGBB words, rows w*4 bytes
 * apart) into the picture texture, (re)made at that size.
 *   errors: -1 (SDL error) when the texture cannot be made; else 0. */
int winview_upload(WinView *v, const uint32_t *px, int w, int h);
/* Show picture [p] of the picture sets (an OpenGL window): drawn by the
 * next winview_present, which fences it for the frame loop. */
void winview_show_texture(WinView *v, WinGlPicture *p);

/* The overlay texture at the output size, locked for overlay_paint (NULL
 * on failure), and its pitch; then winview_overlay_done(). */
uint32_t *winview_overlay_lock(WinView *v, int *w, int *h, int *pitch);
void winview_overlay_done(WinView *v, bool shown);

/* Show the picture letterboxed (scaled to the output keeping its aspect
 * ratio, black bars), then the overlay when it has one, and present. */
void winview_present(WinView *v);

/* Where the window point [x],[y] (SDL mouse coordinates) falls on the
 * picture: *[fx], *[fy] fractions of its width and height (0..1, top left
 * 0;0); returns false when it falls on the black bars or outside.
 *   source: Flitter's pointer_movement_callback (x/width, y/height), here
 *           of the letterboxed picture rather than the whole window. */
bool winview_pointer(const WinView *v, int x, int y, double *fx, double *fy);

#endif
