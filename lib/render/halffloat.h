/* halffloat.h: IEEE 754 half-precision values (binary16) to floats, as the
 * !canvas3d framebuffer (RGBA16F) is read back: every half is exactly a
 * float, so the conversion is exact and the same on every route. */
#ifndef FL_RENDER_HALFFLOAT_H
#define FL_RENDER_HALFFLOAT_H

#include <stddef.h>
#include <stdint.h>

/* The float of binary16 [h] (the literal route: sign, exponent and
 * significand taken apart; subnormals and infinities exact, a NaN keeps
 * its payload and is made quiet, as x86's F16C conversion does). */
float half_to_float(uint16_t h);

/* dst[i] = half_to_float(src[i]) for i < n, with the processor's F16C
 * conversion when it has one (the same values), else the literal route.
 * [literal] forces the literal route (for tests).
 *   errors: none. */
void halves_to_floats(const uint16_t *src, float *dst, size_t n, int literal);
/* Whether halves_to_floats has a fast route on this processor (F16C). */
int halves_fast_route(void);

#endif
