${HEADER}
// !vignette (Flitter docs/shaders.md): the composited input faded to
// transparent over `inset` of the width and height at each edge, through
// the `fade` easing.
in vec2 coord;
out vec4 color;
uniform float alpha;
uniform float inset;
% for name in child_textures:
uniform sampler2D ${name};
% endfor
<%include file="composite_functions.glsl"/>
<%include file="ease_functions.glsl"/>

float edge_fade(float x) {
    if (x < inset) return x / inset;
    if (x > 1.0 - inset) return (1.0 - x) / inset;
    return 1.0;
}

void main() {
% if child_textures:
    vec2 at = coord;
<%include file="merge.glsl"/>
    color = alpha * ease_${ease}(edge_fade(coord.x)) * ease_${ease}(edge_fade(coord.y)) * merged;
% else:
    color = vec4(0.0);
% endif
}
