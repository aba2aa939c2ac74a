/* canvas3d_occlusion.h: the occluders' framebuffer of `!canvas3d`.
 *
 * Why: with multisampling, llvmpipe runs a fragment shader for every
 * fragment a triangle covers, also where the early depth test has
 * rejected all of its samples (only without multisampling does it branch
 * past the shader for such a block); a mesh scene with overdraw pays its
 * whole lighting once per layer (bench/PROFILE.md,
 * "lib/render/gl/canvas3d_occlusion.h: the occluders drawn first"). It
 * does branch past the rest of a shader whose fragments have all been
 * discarded. So the opaque meshes of a render group are first drawn
 * depth only into this framebuffer (the same size and sample count as
 * the picture's), and the lighting program of those meshes (C3D_FRAG_
 * OCCLUDED) reads it and discards a fragment lying, at every sample of
 * its pixel, behind what this framebuffer holds there: such a fragment
 * would fail its depth test at every sample of the picture too, whatever
 * the order, since the picture's depth at a sample is at most the
 * occluders' there. The picture is the same, bit for bit (tests/gl,
 * occlusion_as_without). One per renderer, remade only when the size or
 * the sample count changes.
 *
 * Sphere impostors drawn on octagons write their own depth, so llvmpipe
 * tests their depth only after their whole shader, with one sample too:
 * spheres in front of one another pay their rays and lighting once per
 * layer. Without multisampling, their occluders are proxies drawn into
 * the same framebuffer: for each opaque sphere, an octagon through its
 * centre, facing the eye, within its great disc, which lies behind the
 * sphere's surface on every ray through it. The BILLBOARD_OCCLUDED
 * program then discards a fragment whose own octagon (which touches the
 * sphere's near side: nearer than the surface on every ray) lies behind
 * the proxies, or whose surface does (canvas3d_draw.c, occluders;
 * tests/gl, proxies_as_without).
 */
#ifndef FL_RENDER_CANVAS3D_OCCLUSION_H
#define FL_RENDER_CANVAS3D_OCCLUSION_H

#include <stdbool.h>

typedef struct C3dOcclusion {
    unsigned fbo;        /* the framebuffer (0: none made yet) */
    unsigned depth;      /* its 24-bit depth texture, multisampled with 2 samples or more, else a plain
                            2D texture, read by C3D_FRAG_OCCLUDED and
                            C3D_FRAG_BILLBOARD_OCCLUDED (texture unit 1) */
    int w, h, samples;   /* its size in pixels and sample count */
    int previous_fbo;    /* the draw framebuffer bound when the pass began */
} C3dOcclusion;

/* Bind [o]'s framebuffer of [w] x [h] pixels and [samples] samples (0 or
 * more; made or remade as needed) and clear its depth to 1, keeping
 * the viewport, the depth test and face culling as they are; the draws
 * that follow write only depth there.
 *   errors: false (the previous framebuffer bound again) when the driver
 *           cannot make it complete. */
bool c3d_occlusion_begin(C3dOcclusion *o, int w, int h, int samples);
/* Bind the framebuffer bound before c3d_occlusion_begin again, and [o]'s
 * depth texture to texture unit 1 (unit 0 active on return). */
void c3d_occlusion_end(C3dOcclusion *o);
/* Unbind any depth texture (multisampled or not) from texture unit 1
 * (unit 0 active on return). */
void c3d_occlusion_unbind(void);
/* Delete [o]'s framebuffer and texture (a GL context current); [o] is
 * zeroed. */
void c3d_occlusion_free(C3dOcclusion *o);

#endif
