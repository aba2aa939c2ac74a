/* graph.c: the render graph's tree of passes, its references and its
 * frame (see graph.h; the passes' shared parts in graph_internal.h).
 *
 * A frame walks each top-level window node as Flitter's WindowNode.update
 * does (render/window/__init__.py): the pass of a node registers its id,
 * takes its size, matches its child nodes to the passes it had (first one
 * of the same kind, tags and id, and for a file the same file), updates
 * them in order, draws, then lets each child give back its framebuffer
 * unless it must keep it. Passes no longer matched are freed. */
#include "graph.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "format.h"
#include "graph_internal.h"
#include "media.h"
#include "mem.h"
#include "pass_program.h"
#include "record.h"
#include "rnode.h"
#include "srgb.h"

/* last: they turn the libraries' names into calls through their tables */
#include "cairo_lib.h"
#include "gl_lib.h"

/* Seconds a pooled framebuffer may wait unused, and how often the pool
 * is trimmed (Flitter window render: RenderTarget.empty_pool(glctx, 15)). */
#define POOL_AGE 15.0
#define POOL_TRIM_EVERY 1.0

Graph *graph_new(const GraphEnv *env)
{
    Graph *g = mem_calloc(1, sizeof *g);
    g->env = *env;
    /* a kind that is not drawn is always worth one warning: a picture
     * missing a part must never come silently */
    g->skiplog = g->env.log;
    g->skiplog.debug = true;
    g->skips.log = &g->skiplog;
    g->rec = recorder_new();
    g->frame = -1;
    g->scale = g->draw_scale = 1;
    return g;
}

void graph_note(Graph *g, int kind, const char *fmt, ...)
{
    char line[800];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    for (int i = 0; i < g->nnoted; i++)
        if (strcmp(g->noted[i], line) == 0) return;
    if (g->nnoted < 64) g->noted[g->nnoted++] = mem_strdup(line);
    else if (g->nnoted++ == 64) render_log(&g->env.log, RLOG_WARNING, "(further render messages are not logged)");
    if (g->nnoted <= 64) render_log(&g->env.log, kind, "%s", line);
}

void graph_write_failed(Graph *g, const char *path, const char *line)
{
    g->write_failures++;
    for (int i = 0; i < g->nreported; i++)
        if (strcmp(g->reported[i], path) == 0) return;
    if (g->nreported == 64) return;
    g->reported[g->nreported++] = mem_strdup(path);
    render_log(&g->env.log, RLOG_ERROR, "%s%s", line,
               g->nreported == 64 ? " (errors of further !record files are not logged)" : "");
}

void graph_path(Graph *g, const char *name, Buf *out)
{
    buf_reset(out);
    const char *folder = g->f ? g->f->folder : NULL;
    if (name[0] != '/' && folder && folder[0]) {
        buf_puts(out, folder);
        if (out->len && out->data[out->len - 1] != '/') buf_putc(out, '/');
    }
    buf_puts(out, name);
}

/* {===== GL objects of the graph */

/* Make the context current, creating it and the graph's objects the first
 * time; false when there is none (said once). */
static bool begin(Graph *g)
{
    if (g->failed) return false;
    if (!g->gl) {
        Buf why = BUF_INIT;
        g->gl = gl_context_new(&why);
        if (!g->gl) {
            g->failed = true;
            render_log(&g->env.log, RLOG_WARNING, "window: no OpenGL (%s): windows are not drawn", buf_line(&why));
        }
        buf_free(&why);
        if (!g->gl) return false;
    } else if (!gl_context_use(g->gl)) {
        graph_note(g, RLOG_ERROR, "window: the OpenGL context cannot be made current");
        return false;
    }
    if (!g->pool) {
        g->pool = target_pool_new(g->gl, g->env.budget);
        g->programs = programs_new();
        static const float quad[8] = {-1, 1, -1, -1, 1, 1, 1, -1};
        glGenVertexArrays(1, &g->quad_vao);
        glBindVertexArray(g->quad_vao);
        glGenBuffers(1, &g->quad_vbo);
        glBindBuffer(GL_ARRAY_BUFFER, g->quad_vbo);
        glBufferData(GL_ARRAY_BUFFER, sizeof quad, quad, GL_STATIC_DRAW);
        glEnableVertexAttribArray(0);
        glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, NULL);
        glBindVertexArray(0);
        glBindBuffer(GL_ARRAY_BUFFER, 0);
        static const unsigned char zero[4] = {0, 0, 0, 0};
        glGenTextures(1, &g->zero_tex);
        glBindTexture(GL_TEXTURE_2D, g->zero_tex);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 1, 1, 0, GL_RGBA, GL_UNSIGNED_BYTE, zero);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glBindTexture(GL_TEXTURE_2D, 0);
        glGenSamplers(1, &g->nearest);
        glSamplerParameteri(g->nearest, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glSamplerParameteri(g->nearest, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glSamplerParameteri(g->nearest, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glSamplerParameteri(g->nearest, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    }
    return true;
}

static void end(Graph *g) { gl_context_done(g->gl); }

void graph_draw_quad(Graph *g)
{
    glBindVertexArray(g->quad_vao);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    glBindVertexArray(0);
}

GlTarget *graph_target(Graph *g, int w, int h, int colorbits, bool srgb, bool depth, int samples)
{
    Buf err = BUF_INIT;
    GlTarget *t = target_get(g->pool, w, h, colorbits, srgb, depth, samples, &err);
    if (!t) graph_note(g, RLOG_ERROR, "window: %s", buf_line(&err));
    buf_free(&err);
    return t;
}

/* }===== */

/* {===== passes and references */

static const PassKind *const child_kinds[] = {&pass_record, &pass_reference, &pass_shader, &pass_canvas,
                                               &pass_canvas3d, &pass_image, &pass_video};

/* The pass kind that draws window-level node [n], or NULL. */
static const PassKind *kind_of(const Node *n)
{
    const char *k = rnode_kind(n);
    for (size_t i = 0; i < sizeof child_kinds / sizeof *child_kinds; i++)
        if (strcmp(child_kinds[i]->kind, k) == 0) return child_kinds[i];
    for (size_t i = 0; i < pass_nfilters; i++)
        if (strcmp(pass_filters[i].kind, k) == 0) return &pass_filters[i];
    return NULL;
}

static uint64_t tags_hash(const Node *n)
{
    uint64_t h = HASH_START;
    for (uint32_t i = 0; i < n->ntags; i++) h = hash_update(h, fnv1a_utf8(n->tags[i]->bytes, n->tags[i]->len));
    return h;
}

static void unregister(Graph *g, Pass *p)
{
    for (size_t i = 0; i < g->nrefs;) {
        if (g->refs[i].pass == p) {
            free(g->refs[i].id);
            g->refs[i] = g->refs[--g->nrefs];
        } else {
            i++;
        }
    }
}

void graph_register(Graph *g, const char *id, Pass *p, int camera)
{
    for (size_t i = 0; i < g->nrefs; i++)
        if (strcmp(g->refs[i].id, id) == 0) {
            g->refs[i].pass = p;
            g->refs[i].camera = camera;
            return;
        }
    if (g->nrefs == g->caprefs) {
        g->caprefs = g->caprefs ? 2 * g->caprefs : 16;
        g->refs = mem_realloc_array(g->refs, g->caprefs, sizeof *g->refs);
    }
    g->refs[g->nrefs++] = (Ref){mem_strdup(id), p, camera};
}

static void destroy(Graph *g, Pass *p)
{
    for (size_t i = 0; i < p->nchildren; i++) destroy(g, p->children[i]);
    free(p->children);
    if (p->kind->release) p->kind->release(g, p);
    target_release(g->pool, p->target);
    unregister(g, p);
    buf_free(&p->id);
    free(p);
}

static Pass *new_pass(const PassKind *kind)
{
    Pass *p = mem_calloc(1, kind->size);
    p->kind = kind;
    p->id = (Buf)BUF_INIT;
    return p;
}

GLuint graph_pass_texture(Graph *g, Pass *p, int *w, int *h)
{
    if (p->kind->texture) return p->kind->texture(g, p, w, h);
    if (!p->target) return 0;
    *w = p->target->w;
    *h = p->target->h;
    return p->target->tex;
}

GLuint graph_ref_texture(Graph *g, const char *id, int *w, int *h)
{
    for (size_t i = 0; i < g->nrefs; i++) {
        const Ref *r = &g->refs[i];
        if (strcmp(r->id, id) != 0) continue;
        if (r->camera >= 0) return pass_canvas3d_camera(g, r->pass, r->camera, w, h);
        return graph_pass_texture(g, r->pass, w, h);
    }
    return 0;
}

/* The size of [n]: size=W;H (Flitter node.get('size', 2, int)), else
 * [w] x [h]. */
static void size_of(const Node *n, int *w, int *h)
{
    double s[2];
    if (canvas_attr_nums(n, "size", 2, s) && s[0] >= 1 && s[1] >= 1 && s[0] < 1e9 && s[1] < 1e9) {
        *w = (int)s[0];
        *h = (int)s[1];
    }
}

static void update(Graph *g, Pass *p, const Node *n, const PassCtx *parent);

static bool graph_is_window_pass(const Pass *p) { return p->kind == &pass_window || p->kind == &pass_offscreen; }

/* After [p] drew: each child gives its framebuffer back to the pool
 * unless it must keep it (its kind says, or an id, or a `last`). */
static void finish_children(Graph *g, Pass *p)
{
    for (size_t i = 0; i < p->nchildren; i++) {
        Pass *c = p->children[i];
        if (c->kind->finished) {
            c->kind->finished(g, c);
        } else if (!c->retain && c->target) {
            target_release(g->pool, c->target);
            c->target = NULL;
        }
    }
}

/* Match the children of node [n] to [p]'s passes and update them. */
static void descend(Graph *g, Pass *p, const Node *n, const PassCtx *cx)
{
    size_t had = p->nchildren;
    Pass **old = p->children;
    for (size_t i = 0; i < had; i++) old[i]->seen = false;
    Pass **now = rnode_nchildren(n) ? mem_calloc(rnode_nchildren(n), sizeof *now) : NULL;
    size_t k = 0;
    for (size_t i = 0; i < rnode_nchildren(n); i++) {
        if (g->env.interrupt && *g->env.interrupt) break;
        const Node *c = rnode_child(n, i);
        const PassKind *kind = kind_of(c);
        if (!kind) {
            if (!rnode_is(c, "key") && !rnode_is(c, "pointer"))   /* input, read by lib/runtime/input.c */
                skiplog_note(&g->skips, "window", rnode_kind(c));
            continue;
        }
        Buf id = BUF_INIT;
        const Vec *idv = rnode_attr(c, "id");
        if (idv) fmt_str(&id, idv, g->env.symbols);
        uint64_t tags = tags_hash(c);
        Pass *q = NULL;
        for (size_t j = 0; j < had && !q; j++) {
            Pass *o = old[j];
            if (o->seen || o->kind != kind || o->tags != tags || o->has_id != (idv != NULL) ||
                (idv && strcmp(buf_cstr(&o->id), buf_cstr(&id)) != 0))
                continue;
            if (kind->similar && !kind->similar(o, c, g)) continue;
            q = o;
        }
        buf_free(&id);
        if (!q) q = new_pass(kind);
        q->seen = true;
        q->tags = tags;
        update(g, q, c, cx);
        now[k++] = q;
    }
    for (size_t j = 0; j < had; j++)
        if (!old[j]->seen) destroy(g, old[j]);
    free(old);
    p->children = now;
    p->nchildren = k;
}

static void update(Graph *g, Pass *p, const Node *n, const PassCtx *parent)
{
    const Vec *idv = rnode_attr(n, "id");
    buf_reset(&p->id);
    p->has_id = idv != NULL;
    if (idv) {
        fmt_str(&p->id, idv, g->env.symbols);
        if (!p->kind->refers) graph_register(g, buf_cstr(&p->id), p, -1);
    }
    const Vec *hidden = rnode_attr(n, "hidden");
    p->hidden = hidden && vec_truthy(hidden);
    int w = parent->w, h = parent->h;
    size_of(n, &w, &h);
    p->lw = w;
    p->lh = h;
    p->w = graph_scaled(g, w);
    p->h = graph_scaled(g, h);
    PassCtx cx = *parent;
    cx.w = w;
    cx.h = h;
    if (p->kind->enter) p->kind->enter(g, p, n, &cx);
    p->busy = true;
    if (!p->kind->leaf) descend(g, p, n, &cx);
    p->kind->render(g, p, n, &cx);
    p->busy = false;
    /* a top-level window's children keep their pictures until the next
     * frame, so that the window can still be composited when a front end
     * asks for it after the frame was drawn (graph_frame) */
    if (!graph_is_window_pass(p)) finish_children(g, p);
}

/* }===== */

/* {===== pictures for canvases */

static double encode_srgb(double x)
{
    x = x < 0 ? 0 : x > 1 ? 1 : x;
    return x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1 / 2.4) - 0.055;
}

/* A premultiplied 8-bit value of straight colour [c] (0..1) at alpha [a]. */
static uint32_t premul8(double c, double a)
{
    double v = round(c * a * 255);
    return v < 0 ? 0 : v > 255 ? 255 : (uint32_t)v;
}

/* A cairo picture of premultiplied linear floats [px] (w x h, top row
 * first), as a canvas of [linear] light holds colours: the straight
 * colour, encoded to sRGB unless linear, premultiplied again (Skia's
 * colour-space conversion of a premultiplied picture). */
static cairo_surface_t *surface_of_floats(const float *px, int w, int h, bool linear)
{
    cairo_surface_t *s = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, w, h);
    if (cairo_surface_status(s) != CAIRO_STATUS_SUCCESS) {
        cairo_surface_destroy(s);
        return NULL;
    }
    cairo_surface_flush(s);
    unsigned char *data = cairo_image_surface_get_data(s);
    int stride = cairo_image_surface_get_stride(s);
    for (int y = 0; y < h; y++) {
        uint32_t *row = (uint32_t *)(void *)(data + (size_t)y * (size_t)stride);
        const float *q = px + (size_t)y * (size_t)w * 4;
        for (int x = 0; x < w; x++, q += 4) {
            double a = q[3] < 0 ? 0 : q[3] > 1 ? 1 : q[3];
            uint32_t A = (uint32_t)round(a * 255), ch[3] = {0, 0, 0};
            for (int k = 0; k < 3 && a > 0; k++) {
                double c = q[k] / a;
                ch[k] = premul8(linear ? (c < 0 ? 0 : c > 1 ? 1 : c) : encode_srgb(c), a);
                if (ch[k] > A) ch[k] = A;
            }
            row[x] = A << 24 | ch[0] << 16 | ch[1] << 8 | ch[2];
        }
    }
    cairo_surface_mark_dirty(s);
    return s;
}

/* A cairo picture of the 8-bit straight sRGB picture [img], for a canvas
 * of [linear] light. */
static cairo_surface_t *surface_of_image(const MediaImage *img, bool linear)
{
    cairo_surface_t *s = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, img->w, img->h);
    if (cairo_surface_status(s) != CAIRO_STATUS_SUCCESS) {
        cairo_surface_destroy(s);
        return NULL;
    }
    cairo_surface_flush(s);
    unsigned char *data = cairo_image_surface_get_data(s);
    int stride = cairo_image_surface_get_stride(s);
    for (int y = 0; y < img->h; y++) {
        uint32_t *row = (uint32_t *)(void *)(data + (size_t)y * (size_t)stride);
        const uint8_t *q = img->rgba + (size_t)y * (size_t)img->w * 4;
        for (int x = 0; x < img->w; x++, q += 4) {
            double a = q[3] / 255.0;
            uint32_t ch[3];
            for (int k = 0; k < 3; k++) ch[k] = premul8(linear ? srgb_decode(q[k] / 255.0) : q[k] / 255.0, a);
            row[x] = (uint32_t)q[3] << 24 | ch[0] << 16 | ch[1] << 8 | ch[2];
        }
    }
    cairo_surface_mark_dirty(s);
    return s;
}

static cairo_surface_t *canvas_picture(void *ctx, const char *id, const char *file, bool linear)
{
    Graph *g = ctx;
    const char *key = file ? file : id;
    for (size_t i = 0; i < g->npics; i++) {
        CanvasPic *cp = &g->pics[i];
        if (cp->frame == g->frame && cp->file == (file != NULL) && cp->linear == linear && strcmp(cp->key, key) == 0)
            return cairo_surface_reference(cp->surface);
    }
    cairo_surface_t *s = NULL;
    if (file) {
        Buf path = BUF_INIT;
        graph_path(g, file, &path);
        Buf err = BUF_INIT;
        bool fresh = false;
        const MediaImage *img = media_image(graph_media(g), buf_cstr(&path), 0, 0, &err, &fresh);
        if (img) s = surface_of_image(img, linear);
        else if (fresh) render_log(&g->env.log, RLOG_ERROR, "canvas: %s", buf_line(&err));
        buf_free(&path);
        buf_free(&err);
    } else {
        int w, h;
        GLuint tex = graph_ref_texture(g, id, &w, &h);
        GlTarget *t = tex ? graph_target(g, w, h, 32, false, false, 0) : NULL;
        if (!tex)
            graph_note(g, RLOG_WARNING, "canvas: no window node with a picture has id %s (yet): its image is not drawn",
                       id);
        if (t) {
            target_bind(t);
            static const float clear[4] = {0, 0, 0, 0};
            target_clear(t, clear);
            if (program_copy(g, tex, t)) {
                float *px = mem_alloc((size_t)w * (size_t)h * 4 * sizeof *px);
                target_readf(t, px);
                s = surface_of_floats(px, w, h, linear);
                free(px);
            }
            target_release(g->pool, t);
        }
    }
    if (!s) return NULL;
    /* kept for the frame's other canvases; last frame's go now */
    for (size_t i = 0; i < g->npics;) {
        if (g->pics[i].frame != g->frame) {
            free(g->pics[i].key);
            cairo_surface_destroy(g->pics[i].surface);
            g->pics[i] = g->pics[--g->npics];
        } else {
            i++;
        }
    }
    if (g->npics == g->cappics) {
        g->cappics = g->cappics ? 2 * g->cappics : 8;
        g->pics = mem_realloc_array(g->pics, g->cappics, sizeof *g->pics);
    }
    g->pics[g->npics++] = (CanvasPic){mem_strdup(key), file != NULL, linear, g->frame, cairo_surface_reference(s)};
    return s;
}

static unsigned canvas_texture(void *ctx, const char *id)
{
    Graph *g = ctx;
    int w, h;
    GLuint tex = graph_ref_texture(g, id, &w, &h);
    if (!tex)
        graph_note(g, RLOG_WARNING, "canvas3d: no window node with a picture has id %s (yet): its texture is not used",
                   id);
    return tex;
}

void graph_canvas_images(Graph *g, CanvasEnv *env)
{
    g->images = (CanvasImages){canvas_picture, canvas_texture, g};
    env->images = &g->images;
}

static void drop_pictures(Graph *g)
{
    for (size_t i = 0; i < g->npics; i++) {
        free(g->pics[i].key);
        cairo_surface_destroy(g->pics[i].surface);
    }
    free(g->pics);
    g->pics = NULL;
    g->npics = g->cappics = 0;
}

/* }===== */

/* {===== the frame */

/* What !record nodes [n]'s tree holds: 2 when one names a file this
 * frame, 1 when there are only records that write nothing (Flitter's
 * examples give filename=OUTPUT, null without --define), 0 none. */
static int has_record(const Node *n)
{
    int found = 0;
    for (size_t i = 0; i < rnode_nchildren(n) && found < 2; i++) {
        const Node *c = rnode_child(n, i);
        if (rnode_is(c, "record")) {
            const Vec *name = rnode_attr(c, "filename");
            int here = name && vec_len(name) > 0 ? 2 : 1;
            if (here > found) found = here;
        }
        if (!rnode_is(c, "canvas") && !rnode_is(c, "canvas3d")) {
            int below = has_record(c);
            if (below > found) found = below;
        }
    }
    return found;
}

bool graph_is_window(const Node *n) { return rnode_is(n, "window") || rnode_is(n, "offscreen"); }

/* The records of [root]'s windows, as has_record counts them (the most of
 * any window); *[any]: whether it has a window. */
static int tree_records(const Node *root, bool *any)
{
    int recs = 0;
    *any = false;
    for (size_t i = 0; i < rnode_nchildren(root); i++) {
        const Node *w = rnode_child(root, i);
        if (!graph_is_window(w)) continue;
        *any = true;
        int r = has_record(w);
        if (r > recs) recs = r;
    }
    return recs;
}

/* graph_frame's choice, without windows asked for, of drawing a frame whose
 * records count [recs] (2 when --record's first window is recorded). */
static bool draws_for_files(int recs, bool show) { return recs == 2 || (recs == 1 && !show); }

bool graph_draws_for_files(const Node *root, bool record_first, bool show)
{
    if (!root) return false;
    bool any;
    int recs = tree_records(root, &any);
    return draws_for_files(record_first ? 2 : recs, show);
}

void graph_window_size(const Node *win, int *w, int *h)
{
    double s[2];
    *w = *h = 512;
    if (canvas_attr_nums(win, "size", 2, s) && s[0] >= 1 && s[1] >= 1 && s[0] <= 16384 && s[1] <= 16384 &&
        floor(s[0]) * floor(s[1]) <= 64.0 * 1024 * 1024) {
        *w = (int)s[0];
        *h = (int)s[1];
    }
}

/* Log each line of [err] as an error. */
static void log_lines(Graph *g, const Buf *err)
{
    const char *p = err->data;
    while (p && *p) {
        const char *nl = strchr(p, '\n');
        size_t n = nl ? (size_t)(nl - p) : strlen(p);
        if (n) render_log(&g->env.log, RLOG_ERROR, "%.*s", (int)n, p);
        p = nl ? nl + 1 : p + n;
    }
}

int graph_finish_records(Graph *g)
{
    Buf err = BUF_INIT;
    int rc = recorder_free(g->rec, &err);
    if (rc != 0) log_lines(g, &err);
    buf_free(&err);
    g->rec = recorder_new();
    return rc;
}

void graph_show_windows(Graph *g, bool show) { g->show = show; }

void graph_set_scale(Graph *g, double scale, int max_samples)
{
    g->scale = scale >= 0.01 && scale <= 1 ? scale : 1;
    g->max_samples = max_samples > 0 ? max_samples : 0;
}

void graph_drawn_scale(const Graph *g, double *scale, int *max_samples)
{
    *scale = g->draw_scale;
    *max_samples = g->draw_samples;
}

int graph_scaled(const Graph *g, int n)
{
    if (g->draw_scale == 1) return n;
    double s = round(n * g->draw_scale);
    return s < 1 ? 1 : (int)s;
}

void graph_record_first(Graph *g, const char *path)
{
    free(g->record_first);
    g->record_first = path && *path ? mem_strdup(path) : NULL;
}

/* Write top-level window pass [p]'s picture to the graph_record_first
 * file. */
static void record_window(Graph *g, Pass *p)
{
    if (!p->target) return;
    GlTarget *t = graph_target(g, p->target->w, p->target->h, 8, true, false, 0);
    if (!t) return;
    target_bind(t);
    static const float clear[4] = {0, 0, 0, 0};
    target_clear(t, clear);
    program_copy(g, p->target->tex, t);
    Buf err = BUF_INIT;
    RecordSpec s = {.path = g->record_first, .limit = -1};
    if (record_target(g, t, &s, &err) < 0) graph_write_failed(g, g->record_first, buf_line(&err));
    buf_free(&err);
    target_release(g->pool, t);
}

/* Composite the top-level windows of this frame's [root] that were drawn
 * without (windows now shown: graph_show_windows after the frame). */
static void composite_late(Graph *g, const Node *root, const GraphFrame *f)
{
    if (!begin(g)) return;
    g->f = f;
    size_t k = 0;
    for (size_t i = 0; i < rnode_nchildren(root) && k < g->nwindows; i++) {
        const Node *w = rnode_child(root, i);
        if (!graph_is_window(w)) continue;
        Pass *p = g->windows[k++];
        if (p->target) continue;
        PassCtx cx = {.w = p->lw, .h = p->lh, .colorbits = 16, .write = false};
        p->kind->enter(g, p, w, &cx);
        p->kind->render(g, p, w, &cx);
    }
    end(g);
    g->f = NULL;
}

int graph_frame(Graph *g, const Node *root, const GraphFrame *frame, bool windows)
{
    if (!root) return 0;
    if (frame->frame == g->frame) {
        if (windows && g->show && !g->composited && g->nwindows) composite_late(g, root, frame);
        if (windows) g->composited = g->show;
        return 0;
    }
    bool any;
    int recs = tree_records(root, &any);
    if (g->record_first) recs = 2;
    bool records = recs == 2;
    /* Headless, every frame of a tree with a !record is drawn, as
     * Flitter draws every frame (a !feedback or a `last` evolves frame by
     * frame towards the one recorded); with windows shown, a frame is
     * drawn when a file needs it or the front end takes its pictures,
     * not when it drops them. A frame nothing asks for is not drawn (nor
     * counted as drawn, so that a later call for it does draw). */
    if (!windows && !draws_for_files(recs, g->show)) return 0;
    /* the frames not drawn since the last one are in this one's delta */
    GraphFrame fd = *frame;
    if (g->frame >= 0 && frame->frame > g->frame + 1 && frame->beat >= g->beat) fd.delta = frame->beat - g->beat;
    const GraphFrame *f = &fd;
    g->frame = frame->frame;
    g->beat = frame->beat;
    g->composited = g->show;   /* (a shown window's picture is composited: pass_window.c) */
    /* dynamic resolution only where no file is written */
    bool scaled = windows && g->show && !records;
    g->draw_scale = scaled ? g->scale : 1;
    g->draw_samples = scaled ? g->max_samples : 0;
    g->write_failures = 0;
    if (!any && !g->nwindows) return 0;
    /* the files asked for cannot be written: a failure of the frame's */
    if (!cairo_lib_ready(NULL)) {
        graph_note(g, RLOG_ERROR, "window: cairo cannot be loaded: windows are not drawn");
        return records ? 1 : 0;
    }
    if (!begin(g)) return records ? 1 : 0;
    g->f = f;
    for (size_t i = 0; i < g->nwindows; i++) finish_children(g, g->windows[i]);
    /* the top-level windows, matched by kind and order as Flitter's
     * engine matches its window renderers */
    size_t had = g->nwindows;
    Pass **old = g->windows;
    for (size_t i = 0; i < had; i++) old[i]->seen = false;
    Pass **now = rnode_nchildren(root) ? mem_calloc(rnode_nchildren(root), sizeof *now) : NULL;
    size_t k = 0;
    for (size_t i = 0; i < rnode_nchildren(root); i++) {
        const Node *w = rnode_child(root, i);
        if (!graph_is_window(w)) continue;
        if (g->env.interrupt && *g->env.interrupt) break;
        const PassKind *kind = rnode_is(w, "window") ? &pass_window : &pass_offscreen;
        Pass *q = NULL;
        for (size_t j = 0; j < had && !q; j++)
            if (!old[j]->seen && old[j]->kind == kind) q = old[j];
        if (!q) q = new_pass(kind);
        q->seen = true;
        PassCtx cx = {.w = 512, .h = 512, .colorbits = 16, .write = true};
        /* the first window composites its picture for graph_record_first */
        q->retain = k == 0 && g->record_first;
        update(g, q, w, &cx);
        if (k == 0 && g->record_first) record_window(g, q);
        now[k++] = q;
    }
    for (size_t j = 0; j < had; j++)
        if (!old[j]->seen) destroy(g, old[j]);
    free(old);
    g->windows = now;
    g->nwindows = k;
    double t = target_now();
    if (t >= g->expire_at) {
        target_pool_expire(g->pool, t, POOL_AGE);
        g->expire_at = t + POOL_TRIM_EVERY;
    }
    end(g);
    g->f = NULL;
    return g->write_failures;
}

unsigned graph_window_texture(Graph *g, size_t index, int *w, int *h)
{
    if (index >= g->nwindows || !g->windows[index]->target) return 0;
    GlTarget *t = g->windows[index]->target;
    *w = t->w;
    *h = t->h;
    return t->tex;
}

int graph_read_window(Graph *g, size_t index, uint32_t *px, int w, int h, size_t stride)
{
    if (index >= g->nwindows || !g->windows[index]->target || !begin(g)) return -1;
    GlTarget *src = g->windows[index]->target;
    GlTarget *t = graph_target(g, w, h, 8, true, false, 0);
    int rc = -1;
    if (t) {
        target_bind(t);
        static const float clear[4] = {0, 0, 0, 0};
        target_clear(t, clear);
        if (program_copy(g, src->tex, t)) {
            /* the encoded premultiplied light and its alpha, as a !record
             * stores them: over black, what Flitter's window shows */
            target_read_argb(t, px, stride);
            rc = 0;
        }
        target_release(g->pool, t);
    }
    end(g);
    return rc;
}

static void drop_all(Graph *g)
{
    drop_pictures(g);
    for (size_t i = 0; i < g->nwindows; i++) destroy(g, g->windows[i]);
    free(g->windows);
    g->windows = NULL;
    g->nwindows = g->capwindows = 0;
    pass_canvas3d_free(g);
    media_cache_free(g->media);
    g->media = NULL;
    programs_free(g->programs);
    g->programs = NULL;
    target_pool_free(g->pool);
    g->pool = NULL;
    if (g->quad_vao) glDeleteVertexArrays(1, &g->quad_vao);
    if (g->quad_vbo) glDeleteBuffers(1, &g->quad_vbo);
    if (g->zero_tex) glDeleteTextures(1, &g->zero_tex);
    if (g->nearest) glDeleteSamplers(1, &g->nearest);
    g->quad_vao = g->quad_vbo = g->zero_tex = g->nearest = 0;
}

int graph_attach(Graph *g, Buf *err)
{
    GlContext *host = gl_context_host(err);
    if (!host) return -1;
    if (g->gl && gl_context_use(g->gl)) drop_all(g);
    if (g->gl) gl_context_free(g->gl);
    g->gl = host;
    g->failed = false;
    g->frame = -1;
    return 0;
}

int graph_free(Graph *g)
{
    if (!g) return 0;
    Buf err = BUF_INIT;
    int rc = recorder_free(g->rec, &err);
    if (rc != 0) log_lines(g, &err);
    buf_free(&err);
    if (g->gl && gl_context_use(g->gl)) drop_all(g);
    gl_context_free(g->gl);
    for (size_t i = 0; i < g->nrefs; i++) free(g->refs[i].id);
    free(g->refs);
    free(g->record_first);
    for (int i = 0; i < g->nreported; i++) free(g->reported[i]);
    for (int i = 0; i < g->nnoted && i < 64; i++) free(g->noted[i]);
    free(g);
    return rc;
}

/* }===== */
