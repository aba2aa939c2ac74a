/* canvas3d_shaders.h: the GLSL 3.30 program of `!canvas3d`'s standard
 * lighting, as C strings (canvas3d_shaders.c).
 *
 * Vertex inputs (fixed locations): 0 position, 1 normal, 2 uv (per
 * vertex); per instance 3..6 the model matrix, 7..9 the normal matrix
 * (the cofactor of the model matrix's upper 3x3), 10 albedo RGB and
 * transparency, 11 emissive RGB and translucency, 12 ior, metal,
 * roughness, ao: 37 floats per instance.
 *
 * Lights are a std140 uniform block `Lights` of MAX_LIGHTS mat4 (the
 * fragment source starts with `#define MAX_LIGHTS N`, filled in by
 * canvas3d_fragment_source); a light's columns are (color, type),
 * (position, inner cone cosine), (direction, outer cone cosine or radius),
 * falloff (A, B, C, D); a line light's position is its start and its
 * direction the vector from start to end (not normalised, never zero).
 * Types are the LIGHT_ constants below (Flitter canvas3d.pyx, LightType).
 */
#ifndef FL_RENDER_CANVAS3D_SHADERS_H
#define FL_RENDER_CANVAS3D_SHADERS_H

#include <stdbool.h>
#include <stddef.h>

enum { LIGHT_AMBIENT = 1, LIGHT_DIRECTIONAL = 2, LIGHT_POINT = 3, LIGHT_SPOT = 4, LIGHT_LINE = 5 };

/* Floats per instance in the instance buffer. */
#define C3D_INSTANCE_FLOATS 37

/* The vertex shader of meshes. */
extern const char canvas3d_vertex_source[];
/* The vertex shader of sphere impostors: the same per-instance inputs,
 * position 0 the corners of the unit box (+-0.5, doubled to enclose the
 * unit sphere); the fragment shader finds the sphere in it. */
extern const char canvas3d_impostor_vertex_source[];
/* Fragment shader variants: meshes; sphere impostors (on their box or
 * octagon); sphere impostors on their octagon only (BILLBOARD: for
 * spheres wholly beyond the near plane, with the sample count fixed at
 * compile time); the back-face pass
 * of translucent meshes (out: rgb the light arriving on the back face, a
 * its distance from the eye); translucent meshes (the mesh shader plus the
 * light let through from the back-face pass, read from the uniform
 * sampler2D backface_data, texture unit 0); meshes behind occluders
 * (OCCLUDED: the mesh shader, first discarding a fragment that lies, at
 * every one of the NSAMPLES samples of its pixel, behind the depth of
 * the uniform sampler2DMS occluders, texture unit 1:
 * canvas3d_occlusion.h); the occluders' depth pass (DEPTH: no output);
 * sphere impostors on their octagon behind occluders (BILLBOARD_OCCLUDED,
 * one sample only: BILLBOARD, first discarding a fragment whose octagon,
 * then whose surface, lies behind the depth of the uniform sampler2D
 * occluders, texture unit 1); the spheres' proxies in
 * the occluders' pass (PROXY: DEPTH's shader, the impostor vertex
 * shader's `proxy` octagon through the centre). */
enum { C3D_FRAG_MESH, C3D_FRAG_IMPOSTOR, C3D_FRAG_BACKFACE, C3D_FRAG_TRANSLUCENT, C3D_FRAG_BILLBOARD,
       C3D_FRAG_OCCLUDED, C3D_FRAG_DEPTH, C3D_FRAG_BILLBOARD_OCCLUDED, C3D_FRAG_PROXY };

/* What of the camera a fragment shader is compiled for (C3dFragSpec's
 * camera bits), so that the paths a camera does not take are not in it
 * (a CPU rasteriser runs both sides of a branch): an orthographic view;
 * fog (fog_max > fog_min and fog_curve > 0, as single-precision floats,
 * the uniforms' values); monochrome. */
enum { C3D_ORTHOGRAPHIC = 1, C3D_FOG = 2, C3D_MONOCHROME = 4 };

/* A group's lights are uploaded sorted by what their code is (stable
 * within each): ambient, directional, point, point with a radius (two
 * passes), spot, line (two passes), these 6 slots; the uniform
 * `int light_ends[C3D_LIGHT_SLOTS]` gives where each slot's lights end
 * (cumulative), and the looping shader runs one loop per slot, its code
 * only that of the slot's kind. */
#define C3D_LIGHT_SLOTS 6

/* At most this many lights are compiled in one by one (C3dFragSpec.list). */
#define C3D_LIST_MAX 8
/* A listed light's code: its LIGHT_ type, plus C3D_TWO_PASS when it is
 * lit in two passes (a line light, or a point light with a radius > 0). */
#define C3D_TWO_PASS 8
/* The code of each slot's lights (C3D_LIGHT_SLOTS order). */
extern const unsigned char c3d_slot_codes[C3D_LIGHT_SLOTS];

/* What a fragment shader is made for (zero it, then fill it in: programs
 * are cached by its bytes):
 *   max_lights  the size of the Lights block (MAX_LIGHTS);
 *   kinds       the kinds of light it has code for (bit 1 << LIGHT_*;
 *               ambient light is always there): a light of another kind
 *               contributes nothing;
 *   variant     C3D_FRAG_*;
 *   textures    the material textures it samples (bits above; meshes
 *               only: an impostor has no texture coordinates);
 *   nsamples    the samples the BILLBOARD variant tests: the first
 *               [nsamples] (clamped to 1..8; 1: no sample mask) of
 *               sample_offsets; the samples of the occluders the
 *               OCCLUDED variant reads; the others ignore it;
 *   camera      C3D_* camera bits above;
 *   nlist       0: the lights are read in one loop per slot (above),
 *               over the uniform light_ends; 1..C3D_LIST_MAX:
 *               exactly [nlist] lights, list[i] the code of lights[i]
 *               (C3D_TWO_PASS), each compiled in as straight code with
 *               its type known, as llvmpipe runs a loop over a uniform
 *               block and a dispatch on a type much slower.
 * On a CPU rasteriser (llvmpipe) every branch of a shader runs for every
 * fragment, masked: hence the kinds, the camera bits and the list. */
/* Material textures (Flitter docs/canvas3d.md, Texture Mapping), their
 * bits in C3dFragSpec.textures, in this order: albedo (color_id=), metal,
 * roughness, ao, emissive, transparency; a mesh program with a texture
 * samples it at its texture unit C3D_TEXTURE_UNIT + the bit's index. */
#define C3D_TEXTURES 6
#define C3D_TEXTURE_UNIT 2

typedef struct C3dFragSpec {
    int max_lights;
    unsigned textures;
    unsigned kinds;
    int variant;
    int nsamples;
    unsigned camera;
    int nlist;
    unsigned char list[C3D_LIST_MAX];
} C3dFragSpec;

/* The fragment shader [spec] describes into [out] (NUL-terminated). The
 * impostor variants have the uniforms inverse_pv (the inverse of
 * pv_matrix), viewport_size (pixels), nsamples and sample_offsets[8]
 * (MSAA sample positions within a pixel, 0..1), and need
 * GL_ARB_sample_shading for gl_SampleMask. Returns its length, or the
 * length needed when [cap] is too small. */
size_t canvas3d_fragment_source(char *out, size_t cap, const C3dFragSpec *spec);

#endif
