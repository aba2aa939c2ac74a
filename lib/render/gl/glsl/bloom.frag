${HEADER}
// !bloom (Flitter docs/shaders.md): the children composited (a first pass
// when there are several), their light adjusted (exposure -1 by default),
// blurred across then down in downsampled passes, and the blur laid over
// the original with `lighten`.
in vec2 coord;
out vec4 color;
uniform float alpha;
uniform vec2 size;
uniform int pass;
uniform int downsample;
uniform ivec2 radius;
uniform vec2 sigma;
uniform float exposure;
uniform float contrast;
uniform float brightness;
uniform float shadows;
uniform float highlights;
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
        vec4 source = texture(${'last' if passes == 5 else 'texture0'}, coord);
        vec3 c = source.a > 0.0 ? source.rgb / source.a : vec3(0.0);
        color = vec4(filter_adjust(c, exposure, contrast, brightness, shadows, highlights) * source.a, source.a);
    } else if (step == 1) {
        int r = radius.x / downsample;
        color = filter_blur(last, coord, r, float(r) * sigma.x, vec2(1.0 / size.x, 0.0));
    } else if (step == 2) {
        int r = radius.y / downsample;
        color = filter_blur(last, coord, r, float(r) * sigma.y, vec2(0.0, 1.0 / size.y));
    } else {
        color = alpha * composite_lighten(texture(${'first' if passes == 5 else 'texture0'}, coord), texture(last, coord));
    }
% else:
    color = vec4(0.0);
% endif
}
