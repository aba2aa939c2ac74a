/* test_cpu.c: cpu_has (lib/core/cpu.h), which reads the features glibc's
 * dynamic loader found, against GCC's __builtin_cpu_supports (CPUID of its
 * own) on this processor: every feature the kernels' copies are chosen by
 * must agree, whatever the processor has. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#if defined(__x86_64__) && defined(__GNUC__)
#include <cpuid.h>
#endif

#include "cpu.h"

static void test_agrees(void **s)
{
    (void)s;
#if defined(__x86_64__) && defined(__GNUC__)
    __builtin_cpu_init();
    assert_int_equal(cpu_has(CPU_AVX), __builtin_cpu_supports("avx") != 0);
    assert_int_equal(cpu_has(CPU_AVX2), __builtin_cpu_supports("avx2") != 0);
    assert_int_equal(cpu_has(CPU_AVX512F), __builtin_cpu_supports("avx512f") != 0);
    assert_int_equal(cpu_has(CPU_AVX512VL), __builtin_cpu_supports("avx512vl") != 0);
    unsigned a, b, c, d;
    const bool f16c = __builtin_cpu_supports("avx") && __get_cpuid(1, &a, &b, &c, &d) && (c & bit_F16C);
    assert_int_equal(cpu_has(CPU_F16C), f16c);
#else
    assert_false(cpu_has(CPU_AVX2));
#endif
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_agrees),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
