/* test_turns.c: sincos_t (lib/core/turns.h) gives sin_t(t) and cos_t(t)
 * bit for bit: on random angles, on every kind of double (NaN, infinities,
 * zeros of both signs, huge values), on the ties of the quadrant rounding
 * (4t halfway between integers), and where t + 0.25 rounds (t near a
 * power of two), sweeping the doubles next to each; and, with glibc, that
 * sincos(x) is sin(x) and cos(x) for |x| <= pi/4, the angles sincos_t
 * hands it. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "scene.h"
#include "turns.h"

static Rng rng = {0x5eed};

static double uniform01(void)
{
    return uni(&rng);
}

static uint64_t next_bits(void)
{
    return next_u64(&rng);
}

static int mismatches;

/* [s], [c] against [s1], [c1], bit for bit, at argument [t]. */
static void same_bits(const char *what, double t, double s, double c, double s1, double c1)
{
    if (memcmp(&s, &s1, sizeof s) != 0 || memcmp(&c, &c1, sizeof c) != 0) {
        if (mismatches++ < 10)
            print_error("%s at %a: %a %a against %a %a\n", what, t, s, c, s1, c1);
    }
}

/* sincos_t(t) against sin_t(t) and cos_t(t). */
static void check(double t)
{
    double s, c;
    sincos_t(t, &s, &c);
    same_bits("sincos_t", t, s, c, sin_t(t), cos_t(t));
}

/* [t] and the [n] doubles on each side of it, both signs. */
static void sweep(double t, int n)
{
    double up = t, down = t;
    for (int i = 0; i < n; i++) {
        check(up);
        check(-up);
        check(down);
        check(-down);
        up = nextafter(up, INFINITY);
        down = nextafter(down, -INFINITY);
    }
}

static void same_as_sin_t_and_cos_t(void **st)
{
    (void)st;
    mismatches = 0;
    for (int i = 0; i < 1000000; i++) {
        check((uniform01() - 0.5) * 40);           /* canvas phases */
        check((uniform01() - 0.5) * 2);
        uint64_t b = next_bits();                    /* any double */
        double x;
        memcpy(&x, &b, sizeof x);
        check(x);
        check(ldexp(uniform01(), -(int)(next_bits() % 1100)));   /* tiny */
        check(ldexp(uniform01(), (int)(next_bits() % 60)));      /* large */
    }
    static const double special[] = {0.0, 0.25, 0.5, 0.75, 1.0, 0x1p50, 0x1p51, 0x1p52,
                                     INFINITY, 0x1p-1074, 0x1p-1022, 1e300};
    for (size_t i = 0; i < sizeof special / sizeof special[0]; i++)
        sweep(special[i], 2000);
    check(NAN);
    check(-NAN);
    /* the ties of the quadrant (4t = k + 1/2) and the powers of two
     * where t + 0.25 changes binade and rounds */
    for (int k = -200; k <= 200; k++)
        sweep((k + 0.5) / 4, 64);
    for (int e = -60; e <= 50; e++) {
        sweep(ldexp(1, e), 64);
        sweep(ldexp(1, e) - 0.25, 64);
    }
    assert_int_equal(mismatches, 0);
}

#if defined(__GLIBC__)
/* sin and cos called through pointers the compiler cannot see through:
 * it would otherwise make the two calls of one argument one sincos call
 * (GCC does, without -ffast-math) and compare sincos with itself */
static double (*volatile sin_fn)(double) = sin;
static double (*volatile cos_fn)(double) = cos;

static void check_sincos(double x)
{
    double s, c;
    sincos(x, &s, &c);
    same_bits("sincos", x, s, c, sin_fn(x), cos_fn(x));
}

static void glibc_sincos_is_sin_and_cos(void **st)
{
    (void)st;
    mismatches = 0;
    const double quarter_pi = 0.78539816339744831;
    for (int i = 0; i < 2000000; i++) {
        check_sincos((uniform01() * 2 - 1) * quarter_pi);
        check_sincos(ldexp(uniform01(), -(int)(next_bits() % 1080)) * (i % 2 ? 1 : -1));
    }
    /* the ends of glibc's ranges inside |x| <= pi/4 */
    static const double edge[] = {0.126, 0x1p-26, 0x1p-27, 0.78539816339744831, 0x1p-1022};
    for (size_t e = 0; e < sizeof edge / sizeof edge[0]; e++) {
        double x = edge[e];
        for (int k = 0; k < 20000; k++) {
            check_sincos(x);
            check_sincos(-x);
            x = nextafter(x, 0);
        }
    }
    check_sincos(0.0);
    check_sincos(-0.0);
    assert_int_equal(mismatches, 0);
}
#endif

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(same_as_sin_t_and_cos_t),
#if defined(__GLIBC__)
        cmocka_unit_test(glibc_sincos_is_sin_and_cos),
#endif
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
