/* test_halffloat.c: binary16 to float (lib/render/halffloat.h), the
 * read-back of the !canvas3d framebuffer: hand-checked values (one, a
 * negative, the largest half, the smallest subnormal and another, zero of
 * each sign, infinity, NaNs made quiet with their payload), then every one
 * of the 65,536 halves through the fast route against the literal one,
 * bit for bit (skipped on a processor without F16C, which has only the
 * literal route). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "halffloat.h"

static uint32_t bits_of(float f)
{
    uint32_t b;
    memcpy(&b, &f, sizeof b);
    return b;
}

static void known_values(void **st)
{
    (void)st;
    assert_true(half_to_float(0x3c00) == 1.0f);
    assert_true(half_to_float(0xc000) == -2.0f);
    assert_true(half_to_float(0x3555) == 0x1.554p-2f);      /* 0.333251953125 */
    assert_true(half_to_float(0x7bff) == 65504.0f);
    assert_true(half_to_float(0x0001) == 0x1p-24f);         /* the smallest subnormal */
    assert_true(half_to_float(0x03ff) == 1023 * 0x1p-24f);  /* the largest */
    assert_true(half_to_float(0x0400) == 0x1p-14f);         /* the smallest normal */
    assert_int_equal(bits_of(half_to_float(0x0000)), 0x00000000u);
    assert_int_equal(bits_of(half_to_float(0x8000)), 0x80000000u);
    assert_int_equal(bits_of(half_to_float(0x7c00)), 0x7f800000u);
    assert_int_equal(bits_of(half_to_float(0xfc00)), 0xff800000u);
    assert_int_equal(bits_of(half_to_float(0x7e00)), 0x7fc00000u);   /* quiet NaN */
    assert_int_equal(bits_of(half_to_float(0x7c01)), 0x7fc02000u);   /* signalling: made quiet */
}

static void routes_agree(void **st)
{
    (void)st;
    if (!halves_fast_route()) skip();   /* no F16C here: one route only */
    static uint16_t h[65536 + 5];
    static float fast[65536 + 5], literal[65536 + 5];
    for (uint32_t i = 0; i < 65536 + 5; i++) h[i] = (uint16_t)(i * 40503u);   /* every value, scrambled */
    halves_to_floats(h, fast, 65536 + 5, 1);   /* a length that is not a multiple of 8 */
    halves_to_floats(h, literal, 65536 + 5, 0);
    for (uint32_t i = 0; i < 65536 + 5; i++) {
        if (bits_of(fast[i]) != bits_of(literal[i]))
            fail_msg("half %04x: %08x against the literal %08x", h[i], bits_of(fast[i]), bits_of(literal[i]));
        assert_int_equal(bits_of(literal[i]), bits_of(half_to_float(h[i])));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(known_values),
        cmocka_unit_test(routes_agree),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
