${HEADER}
// !flare (Flitter docs/shaders.md): lens ghosts and a halo of the bright
// parts, blurred across then down in downsampled passes with the starburst
// lines added, then added to the original.
in vec2 coord;
out vec4 color;
uniform float alpha;
uniform vec2 size;
uniform int pass;
uniform int ghosts;
uniform float upright_length;
uniform float diagonal_length;
uniform float halo_radius;
uniform float halo_attenuation;
uniform float threshold;
uniform float attenuation;
uniform float aberration;
% if passes == 5:
uniform sampler2D first;
% endif
% if passes > 1:
uniform sampler2D last;
%     for name in child_textures:
uniform sampler2D ${name};
%     endfor
% endif
<%include file="composite_functions.glsl"/>
<%include file="filter_functions.glsl"/>

void main() {
% if passes > 1:
%     if passes == 5:
    if (pass == 0) {
        vec2 at = coord;
<%include file="merge.glsl"/>
        color = merged;
        return;
    }
%     endif
    int step = pass - ${passes - 4};
    if (step == 0) {
        vec3 c = vec3(0.0);
% if ghosts > 0:
        c += filter_lens_ghost(${'last' if passes == 5 else 'texture0'}, coord, size, 1.0, -1.25, threshold, attenuation, aberration);
% endif
% if ghosts > 1:
        c += filter_lens_ghost(${'last' if passes == 5 else 'texture0'}, coord, size, 1.5, -0.25, threshold, attenuation, aberration);
% endif
% if ghosts > 2:
        c += filter_lens_ghost(${'last' if passes == 5 else 'texture0'}, coord, size, 0.5, 0.25, threshold, attenuation + 1.0, aberration);
% endif
% if ghosts > 3:
        c += filter_lens_ghost(${'last' if passes == 5 else 'texture0'}, coord, size, 0.75, -3.0, threshold, attenuation + 2.0, 0.5 * aberration);
% endif
% if ghosts > 4:
        c += filter_lens_ghost(${'last' if passes == 5 else 'texture0'}, coord, size, 0.25, 2.0, threshold, attenuation + 3.0, 0.5 * aberration);
% endif
% if ghosts > 5:
        c += filter_lens_ghost(${'last' if passes == 5 else 'texture0'}, coord, size, 1.0, -0.75, threshold, attenuation + 1.0, aberration);
% endif
        c += filter_lens_halo(${'last' if passes == 5 else 'texture0'}, coord, size, halo_radius, threshold, attenuation + halo_attenuation - 0.5);
        color = vec4(c, 1.0);
    } else if (step == 1) {
        int r = int(0.05 * min(size.x, size.y));
        color = filter_blur(last, coord, r, 0.3 * float(r), vec2(1.0 / size.x, 0.0));
    } else if (step == 2) {
        int r = int(0.05 * min(size.x, size.y));
        vec4 blurred = filter_blur(last, coord, r, 0.3 * float(r), vec2(0.0, 1.0 / size.y));
        blurred.rgb += filter_lens_flare(${'first' if passes == 5 else 'texture0'}, coord, size, upright_length, diagonal_length, threshold, attenuation);
        color = blurred;
    } else {
        color = alpha * composite_add(texture(${'first' if passes == 5 else 'texture0'}, coord), texture(last, coord));
    }
% else:
    color = vec4(0.0);
% endif
}
