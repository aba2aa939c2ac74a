/* geom_uv_remap.h: new texture coordinates for a drawn model, Flitter's
 * `uv_remap=` (docs/canvas3d.md, "Controlling Model Shading"; its
 * behaviour read from models.pyx, UVRemap), applied after the shading
 * controls to the vertices the renderer draws (geom_primitives.h's
 * MeshData: 8 floats a vertex, position, normal, u, v). */
#ifndef FL_RENDER_GEOM_UV_REMAP_H
#define FL_RENDER_GEOM_UV_REMAP_H

#include "geom_primitives.h"

enum UvRemap { UV_REMAP_NONE, UV_REMAP_SPHERE, UV_REMAP_PLANE, UV_REMAP_BOOK };

/* The mapping a `uv_remap=` value names: "sphere", "plane" or "book";
 * anything else (NULL included) is UV_REMAP_NONE, the coordinates left as
 * they are, as in Flitter. */
int geom_uv_remap_parse(const char *name);

/* Replace [d]'s texture coordinates by [mapping], with [bounds] the model's
 * bounding box (min x, y, z, then max x, y, z, model units):
 *   - sphere: u the longitude atan2(y, x) in turns in [0, 1), v = 0.5 + the
 *     latitude atan2(z, |(x, y)|) in half turns, seen from the model's
 *     origin (the projection of the !sphere primitive); a triangle that
 *     straddles u = 0 (a corner above 0.75 and another below 0.25) gets
 *     copies of its low corners with u + 1, appended to the vertices;
 *   - plane: u, v = (x, y) scaled from the box's lower left corner to 1
 *     at its upper right (seen down the z axis);
 *   - book: v as plane; u the plane's u halved, on the right half of the
 *     texture for vertices whose normal faces +z, mirrored onto the left
 *     for the rest.
 * The arithmetic is Flitter's, in single precision where its arrays are.
 * A flat box side (zero width or height) gives infinite or NaN
 * coordinates, as in Flitter.
 *   errors: none (allocation failure goes through mem.h). */
void geom_uv_remap(MeshData *d, int mapping, const double bounds[6]);

#endif
