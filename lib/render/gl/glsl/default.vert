${HEADER}
// The vertex shader of every screen-space program: the quad's corners in
// -1..1, and the texture coordinate 0..1 of each point (Flitter
// docs/shaders.md, "Shader programs").
in vec2 position;
out vec2 coord;

void main() {
    coord = 0.5 * position + 0.5;
    gl_Position = vec4(position, 0.0, 1.0);
}
