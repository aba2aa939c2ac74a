/* test_simplify.c: the simplifier's rules one by one (LANGUAGE.md §4.17
 * S1-S18, F1, F2).
 *
 * Each case is an expression over dynamic operands x, y, z (state lookups,
 * which the simplifier cannot know) and literals. It is run for one frame in
 * Flitter's default mode and with --nosimplify; the test checks the
 * simplified expression as printed by fl_dump_program (so a rule that does
 * not change the value still shows) and the value of both runs bit for bit
 * (doubles compared by their bit patterns, so -0 and 0 differ). The expected
 * values were worked out by hand with IEEE double arithmetic, one rounding
 * per operation, in the order each form evaluates.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>
#include <unistd.h>

#include "runtime.h"
#include "node.h"
#include "state.h"
#include "value.h"

#define MAXN 8

typedef struct Case {
    const char *expr;      /* expression for attribute v */
    double x[MAXN], y[MAXN], z[MAXN];
    int nx, ny, nz;        /* operand lengths (0: not set) */
    const char *simplified; /* the simplified expression as dumped */
    double want_s[MAXN];   /* value in default mode */
    int ns;                /* its length (-1: null) */
    double want_n[MAXN];   /* value with --nosimplify */
    int nn;
} Case;

static void set_operand(fl_runtime *rt, const char *name, const double *v, int n)
{
    if (!n) return;
    Vec *k = vec_num1(symbol_value(name, strlen(name)));
    Vec *val = vec_from_nums(v, (uint32_t)n);
    state_set(rt_state(rt), k, val);
    vec_release(k);
    vec_release(val);
}

/* Run [c] in one mode; returns the program dump (caller frees) and checks
 * the value against [want]/[n]. */
static char *run_case(const Case *c, bool simplify, const double *want, int n)
{
    char src[512];
    snprintf(src, sizeof src, "let x=$(:x) y=$(:y) z=$(:z)\n!t v=%s\n", c->expr);
    fl_options o = fl_default_options();
    RtStreams streams = {NULL, NULL};
    rt_log_to_files(&o, &streams);
    o.no_simplify = !simplify;
    fl_runtime *rt = fl_new(&o);
    Buf err = BUF_INIT;
    assert_int_equal(rt_load_text(rt, "rule.fl", src, strlen(src), &err), 0);
    buf_free(&err);
    set_operand(rt, "x", c->x, c->nx);
    set_operand(rt, "y", c->y, c->ny);
    set_operand(rt, "z", c->z, c->nz);
    Buf dump = BUF_INIT;
    rt_dump_program(rt, &dump);
    fl_step(rt);
    const Node *root = rt_root(rt);
    assert_int_equal(root->nchildren, 1);
    const Vec *v = node_attr(root->children[0], "v");
    if (n < 0) {
        if (v) fail_msg("%s (%s): expected null", c->expr, simplify ? "simplified" : "nosimplify");
    } else {
        if (!vec_is_num(v) || (int)v->len != n)
            fail_msg("%s (%s): expected %d numbers, got %d", c->expr,
                     simplify ? "simplified" : "nosimplify", n, (int)vec_len(v));
        for (int i = 0; i < n; i++)
            if (memcmp(&vec_cnums(v)[i], &want[i], sizeof(double)) != 0)
                fail_msg("%s (%s): element %d = %.17g, expected %.17g", c->expr,
                         simplify ? "simplified" : "nosimplify", i, vec_cnums(v)[i], want[i]);
    }
    fl_free(rt);
    char *text = strdup(buf_cstr(&dump));
    buf_free(&dump);
    return text;
}

static void check(const Case *c)
{
    char *dump = run_case(c, true, c->want_s, c->ns);
    char want[256];
    snprintf(want, sizeof want, "(!t) v=%s\n", c->simplified);
    const char *seen = strstr(dump, "!t");
    if (!strstr(dump, want) && !(seen && strcmp(c->simplified, "LITERAL") == 0))
        fail_msg("%s simplified to:\n%s\nexpected a line ending: %s", c->expr, dump, want);
    free(dump);
    free(run_case(c, false, c->want_n, c->nn));
}

#define X1(a) .x = {a}, .nx = 1
#define S(...) .want_s = {__VA_ARGS__}
#define N(...) .want_n = {__VA_ARGS__}

/* S1: all-literal operations fold, unfused even for a + b*c. */
static void test_s1_fold(void **unused)
{
    (void)unused;
    Case c = {.expr = "(1;2;3;4;5;6)+(1;2)*(1;2;3)", .simplified = "LITERAL",
              S(2, 6, 6, 5, 9, 9), .ns = 6, N(2, 6, 6, 6, 7, 12), .nn = 6};
    char *dump = run_case(&c, true, c.want_s, c.ns);
    assert_non_null(strstr(dump, "(!t v=2;6;6;5;9;9)"));
    free(dump);
    free(run_case(&c, false, c.want_n, c.nn));
    Case d = {.expr = "0.1+0.2", S(0.30000000000000004), .ns = 1, N(0.30000000000000004), .nn = 1};
    dump = run_case(&d, true, d.want_s, d.ns);
    assert_non_null(strstr(dump, "(!t v=0.30000000000000004)"));
    free(dump);
}

/* S2: adding literal 0 on either side leaves +x. */
static void test_s2_add_zero(void **unused)
{
    (void)unused;
    check(&(Case){.expr = "0+x", X1(2.5), .simplified = "(+x)", S(2.5), .ns = 1, N(2.5), .nn = 1});
    check(&(Case){.expr = "x+0", X1(-0.0), .simplified = "(+x)", S(-0.0), .ns = 1, N(0.0), .nn = 1});
}

/* S3: x - 0 -> +x; 0 - x -> -x. */
static void test_s3_sub_zero(void **unused)
{
    (void)unused;
    check(&(Case){.expr = "x-0", X1(-0.0), .simplified = "(+x)", S(-0.0), .ns = 1, N(-0.0), .nn = 1});
    check(&(Case){.expr = "0-x", X1(0.0), .simplified = "(-x)", S(-0.0), .ns = 1, N(0.0), .nn = 1});
}

/* S4: x - L -> x + (-L). */
static void test_s4_sub_literal(void **unused)
{
    (void)unused;
    check(&(Case){.expr = "x-0.1", X1(0.3), .simplified = "(x + -0.1)", S(0.19999999999999998), .ns = 1,
                  N(0.19999999999999998), .nn = 1});
}

/* S5: multiplying, dividing or raising by 1 leaves +x; by -1 gives -x. */
static void test_s5_unit(void **unused)
{
    (void)unused;
    check(&(Case){.expr = "1*x", X1(7), .simplified = "(+x)", S(7), .ns = 1, N(7), .nn = 1});
    check(&(Case){.expr = "x*1", X1(7), .simplified = "(+x)", S(7), .ns = 1, N(7), .nn = 1});
    check(&(Case){.expr = "x/1", X1(7), .simplified = "(+x)", S(7), .ns = 1, N(7), .nn = 1});
    check(&(Case){.expr = "x**1", X1(7), .simplified = "(+x)", S(7), .ns = 1, N(7), .nn = 1});
    check(&(Case){.expr = "-1*x", X1(7), .simplified = "(-x)", S(-7), .ns = 1, N(-7), .nn = 1});
    check(&(Case){.expr = "x*-1", X1(7), .simplified = "(-x)", S(-7), .ns = 1, N(-7), .nn = 1});
}

/* S6: x / L -> (1/L) * x, which rounds differently. */
static void test_s6_reciprocal(void **unused)
{
    (void)unused;
    check(&(Case){.expr = "x/10", X1(0.1), .simplified = "(0.1 * x)", S(0.010000000000000002), .ns = 1,
                  N(0.01), .nn = 1});
    check(&(Case){.expr = "x/10", X1(3), .simplified = "(0.1 * x)", S(0.30000000000000004), .ns = 1,
                  N(0.3), .nn = 1});
}

/* S7: L * (a + b) with a literal side distributes. */
static void test_s7_distribute(void **unused)
{
    (void)unused;
    check(&(Case){.expr = "3*(x+0.1)", X1(0.7), .simplified = "(0.30000000000000004 + (3 * x))",
                  S(2.3999999999999995), .ns = 1, N(2.4), .nn = 1});
    check(&(Case){.expr = "(x-0.1)*3", X1(0.7), .simplified = "(-0.30000000000000004 + (3 * x))",
                  S(1.7999999999999996), .ns = 1, N(1.7999999999999998), .nn = 1});
}

/* S8: L * (M * y) reassociates to (L*M) * y. */
static void test_s8_reassociate(void **unused)
{
    (void)unused;
    check(&(Case){.expr = "x*0.1*3", X1(0.7), .simplified = "(0.30000000000000004 * x)",
                  S(0.21000000000000002), .ns = 1, N(0.20999999999999996), .nn = 1});
    check(&(Case){.expr = "3*(0.1*x)", X1(0.7), .simplified = "(0.30000000000000004 * x)",
                  S(0.21000000000000002), .ns = 1, N(0.20999999999999996), .nn = 1});
}

/* S9: L * (M / y) -> (L*M) / y. */
static void test_s9_divide(void **unused)
{
    (void)unused;
    check(&(Case){.expr = "3*(0.1/x)", X1(0.7), .simplified = "(0.30000000000000004 / x)",
                  S(0.42857142857142866), .ns = 1, N(0.4285714285714286), .nn = 1});
}

/* S10: L * (-y) -> (-L) * y. */
static void test_s10_negated_factor(void **unused)
{
    (void)unused;
    check(&(Case){.expr = "3*(-x)", X1(0.5), .simplified = "(-3 * x)", S(-1.5), .ns = 1, N(-1.5), .nn = 1});
}

/* S11: the literal operand of a negated product or quotient is negated. */
static void test_s11_negate_literal(void **unused)
{
    (void)unused;
    check(&(Case){.expr = "-(x*3)", X1(0.5), .simplified = "(x * -3)", S(-1.5), .ns = 1, N(-1.5), .nn = 1});
    check(&(Case){.expr = "-(x/10)", X1(0.1), .simplified = "(-0.1 * x)", S(-0.010000000000000002),
                  .ns = 1, N(-0.01), .nn = 1});
    check(&(Case){.expr = "-(2/x)", X1(4), .simplified = "(-2 / x)", S(-0.5), .ns = 1, N(-0.5), .nn = 1});
}

/* S12: negated sums and differences with a literal side; double negation. */
static void test_s12_negate_sum(void **unused)
{
    (void)unused;
    check(&(Case){.expr = "-(x+1)", X1(0.5), .simplified = "(-1 - x)", S(-1.5), .ns = 1, N(-1.5), .nn = 1});
    check(&(Case){.expr = "-(x-1)", X1(0.5), .simplified = "(1 - x)", S(0.5), .ns = 1, N(0.5), .nn = 1});
    check(&(Case){.expr = "-(-x)", X1(0.5), .simplified = "(+x)", S(0.5), .ns = 1, N(0.5), .nn = 1});
}

/* S13: unary plus around a maths operation vanishes; (+a) op b -> a op b. */
static void test_s13_plus(void **unused)
{
    (void)unused;
    check(&(Case){.expr = "+(x*y)", X1(2), .y = {3}, .ny = 1, .simplified = "(x * y)", S(6), .ns = 1,
                  N(6), .nn = 1});
    check(&(Case){.expr = "(+x)*y", X1(2), .y = {3}, .ny = 1, .simplified = "(x * y)", S(6), .ns = 1,
                  N(6), .nn = 1});
}

/* S14: adding a negation subtracts, subtracting one adds. */
static void test_s14_negation_terms(void **unused)
{
    (void)unused;
    check(&(Case){.expr = "x+(-y)", X1(5), .y = {3}, .ny = 1, .simplified = "(x - y)", S(2), .ns = 1,
                  N(2), .nn = 1});
    check(&(Case){.expr = "(-x)+y", X1(5), .y = {3}, .ny = 1, .simplified = "(y - x)", S(-2), .ns = 1,
                  N(-2), .nn = 1});
    check(&(Case){.expr = "x-(-y)", X1(5), .y = {3}, .ny = 1, .simplified = "(x + y)", S(8), .ns = 1,
                  N(8), .nn = 1});
}

/* S15: (p*q) + b -> b + (p*q), which the evaluator then fuses (F1). */
static void test_s15_product_last(void **unused)
{
    (void)unused;
    check(&(Case){.expr = "(x*y)+z", .x = {1, 2}, .nx = 2, .y = {1, 2, 3}, .ny = 3,
                  .z = {1, 2, 3, 4, 5, 6}, .nz = 6, .simplified = "(z + (x * y))",
                  S(2, 6, 6, 6, 7, 12), .ns = 6, N(2, 6, 6, 5, 9, 9), .nn = 6});
}

/* S16: x // 1 -> floor(x); x % 1 -> fract(x). */
static void test_s16_floor_fract(void **unused)
{
    (void)unused;
    check(&(Case){.expr = "x//1", X1(-2.5), .simplified = "floor(x)", S(-3), .ns = 1, N(-3), .nn = 1});
    check(&(Case){.expr = "x%1", X1(-2.25), .simplified = "fract(x)", S(0.75), .ns = 1, N(0.75), .nn = 1});
}

/* S17: a maths operation with a literal non-numeric operand is null. */
static void test_s17_non_numeric(void **unused)
{
    (void)unused;
    check(&(Case){.expr = "x+\"a\"", X1(1), .simplified = "LITERAL", .ns = -1, .nn = -1});
    char *dump = run_case(&(Case){.expr = "null*x", X1(1)}, true, NULL, -1);
    assert_non_null(strstr(dump, "(!t)\n"));   /* v=null: no attribute at all */
    free(dump);
}

/* S18: null in y is true. */
static void test_s18_null_in(void **unused)
{
    (void)unused;
    check(&(Case){.expr = "null in x", X1(1), .simplified = "LITERAL", S(1), .ns = 1, N(1), .nn = 1});
    char *dump = run_case(&(Case){.expr = "null in x", X1(1)}, true, (double[]){1}, 1);
    assert_non_null(strstr(dump, "(!t v=1)"));
    free(dump);
}

/* F1: a + b*c is one broadcasting pass, with or without the simplifier. */
static void test_f1_fused(void **unused)
{
    (void)unused;
    check(&(Case){.expr = "z+x*y", .x = {1, 2}, .nx = 2, .y = {1, 2, 3}, .ny = 3,
                  .z = {1, 2, 3, 4, 5, 6}, .nz = 6, .simplified = "(z + (x * y))",
                  S(2, 6, 6, 6, 7, 12), .ns = 6, N(2, 6, 6, 6, 7, 12), .nn = 6});
}

/* F2: x ** 2 is x * x. */
static void test_f2_square(void **unused)
{
    (void)unused;
    check(&(Case){.expr = "x**2", X1(1.1), .simplified = "(x ** 2)", S(1.2100000000000002), .ns = 1,
                  N(1.2100000000000002), .nn = 1});
    check(&(Case){.expr = "z+x**2", X1(3), .z = {1, 2}, .nz = 2, .simplified = "(z + (x ** 2))",
                  S(10, 11), .ns = 2, N(10, 11), .nn = 2});
}

/* Loops over literal sources unroll; functions without captures inline. */
static void test_unroll_and_inline(void **unused)
{
    (void)unused;
    const char *src = "func f(a)\n    a/10\nlet t=$(:x)\n!t v=(f(t) for i in ..2)\n";
    fl_options o = fl_default_options();
    RtStreams streams = {NULL, stdout};
    rt_log_to_files(&o, &streams);
    fl_runtime *rt = fl_new(&o);
    Buf err = BUF_INIT, dump = BUF_INIT;
    assert_int_equal(rt_load_text(rt, "u.fl", src, strlen(src), &err), 0);
    rt_dump_program(rt, &dump);
    assert_non_null(strstr(buf_cstr(&dump), "(!t) v=((0.1 * t); (0.1 * t))\n"));
    buf_free(&err);
    buf_free(&dump);
    fl_free(rt);
}

/* let stable: once a value is the same on two frames in a row, the program
 * is simplified again with it known (here: time/(k+10) becomes
 * (1/(k+10))*time from the frame after); when it changes, that frame runs
 * the program as first simplified. */
static void test_let_stable(void **unused)
{
    (void)unused;
    const char *src = "let stable k=frame//3\n!t v=time/(k+10)\n";
    for (int mode = 0; mode < 2; mode++) {
        fl_options o = fl_default_options();
        RtStreams streams = {NULL, stdout};
        rt_log_to_files(&o, &streams);
        o.no_simplify = mode == 1;
        fl_runtime *rt = fl_new(&o);
        Buf err = BUF_INIT;
        assert_int_equal(rt_load_text(rt, "s.fl", src, strlen(src), &err), 0);
        buf_free(&err);
        for (int f = 0; f < 8; f++) {
            fl_step(rt);
            double t = fl_frame_time(rt), k = (double)(f / 3), want;
            /* stable from frame 1 (k=0: frames 2), from frame 4 (k=1: frame 5) */
            bool rewritten = mode == 0 && (f == 2 || f == 5);
            want = rewritten ? (1.0 / (k + 10)) * t : t / (k + 10);
            const Vec *v = node_attr(rt_root(rt)->children[0], "v");
            assert_true(vec_is_scalar(v));
            if (memcmp(&vec_cnums(v)[0], &want, sizeof want) != 0)
                fail_msg("mode %d frame %d: v = %.17g, expected %.17g", mode, f, vec_cnums(v)[0], want);
        }
        fl_free(rt);
    }
}

/* Write [text] to [dir]/[name]. */
static void write_file(const char *dir, const char *name, const char *text)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
}

/* import and %include with literal paths: a module's literal names and
 * capture-free functions become static bindings (inlined, so the rules
 * apply at the call site); only the dynamic names are imported at run
 * time; an included file is spliced in and simplified in place. */
static void test_import_and_include(void **unused)
{
    (void)unused;
    char dir[] = "/tmp/flitter-simplify-XXXXXX";
    assert_non_null(mkdtemp(dir));
    write_file(dir, "mod.fl", "let K=10\n    S=$(:s)\nfunc f(x)\n    x/K\n");
    write_file(dir, "inc.fl", "!i v=time/4\n");
    const char *src = "import f;K;S from 'mod.fl'\n%include 'inc.fl'\n!t a=f(time) b=K d=f(3)\n";
    char main[600];
    snprintf(main, sizeof main, "%s/main.fl", dir);
    fl_options o = fl_default_options();
    RtStreams streams = {NULL, stdout};
    rt_log_to_files(&o, &streams);
    fl_runtime *rt = fl_new(&o);
    Buf err = BUF_INIT, dump = BUF_INIT;
    assert_int_equal(rt_load_text(rt, main, src, strlen(src), &err), 0);
    rt_dump_program(rt, &dump);
    const char *d = buf_cstr(&dump);
    assert_non_null(strstr(d, "import S from \"mod.fl\"\n"));
    assert_non_null(strstr(d, "(!i) v=(0.25 * time)\n"));
    assert_non_null(strstr(d, "(!t) a=(0.1 * time) b=10 d=0.30000000000000004\n"));
    fl_step(rt);
    fl_step(rt);
    const Vec *a = node_attr(rt_root(rt)->children[1], "a");
    assert_true(vec_is_scalar(a));
    double want = 0.1 * (1.0 / 60.0);   /* time of frame 1 times (1/10) */
    assert_memory_equal(&vec_cnums(a)[0], &want, sizeof want);
    buf_free(&err);
    buf_free(&dump);
    fl_free(rt);
    char path[600];
    snprintf(path, sizeof path, "%s/mod.fl", dir);
    unlink(path);
    snprintf(path, sizeof path, "%s/inc.fl", dir);
    unlink(path);
    rmdir(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_s1_fold),
        cmocka_unit_test(test_s2_add_zero),
        cmocka_unit_test(test_s3_sub_zero),
        cmocka_unit_test(test_s4_sub_literal),
        cmocka_unit_test(test_s5_unit),
        cmocka_unit_test(test_s6_reciprocal),
        cmocka_unit_test(test_s7_distribute),
        cmocka_unit_test(test_s8_reassociate),
        cmocka_unit_test(test_s9_divide),
        cmocka_unit_test(test_s10_negated_factor),
        cmocka_unit_test(test_s11_negate_literal),
        cmocka_unit_test(test_s12_negate_sum),
        cmocka_unit_test(test_s13_plus),
        cmocka_unit_test(test_s14_negation_terms),
        cmocka_unit_test(test_s15_product_last),
        cmocka_unit_test(test_s16_floor_fract),
        cmocka_unit_test(test_s17_non_numeric),
        cmocka_unit_test(test_s18_null_in),
        cmocka_unit_test(test_f1_fused),
        cmocka_unit_test(test_f2_square),
        cmocka_unit_test(test_unroll_and_inline),
        cmocka_unit_test(test_import_and_include),
        cmocka_unit_test(test_let_stable),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
