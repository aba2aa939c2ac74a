/* geom_mesh.h: an indexed triangle mesh in double precision, the form a
 * model takes in the geometry room (model files, vectors of vertices and
 * faces, constructive solid geometry, signed distance fields) before the
 * GL room turns it into vertex buffers (models_mesh.h).
 *
 * Positions are model units; triangles wind counter-clockwise seen from
 * outside (their right-hand normal points out of the volume). Texture
 * coordinates and normals are optional per-vertex arrays: a mesh made by
 * a boolean operation or an SDF has neither (Flitter docs/canvas3d.md,
 * "Constructive Solid Geometry": results lose their texture mapping), and
 * the renderer computes normals for a mesh without them.
 */
#ifndef FL_RENDER_GEOM_MESH_H
#define FL_RENDER_GEOM_MESH_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct GeomMesh {
    double *pos;      /* npos * 3: x, y, z */
    float *uv;        /* npos * 2: u, v, or NULL */
    float *normal;    /* npos * 3: unit normals, or NULL */
    uint32_t npos;
    uint32_t *tri;    /* ntri * 3 indices into pos */
    uint32_t ntri;
} GeomMesh;

/* Free [m]'s arrays and zero it (NULL, or a zeroed mesh, is a no-op). */
void geom_mesh_free(GeomMesh *m);

/* Append a vertex (uv and normal arrays are grown with it when present)
 * and return its index; append a triangle. [cap] counts are kept in the
 * caller's [pcap]/[tcap] (start them at 0 with a zeroed mesh).
 *   errors: none (allocation failure goes through mem.h). */
uint32_t geom_mesh_add_pos(GeomMesh *m, uint32_t *pcap, double x, double y, double z);
void geom_mesh_add_tri(GeomMesh *m, uint32_t *tcap, uint32_t a, uint32_t b, uint32_t c);

/* The signed volume enclosed by [m] (the divergence theorem: the sum of
 * each triangle's signed tetrahedron with the origin, a.(b x c)/6):
 * positive for a closed mesh wound outwards, model units cubed. */
double geom_mesh_volume(const GeomMesh *m);
/* The total area of [m]'s triangles, model units squared. */
double geom_mesh_area(const GeomMesh *m);
/* [m]'s bounding box: min x, y, z then max x, y, z (all zero when empty). */
void geom_mesh_bounds(const GeomMesh *m, double out[6]);
/* For every vertex of [m], the first vertex at exactly its position (-0
 * and +0 one position): an array of npos indices, to free. */
uint32_t *geom_mesh_position_ids(const GeomMesh *m);
/* Whether every edge of [m] is shared by exactly two triangles that run
 * along it in opposite directions (a closed, consistently wound surface). */
bool geom_mesh_is_closed(const GeomMesh *m);

/* Merge vertices whose positions are exactly equal into one (the first),
 * dropping uv and normal arrays (a merged vertex has no one texture
 * coordinate), and drop triangles that become degenerate (two equal
 * corners). The form boolean operations need: primitives and model files
 * repeat a position at every seam. */
void geom_mesh_weld(GeomMesh *m);

/* Flitter's repair= (docs/canvas3d.md, Models; trimesh's process with
 * validation, as models.pyx asks for it): vertices equal in position,
 * texture coordinate and normal merged into one; triangles with two
 * corners at one position, of no area, or over the same three positions
 * as an earlier one dropped; every connected part (triangles sharing a
 * side by position) wound as its first triangle; the whole turned inside
 * out when it is then closed and its volume negative; vertices no triangle
 * uses dropped. Normals are dropped (the renderer makes them from the new
 * winding); texture coordinates are kept.
 *   errors: none (allocation failure goes through mem.h). */
void geom_mesh_repair(GeomMesh *m);

/* A deep copy of [src] into [dst]. */
void geom_mesh_copy(const GeomMesh *src, GeomMesh *dst);

#ifdef __cplusplus
}
#endif

#endif
