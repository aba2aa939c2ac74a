/* window.c: windows, canvases, records and references (see window.h). */
#include "window.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <cairo.h>

#include "buf.h"
#include "canvas.h"
#include "gifout.h"
#include "mem.h"
#include "rnode.h"

typedef struct GifSlot {
    char *path;
    GifOut *gif;
} GifSlot;

struct Renderer {
    const SymTab *symbols;
    RenderLog log;
    SkipLog skips;
    GifSlot *gifs;
    size_t ngifs;
    bool saw_window;
    int failed_reported;   /* write errors are reported once per renderer */
};

/* Pictures of id'd nodes drawn so far in this window, for !reference. */
typedef struct Refs {
    const Vec *id[64];
    cairo_surface_t *pic[64];
    int n;
} Refs;

Renderer *renderer_new(const SymTab *symbols, const RenderLog *log)
{
    Renderer *r = calloc(1, sizeof *r);
    if (!r) mem_oom();
    r->symbols = symbols;
    if (log) r->log = *log;
    r->skips.log = &r->log;
    return r;
}

bool renderer_saw_window(const Renderer *r) { return r->saw_window; }

int renderer_free(Renderer *r)
{
    if (!r) return 0;
    int rc = 0;
    for (size_t i = 0; i < r->ngifs; i++) {
        if (gifout_close(r->gifs[i].gif) != 0) {
            render_log(&r->log, RLOG_ERROR, "%s: cannot finish GIF", r->gifs[i].path);
            rc = -1;
        }
        free(r->gifs[i].path);
    }
    free(r->gifs);
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

static cairo_surface_t *new_picture(int w, int h)
{
    return cairo_image_surface_create(CAIRO_FORMAT_ARGB32, w, h);
}

/* Paint [src] over [dst], stretched to [dst]'s size when they differ (as
 * Flitter's window shader samples each child over the whole output). */
static void composite(cairo_surface_t *dst, cairo_surface_t *src)
{
    cairo_t *cr = cairo_create(dst);
    int dw = cairo_image_surface_get_width(dst), dh = cairo_image_surface_get_height(dst);
    int sw = cairo_image_surface_get_width(src), sh = cairo_image_surface_get_height(src);
    if (dw != sw || dh != sh) cairo_scale(cr, (double)dw / sw, (double)dh / sh);
    cairo_set_source_surface(cr, src, 0, 0);
    cairo_pattern_set_filter(cairo_get_source(cr), CAIRO_FILTER_BILINEAR);
    cairo_pattern_set_extend(cairo_get_source(cr), CAIRO_EXTEND_PAD);
    cairo_paint(cr);
    cairo_destroy(cr);
}

static void write_record(Renderer *r, const Node *n, cairo_surface_t *pic, double fps);

/* Draw the window-level children of [n] onto [target] ([w] x [h]). */
static void render_children(Renderer *r, const Node *n, cairo_surface_t *target, int w, int h,
                            Refs *refs, double fps)
{
    for (size_t i = 0; i < rnode_nchildren(n); i++) {
        const Node *c = rnode_child(n, i);
        cairo_surface_t *pic = NULL;
        if (rnode_is(c, "canvas")) {
            int cw, ch;
            size_of(c, w, h, &cw, &ch);
            pic = new_picture(cw, ch);
            cairo_t *cr = cairo_create(pic);
            CanvasEnv env = {.symbols = r->symbols, .skips = &r->skips};
            canvas_draw(cr, c, &env);
            cairo_destroy(cr);
        } else if (rnode_is(c, "record")) {
            int cw, ch;
            size_of(c, w, h, &cw, &ch);
            pic = new_picture(cw, ch);
            render_children(r, c, pic, cw, ch, refs, fps);
            write_record(r, c, pic, fps);
        } else if (rnode_is(c, "reference")) {
            const Vec *id = rnode_attr(c, "id");
            for (int k = 0; id && k < refs->n; k++)
                if (vec_equal(refs->id[k], id)) {
                    composite(target, refs->pic[k]);
                    break;
                }
            continue;
        } else if (rnode_nchildren(c) > 0 && !rnode_is(c, "canvas3d")) {
            /* an effect (!shader, !bloom, !feedback, ...): its input drawn as is */
            skiplog_effect(&r->skips, rnode_kind(c));
            int cw, ch;
            size_of(c, w, h, &cw, &ch);
            pic = new_picture(cw, ch);
            render_children(r, c, pic, cw, ch, refs, fps);
        } else {
            skiplog_note(&r->skips, "window", rnode_kind(c));
            continue;
        }
        composite(target, pic);
        const Vec *id = rnode_attr(c, "id");
        if (id && refs->n < 64) {
            refs->id[refs->n] = id;
            refs->pic[refs->n++] = pic;
        } else {
            cairo_surface_destroy(pic);
        }
    }
}

static bool ends_with(const char *s, const char *tail)
{
    size_t a = strlen(s), b = strlen(tail);
    return a >= b && strcasecmp(s + a - b, tail) == 0;
}

static void report(Renderer *r, const char *msg, const char *path)
{
    if (r->failed_reported++ == 0) render_log(&r->log, RLOG_ERROR, "%s: %s", path, msg);
}

static void write_record(Renderer *r, const Node *n, cairo_surface_t *pic, double fps)
{
    Buf name = BUF_INIT, codec = BUF_INIT;
    if (!canvas_attr_str(n, "filename", r->symbols, &name) || name.len == 0) goto done;
    const char *path = buf_cstr(&name);
    /* a .png name stays a still picture whatever the codec (as in Flitter) */
    bool gif = ends_with(path, ".gif") ||
               (!ends_with(path, ".png") && canvas_attr_str(n, "codec", r->symbols, &codec) &&
                strcmp(buf_cstr(&codec), "gif") == 0);
    if (!gif && !ends_with(path, ".png")) {   /* not a PNG under another name */
        report(r, "only .png pictures and .gif animations are written; !record skipped", path);
        goto done;
    }
    cairo_surface_flush(pic);
    int w = cairo_image_surface_get_width(pic), h = cairo_image_surface_get_height(pic);
    if (gif) {
        GifSlot *slot = NULL;
        for (size_t i = 0; i < r->ngifs; i++)
            if (strcmp(r->gifs[i].path, path) == 0) slot = &r->gifs[i];
        if (!slot) {
            char err[512];
            double cs = 100.0 / fps;   /* GIF delays are 1..65535 hundredths of a second */
            int delay = cs >= 65535 ? 65535 : cs <= 1 ? 1 : (int)lround(cs);
            GifOut *g = gifout_open(path, w, h, delay, err, sizeof err);
            if (!g) {
                report(r, "cannot create the GIF file", path);
                goto done;
            }
            r->gifs = realloc(r->gifs, (r->ngifs + 1) * sizeof *r->gifs);
            if (!r->gifs) mem_oom();
            slot = &r->gifs[r->ngifs++];
            slot->path = strdup(path);
            slot->gif = g;
        }
        if (gifout_frame(slot->gif, cairo_image_surface_get_data(pic), cairo_image_surface_get_stride(pic)) != 0)
            report(r, "cannot write a GIF frame", path);
    } else {
        cairo_status_t st;
        if (rnode_attr(n, "keep_alpha") && vec_truthy(rnode_attr(n, "keep_alpha"))) {
            st = cairo_surface_write_to_png(pic, path);
        } else {   /* opaque: premultiplied colour over black */
            cairo_surface_t *rgb = cairo_image_surface_create(CAIRO_FORMAT_RGB24, w, h);
            composite(rgb, pic);
            st = cairo_surface_write_to_png(rgb, path);
            cairo_surface_destroy(rgb);
        }
        if (st != CAIRO_STATUS_SUCCESS) report(r, cairo_status_to_string(st), path);
    }
done:
    buf_free(&name);
    buf_free(&codec);
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

int renderer_frame(Renderer *r, const Node *root, double fps)
{
    int before = r->failed_reported;
    for (size_t i = 0; root && i < rnode_nchildren(root); i++) {
        const Node *win = rnode_child(root, i);
        if (!rnode_is(win, "window") && !rnode_is(win, "offscreen")) continue;
        r->saw_window = true;
        if (!has_record(win)) continue;
        int w, h;
        size_of(win, 512, 512, &w, &h);
        cairo_surface_t *pic = new_picture(w, h);
        Refs refs = {.n = 0};
        render_children(r, win, pic, w, h, &refs, fps);
        for (int k = 0; k < refs.n; k++) cairo_surface_destroy(refs.pic[k]);
        cairo_surface_destroy(pic);
    }
    return r->failed_reported - before;
}
