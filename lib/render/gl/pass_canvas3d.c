/* pass_canvas3d.c: the `!canvas3d` pass (Flitter docs/canvas3d.md;
 * render/window/canvas3d.pyx, Canvas3D.render): the scene walked once
 * (canvas3d.h), drawn through the canvas's camera (its own, or the one
 * camera_id= names) into a framebuffer of that camera's size, colour depth
 * and samples, with a depth buffer; then through each other camera with an
 * id and secondary=true into one of its own, registered under its id for
 * references and textures. The pictures stay until the next frame's. */
#include <string.h>
#include <time.h>

#include "canvas3d.h"
#include "geom_model.h"
#include "graph_internal.h"

/* Flitter's --modelcache default, seconds */
#define MODEL_CACHE_DEFAULT 300

static void note_line(void *ctx, const char *line) { graph_note(ctx, RLOG_ERROR, "%s", line); }

/* The models, made the first time, begun for this frame. */
static GeomModels *models_of(Graph *g)
{
    if (!g->models) {
        GeomEnv env = {.symbols = g->env.symbols, .budget = g->env.budget, .interrupt = g->env.interrupt,
                       .error = note_line, .error_ctx = g, .distance = g->env.distance, .function_key = g->env.function_key,
                       .ctx = g->env.ctx};
        g->models = geom_models_new(&env);
    }
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    double age = g->env.model_cache > 0 ? g->env.model_cache : MODEL_CACHE_DEFAULT;
    geom_models_frame(g->models, g->f ? g->f->folder : NULL, (double)ts.tv_sec + ts.tv_nsec * 1e-9, age);
    return g->models;
}

typedef struct C3dPass {
    Pass base;
    GlTarget *cameras[16];   /* the secondary cameras' pictures, by camera index */
    int ncameras;
} C3dPass;

static void drop(Graph *g, C3dPass *cp)
{
    for (int i = 0; i < cp->ncameras; i++) {
        target_release(g->pool, cp->cameras[i]);
        cp->cameras[i] = NULL;
    }
    cp->ncameras = 0;
}

/* Draw camera [i] into a new target, or NULL (logged once). */
static GlTarget *draw_camera(Graph *g, int i)
{
    C3dCameraInfo info;
    canvas3d_camera(g->c3d, i, &info);
    /* at the frame's scale and cap on samples (the camera's matrices are
     * those of its full size: the same picture at fewer pixels) */
    int samples = g->draw_samples && info.samples > g->draw_samples ? g->draw_samples : info.samples;
    if (samples < 2) samples = 0;
    GlTarget *t = graph_target(g, graph_scaled(g, info.width), graph_scaled(g, info.height), info.colorbits, false, true,
                               samples);
    if (!t) return NULL;
    Buf err = BUF_INIT;
    if (canvas3d_draw(g->c3d, i, t, &g->env.log, &err) != 0) graph_note(g, RLOG_ERROR, "canvas3d: %s", buf_line(&err));
    buf_free(&err);
    return t;
}

static void render_canvas3d(Graph *g, Pass *p, const Node *n, const PassCtx *cx)
{
    C3dPass *cp = (C3dPass *)p;
    if (!g->c3d) g->c3d = canvas3d_new(&g->env.c3d);
    canvas3d_set_models(g->c3d, models_of(g), g->env.budget, note_line, g);
    CanvasEnv env = {.symbols = g->env.symbols, .skips = &g->skips, .interrupt = g->env.interrupt};
    graph_canvas_images(g, &env);
    int primary;
    int ncams = canvas3d_scene(g->c3d, n, p->lw, p->lh, cx->colorbits, &env, &primary);
    target_release(g->pool, p->target);
    drop(g, cp);
    p->target = draw_camera(g, primary);
    C3dCameraInfo info;
    canvas3d_camera(g->c3d, primary, &info);
    /* kept for the frame while an id names it (its own, or its camera's);
     * else a parent that only copies it may take it over */
    p->retain = p->has_id || info.id;
    if (info.id) graph_register(g, info.id, p, -1);
    for (int i = 0; i < ncams && i < 16; i++) {
        canvas3d_camera(g->c3d, i, &info);
        if (i == primary || !info.secondary || !info.id) continue;
        cp->cameras[i] = draw_camera(g, i);
        if (i >= cp->ncameras) cp->ncameras = i + 1;
        graph_register(g, info.id, p, i);
    }
}

GLuint pass_canvas3d_camera(Graph *g, Pass *p, int camera, int *w, int *h)
{
    (void)g;
    C3dPass *cp = (C3dPass *)p;
    if (p->kind != &pass_canvas3d || camera < 0 || camera >= cp->ncameras || !cp->cameras[camera]) return 0;
    *w = cp->cameras[camera]->w;
    *h = cp->cameras[camera]->h;
    return cp->cameras[camera]->tex;
}

static void release_canvas3d(Graph *g, Pass *p) { drop(g, (C3dPass *)p); }

/* its pictures stay until its next drawing */
static void keep(Graph *g, Pass *p)
{
    (void)g;
    (void)p;
}

void pass_canvas3d_free(Graph *g)
{
    canvas3d_free(g->c3d);
    g->c3d = NULL;
    geom_models_free(g->models);
    g->models = NULL;
}

const PassKind pass_canvas3d = {.kind = "canvas3d", .size = sizeof(C3dPass), .leaf = true,
                                .render = render_canvas3d, .release = release_canvas3d, .finished = keep};
