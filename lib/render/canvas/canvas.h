/* canvas.h: drawing a Flitter `!canvas` node tree with cairo.
 *
 * The node set, attributes and units follow Flitter's canvas renderer
 * (jonathanhogg/flitter, src/flitter/render/window/canvas.pyx): coordinates
 * in pixels with the origin top-left and y down; `rotate`, arc `start`,
 * `end` and `sweep` in turns (1 = 360 degrees, positive turns clockwise on
 * screen); colours as 1 (grey), 3 (RGB) or 4 (RGBA) numbers in 0..1 written
 * straight into the sRGB picture (into a linear-light picture for a
 * `linear=true` canvas: CanvasEnv.linear); paint attributes inherited down
 * the tree.
 * The default paint is opaque black, anti-aliased, hairline strokes, miter
 * joins, butt caps; the default font is Helvetica 20 (fontconfig picks a
 * metric-compatible face, e.g. Liberation Sans). Besides the set,
 * `!mask` (clip to the outside of the path, for paths that do not overlap
 * themselves) and `!dash intervals=... [offset=]` (dashed strokes for the
 * siblings after it, as a path effect) are drawn. `!image` draws a
 * picture (a file's, or a window node's by id: CanvasEnv.images) at
 * point= with size=, fill= or fit=; `!pattern` makes one the paint,
 * tiled, placed by translate=, rotate= and scale=; `!blend` mixes the
 * paints of its two children by ratio= or lays the second on the first
 * with mode= (Flitter canvas.pyx, make_image and make_shader).
 */
#ifndef FL_RENDER_CANVAS_H
#define FL_RENDER_CANVAS_H

#include <stdio.h>

#include <stdbool.h>

#include <cairo.h>

#include "node.h"
#include "value.h"

/* Where the renderer's messages go: [fn] (NULL: nowhere) receives one line,
 * without its newline, of [kind] RLOG_ERROR (a file that cannot be written)
 * or RLOG_WARNING (a skipped node kind, sent only when [debug] is set); the
 * kinds have the values of flitter.h's FL_LOG_ERROR and FL_LOG_WARNING. */
enum { RLOG_ERROR = 0, RLOG_WARNING = 1 };
typedef struct RenderLog {
    void (*fn)(void *ctx, int kind, const char *line);
    void *ctx;
    bool debug;
} RenderLog;

/* Send one formatted line of [kind] to [log] (NULL or no fn: nowhere). */
__attribute__((format(printf, 3, 4)))
void render_log(const RenderLog *log, int kind, const char *fmt, ...);

/* Node kinds already reported as skipped, so each is reported once. */
typedef struct SkipLog {
    const RenderLog *log;    /* where "skipped node" messages go (only with
                                log->debug); NULL: nowhere */
    int n;                   /* kinds recorded */
    char kinds[32][24];      /* their names (truncated) */
} SkipLog;

/* Report `[where]: skipping unsupported !KIND` as a warning unless [kind]
 * was reported before (at most 32 kinds are remembered). */
void skiplog_note(SkipLog *log, const char *where, const char *kind);

/* Where a canvas's `!image` and `!pattern` find their pictures (Flitter
 * docs/canvas.md "Images", "Pattern"): [get] returns a new reference to a
 * premultiplied ARGB32 image surface holding the picture of the window
 * node registered as [id] (texture_id=/image_id=; [file] NULL) or of the
 * picture file [file] (filename=; [id] NULL), as the canvas's pixels hold
 * light: sRGB-encoded, or linear light when [linear]; NULL when there is
 * none (it says why on its own log, once). */
typedef struct CanvasImages {
    cairo_surface_t *(*get)(void *ctx, const char *id, const char *file, bool linear);
    /* for a 3D canvas's material textures: the OpenGL texture name of the
     * picture registered as [id] (linear light, premultiplied), or 0 */
    unsigned (*texture)(void *ctx, const char *id);
    void *ctx;
} CanvasImages;

/* What a drawing needs besides the cairo context. */
typedef struct CanvasEnv {
    const SymTab *symbols;   /* names symbol values such as :italic (may be NULL) */
    SkipLog *skips;          /* skipped-kind messages (may be NULL) */
    bool linear;             /* the target holds linear light (`!canvas
                                linear=true`, canvas_is_linear): colours are
                                linear values, rounded to 8 bits as Flitter's
                                8-bit target stores them, and gradient stops
                                are sRGB colours decoded to linear light */
    const CanvasImages *images; /* pictures for !image and !pattern (NULL: none) */
    volatile int *interrupt; /* polled before each node is drawn: once set, the
                                rest of the canvas is left undrawn (NULL: never) */
} CanvasEnv;

/* Whether `!canvas` node [canvas] is drawn in linear light: its `linear`
 * attribute is one true value (Flitter docs/canvas.md `linear=`;
 * render/window/canvas.pyx, Canvas.create: a linear-sRGB Skia surface on
 * an 8-bit non-sRGB texture, whose colours, blending and anti-aliasing
 * are all in linear light, read by the window as linear light). */
bool canvas_is_linear(const Node *canvas);

/* The string conversion of attribute [name] of [n] (LANGUAGE.md §3.13, so
 * symbols give their names) into [b]; false when absent. */
struct Buf;
bool canvas_attr_str(const Node *n, const char *name, const SymTab *st, struct Buf *b);
/* [count] numbers of attribute [name] into [out] (a single number is
 * repeated, as Flitter's Vector.match); false when absent or mismatched. */
bool canvas_attr_nums(const Node *n, const char *name, int count, double *out);

/* Draw [canvas] (a `!canvas` node, or any group-like node) and its
 * descendants onto [cr]; the node's own translate/rotate/scale, paint and
 * font attributes apply to the whole tree, as in Flitter. Nodes outside the
 * canvas node set are skipped, each kind reported once through env->skips.
 * env->interrupt (when not NULL) is polled between shapes and, for a path
 * of more than 10,000 operations, every 10 ms of its fill or stroke.
 * Returns false when that fill or stroke was interrupted and left to
 * finish on a thread of its own: [cr]'s target is then still being
 * written, and must be dropped (cairo_surface_destroy: the thread holds a
 * reference of its own), never read or drawn again.
 *   errors: none; malformed attributes are ignored as Flitter does. */
bool canvas_draw(cairo_t *cr, const Node *canvas, const CanvasEnv *env);

#endif
