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
#include "canvas3d.h"
#include "scene_picture.h"
#include "format.h"
#include "gifout.h"
#include "mat4.h"
#include "mem.h"
#include "srgb.h"

/* last: it turns the library's names into calls through its table */
#include "cairo_lib.h"

enum { PANEL = 480, PANEL_1D = 160, MARGIN = 24, TITLE = 28, MAX_PANELS = 16 };
enum { FMT_PNG, FMT_SVG, FMT_GIF };

typedef struct Bounds {
    bool valid;
    double x0, x1, y0, y1;
} Bounds;

/* The box of a 3D system's bodies (positions +- radius). */
typedef struct Bounds3 {
    bool valid;
    double lo[3], hi[3];
} Bounds3;

struct View {
    char *path;                /* NULL: a view drawn by view_draw_fit only */
    int format, delay;
    const SymTab *symbols;
    int npanels;               /* fixed by the first frame (0 before) */
    int pw[MAX_PANELS], ph[MAX_PANELS];
    int width, height;
    Bounds fit[MAX_PANELS];
    Bounds3 fit3[MAX_PANELS];
    GifOut *gif;
    int axes[2];               /* the flat projection asked for ({0, 0}: none) */
    RenderLog log;             /* where "3D systems drawn flat" goes */
    bool flat_said;            /* ... said once */
    ScenePicture *gl;          /* the 3D panels' renderer (made when first needed) */
    cairo_surface_t *pic3d;    /* a 3D panel's picture, reused */
    C3dItem *items;            /* a 3D panel's shapes, reused */
    size_t cap_items;
};

static bool ends_with(const char *s, const char *tail)
{
    size_t a = strlen(s), b = strlen(tail);
    return a >= b && strcasecmp(s + a - b, tail) == 0;
}

View *view_open(const char *path, int delay_cs, const SymTab *symbols, Buf *err)
{
    int format;
    if (ends_with(path, ".png")) format = FMT_PNG;
    else if (ends_with(path, ".svg")) format = FMT_SVG;
    else if (ends_with(path, ".gif")) format = FMT_GIF;
    else {
        buf_printf(err, "%s: a view is written to a .png, .svg or .gif file\n", path);
        return NULL;
    }
    View *v = mem_calloc(1, sizeof *v);
    v->path = mem_strdup(path);
    v->format = format;
    v->delay = delay_cs < 1 ? 1 : delay_cs;
    v->symbols = symbols;
    return v;
}

View *view_new_fit(const SymTab *symbols)
{
    View *v = mem_calloc(1, sizeof *v);
    v->format = FMT_PNG;
    v->symbols = symbols;
    return v;
}

void view_set_style(View *v, const int axes[2], const RenderLog *log)
{
    bool ok = axes && axes[0] >= 0 && axes[0] <= 3 && axes[1] >= 0 && axes[1] <= 3 && axes[0] != axes[1];
    v->axes[0] = ok ? axes[0] : 0;
    v->axes[1] = ok ? axes[1] : 0;
    v->log = log ? *log : (RenderLog){0};
}

bool view_animated(const View *v) { return v->format == FMT_GIF; }

int view_close(View *v)
{
    if (!v) return 0;
    int rc = gifout_close(v->gif);
    scene_picture_free(v->gl);
    if (v->pic3d) cairo_surface_destroy(v->pic3d);
    free(v->items);
    free(v->path);
    free(v);
    return rc;
}

static const char AXIS_NAMES[] = "xyzw";

bool view_parse_axes(const char *text, int axes[2])
{
    if (!text || strlen(text) != 3 || text[1] != ';') return false;
    const char *a = strchr(AXIS_NAMES, text[0]), *b = strchr(AXIS_NAMES, text[2]);
    if (!a || !b || !text[0] || !text[2] || a == b) return false;
    axes[0] = (int)(a - AXIS_NAMES);
    axes[1] = (int)(b - AXIS_NAMES);
    return true;
}

/* How system [s] is drawn: true in 3D (a 3D system without an applicable
 * flat projection asked for); else false with the two coordinates of its
 * flat projection in [ax]: the ones asked for when the system has both,
 * else x and y. */
static bool axes_of(const int axes[2], const PsSystem *s, int ax[2])
{
    bool asked = axes[0] != axes[1] && axes[0] < s->dims && axes[1] < s->dims;   /* 0..3 */
    ax[0] = asked ? axes[0] : 0;
    ax[1] = asked ? axes[1] : 1;
    return s->dims == 3 && !asked;
}

static bool panel_axes(const View *v, const PsSystem *s, int ax[2]) { return axes_of(v->axes, s, ax); }

bool view_draws_3d(const int axes[2], const PsSystem *systems, size_t n)
{
    /* the projection view_set_style would take from [axes] */
    bool ok = axes && axes[0] >= 0 && axes[0] <= 3 && axes[1] >= 0 && axes[1] <= 3 && axes[0] != axes[1];
    int ax[2], use[2] = {ok ? axes[0] : 0, ok ? axes[1] : 0};
    for (size_t i = 0; i < n && i < MAX_PANELS; i++)   /* the systems a view shows */
        if (axes_of(use, &systems[i], ax)) return true;
    return false;
}

/* Projected x/y of a position on coordinates [ax] (1D: y = 0 is the
 * caller's). */
static void project(const Vec *pos, const int ax[2], double *x, double *y)
{
    *x = ps_coord(pos, ax[0]);
    *y = ps_coord(pos, ax[1]);
}

static bool finite2(double x, double y) { return isfinite(x) && isfinite(y); }

static Bounds bounds_of(const PsSystem *s, const int ax[2])
{
    Bounds b = {0};
    for (size_t i = 0; i < s->nbodies; i++) {
        const PsBody *p = &s->bodies[i];
        if (!p->pos) continue;
        double x, y, r = p->radius;
        project(p->pos, ax, &x, &y);
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

/* {===== 3D panels */

/* The camera looks at the middle of the bodies' box from this direction
 * (x right, y away, z up: seen from the front, right and above). */
static const double EYE[3] = {1, -2, 1};
/* Horizontal field of view in turns (the panels are square). */
#define FOV 0.125

static Bounds3 bounds3_of(const PsSystem *s)
{
    Bounds3 b = {0};
    for (size_t i = 0; i < s->nbodies; i++) {
        const PsBody *p = &s->bodies[i];
        if (!p->pos) continue;
        double x[3], r = p->radius;
        for (int k = 0; k < 3; k++) x[k] = ps_coord(p->pos, k);
        if (!isfinite(x[0]) || !isfinite(x[1]) || !isfinite(x[2]) || !isfinite(r)) continue;
        for (int k = 0; k < 3; k++) {
            double lo = x[k] - r, hi = x[k] + r;
            if (!isfinite(lo) || !isfinite(hi)) lo = hi = x[k];   /* a radius past the doubles */
            b.lo[k] = b.valid ? fmin(b.lo[k], lo) : lo;
            b.hi[k] = b.valid ? fmax(b.hi[k], hi) : hi;
        }
        b.valid = true;
    }
    return b;
}

static C3dItem *new_item(View *v, size_t *n, int shape, const M4 *m, const double rgb[3], double transparency)
{
    if (*n == v->cap_items) {
        v->cap_items = v->cap_items ? 2 * v->cap_items : 64;
        v->items = mem_realloc_array(v->items, v->cap_items, sizeof *v->items);
    }
    C3dItem *it = &v->items[(*n)++];
    it->shape = shape;
    memcpy(it->model, m->m, sizeof it->model);
    for (int k = 0; k < 3; k++) it->color[k] = srgb_decode(rgb[k]);   /* the flat view's colours, as light */
    it->transparency = transparency;
    return it;
}

/* The rotation taking z to the unit vector [u]. */
static M4 turn_z_to(const double u[3])
{
    double q[4] = {1 + u[2], -u[1], u[0], 0};   /* w;x;y;z: half the turn z -> u */
    if (q[0] < 1e-12) q[0] = 0, q[1] = 1, q[2] = 0, q[3] = 0;   /* -z: half a turn about x */
    return m4_quaternion(q);
}

/* An item of [shape] at [at], scaled by [size], turned z to [u] (NULL: not turned). */
static void put(View *v, size_t *n, int shape, const double at[3], const double size[3], const double *u,
                const double rgb[3], double transparency)
{
    M4 m = m4_translate(at), x;
    if (u) x = turn_z_to(u), m = m4_mul(&m, &x);
    x = m4_scale(size);
    m = m4_mul(&m, &x);
    new_item(v, n, shape, &m, rgb, transparency);
}

/* Draw the 3D system [s] in panel [index] through the canvas3d renderer:
 * false when it cannot (no OpenGL: said once), and the panel is then for
 * the flat view to draw. The scene is moved and scaled so that the bodies'
 * box (running, as the flat view's, in an animation) is centred on the
 * origin with a half-diagonal of 1, so that any finite positions give
 * single-precision numbers the GPU can take. */
static bool draw_panel_3d(View *v, cairo_t *cr, int index, const PsSystem *s)
{
    int w = v->pw[index], h = v->ph[index];
    Bounds3 now = bounds3_of(s), *b = &v->fit3[index];
    if (now.valid && v->format == FMT_GIF && b->valid) {
        for (int k = 0; k < 3; k++) b->lo[k] = fmin(b->lo[k], now.lo[k]), b->hi[k] = fmax(b->hi[k], now.hi[k]);
    } else if (now.valid || v->format != FMT_GIF) {
        *b = now;   /* a single picture has no history: it is fitted to itself alone */
    }
    if (!b->valid) return true;   /* no body to show: the panel stays empty, as a flat one would */
    /* the picture's size in device pixels (the panel inside its frame) */
    double aw = w - 2, ah = h - TITLE - 2, dw = aw, dh = ah;
    cairo_user_to_device_distance(cr, &dw, &dh);
    dw = fabs(dw), dh = fabs(dh);
    if (!(dw >= 1 && dh >= 1)) return true;
    int pw = dw > 8192 ? 8192 : (int)ceil(dw), ph = dh > 8192 ? 8192 : (int)ceil(dh);
    double c[3], half = 0;
    for (int k = 0; k < 3; k++) {
        c[k] = b->lo[k] / 2 + b->hi[k] / 2;
        double e = b->hi[k] / 2 - b->lo[k] / 2;
        half += e * e;
    }
    double R = sqrt(half);
    if (!(R > 0) || !isfinite(R)) R = 1;
    /* the camera: the box's bounding sphere (radius 1) just fills the narrower field of view */
    double aspect = (double)pw / ph, g = tan(M_PI * FOV);
    double gmin = aspect >= 1 ? g / aspect : g;
    double dist = sqrt(1 + gmin * gmin) / gmin;   /* 1 / sin(atan(gmin)) */
    double el = sqrt(EYE[0] * EYE[0] + EYE[1] * EYE[1] + EYE[2] * EYE[2]), e[3];
    for (int k = 0; k < 3; k++) e[k] = EYE[k] / el;
    C3dScene sc = {.position = {e[0] * dist, e[1] * dist, e[2] * dist}, .up = {0, 0, 1}, .fov = FOV,
                   .near = fmax(0.1, dist - 3), .far = dist + 3, .samples = 4, .ambient = {0.3, 0.3, 0.3},
                   .sun = {0.9, 0.9, 0.9}, .roughness = 0.5};
    /* the light comes from the camera's upper left, in front */
    double right[3] = {-e[1], e[0], 0};   /* forward (-e) cross up (z) */
    double rl = hypot(right[0], right[1]);
    for (int k = 0; k < 3; k++) right[k] /= rl;
    double up[3] = {right[1] * -e[2] - right[2] * -e[1], right[2] * -e[0] - right[0] * -e[2],
                    right[0] * -e[1] - right[1] * -e[0]};   /* right cross forward */
    for (int k = 0; k < 3; k++) sc.sun_direction[k] = right[k] - up[k] - e[k];
    double pxn = 2 * dist * g / pw;   /* one pixel at the middle, in scene units */
    size_t n = 0;
    /* particles and anchors, in scene units: (world - c) / R */
    double qmax = 0;
    for (size_t i = 0; i < s->nbodies; i++)
        if (isfinite(s->bodies[i].charge)) qmax = fmax(qmax, fabs(s->bodies[i].charge));
    static const double dark[3] = {0, 0, 0}, pale[3] = {0.88, 0.88, 0.88}, linkc[3] = {0.7, 0.7, 0.7},
                        barc[3] = {0.15, 0.15, 0.15};
    for (size_t i = 0; i < s->nbodies; i++) {
        const PsBody *p = &s->bodies[i];
        if (!p->pos) continue;
        double at[3];
        for (int k = 0; k < 3; k++) at[k] = (ps_coord(p->pos, k) - c[k]) / R;
        if (!isfinite(at[0]) || !isfinite(at[1]) || !isfinite(at[2]) || fabs(at[0]) + fabs(at[1]) + fabs(at[2]) > 1e6)
            continue;
        double r = isfinite(p->radius) ? fmin(p->radius / R, 1e3) : 0;
        if (!p->anchor) {
            double rgb[3];
            if (!(r > pxn)) r = 2 * pxn;
            charge_colour(p->charge, qmax, rgb);
            double size[3] = {r, r, r};
            put(v, &n, C3D_SHAPE_SPHERE, at, size, NULL, rgb, 0);
            continue;
        }
        /* an anchor: a dark cross along the three axes, in a pale glassy ball when it has a radius */
        double arm = 6 * pxn + (r > pxn ? r : 0), t = 2 * pxn;
        for (int k = 0; k < 3; k++) {
            double size[3] = {t, t, t};
            size[k] = 2 * arm;
            put(v, &n, C3D_SHAPE_BOX, at, size, NULL, dark, 0);
        }
        if (r > pxn) {
            double size[3] = {r, r, r};
            put(v, &n, C3D_SHAPE_SPHERE, at, size, NULL, pale, 0.6);
        }
    }
    /* !distance links: thin grey rods */
    for (size_t i = 0; i < s->nlinks; i++) {
        if (!s->links[i].from || !s->links[i].to) continue;
        double a[3], d[3], mid[3], len = 0;
        for (int k = 0; k < 3; k++) {
            a[k] = (ps_coord(s->links[i].from, k) - c[k]) / R;
            d[k] = (ps_coord(s->links[i].to, k) - c[k]) / R - a[k];
            len += d[k] * d[k];
        }
        len = sqrt(len);
        if (!(len > 0) || !isfinite(len) || len > 1e6) continue;
        for (int k = 0; k < 3; k++) mid[k] = a[k] + d[k] / 2, d[k] /= len;
        double size[3] = {0.75 * pxn, 0.75 * pxn, len};
        put(v, &n, C3D_SHAPE_CYLINDER, mid, size, d, linkc, 0);
    }
    /* barriers: dark glassy squares across the box's bounding sphere,
     * centred on the point of their plane nearest its middle, as wide as
     * the sphere's section there */
    for (size_t i = 0; i < s->nbarriers; i++) {
        if (!s->barriers[i].pos || !s->barriers[i].normal) continue;
        double nv[3], nl = 0, off = 0;
        for (int k = 0; k < 3; k++) nv[k] = ps_coord(s->barriers[i].normal, k), nl += nv[k] * nv[k];
        nl = sqrt(nl);
        if (!(nl > 0) || !isfinite(nl)) continue;
        for (int k = 0; k < 3; k++) nv[k] /= nl, off += (ps_coord(s->barriers[i].pos, k) - c[k]) / R * nv[k];
        if (!(fabs(off) < 1)) continue;   /* misses the box's bounding sphere */
        double side = 2 * sqrt(1 - fmin(off * off, 1)) + 8 * pxn;   /* the sphere's section, and a little */
        double at[3] = {off * nv[0], off * nv[1], off * nv[2]}, size[3] = {side, side, 2 * pxn};
        put(v, &n, C3D_SHAPE_BOX, at, size, nv, barc, 0.9);
    }
    sc.items = v->items;
    sc.nitems = n;
    if (!v->pic3d || cairo_image_surface_get_width(v->pic3d) != pw || cairo_image_surface_get_height(v->pic3d) != ph) {
        if (v->pic3d) cairo_surface_destroy(v->pic3d);
        v->pic3d = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, pw, ph);
        if (cairo_surface_status(v->pic3d) == CAIRO_STATUS_NO_MEMORY) mem_oom();
    }
    if (!v->gl) v->gl = scene_picture_new();
    Buf err = BUF_INIT;
    bool drawn = scene_picture_draw(v->gl, &sc, v->pic3d, &err) == 0;
    if (!drawn && !v->flat_said)
        render_log(&v->log, RLOG_WARNING, "view: 3D systems are drawn flat on x;y%s%s", err.len ? ": " : "",
                   buf_line(&err));
    buf_free(&err);
    if (!drawn) {
        v->flat_said = true;
        return false;
    }
    cairo_save(cr);
    cairo_rectangle(cr, 1, TITLE + 1, aw, ah);
    cairo_clip(cr);
    cairo_translate(cr, 1, TITLE + 1);
    cairo_scale(cr, aw / pw, ah / ph);
    cairo_set_source_surface(cr, v->pic3d, 0, 0);
    cairo_paint(cr);
    cairo_restore(cr);
    return true;
}

/* }===== */

static void draw_panel(View *v, cairo_t *cr, int index, long frame, const PsSystem *s)
{
    int w = v->pw[index], h = v->ph[index];
    int ax[2];
    bool solid = panel_axes(v, s, ax);
    /* title */
    Buf title = BUF_INIT;
    if (s->title) buf_puts(&title, s->title);   /* a frozen copy's (systems.h) */
    else fmt_str(&title, s->prefix, v->symbols);
    size_t np = 0;
    for (size_t i = 0; i < s->nbodies; i++) np += !s->bodies[i].anchor;
    buf_printf(&title, "  %dD  %zu particles", s->dims, np);
    if (!solid && s->dims >= 2 && (ax[0] != 0 || ax[1] != 1))
        buf_printf(&title, "  %c;%c", AXIS_NAMES[ax[0]], AXIS_NAMES[ax[1]]);
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

    if (solid && draw_panel_3d(v, cr, index, s)) return;
    Bounds now = bounds_of(s, ax), *b = &v->fit[index];
    if (now.valid && v->format == FMT_GIF && b->valid) {
        b->x0 = fmin(b->x0, now.x0);
        b->x1 = fmax(b->x1, now.x1);
        b->y0 = fmin(b->y0, now.y0);
        b->y1 = fmax(b->y1, now.y1);
    } else if (now.valid || v->format != FMT_GIF) {
        *b = now;   /* a single picture has no history: it is fitted to itself alone */
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
        project(s->barriers[i].pos, ax, &x, &y);
        project(s->barriers[i].normal, ax, &nx, &ny);
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
        project(s->links[i].from, ax, &x0, &y0);
        project(s->links[i].to, ax, &x1, &y1);
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
            project(p->pos, ax, &x, &y);
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

size_t view_draw_fit(View *v, cairo_surface_t *target, const PsSystem *systems, size_t n)
{
    v->npanels = v->width = v->height = 0;   /* laid out anew: the systems may have changed */
    lay_out(v, systems, n);
    double tw = cairo_image_surface_get_width(target), th = cairo_image_surface_get_height(target);
    double scale = fmin(tw / v->width, th / v->height);
    cairo_t *cr = cairo_create(target);
    cairo_set_source_rgb(cr, 0, 0, 0);   /* the bars beside a picture of another shape */
    cairo_paint(cr);
    cairo_translate(cr, (tw - v->width * scale) / 2, (th - v->height * scale) / 2);
    cairo_scale(cr, scale, scale);
    cairo_rectangle(cr, 0, 0, v->width, v->height);
    cairo_clip(cr);
    draw_all(v, cr, 0, systems, n);
    cairo_destroy(cr);
    cairo_surface_flush(target);
    return (size_t)v->npanels;
}

int view_frame(View *v, long frame, const PsSystem *systems, size_t n, Buf *err)
{
    if (!cairo_lib_ready(err)) return -1;
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
            buf_printf(err, "%s: %s\n", v->path, cairo_status_to_string(cairo_surface_status(surf)));
            rc = -1;
        }
    } else if (v->format == FMT_PNG) {
        cairo_status_t st = cairo_surface_write_to_png(surf, v->path);
        if (st != CAIRO_STATUS_SUCCESS) {
            buf_printf(err, "%s: %s\n", v->path, cairo_status_to_string(st));
            rc = -1;
        }
    } else {
        cairo_surface_flush(surf);
        if (!v->gif) v->gif = gifout_open(v->path, v->width, v->height, v->delay, err);
        if (!v->gif) {
            rc = -1;
        } else if (gifout_frame(v->gif, cairo_image_surface_get_data(surf),
                                cairo_image_surface_get_stride(surf)) != 0) {
            buf_printf(err, "%s: cannot write a GIF frame\n", v->path);
            rc = -1;
        }
    }
    cairo_surface_destroy(surf);
    return rc;
}
