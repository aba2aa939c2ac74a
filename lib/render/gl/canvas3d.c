/* canvas3d.c: the `!canvas3d` scene walk and the frame around its render
 * passes (see canvas3d.h).
 *
 * One frame: collect() walks the node tree once, carrying the local
 * transform and the current material, into a flat list of render groups
 * (pre-order, so a parent group is drawn before the groups inside it),
 * each holding its lights and its instances (model matrix, material, mesh)
 * in reused arrays that only grow (canvas3d_scene.h); cameras with an id
 * are derived from the canvas's default camera. Then a camera's target
 * is cleared and each group is drawn by canvas3d_draw.c (opaque instances
 * front to back, translucent ones' back faces, then transparent and
 * translucent ones back to front). */
#include "canvas3d.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <epoxy/gl.h>

#include "canvas3d_scene.h"
#include "canvas3d_shaders.h"
#include "mem.h"
#include "geom_model.h"
#include "geom_uv_remap.h"
#include "rnode.h"
#include "transform3d.h"

/* last: it turns the library's names into calls through its table */
#include "gl_lib.h"

#define DEFAULT_MAX_LIGHTS 50
#define DEFAULT_SEGMENTS 64

Canvas3D *canvas3d_new(const C3dRoutes *routes)
{
    static const C3dRoutes defaults = {0};
    if (!routes) routes = &defaults;
    Canvas3D *c = mem_calloc(1, sizeof *c);
    c->impostors = !routes->no_impostors;
    c->octagons = !routes->box_impostors;
    c->occlusion_mode = routes->occlusion == C3D_OCCLUSION_ALWAYS || routes->occlusion == C3D_OCCLUSION_NEVER
                            ? routes->occlusion : C3D_OCCLUSION_AUTO;
    c->light_culling = !routes->no_light_culling;
    for (int i = 0; i < C3D_CAMERAS; i++) c->cam_id[i] = (Buf)BUF_INIT;
    c->name = (Buf)BUF_INIT;
    return c;
}

void canvas3d_set_models(Canvas3D *c, struct GeomModels *models, MemBudget *budget,
                         void (*note)(void *ctx, const char *line), void *ctx)
{
    c->models = models;
    c->budget = budget;
    c->note = note;
    c->note_ctx = ctx;
}

void c3d_note(Canvas3D *c, const char *fmt, ...)
{
    if (!c->note) return;
    char line[600];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    c->note(c->note_ctx, line);
}

/* {===== attributes */

static bool nums(const Node *n, const char *name, int count, double *out)
{
    return canvas_attr_nums(n, name, count, out);
}

static double num(const Node *n, const char *name, double dflt)
{
    double x;
    return nums(n, name, 1, &x) ? x : dflt;
}

static bool flag(const Node *n, const char *name, bool dflt)
{
    const Vec *v = rnode_attr(n, name);
    return v ? vec_truthy(v) : dflt;
}

/* The text of attribute [name] (a symbol's name) in c->name, or NULL. */
static const char *text(Canvas3D *c, const Node *n, const char *name)
{
    if (!canvas_attr_str(n, name, c->env->symbols, &c->name)) return NULL;
    return buf_cstr(&c->name);
}

static double clampd(double x, double lo, double hi) { return x < lo ? lo : x > hi ? hi : x; }

/* }===== */

/* {===== the scene walk */

static bool is_material_attr(const char *a)
{
    static const char *const names[] = {"color", "metal", "roughness", "ao", "emissive", "transparency",
                                        "ior", "translucency", "color_id", "metal_id", "roughness_id", "ao_id",
                                        "emissive_id", "transparency_id", "texture_id", "metal_texture_id",
                                        "roughness_texture_id", "ao_texture_id", "emissive_texture_id",
                                        "transparency_texture_id"};
    for (size_t i = 0; i < sizeof names / sizeof *names; i++)
        if (strcmp(a, names[i]) == 0) return true;
    return false;
}


/* The index of texture set [t] in c->texsets, added when new. */
static int intern_texset(Canvas3D *c, const TexSet *t)
{
    for (int i = 1; i < c->ntexsets; i++)
        if (memcmp(&c->texsets[i], t, sizeof *t) == 0) return i;
    c->texsets = mem_grow(c->texsets, &c->cap_texsets, (size_t)(c->ntexsets + 1), sizeof *c->texsets);
    c->texsets[c->ntexsets] = *t;
    return c->ntexsets++;
}

/* Flitter canvas3d.pyx, Material.update, the textures: each property's
 * id (its name, else its older *_texture_id spelling), border= (3 numbers
 * and an alpha of 1, or 4) and repeat=, over the inherited ones. */
static int update_textures(Canvas3D *c, const Node *n, int inherited)
{
    static const char *const names[C3D_TEXTURES][2] = {
        {"color_id", "texture_id"}, {"metal_id", "metal_texture_id"}, {"roughness_id", "roughness_texture_id"},
        {"ao_id", "ao_texture_id"}, {"emissive_id", "emissive_texture_id"},
        {"transparency_id", "transparency_texture_id"}};
    TexSet t;
    memset(&t, 0, sizeof t);
    if (inherited) t = c->texsets[inherited];
    bool any = false;
    for (int k = 0; k < C3D_TEXTURES; k++) {
        const char *id = text(c, n, names[k][0]);
        if (!id) id = text(c, n, names[k][1]);
        if (!id || !id[0]) continue;
        snprintf(t.id[k], sizeof t.id[k], "%s", id);
        any = true;
    }
    double v[4] = {0, 0, 0, 1};
    if (nums(n, "border", 3, v) || nums(n, "border", 4, v)) {
        if (vec_len(rnode_attr(n, "border")) != 4) v[3] = 1;
        for (int k = 0; k < 4; k++) t.border[k] = (float)v[k];
        any = t.has_border = true;
    }
    if (nums(n, "repeat", 2, v)) {
        t.repeat_x = v[0] != 0;
        t.repeat_y = v[1] != 0;
        any = true;
    }
    return any ? intern_texset(c, &t) : inherited;
}

/* Flitter canvas3d.pyx, Material.update (roughness: the smaller of the
 * node's, default 1, and the inherited one, as Flitter does). */
static Material update_material(Canvas3D *c, const Node *n, const Material *m)
{
    Material r = *m;
    if (rnode_nattrs(n) == 0) return r;
    r.tex = update_textures(c, n, m->tex);
    nums(n, "color", 3, r.albedo);
    r.ior = fmax(1, num(n, "ior", m->ior));
    r.roughness = fmin(fmax(1e-6, num(n, "roughness", 1)), m->roughness);
    r.metal = clampd(num(n, "metal", m->metal), 0, 1);
    r.ao = clampd(num(n, "ao", m->ao), 0, 1);
    nums(n, "emissive", 3, r.emissive);
    r.transparency = clampd(num(n, "transparency", m->transparency), 0, 1);
    r.translucency = fmax(0, num(n, "translucency", m->translucency));
    return r;
}

static void add_light(Canvas3D *c, const Node *n, const M4 *t, int group)
{
    double color[3];
    if (!nums(n, "color", 3, color) || (color[0] == 0 && color[1] == 0 && color[2] == 0)) return;
    double pos[3], focus[3], dir[3], start[3], end[3];
    bool has_pos = nums(n, "position", 3, pos), has_focus = nums(n, "focus", 3, focus);
    bool has_dir = nums(n, "direction", 3, dir);
    if (!has_dir && has_pos && has_focus) {
        for (int k = 0; k < 3; k++) dir[k] = focus[k] - pos[k];
        has_dir = true;
    }
    if (has_dir && dir[0] == 0 && dir[1] == 0 && dir[2] == 0) has_dir = false;
    bool line = nums(n, "start", 3, start) && nums(n, "end", 3, end);
    c->lights = mem_grow(c->lights, &c->cap_lights, (size_t)(c->nlights + 1), sizeof *c->lights);
    Light *l = &c->lights[c->nlights++];
    memset(l, 0, sizeof *l);
    float *d = l->data;
    for (int k = 0; k < 3; k++) d[k] = (float)color[k];
    double falloff[4] = {0, 0, 1, 0};
    nums(n, "falloff", 4, falloff);
    for (int k = 0; k < 4; k++) d[12 + k] = (float)falloff[k];
    double wp[3], wd[3];
    if (line) {
        /* Flitter canvas3d.pyx, collect: a line light is its start and the
         * vector to its end, both through the full transform, and radius */
        double we[3];
        m4_point(t, start, wp);
        m4_point(t, end, we);
        for (int k = 0; k < 3; k++) wd[k] = we[k] - wp[k];
        d[11] = (float)num(n, "radius", 0);
        /* a line of no length (in single precision, as the shader sees it)
         * would divide by zero there: it is a point light with the radius */
        float len2 = 0;
        for (int k = 0; k < 3; k++) len2 += (float)wd[k] * (float)wd[k];
        d[3] = len2 > 0 && isfinite(len2) ? LIGHT_LINE : LIGHT_POINT;
        if (d[3] == LIGHT_POINT) wd[0] = wd[1] = wd[2] = 0;
    } else if (has_pos && has_dir) {
        double outer = clampd(num(n, "outer", 0.25), 0, 1);
        double inner = clampd(num(n, "inner", 0), 0, outer);
        d[3] = LIGHT_SPOT;
        m4_point(t, pos, wp);
        m4_direction(t, dir, wd);
        d[7] = (float)cos(inner * M_PI);
        d[11] = (float)cos(outer * M_PI);
    } else if (has_pos) {
        d[3] = LIGHT_POINT;
        m4_point(t, pos, wp);
        wd[0] = wd[1] = wd[2] = 0;
        d[11] = (float)num(n, "radius", 0);
    } else if (has_dir) {
        d[3] = LIGHT_DIRECTIONAL;
        wp[0] = wp[1] = wp[2] = 0;
        m4_direction(t, dir, wd);
    } else {
        d[3] = LIGHT_AMBIENT;
        wp[0] = wp[1] = wp[2] = wd[0] = wd[1] = wd[2] = 0;
    }
    for (int k = 0; k < 3; k++) d[4 + k] = (float)wp[k], d[8 + k] = (float)wd[k];
    l->group = group;
}

static void camera_matrices(Camera *cam, int w, int h);

/* Flitter canvas3d.pyx, Camera.derive: [base]'s settings with [n]'s
 * attributes over them, positions through [t]; w x h the picture. */
static void derive_camera(Canvas3D *c, const Node *n, const M4 *t, const Camera *base, int w, int h, Camera *cam)
{
    *cam = *base;
    double v[3];
    if (nums(n, "position", 3, v) || nums(n, "viewpoint", 3, v)) m4_point(t, v, cam->position);
    if (nums(n, "focus", 3, v)) m4_point(t, v, cam->focus);
    if (nums(n, "up", 3, v)) m4_direction(t, v, cam->up);
    cam->fov = num(n, "fov", base->fov);
    const char *ref = text(c, n, "fov_ref");
    if (ref) snprintf(cam->fov_ref, sizeof cam->fov_ref, "%s", ref);
    cam->monochrome = flag(n, "monochrome", base->monochrome);
    nums(n, "tint", 3, cam->tint);
    cam->orthographic = flag(n, "orthographic", base->orthographic);
    cam->ortho_width = num(n, "width", base->ortho_width);
    cam->near = fmax(1e-9, num(n, "near", base->near));
    cam->far = fmax(cam->near + 1e-9, num(n, "far", base->far));
    cam->fog_min = num(n, "fog_min", base->fog_min);
    cam->fog_max = num(n, "fog_max", base->fog_max);
    nums(n, "fog_color", 3, cam->fog_color);
    cam->fog_curve = fmax(0, num(n, "fog_curve", base->fog_curve));
    double s = num(n, "samples", base->samples);
    cam->samples = s >= 2 && s < 1e6 ? (int)s : 0;
    double size[2];
    if (nums(n, "size", 2, size) && size[0] < 1e6 && size[1] < 1e6) {
        cam->width = size[0] >= 1 ? (int)size[0] : 1;
        cam->height = size[1] >= 1 ? (int)size[1] : 1;
    }
    double bits;
    if (nums(n, "colorbits", 1, &bits) && (bits == 8 || bits == 16 || bits == 32)) cam->colorbits = (int)bits;
    cam->secondary = flag(n, "secondary", false);
    (void)w, (void)h;
    camera_matrices(cam, cam->width, cam->height);
}

/* [cam]'s view and projection matrices for a w x h picture, from its
 * position, focus, up, fov/fov_ref or orthographic width, near and far. */
static void camera_matrices(Camera *cam, int w, int h)
{
    double aspect = (double)w / h;
    M4 proj;
    if (cam->orthographic) {
        proj = m4_ortho(aspect, cam->ortho_width, cam->near, cam->far);
    } else {
        double g = tan(M_PI * cam->fov);
        const char *r = cam->fov_ref;
        bool vertical = strcmp(r, "vertical") == 0 || (strcmp(r, "wide") == 0 && aspect <= 1) ||
                        (strcmp(r, "narrow") == 0 && aspect > 1);
        if (strcmp(r, "diagonal") == 0) {
            double dr = sqrt(1 + aspect * aspect);
            proj = m4_project(aspect * g / dr, g / dr, cam->near, cam->far);
        } else if (vertical) {
            proj = m4_project(aspect * g, g, cam->near, cam->far);
        } else {
            proj = m4_project(g, g / aspect, cam->near, cam->far);
        }
    }
    m4_look(cam->position, cam->focus, cam->up, &cam->view);
    cam->pv = m4_mul(&proj, &cam->view);
}

static int mesh_kind(const Node *n)
{
    if (rnode_is(n, "box")) return MESH_BOX;
    if (rnode_is(n, "sphere")) return MESH_SPHERE;
    if (rnode_is(n, "cylinder")) return MESH_CYLINDER;
    if (rnode_is(n, "cone")) return MESH_CONE;
    return -1;
}

/* Flitter canvas3d.pyx get_model (top): the GL mesh of model node [n]
 * (a file, vectors, CSG, SDF; a primitive with snap_edges= or
 * uv_remap=) with its shading: flat, else its edges snapped at snap_edges
 * (default geom_model_snap's), invert, then its uv_remap=. NULL when it has none (the
 * reason logged once by the models). */
static const GlMesh *model_mesh(Canvas3D *c, const Node *n, MeshKey *key)
{
    if (!c->models) return NULL;
    GeomModel *m = geom_model_of(c->models, n, true);
    if (!m) return NULL;
    const GeomMesh *g = geom_model_mesh(c->models, m);
    if (!g) return NULL;
    key->kind = -1;
    key->model = geom_model_serial(m);
    key->snap = key->flat ? 0 : clampd(num(n, "snap_edges", geom_model_snap(m)), 0, 0.5);
    if (key->snap <= 0) key->flat = true, key->snap = 0;
    key->uv_remap = geom_uv_remap_parse(text(c, n, "uv_remap"));
    const GlMesh *gl = mesh_cache_get_model(c->meshes, key, g, c->frames);
    if (!gl) c3d_note(c, "!%s: its mesh (%u triangles) does not fit in the memory budget", rnode_kind(n), g->ntri);
    return gl;
}

static void add_instance(Canvas3D *c, const Node *n, int kind, const M4 *t, const Material *mat, int group)
{
    MeshKey key = {.kind = kind, .flat = flag(n, "flat", false), .invert = flag(n, "invert", false)};
    const GlMesh *mesh;
    if (kind >= 0) {
        const char *uv = kind == MESH_BOX ? text(c, n, "uv_map") : NULL;
        key.uv_repeat = uv && strcmp(uv, "repeat") == 0;
        key.segments = mesh_segments(kind, (int)clampd(num(n, "segments", DEFAULT_SEGMENTS), 0, 1e6));
        mesh = mesh_cache_get(c->meshes, &key);
        if (!mesh)
            c3d_note(c, "!%s: its mesh (%d segments) does not fit in the memory budget", rnode_kind(n), key.segments);
    } else {
        mesh = model_mesh(c, n, &key);
    }
    if (!mesh) return;
    c->inst = mem_grow(c->inst, &c->cap_inst, (size_t)(c->ninst + 1), sizeof *c->inst);
    Instance *in = &c->inst[c->ninst++];
    in->mesh = mesh;
    in->group = group;
    in->model = transform3d_model(n, *t, NULL);
    in->mat = *mat;
    for (size_t i = 0; i < rnode_nattrs(n); i++)
        if (is_material_attr(rnode_attr_name(n, i))) {
            in->mat = update_material(c, n, mat);
            break;
        }
    c->groups[group].ninstances++;
}

static int new_group(Canvas3D *c, const Node *n, int parent)
{
    c->groups = mem_grow(c->groups, &c->cap_groups, (size_t)(c->ngroups + 1), sizeof *c->groups);
    Group *g = &c->groups[c->ngroups];
    const Group *p = parent >= 0 ? &c->groups[parent] : NULL;
    g->parent = parent;
    g->max_lights = (int)clampd(num(n, "max_lights", p ? p->max_lights : DEFAULT_MAX_LIGHTS), 1, 1000);
    g->depth_sort = flag(n, "depth_sort", p ? p->depth_sort : true);
    g->depth_test = flag(n, "depth_test", p ? p->depth_test : true);
    g->face_cull = flag(n, "face_cull", p ? p->face_cull : true);
    const char *cf = text(c, n, "cull_face");
    g->cull_front = cf ? strcmp(cf, "front") == 0 : (p ? p->cull_front : false);
    g->composite = p ? p->composite : COMP_OVER;
    const char *comp = text(c, n, "composite");
    if (comp) {
        static const char *const names[] = {"over", "dest_over", "add", "subtract", "lighten", "darken", "source", "dest"};
        g->composite = COMP_OVER;
        for (int i = 0; i < 8; i++)
            if (strcmp(comp, names[i]) == 0) g->composite = i;
    }
    if (rnode_attr(n, "vertex") || rnode_attr(n, "fragment"))
        skiplog_note(c->env->skips, "canvas3d", "group vertex=/fragment= (custom shaders)");
    g->ninstances = 0;
    return c->ngroups++;
}

static void collect(Canvas3D *c, const Node *n, M4 t, const Material *mat, int group, const Camera *base)
{
    Material m = *mat;
    int kind;
    if (rnode_is(n, "transform")) {
        t = transform3d_update(n, t);
    } else if (rnode_is(n, "material")) {
        m = update_material(c, n, mat);
    } else if (rnode_is(n, "light")) {
        add_light(c, n, &t, group);
        return;
    } else if (rnode_is(n, "camera")) {
        const char *id = text(c, n, "id");
        if (id && c->ncams < C3D_CAMERAS) {
            /* a later camera of the same id replaces the earlier (Flitter: a dict) */
            int k = c->ncams;
            for (int i = 1; i < c->ncams; i++)
                if (strcmp(buf_cstr(&c->cam_id[i]), id) == 0) k = i;
            buf_reset(&c->cam_id[k]);
            buf_puts(&c->cam_id[k], id);
            derive_camera(c, n, &t, base, c->width, c->height, &c->cams[k]);
            if (k == c->ncams) c->ncams++;
        } else if (id) {
            skiplog_note(c->env->skips, "canvas3d", "camera (more than 15 with an id)");
        }
        return;
    } else if (rnode_is(n, "group") || rnode_is(n, "canvas3d")) {
        t = transform3d_update(n, t);
        m = update_material(c, n, mat);
        group = new_group(c, n, group);
    } else if ((kind = mesh_kind(n)) >= 0 && !rnode_attr(n, "snap_edges") && !rnode_attr(n, "uv_remap")) {
        add_instance(c, n, kind, &t, mat, group);
        return;
    } else if (geom_is_model_kind(n)) {
        add_instance(c, n, -1, &t, mat, group);
        return;
    } else {
        skiplog_note(c->env->skips, "canvas3d", rnode_kind(n));
        return;
    }
    for (size_t i = 0; i < rnode_nchildren(n); i++) collect(c, rnode_child(n, i), t, &m, group, base);
}

/* }===== */

/* The meshes and the instance buffer, made the first time (with the
 * caller's context current). */
static void begin(Canvas3D *c)
{
    if (c->meshes) return;
    c->meshes = mesh_cache_new(c->budget);
    glGenBuffers(1, &c->instance_vbo);
}

/* Draw the collected groups, lights and instances through [cam] into
 * target [t].
 *   errors: -1 with a message in [err] when a program does not compile
 *           (the groups before it are drawn); else 0. */
static int render(Canvas3D *c, const Camera *cam, GlTarget *t, const float clear[4], Buf *err)
{
    size_t mark = err->len;
    c->width = t->w;
    c->height = t->h;
    c->samples_used = t->given;
    c->frames++;
    target_bind(t);
    glDisable(GL_FRAMEBUFFER_SRGB);
    target_clear(t, clear);
    if (t->given > 0) glEnable(GL_MULTISAMPLE);
    int rc = 0;
    /* instances by group */
    if (c->cap_order < 2 * c->ninst) {
        c->cap_order = 2 * c->ninst;
        c->order = mem_realloc_array(c->order, (size_t)c->cap_order, sizeof *c->order);
    }
    for (int g = 0; g < c->ngroups; g++) {
        int n = 0;
        for (int i = 0; i < c->ninst; i++)
            if (c->inst[i].group == g) c->order[n++] = &c->inst[i];
        if (n) c3d_draw_group(c, g, c->order, n, cam, err);
        if (err->len > mark) {
            rc = -1;
            break;
        }
    }
    glBindVertexArray(0);
    glDisable(GL_BLEND);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glUseProgram(0);
    target_finish(t);
    return rc;
}

int canvas3d_scene(Canvas3D *c, const Node *node, int w, int h, int colorbits, const CanvasEnv *env, int *primary)
{
    begin(c);
    c->env = env;
    c->width = w;
    c->height = h;
    /* Flitter canvas3d.pyx, Canvas3D.render: the default camera, then the
     * canvas's own attributes over it */
    Camera base = {.width = w, .height = h, .colorbits = colorbits, .position = {0, 0, w / 2.0}, .up = {0, 1, 0},
                   .fov = 0.25, .tint = {1, 1, 1}, .ortho_width = w, .near = 1, .far = w, .fog_curve = 1,
                   .fov_ref = "horizontal"};
    M4 id = m4_identity();
    buf_reset(&c->cam_id[0]);
    const char *own = text(c, node, "id");
    if (own) buf_puts(&c->cam_id[0], own);
    derive_camera(c, node, &id, &base, w, h, &c->cams[0]);
    c->cams[0].secondary = false;
    c->ncams = 1;
    Material mat = {.ior = 1.5, .roughness = 1, .ao = 1};
    c->ngroups = c->nlights = c->ninst = 0;
    c->texsets = mem_grow(c->texsets, &c->cap_texsets, 1, sizeof *c->texsets);
    memset(&c->texsets[0], 0, sizeof c->texsets[0]);
    c->ntexsets = 1;
    collect(c, node, id, &mat, -1, &c->cams[0]);
    /* models' buffers unused for a while go (their meshes stay with the models) */
    mesh_cache_sweep(c->meshes, c->frames - 60);
    c->primary = 0;
    const char *want = text(c, node, "camera_id");
    for (int i = 0; want && i < c->ncams; i++)
        if (c->cam_id[i].len && strcmp(buf_cstr(&c->cam_id[i]), want) == 0) c->primary = i;
    *primary = c->primary;
    return c->ncams;
}

void canvas3d_camera(const Canvas3D *c, int i, C3dCameraInfo *out)
{
    const Camera *cam = &c->cams[i];
    out->id = c->cam_id[i].len ? c->cam_id[i].data : NULL;
    out->width = cam->width;
    out->height = cam->height;
    out->colorbits = cam->colorbits;
    out->samples = cam->samples;
    out->secondary = cam->secondary;
    /* Flitter Camera.get_clear_color: the fog colour (grey when
     * monochrome) tinted, opaque, when there is fog */
    bool fog = cam->fog_max > cam->fog_min;
    double fc[3] = {cam->fog_color[0], cam->fog_color[1], cam->fog_color[2]};
    if (fog && cam->monochrome) fc[0] = fc[1] = fc[2] = 0.299 * fc[0] + 0.587 * fc[1] + 0.114 * fc[2];
    for (int k = 0; k < 3; k++) out->clear[k] = fog ? (float)(fc[k] * cam->tint[k]) : 0;
    out->clear[3] = fog ? 1 : 0;
}

int canvas3d_draw(Canvas3D *c, int i, GlTarget *t, const RenderLog *log, Buf *err)
{
    C3dCameraInfo info;
    canvas3d_camera(c, i, &info);
    int rc = render(c, &c->cams[i], t, info.clear, err);
    if (c->program_note[0] && !c->program_noted) {
        render_log(log, RLOG_WARNING, "%s", c->program_note);
        c->program_noted = true;
    }
    return rc;
}

int canvas3d_draw_scene(Canvas3D *c, const C3dScene *s, GlTarget *t, Buf *err)
{
    begin(c);
    c->env = NULL;
    c->width = t->w;
    c->height = t->h;
    c->ngroups = c->nlights = c->ninst = c->ncams = 0;
    c->groups = mem_grow(c->groups, &c->cap_groups, 1, sizeof *c->groups);
    c->groups[0] = (Group){.parent = -1, .max_lights = 2, .depth_sort = true, .depth_test = true,
                           .face_cull = true, .composite = COMP_OVER};
    c->ngroups = 1;
    c->lights = mem_grow(c->lights, &c->cap_lights, 2, sizeof *c->lights);
    memset(c->lights, 0, 2 * sizeof *c->lights);
    float *d = c->lights[0].data;
    for (int k = 0; k < 3; k++) d[k] = (float)s->ambient[k];
    d[3] = LIGHT_AMBIENT;
    d = c->lights[1].data;
    double len = sqrt(s->sun_direction[0] * s->sun_direction[0] + s->sun_direction[1] * s->sun_direction[1] +
                      s->sun_direction[2] * s->sun_direction[2]);
    for (int k = 0; k < 3; k++) d[k] = (float)s->sun[k], d[8 + k] = len > 0 ? (float)(s->sun_direction[k] / len) : 0;
    d[3] = LIGHT_DIRECTIONAL;
    d[14] = 1;   /* falloff 0;0;1;0 (unused by a directional light, whose distance is 1) */
    c->nlights = len > 0 && isfinite(len) ? 2 : 1;
    c->inst = mem_grow(c->inst, &c->cap_inst, s->nitems, sizeof *c->inst);
    for (size_t i = 0; i < s->nitems; i++) {
        const C3dItem *it = &s->items[i];
        MeshKey key = {.kind = it->shape == C3D_SHAPE_SPHERE     ? MESH_SPHERE
                               : it->shape == C3D_SHAPE_CYLINDER ? MESH_CYLINDER
                                                                 : MESH_BOX};
        key.segments = mesh_segments(key.kind, DEFAULT_SEGMENTS);
        Instance *in = &c->inst[c->ninst++];
        memset(in, 0, sizeof *in);
        in->mesh = mesh_cache_get(c->meshes, &key);
        memcpy(in->model.m, it->model, sizeof in->model.m);
        for (int k = 0; k < 3; k++) in->mat.albedo[k] = it->color[k];
        in->mat.ior = 1.5;
        in->mat.roughness = clampd(s->roughness, 1e-6, 1);
        in->mat.ao = 1;
        in->mat.transparency = clampd(it->transparency, 0, 1);
        in->group = 0;
    }
    Camera cam = {.width = t->w, .height = t->h, .fov = s->fov, .near = s->near, .far = s->far, .tint = {1, 1, 1},
                  .fog_curve = 1, .fov_ref = "horizontal", .samples = s->samples};
    memcpy(cam.position, s->position, sizeof cam.position);
    memcpy(cam.focus, s->focus, sizeof cam.focus);
    memcpy(cam.up, s->up, sizeof cam.up);
    camera_matrices(&cam, c->width, c->height);
    static const float clear[4] = {0, 0, 0, 0};
    int rc = render(c, &cam, t, clear, err);
    return rc;
}

void canvas3d_free(Canvas3D *c)
{
    if (!c) return;
    if (c->meshes) {
        mesh_cache_free(c->meshes);
        for (int i = 0; i < c->nprog; i++) c3d_program_free(&c->prog[i]);
        glDeleteBuffers(1, &c->instance_vbo);
        if (c->cull_ubo) glDeleteBuffers(1, &c->cull_ubo);
        c3d_backface_free(&c->backface);
        c3d_occlusion_free(&c->occlusion);
    }
    free(c->groups);
    free(c->lights);
    free(c->inst);
    free(c->order);
    free(c->split);
    free(c->tl);
    free(c->occ);
    free(c->seen);
    free(c->idata);
    free(c->lightbuf);
    free(c->lightsort);
    free(c->cullbuf);
    free(c->texsets);
    for (int i = 0; i < C3D_CAMERAS; i++) buf_free(&c->cam_id[i]);
    buf_free(&c->name);
    free(c);
}
