// Colour conversions and tone curves (Flitter docs/shaders.md, !adjust).

// Linear light to sRGB (IEC 61966-2-1), clamped to 0..1.
vec3 srgb_transfer(vec3 c) {
    vec3 x = clamp(c, vec3(0.0), vec3(1.0));
    vec3 curve = 1.055 * pow(x, vec3(1.0 / 2.4)) - 0.055;
    return mix(x * 12.92, curve, vec3(greaterThan(x, vec3(0.0031308))));
}

// Relative luminance of a linear colour (Rec. 709 primaries).
float srgb_luminance(vec3 c) { return c.r * 0.2126 + c.g * 0.7152 + c.b * 0.0722; }

// Reinhard's curve x / (1 + x); with a white point above 1, the extended
// curve that reaches 1 there.
vec3 tonemap_reinhard(vec3 color, float whitepoint) {
    vec3 mapped = color / (color + 1.0);
    if (whitepoint > 1.0) mapped *= 1.0 + color / (whitepoint * whitepoint);
    return mapped;
}

// The ACES filmic curve as Stephen Hill's fit (input and output matrices
// around a rational curve).
vec3 tonemap_aces(vec3 color) {
    const mat3 into = mat3(0.59719, 0.07600, 0.02840,
                           0.35458, 0.90834, 0.13383,
                           0.04823, 0.01566, 0.83777);
    const mat3 back = mat3(1.60475, -0.10208, -0.00327,
                           -0.53108, 1.10813, -0.07276,
                           -0.07367, -0.00605, 1.07602);
    vec3 x = into * color;
    vec3 top = x * (x + 0.0245786) - 0.000090537;
    vec3 bottom = x * (x * 0.983729 + 0.4329510) + 0.238081;
    return back * (top / bottom);
}

// AgX: the log-encoded input through a sixth-order fit of its contrast
// curve, then back through the inverse of the input matrix.
vec3 agx_curve(vec3 color) {
    const mat3 into = mat3(0.842479062253094, 0.0423282422610123, 0.0423756549057051,
                           0.0784335999999992, 0.878468636469772, 0.0784336,
                           0.0792237451477643, 0.0791661274605434, 0.879142973793104);
    const float lo = -12.47393, hi = 4.026069;
    vec3 x = (clamp(log2(into * color), lo, hi) - lo) / (hi - lo);
    vec3 x2 = x * x, x4 = x2 * x2;
    return x4 * x2 * 15.5 - x4 * x * 40.14 + x4 * 31.96 - x2 * x * 6.868 + x2 * 0.4298 + x * 0.1191 - 0.00232;
}

vec3 agx_out(vec3 color) {
    const mat3 back = mat3(1.19687900512017, -0.0528968517574562, -0.0529716355144438,
                           -0.0980208811401368, 1.15190312990417, -0.0980434501171241,
                           -0.0990297440797205, -0.0989611768448433, 1.15107367264116);
    return back * color;
}

vec3 tonemap_agx(vec3 color) { return agx_out(agx_curve(color)); }

vec3 tonemap_agx_punchy(vec3 color) {
    vec3 x = agx_curve(color);
    float luma = srgb_luminance(x);
    x = pow(x, vec3(1.35));
    return agx_out(luma + (x - luma) * 1.4);
}

// Hue, saturation and value in 0..1 (hue 0 for greys).
vec3 rgb_to_hsv(vec3 c) {
    float top = max(c.r, max(c.g, c.b));
    float spread = top - min(c.r, min(c.g, c.b));
    float hue = 0.0;
    if (spread > 0.0) {
        if (top == c.r) hue = (c.g - c.b) / spread;
        else if (top == c.g) hue = (c.b - c.r) / spread + 2.0;
        else hue = (c.r - c.g) / spread + 4.0;
        hue = hue / 6.0;
        if (hue < 0.0) hue += 1.0;
    }
    return vec3(hue, top > 0.0 ? spread / top : 0.0, top);
}

vec3 hsv_to_rgb(vec3 c) {
    vec3 k = mod(vec3(5.0, 3.0, 1.0) + c.x * 6.0, 6.0);
    return c.z - c.z * c.y * clamp(min(k, 4.0 - k), 0.0, 1.0);
}

// Flitter's HSL: through HSV, the value being lightness over 1 - S/2.
vec3 hsl_to_rgb(vec3 color) {
    vec3 c = clamp(color, vec3(0.0), vec3(1.0));
    if (c.y == 0.0) return hsv_to_rgb(c);
    float v = min(1.0, c.z / (1.0 - c.y / 2.0));
    float s = (c.z == 0.0 || c.z == 1.0) ? 0.0 : (v - c.z) / min(c.z / 2.0, 1.0 - c.z / 2.0);
    return hsv_to_rgb(vec3(c.x, s, v));
}
