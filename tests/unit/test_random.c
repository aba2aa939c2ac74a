/* test_random.c: pseudo-random streams and shuffle (LANGUAGE.md §5.8,
 * §7.5, tests/lang random.tree), checked bit for bit against the
 * reference's values. Builtins are called with ev = NULL (no error set). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "builtins.h"
#include "streams.h"
#include "value.h"

/* ------------------------------------------------------------------ */
/* Helpers                                                             */
/* ------------------------------------------------------------------ */

static Vec *nums(int n, ...)
{
    va_list ap;
    va_start(ap, n);
    Vec *v = vec_new_num((uint32_t)n);
    for (int i = 0; i < n; i++) vec_nums(v)[i] = va_arg(ap, double);
    va_end(ap);
    return v;
}

static Vec *sym(const char *name) { return vec_num1(symbol_value(name, strlen(name))); }

static bool same(double a, double b) { return memcmp(&a, &b, sizeof a) == 0; }

/* Call builtin [name] with [n] borrowed arguments; returns its result. */
static Vec *call(const char *name, int n, Vec *const *args)
{
    const Builtin *bi = bi_lookup(name, strlen(name));
    assert_non_null(bi);
    return bi->fn(NULL, bi, n, args);
}

/* The stream's value at Flitter index [k] ((uint64)(int64)floor(k)). */
static double at(const Vec *s, double k)
{
    return rng_value((StreamKind)s->stream, s->key, (uint64_t)(int64_t)floor(k));
}

/* A stream made by builtin [name] from the seed [seed] (consumed; NULL
 * for no argument). */
static Vec *stream(const char *name, Vec *seed)
{
    Vec *r = seed ? call(name, 1, &seed) : call(name, 0, NULL);
    vec_release(seed);
    assert_true(vec_is_stream(r));
    assert_int_equal(vec_len(r), 0);
    return r;
}

static void check_values(const Vec *s, int n, const double *idx, const double *want)
{
    for (int i = 0; i < n; i++) {
        double got = at(s, idx[i]);
        if (!same(got, want[i]))
            fail_msg("index %g: got %.17g want %.17g", idx[i], got, want[i]);
    }
}

/* ------------------------------------------------------------------ */
/* Seed hashes and uniform (§3.16, §7.5 #73-77, #88)                   */
/* ------------------------------------------------------------------ */

static void test_seed_hash(void **st)
{
    (void)st;
    assert_true(vec_hash(NULL, true) == UINT64_C(0xe220a8397b1dcdaf));
    Vec *one = vec_num1(1);
    assert_true(vec_hash(one, true) == UINT64_C(0x03953eea0e693074));
    Vec *u = stream("uniform", NULL);
    assert_true(u->key == HASH_START);
    assert_int_equal(u->stream, STREAM_UNIFORM);
    vec_release(u);
    Vec *arg = NULL;
    u = call("uniform", 1, &arg); /* explicit null */
    assert_true(u->key == HASH_START);
    vec_release(u);
    u = call("uniform", 1, &one);
    assert_true(u->key == UINT64_C(0x03953eea0e693074));
    vec_release(u);
    vec_release(one);
}

static void test_squares(void **st)
{
    (void)st;
    /* value 0 of uniform() is squares(0, K) = K*K-derived; check scale */
    double u = rng_uniform(HASH_START, 0);
    assert_true(same(u, 0.11377270426292592));
    assert_true(same(u, (double)rng_squares(0, HASH_START) / 18446744073709551616.0));
    /* rng_uniform converts the 64-bit output without the compiler's
     * unsigned conversion: the same bits as the cast, over a million
     * outputs (half of them 2^63 and up, about 250 of those exactly
     * halfway between two doubles, so both ways a tie can go) */
    uint64_t key = 0x9e3779b97f4a7c15u;
    for (uint64_t i = 0; i < 1000000; i++) {
        double a = rng_uniform(key, i);
        double b = (double)rng_squares(i, key) / 18446744073709551616.0;
        assert_memory_equal(&a, &b, sizeof a);
        key = key * 6364136223846793005u + 1442695040888963407u;
    }
}

static void test_uniform_vectors(void **st)
{
    (void)st;
    Vec *u = stream("uniform", NULL);
    check_values(u, 1, (double[]){0}, (double[]){0.11377270426292592});
    vec_release(u);

    u = stream("uniform", sym("x"));
    check_values(u, 4, (double[]){0, 1, 2, -1},
                 (double[]){0.5012199625101028, 0.8455173988858942, 0.1393270459400855,
                            0.7565468999279326});
    vec_release(u);

    Vec *a = stream("uniform", vec_num1(1)), *b = stream("uniform", vec_num1(1.5));
    assert_true(a->key == b->key);
    check_values(a, 1, (double[]){0}, (double[]){0.3236437711805903});
    vec_release(a);
    vec_release(b);

    a = stream("uniform", nums(2, symbol_value("x", 1), -0.5));
    b = stream("uniform", nums(2, symbol_value("x", 1), -1.0));
    assert_true(a->key == b->key);
    vec_release(a);
    vec_release(b);

    /* "x" and :x seed differently; -0 and 0 too */
    a = stream("uniform", vec_str("x", 1));
    b = stream("uniform", sym("x"));
    assert_true(a->key != b->key);
    vec_release(a);
    vec_release(b);
    a = stream("uniform", vec_num1(-0.0));
    b = stream("uniform", vec_num1(0.0));
    assert_true(a->key != b->key);
    vec_release(a);
    vec_release(b);
}

/* ------------------------------------------------------------------ */
/* beta and normal (§7.5 #78-81)                                       */
/* ------------------------------------------------------------------ */

static void test_beta(void **st)
{
    (void)st;
    Vec *b = stream("beta", vec_num1(1));
    assert_int_equal(b->stream, STREAM_BETA);
    check_values(b, 2, (double[]){0, 1}, (double[]){0.3236437711805903, 0.6619503345041775});
    vec_release(b);

    b = stream("beta", sym("q"));
    char text[80];
    snprintf(text, sizeof text, "%.9g;%.9g;%.9g", at(b, 0), at(b, 1), at(b, 2));
    assert_string_equal(text, "0.475603294;0.515468558;0.314542472");
    vec_release(b);

    /* median of uniform values 4i, 4i+1, 4i+2 */
    uint64_t k = UINT64_C(0x0123456789abcdef);
    for (uint64_t i = 0; i < 50; i++) {
        double u[3] = {rng_uniform(k, 4 * i), rng_uniform(k, 4 * i + 1), rng_uniform(k, 4 * i + 2)};
        double lo = fmin(u[0], fmin(u[1], u[2])), hi = fmax(u[0], fmax(u[1], u[2]));
        double med = u[0] + u[1] + u[2] - lo - hi;
        assert_true(fabs(rng_beta(k, i) - med) < 1e-15);
    }
}

static void test_normal(void **st)
{
    (void)st;
    Vec *n = stream("normal", vec_num1(1));
    assert_int_equal(n->stream, STREAM_NORMAL);
    char text[80];
    snprintf(text, sizeof text, "%.9g;%.9g", at(n, 0), at(n, 1));
    assert_string_equal(text, "-1.50110779;-0.0538430951");
    snprintf(text, sizeof text, "%.10g", at(n, 0));
    assert_string_equal(text, "-1.501107791");
    vec_release(n);

    n = stream("normal", NULL);
    snprintf(text, sizeof text, "%.9g;%.9g;%.9g;%.9g", at(n, 0), at(n, 1), at(n, 2), at(n, 3));
    assert_string_equal(text, "1.50032773;1.44779901;1.69169514;0.837380376");
    vec_release(n);

    /* the pair rule: i and i^1 share R */
    uint64_t k = 77;
    for (uint64_t i = 0; i < 20; i += 2) {
        double a = rng_normal(k, i), b = rng_normal(k, i + 1);
        double r = sqrt(-2 * log(rng_uniform(k, i)));
        assert_true(fabs(hypot(a, b) - r) < 1e-12);
    }
    /* rng_normal_pair gives both values of a pair, bit for bit (32 keys
     * x 32 pairs) */
    uint64_t key = 1;
    for (int n = 0; n < 32; n++, key = key * 3 + 1) {
        for (uint64_t e = 0; e < 64; e += 2) {
            double two[2], one[2] = {rng_normal(key, e), rng_normal(key, e + 1)};
            rng_normal_pair(key, e, two);
            assert_memory_equal(one, two, sizeof one);
        }
    }
    /* indexing a normal stream takes a pair's two values at once where an
     * even index is followed by the next (vec_index): the values are
     * rng_normal's, whatever the order and parity of the indices */
    static const double idx[][6] = {{0, 1, 2, 3, 4, 5}, {1, 2, 3, 4, 5, 6}, {4, 5, 3, 2, 7, 6},
                                    {6, 7, 7, 6, 8, 10}, {-2, -1, 0, 1, 1e6, 1e6 + 1},
                                    {2.5, 3.5, 8, 9.9, 9, 10}};
    Vec *nv = vec_stream(STREAM_NORMAL, 1234);
    for (size_t t = 0; t < sizeof idx / sizeof *idx; t++) {
        for (uint32_t len = 1; len <= 6; len++) {
            Vec *ix = vec_from_nums(idx[t], len);
            Vec *got = vec_index(nv, ix, false);
            assert_non_null(got);
            assert_int_equal(got->len, len);
            for (uint32_t i = 0; i < len; i++) {
                const double want = at(nv, idx[t][i]);
                assert_memory_equal(&vec_cnums(got)[i], &want, sizeof want);
            }
            vec_release(got);
            vec_release(ix);
        }
    }
    vec_release(nv);
}

/* ------------------------------------------------------------------ */
/* random.tree                                                         */
/* ------------------------------------------------------------------ */

static void test_random_tree(void **st)
{
    (void)st;
    Vec *u = stream("uniform", sym("seed"));
    check_values(u, 4, (double[]){0, 1, 2, 3},
                 (double[]){0.9008132191531274, 0.8027092774195856, 0.6535860757356463,
                            0.1431107518326226});
    vec_release(u);

    Vec *n = stream("normal", sym("n"));
    check_values(n, 6, (double[]){0, 1, 2, 3, 4, 5},
                 (double[]){0.44950035465883026, 0.1658641555028605, -0.6010647494051493,
                            0.5383422418123622, -0.21760860961452175, 0.33334785409843143});
    vec_release(n);

    Vec *b = stream("beta", sym("b"));
    check_values(b, 4, (double[]){0, 1, 2, 3},
                 (double[]){0.7105301474048341, 0.08848775400129169, 0.7931373204671822,
                            0.7858053407710198});
    vec_release(b);

    u = stream("uniform", nums(2, symbol_value("s", 1), 3.0));
    check_values(u, 1, (double[]){10}, (double[]){0.3991182428324899});
    vec_release(u);

    n = stream("normal", nums(3, symbol_value("x", 1), 1.0, 2.0));
    check_values(n, 1, (double[]){100}, (double[]){0.42618870442472856});
    vec_release(n);

    b = stream("beta", nums(3, 1.0, 2.0, 3.0));
    check_values(b, 1, (double[]){7}, (double[]){0.4540062244078132});
    vec_release(b);

    u = stream("uniform", vec_str("str", 3));
    check_values(u, 1, (double[]){0}, (double[]){0.688233166934117});
    vec_release(u);

    u = stream("uniform", sym("a"));
    check_values(u, 1, (double[]){-1}, (double[]){0.8059838674416808});
    vec_release(u);
}

/* ------------------------------------------------------------------ */
/* shuffle (§7.5 #82, random.tree)                                      */
/* ------------------------------------------------------------------ */

static Vec *range(int n)
{
    Vec *v = vec_new_num((uint32_t)n);
    for (int i = 0; i < n; i++) vec_nums(v)[i] = i;
    return v;
}

static void assert_perm(Vec *v, int n, const double *want)
{
    assert_non_null(v);
    assert_int_equal(v->kind, VEC_NUM);
    assert_int_equal(v->len, n);
    for (int i = 0; i < n; i++) assert_true(same(vec_nums(v)[i], want[i]));
    vec_release(v);
}

static void test_shuffle(void **st)
{
    (void)st;
    Vec *args[2] = {stream("uniform", sym("a")), range(6)};
    assert_perm(call("shuffle", 2, args), 6, (double[]){3, 0, 1, 5, 4, 2});
    vec_release(args[0]);
    vec_release(args[1]);

    args[0] = stream("uniform", sym("sh"));
    args[1] = range(8);
    assert_perm(call("shuffle", 2, args), 8, (double[]){3, 0, 1, 6, 4, 2, 7, 5});
    /* the argument is not modified */
    for (int i = 0; i < 8; i++) assert_true(vec_nums(args[1])[i] == i);
    vec_release(args[1]);

    /* empty xs → null; non-stream source → null (error) */
    args[1] = NULL;
    assert_null(call("shuffle", 2, args));
    vec_release(args[0]);
    args[0] = vec_num1(1);
    args[1] = range(3);
    assert_null(call("shuffle", 2, args));
    vec_release(args[0]);
    args[0] = NULL;
    assert_null(call("shuffle", 2, args));
    vec_release(args[1]);
}

static void test_shuffle_objects(void **st)
{
    (void)st;
    /* an object vector is permuted like the numbers 0..n-1 */
    const char *words[6] = {"a", "b", "c", "d", "e", "f"};
    Vec *obj = vec_new_obj(6);
    for (int i = 0; i < 6; i++) {
        vec_elems(obj)[i].kind = EL_STR;
        vec_elems(obj)[i].str = str_from(words[i]);
    }
    Vec *args[2] = {stream("uniform", sym("a")), obj};
    Vec *r = call("shuffle", 2, args);
    assert_non_null(r);
    assert_int_equal(r->kind, VEC_OBJ);
    const int want[6] = {3, 0, 1, 5, 4, 2};
    for (int i = 0; i < 6; i++) assert_string_equal(vec_elems(r)[i].str->bytes, words[want[i]]);
    vec_release(r);
    /* normal and beta sources use their own distributions */
    vec_release(args[0]);
    args[0] = stream("beta", sym("a"));
    r = call("shuffle", 2, args);
    assert_int_equal(vec_len(r), 6);
    vec_release(r);
    vec_release(args[0]);
    args[0] = stream("normal", sym("a")); /* may leave [0, n): clamped, never UB */
    r = call("shuffle", 2, args);
    assert_int_equal(vec_len(r), 6);
    vec_release(r);
    vec_release(args[0]);
    vec_release(obj);
}

static void test_single_and_lookup(void **st)
{
    (void)st;
    Vec *args[2] = {stream("uniform", NULL), vec_num1(42)};
    assert_perm(call("shuffle", 2, args), 1, (double[]){42});
    vec_release(args[0]);
    vec_release(args[1]);
    const Builtin *bi = bi_lookup("uniform", 7);
    assert_string_equal(bi->internal, "uniform");
    assert_int_equal(bi->min_args, 0);
    assert_int_equal(bi->max_args, 1);
    assert_string_equal(bi->params[0], "value");
    bi = bi_lookup("shuffle", 7);
    assert_int_equal(bi->min_args, 2);
    assert_string_equal(bi->params[1], "xs");
    assert_non_null(bi_lookup("normal", 6));
    assert_non_null(bi_lookup("beta", 4));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_seed_hash),
        cmocka_unit_test(test_squares),
        cmocka_unit_test(test_uniform_vectors),
        cmocka_unit_test(test_beta),
        cmocka_unit_test(test_normal),
        cmocka_unit_test(test_random_tree),
        cmocka_unit_test(test_shuffle),
        cmocka_unit_test(test_shuffle_objects),
        cmocka_unit_test(test_single_and_lookup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
