/* models_mesh.h: the OpenGL buffers of `!canvas3d`'s models, cached on
 * the context that made them: primitives by their MeshKey
 * (geom_primitives.h), and the meshes of the geometry room's models
 * (files, vectors, CSG, SDF) by the model's identity.
 */
#ifndef FL_RENDER_MODELS_MESH_H
#define FL_RENDER_MODELS_MESH_H

#include <stdbool.h>
#include <stdint.h>

#include "geom_primitives.h"

/* A model's buffers on the GL context current when it was made. */
typedef struct GlMesh {
    MeshKey key;
    unsigned vao, vbo, ebo;   /* GL names */
    int nindex;
    float bounds[6];          /* model-space min x,y,z and max x,y,z */
} GlMesh;

typedef struct MeshCache MeshCache;

MeshCache *mesh_cache_new(void);
/* The GL mesh of [key], built and uploaded the first time it is asked for
 * (the cache's context must be current); the pointer stays valid until
 * mesh_cache_free. */
const GlMesh *mesh_cache_get(MeshCache *c, const MeshKey *key);
/* Delete the buffers (the context must be current) and free [c] (NULL is a no-op). */
void mesh_cache_free(MeshCache *c);

#endif
