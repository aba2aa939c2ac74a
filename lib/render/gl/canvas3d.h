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
 * `!cylinder` and `!cone` (models_mesh.h) with position, size, rotation
 * or start/end/radius, flat and invert; identical models of a group are
 * drawn as one instanced draw call, opaque ones front to back, transparent
 * ones afterwards back to front without depth writes; translucent ones
 * have their back faces drawn first into a framebuffer of their own
 * (canvas3d_backface.h), then are drawn among the transparent ones with
 * depth writes, letting through the back faces' light by thickness
 * (canvas3d_shaders.h). `samples` gives
 * MSAA, fog_color/fog_min/fog_max/fog_curve fog (the picture then starts
 * filled with the fog colour).
 *
 * Lighting is computed in linear light into a half-float framebuffer; the
 * picture handed back is the sRGB encoding of that light (clamped to
 * 0..1, as Flitter's window does last), premultiplied, with an alpha of at
 * least each encoded channel so that composited over black it gives
 * exactly Flitter's window output. Textures,
 * custom shaders, secondary cameras and model kinds other than the four
 * primitives are not drawn: each kind is reported once (textures once per
 * material property: color_id/texture_id, metal_id, roughness_id, ao_id,
 * emissive_id, transparency_id and their *_texture_id aliases).
 */
#ifndef FL_RENDER_CANVAS3D_H
#define FL_RENDER_CANVAS3D_H

#include <cairo.h>

#include "canvas.h"
#include "node.h"
#include "value.h"

typedef struct Canvas3D Canvas3D;

/* A 3D renderer with no GL context yet: the context is created by the
 * first canvas3d_draw (so a run without `!canvas3d` never opens EGL). */
Canvas3D *canvas3d_new(void);
/* Draw the `!canvas3d` node [node] into [pic], an ARGB32 cairo image
 * surface (its size is the camera's), replacing its pixels. [env]'s
 * symbols name symbol attributes (camera_id, fov_ref, composite,
 * cull_face); skipped kinds go to env->skips; [log] receives one warning
 * if no GL context can be made (then, and on every later call, nothing is
 * drawn and -1 is returned).
 *   errors: -1 when nothing could be drawn ([pic] left transparent), else 0. */
int canvas3d_draw(Canvas3D *c, const Node *node, cairo_surface_t *pic, const CanvasEnv *env,
                  const RenderLog *log);
/* canvas3d_draw for a w x h picture of which only the linear light is
 * wanted (canvas3d_linear; a !bloom's input): the same drawing without the
 * 8-bit sRGB picture.
 *   errors: -1 when nothing could be drawn (no linear light then), else 0. */
int canvas3d_draw_linear(Canvas3D *c, const Node *node, int w, int h, const CanvasEnv *env,
                         const RenderLog *log);
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

/* Draw [s] into [pic], an ARGB32 cairo image surface whose size is the
 * camera's, replacing its pixels as canvas3d_draw does (transparent where
 * nothing is drawn). The GL context is made by the first call of either.
 *   errors: -1 with one line in [err] (no OpenGL; "" when that was said
 *           by an earlier call, then nothing is drawn again) when nothing
 *           could be drawn, else 0. */
int canvas3d_draw_scene(Canvas3D *c, const C3dScene *s, cairo_surface_t *pic, char *err, size_t errlen);
/* The linear light of the last canvas3d_draw, before its sRGB encoding:
 * *w x *h pixels of four floats (premultiplied RGBA, top row first, values
 * above 1 kept), as a window effect such as !bloom takes it (Flitter's
 * canvas texture is a half-float framebuffer). Borrowed: valid until the
 * next canvas3d_draw or canvas3d_free.
 *   errors: NULL when the last draw drew nothing (no GL context, or none yet). */
const float *canvas3d_linear(const Canvas3D *c, int *w, int *h);
/* The buffer of canvas3d_linear's light, taken over by the caller (its
 * capacity in floats through [taken_cap]), instead of copied; [buf] (a
 * malloc'd buffer of [cap] floats, or NULL) becomes the canvas's buffer
 * for its next drawing. The canvas then has no picture (canvas3d_linear
 * is NULL) until it draws again.
 *   errors: NULL when there is no picture ([buf] is not taken). */
float *canvas3d_take_linear(Canvas3D *c, float *buf, size_t cap, size_t *taken_cap);
/* Milliseconds spent in canvas3d_draw calls so far and their count. */
double canvas3d_time_ms(const Canvas3D *c, long *calls);
/* Release the GL context and everything on it (NULL is a no-op). */
void canvas3d_free(Canvas3D *c);

#endif
