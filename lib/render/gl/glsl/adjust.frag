${HEADER}
// !adjust (Flitter docs/shaders.md): un-premultiply, colour matrix, hue
// and saturation, exposure, brightness and contrast, shadows and
// highlights, clamp at 0, gamma, tone map, premultiply; times alpha.
in vec2 coord;
out vec4 color;
uniform float alpha;
uniform mat3 color_matrix;
uniform float hue;
uniform float saturation;
uniform float exposure;
uniform float contrast;
uniform float brightness;
uniform float shadows;
uniform float highlights;
uniform float gamma;
% if tonemap_function == 'reinhard':
uniform float whitepoint;
% endif
% for name in child_textures:
uniform sampler2D ${name};
% endfor
<%include file="composite_functions.glsl"/>
<%include file="filter_functions.glsl"/>

void main() {
% if child_textures:
    vec2 at = coord;
<%include file="merge.glsl"/>
    vec3 c = merged.a > 0.0 ? merged.rgb / merged.a : vec3(0.0);
    vec3 hsv = rgb_to_hsv(color_matrix * c);
    c = hsv_to_rgb(vec3(hsv.x + hue, hsv.y * saturation, hsv.z));
    c = max(filter_adjust(c, exposure, contrast, brightness, shadows, highlights), vec3(0.0));
%     if gamma != 1:
    c = pow(c, vec3(gamma));
%     endif
%     if tonemap_function == 'reinhard':
    c = tonemap_reinhard(c, whitepoint);
%     elif tonemap_function:
    c = tonemap_${tonemap_function}(c);
%     endif
    color = alpha * vec4(c * merged.a, merged.a);
% else:
    color = vec4(0.0);
% endif
}
