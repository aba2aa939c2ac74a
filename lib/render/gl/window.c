/* window.c: windows, canvases, records and references (see window.h). */
#include "window.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <cairo.h>

#include "bloom.h"
#include "buf.h"
#include "canvas.h"
#include "canvas3d.h"
#include "mem.h"
#include "record.h"
#include "rnode.h"
#include "srgb.h"
#include "turns.h"

/* last: it turns the library's names into calls through its table */
#include "cairo_lib.h"

/* How many finished pictures a renderer keeps for reuse: a frame's
 * pictures (window, !record, !bloom, canvases) are mostly the same sizes
 * as the last frame's. */
#define SPARE_PICTURES 6

struct Renderer {
    const SymTab *symbols;
    RenderLog log;
    RenderLog skiplog;     /* [log] with skipped-kind warnings always on */
    SkipLog skips;
    Canvas3D *c3d;         /* made by the first !canvas3d (its GL context with it) */
    Bloom *bloom;          /* !bloom's scratch framebuffers, made by the first */
    float *bloom_light;    /* a !bloom's linear light (bloom_cap floats), reused */
    size_t bloom_cap;
    bool bloom_busy;       /* bloom_light is in use (a !bloom is being drawn) */
    cairo_surface_t *canvas_light;  /* while a !bloom is drawn: the linear
                                       light of the last `linear=true`
                                       canvas drawn (8-bit), or NULL */
    SrgbTable *srgb;       /* linear canvases' output encoding, made by the first */
    Recorder *rec;         /* the !record files open across frames (record.h) */
    char *record;          /* renderer_set_record: the first window's file, or NULL */
    bool saw_window;
    int failed_reported;   /* write errors so far (each file's first is logged) */
    char *reported[64];    /* the files whose write error was logged (errors
                              of further files are counted, not logged) */
    int nreported;
    cairo_surface_t *spare[SPARE_PICTURES];   /* pictures of past frames for new_picture */
    int nspare;
};

/* Pictures of id'd nodes drawn so far in this window, for !reference. */
typedef struct Refs {
    const Vec *id[64];
    cairo_surface_t *pic[64];
    int n;
} Refs;

/* One drawing of one window: its references, the GIF frame rate, and
 * whether !record nodes write their files (renderer_frame) or only give
 * their pictures (renderer_draw_window). */
typedef struct Pass {
    Refs refs;
    double fps;
    bool write;
} Pass;

Renderer *renderer_new(const SymTab *symbols, const RenderLog *log)
{
    Renderer *r = calloc(1, sizeof *r);
    if (!r) mem_oom();
    r->symbols = symbols;
    if (log) r->log = *log;
    /* a kind that is not drawn is always worth one warning: a picture
     * missing a part must never come silently (issue 25) */
    r->skiplog = r->log;
    r->skiplog.debug = true;
    r->skips.log = &r->skiplog;
    r->rec = recorder_new();
    return r;
}

void renderer_set_record(Renderer *r, const char *path)
{
    free(r->record);
    r->record = NULL;
    if (path && *path && !(r->record = strdup(path))) mem_oom();
}

bool renderer_saw_window(const Renderer *r) { return r->saw_window; }

int renderer_free(Renderer *r)
{
    if (!r) return 0;
    char err[600];
    int rc = recorder_free(r->rec, err, sizeof err);
    if (rc != 0) render_log(&r->log, RLOG_ERROR, "%s", err);
    free(r->record);
    canvas3d_free(r->c3d);
    bloom_free(r->bloom);
    free(r->bloom_light);
    if (r->canvas_light) cairo_surface_destroy(r->canvas_light);
    for (int i = 0; i < r->nspare; i++) cairo_surface_destroy(r->spare[i]);
    free(r->srgb);
    for (int i = 0; i < r->nreported; i++) free(r->reported[i]);
    free(r);
    return rc;
}

static void size_of(const Node *n, int dflt_w, int dflt_h, int *w, int *h)
{
    double s[2];
    *w = dflt_w;
    *h = dflt_h;
    /* each side 1..16384 and at most 64 Mpixels (a 256 MB picture), else the default */
    if (canvas_attr_nums(n, "size", 2, s) && s[0] >= 1 && s[1] >= 1 && s[0] <= 16384 && s[1] <= 16384 &&
        floor(s[0]) * floor(s[1]) <= 64.0 * 1024 * 1024) {
        *w = (int)s[0];
        *h = (int)s[1];
    }
}

/* A transparent ARGB32 picture of [w] x [h]: a kept one of that size
 * cleared (a 1080x1080 picture is 4.6 MB, which a fresh allocation would
 * fault in page by page every frame), else a new one. Give it back with
 * drop_picture. */
static cairo_surface_t *new_picture(Renderer *r, int w, int h)
{
    for (int i = r->nspare - 1; i >= 0; i--) {
        cairo_surface_t *s = r->spare[i];
        if (cairo_image_surface_get_width(s) != w || cairo_image_surface_get_height(s) != h) continue;
        memmove(r->spare + i, r->spare + i + 1, (size_t)(r->nspare - i - 1) * sizeof *r->spare);
        r->nspare--;
        cairo_surface_flush(s);
        memset(cairo_image_surface_get_data(s), 0, (size_t)cairo_image_surface_get_stride(s) * (size_t)h);
        cairo_surface_mark_dirty(s);
        return s;
    }
    return cairo_image_surface_create(CAIRO_FORMAT_ARGB32, w, h);
}

/* Release picture [s] (new_picture's), keeping it for reuse when nothing
 * else holds it (an encoder may) and it is sound; the oldest kept one
 * makes room (so that the sizes of a window that changed size age out);
 * NULL is a no-op. */
static void drop_picture(Renderer *r, cairo_surface_t *s)
{
    if (!s) return;
    if (cairo_surface_status(s) != CAIRO_STATUS_SUCCESS || cairo_surface_get_reference_count(s) != 1 ||
        !cairo_image_surface_get_data(s)) {
        cairo_surface_destroy(s);
        return;
    }
    if (r->nspare == SPARE_PICTURES) {
        cairo_surface_destroy(r->spare[0]);
        memmove(r->spare, r->spare + 1, (SPARE_PICTURES - 1) * sizeof *r->spare);
        r->nspare--;
    }
    r->spare[r->nspare++] = s;
}

/* How the children of a window-level `!transform` are placed on its
 * picture: [m] maps the picture's pixels (each child stretched over it)
 * to where they land, sampled with [filter] and [extend] outside. */
typedef struct Place {
    cairo_matrix_t m;
    cairo_filter_t filter;
    cairo_extend_t extend;
} Place;

/* Paint [src] over [dst], stretched to [dst]'s size when they differ (as
 * Flitter's window shader samples each child over the whole output), and
 * then placed by [at] (NULL: as it is). */
static void composite(cairo_surface_t *dst, cairo_surface_t *src, const Place *at)
{
    cairo_t *cr = cairo_create(dst);
    int dw = cairo_image_surface_get_width(dst), dh = cairo_image_surface_get_height(dst);
    int sw = cairo_image_surface_get_width(src), sh = cairo_image_surface_get_height(src);
    if (at) cairo_transform(cr, &at->m);
    if (dw != sw || dh != sh) cairo_scale(cr, (double)dw / sw, (double)dh / sh);
    cairo_set_source_surface(cr, src, 0, 0);
    cairo_pattern_set_filter(cairo_get_source(cr), at ? at->filter : CAIRO_FILTER_BILINEAR);
    cairo_pattern_set_extend(cairo_get_source(cr), at ? at->extend : CAIRO_EXTEND_PAD);
    cairo_paint(cr);
    cairo_destroy(cr);
}

static void write_record(Renderer *r, const Node *n, cairo_surface_t *pic, double fps);

static void render_children(Renderer *r, const Node *n, cairo_surface_t *target, int w, int h,
                            Pass *pass, const Place *at);
static cairo_surface_t *render_bloom(Renderer *r, const Node *n, int w, int h, Pass *pass);
static cairo_surface_t *render_transform(Renderer *r, const Node *n, int w, int h, Pass *pass);

/* The picture ([w] x [h]) of `!canvas` node [c]. A `linear=true` canvas
 * (canvas_is_linear) is drawn with linear colours into an 8-bit picture,
 * blending in linear light as Flitter's 8-bit linear target does, and
 * encoded as the window encodes its output (srgb_encode_linear8), so that
 * over black it shows what Flitter's window shows; while a !bloom is
 * drawn its linear light is kept in r->canvas_light for the bloom. */
static cairo_surface_t *render_canvas(Renderer *r, const Node *c, int w, int h)
{
    bool linear = canvas_is_linear(c);
    cairo_surface_t *pic = new_picture(r, w, h);
    cairo_t *cr = cairo_create(pic);
    CanvasEnv env = {.symbols = r->symbols, .skips = &r->skips, .linear = linear};
    canvas_draw(cr, c, &env);
    cairo_destroy(cr);
    if (!linear) return pic;
    if (!r->srgb) {
        r->srgb = mem_alloc(sizeof *r->srgb);
        srgb_table_init(r->srgb);
    }
    if (!r->bloom_busy) {
        srgb_encode_linear8(r->srgb, pic, pic);
        return pic;
    }
    if (r->canvas_light) drop_picture(r, r->canvas_light);
    r->canvas_light = pic;
    cairo_surface_t *enc = new_picture(r, w, h);
    srgb_encode_linear8(r->srgb, pic, enc);
    return enc;
}

/* Draw window-level node [c] onto [target] ([w] x [h]): its picture
 * composited in place, placed by [at] (NULL: as it is; the children of a
 * !transform), and kept for !reference when it has an id. */
static void render_child(Renderer *r, const Node *c, cairo_surface_t *target, int w, int h, Pass *pass,
                         const Place *at)
{
    Refs *refs = &pass->refs;
    cairo_surface_t *pic = NULL;
    if (rnode_is(c, "canvas")) {
        int cw, ch;
        size_of(c, w, h, &cw, &ch);
        pic = render_canvas(r, c, cw, ch);
    } else if (rnode_is(c, "canvas3d")) {
        int cw, ch;
        size_of(c, w, h, &cw, &ch);
        pic = new_picture(r, cw, ch);
        if (!r->c3d) r->c3d = canvas3d_new();
        CanvasEnv env = {.symbols = r->symbols, .skips = &r->skips};
        canvas3d_draw(r->c3d, c, pic, &env, &r->log);
    } else if (rnode_is(c, "record")) {
        int cw, ch;
        size_of(c, w, h, &cw, &ch);
        pic = new_picture(r, cw, ch);
        render_children(r, c, pic, cw, ch, pass, NULL);
        if (pass->write) write_record(r, c, pic, pass->fps);
    } else if (rnode_is(c, "key") || rnode_is(c, "pointer")) {
        return;   /* input, not a picture: lib/input.c reads them */
    } else if (rnode_is(c, "reference")) {
        const Vec *id = rnode_attr(c, "id");
        for (int k = 0; id && k < refs->n; k++)
            if (vec_equal(refs->id[k], id)) {
                composite(target, refs->pic[k], at);
                break;
            }
        return;
    } else if (rnode_is(c, "bloom")) {
        int cw, ch;
        size_of(c, w, h, &cw, &ch);
        pic = render_bloom(r, c, cw, ch, pass);
    } else if (rnode_is(c, "transform")) {
        int cw, ch;
        size_of(c, w, h, &cw, &ch);
        pic = render_transform(r, c, cw, ch, pass);
    } else if (rnode_nchildren(c) > 0) {
        /* an effect (!shader, !adjust, !feedback, ...): its input drawn as is */
        skiplog_effect(&r->skips, rnode_kind(c));
        int cw, ch;
        size_of(c, w, h, &cw, &ch);
        pic = new_picture(r, cw, ch);
        render_children(r, c, pic, cw, ch, pass, NULL);
    } else {
        skiplog_note(&r->skips, "window", rnode_kind(c));
        return;
    }
    composite(target, pic, at);
    const Vec *id = rnode_attr(c, "id");
    if (id && refs->n < 64) {
        refs->id[refs->n] = id;
        refs->pic[refs->n++] = pic;
    } else {
        drop_picture(r, pic);
    }
}

/* Draw the window-level children of [n] onto [target] ([w] x [h]),
 * placed by [at] (NULL: as they are). */
static void render_children(Renderer *r, const Node *n, cairo_surface_t *target, int w, int h,
                            Pass *pass, const Place *at)
{
    for (size_t i = 0; i < rnode_nchildren(n); i++)
        render_child(r, rnode_child(n, i), target, w, h, pass, at);
}

/* The placement of the children of window-level `!transform` [n] on its
 * picture ([w] x [h]), as Flitter's Transform filter does (docs/shaders.md
 * "!transform"; render/window/shaders.py, Transform.render, and
 * glsl/transform.frag): `scale` (one or two numbers), `translate` (one or
 * two, pixels) and `rotate` (turns) make one matrix in attribute order
 * (the last applied first to the picture), about the picture's centre and
 * with the y axis pointing up, so translate=0;10 moves the picture 10
 * pixels up and rotate=0.25 turns it a quarter turn anticlockwise on
 * screen (Matrix33.rotate; Flitter's documentation says clockwise, its
 * code turns anticlockwise, and this follows the code). Pixels are
 * sampled bilinearly (`nearest=true`: the nearest), transparent outside
 * the children unless `repeat=true`. false when the matrix is singular or
 * not finite (nothing is drawn: Flitter samples at NaN). `keystone=`
 * (a projective map), `border=` and a `repeat` of one axis only are not
 * drawn; each is reported once. */
static bool transform_place(Renderer *r, const Node *n, int w, int h, Place *at)
{
    cairo_matrix_init_translate(&at->m, w / 2.0, h / 2.0);
    double v[4];
    for (size_t i = 0; i < rnode_nattrs(n); i++) {
        const char *key = rnode_attr_name(n, i);
        cairo_matrix_t step;
        if (strcmp(key, "scale") == 0 && canvas_attr_nums(n, key, 2, v)) {
            cairo_matrix_init_scale(&step, v[0], v[1]);
        } else if (strcmp(key, "translate") == 0 && canvas_attr_nums(n, key, 2, v)) {
            cairo_matrix_init_translate(&step, v[0], -v[1]);   /* y up */
        } else if (strcmp(key, "rotate") == 0 && canvas_attr_nums(n, key, 1, v) && !isnan(v[0])) {
            /* Flitter's rotation in y-up space, seen in cairo's y-down space */
            double c = cos_t(v[0]), s = sin_t(v[0]);
            cairo_matrix_init(&step, c, -s, s, c, 0, 0);
        } else {
            if (strcmp(key, "keystone") == 0 && canvas_attr_nums(n, key, 2, v) && (v[0] != 0 || v[1] != 0))
                skiplog_note(&r->skips, "window", "transform keystone=");
            continue;
        }
        cairo_matrix_multiply(&at->m, &step, &at->m);   /* [step] first, then what came before */
    }
    cairo_matrix_translate(&at->m, -w / 2.0, -h / 2.0);
    at->filter = rnode_attr(n, "nearest") && vec_truthy(rnode_attr(n, "nearest")) ? CAIRO_FILTER_NEAREST
                                                                                  : CAIRO_FILTER_BILINEAR;
    at->extend = CAIRO_EXTEND_NONE;
    if (canvas_attr_nums(n, "border", 4, v)) {
        if (v[0] != 0 || v[1] != 0 || v[2] != 0 || v[3] != 0) skiplog_note(&r->skips, "window", "transform border=");
    } else if (rnode_attr(n, "repeat")) {
        const Vec *rep = rnode_attr(n, "repeat");
        bool rx = vec_truthy(rep), ry = rx;
        if (vec_is_num(rep) && vec_len(rep) == 2) rx = vec_cnums(rep)[0] != 0, ry = vec_cnums(rep)[1] != 0;
        if (rx && ry) at->extend = CAIRO_EXTEND_REPEAT;
        else if (rx || ry) skiplog_note(&r->skips, "window", "transform repeat= of one axis");
    }
    cairo_matrix_t inv = at->m;
    const cairo_matrix_t *m = &at->m;
    if (!isfinite(m->xx) || !isfinite(m->yx) || !isfinite(m->xy) || !isfinite(m->yy) || !isfinite(m->x0) ||
        !isfinite(m->y0))
        return false;
    return cairo_matrix_invert(&inv) == CAIRO_STATUS_SUCCESS;
}

/* The picture ([w] x [h]) of window-level `!transform` node [n]: its
 * children composited `over`, each stretched over the picture and placed
 * by transform_place in one resampling (as Flitter's shader samples each
 * child once), times `alpha` (one number, default 1, clamped to 0..1 in
 * this 8-bit picture). */
static cairo_surface_t *render_transform(Renderer *r, const Node *n, int w, int h, Pass *pass)
{
    cairo_surface_t *pic = new_picture(r, w, h);
    Place at;
    if (!transform_place(r, n, w, h, &at)) return pic;
    render_children(r, n, pic, w, h, pass, &at);
    double alpha;
    if (canvas_attr_nums(n, "alpha", 1, &alpha) && !(alpha >= 1)) {
        cairo_t *cr = cairo_create(pic);
        cairo_set_operator(cr, CAIRO_OPERATOR_DEST_IN);   /* every pixel times alpha */
        cairo_set_source_rgba(cr, 0, 0, 0, alpha > 0 ? alpha : 0);
        cairo_paint(cr);
        cairo_destroy(cr);
    }
    return pic;
}

/* Forget the kept linear light of a canvas (r->canvas_light). */
static void drop_canvas_light(Renderer *r)
{
    if (r->canvas_light) drop_picture(r, r->canvas_light);
    r->canvas_light = NULL;
}

/* The picture ([w] x [h]) of `!bloom` node [n] (bloom.h): its children
 * composited `over` in linear light (a !canvas3d of the bloom's size
 * gives its light unclamped, as Flitter's half-float textures do; a
 * `linear=true` !canvas of its size its 8-bit linear light, as Flitter's
 * linear canvas texture is read; any other child is drawn as in a window
 * and decoded from sRGB), bloomed, and encoded as the window encodes its
 * output. */
static cairo_surface_t *render_bloom(Renderer *r, const Node *n, int w, int h, Pass *pass)
{
    size_t npix = (size_t)w * h;
    /* the renderer's buffer, kept from frame to frame (a fresh one for a
     * !bloom inside a !bloom) */
    float *light;
    bool own = r->bloom_busy || npix * 4 > r->bloom_cap;
    if (!r->bloom_busy && own) {
        free(r->bloom_light);
        r->bloom_light = mem_alloc(npix * 4 * sizeof(float));
        r->bloom_cap = npix * 4;
        own = false;
    }
    light = own ? mem_alloc(npix * 4 * sizeof(float)) : r->bloom_light;
    bool was_busy = r->bloom_busy;
    r->bloom_busy = true;
    float *one = NULL;
    bool empty = true;
    for (size_t i = 0; i < rnode_nchildren(n); i++) {
        const Node *c = rnode_child(n, i);
        cairo_surface_t *layer = NULL;
        drop_canvas_light(r);
        int lw = 0, lh = 0;
        const float *lin = NULL;
        if (rnode_is(c, "canvas3d") && !rnode_attr(c, "id")) {
            /* a !canvas3d of the bloom's size that nothing refers to gives
             * its linear light alone: its 8-bit picture would not be used */
            int cw, ch;
            size_of(c, w, h, &cw, &ch);
            if (cw == w && ch == h) {
                if (!r->c3d) r->c3d = canvas3d_new();
                CanvasEnv env = {.symbols = r->symbols, .skips = &r->skips};
                /* (a group whose program fails leaves those before it drawn) */
                canvas3d_draw_linear(r->c3d, c, w, h, &env, &r->log);
                lin = canvas3d_linear(r->c3d, &lw, &lh);
                if (!lin) layer = new_picture(r, w, h);   /* nothing drawn: a transparent layer */
            }
        }
        if (!lin && !layer) {
            layer = new_picture(r, w, h);
            render_child(r, c, layer, w, h, pass, NULL);
            lin = rnode_is(c, "canvas3d") ? canvas3d_linear(r->c3d, &lw, &lh) : NULL;
        }
        if (lin && (lw != w || lh != h)) lin = NULL;
        if (!lin && !layer) layer = new_picture(r, w, h);
        /* a linear canvas of the bloom's size gives its own linear light */
        cairo_surface_t *clight = rnode_is(c, "canvas") ? r->canvas_light : NULL;
        if (clight && (cairo_image_surface_get_width(clight) != w || cairo_image_surface_get_height(clight) != h))
            clight = NULL;
        float *dst = light;
        if (!empty && (clight || !lin)) {
            if (!one) one = mem_alloc(npix * 4 * sizeof(float));
            dst = one;
        }
        if (lin) {
            size_t cap;
            float *taken;
            if (empty && !own && (taken = canvas3d_take_linear(r->c3d, r->bloom_light, r->bloom_cap, &cap))) {
                /* the first layer over nothing is itself: the canvas's
                 * buffer becomes the bloom's and the bloom's the canvas's
                 * next, instead of a copy (18 MB at 1080x1080) */
                light = r->bloom_light = taken;
                r->bloom_cap = cap;
            } else if (empty) {
                memcpy(light, lin, npix * 4 * sizeof(float));
            } else {
                bloom_over(light, lin, npix);
            }
        } else {
            if (clight) bloom_decode_linear(clight, dst);
            else bloom_decode(layer, dst);
            if (!empty) bloom_over(light, one, npix);
        }
        drop_canvas_light(r);
        empty = false;
        drop_picture(r, layer);
    }
    if (empty) memset(light, 0, npix * 4 * sizeof(float));
    if (!r->bloom) r->bloom = bloom_new();
    BloomParams bp;
    bloom_params(n, &bp);
    bloom_apply(r->bloom, &bp, light, w, h);
    cairo_surface_t *pic = new_picture(r, w, h);
    bloom_encode(r->bloom, light, pic);
    r->bloom_busy = was_busy;
    if (own) free(light);
    free(one);
    return pic;
}

/* Count a write error of file [path] and log [line] if it is the file's
 * first (for the first 64 files; a script making up a new name every
 * frame cannot flood the log). */
static void report(Renderer *r, const char *path, const char *line)
{
    r->failed_reported++;
    for (int i = 0; i < r->nreported; i++)
        if (strcmp(r->reported[i], path) == 0) return;
    if (r->nreported == 64) return;
    if (!(r->reported[r->nreported++] = strdup(path))) mem_oom();
    render_log(&r->log, RLOG_ERROR, "%s%s", line,
               r->nreported == 64 ? " (errors of further !record files are not logged)" : "");
}

/* The attributes of !record that are not encoder options: Flitter's own
 * (record.py) and the generic ones no encoder knows. */
static bool is_record_attr(const char *name)
{
    static const char *const own[] = {"filename", "codec", "pixfmt", "limit", "hidden", "keep_alpha",
                                      "quality", "size", "id"};
    for (size_t i = 0; i < sizeof own / sizeof *own; i++)
        if (strcmp(name, own[i]) == 0) return true;
    return false;
}

/* Write the picture [pic] of one frame as [s] asks (record.h), reporting a
 * failure once and an unused-option note on the debug stream. */
static void write_spec(Renderer *r, const RecordSpec *s, cairo_surface_t *pic, double fps)
{
    char err[800];
    int rc = recorder_write(r->rec, s, pic, fps, err, sizeof err);
    if (rc < 0) report(r, s->path, err);
    else if (rc > 0 && r->log.debug) render_log(&r->log, RLOG_WARNING, "%s", err);
}

static void write_record(Renderer *r, const Node *n, cairo_surface_t *pic, double fps)
{
    Buf name = BUF_INIT, codec = BUF_INIT, pixfmt = BUF_INIT;
    if (!canvas_attr_str(n, "filename", r->symbols, &name) || name.len == 0) goto done;
    RecordSpec s = {.path = buf_cstr(&name), .limit = -1};
    if (canvas_attr_str(n, "codec", r->symbols, &codec)) s.codec = buf_cstr(&codec);
    if (canvas_attr_str(n, "pixfmt", r->symbols, &pixfmt)) s.pixfmt = buf_cstr(&pixfmt);
    s.keep_alpha = rnode_attr(n, "keep_alpha") && vec_truthy(rnode_attr(n, "keep_alpha"));
    double limit;
    if (canvas_attr_nums(n, "limit", 1, &limit) && limit >= 0) s.limit = limit;
    /* every other attribute is an encoder option, as text (Flitter) */
    size_t nattrs = rnode_nattrs(n), nopt = 0;
    VideoOption *opts = nattrs ? calloc(nattrs, sizeof *opts) : NULL;
    Buf *vals = nattrs ? calloc(nattrs, sizeof *vals) : NULL;
    if (nattrs && (!opts || !vals)) mem_oom();
    for (size_t i = 0; i < nattrs; i++) {
        const char *key = rnode_attr_name(n, i);
        if (is_record_attr(key) || !canvas_attr_str(n, key, r->symbols, &vals[nopt])) continue;
        opts[nopt].key = key;
        opts[nopt].value = buf_cstr(&vals[nopt]);
        nopt++;
    }
    s.options = opts;
    s.noptions = nopt;
    write_spec(r, &s, pic, fps);
    for (size_t i = 0; i < nattrs; i++) buf_free(&vals[i]);
    free(vals);
    free(opts);
done:
    buf_free(&name);
    buf_free(&codec);
    buf_free(&pixfmt);
}

/* Whether [n]'s window-level tree holds a !record with a filename: the
 * only consumer of pictures, so a window without one is not drawn. */
static bool has_record(const Node *n)
{
    for (size_t i = 0; i < rnode_nchildren(n); i++) {
        const Node *c = rnode_child(n, i);
        if (rnode_is(c, "record") && vec_truthy(rnode_attr(c, "filename"))) return true;
        if (!rnode_is(c, "canvas") && has_record(c)) return true;   /* e.g. inside an effect */
    }
    return false;
}

bool window_is_top(const Node *n) { return rnode_is(n, "window") || rnode_is(n, "offscreen"); }

void window_size(const Node *win, int *w, int *h) { size_of(win, 512, 512, w, h); }

/* Composite the children of window [win] onto [target] (the window's
 * size), as one pass; with [write], its !record nodes write their files. */
static void draw_window(Renderer *r, const Node *win, cairo_surface_t *target, double fps, bool write)
{
    int w = cairo_image_surface_get_width(target), h = cairo_image_surface_get_height(target);
    Pass pass = {.refs.n = 0, .fps = fps, .write = write};
    render_children(r, win, target, w, h, &pass, NULL);
    for (int k = 0; k < pass.refs.n; k++) drop_picture(r, pass.refs.pic[k]);
}

int renderer_frame(Renderer *r, const Node *root, double fps)
{
    int before = r->failed_reported;
    bool first = true;   /* the first window: renderer_set_record's */
    for (size_t i = 0; root && i < rnode_nchildren(root); i++) {
        const Node *win = rnode_child(root, i);
        if (!window_is_top(win)) continue;
        r->saw_window = true;
        bool extra = first && r->record;
        first = false;
        if (!has_record(win) && !extra) continue;
        char why[300];
        if (!cairo_lib_ready(why, sizeof why)) {
            report(r, "window", why);   /* logged once: the same answer every frame */
            return r->failed_reported - before;
        }
        int w, h;
        window_size(win, &w, &h);
        cairo_surface_t *pic = new_picture(r, w, h);
        draw_window(r, win, pic, fps, true);
        if (extra) write_spec(r, &(RecordSpec){.path = r->record, .limit = -1}, pic, fps);
        drop_picture(r, pic);
    }
    return r->failed_reported - before;
}

int renderer_draw_window(Renderer *r, const Node *win, cairo_surface_t *target)
{
    if (!cairo_lib_ready(NULL, 0)) return -1;   /* the caller made [target] with its own cairo */
    int w, h;
    window_size(win, &w, &h);
    if (cairo_surface_get_type(target) != CAIRO_SURFACE_TYPE_IMAGE ||
        cairo_image_surface_get_format(target) != CAIRO_FORMAT_ARGB32 ||
        cairo_image_surface_get_width(target) != w || cairo_image_surface_get_height(target) != h)
        return -1;
    r->saw_window = true;
    /* the picture starts transparent, as new_picture's does */
    cairo_t *cr = cairo_create(target);
    cairo_set_operator(cr, CAIRO_OPERATOR_CLEAR);
    cairo_paint(cr);
    cairo_destroy(cr);
    draw_window(r, win, target, 1.0, false);
    cairo_surface_flush(target);
    return 0;
}
