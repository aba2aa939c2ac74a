${HEADER}
// !blur (Flitter docs/shaders.md): with several children a first pass
// composites them; then a horizontal and a vertical Gaussian pass.
in vec2 coord;
out vec4 color;
uniform float alpha;
uniform vec2 size;
uniform int pass;
uniform ivec2 radius;
uniform vec2 sigma;
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
%     if passes == 3:
    if (pass == 0) {
        vec2 at = coord;
<%include file="merge.glsl"/>
        color = merged;
        return;
    }
%     endif
    if (pass == ${passes - 2}) {
        color = filter_blur(${'last' if passes == 3 else 'texture0'}, coord, radius.x, float(radius.x) * sigma.x, vec2(1.0 / size.x, 0.0));
    } else {
        color = alpha * filter_blur(last, coord, radius.y, float(radius.y) * sigma.y, vec2(0.0, 1.0 / size.y));
    }
% else:
    color = vec4(0.0);
% endif
}
