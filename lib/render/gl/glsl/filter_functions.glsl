// Filters shared by the built-in shaders (Flitter docs/shaders.md: !blur,
// !adjust, !bloom, !flare).
<%include file="color_functions.glsl"/>

// One direction of a normalised Gaussian blur: the samples [step] apart
// out to [radius] on both sides of [coord], weighted exp(-i^2 / 2 sigma^2)
// (sigma in samples). The weights come from one exp by recurrence, as
// Flitter's do: with q = exp(-1 / 2 sigma^2), w(i) = w(i-1) q^(2i-1),
// the factor itself growing by q^2 a step.
vec4 filter_blur(sampler2D tex, vec2 coord, int radius, float sigma, vec2 step) {
    vec4 total = texture(tex, coord);
    float weights = 1.0;
    float q = exp(-0.5 / (sigma * sigma));
    float w = q, factor = q * q * q;
    float q2 = q * q;
    for (int i = 1; i <= radius; i++) {
        total += w * (texture(tex, coord + float(i) * step) + texture(tex, coord - float(i) * step));
        weights += 2.0 * w;
        w *= factor;
        factor *= q2;
    }
    return total / weights;
}

// Exposure (stops), contrast about 0.5 and brightness, then shadows below
// a luminance of 0.25 and highlights above 0.5 (stops, faded in).
vec3 filter_adjust(vec3 color, float exposure, float contrast, float brightness, float shadows, float highlights) {
    vec3 c = exp2(exposure) * contrast * color + (brightness + 0.5 * (1.0 - contrast));
    float l = srgb_luminance(c);
    c *= exp2(shadows * clamp((0.25 - l) * 4.0, 0.0, 1.0));
    c *= exp2(highlights * clamp((l - 0.5) * 2.0, 0.0, 1.0));
    return c;
}

// The fraction of a colour that counts as "bright" above [threshold].
float flare_bright(vec3 c, float threshold) { return smoothstep(0.0, 1.0, srgb_luminance(c) - threshold); }

// A lens ghost: the image reflected through the centre, its radius
// distorted by [distort] and shrunk by [scale], faded towards the edge,
// split into six bands of the spectrum by [aberration].
vec3 filter_lens_ghost(sampler2D tex, vec2 coord, vec2 size, float distort, float scale, float threshold,
                       float attenuation, float aberration) {
    const vec3 bands[6] = vec3[6](vec3(0.1, 0.0, 0.3), vec3(0.0, 0.0, 0.5), vec3(0.0, 0.25, 0.2),
                                  vec3(0.0, 0.5, 0.0), vec3(0.4, 0.25, 0.0), vec3(0.5, 0.0, 0.0));
    vec2 p = (coord - 0.5) * size;
    float r = length(p);
    vec2 dir = p / r;
    float edge = 0.5 * length(size);
    r = edge * (1.0 - pow(1.0 - r / edge, distort)) / scale;
    float fade = 1.0 - pow(clamp(r / edge, 0.0, 1.0), 2.0);
    vec3 sum = vec3(0.0);
    if (aberration > 0.0) {
        for (int j = 0; j < 6; j++) {
            float stretch = 1.0 + 0.25 * aberration * (float(j) / 5.0 - 0.5);
            vec3 c = texture(tex, dir * r * stretch / size + 0.5).rgb;
            sum += bands[j] * c * flare_bright(c, threshold);
        }
    } else {
        vec3 c = texture(tex, dir * r / size + 0.5).rgb;
        sum = c * flare_bright(c, threshold);
    }
    return sum * fade * exp2(-attenuation);
}

// One starburst direction pair: the brightest of four directions at each
// step, weighted down quadratically along [n] steps.
vec3 flare_rays(sampler2D tex, vec2 coord, vec2 size, float n, vec2 a, vec2 b, float threshold) {
    vec3 sum = vec3(0.0);
    for (float i = 0.0; i < n; i += 1.0) {
        vec3 c = max(max(texture(tex, coord + i * a / size).rgb, texture(tex, coord - i * a / size).rgb),
                     max(texture(tex, coord + i * b / size).rgb, texture(tex, coord - i * b / size).rgb));
        float w = (1.0 - i / n) * (1.0 - i / n);
        sum += c * flare_bright(c, threshold) * w;
    }
    return n > 0.0 ? sum / n : sum;
}

// Starburst lines, upright and diagonal, as long as [upright_length] and
// [diagonal_length] of half the shorter side.
vec3 filter_lens_flare(sampler2D tex, vec2 coord, vec2 size, float upright_length, float diagonal_length,
                       float threshold, float attenuation) {
    float half_side = 0.5 * min(size.x, size.y);
    vec3 upright = vec3(0.0), diagonal = vec3(0.0);
    float n = upright_length * half_side;
    if (n > 0.0) upright = flare_rays(tex, coord, size, n, vec2(0.0, 1.0), vec2(1.0, 0.0), threshold);
    n = diagonal_length * half_side * sqrt(2.0) / 2.0;
    if (n > 0.0) diagonal = flare_rays(tex, coord, size, n, vec2(1.0, 1.0), vec2(1.0, -1.0), threshold);
    return max(upright, diagonal) * exp2(-attenuation);
}

// A halo: the bright parts of the ring of [radius] (of half the shorter
// side) around each pixel, averaged.
vec3 filter_lens_halo(sampler2D tex, vec2 coord, vec2 size, float radius, float threshold, float attenuation) {
    const float turn = 6.283185307179586;
    float r = radius * 0.5 * min(size.x, size.y);
    float n = turn * r;
    vec3 sum = vec3(0.0);
    if (n > 0.0) {
        for (float i = 0.0; i < n; i += 1.0) {
            float a = turn * i / n;
            vec3 c = texture(tex, coord + r * vec2(cos(a), sin(a)) / size).rgb;
            sum += c * flare_bright(c, threshold);
        }
        sum /= n;
    }
    return sum * exp2(-attenuation);
}
