${HEADER}
// !feedback (Flitter docs/shaders.md): the composited input (brightened by
// `glow`) mixed with the last frame's output, moved by translate, scale
// and rotate and weighted by mixer, each as a rate per `timebase` beats
// over the beats since the last frame (`delta`).
in vec2 coord;
out vec4 color;
uniform float alpha;
uniform vec2 size;
uniform float delta;
uniform float mixer;
uniform float timebase;
uniform float glow;
uniform vec2 translate;
uniform vec2 scale;
uniform float rotate;
uniform sampler2D last;
% for name in child_textures:
uniform sampler2D ${name};
% endfor
<%include file="composite_functions.glsl"/>

void main() {
% if child_textures:
    vec2 at = coord;
<%include file="merge.glsl"/>
    float t = delta / timebase;
    float angle = 6.283185307179586 * rotate * t;
    vec2 p = (coord - 0.5) * size / pow(scale, vec2(t));
    p = vec2(p.x * cos(angle) - p.y * sin(angle), p.x * sin(angle) + p.y * cos(angle));
    p -= translate * vec2(t, -t);
    float keep = mixer > 0.0 ? pow(mixer, t) : 0.0;
    color = alpha * mix((1.0 + glow) * merged, texture(last, p / size + 0.5), keep);
% else:
    color = vec4(0.0);
% endif
}
