// Blend functions of the composite= attribute: [s] is drawn onto [d];
// both are premultiplied RGBA (Flitter docs/windows.md, composite=).
vec4 composite_over(vec4 s, vec4 d) { return s + (1.0 - s.a) * d; }
vec4 composite_dest_over(vec4 s, vec4 d) { return d + (1.0 - d.a) * s; }
vec4 composite_lighten(vec4 s, vec4 d) { return max(d, s); }
vec4 composite_darken(vec4 s, vec4 d) { return min(d, s); }
vec4 composite_add(vec4 s, vec4 d) { return vec4(d.rgb + s.rgb, min(1.0, d.a + s.a)); }
vec4 composite_difference(vec4 s, vec4 d) { return vec4(abs(s.rgb - d.rgb), max(d.a, s.a)); }
vec4 composite_multiply(vec4 s, vec4 d) { return d * s; }
