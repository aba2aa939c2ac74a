/* test_kernel.c: loop kernels (lib/eval/kernel.c) against the routes
 * without them.
 *
 * Each script runs three frames on five routes: the generic tree walk
 * (FLITTER_NOFAST=1), the compiled route without kernels
 * (FLITTER_NOKERNEL=1), and kernels on one, two and three threads
 * (FLITTER_THREADS), each with and without the simplifier. Every route must
 * give the generic route's node tree and log, byte for byte, and the
 * kernel routes must really have run loops with their kernels
 * (rt_kernel_iterations). The scripts cover what a kernel must hand back
 * to the body's own records: names from outside that are not one number,
 * NaN in comparisons, builtins given the wrong shapes, loops of several
 * names whose last iteration is short, nested kernels, a loop run again
 * by a recursive call from its own body, the recursion limit, and loops
 * longer than a window of registers. One case is checked against values
 * worked out by hand.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "kernel.h"
#include "program.h"
#include "runscript.h"
#include "random_calls.h"

/* fl_debug_options.kernel_chunk and kernel_window for the runs (0: the
 * kernel's own sizes). */
static unsigned kernel_chunk = 7;
static unsigned kernel_window = 63;

enum { R_GENERIC, R_NOKERNEL, R_THREADS1, R_THREADS2, R_THREADS3, R_COUNT };

static const char *const route_names[R_COUNT] = {"generic", "no kernel", "kernel, 1 thread",
                                                 "kernel, 2 threads", "kernel, 3 threads"};

/* The tree dump of the last of [frames] frames of [src] on [route], the
 * log in *[log_out] and the kernel's iterations in *[kiters]. */
static char *run_route(const char *src, int frames, bool simplify, int route, char **log_out,
                       uint64_t *kiters)
{
    run_script_debug = (fl_debug_options){.no_fast = route == R_GENERIC, .no_kernel = route == R_NOKERNEL};
    run_script_threads = route == R_THREADS3 ? 3 : route == R_THREADS2 ? 2 : 1;
    /* small chunks and windows, so that small loops (quick under valgrind)
     * are many tasks, taken in any order, and several windows */
    run_script_debug.kernel_chunk = kernel_chunk;
    run_script_debug.kernel_window = kernel_window;
    char *tree = run_script("kernel.fl", src, frames, simplify, log_out, kiters);
    run_script_debug = (fl_debug_options){0};
    run_script_threads = 0;
    return tree;
}

/* Every route of [src] gives the generic route's tree and log in both
 * modes; the kernel routes ran at least [min_kiters] iterations with
 * kernels in each mode. Returns the generic tree of the simplifier's mode
 * (the caller frees it). */
static char *expect_routes(const char *src, int frames, uint64_t min_kiters)
{
    char *keep = NULL;
    for (int simplify = 0; simplify < 2; simplify++) {
        char *log0, *tree0;
        uint64_t k;
        tree0 = run_route(src, frames, simplify, R_GENERIC, &log0, &k);
        assert_int_equal(k, 0);
        for (int route = R_NOKERNEL; route < R_COUNT; route++) {
            char *log;
            char *tree = run_route(src, frames, simplify, route, &log, &k);
            if (strcmp(tree, tree0) != 0 || strcmp(log, log0) != 0)
                fprintf(stderr, "route %s, simplify %d differs\n", route_names[route], simplify);
            assert_string_equal(tree, tree0);
            assert_string_equal(log, log0);
            if (route == R_NOKERNEL) assert_int_equal(k, 0);
            else if (k < min_kiters) fail_msg("route %s, simplify %d: %llu kernel iterations, want %llu",
                                              route_names[route], simplify, (unsigned long long)k,
                                              (unsigned long long)min_kiters);
            free(tree);
            free(log);
        }
        free(log0);
        if (simplify) keep = tree0;
        else free(tree0);
    }
    return keep;
}

/* Values worked out by hand: i*0.5 and i*0.5 + 1 are exact; sin in turns
 * of i*0.25 reduces to quadrant i%4 with a zero remainder, so it is
 * sin(+0) = 0, cos(0) = 1, -sin(+0) = -0 or -cos(0) = -1 (LANGUAGE.md
 * §5.2); hsv(h;0;v) is v;v;v (no saturation: lightness v, both hue
 * bounds v). The tree checked is the simplifier's mode's. The loop is long enough for its kernel; `time` is 0 in the
 * first frame. */
static void test_hand_values(void **s)
{
    (void)s;
    char *tree = expect_routes("let n=400+floor(time)\n!g\n    for i in ..n\n        let p=i*0.5+time\n"
                               "        !d x=p;p+1 y=sin(p*0.5) c=hsv(time;0;p/1000) t=p>1\n",
                               1, 400);
    Buf want = BUF_INIT;
    buf_puts(&want, "!root\n !g\n");
    /* (trees write -0 as 0) */
    static const char *const quadrant[] = {"0", "1", "0", "-1"};
    for (int i = 0; i < 400; i++) {
        /* the simplifier's x/k is x*(1/k) (Flitter's rule, LANGUAGE.md
         * §4.17): p/1000 is p*0.001 */
        double p = i * 0.5, v = p * (1.0 / 1000);
        char c[32];
        /* the shortest text that reads back as v, as values are written */
        for (int d = 1; d <= 17; d++) {
            snprintf(c, sizeof c, "%.*g", d, v);
            if (strtod(c, NULL) == v) break;
        }
        buf_printf(&want, "  !d x=%g;%g y=%s c=%s;%s;%s t=%d\n", p, p + 1, quadrant[i % 4], c, c, c, p > 1);
    }
    assert_string_equal(tree, buf_cstr(&want));
    free(tree);
    buf_free(&want);
}

/* Lets, element functions and hsv/hsl calls the kernel computes, in a loop
 * that stays a loop (its length depends on `time`), over three frames. */
static void test_lets_and_calls(void **s)
{
    (void)s;
    free(expect_routes("let n=300+floor(time)\n"
                       "!g\n"
                       "    for i in ..n\n"
                       "        let p=time+i*0.01\n"
                       "            q=p*2\n"
                       "        !dot x=(i+0.5)*2+8*sin(p);(q+1)*cos(p) r=2+sin(time*2+i*i/100) "
                       "c=hsv(time/10+i/n;0.8;0.5+0.5*sin(p)) s=time>0 k=hsl(i/n;0.5;q) "
                       "m=i//7 o=i%7 w=q**0.5 z=(-i)**0.5\n",
                       3, 3 * 300));
}

/* A `let` of a kernel's number is not made while only the kernel's
 * records read it (C_KLET), nor a loop name; read by anything else (the
 * name itself, a sequence with a string, an if-else, a later binding of
 * the same `let`), it is. */
static void test_lets_read_elsewhere(void **s)
{
    (void)s;
    free(expect_routes("let n=200+floor(time)\n"
                       "!g\n"
                       "    for i in ..n\n"
                       "        let p=i*0.5+time\n"
                       "            q=i*2+time\n"
                       "            r=i+time\n"
                       "            u=i-time\n"
                       "            w=q+1\n"
                       "        !a x=p y=sin(q) z=(\"a\";r) v=(u if i%2 else -u) m=w*2 k=q*2\n"
                       "    for j in ..n\n"
                       "        !b x=j*2 y=(\"b\";j)\n"
                       "    for j in ..n\n"
                       "        !c x=j*2 y=(j if j%2 else -j)\n",
                       2, 2 * 3 * 200));
}

/* Memoized expressions of engine names in a kernel's body keep their
 * value for the loop's run; a NaN result is never kept (two NaN vectors
 * are not the same vector: c is 0, §3.6). */
static void test_memo(void **s)
{
    (void)s;
    char *tree = expect_routes("let n=200+floor(time)\n"
                               "!g\n"
                               "    for i in ..n\n"
                               "        let p=time+0/0\n"
                               "            q=time+0/0\n"
                               "        !m a=sin(time+0.25) b=time>0 c=p==q d=(time+0/0) e=time*0.5 f=i*2\n"
                               "        !k a=sin(time+0.25) b=time>0 c=p==q e=time*0.5 g=(time*0.5)+i\n",
                               3, 3 * 200);
    /* frame 3: time 2/60 */
    assert_non_null(strstr(tree, " b=1 c=0 d=nan e=0.016666666666666666 f=398\n"));
    free(tree);
}

/* How many times [needle] occurs in [tree]. */
static int occurrences(const char *tree, const char *needle)
{
    int n = 0;
    for (const char *t = tree; (t = strstr(t, needle)) != NULL; t++) n++;
    return n;
}

/* An `if`/`elif`/`else` in a kernel's body (a C_IF of the compiled route)
 * around nodes of the kernel's numbers and of memoized engine names: the
 * lets read only under it, in its conditions and in its nodes' attributes,
 * keep their values on every route. Counted by hand in frame 3 (time
 * 2/60, n 200): i%3 == 0 gives !a (i = 0, 3, ..., 198: 67 nodes), else
 * i*0.5 + time > 50 gives !b (i = 100..199: 67 of them) and the rest !c
 * (i = 1..98: 66). */
static void test_if_around_nodes(void **s)
{
    (void)s;
    char *tree = expect_routes("let n=200+floor(time)\n"
                               "!g\n"
                               "    for i in ..n\n"
                               "        let p=i*0.5+time\n"
                               "            q=i*2+time\n"
                               "            r=i%3\n"
                               "        if r == 0\n"
                               "            !a x=p y=sin(q) m=time*0.5\n"
                               "        elif p > 50\n"
                               "            !b x=q*2 z=(p if i%2 else -p)\n"
                               "        else\n"
                               "            !c x=p+q w=time*0.5+i\n",
                               3, 3 * 200);
    assert_int_equal(occurrences(tree, "\n  !a "), 67);
    assert_int_equal(occurrences(tree, "\n  !b "), 67);
    assert_int_equal(occurrences(tree, "\n  !c "), 66);
    assert_non_null(strstr(tree, "\n  !a x=0.03333333333333333 "));   /* i = 0: p is time */
    free(tree);
}

/* `v[x]` of one number in a kernel's body (numexpr.c NX_INDEX in the
 * kernel's lanes): a constant vector (a), a constant stream (b, f), a NaN
 * index (e: INT32_MIN, which wraps to 2 of 5); a name's vector (c) is
 * left to the body's own records. By hand, frame 3 (n 200): a is i%5 + 1,
 * 40 nodes of each; e is 3 everywhere; two draws of a stream 200 apart
 * differ (f is 0); g keeps a kernel without the simplifier too (whose
 * unfolded vectors and calls it does not take). */
static void test_index_in_kernels(void **s)
{
    (void)s;
    char *tree = expect_routes("let n=200+floor(time)\n"
                               "    r=(1;2;3;4;5)*(1+time)\n"
                               "!g\n"
                               "    for i in ..n\n"
                               "        !d a=(1;2;3;4;5)[i] b=uniform(:u)[i]*2 c=r[i] e=(1;2;3;4;5)[i*0.5+0/0] "
                               "f=(uniform(:u)[i]==uniform(:u)[i+200]) g=i*2\n",
                               3, 3 * 200);
    for (int k = 1; k <= 5; k++) {
        char a[16];
        snprintf(a, sizeof a, "\n  !d a=%d ", k);
        assert_int_equal(occurrences(tree, a), 40);
    }
    assert_int_equal(occurrences(tree, " e=3 f=0 g="), 200);
    assert_non_null(strstr(tree, "\n  !d a=1 b=1.5807589083341713 c=1.0333333333333334 e=3 f=0 g=0\n"));
    free(tree);
}

/* hypot of one argument in a kernel's registers (NX_HYPOT, in the `let`s
 * p and q; an attribute's own call is C_KCALL's, f): the square root of
 * the square, which overflows to inf (i*1e200) and underflows to 0
 * (i*1e-200) where a magnitude would not, on every route. (A vector's
 * sum of squares is test_fastroute's test_hypot_in_expressions.) */
static void test_hypot_in_kernels(void **s)
{
    (void)s;
    char *tree = expect_routes("let n=60+floor(time)\n"
                               "!g\n"
                               "    for i in ..n\n"
                               "        let d=hypot(i-3+time) p=hypot(i*1e200-time) q=hypot(i*1e-200+time)\n"
                               "        !d a=p b=d*2 c=q f=hypot(i*1e200+time)\n",
                               1, 60);
    Buf want = BUF_INIT;
    buf_puts(&want, "!root\n !g\n");
    for (int i = 0; i < 60; i++)
        buf_printf(&want, "  !d a=%s b=%d c=0 f=%s\n", i ? "inf" : "0", 2 * abs(i - 3), i ? "inf" : "0");
    assert_string_equal(tree, buf_cstr(&want));
    buf_free(&want);
    free(tree);
}

/* Draws of streams made from numbers (`uniform(:u;i)[t]`, NX_STREAM) in
 * a kernel's registers, in a loop whose range the simplifier cannot
 * unroll: the same numbers on every route; a key's numbers are floored
 * (the builtin's seed), so (:u;i+0.5) is the stream of (:u;i), and an
 * index too (0.75 is 0): f is 1 in every iteration. */
static void test_stream_draws_in_kernels(void **s)
{
    (void)s;
    char *tree = expect_routes("let n=50+floor(time)\n"
                               "!g\n"
                               "    for i in ..n\n"
                               "        let u=uniform(:u;i)[time*60+0.5] b=beta(:b;i;2)[i+0.25]\n"
                               "        !d a=u c=b*2 e=normal(i*0.5)[i]+1 f=uniform(:u;i)[0]==uniform(:u;i+0.5)[0.75]\n",
                               2, 50);
    assert_int_equal(occurrences(tree, " f=1\n"), 50);
    assert_int_equal(occurrences(tree, "  !d a="), 50);
    free(tree);
}

/* map and clamp in a kernel's registers (NX_MAP, NX_CLAMP), in a loop
 * the simplifier cannot unroll: map(i/64, 2, 6) is 2 + i/16 exactly
 * ((1 - x)*2 + x*6 with x a multiple of 1/64), clamp(i - 10, 0, 20)
 * holds i - 10 between 0 and 20, and a NaN is clamped to lo. */
static void test_map_clamp_in_kernels(void **s)
{
    (void)s;
    char *tree = expect_routes("let n=40+floor(time)\n"
                               "!g\n"
                               "    for i in ..n\n"
                               "        let m=map(i/64+time, 2, 6) c=clamp(i-10+time, 0, 20)\n"
                               "        !d a=m*2 b=c+1 e=clamp(0/0+i, 0, 1)+1\n",
                               1, 40);
    Buf want = BUF_INIT;
    buf_puts(&want, "!root\n !g\n");
    for (int i = 0; i < 40; i++) {
        int c = i - 10 < 0 ? 0 : i - 10 > 20 ? 20 : i - 10;
        buf_printf(&want, "  !d a=%.17g b=%d e=1\n", 2 * (2 + i / 16.0), c + 1);
    }
    assert_string_equal(tree, buf_cstr(&want));
    buf_free(&want);
    free(tree);
}

/* noise in a loop with a kernel: the kernel leaves it to the body's
 * record (the runtime's table of permutations is not for other threads),
 * and the body's numbers are the same on every route; noise(:s, 0.5) is
 * Flitter's 0.6390421355507776 (test_fastroute's test_noise_route). */
static void test_noise_beside_kernels(void **s)
{
    (void)s;
    char *tree = expect_routes("let n=40+floor(time)\n"
                               "!g\n"
                               "    for i in ..n\n"
                               "        let a=noise(:s, i*0.25+time)*1 b=i*2+time\n"
                               "        !d a=a b=b\n",
                               1, 40);
    assert_non_null(strstr(tree, "\n  !d a=0.6390421355507776 b=4\n"));
    assert_int_equal(occurrences(tree, "  !d a="), 40);
    free(tree);
}

/* Random expressions with the calls compiled into them (random_calls.h)
 * of numbers (NaN among them) as attributes in a loop the simplifier
 * cannot unroll: every route,
 * kernels on 1 to 3 threads among them, gives the generic route's tree
 * and log, in both modes. */
static void test_random_calls_in_kernels(void **s)
{
    (void)s;
    uint32_t st = 2024;
    for (int round = 0; round < 6; round++) {
        Buf b = BUF_INIT;
        /* p, q and w one number each here (a vector from outside is no
         * register: test_fastroute's rounds have them as vectors) */
        buf_puts(&b, "let n=30+floor(time)\n    x=1.25+time\n    p=-2+time\n"
                     "    q=4*(1+time)\n    w=(0/0)+time\n    mz=-time\n    s=\"a\"\n"
                     "!g\n    for i in ..n\n        let y=i*0.5+x\n        !e");
        for (int k = 0; k < 12; k++) {
            buf_printf(&b, " a%d=", k);
            random_cexpr(&b, &st, 3);
        }
        buf_puts(&b, "\n");
        free(expect_routes(buf_cstr(&b), 2, 0));
        buf_free(&b);
    }
}

/* What the kernel cannot compute goes back to the body's own records:
 * names from outside that are a vector, null, a string or NaN; NaN in
 * comparisons (the identity rule of §3.6); builtins given other shapes. */
static void test_fallbacks(void **s)
{
    (void)s;
    free(expect_routes("let n=200+floor(time)\n"
                       "    v=(1;2)+time\n"
                       "    z=null\n"
                       "    s=\"a\"\n"
                       "    h=0/0+time\n"
                       "!g\n"
                       "    for i in ..n\n"
                       "        let c=h>i\n"
                       "            e=(i/(i%5)) > 1\n"
                       "            f=c+1\n"
                       "        !f a=v*i b=z+i c=c+1 d=s+i e=h==h f=f*2 g=hsv(v) h=hsv(v;i) "
                       "k=hsv(i;1;1;1) m=e o=hsl(i;i) p=hsv(i/n) q=(h+i)<(h+i) r=e+i\n",
                       3, 3 * 200));
    /* names from outside that are not one number, with nothing failing
     * in the iteration before them */
    free(expect_routes("let n=200+floor(time)\n"
                       "    v=(1;2)+time\n"
                       "    s=\"a\"\n"
                       "!g\n"
                       "    for i in ..n\n"
                       "        !f a=i*2 b=v*i c=s+i d=v+i*0.5 e=sin(i*0.01)\n",
                       3, 3 * 200));
}

/* Loops of several names over a source whose length is no multiple of
 * theirs: the last iteration's missing names are null; nodes of kernel
 * numbers alone (C_KNODE) in such an iteration, and in iterations where
 * a comparison meets a NaN, are built as the body's records build them. */
static void test_several_names(void **s)
{
    (void)s;
    free(expect_routes("let n=301+floor(time)\n"
                       "    src=(k*0.5+time for k in ..n)\n"
                       "!g\n"
                       "    for a;b;c in src\n"
                       "        let d=a*b\n"
                       "        !t x=a+b*c y=sin(a)+cos(b) z=c w=d+c\n"
                       "        !u x=a*2 y=b+1 z=hsv(a;b;c)\n"
                       "        !v x=(a/(a%3)) > 1 y=a*3\n",
                       2, 2 * 100));
}

/* [src]'s routes agree (expect_routes, [frames] frames, at least
 * [min_kiters] kernel iterations), and the kernel's runs on two threads
 * ran iterations as a straight body (kernel.c, straight_iteration): at
 * least min_straight[simplify] in each mode, none where it is 0, any
 * number where it is -1. */
static void expect_straight(const char *src, int frames, uint64_t min_kiters, const int64_t min_straight[2])
{
    free(expect_routes(src, frames, min_kiters));
    for (int simplify = 0; simplify < 2; simplify++) {
        char *log;
        uint64_t k;
        free(run_route(src, frames, simplify, R_THREADS2, &log, &k));
        free(log);
        const int64_t want = min_straight[simplify];
        if (want > 0 ? run_script_straight < (uint64_t)want : want == 0 && run_script_straight != 0)
            fail_msg("simplify %d: %llu straight iterations, want %s %lld", simplify,
                     (unsigned long long)run_script_straight, want ? "at least" : "exactly", (long long)want);
    }
}

/* Bodies of nodes of kernel numbers and memo values alone, under `let`s
 * the kernel's records alone read, run as their nodes without their
 * records (kernel.c, straight_iteration): several nodes and memo values,
 * an iteration a NaN comparison sends back to the records (i = 7, each
 * frame), the copies of an unrolled inner loop, and bodies that are not
 * straight: a `let` another record reads, a conditional node, a node
 * with a child. */
static void test_straight(void **s)
{
    (void)s;
    expect_straight("let n=60+floor(time)\n"
                    "!g\n"
                    "    for i in ..n\n"
                    "        let p=i*0.5+time\n"
                    "        !a x=p+1 y=sin(p) t=time>0 u=time*2\n"
                    "        let q=p*2\n"
                    "            r=cos(q)\n"
                    "        !b x=q-1;r*2 c=hsv(p*0.1;0.5;p)\n"
                    "        !c w=q+p v=(i-7)/(i-7)>0\n",
                    3, 3 * 60, (const int64_t[]){3 * 60 - 3, 3 * 60 - 3});
    expect_straight("!g\n"
                    "    for i in ..50\n"
                    "        !a x=i*time\n",
                    3, 2 * 50, (const int64_t[]){2 * 50, 2 * 50});
    /* the simplifier unrolls the literal inner range: the outer loop's
     * body is the three copies (without it, the inner loops are too
     * short for their kernels) */
    expect_straight("let n=40+floor(time)\n"
                    "!g\n"
                    "    for i in ..n\n"
                    "        for j in ..3\n"
                    "            !p x=i*j+time y=sin(i*0.1+j*time)\n",
                    3, 0, (const int64_t[]){-1, 3 * 40});
    expect_straight("let n=40+floor(time)\n"
                    "!g\n"
                    "    for i in ..n\n"
                    "        let p=i*0.5+time\n"
                    "        !a x=p\n"
                    "        !b y=p n=\"a\" if time>0 else 1\n",
                    3, 3 * 40, (const int64_t[]){0, 0});
    expect_straight("let n=40+floor(time)\n"
                    "!g\n"
                    "    for i in ..n\n"
                    "        !a x=i+time\n"
                    "        !b y=i*time if i%2 else null\n",
                    3, 3 * 40, (const int64_t[]){0, 0});
    expect_straight("let n=40+floor(time)\n"
                    "!g\n"
                    "    for i in ..n\n"
                    "        !a x=i+time\n"
                    "            !b y=i*time\n",
                    3, 3 * 40, (const int64_t[]){0, 0});
}

/* A kernel inside a kernel's body: the inner loop reads the outer one's
 * `let` as a name from outside, afresh each time it starts. */
static void test_nested(void **s)
{
    (void)s;
    free(expect_routes("let n=30+floor(time)\n"
                       "!g\n"
                       "    for i in ..n\n"
                       "        let u=i*0.1+time\n"
                       "        !row u=u\n"
                       "        for j in ..n\n"
                       "            !p x=u+j y=sin(u*j) z=hsv(u;j/n;0.5)\n",
                       2, 2 * 30 * 30));
}

/* A recursive call from a loop's body runs the same loop again while its
 * kernel is running; deep enough, the recursion limit's message. */
static void test_recursion(void **s)
{
    (void)s;
    free(expect_routes("func f(d)\n"
                       "    for i in ..(100+floor(time))\n"
                       "        let p=i*d+time\n"
                       "        !r x=p*2 y=sin(p) d=d\n"
                       "        f(d-1) if d > 0 and i == 3 else null\n"
                       "!g << f(3)\n",
                       2, 2 * 400));
    /* the run again is too short for the kernel: it runs as eval_for, its
     * C_KNUM records computing their own numbers, not the kernel's */
    free(expect_routes("func f(d)\n"
                       "    for i in ..(100+floor(time) if d == 0 else 3)\n"
                       "        let p=i*(d+1)+time\n"
                       "        !r x=p*2 y=sin(p) d=d\n"
                       "        f(d+1) if d < 2 and i == 1 else null\n"
                       "!g << f(0)\n",
                       2, 2 * 100));
    free(expect_routes("func f(d)\n"
                       "    for i in ..(300+floor(time))\n"
                       "        let p=i*d+time\n"
                       "        !r x=p*2\n"
                       "        f(d+1) if i == 299 else null\n"
                       "!g << f(0)\n",
                       1, 300));
}

/* The depth limit (MAX_EVAL_DEPTH) reached around a kernel loop's body:
 * a `let` of a memoized expression (the same expression twice, so a
 * C_MEMO) is left unmade only where its record would not overflow, so
 * the routes agree on whether the frame overflows. Recursion of [d]
 * levels of 30 nested if-elses, then [p] more calls, then the loop: a
 * sweep of [p] whose depths straddle the limit inside the loop. */
static void test_depth_limit(void **s)
{
    (void)s;
    int overflowed = 0, whole = 0, straight = 0;
    for (int p = 0; p <= 12; p++) {
        Buf src = BUF_INIT;
        const char *e = "time*1.5+0.25";
        Buf memo = BUF_INIT;
        buf_puts(&memo, e);
        for (int k = 0; k < 13; k++) {
            Buf t = BUF_INIT;
            buf_printf(&t, "(%s)*2+1", buf_cstr(&memo));
            buf_free(&memo);
            memo = t;
        }
        buf_printf(&src, "func g()\n    for i in ..(5+floor(time))\n        let m=%s\n            q=%s\n"
                         "        !d x=m+i y=q+i\n",
                   buf_cstr(&memo), buf_cstr(&memo));
        buf_free(&memo);
        buf_puts(&src, "func h(p)\n    h(p-1) if p > 0 else g()\nfunc f(d)\n    ");
        Buf call = BUF_INIT;
        buf_puts(&call, "f(d-1)");
        for (int k = 0; k < 30; k++) {
            Buf t = BUF_INIT;
            buf_printf(&t, "(%s if d >= %d else null)", buf_cstr(&call), -k - 1);
            buf_free(&call);
            call = t;
        }
        buf_printf(&src, "%s if d > 0 else h(%d)\n!g << f(362)\n", buf_cstr(&call), p);
        buf_free(&call);
        char *log0, *log1;
        uint64_t k0, k1;
        char *t0 = run_route(buf_cstr(&src), 1, false, R_GENERIC, &log0, &k0);
        char *t1 = run_route(buf_cstr(&src), 1, false, R_THREADS2, &log1, &k1);
        straight += run_script_straight > 0;
        if (strcmp(t0, t1) != 0 || strcmp(log0, log1) != 0) fprintf(stderr, "p = %d differs\n", p);
        assert_string_equal(t1, t0);
        assert_string_equal(log1, log0);
        if (strstr(log0, "Stack overflow")) overflowed++;
        else whole++;
        free(t0);
        free(t1);
        free(log0);
        free(log1);
        buf_free(&src);
    }
    /* the sweep crosses the limit, and the loop's body is straight
     * (kernel.c, straight_iteration) in some of the runs */
    assert_true(overflowed > 0 && whole > 0);
    assert_true(straight > 0);
}

/* Budgets from 5,800 to 7,400 KiB for [frames] frames of [src], with or
 * without transient trees: the kernel route on two threads gives
 * FLITTER_NOKERNEL's tree and log at each; some budgets run out and some
 * fit (when fitting, at least [min_kiters] iterations ran with kernels). */
static void budget_sweep(const char *src, int frames, bool transient, uint64_t min_kiters)
{
    int out = 0, fits = 0;
    run_script_transient = transient;
    for (size_t kb = 5800; kb <= 7400; kb += 200) {
        run_script_budget = kb << 10;
        char *log0, *log1;
        uint64_t k0, k1;
        char *t0 = run_route(src, frames, true, R_NOKERNEL, &log0, &k0);
        char *t1 = run_route(src, frames, true, R_THREADS2, &log1, &k1);
        if (strcmp(t0, t1) != 0 || strcmp(log0, log1) != 0)
            fprintf(stderr, "transient %d, budget %zu KiB differs\n", transient, kb);
        assert_string_equal(t1, t0);
        assert_string_equal(log1, log0);
        if (strstr(log0, "Out of memory")) out++;
        else fits++, assert_true(k1 >= min_kiters);
        free(t0);
        free(t1);
        free(log0);
        free(log1);
    }
    run_script_transient = false;
    run_script_budget = 0;
    assert_true(out > 0 && fits > 0);
}

/* A memory budget (--max-memory) that runs out in a kernel loop's body
 * runs out where it does without kernels: the registers are left out of
 * the budget (kernel.h KernelScratch). A sweep of budgets across the
 * frame's need; the runs must agree with FLITTER_NOKERNEL's, and some
 * must run out. */
static void test_budget(void **s)
{
    (void)s;
    const char *src = "let n=20000+floor(time)\n"
                      "!g\n"
                      "    for i in ..n\n"
                      "        let p=i*0.5+time\n"
                      "        !d x=p y=sin(p) z=cos(p)*2\n";
    /* the kernel's own window: a block of about 1 MB of registers */
    kernel_chunk = kernel_window = 0;
    budget_sweep(src, 1, false, 20000);
    /* with transient trees (fl_options.transient_tree), over three frames:
     * the last tree's blocks serve the next frame on every route alike */
    budget_sweep(src, 3, true, 0);
    kernel_chunk = 7;
    kernel_window = 63;
}

/* The simplifier's loop forms (literal ranges, template passes): nested
 * literal loops as canvas10k has them. */
static void test_loop_forms(void **s)
{
    (void)s;
    free(expect_routes("let W=640\n    N=40\n"
                       "!window size=W;W\n"
                       "    !canvas\n"
                       "        for i in ..N\n"
                       "            for j in ..N\n"
                       "                let phase=time+i*0.07+j*0.05\n"
                       "                !ellipse point=(i+0.5)*W/N+8*sin(phase);(j+0.5)*W/N+8*cos(phase) "
                       "radius=2+sin(time*2+i*j/100) fill=hsv(time/10+i/N;0.8;0.5+0.5*sin(phase)) "
                       "stroke=time>0\n",
                       3, 3 * 39));
}

/* A loop longer than one window of registers (here 63 iterations; the
 * first and the last window's last chunk short): several windows, one
 * after the other; and the same with the windows of K_WINDOW_BYTES. */
static void test_windows(void **s)
{
    (void)s;
    free(expect_routes("let n=1000+floor(time)\n"
                       "!g\n"
                       "    for i in ..n\n"
                       "        !w x=i*0.25+time y=sin(i/n) z=i%3\n",
                       1, 1000));
    /* 60 numbers an iteration, about 600 bytes of registers: the
     * windows of K_WINDOW_BYTES take about 3,500 iterations each */
    Buf src = BUF_INIT;
    buf_puts(&src, "let n=8000+floor(time)\n!g\n    for i in ..n\n        !w");
    for (int a = 0; a < 60; a++) buf_printf(&src, " a%d=i*%d+time", a, a + 1);
    buf_puts(&src, "\n");
    kernel_window = 0;
    free(expect_routes(buf_cstr(&src), 1, 8000));
    kernel_window = 63;
    buf_free(&src);
}

/* FLITTER_NOKERNEL leaves loops without kernels (AstNode.fast 3). */
static int count_kernels(const AstNode *n)
{
    if (!n) return 0;
    int c = n->kind == AST_FOR && n->fast == 3;
    c += count_kernels(n->a) + count_kernels(n->b) + count_kernels(n->c);
    for (uint32_t i = 0; i < n->nkids; i++) c += count_kernels(n->kids[i]);
    return c;
}

/* The calls the kernels of [n]'s loops share (kernel_shared_calls). */
static uint32_t count_shared(const AstNode *n)
{
    if (!n) return 0;
    uint32_t c = kernel_shared_calls(n);
    c += count_shared(n->a) + count_shared(n->b) + count_shared(n->c);
    for (uint32_t i = 0; i < n->nkids; i++) c += count_shared(n->kids[i]);
    return c;
}

/* The calls shared by the kernels of [src] as a program loaded alone
 * (no runtime: the engine names such as `time` are not known, so the
 * loop must not read them). */
static uint32_t shared_calls(const char *src)
{
    SymTab *st = symtab_new();
    Buf err = BUF_INIT;
    Program *p = program_load_text("t.fl", src, strlen(src), NULL, st, &err);
    assert_non_null(p);
    uint32_t n = count_shared(p->top);
    program_release(p);
    buf_free(&err);
    symtab_free(st);
    return n;
}

/* An element function called on the same register by several of an
 * iteration's expressions, or twice by one, is computed once, and sin and
 * cos of one register together (kernel.c, share_calls): how many calls
 * are, and that every route still gives the generic route's nodes. The
 * calls: sin(p) in three attributes, one of them an hsv argument (a
 * builtin's kernel that names its argument's expression by index, which
 * the new expressions move), sin(p)*sin(p) in one, cos(q) in two; sin(q)
 * and cos(p) once each (each made with its partner); an iteration whose
 * comparison meets a NaN (i = 5), whose registers are computed again one
 * expression at a time; shared calls of registers that do not hold their
 * numbers; sin and cos of angles of both signs, on the ties of their
 * quadrants (eighths of a turn) and where t + 0.25 rounds (sincos_t then
 * calls both). */
static void test_shared_calls(void **s)
{
    (void)s;
    static const struct {
        const char *src;
        uint32_t shared;
        int frames;
        uint64_t kiters;
    } cases[] = {
        {"let n=80+floor(time)\n"
         "!g\n"
         "    for i in ..n\n"
         "        let p=i*0.25+n*0.01\n"
         "            q=i*0.5\n"
         "        !a x=sin(p)+1 y=cos(q)*2 z=sin(q)\n"
         "        !b c=hsv(sin(p);0.5;cos(q)) w=sin(p)*sin(p) v=cos(p) u=(i-5)/(i-5)>0\n",
         4, 3, 3 * 80},
        /* shared calls whose register does not hold its number: a name
         * from outside that is null in odd frames, and the last iteration
         * of a loop of two names over an odd count (b missing), each
         * computed again one expression at a time, the shared register's
         * inputs checked */
        {"let k=(frame*0.5 if frame%2==0 else null)\n"
         "    n=301+frame%2\n"
         "!g\n"
         "    for a;b in ..n\n"
         "        !a x=sin(b)+a y=sin(b)*a\n"
         "        !c x=sin(k)+a y=sin(k)*a z=cos(k)\n",
         3, 4, 4 * 150},
        {"let n=200+floor(time)\n"
         "!g\n"
         "    for i in ..n\n"
         "        let p=(i-100)*0.125+(n-200)*0.01\n"
         "            q=0.75-2*(i%2)+(i-100)/9007199254740992\n"
         "        !a x=sin(p) y=cos(p) z=cos(q)*sin(q)\n",
         4, 3, 3 * 200},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        assert_int_equal(shared_calls(cases[i].src), cases[i].shared);
        free(expect_routes(cases[i].src, cases[i].frames, cases[i].kiters));
    }
    assert_int_equal(shared_calls("let n=9+time\nfor i in ..n\n    !a x=sin(i) y=cos(i) z=sin(i*2)\n"), 2);
    assert_int_equal(shared_calls("let n=9+time\nfor i in ..n\n    !a x=sin(i) y=cos(i*2) z=sin(i*3)\n"), 0);
}

/* The library reads no environment: with FLITTER_NOFAST and
 * FLITTER_NOKERNEL set (the flitter command's names for the routes), a
 * runtime with the default options still runs its loops through kernels;
 * with fl_debug_options.no_kernel or no_fast it runs none, with the same
 * tree. */
static void test_routes_from_options_only(void **s)
{
    (void)s;
    const char *src = "let n=40+floor(time)\nfor i in ..n\n    !a x=i*2+sin(i*time)\n";
    setenv("FLITTER_NOFAST", "1", 1);
    setenv("FLITTER_NOKERNEL", "1", 1);
    char *log[3], *tree[3];
    uint64_t k[3];
    run_script_debug = (fl_debug_options){.kernel_chunk = 7};   /* small loops take kernels */
    tree[0] = run_script("env.fl", src, 2, true, &log[0], &k[0]);
    unsetenv("FLITTER_NOFAST");
    unsetenv("FLITTER_NOKERNEL");
    run_script_debug.no_kernel = true;
    tree[1] = run_script("env.fl", src, 2, true, &log[1], &k[1]);
    run_script_debug = (fl_debug_options){.no_fast = true, .kernel_chunk = 7};
    tree[2] = run_script("env.fl", src, 2, true, &log[2], &k[2]);
    run_script_debug = (fl_debug_options){0};
    assert_int_equal(k[0], 80);
    assert_int_equal(k[1], 0);
    assert_int_equal(k[2], 0);
    for (int i = 0; i < 3; i++) {
        assert_string_equal(tree[i], tree[0]);
        assert_string_equal(log[i], "");
    }
    for (int i = 0; i < 3; i++) {
        free(tree[i]);
        free(log[i]);
    }
}

static void test_compiled(void **s)
{
    (void)s;
    const char *src = "let n=9+time\nfor i in ..n\n    !a x=i*2+sin(i)\n";
    SymTab *st = symtab_new();
    Buf err = BUF_INIT;
    Program *p = program_load_text("t.fl", src, strlen(src), NULL, st, &err);
    assert_non_null(p);
    assert_int_equal(count_kernels(p->top), 1);
    program_release(p);
    Globals no_kernels = {.routes.kernel.off = true};
    p = program_load_text("t.fl", src, strlen(src), &no_kernels, st, &err);
    assert_non_null(p);
    assert_int_equal(count_kernels(p->top), 0);
    program_release(p);
    buf_free(&err);
    symtab_free(st);
}

/* {===== nodes refilled in place (kernel.h KNodeCache) */

#define REUSE_FRAMES 9

/* Each of [REUSE_FRAMES] frames' tree and state of [src] in trees[], its log in
 * *[log_out], with nodes refilled (fl_debug_options.no_kernel_reuse false) or not, on two
 * threads, and how many were refilled in *[reused]. With [hold], the
 * trees of frames 0 and 3 are held (as an embedder holding fl_tree's
 * root would) until the last frame and must then read as they did. With
 * [transient], the runtime releases each tree when the next frame starts
 * (fl_options.transient_tree), and the last frame's nodes are refilled. */
static void reuse_run(const char *src, bool simplify, bool reuse, bool hold, bool transient, char **trees,
                      char **log_out, uint64_t *reused)
{
    run_script_transient = transient;
    run_script_debug = (fl_debug_options){.no_kernel_reuse = !reuse, .kernel_chunk = 7, .kernel_window = 63};
    run_script_threads = 2;
    char *log = NULL;
    size_t loglen;
    FILE *lf = open_memstream(&log, &loglen);
    RtStreams streams = {lf, lf};
    fl_runtime *rt = script_runtime("reuse.fl", src, simplify, &streams);
    Node *held[REUSE_FRAMES] = {0};
    size_t tree_len[REUSE_FRAMES];
    for (int f = 0; f < REUSE_FRAMES; f++) {
        fl_step(rt);
        Buf t = BUF_INIT;
        fmt_tree(&t, rt_root(rt), rt_symbols(rt));
        tree_len[f] = t.len;
        fmt_state_dump(&t, rt_state(rt), f, 0.0, rt_symbols(rt));
        trees[f] = strdup(buf_cstr(&t));
        buf_free(&t);
        if (hold && (f == 0 || f == 3)) held[f] = node_retain((Node *)rt_root(rt));
    }
    for (int f = 0; f < REUSE_FRAMES; f++) {
        if (!held[f]) continue;
        Buf t = BUF_INIT;
        fmt_tree(&t, held[f], rt_symbols(rt));
        assert_true(t.len == tree_len[f] && memcmp(buf_cstr(&t), trees[f], t.len) == 0);
        buf_free(&t);
        node_release(held[f]);
    }
    *reused = rt_kernel_reused(rt);
    fl_free(rt);
    fclose(lf);
    *log_out = log;
    run_script_transient = false;
    run_script_debug = (fl_debug_options){0};
    run_script_threads = 0;
}

/* Every frame's tree and the log with nodes refilled, with and without
 * earlier trees held, with and without transient trees, equal to those of
 * nodes built anew, in both modes; nodes were refilled (at least
 * [min_reused]), and with transient trees as many as without, or more
 * when [more] (the last frame's nodes are refilled, so the second frame
 * builds none; not where a physics system holds them). */
static void expect_reuse(const char *src, uint64_t min_reused, bool more)
{
    for (int simplify = 0; simplify < 2; simplify++) {
        char *want[REUSE_FRAMES], *got[REUSE_FRAMES], *log0, *log;
        uint64_t reused, reused_kept = 0;
        reuse_run(src, simplify, false, false, false, want, &log0, &reused);
        assert_int_equal(reused, 0);
        for (int run = 0; run < 4; run++) {
            const bool hold = run & 1, transient = run >= 2;
            reuse_run(src, simplify, true, hold, transient, got, &log, &reused);
            if (reused < min_reused)
                fail_msg("simplify %d, hold %d, transient %d: %llu nodes refilled, want %llu", simplify, hold,
                         transient, (unsigned long long)reused, (unsigned long long)min_reused);
            if (run == 0) reused_kept = reused;
            if (run == 2 && (more ? reused <= reused_kept : reused < reused_kept))
                fail_msg("simplify %d: %llu nodes refilled with transient trees, %llu without", simplify,
                         (unsigned long long)reused, (unsigned long long)reused_kept);
            for (int f = 0; f < REUSE_FRAMES; f++) {
                if (strcmp(got[f], want[f]) != 0)
                    fprintf(stderr, "simplify %d, hold %d, transient %d: frame %d differs\n", simplify, hold,
                            transient, f);
                assert_string_equal(got[f], want[f]);
                free(got[f]);
            }
            assert_string_equal(log, log0);
            free(log);
        }
        for (int f = 0; f < REUSE_FRAMES; f++) free(want[f]);
        free(log0);
    }
}

/* A loop whose length changes from frame to frame, whose iterations
 * build nodes of one kind with different attributes by turns (so a slot
 * meets a node of other names), one attribute a memo value that is null
 * in some frames (the node then lacks it), an hsv call the kernel
 * computes, and a memo value shared by every node. */
static void test_reuse(void **s)
{
    (void)s;
    expect_reuse("let n=40+(frame%3)*5\n"
                 "!g\n"
                 "    for i in ..n\n"
                 "        let p=i*0.5+time\n"
                 "            q=(i+frame)%5\n"
                 "        !d x=p;p+1 y=sin(p*0.5) t=time>0.02 e=(q*0)/q > 1\n"
                 "        !e c=hsv(p/100;0.5;0.5) z=(1 if frame%4 == 0 else null)\n"
                 "        !d w=(i*2+frame)*0.25\n",
                 200, true);
    /* particle ids the physics system hashes (vec_key_hash keeps the
     * hash in the vector, which a refill must forget) */
    expect_reuse("let n=60+(frame%3)*5\n"
                 "!physics state=:s dimensions=2\n"
                 "    for i in ..n\n"
                 "        !particle id=(i*7+frame)%97 position=i;i*0.5+time radius=i%3+1\n"
                 "    !collision\n",
                 200, false);
    /* counters' state keys (the dictionary keeps a key's hash in the key
     * vector) and a memo value (time>0.02, false in frames 0 and 1) */
    expect_reuse("let n=20+(frame%3)*3\n"
                 "for i in ..n\n"
                 "    !counter state=(i*3+frame)%11 rate=i+1 initial=time>0.02\n",
                 50, true);
    /* a name from outside that is null in odd frames: no iteration is
     * clean there, none takes a kept node, and the next frame refills
     * those of the frame before (with transient trees, kept meanwhile in
     * the second cache) */
    expect_reuse("let k=(1 if frame%2 == 0 else null)\n"
                 "!g\n"
                 "    for i in ..60\n"
                 "        !a x=sin(i*0.1+time)+k\n",
                 100, false);
    /* a loop in a function called three times a frame (a cache for each
     * run of the loop in a frame), of three lengths */
    expect_reuse("func ring(k)\n"
                 "    for i in ..40+k*3+frame%2\n"
                 "        !p x=i*k+time y=sin(i*0.1+k)\n"
                 "!g\n"
                 "    ring(1)\n"
                 "    ring(2)\n"
                 "    ring(3)\n",
                 500, true);
}

/* Under a memory budget, the nodes kept for a loop that stopped running
 * give their blocks back when the frame needs them (kernel.h,
 * kernel_scratch_reclaim): every frame then runs out of memory, or not,
 * as it does without refills. Budgets across the edge (the first frames
 * fit in all of them, the third fits only from about 2,000 KiB). */
static void test_reuse_budget(void **s)
{
    (void)s;
    const char *src = "let n=5000+floor(time)\n"
                      "if frame < 2\n"
                      "    for i in ..n\n"
                      "        !a x=i*time\n"
                      "else\n"
                      "    for i in ..n\n"
                      "        !b x=i*time\n";
    for (size_t kib = 1800; kib <= 2600; kib += 200) {
        run_script_budget = kib << 10;
        char *log0, *log1;
        run_script_debug.no_kernel_reuse = true;
        char *tree0 = run_script("reuse.fl", src, 5, true, &log0, NULL);
        run_script_debug.no_kernel_reuse = false;
        char *tree1 = run_script("reuse.fl", src, 5, true, &log1, NULL);
        if (strcmp(tree0, tree1) != 0 || strcmp(log0, log1) != 0) fprintf(stderr, "budget %zu KiB differs\n", kib);
        assert_string_equal(tree1, tree0);
        assert_string_equal(log1, log0);
        free(tree0);
        free(tree1);
        free(log0);
        free(log1);
    }
    run_script_budget = 0;
}

/* }===== */

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_hand_values),
        cmocka_unit_test(test_lets_and_calls),
        cmocka_unit_test(test_lets_read_elsewhere),
        cmocka_unit_test(test_memo),
        cmocka_unit_test(test_if_around_nodes),
        cmocka_unit_test(test_index_in_kernels),
        cmocka_unit_test(test_hypot_in_kernels),
        cmocka_unit_test(test_stream_draws_in_kernels),
        cmocka_unit_test(test_map_clamp_in_kernels),
        cmocka_unit_test(test_noise_beside_kernels),
        cmocka_unit_test(test_random_calls_in_kernels),
        cmocka_unit_test(test_fallbacks),
        cmocka_unit_test(test_several_names),
        cmocka_unit_test(test_nested),
        cmocka_unit_test(test_recursion),
        cmocka_unit_test(test_depth_limit),
        cmocka_unit_test(test_budget),
        cmocka_unit_test(test_loop_forms),
        cmocka_unit_test(test_windows),
        cmocka_unit_test(test_compiled),
        cmocka_unit_test(test_routes_from_options_only),
        cmocka_unit_test(test_straight),
        cmocka_unit_test(test_shared_calls),
        cmocka_unit_test(test_reuse),
        cmocka_unit_test(test_reuse_budget),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
