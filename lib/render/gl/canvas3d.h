/* canvas3d.h: drawing a `!canvas3d` node tree with OpenGL into a picture.
 *
 * Behaviour from Flitter's documentation (docs/canvas3d.md) and renderer
 * (render/window/canvas3d.pyx): the scene is walked once per frame into
 * render groups (the canvas itself and each `!group`), each with its
 * lights (its own, then its ancestors', at most `max_lights`, default 50)
 * and its model instances; `!transform` (translate, scale, rotate as
 * three turns or a quaternion, rotate_x/_y/_z, matrix, in attribute
 * order), `!material` (color, ior, metal, roughness, ao, emissive,
 * transparency, translucency) and `!light` (ambient, directional, point with radius,
 * spot with inner/outer, line from start to end with radius, and
 * falloff) nodes as documented; `!camera id=`
 * nodes and `camera_id` pick the camera; the default camera sits at
 * 0;0;width/2 looking at the origin with up 0;1;0, a horizontal fov of
 * 0.25 turns, near 1 and far width. Models are `!box`, `!sphere`,
 * `!cylinder` and `!cone` (geom_primitives.h) with position, size, rotation
 * or start/end/radius, flat and invert, and `!model` files and vectors,
 * constructive solid geometry and `!sdf` (geom_model.h, set by
 * canvas3d_set_models) with snap_edges as well; identical models of a group are
 * drawn as one instanced draw call, opaque ones front to back, transparent
 * ones afterwards back to front without depth writes; translucent ones
 * have their back faces drawn first into a framebuffer of their own
 * (canvas3d_backface.h), then are drawn among the transparent ones with
 * depth writes, letting through the back faces' light by thickness
 * (canvas3d_shaders.h). `samples` gives
 * MSAA, fog_color/fog_min/fog_max/fog_curve fog (the picture then starts
 * filled with the fog colour). A `!camera` with an id and secondary=true
 * is drawn into a picture of its own besides the canvas's (the render
 * graph makes its framebuffers and registers its id).
 *
 * Lighting is computed in linear light into the framebuffer the caller
 * gives (half floats by default, values above 1 kept, as Flitter's
 * 16-bit `colorbits`). Custom shaders and model kinds other than the four
 * primitives are not drawn: each kind is reported once.
 *
 * Every call needs an OpenGL context current on the calling thread (the
 * render graph's, or the physics view's): the renderer keeps its meshes
 * and programs on it, and canvas3d_free must be called with it current.
 */
#ifndef FL_RENDER_CANVAS3D_H
#define FL_RENDER_CANVAS3D_H

#include <stdbool.h>

#include "buf.h"
#include "canvas.h"
#include "gl_target.h"
#include "node.h"
#include "value.h"

typedef struct Canvas3D Canvas3D;

/* When render groups have an occluders' pass (canvas3d_occlusion.h):
 * when it is likely to pay (the default), whenever it can (for the
 * tests), never. */
enum { C3D_OCCLUSION_AUTO, C3D_OCCLUSION_ALWAYS, C3D_OCCLUSION_NEVER };

/* How a renderer draws, for tests and measurements (fl_debug_options):
 * every choice gives the same picture; all zero is the default. */
typedef struct C3dRoutes {
    bool no_impostors;   /* spheres always as meshes */
    bool box_impostors;  /* impostors always on their boxes, never on octagons */
    int occlusion;       /* C3D_OCCLUSION_* */
    bool no_light_culling;   /* every light of a group in every draw (canvas3d_cull.h) */
} C3dRoutes;

/* A 3D renderer (its GL objects are made by the first drawing), drawing as
 * [routes] says (NULL: the defaults). */
Canvas3D *canvas3d_new(const C3dRoutes *routes);

struct GeomModels;
/* The models (geom_model.h) that the scene's model kinds are made from,
 * the budget its meshes' buffers are charged to (may be NULL), and where
 * its one-off notes go (each said once by [note]'s owner); all borrowed,
 * set before each canvas3d_scene. */
void canvas3d_set_models(Canvas3D *c, struct GeomModels *models, MemBudget *budget,
                         void (*note)(void *ctx, const char *line), void *ctx);

/* One camera of the scene canvas3d_scene collected. */
typedef struct C3dCameraInfo {
    const char *id;        /* its id (borrowed until the next canvas3d_scene), or NULL */
    int width, height;     /* its picture's size */
    int colorbits;         /* its framebuffer's colour depth (8, 16 or 32) */
    int samples;           /* MSAA samples (0: none), as the node asks */
    bool secondary;        /* drawn besides the canvas's picture */
    float clear[4];        /* the colour its picture starts as (the fog's, or transparent) */
} C3dCameraInfo;

/* Walk `!canvas3d` node [node] ([w] x [h], the window's [colorbits] the
 * default) into a scene: render groups, lights, instances and cameras.
 * [env]'s symbols name symbol attributes (camera_id, fov_ref, composite,
 * cull_face), skipped kinds go to env->skips. Returns the number of
 * cameras (at least 1: the canvas's own is camera 0) and sets *[primary]
 * to the one whose picture is the canvas's (camera_id=). */
int canvas3d_scene(Canvas3D *c, const Node *node, int w, int h, int colorbits, const CanvasEnv *env, int *primary);
/* Camera [i] of the last scene. */
void canvas3d_camera(const Canvas3D *c, int i, C3dCameraInfo *out);
/* Draw the last scene through camera [i] into target [t] (its size and
 * samples the camera's; it must have a depth buffer): cleared to the
 * camera's clear colour, drawn, resolved. A program that failed without
 * failing the frame is noted once on [log].
 *   errors: -1 with one line in [err] when a program does not compile
 *           (the groups before it are drawn); else 0. */
int canvas3d_draw(Canvas3D *c, int i, GlTarget *t, const RenderLog *log, Buf *err);

/* A scene given as shapes rather than as a node tree: the physics view's
 * (view.c). One render group (depth sorted and tested, back faces culled,
 * `over`) lit by an ambient and a directional light, with every item's
 * material Flitter's default but for its colour, transparency and the
 * scene's roughness (ior 1.5, metal 0, ao 1: Flitter docs/canvas3d.md,
 * Materials); seen by a perspective camera (Flitter docs/canvas3d.md,
 * Cameras: `position`, `focus`, `up`, `fov` in turns across the picture's
 * width, `near`, `far`, `samples`). */
enum { C3D_SHAPE_BOX, C3D_SHAPE_SPHERE, C3D_SHAPE_CYLINDER };
typedef struct C3dItem {
    int shape;             /* C3D_SHAPE_*: the unit model of `!box` (corners
                              at +-0.5), `!sphere` (radius 1) or `!cylinder`
                              (radius 1, height 1 along z) */
    double model[16];      /* model to world, column-major (m[12..14] the
                              translation) */
    double color[3];       /* albedo, linear */
    double transparency;   /* 0..1 */
} C3dItem;

typedef struct C3dScene {
    double position[3], focus[3], up[3];   /* the camera */
    double fov;                            /* horizontal field of view, turns */
    double near, far;
    int samples;                           /* MSAA samples (below 2: none) */
    double ambient[3];                     /* ambient light, linear */
    double sun[3], sun_direction[3];       /* directional light and the
                                              direction it shines in (a zero
                                              direction: none) */
    double roughness;                      /* every item's */
    const C3dItem *items;
    size_t nitems;
} C3dScene;

/* Draw [s] into target [t] (the camera's picture, with a depth buffer and
 * [s]->samples), as canvas3d_draw does.
 *   errors: -1 with one line in [err] when a program does not compile;
 *           else 0. */
int canvas3d_draw_scene(Canvas3D *c, const C3dScene *s, GlTarget *t, Buf *err);
/* Release the GL objects (the context they were made on current) and
 * the renderer (NULL is a no-op). */
void canvas3d_free(Canvas3D *c);

#endif
