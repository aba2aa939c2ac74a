${HEADER}
// The vertex shader of !video: frames arrive top row first, so the quad
// is drawn upside down (Flitter docs/windows.md, !video).
in vec2 position;
out vec2 coord;

void main() {
    coord = 0.5 * position + 0.5;
    gl_Position = vec4(position.x, -position.y, 0.0, 1.0);
}
