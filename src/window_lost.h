/* window_lost.h: a run with live windows that loses its window or its X
 * display ends as Escape ends it: every page's --state saved, its
 * outputs finished, --dump-state and --dump-tree printed, then exit
 * status 3 (EXIT_WINDOW_LOST). Two ways to lose it:
 *   - the window destroyed by another X client (XDestroyWindow: xdotool
 *     windowclose, a window manager's "destroy"): the display sees its
 *     DestroyNotify, the run ends through the frame loop as a closed
 *     window does, with status 3; the X errors that SDL's calls on the
 *     gone window then raise are ignored instead of ending the process;
 *   - the connection lost (xkill, the X server gone): Xlib calls the
 *     display's exit handler on whichever thread noticed, and never lets
 *     that thread return; the run is ended from there (winlost_connection).
 * X11 only: under another video driver (Wayland) nothing is watched.
 * libX11 is not linked: its functions are looked up in the copy SDL
 * loaded (dlopen RTLD_NOLOAD). */
#ifndef FL_WINDOW_LOST_H
#define FL_WINDOW_LOST_H

#include <signal.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stdint.h>

#include <SDL.h>

#include "window_gl.h"

typedef enum LostKind {
    LOST_NONE,
    LOST_DESTROYED,          /* a window destroyed by another X client */
    LOST_CONNECTION,         /* the connection to the X display lost */
} LostKind;

typedef struct WinLost {
    atomic_int kind;              /* LostKind: the first loss */
    atomic_int claimed;           /* 1 once a thread has begun ending the run */
    atomic_uintptr_t finisher;    /* that thread (its pthread_t) */
    atomic_bool frame_running;    /* the frame loop's thread has not ended */
    atomic_uintptr_t frame_thread;
    volatile int *interrupt;      /* the run's: set so that a frame ends early */
    WinGl *gl;                    /* the turn the display's handler gives up */
    void (*finish)(void *ctx);    /* ends the run (saves, dumps) and _exits; never returns */
    void *ctx;
    void *dpy;                    /* the X Display watched, or NULL */
    void *x11;                    /* libX11 (dlopen RTLD_NOLOAD), or NULL */
    void *get_geometry;           /* its XGetGeometry */
    void *sync;                   /* its XSync */
    void *grab, *ungrab, *flush;  /* its XGrabServer, XUngrabServer, XFlush */
} WinLost;

/* Make [w]: nothing lost, nothing watched yet. [finish]([ctx]) ends the
 * run once the frame loop is outside a step and must not return;
 * [interrupt] is set to end a frame early; [gl] may be NULL. */
void winlost_init(WinLost *w, volatile int *interrupt, WinGl *gl, void (*finish)(void *), void *ctx);

/* Watch the X display of SDL window [win] (the display thread, for each
 * window it opens; the first one with an X11 display installs the
 * handlers: that display's exit handler with [w], and, process-wide as
 * Xlib has them, an I/O error handler that returns and a protocol error
 * handler that logs and returns instead of exiting). Ask SDL for the raw
 * X events (SDL_SYSWMEVENT) that carry DestroyNotify. */
void winlost_watch(WinLost *w, SDL_Window *win);

/* Drop the libX11 reference winlost_watch took (after SDL_Quit). */
void winlost_free(WinLost *w);

/* Whether SDL window [win] still exists on the watched display (one
 * round trip; true when nothing is watched). Mesa's software GLX takes a
 * destroyed window's size from a failed request, uninitialised: OpenGL
 * must not draw into one (window_display.c asks before each present). */
bool winlost_window_exists(WinLost *w, SDL_Window *win);

/* Hold the watched display's server for this client alone ([hold]:
 * XGrabServer) or let it go (XUngrabServer, flushed). Returns whether it
 * did (false when nothing is watched). For the few requests from a
 * winlost_window_exists to the draw that reads the window's size back. */
bool winlost_hold_server(WinLost *w, bool hold);

/* Process the watched display's pending errors now, while this module's
 * handler is installed (before SDL_Quit, which restores Xlib's default
 * handler first: the errors of requests on a destroyed window would then
 * end the process with status 1). */
void winlost_sync(WinLost *w);

/* The X window id of SDL window [win] (0 when it has none). */
unsigned long winlost_xid(SDL_Window *win);

/* The X window id that SDL event [ev] says was destroyed (DestroyNotify
 * through SDL_SYSWMEVENT), or 0. */
unsigned long winlost_destroyed(const SDL_Event *ev);

/* Record that a window was destroyed by another client (the first loss
 * only); returns whether this was the first. */
bool winlost_set_destroyed(WinLost *w);

/* The frame loop's thread starts (before anything can be lost). */
void winlost_frame_started(WinLost *w);

/* The frame loop's thread is about to end (it has left every step and
 * makes no more X calls before this): when the connection was lost, end
 * the run here (never returns); else note that it ended. */
void winlost_frame_ending(WinLost *w);

/* What was lost (LOST_NONE while nothing). */
LostKind winlost_kind(WinLost *w);

/* Block SIGPIPE on the calling thread (and the threads it starts after,
 * which inherit the mask: the frame loop's, the GL's), the mask before in
 * *[old]: a connection killed by another client (xkill) then fails a write
 * to X with EPIPE and ends the run through Xlib's I/O error path (exit
 * status 3, state saved) instead of killing the process first. */
void winlost_block_sigpipe(sigset_t *old);

/* Put mask [old] back, a SIGPIPE raised while it was blocked taken first
 * (not delivered then), unless [old] itself blocks SIGPIPE. */
void winlost_unblock_sigpipe(const sigset_t *old);

#endif
