/* scene_picture.c: a shapes scene drawn into a cairo picture (see
 * scene_picture.h): drawn into a half-float framebuffer, read back as
 * floats and sRGB-encoded as the window encodes its output
 * (srgb_encode_surface). */
#include "scene_picture.h"

#include <stdio.h>
#include <stdlib.h>

#include "gl_context.h"
#include "gl_target.h"
#include "mem.h"
#include "srgb.h"

/* last: they turn the libraries' names into calls through their tables */
#include "cairo_lib.h"
#include "gl_lib.h"

struct ScenePicture {
    GlContext *gl;
    bool failed;             /* no context: said once */
    TargetPool *pool;
    Canvas3D *c3d;
    SrgbTable srgb;
    float *px;
    size_t cap;
};

ScenePicture *scene_picture_new(void)
{
    ScenePicture *sp = mem_calloc(1, sizeof *sp);
    srgb_table_init(&sp->srgb);
    return sp;
}

int scene_picture_draw(ScenePicture *sp, const C3dScene *s, cairo_surface_t *pic, Buf *err)
{
    if (sp->failed) return -1;
    if (!sp->gl) {
        Buf why = BUF_INIT;
        sp->gl = gl_context_new(&why);
        if (!sp->gl) {
            sp->failed = true;
            buf_printf(err, "canvas3d: no OpenGL (%s)\n", buf_line(&why));
        }
        buf_free(&why);
        if (!sp->gl) return -1;
        sp->pool = target_pool_new(sp->gl, NULL);
        sp->c3d = canvas3d_new(NULL);
    } else if (!gl_context_use(sp->gl)) {
        buf_printf(err, "the OpenGL context cannot be made current\n");
        return -1;
    }
    int w = cairo_image_surface_get_width(pic), h = cairo_image_surface_get_height(pic);
    GlTarget *t = target_get(sp->pool, w, h, 16, false, true, s->samples, err);
    int rc = -1;
    if (t) {
        rc = canvas3d_draw_scene(sp->c3d, s, t, err);
        size_t n = (size_t)w * (size_t)h * 4;
        if (n > sp->cap) {
            free(sp->px);
            sp->px = mem_alloc(n * sizeof *sp->px);
            sp->cap = n;
        }
        target_readf(t, sp->px);
        target_release(sp->pool, t);
        srgb_encode_surface(&sp->srgb, sp->px, w, h, pic);
    }
    gl_context_done(sp->gl);
    return rc;
}

void scene_picture_free(ScenePicture *sp)
{
    if (!sp) return;
    if (sp->gl && gl_context_use(sp->gl)) {
        canvas3d_free(sp->c3d);
        target_pool_free(sp->pool);
    }
    gl_context_free(sp->gl);
    free(sp->px);
    free(sp);
}
