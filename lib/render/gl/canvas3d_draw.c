/* canvas3d_draw.c: the GL passes of one `!canvas3d` render group (see
 * canvas3d_scene.h; the order of passes is Flitter's canvas3d.pyx, render,
 * and docs/canvas3d.md, Instance Ordering). The group's lights go into its
 * program's uniform buffer; its instances are sorted by mesh (in order of
 * first appearance) and by the camera distance of the nearest corner of
 * the mesh's bounding box (Flitter's nearest_corner); with samples and
 * many lights, the opaque meshes may first be drawn depth only (the
 * occluders' pass, canvas3d_occlusion.h); opaque ones are dispatched per
 * mesh front to back in one instanced call (smooth spheres as ray-cast
 * impostors where they fit); translucent ones have their back faces
 * drawn, nearest first, into the back-face framebuffer
 * (canvas3d_backface.h); then transparent
 * and translucent ones are drawn back to front, the transparent ones with
 * depth writes off, the translucent ones with them on and with the
 * translucent program, always as meshes. */
#include "canvas3d_scene.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "canvas3d_shaders.h"
#include "mem.h"

/* last: it turns the library's names into calls through its table */
#include "gl_lib.h"

/* The number of MSAA samples whose rays the impostor shaders test. */
static int tested_samples(const Canvas3D *c) { return c->samples_used > 8 ? 8 : c->samples_used; }

/* The kind of camera a program is compiled for (C3D_* of
 * canvas3d_shaders.h), decided on the floats the shader would see. */
static unsigned camera_kind(const Camera *cam)
{
    float fog_min = (float)cam->fog_min, fog_max = (float)cam->fog_max, fog_curve = (float)cam->fog_curve;
    return (cam->orthographic ? C3D_ORTHOGRAPHIC : 0u) | (fog_max > fog_min && fog_curve > 0 ? C3D_FOG : 0u) |
           (cam->monochrome ? C3D_MONOCHROME : 0u);
}

/* The slot (C3D_LIGHT_SLOTS) of light [d] (16 floats): its kind, a point
 * light with a radius (the shader's test: light[2].w > 0) apart. */
static int light_slot(const float *d)
{
    switch ((int)d[3]) {
    case LIGHT_AMBIENT: return 0;
    case LIGHT_DIRECTIONAL: return 1;
    case LIGHT_POINT: return d[11] > 0 ? 3 : 2;
    case LIGHT_SPOT: return 4;
    default: return 5;
    }
}

/* The program for [key] (its camera, sample count and light list filled
 * in here from [cam], the frame and the [nl] lights of c->lightbuf),
 * made when not kept. A canvas compiles C3D_LISTED_MAX programs with a
 * list of lights at once and then one more every C3D_LISTED_FRAMES
 * frames; lights without a kept program are looped over meanwhile. */
static C3dProgram *program_for(Canvas3D *c, C3dFragSpec *key, const Camera *cam, int nl, Buf *err)
{
    key->nsamples = tested_samples(c);
    key->camera = camera_kind(cam);
    key->nlist = 0;
    if (nl > 0 && nl <= C3D_LIST_MAX) {
        key->nlist = nl;
        for (int i = 0; i < nl; i++) key->list[i] = c3d_slot_codes[light_slot(c->lightbuf + (size_t)16 * i)];
    }
    if (c->listed_made > 0 && c->frames - c->listed_at >= C3D_LISTED_FRAMES) {
        c->listed_made--;
        c->listed_at = c->frames;
    }
    for (int round = 0; round < 2; round++) {
        for (int i = 0; i < c->nprog; i++)
            if (memcmp(&c->prog[i].key, key, sizeof *key) == 0) return &c->prog[i];
        if (key->nlist == 0 || c->listed_made < C3D_LISTED_MAX) break;
        /* enough listed programs made: the looping one */
        key->nlist = 0;
        memset(key->list, 0, sizeof key->list);
    }
    C3dProgram made;
    Buf note = BUF_INIT;
    bool ok = c3d_program_make(&made, key, err, &note);
    if (ok && note.len && !c->program_note[0])
        snprintf(c->program_note, sizeof c->program_note, "%s", buf_line(&note));
    buf_free(&note);
    if (!ok) return NULL;
    if (key->nlist) c->listed_made++;
    int slot = c->nprog < C3D_PROGRAMS ? c->nprog++ : c->prog_turn++ % C3D_PROGRAMS;
    c3d_program_free(&c->prog[slot]);
    c->prog[slot] = made;
    return &c->prog[slot];
}

static void set_blend(int composite)
{
    glBlendEquation(GL_FUNC_ADD);
    switch (composite) {
    case COMP_SOURCE: glBlendFunc(GL_ONE, GL_ZERO); break;
    case COMP_DEST: glBlendFunc(GL_ZERO, GL_ONE); break;
    case COMP_DEST_OVER: glBlendFunc(GL_ONE_MINUS_DST_ALPHA, GL_ONE); break;
    case COMP_ADD: glBlendFunc(GL_ONE, GL_ONE); break;
    case COMP_SUBTRACT: glBlendEquation(GL_FUNC_SUBTRACT); glBlendFunc(GL_ONE, GL_ONE); break;
    case COMP_LIGHTEN: glBlendEquation(GL_MAX); glBlendFunc(GL_ONE, GL_ONE); break;
    case COMP_DARKEN: glBlendEquation(GL_MIN); glBlendFunc(GL_ONE, GL_ONE); break;
    default: glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA); break;
    }
}

/* The most light-instance-plane tests one draw makes to cull its lights
 * (canvas3d_cull.h): thousands of flat meshes under hundreds of lights
 * are drawn with all of them. */
#define CULL_WORK_MAX 200000

/* Leave out of the draw of [n] instances [list] of [mesh] with [sh] (in
 * use) the lights of c->lightbuf that none of them can see: when there
 * are such lights, bind a uniform buffer of the others, set [sh]'s
 * light_ends to [ends] (filled here) and return true; the caller puts
 * back c->cull_restore and c->light_ends after the draw. Only with a
 * looping program (c->cull_nl set by c3d_draw_group) and a mesh shader
 * (an impostor's mesh is its box or octagon, not its surface). */
static bool cull_lights(Canvas3D *c, Instance **list, int n, const GlMesh *mesh, const C3dShader *sh,
                        int ends[C3D_LIGHT_SLOTS])
{
    if (c->cull_nl <= 0 || mesh->planes.n <= 0 || sh->u_light_ends < 0 || sh->u_inverse_pv >= 0) return false;
    if ((double)n * c->cull_nl * mesh->planes.n > CULL_WORK_MAX) return false;
    int kept = 0;
    for (int k = 0, i = 0; k < C3D_LIGHT_SLOTS; k++) {
        /* (slots 2, 3 and 4: point lights, with and without a radius, and spot lights) */
        for (; i < c->light_ends[k]; i++) {
            const float *d = c->lightbuf + (size_t)16 * i;
            bool unseen = k >= 2 && k <= 4;
            for (int j = 0; unseen && j < n; j++) unseen = c3d_light_unseen(d, list[j]->model.m, &mesh->planes);
            if (!unseen) memcpy(c->cullbuf + (size_t)16 * kept++, d, 64);
        }
        ends[k] = kept;
    }
    int all = c->light_ends[C3D_LIGHT_SLOTS - 1];
    if (kept == all) return false;
    c->lights_culled += all - kept;
    if (!c->cull_ubo) glGenBuffers(1, &c->cull_ubo);
    /* new storage for each draw: the last draw may still read the old */
    glBindBuffer(GL_UNIFORM_BUFFER, c->cull_ubo);
    glBufferData(GL_UNIFORM_BUFFER, (GLsizeiptr)c->cull_bytes, NULL, GL_STREAM_DRAW);
    if (kept) glBufferSubData(GL_UNIFORM_BUFFER, 0, (GLsizeiptr)kept * 64, c->cullbuf);
    glBindBufferBase(GL_UNIFORM_BUFFER, 1, c->cull_ubo);
    glUniform1iv(sh->u_light_ends, C3D_LIGHT_SLOTS, ends);
    return true;
}

/* Draw [n] instances from [list] with the buffers of [mesh] and [sh]. */
static void draw_instances(Canvas3D *c, Instance **list, int n, const GlMesh *mesh, const C3dShader *sh)
{
    if (n <= 0 || !mesh) return;   /* (a mesh past the memory budget has no buffers) */
    size_t need = (size_t)n * C3D_INSTANCE_FLOATS;
    if (need > c->cap_idata) {
        c->cap_idata = need * 2;
        c->idata = mem_realloc_array(c->idata, c->cap_idata, sizeof(float));
    }
    for (int i = 0; i < n; i++) {
        const Instance *in = list[i];
        float *d = c->idata + (size_t)i * C3D_INSTANCE_FLOATS;
        for (int k = 0; k < 16; k++) d[k] = (float)in->model.m[k];
        double nm[9];
        m4_cofactor3(&in->model, nm);
        for (int k = 0; k < 9; k++) d[16 + k] = (float)nm[k];
        const Material *m = &in->mat;
        for (int k = 0; k < 3; k++) d[25 + k] = (float)m->albedo[k], d[29 + k] = (float)m->emissive[k];
        d[28] = (float)m->transparency;
        d[32] = (float)m->translucency;
        d[33] = (float)m->ior, d[34] = (float)m->metal, d[35] = (float)m->roughness, d[36] = (float)m->ao;
    }
    glUseProgram(sh->prog);
    glBindVertexArray(mesh->vao);
    glBindBuffer(GL_ARRAY_BUFFER, c->instance_vbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(need * sizeof(float)), c->idata, GL_STREAM_DRAW);
    static const int offsets[10] = {0, 4, 8, 12, 16, 19, 22, 25, 29, 33};
    static const int sizes[10] = {4, 4, 4, 4, 3, 3, 3, 4, 4, 4};
    for (int a = 0; a < 10; a++) {
        glEnableVertexAttribArray(3 + a);
        glVertexAttribPointer(3 + a, sizes[a], GL_FLOAT, GL_FALSE, C3D_INSTANCE_FLOATS * sizeof(float),
                              (const void *)(sizeof(float) * (size_t)offsets[a]));
        glVertexAttribDivisor(3 + a, 1);
    }
    int ends[C3D_LIGHT_SLOTS];
    bool culled = cull_lights(c, list, n, mesh, sh, ends);
    glDrawElementsInstanced(GL_TRIANGLES, mesh->nindex, GL_UNSIGNED_INT, NULL, n);
    if (culled) {
        glBindBufferBase(GL_UNIFORM_BUFFER, 1, c->cull_restore);
        glUniform1iv(sh->u_light_ends, C3D_LIGHT_SLOTS, c->light_ends);
    }
}

/* Whether a sphere instance may be drawn as an impostor: its bounding box
 * (the unit sphere's, +-1 in model space) lies wholly beyond the camera's
 * near plane, so that the box's front faces cover all of it. */
static bool impostor_fits(const Instance *in, const Camera *cam)
{
    const double *m = in->model.m;
    double reach = 0, d2 = 0;
    for (int k = 0; k < 3; k++) {
        reach += sqrt(m[k * 4] * m[k * 4] + m[k * 4 + 1] * m[k * 4 + 1] + m[k * 4 + 2] * m[k * 4 + 2]);
        d2 += (cam->position[k] - m[12 + k]) * (cam->position[k] - m[12 + k]);
    }
    return m[3] == 0 && m[7] == 0 && m[11] == 0 && m[15] == 1 && sqrt(d2) > reach + cam->near;
}

/* Whether [cam]'s view matrix is the look-at of its position and focus,
 * from which the impostor vertex shader builds its octagons (not the
 * identity of a look-at that failed: focus at the position, or up along
 * the line of sight). */
static bool view_is_look_at(const Camera *cam)
{
    const double *v = cam->view.m;
    double e[3], f[3], scale = 1;
    for (int k = 0; k < 3; k++) {
        e[k] = v[k] * cam->position[0] + v[4 + k] * cam->position[1] + v[8 + k] * cam->position[2] + v[12 + k];
        f[k] = v[k] * cam->focus[0] + v[4 + k] * cam->focus[1] + v[8 + k] * cam->focus[2] + v[12 + k];
        scale += fabs(cam->position[k]) + fabs(cam->focus[k]);
    }
    double eps = 1e-9 * scale;
    return fabs(e[0]) <= eps && fabs(e[1]) <= eps && fabs(e[2]) <= eps && fabs(f[0]) <= eps && fabs(f[1]) <= eps &&
           f[2] < -eps;
}

/* Whether an impostor (impostor_fits) of a camera whose view_is_look_at
 * may be drawn on the octagon facing the eye (the impostor vertex
 * shader's billboard) rather than on its box: its model matrix scales the unit sphere evenly (a sphere, not an
 * ellipsoid: equal, orthogonal columns) and the whole octagon, which lies
 * within 2.1 r of the sphere's centre, is beyond the near plane. The
 * octagon covers a sphere's picture with fewer fragments than its box's
 * front faces (1.05 times the sphere's disc, against 1.3 to 2.2). */
static bool billboard_fits(const Instance *in, const Camera *cam)
{
    const double *m = in->model.m, *v = cam->view.m;
    double len[3], dot01 = 0, dot02 = 0, dot12 = 0;
    for (int k = 0; k < 3; k++) {
        len[k] = sqrt(m[k * 4] * m[k * 4] + m[k * 4 + 1] * m[k * 4 + 1] + m[k * 4 + 2] * m[k * 4 + 2]);
        dot01 += m[k] * m[4 + k];
        dot02 += m[k] * m[8 + k];
        dot12 += m[4 + k] * m[8 + k];
    }
    double r = len[0], tol = 1e-6 * r;
    if (!(r > 0) || fabs(len[1] - r) > tol || fabs(len[2] - r) > tol) return false;
    if (fabs(dot01) > tol * r || fabs(dot02) > tol * r || fabs(dot12) > tol * r) return false;
    /* the centre's depth along the camera's axis; the octagon's plane is r
     * nearer than the centre along the line of sight and its rim at most
     * 1.1 r from that plane's middle */
    double depth = -(v[2] * m[12] + v[6] * m[13] + v[10] * m[14] + v[14]);
    return depth - 2.2 * r > cam->near * 1.01;
}

/* Whether dispatch may draw instances of [mesh] in a group that culls back
 * faces when [cull_back] as ray-cast impostors: smooth spheres (not
 * flat, not inverted), when the program has them. */
static bool impostor_mesh(const Canvas3D *c, const GlMesh *mesh, const C3dProgram *p, bool cull_back)
{
    return c->impostors && cull_back && p->impostor.prog && mesh->key.kind == MESH_SPHERE && !mesh->key.flat &&
           !mesh->key.invert;
}

/* Draw [n] instances of one mesh from [list] in that order: smooth spheres
 * (impostor_mesh) as ray-cast impostors where they fit (billboards with
 * p->billboard_occluded when [proxied], after the occluders' pass drew
 * their proxies), the rest as meshes with [mesh_sh] (p->mesh, or
 * p->occluded after the occluders' pass). */
static void dispatch(Canvas3D *c, Instance **list, int n, const C3dProgram *p, const Camera *cam, bool cull_back,
                     const C3dShader *mesh_sh, bool proxied)
{
    if (n <= 0) return;
    const GlMesh *mesh = list[0]->mesh;
    if (!impostor_mesh(c, mesh, p, cull_back)) {
        draw_instances(c, list, n, mesh, mesh_sh);
        return;
    }
    if (c->cap_split < 2 * n) {
        c->cap_split = 2 * n;
        c->split = mem_realloc_array(c->split, (size_t)c->cap_split, sizeof *c->split);
    }
    /* the billboards into c->split[0..), the box impostors into
     * c->split[n..), the meshes back into list, each in the list's order */
    Instance **bill = c->split, **boxed = c->split + n;
    bool look = view_is_look_at(cam);
    int nb = 0, nx = 0, nm = 0;
    for (int i = 0; i < n; i++)
        if (!impostor_fits(list[i], cam)) list[nm++] = list[i];
        else if (look && c->octagons && billboard_fits(list[i], cam)) bill[nb++] = list[i];
        else boxed[nx++] = list[i];
    MeshKey octagon = {.kind = MESH_OCTAGON}, box = {.kind = MESH_BOX};
    /* (draw_instances keeps the program in use) */
    const C3dShader *octagons = proxied ? &p->billboard_occluded : p->billboard.prog ? &p->billboard : &p->impostor;
    glUseProgram(octagons->prog);
    glUniform1i(octagons->u_billboard, 1);
    draw_instances(c, bill, nb, mesh_cache_get(c->meshes, &octagon), octagons);
    glUseProgram(p->impostor.prog);
    glUniform1i(p->impostor.u_billboard, 0);
    draw_instances(c, boxed, nx, mesh_cache_get(c->meshes, &box), &p->impostor);
    draw_instances(c, list, nm, mesh, mesh_sh);
}

/* Sort the [nl] lights of c->lightbuf by slot, keeping their order within
 * each (a counting sort), and set c->light_ends. */
static void sort_lights(Canvas3D *c, int nl)
{
    int count[C3D_LIGHT_SLOTS] = {0}, at[C3D_LIGHT_SLOTS];
    for (int i = 0; i < nl; i++) count[light_slot(c->lightbuf + (size_t)16 * i)]++;
    for (int k = 0, sum = 0; k < C3D_LIGHT_SLOTS; k++) {
        at[k] = sum;
        sum += count[k];
        c->light_ends[k] = sum;
    }
    for (int i = 0; i < nl; i++) {
        const float *d = c->lightbuf + (size_t)16 * i;
        memcpy(c->lightsort + (size_t)16 * at[light_slot(d)]++, d, 64);
    }
    float *t = c->lightbuf;
    c->lightbuf = c->lightsort;
    c->lightsort = t;
}

/* The camera's uniforms of [sh] (and the impostor's view of the target). */
static void set_uniforms(Canvas3D *c, const C3dShader *sh, const C3dProgram *p, const Camera *cam)
{
    if (!sh->prog) return;
    glUseProgram(sh->prog);
    float pv[16];
    for (int k = 0; k < 16; k++) pv[k] = (float)cam->pv.m[k];
    glUniformMatrix4fv(sh->u_pv, 1, GL_FALSE, pv);
    glUniform3f(sh->u_view_position, (float)cam->position[0], (float)cam->position[1], (float)cam->position[2]);
    glUniform3f(sh->u_view_focus, (float)cam->focus[0], (float)cam->focus[1], (float)cam->focus[2]);
    glUniform1i(sh->u_orthographic, cam->orthographic);
    glUniform1f(sh->u_fog_min, (float)cam->fog_min);
    glUniform1f(sh->u_fog_max, (float)cam->fog_max);
    glUniform1f(sh->u_fog_curve, (float)cam->fog_curve);
    glUniform3f(sh->u_fog_color, (float)cam->fog_color[0], (float)cam->fog_color[1], (float)cam->fog_color[2]);
    glUniform1i(sh->u_monochrome, cam->monochrome);
    glUniform3f(sh->u_tint, (float)cam->tint[0], (float)cam->tint[1], (float)cam->tint[2]);
    glUniform1iv(sh->u_light_ends, C3D_LIGHT_SLOTS, c->light_ends);
    glBindBufferBase(GL_UNIFORM_BUFFER, 1, p->ubo);
    if (sh->u_inverse_pv < 0) return;
    M4 inv;
    m4_inverse(&cam->pv, &inv);
    for (int k = 0; k < 16; k++) pv[k] = (float)inv.m[k];
    glUniformMatrix4fv(sh->u_inverse_pv, 1, GL_FALSE, pv);
    glUniform2f(sh->u_viewport_size, (float)c->width, (float)c->height);
    int ns = tested_samples(c);
    float offsets[16] = {0};
    for (int i = 0; i < ns; i++) glGetMultisamplefv(GL_SAMPLE_POSITION, (GLuint)i, offsets + 2 * i);
    glUniform1i(sh->u_nsamples, ns);
    glUniform2fv(sh->u_sample_offsets, 8, offsets);
}

/* Meshes in order of first appearance in the group (Flitter iterates its
 * group's dict of models, filled in tree order), each mesh's instances
 * nearest first. */
static int by_mesh_then_z(const void *a, const void *b)
{
    const Instance *x = *(Instance *const *)a, *y = *(Instance *const *)b;
    if (x->rank != y->rank) return x->rank < y->rank ? -1 : 1;
    return x->z < y->z ? -1 : x->z > y->z;
}

/* Number each instance's mesh by its first appearance in [list] (tree
 * order): Instance.rank. */
static void rank_meshes(Canvas3D *c, Instance **list, int n)
{
    int nseen = 0;
    for (int i = 0; i < n; i++) {
        int r = 0;
        while (r < nseen && c->seen[r] != list[i]->mesh) r++;
        if (r == nseen) {
            if (nseen == c->cap_seen) {
                c->cap_seen = c->cap_seen ? 2 * c->cap_seen : 8;
                c->seen = mem_realloc_array(c->seen, (size_t)c->cap_seen, sizeof *c->seen);
            }
            c->seen[nseen++] = list[i]->mesh;
        }
        list[i]->rank = r;
    }
}

static int far_first(const void *a, const void *b)
{
    const Instance *x = *(Instance *const *)a, *y = *(Instance *const *)b;
    return x->z > y->z ? -1 : x->z < y->z;
}

/* Flitter canvas3d.pyx, nearest_corner. */
static double nearest_corner(const float b[6], const M4 *vm)
{
    double best = 0;
    for (int i = 0; i < 8; i++) {
        double d = -vm->m[14];
        for (int j = 0; j < 3; j++) d -= vm->m[4 * j + 2] * b[((i >> j) & 1) * 3 + j];
        if (i == 0 || d < best) best = d;
    }
    return best;
}

static int near_first(const void *a, const void *b)
{
    const Instance *x = *(Instance *const *)a, *y = *(Instance *const *)b;
    return x->z < y->z ? -1 : x->z > y->z;
}

/* The blending, depth test and face culling of [g]. */
static void group_state(const Group *g)
{
    glEnable(GL_BLEND);
    set_blend(g->composite);
    if (g->depth_test) glEnable(GL_DEPTH_TEST);
    else glDisable(GL_DEPTH_TEST);
    if (g->face_cull) {
        glEnable(GL_CULL_FACE);
        glCullFace(g->cull_front ? GL_FRONT : GL_BACK);
    } else {
        glDisable(GL_CULL_FACE);
    }
}

/* Make [p]'s translucency programs and give them the camera's uniforms
 * and the group's lights (already in p->ubo, their slots' ends in
 * c->light_ends).
 *   errors: false when they cannot be made (said once through the skip
 *           log: translucent instances are then drawn as before, opaque
 *           in their light). */
static bool translucency_ready(Canvas3D *c, C3dProgram *p, const Camera *cam)
{
    Buf err = BUF_INIT;   /* said through the skip log, not in its words */
    bool ok = c3d_program_translucency(p, &err);
    buf_free(&err);
    if (!ok) {
        if (c->env) skiplog_note(c->env->skips, "canvas3d", "translucency= (no shader program: drawn opaque)");
        return false;
    }
    set_uniforms(c, &p->backface, p, cam);
    set_uniforms(c, &p->translucent, p, cam);
    return true;
}

/* The back-face pass of Flitter's translucency (canvas3d.pyx, render):
 * the back faces of the [n] translucent instances [list] (nearest first;
 * each run of one mesh in one call) lit by the group's lights, with their
 * eye distance, into the cleared back-face framebuffer (with [n] 0 it
 * holds no back face), depth tested among themselves, front faces culled,
 * without blending; then the group's target and state again, and the
 * back faces on texture unit 0.
 *   errors: false when the framebuffer cannot be made (nothing drawn,
 *           said once through the skip log). */
static bool back_faces(Canvas3D *c, const C3dProgram *p, Instance **list, int n, const Group *g)
{
    if (!c3d_backface_begin(&c->backface, c->width, c->height)) {
        if (c->env) skiplog_note(c->env->skips, "canvas3d", "translucency= (no back-face framebuffer: drawn opaque)");
        return false;
    }
    glDisable(GL_BLEND);
    glEnable(GL_DEPTH_TEST);
    glEnable(GL_CULL_FACE);
    glCullFace(GL_FRONT);
    for (int a = 0; a < n;) {
        int b = a;
        while (b < n && list[b]->mesh == list[a]->mesh) b++;
        draw_instances(c, list + a, b - a, list[a]->mesh, &p->backface);
        a = b;
    }
    c3d_backface_end(&c->backface);
    group_state(g);
    return true;
}

/* Lights of a render group, and layers of its opaque meshes (their
 * pixels' sum over the pixels of their union, as estimated by
 * layers()), from which the occluders' pass pays for itself (its cost:
 * clearing and filling a multisampled depth buffer, and the samples'
 * depth read by every mesh fragment; its gain: the lighting of the
 * hidden layers). */
#define OCCLUSION_MIN_LIGHTS 12
#define OCCLUSION_MIN_LAYERS 2.0

/* The area of the convex hull of the [n] (at most 8) points xy (x0, y0,
 * x1, ...): Andrew's monotone chain, then the shoelace formula. */
static double hull_area(double *xy, int n)
{
    /* sort by x, then y (insertion: n <= 8) */
    for (int i = 1; i < n; i++)
        for (int j = i; j > 0 && (xy[2 * j] < xy[2 * j - 2] ||
                                  (xy[2 * j] == xy[2 * j - 2] && xy[2 * j + 1] < xy[2 * j - 1])); j--) {
            double tx = xy[2 * j], ty = xy[2 * j + 1];
            xy[2 * j] = xy[2 * j - 2], xy[2 * j + 1] = xy[2 * j - 1];
            xy[2 * j - 2] = tx, xy[2 * j - 1] = ty;
        }
    double h[2 * 17];
    int k = 0;
    for (int pass = 0; pass < 2; pass++) {
        int start = k;
        for (int t = 0; t < n; t++) {
            int i = pass ? n - 1 - t : t;
            double x = xy[2 * i], y = xy[2 * i + 1];
            while (k - start >= 2) {
                double ax = h[2 * k - 4], ay = h[2 * k - 3], bx = h[2 * k - 2], by = h[2 * k - 1];
                if ((bx - ax) * (y - ay) - (by - ay) * (x - ax) > 0) break;
                k--;
            }
            h[2 * k] = x, h[2 * k + 1] = y;
            k++;
        }
        k--;   /* the last point is the other chain's first */
    }
    double area = 0;
    for (int i = 0; i < k; i++) {
        int j = (i + 1) % k;
        area += h[2 * i] * h[2 * j + 1] - h[2 * j] * h[2 * i + 1];
    }
    return fabs(area) / 2;
}

/* How many layers deep the [m] instances of c->occ lie on the picture:
 * the sum of the areas of their bounding boxes' projections (each the
 * convex hull of its 8 projected corners: about the pixels a closed mesh
 * with its back faces culled covers) over the area of the rectangle
 * around them all (clamped to the picture). 0 when a corner is at or
 * behind the eye's plane (no estimate: no pass). */
static double layers(const Canvas3D *c, const Camera *cam, int m)
{
    double sum = 0, lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (int i = 0; i < m; i++) {
        double xy[16];
        if (!c3d_project_box(&cam->pv, c->occ[i], c->width, c->height, xy)) return 0;
        for (int k = 0; k < 16; k++) {
            if (xy[k] < lo[k & 1]) lo[k & 1] = xy[k];
            if (xy[k] > hi[k & 1]) hi[k & 1] = xy[k];
        }
        sum += hull_area(xy, 8);
    }
    double size[2] = {c->width, c->height}, area = 1;
    for (int a = 0; a < 2; a++) {
        double l = lo[a] < 0 ? 0 : lo[a], h = hi[a] > size[a] ? size[a] : hi[a];
        area *= h > l ? h - l : 0;
    }
    return area > 0 ? sum / area : 0;
}

/* Whether [in] is drawn with a group's opaque instances (not moved to the
 * transparent ones of a sorted group, nor drawn with the translucent
 * program). */
static bool drawn_opaque(const Instance *in, bool sorted, bool see_through)
{
    if (sorted && (in->mat.transparency > 0 || in->mat.translucency > 0)) return false;
    return !(see_through && in->mat.translucency > 0);
}

/* The opaque spheres drawn on octagons from which the occluders' pass
 * draws their proxies (the spheres' own octagons then being drawn with
 * p->billboard_occluded): its cost is a depth buffer cleared and filled,
 * and a read of it by every sphere fragment; its gain, the rays and
 * lighting of hidden sphere fragments. */
#define PROXY_MIN_SPHERES 8

/* What the occluders' pass drew (a bit set). */
enum { OCCLUDED_MESHES = 1, OCCLUDED_SPHERES = 2 };

/* The occluders' pass of group [g] (canvas3d_occlusion.h), with a depth
 * test and composite "over" (an opaque fragment then replaces what is
 * behind it: hidden ones leave no trace), into c->occlusion:
 *   - with multisampling, its opaque non-sphere meshes of [list] (n,
 *     sorted by mesh) drawn depth only, when there are at least two, they
 *     lie OCCLUSION_MIN_LAYERS deep or more and the group has
 *     OCCLUSION_MIN_LIGHTS lights ([nl]) or more (with
 *     C3D_OCCLUSION_ALWAYS whenever there is one): the group's opaque
 *     meshes are then drawn with p->occluded (OCCLUDED_MESHES);
 *   - without multisampling, the proxies of its opaque spheres that
 *     dispatch draws on octagons, when there are PROXY_MIN_SPHERES of
 *     them or more (with C3D_OCCLUSION_ALWAYS, one or more): those
 *     octagons are then drawn with p->billboard_occluded
 *     (OCCLUDED_SPHERES). With samples, a multisampled depth buffer to
 *     clear and fill and every sample of it read cost more than the
 *     hidden fragments (bench/PROFILE.md, "Spheres' proxies").
 * Each discards only fragments that lie behind an opaque surface at
 * every sample: the picture is the same. Returns what was drawn (0:
 * nothing), the programs' uniforms set. */
static int occluders(Canvas3D *c, const Group *g, C3dProgram *p, Instance **list, int n, int nl, bool sorted,
                     bool see_through, const Camera *cam)
{
    bool always = c->occlusion_mode == C3D_OCCLUSION_ALWAYS;
    if (c->occlusion_mode == C3D_OCCLUSION_NEVER || !g->depth_test || g->composite != COMP_OVER) return 0;
    if (c->cap_occ < n) {
        c->cap_occ = n;
        c->occ = mem_realloc_array(c->occ, (size_t)c->cap_occ, sizeof *c->occ);
    }
    /* the meshes into c->occ[0..m), the spheres' proxies after them */
    int m = 0;
    if (c->samples_used >= 2 && (nl >= OCCLUSION_MIN_LIGHTS || always))
        for (int i = 0; i < n; i++) {
            const Instance *in = list[i];
            if (drawn_opaque(in, sorted, see_through) && in->mesh->key.kind != MESH_SPHERE) c->occ[m++] = list[i];
        }
    bool meshes = m >= 1 && (always || (m >= 2 && layers(c, cam, m) >= OCCLUSION_MIN_LAYERS)) &&
                  c3d_program_occlusion(p);
    if (!meshes) m = 0;
    int ns = 0;
    bool cull_back = g->face_cull && !g->cull_front;
    if (c->samples_used <= 1 && c->octagons && p->billboard.prog && view_is_look_at(cam))
        for (int i = 0; i < n; i++) {
            Instance *in = list[i];
            if (drawn_opaque(in, sorted, see_through) && impostor_mesh(c, in->mesh, p, cull_back) &&
                impostor_fits(in, cam) && billboard_fits(in, cam))
                c->occ[m + ns++] = in;
        }
    bool spheres = ns >= (always ? 1 : PROXY_MIN_SPHERES) && c3d_program_proxies(p);
    if (!meshes && !spheres) return 0;
    if (meshes) {
        set_uniforms(c, &p->depth, p, cam);
        set_uniforms(c, &p->occluded, p, cam);
    }
    if (spheres) {
        set_uniforms(c, &p->proxy, p, cam);
        set_uniforms(c, &p->billboard_occluded, p, cam);
    }
    if (!c3d_occlusion_begin(&c->occlusion, c->width, c->height, c->samples_used)) return 0;
    for (int a = 0; a < m;) {
        int b = a;
        while (b < m && c->occ[b]->mesh == c->occ[a]->mesh) b++;
        draw_instances(c, c->occ + a, b - a, c->occ[a]->mesh, &p->depth);
        a = b;
    }
    if (spheres) {
        MeshKey octagon = {.kind = MESH_OCTAGON};
        draw_instances(c, c->occ + m, ns, mesh_cache_get(c->meshes, &octagon), &p->proxy);
    }
    c3d_occlusion_end(&c->occlusion);
    return (meshes ? OCCLUDED_MESHES : 0) | (spheres ? OCCLUDED_SPHERES : 0);
}

/* The textures of set [ts] found (the canvas's env gives them by id),
 * bound from texture unit C3D_TEXTURE_UNIT with [sampler]; returns the
 * C3dFragSpec.textures bits of those found. */
static unsigned bind_textures(Canvas3D *c, const TexSet *ts, GLuint sampler)
{
    unsigned mask = 0;
    const CanvasImages *im = c->env ? c->env->images : NULL;
    for (int k = 0; k < C3D_TEXTURES; k++) {
        GLuint tex = ts->id[k][0] && im && im->texture ? im->texture(im->ctx, ts->id[k]) : 0;
        glActiveTexture(GL_TEXTURE0 + C3D_TEXTURE_UNIT + (GLenum)k);
        glBindTexture(GL_TEXTURE_2D, tex);
        glBindSampler(C3D_TEXTURE_UNIT + (GLuint)k, tex ? sampler : 0);
        if (tex) mask |= 1u << k;
    }
    glActiveTexture(GL_TEXTURE0);
    return mask;
}

static void unbind_textures(void)
{
    for (int k = 0; k < C3D_TEXTURES; k++) {
        glActiveTexture(GL_TEXTURE0 + C3D_TEXTURE_UNIT + (GLenum)k);
        glBindTexture(GL_TEXTURE_2D, 0);
        glBindSampler(C3D_TEXTURE_UNIT + (GLuint)k, 0);
    }
    glActiveTexture(GL_TEXTURE0);
}

/* Whether [in] is drawn among the transparent ones: a transparency, or a
 * transparency texture (Flitter canvas3d.pyx, render). */
static bool textured_transparent(const Canvas3D *c, const Instance *in)
{
    return in->mat.transparency > 0 || in->mat.translucency > 0 || c->texsets[in->mat.tex].id[C3D_TEXTURES - 1][0];
}

static int tex_then_z(const void *a, const void *b)
{
    const Instance *x = *(Instance *const *)a, *y = *(Instance *const *)b;
    if (x->mat.tex != y->mat.tex) return x->mat.tex < y->mat.tex ? -1 : 1;
    if (x->rank != y->rank) return x->rank < y->rank ? -1 : 1;
    return x->z < y->z ? -1 : x->z > y->z;
}

/* Draw the [n] textured instances of [list] (their z set) of group [g]:
 * the opaque ones ([transparent] false: front to back, each run of one
 * texture set and mesh at a time), or the transparent ones (back to
 * front, without writing depth). Each texture set draws with a mesh
 * program sampling the textures it has (canvas3d_shaders.h); lights as
 * c->lightbuf holds them ([nl]). Translucency is not drawn for textured
 * instances (they are lit as transparent ones). */
static void draw_textured(Canvas3D *c, const Group *g, Instance **list, int n, const Camera *cam,
                          const C3dFragSpec *base, int nl, bool transparent, Buf *err)
{
    int m = 0;
    bool sorted = g->depth_sort && g->depth_test;
    for (int i = 0; i < n; i++)
        if ((sorted && textured_transparent(c, list[i])) == transparent) c->tl[m++] = list[i];
    if (!m) return;
    if (transparent) {
        qsort(c->tl, (size_t)m, sizeof *c->tl, far_first);
        glDepthMask(GL_FALSE);
    } else {
        qsort(c->tl, (size_t)m, sizeof *c->tl, tex_then_z);
    }
    GLuint sampler;
    glGenSamplers(1, &sampler);
    for (int a = 0; a < m;) {
        int b = a;
        while (b < m && c->tl[b]->mat.tex == c->tl[a]->mat.tex && c->tl[b]->mesh == c->tl[a]->mesh) b++;
        const TexSet *ts = &c->texsets[c->tl[a]->mat.tex];
        if (ts->has_border) {
            glSamplerParameteri(sampler, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_BORDER);
            glSamplerParameteri(sampler, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_BORDER);
            glSamplerParameterfv(sampler, GL_TEXTURE_BORDER_COLOR, ts->border);
        } else {
            glSamplerParameteri(sampler, GL_TEXTURE_WRAP_S, ts->repeat_x ? GL_REPEAT : GL_CLAMP_TO_EDGE);
            glSamplerParameteri(sampler, GL_TEXTURE_WRAP_T, ts->repeat_y ? GL_REPEAT : GL_CLAMP_TO_EDGE);
        }
        glSamplerParameteri(sampler, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glSamplerParameteri(sampler, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        C3dFragSpec key = *base;
        key.textures = bind_textures(c, ts, sampler);
        C3dProgram *p = program_for(c, &key, cam, nl, err);
        if (!p) break;
        glBindBuffer(GL_UNIFORM_BUFFER, p->ubo);
        if (nl) glBufferSubData(GL_UNIFORM_BUFFER, 0, (GLsizeiptr)nl * 64, c->lightbuf);
        set_uniforms(c, &p->mesh, p, cam);
        draw_instances(c, c->tl + a, b - a, c->tl[a]->mesh, &p->mesh);
        a = b;
    }
    unbind_textures();
    glDeleteSamplers(1, &sampler);
    glDepthMask(GL_TRUE);
}

void c3d_draw_group(Canvas3D *c, int gi, Instance **list, int n, const Camera *cam, Buf *err)
{
    const Group *g = &c->groups[gi];
    /* the group's lights, then its ancestors', and their kinds */
    int nl = 0;
    unsigned kinds = 0;
    c->cull_nl = 0;
    if (c->cap_lightbuf < g->max_lights * 16) {
        c->cap_lightbuf = g->max_lights * 16;
        c->lightbuf = mem_realloc_array(c->lightbuf, (size_t)c->cap_lightbuf, sizeof(float));
        c->lightsort = mem_realloc_array(c->lightsort, (size_t)c->cap_lightbuf, sizeof(float));
        c->cullbuf = mem_realloc_array(c->cullbuf, (size_t)c->cap_lightbuf, sizeof(float));
    }
    for (int k = gi; k >= 0 && nl < g->max_lights; k = c->groups[k].parent)
        for (int l = 0; l < c->nlights && nl < g->max_lights; l++)
            if (c->lights[l].group == k) {
                memcpy(c->lightbuf + (size_t)16 * nl++, c->lights[l].data, 64);
                kinds |= 1u << (int)c->lights[l].data[3];
            }
    sort_lights(c, nl);
    C3dFragSpec key;
    memset(&key, 0, sizeof key);
    key.max_lights = g->max_lights;
    key.kinds = kinds;
    /* textured instances apart (to the end of the list): drawn with
     * programs of their own, the opaque ones first, the transparent ones
     * last */
    int ntex = 0;
    for (int i = 0, j = n; i < j;) {
        if (list[i]->mat.tex) {
            Instance *t = list[i];
            list[i] = list[--j];
            list[j] = t;
            ntex++;
        } else {
            i++;
        }
    }
    n -= ntex;
    Instance **textured = list + n;
    if (ntex) {
        if (c->cap_tl < ntex + n) {
            c->cap_tl = 2 * (ntex + n);
            c->tl = mem_realloc_array(c->tl, (size_t)c->cap_tl, sizeof *c->tl);
        }
        for (int i = 0; i < ntex; i++) {
            M4 vm = m4_mul(&cam->view, &textured[i]->model);
            textured[i]->z = nearest_corner(textured[i]->mesh->bounds, &vm);
        }
        group_state(g);
        size_t mark = err->len;
        draw_textured(c, g, textured, ntex, cam, &key, nl, false, err);
        if (err->len > mark) return;
    }
    size_t mark = err->len;
    C3dProgram *p = n ? program_for(c, &key, cam, nl, err) : NULL;
    if (!p) {
        if (ntex && err->len == mark) draw_textured(c, g, textured, ntex, cam, &key, nl, true, err);
        return;
    }
    glBindBuffer(GL_UNIFORM_BUFFER, p->ubo);
    if (nl) glBufferSubData(GL_UNIFORM_BUFFER, 0, (GLsizeiptr)nl * 64, c->lightbuf);
    set_uniforms(c, &p->mesh, p, cam);
    set_uniforms(c, &p->impostor, p, cam);
    set_uniforms(c, &p->billboard, p, cam);
    /* a looping program's draws may leave out lights their meshes cannot
     * see (a listed program's code is that of its lights, in order) */
    if (c->light_culling && p->key.nlist == 0 && nl > 0) {
        c->cull_nl = nl;
        c->cull_restore = p->ubo;
        c->cull_bytes = (size_t)p->key.max_lights * 64;
    }

    group_state(g);
    glDepthMask(GL_TRUE);
    bool sorted = g->depth_sort && g->depth_test;
    bool see_through = false;
    for (int i = 0; i < n && !see_through; i++) see_through = list[i]->mat.translucency > 0;
    if (see_through) {
        see_through = translucency_ready(c, p, cam);
        if (c->cap_tl < n) {
            c->cap_tl = 2 * n;
            c->tl = mem_realloc_array(c->tl, (size_t)c->cap_tl, sizeof *c->tl);
        }
    }
    /* unsorted, translucent instances find no back faces (Flitter gives
     * them an empty texture): only their specular light is drawn */
    if (see_through && !sorted) see_through = back_faces(c, p, NULL, 0, g);
    for (int i = 0; i < n; i++) {
        M4 vm = m4_mul(&cam->view, &list[i]->model);
        list[i]->z = sorted ? nearest_corner(list[i]->mesh->bounds, &vm) : 0;
    }
    rank_meshes(c, list, n);
    qsort(list, (size_t)n, sizeof *list, by_mesh_then_z);
    int occluded = occluders(c, g, p, list, n, nl, sorted, see_through, cam);
    /* opaque instances: per mesh, front to back; transparent and
     * translucent ones moved to the end (unsorted translucent ones drawn
     * after their mesh's others) */
    int nt = 0;
    Instance **transparent = c->order + c->ninst;   /* the second half of c->order */
    int i = 0;
    while (i < n) {
        int j = i, k = 0, kt = 0;
        while (j < n && list[j]->mesh == list[i]->mesh) {
            if (drawn_opaque(list[j], sorted, see_through))
                list[i + k++] = list[j];
            else if (sorted && (list[j]->mat.transparency > 0 || list[j]->mat.translucency > 0))
                transparent[nt++] = list[j];
            else
                c->tl[kt++] = list[j];
            j++;
        }
        dispatch(c, list + i, k, p, cam, g->face_cull && !g->cull_front,
                 occluded & OCCLUDED_MESHES ? &p->occluded : &p->mesh, occluded & OCCLUDED_SPHERES);
        draw_instances(c, c->tl, kt, list[i]->mesh, &p->translucent);
        i = j;
    }
    if (occluded) c3d_occlusion_unbind();
    if (nt == 0) {
        c->cull_nl = 0;
        if (ntex) draw_textured(c, g, textured, ntex, cam, &key, nl, true, err);
        return;
    }
    if (see_through) {
        /* Flitter: the translucent instances' back faces first, nearest first */
        int m = 0;
        for (int a = 0; a < nt; a++)
            if (transparent[a]->mat.translucency > 0) c->tl[m++] = transparent[a];
        qsort(c->tl, (size_t)m, sizeof *c->tl, near_first);
        see_through = back_faces(c, p, c->tl, m, g);
    }
    /* then all of them back to front, translucent ones writing depth (Flitter does) */
    qsort(transparent, (size_t)nt, sizeof *transparent, far_first);
    for (int a = 0; a < nt;) {
        bool tl = see_through && transparent[a]->mat.translucency > 0;
        int b = a;
        while (b < nt && transparent[b]->mesh == transparent[a]->mesh &&
               (see_through && transparent[b]->mat.translucency > 0) == tl)
            b++;
        glDepthMask(tl ? GL_TRUE : GL_FALSE);
        if (tl) draw_instances(c, transparent + a, b - a, transparent[a]->mesh, &p->translucent);
        else dispatch(c, transparent + a, b - a, p, cam, g->face_cull && !g->cull_front, &p->mesh, false);
        a = b;
    }
    glDepthMask(GL_TRUE);
    c->cull_nl = 0;
    if (ntex) draw_textured(c, g, textured, ntex, cam, &key, nl, true, err);
}
