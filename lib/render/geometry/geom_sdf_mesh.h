/* geom_sdf_mesh.h: the surface of a signed distance field as a triangle
 * mesh, by marching tetrahedra over a regular grid: the geometry behind
 * Flitter's `!sdf` node (Flitter docs/canvas3d.md, "Signed Distance
 * Fields"), which meshes the zero level set of a function over the box
 * `minimum`..`maximum` with grid spacing `resolution`.
 *
 * The distance function is the caller's (a Flitter function, a tree of
 * primitive distances, a test's closure): it is asked for the distances
 * of one plane of grid points at a time, so that an interpreted function
 * pays its per-call cost once per plane and the meshing holds two planes,
 * not the whole grid, in memory.
 */
#ifndef FL_RENDER_GEOM_SDF_MESH_H
#define FL_RENDER_GEOM_SDF_MESH_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "geom_mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

#include "buf.h"

/* Distances of [n] points: xyz holds 3n doubles (x, y, z per point, model
 * units), out gets n signed distances (negative inside; NaN counts as
 * outside). Returns false to stop the meshing (an interrupt, or an error
 * the caller reports). */
typedef bool (*GeomDistanceFn)(void *ctx, const double *xyz, size_t n, double *out);

/* The grid geom_sdf_mesh samples: per axis, points min + i*resolution for
 * i in 0..count-1 with count = ceil((max - min) / resolution) + 1 (the
 * last point at or just past max; counted in floating point, so count is
 * the smallest n >= 1 for which min + (n-1)*resolution >= max as the
 * machine computes it). [min], [max]: 3 doubles each (x, y, z, model
 * units); [resolution]: model units; [max_points]: the largest product of
 * the three counts allowed; [count]: receives the 3 counts.
 *   errors: false when resolution is not a positive finite number, min/max
 *           not finite or max < min on an axis, or the product of counts
 *           exceeds max_points (the budget), or a count exceeds
 *           UINT32_MAX; counts untouched then.
 * Method: Flitter docs/canvas3d.md, "Signed Distance Fields" (the box
 * minimum..maximum sampled every resolution). */
bool geom_sdf_grid(const double min[3], const double max[3], double resolution, uint64_t max_points,
                   uint32_t count[3]);

/* Mesh the surface where f = 0 (Flitter docs/canvas3d.md, "Signed
 * Distance Fields": the zero level set of a signed distance function,
 * negative inside and positive outside, over the box [min]..[max] at grid
 * spacing [resolution], by marching tetrahedra).
 *
 * Sampling: the grid of geom_sdf_grid([min], [max], [resolution],
 * [max_points]) (positions in model units). [f] is called once per grid
 * plane of constant z, in increasing z, with the count[0]*count[1] points
 * of that plane, x varying fastest; every grid point is asked exactly
 * once, and only the distances of two planes are held at a time (memory
 * O(count[0]*count[1]) besides the mesh). [ctx] is passed to f unchanged.
 * [interrupt] (may be NULL) is read before each plane; once non-zero the
 * meshing stops.
 *
 * The rule: a grid point is inside when its distance is < 0 (0, positive
 * and NaN are outside). Space outside the box counts as outside, as if
 * the grid were surrounded by a layer of points at distance +infinity, so
 * the surface is always closed: where the shape is cut by the box it is
 * capped on the box's faces (the outermost grid points). Each grid cube is
 * split into 6 tetrahedra around its diagonal from the lowest corner to
 * the highest (the same split in every cube, so the faces of neighbouring
 * cubes match); a tetrahedron with 1 or 3 corners inside gives one
 * triangle, with 2 inside two. Each cut edge of the tetrahedra gives one
 * vertex, shared by every triangle on that edge, placed by linear
 * interpolation of the two distances (at the inside end when the outside
 * one is +infinity or NaN, as on the layer around the box; at the outside
 * end when the inside one is -infinity and the outside one finite;
 * exactly at the outside grid point when its distance is exactly 0).
 * The mesh bounds the region where the piecewise-linear interpolation of
 * the samples over the tetrahedra is negative; where the surface runs
 * exactly through grid points (an axis-aligned box with its faces on grid
 * planes) a tetrahedron whose corners are all on it adds nothing, which
 * cuts some of the box's edges by half a grid cube (tests/unit/
 * test_geom_sdf.c works the box out).
 *
 * Welding: a vertex that lands on a grid point (by the rules above, or
 * because the interpolation rounds onto the point's coordinate) is that
 * grid point's one vertex, so no two vertices share a position (what
 * geom_mesh_weld would do is already done). Triangles with two equal
 * corners are left out, and so are pairs of triangles on the same three
 * vertices wound opposite ways: where the inside is one grid point thick
 * against the box, NaN or +infinity, both its sides fall on the same grid
 * points, a sheet of no volume (a grid one point thick along an axis
 * gives no triangles). Vertices no triangle uses are dropped.
 *
 * Result: 0 with [out] (overwritten, not freed first: pass a zeroed or
 * freed mesh) holding the mesh: positions in model units, triangles
 * counter-clockwise seen from outside (their normal points from inside to
 * outside), no uv and no normals; release it with geom_mesh_free. 0 with
 * out->ntri == 0 (npos 0, arrays NULL) when no grid point is inside or
 * the inside is only a sheet of no volume. [min], [max] (3 doubles each)
 * and [out] must not be NULL.
 *   errors: -1 with [out] zeroed and a one-line message appended to
 *           [err] (which may be NULL):
 *           "bad resolution R" (not a positive finite number);
 *           "bad bounds" (min/max not finite, or max < min on an axis);
 *           "resolution R is below the precision of the bounds" (two grid
 *           coordinates min + i*resolution equal in floating point);
 *           "resolution R gives N points, more than the budget of M" (the
 *           product of counts past [max_points]);
 *           "interrupted" (*interrupt non-zero before a plane, or when f
 *           stopped); "distance function failed" (f returned false with no
 *           interrupt set; f may have left its own message elsewhere);
 *           "no distance function" (f NULL); "the mesh has too many
 *           vertices or triangles" (past 2^32 - 2, only for an absurd
 *           budget); "resolution R gives N points, ..." also when a count
 *           passes UINT32_MAX. Allocation failure goes through mem.h.
 * Cost: max_points bounds everything: at most 8 vertices per grid point
 * (its 7 edges and itself, plus the surrounding layer) and 12 triangles
 * per grid cube, so a budget keeps the mesh, and the uint32 counts,
 * bounded (a count that would pass 2^32 - 2 is the error above, never a
 * wrap); time is linear in the grid size plus the surface's size (and
 * n log n in the triangles that touch grid points, for the sheets). */
int geom_sdf_mesh(GeomDistanceFn f, void *ctx, const double min[3], const double max[3], double resolution,
                  uint64_t max_points, volatile int *interrupt, GeomMesh *out, Buf *err);

#ifdef __cplusplus
}
#endif

#endif
