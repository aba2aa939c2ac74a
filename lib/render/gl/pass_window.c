/* pass_window.c: the passes of `!window`, `!offscreen`, `!record` and
 * `!reference` (Flitter docs/windows.md; render/window/__init__.py
 * Window and Reference, record.py).
 *
 * A window composites its children with the default program into a
 * framebuffer of its colorbits= (16 by default, and the default of every
 * pass in its tree) when windows are shown (graph_show_windows) or it has
 * an id (as Flitter composites its `!offscreen` windows), not otherwise:
 * nothing would read the picture. A record composites its
 * children into an 8-bit sRGB framebuffer and, when filename= is given,
 * writes it: read back once and handed to the recorder (record.h). A
 * reference has the picture of the pass registered under its id. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "graph_internal.h"
#include "mem.h"
#include "pass_program.h"
#include "record.h"
#include "rnode.h"

/* last: they turn the libraries' names into calls through their tables */
#include "cairo_lib.h"
#include "gl_lib.h"

/* {===== !window and !offscreen */

static int window_colorbits(const Node *n)
{
    double c;
    if (!canvas_attr_nums(n, "colorbits", 1, &c)) return 16;
    int bits = (int)floor(c);
    return bits == 8 || bits == 16 || bits == 32 ? bits : 16;
}

static void render_window(Graph *g, Pass *p, const Node *n, const PassCtx *cx, bool visible)
{
    (void)cx;
    ProgramPass *pp = (ProgramPass *)p;
    (void)visible;
    /* shown (a front end may ask for any window's picture, an !offscreen
     * one too), referred to by id, or the first window's picture for
     * --record (graph_frame asks through [retain]) */
    if (g->show || p->has_id || p->retain) {
        ProgramParams pr = {.colorbits = window_colorbits(n), .pass_through = true,
                            .keep_format = rnode_attr(n, "colorbits") != NULL};
        program_render(g, pp, n, cx, &pr);
    } else if (p->target) {
        target_release(g->pool, p->target);
        p->target = NULL;
    }
}

static void update_window(Graph *g, Pass *p, const Node *n, const PassCtx *cx) { render_window(g, p, n, cx, true); }

static void update_offscreen(Graph *g, Pass *p, const Node *n, const PassCtx *cx)
{
    render_window(g, p, n, cx, false);
}

/* The passes in a window's tree take its colorbits= as their default. */
static void enter_window(Graph *g, Pass *p, const Node *n, PassCtx *cx)
{
    (void)g;
    (void)p;
    cx->colorbits = window_colorbits(n);
}

const PassKind pass_window = {.kind = "window", .size = sizeof(ProgramPass), .enter = enter_window,
                              .render = update_window, .release = program_pass_release};
const PassKind pass_offscreen = {.kind = "offscreen", .size = sizeof(ProgramPass), .enter = enter_window,
                                 .render = update_offscreen, .release = program_pass_release};

/* }===== */

/* {===== !record */

/* The attributes of !record that are not encoder options (Flitter
 * record.py, and the generic ones no encoder knows). */
static bool is_record_attr(const char *name)
{
    static const char *const own[] = {"filename", "codec", "pixfmt", "limit", "hidden", "keep_alpha",
                                      "quality", "size", "id", "colorbits", "composite", "blend", "alpha"};
    for (size_t i = 0; i < sizeof own / sizeof *own; i++)
        if (strcmp(name, own[i]) == 0) return true;
    return false;
}

/* Make the folders of [path] that are missing (Flitter: mkdir(parents=True)). */
static void make_folders(const char *path)
{
    char *dir = mem_strdup(path);
    for (char *s = dir + 1; *s; s++) {
        if (*s != '/') continue;
        *s = '\0';
        mkdir(dir, 0777);
        *s = '/';
    }
    free(dir);
}

int record_target(Graph *g, GlTarget *t, const RecordSpec *s, Buf *err)
{
    cairo_surface_t *pic = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, t->w, t->h);
    int rc = -1;
    if (cairo_surface_status(pic) != CAIRO_STATUS_SUCCESS) {
        buf_printf(err, "%s: %s\n", s->path, cairo_status_to_string(cairo_surface_status(pic)));
    } else {
        cairo_surface_flush(pic);
        unsigned char *data = cairo_image_surface_get_data(pic);
        size_t stride = (size_t)cairo_image_surface_get_stride(pic);
        target_read_argb(t, (uint32_t *)(void *)data, stride);
        /* Flitter writes the encoded (premultiplied) light: opaque, or with
         * keep_alpha as straight colour beside its alpha, which cairo
         * takes premultiplied */
        for (int y = 0; y < t->h; y++) {
            uint32_t *row = (uint32_t *)(void *)(data + (size_t)y * stride);
            for (int x = 0; x < t->w; x++) {
                uint32_t q = row[x];
                if (!s->keep_alpha) {
                    row[x] = q | 0xff000000u;
                    continue;
                }
                uint32_t a = q >> 24;
                uint32_t r = (((q >> 16) & 0xff) * a + 127) / 255, gg = (((q >> 8) & 0xff) * a + 127) / 255,
                         b = ((q & 0xff) * a + 127) / 255;
                row[x] = a << 24 | r << 16 | gg << 8 | b;
            }
        }
        cairo_surface_mark_dirty(pic);
        make_folders(s->path);
        RecordClock clock = {g->f ? g->f->fps : 60, g->f ? g->f->time : 0, g->f && g->f->realtime};
        rc = recorder_write(g->rec, s, pic, &clock, err);
    }
    cairo_surface_destroy(pic);
    return rc;
}

/* Write the picture of record pass [p] as its node [n] asks. */
static void write_record(Graph *g, Pass *p, const Node *n)
{
    const SymTab *st = g->env.symbols;
    Buf name = BUF_INIT, path = BUF_INIT, codec = BUF_INIT, pixfmt = BUF_INIT;
    const Vec *fv = rnode_attr(n, "filename");
    if (!fv || !vec_truthy(fv) || !canvas_attr_str(n, "filename", st, &name) || name.len == 0) goto done;
    graph_path(g, buf_cstr(&name), &path);
    RecordSpec s = {.path = buf_cstr(&path), .limit = -1};
    if (canvas_attr_str(n, "codec", st, &codec)) s.codec = buf_cstr(&codec);
    if (canvas_attr_str(n, "pixfmt", st, &pixfmt)) s.pixfmt = buf_cstr(&pixfmt);
    s.keep_alpha = rnode_attr(n, "keep_alpha") && vec_truthy(rnode_attr(n, "keep_alpha"));
    double x;
    if (canvas_attr_nums(n, "limit", 1, &x) && x >= 0) s.limit = x;
    s.quality = canvas_attr_nums(n, "quality", 1, &x) && x >= 1 && x <= 100 ? (int)x : 0;
    /* every other attribute is an encoder option, as text (Flitter) */
    size_t nattrs = rnode_nattrs(n), nopt = 0;
    VideoOption *opts = nattrs ? mem_calloc(nattrs, sizeof *opts) : NULL;
    Buf *vals = nattrs ? mem_calloc(nattrs, sizeof *vals) : NULL;
    for (size_t i = 0; i < nattrs; i++) {
        const char *key = rnode_attr_name(n, i);
        if (is_record_attr(key) || !canvas_attr_str(n, key, st, &vals[nopt])) continue;
        opts[nopt].key = key;
        opts[nopt].value = buf_cstr(&vals[nopt]);
        nopt++;
    }
    s.options = opts;
    s.noptions = nopt;
    Buf err = BUF_INIT;
    int rc = record_target(g, p->target, &s, &err);
    if (rc < 0) graph_write_failed(g, s.path, buf_line(&err));
    else if (rc > 0 && g->env.log.debug) render_log(&g->env.log, RLOG_WARNING, "%s", buf_line(&err));
    buf_free(&err);
    for (size_t i = 0; i < nattrs; i++) buf_free(&vals[i]);
    free(vals);
    free(opts);
done:
    buf_free(&name);
    buf_free(&path);
    buf_free(&codec);
    buf_free(&pixfmt);
}

static void update_record(Graph *g, Pass *p, const Node *n, const PassCtx *cx)
{
    /* a record that writes no file this frame may pass its child's
     * picture through unchanged (its 8-bit sRGB framebuffer matters only
     * to the file) */
    const Vec *fv = rnode_attr(n, "filename");
    bool writes = cx->write && fv && vec_truthy(fv);
    ProgramParams pr = {.srgb = true, .colorbits = 8, .pass_through = true, .keep_format = writes};
    program_render(g, (ProgramPass *)p, n, cx, &pr);
    /* a picture whose drawing an interrupt cut short is not written: a
     * file never holds half a frame as if it were whole */
    bool cut = g->env.interrupt && *g->env.interrupt;
    if (p->target && cx->write && !cut) write_record(g, p, n);
}

const PassKind pass_record = {.kind = "record", .size = sizeof(ProgramPass), .render = update_record,
                              .release = program_pass_release};

/* }===== */

/* {===== !reference */

typedef struct RefPass {
    Pass base;
    Buf to;                  /* the id it refers to */
} RefPass;

static void update_reference(Graph *g, Pass *p, const Node *n, const PassCtx *cx)
{
    (void)cx;
    RefPass *r = (RefPass *)p;
    /* its own id is the one it refers to (Flitter Reference.update): it
     * registers nothing */
    buf_reset(&r->to);
    if (p->has_id) buf_puts(&r->to, buf_cstr(&p->id));
    (void)n;
    if (!r->to.len) {
        graph_note(g, RLOG_WARNING, "window: !reference without an id shows nothing");
        return;
    }
    bool found = false;
    for (size_t i = 0; i < g->nrefs; i++) {
        if (strcmp(g->refs[i].id, buf_cstr(&r->to)) != 0) continue;
        found = true;
        if (g->refs[i].pass->busy)
            graph_note(g, RLOG_WARNING, "window: !reference id=%s is inside the pass it refers to: it shows that "
                       "pass's picture of the frame before", buf_cstr(&r->to));
    }
    if (!found)
        graph_note(g, RLOG_WARNING, "window: !reference id=%s: no window node drawn before it has that id: it "
                   "shows nothing", buf_cstr(&r->to));
}

static GLuint reference_texture(Graph *g, Pass *p, int *w, int *h)
{
    RefPass *r = (RefPass *)p;
    if (!r->to.len) return 0;
    /* a reference to itself, or a loop of references, has no picture */
    if (g->ref_depth > 8) return 0;
    g->ref_depth++;
    GLuint tex = 0;
    for (size_t i = 0; i < g->nrefs; i++)
        if (strcmp(g->refs[i].id, buf_cstr(&r->to)) == 0 && g->refs[i].pass != p) {
            tex = graph_ref_texture(g, buf_cstr(&r->to), w, h);
            break;
        }
    g->ref_depth--;
    return tex;
}

static void release_reference(Graph *g, Pass *p)
{
    (void)g;
    buf_free(&((RefPass *)p)->to);
}

const PassKind pass_reference = {.kind = "reference", .size = sizeof(RefPass), .leaf = true, .refers = true,
                                 .render = update_reference, .texture = reference_texture,
                                 .release = release_reference};

/* }===== */
