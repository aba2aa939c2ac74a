${HEADER}
// The compositing program of !window, !offscreen, !record and a bare
// !shader: the children in order, each drawn onto the ones before with
// the composite= blend, times alpha.
in vec2 coord;
out vec4 color;
uniform float alpha;
% for name in child_textures:
uniform sampler2D ${name};
% endfor
<%include file="composite_functions.glsl"/>

void main() {
    vec4 merged = vec4(0.0);
% for name in child_textures:
%     if loop.first:
    merged = texture(${name}, coord);
%     else:
    merged = composite_${composite}(texture(${name}, coord), merged);
%     endif
% endfor
    color = alpha * merged;
}
