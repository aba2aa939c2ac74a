/* geom_shading.h: a model's mesh as the vertices the renderer draws (8
 * floats each: position, normal, texture u, v; geom_primitives.h's
 * MeshData), with Flitter's shading controls (docs/canvas3d.md,
 * "Controlling Model Shading"): flat faces, edges snapped at an angle,
 * smooth normals, turned inside out. */
#ifndef FL_RENDER_GEOM_SHADING_H
#define FL_RENDER_GEOM_SHADING_H

#include <stdbool.h>

#include "geom_mesh.h"
#include "geom_primitives.h"

/* The shading of one drawn model. */
typedef struct GeomShading {
    bool flat;          /* flat=true: every triangle its own face normal */
    double snap;        /* snap_edges= in turns: where two faces meet at more
                           than this angle the edge stays sharp, elsewhere
                           normals are averaged; >= 0.5 keeps the mesh's own
                           normals (smooth ones made where it has none);
                           <= 0 is flat */
    bool invert;        /* invert=true: normals and winding reversed */
} GeomShading;

/* [m]'s drawn vertices and triangles into [out] (free with
 * mesh_data_free). Smooth normals are the area-weighted sums of the
 * faces' normals around a vertex (Flitter models.pyx, fill_in_normals);
 * snapped ones the same sum over only the faces within the angle of the
 * corner's own face, vertices at the same position counted as one.
 *   errors: none (allocation failure goes through mem.h). */
void geom_shade(const GeomMesh *m, const GeomShading *s, MeshData *out);

#endif
