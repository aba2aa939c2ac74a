/* models_mesh.c: the GL buffer cache of `!canvas3d`'s models (see
 * models_mesh.h). The cache is a plain array searched linearly: a scene
 * holds a handful of distinct shapes, while a shape may have thousands of
 * instances. */
#include "models_mesh.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <epoxy/gl.h>

#include "geom_shading.h"
#include "geom_uv_remap.h"
#include "mem.h"

/* last: it turns the library's names into calls through its table */
#include "gl_lib.h"

/* {===== the GL cache */

struct MeshCache {
    GlMesh **mesh;
    int n, cap;
    MemBudget *budget;
};

MeshCache *mesh_cache_new(MemBudget *budget)
{
    MeshCache *c = mem_calloc(1, sizeof(MeshCache));
    c->budget = budget;
    return c;
}

static bool same_key(const MeshKey *k, const MeshKey *key)
{
    return k->kind == key->kind && k->segments == key->segments && k->flat == key->flat && k->invert == key->invert &&
           k->uv_repeat == key->uv_repeat && k->model == key->model && k->snap == key->snap &&
           k->uv_remap == key->uv_remap;
}

static size_t mesh_bytes(uint64_t nverts, uint64_t nindex)
{
    return (size_t)(nverts * 8 * sizeof(float) + nindex * sizeof(uint32_t));
}

/* Upload [d] as a new cached mesh of [key] (the data is freed), its bytes
 * already charged to the budget. */
static GlMesh *upload(MeshCache *c, const MeshKey *key, MeshData *d)
{
    size_t bytes = mesh_bytes(d->nverts, d->nindex);
    GlMesh *g = mem_calloc(1, sizeof *g);
    g->key = *key;
    g->bytes = bytes;
    g->nindex = (int)d->nindex;
    for (int k = 0; k < 3; k++) g->bounds[k] = INFINITY, g->bounds[k + 3] = -INFINITY;
    for (uint32_t i = 0; i < d->nverts; i++)
        for (int k = 0; k < 3; k++) {
            float x = d->verts[(size_t)i * 8 + k];
            if (x < g->bounds[k]) g->bounds[k] = x;
            if (x > g->bounds[k + 3]) g->bounds[k + 3] = x;
        }
    c3d_planes_make(&g->planes, d->verts, d->nverts, d->index, d->nindex);
    glGenVertexArrays(1, &g->vao);
    glBindVertexArray(g->vao);
    glGenBuffers(1, &g->vbo);
    glBindBuffer(GL_ARRAY_BUFFER, g->vbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)d->nverts * 8 * sizeof(float), d->verts, GL_STATIC_DRAW);
    glGenBuffers(1, &g->ebo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g->ebo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)d->nindex * sizeof(uint32_t), d->index, GL_STATIC_DRAW);
    /* attributes 0..2: position, normal, uv (canvas3d_shaders.h) */
    for (int a = 0; a < 3; a++) {
        glEnableVertexAttribArray(a);
        glVertexAttribPointer(a, a == 2 ? 2 : 3, GL_FLOAT, GL_FALSE, 8 * sizeof(float),
                              (const void *)(sizeof(float) * (size_t)(a * 3)));
    }
    glBindVertexArray(0);
    mesh_data_free(d);
    if (c->n == c->cap) {
        c->cap = c->cap ? c->cap * 2 : 8;
        c->mesh = mem_realloc_array(c->mesh, (size_t)c->cap, sizeof *c->mesh);
    }
    c->mesh[c->n++] = g;
    return g;
}

const GlMesh *mesh_cache_get(MeshCache *c, const MeshKey *key)
{
    for (int i = 0; i < c->n; i++)
        if (same_key(&c->mesh[i]->key, key)) return c->mesh[i];
    /* asked of the budget before anything is built: a sphere of 4096
     * segments would be gigabytes */
    uint64_t nv, ni;
    mesh_counts(key, &nv, &ni);
    if (nv > UINT32_MAX || ni > UINT32_MAX || !mem_budget_reserve(c->budget, mesh_bytes(nv, ni))) return NULL;
    MeshData d;
    mesh_build(key, &d);
    if (mesh_bytes(d.nverts, d.nindex) != mesh_bytes(nv, ni)) {
        /* (mesh_counts and mesh_build disagree: charge what was made) */
        mem_budget_release(c->budget, mesh_bytes(nv, ni));
        if (!mem_budget_reserve(c->budget, mesh_bytes(d.nverts, d.nindex))) {
            mesh_data_free(&d);
            return NULL;
        }
    }
    return upload(c, key, &d);
}

const GlMesh *mesh_cache_get_model(MeshCache *c, const MeshKey *key, const GeomMesh *mesh, long frame)
{
    for (int i = 0; i < c->n; i++)
        if (same_key(&c->mesh[i]->key, key)) {
            c->mesh[i]->used = frame;
            return c->mesh[i];
        }
    GeomShading s = {.flat = key->flat, .snap = key->snap, .invert = key->invert};
    /* at most three vertices a triangle, and a sphere's uv_remap= copies
     * at most two corners of each */
    uint64_t ni = (uint64_t)mesh->ntri * 3, nv = key->flat || key->snap < 0.5 ? ni : mesh->npos;
    if (key->uv_remap == UV_REMAP_SPHERE) nv += (uint64_t)mesh->ntri * 2;
    if (!mem_budget_reserve(c->budget, mesh_bytes(nv, ni))) return NULL;
    MeshData d;
    geom_shade(mesh, &s, &d);
    if (key->uv_remap != UV_REMAP_NONE) {
        double bounds[6];
        geom_mesh_bounds(mesh, bounds);
        geom_uv_remap(&d, key->uv_remap, bounds);
    }
    mem_budget_release(c->budget, mesh_bytes(nv, ni));
    if (!mem_budget_reserve(c->budget, mesh_bytes(d.nverts, d.nindex))) {
        mesh_data_free(&d);
        return NULL;
    }
    GlMesh *g = upload(c, key, &d);
    if (g) g->used = frame;
    return g;
}

static void delete_mesh(MeshCache *c, GlMesh *g)
{
    glDeleteVertexArrays(1, &g->vao);
    glDeleteBuffers(1, &g->vbo);
    glDeleteBuffers(1, &g->ebo);
    mem_budget_release(c->budget, g->bytes);
    free(g);
}

void mesh_cache_sweep(MeshCache *c, long before)
{
    int k = 0;
    for (int i = 0; i < c->n; i++) {
        if (c->mesh[i]->key.model && c->mesh[i]->used < before) delete_mesh(c, c->mesh[i]);
        else c->mesh[k++] = c->mesh[i];
    }
    c->n = k;
}

void mesh_cache_free(MeshCache *c)
{
    if (!c) return;
    for (int i = 0; i < c->n; i++) delete_mesh(c, c->mesh[i]);
    free(c->mesh);
    free(c);
}

/* }===== */
