/* api_windows.c: the public functions of flitter.h's "Windows: a frame's
 * pictures and input", over the runtime's pictures (pictures.h) and input
 * (input.h): the list of top-level `!window`/`!offscreen` nodes of the
 * last frame in tree order, each window's picture drawn once a frame by
 * the render graph, either read back into the caller's pixels
 * (fl_draw_window) or handed over as a texture of the caller's own OpenGL
 * context (fl_gl_attach, fl_gl_window_texture); the view of the
 * `!physics` systems (render/view/view.c), drawn here or from a snapshot
 * on another thread; and the windows' keys and pointer.
 */
#include "runtime.h"

#include <stdlib.h>
#include <string.h>

#include <cairo.h>

#include "canvas.h"
#include "graph.h"
#include "input.h"
#include "mem.h"
#include "pictures.h"
#include "systems.h"
#include "view.h"

/* last: it turns the library's names into calls through its table */
#include "cairo_lib.h"

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
        rt_fail(rt, "%s: size %dx%d outside 1..16384", fn, width, height);
        return -1;
    }
    if (!pixels) {
        rt_fail(rt, "%s: no pixel buffer", fn);
        return -1;
    }
    if (stride < (size_t)width * 4 || stride % 4 != 0 || stride > (size_t)INT32_MAX) {
        rt_fail(rt, "%s: stride %zu bytes: must be a multiple of 4 and at least width*4 = %zu",
             fn, stride, (size_t)width * 4);
        return -1;
    }
    Buf why = BUF_INIT;
    bool ready = cairo_lib_ready(&why);
    if (!ready) rt_fail(rt, "%s: %s", fn, buf_line(&why));
    buf_free(&why);
    return ready ? 0 : -1;
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
        rt_fail(rt, "fl_draw_window: no window %zu (the last frame has %zu)", index, count);
    } else if (graph_window_size(win, &w, &h), w != width || h != height) {
        rt_fail(rt, "fl_draw_window: window %zu is %dx%d, not %dx%d", index, w, h, width, height);
    } else if (check_buffer(rt, "fl_draw_window", pixels, width, height, stride) == 0) {
        Pictures *p = rt_pictures(rt);
        pictures_show_windows(p);
        rt_render(rt, true);
        rc = 0;
        if (graph_read_window(pictures_graph(p), index, pixels, width, height, stride) != 0) {
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
    Buf err = BUF_INIT;
    int rc = graph_attach(pictures_graph(p), &err);
    if (rc != 0) rt_fail(rt, "fl_gl_attach: %s", buf_line(&err));
    else pictures_show_windows(p);
    buf_free(&err);
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
        pictures_show_windows(p);
        rt_render(rt, true);
        tex = graph_window_texture(pictures_graph(p), index, &w, &h);
        mem_leave(prev);
    }
    if (width) *width = w;
    if (height) *height = h;
    return tex;
}

void fl_set_window_scale(fl_runtime *rt, double scale, int max_samples)
{
    if (!rt) return;
    pictures_set_scale(rt_pictures(rt), scale, max_samples);
}

double fl_window_scale(fl_runtime *rt, int *max_samples)
{
    double scale = 1;
    int samples = 0;
    const Graph *g = rt ? pictures_graph_made(rt_pictures(rt)) : NULL;
    if (g) graph_drawn_scale(g, &scale, &samples);
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
            rt_fail(rt, "fl_draw_view: %s", cairo_status_to_string(cairo_surface_status(s)));
        } else {
            PsSystem *sys;
            size_t n;
            ps_collect(rt_root(rt), rt_state(rt), &sys, &n);
            const RenderLog *log;
            View *view = pictures_view(rt_pictures(rt), &log);
            view_set_style(view, rt_options(rt)->view_axes, log);
            size_t drawn = view_draw_fit(view, s, sys, n);
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
        stride < (size_t)width * 4 || stride % 4 != 0 || stride > (size_t)INT32_MAX || !cairo_lib_ready(NULL))
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

/* {=====================================================================
 * Input: keys and the pointer (input.h)
 * ===================================================================== */

int fl_key(fl_runtime *rt, size_t window, const char *name, bool pressed)
{
    if (!rt) return -1;
    if (!name) return rt_fail(rt, "fl_key: [name] is NULL");
    int code = input_key_code(name, strlen(name));
    if (code < 0) return 0;
    MemHandler prev = rt_enter(rt);
    bool claimed = input_key(rt_input(rt), rt_root(rt), window, code, pressed, rt_state(rt),
                             rt_symbols(rt), rt_beat(rt));
    mem_leave(prev);
    return claimed;
}

void fl_pointer(fl_runtime *rt, size_t window, bool inside, double x, double y)
{
    if (!rt) return;
    MemHandler prev = rt_enter(rt);
    input_pointer(rt_root(rt), window, inside, x, y, rt_state(rt));
    mem_leave(prev);
}

void fl_pointer_button(fl_runtime *rt, size_t window, int button, bool pressed)
{
    if (!rt) return;
    MemHandler prev = rt_enter(rt);
    input_pointer_button(rt_root(rt), window, button, pressed, rt_state(rt));
    mem_leave(prev);
}

/* }===================================================================== */
