/* test_state.c: the state dictionary (LANGUAGE.md §3.17). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <stdio.h>
#include <stdlib.h>

#include "state.h"

static Vec *key2(double a, double b)
{
    double x[2] = {a, b};
    return vec_from_nums(x, 2);
}

static void test_set_get_delete(void **s)
{
    (void)s;
    StateDict *sd = state_new();
    Vec *k = key2(symbol_value("dish", 4), 3), *v = vec_num1(42);
    assert_true(state_set(sd, k, v));
    assert_false(state_set(sd, k, v));             /* same value: no change */
    assert_true(vec_cnums(state_get(sd, k))[0] == 42);
    Vec *k2 = key2(symbol_value("dish", 4), 3);    /* an equal, distinct key */
    assert_ptr_equal(state_get(sd, k2), state_get(sd, k));
    assert_true(state_set(sd, k2, NULL));          /* null deletes */
    assert_null(state_get(sd, k));
    assert_false(state_set(sd, k2, NULL));
    assert_int_equal(state_count(sd), 0);
    vec_release(k); vec_release(k2); vec_release(v);
    state_free(sd);
}

static void test_key_kinds(void **s)
{
    (void)s;
    StateDict *sd = state_new();
    Vec *zero = vec_num1(0.0), *negz = vec_num1(-0.0), *sym = vec_num1(symbol_value("a", 1));
    Vec *str = vec_str("a", 1), *one = vec_num1(1), *two = vec_num1(2);
    state_set(sd, zero, one);
    state_set(sd, sym, one);
    assert_null(state_get(sd, negz));              /* 0 and -0 are different keys */
    assert_null(state_get(sd, str));               /* :a and "a" differ */
    state_set(sd, str, two);
    assert_true(vec_cnums(state_get(sd, str))[0] == 2);
    assert_true(vec_cnums(state_get(sd, sym))[0] == 1);
    assert_null(state_get(sd, NULL));
    vec_release(zero); vec_release(negz); vec_release(sym); vec_release(str);
    vec_release(one); vec_release(two);
    state_free(sd);
}

static void test_growth_and_churn(void **s)
{
    (void)s;
    StateDict *sd = state_new();
    for (int round = 0; round < 3; round++) {
        for (int i = 0; i < 5000; i++) {
            Vec *k = key2(round, i), *v = vec_num1(i * 2.0);
            state_set(sd, k, v);
            vec_release(k);
            vec_release(v);
        }
        for (int i = 0; i < 5000; i += 2) {
            Vec *k = key2(round, i);
            state_set(sd, k, NULL);
            vec_release(k);
        }
    }
    assert_int_equal(state_count(sd), 3 * 2500);
    for (int i = 1; i < 5000; i += 2) {
        Vec *k = key2(2, i);
        const Vec *v = state_get(sd, k);
        assert_non_null(v);
        assert_true(vec_cnums(v)[0] == i * 2.0);
        vec_release(k);
    }
    size_t n;
    StateEntry *e = state_entries(sd, &n);
    assert_int_equal(n, 7500);
    free(e);
    state_clear(sd);
    assert_int_equal(state_count(sd), 0);
    state_free(sd);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_set_get_delete),
        cmocka_unit_test(test_key_kinds),
        cmocka_unit_test(test_growth_and_churn),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
