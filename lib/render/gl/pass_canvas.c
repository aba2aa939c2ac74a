/* pass_canvas.c: the `!canvas` pass (Flitter docs/canvas.md;
 * render/window/canvas.pyx, Canvas): the 2D tree drawn with cairo
 * (canvas.h) into a picture of the pass's size, uploaded into an 8-bit
 * texture: sRGB-encoded, so that the passes above it read linear light,
 * or, for `linear=true`, holding linear values as they are. The picture
 * and the texture stay from frame to frame. */
#include <stdlib.h>
#include <string.h>

#include "graph_internal.h"
#include "mem.h"
#include "rnode.h"

/* last: they turn the libraries' names into calls through their tables */
#include "cairo_lib.h"
#include "gl_lib.h"

typedef struct CanvasPass {
    Pass base;
    cairo_surface_t *pic;    /* drawn each frame, kept for the next */
    uint32_t *rows;          /* the picture bottom row first, for GL */
    size_t caprows;
} CanvasPass;

/* Upload [pic] into [t]'s texture, its rows in GL's order. */
static void upload(CanvasPass *cp, cairo_surface_t *pic, GlTarget *t)
{
    int w = t->w, h = t->h, stride = cairo_image_surface_get_stride(pic);
    const unsigned char *data = cairo_image_surface_get_data(pic);
    size_t n = (size_t)w * (size_t)h;
    if (n > cp->caprows) {
        free(cp->rows);
        cp->rows = mem_alloc(n * sizeof *cp->rows);
        cp->caprows = n;
    }
    for (int y = 0; y < h; y++) memcpy(cp->rows + (size_t)(h - 1 - y) * (size_t)w, data + (size_t)y * (size_t)stride, (size_t)w * 4);
    glBindTexture(GL_TEXTURE_2D, t->tex);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, w, h, GL_BGRA, GL_UNSIGNED_INT_8_8_8_8_REV, cp->rows);
    glBindTexture(GL_TEXTURE_2D, 0);
}

static void render_canvas(Graph *g, Pass *p, const Node *n, const PassCtx *cx)
{
    (void)cx;
    CanvasPass *cp = (CanvasPass *)p;
    bool linear = canvas_is_linear(n);
    int w = p->w, h = p->h;
    if (p->target && (p->target->w != w || p->target->h != h || p->target->srgb == linear)) {
        target_release(g->pool, p->target);
        p->target = NULL;
    }
    if (!p->target) p->target = graph_target(g, w, h, 8, !linear, false, 0);
    /* (kept from frame to frame by its `finished`; a parent that only
     * copies it may take it over unless an id names it) */
    p->retain = p->has_id;
    if (!p->target) return;
    if (cp->pic && (cairo_image_surface_get_width(cp->pic) != w || cairo_image_surface_get_height(cp->pic) != h)) {
        cairo_surface_destroy(cp->pic);
        cp->pic = NULL;
    }
    if (!cp->pic) {
        cp->pic = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, w, h);
        if (cairo_surface_status(cp->pic) != CAIRO_STATUS_SUCCESS) {
            graph_note(g, RLOG_ERROR, "canvas: cannot make a %dx%d picture: %s", w, h,
                       cairo_status_to_string(cairo_surface_status(cp->pic)));
            cairo_surface_destroy(cp->pic);
            cp->pic = NULL;
            return;
        }
    }
    cairo_t *cr = cairo_create(cp->pic);
    cairo_set_operator(cr, CAIRO_OPERATOR_CLEAR);
    cairo_paint(cr);
    cairo_set_operator(cr, CAIRO_OPERATOR_OVER);
    /* at the frame's scale: drawn in Flitter's pixels all the same */
    if (w != p->lw || h != p->lh) cairo_scale(cr, (double)w / p->lw, (double)h / p->lh);
    CanvasEnv env = {.symbols = g->env.symbols, .skips = &g->skips, .linear = linear,
                     .interrupt = g->env.interrupt};
    graph_canvas_images(g, &env);
    bool whole = canvas_draw(cr, n, &env);
    cairo_destroy(cr);
    if (!whole) {   /* interrupted in a long draw, still writing it: dropped, not shown */
        cairo_surface_destroy(cp->pic);
        cp->pic = NULL;
        return;
    }
    cairo_surface_flush(cp->pic);
    upload(cp, cp->pic, p->target);
}

static void release_canvas(Graph *g, Pass *p)
{
    (void)g;
    CanvasPass *cp = (CanvasPass *)p;
    if (cp->pic) cairo_surface_destroy(cp->pic);
    free(cp->rows);
}

/* its picture stays */
static void keep(Graph *g, Pass *p)
{
    (void)g;
    (void)p;
}

const PassKind pass_canvas = {.kind = "canvas", .size = sizeof(CanvasPass), .leaf = true, .render = render_canvas,
                              .release = release_canvas, .finished = keep};
