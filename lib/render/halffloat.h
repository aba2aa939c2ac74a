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

/* dst[i] = half_to_float(src[i]) for i < n: with the processor's F16C
 * conversion when [fast] is set (the same values), else the literal route.
 * [fast] must be what halves_fast_route() answered: the caller asks once
 * and keeps the answer (GlContext does), because the question executes
 * CPUID, which a virtual machine may trap (9.4 us a call on the machine of
 * bench/PROFILE.md, where asking once per framebuffer row cost 10 ms of
 * CPU time a frame at 1080x1080).
 *   errors: none. */
void halves_to_floats(const uint16_t *src, float *dst, size_t n, int fast);
/* Whether halves_to_floats has a fast route on this processor (F16C):
 * ask once (see above). */
int halves_fast_route(void);

#endif
