/* canvas3d_program.h: the GL programs of `!canvas3d`'s standard lighting
 * (canvas3d_shaders.h): for each C3dFragSpec (max_lights, kinds of light,
 * MSAA sample count, kind of camera, list of lights), one program for
 * meshes and two for sphere impostors (on their box, and on their
 * octagon), sharing the lights' uniform buffer, and, made when a frame
 * first has translucent instances, the two programs of `translucency=`:
 * the back-face pass and translucent meshes.
 */
#ifndef FL_RENDER_CANVAS3D_PROGRAM_H
#define FL_RENDER_CANVAS3D_PROGRAM_H

#include <stdbool.h>
#include <stddef.h>

#include "buf.h"
#include "canvas3d_shaders.h"

/* One linked program and its uniform locations (-1: absent). */
typedef struct C3dShader {
    unsigned prog;   /* GL name, 0 when it could not be made */
    int u_pv, u_view_position, u_view_focus, u_orthographic, u_fog_min, u_fog_max, u_fog_curve, u_fog_color,
        u_monochrome, u_tint, u_light_ends;
    int u_inverse_pv, u_viewport_size, u_nsamples, u_sample_offsets, u_billboard, u_proxy;   /* impostors only */
} C3dShader;

typedef struct C3dProgram {
    C3dFragSpec key;       /* what its shaders are made for (variant 0) */
    unsigned ubo;          /* the Lights block: key.max_lights mat4s, bound at binding point 1 */
    C3dShader mesh;        /* triangle meshes */
    C3dShader impostor;    /* ray-cast spheres on their box; prog 0 when the driver cannot (no GL_ARB_sample_shading) */
    C3dShader billboard;   /* ray-cast spheres on their octagon (BILLBOARD); prog 0 when it could not be made,
                              then impostor draws them */
    C3dShader backface;    /* translucent meshes' back faces: light in, distance (prog 0 until made) */
    C3dShader translucent; /* translucent meshes, reading the back faces from texture unit 0 (0 until made) */
    bool translucency_failed;   /* making the two did not work: not tried again */
    C3dShader depth;       /* the occluders' depth pass (prog 0 until made) */
    C3dShader occluded;    /* meshes discarding what the occluders hide, texture unit 1 (0 until made) */
    bool occlusion_failed;      /* making the two did not work: not tried again */
    C3dShader proxy;       /* spheres' proxies in the occluders' pass (C3D_FRAG_PROXY; prog 0 until made) */
    C3dShader billboard_occluded;   /* billboard discarding what the occluders hide, texture unit 1 (0 until made) */
    bool proxies_failed;        /* making the two did not work: not tried again */
} C3dProgram;

/* Compile and link the programs for [key] (its variant ignored; see
 * C3dFragSpec in canvas3d_shaders.h) into [p] (a GL context current). The impostor program failing leaves
 * p->impostor.prog 0 (meshes are drawn instead), the billboard one
 * p->billboard.prog 0 (the impostor program draws octagons too).
 *   errors: false with a message in [err] when the mesh program does not
 *           compile or link ([p] then holds nothing); the billboard
 *           program failing where the impostor one did not is described
 *           appended to [note] (nothing otherwise), to be reported once. */
bool c3d_program_make(C3dProgram *p, const C3dFragSpec *key, Buf *err, Buf *note);
/* Make [p]'s back-face and translucent programs when not made yet (a GL
 * context current).
 *   errors: false with a message in [err] when they do not compile or link
 *           (then, and on every later call, false with nothing appended). */
bool c3d_program_translucency(C3dProgram *p, Buf *err);
/* Make [p]'s occluders' depth program and its OCCLUDED mesh program
 * (canvas3d_occlusion.h) when not made yet (a GL context current).
 *   errors: false when they do not compile or link (then, and on every
 *           later call, false; the meshes are drawn without). */
bool c3d_program_occlusion(C3dProgram *p);
/* Make [p]'s sphere proxies' depth program and its BILLBOARD_OCCLUDED
 * program (canvas3d_draw.c, occluders) when not made yet (a GL context
 * current; [p]'s billboard program made).
 *   errors: false when there is no billboard program or they do not
 *           compile or link (then, and on every later call, false; the
 *           spheres are drawn without). */
bool c3d_program_proxies(C3dProgram *p);
/* Delete [p]'s programs and buffer (the context current); [p] is zeroed. */
void c3d_program_free(C3dProgram *p);

#endif
