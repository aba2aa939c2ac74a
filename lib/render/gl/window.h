/* window.h: the 2D part of Flitter's window tree, rendered offscreen.
 *
 * Each frame, every top-level `!window` or `!offscreen` node (size=W;H,
 * default 512;512, also used for a size with a side outside 1..16384 or
 * over 64 Mpixels) is drawn: its `!canvas` children are drawn with cairo
 * (canvas.h) into pictures of their own `size` (default: the window's)
 * and composited in order, stretched to the window's size as in Flitter;
 * a `!record filename=F` child composites its own children the same way
 * and writes the picture to F when F is not null, as Flitter's !record
 * does (record.h): an animated GIF (a frame appended each time) when F
 * ends in `.gif` (or codec=:gif and F does not end in `.png`), a PNG
 * replaced each time for F ending in `.png` (RGBA with keep_alpha=true,
 * else RGB over black), a video for .mp4, .mov, .m4v, .mkv and .webm
 * (video.h; codec=, pixfmt=, limit= and the encoder's options); any other
 * name (JPEG, ...) is reported and not written. Files are written under a
 * temporary name and renamed into place; animations and videos appear at
 * the end of the run (renderer_free). `!reference id=X` composites the
 * picture of the earlier sibling node with id=X. As pictures are only ever
 * written by !record, a window with no !record filename in its tree is
 * not drawn at all. A `!canvas3d` child is drawn with OpenGL (canvas3d.h)
 * into a picture of its own size and composited in its place like a
 * canvas; when no GL context can be made it is skipped with one warning.
 * A `!canvas linear=true` is drawn in linear light into an 8-bit picture
 * and encoded to sRGB as the window's output is (Flitter canvas.pyx,
 * Canvas.create). A `!transform` node composites its children scaled,
 * rotated and translated about its centre with y up, as Flitter's
 * window-level Transform filter does (shaders.py, glsl/transform.frag).
 * A `!bloom` node (bloom.h) composites its children in linear light,
 * blooms them and composites the result in its place. Any other
 * window-level effect node with children (shaders, !adjust, !feedback,
 * ...) composites its children without the effect; other window-level
 * kinds (video, images) are skipped. Each unsupported kind is reported
 * once as a warning, with or without log->debug (issue 25: a picture
 * missing a part never comes silently).
 */
#ifndef FL_RENDER_WINDOW_H
#define FL_RENDER_WINDOW_H

#include <stdio.h>

#include <cairo.h>

#include "canvas.h"
#include "node.h"
#include "value.h"

typedef struct Renderer Renderer;

/* A renderer; [symbols] names symbols in attributes (borrowed, must outlive
 * it); [log] (copied; may be NULL: nowhere) receives write errors and
 * skipped-node warnings (once per kind). Its GL context, if any, is made
 * by the first !canvas3d it draws and freed by renderer_free. */
Renderer *renderer_new(const SymTab *symbols, const RenderLog *log);
/* Render the windows of one frame's tree [root] (a !root node); [fps] sets
 * the frame delay of animated GIFs.
 *   errors: returns the number of files that could not be written (each
 *           reported on the log once), else 0. */
int renderer_frame(Renderer *r, const Node *root, double fps);
/* Draw window [win] (a top-level !window or !offscreen node) into
 * [target], an ARGB32 cairo image surface of the window's size
 * (window_size): cleared to transparent, then its children composited
 * exactly as renderer_frame composites them for a !record of the window,
 * but no !record file is written (fl_draw_window).
 *   errors: -1 when [target] is not such a surface (nothing drawn), else 0;
 *           skipped kinds are reported once, as by renderer_frame. */
int renderer_draw_window(Renderer *r, const Node *win, cairo_surface_t *target);
/* True for a top-level window node: `!window` or `!offscreen`. */
bool window_is_top(const Node *n);
/* The size of window [win] in pixels: its size=W;H, or 512;512 when absent
 * or out of bounds (each side 1..16384, at most 64 Mpixels). */
void window_size(const Node *win, int *w, int *h);
/* Record the first top-level window of every later frame to [path] as if
 * it had a `!record filename=PATH` child holding all its children (the
 * `flitter run --record FILE` option; default attributes); NULL or ""
 * stops. [path] is copied. */
void renderer_set_record(Renderer *r, const char *path);
/* True when any window was found so far (a script that draws). */
bool renderer_saw_window(const Renderer *r);
/* Finish animated GIFs and videos (each renamed into place) and free [r]
 * (NULL is a no-op); returns -1, with the message on the log, when one
 * could not be finished. */
int renderer_free(Renderer *r);

#endif
