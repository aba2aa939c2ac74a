/* test_builtins.c: the vector, maths, quaternion, waveform, easing and noise
 * built-ins (LANGUAGE.md §5.3-§5.7, §5.9) and the registry. Expected values
 * are the reference's: §7.4/§7.5 vectors and the tests/lang builtins.tree
 * and random.tree dumps, compared bit for bit (or as %.9g text where the
 * spec gives only that). Builtins are called with ev = NULL. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "builtins.h"
#include "turns.h"
#include "node.h"
#include "value.h"

/* ------------------------------------------------------------------ */
/* Helpers                                                             */
/* ------------------------------------------------------------------ */

#define NUMS(...) nums_(sizeof((double[]){__VA_ARGS__}) / sizeof(double), (double[]){__VA_ARGS__})
#define MAXARGS 8

static Vec *nums_(size_t n, const double *x) { return vec_from_nums(x, (uint32_t)n); }
static Vec *num(double x) { return vec_num1(x); }
static Vec *sym(const char *name) { return vec_num1(symbol_value(name, strlen(name))); }
static Vec *str(const char *s) { return vec_str(s, strlen(s)); }

/* An object vector of strings (and :symbols written ":name"). */
static Vec *strs(int n, ...)
{
    va_list ap;
    va_start(ap, n);
    Vec *v = vec_new_obj((uint32_t)n);
    for (int i = 0; i < n; i++) {
        const char *s = va_arg(ap, const char *);
        Elem *e = &vec_elems(v)[i];
        if (s[0] == ':') {
            e->kind = EL_NUM;
            e->num = symbol_value(s + 1, strlen(s + 1));
        } else {
            e->kind = EL_STR;
            e->str = str_from(s);
        }
    }
    va_end(ap);
    return v;
}

static bool same(double a, double b)
{
    return memcmp(&a, &b, sizeof a) == 0 || (isnan(a) && isnan(b));
}

/* Call builtin [name] with [n] arguments, consuming the arguments. */
static Vec *callv(const char *name, int n, Vec **args)
{
    const Builtin *bi = bi_lookup(name, strlen(name));
    if (!bi) fail_msg("no builtin %s", name);
    assert_true(n >= bi->min_args);
    assert_true(bi->max_args == BI_VARIADIC || n <= bi->max_args);
    Vec *r = bi->fn(NULL, bi, n, args);
    for (int i = 0; i < n; i++) vec_release(args[i]);
    return r;
}

#define CALL(name, ...) callv(name, (int)(sizeof((Vec *[]){__VA_ARGS__}) / sizeof(Vec *)), (Vec *[]){__VA_ARGS__})
#define CALL0(name) callv(name, 0, (Vec *[]){NULL})

/* Assert [v] is numeric with exactly the doubles given (bit patterns,
 * NaN matching NaN), then release it. */
static void expect_(Vec *v, size_t n, const double *want, const char *what)
{
    if (!v) fail_msg("%s: null", what);
    if (v->kind != VEC_NUM || v->len != n) fail_msg("%s: kind %d len %u", what, v->kind, v->len);
    for (size_t i = 0; i < n; i++)
        if (!same(vec_nums(v)[i], want[i]))
            fail_msg("%s[%zu]: got %.17g want %.17g", what, i, vec_nums(v)[i], want[i]);
    vec_release(v);
}
#define EXPECT(v, ...) \
    expect_(v, sizeof((double[]){__VA_ARGS__}) / sizeof(double), (double[]){__VA_ARGS__}, #v)

/* Assert [v] prints as [text] with %.9g per element joined by ';'. */
static void expect_text(Vec *v, const char *text)
{
    char buf[256] = "";
    assert_non_null(v);
    assert_int_equal(v->kind, VEC_NUM);
    for (uint32_t i = 0; i < v->len; i++) {
        size_t at = strlen(buf);
        snprintf(buf + at, sizeof buf - at, i ? ";%.9g" : "%.9g", vec_nums(v)[i]);
    }
    assert_string_equal(buf, text);
    vec_release(v);
}

/* ------------------------------------------------------------------ */
/* Registry                                                            */
/* ------------------------------------------------------------------ */

static void test_lookup(void **st)
{
    (void)st;
    static const char *const mine[] = {
        "len", "sum", "product", "accumulate", "mean", "min", "max", "minindex", "maxindex",
        "sort", "count", "zip", "shuffle", "abs", "floor", "ceil", "fract", "round", "sqrt",
        "exp", "log", "log2", "log10", "sin", "cos", "tan", "asin", "acos", "polar", "angle",
        "length", "hypot", "normalize", "dot", "cross", "clamp", "map", "inverse",
        "point_towards", "quaternion", "qmul", "qbetween", "slerp", "sine", "bounce",
        "sawtooth", "triangle", "square", "sharkfin", "impulse", "linear", "quad", "cubic",
        "snap", "uniform", "normal", "beta", "noise", "octnoise",
    };
    for (size_t i = 0; i < sizeof mine / sizeof mine[0]; i++) {
        const Builtin *bi = bi_lookup(mine[i], strlen(mine[i]));
        if (!bi) fail_msg("missing %s", mine[i]);
        assert_string_equal(bi->name, mine[i]);
        assert_non_null(bi->fn);
        assert_false(bi->flags & BI_DYNAMIC);
    }
    assert_string_equal(bi_lookup("sin", 3)->internal, "sinv");
    assert_string_equal(bi_lookup("abs", 3)->internal, "absv");
    assert_string_equal(bi_lookup("zip", 3)->internal, "zipv");
    assert_string_equal(bi_lookup("map", 3)->internal, "mapv");
    assert_string_equal(bi_lookup("len", 3)->internal, "lenv");
    assert_string_equal(bi_lookup("sqrt", 4)->internal, "sqrtv");
    assert_string_equal(bi_lookup("round", 5)->params[1], "ys");
    assert_string_equal(bi_lookup("sum", 3)->params[1], "w");
    assert_int_equal(bi_lookup("hypot", 5)->max_args, BI_VARIADIC);
    assert_null(bi_lookup("pow", 3));
    assert_null(bi_lookup("sinx", 4)); /* length matters */
    assert_non_null(bi_lookup("sinx", 3));
    assert_null(bi_lookup("si", 2));
    assert_null(bi_lookup(NULL, 0));
    /* bi_error tolerates a missing evaluator */
    assert_null(bi_error(NULL, bi_lookup("sqrt", 4), "detail %d", 1));
}

/* ------------------------------------------------------------------ */
/* Turns and mathematics (§5.2, §5.4, §7.4 #40-46, #51, #58-60, #72)   */
/* ------------------------------------------------------------------ */

/* sin_t as LANGUAGE.md §5.2 states it, with libm's remquo. */
static double sin_t_remquo(double t)
{
    if (t < 0) return -sin_t_remquo(-t);
    int q;
    double r = remquo(t * 4.0, 1.0, &q) * HALF_PI;
    switch (q & 3) {
    case 0: return sin(r);
    case 1: return cos(r);
    case 2: return -sin(r);
    default: return -cos(r);
    }
}

static void test_turns(void **st)
{
    (void)st;
    assert_true(same(sin_t(0.25), 1.0));
    assert_true(same(sin_t(0.5), -0.0));
    assert_true(same(cos_t(0.25), -0.0));
    assert_true(same(cos_t(0.5), -1.0));
    assert_true(same(sin_t(-0.25), -1.0));
    assert_true(isnan(sin_t(NAN)) && isnan(sin_t(INFINITY)));
    /* the quadrant reduction matches remquo's bit for bit: ties to even,
     * signed zeros, near 2^50, huge arguments */
    const double probes[] = {0.0, -0.0, 0.125, 0.375, 0.625, 0.875, 1.0, 2.5 / 4, 3.5 / 4,
                             1e-300, 0x1p50 / 4 + 0.125, 0x1p52 / 4, 0x1p52 / 4 - 0.125,
                             0x1p53, 1e300, 123456.789};
    for (size_t i = 0; i < sizeof probes / sizeof probes[0]; i++) {
        for (int neg = 0; neg < 2; neg++) {
            double t = neg ? -probes[i] : probes[i], want = sin_t_remquo(t);
            if (!same(sin_t(t), want)) fail_msg("sin_t(%a) = %a, want %a", t, sin_t(t), want);
        }
    }
    for (int k = 0; k < 200000; k++) {
        double t = (double)k * 0.0123456789 - 1000.0, want = sin_t_remquo(t);
        if (!same(sin_t(t), want)) fail_msg("sin_t(%a) = %a, want %a", t, sin_t(t), want);
    }
    EXPECT(CALL("sin", num(0.25)), 1);
    EXPECT(CALL("cos", num(0.5)), -1);
    EXPECT(CALL("sin", num(0.5)), -0.0);
    EXPECT(CALL("cos", num(1.0 / 3)), -0.49999999999999956);
    EXPECT(CALL("sin", num(0.125)), 0.7071067811865475);
    expect_text(CALL("cos", num(1.0 / 3)), "-0.5");
    EXPECT(CALL("polar", num(0.25)), -0.0, 1);
    EXPECT(CALL("polar", NUMS(0, 0.5)), 1, 0, -1, -0.0);
    EXPECT(CALL("tan", num(0.125)), 0.9999999999999999);
    EXPECT(CALL("asin", num(1)), 0.25);
    EXPECT(CALL("acos", num(0)), 0.25);
    assert_null(CALL("sin", str("x")));
    assert_null(CALL("sin", NULL));
}

static void test_elementwise(void **st)
{
    (void)st;
    EXPECT(CALL("abs", num(-2.5)), 2.5);
    EXPECT(CALL("abs", NUMS(-1, -0.0, 3)), 1, 0, 3);
    EXPECT(CALL("floor", num(-0.5)), -1);
    EXPECT(CALL("floor", num(-0.0)), -0.0);
    EXPECT(CALL("ceil", num(1.2)), 2);
    EXPECT(CALL("fract", num(-0.25)), 0.75);
    EXPECT(CALL("sqrt", num(2)), 1.4142135623730951);
    EXPECT(CALL("sqrt", num(-1)), NAN);
    EXPECT(CALL("exp", num(1)), 2.718281828459045);
    EXPECT(CALL("log", num(10)), 2.302585092994046);
    EXPECT(CALL("log", num(0)), -INFINITY);
    EXPECT(CALL("log2", num(8)), 3);
    EXPECT(CALL("log10", num(1000)), 3);
    assert_null(CALL("sqrt", strs(1, "a")));
    /* §7.4 #72: two arguments is the caller's arity error; here: max 1 */
    assert_int_equal(bi_lookup("sqrt", 4)->max_args, 1);
}

static void test_round(void **st)
{
    (void)st;
    EXPECT(CALL("round", num(2.5)), 3);
    EXPECT(CALL("round", num(-2.5)), -3);
    EXPECT(CALL("round", num(1.2345), num(2)), 1.23);
    EXPECT(CALL("round", num(0.125), num(2)), 0.13);
    EXPECT(CALL("round", num(1.2345), num(2.9)), 1.23); /* floor of ys */
    EXPECT(CALL("round", num(1234), num(-2)), NAN);     /* integer-power quirk */
    EXPECT(CALL("round", num(1.5), num(64)), NAN);      /* 10**64 wraps to 0 */
    EXPECT(CALL("round", num(1.5), num(NAN)), NAN);
    assert_null(CALL("round", num(1.5), NULL));
    assert_null(CALL("round", num(1.5), NUMS(1, 2)));
    assert_null(CALL("round", str("a"), num(1)));
}

static void test_angle_length_hypot(void **st)
{
    (void)st;
    EXPECT(CALL("angle", NUMS(0, 1)), 0.25);
    EXPECT(CALL("angle", num(1), num(1)), 0.125);
    EXPECT(CALL("angle", NUMS(1, 0, 0, 1, 5)), 0, 0.25); /* odd tail ignored */
    assert_null(CALL("angle", num(1)));
    assert_null(CALL("angle", num(1), NULL));
    EXPECT(CALL("length", NUMS(3, 4, 6, 8)), 5, 10);
    EXPECT(CALL("length", NUMS(3, 6), num(4)), 5, sqrt(52));
    EXPECT(CALL("hypot", NUMS(3, 4)), 5);
    EXPECT(CALL("hypot", num(3), num(4)), 5);
    EXPECT(CALL("hypot", NUMS(3, 5), num(4), num(0)), 5, sqrt(41));
    assert_null(CALL0("hypot"));
    assert_null(CALL("hypot", num(3), NULL));
    assert_null(CALL("hypot", NULL));
}

static void test_vector_maths(void **st)
{
    (void)st;
    EXPECT(CALL("normalize", NUMS(3, 4)), 0.6, 0.8);
    assert_null(CALL("normalize", NUMS(0, 0)));
    EXPECT(CALL("dot", NUMS(1, 2, 3), NUMS(4, 5, 6)), 32);
    EXPECT(CALL("dot", NUMS(1, 2, 3), num(2)), 12);
    assert_null(CALL("dot", NUMS(1, 2, 3), NULL));
    EXPECT(CALL("cross", NUMS(1, 0, 0), NUMS(0, 1, 0)), 0, 0, 1);
    assert_null(CALL("cross", NUMS(1, 0), NUMS(0, 1, 0)));
    EXPECT(CALL("clamp", NUMS(-1, 5), num(0), num(3)), 0, 3);
    EXPECT(CALL("clamp", num(NAN), num(0), num(1)), 0);
    EXPECT(CALL("clamp", num(0.5), num(NAN), num(1)), NAN);
    assert_null(CALL("clamp", num(0.5), NULL, num(1)));
    EXPECT(CALL("map", num(0.25), num(10), num(20)), 12.5);
    EXPECT(CALL("map", NUMS(0, 1), num(10), NUMS(20, 30)), 10, 30);
}

/* Operands of three different lengths wrap around each on its own (the
 * longest decides): values worked by hand, element by element. */
static void test_broadcast_lengths(void **st)
{
    (void)st;
    /* clamp(1..5, 2;4.5, 9;3;9): lo 2,4.5,2,4.5,2 and hi 9,3,9,9,3 */
    EXPECT(CALL("clamp", NUMS(1, 2, 3, 4, 5), NUMS(2, 4.5), NUMS(9, 3, 9)), 2, 3, 3, 4.5, 3);
    /* map(x, a, b) = (1-x) a + x b over 4: x .25,.5,.75,.25; a 0,10,0,10 */
    EXPECT(CALL("map", NUMS(0.25, 0.5, 0.75), NUMS(0, 10), NUMS(100, 200, 300, 400)), 25, 105, 225, 107.5);
    /* dot(1..5, 10;20) = 10 + 40 + 30 + 80 + 50 */
    EXPECT(CALL("dot", NUMS(1, 2, 3, 4, 5), NUMS(10, 20)), 210);
    /* hypot(3;0;5, 4;6) = hypot(3,4), hypot(0,6), hypot(5,4) */
    EXPECT(CALL("hypot", NUMS(3, 0, 5), NUMS(4, 6)), 5, 6, sqrt(41));
    /* angle(x, y) and length(x, y) of 1;0;-1 against 0;1 */
    EXPECT(CALL("angle", NUMS(1, 0, -1), NUMS(0, 1)), 0, 0.25, 0.5);
    EXPECT(CALL("length", NUMS(3, 0, 5), NUMS(4, 2)), 5, 2, sqrt(41));
    /* sum, product and mean in lanes of 2 and 3 */
    EXPECT(CALL("sum", NUMS(1, 2, 3, 4, 5), num(2)), 9, 6);
    EXPECT(CALL("product", NUMS(1, 2, 3, 4, 5), num(3)), 4, 10, 3);
    EXPECT(CALL("mean", NUMS(1, 2, 3, 4, 5), num(2)), 3, 3);
    /* the fused a + b*c (LANGUAGE.md §4.17): each operand wraps on its own */
    Vec *a = NUMS(1, 2, 3, 4, 5), *b = NUMS(10, 20), *c = NUMS(0.5, 1.5, 2.5);
    Vec *r = vec_add_mul(a, b, c);
    static const double want[5] = {6, 32, 28, 14, 20};   /* 4 + 20*0.5, 5 + 10*1.5 */
    assert_int_equal(r->len, 5);
    for (int i = 0; i < 5; i++) assert_true(vec_nums(r)[i] == want[i]);
    vec_release(r);
    vec_release(a);
    vec_release(b);
    vec_release(c);
    /* and the plain operators: (1..5) - (10;20) */
    a = NUMS(1, 2, 3, 4, 5);
    b = NUMS(10, 20, 30);
    r = vec_arith(OP_SUB, a, b);
    static const double diff[5] = {-9, -18, -27, -6, -15};
    for (int i = 0; i < 5; i++) assert_true(vec_nums(r)[i] == diff[i]);
    vec_release(r);
    vec_release(a);
    vec_release(b);
}

static void test_inverse(void **st)
{
    (void)st;
    EXPECT(CALL("inverse", NUMS(2, 0, 0, 0, 4, 0, 0, 0, 8)), 0.5, 0, 0, 0, 0.25, 0, 0, 0, 0.125);
    Vec *t = CALL("inverse", NUMS(1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 2, 3, 4, 1));
    static const double ti[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -2, -3, -4, 1};
    for (int i = 0; i < 16; i++) assert_true(vec_nums(t)[i] == ti[i]);
    vec_release(t);
    assert_null(CALL("inverse", NUMS(1, 2, 3)));
    Vec *m = CALL("inverse", NUMS(0, 0, 0, 0, 0, 0, 0, 0, 0));
    assert_true(isnan(vec_nums(m)[0]) || isinf(vec_nums(m)[0]));
    vec_release(m);
}

static void test_point_towards(void **st)
{
    (void)st;
    /* looking down -z with y up is the identity rotation */
    Vec *r = CALL("point_towards", NUMS(0, 0, -1), NUMS(0, 1, 0));
    assert_non_null(r);
    assert_int_equal(r->len, 16);
    static const double id[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    for (int i = 0; i < 16; i++) assert_true(vec_nums(r)[i] == id[i]);
    vec_release(r);
    /* columns x, y, z of the result: z = -normalize(direction) */
    r = CALL("point_towards", NUMS(1, 0, 0), NUMS(0, 0, 1));
    const double *m = vec_nums(r);
    assert_true(m[8] == -1 && m[9] == 0 && m[10] == 0);
    assert_true(m[4] == 0 && m[5] == 0 && m[6] == 1);
    assert_true(m[15] == 1);
    vec_release(r);
    assert_null(CALL("point_towards", NUMS(0, 0, 0), NUMS(0, 1, 0)));
    assert_null(CALL("point_towards", NUMS(0, 1, 0), NUMS(0, 1, 0))); /* up ∥ dir */
    assert_null(CALL("point_towards", NUMS(0, 0, -1, 0), NUMS(0, 1, 0)));
    assert_null(CALL("point_towards", NUMS(0, 0, -1), NULL));
    /* a 1-element direction broadcasts against the origin 0;0;0 */
    r = CALL("point_towards", num(1), NUMS(0, 1, 0));
    assert_non_null(r);
    vec_release(r);
}

/* ------------------------------------------------------------------ */
/* Quaternions (§5.5, §7.4 #67)                                        */
/* ------------------------------------------------------------------ */

static void test_quaternions(void **st)
{
    (void)st;
    EXPECT(CALL("quaternion", NUMS(0, 0, 1), num(0.25)), 0.7071067811865475, 0, 0,
           0.7071067811865475);
    Vec *q = CALL("quaternion", NUMS(0, 0, 1), num(0.25));
    EXPECT(CALL("qmul", q, NUMS(1, 0, 0)), 0, 1, 0);
    assert_null(CALL("quaternion", NUMS(0, 1), num(0.25)));
    assert_null(CALL("quaternion", NUMS(0, 0, 1), NUMS(1, 2)));
    /* Hamilton product: i*j = k */
    EXPECT(CALL("qmul", NUMS(0, 1, 0, 0), NUMS(0, 0, 1, 0)), 0, 0, 0, 1);
    assert_null(CALL("qmul", NUMS(1, 0, 0), NUMS(1, 0, 0)));
    assert_null(CALL("qmul", NUMS(1, 0, 0, 0), NUMS(1, 0)));
    /* qbetween of x and y: a quarter turn about z */
    Vec *b = CALL("qbetween", NUMS(1, 0, 0), NUMS(0, 1, 0));
    expect_text(vec_retain(b), "0.707106781;0;0;0.707106781");
    EXPECT(CALL("qmul", b, NUMS(1, 0, 0)), 2.2204460492503131e-16, 1, 0);
    /* opposite vectors: perpendicular axis, w = 0 */
    EXPECT(CALL("qbetween", NUMS(1, 0, 0), NUMS(-1, 0, 0)), 0, -0.0, 1, 0);
    EXPECT(CALL("qbetween", NUMS(0, 0, 1), NUMS(0, 0, -1)), 0, 0, -1, 0);
    /* slerp: endpoints and the midpoint of identity → quarter turn */
    Vec *id = NUMS(1, 0, 0, 0), *qz = CALL("quaternion", NUMS(0, 0, 1), num(0.25));
    EXPECT(CALL("slerp", num(0), vec_retain(id), vec_retain(qz)), 1, 0, 0, 0);
    expect_text(CALL("slerp", num(0.5), vec_retain(id), vec_retain(qz)),
                "0.923879533;0;0;0.382683432");
    expect_text(CALL("slerp", num(1), vec_retain(id), vec_retain(qz)),
                "0.707106781;0;0;0.707106781");
    EXPECT(CALL("slerp", num(0.5), vec_retain(id), vec_retain(id)), 1, 0, 0, 0);
    assert_null(CALL("slerp", NUMS(0, 1), vec_retain(id), vec_retain(qz)));
    vec_release(id);
    vec_release(qz);
}

/* ------------------------------------------------------------------ */
/* Waveforms and easing (§5.6, §5.7, §7.4 #61-63)                      */
/* ------------------------------------------------------------------ */

static void test_waves(void **st)
{
    (void)st;
    EXPECT(CALL("impulse", num(0.1)), 0.784);
    EXPECT(CALL("impulse", num(0.625), num(0.25)), 0.125);
    expect_text(CALL("impulse", NUMS(0.1, 0.1), NUMS(0.25, 0.5)), "0.784;0.488");
    assert_null(CALL("impulse", num(0.1), NULL));
    EXPECT(CALL("sharkfin", num(0.25)), 0.7071067811865475);
    EXPECT(CALL("sharkfin", num(0.75)), 1 - sin(3.141592653589793 * 0.25));
    EXPECT(CALL("triangle", num(0.25)), 0.5);
    EXPECT(CALL("square", num(0.5)), 1);
    EXPECT(CALL("square", NUMS(0.25, -0.25, NAN)), 0, 1, 1);
    EXPECT(CALL("sawtooth", num(1.25)), 0.25);
    EXPECT(CALL("bounce", num(0.5)), 1);
    EXPECT(CALL("sine", num(0.25)), 0.5);
    EXPECT(CALL("sine", num(0)), 0);
    assert_null(CALL("sine", str("x")));
}

static void test_easing(void **st)
{
    (void)st;
    EXPECT(CALL("quad", num(0.25)), 0.125);
    EXPECT(CALL("cubic", num(0.75)), 0.9375);
    EXPECT(CALL("snap", num(0.125)), 0.25);
    EXPECT(CALL("linear", NUMS(2, -1, 0.5)), 1, 0, 0.5);
    EXPECT(CALL("quad", num(0.9)), 0.98);
    EXPECT(CALL("cubic", num(0.1)), 0.004000000000000001);
    EXPECT(CALL("quad", NUMS(-1, 2)), 0, 1);
    EXPECT(CALL("snap", NUMS(-1, 2, 0.875)), 0, 1, 0.75);
    EXPECT(CALL("linear", num(NAN)), NAN);
}

/* ------------------------------------------------------------------ */
/* Vector utilities (§5.3, §7.4 #47-57, #70)                           */
/* ------------------------------------------------------------------ */

static void test_len_sum(void **st)
{
    (void)st;
    EXPECT(CALL("len", str("abc")), 1);
    EXPECT(CALL("len", NULL), 0);
    EXPECT(CALL("len", NUMS(1, 2, 3)), 3);
    Vec *mixed = vec_new_obj(3); /* 1;"a";!n */
    Str *kind = str_from("n");
    vec_elems(mixed)[1].kind = EL_STR;
    vec_elems(mixed)[1].str = str_from("a");
    vec_elems(mixed)[2].kind = EL_NODE;
    vec_elems(mixed)[2].node = node_new(kind);
    str_release(kind);
    vec_elems(mixed)[0].num = 1;
    EXPECT(CALL("len", vec_retain(mixed)), 3);
    /* count and sort with a node: nodes equal structurally, never ordered */
    EXPECT(CALL("count", vec_retain(mixed), vec_retain(mixed)), 1, 1, 1);
    assert_null(CALL("sort", vec_retain(mixed)));
    assert_null(CALL("min", vec_retain(mixed)));
    Vec *one = vec_new_obj(1);
    vec_elems(one)[0] = vec_elems(mixed)[2];
    node_retain(vec_elems(one)[0].node);
    Vec *sorted = CALL("sort", vec_retain(one));
    assert_true(sorted && sorted->kind == VEC_OBJ && sorted->len == 1);
    vec_release(sorted);
    sorted = CALL("max", one);
    assert_true(sorted && vec_elems(sorted)[0].kind == EL_NODE);
    vec_release(sorted);
    vec_release(mixed);
    EXPECT(CALL("sum", NUMS(1, 2, 3, 4), num(2)), 4, 6);
    EXPECT(CALL("sum", NUMS(1, 2, 3, 4, 5), num(2)), 9, 6);
    assert_null(CALL("sum", NUMS(1, 2, 3), num(0.5)));
    EXPECT(CALL("sum", NULL), 0);
    EXPECT(CALL("sum", NUMS(1, 2), num(2.9)), 1, 2);
    EXPECT(CALL("sum", NUMS(0.1, 0.2, 0.3)), 0.6000000000000001);
    assert_null(CALL("sum", strs(1, "a")));
    assert_null(CALL("sum", NUMS(1, 2), NULL));
    assert_null(CALL("sum", NUMS(1, 2), num(NAN)));
    assert_null(CALL("sum", NUMS(1, 2), num(-3e9)));
    EXPECT(CALL("product", NUMS(1, 2, 3, 4), num(2)), 3, 8);
    EXPECT(CALL("product", NULL), 1);
    EXPECT(CALL("mean", NUMS(1, 2, 3)), 2);
    EXPECT(CALL("mean", NULL), 0);
    EXPECT(CALL("mean", NUMS(1, 2, 3), num(5)), 1, 2, 3, 0, 0);
    EXPECT(CALL("mean", NUMS(1, 2, 3, 4, 5), num(2)), 3, 3);
    EXPECT(CALL("accumulate", NUMS(1, 2, 3)), 1, 3, 6);
    EXPECT(CALL("accumulate", NUMS(1, 2, 3, 4), num(2)), 1, 2, 4, 6);
    assert_null(CALL("accumulate", NULL));
    assert_null(CALL("accumulate", NUMS(1, 2), num(0)));
}

static void test_min_max(void **st)
{
    (void)st;
    EXPECT(CALL("max", num(3), NUMS(1, 5), num(2)), 3);
    EXPECT(CALL("max", NUMS(1, 5, 3)), 5);
    assert_null(CALL("min", num(1), str("a")));
    EXPECT(CALL("min", NUMS(NAN, 1)), NAN);
    EXPECT(CALL("min", NUMS(1, NAN)), 1);
    assert_null(CALL("min", NULL));
    EXPECT(CALL("minindex", NUMS(3, 1, 2)), 1);
    EXPECT(CALL("maxindex", num(1), num(5), num(3)), 1);
    EXPECT(CALL("maxindex", NUMS(1, 5, 5)), 1);
    assert_null(CALL("maxindex", NULL));
    EXPECT(CALL("minindex", num(1), NUMS(1, 0), num(0.5)), 2);
    Vec *r = CALL("max", strs(3, "b", "c", "a"));
    assert_int_equal(r->kind, VEC_OBJ);
    assert_string_equal(vec_elems(r)[0].str->bytes, "c");
    vec_release(r);
    EXPECT(CALL("minindex", strs(3, "b", "c", "a")), 2);
    assert_null(CALL("max", strs(2, "b", ":a")));
}

static void test_min_null_argument(void **st)
{
    (void)st;
    /* null is less than anything (§3.7), so min(1, null) is null */
    assert_null(CALL("min", num(1), NULL));
    EXPECT(CALL("max", num(1), NULL), 1);
    EXPECT(CALL("minindex", num(1), NULL), 1);
}

static void test_sort_count_zip(void **st)
{
    (void)st;
    EXPECT(CALL("sort", NUMS(3, 1, 2)), 1, 2, 3);
    EXPECT(CALL("sort", NUMS(0.0, -0.0, -1)), -1, 0.0, -0.0); /* stable */
    Vec *r = CALL("sort", strs(3, "b", "a", "c"));
    assert_int_equal(r->kind, VEC_OBJ);
    assert_string_equal(vec_elems(r)[0].str->bytes, "a");
    assert_string_equal(vec_elems(r)[1].str->bytes, "b");
    assert_string_equal(vec_elems(r)[2].str->bytes, "c");
    vec_release(r);
    assert_null(CALL("sort", strs(2, "a", ":b")));
    assert_null(CALL("sort", NULL));
    double big[100];
    for (int i = 0; i < 100; i++) big[i] = (i * 37) % 100;
    r = CALL("sort", vec_from_nums(big, 100));
    for (int i = 0; i < 100; i++) assert_true(vec_nums(r)[i] == i);
    vec_release(r);

    EXPECT(CALL("count", NUMS(1, 2), NUMS(1, 1, 2)), 2, 1);
    EXPECT(CALL("count", strs(2, "a", ":a"), strs(3, "a", "a", ":a")), 2, 1);
    EXPECT(CALL("count", num(1), NULL), 0);
    assert_null(CALL("count", NULL, num(1)));

    EXPECT(CALL("zip", NUMS(1, 2), NUMS(10, 20, 30)), 1, 10, 2, 20, 1, 30);
    EXPECT(CALL("zip", NUMS(1, 2, 3, 4), num(0)), 1, 0, 2, 0, 3, 0, 4, 0);
    r = CALL("zip", NUMS(1, 2, 3), strs(2, "a", "b")); /* 1;'a';2;'b';3;'a' */
    assert_int_equal(r->kind, VEC_OBJ);
    assert_int_equal(r->len, 6);
    for (int i = 0; i < 6; i += 2) {
        assert_int_equal(vec_elems(r)[i].kind, EL_NUM);
        assert_true(vec_elems(r)[i].num == i / 2 + 1);
        assert_int_equal(vec_elems(r)[i + 1].kind, EL_STR);
        assert_string_equal(vec_elems(r)[i + 1].str->bytes, i == 2 ? "b" : "a");
    }
    vec_release(r);
    EXPECT(CALL("zip", NULL, NUMS(1, 2), NULL), 1, 2);
    assert_null(CALL0("zip"));
    assert_null(CALL("zip", NULL, NULL));
}

/* ------------------------------------------------------------------ */
/* Noise (§5.9, §7.5 #84-87, random.tree)                              */
/* ------------------------------------------------------------------ */

static void test_noise_vectors(void **st)
{
    (void)st;
    EXPECT(CALL("noise", sym("s"), num(0.5)), 0.6390421355507776);
    EXPECT(CALL("noise", sym("s"), num(0.5), num(0.25)), 0.5816501773837107);
    EXPECT(CALL("noise", NULL, num(1.3)), 0.4902465961370626);
    expect_text(CALL("noise", sym("s"), num(0.3), num(0.6), num(0.9)), "-0.427225357");
    expect_text(CALL("noise", sym("s"), num(0.3), num(0.6), num(0.9), num(1.2)), "-0.413527839");
    expect_text(CALL("noise", sym("s"), NUMS(1, 2), num(3)), "-0.232062298;-0.0979359928");
    expect_text(CALL("octnoise", sym("s"), num(3), num(0.5), num(0.3), num(0.7)), "0.0101296387");
    assert_null(CALL("octnoise", sym("s"), num(0), num(0.5), num(1)));
}

static void test_noise_tree(void **st)
{
    (void)st;
    EXPECT(CALL("noise", sym("n"), num(0.5)), -0.6962697082581172);
    EXPECT(CALL("noise", sym("n"), num(0.5), num(1.5)), -0.1222555981585328);
    EXPECT(CALL("noise", sym("n"), num(0.1), num(0.2), num(0.3)), 0.10386073574110029);
    EXPECT(CALL("noise", sym("n"), NUMS(0.1, 0.2, 0.3)), -0.16773580189594284,
           -0.32532952606499393, -0.4692263756132082);
    EXPECT(CALL("octnoise", sym("n"), num(3), num(0.5), num(0.25), num(0.75)),
           -0.051189355985982385);
}

static void test_noise_shapes(void **st)
{
    (void)st;
    assert_null(CALL("noise", sym("s")));
    assert_null(CALL("noise", sym("s"), num(1), num(2), num(3), num(4), num(5)));
    assert_null(CALL("noise", sym("s"), num(1), NULL));
    assert_null(CALL("noise", sym("s"), str("x")));
    /* outer product, x outermost */
    Vec *grid = CALL("noise", sym("s"), NUMS(0.1, 0.2), NUMS(0.3, 0.4, 0.5));
    assert_int_equal(vec_len(grid), 6);
    EXPECT(CALL("noise", sym("s"), num(0.2), num(0.4)), vec_nums(grid)[4]);
    vec_release(grid);
    grid = CALL("noise", sym("s"), NUMS(1, 2), NUMS(3, 4), NUMS(5, 6), NUMS(7, 8, 9));
    assert_int_equal(vec_len(grid), 24);
    EXPECT(CALL("noise", sym("s"), num(2), num(3), num(6), num(8)), vec_nums(grid)[16]);
    vec_release(grid);
    /* 1 coordinate is (x, 0); seeds are floored */
    Vec *a = CALL("noise", sym("s"), num(0.7));
    EXPECT(CALL("noise", sym("s"), num(0.7), num(0)), vec_nums(a)[0]);
    EXPECT(CALL("noise", NUMS(symbol_value("s", 1)), num(0.7)), vec_nums(a)[0]);
    vec_release(a);
    a = CALL("noise", num(2), num(0.7));
    EXPECT(CALL("noise", num(2.9), num(0.7)), vec_nums(a)[0]);
    vec_release(a);
    /* octnoise with one octave is noise; octaves truncate; n <= 0 null */
    a = CALL("noise", sym("s"), num(0.3), num(0.7));
    EXPECT(CALL("octnoise", sym("s"), num(1), num(0.5), num(0.3), num(0.7)), vec_nums(a)[0]);
    EXPECT(CALL("octnoise", sym("s"), num(1.9), num(9), num(0.3), num(0.7)), vec_nums(a)[0]);
    vec_release(a);
    a = CALL("octnoise", sym("s"), num(3), num(0.5), num(0.3), num(0.7));
    EXPECT(CALL("octnoise", sym("s"), num(3.7), num(0.5), num(0.3), num(0.7)), vec_nums(a)[0]);
    vec_release(a);
    assert_null(CALL("octnoise", sym("s"), num(-2), num(0.5), num(1)));
    assert_null(CALL("octnoise", sym("s"), num(NAN), num(0.5), num(1)));
    assert_null(CALL("octnoise", sym("s"), NUMS(3, 4), num(0.5), num(1)));
    assert_null(CALL("octnoise", sym("s"), num(3), NULL, num(1)));
    assert_null(CALL("octnoise", sym("s"), num(3), num(0.5), str("x")));
    assert_null(CALL("octnoise", sym("s"), num(3), num(0.5)));
    assert_null(CALL("octnoise", sym("s"), num(1e9), num(0.5), num(1))); /* error */
    /* range and non-finite inputs */
    for (int i = 0; i < 200; i++) {
        double x = i * 0.37 - 30;
        Vec *v = CALL("noise", sym("r"), num(x), num(x * 0.7), num(-x), num(x * 1.3));
        assert_true(fabs(vec_nums(v)[0]) < 1);
        vec_release(v);
    }
    Vec *v = CALL("noise", sym("s"), NUMS(NAN, INFINITY, -1e300), num(1), num(2));
    for (int i = 0; i < 3; i++) assert_false(isinf(vec_nums(v)[i]));
    vec_release(v);
}

/* concat() refuses a result over 2^28 bytes (null, not an abort in
 * str_new): two references to one string of 2^27 + 1 bytes. */
static void test_concat_too_long(void **state)
{
    (void)state;
    size_t half = ((size_t)1 << 27) + 1;
    char *text = malloc(half);
    assert_non_null(text);
    memset(text, 'x', half);
    Str *s = str_new(text, half);
    free(text);
    Vec *v = vec_new_obj(2);
    for (int i = 0; i < 2; i++) {
        vec_elems(v)[i].kind = EL_STR;
        vec_elems(v)[i].str = str_retain(s);
    }
    str_release(s);
    assert_null(CALL("concat", v));
    Vec *r = CALL("concat", strs(2, "ab", "c"));
    assert_non_null(r);
    assert_int_equal(r->len, 1);
    assert_string_equal(vec_elems(r)[0].str->bytes, "abc");
    vec_release(r);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_lookup),
        cmocka_unit_test(test_turns),
        cmocka_unit_test(test_elementwise),
        cmocka_unit_test(test_round),
        cmocka_unit_test(test_angle_length_hypot),
        cmocka_unit_test(test_vector_maths),
        cmocka_unit_test(test_broadcast_lengths),
        cmocka_unit_test(test_inverse),
        cmocka_unit_test(test_point_towards),
        cmocka_unit_test(test_quaternions),
        cmocka_unit_test(test_waves),
        cmocka_unit_test(test_easing),
        cmocka_unit_test(test_len_sum),
        cmocka_unit_test(test_min_max),
        cmocka_unit_test(test_min_null_argument),
        cmocka_unit_test(test_sort_count_zip),
        cmocka_unit_test(test_noise_vectors),
        cmocka_unit_test(test_noise_tree),
        cmocka_unit_test(test_noise_shapes),
        cmocka_unit_test(test_concat_too_long),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
