/* models_mesh.h: the OpenGL buffers of `!canvas3d`'s models, cached on
 * the context that made them: primitives by their MeshKey
 * (geom_primitives.h), and the meshes of the geometry room's models
 * (files, vectors, CSG, SDF) by the model's identity.
 */
#ifndef FL_RENDER_MODELS_MESH_H
#define FL_RENDER_MODELS_MESH_H

#include <stdbool.h>
#include <stdint.h>

#include "canvas3d_cull.h"
#include "geom_primitives.h"
#include "mem.h"

/* A model's buffers on the GL context current when it was made. */
typedef struct GlMesh {
    MeshKey key;
    unsigned vao, vbo, ebo;   /* GL names */
    int nindex;
    float bounds[6];          /* model-space min x,y,z and max x,y,z */
    long used;                /* the frame it was last asked for (models' meshes) */
    size_t bytes;             /* charged to the budget */
    C3dPlanes planes;         /* its flat faces' normals, for culling lights (canvas3d_cull.h) */
} GlMesh;

typedef struct MeshCache MeshCache;

/* A cache charging its buffers to [budget] (may be NULL). */
MeshCache *mesh_cache_new(MemBudget *budget);
/* The GL mesh of [key], built and uploaded the first time it is asked for
 * (the cache's context must be current); the pointer stays valid until
 * mesh_cache_free. */
const GlMesh *mesh_cache_get(MeshCache *c, const MeshKey *key);
/* The GL mesh of model [key] (key->model set), made from [mesh] with
 * [key]'s shading the first time (geom_shading.h), or NULL when its
 * buffers do not fit in the memory budget. Marked used in [frame]. */
const GlMesh *mesh_cache_get_model(MeshCache *c, const MeshKey *key, const GeomMesh *mesh, long frame);
/* Delete the buffers of models' meshes not asked for since frame [before]. */
void mesh_cache_sweep(MeshCache *c, long before);
/* Delete the buffers (the context must be current) and free [c] (NULL is a no-op). */
void mesh_cache_free(MeshCache *c);

#endif
