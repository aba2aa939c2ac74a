/* cpu.h: which vector instruction sets this processor and its operating
 * system run, for the copies of the numeric kernels compiled for them
 * (physics pair kernels, the read-back's half floats).
 *
 * With glibc (2.33 on) the answer is the one its dynamic loader worked
 * out at start-up (<sys/platform/x86.h>'s table, as CPU_FEATURE_ACTIVE
 * reads it): no CPUID of our own, which a hypervisor traps
 * (bench/PROFILE.md, "lib/core/cpu.h: no CPUID of our own"), and no
 * constructor of libgcc's __builtin_cpu_supports, which asks about a
 * dozen leaves when every process starts. Elsewhere on x86-64,
 * __builtin_cpu_supports and CPUID; on other processors, none. */
#ifndef FL_CPU_H
#define FL_CPU_H

#include <stdbool.h>

typedef enum {
    CPU_AVX,       /* and the system saves the AVX registers */
    CPU_AVX2,
    CPU_AVX512F,
    CPU_AVX512VL,
    CPU_F16C,      /* half-float conversions (AVX's encoding) */
} CpuFeature;

/* Whether the processor has [f] and the system lets programs use it.
 * Cheap: callers may ask on every call. */
bool cpu_has(CpuFeature f);

#endif
