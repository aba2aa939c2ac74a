/* graph.h: the render graph, Flitter's window rendering tree drawn as a
 * chain of OpenGL render passes (Flitter docs/windows.md and
 * docs/shaders.md; render/window/__init__.py for behaviour).
 *
 * Every top-level `!window` and `!offscreen` node, and every window-level
 * node under it, is a pass: `!canvas` (cairo, uploaded), `!canvas3d`,
 * `!image`, `!video`, `!shader` and the built-in filters (`!adjust`,
 * `!bloom`, `!blur`, `!chromakey`, `!edges`, `!feedback`, `!flare`,
 * `!kaleid`, `!noise`, `!transform`, `!vignette`), `!record` and
 * `!reference`. A pass renders its children first and samples their
 * output textures (texture0, texture1, ... in order, leaving out those
 * with `hidden=true`), drawing into a framebuffer of its own `size`
 * (inherited from its parent) from a pool reused across passes and
 * frames. Passes live across frames, matched to the new frame's nodes by
 * kind, `id` and (`!image`, `!video`) file name, so that `last`, feedback
 * and decoded media carry over. `id=` makes a pass's output reachable from
 * a `!reference`, a canvas `!image`/`!pattern` (texture_id, image_id) and
 * a 3D material's textures, anywhere in the graph, from the previous frame
 * when it comes later. A `!record` writes its output to a file: the only
 * place pixels come back to the CPU, besides a canvas drawing another
 * pass's picture and the front end's graph_read_window.
 *
 * Kinds the graph does not draw (and 3D kinds a canvas does not know)
 * are named once each on the log, never dropped silently.
 * A pass that cannot be drawn (a shader that does not compile, a file that
 * does not decode, a framebuffer past the GL limit or the memory budget)
 * gives no output, with one message, and the frame goes on.
 */
#ifndef FL_RENDER_GRAPH_H
#define FL_RENDER_GRAPH_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "buf.h"
#include "canvas.h"
#include "canvas3d.h"
#include "mem.h"
#include "node.h"
#include "value.h"

typedef struct Graph Graph;

/* What the graph needs from its runtime, fixed at graph_new. */
typedef struct GraphEnv {
    const SymTab *symbols;       /* names of symbol values (borrowed, outlives the graph) */
    RenderLog log;               /* errors and once-only warnings */
    MemBudget *budget;           /* charged for framebuffers, textures and decoded media (may be NULL) */
    volatile int *interrupt;     /* polled by long drawing loops (may be NULL) */
    double model_cache;          /* seconds a model unused is kept (--modelcache); 0: Flitter's 300 */
    C3dRoutes c3d;               /* how !canvas3d draws (fl_debug_options) */
    /* `!sdf function=`: distances (negative inside) of function value [fn]
     * at [n] points (xyz: 3n doubles) into [out], a result that is not one
     * number NaN; false once interrupted (geom_model.h). NULL: no model. */
    bool (*distance)(void *ctx, const Vec *fn, const double *xyz, size_t n, double *out);
    /* the same number for two function values exactly when they compute
     * the same (definition and captured values), for the model cache */
    uint64_t (*function_key)(void *ctx, const Vec *fn);
    void *ctx;
} GraphEnv;

/* One frame as the passes see it: Flitter's engine names (the standard
 * uniforms of docs/shaders.md, and names for shader templates), the
 * folder relative file names are taken from, and how videos are timed. */
typedef struct GraphFrame {
    long frame;                  /* the frame's number (graph_frame draws each once) */
    double beat, quantum, tempo, delta, time, fps, performance;
    bool realtime;               /* recording videos on the wall clock (else one frame a frame) */
    const char *script;          /* the script's name, for messages (may be NULL) */
    const char *folder;          /* the script's folder ("" or NULL: the working directory) */
    /* the value of an engine name or define [name] (borrowed), or NULL */
    const Vec *(*name)(void *ctx, const char *name, size_t len);
    void *ctx;
} GraphFrame;

/* A graph with no GL context yet: graph_frame makes the library's own EGL
 * context the first time it has something to draw, unless graph_attach
 * gave it the host's. */
Graph *graph_new(const GraphEnv *env);
/* Draw with the OpenGL context current on the calling thread from now on
 * (a front end's window context), instead of one of the graph's own;
 * everything drawn so far is dropped (its objects belong to the other
 * context). Later calls must come with that context current.
 *   errors: -1 with one line in [err] (no context current, below OpenGL
 *           3.3, no libepoxy); the graph keeps drawing as before. */
int graph_attach(Graph *g, Buf *err);
/* Whether graph_frame composites each top-level window's own picture (as
 * a shown window needs it) even when nothing refers to it; off by default
 * (Flitter composites `!offscreen` and hidden windows only when they have
 * an id). */
void graph_show_windows(Graph *g, bool show);
/* Draw the pictures of shown windows at [scale] (0.01..1) of every
 * pass's size in each dimension, and a `!canvas3d` with at most
 * [max_samples] samples (0: as it asks), from the next frame drawn on:
 * a live window's dynamic resolution. The passes' pixel measures follow
 * (a canvas's drawing is scaled, a blur's radius=, the size a filter
 * works in: the picture is the full one at a lower resolution; a
 * `!shader`'s `size` is its framebuffer's). A frame that writes a file
 * (a `!record` with a filename, graph_record_first) or that is drawn
 * while windows are not shown is drawn at full size and samples. Out of
 * range or NaN: 1. */
void graph_set_scale(Graph *g, double scale, int max_samples);
/* The scale and samples cap the last frame was drawn with. */
void graph_drawn_scale(const Graph *g, double *scale, int *max_samples);
/* Draw the window rendering trees of [root] (a !root node) for frame [f],
 * once per frame number (a second call for the same frame only
 * composites the windows if [windows] asks for them now), writing the
 * records' files: when a `!record` names a file (or graph_record_first
 * is set), when [windows] (the caller wants the windows' pictures), and,
 * while windows are not shown (headless), whenever a tree holds a
 * `!record` at all, as Flitter draws every frame. A frame that nothing
 * asks to draw is not drawn at all (a live window dropping pictures it
 * cannot show); the next frame drawn then gives its passes (!feedback,
 * `delta`) the beats since the last frame drawn as its delta.
 *   errors: returns the number of record files that could not be written
 *           this frame (each file's first failure logged; a frame with
 *           records and no OpenGL counts one), else 0; when no GL context
 *           can be made, logs that once and draws nothing. */
int graph_frame(Graph *g, const Node *root, const GraphFrame *f, bool windows);
/* Record the first top-level window of every later frame to [path] as if
 * it had a `!record filename=PATH` holding all its children (`flitter run
 * --record FILE`); NULL or "" stops. [path] is copied. */
void graph_record_first(Graph *g, const char *path);
/* The GL texture name of top-level window [index]'s picture (in the
 * order of the last frame's tree, counting `!window` and `!offscreen`):
 * linear, premultiplied RGBA of the window's size (*w, *h), in the
 * graph's context. 0 when the window was not composited (not shown, or
 * nothing drawn). Valid until the next graph_frame. */
unsigned graph_window_texture(Graph *g, size_t index, int *w, int *h);
/* Read top-level window [index]'s picture into [px] (w x h pixels the
 * window's size, rows [stride] bytes apart, 0xAARRGGBB: the sRGB encoding
 * of the premultiplied light and its alpha, as a !record stores them;
 * copied over black without blending, what Flitter's window shows).
 *   errors: -1 when the window has no picture this frame (nothing
 *           composited: the caller clears its pixels), else 0. */
int graph_read_window(Graph *g, size_t index, uint32_t *px, int w, int h, size_t stride);
/* Finish the animated GIFs and videos the records opened (each renamed
 * into place; later frames start them again); -1 when one could not be
 * finished (logged), else 0. */
int graph_finish_records(Graph *g);
/* Whether graph_frame, asked for no windows, would draw the frame of
 * [root] (its records write files, or --record's first window is
 * recorded: [record_first]; or, with no windows shown ([show] false), it
 * has a !record at all); false for a NULL [root]. Reads the tree alone,
 * not the graph: a front end whose drawing thread holds the graph asks
 * it on the frame loop's (fl_outputs_draws). */
bool graph_draws_for_files(const Node *root, bool record_first, bool show);
/* True for a top-level window node: `!window` or `!offscreen`. */
bool graph_is_window(const Node *n);
/* The size of window node [win] in pixels: its size=W;H, or 512;512 when
 * absent or out of bounds (each side 1..16384, at most 64 Mpixels). */
void graph_window_size(const Node *win, int *w, int *h);
/* Finish animated GIFs and videos (each renamed into place), free every
 * GL object and the graph (NULL is a no-op); -1 when a file could not be
 * finished (logged), else 0. */
int graph_free(Graph *g);

#endif
