/* models_mesh.c: the GL buffer cache of `!canvas3d`'s models (see
 * models_mesh.h). The cache is a plain array searched linearly: a scene
 * holds a handful of distinct shapes, while a shape may have thousands of
 * instances. */
#include "models_mesh.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <epoxy/gl.h>

#include "mem.h"

/* last: it turns the library's names into calls through its table */
#include "gl_lib.h"

/* {===== the GL cache */

struct MeshCache {
    GlMesh **mesh;
    int n, cap;
};

MeshCache *mesh_cache_new(void) { return mem_calloc(1, sizeof(MeshCache)); }

const GlMesh *mesh_cache_get(MeshCache *c, const MeshKey *key)
{
    for (int i = 0; i < c->n; i++) {
        const MeshKey *k = &c->mesh[i]->key;
        if (k->kind == key->kind && k->segments == key->segments && k->flat == key->flat && k->invert == key->invert &&
            k->uv_repeat == key->uv_repeat)
            return c->mesh[i];
    }
    MeshData d;
    mesh_build(key, &d);
    GlMesh *g = mem_calloc(1, sizeof *g);
    g->key = *key;
    g->nindex = (int)d.nindex;
    for (int k = 0; k < 3; k++) g->bounds[k] = INFINITY, g->bounds[k + 3] = -INFINITY;
    for (uint32_t i = 0; i < d.nverts; i++)
        for (int k = 0; k < 3; k++) {
            float x = d.verts[(size_t)i * 8 + k];
            if (x < g->bounds[k]) g->bounds[k] = x;
            if (x > g->bounds[k + 3]) g->bounds[k + 3] = x;
        }
    glGenVertexArrays(1, &g->vao);
    glBindVertexArray(g->vao);
    glGenBuffers(1, &g->vbo);
    glBindBuffer(GL_ARRAY_BUFFER, g->vbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)d.nverts * 8 * sizeof(float), d.verts, GL_STATIC_DRAW);
    glGenBuffers(1, &g->ebo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g->ebo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)d.nindex * sizeof(uint32_t), d.index, GL_STATIC_DRAW);
    /* attributes 0..2: position, normal, uv (canvas3d_shaders.h) */
    for (int a = 0; a < 3; a++) {
        glEnableVertexAttribArray(a);
        glVertexAttribPointer(a, a == 2 ? 2 : 3, GL_FLOAT, GL_FALSE, 8 * sizeof(float),
                              (const void *)(sizeof(float) * (size_t)(a * 3)));
    }
    glBindVertexArray(0);
    mesh_data_free(&d);
    if (c->n == c->cap) {
        c->cap = c->cap ? c->cap * 2 : 8;
        c->mesh = mem_realloc_array(c->mesh, (size_t)c->cap, sizeof *c->mesh);
    }
    c->mesh[c->n++] = g;
    return g;
}

void mesh_cache_free(MeshCache *c)
{
    if (!c) return;
    for (int i = 0; i < c->n; i++) {
        glDeleteVertexArrays(1, &c->mesh[i]->vao);
        glDeleteBuffers(1, &c->mesh[i]->vbo);
        glDeleteBuffers(1, &c->mesh[i]->ebo);
        free(c->mesh[i]);
    }
    free(c->mesh);
    free(c);
}

/* }===== */
