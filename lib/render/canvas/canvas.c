/* canvas.c: the `!canvas` node set drawn with cairo (see canvas.h).
 *
 * Flitter builds paths in the local coordinates of the node that adds to
 * them and applies the transform in effect when a path is filled, stroked
 * or clipped; cairo instead transforms points as they are added. So a path
 * here is a list of operations kept in local coordinates and replayed into
 * cairo at the moment it is drawn. */
#include "canvas.h"

#include <math.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <time.h>

#include "buf.h"
#include "format.h"
#include "mem.h"
#include "rnode.h"
#include "srgb.h"

/* last: it turns the library's names into calls through its table */
#include "cairo_lib.h"

#define TAU 6.283185307179586

/* True the first time [kind] is seen by [log] (remembering it). */
static bool skiplog_first(SkipLog *log, const char *kind)
{
    if (!log) return false;
    for (int i = 0; i < log->n; i++)
        if (strncmp(log->kinds[i], kind, sizeof log->kinds[i] - 1) == 0) return false;
    if (log->n < (int)(sizeof log->kinds / sizeof log->kinds[0])) {
        snprintf(log->kinds[log->n], sizeof log->kinds[0], "%s", kind);
        log->n++;
    }
    return true;
}

void render_log(const RenderLog *log, int kind, const char *fmt, ...)
{
    if (!log || !log->fn) return;
    char line[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    log->fn(log->ctx, kind, line);
}

/* Whether skipped-kind messages are wanted at all. */
static bool skiplog_on(const SkipLog *log)
{
    return log && log->log && log->log->debug;
}

void skiplog_note(SkipLog *log, const char *where, const char *kind)
{
    if (skiplog_on(log) && skiplog_first(log, kind))
        render_log(log->log, RLOG_WARNING, "%s: skipping unsupported !%s", where, kind);
}

bool canvas_attr_nums(const Node *n, const char *name, int count, double *out)
{
    return rnode_nums(n, name, count, out);
}

bool canvas_attr_str(const Node *n, const char *name, const SymTab *st, Buf *b)
{
    const Vec *v = rnode_attr(n, name);
    if (!v) return false;
    buf_reset(b);
    fmt_str(b, v, st);
    return true;
}

static double attr_num(const Node *n, const char *name, double dflt)
{
    double x;
    return canvas_attr_nums(n, name, 1, &x) ? x : dflt;
}

static bool attr_bool(const Node *n, const char *name, bool dflt)
{
    const Vec *v = rnode_attr(n, name);
    return v ? vec_truthy(v) : dflt;
}

bool canvas_is_linear(const Node *canvas)
{
    /* Flitter: node.get('linear', 1, bool, False), one value */
    const Vec *v = rnode_attr(canvas, "linear");
    return v && vec_len(v) == 1 && vec_truthy(v);
}

/* ---- paint and font state (inherited down the tree) ---- */

typedef struct Paint {
    double rgba[4];
    cairo_pattern_t *shader;   /* a gradient replacing the colour, or NULL */
    double width;              /* 0: hairline (one device pixel) */
    cairo_line_join_t join;
    cairo_line_cap_t cap;
    cairo_operator_t op;
    bool antialias;
    const double *dashes;      /* !dash intervals (borrowed from the node), or NULL */
    int ndashes;
    double dash_offset;
} Paint;

typedef struct Font {
    char family[96];
    double size;
    cairo_font_weight_t weight;
    cairo_font_slant_t slant;
} Font;

typedef struct Ctx {
    cairo_t *cr;               /* cairo's inert nil context once a long draw is abandoned */
    const CanvasEnv *env;
    Buf text;                  /* scratch for string attributes */
    size_t nops;               /* operations of the path last replayed onto cr */
    bool abandoned;            /* a long fill or stroke was left to finish alone */
} Ctx;

static void paint_copy(Paint *dst, const Paint *src)
{
    *dst = *src;
    if (dst->shader) cairo_pattern_reference(dst->shader);
}

static void paint_done(Paint *p)
{
    if (p->shader) cairo_pattern_destroy(p->shader);
    p->shader = NULL;
}

/* The colour of [n] (1, 3 or 4 numbers) into [rgba]; false when absent. */
static bool node_color(const Node *n, double rgba[4])
{
    const Vec *v = rnode_attr(n, "color");
    if (!vec_is_num(v)) return false;
    const double *x = vec_cnums(v);
    switch (vec_len(v)) {
    case 1: rgba[0] = rgba[1] = rgba[2] = x[0]; rgba[3] = 1; return true;
    case 3: rgba[0] = x[0]; rgba[1] = x[1]; rgba[2] = x[2]; rgba[3] = 1; return true;
    case 4: memcpy(rgba, x, 4 * sizeof *x); return true;
    default: return false;
    }
}

static double clamp01(double x) { return x > 0 ? (x < 1 ? x : 1) : 0; }

/* Colour [in] as cairo is to be given it on a linear canvas, so that it
 * lands as Flitter's 8-bit linear target stores it: each premultiplied
 * channel rounded to the nearest of 255 steps (the GPU's conversion),
 * where cairo would truncate its 16-bit colour to 8 bits. The alpha
 * becomes A/255 and each channel p/A, p the rounded premultiplied value,
 * so that cairo's premultiplied 16-bit value is 257p, which truncates to
 * p exactly. */
static void linear_rgba(const double in[4], double out[4])
{
    double a = clamp01(in[3]);
    double big_a = round(a * 255);
    out[3] = big_a / 255;
    for (int k = 0; k < 3; k++) {
        double p = round(clamp01(in[k]) * a * 255);
        out[k] = big_a > 0 ? fmin(p / big_a, 1) : 0;
    }
}

/* A gradient stop's colour [rgba] on a linear canvas: Flitter hands Skia
 * stop colours as 8-bit sRGB colours (Color4f.toColor, in canvas.pyx
 * make_shader), which Skia converts to the linear target's space and
 * interpolates there; so each channel is rounded to 8 bits and decoded. */
static void linear_stop(double rgba[4])
{
    for (int k = 0; k < 3; k++) rgba[k] = srgb_decode(round(clamp01(rgba[k]) * 255) / 255);
    rgba[3] = round(clamp01(rgba[3]) * 255) / 255;
}

/* A solid-colour pattern of [rgba] for the canvas of [c]. */
static cairo_pattern_t *color_pattern(const Ctx *c, const double rgba[4])
{
    double v[4];
    if (c->env->linear) linear_rgba(rgba, v);
    else memcpy(v, rgba, sizeof v);
    return cairo_pattern_create_rgba(v[0], v[1], v[2], v[3]);
}

static const struct { const char *name; cairo_operator_t op; } composites[] = {
    {"clear", CAIRO_OPERATOR_CLEAR}, {"source", CAIRO_OPERATOR_SOURCE},
    {"dest", CAIRO_OPERATOR_DEST}, {"over", CAIRO_OPERATOR_OVER},
    {"dest_over", CAIRO_OPERATOR_DEST_OVER}, {"in", CAIRO_OPERATOR_IN},
    {"dest_in", CAIRO_OPERATOR_DEST_IN}, {"out", CAIRO_OPERATOR_OUT},
    {"dest_out", CAIRO_OPERATOR_DEST_OUT}, {"atop", CAIRO_OPERATOR_ATOP},
    {"dest_atop", CAIRO_OPERATOR_DEST_ATOP}, {"xor", CAIRO_OPERATOR_XOR},
    {"add", CAIRO_OPERATOR_ADD}, {"modulate", CAIRO_OPERATOR_MULTIPLY},
    {"screen", CAIRO_OPERATOR_SCREEN}, {"overlay", CAIRO_OPERATOR_OVERLAY},
    {"darken", CAIRO_OPERATOR_DARKEN}, {"lighten", CAIRO_OPERATOR_LIGHTEN},
    {"color_dodge", CAIRO_OPERATOR_COLOR_DODGE}, {"color_burn", CAIRO_OPERATOR_COLOR_BURN},
    {"hard_light", CAIRO_OPERATOR_HARD_LIGHT}, {"soft_light", CAIRO_OPERATOR_SOFT_LIGHT},
    {"difference", CAIRO_OPERATOR_DIFFERENCE}, {"exclusion", CAIRO_OPERATOR_EXCLUSION},
    {"multiply", CAIRO_OPERATOR_MULTIPLY}, {"hue", CAIRO_OPERATOR_HSL_HUE},
    {"saturation", CAIRO_OPERATOR_HSL_SATURATION}, {"color", CAIRO_OPERATOR_HSL_COLOR},
    {"luminosity", CAIRO_OPERATOR_HSL_LUMINOSITY},
};

/* Apply [n]'s paint attributes, in attribute order, to [p]. */
static void update_paint(Ctx *c, const Node *n, Paint *p)
{
    for (size_t i = 0; i < rnode_nattrs(n); i++) {
        const char *key = rnode_attr_name(n, i);
        if (strcmp(key, "color") == 0) {
            if (node_color(n, p->rgba)) paint_done(p);
        } else if (strcmp(key, "stroke_width") == 0) {
            p->width = attr_num(n, key, p->width);
        } else if (strcmp(key, "stroke_join") == 0 && canvas_attr_str(n, key, c->env->symbols, &c->text)) {
            const char *s = buf_cstr(&c->text);
            if (strcmp(s, "miter") == 0) p->join = CAIRO_LINE_JOIN_MITER;
            else if (strcmp(s, "round") == 0) p->join = CAIRO_LINE_JOIN_ROUND;
            else if (strcmp(s, "bevel") == 0) p->join = CAIRO_LINE_JOIN_BEVEL;
        } else if (strcmp(key, "stroke_cap") == 0 && canvas_attr_str(n, key, c->env->symbols, &c->text)) {
            const char *s = buf_cstr(&c->text);
            if (strcmp(s, "butt") == 0) p->cap = CAIRO_LINE_CAP_BUTT;
            else if (strcmp(s, "round") == 0) p->cap = CAIRO_LINE_CAP_ROUND;
            else if (strcmp(s, "square") == 0) p->cap = CAIRO_LINE_CAP_SQUARE;
        } else if (strcmp(key, "composite") == 0 && canvas_attr_str(n, key, c->env->symbols, &c->text)) {
            for (size_t k = 0; k < sizeof composites / sizeof composites[0]; k++)
                if (strcmp(buf_cstr(&c->text), composites[k].name) == 0) p->op = composites[k].op;
        } else if (strcmp(key, "antialias") == 0) {
            p->antialias = attr_bool(n, key, p->antialias);
        }
    }
}

/* macOS faces Flitter's documentation asks for that fontconfig has no
 * metric-compatible substitute for: the generic family of the same kind,
 * so that a monospaced face stays monospaced. */
static const char *font_substitute(const char *family)
{
    static const char *const mono[] = {"Menlo", "Monaco", "SF Mono", "Andale Mono"};
    for (size_t i = 0; i < sizeof mono / sizeof mono[0]; i++)
        if (strcasecmp(family, mono[i]) == 0) return "monospace";
    return family;
}

static void update_font(Ctx *c, const Node *n, Font *f)
{
    const SymTab *st = c->env->symbols;
    if (canvas_attr_str(n, "font_family", st, &c->text))
        snprintf(f->family, sizeof f->family, "%s", font_substitute(buf_cstr(&c->text)));
    if (canvas_attr_str(n, "font_weight", st, &c->text)) {
        const char *s = buf_cstr(&c->text);
        /* cairo's font selection knows two weights: semi-bold and heavier are bold */
        if (strcmp(s, "bold") == 0 || strcmp(s, "semi_bold") == 0 || strcmp(s, "extra_bold") == 0 ||
            strcmp(s, "black") == 0 || strcmp(s, "extra_black") == 0)
            f->weight = CAIRO_FONT_WEIGHT_BOLD;
        else if (strcmp(s, "normal") == 0 || strcmp(s, "medium") == 0 || strcmp(s, "light") == 0 ||
                 strcmp(s, "extra_light") == 0 || strcmp(s, "thin") == 0)
            f->weight = CAIRO_FONT_WEIGHT_NORMAL;
    }
    if (canvas_attr_str(n, "font_slant", st, &c->text)) {
        const char *s = buf_cstr(&c->text);
        if (strcmp(s, "italic") == 0) f->slant = CAIRO_FONT_SLANT_ITALIC;
        else if (strcmp(s, "oblique") == 0) f->slant = CAIRO_FONT_SLANT_OBLIQUE;
        else if (strcmp(s, "upright") == 0) f->slant = CAIRO_FONT_SLANT_NORMAL;
    }
    f->size = attr_num(n, "font_size", f->size);
}

/* translate / rotate (turns) / scale, in attribute order. */
static void update_transform(Ctx *c, const Node *n)
{
    double v[2];
    for (size_t i = 0; i < rnode_nattrs(n); i++) {
        const char *key = rnode_attr_name(n, i);
        if (strcmp(key, "translate") == 0 && canvas_attr_nums(n, key, 2, v))
            cairo_translate(c->cr, v[0], v[1]);
        else if (strcmp(key, "rotate") == 0 && canvas_attr_nums(n, key, 1, v))
            cairo_rotate(c->cr, v[0] * TAU);
        else if (strcmp(key, "scale") == 0 && canvas_attr_nums(n, key, 2, v) && v[0] != 0 && v[1] != 0)
            cairo_scale(c->cr, v[0], v[1]);
    }
}

/* ---- paths in local coordinates ---- */

enum { OP_MOVE, OP_LINE, OP_QUAD, OP_CUBIC, OP_ARC, OP_RECT, OP_RRECT, OP_OVAL, OP_CLOSE };

typedef struct PathOp {
    int op;
    double a[6];
} PathOp;

typedef struct Path {
    PathOp *ops;
    size_t n, cap;
    cairo_fill_rule_t rule;
} Path;

static PathOp *path_add(Ctx *c, Path *p, int op)
{
    (void)c;
    if (p->n == p->cap) {
        p->cap = p->cap ? 2 * p->cap : 16;
        p->ops = realloc(p->ops, p->cap * sizeof *p->ops);
        if (!p->ops) mem_oom();
    }
    PathOp *o = &p->ops[p->n++];
    memset(o, 0, sizeof *o);
    o->op = op;
    return o;
}

static void path_free(Path *p) { free(p->ops); *p = (Path){0}; }

/* Replay [p] as cairo's current path under the transform in effect now:
 * as in Flitter, a path's points are mapped by the transform of the node
 * that fills, strokes or clips it. */
static void path_replay(Ctx *c, const Path *p)
{
    cairo_t *cr = c->cr;
    c->nops = p->n;
    cairo_new_path(cr);
    for (size_t i = 0; i < p->n; i++) {
        const PathOp *o = &p->ops[i];
        const double *a = o->a;
        switch (o->op) {
        case OP_MOVE: cairo_move_to(cr, a[0], a[1]); break;
        case OP_LINE:
            if (cairo_has_current_point(cr)) cairo_line_to(cr, a[0], a[1]);
            else cairo_move_to(cr, a[0], a[1]);
            break;
        case OP_QUAD: {
            double x0 = a[0], y0 = a[1];
            if (cairo_has_current_point(cr)) cairo_get_current_point(cr, &x0, &y0);
            else cairo_move_to(cr, x0, y0);
            cairo_curve_to(cr, x0 + 2.0 / 3.0 * (a[0] - x0), y0 + 2.0 / 3.0 * (a[1] - y0),
                           a[2] + 2.0 / 3.0 * (a[0] - a[2]), a[3] + 2.0 / 3.0 * (a[1] - a[3]),
                           a[2], a[3]);
            break;
        }
        case OP_CUBIC:
            if (!cairo_has_current_point(cr)) cairo_move_to(cr, a[0], a[1]);
            cairo_curve_to(cr, a[0], a[1], a[2], a[3], a[4], a[5]);
            break;
        case OP_ARC: {   /* centre x,y; radii rx,ry; start, sweep (turns); a[6] unused */
            if (a[2] <= 0 || a[3] <= 0) break;
            cairo_save(cr);
            cairo_translate(cr, a[0], a[1]);
            cairo_scale(cr, a[2], a[3]);
            double s = a[4] * TAU, e = (a[4] + a[5]) * TAU;
            if (a[5] >= 0) cairo_arc(cr, 0, 0, 1, s, e);
            else cairo_arc_negative(cr, 0, 0, 1, s, e);
            cairo_restore(cr);
            break;
        }
        case OP_RECT: cairo_rectangle(cr, a[0], a[1], a[2], a[3]); break;
        case OP_RRECT: {   /* x, y, w, h, rx, ry */
            double x = a[0], y = a[1], w = a[2], h = a[3];
            double rx = fmin(fabs(a[4]), fabs(w) / 2), ry = fmin(fabs(a[5]), fabs(h) / 2);
            if (rx <= 0 || ry <= 0) { cairo_rectangle(cr, x, y, w, h); break; }
            cairo_new_sub_path(cr);
            cairo_save(cr);
            const double cx[4] = {x + w - rx, x + w - rx, x + rx, x + rx};
            const double cy[4] = {y + ry, y + h - ry, y + h - ry, y + ry};
            for (int k = 0; k < 4; k++) {
                cairo_save(cr);
                cairo_translate(cr, cx[k], cy[k]);
                cairo_scale(cr, rx, ry);
                cairo_arc(cr, 0, 0, 1, (k - 1) * TAU / 4, k * TAU / 4);
                cairo_restore(cr);
            }
            cairo_restore(cr);
            cairo_close_path(cr);
            break;
        }
        case OP_OVAL:   /* centre x,y; radii */
            if (a[2] <= 0 || a[3] <= 0) break;
            cairo_new_sub_path(cr);
            cairo_save(cr);
            cairo_translate(cr, a[0], a[1]);
            cairo_scale(cr, a[2], a[3]);
            cairo_arc(cr, 0, 0, 1, 0, TAU);
            cairo_restore(cr);
            cairo_close_path(cr);
            break;
        case OP_CLOSE: cairo_close_path(cr); break;
        }
    }
    cairo_set_fill_rule(cr, p->rule);
}

/* The smoothing test of Flitter's !line with 0 < curve < 0.5: the turn
 * (in turns, 0..0.25) between the segments a->b and b->c. */
static double turn_angle(double x0, double y0, double x1, double y1, double x2, double y2)
{
    double xa = x1 - x0, ya = y1 - y0, xb = x2 - x1, yb = y2 - y1;
    double la = sqrt(xa * xa + ya * ya), lb = sqrt(xb * xb + yb * yb);
    if (la == 0 || lb == 0) return 0;
    /* clamped to 0..1 as Flitter does, so a turn sharper than a right
     * angle counts as a quarter turn */
    double d = (xa * xb + ya * yb) / (la * lb);
    if (!(d > 0)) d = 0;
    if (d > 1) d = 1;
    return acos(d) / TAU;
}

/* !line points=x0;y0;x1;y1;... [curve=C] [close=B] (Flitter's line_path):
 * sharp corners when curve <= 0, else quadratic curves through segment
 * midpoints where the corner turns by at most `curve` turns. */
static void line_path(Ctx *c, Path *p, const double *pts, uint32_t n, double curve, bool closed)
{
    if (n == 0) return;
    bool sharp = curve <= 0;
    uint32_t m = n + (closed && !sharp ? 2 : 0);
    double last_x = 0, last_y = 0, last_mx = 0, last_my = 0;
    for (uint32_t i = 0; i < m; i++) {
        double x = pts[i % n * 2], y = pts[i % n * 2 + 1];
        if (i == 0) {
            if (sharp || !closed) {
                PathOp *o = path_add(c, p, OP_MOVE);
                o->a[0] = x; o->a[1] = y;
            }
        } else if (sharp) {
            PathOp *o = path_add(c, p, OP_LINE);
            o->a[0] = x; o->a[1] = y;
        } else {
            double mx = (last_x + x) / 2, my = (last_y + y) / 2;
            if (i == 1) {
                PathOp *o = path_add(c, p, closed ? OP_MOVE : OP_LINE);
                o->a[0] = mx; o->a[1] = my;
            } else if (curve >= 0.5 || turn_angle(last_mx, last_my, last_x, last_y, mx, my) <= curve) {
                PathOp *o = path_add(c, p, OP_QUAD);
                o->a[0] = last_x; o->a[1] = last_y; o->a[2] = mx; o->a[3] = my;
            } else {
                PathOp *o = path_add(c, p, OP_LINE);
                o->a[0] = last_x; o->a[1] = last_y;
                o = path_add(c, p, OP_LINE);
                o->a[0] = mx; o->a[1] = my;
            }
            if (!closed && i == m - 1) {
                PathOp *o = path_add(c, p, OP_LINE);
                o->a[0] = x; o->a[1] = y;
            }
            last_mx = mx;
            last_my = my;
        }
        last_x = x;
        last_y = y;
    }
    if (closed) path_add(c, p, OP_CLOSE);
}

/* ---- drawing ---- */

static void set_source(Ctx *c, const Paint *p)
{
    cairo_t *cr = c->cr;
    double v[4];
    if (p->shader) {
        cairo_set_source(cr, p->shader);
    } else if (c->env->linear) {
        linear_rgba(p->rgba, v);
        cairo_set_source_rgba(cr, v[0], v[1], v[2], v[3]);
    } else {
        cairo_set_source_rgba(cr, p->rgba[0], p->rgba[1], p->rgba[2], p->rgba[3]);
    }
    cairo_set_operator(cr, p->op);
    cairo_set_antialias(cr, p->antialias ? CAIRO_ANTIALIAS_DEFAULT : CAIRO_ANTIALIAS_NONE);
}

/* {===== a long path's fill or stroke, on a thread of its own
 * cairo cannot stop a fill or a stroke once begun, and one of a path of
 * millions of segments takes minutes. A path of more than LONG_PATH
 * operations is filled or stroked on a thread of its own while this one
 * polls the interrupt every 10 ms. Interrupted, this side leaves the call
 * to finish alone: the thread holds its own reference to the context (and
 * through it to the picture), dropped when it is done; this side draws
 * nothing more (Ctx.cr becomes cairo's inert nil context) and canvas_draw
 * says so, so that the picture is dropped, never shown or read while the
 * thread may still write it. The pixels are those of the same call made
 * here. */

enum { LONG_PATH = 10000 };

typedef struct LongDraw {
    pthread_mutex_t mu;
    pthread_cond_t cond;
    cairo_t *cr;               /* the thread's reference */
    bool fill;                 /* fill, else stroke */
    bool done;
    int refs;                  /* sides still holding it (2, then 1, then freed) */
} LongDraw;

static void long_draw_release(LongDraw *d)
{
    pthread_mutex_lock(&d->mu);
    bool last = --d->refs == 0;
    pthread_mutex_unlock(&d->mu);
    if (!last) return;
    cairo_destroy(d->cr);
    pthread_cond_destroy(&d->cond);
    pthread_mutex_destroy(&d->mu);
    free(d);
}

static void *long_draw_main(void *arg)
{
    LongDraw *d = arg;
    if (d->fill) cairo_fill_preserve(d->cr);
    else cairo_stroke_preserve(d->cr);
    pthread_mutex_lock(&d->mu);
    d->done = true;
    pthread_cond_signal(&d->cond);
    pthread_mutex_unlock(&d->mu);
    long_draw_release(d);
    return NULL;
}

/* Start [fill] or stroke of [cr]'s current path on a detached thread: its
 * LongDraw, or NULL (nothing started, nothing held) when no thread could
 * be had. */
static LongDraw *long_draw_start(cairo_t *cr, bool fill)
{
    LongDraw *d = calloc(1, sizeof *d);
    if (!d) return NULL;
    if (pthread_mutex_init(&d->mu, NULL) != 0) goto no_mutex;
    if (pthread_cond_init(&d->cond, NULL) != 0) goto no_cond;
    d->cr = cairo_reference(cr);
    d->fill = fill;
    d->refs = 2;
    pthread_attr_t attr;
    if (pthread_attr_init(&attr) != 0) goto no_thread;
    pthread_t t;
    bool started = pthread_attr_setdetachstate(&attr, PTHREAD_CREATE_DETACHED) == 0 &&
                   pthread_create(&t, &attr, long_draw_main, d) == 0;
    pthread_attr_destroy(&attr);
    if (started) return d;
no_thread:
    cairo_destroy(d->cr);
    pthread_cond_destroy(&d->cond);
no_cond:
    pthread_mutex_destroy(&d->mu);
no_mutex:
    free(d);
    return NULL;
}

/* Fill ([fill]) or stroke c->cr's current path, a long one on a thread of
 * its own (above). */
static void fill_or_stroke(Ctx *c, bool fill)
{
    volatile int *stop = c->env->interrupt;
    LongDraw *d = stop && c->nops > LONG_PATH ? long_draw_start(c->cr, fill) : NULL;
    if (!d) {   /* a short path, or no thread to be had: here */
        if (fill) cairo_fill_preserve(c->cr);
        else cairo_stroke_preserve(c->cr);
        return;
    }
    pthread_mutex_lock(&d->mu);
    while (!d->done && !*stop) {
        struct timespec until;
        clock_gettime(CLOCK_REALTIME, &until);
        until.tv_nsec += 10000000;
        if (until.tv_nsec >= 1000000000) until.tv_sec++, until.tv_nsec -= 1000000000;
        pthread_cond_timedwait(&d->cond, &d->mu, &until);
    }
    bool done = d->done;
    pthread_mutex_unlock(&d->mu);
    long_draw_release(d);
    if (!done) {
        c->abandoned = true;
        c->cr = cairo_create(NULL);   /* (cairo's nil context: every call on it does nothing) */
    }
}

static void do_fill(Ctx *c, const Paint *p)
{
    set_source(c, p);
    fill_or_stroke(c, true);
}

static void do_stroke(Ctx *c, const Paint *p)
{
    cairo_t *cr = c->cr;
    set_source(c, p);
    cairo_set_line_join(cr, p->join);
    cairo_set_line_cap(cr, p->cap);
    cairo_set_miter_limit(cr, 4.0);   /* Skia's default */
    cairo_set_dash(cr, p->dashes, p->ndashes, p->dash_offset);
    if (p->width > 0) {
        cairo_set_line_width(cr, p->width);
    } else {   /* hairline: one device pixel whatever the transform */
        double dx = 1, dy = 0;
        cairo_device_to_user_distance(cr, &dx, &dy);
        cairo_set_line_width(cr, hypot(dx, dy));
    }
    fill_or_stroke(c, false);
}

/* Fill and/or stroke [path] with [n]'s own paint attributes on top of [p]
 * (the !rect/!ellipse/!line fill=/stroke= shorthand). */
static void draw_shape(Ctx *c, const Node *n, const Paint *p, const Path *path, bool fill, bool stroke)
{
    Paint dp;
    paint_copy(&dp, p);
    update_paint(c, n, &dp);
    path_replay(c, path);
    if (fill) do_fill(c, &dp);
    if (stroke) do_stroke(c, &dp);
    cairo_new_path(c->cr);
    paint_done(&dp);
}

static void draw_text(Ctx *c, const Node *n, const Paint *p, const Font *inherited)
{
    if (!canvas_attr_str(n, "text", c->env->symbols, &c->text)) return;
    cairo_t *cr = c->cr;
    Paint tp;
    paint_copy(&tp, p);
    update_paint(c, n, &tp);
    Font f = *inherited;
    update_font(c, n, &f);
    double pt[2] = {0, 0};
    canvas_attr_nums(n, "point", 2, pt);
    bool stroke = attr_bool(n, "stroke", false), fill = attr_bool(n, "fill", !stroke);
    cairo_select_font_face(cr, f.family, f.slant, f.weight);
    cairo_set_font_size(cr, f.size);
    const char *s = buf_cstr(&c->text);
    double x = pt[0], y = pt[1];
    if (attr_bool(n, "center", true)) {   /* centre the ink bounds on the point */
        cairo_text_extents_t e;
        cairo_text_extents(cr, s, &e);
        x -= e.x_bearing + e.width / 2;
        y -= e.y_bearing + e.height / 2;
    }
    cairo_new_path(cr);
    cairo_move_to(cr, x, y);
    cairo_text_path(cr, s);
    if (fill) do_fill(c, &tp);
    if (stroke) do_stroke(c, &tp);
    cairo_new_path(cr);
    paint_done(&tp);
}

/* !gradient start=X;Y end=X;Y | radius=RX;RY [point=X;Y rotate=T], with
 * !stop [offset=F] [color=...] children: a new shader for [p]. */
static bool make_gradient(const Ctx *c, const Node *n, Paint *p)
{
    size_t nstops = 0;
    for (size_t i = 0; i < rnode_nchildren(n); i++)
        if (rnode_is(rnode_child(n, i), "stop")) nstops++;
    if (nstops == 0) return false;
    double start[2], end[2], radius[2];
    cairo_pattern_t *pat;
    if (canvas_attr_nums(n, "start", 2, start) && canvas_attr_nums(n, "end", 2, end)) {
        pat = cairo_pattern_create_linear(start[0], start[1], end[0], end[1]);
    } else if (canvas_attr_nums(n, "radius", 2, radius) && radius[0] != 0 && radius[1] != 0) {
        pat = cairo_pattern_create_radial(0, 0, 0, 0, 0, 1);
        double point[2] = {0, 0};
        canvas_attr_nums(n, "point", 2, point);
        cairo_matrix_t m;   /* pattern space -> user space, then inverted */
        cairo_matrix_init_translate(&m, point[0], point[1]);
        cairo_matrix_rotate(&m, attr_num(n, "rotate", 0) * TAU);
        cairo_matrix_scale(&m, radius[0], radius[1]);
        if (cairo_matrix_invert(&m) == CAIRO_STATUS_SUCCESS) cairo_pattern_set_matrix(pat, &m);
    } else {
        return false;
    }
    size_t k = 0;
    for (size_t i = 0; i < rnode_nchildren(n); i++) {
        const Node *s = rnode_child(n, i);
        if (!rnode_is(s, "stop")) continue;
        double rgba[4];
        memcpy(rgba, p->rgba, sizeof rgba);
        node_color(s, rgba);
        if (c->env->linear) linear_stop(rgba);
        double off = attr_num(s, "offset", nstops > 1 ? (double)k / (double)(nstops - 1) : 0);
        cairo_pattern_add_color_stop_rgba(pat, off, rgba[0], rgba[1], rgba[2], rgba[3]);
        k++;
    }
    paint_done(p);
    p->shader = pat;
    return true;
}

static void draw_node(Ctx *c, const Node *n, Paint *paint, const Font *font, Path *path);
/* ---- pictures: !image, !pattern, !blend ---- */

/* The picture [n] names (filename=, else image_id= or texture_id=), a new
 * reference, or NULL. */
static cairo_surface_t *node_image(Ctx *c, const Node *n)
{
    const CanvasImages *im = c->env->images;
    if (!im || !im->get) return NULL;
    if (canvas_attr_str(n, "filename", c->env->symbols, &c->text) && c->text.len)
        return im->get(im->ctx, NULL, buf_cstr(&c->text), c->env->linear);
    if ((canvas_attr_str(n, "image_id", c->env->symbols, &c->text) ||
         canvas_attr_str(n, "texture_id", c->env->symbols, &c->text)) && c->text.len)
        return im->get(im->ctx, buf_cstr(&c->text), NULL, c->env->linear);
    return NULL;
}

/* !image: the picture from its rectangle [src] onto [dst] (x, y, w, h),
 * with the paint's alpha and blend (Flitter canvas.pyx, _draw "image":
 * fill= crops the picture to the aspect of the rectangle it fills, fit=
 * fits it inside with its aspect kept, else size=, default its own). */
static void draw_image(Ctx *c, const Node *n, const Paint *paint)
{
    cairo_surface_t *img = node_image(c, n);
    if (!img) return;
    double w = cairo_image_surface_get_width(img), h = cairo_image_surface_get_height(img);
    double pt[2] = {0, 0}, v[2], src[4] = {0, 0, w, h}, dst[4];
    canvas_attr_nums(n, "point", 2, pt);
    if (canvas_attr_nums(n, "fill", 2, v) && v[0] > 0 && v[1] > 0) {
        double aspect = v[0] / v[1];
        if (w / h > aspect) src[2] = h * aspect, src[0] = (w - src[2]) / 2;
        else src[3] = w / aspect, src[1] = (h - src[3]) / 2;
        dst[0] = pt[0], dst[1] = pt[1], dst[2] = v[0], dst[3] = v[1];
    } else if (canvas_attr_nums(n, "fit", 2, v) && v[0] > 0 && v[1] > 0) {
        double aspect = w / h;
        if (v[0] / v[1] > aspect) dst[2] = v[1] * aspect, dst[3] = v[1], dst[0] = pt[0] + (v[0] - dst[2]) / 2, dst[1] = pt[1];
        else dst[2] = v[0], dst[3] = v[0] / aspect, dst[0] = pt[0], dst[1] = pt[1] + (v[1] - dst[3]) / 2;
    } else {
        if (!canvas_attr_nums(n, "size", 2, v)) v[0] = w, v[1] = h;
        dst[0] = pt[0], dst[1] = pt[1], dst[2] = v[0], dst[3] = v[1];
    }
    if (dst[2] != 0 && dst[3] != 0 && src[2] > 0 && src[3] > 0 && isfinite(dst[0] + dst[1] + dst[2] + dst[3])) {
        cairo_t *cr = c->cr;
        cairo_save(cr);
        cairo_rectangle(cr, dst[0], dst[1], dst[2], dst[3]);
        cairo_clip(cr);
        cairo_translate(cr, dst[0], dst[1]);
        cairo_scale(cr, dst[2] / src[2], dst[3] / src[3]);
        cairo_set_source_surface(cr, img, -src[0], -src[1]);
        /* Skia's default sampling, as Flitter draws it: nearest */
        cairo_pattern_set_filter(cairo_get_source(cr), CAIRO_FILTER_NEAREST);
        cairo_set_operator(cr, paint->op);
        cairo_paint_with_alpha(cr, clamp01(paint->rgba[3]));
        cairo_restore(cr);
    }
    cairo_surface_destroy(img);
}

/* !pattern: the picture tiled, its local matrix made of translate,
 * rotate (turns) and scale in attribute order, each after the ones
 * before (Skia's postTranslate/postRotate/postScale). */
static cairo_pattern_t *make_pattern(Ctx *c, const Node *n)
{
    cairo_surface_t *img = node_image(c, n);
    if (!img) return NULL;
    cairo_matrix_t local, step;
    cairo_matrix_init_identity(&local);
    double v[2];
    for (size_t i = 0; i < rnode_nattrs(n); i++) {
        const char *key = rnode_attr_name(n, i);
        if (strcmp(key, "translate") == 0 && canvas_attr_nums(n, key, 2, v)) cairo_matrix_init_translate(&step, v[0], v[1]);
        else if (strcmp(key, "rotate") == 0 && canvas_attr_nums(n, key, 1, v)) cairo_matrix_init_rotate(&step, v[0] * TAU);
        else if (strcmp(key, "scale") == 0 && canvas_attr_nums(n, key, 2, v)) cairo_matrix_init_scale(&step, v[0], v[1]);
        else continue;
        cairo_matrix_multiply(&local, &local, &step);   /* [local] first, then [step] */
    }
    cairo_pattern_t *pat = cairo_pattern_create_for_surface(img);
    cairo_surface_destroy(img);
    if (cairo_matrix_invert(&local) == CAIRO_STATUS_SUCCESS) cairo_pattern_set_matrix(pat, &local);
    cairo_pattern_set_extend(pat, CAIRO_EXTEND_REPEAT);
    cairo_pattern_set_filter(pat, CAIRO_FILTER_NEAREST);   /* makeShader's default sampling */
    return pat;
}

/* The paint that shader node [n] (!color, !gradient, !pattern, !blend)
 * makes of [paint], or NULL (a new reference). */
static cairo_pattern_t *child_shader(Ctx *c, const Node *n, const Paint *paint, const Font *font, Path *path)
{
    Paint p;
    paint_copy(&p, paint);
    paint_done(&p);
    draw_node(c, n, &p, font, path);
    cairo_pattern_t *r = p.shader;
    p.shader = NULL;
    paint_done(&p);
    return r;
}

/* !blend: its two children's paints mixed by ratio= (0: the first, 1: the
 * second; Skia's Lerp), or the second laid on the first with mode=; one
 * child's paint alone. The mix is made once over the clip's extent. */
static void make_blend(Ctx *c, const Node *n, Paint *paint, const Font *font, Path *path)
{
    cairo_pattern_t *sh[2] = {NULL, NULL};
    int k = 0;
    for (size_t i = 0; i < rnode_nchildren(n) && k < 2; i++) {
        cairo_pattern_t *s = child_shader(c, rnode_child(n, i), paint, font, path);
        if (s) sh[k++] = s;
    }
    if (k == 1) {
        paint_done(paint);
        paint->shader = sh[0];
        return;
    }
    if (k < 2) return;
    double ratio;
    bool lerp = canvas_attr_nums(n, "ratio", 1, &ratio);
    cairo_operator_t op = CAIRO_OPERATOR_OVER;
    if (!lerp && canvas_attr_str(n, "mode", c->env->symbols, &c->text))
        for (size_t m = 0; m < sizeof composites / sizeof composites[0]; m++)
            if (strcmp(buf_cstr(&c->text), composites[m].name) == 0) op = composites[m].op;
    cairo_t *cr = c->cr;
    cairo_save(cr);
    cairo_push_group(cr);
    cairo_set_source(cr, sh[0]);
    cairo_set_operator(cr, CAIRO_OPERATOR_SOURCE);
    if (lerp) {
        ratio = clamp01(ratio);
        cairo_paint_with_alpha(cr, 1 - ratio);
        cairo_set_source(cr, sh[1]);
        cairo_set_operator(cr, CAIRO_OPERATOR_ADD);
        cairo_paint_with_alpha(cr, ratio);
    } else {
        cairo_paint(cr);
        cairo_set_source(cr, sh[1]);
        cairo_set_operator(cr, op);
        cairo_paint(cr);
    }
    cairo_pattern_t *mixed = cairo_pop_group(cr);
    cairo_restore(cr);
    cairo_pattern_destroy(sh[0]);
    cairo_pattern_destroy(sh[1]);
    paint_done(paint);
    paint->shader = mixed;
}


static void draw_children(Ctx *c, const Node *n, Paint *paint, const Font *font, Path *path)
{
    volatile int *stop = c->env->interrupt;
    for (size_t i = 0; i < rnode_nchildren(n) && !(stop && *stop); i++)
        draw_node(c, rnode_child(n, i), paint, font, path);
}

/* A scope with its own path, paint and font (group, layer, canvas root). */
static void draw_scope(Ctx *c, const Node *n, const Paint *paint, const Font *font)
{
    Path path = {.rule = CAIRO_FILL_RULE_WINDING};
    Buf *t = &c->text;
    if (canvas_attr_str(n, "fill_type", c->env->symbols, t)) {
        if (strcmp(buf_cstr(t), "even_odd") == 0) path.rule = CAIRO_FILL_RULE_EVEN_ODD;
    }
    update_transform(c, n);
    Paint p;
    paint_copy(&p, paint);
    update_paint(c, n, &p);
    Font f = *font;
    update_font(c, n, &f);
    draw_children(c, n, &p, &f, &path);
    paint_done(&p);
    path_free(&path);
}

/* !group: its children in a scope of their own (paint, font, transform restored after). */
static void kind_group(Ctx *c, const Node *n, Paint *paint, const Font *font, Path *path)
{
    (void)path;
    cairo_t *cr = c->cr;
    cairo_save(cr);
    draw_scope(c, n, paint, font);
    cairo_restore(c->cr);
}

/* !transform: its children under translate, rotate, scale (cairo state restored after). */
static void kind_transform(Ctx *c, const Node *n, Paint *paint, const Font *font, Path *path)
{
    cairo_t *cr = c->cr;
    cairo_save(cr);
    update_transform(c, n);
    draw_children(c, n, paint, font, path);
    cairo_restore(c->cr);
}

/* !paint: its children with the paint (colour, stroke width, composite...) changed. */
static void kind_paint(Ctx *c, const Node *n, Paint *paint, const Font *font, Path *path)
{
    Paint p;
    paint_copy(&p, paint);
    update_paint(c, n, &p);
    draw_children(c, n, &p, font, path);
    paint_done(&p);
}

/* !font: its children with the font (family, size, weight, slant) changed. */
static void kind_font(Ctx *c, const Node *n, Paint *paint, const Font *font, Path *path)
{
    Font f = *font;
    update_font(c, n, &f);
    draw_children(c, n, paint, &f, path);
}

/* !path: its children build a path of their own (fill_type=:even_odd or winding). */
static void kind_path(Ctx *c, const Node *n, Paint *paint, const Font *font, Path *path)
{
    (void)path;
    Path p = {.rule = CAIRO_FILL_RULE_WINDING};
    if (canvas_attr_str(n, "fill_type", c->env->symbols, &c->text) &&
        strcmp(buf_cstr(&c->text), "even_odd") == 0)
        p.rule = CAIRO_FILL_RULE_EVEN_ODD;
    draw_children(c, n, paint, font, &p);
    path_free(&p);
}

/* !move_to and !line_to point=X;Y: a step of the current path. */
static void kind_move_or_line_to(Ctx *c, const Node *n, Paint *paint, const Font *font, Path *path)
{
    (void)paint; (void)font;
    const char *kind = rnode_kind(n);
    double v[2];
    PathOp *o;
    if (canvas_attr_nums(n, "point", 2, v)) {
        o = path_add(c, path, kind[0] == 'm' ? OP_MOVE : OP_LINE);
        o->a[0] = v[0]; o->a[1] = v[1];
    }
}

/* !curve_to point= c1= [c2=]: a quadratic or cubic segment of the current path. */
static void kind_curve_to(Ctx *c, const Node *n, Paint *paint, const Font *font, Path *path)
{
    (void)paint; (void)font;
    double v[2];
    PathOp *o;
    double c1[2], c2[2];
    if (canvas_attr_nums(n, "point", 2, v) && canvas_attr_nums(n, "c1", 2, c1)) {
        if (canvas_attr_nums(n, "c2", 2, c2)) {
            o = path_add(c, path, OP_CUBIC);
            o->a[0] = c1[0]; o->a[1] = c1[1]; o->a[2] = c2[0]; o->a[3] = c2[1];
            o->a[4] = v[0]; o->a[5] = v[1];
        } else {
            o = path_add(c, path, OP_QUAD);
            o->a[0] = c1[0]; o->a[1] = c1[1]; o->a[2] = v[0]; o->a[3] = v[1];
        }
    }
}

/* !arc point= radius= start= sweep=|end= [move_to=]: an elliptical arc of the current path (turns). */
static void kind_arc(Ctx *c, const Node *n, Paint *paint, const Font *font, Path *path)
{
    (void)paint; (void)font;
    double r[2];
    PathOp *o;
    double pt[2] = {0, 0}, sweep;
    canvas_attr_nums(n, "point", 2, pt);
    if (!canvas_attr_nums(n, "radius", 2, r)) return;
    double start = attr_num(n, "start", 0);
    if (!canvas_attr_nums(n, "sweep", 1, &sweep)) {
        double end;
        if (!canvas_attr_nums(n, "end", 1, &end)) return;
        sweep = end - start;
    }
    if (attr_bool(n, "move_to", false)) {
        /* start a new contour at the arc's first point */
        o = path_add(c, path, OP_MOVE);
        o->a[0] = pt[0] + r[0] * cos(start * TAU);
        o->a[1] = pt[1] + r[1] * sin(start * TAU);
    }
    o = path_add(c, path, OP_ARC);
    o->a[0] = pt[0]; o->a[1] = pt[1]; o->a[2] = r[0]; o->a[3] = r[1];
    o->a[4] = start; o->a[5] = sweep;
}

/* !rect, !ellipse and !line: added to the current path, or drawn at once when fill= or stroke=. */
static void kind_shape(Ctx *c, const Node *n, Paint *paint, const Font *font, Path *path)
{
    (void)font;
    const char *kind = rnode_kind(n);
    double v[2], r[2];
    PathOp *o;
    Path own = {.rule = path->rule};
    bool fill = attr_bool(n, "fill", false), stroke = attr_bool(n, "stroke", false);
    Path *target = (fill || stroke) ? &own : path;
    double pt[2] = {0, 0};
    canvas_attr_nums(n, "point", 2, pt);
    if (kind[0] == 'r') {
        if (!canvas_attr_nums(n, "size", 2, v)) return;
        r[0] = r[1] = 0;
        canvas_attr_nums(n, "radius", 2, r);
        o = path_add(c, target, (r[0] != 0 || r[1] != 0) ? OP_RRECT : OP_RECT);
        o->a[0] = pt[0]; o->a[1] = pt[1]; o->a[2] = v[0]; o->a[3] = v[1];
        o->a[4] = r[0]; o->a[5] = r[1];
    } else if (kind[0] == 'e') {
        if (!canvas_attr_nums(n, "radius", 2, r)) return;
        o = path_add(c, target, OP_OVAL);
        o->a[0] = pt[0]; o->a[1] = pt[1]; o->a[2] = r[0]; o->a[3] = r[1];
    } else {
        const Vec *pts = rnode_attr(n, "points");
        if (!vec_is_num(pts)) return;
        line_path(c, target, vec_cnums(pts), vec_len(pts) / 2, attr_num(n, "curve", 0),
                  attr_bool(n, "close", false));
    }
    if (fill || stroke) draw_shape(c, n, paint, &own, fill, stroke);
    path_free(&own);
}

/* !close: closes the current contour. */
static void kind_close(Ctx *c, const Node *n, Paint *paint, const Font *font, Path *path)
{
    (void)n; (void)paint; (void)font;
    path_add(c, path, OP_CLOSE);
}

/* !fill and !stroke: draw the current path. */
static void kind_fill_or_stroke(Ctx *c, const Node *n, Paint *paint, const Font *font, Path *path)
{
    (void)font;
    const char *kind = rnode_kind(n);
    draw_shape(c, n, paint, path, kind[0] == 'f', kind[0] == 's');
}

/* !clip: clip to the current path; !mask: clip to its outside. */
static void kind_clip_or_mask(Ctx *c, const Node *n, Paint *paint, const Font *font, Path *path)
{
    (void)n; (void)font;
    cairo_t *cr = c->cr;
    const char *kind = rnode_kind(n);
    path_replay(c, path);
    if (kind[0] == 'm') {   /* clip to the outside of the path: the path XOR the whole picture */
        cairo_matrix_t m;
        cairo_get_matrix(cr, &m);
        cairo_identity_matrix(cr);
        double x0, y0, x1, y1;
        cairo_clip_extents(cr, &x0, &y0, &x1, &y1);
        cairo_rectangle(cr, x0 - 1, y0 - 1, x1 - x0 + 2, y1 - y0 + 2);
        cairo_set_matrix(cr, &m);
        cairo_set_fill_rule(cr, CAIRO_FILL_RULE_EVEN_ODD);
    }
    cairo_set_antialias(cr, paint->antialias ? CAIRO_ANTIALIAS_DEFAULT : CAIRO_ANTIALIAS_NONE);
    cairo_clip(cr);
}

/* !dash intervals= offset=: a dash pattern for the strokes after it. */
static void kind_dash(Ctx *c, const Node *n, Paint *paint, const Font *font, Path *path)
{
    (void)c; (void)font; (void)path;
    /* a path effect for the strokes after it: intervals=ON;OFF;... offset=D */
    const Vec *iv = rnode_attr(n, "intervals");
    bool ok = vec_is_num(iv) && vec_len(iv) > 0 && vec_len(iv) < 1024;
    double sum = 0;
    for (uint32_t k = 0; ok && k < vec_len(iv); k++) {
        double d = vec_cnums(iv)[k];
        ok = d >= 0 && isfinite(d);
        sum += d;
    }
    if (ok && sum > 0) {
        paint->dashes = vec_cnums(iv);
        paint->ndashes = (int)vec_len(iv);
        paint->dash_offset = attr_num(n, "offset", 0);
        if (!isfinite(paint->dash_offset)) paint->dash_offset = 0;
    }
}

/* !text: a line of text in the current font. */
static void kind_text(Ctx *c, const Node *n, Paint *paint, const Font *font, Path *path)
{
    (void)path;
    draw_text(c, n, paint, font);
}

/* !layer size= origin= alpha=: its children drawn into a group, composited with alpha. */
static void kind_layer(Ctx *c, const Node *n, Paint *paint, const Font *font, Path *path)
{
    (void)path;
    cairo_t *cr = c->cr;
    double v[2];
    if (!canvas_attr_nums(n, "size", 2, v)) return;
    double origin[2] = {0, 0};
    canvas_attr_nums(n, "origin", 2, origin);
    double alpha = attr_num(n, "alpha", 1);
    /* as in Flitter, the layer's clip outlives the layer */
    cairo_rectangle(cr, origin[0], origin[1], v[0], v[1]);
    cairo_clip(cr);
    cairo_push_group(cr);
    draw_scope(c, n, paint, font);
    cairo_pop_group_to_source(cr);
    cairo_set_operator(cr, CAIRO_OPERATOR_OVER);
    cairo_paint_with_alpha(cr, alpha);
}

/* !gradient: a linear or radial gradient as the paint. */
static void kind_gradient(Ctx *c, const Node *n, Paint *paint, const Font *font, Path *path)
{
    (void)font; (void)path;
    make_gradient(c, n, paint);
}

/* !image: a picture file or a window's picture drawn into a rectangle. */
static void kind_image(Ctx *c, const Node *n, Paint *paint, const Font *font, Path *path)
{
    (void)font; (void)path;
    draw_image(c, n, paint);
}

/* !pattern: a repeated picture as the paint. */
static void kind_pattern(Ctx *c, const Node *n, Paint *paint, const Font *font, Path *path)
{
    (void)font; (void)path;
    cairo_pattern_t *pat = make_pattern(c, n);
    if (pat) {
        paint_done(paint);
        paint->shader = pat;
    }
}

/* !blend: its children blended by a cairo operator. */
static void kind_blend(Ctx *c, const Node *n, Paint *paint, const Font *font, Path *path)
{
    make_blend(c, n, paint, font, path);
}

/* !color color=: a flat colour as the paint. */
static void kind_color(Ctx *c, const Node *n, Paint *paint, const Font *font, Path *path)
{
    (void)font; (void)path;
    double rgba[4];
    memcpy(rgba, paint->rgba, sizeof rgba);
    node_color(n, rgba);
    paint_done(paint);
    paint->shader = color_pattern(c, rgba);
}

/* The canvas node kinds and their drawers, sorted by kind for bsearch. */
typedef void (*NodeDrawer)(Ctx *c, const Node *n, Paint *paint, const Font *font, Path *path);
static const struct NodeKind {
    const char *kind;
    NodeDrawer draw;
} node_kinds[] = {
    {"arc", kind_arc},
    {"blend", kind_blend},
    {"clip", kind_clip_or_mask},
    {"close", kind_close},
    {"color", kind_color},
    {"curve_to", kind_curve_to},
    {"dash", kind_dash},
    {"ellipse", kind_shape},
    {"fill", kind_fill_or_stroke},
    {"font", kind_font},
    {"gradient", kind_gradient},
    {"group", kind_group},
    {"image", kind_image},
    {"layer", kind_layer},
    {"line", kind_shape},
    {"line_to", kind_move_or_line_to},
    {"mask", kind_clip_or_mask},
    {"move_to", kind_move_or_line_to},
    {"paint", kind_paint},
    {"path", kind_path},
    {"pattern", kind_pattern},
    {"rect", kind_shape},
    {"stroke", kind_fill_or_stroke},
    {"text", kind_text},
    {"transform", kind_transform},
};

static int node_kind_cmp(const void *key, const void *entry)
{
    return strcmp(key, ((const struct NodeKind *)entry)->kind);
}

/* Draw [n] by its kind (c->cr after children: a long draw abandoned
 * replaces it); a kind that is not a canvas node's is noted as skipped. */
static void draw_node(Ctx *c, const Node *n, Paint *paint, const Font *font, Path *path)
{
    const char *kind = rnode_kind(n);
    const struct NodeKind *k =
        bsearch(kind, node_kinds, sizeof node_kinds / sizeof node_kinds[0], sizeof node_kinds[0], node_kind_cmp);
    if (k) k->draw(c, n, paint, font, path);
    else skiplog_note(c->env->skips, "canvas", kind);
}

bool canvas_draw(cairo_t *cr, const Node *canvas, const CanvasEnv *env)
{
    Ctx c = {.cr = cr, .env = env, .text = BUF_INIT};
    Paint p = {.rgba = {0, 0, 0, 1}, .width = 0, .join = CAIRO_LINE_JOIN_MITER,
               .cap = CAIRO_LINE_CAP_BUTT, .op = CAIRO_OPERATOR_OVER, .antialias = true};
    Font f = {.family = "Helvetica", .size = 20, .weight = CAIRO_FONT_WEIGHT_NORMAL,
              .slant = CAIRO_FONT_SLANT_NORMAL};
    cairo_save(cr);
    draw_scope(&c, canvas, &p, &f);
    cairo_restore(c.cr);
    buf_free(&c.text);
    return !c.abandoned;
}
