/* halffloat.c: binary16 to float (see halffloat.h). */
#include "halffloat.h"

#include <string.h>

float half_to_float(uint16_t h)
{
    uint32_t sign = (uint32_t)(h & 0x8000u) << 16, exp = (h >> 10) & 0x1fu, man = h & 0x3ffu, bits;
    if (exp == 0x1f) {
        /* infinity, or NaN with its payload, made quiet (as F16C does) */
        bits = sign | 0x7f800000u | man << 13 | (man ? 0x00400000u : 0);
    } else if (exp != 0) {
        bits = sign | (exp + 112) << 23 | man << 13;   /* rebias 15 -> 127 */
    } else if (man == 0) {
        bits = sign;
    } else {
        /* subnormal: man * 2^-24, normalised */
        int shift = 0;
        while (!(man & 0x400u)) man <<= 1, shift++;
        bits = sign | (uint32_t)(113 - shift) << 23 | (man & 0x3ffu) << 13;
    }
    float f;
    memcpy(&f, &bits, sizeof f);
    return f;
}

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>

#include "cpu.h"

/* Whether the processor has F16C and the system keeps the AVX registers
 * (cpu.h). */
static int has_f16c(void) { return cpu_has(CPU_AVX) && cpu_has(CPU_F16C); }

__attribute__((target("avx,f16c"))) static void halves_f16c(const uint16_t *src, float *dst, size_t n)
{
    size_t i = 0;
    for (; i + 8 <= n; i += 8)
        _mm256_storeu_ps(dst + i, _mm256_cvtph_ps(_mm_loadu_si128((const __m128i *)(const void *)(src + i))));
    for (; i < n; i++) dst[i] = half_to_float(src[i]);
}
#endif

int halves_fast_route(void)
{
#if defined(__x86_64__) && defined(__GNUC__)
    return has_f16c();
#else
    return 0;
#endif
}

void halves_to_floats(const uint16_t *src, float *dst, size_t n, int fast)
{
#if defined(__x86_64__) && defined(__GNUC__)
    if (fast) {
        halves_f16c(src, dst, n);
        return;
    }
#endif
    for (size_t i = 0; i < n; i++) dst[i] = half_to_float(src[i]);
}
