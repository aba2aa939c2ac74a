${HEADER}
// !video (Flitter docs/windows.md): the frame at `position`, mixed with
// the next by `ratio` when interpolating, stretched over the output
// (aspect_mode 0), fitted inside it (1) or filling it (2), times alpha.
in vec2 coord;
out vec4 color;
uniform sampler2D ${child_textures[0]};
uniform sampler2D ${child_textures[1]};
uniform float alpha;
uniform float ratio;
uniform vec2 size;
uniform vec2 frame_size;
uniform int aspect_mode;

void main() {
    vec2 scaled = size, shift = vec2(0.0);
    bool wider = size.x / size.y > frame_size.x / frame_size.y;
    if (aspect_mode == 1) {
        scaled = wider ? frame_size * (size.y / frame_size.y) : frame_size * (size.x / frame_size.x);
    } else if (aspect_mode == 2) {
        scaled = wider ? frame_size * (size.x / frame_size.x) : frame_size * (size.y / frame_size.y);
    }
    if (aspect_mode != 0) shift = (scaled - size) / 2.0;
    vec2 at = (coord * size + shift) / scaled;
    color = alpha * mix(texture(${child_textures[0]}, at), texture(${child_textures[1]}, at), ratio);
}
