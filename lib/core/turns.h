/* turns.h: trigonometry in turns with exact quadrants (LANGUAGE.md §5.2),
 * shared by the maths built-ins, normal streams and colour conversions
 * (turns.c). */
#ifndef FL_TURNS_H
#define FL_TURNS_H

/* sin of [t] turns: remquo(4t, 1) picks the quadrant, C sin/cos the rest;
 * sin_t(0.25) == 1 exactly, sin_t(0.5) == -0.0. */
double sin_t(double t);
/* cos_t(t) = sin_t(t + 0.25). */
double cos_t(double t);
/* sin_t(t) into [s] and cos_t(t) into [c], bit for bit, with one call of
 * the C library's sincos where the two reduce to the same angle (glibc),
 * else two calls. */
void sincos_t(double t, double *s, double *c);

#define HALF_PI 1.5707963267948966
#define TAU 6.283185307179586

#endif
