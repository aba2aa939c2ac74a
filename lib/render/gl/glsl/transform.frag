${HEADER}
// !transform (Flitter docs/shaders.md): each output pixel, about the
// centre, through the inverse of the scale, rotate, translate and keystone
// matrix, reads the composited children there.
in vec2 coord;
out vec4 color;
uniform float alpha;
uniform vec2 size;
uniform mat3 transform_matrix;
% for name in child_textures:
uniform sampler2D ${name};
% endfor
<%include file="composite_functions.glsl"/>

void main() {
% if child_textures:
    vec3 h = transform_matrix * vec3((coord - 0.5) * size, 1.0);
    vec2 at = h.xy / (h.z * size) + 0.5;
<%include file="merge.glsl"/>
    color = alpha * merged;
% else:
    color = vec4(0.0);
% endif
}
