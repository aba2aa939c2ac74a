${HEADER}
// !noise (Flitter docs/shaders.md): `octaves` of OpenSimplex 2S noise on a
// plane (the XY-improved orientation), a cylinder or a sphere, one channel
// per component, the children's colours (composited) offsetting the
// points, scaled by `multiplier` and moved by `offset`; unused channels
// take `default`.
in vec2 coord;
out vec4 color;
uniform float alpha;
uniform vec2 size;
uniform float seed_hash;
uniform int components;
uniform int octaves;
uniform float roughness;
uniform vec2 origin;
uniform float z;
uniform vec3 scale;
uniform vec3 tscale;
uniform float multiplier;
uniform float offset;
uniform vec4 default_values;
% for name in child_textures:
uniform sampler2D ${name};
% endfor
<%include file="composite_functions.glsl"/>
<%include file="noise_functions.glsl"/>

void main() {
    const float turn = 6.283185307179586;
% if noise_shape == 'cylinder':
    float a = turn * coord.x, r = size.x / turn;
    vec3 point = vec3(r * cos(a), r * sin(a), coord.y * size.y);
% elif noise_shape == 'sphere':
    float a = turn * coord.x, r = size.x / turn, lat = 0.5 * turn * (coord.y - 0.5);
    vec3 point = vec3(r * cos(lat) * cos(a), r * cos(lat) * sin(a), r * sin(lat));
% else:
    vec3 point = vec3(coord * size, 0.0);
% endif
    point += vec3(origin, z);
% if child_textures:
    vec2 at = coord;
<%include file="merge.glsl"/>
    point += tscale * merged.rgb;
% endif
    point *= scale;
    vec4 seeds[4];
    seeds[0] = vec4(seed_hash);
    for (int j = 1; j < 4; j++) seeds[j] = opensimplex2s_permute(seeds[j - 1] + 1.0);
    vec4 total = vec4(0.0);
    float k = 1.0, weight = 0.0;
    for (int i = 0; i < octaves; i++) {
        for (int j = 0; j < components && j < 4; j++) {
% if noise_shape in ('cylinder', 'sphere'):
            total[j] += k * opensimplex2s(seeds[j], point / k);
% else:
            total[j] += k * opensimplex2s_improvexy(seeds[j], point / k);
% endif
        }
        weight += k;
        k *= roughness;
    }
    vec4 result = default_values;
    for (int j = 0; j < components && j < 4; j++) result[j] = total[j] / weight * multiplier + offset;
    color = alpha * result;
}
