${HEADER}
// !chromakey (Flitter docs/shaders.md): a mask of the pixels outside the
// keyed hue range (or too grey or too dark), blurred across then down in
// downsampled passes, raised to `hard`, times the original.
in vec2 coord;
out vec4 color;
uniform float alpha;
uniform vec2 size;
uniform int pass;
uniform int downsample;
uniform ivec2 radius;
uniform vec2 sigma;
uniform float hue;
uniform float range;
uniform float saturation;
uniform float brightness;
uniform float hard;
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
        vec3 hsv = rgb_to_hsv(texture(${'last' if passes == 5 else 'texture0'}, coord).rgb);
        bool keyed = abs(hsv.x - hue) < range / 2.0 && hsv.y > saturation && hsv.z > brightness;
        color = keyed ? vec4(0.0) : vec4(1.0);
    } else if (step == 1) {
        int r = radius.x / downsample;
        color = filter_blur(last, coord, r, float(r) * sigma.x, vec2(1.0 / size.x, 0.0));
    } else if (step == 2) {
        int r = radius.y / downsample;
        color = filter_blur(last, coord, r, float(r) * sigma.y, vec2(0.0, 1.0 / size.y));
    } else {
        float mask = texture(last, coord).r;
        color = alpha * pow(mask, hard) * texture(${'first' if passes == 5 else 'texture0'}, coord);
    }
% else:
    color = vec4(0.0);
% endif
}
