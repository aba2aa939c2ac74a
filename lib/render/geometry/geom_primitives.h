/* geom_primitives.h: the primitive models of `!canvas3d` as triangle
 * meshes.
 *
 * Shapes, sizes and segment rules follow Flitter's documentation
 * (docs/canvas3d.md, "Primitive Models") and models.pyx: every model has
 * its origin at the centre of its bounding box; `!box` is the unit cube
 * (corners at +-0.5); `!sphere` the unit-radius sphere made of eight
 * subdivided octants (segments rounded up to a multiple of 4, at least 4;
 * an octant has segments/4 rows of triangles); `!cylinder` radius 1 and
 * height 1 along z with flat caps; `!cone` radius 1 at z=-0.5, its point
 * at z=+0.5 (both: at least 2 segments). Faces wind counter-clockwise seen
 * from outside. `flat` gives every triangle its own face normal; `invert`
 * turns the model inside out (winding and normals reversed).
 *
 * A vertex is 8 floats: position x,y,z, normal x,y,z, texture u,v, laid
 * out on the texture as docs/canvas3d.md "Primitive model texture
 * mapping" says (a box's uv_map=:standard, each face a sixth of the width,
 * or :repeat; the sphere equirectangular; the cylinder and cone wrapped).
 */
#ifndef FL_RENDER_GEOM_PRIMITIVES_H
#define FL_RENDER_GEOM_PRIMITIVES_H

#include <stdbool.h>
#include <stdint.h>

#include "geom_mesh.h"

/* MESH_OCTAGON is not a model: the flat octagon in the xy plane (normal
 * +z, counter-clockwise seen from +z) whose inscribed circle is the unit
 * circle, the proxy a sphere impostor is drawn with (canvas3d_draw.c). */
enum MeshKind { MESH_BOX, MESH_SPHERE, MESH_CYLINDER, MESH_CONE, MESH_OCTAGON };

/* The identity of one cached model shape. */
typedef struct MeshKey {
    int kind;       /* enum MeshKind */
    int segments;   /* as normalised by mesh_segments (0 for boxes) */
    bool flat, invert;
    bool uv_repeat; /* a box's uv_map=:repeat (each face the whole texture) */
    uint64_t model; /* not a primitive: the geometry room's model (geom_model_serial), else 0 */
    double snap;    /* a model's snap_edges (geom_shading.h) */
    int uv_remap;   /* a model's uv_remap= (geom_uv_remap.h), UV_REMAP_NONE for a primitive */
} MeshKey;

typedef struct MeshData {
    float *verts;         /* nverts * 8 floats */
    uint32_t nverts;
    uint32_t *index;      /* nindex indices, 3 per triangle */
    uint32_t nindex;
} MeshData;

/* The segment count used for [kind] when a node asks for [segments]
 * (Flitter's rounding; at most 4096 to bound the mesh's size). */
int mesh_segments(int kind, int segments);
/* Build the mesh of [key] into [out] (free with mesh_data_free).
 *   errors: none (allocation failure goes through mem.h). */
void mesh_build(const MeshKey *key, MeshData *out);
/* The vertices and indices mesh_build makes for [key] (counted from the
 * shapes' rules, without building it: a budget is asked first). */
void mesh_counts(const MeshKey *key, uint64_t *nverts, uint64_t *nindex);
void mesh_data_free(MeshData *m);

/* [key]'s mesh as a GeomMesh with its normals and texture coordinates
 * (free with geom_mesh_free), the form constructive solid geometry takes.
 *   errors: none (allocation failure goes through mem.h). */
void geom_primitive_mesh(const MeshKey *key, GeomMesh *out);
/* The same solid as an operand of constructive solid geometry: a
 * cylinder's and a cone's caps are fans from the rim's first point, not
 * from their centres, which is the same surface. Coaxial cylinders' caps
 * then share no vertex of 64 triangles each, on which CGAL's coplanar
 * corefinement spent about 10 s (a 64-segment tube, one cylinder less a
 * coaxial one: 1.5 s instead). Texture coordinates are the drawn mesh's,
 * but the caps' no longer vary radially (a boolean's result has none).
 *   errors: none (allocation failure goes through mem.h). */
void geom_primitive_solid(const MeshKey *key, GeomMesh *out);

#endif
