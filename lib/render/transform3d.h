/* transform3d.h: the 3D transforms that node attributes give, shared by
 * the renderer's scene walk (gl/canvas3d.c) and the model tree
 * (geometry/geom_model.c). Flitter docs/canvas3d.md, "Transforms" and
 * "Primitive Models"; render/window/canvas3d.pyx for behaviour. */
#ifndef FL_RENDER_TRANSFORM3D_H
#define FL_RENDER_TRANSFORM3D_H

#include <stdbool.h>

#include "mat4.h"
#include "node.h"

/* [t] followed by `!transform` node [n]'s transform attributes, in the
 * node's attribute order: translate (1 or 3 numbers), scale (1 or 3),
 * rotate (a quaternion of 4, or 1 or 3 turns about x, y, z), rotate_x,
 * rotate_y, rotate_z (turns), matrix (16 numbers, column-major); others
 * and malformed values are ignored (Flitter update_transform_matrix). */
M4 transform3d_update(const Node *n, M4 t);

/* The unit model along z from [s] to [e] with x and y scaled by [radius]
 * (Flitter instance_start_end_matrix); false when degenerate (s == e or
 * radius <= 0). */
bool transform3d_start_end(const double s[3], const double e[3], double radius, M4 *out);

/* [t] followed by model node [n]'s own placement: `start`/`end`/`radius`
 * when `end` is given, else `position`, `rotation` (turns), `size`
 * (Flitter get_model_transform). [moved] (may be NULL) says whether any
 * applied. */
M4 transform3d_model(const Node *n, M4 t, bool *moved);

#endif
