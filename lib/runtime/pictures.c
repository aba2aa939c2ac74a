/* pictures.c: the runtime's render graph (render/gl/graph.h) and the
 * last frame's windows as a front end sees them (see pictures.h): the list
 * of top-level `!window`/`!offscreen` nodes in tree order, each window's
 * picture drawn once a frame by the graph, either read back into the
 * caller's pixels (fl_draw_window) or handed over as a texture of the
 * caller's own OpenGL context (fl_gl_attach, fl_gl_window_texture), and
 * the view of the `!physics` systems (render/view/view.c).
 */
#include "runtime.h"

#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include <cairo.h>

#include "canvas.h"
#include "graph.h"
#include "mem.h"
#include "pictures.h"
#include "program.h"
#include "systems.h"
#include "view.h"

/* last: it turns the library's names into calls through its table */
#include "cairo_lib.h"

struct Pictures {
    fl_runtime *rt;
    Graph *graph;    /* the windows' passes, made by the first frame that draws */
    View *view;      /* draws the physics view (its 3D renderer kept across frames) */
    RenderLog log;
    bool show;       /* windows are shown: each is composited every frame */
    char *record;    /* --record FILE, until the graph is made */
    double scale;    /* fl_set_window_scale's, until the graph is made */
    int max_samples;
    char folder[4096];
};

Pictures *pictures_new(fl_runtime *rt)
{
    Pictures *p = mem_calloc(1, sizeof *p);
    p->rt = rt;
    /* skipped kinds are worth a warning here: a shown window lacks them */
    p->log = (RenderLog){NULL, NULL, true};
    rt_log_target(rt, &p->log.fn, &p->log.ctx);
    p->view = view_new_fit(rt_symbols(rt));
    p->scale = 1;
    return p;
}

static bool sdf_distance(void *ctx, const Vec *fn, const double *xyz, size_t n, double *out)
{
    return rt_call_distances(ctx, fn, xyz, n, out);
}

static uint64_t sdf_function_key(void *ctx, const Vec *fn)
{
    (void)ctx;
    return eval_function_key(fn);
}

/* The graph, made the first time. */
static Graph *graph_of(Pictures *p)
{
    if (!p->graph) {
        const fl_options *o = rt_options(p->rt);
        GraphEnv env = {.symbols = rt_symbols(p->rt), .log = p->log, .budget = rt_budget(p->rt),
                        .interrupt = o->interrupt, .model_cache = o->model_cache,
                        .c3d = {.no_impostors = o->debug.impostors == FL_IMPOSTORS_OFF,
                                .box_impostors = o->debug.impostors == FL_IMPOSTORS_BOX,
                                .occlusion = o->debug.occlusion == FL_OCCLUSION_ALWAYS  ? C3D_OCCLUSION_ALWAYS
                                             : o->debug.occlusion == FL_OCCLUSION_NEVER ? C3D_OCCLUSION_NEVER
                                                                                         : C3D_OCCLUSION_AUTO},
                        .distance = sdf_distance, .function_key = sdf_function_key, .ctx = p->rt};
        p->graph = graph_new(&env);
        graph_show_windows(p->graph, p->show);
        graph_record_first(p->graph, p->record);
        graph_set_scale(p->graph, p->scale, p->max_samples);
    }
    return p->graph;
}

void pictures_free(Pictures *p)
{
    if (!p) return;
    graph_free(p->graph);
    view_close(p->view);
    free(p->record);
    free(p);
}

static const Vec *frame_name(void *ctx, const char *name, size_t len)
{
    return rt_global(ctx, name, len);
}

static double global_num(const fl_runtime *rt, const char *name, double dflt)
{
    const Vec *v = rt_global(rt, name, strlen(name));
    return vec_is_scalar(v) ? vec_scalar(v) : dflt;
}

int pictures_render(fl_runtime *rt, bool windows)
{
    Pictures *p = rt_pictures(rt);
    if (!rt_root(rt)) return 0;
    const char *script = rt_script_path(rt);
    p->folder[0] = '\0';
    if (script) {
        const char *slash = strrchr(script, '/');
        if (slash && (size_t)(slash - script) < sizeof p->folder)
            snprintf(p->folder, sizeof p->folder, "%.*s", (int)(slash - script), script);
        if (slash == script) snprintf(p->folder, sizeof p->folder, "/");
    }
    GraphFrame f = {.frame = fl_frame_count(rt) - 1, .beat = global_num(rt, "beat", 0),
                    .quantum = global_num(rt, "quantum", 4), .tempo = global_num(rt, "tempo", 120),
                    .delta = global_num(rt, "delta", 0), .time = global_num(rt, "time", 0),
                    .fps = fl_target_fps(rt), .performance = global_num(rt, "performance", 1),
                    .realtime = rt_realtime(rt), .script = script, .folder = p->folder, .name = frame_name,
                    .ctx = rt};
    return graph_frame(graph_of(p), rt_root(rt), &f, windows);
}

void pictures_record_first(fl_runtime *rt, const char *path)
{
    Pictures *p = rt_pictures(rt);
    free(p->record);
    p->record = path && *path ? mem_strdup(path) : NULL;
    if (p->graph) graph_record_first(p->graph, p->record);
}

int pictures_finish_records(fl_runtime *rt)
{
    Pictures *p = rt_pictures(rt);
    return p->graph ? graph_finish_records(p->graph) : 0;
}

/* Windows are shown from now on: each is composited every frame. */
static void show_windows(Pictures *p)
{
    if (p->show) return;
    p->show = true;
    if (p->graph) graph_show_windows(p->graph, true);
}

/* Replace [rt]'s fl_error() text with one formatted line. */
__attribute__((format(printf, 2, 3)))
static void fail(fl_runtime *rt, const char *fmt, ...)
{
    Buf *b = rt_error_buf(rt);
    buf_reset(b);
    char line[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    buf_printf(b, "%s\n", line);
}

/* The top-level window [index] of the last frame, or NULL; [*count] (may
 * be NULL) gets the number of windows. */
static const Node *window_at(const fl_runtime *rt, size_t index, size_t *count)
{
    const Node *root = rt_root(rt), *found = NULL;
    size_t k = 0;
    for (uint32_t i = 0; root && i < root->nchildren; i++) {
        const Node *c = root->children[i];
        if (!graph_is_window(c)) continue;
        if (k++ == index) found = c;
    }
    if (count) *count = k;
    return found;
}

/* fullscreen= / vsync= as Flitter's node.get(NAME, 1, bool): one value,
 * its truth; -1 when absent or not a single value. */
static int flag_of(const Node *n, const char *name)
{
    const Vec *v = node_attr(n, name);
    return v && vec_len(v) == 1 ? vec_truthy(v) : -1;
}

/* Copy the title into [out] ([cap] bytes), cut at a UTF-8 character
 * boundary when it does not fit. */
static void copy_title(const Node *win, const SymTab *st, char *out, size_t cap)
{
    Buf t = BUF_INIT;
    out[0] = '\0';
    if (canvas_attr_str(win, "title", st, &t) && t.len) {
        size_t k = t.len < cap - 1 ? t.len : cap - 1;
        if (k < t.len)   /* do not split a character: back off continuation bytes */
            while (k > 0 && ((unsigned char)t.data[k] & 0xC0) == 0x80) k--;
        memcpy(out, t.data, k);
        out[k] = '\0';
    }
    buf_free(&t);
}

size_t fl_windows(fl_runtime *rt, fl_window_info *out, size_t cap)
{
    if (!rt) return 0;
    MemHandler prev = rt_enter(rt);
    const Node *root = rt_root(rt);
    size_t k = 0;
    for (uint32_t i = 0; root && i < root->nchildren; i++) {
        const Node *c = root->children[i];
        if (!graph_is_window(c)) continue;
        if (out && k < cap) {
            fl_window_info *w = &out[k];
            graph_window_size(c, &w->width, &w->height);
            copy_title(c, rt_symbols(rt), w->title, sizeof w->title);
            w->offscreen = node_is(c, "offscreen");
            w->fullscreen = flag_of(c, "fullscreen");
            w->vsync = flag_of(c, "vsync");
        }
        k++;
    }
    mem_leave(prev);
    return k;
}

/* Check a caller's pixel buffer: -1 with fl_error() text when unusable. */
static int check_buffer(fl_runtime *rt, const char *fn, const uint32_t *pixels, int width,
                        int height, size_t stride)
{
    if (width < 1 || height < 1 || width > 16384 || height > 16384) {
        fail(rt, "%s: size %dx%d outside 1..16384", fn, width, height);
        return -1;
    }
    if (!pixels) {
        fail(rt, "%s: no pixel buffer", fn);
        return -1;
    }
    if (stride < (size_t)width * 4 || stride % 4 != 0 || stride > (size_t)INT32_MAX) {
        fail(rt, "%s: stride %zu bytes: must be a multiple of 4 and at least width*4 = %zu",
             fn, stride, (size_t)width * 4);
        return -1;
    }
    char why[300];
    if (!cairo_lib_ready(why, sizeof why)) {
        fail(rt, "%s: %s", fn, why);
        return -1;
    }
    return 0;
}

/* A cairo ARGB32 image surface over the caller's [pixels]. */
static cairo_surface_t *wrap(uint32_t *pixels, int width, int height, size_t stride)
{
    cairo_surface_t *s = cairo_image_surface_create_for_data((unsigned char *)pixels,
                                                             CAIRO_FORMAT_ARGB32, width, height,
                                                             (int)stride);
    if (cairo_surface_status(s) == CAIRO_STATUS_NO_MEMORY) mem_oom();
    return s;
}

int fl_draw_window(fl_runtime *rt, size_t index, uint32_t *pixels, int width, int height,
                   size_t stride)
{
    if (!rt) return -1;
    MemHandler prev = rt_enter(rt);
    buf_reset(rt_error_buf(rt));
    int rc = -1;
    size_t count;
    const Node *win = window_at(rt, index, &count);
    int w, h;
    if (!win) {
        fail(rt, "fl_draw_window: no window %zu (the last frame has %zu)", index, count);
    } else if (graph_window_size(win, &w, &h), w != width || h != height) {
        fail(rt, "fl_draw_window: window %zu is %dx%d, not %dx%d", index, w, h, width, height);
    } else if (check_buffer(rt, "fl_draw_window", pixels, width, height, stride) == 0) {
        Pictures *p = rt_pictures(rt);
        show_windows(p);
        pictures_render(rt, true);
        rc = 0;
        if (graph_read_window(p->graph, index, pixels, width, height, stride) != 0) {
            /* nothing drawn (no OpenGL, or nothing in the window): transparent */
            for (int y = 0; y < height; y++) memset((char *)pixels + (size_t)y * stride, 0, (size_t)width * 4);
        }
    }
    mem_leave(prev);
    return rc;
}

int fl_gl_attach(fl_runtime *rt)
{
    if (!rt) return -1;
    MemHandler prev = rt_enter(rt);
    buf_reset(rt_error_buf(rt));
    Pictures *p = rt_pictures(rt);
    char err[600];
    int rc = graph_attach(graph_of(p), err, sizeof err);
    if (rc != 0) fail(rt, "fl_gl_attach: %s", err);
    else show_windows(p);
    mem_leave(prev);
    return rc;
}

unsigned fl_gl_window_texture(fl_runtime *rt, size_t index, int *width, int *height)
{
    int w = 0, h = 0;
    unsigned tex = 0;
    if (rt) {
        MemHandler prev = rt_enter(rt);
        Pictures *p = rt_pictures(rt);
        show_windows(p);
        pictures_render(rt, true);
        tex = graph_window_texture(graph_of(p), index, &w, &h);
        mem_leave(prev);
    }
    if (width) *width = w;
    if (height) *height = h;
    return tex;
}

void fl_set_window_scale(fl_runtime *rt, double scale, int max_samples)
{
    if (!rt) return;
    Pictures *p = rt_pictures(rt);
    p->scale = scale;   /* (graph_set_scale takes what is out of range as none) */
    p->max_samples = max_samples;
    if (p->graph) graph_set_scale(p->graph, p->scale, p->max_samples);
}

double fl_window_scale(fl_runtime *rt, int *max_samples)
{
    double scale = 1;
    int samples = 0;
    if (rt && rt_pictures(rt)->graph) graph_drawn_scale(rt_pictures(rt)->graph, &scale, &samples);
    if (max_samples) *max_samples = samples;
    return scale;
}

int fl_draw_view(fl_runtime *rt, uint32_t *pixels, int width, int height, size_t stride,
                 size_t *nsystems)
{
    if (nsystems) *nsystems = 0;
    if (!rt) return -1;
    MemHandler prev = rt_enter(rt);
    buf_reset(rt_error_buf(rt));
    int rc = -1;
    if (check_buffer(rt, "fl_draw_view", pixels, width, height, stride) == 0) {
        cairo_surface_t *s = wrap(pixels, width, height, stride);
        if (cairo_surface_status(s) != CAIRO_STATUS_SUCCESS) {
            fail(rt, "fl_draw_view: %s", cairo_status_to_string(cairo_surface_status(s)));
        } else {
            PsSystem *sys;
            size_t n;
            ps_collect(rt_root(rt), rt_state(rt), &sys, &n);
            Pictures *p = rt_pictures(rt);
            view_set_style(p->view, rt_options(rt)->view_axes, &p->log);
            size_t drawn = view_draw_fit(p->view, s, sys, n);
            ps_free(sys, n);
            if (nsystems) *nsystems = drawn;
            rc = 0;
        }
        cairo_surface_destroy(s);
    }
    mem_leave(prev);
    return rc;
}

/* {=====================================================================
 * The view drawn on another thread
 * ===================================================================== */

struct fl_view_snapshot {
    PsFrozen frozen;   /* the systems, owning their numbers and titles */
    int axes[2];       /* the runtime's flat projection (fl_options.view_axes) */
};

struct fl_view_painter {
    View *view;        /* its fitted extents, kept from picture to picture */
};

fl_view_snapshot *fl_view_snapshot_take(fl_runtime *rt, fl_view_snapshot *reuse)
{
    if (!rt) return NULL;
    MemHandler prev = rt_enter(rt);
    buf_reset(rt_error_buf(rt));
    PsSystem *sys;
    size_t n;
    ps_collect(rt_root(rt), rt_state(rt), &sys, &n);
    const int *axes = rt_options(rt)->view_axes;
    fl_view_snapshot *snap = NULL;
    if (!view_draws_3d(axes, sys, n)) {
        snap = reuse ? reuse : mem_calloc(1, sizeof *snap);
        if (ps_freeze(&snap->frozen, sys, n, rt_symbols(rt))) {
            snap->axes[0] = axes[0];
            snap->axes[1] = axes[1];
        } else {
            /* past the memory budget (mem.h): no snapshot, the frame is
             * drawn with fl_draw_view ([reuse] is as it was) */
            if (snap != reuse) free(snap);
            snap = NULL;
        }
    }
    ps_free(sys, n);
    mem_leave(prev);
    return snap;
}

void fl_view_snapshot_free(fl_view_snapshot *snap)
{
    if (!snap) return;
    ps_frozen_free(&snap->frozen);
    free(snap);
}

fl_view_painter *fl_view_painter_new(void)
{
    fl_view_painter *p = mem_calloc(1, sizeof *p);
    p->view = view_new_fit(NULL);   /* titles come written in the snapshot */
    return p;
}

void fl_view_painter_free(fl_view_painter *painter)
{
    if (!painter) return;
    view_close(painter->view);
    free(painter);
}

int fl_view_painter_draw(fl_view_painter *painter, const fl_view_snapshot *snap, uint32_t *pixels,
                         int width, int height, size_t stride, size_t *nsystems)
{
    if (nsystems) *nsystems = 0;
    if (!painter || !snap || !pixels || width < 1 || height < 1 || width > 16384 || height > 16384 ||
        stride < (size_t)width * 4 || stride % 4 != 0 || stride > (size_t)INT32_MAX || !cairo_lib_ready(NULL, 0))
        return -1;
    cairo_surface_t *s = wrap(pixels, width, height, stride);
    int rc = -1;
    if (cairo_surface_status(s) == CAIRO_STATUS_SUCCESS) {
        /* a snapshot has no 3D system (fl_view_snapshot_take): nothing to log */
        view_set_style(painter->view, snap->axes, NULL);
        size_t drawn = view_draw_fit(painter->view, s, snap->frozen.sys, snap->frozen.n);
        if (nsystems) *nsystems = drawn;
        rc = 0;
    }
    cairo_surface_destroy(s);
    return rc;
}

/* }===================================================================== */
