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

/* state_get_nums: the entry state_get finds for the numeric key of those
 * numbers, through tombstones; bits compared (0 and -0 differ, a NaN key
 * matches its own bits), an object key of the same texts never; one read
 * counted each; nothing for no numbers */
static void test_get_nums(void **s)
{
    (void)s;
    StateDict *sd = state_new();
    double a = symbol_value("a", 1), nan_bits = symbol_value("zz", 2);
    for (int i = 0; i < 300; i++) {
        Vec *k = key2(a, i), *v = vec_num1(i + 0.5);
        state_set(sd, k, v);
        vec_release(k);
        vec_release(v);
    }
    for (int i = 0; i < 300; i += 3) {   /* tombstones in the probe chains */
        Vec *k = key2(a, i);
        state_set(sd, k, NULL);
        vec_release(k);
    }
    for (int i = 0; i < 300; i++) {
        double x[2] = {a, i};
        Vec *k = key2(a, i);
        const Vec *got = state_get_nums(sd, x, 2);
        assert_ptr_equal(got, state_get(sd, k));
        if (i % 3) assert_true(vec_cnums(got)[0] == i + 0.5);
        else assert_null(got);
        vec_release(k);
    }
    Vec *zero = vec_num1(0.0), *one = vec_num1(1), *sym = vec_num1(nan_bits), *str = vec_str("a", 1);
    state_set(sd, zero, one);
    state_set(sd, sym, one);
    state_set(sd, str, one);
    double z = 0.0, nz = -0.0, x1[1] = {a};
    assert_ptr_equal(state_get_nums(sd, &z, 1), state_get(sd, zero));
    assert_null(state_get_nums(sd, &nz, 1));
    assert_ptr_equal(state_get_nums(sd, &nan_bits, 1), state_get(sd, sym));
    assert_null(state_get_nums(sd, x1, 1));          /* :a, not "a" */
    assert_null(state_get_nums(sd, x1, 0));
    unsigned long long gets = state_counts(sd).gets;
    state_get_nums(sd, &z, 1);
    state_get_nums(sd, x1, 0);
    assert_int_equal(state_counts(sd).gets, gets + 2);
    vec_release(zero); vec_release(one); vec_release(sym); vec_release(str);
    state_free(sd);
}

/* state_set_nums: in place only when the state alone holds a numeric
 * value of the length; else a new vector, as state_set stores it (an equal
 * value kept); one read counted, a write when not in place */
static void test_set_nums(void **s)
{
    (void)s;
    StateDict *sd = state_new();
    Vec *k = key2(symbol_value("p", 1), 7);
    const double a[2] = {1.5, -2}, b[2] = {3, 4}, c[3] = {5, 6, 7};
    StateCounts n0 = state_counts(sd);
    Vec *v = state_set_nums(sd, k, a, 2);                 /* absent: inserted */
    StateCounts n1 = state_counts(sd);
    assert_int_equal(n1.sets - n0.sets, 1);
    assert_int_equal(n1.compound - n0.compound, 1);
    assert_int_equal(n1.gets - n0.gets, 1);
    assert_ptr_equal(v, state_get(sd, k));
    assert_true(vec_cnums(v)[0] == 1.5 && vec_cnums(v)[1] == -2 && v->len == 2 && v->refs == 1);
    n1 = state_counts(sd);
    Vec *w = state_set_nums(sd, k, b, 2);                 /* only the state holds it: in place */
    assert_ptr_equal(w, v);
    assert_true(vec_cnums(v)[0] == 3 && vec_cnums(v)[1] == 4);
    StateCounts n2 = state_counts(sd);
    assert_int_equal(n2.sets, n1.sets);
    assert_int_equal(n2.compound, n1.compound);
    assert_int_equal(n2.gets - n1.gets, 1);
    Vec *held = vec_retain(v);                            /* held elsewhere: a new vector */
    w = state_set_nums(sd, k, a, 2);
    assert_ptr_not_equal(w, held);
    assert_true(vec_cnums(held)[0] == 3 && vec_cnums(held)[1] == 4);
    assert_true(vec_cnums(w)[0] == 1.5 && vec_cnums(w)[1] == -2);
    assert_int_equal(held->refs, 1);
    vec_release(held);
    held = vec_retain(w);                                 /* held, equal numbers: kept */
    assert_ptr_equal(state_set_nums(sd, k, a, 2), held);
    assert_int_equal(state_counts(sd).compound - n2.compound, 2);
    vec_release(held);
    w = state_set_nums(sd, k, c, 3);                      /* another length: a new vector */
    assert_int_equal(w->len, 3);
    assert_ptr_equal(state_get(sd, k), w);
    assert_null(state_set_nums(sd, NULL, a, 2));
    assert_null(state_set_nums(sd, k, a, 0));
    assert_int_equal(state_count(sd), 1);
    vec_release(k);
    state_free(sd);
}

/* state_get_cached: for each of 24 keys a cell, read after each of 3,000
 * random changes (new keys, new values of present keys, in place or not,
 * deletions, a rebuild, a clear) gives the very vector state_get gives;
 * one cell read from two dictionaries in turn gives each its own entry;
 * one read counted each time; a cell outlives its dictionary */
static void test_get_cached(void **s)
{
    (void)s;
    enum { NKEYS = 24, NCELLS = 24 };
    StateDict *sd = state_new();
    Vec *keys[NKEYS];
    StateCached cells[NCELLS] = {{0}};
    for (int i = 0; i < NKEYS; i++) keys[i] = key2(symbol_value("k", 1), i);
    uint64_t x = 12345;
    for (int step = 0; step < 3000; step++) {
        x = x * UINT64_C(6364136223846793005) + UINT64_C(1442695040888963407);
        unsigned r = (unsigned)(x >> 33), k = r % NKEYS, what = (r / NKEYS) % 16;
        if (what < 6) {                                  /* a value, maybe a new key */
            Vec *v = vec_num1(step);
            state_set(sd, keys[k], v);
            vec_release(v);
        } else if (what < 9) {                           /* in place when it can be */
            double y[1] = {-step};
            state_set_nums(sd, keys[k], y, 1);
        } else if (what < 13) {
            state_set(sd, keys[k], NULL);                /* deleted (or absent already) */
        } else if (what == 13 && step % 7 == 0) {
            state_reserve(sd, 200 + (size_t)step);       /* rebuilt */
        } else if (what == 14 && step % 11 == 0) {
            state_clear(sd);
        }
        for (int c = 0; c < NCELLS; c++) {
            unsigned long long gets = state_counts(sd).gets;
            const Vec *want = state_get(sd, keys[c % NKEYS]);
            assert_ptr_equal(state_get_cached(sd, keys[c % NKEYS], &cells[c]), want);
            assert_int_equal(state_counts(sd).gets, gets + 2);
        }
    }
    /* an equal, distinct key vector finds the same entry */
    Vec *v = vec_num1(7), *k3 = key2(symbol_value("k", 1), 3);
    state_set(sd, keys[3], v);
    StateCached c3 = {0};
    assert_ptr_equal(state_get_cached(sd, k3, &c3), state_get(sd, keys[3]));
    assert_true(vec_cnums(state_get_cached(sd, k3, &c3))[0] == 7);
    /* two dictionaries through one cell, each holding the key in another
     * value (and in another slot: sd2 is small, sd has been rebuilt) */
    StateDict *sd2 = state_new();
    Vec *w = vec_num1(8);
    state_set(sd2, keys[3], w);
    for (int i = 0; i < 3; i++) {
        assert_true(vec_cnums(state_get_cached(sd, k3, &c3))[0] == 7);
        assert_true(vec_cnums(state_get_cached(sd2, k3, &c3))[0] == 8);
    }
    state_set(sd2, keys[3], NULL);
    assert_null(state_get_cached(sd2, k3, &c3));
    assert_null(state_get_cached(sd2, k3, &c3));       /* absent, kept */
    state_set(sd2, keys[3], v);
    assert_true(vec_cnums(state_get_cached(sd2, k3, &c3))[0] == 7);   /* added: found */
    StateCached c0 = {0};
    assert_null(state_get_cached(sd2, NULL, &c0));    /* no key: nothing kept */
    assert_null(c0.layout);
    state_free(sd2);                                  /* c3 keeps its layout */
    assert_true(vec_cnums(state_get_cached(sd, k3, &c3))[0] == 7);
    state_cached_release(&c3);
    assert_null(c3.layout);
    for (int c = 0; c < NCELLS; c++) state_cached_release(&cells[c]);
    for (int i = 0; i < NKEYS; i++) vec_release(keys[i]);
    vec_release(v); vec_release(w); vec_release(k3);
    state_free(sd);
}

/* state_reserve, then inserts, deletes and finds: the same contents as
 * without it, tombstones included */
static void test_reserve(void **s)
{
    (void)s;
    StateDict *sd = state_new();
    for (int i = 0; i < 40; i++) {
        Vec *k = key2(-1, i), *v = vec_num1(i);
        state_set(sd, k, v);
        vec_release(k);
        vec_release(v);
    }
    for (int i = 0; i < 40; i += 3) {
        Vec *k = key2(-1, i);
        state_set(sd, k, NULL);
        vec_release(k);
    }
    state_reserve(sd, 3000);
    state_reserve(sd, 10);                                /* room already: nothing */
    for (int i = 0; i < 3000; i++) {
        Vec *k = key2(1, i);
        double x = i;
        state_set_nums(sd, k, &x, 1);
        vec_release(k);
    }
    assert_int_equal(state_count(sd), 3000 + 40 - 14);
    for (int i = 0; i < 40; i++) {
        Vec *k = key2(-1, i);
        const Vec *v = state_get(sd, k);
        if (i % 3 == 0) assert_null(v);
        else assert_true(v && vec_cnums(v)[0] == i);
        vec_release(k);
    }
    for (int i = 0; i < 3000; i++) {
        Vec *k = key2(1, i);
        const Vec *v = state_get(sd, k);
        assert_true(v && v->len == 1 && vec_cnums(v)[0] == i);
        vec_release(k);
    }
    state_free(sd);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_set_get_delete),
        cmocka_unit_test(test_key_kinds),
        cmocka_unit_test(test_growth_and_churn),
        cmocka_unit_test(test_get_nums),
        cmocka_unit_test(test_set_nums),
        cmocka_unit_test(test_reserve),
        cmocka_unit_test(test_get_cached),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
