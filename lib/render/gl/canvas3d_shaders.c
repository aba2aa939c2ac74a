/* canvas3d_shaders.c: the standard lighting program (see
 * canvas3d_shaders.h). The lighting follows the equations of Flitter's
 * standard_lighting.frag and lighting_functions.glsl (render/window/glsl):
 * a Cook-Torrance specular term (GGX distribution, Schlick-GGX geometry
 * with k = (roughness+1)^2/8, Schlick Fresnel with F0 from ior, mixed
 * towards the albedo by metal), a Lambert diffuse term scaled by
 * (1-F0)(1-metal), ambient light times ao, light fall-off
 * 1/(A + B d + C d^2 + D d^3), spot cones fading linearly in cosine
 * between inner and outer, point lights with a radius as Flitter's
 * two-pass approximation, line lights (a segment from a start, with an
 * optional radius making it a capsule) as Flitter's two passes: for the
 * diffuse term a point on the part of the segment above the surface's
 * tangent plane, a quarter of the way from the point nearest the surface
 * to that part's middle, nearer by the radius; for the specular term the
 * point of the segment nearest the reflected view ray, moved towards the
 * ray by up to the radius (Flitter lighting_functions.glsl,
 * compute_pbr_lighting, the Line case), emissive colour with its directional part when
 * brighter than 1, fog mixed by ((d - fog_min)/(fog_max - fog_min))^(1/curve)
 * and transparency as premultiplied alpha. Two more variants serve
 * `translucency=` (canvas3d.c draws them only for translucent instances,
 * so that the pictures of other scenes come from the unchanged mesh and
 * impostor programs): BACKFACE writes, for a back face, the light that
 * gets into it (each light's diffuse-pass radiance, times
 * (1-F0)(1-metal)(1+albedo)/2, with the face's own normal as the view
 * direction: Flitter backface_lighting.frag and the transmission term of
 * compute_pbr_lighting) and its distance from the eye; TRANSLUCENT adds
 * the light let through to the front face's (see_through below). */
#include "canvas3d_shaders.h"

#include <stdarg.h>
#include <stdio.h>

const char canvas3d_vertex_source[] =
    "#version 330 core\n"
    "layout(location = 0) in vec3 model_position;\n"
    "layout(location = 1) in vec3 model_normal;\n"
    "layout(location = 2) in vec2 model_uv;\n"
    "layout(location = 3) in mat4 model_matrix;\n"
    "layout(location = 7) in mat3 normal_matrix;\n"
    "layout(location = 10) in vec4 material_albedo;\n"
    "layout(location = 11) in vec4 material_emissive;\n"
    "layout(location = 12) in vec4 material_properties;\n"
    "out vec3 world_position;\n"
    "out vec3 world_normal;\n"
    "out vec2 texture_uv;\n"
    "flat out vec4 albedo;\n"
    "flat out vec4 emissive;\n"
    "flat out vec4 properties;\n"
    "uniform mat4 pv_matrix;\n"
    "void main() {\n"
    "    vec4 p = model_matrix * vec4(model_position, 1.0);\n"
    "    world_position = p.xyz;\n"
    "    gl_Position = pv_matrix * p;\n"
    "    world_normal = normal_matrix * model_normal;\n"
    "    texture_uv = model_uv;\n"
    "    albedo = material_albedo;\n"
    "    emissive = material_emissive;\n"
    "    properties = material_properties;\n"
    "}\n";

const char canvas3d_impostor_vertex_source[] =
    "#version 330 core\n"
    "layout(location = 0) in vec3 model_position;\n"
    "layout(location = 3) in mat4 model_matrix;\n"
    "layout(location = 7) in mat3 normal_matrix;\n"
    "layout(location = 10) in vec4 material_albedo;\n"
    "layout(location = 11) in vec4 material_emissive;\n"
    "layout(location = 12) in vec4 material_properties;\n"
    "out vec3 world_position;\n"
    "flat out mat4 ray_matrix;\n"
    "flat out mat4x3 model_affine;\n"
    "flat out mat3 normal_mat;\n"
    "flat out vec4 albedo;\n"
    "flat out vec4 emissive;\n"
    "flat out vec4 properties;\n"
    "uniform mat4 pv_matrix;\n"
    "uniform mat4 inverse_pv;\n"
    "uniform bool billboard;\n"
    "uniform bool proxy;\n"
    "uniform vec3 view_position;\n"
    "uniform vec3 view_focus;\n"
    "uniform bool orthographic;\n"
    "void main() {\n"
    "    vec4 p;\n"
    "    if (billboard) {\n"
    /* a sphere of radius r about c: the octagon in the plane that touches its near
     * side, facing the eye, around the circle in which the cone of the eye's rays
     * that touch the sphere (a cylinder in an orthographic view) meets that plane,
     * one part in a hundred larger; every ray that hits the sphere crosses it */
    "        vec3 c = model_matrix[3].xyz;\n"
    "        float r = length(model_matrix[0].xyz);\n"
    "        vec3 v;\n"
    "        float rho = r;\n"
    "        if (orthographic) {\n"
    "            v = normalize(view_focus - view_position);\n"
    "        } else {\n"
    "            v = c - view_position;\n"
    "            float dist = length(v);\n"
    "            v /= dist;\n"
    "            rho = (dist - r) * r / sqrt(dist * dist - r * r);\n"
    "        }\n"
    "        vec3 right = normalize(cross(v, abs(v.z) < 0.9 ? vec3(0.0, 0.0, 1.0) : vec3(1.0, 0.0, 0.0)));\n"
    "        vec3 up = cross(right, v);\n"
    "        if (proxy)\n"
    /* the occluders' proxy (C3D_FRAG_PROXY): the octagon in the plane
     * through the centre, facing the eye, its rim 0.9 r from the centre:
     * inside the sphere's great disc, so that every ray through it meets
     * the sphere nearer than it (canvas3d_draw.c, occluders) */
    "            p = vec4(c + (model_position.x * right + model_position.y * up) * (r * 0.9 * 0.9238795325112867), 1.0);\n"
    "        else\n"
    "            p = vec4(c - v * r + (model_position.x * right + model_position.y * up) * (rho * 1.01), 1.0);\n"
    "    } else {\n"
    "        p = model_matrix * vec4(model_position * 2.0, 1.0);\n"   /* the unit box, made to enclose the unit sphere */
    "    }\n"
    "    world_position = p.xyz;\n"
    "    gl_Position = pv_matrix * p;\n"
    "    ray_matrix = inverse(model_matrix) * inverse_pv;\n"
    "    model_affine = mat4x3(model_matrix);\n"
    "    normal_mat = normal_matrix;\n"
    "    albedo = material_albedo;\n"
    "    emissive = material_emissive;\n"
    "    properties = material_properties;\n"
    "}\n";

/* shade() up to its lights. */
static const char fragment_head[] =
    "flat in vec4 albedo;\n"
    "flat in vec4 emissive;\n"
    "flat in vec4 properties;\n"
    "out vec4 fragment_color;\n"
    "vec2 surface_uv = vec2(0.0);\n"   /* the point's texture coordinate (meshes set it) */
    "#if TEXTURES\n"
    "uniform sampler2D albedo_texture;\n"
    "uniform sampler2D metal_texture;\n"
    "uniform sampler2D roughness_texture;\n"
    "uniform sampler2D ao_texture;\n"
    "uniform sampler2D emissive_texture;\n"
    "uniform sampler2D transparency_texture;\n"
    /* Flitter docs/canvas3d.md, Texture Mapping: a colour texture laid over
     * the property's value by its alpha; another property's texture gives
     * its luminance, clamped to 0..1, laid over the same way */
    "void overlay_color(sampler2D t, inout vec3 c) {\n"
    "    vec4 s = texture(t, surface_uv);\n"
    "    c = c * (1.0 - clamp(s.a, 0.0, 1.0)) + s.rgb;\n"
    "}\n"
    "void overlay_value(sampler2D t, inout float v) {\n"
    "    vec4 s = texture(t, surface_uv);\n"
    "    v = v * (1.0 - clamp(s.a, 0.0, 1.0)) + clamp(dot(s.rgb, vec3(0.2126, 0.7152, 0.0722)), 0.0, 1.0);\n"
    "}\n"
    "#endif\n"
    "uniform vec3 view_position;\n"
    "uniform vec3 view_focus;\n"
    "uniform bool orthographic;\n"
    "uniform float fog_min;\n"
    "uniform float fog_max;\n"
    "uniform float fog_curve;\n"
    "uniform vec3 fog_color;\n"
    "uniform bool monochrome;\n"
    "uniform vec3 tint;\n"
    "uniform int light_ends[LIGHT_SLOTS];\n"
    "layout(std140) uniform Lights { mat4 lights[MAX_LIGHTS]; };\n"
    "\n"
    "float luminance(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }\n"
    "float largest(vec3 v) { return max(v.x, max(v.y, v.z)); }\n"
    "\n"
    "void shade(vec3 P, vec3 Nw) {\n"
    "    vec4 albedo = albedo, emissive = emissive, properties = properties;\n"
    "#if TEXTURES & 32\n"
    "    overlay_value(transparency_texture, albedo.a);\n"
    "#endif\n"
    "#if TEXTURES & 1\n"
    "    overlay_color(albedo_texture, albedo.rgb);\n"
    "#endif\n"
    "#if TEXTURES & 16\n"
    "    overlay_color(emissive_texture, emissive.rgb);\n"
    "#endif\n"
    "#if TEXTURES & 2\n"
    "    overlay_value(metal_texture, properties.y);\n"
    "#endif\n"
    "#if TEXTURES & 4\n"
    "    overlay_value(roughness_texture, properties.z);\n"
    "#endif\n"
    "#if TEXTURES & 8\n"
    "    overlay_value(ao_texture, properties.w);\n"
    "#endif\n"
    "    vec3 V;\n"
    "    float distance_to_eye;\n"
    "#if ORTHOGRAPHIC\n"
    "    V = normalize(view_position - view_focus);\n"
    "    distance_to_eye = dot(view_position - P, V);\n"
    "#else\n"
    "    V = view_position - P;\n"
    "    distance_to_eye = length(V);\n"
    "    V /= distance_to_eye;\n"
    "#endif\n"
    "    float fog = 0.0;\n"
    "#ifdef BACKFACE\n"
    "    V = normalize(Nw);\n"   /* a back face is lit as if seen along its own normal, without fog */
    "#else\n"
    "#if FOG\n"   /* fog_max > fog_min and fog_curve > 0 */
    "    fog = pow(clamp((distance_to_eye - fog_min) / (fog_max - fog_min), 0.0, 1.0), 1.0 / fog_curve);\n"
    "#endif\n"
    "#endif\n"
    "    float opacity = 1.0 - albedo.a;\n"
    "    vec3 color;\n"
    "    if (fog >= 1.0) {\n"
    "        color = fog_color * opacity;\n"
    "    } else {\n"
    "        vec3 base = albedo.rgb;\n"
    "        float ior = properties.x, metal = properties.y, roughness = properties.z, ao = properties.w;\n"
    "        vec3 N = normalize(Nw);\n"
    "        vec3 diffuse = vec3(0.0), specular = vec3(0.0);\n"
    "#ifdef BACKFACE\n"
    "        vec3 transmitted = vec3(0.0);\n"
    "#endif\n"
    "        float glow = luminance(emissive.rgb);\n"
    "        if (glow > 1.0) {\n"
    "            vec3 e = emissive.rgb / glow;\n"
    "            specular += e + (emissive.rgb - e) * dot(N, V);\n"
    "        } else {\n"
    "            specular += emissive.rgb;\n"
    "        }\n"
    "        float r0 = (ior - 1.0) / (ior + 1.0);\n"
    "        vec3 F0 = mix(vec3(r0 * r0), base, metal);\n"
    "        float a2 = roughness * roughness * roughness * roughness;\n"
    "        float k = (roughness + 1.0) * (roughness + 1.0) / 8.0;\n"
    "        float NdotV = clamp(dot(N, V), 0.0, 1.0);\n"
    "        float GV = NdotV / (NdotV * (1.0 - k) + k);\n";

/* One light's part of shade(): in scope are `light` (its mat4), `type`
 * (its LIGHT_ type) and `two` (lit in two passes), type and two constant.
 * canvas3d_fragment_source puts it in the loop of each slot of lights
 * (C3D_LIGHT_SLOTS), or once per listed light in a block of its own
 * (C3dFragSpec). */
static const char light_body[] =
    "            vec3 light_color = light[0].xyz;\n"
    "            if (type == 1) {\n"
    "                diffuse += (1.0 - F0) * (1.0 - metal) * base * light_color * ao;\n"
    "            }\n"
    "#if LIGHTS_DIRECTIONAL || LIGHTS_POINT || LIGHTS_SPOT || LIGHTS_LINE\n"
    "            else {\n"
    "            int passes = two ? 2 : 1;\n"
    "            for (int pass = 0; pass < passes; pass++) {\n"
    "                vec3 L;\n"
    "                float d = 1.0, strength = 1.0;\n"
    "                if (false) {\n"
    "#if LIGHTS_DIRECTIONAL\n"
    "                } else if (type == 2) {\n"
    "                    L = -light[2].xyz;\n"
    "#endif\n"
    "#if LIGHTS_SPOT\n"
    "                } else if (type == 4) {\n"
    "                    L = light[1].xyz - P;\n"
    "                    d = length(L);\n"
    "                    L /= d;\n"
    "                    float inner = light[1].w, outer = light[2].w;\n"
    "                    strength = 1.0 - clamp((inner - dot(L, -light[2].xyz)) / (inner - outer), 0.0, 1.0);\n"
    "#endif\n"
    "#if LIGHTS_LINE\n"
    "                } else if (type == 5) {\n"
    "                    vec3 span = light[2].xyz;\n"
    "                    float len = length(span);\n"
    "                    vec3 axis = span / len;\n"
    "                    float radius = light[2].w;\n"
    "                    L = light[1].xyz - P;\n"                       /* to the start */
    "                    if (pass == 0) {\n"
    "                        float above = dot(L, N);\n"
    "                        float nearest = clamp(-dot(L, axis), 0.0, len);\n"
    "                        float an = dot(axis, N);\n"
    "                        float crossing = an != 0.0 ? clamp(-above / an, 0.0, len) : 0.0;\n"
    "                        float middle = 0.5 * len;\n"
    "                        if (above < 0.0) {\n"
    "                            middle = 0.5 * (crossing + len);\n"
    "                            nearest = max(nearest, crossing);\n"
    "                        } else if (dot(L + span, N) < 0.0) {\n"
    "                            middle = 0.5 * crossing;\n"
    "                            nearest = min(nearest, crossing);\n"
    "                        }\n"
    "                        L += axis * (0.75 * nearest + 0.25 * middle);\n"
    "                        d = length(L);\n"
    "                        L /= d;\n"
    "                        strength = clamp(1.0 - radius / d, 0.0, 1.0);\n"
    "                        d -= min(radius, d * 0.99);\n"
    "                    } else {\n"
    "                        vec3 R = reflect(V, N);\n"
    "                        float c = dot(R, axis), q = 1.0 - c * c;\n"
    "                        float s = q > 1e-6 ? (c * dot(L, R) - dot(L, axis)) / q : -dot(L, axis);\n"
    "                        L += clamp(s, 0.0, len) * axis;\n"
    "                        vec3 off = dot(L, R) * R - L;\n"
    "                        d = length(L);\n"
    "                        L += off * min(0.99, radius / d);\n"
    "                        strength = clamp(1.0 - radius / d, 0.0, 1.0);\n"
    "                        d = length(L);\n"
    "                        L /= d;\n"
    "                    }\n"
    "#endif\n"
    "#if LIGHTS_POINT\n"
    "                } else if (type == 3) {\n"
    "                    float radius = light[2].w;\n"
    "                    L = light[1].xyz - P;\n"
    "                    d = length(L);\n"
    "                    if (two) {\n"
    "                        strength = clamp(1.0 - radius / d, 0.005, 1.0);\n"
    "                        if (pass == 0) {\n"
    "                            d -= min(radius, d * 0.99);\n"
    "                        } else {\n"
    "                            vec3 R = reflect(V, N);\n"
    "                            vec3 off = dot(L, R) * R - L;\n"
    "                            L += off * min(0.99, radius / length(off));\n"
    "                            d = length(L);\n"
    "                        }\n"
    "                    }\n"
    "                    L = normalize(L);\n"
    "#endif\n"
    "                } else {\n"
    "                    L = vec3(0.0);\n"   /* another kind: NdotL 0, nothing */
    "                }\n"
    /* if-blocks rather than `continue`: llvmpipe's code for the lights
     * listed one by one is then straight */
    "                float NdotL = clamp(dot(N, L), 0.0, 1.0);\n"
    "                strength /= dot(vec4(1.0, d, d * d, d * d * d), light[3]);\n"
    "                vec3 radiance = light_color * strength * NdotL;\n"
    "                if (NdotL != 0.0 && !(largest(abs(radiance)) < (pass == passes - 1 ? 1e-3 * a2 : 1e-3))) {\n"
    "                if (pass == 0) diffuse += radiance * (1.0 - F0) * (1.0 - metal) * base;\n"
    "#ifdef BACKFACE\n"
    "                if (pass == 0) transmitted += radiance * (1.0 - F0) * (1.0 - metal) * (1.0 + base) * 0.5;\n"
    "#endif\n"
    "                if (pass == passes - 1) {\n"
    "                    vec3 H = normalize(V + L);\n"
    "                    float HdotV = clamp(dot(H, V), 0.0, 1.0);\n"
    "                    float f1 = 1.0 - HdotV, f2 = f1 * f1;\n"   /* (1 - HdotV)^5: llvmpipe makes pow() exp2(log2) */
    "                    vec3 F = F0 + (1.0 - F0) * (f2 * f2 * f1);\n"
    "                    float NdotH = clamp(dot(N, H), 0.0, 1.0);\n"
    "                    float q = NdotH * NdotH * (a2 - 1.0) + 1.0;\n"
    "                    float G = GV * NdotL / (NdotL * (1.0 - k) + k);\n"
    "                    specular += radiance * (a2 / (q * q)) * G * F / (4.0 * NdotV * NdotL + 1e-6);\n"
    "                }\n"
    "                }\n"
    "            }\n"
    "            }\n"
    "#endif\n";

/* The rest of shade() after the lights. */
static const char fragment_tail[] =
    "#ifdef BACKFACE\n"
    "        fragment_color = vec4(transmitted, distance_to_eye);\n"
    "        return;\n"
    "#endif\n"
    "#ifdef TRANSLUCENT\n"
    "        if (emissive.a > 0.0) see_through(P, V, distance_to_eye, base, emissive.a, opacity, specular);\n"
    "#endif\n"
    "        color = mix(diffuse, fog_color, fog) * opacity + specular * (1.0 - fog);\n"
    "    }\n"
    "#if MONOCHROME\n"
    "    color = vec3(luminance(color));\n"
    "#endif\n"
    "    color *= tint;\n"
    "    if (any(isinf(color)) || any(isnan(color)))\n"
    "        fragment_color = vec4(0.0);\n"
    "    else\n"
    "        fragment_color = vec4(color, opacity);\n"
    "}\n";

/* Light let through a translucent surface (TRANSLUCENT only; Flitter
 * docs/canvas3d.md, Materials, `translucency=`, and
 * lighting_functions.glsl, compute_translucency). backface_data holds the
 * back-face pass: per pixel the light arriving on the nearest back face of
 * the translucent instances (rgb) and that face's distance from the eye
 * (a; 0 where there is none). Behind the fragment at distance [dist] the
 * object is back.a - dist thick; where it has no back face the surface
 * keeps only its specular light (opacity 0). Otherwise the back-face light
 * is averaged over a cloud of points around the back face, offsets drawn
 * from a normal distribution of deviation thickness^2 / (5 translucency)
 * per axis (Box-Muller pairs from a PCG hash seeded by the pixel: Jarzynski
 * and Olano, "Hash Functions for GPU Rendering", JCGT 2020), 1000 c (1 - c)
 * pairs for c = thickness / (5 translucency) held to 0.01..0.99, keeping
 * the points whose back face lies behind the fragment; with the averaged
 * thickness T, t = 0.5^(T / translucency) of the light passes: the colour
 * gains back light * albedo * t (1 - t) and the opacity is scaled by
 * 1 - t^5. The cloud is centred on the back face itself (P - V thickness);
 * Flitter steps from the eye away from the surface instead, which projects
 * to the same place in a perspective view (and to the picture's middle in
 * an orthographic one). */
static const char translucency_functions[] =
    "uniform sampler2D backface_data;\n"
    "uniform mat4 pv_matrix;\n"
    "uint pcg_hash(uint v) {\n"
    "    uint s = v * 747796405u + 2891336453u;\n"
    "    uint w = ((s >> ((s >> 28u) + 4u)) ^ s) * 277803737u;\n"
    "    return (w >> 22u) ^ w;\n"
    "}\n"
    "float unit_random(inout uint seed) {\n"   /* in (0, 1), never 0 or 1 */
    "    seed = pcg_hash(seed);\n"
    "    return (float(seed >> 8u) + 0.5) * (1.0 / 16777216.0);\n"
    "}\n"
    "vec3 unit_random3(inout uint seed) {\n"
    "    float x = unit_random(seed);\n"
    "    float y = unit_random(seed);\n"
    "    float z = unit_random(seed);\n"
    "    return vec3(x, y, z);\n"
    "}\n"
    "vec2 screen_of(vec3 p) {\n"
    "    vec4 clip = pv_matrix * vec4(p, 1.0);\n"
    "    return (clip.xy / clip.w + 1.0) * 0.5;\n"
    "}\n"
    "void see_through(vec3 P, vec3 V, float dist, vec3 base, float translucency, inout float opacity,\n"
    "                 inout vec3 light) {\n"
    "    vec2 uv = screen_of(P);\n"
    "    vec4 back = textureLod(backface_data, uv, 0.0);\n"
    "    if (!(back.a > dist)) {\n"
    "        opacity = 0.0;\n"
    "        return;\n"
    "    }\n"
    "    float thickness = back.a - dist;\n"
    "    vec3 B = P - V * thickness;\n"
    "    float spread = thickness / (5.0 * translucency);\n"
    "    float c = clamp(spread, 0.01, 0.99);\n"
    "    float deviation = thickness * spread;\n"
    "    int pairs = int(round(1000.0 * c * (1.0 - c)));\n"
    "    ivec2 size = textureSize(backface_data, 0);\n"
    "    ivec2 texel = clamp(ivec2(uv * vec2(size)), ivec2(0), size - 1);\n"
    "    uint seed = uint(texel.y) * uint(size.x) + uint(texel.x);\n"
    "    vec4 sum = back;\n"
    "    float count = 1.0;\n"
    "    for (int i = 0; i < pairs; i++) {\n"
    "        vec3 r = sqrt(-2.0 * log(unit_random3(seed))) * deviation;\n"
    "        vec3 angle = 6.283185307179586 * unit_random3(seed);\n"
    "        vec4 s = textureLod(backface_data, screen_of(B - r * sin(angle)), 0.0);\n"
    "        if (s.a > dist) { sum += s; count += 1.0; }\n"
    "        s = textureLod(backface_data, screen_of(B - r * cos(angle)), 0.0);\n"
    "        if (s.a > dist) { sum += s; count += 1.0; }\n"
    "    }\n"
    "    sum /= count;\n"
    "    float t = pow(0.5, (sum.a - dist) / translucency);\n"
    "    light += sum.rgb * base * t * (1.0 - t);\n"
    "    opacity *= 1.0 - pow(t, 5.0);\n"
    "}\n";

/* The mesh path: the interpolated surface of the triangles. */
static const char mesh_main[] =
    "in vec3 world_position;\n"
    "in vec3 world_normal;\n"
    "in vec2 texture_uv;\n"
    "#ifdef OCCLUDED\n"
    "uniform sampler2DMS occluders;\n"
    "#endif\n"
    "void main() {\n"
    "#ifdef OCCLUDED\n"
    /* the farthest occluder among the pixel's samples, against the
     * nearest this fragment's plane comes within the pixel (a sample
     * lies within half a pixel of the centre along each axis), less a
     * margin of a few steps of the 24-bit depth buffer for the
     * rasteriser's own interpolation: only a fragment behind at every
     * sample is discarded */
    "    ivec2 at = ivec2(gl_FragCoord.xy);\n"
    "    float occluder = texelFetch(occluders, at, 0).r;\n"
    "    for (int i = 1; i < NSAMPLES; i++) occluder = max(occluder, texelFetch(occluders, at, i).r);\n"
    "    float z = gl_FragCoord.z;\n"
    "    float nearest = z - 0.5 * (abs(dFdx(z)) + abs(dFdy(z)));\n"
    "    if (nearest > occluder + 4.0 / 16777216.0) discard;\n"
    "#endif\n"
    "    surface_uv = texture_uv;\n"
    "    shade(world_position, world_normal);\n"
    "}\n";

/* The impostor path: the ray from the eye through this fragment of the
 * bounding cube meets the unit sphere of the model (found in model space,
 * so scaled and rotated spheres are exact ellipsoids); the surface point,
 * its normal (the normal matrix applied to the model-space point) and its
 * depth are the sphere's, fragments whose ray misses are discarded. With
 * MSAA the sample mask keeps only the samples whose own rays hit
 * (sample_offsets: the sample positions within the pixel).
 *
 * BILLBOARD (the octagon of a sphere wholly beyond the near plane, so
 * that every point of it on a ray is in front of the eye) tests the
 * NSAMPLES samples' rays more cheaply: a ray's line, through its points
 * a on the near plane and b on the far one (homogeneous, model space),
 * has the Plücker coordinates u = a.w b.xyz - b.w a.xyz (its direction)
 * and m = a.xyz x b.xyz (its moment), and passes within |m| / |u| of the
 * unit sphere's centre; both are linear in the sample's offset within
 * the pixel (a and b move by the same s, and b - a = 2 c is constant), so
 * a sample costs two small updates and two dot products instead of the
 * ray's divisions and square root. Near and far points are used, not the
 * eye, so that neither is computed as a difference of nearly equal
 * numbers. The fragment is then shaded on the centre's ray, or on the
 * first covered sample's when the centre's misses, as below. */
static const char impostor_main[] =
    "in vec3 world_position;\n"
    "flat in mat4 ray_matrix;\n"
    "flat in mat4x3 model_affine;\n"
    "flat in mat3 normal_mat;\n"
    "uniform mat4 pv_matrix;\n"
    "uniform mat4 inverse_pv;\n"
    "uniform vec2 viewport_size;\n"
    "uniform int nsamples;\n"
    "uniform vec2 sample_offsets[8];\n"
    "vec2 to_ndc(vec2 frag) { return frag / viewport_size * 2.0 - 1.0; }\n"
    /* the ray in model space, from o (near plane) to o + d (far plane);
     * w: the homogeneous w of those two points (the model matrix is
     * affine: the same as in world space) */
    "bool hit_at(vec2 frag, out vec3 o, out vec3 d, out float t, out vec2 w) {\n"
    "    vec2 n = to_ndc(frag);\n"
    "    vec4 a = ray_matrix[0] * n.x + ray_matrix[1] * n.y + ray_matrix[3] - ray_matrix[2];\n"
    "    vec4 b = a + 2.0 * ray_matrix[2];\n"
    "    w = vec2(a.w, b.w);\n"
    "    o = a.xyz / a.w;\n"
    "    d = b.xyz / b.w - o;\n"
    "    float qa = dot(d, d), qb = dot(o, d), qc = dot(o, o) - 1.0;\n"
    "    float disc = qb * qb - qa * qc;\n"
    "    t = (-qb - sqrt(max(disc, 0.0))) / qa;\n"
    "    return disc >= 0.0 && t >= 0.0;\n"
    "}\n"
    "#ifdef OCCLUDED\n"
    "uniform sampler2D occluders;\n"
    "#endif\n"
    "void main() {\n"
    "#ifdef OCCLUDED\n"
    /* (one sample) the octagon lies in the plane touching the sphere's
     * near side, so its depth is at most the sphere's on every ray through
     * it; the fragment is discarded, before its ray is cast, where that
     * plane lies behind the occluders' proxies, with mesh_main's margin */
    "    float occluder = texelFetch(occluders, ivec2(gl_FragCoord.xy), 0).r;\n"
    "    if (gl_FragCoord.z > occluder + 4.0 / 16777216.0) discard;\n"
    "#endif\n"
    "    vec3 o, d;\n"
    "    float t;\n"
    "    vec2 w;\n"
    "    vec2 frag = gl_FragCoord.xy;\n"
    "#if defined(BILLBOARD) && NSAMPLES > 1\n"
    "    vec2 n = to_ndc(frag);\n"
    "    vec4 c = ray_matrix[2];\n"
    "    vec4 na = ray_matrix[0] * n.x + ray_matrix[1] * n.y + ray_matrix[3] - c;\n"   /* near */
    "    vec4 fa = na + 2.0 * c;\n"   /* far */
    "    vec3 u0 = na.w * fa.xyz - fa.w * na.xyz, m0 = cross(na.xyz, fa.xyz);\n"
    "    int mask = 0;\n"
    "    vec2 first = vec2(0.5);\n"
    "    for (int i = NSAMPLES - 1; i >= 0; i--) {\n"   /* constant bounds: unrolled, no branches */
    "        vec2 e = (sample_offsets[i] - 0.5) * 2.0 / viewport_size;\n"
    "        vec4 s = ray_matrix[0] * e.x + ray_matrix[1] * e.y;\n"
    "        vec3 u = u0 - 2.0 * (c.w * s.xyz - s.w * c.xyz), m = m0 + 2.0 * cross(s.xyz, c.xyz);\n"
    "        bool hit = dot(m, m) <= dot(u, u);\n"
    "        mask |= hit ? 1 << i : 0;\n"
    "        first = hit ? sample_offsets[i] : first;\n"
    "    }\n"
    "    if (mask == 0) discard;\n"
    "    frag = floor(frag) + (dot(m0, m0) <= dot(u0, u0) ? vec2(0.5) : first);\n"
    "    if (!hit_at(frag, o, d, t, w)) discard;\n"
    "    gl_SampleMask[0] = mask;\n"
    "#else\n"
    "    bool centre = hit_at(frag, o, d, t, w);\n"
    "    if (nsamples > 1) {\n"
    "        int mask = 0;\n"
    "        vec3 o2, d2;\n"
    "        float t2;\n"
    "        vec2 w2;\n"
    "        for (int i = 0; i < nsamples; i++) {\n"
    "            vec2 f = floor(gl_FragCoord.xy) + sample_offsets[i];\n"
    "            if (hit_at(f, o2, d2, t2, w2)) {\n"
    "                mask |= 1 << i;\n"
    "                if (!centre) { centre = true; o = o2; d = d2; t = t2; w = w2; frag = f; }\n"
    "            }\n"
    "        }\n"
    "        if (mask == 0) discard;\n"
    "        gl_SampleMask[0] = mask;\n"
    "    } else if (!centre) {\n"
    "        discard;\n"
    "    }\n"
    "#endif\n"
    "    vec3 m = o + t * d;\n"
    /* the depth: the point at t of the way from o to o + d is, in
     * homogeneous coordinates, s of the way from near to far (NDC z =
     * 2s - 1, window depth s), s = t w0 / ((1 - t) w1 + t w0) */
    "    float s = t * w.x / ((1.0 - t) * w.y + t * w.x);\n"
    "    if (s > 1.0) discard;\n"
    "#ifdef OCCLUDED\n"
    /* the surface's depth behind the occluders': no lighting for a
     * fragment that would fail its depth test */
    "    if (s > occluder + 4.0 / 16777216.0) discard;\n"
    "#endif\n"
    "    gl_FragDepth = s;\n"
    "    shade(model_affine * vec4(m, 1.0), normal_mat * m);\n"
    "}\n";

const unsigned char c3d_slot_codes[C3D_LIGHT_SLOTS] = {
    LIGHT_AMBIENT, LIGHT_DIRECTIONAL, LIGHT_POINT, LIGHT_POINT | C3D_TWO_PASS, LIGHT_SPOT, LIGHT_LINE | C3D_TWO_PASS};

/* Append to [out] (of [cap] bytes, NULL to measure) at *[n], as
 * snprintf would; *[n] counts what the whole text needs. */
static void put(char *out, size_t cap, size_t *n, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int k = vsnprintf(out && *n < cap ? out + *n : NULL, out && *n < cap ? cap - *n : 0, fmt, ap);
    va_end(ap);
    if (k > 0) *n += (size_t)k;
}

size_t canvas3d_fragment_source(char *out, size_t cap, const C3dFragSpec *spec)
{
    int variant = spec->variant;
    if (variant == C3D_FRAG_DEPTH || variant == C3D_FRAG_PROXY) {
        static const char depth_only[] = "#version 330 core\nvoid main() {}\n";
        if (out && cap) snprintf(out, cap, "%s", depth_only);
        return sizeof depth_only - 1;
    }
    unsigned kinds = spec->kinds, camera = spec->camera;
    bool impostor = variant == C3D_FRAG_IMPOSTOR || variant == C3D_FRAG_BILLBOARD || variant == C3D_FRAG_BILLBOARD_OCCLUDED;
    size_t n = 0;
    if (out && cap) out[0] = '\0';
#define KIND(k) ((kinds >> (k)) & 1u)
    put(out, cap, &n,
        "#version 330 core\n%s#define MAX_LIGHTS %d\n"
        "#define LIGHTS_DIRECTIONAL %u\n#define LIGHTS_POINT %u\n"
        "#define LIGHTS_SPOT %u\n#define LIGHTS_LINE %u\n"
        "#define ORTHOGRAPHIC %d\n#define FOG %d\n#define MONOCHROME %d\n#define LIGHT_SLOTS %d\n"
        "#define TEXTURES %u\n",
        impostor ? "#extension GL_ARB_sample_shading : require\n" : "", spec->max_lights, KIND(LIGHT_DIRECTIONAL),
        KIND(LIGHT_POINT), KIND(LIGHT_SPOT), KIND(LIGHT_LINE), (camera & C3D_ORTHOGRAPHIC) != 0,
        (camera & C3D_FOG) != 0, (camera & C3D_MONOCHROME) != 0, C3D_LIGHT_SLOTS,
        impostor ? 0u : spec->textures & ((1u << C3D_TEXTURES) - 1));
#undef KIND
    if (variant == C3D_FRAG_BACKFACE) put(out, cap, &n, "#define BACKFACE\n");
    if (variant == C3D_FRAG_TRANSLUCENT) put(out, cap, &n, "#define TRANSLUCENT\n%s", translucency_functions);
    if (variant == C3D_FRAG_BILLBOARD || variant == C3D_FRAG_OCCLUDED || variant == C3D_FRAG_BILLBOARD_OCCLUDED)
        put(out, cap, &n, "%s%s\n#define NSAMPLES %d\n", variant != C3D_FRAG_OCCLUDED ? "#define BILLBOARD\n" : "",
            variant != C3D_FRAG_BILLBOARD ? "#define OCCLUDED" : "",
            spec->nsamples < 1 ? 1 : spec->nsamples > 8 ? 8 : spec->nsamples);
    put(out, cap, &n, "%s", fragment_head);
    int nlist = spec->nlist > C3D_LIST_MAX ? C3D_LIST_MAX : spec->nlist;
    /* the #if of each slot's kind of light */
    static const char *const kind[C3D_LIGHT_SLOTS] = {"1", "LIGHTS_DIRECTIONAL", "LIGHTS_POINT", "LIGHTS_POINT",
                                                      "LIGHTS_SPOT", "LIGHTS_LINE"};
    for (int k = 0; nlist <= 0 && k < C3D_LIGHT_SLOTS; k++) {
        char start[24] = "0";
        if (k) snprintf(start, sizeof start, "light_ends[%d]", k - 1);
        put(out, cap, &n,
            "#if %s\n"
            "        for (int i = %s; i < light_ends[%d]; i++) {\n"
            "            mat4 light = lights[i];\n"
            "            const int type = %d;\n"
            "            const bool two = %s;\n"
            "%s        }\n"
            "#endif\n",
            kind[k], start, k, c3d_slot_codes[k] & (C3D_TWO_PASS - 1),
            c3d_slot_codes[k] & C3D_TWO_PASS ? "true" : "false", light_body);
    }
    for (int i = 0; i < nlist; i++)
        put(out, cap, &n,
            "        {\n"
            "            mat4 light = lights[%d];\n"
            "            const int type = %d;\n"
            "            const bool two = %s;\n"
            "%s        }\n",
            i, spec->list[i] & (C3D_TWO_PASS - 1), spec->list[i] & C3D_TWO_PASS ? "true" : "false", light_body);
    put(out, cap, &n, "%s%s", fragment_tail, impostor ? impostor_main : mesh_main);
    return n;
}
