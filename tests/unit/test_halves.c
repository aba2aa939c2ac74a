/* test_halves.c: rows_in_halves (lib/render/halves.h), the two-thread
 * split of the window's CPU passes: every row is worked on exactly once,
 * the first half by the caller (part 0) and the rest by the second thread
 * (part 1), and a picture under the threshold entirely by the caller. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "halves.h"

#define ROWS 1001

typedef struct Seen {
    int count[ROWS];
    int part[ROWS];
    int calls[2];
} Seen;

static void mark(void *ctx, int y0, int y1, int part)
{
    Seen *s = ctx;
    s->calls[part]++;
    for (int y = y0; y < y1; y++) {
        s->count[y]++;
        s->part[y] = part;
    }
}

static void split_in_two(void **st)
{
    (void)st;
    static Seen s;
    memset(&s, 0, sizeof s);
    rows_in_halves(ROWS, 64, mark, &s);
    for (int y = 0; y < ROWS; y++) {
        assert_int_equal(s.count[y], 1);
        assert_int_equal(s.part[y], y < ROWS / 2 ? 0 : 1);
    }
    assert_int_equal(s.calls[0], 1);
    assert_int_equal(s.calls[1], 1);
}

static void small_on_caller(void **st)
{
    (void)st;
    static Seen s;
    memset(&s, 0, sizeof s);
    rows_in_halves(63, 64, mark, &s);
    for (int y = 0; y < 63; y++) {
        assert_int_equal(s.count[y], 1);
        assert_int_equal(s.part[y], 0);
    }
    assert_int_equal(s.calls[0], 1);
    assert_int_equal(s.calls[1], 0);
    memset(&s, 0, sizeof s);
    rows_in_halves(0, 1, mark, &s);
    rows_in_halves(-5, 1, mark, &s);
    assert_int_equal(s.calls[0] + s.calls[1], 0);
    rows_in_halves(1, 1, mark, &s);   /* one row cannot be halved */
    assert_int_equal(s.count[0], 1);
    assert_int_equal(s.calls[1], 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(split_in_two),
        cmocka_unit_test(small_on_caller),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
