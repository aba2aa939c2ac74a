/* test_counter.c: unit tests of the !counter renderer (lib/runtime/counter.c,
 * COUNTERS.md). Each test builds a !counter node, runs counter_update for a
 * few frame times and checks the state dictionary entries KEY and KEY;:time
 * exactly. The inputs are chosen so that every expected value is an exact
 * double computed by hand from the update rule. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>

#include "counter.h"
#include "node.h"
#include "state.h"
#include "value.h"

static Node *counter_node(void)
{
    Str *k = str_from("counter");
    Node *n = node_new(k);
    str_release(k);
    return n;
}

/* Set attribute [name] of [n] to [v] (consumes v). */
static void set(Node *n, const char *name, Vec *v)
{
    Str *s = str_from(name);
    node_set_attr(n, s, v);
    str_release(s);
}

static Vec *nums(int n, ...)
{
    double d[8];
    va_list ap;
    va_start(ap, n);
    for (int i = 0; i < n; i++) d[i] = va_arg(ap, double);
    va_end(ap);
    return vec_from_nums(d, (uint32_t)n);
}

static Vec *sym(const char *name) { return vec_num1(symbol_value(name, strlen(name))); }

/* The value under :c (borrowed). */
static const Vec *value(StateDict *sd)
{
    Vec *k = sym("c");
    const Vec *v = state_get(sd, k);
    vec_release(k);
    return v;
}

/* The value under :c;:time (borrowed). */
static const Vec *time_value(StateDict *sd)
{
    Vec *parts[2] = {sym("c"), sym("time")};
    Vec *k = vec_compose(parts, 2);
    const Vec *v = state_get(sd, k);
    vec_release(k);
    vec_release(parts[0]);
    vec_release(parts[1]);
    return v;
}

/* Assert that [v] is exactly the numbers given. */
static void expect(const Vec *v, int n, ...)
{
    assert_true(vec_is_num(v));
    assert_int_equal(v->len, n);
    va_list ap;
    va_start(ap, n);
    for (int i = 0; i < n; i++) {
        double want = va_arg(ap, double), got = vec_cnums(v)[i];
        if (!(got == want || (isnan(got) && isnan(want))))
            fail_msg("element %d = %.17g, expected %.17g", i, got, want);
    }
    va_end(ap);
}

/* First frame takes `initial`; later frames add (time - last) * rate. */
static void test_initial_then_rate(void **unused)
{
    (void)unused;
    StateDict *sd = state_new();
    Node *n = counter_node();
    set(n, "state", sym("c"));
    set(n, "initial", vec_num1(5));
    set(n, "rate", vec_num1(2));
    counter_update(n, sd, 0.0);
    expect(value(sd), 1, 5.0);
    expect(time_value(sd), 1, 0.0);
    counter_update(n, sd, 0.5);
    expect(value(sd), 1, 6.0);        /* (0.5 - 0) * 2 + 5 */
    expect(time_value(sd), 1, 0.5);
    /* a vector rate broadcasts over the scalar value */
    set(n, "rate", nums(2, 1.0, -2.0));
    counter_update(n, sd, 1.5);
    expect(value(sd), 2, 7.0, 4.0);   /* (1.5 - 0.5) * (1;-2) + 6 */
    node_release(n);
    state_free(sd);
}

/* Without attributes other than state: value 0, rate 0, frame time kept. */
static void test_defaults(void **unused)
{
    (void)unused;
    StateDict *sd = state_new();
    Node *n = counter_node();
    set(n, "state", sym("c"));
    counter_update(n, sd, 3.25);
    expect(value(sd), 1, 0.0);
    expect(time_value(sd), 1, 3.25);
    counter_update(n, sd, 4.0);
    expect(value(sd), 1, 0.0);
    /* a non-numeric `time` falls back to the frame time */
    set(n, "time", vec_str("x", 1));
    counter_update(n, sd, 6.5);
    expect(time_value(sd), 1, 6.5);
    node_release(n);
    state_free(sd);
}

/* The `time` attribute replaces the frame time, and may be a vector. */
static void test_custom_time(void **unused)
{
    (void)unused;
    StateDict *sd = state_new();
    Node *n = counter_node();
    set(n, "state", sym("c"));
    set(n, "time", nums(2, 10.0, 20.0));
    set(n, "rate", vec_num1(0.5));
    counter_update(n, sd, 0.0);
    expect(value(sd), 1, 0.0);
    expect(time_value(sd), 2, 10.0, 20.0);
    set(n, "time", nums(2, 12.0, 28.0));
    counter_update(n, sd, 1.0);
    expect(value(sd), 2, 1.0, 4.0);   /* (2;8) * 0.5 + 0 */
    node_release(n);
    state_free(sd);
}

/* reset selects `initial` element-wise where it is non-zero. */
static void test_reset(void **unused)
{
    (void)unused;
    StateDict *sd = state_new();
    Node *n = counter_node();
    set(n, "state", sym("c"));
    set(n, "initial", nums(2, 1.0, 2.0));
    set(n, "rate", vec_num1(4));
    counter_update(n, sd, 0.0);
    expect(value(sd), 2, 1.0, 2.0);
    counter_update(n, sd, 0.25);
    expect(value(sd), 2, 2.0, 3.0);
    set(n, "reset", nums(2, 0.0, 1.0));
    counter_update(n, sd, 0.5);
    expect(value(sd), 2, 3.0, 2.0);   /* element 0 advances, element 1 resets */
    set(n, "reset", vec_num1(1));
    counter_update(n, sd, 0.75);
    expect(value(sd), 2, 1.0, 2.0);
    set(n, "reset", vec_str("yes", 3));   /* non-numeric: default 0 */
    counter_update(n, sd, 1.0);
    expect(value(sd), 2, 2.0, 3.0);
    node_release(n);
    state_free(sd);
}

/* reset, initial and the advanced value of different lengths: the longest
 * decides, the others wrap around (a single reset picks the whole of one,
 * repeated to that length). */
static void test_reset_wraps(void **unused)
{
    (void)unused;
    StateDict *sd = state_new();
    Node *n = counter_node();
    set(n, "state", sym("c"));
    set(n, "initial", nums(3, 5.0, 6.0, 7.0));
    set(n, "rate", vec_num1(2));
    counter_update(n, sd, 0.0);
    expect(value(sd), 3, 5.0, 6.0, 7.0);
    /* a longer initial: the advanced 6;7;8 wraps to its length */
    set(n, "initial", nums(4, 1.0, 1.0, 1.0, 1.0));
    counter_update(n, sd, 0.5);
    expect(value(sd), 4, 6.0, 7.0, 8.0, 6.0);
    /* a single reset picks the shorter initial, repeated */
    set(n, "initial", nums(2, -1.0, -2.0));
    set(n, "rate", nums(4, 0.0, 0.0, 0.0, 4.0));
    set(n, "reset", vec_num1(1));
    counter_update(n, sd, 1.0);
    expect(value(sd), 4, -1.0, -2.0, -1.0, -2.0);
    /* a shorter reset wraps too: 1;0 over 4 elements */
    set(n, "reset", nums(2, 1.0, 0.0));
    set(n, "initial", nums(3, 10.0, 20.0, 30.0));
    counter_update(n, sd, 1.5);
    expect(value(sd), 4, 10.0, -2.0, 30.0, 0.0);   /* advanced -1;-2;-1;0 */
    node_release(n);
    state_free(sd);
}

/* minimum/maximum (or min/max) clamp element-wise, broadcasting bounds. */
static void test_clamping(void **unused)
{
    (void)unused;
    StateDict *sd = state_new();
    Node *n = counter_node();
    set(n, "state", sym("c"));
    set(n, "initial", nums(3, -3.0, 5.0, 12.0));
    set(n, "min", vec_num1(0));
    set(n, "max", vec_num1(10));
    counter_update(n, sd, 0.0);
    expect(value(sd), 3, 0.0, 5.0, 10.0);
    /* `minimum` wins over `min`; a longer bound lengthens the value */
    set(n, "minimum", nums(4, 1.0, 6.0, 0.0, 7.0));
    set(n, "rate", vec_num1(0));
    counter_update(n, sd, 1.0);
    expect(value(sd), 4, 1.0, 6.0, 10.0, 7.0);
    node_release(n);
    state_free(sd);

    /* NaN stays NaN under Python's max/min rules */
    sd = state_new();
    n = counter_node();
    set(n, "state", sym("c"));
    set(n, "initial", vec_num1(NAN));
    set(n, "minimum", vec_num1(0));
    set(n, "maximum", vec_num1(1));
    counter_update(n, sd, 0.0);
    expect(value(sd), 1, (double)NAN);
    node_release(n);
    state_free(sd);
}

/* A value without its :time key advances to null, so the key is removed;
 * the next frame starts again from `initial`. */
static void test_null_time_key(void **unused)
{
    (void)unused;
    StateDict *sd = state_new();
    Node *n = counter_node();
    set(n, "state", sym("c"));
    set(n, "initial", vec_num1(7));
    set(n, "rate", vec_num1(1));
    Vec *k = sym("c"), *v = vec_num1(3);
    state_set(sd, k, v);
    counter_update(n, sd, 2.0);
    assert_null(value(sd));
    expect(time_value(sd), 1, 2.0);
    counter_update(n, sd, 3.0);
    expect(value(sd), 1, 7.0);
    vec_release(k);
    vec_release(v);
    node_release(n);
    state_free(sd);
}

/* Without a `state` key the node does nothing. */
static void test_no_key(void **unused)
{
    (void)unused;
    StateDict *sd = state_new();
    Node *n = counter_node();
    set(n, "rate", vec_num1(1));
    counter_update(n, sd, 1.0);
    assert_int_equal(state_count(sd), 0);
    node_release(n);
    state_free(sd);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_initial_then_rate),
        cmocka_unit_test(test_defaults),
        cmocka_unit_test(test_custom_time),
        cmocka_unit_test(test_reset),
        cmocka_unit_test(test_reset_wraps),
        cmocka_unit_test(test_clamping),
        cmocka_unit_test(test_null_time_key),
        cmocka_unit_test(test_no_key),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
