// OpenSimplex 2S 3D noise (K. Spencer's algorithm, public domain), with a
// seed hash added to the lattice hashing (Flitter docs/shaders.md, !noise).
// opensimplex2s() is the conventional orientation, opensimplex2s_improvexy()
// the one for XY planes; both take four seed hashes (one per lattice
// corner's hash chain, usually all the same) and give values in (-1, 1).

// The lattice hash: a permutation polynomial modulo 289.
vec4 opensimplex2s_permute(vec4 t) {
    vec4 m = mod(t, 289.0);
    return m * (m * 34.0 + 133.0);
}

// The gradient of lattice hash [h] (0..47): bits 0-2 pick a cube corner,
// bit 3 between it and a rhombic direction, h / 16 the axis zeroed.
vec3 osn_gradient(float h) {
    vec3 corner = mod(floor(h / vec3(1.0, 2.0, 4.0)), 2.0) * 2.0 - 1.0;
    vec3 edge = corner;
    edge[int(h / 16.0)] = 0.0;
    float kind = mod(floor(h / 8.0), 2.0);
    vec3 rhombic = kind > 0.5 ? edge + cross(corner, edge) : corner;
    return (edge * 1.22474487139 + rhombic) * (1.0 - 0.042942436724648037 * kind) * 3.5946317686139184;
}

// The contributions of the four lattice points around [p] (one of the two
// interleaved lattices).
float osn_lattice(vec4 seeds, vec3 p) {
    vec3 base = floor(p);
    vec4 f = vec4(p - base, 2.5);
    vec3 c1 = base + floor(dot(f, vec4(0.25)));
    vec3 c2 = base + vec3(1.0, 0.0, 0.0) + vec3(-1.0, 1.0, 1.0) * floor(dot(f, vec4(-0.25, 0.25, 0.25, 0.35)));
    vec3 c3 = base + vec3(0.0, 1.0, 0.0) + vec3(1.0, -1.0, 1.0) * floor(dot(f, vec4(0.25, -0.25, 0.25, 0.35)));
    vec3 c4 = base + vec3(0.0, 0.0, 1.0) + vec3(1.0, 1.0, -1.0) * floor(dot(f, vec4(0.25, 0.25, -0.25, 0.35)));
    vec4 h = opensimplex2s_permute(seeds + vec4(c1.x, c2.x, c3.x, c4.x));
    h = opensimplex2s_permute(h + vec4(c1.y, c2.y, c3.y, c4.y));
    h = mod(opensimplex2s_permute(h + vec4(c1.z, c2.z, c3.z, c4.z)), 48.0);
    vec3 d1 = p - c1, d2 = p - c2, d3 = p - c3, d4 = p - c4;
    vec4 fall = max(vec4(0.75) - vec4(dot(d1, d1), dot(d2, d2), dot(d3, d3), dot(d4, d4)), 0.0);
    fall *= fall;
    fall *= fall;
    vec4 ramps = vec4(dot(d1, osn_gradient(h.x)), dot(d2, osn_gradient(h.y)), dot(d3, osn_gradient(h.z)),
                      dot(d4, osn_gradient(h.w)));
    return dot(fall, ramps);
}

float opensimplex2s(vec4 seed_hashes, vec3 p) {
    vec3 q = vec3(dot(p, vec3(2.0 / 3.0))) - p;
    return osn_lattice(seed_hashes, q) + osn_lattice(seed_hashes, q + 144.5);
}

float opensimplex2s_improvexy(vec4 seed_hashes, vec3 p) {
    const mat3 turn = mat3(0.788675134594813, -0.211324865405187, -0.577350269189626,
                           -0.211324865405187, 0.788675134594813, -0.577350269189626,
                           0.577350269189626, 0.577350269189626, 0.577350269189626);
    vec3 q = turn * p;
    return osn_lattice(seed_hashes, q) + osn_lattice(seed_hashes, q + 144.5);
}
