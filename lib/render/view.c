/* view.c: pictures of physics systems (see view.h). */
#include "view.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include <cairo-svg.h>
#include <cairo.h>

#include "buf.h"
#include "format.h"
#include "gifout.h"
#include "mem.h"

enum { PANEL = 480, PANEL_1D = 160, MARGIN = 24, TITLE = 28, MAX_PANELS = 16 };
enum { FMT_PNG, FMT_SVG, FMT_GIF };

typedef struct Bounds {
    bool valid;
    double x0, x1, y0, y1;
} Bounds;

struct View {
    char *path;
    int format, delay;
    const SymTab *symbols;
    int npanels;               /* fixed by the first frame (0 before) */
    int pw[MAX_PANELS], ph[MAX_PANELS];
    int width, height;
    Bounds fit[MAX_PANELS];
    GifOut *gif;
};

static bool ends_with(const char *s, const char *tail)
{
    size_t a = strlen(s), b = strlen(tail);
    return a >= b && strcasecmp(s + a - b, tail) == 0;
}

View *view_open(const char *path, int delay_cs, const SymTab *symbols, char *err, size_t errlen)
{
    int format;
    if (ends_with(path, ".png")) format = FMT_PNG;
    else if (ends_with(path, ".svg")) format = FMT_SVG;
    else if (ends_with(path, ".gif")) format = FMT_GIF;
    else {
        snprintf(err, errlen, "%s: a view is written to a .png, .svg or .gif file", path);
        return NULL;
    }
    View *v = calloc(1, sizeof *v);
    if (!v || !(v->path = strdup(path))) mem_oom();
    v->format = format;
    v->delay = delay_cs < 1 ? 1 : delay_cs;
    v->symbols = symbols;
    return v;
}

bool view_animated(const View *v) { return v->format == FMT_GIF; }

int view_close(View *v)
{
    if (!v) return 0;
    int rc = gifout_close(v->gif);
    free(v->path);
    free(v);
    return rc;
}

/* Projected x/y of a position (1D: y = 0). */
static void project(const Vec *pos, double *x, double *y)
{
    *x = ps_coord(pos, 0);
    *y = ps_coord(pos, 1);
}

static bool finite2(double x, double y) { return isfinite(x) && isfinite(y); }

static Bounds bounds_of(const PsSystem *s)
{
    Bounds b = {0};
    for (size_t i = 0; i < s->nbodies; i++) {
        const PsBody *p = &s->bodies[i];
        if (!p->pos) continue;
        double x, y, r = p->radius;
        project(p->pos, &x, &y);
        if (s->dims == 1) y = 0;
        if (!finite2(x, y) || !isfinite(r)) continue;
        if (!b.valid) {
            b = (Bounds){true, x - r, x + r, y - r, y + r};
        } else {
            b.x0 = fmin(b.x0, x - r);
            b.x1 = fmax(b.x1, x + r);
            b.y0 = fmin(b.y0, y - r);
            b.y1 = fmax(b.y1, y + r);
        }
    }
    return b;
}

/* Charge colour: grey at 0, red towards +max, blue towards -max. */
static void charge_colour(double q, double qmax, double rgb[3])
{
    static const double grey[3] = {0.55, 0.55, 0.55}, red[3] = {0.85, 0.15, 0.1},
                        blue[3] = {0.1, 0.3, 0.85};
    double t = qmax > 0 && isfinite(q) ? fmin(fabs(q) / qmax, 1) : 0;
    const double *to = q > 0 ? red : blue;
    for (int k = 0; k < 3; k++) rgb[k] = grey[k] + t * (to[k] - grey[k]);
}

static void draw_panel(View *v, cairo_t *cr, int index, long frame, const PsSystem *s)
{
    int w = v->pw[index], h = v->ph[index];
    /* title */
    Buf title = BUF_INIT;
    fmt_str(&title, s->prefix, v->symbols);
    size_t np = 0;
    for (size_t i = 0; i < s->nbodies; i++) np += !s->bodies[i].anchor;
    buf_printf(&title, "  %dD  %zu particles", s->dims, np);
    if (v->format == FMT_GIF) buf_printf(&title, "  frame %ld", frame);
    cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, 14);
    cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
    cairo_move_to(cr, 8, 19);
    cairo_show_text(cr, buf_cstr(&title));
    buf_free(&title);
    /* frame of the panel */
    cairo_set_line_width(cr, 1);
    cairo_set_source_rgb(cr, 0.8, 0.8, 0.8);
    cairo_rectangle(cr, 0.5, TITLE + 0.5, w - 1, h - TITLE - 1);
    cairo_stroke(cr);

    Bounds now = bounds_of(s), *b = &v->fit[index];
    if (now.valid) {
        if (v->format == FMT_GIF && b->valid) {
            b->x0 = fmin(b->x0, now.x0);
            b->x1 = fmax(b->x1, now.x1);
            b->y0 = fmin(b->y0, now.y0);
            b->y1 = fmax(b->y1, now.y1);
        } else {
            *b = now;
        }
    }
    if (!b->valid) return;
    double bw = b->x1 - b->x0, bh = b->y1 - b->y0;
    if (!(bw > 0)) bw = 1;
    if (!(bh > 0)) bh = 1;
    double aw = w - 2 * MARGIN, ah = h - TITLE - 2 * MARGIN;
    double scale = fmin(aw / bw, ah / bh);
    if (!isfinite(scale) || scale <= 0) return;
    double cx = (b->x0 + b->x1) / 2, cy = (b->y0 + b->y1) / 2;
    cairo_save(cr);
    cairo_rectangle(cr, 1, TITLE + 1, w - 2, h - TITLE - 2);
    cairo_clip(cr);
    cairo_translate(cr, w / 2.0, TITLE + (h - TITLE) / 2.0);
    /* world -> panel; the world's y axis points down, as on a Flitter canvas */
    cairo_scale(cr, scale, scale);
    cairo_translate(cr, -cx, -cy);
    double px = 1 / scale;   /* one pixel in world units */
    if (s->dims == 1) {
        cairo_set_source_rgb(cr, 0.75, 0.75, 0.75);
        cairo_set_line_width(cr, px);
        cairo_move_to(cr, b->x0 - bw, 0);
        cairo_line_to(cr, b->x1 + bw, 0);
        cairo_stroke(cr);
    }
    /* barriers */
    double reach = 4 * (bw + bh);
    cairo_set_source_rgb(cr, 0.15, 0.15, 0.15);
    cairo_set_line_width(cr, 3 * px);
    for (size_t i = 0; i < s->nbarriers; i++) {
        double x, y, nx, ny;
        if (!s->barriers[i].pos || !s->barriers[i].normal) continue;
        project(s->barriers[i].pos, &x, &y);
        project(s->barriers[i].normal, &nx, &ny);
        if (s->dims == 1) {
            cairo_move_to(cr, x, -reach);
            cairo_line_to(cr, x, reach);
        } else {
            double len = hypot(nx, ny);
            if (!(len > 0) || !finite2(x, y)) continue;
            double dx = -ny / len, dy = nx / len;
            cairo_move_to(cr, x - reach * dx, y - reach * dy);
            cairo_line_to(cr, x + reach * dx, y + reach * dy);
        }
        cairo_stroke(cr);
    }
    /* distance links */
    cairo_set_source_rgb(cr, 0.78, 0.78, 0.78);
    cairo_set_line_width(cr, px);
    for (size_t i = 0; i < s->nlinks; i++) {
        double x0, y0, x1, y1;
        if (!s->links[i].from || !s->links[i].to) continue;
        project(s->links[i].from, &x0, &y0);
        project(s->links[i].to, &x1, &y1);
        if (s->dims == 1) y0 = y1 = 0;
        if (!finite2(x0, y0) || !finite2(x1, y1)) continue;
        cairo_move_to(cr, x0, y0);
        cairo_line_to(cr, x1, y1);
        cairo_stroke(cr);
    }
    /* particles, then anchors on top */
    double qmax = 0;
    for (size_t i = 0; i < s->nbodies; i++)
        if (isfinite(s->bodies[i].charge)) qmax = fmax(qmax, fabs(s->bodies[i].charge));
    for (int pass = 0; pass < 2; pass++)
        for (size_t i = 0; i < s->nbodies; i++) {
            const PsBody *p = &s->bodies[i];
            if (p->anchor != (pass == 1) || !p->pos) continue;
            double x, y;
            project(p->pos, &x, &y);
            if (s->dims == 1) y = 0;
            if (!finite2(x, y)) continue;
            if (p->anchor) {
                if (p->radius > px) {   /* an anchor with a body: a pale disc under the cross */
                    cairo_new_sub_path(cr);
                    cairo_arc(cr, x, y, p->radius, 0, 2 * M_PI);
                    cairo_set_source_rgb(cr, 0.88, 0.88, 0.88);
                    cairo_fill_preserve(cr);
                    cairo_set_source_rgb(cr, 0.3, 0.3, 0.3);
                    cairo_set_line_width(cr, px);
                    cairo_stroke(cr);
                }
                double a = 6 * px;
                cairo_set_source_rgb(cr, 0, 0, 0);
                cairo_set_line_width(cr, 2 * px);
                cairo_move_to(cr, x - a, y - a);
                cairo_line_to(cr, x + a, y + a);
                cairo_move_to(cr, x - a, y + a);
                cairo_line_to(cr, x + a, y - a);
                cairo_stroke(cr);
                continue;
            }
            double rgb[3], r = p->radius > px ? p->radius : 2 * px;
            charge_colour(p->charge, qmax, rgb);
            cairo_new_sub_path(cr);
            cairo_arc(cr, x, y, r, 0, 2 * M_PI);
            cairo_set_source_rgb(cr, rgb[0], rgb[1], rgb[2]);
            cairo_fill_preserve(cr);
            cairo_set_source_rgba(cr, 0, 0, 0, 0.5);
            cairo_set_line_width(cr, px);
            cairo_stroke(cr);
        }
    cairo_restore(cr);
}

static void draw_all(View *v, cairo_t *cr, long frame, const PsSystem *systems, size_t n)
{
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
    int x = 0;
    for (int i = 0; i < v->npanels && (size_t)i < n; i++) {
        cairo_save(cr);
        cairo_translate(cr, x, 0);
        draw_panel(v, cr, i, frame, &systems[i]);
        cairo_restore(cr);
        x += v->pw[i];
    }
    if (n == 0) {
        cairo_set_source_rgb(cr, 0.3, 0.3, 0.3);
        cairo_set_font_size(cr, 14);
        cairo_move_to(cr, 8, 19);
        cairo_show_text(cr, "no !physics system");
    }
}

/* Fix [v]'s layout (panels and picture size) for [n] [systems]. */
static void lay_out(View *v, const PsSystem *systems, size_t n)
{
    v->npanels = n > MAX_PANELS ? MAX_PANELS : (int)n;
    v->height = v->npanels ? 0 : 40;
    v->width = v->npanels ? 0 : 240;
    for (int i = 0; i < v->npanels; i++) {
        v->pw[i] = PANEL;
        v->ph[i] = TITLE + (systems[i].dims == 1 ? PANEL_1D : PANEL);
        v->width += v->pw[i];
        if (v->ph[i] > v->height) v->height = v->ph[i];
    }
    for (int i = 0; i < v->npanels; i++) v->ph[i] = v->height;
}

size_t view_draw_fit(cairo_surface_t *target, const PsSystem *systems, size_t n, const SymTab *symbols)
{
    View v = {.format = FMT_PNG, .symbols = symbols};
    lay_out(&v, systems, n);
    double tw = cairo_image_surface_get_width(target), th = cairo_image_surface_get_height(target);
    double scale = fmin(tw / v.width, th / v.height);
    cairo_t *cr = cairo_create(target);
    cairo_set_source_rgb(cr, 0, 0, 0);   /* the bars beside a picture of another shape */
    cairo_paint(cr);
    cairo_translate(cr, (tw - v.width * scale) / 2, (th - v.height * scale) / 2);
    cairo_scale(cr, scale, scale);
    cairo_rectangle(cr, 0, 0, v.width, v.height);
    cairo_clip(cr);
    draw_all(&v, cr, 0, systems, n);
    cairo_destroy(cr);
    cairo_surface_flush(target);
    return (size_t)v.npanels;
}

int view_frame(View *v, long frame, const PsSystem *systems, size_t n, char *err, size_t errlen)
{
    if (v->npanels == 0 && v->width == 0) lay_out(v, systems, n);   /* fix the layout */
    cairo_surface_t *surf;
    if (v->format == FMT_SVG) surf = cairo_svg_surface_create(v->path, v->width, v->height);
    else surf = cairo_image_surface_create(CAIRO_FORMAT_RGB24, v->width, v->height);
    cairo_t *cr = cairo_create(surf);
    draw_all(v, cr, frame, systems, n);
    cairo_destroy(cr);
    int rc = 0;
    if (v->format == FMT_SVG) {
        cairo_surface_finish(surf);
        if (cairo_surface_status(surf) != CAIRO_STATUS_SUCCESS) {
            snprintf(err, errlen, "%s: %s", v->path, cairo_status_to_string(cairo_surface_status(surf)));
            rc = -1;
        }
    } else if (v->format == FMT_PNG) {
        cairo_status_t st = cairo_surface_write_to_png(surf, v->path);
        if (st != CAIRO_STATUS_SUCCESS) {
            snprintf(err, errlen, "%s: %s", v->path, cairo_status_to_string(st));
            rc = -1;
        }
    } else {
        cairo_surface_flush(surf);
        if (!v->gif) v->gif = gifout_open(v->path, v->width, v->height, v->delay, err, errlen);
        if (!v->gif) {
            rc = -1;
        } else if (gifout_frame(v->gif, cairo_image_surface_get_data(surf),
                                cairo_image_surface_get_stride(surf)) != 0) {
            snprintf(err, errlen, "%s: cannot write a GIF frame", v->path);
            rc = -1;
        }
    }
    cairo_surface_destroy(surf);
    return rc;
}
