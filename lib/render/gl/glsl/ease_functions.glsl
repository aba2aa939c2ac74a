// Easing curves of 0..1 (Flitter docs/shaders.md, !vignette fade=).
float ease_linear(float x) { return clamp(x, 0.0, 1.0); }

float ease_quad(float x) {
    if (x < 0.5) {
        float t = 2.0 * max(x, 0.0);
        return 0.5 * t * t;
    }
    float t = 2.0 * (1.0 - min(x, 1.0));
    return 1.0 - 0.5 * t * t;
}

float ease_cubic(float x) {
    if (x < 0.5) {
        float t = 2.0 * max(x, 0.0);
        return 0.5 * t * t * t;
    }
    float t = 2.0 * (1.0 - min(x, 1.0));
    return 1.0 - 0.5 * t * t * t;
}
