/* repl_window.h: the REPL's live window (`:window`): one SDL window
 * (window_sdl.c) showing the session runtime's first !window, or its
 * physics view when the last frame has none. */
#ifndef FL_REPL_WINDOW_H
#define FL_REPL_WINDOW_H

#include <stdbool.h>
#include <stddef.h>

#include "flitter.h"

typedef struct ReplWindow ReplWindow;

/* Open a window titled as the first !window of [rt]'s last frame (its
 * title=, else [name]) at its size=, or the physics view at 512x512 when
 * the frame has none (or there is no frame yet), and show the frame.
 * Should the connection to the X display be lost (xkill, the X server
 * gone: Xlib lets no X call return then), [lost]([ctx]) is called, from
 * inside the window's X call, to save what the session must keep; the
 * process then exits with status 3 (window_lost.h).
 *   errors: NULL with the reason in [why] ([cap] bytes) when there is no
 *           display or the window cannot be opened; nothing is left
 *           started. */
ReplWindow *repl_window_open(fl_runtime *rt, const char *name, void (*lost)(void *ctx), void *ctx,
                             char *why, size_t cap);

/* Handle the window's pending events: closing it or Escape ask for it to
 * close, and so does its destruction by another X client (said on
 * stderr); an exposed or resized window is presented again. Returns false
 * when the window should close (the caller then calls repl_window_close).
 *   source: Flitter render/window/__init__.py (close and Escape end the
 *           window; here they end only the window, not the session). */
bool repl_window_poll(ReplWindow *w);

/* After a frame of [rt]: draw and present its picture (following the
 * !window's title and size) when [force], or when at least 1/60 s passed
 * since the last picture (so a long :step keeps up without costing a
 * picture per frame). */
void repl_window_frame(ReplWindow *w, fl_runtime *rt, bool force);

/* Close the window and stop SDL's video (NULL: nothing). */
void repl_window_close(ReplWindow *w);

#endif
