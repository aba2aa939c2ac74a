/* geom_csg.h: constructive solid geometry on triangle meshes (Flitter's
 * !union, !intersect, !difference and !trim; docs/canvas3d.md,
 * "Constructive Solid Geometry"), computed exactly by CGAL's Polygon Mesh
 * Processing (geom_csg.cpp) behind this C interface, and the convex hull
 * of a cloud of points, the solid `!model vertices=` makes without faces.
 *
 * Meshes are GeomMesh (geom_mesh.h): positions in model units, triangles
 * counter-clockwise seen from outside. A result has positions and
 * triangles only (no uv or normal arrays), is triangulated, closed and
 * wound outwards, and its arrays are allocated with malloc, to be freed
 * with geom_mesh_free. The arithmetic is exact (rational numbers behind
 * interval filters), so shared or coplanar faces (boxes side by side, a
 * trim through a union) are handled; result positions are the exact ones
 * rounded to the nearest double.
 *
 * Thread-safe: calls from different threads take turns on one lock
 * (geom_csg.cpp says why). A call takes a few milliseconds for boxes, tens
 * for meshes of a thousand triangles, a few hundred for 20,000.
 */
#ifndef FL_RENDER_GEOM_CSG_H
#define FL_RENDER_GEOM_CSG_H

#include <stddef.h>

#include "geom_mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

#include "buf.h"

typedef enum GeomBoolOp { GEOM_UNION, GEOM_INTERSECT, GEOM_DIFFERENCE } GeomBoolOp;

/* [out] = in[0] op in[1] op ... in[n-1]; for GEOM_DIFFERENCE in[0] less every other.
 * Inputs need not be welded (exactly equal positions are merged first, as primitives and
 * model files repeat a position at every seam); each must then be closed and bound a volume.
 * An input without triangles is the empty solid. [interrupt] (may be NULL) is polled
 * between the pairwise operations: once non-zero the call ends with -1 and "interrupted".
 * n == 1 gives the welded copy of in[0] (checked like any input).
 *   errors: -1 with one line appended to [err] (may be NULL), e.g. "mesh 2 of 3 is not a
 *           volume", "boolean operation failed"; out is then zeroed. An empty result (two
 *           disjoint solids intersected) is 0 with out->ntri == 0. Never throws, never aborts
 *           (running out of memory is the error "out of memory"). */
int geom_csg_boolean(GeomBoolOp op, const GeomMesh *const *in, size_t n, GeomMesh *out,
                     volatile int *interrupt, Buf *err);

/* The part of [in] where (p - origin) . normal <= 0, closed with a flat cap where the plane cuts it
 * (Flitter's !trim: the half-space the normal points into is removed). normal need not be unit length;
 * a zero normal is an error. origin is in model units. A plane that misses [in] gives its welded copy
 * or the empty mesh. Same errors as geom_csg_boolean (the input is "mesh 1 of 1"). */
int geom_csg_trim(const GeomMesh *in, const double origin[3], const double normal[3], GeomMesh *out,
                  Buf *err);

/* The convex hull of the [n] points [xyz] (3n doubles, model units), for
 * Flitter's `!model vertices=` without `faces=` (docs/canvas3d.md, Custom
 * Models): the triangles of the smallest convex solid that holds them,
 * wound outwards, its corners some of the points (exact predicates decide
 * which; a point on a face or an edge of the hull is not a corner).
 *   errors: -1 with the message appended to [err] (may be NULL): "fewer
 *           than 4 vertices have no hull with a volume", "the vertices lie
 *           in one plane: their hull has no volume", "a vertex is not
 *           finite"; out is then zeroed. */
int geom_csg_hull(const double *xyz, size_t n, GeomMesh *out, Buf *err);

#ifdef __cplusplus
}
#endif

#endif
