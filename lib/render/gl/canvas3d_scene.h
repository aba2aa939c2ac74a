/* canvas3d_scene.h: one frame's `!canvas3d` scene as canvas3d.c collects
 * it (render groups, lights, model instances, cameras) and the renderer
 * that holds it, shared with canvas3d_draw.c, which draws a render group.
 * Internal to the two files; canvas3d.h is the interface.
 */
#ifndef FL_RENDER_CANVAS3D_SCENE_H
#define FL_RENDER_CANVAS3D_SCENE_H

#include <math.h>
#include <stdbool.h>
#include <stddef.h>

#include <epoxy/gl.h>

#include "buf.h"
#include "canvas.h"
#include "canvas3d.h"
#include "canvas3d_backface.h"
#include "canvas3d_occlusion.h"
#include "canvas3d_program.h"
#include "gl_target.h"
#include "mat4.h"
#include "models_mesh.h"

typedef struct Material {
    double albedo[3], emissive[3];
    double ior, metal, roughness, ao, transparency, translucency;
    int tex;           /* its textures: an index into Canvas3D.texsets, 0 for none */
} Material;

/* The textures of a material (Flitter canvas3d.pyx, Textures): one id per
 * property (C3D_TEXTURES order; "" for none) and how they are sampled
 * beyond 0..1 (a border colour, else repeat or clamp per axis). */
typedef struct TexSet {
    char id[C3D_TEXTURES][64];
    bool has_border;
    float border[4];
    bool repeat_x, repeat_y;
} TexSet;

typedef struct Instance {
    M4 model;
    Material mat;
    const GlMesh *mesh;
    double z;          /* distance of the nearest bounding-box corner along the view axis */
    int group;
    int rank;          /* its mesh's place among its group's meshes, by first appearance (c3d_draw_group) */
} Instance;

/* Cameras of one canvas (its own and those with an id). */
#define C3D_CAMERAS 16

/* Programs kept by a canvas (one per max_lights and set of light kinds its
 * render groups use). */
#define C3D_PROGRAMS 8
/* Programs with their lights listed (C3dFragSpec.nlist) that one canvas
 * may compile at once (each some tens of milliseconds of compiling), and
 * the frames after which it may compile one more: a scene whose lights
 * change every frame soon has its lights looped over, and a long live
 * session is not left looping for good. */
#define C3D_LISTED_MAX 16
#define C3D_LISTED_FRAMES 30

typedef struct Light {
    float data[16];   /* the shader's mat4 (canvas3d_shaders.h) */
    int group;        /* the render group it lights */
} Light;

enum Composite { COMP_OVER, COMP_DEST_OVER, COMP_ADD, COMP_SUBTRACT, COMP_LIGHTEN, COMP_DARKEN, COMP_SOURCE, COMP_DEST };

typedef struct Group {
    int parent;                 /* index of the enclosing group, -1 for the canvas */
    int max_lights;
    bool depth_sort, depth_test, face_cull, cull_front;
    int composite;              /* enum Composite */
    int ninstances;
} Group;

typedef struct Camera {
    int width, height;          /* its picture's size (size=, else the canvas's) */
    int colorbits;              /* its framebuffer's (colorbits=, else the window's) */
    bool secondary;             /* secondary=true: drawn besides the canvas's own picture */
    double position[3], focus[3], up[3];
    double fov, ortho_width, near, far;
    double fog_min, fog_max, fog_color[3], fog_curve, tint[3];
    bool orthographic, monochrome;
    char fov_ref[12];
    int samples;
    M4 view, pv;
} Camera;


struct Canvas3D {
    MeshCache *meshes;         /* made by the first drawing (with a context current) */
    struct GeomModels *models; /* the model kinds' models (canvas3d_set_models; may be NULL) */
    MemBudget *budget;         /* charged for the meshes' buffers (may be NULL) */
    void (*note)(void *ctx, const char *line);   /* one-off notes (may be NULL) */
    void *note_ctx;
    C3dProgram prog[C3D_PROGRAMS];   /* by C3dFragSpec; when full, */
    int nprog, prog_turn;            /* each new one replaces the next in turn */
    int listed_made;                 /* listed programs made, less one per C3D_LISTED_FRAMES frames */
    long frames, listed_at;          /* frames drawn; the frame listed_made last went down */
    GLuint instance_vbo;
    /* the frame's scene, reused across frames */
    Group *groups; int ngroups; size_t cap_groups;
    Light *lights; int nlights; size_t cap_lights;
    Instance *inst; int ninst; size_t cap_inst;
    Instance **order; int cap_order;
    Instance **split; int cap_split;      /* one dispatch's impostors: billboards, box ones from n (2n) */
    Instance **tl; int cap_tl;            /* one group's translucent instances */
    C3dBackface backface;                 /* the back-face pass's framebuffer */
    C3dOcclusion occlusion;               /* the occluders' pass's framebuffer */
    int occlusion_mode;                   /* C3D_OCCLUSION_* (C3dRoutes.occlusion) */
    Instance **occ; int cap_occ;          /* one group's occluders */
    const GlMesh **seen; int cap_seen;    /* one group's meshes, in order of first appearance */
    bool impostors;                       /* spheres may be drawn as impostors (C3dRoutes.no_impostors: never) */
    bool octagons;                        /* impostors may be drawn on octagons (C3dRoutes.box_impostors: never) */
    char program_note[600];               /* a program that failed without failing the frame (reported once) */
    bool program_noted;
    int samples_used;                     /* MSAA samples of this frame's target (0: none) */
    float *idata; size_t cap_idata;       /* instance floats of one dispatch */
    float *lightbuf; int cap_lightbuf;    /* mat4s of one group, sorted by slot (C3D_LIGHT_SLOTS) */
    float *lightsort;                     /* scratch of cap_lightbuf floats for the sort */
    int light_ends[C3D_LIGHT_SLOTS];      /* where each slot's lights end in lightbuf */
    /* lights culled per draw (canvas3d_cull.h): while a group's looping
     * program draws, the lights of lightbuf that may be culled (0: none),
     * its uniform buffer, and the block's size; the buffer of a draw's
     * remaining lights, and their mat4s (cap_lightbuf floats) */
    bool light_culling;                   /* lights may be culled (C3dRoutes.no_light_culling: never) */
    int cull_nl; GLuint cull_restore; size_t cull_bytes;
    GLuint cull_ubo; float *cullbuf;
    long lights_culled;                   /* lights left out of draws, all frames (for tests) */
    TexSet *texsets; int ntexsets; size_t cap_texsets;   /* the frame's distinct textures; [0] none */
    /* the frame's cameras: the canvas's own first, then each !camera with an id */
    Camera cams[C3D_CAMERAS]; Buf cam_id[C3D_CAMERAS]; int ncams;
    int primary;                          /* the camera whose picture is the canvas's */
    Buf name;
    const CanvasEnv *env;
    int width, height;
};

/* Draw render group [gi] of [c]'s scene: its [n] instances [list] (in any
 * order; reordered here) through [cam] into the bound framebuffer, lit by
 * the group's lights and its ancestors' (at most its max_lights).
 *   errors: a message in [err] when its program does not compile (nothing
 *           drawn); [err] untouched otherwise. */
/* A one-off note about the scene (the receiver says each line once). */
void c3d_note(Canvas3D *c, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

void c3d_draw_group(Canvas3D *c, int gi, Instance **list, int n, const Camera *cam, Buf *err);

/* The 8 corners of [in]'s mesh's bounding box projected through [pv]
 * onto a [w] x [h] framebuffer: GL window coordinates (pixels, y up) in
 * xy (x0, y0, x1, ...). False when a corner is at or behind the eye's
 * plane (clip w <= 1e-9) or not finite: no projection bounds it then. */
static inline bool c3d_project_box(const M4 *pv, const Instance *in, int w, int h, double xy[16])
{
    M4 m = m4_mul(pv, &in->model);
    const float *b = in->mesh->bounds;
    for (int k = 0; k < 8; k++) {
        double v[3] = {b[(k & 1) ? 3 : 0], b[(k & 2) ? 4 : 1], b[(k & 4) ? 5 : 2]}, clip[4];
        for (int r = 0; r < 4; r++) clip[r] = m.m[r] * v[0] + m.m[4 + r] * v[1] + m.m[8 + r] * v[2] + m.m[12 + r];
        if (!(clip[3] > 1e-9) || !isfinite(clip[0]) || !isfinite(clip[1]) || !isfinite(clip[3])) return false;
        xy[2 * k] = (clip[0] / clip[3] * 0.5 + 0.5) * w;
        xy[2 * k + 1] = (clip[1] / clip[3] * 0.5 + 0.5) * h;
    }
    return true;
}

#endif
