/* canvas3d_cull.h: lights that cannot reach a mesh, left out of its draw.
 *
 * The lighting shader (canvas3d_shaders.c) adds a point or spot light's
 * light to a fragment only where NdotL = clamp(dot(N, L), 0, 1) is not 0,
 * N the fragment's normal (the normal matrix times the interpolated
 * vertex normal) and L the direction from the fragment's position P to
 * the light: its position, or for a point light with a radius r, in the
 * specular pass, a point within r of it. Where every face of a mesh is
 * flat (its three vertices hold one normal), the fragments of a face lie
 * on the face's plane with that normal, so a light whose centre lies
 * behind the planes of all faces by more than its radius gives every
 * fragment NdotL = 0 in every pass: it adds nothing, and leaving it out of
 * the draw's list of lights gives the same picture, bit for bit (the
 * other lights' sums are made in the same order). A light inside a closed
 * convex mesh whose normals point out (the outer wall of a glass box with
 * lights inside: Flitter's examples/bounce.fl) is such a light.
 *
 * The test (c3d_light_unseen) works on each distinct normal of the mesh
 * (its "planes": the faces sharing it, with their vertices' extreme
 * offsets along it) in world space, with a margin of 1/1000 of the
 * coordinates' size for the single-precision arithmetic of the shader
 * (its rounding is some 1e-6 of them); a mesh with a smooth face, a face
 * whose normal leans off its plane (a model file's normals: a sample's
 * position, interpolated at the pixel's centre, may lie off the triangle,
 * where only the face's own plane bounds it), or more than C3D_PLANES_MAX
 * normals, has no planes and culls nothing.
 * Ambient, directional and line lights are never culled.
 */
#ifndef FL_RENDER_CANVAS3D_CULL_H
#define FL_RENDER_CANVAS3D_CULL_H

#include <stdbool.h>
#include <stdint.h>

/* The most distinct normals a mesh may have to be culled against. */
#define C3D_PLANES_MAX 32

/* One normal of a mesh's flat faces, in model space: the normal as its
 * vertices hold it, and the vertices of those faces with the least and
 * the greatest dot(normal, position). */
typedef struct C3dPlane {
    float normal[3];
    float low[3], high[3];
} C3dPlane;

/* A mesh's planes: n of them, or n = 0 when lights cannot be culled
 * against it. */
typedef struct C3dPlanes {
    int n;
    C3dPlane plane[C3D_PLANES_MAX];
} C3dPlanes;

/* The planes of the mesh of [nverts] vertices [verts] (8 floats each:
 * position, normal, uv; canvas3d_shaders.h) and triangles [index]
 * ([nindex] indices, 3 a triangle): none (n = 0) when a triangle's three
 * normals differ, its normal is not perpendicular to it (its vertices'
 * offsets along it differ by more than 1e-5 of its largest coordinate),
 * a number is not finite, the mesh has no triangle or more than
 * C3D_PLANES_MAX normals. Never fails. */
void c3d_planes_make(C3dPlanes *out, const float *verts, uint32_t nverts, const uint32_t *index,
                     uint32_t nindex);

/* Whether [light] (the shader's mat4 of 16 floats: canvas3d_shaders.h)
 * adds nothing to any fragment of a mesh with [planes] drawn with the
 * model matrix [model] (16 doubles, column-major, affine): a point light
 * (with its radius) or a spot light behind every plane, by the margin
 * above. False whenever in doubt: another kind of light, a mesh without
 * planes, a degenerate matrix, a non-finite number. */
bool c3d_light_unseen(const float light[16], const double model[16], const C3dPlanes *planes);

#endif
