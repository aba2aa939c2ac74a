/* test_fastroute.c: the compiled evaluation route (lib/eval/numexpr.c,
 * lib/eval/evalcode.c) against the generic tree walk (FLITTER_NOFAST=1).
 *
 * Each script runs for one frame four ways: compiled and generic, with and
 * without the simplifier. All four node trees must equal the expected dump,
 * whose values were worked out by hand (IEEE doubles, one rounding per
 * operation; sin/cos in turns, exact at quadrants). The scripts take their
 * numbers from `time` (0 in the first frame) so that the simplifier cannot
 * fold them away, and cover the operand shapes that must leave the compiled
 * route for the generic one: vectors, strings, null, nodes, NaN in
 * comparisons (where the identity of the two operands matters).
 * A white-box case checks that the compiled route really is taken.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "evalcode.h"
#include "numexpr.h"
#include "program.h"
#include "runscript.h"
#include "random_calls.h"

/* The tree dump of the last of [frames] frames of [src], and the log. */
static char *run_frames(const char *src, int frames, bool simplify, bool fast, char **log_out)
{
    run_script_debug.no_fast = !fast;
    char *tree = run_script("fast.fl", src, frames, simplify, log_out, NULL);
    run_script_debug.no_fast = false;
    return tree;
}

/* The tree dump and log of one frame of [src]. */
static char *run_one(const char *src, bool simplify, bool fast, char **log_out)
{
    return run_frames(src, 1, simplify, fast, log_out);
}

/* All four ways give [want] and the same log. */
static void expect4(const char *src, const char *want)
{
    char *log0 = NULL;
    for (int way = 0; way < 4; way++) {
        char *log;
        char *tree = run_one(src, way & 1, way & 2, &log);
        if (strcmp(tree, want) != 0) fprintf(stderr, "way %d (simplify %d, fast %d)\n", way, way & 1, !!(way & 2));
        assert_string_equal(tree, want);
        if (log0) assert_string_equal(log, log0);
        free(tree);
        if (log0) free(log);
        else log0 = log;
    }
    free(log0);
}

static void test_arithmetic(void **s)
{
    (void)s;
    expect4("let x=3+time\n"
            "!arith a=x+1 b=x-0.5 c=x*2 d=x/0 e=-x/0 f=x//2 g=x%2 h=x**0.5 i=x**2 j=-x//2 "
            "k=(-x)%2 l=(x-3)/0 m=x%0 o=x//0 p=(0.1+time)+0.2 q=2**(-1+time) r=1/(-time)\n",
            "!root\n"
            " !arith a=4 b=2.5 c=6 d=inf e=-inf f=1 g=1 h=1.7320508075688772 i=9 j=-2 k=1 "
            "l=nan m=nan o=inf p=0.30000000000000004 q=0.5 r=-inf\n");
}

static void test_comparisons(void **s)
{
    (void)s;
    /* n==n is true although n is NaN: both operands are the same vector
     * (§3.6 rule 1); (0/0)==(0/0) compares two vectors */
    expect4("let x=3+time\n    n=(0/0)+time\n"
            "!cmp a=x>2 b=x==3 c=x!=3 d=x<=3 e=x>=4 f=x<3 g=n==n h=n!=n i=n<n j=n<=n "
            "k=(time/0)==(time/0) l=n>=n m=not x o=not (x-3) p=not n q=n>1 r=1<n\n",
            "!root\n"
            " !cmp a=1 b=1 c=0 d=1 e=0 f=0 g=1 h=0 i=0 j=1 k=0 l=1 m=0 o=1 p=0 q=1 r=0\n");
}

static void test_fallback_shapes(void **s)
{
    (void)s;
    /* vectors, strings, null and nodes leave the compiled route: the
     * generic rules give vectors or null (absent attributes) */
    expect4("let x=3+time\n    v=(1;2)+time\n    s=\"a\"\n    z=null\n    k=!foo\n"
            "!fallback a=v*2+1 b=s+1 c=z+1 d=k*2 e=sin(v) f=not v g=-v h=v==v i=(x;x+1;x*2) "
            "j=x+s k=v>1 l=x in v m=(x;v;x) o=sin(s) p=x*2+v\n",
            "!root\n"
            " !fallback a=3;5 e=0;0 f=0 g=-1;-2 h=1 i=3;4;6 k=1 l=0 m=3;1;2;3 p=7;8\n");
}

static void test_builtin_kernels(void **s)
{
    (void)s;
    expect4("let x=3+time\n"
            "!kernels a=sin(0.25+time) b=cos(0.5+time) c=sqrt(2+time) d=abs(-x) "
            "e=floor(time-0.5) f=exp(1+time) g=log(x) h=sine(0.25+time) i=sqrt(time-1) "
            "j=hsv(0;0;x/6) k=fract(x+0.25)\n",
            "!root\n"
            " !kernels a=1 b=-1 c=1.4142135623730951 d=3 e=-1 f=2.718281828459045 "
            "g=1.0986122886681098 h=0.5 i=nan j=0.5;0.5;0.5 k=0.25\n");
}

static void test_nodes_and_loops(void **s)
{
    (void)s;
    /* compiled lets, attributes, appends and sequences, inside and outside
     * loops (unrolled by the simplifier, kept without it) */
    expect4("let w=2+time\n"
            "!group n=w\n"
            "    for i in ..2\n"
            "        let p=i*w\n"
            "        !dot #t x=p;p+1 y=p>1\n"
            "!tail\n",
            "!root\n"
            " !group n=2\n"
            "  !dot #t x=0;1 y=0\n"
            "  !dot #t x=2;3 y=1\n"
            " !tail\n");
}

/* Both routes give the same tree and the same messages: [src] evaluated
 * compiled and generic, in the mode [simplify]; the log must contain
 * [message]. */
static void expect_same(const char *src, bool simplify, const char *message)
{
    char *log_g, *log_f;
    char *tree_g = run_one(src, simplify, false, &log_g);
    char *tree_f = run_one(src, simplify, true, &log_f);
    assert_string_equal(tree_f, tree_g);
    assert_string_equal(log_f, log_g);
    assert_non_null(strstr(log_f, message));
    free(tree_g);
    free(tree_f);
    free(log_g);
    free(log_f);
}

/* Run-time limits hit inside compiled regions: the recursion limit, and
 * the evaluator's depth limit (without the simplifier each `let` of the
 * chain, kept apart from the next by a node, is a level, 40 per call, so
 * the depth runs out before the recursion limit of 500 calls; consecutive
 * `let` lines would be one `let` of 40 bindings, ast.h ast_sequence). */
static void test_limits_same(void **s)
{
    (void)s;
    expect_same("func f(n)\n    let m=n+1\n    !x v=m\n    f(m)\n!r << f(time)\n", false,
                "Recursion depth exceeded for func 'f'");
    char src[8192];
    size_t len = 0;
    len += (size_t)snprintf(src + len, sizeof src - len, "func g(n)\n    let a0=n+1\n");
    for (int i = 1; i < 40; i++)
        len += (size_t)snprintf(src + len, sizeof src - len, "    !z\n    let a%d=a%d+1\n", i, i - 1);
    snprintf(src + len, sizeof src - len, "    !y v=a39\n    g(a39)\n!r << g(time)\n");
    expect_same(src, false, "Stack overflow in program");
    /* the simplifier folds the chain (its nodes are literals): the
     * recursion limit comes first */
    expect_same(src, true, "Recursion depth exceeded for func 'g'");
    /* a chain of 80 through the records of evalcode.h's C_IF, C_BINOP,
     * C_INDEX and C_LOOKUP: the depth runs out at the same place */
    len = (size_t)snprintf(src, sizeof src, "func h(n)\n    let a0=n+(1;1)\n");
    for (int i = 1; i < 80; i++)
        len += (size_t)snprintf(src + len, sizeof src - len,
                                "    !z\n    let a%d=(a%d+(1;2)*a%d)[0;1] if a%d[0] else $(:q;a%d[1])\n",
                                i, i - 1, i - 1, i - 1, i - 1);
    snprintf(src + len, sizeof src - len, "    !y v=a79\n    h(a79)\n!r << h(time)\n");
    expect_same(src, false, "Stack overflow in program");
}


/* Append a random expression of depth up to [depth] to [b]. */
static void random_expr(Buf *b, uint32_t *st, int depth)
{
    static const char *const leaves[] = {"x", "y", "n", "inf", "mz", "v", "s", "z", "k", "2", "0.5",
                                         "-3", "0", "1e308"};
    static const char *const binops[] = {"+", "-", "*", "/", "//", "%", "**", "==", "!=", "<", ">",
                                         "<=", ">="};
    static const char *const calls[] = {"sin", "cos", "sqrt", "abs", "floor", "exp", "log", "fract"};
    uint32_t r = lcg(st) % 10;
    if (depth == 0 || r < 3) {
        buf_puts(b, leaves[lcg(st) % (sizeof leaves / sizeof leaves[0])]);
    } else if (r < 7) {
        buf_puts(b, "(");
        random_expr(b, st, depth - 1);
        buf_printf(b, ")%s(", binops[lcg(st) % (sizeof binops / sizeof binops[0])]);
        random_expr(b, st, depth - 1);
        buf_puts(b, ")");
    } else if (r < 8) {
        buf_puts(b, lcg(st) % 2 ? "-(" : "not (");
        random_expr(b, st, depth - 1);
        buf_puts(b, ")");
    } else if (r < 9) {
        buf_printf(b, "%s(", calls[lcg(st) % (sizeof calls / sizeof calls[0])]);
        random_expr(b, st, depth - 1);
        buf_puts(b, ")");
    } else {
        buf_puts(b, "(");
        random_expr(b, st, depth - 1);
        buf_puts(b, ";");
        random_expr(b, st, depth - 1);
        buf_puts(b, ")");
    }
}

/* Eight rounds of a script: [prelude], then a node of 60 attributes,
 * each a random expression of [gen] from the seed [st]; both routes give
 * the same tree and log, with and without the simplifier. */
static void random_rounds(uint32_t st, const char *prelude, void (*gen)(Buf *, uint32_t *, int))
{
    for (int round = 0; round < 8; round++) {
        Buf b = BUF_INIT;
        buf_puts(&b, prelude);
        for (int i = 0; i < 60; i++) {
            buf_printf(&b, " a%d=", i);
            gen(&b, &st, 4);
        }
        buf_puts(&b, "\n");
        for (int simplify = 0; simplify < 2; simplify++) {
            char *log_g, *log_f;
            char *tree_g = run_one(buf_cstr(&b), simplify, false, &log_g);
            char *tree_f = run_one(buf_cstr(&b), simplify, true, &log_f);
            assert_string_equal(tree_f, tree_g);
            assert_string_equal(log_f, log_g);
            /* the tree holds real values, not just an empty node */
            assert_true(strlen(tree_g) > 200);
            free(tree_g);
            free(tree_f);
            free(log_g);
            free(log_f);
        }
        buf_free(&b);
    }
}

/* Random arithmetic over numbers and every special operand (NaN, inf, -0,
 * huge, vectors, strings, null, nodes): both routes give the same tree,
 * with and without the simplifier. */
static void test_random_expressions(void **s)
{
    (void)s;
    random_rounds(12345, "let x=3+time\n    y=time-0.25\n    n=(0/0)+time\n    inf=(1/0)+time\n"
                         "    mz=-time\n    v=(1;-2)+time\n    s=\"a\"\n    z=null\n    k=!foo\n!e",
                  random_expr);
}

/* random_expr over vectors of one to three numbers (NaN, inf and -0
 * among them) and a builtin of each numeric route (hypot, the element-wise
 * ones, hsv), with indexing. */
static void random_vexpr(Buf *b, uint32_t *st, int depth)
{
    static const char *const leaves[] = {"x", "p", "q", "r", "w", "n", "2", "0.5", "(1;2)", "s"};
    static const char *const binops[] = {"+", "-", "*", "/", "//", "%", "**", "<", "==", "+", "-", "*"};
    static const char *const calls[] = {"hypot", "sin", "sqrt", "abs", "hsv", "sine", "hypot", "fract"};
    uint32_t r = lcg(st) % 12;
    if (depth == 0 || r < 3) {
        buf_puts(b, leaves[lcg(st) % (sizeof leaves / sizeof leaves[0])]);
    } else if (r < 8) {
        buf_puts(b, "(");
        random_vexpr(b, st, depth - 1);
        buf_printf(b, ")%s(", binops[lcg(st) % (sizeof binops / sizeof binops[0])]);
        random_vexpr(b, st, depth - 1);
        buf_puts(b, ")");
    } else if (r < 9) {
        buf_puts(b, lcg(st) % 2 ? "-(" : "not (");
        random_vexpr(b, st, depth - 1);
        buf_puts(b, ")");
    } else if (r < 11) {
        buf_printf(b, "%s(", calls[lcg(st) % (sizeof calls / sizeof calls[0])]);
        random_vexpr(b, st, depth - 1);
        buf_puts(b, ")");
    } else {
        buf_puts(b, lcg(st) % 2 ? "p[" : "w[");
        random_vexpr(b, st, depth - 1);
        buf_puts(b, "]");
    }
}

/* Random arithmetic on names holding vectors, the compiled expressions'
 * vector form and the calls' numbers (evalrun.c arg_nums) against the
 * generic route, with and without the simplifier. */
static void test_random_vector_expressions(void **s)
{
    (void)s;
    random_rounds(777, "let x=3+time\n    p=(1;-2;0.25)+time\n    q=(0.5;4;-3)*(1+time)\n"
                       "    r=(0/0;1/0;-0.0)+time\n    w=(2;7)+time\n    n=(0/0)+time\n    s=\"a\"\n!e",
                  random_vexpr);
}

/* Random expressions with the calls compiled into them (random_cexpr)
 * against the generic route, with and without the simplifier, in the
 * top level and in a loop over a range the simplifier cannot unroll
 * (where kernels may take them: test_kernel's routes are the threads'). */
static void test_random_compiled_calls(void **s)
{
    (void)s;
    random_rounds(4242, "let x=1.25+time\n    p=(1;-2;0.25)+time\n    q=(0.5;4;-3)*(1+time)\n"
                        "    w=(2;7)+time\n    n=(0/0)+time\n    mz=-time\n    s=\"a\"\n    i=3+time\n!e",
                  random_cexpr);
    random_rounds(99, "let x=1.25+time\n    p=(1;-2;0.25)+time\n    q=(0.5;4;-3)*(1+time)\n"
                      "    w=(2;7)+time\n    n=(0/0)+time\n    mz=-time\n    s=\"a\"\n!g\n"
                      "    for i in ..(3+floor(time))\n        !e",
                  random_cexpr);
}

/* A loop whose body is a compiled expression (eval.c eval_for's
 * LoopNums): its iterations' numbers go straight into the result, and an
 * iteration the compiled expression gives up on (a string bound, a name
 * holding a vector, a comparison meeting a NaN) takes the generic route
 * between them, in order. Worked by hand with time 0: a = 0;2;4;6; b: the
 * source 1;"a";3;2;7 gives 2, null, 6, 4, 14; c: 2;7 times 0, 1, 2; d: 1/i
 * > 0 of 1, -1, NaN, 2 (a NaN compares greater both ways, LANGUAGE.md
 * §3.7: 1; the compiled expression gives up on it, the generic route
 * gives it); g: the sum of 200 such comparisons, every 7th from 7 on a
 * NaN's (1/0 is inf at 0), all 1, so 200 with 28 of them generic; e: one
 * iteration; f: none (null: left out). The same on the four routes. */
static void test_loop_numbers(void **s)
{
    (void)s;
    expect4("let w=(2;7)+time\n    z=floor(time)\n"
            "!n a=(i*2 for i in ..4+z) b=(v*2 for v in (1;\"a\";3;w)) c=(w*i for i in ..3+z) "
            "d=(1/i>0 for i in (1;-1;0/0+time;2)) g=sum((1/(i+(0/0 if i%7==0 and i>0 else 0))>=0) for i in ..200+z) "
            "e=(i+1 for i in ..1+z) f=(i for i in ..z)\n",
            "!root\n !n a=0;2;4;6 b=2;6;4;14 c=0;0;2;7;4;14 d=1;0;1;1 g=200 e=1\n");
}

/* random_expr as the body of a loop over sources of numbers, of the
 * special numbers, and of a string and a node among numbers (x is the
 * loop's name, which the body reads). */
static void random_loop_expr(Buf *b, uint32_t *st, int depth)
{
    static const char *const srcs[] = {"..(3+floor(time))", "p", "(1;s;-0.0;n)", "(k;2;x)", "(0/0;inf;mz)",
                                       "..(70+floor(time))"};
    buf_puts(b, "(");
    random_expr(b, st, depth - 1);
    buf_printf(b, " for x in %s)", srcs[lcg(st) % (sizeof srcs / sizeof srcs[0])]);
}

/* Random loops of random bodies (random_loop_expr) against the generic
 * route, with and without the simplifier. */
static void test_random_loops(void **s)
{
    (void)s;
    random_rounds(2468, "let x=3+time\n    y=time-0.25\n    n=(0/0)+time\n    inf=(1/0)+time\n"
                        "    mz=-time\n    v=(1;-2)+time\n    s=\"a\"\n    z=null\n    k=!foo\n"
                        "    p=(1;-2;0.25)+time\n!e",
                  random_loop_expr);
}

/* Attributes set on a literal node that has attributes, tags and children
 * of its own (evalrun.c run_attrs' copy of the one node): a value replaces
 * the literal's in its place, null removes it or is dropped, the tags and
 * children stay; children appended to a literal node with children of its
 * own (eval.c append_nodes' copy of the one node) follow them. */
static void test_attributes_on_literal_nodes(void **s)
{
    (void)s;
    expect4("let x=3+time\n    z=null\n"
            "!g\n"
            "    for i in ..2\n"
            "        (!dot #t a=1 b=2 << !kid k=i) b=x+i c=z a=z\n"
            "    (!tagged #u #v q=5) q=x r=x;x\n"
            "    (!box #w << !first) << (!second v=x) << !third\n",   /* << groups to the right */
            "!root\n"
            " !g\n"
            "  !dot #t b=3\n"
            "   !kid k=0\n"
            "  !dot #t b=4\n"
            "   !kid k=1\n"
            "  !tagged #u #v q=3 r=3;3\n"
            "  !box #w\n"
            "   !first\n"
            "   !second v=3\n"
            "    !third\n");
}

/* Attributes of their own set on a literal node (evalcode.c C_ATTRS pad 1:
 * names pairwise different, none the literal's, each added without a
 * search): after the literal's, in order, a null one dropped; names set
 * twice (no pad: the second value replaces the first in its place, or, null,
 * removes it) and a null on a literal of one attribute. */
static void test_new_attributes_on_literal_nodes(void **s)
{
    (void)s;
    expect4("let x=3+time\n    z=null\n"
            "!g\n"
            "    for i in ..2\n"
            "        (!lit #t a=1 << !kid k=i) b=x+i c=z d=x;i\n"
            "    (!one a=1) b=x c=x b=x+1 e=x e=z+1\n"
            "    (!two q=2) r=z\n",
            "!root\n"
            " !g\n"
            "  !lit #t a=1 b=3 d=3;0\n"
            "   !kid k=0\n"
            "  !lit #t a=1 b=4 d=3;1\n"
            "   !kid k=1\n"
            "  !one a=1 b=4 c=3\n"
            "  !two q=2\n");
}

/* Children given to a node as a sequence of two to eight parts
 * (evalrun.c run_append_parts, eval.c append_parts: the parts' nodes moved
 * into the node's children without composing them first): nodes of a
 * part held only there and of a name (shared), a loop's several nodes, and
 * numbers, strings, a stream and a null `if` left out; a fresh parent; two
 * parents (composed and appended); nine parts; no nodes at all. */
static void test_children_parts(void **s)
{
    (void)s;
    expect4("let x=3+time\n    k=!held v=x\n"
            "!g\n"
            "    (!lit #t a=1 << !old)\n"
            "        !n1 v=x\n        k\n        x\n"
            "        for i in ..2\n            !loop i=i\n"
            "        \"s\"\n        uniform(:u)\n"
            "        if x > 5\n            !never\n"
            "        !n2 w=x*2\n"
            "    !fresh v=x\n        !c1\n        k\n"
            "    (!a;!b)\n        !c v=x\n        !d\n"
            "    !nine\n        !p1\n        !p2 v=x\n        !p3\n        x\n        !p4\n"
            "        k\n        !p5\n        !p6\n        !p7 v=x\n"
            "    !none\n        x\n        \"s\"\n        x;x\n",
            "!root\n"
            " !g\n"
            "  !lit #t a=1\n   !old\n   !n1 v=3\n   !held\n   !loop i=0\n   !loop i=1\n   !n2 w=6\n"
            "  !fresh v=3\n   !c1\n   !held\n"
            "  !a\n   !c v=3\n   !d\n"
            "  !b\n   !c v=3\n   !d\n"
            "  !nine\n   !p1\n   !p2 v=3\n   !p3\n   !p4\n   !held\n   !p5\n   !p6\n   !p7 v=3\n"
            "  !none\n");
}

/* map() and clamp() of three arguments that are numbers on the C stack
 * (evalrun.c run_callbi_args, maths.c bi_call_nums_args), against
 * hand-worked values: (1-x)*y + x*z and max then min, each argument
 * repeated to the longest; a NaN clamped to the low bound (its comparisons
 * are false); a string (null) and a result of 17 numbers left to the
 * builtin. */
static void test_map_clamp_route(void **s)
{
    (void)s;
    expect4("let x=0.25+time\n    t=time\n"
            "!m a=map(x, 2, 6) b=map(0.5+t, (0;10), (1;20;100)) c=clamp((-1;0.5;7)+t, 0, 1) "
            "d=clamp((0/0)+t, 0, 1) e=map(x, \"a\", 1) f=len(map(x, 1, (..17)+t)) g=clamp(x, 1, 0)\n",
            "!root\n"
            " !m a=3 b=0.5;15;50 c=0;0.5;1 d=0 f=17 g=0\n");
}

/* noise() calls whose arguments are numbers on the C stack (evalrun.c
 * run_callbi_args, noise.c bi_noise_nums): one point in one to four
 * dimensions and grids, with the values test_vectors takes from Flitter
 * (a to e, l); a seed of two numbers; a seed of a fraction, hashed as
 * its floor (m, as o); and the calls it leaves to the
 * builtin: a string seed or coordinate, five coordinates, a grid of more
 * than BI_NUMS_MAX points, a null seed. */
static void test_noise_route(void **s)
{
    (void)s;
    expect4("let x=0.5+time\n    t=time\n"
            "!n a=noise(:s, x) b=noise(:s, x, 0.25) c=noise(:s, 0.3+t, 0.6, 0.9) "
            "d=noise(:s, 0.3, 0.6+t, 0.9, 1.2) e=noise(:s, (1;2)+t, 3) f=noise(:s;t, x) g=noise(\"s\", x) "
            "h=noise(:s, x, \"x\") i=noise(:s, 1, 2, 3, 4, 5+t) j=len(noise(:s, (..17)+t)) "
            "k=noise(:s, x;x, 0.25;1+t) l=noise(null, 1.3+t) m=noise(0.75+t, x) o=noise(0, x)\n",
            "!root\n"
            " !n a=0.6390421355507776 b=0.5816501773837107 c=-0.4272253565307444 d=-0.4135278393516153 "
            "e=-0.23206229791237545;-0.09793599283942231 f=0.35871384849177557 g=0.6568176593613215 j=17 "
            "k=0.5816501773837107;0.05250111798922778;0.5816501773837107;0.05250111798922778 "
            "l=0.4902465961370626 m=-0.42051860444936273 o=-0.42051860444936273\n");
}

/* Names holding vectors in compiled expressions (numexpr_run_vec) and
 * one-argument calls with a numeric route given a vector (evalrun.c
 * arg_nums), against hand-worked values: element by element, a one-number
 * operand repeated; lengths that differ, comparisons and `not` of vectors
 * left to the generic route's rules. */
static void test_vector_expressions(void **s)
{
    (void)s;
    expect4("let v=(1;2;3)+time\n    w=(4;0.5;-2)+time\n    s=2+time\n"
            "!vec a=v-w b=v*s+1 c=hypot(v-w) d=sin(v*0.25) e=-v f=v**2 g=abs(w-v) h=v//2 "
            "i=(v+w)%2 j=(v;w) k=v+(1;2) l=v<w m=sqrt(v) n=v+w*s p=hypot(v-(1;2)) q=hypot(v) "
            "r=hsv(v/3-s*0.25) t=not v u=v[s]+v x=s+v y=v[s]*w[s]\n",
            "!root\n"
            " !vec a=-3;1.5;5 b=3;5;7 c=6.020797289396148 d=1;0;-1 e=-1;-2;-3 f=1;4;9 g=3;1.5;5 "
            "h=0;1;1 i=1;0.5;1 j=1;2;3;4;0.5;-2 k=2;4;4 l=1 m=1;1.4142135623730951;1.7320508075688772 "
            "n=9;3;-1 p=2 q=3.7416573867739413 r=0.5;0.41666666666666674;0.5 t=0 u=4;5;6 x=3;4;5 y=-6\n");
}

/* Names read first by a compiled expression holding what numexpr_run
 * cannot take (a vector: straight to the vector form; null, a string:
 * the generic route), and vectors longer than the vector form takes, in
 * value.c's arithmetic (four numbers at a time where the processor can;
 * a short operand repeated by tiles), against hand-worked values. */
static void test_lead_names_and_long_vectors(void **s)
{
    (void)s;
    expect4("let v=(1..21)+time\n    p=(0.5;-3)+time\n    z=null\n    t=\"ab\"\n    w=(1;2;3)+time\n"
            "!long a=v%p b=v*2 c=v/4 d=v-v e=v//p f=z+1 g=t*2 h=z-v i=w-1 j=hypot(w-w) k=w*(2;1)\n",
            "!root\n"
            " !long a=0;-1;0;-2;0;0;0;-1;0;-2;0;0;0;-1;0;-2;0;0;0;-1 "
            "b=2;4;6;8;10;12;14;16;18;20;22;24;26;28;30;32;34;36;38;40 "
            "c=0.25;0.5;0.75;1;1.25;1.5;1.75;2;2.25;2.5;2.75;3;3.25;3.5;3.75;4;4.25;4.5;4.75;5 "
            "d=0;0;0;0;0;0;0;0;0;0;0;0;0;0;0;0;0;0;0;0 "
            "e=2;-1;6;-2;10;-2;14;-3;18;-4;22;-4;26;-5;30;-6;34;-6;38;-7 i=0;1;2 j=0 k=2;2;6\n");
}

/* Expressions of engine names alone, repeated in the bodies of an
 * unrolled loop, share a kept result (evalcode.h C_MEMO): the values are
 * those of the generic route in the first frame and after `time` moved,
 * and a NaN result is never shared (two NaN vectors are not equal). */
static void test_memo(void **s)
{
    (void)s;
    const char *src = "for i in ..3\n"
                      "    let p=time+0/0\n"
                      "        q=time+0/0\n"
                      "    !m a=sin(time+0.25) b=time>0 c=p==q d=(time+0/0) e=time*0.5\n";
    expect4(src, "!root\n"
                 " !m a=1 b=0 c=0 d=nan e=0\n"
                 " !m a=1 b=0 c=0 d=nan e=0\n"
                 " !m a=1 b=0 c=0 d=nan e=0\n");
    for (int simplify = 0; simplify < 2; simplify++) {
        char *log_g, *log_f;
        char *tree_g = run_frames(src, 3, simplify, false, &log_g);
        char *tree_f = run_frames(src, 3, simplify, true, &log_f);
        assert_string_equal(tree_f, tree_g);
        assert_string_equal(log_f, log_g);
        /* frame 3: time 2/60, so b is 1 and e is 1/60 */
        assert_non_null(strstr(tree_f, "b=1 c=0 d=nan e=0.016666666666666666\n"));
        free(tree_g);
        free(tree_f);
        free(log_g);
        free(log_f);
    }
}

/* All four ways give a tree whose text from the first [from] on is
 * [want], in the last of [frames] frames. */
static void expect4_from(const char *src, int frames, const char *from, const char *want)
{
    for (int way = 0; way < 4; way++) {
        char *log;
        char *tree = run_frames(src, frames, way & 1, way & 2, &log);
        const char *tail = strstr(tree, from);
        assert_non_null(tail);
        assert_string_equal(tail, want);
        free(tree);
        free(log);
    }
}

/* `$key` and `a[b]` in a compiled region (evalcode.h C_LOOKUP, C_INDEX):
 * a key or index of up to 8 computed numbers is looked up or used as
 * numbers, anything else (a string in the key, 9 or more numbers, no
 * numbers at all) as a vector, with the generic results: in frame 1 (t is
 * 1), the counters of frame 0 have set (:k;j) to 10j+(1;2;3) and ("s";1)
 * to 7; a key of constants and names alone (`:k;t`, `:k;frame`) is read
 * without its expression, and one of them holding a string (`q;t`) takes
 * the generic way; an absent key gives null (the attribute is left out); an index
 * is floored and wraps, NaN and -1e300 convert to INT32_MIN, which wraps
 * to 2 of 10. */
static void test_lookup_and_index(void **s)
{
    (void)s;
    const char *src =
        "for j in ..3\n"
        "    !counter state=:k;j initial=10*j+(1;2;3) rate=0\n"
        "!counter state=\"s\";1 initial=7 rate=0\n"
        "let t=time*60\n"
        "    v=(5;6;7;8;9;10;11;12;13;14)\n"
        "    q=\"s\"\n"
        "!m a=$(:k;t) b=$(:k;t+1) c=$(:k;(t+2)) d=$(\"s\";t) e=$(:k;t;0) "
        "f=$((:k;t+1;0;1;2;3;4;5;6;7)) g=$(:k;(0/0)+t) h=$(:z) i=$(:k;frame) j=$(q;t) k=$(:k;t;t)\n"
        "!i a=v[t] b=v[t-1] c=v[t+23] d=v[t;t+1;t+2] e=v[0/0+t] f=v[t..t+10] "
        "g=v[(t;1;2;3;4;5;6;7;8;9)] h=v[t+2.5] i=v[-t-1e300] j=(:k;1)[t]\n";
    const char *want = " !m a=11;12;13 b=21;22;23 d=7 i=11;12;13 j=7\n"
                       " !i a=6 b=5 c=9 d=6;7;8 e=7 f=6;7;8;9;10;11;12;13;14;5 "
                       "g=6;6;7;8;9;10;11;12;13;14 h=8 i=7 j=1\n";
    expect4_from(src, 2, " !m ", want);
}

/* The lookup cells of the compiled regions of [n]'s tree (CBlock.nlooks). */
static int count_lookup_cells(const AstNode *n)
{
    if (!n) return 0;
    int c = n->fast == 2 ? (int)((const CBlock *)n->aux)->nlooks : 0;
    c += count_lookup_cells(n->a) + count_lookup_cells(n->b) + count_lookup_cells(n->c);
    for (uint32_t i = 0; i < n->nkids; i++) c += count_lookup_cells(n->kids[i]);
    return c;
}

/* The lookup cells of literal keys (evalcode.h C_LOOKUP, state.h
 * state_get_cached) over frames in which the state's table changes: the
 * counter :a is there from frame 1 and changes every frame; :b is added
 * in frame 3; 30 counters more a frame (60 keys with their times) add
 * entries and rebuild the table under the kept cells. Worked by hand from
 * COUNTERS.md (frame f reads what frame f-1's update wrote): a is
 * 100+(f-1), b 200 then 202, (:c;40) is made in frame 2's update (40 <
 * 2*30), (:c;5) in frame 1's; an absent key leaves its attribute out. The
 * same on the four routes; white box: the simplified program has a cell
 * for each of its five literal keys. */
static void test_lookup_cells(void **s)
{
    (void)s;
    const char *src =
        "!counter state=:a time=frame rate=1 initial=100\n"
        "if frame >= 2\n"
        "    !counter state=:b time=frame rate=2 initial=200\n"
        "for j in ..frame*30\n"
        "    !counter state=:c;j time=frame rate=0 initial=j\n"
        "!m a=$(:a) b=$(:b) c=$(:c;40) d=$(:c;5) z=$(:z)\n";
    const char *want[5] = {
        " !m\n", " !m a=100\n", " !m a=101 d=5\n", " !m a=102 b=200 c=40 d=5\n",
        " !m a=103 b=202 c=40 d=5\n",
    };
    for (int f = 0; f < 5; f++) expect4_from(src, f + 1, " !m", want[f]);
    SymTab *st = symtab_new();
    Buf err = BUF_INIT;
    Globals g = {.simplify = true};
    globals_add(&g, "frame");
    g.ndynamic = 1;
    Program *p = program_load_text("t.fl", src, strlen(src), &g, st, &err);
    assert_non_null(p);
    assert_int_equal(count_lookup_cells(p->top), 5);
    program_release(p);
    globals_free(&g);
    buf_free(&err);
    symtab_free(st);
}

/* `v[x]` of a one-number index inside a compiled numeric expression
 * (numexpr.c NX_INDEX, NX_INDEXL): a constant numeric vector or stream, or
 * a name's vector. Worked by hand for frame 1 (t is 1, v is 5;6;7): the
 * index is floored (b: 2.5 is 2) and wraps (c: -1 is 2); NaN, -1e300 and
 * 1e10 convert to INT32_MIN, which wraps to 1 of 3 (d, k, m); a literal
 * range of one number indexes too (g); a name holding strings takes the
 * generic way (f); a stream bound to a name gives the stream's own draw
 * (h). */
static void test_index_in_numbers(void **s)
{
    (void)s;
    const char *src =
        "let t=time*60\n"
        "    v=(5;6;7)+t-1\n"
        "    s=\"a\";\"b\"\n"
        "    w=uniform(:w)\n"
        "!x a=(5;6;7)[t] b=(5;6;7)[t+1.5] c=(5;6;7)[-t] d=(5;6;7)[0/0+t] e=v[t]*2 f=s[t] "
        "g=(5;6;7)[1..2]+t h=(w[t]==uniform(:w)[1]) k=v[t-1e300] m=(5;6;7)[t*1e10]\n";
    expect4_from(src, 2, "!root\n", "!root\n !x a=6 b=7 c=7 d=6 e=12 f=\"b\" g=7 h=1 k=6 m=6\n");
}

/* A random stream made from numbers and indexed at once in a compiled
 * region (evalrun.c run_stream_index): the seed hashed from the key's
 * numbers and the draws made without the key or stream vectors, with the
 * values of the stream bound to a name and indexed (b), of a key floored
 * (j: 1.75 and 1 give one stream), of a normal pair (d) and its second
 * member alone (e), of a range index (g); a string key (f), a key of 9
 * numbers (k) and a string index (h: null, left out) take the generic
 * way. The numbers are those of the tree walk (FLITTER_NOFAST) at
 * 12ed5b4, before this route. */
static void test_stream_index(void **s)
{
    (void)s;
    const char *src =
        "let t=time*60\n"
        "    u=uniform(:k;t)\n"
        "!s a=uniform(:k;t)[t] b=(uniform(:k;t)[t] == u[t]) c=beta(:b;t;2)[t+0.5] d=normal(:n;t)[t;t+1] "
        "e=normal(:n;t)[t+1] f=uniform(\"s\";t)[t] g=uniform(:k;t)[t..t+3] h=uniform(:k;t)[\"x\"] "
        "i=uniform(t+0.75)[0] j=(uniform(t+0.75)[0] == uniform(1)[0]) k=uniform((:k;t;1;2;3;4;5;6;7))[t]\n";
    const char *want =
        "!root\n"
        " !s a=0.7099828147146965 b=1 c=0.33582077516940223 d=1.258440727101958;-1.6161527114824759 "
        "e=-1.6161527114824759 f=0.850759125555344 g=0.7099828147146965;0.26358433362001144;0.6443187373369204 "
        "i=0.3236437711805903 j=1 k=0.3319636173921611\n";
    expect4_from(src, 2, "!root\n", want);
}

/* Vector operators in a compiled region (evalcode.h C_BINOP), eval_binop's
 * fused forms (x**2, a + b*c, a + b**2) included, and `if`/`else` (C_IF)
 * on conditions of every kind: in frame 1, t is 1, v is 2;3;4 and w is
 * 1;10; shorter operands repeat; 0;0;0, null and "" are false, NaN, a
 * vector with a non-zero number and "s" true; the attribute g, null, is
 * left out. */
static void test_vector_operators_and_ifs(void **s)
{
    (void)s;
    const char *src =
        "let t=time*60\n"
        "    v=(1;2;3)+t\n"
        "    w=(t;10)\n"
        "!b a=v-w b=v**2 c=t+v*w d=t+v**2 e=v+w**2 f=v*(2;t+2) g=v//0 h=w**(t+1)\n"
        "!c a=(\"x\" if t else \"y\") b=(1 if v-v else 2) c=(1 if (0/0)+t else 2) d=(1 if null else 2) "
        "e=(1 if \"\" else (2 if \"s\" else 3)) f=(1 if t-1 else 2 if (t;0) else 3) g=(1 if t-1 else null) "
        "i=(1 if v else 2)\n";
    const char *want = "!root\n"
                       " !b a=1;-7;3 b=4;9;16 c=3;31;5 d=5;10;17 e=3;103;5 f=4;9;8 g=inf;inf;inf h=1;100\n"
                       " !c a=\"x\" b=2 c=1 d=2 e=2 f=2 i=1\n";
    expect4_from(src, 2, "!root\n", want);
}

/* Sequences longer than PARTS_CHUNK (eval_internal.h), composed a chunk at
 * a time: numbers stay a numeric vector, numbers and strings an object
 * vector, nodes stay in order, and a sequence whose only non-empty part is
 * one vector (among 99 empty streams or nulls) is that very vector, so that
 * comparing it with itself is 1 even though it holds NaN (§3.6 rule 1). */
static void test_long_sequences(void **s)
{
    (void)s;
    const char *src = "let n=time+0/0\n"
                      "    s=((uniform(k) if k != 70 else n) for k in ..100)\n"
                      "    u=((null if k != 3 else n) for k in ..100)\n"
                      "    x=((k if k%3 else \"s\") for k in ..150)\n"
                      "!m a=s==n b=u==n c=s==(time+0/0) d=x\n"
                      "!v x=(k*time+k for k in ..130)\n"
                      "!g\n"
                      "    for i in ..150\n"
                      "        !c i=i\n";
    Buf want = BUF_INIT;
    buf_puts(&want, "!root\n !m a=1 b=1 c=0 d=");
    for (int k = 0; k < 150; k++) {
        if (k) buf_putc(&want, ';');
        if (k % 3) buf_printf(&want, "%d", k);
        else buf_puts(&want, "\"s\"");
    }
    buf_puts(&want, "\n !v x=");
    for (int k = 0; k < 130; k++) buf_printf(&want, k ? ";%d" : "%d", k);
    buf_puts(&want, "\n !g\n");
    for (int i = 0; i < 150; i++) buf_printf(&want, "  !c i=%d\n", i);
    expect4(src, buf_cstr(&want));
    buf_free(&want);
}

/* Compilation marks nodes (AstNode.fast) unless FLITTER_NOFAST is set. */
static int count_fast(const AstNode *n)
{
    if (!n) return 0;
    int c = n->fast ? 1 : 0;
    c += count_fast(n->a) + count_fast(n->b) + count_fast(n->c);
    for (uint32_t i = 0; i < n->nkids; i++) c += count_fast(n->kids[i]);
    return c;
}

static void test_route_taken(void **s)
{
    (void)s;
    const char *src = "let x=3\n!a b=x*2+1 c=sin(x);x\n";
    SymTab *st = symtab_new();
    Buf err = BUF_INIT;
    Program *p = program_load_text("t.fl", src, strlen(src), NULL, st, &err);
    assert_non_null(p);
    assert_true(count_fast(p->top) >= 1);
    program_release(p);
    Globals literal = {.routes.no_fast = true};
    p = program_load_text("t.fl", src, strlen(src), &literal, st, &err);
    assert_non_null(p);
    assert_int_equal(count_fast(p->top), 0);
    program_release(p);
    buf_free(&err);
    symtab_free(st);
}

/* How many compiled expressions (fast == 1) of [n]'s tree are small
 * (numexpr_small), and how many are not. */
static void count_small(const AstNode *n, int *small, int *other)
{
    if (!n) return;
    if (n->fast == 1 && n->aux) {
        if (numexpr_small(numexpr_of(n))) ++*small;
        else ++*other;
    }
    count_small(n->a, small, other);
    count_small(n->b, small, other);
    count_small(n->c, small, other);
    for (uint32_t i = 0; i < n->nkids; i++) count_small(n->kids[i], small, other);
}

/* [src], loaded with the engine names time and beat, has [small]
 * compiled expressions that are small (numexpr_small) and [other] that
 * are not. */
static void expect_compiled(const char *src, int small, int other)
{
    SymTab *st = symtab_new();
    Buf err = BUF_INIT;
    Globals g = {0};
    globals_add(&g, "time");
    globals_add(&g, "beat");
    Program *p = program_load_text("t.fl", src, strlen(src), &g, st, &err);
    assert_non_null(p);
    int ns = 0, no = 0;
    count_small(p->top, &ns, &no);
    assert_int_equal(ns, small);
    assert_int_equal(no, other);
    program_release(p);
    globals_free(&g);
    buf_free(&err);
    symtab_free(st);
}

/* One operation on one or two constants or names is compiled as small
 * (numexpr_run_small runs it): `time+1`, `time<2`, `-time`, `time*time`,
 * `time/beat`; `(time+1)*2` and `sin(time)` are not. Their values on the
 * four routes are test_arithmetic's and test_comparisons'. */
static void test_small_expressions(void **s)
{
    (void)s;
    expect_compiled("!a b=time+1 c=(time+1)*2 d=time<2 e=-time f=time*time g=time/beat h=sin(time)\n", 5, 2);
    expect4("!a b=time+1 d=time<2 e=-time f=(time+3)*(time+3) g=(time+1)/(time+4) i=time-5 j=10/(time+2) "
            "k=time>=0 l=time!=time m=(0/0+time)==(0/0+time)\n",
            "!root\n !a b=1 d=1 e=0 f=9 g=0.25 i=-5 j=5 k=1 l=0 m=0\n");
}

/* hypot(a-b) of two names, the distance between two points (numexpr.c's
 * NX_DIST, the vector form's direct form): two vectors of one length
 * (either way round), a vector and a shorter one or one number (the
 * vector form's or the generic route's broadcasting), NaN and inf - inf,
 * a string (null), 17 numbers (past the vector form: generic), one
 * number each (the scalar machine). Worked by hand: (3;4;12) - (1;1;1) is
 * (2;3;11), the sum of squares in order 134; (3;4;12) - (1;2), wrapped,
 * is (2;2;11), 129; 1..17 from 17 zeros, 1785; (2;1) - (0.5;-0.5) is
 * (1.5;1.5), 4.5; (0.3;0.7;1.1) - 0 in order is 1.3379088160259651
 * (in reverse order the last bit differs). The same on the four routes. */
static void test_distance_in_expressions(void **s)
{
    (void)s;
    expect4("let a=(3;4;12)+time\n    b=(1;1;1)+time\n    c=(1;2)+time\n    o=1+time\n"
            "    n=(0/0;1;2)+time\n    i=(1/0;0;0)+time\n    s=\"a\"\n"
            "    l=(1;2;3;4;5;6;7;8;9;10;11;12;13;14;15;16;17)+time\n    m=l*0\n"
            "    p=(2;1)+time\n    q=(0.5;-0.5)+time\n    x=(0.3;0.7;1.1)+time\n    z=x*0\n"
            "!d a=hypot(a-b) b=hypot(b-a) c=hypot(a-c) d=hypot(a-o) e=hypot(o-a) f=hypot(n-b) "
            "g=hypot(i-i) h=hypot(a-s) k=hypot(l-m) m=hypot(o-o) r=hypot(p-q) t=hypot(x-z)\n",
            "!root\n !d a=11.575836902790225 b=11.575836902790225 c=11.357816691600547 "
            "d=11.575836902790225 e=11.575836902790225 f=nan g=nan k=42.24926034855522 m=0 "
            "r=2.1213203435596424 t=1.3379088160259651\n");
}

/* hypot of one argument is an instruction of the compiled expression
 * that holds it (NX_HYPOT), not a call of its own: `hypot(time-1)*2` is
 * one compiled expression, not small, where a call would have left only
 * its small argument compiled. Its values on the four routes: one number
 * (the builtin's sqrt of its square: overflow to inf and underflow to 0
 * where the magnitude would not), a vector name's sum of squares in
 * order (3;4 gives 5; 1e200 overflows), a vector that the vector form
 * does not take (longer than it holds: the generic call), NaN, and null
 * and a string (null, the builtin's). */
static void test_hypot_in_expressions(void **s)
{
    (void)s;
    expect_compiled("!a b=hypot(time-1)*2\n", 0, 1);
    expect4("let v=(3;4)+time\n    w=(1e200;0)+time\n    u=(1..21)+time\n    z=null\n    t=\"ab\"\n"
            "!h a=hypot(time-3) b=hypot(time+1e200) c=hypot(time-1e-200) d=hypot(v) e=hypot(w)+1 "
            "f=hypot(v-(1;1))*2 g=hypot(u-u) h=hypot(u) i=hypot(0/0+time) j=hypot(z) k=hypot(t) "
            "l=hypot(v)<hypot(v*2)\n",
            "!root\n !h a=3 b=inf c=0 d=5 e=inf f=7.211102550927978 g=0 h=53.5723809439155 i=nan l=1\n");
}

/* A draw of a stream made from numbers (`beta(:x;time)[time]`) is an
 * instruction of the compiled expression that holds it (NX_STREAM): the
 * attribute below is one compiled expression, not small; a key of more
 * numbers than the instruction takes (9), or of a string, leaves the
 * draw to its index record. The values are test_stream_index's. */
static void test_stream_draws_compiled(void **s)
{
    (void)s;
    /* b whole, and c's key of nine numbers, a compiled sequence of its
     * own (c's draw is its index record's, and so is d's: their `+1`s
     * have no number to compile) */
    expect_compiled("!a b=beta(:x;time)[time*2]*2 c=uniform((:k;time;1;2;3;4;5;6;7))[time]+1 "
                    "d=uniform(\"s\";time)[time]+1\n", 0, 2);
    /* in the vector form too (w holds two numbers): a key's numbers and
     * the index floored, as the builtin's seed and the stream's index, so
     * that a and b, and c and d, are the same numbers on every route */
    const char *vsrc = "let w=(1;2)+time\n    t=time*60\n"
                       "!v a=w*0+uniform(:u;t+0.5)[0.5] b=w*0+uniform(:u;t)[0] "
                       "c=w*0+beta(:u;t;1.25)[0] d=w*0+beta(:u;t;1)[0.75]\n";
    char *log;
    char *want = run_one(vsrc, false, false, &log);
    free(log);
    for (int way = 0; way < 4; way++) {
        char *tree = run_one(vsrc, way & 1, way & 2, &log);
        assert_string_equal(tree, want);
        assert_string_equal(log, "");
        free(tree);
        free(log);
    }
    char x[64], y[64], z[64], q[64];
    assert_int_equal(sscanf(want, "!root\n !v a=%63s b=%63s c=%63s d=%63s", x, y, z, q), 4);
    assert_string_equal(x, y);
    assert_string_equal(z, q);
    assert_string_not_equal(x, z);
    free(want);
}

/* map and clamp inside an expression are instructions of the compiled
 * expression (NX_MAP, NX_CLAMP): `map(time, 2, time*3)+1` is one compiled
 * expression, not small. Their values on the four routes, by hand: a
 * scalar's (map(0.1, 0.3, 0.7) is 0.9*0.3 + 0.07, rounded at each step:
 * 0.34), a vector name's (map(v, 2, 6) of 0;0.5;1 is 2;4;6), one number
 * with two vectors (map(0.25, 0;4, 4;8) is 1;5), clamp's max before its
 * min (clamp(x, 1, 0) is 0) and NaN (clamp gives lo, 0), a string
 * (null, the builtin's), and vectors of two lengths (the builtin's
 * repeats: map(0;0.5;1, 0;4, 1) is 0;2.5;1). */
static void test_map_clamp_compiled(void **s)
{
    (void)s;
    expect_compiled("!a b=map(time, 2, time*3)+1 c=clamp(time*2, 0, 1)*2\n", 0, 2);
    expect4("let x=0.25+time\n    y=0.1+time\n    v=(0;0.5;1)+time\n    p=(0;4)+time\n    q=(4;8)+time\n"
            "    z=\"s\"\n"
            "!m a=map(x, 2, 6)*2 b=map(y, 0.3, 0.7)*1 c=map(v, 2, 6)+0 d=map(x, p, q)+0 e=clamp(v*10-3, 0, 1)+0 "
            "f=clamp(x, 1, 0)*1 g=clamp(0/0+time, 0, 1)*1 h=map(z, 1, 2)+0 i=map(v, p, 1)+0 "
            "j=clamp(x*4, x, 0.5)-x\n",
            "!root\n !m a=6 b=0.34 c=2;4;6 d=1;5 e=0;1;1 f=0 g=0 i=0;2.5;1 j=0.25\n");
}

/* noise of a seed and one to four coordinates inside an expression is an
 * instruction of the compiled expression (NX_NOISE): `noise(:s, time)*2`
 * is one compiled expression. The values are test_noise_route's
 * (Flitter's), through exact operations (*2, +0, negation, *1): one to
 * four coordinates, a seed of a symbol and a name, a fraction of a seed
 * floored (0.75 is 0), the vector form (w holds two numbers) and a
 * coordinate that is a vector, a grid, left to the builtin. */
static void test_noise_compiled(void **s)
{
    (void)s;
    expect_compiled("!a b=noise(:s, time)*2\n", 0, 1);
    expect4("let x=0.5+time\n    t=time\n    w=(1;2)+time\n"
            "!n a=noise(:s, x)*2 b=noise(:s, x, 0.25)+0 c=-noise(:s, 0.3+t, 0.6, 0.9) "
            "d=noise(:s, 0.3, 0.6+t, 0.9, 1.2)*1 f=noise(:s;t, x)*1 m=noise(0.75+t, x)*1 "
            "v=w*0+noise(:s, x) g=noise(:s, w*0+x)*1\n",
            "!root\n"
            " !n a=1.2780842711015552 b=0.5816501773837107 c=0.4272253565307444 d=-0.4135278393516153 "
            "f=0.35871384849177557 m=-0.42051860444936273 v=0.6390421355507776;0.6390421355507776 "
            "g=0.6390421355507776;0.6390421355507776\n");
}

/* The first compiled sequence (AST_SEQUENCE, fast == 1) of [n]'s tree. */
static const AstNode *compiled_sequence(const AstNode *n)
{
    if (!n) return NULL;
    if (n->kind == AST_SEQUENCE && n->fast == 1) return n;
    const AstNode *k[3] = {n->a, n->b, n->c};
    for (int i = 0; i < 3; i++) {
        const AstNode *f = compiled_sequence(k[i]);
        if (f) return f;
    }
    for (uint32_t i = 0; i < n->nkids; i++) {
        const AstNode *f = compiled_sequence(n->kids[i]);
        if (f) return f;
    }
    return NULL;
}

static void test_constant_vectors_in_sequences(void **s)
{
    (void)s;
    /* a constant vector of several numbers in a sequence of one-number
     * expressions: its numbers are the sequence's, in order (the
     * simplifier folds `1;0` and `K` into constants; without it they stay
     * sequences and names) */
    expect4("let x=3+time\n    K=-1.5;0/0\n"
            "!c a=x;1;0 b=(2;4);x*2;K c=hsv(x/12;1;0.5) d=K;x\n",
            "!root\n"
            " !c a=3;1;0 b=2;4;6;-1.5;nan c=0.25;0.5;0 d=-1.5;nan;3\n");
    /* white box: the simplified sequence is one compiled expression of
     * six numbers (before, a constant vector in it kept it generic) */
    const char *src = "let K=1;2\n!a b=time;K;time*2;-0.0;0/0\n";
    SymTab *st = symtab_new();
    Buf err = BUF_INIT;
    Globals g = {.simplify = true};
    globals_add(&g, "time");
    g.ndynamic = 1;   /* `time` changes from frame to frame: not folded */
    Program *p = program_load_text("t.fl", src, strlen(src), &g, st, &err);
    assert_non_null(p);
    const AstNode *q = compiled_sequence(p->top);
    assert_non_null(q);
    assert_int_equal(numexpr_outputs(numexpr_of(q)), 6);
    program_release(p);
    globals_free(&g);
    buf_free(&err);
    symtab_free(st);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_arithmetic),
        cmocka_unit_test(test_lookup_and_index),
        cmocka_unit_test(test_lookup_cells),
        cmocka_unit_test(test_stream_index),
        cmocka_unit_test(test_index_in_numbers),
        cmocka_unit_test(test_vector_operators_and_ifs),
        cmocka_unit_test(test_comparisons),
        cmocka_unit_test(test_fallback_shapes),
        cmocka_unit_test(test_builtin_kernels),
        cmocka_unit_test(test_nodes_and_loops),
        cmocka_unit_test(test_limits_same),
        cmocka_unit_test(test_random_expressions),
        cmocka_unit_test(test_vector_expressions),
        cmocka_unit_test(test_lead_names_and_long_vectors),
        cmocka_unit_test(test_attributes_on_literal_nodes),
        cmocka_unit_test(test_new_attributes_on_literal_nodes),
        cmocka_unit_test(test_children_parts),
        cmocka_unit_test(test_noise_route),
        cmocka_unit_test(test_map_clamp_route),
        cmocka_unit_test(test_random_vector_expressions),
        cmocka_unit_test(test_random_compiled_calls),
        cmocka_unit_test(test_loop_numbers),
        cmocka_unit_test(test_random_loops),
        cmocka_unit_test(test_memo),
        cmocka_unit_test(test_long_sequences),
        cmocka_unit_test(test_constant_vectors_in_sequences),
        cmocka_unit_test(test_route_taken),
        cmocka_unit_test(test_small_expressions),
        cmocka_unit_test(test_hypot_in_expressions),
        cmocka_unit_test(test_distance_in_expressions),
        cmocka_unit_test(test_stream_draws_compiled),
        cmocka_unit_test(test_map_clamp_compiled),
        cmocka_unit_test(test_noise_compiled),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
