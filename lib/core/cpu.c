/* cpu.c: cpu_has (cpu.h). */
#include "cpu.h"

/* glibc 2.33 on: its table of the features its loader found (2.32 had the
 * header without the active features) */
#if defined(__x86_64__) && defined(__has_include)
#if __has_include(<sys/platform/x86.h>)
#include <features.h>
#if defined(__GLIBC_PREREQ)
#if __GLIBC_PREREQ(2, 33)
#include <sys/platform/x86.h>
#define HAVE_PLATFORM_X86 1
#endif
#endif
#endif
#endif

#if !defined(HAVE_PLATFORM_X86) && defined(__x86_64__) && defined(__GNUC__)
#include <cpuid.h>
#endif

#if defined(HAVE_PLATFORM_X86)
/* CPU_FEATURE_ACTIVE's reading of glibc's table, with an unsigned shift:
 * the header's inline x86_cpu_active shifts a signed 1 left by the bit,
 * which for bit 31 (AVX-512VL, leaf 7 EBX) is undefined behaviour that
 * UBSan reports. */
static bool active(unsigned index)
{
    const struct cpuid_feature *p = __x86_get_cpuid_feature_leaf(index / 128);
    return p->active_array[(index % 128) / 32] >> (index % 32) & 1u;
}
#endif

bool cpu_has(CpuFeature f)
{
#if defined(HAVE_PLATFORM_X86)
    switch (f) {
    case CPU_AVX: return active(x86_cpu_AVX);
    case CPU_AVX2: return active(x86_cpu_AVX2);
    case CPU_AVX512F: return active(x86_cpu_AVX512F);
    case CPU_AVX512VL: return active(x86_cpu_AVX512VL);
    case CPU_F16C: return active(x86_cpu_F16C);
    }
    return false;
#elif defined(__x86_64__) && defined(__GNUC__)
    __builtin_cpu_init();
    switch (f) {
    case CPU_AVX: return __builtin_cpu_supports("avx");
    case CPU_AVX2: return __builtin_cpu_supports("avx2");
    case CPU_AVX512F: return __builtin_cpu_supports("avx512f");
    case CPU_AVX512VL: return __builtin_cpu_supports("avx512vl");
    case CPU_F16C: {
        /* not every compiler's __builtin_cpu_supports knows "f16c":
         * CPUID leaf 1, ECX bit 29, with AVX's registers kept */
        unsigned a, b, c, d;
        return __builtin_cpu_supports("avx") && __get_cpuid(1, &a, &b, &c, &d) && (c & bit_F16C);
    }
    }
    return false;
#else
    (void)f;
    return false;
#endif
}
