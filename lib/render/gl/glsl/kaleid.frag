${HEADER}
// !kaleid (Flitter docs/shaders.md): the composited input folded into
// `segments` mirrored wedges about the centre, turned by `rotation`, and
// folded back beyond `radius` (of half the shorter side).
in vec2 coord;
out vec4 color;
uniform float alpha;
uniform vec2 size;
uniform float segments;
uniform float rotation;
uniform float radius;
% for name in child_textures:
uniform sampler2D ${name};
% endfor
<%include file="composite_functions.glsl"/>

void main() {
% if child_textures:
    const float turn = 6.283185307179586;
    vec2 p = (coord - 0.5) * size;
    float wedge = (atan(p.y, p.x) / turn + 0.5 - rotation) * segments;
    float w = floor(wedge);
    float within = mod(w, 2.0) == 0.0 ? wedge - w : w + 1.0 - wedge;
    float angle = (within / segments + rotation - 0.5) * turn;
    float reach = radius * 0.5 * min(size.x, size.y);
    float r = length(p) / reach;
    float ring = floor(r);
    r = reach * (mod(ring, 2.0) == 0.0 ? r - ring : ring + 1.0 - r);
    vec2 at = r * vec2(cos(angle), sin(angle)) / size + 0.5;
<%include file="merge.glsl"/>
    color = alpha * merged;
% else:
    color = vec4(0.0);
% endif
}
