/* window.h: the 2D part of Flitter's window tree, rendered offscreen.
 *
 * Each frame, every top-level `!window` or `!offscreen` node (size=W;H,
 * default 512;512, also used for a size with a side outside 1..16384 or
 * over 64 Mpixels) is drawn: its `!canvas` children are drawn with cairo
 * (canvas.h) into pictures of their own `size` (default: the window's)
 * and composited in order, stretched to the window's size as in Flitter;
 * a `!record filename=F` child composites its own children the same way
 * and writes the picture to F when F is not null, as Flitter's !record
 * does: an animated GIF (one file, a frame appended each time) when F ends
 * in `.gif` (or codec=:gif and F does not end in `.png`), else, for F
 * ending in `.png`, a PNG replaced each time (RGBA with keep_alpha=true,
 * else RGB over black); any other name (video, JPEG, ...) is reported once
 * and not written. `!reference id=X` composites the
 * picture of the earlier sibling node with id=X. As pictures are only ever
 * written by !record, a window with no !record filename in its tree is
 * not drawn at all. A window-level effect node with children (shaders,
 * !bloom, !feedback, ...) composites its children without the effect;
 * other window-level kinds (3D, video, images) are skipped. Each
 * unsupported kind is reported once (on the debug stream).
 */
#ifndef FL_RENDER_WINDOW_H
#define FL_RENDER_WINDOW_H

#include <stdio.h>

#include "canvas.h"
#include "node.h"
#include "value.h"

typedef struct Renderer Renderer;

/* A renderer; [symbols] names symbols in attributes (borrowed, must outlive
 * it); [log] (copied; may be NULL: nowhere) receives write errors and, when
 * log->debug is set, skipped-node messages. */
Renderer *renderer_new(const SymTab *symbols, const RenderLog *log);
/* Render the windows of one frame's tree [root] (a !root node); [fps] sets
 * the frame delay of animated GIFs.
 *   errors: returns the number of files that could not be written (each
 *           reported on the log once), else 0. */
int renderer_frame(Renderer *r, const Node *root, double fps);
/* True when any window was found so far (a script that draws). */
bool renderer_saw_window(const Renderer *r);
/* Finish animated GIFs and free [r] (NULL is a no-op); returns -1 when a
 * GIF could not be finished. */
int renderer_free(Renderer *r);

#endif
