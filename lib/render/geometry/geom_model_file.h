/* geom_model_file.h: triangle meshes read from model files (OBJ, STL,
 * PLY, OFF, glTF/GLB, 3DS, Collada and the other formats Assimp reads),
 * for `!model filename=` (Flitter docs/canvas3d.md, "Models").
 *
 * Assimp is opened with dlopen the first time a file is read (as cairo
 * and FFmpeg are: a process that draws no model does not load it). */
#ifndef FL_RENDER_GEOM_MODEL_FILE_H
#define FL_RENDER_GEOM_MODEL_FILE_H

#include <stddef.h>

#include "buf.h"
#include "geom_mesh.h"

/* Read every mesh of the model file [path] into [out]: the scene's node
 * transforms applied, polygons triangulated, identical vertices joined,
 * the file's normals kept (smooth normals made where it has none) and its
 * first texture coordinates (none: all zero). Points and lines are left
 * out. Counter-clockwise winding as the file gives it.
 *   errors: -1 with one line appended to [err] ("cannot load model:
 *           REASON": the file missing or unreadable, not a format Assimp
 *           knows, damaged, no triangles, more than [max_vertices]
 *           vertices, or Assimp not installed); [out] is then zeroed.
 *           Never aborts. */
int geom_model_file_read(const char *path, size_t max_vertices, GeomMesh *out, Buf *err);

#endif
