/* window_gl.h: the live window's OpenGL (window_gl.c): how a frame's
 * pictures go from the runtime's render graph to the screen without
 * coming back to the CPU.
 *
 * Two OpenGL 3.3 core contexts that share their objects, made by SDL on
 * the display's thread: the display's, which draws into the windows and
 * presents, and the frame loop's, current on the frame loop's thread, with
 * which the runtimes draw their windows (fl_gl_attach). Each frame the
 * frame loop draws each shown window's picture (fl_gl_window_texture:
 * linear light) into a texture of its picture set as the window shows it
 * (clamped, over black, sRGB-encoded by the GL as it is written) and puts
 * a fence after it; the display waits on that fence in its own context,
 * copies the texture letterboxed into the window (a textured quad that
 * samples the sRGB bytes undecoded, or a blit where the GL cannot skip
 * the decoding), the overlay over it, swaps, and puts a fence of its
 * own, which the frame loop waits on before it writes that texture
 * again. Each side owns its
 * own framebuffers and vertex arrays; textures, programs, samplers and
 * fences are shared.
 *
 * Pictures drawn on the CPU (the physics view's) are uploaded by the
 * display into a texture of its own and drawn the same way.
 */
#ifndef FL_WINDOW_GL_H
#define FL_WINDOW_GL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <SDL.h>

typedef struct WinGl WinGl;

/* Make the two contexts (on the thread that started SDL, before any
 * window): each with a hidden window of its own; the display's is left
 * current on the calling thread.
 *   errors: NULL with the reason in [why] ([cap] bytes) when SDL cannot
 *           make OpenGL 3.3 core contexts that share (the windows then
 *           show pictures through SDL's renderer, read back). */
WinGl *wingl_start(char *why, size_t cap);
/* Free the contexts (display thread, after every window is closed and the
 * frame loop has left its context; NULL is a no-op). */
void wingl_stop(WinGl *g);

/* Whether [g]'s OpenGL is a renderer on the CPU (Mesa's llvmpipe or
 * softpipe): then pictures painted on the CPU are shown through SDL's
 * renderer instead. False for NULL. */
bool wingl_software(const WinGl *g);

/* Take and give back the turn to draw with OpenGL (every call of either
 * side's that draws, copies, swaps or frees GL objects, on either
 * thread). A no-op with a GPU's driver; with Mesa's renderers on the CPU
 * (llvmpipe, softpipe) the two contexts draw one at a time: drawing with
 * both at once was seen to crash inside llvmpipe, and they share the
 * same cores anyway. Not recursive. A NULL [g] is a no-op. */
void wingl_lock(WinGl *g);
void wingl_unlock(WinGl *g);
/* Give the turn back when the calling thread holds it, else nothing: for
 * a thread that will never reach its own wingl_unlock (the display's
 * handler of a lost X connection, window_lost.c). */
void wingl_give_up_turn(WinGl *g);

/* The hidden SDL windows that hold [g]'s two contexts (NULLs for NULL). */
void wingl_windows(const WinGl *g, SDL_Window **display, SDL_Window **frame);

/* {===== the frame loop's side */

/* Make the frame loop's context current on the calling thread (false when
 * SDL refuses: then no picture is drawn through OpenGL). */
bool wingl_frame_enter(WinGl *g);
/* Release it (before drawing with the library's own EGL context, which a
 * thread cannot have current beside a GLX one, and at the end). */
void wingl_frame_leave(WinGl *g);

/* A picture handed from the frame loop to the display: a texture of the
 * shared objects and its fences. Zero it before the first use. */
typedef struct WinGlPicture {
    unsigned tex;            /* SRGB8_ALPHA8: the picture as the window shows it; 0: none */
    int w, h;                /* its size */
    void *ready;             /* the frame loop's fence after its copy (a GLsync), or NULL */
    void *done;              /* the display's fence after drawing it, or NULL */
} WinGlPicture;

/* Draw texture [src] ([w] x [h], the runtime's window picture: linear
 * light, premultiplied) into [p]'s texture as the window shows it
 * (clamped, over black, sRGB-encoded; made or resized as needed, after the
 * display's fence on it) and fence the copy. Frame loop's thread, its
 * context current.
 *   errors: false when the copy cannot be made (an incomplete
 *           framebuffer); [p] then shows nothing. */
bool wingl_frame_copy(WinGl *g, WinGlPicture *p, unsigned src, int w, int h);
/* Delete [p]'s texture and fences (either thread with its context
 * current; the objects are shared). */
void wingl_picture_free(WinGlPicture *p);

/* }===== */

/* {===== the display's side */

/* Make the display's context current with window [w] (display thread). */
bool wingl_use(WinGl *g, SDL_Window *w);
/* The window's drawable size in pixels. */
void wingl_output_size(SDL_Window *w, int *width, int *height);
/* Copy picture [p] into the rectangle x, y, w, h of the window's [W] x
 * [H] pixels (top-left origin; scaled bilinearly when the sizes differ);
 * with [fenced],
 * after waiting on its ready fence, and fencing it for the frame loop
 * after (a picture of a set being shown; a later present of the same
 * texture draws it as it is then, unfenced). */
void wingl_draw_picture(WinGl *g, WinGlPicture *p, bool fenced, int x, int y, int w, int h, int W, int H);
/* Draw [pixels] (pw x ph 0xAARRGGBB, already sRGB) into the rectangle as
 * above, through the display's picture texture: replacing what is there
 * ([straight] false: a premultiplied picture over black), or laid over it
 * by straight alpha ([straight] true: the overlay). */
void wingl_draw_pixels(WinGl *g, const uint32_t *pixels, int pw, int ph, int x, int y, int w, int h, int W, int H,
                       bool straight);
/* Clear the window to black. */
void wingl_clear(int W, int H);

/* }===== */

#endif
