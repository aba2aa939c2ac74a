${HEADER}
// !edges (Flitter docs/shaders.md): the composited input blurred across
// then down in downsampled passes, its difference from the original, with
// `mixer` of the original laid under it.
in vec2 coord;
out vec4 color;
uniform float alpha;
uniform vec2 size;
uniform int pass;
uniform int downsample;
uniform ivec2 radius;
uniform vec2 sigma;
uniform float mixer;
% if passes == 4:
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
%     if passes == 4:
    if (pass == 0) {
        vec2 at = coord;
<%include file="merge.glsl"/>
        color = merged;
        return;
    }
%     endif
    int step = pass - ${passes - 3};
    if (step == 0) {
        int r = radius.x / downsample;
        color = filter_blur(${'last' if passes == 4 else 'texture0'}, coord, r, float(r) * sigma.x, vec2(1.0 / size.x, 0.0));
    } else if (step == 1) {
        int r = radius.y / downsample;
        color = filter_blur(last, coord, r, float(r) * sigma.y, vec2(0.0, 1.0 / size.y));
    } else {
        vec4 original = texture(${'first' if passes == 4 else 'texture0'}, coord);
        vec4 edge = composite_difference(original, texture(last, coord));
        color = alpha * composite_over(mixer * original, edge);
    }
% else:
    color = vec4(0.0);
% endif
}
