/* pictures.c: the last frame's windows as a front end sees them (see
 * pictures.h): the list of top-level `!window`/`!offscreen` nodes in tree
 * order, each window's picture drawn into the caller's pixels through a
 * cairo image surface over them (the compositing of render/window.c that
 * `!record` uses, so both give the same pixels), and the view of the
 * `!physics` systems (render/view.c).
 */
#include "runtime.h"

#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include <cairo.h>

#include "canvas.h"
#include "mem.h"
#include "pictures.h"
#include "systems.h"
#include "view.h"
#include "window.h"

/* last: it turns the library's names into calls through its table */
#include "cairo_lib.h"

struct Pictures {
    Renderer *ren;   /* draws windows; never writes !record files */
    View *view;      /* draws the physics view (its 3D renderer kept across frames) */
    RenderLog log;
};

Pictures *pictures_new(const SymTab *symbols, fl_log_fn log, void *ctx)
{
    Pictures *p = mem_calloc(1, sizeof *p);
    /* skipped kinds are worth a warning here: a shown window lacks them */
    p->log = (RenderLog){log, ctx, true};
    p->ren = renderer_new(symbols, &p->log);
    p->view = view_new_fit(symbols);
    return p;
}

void pictures_free(Pictures *p)
{
    if (!p) return;
    renderer_free(p->ren);   /* writes nothing: no GIF to finish */
    view_close(p->view);
    free(p);
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
        if (!window_is_top(c)) continue;
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
        if (!window_is_top(c)) continue;
        if (out && k < cap) {
            fl_window_info *w = &out[k];
            window_size(c, &w->width, &w->height);
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
    } else if (window_size(win, &w, &h), w != width || h != height) {
        fail(rt, "fl_draw_window: window %zu is %dx%d, not %dx%d", index, w, h, width, height);
    } else if (check_buffer(rt, "fl_draw_window", pixels, width, height, stride) == 0) {
        cairo_surface_t *s = wrap(pixels, width, height, stride);
        if (cairo_surface_status(s) != CAIRO_STATUS_SUCCESS) {
            fail(rt, "fl_draw_window: %s", cairo_status_to_string(cairo_surface_status(s)));
        } else {
            rc = renderer_draw_window(rt_pictures(rt)->ren, win, s);
            if (rc != 0) fail(rt, "fl_draw_window: cannot draw into the buffer");
        }
        cairo_surface_destroy(s);
    }
    mem_leave(prev);
    return rc;
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
