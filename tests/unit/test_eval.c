/* test_eval.c: evaluation semantics (LANGUAGE.md §4) through the public API:
 * scopes, closures, recursion limits, templates, node operations, run-time
 * error messages. Each test evaluates one frame of a program and compares
 * the node-tree dump (FORMATS.md §3) and the logged messages. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "runtime.h"
#include "format.h"

typedef struct Run {
    char *tree;     /* tree dump of the last frame */
    char *log;      /* everything logged */
} Run;

/* Evaluate [frames] frames of the program text [src], or of the file
 * [path] when [src] is NULL; with [simplify] in Flitter's default mode, else
 * as parsed (--nosimplify: these tests are about the evaluator). */
static Run run_program_mode(const char *src, const char *path, int frames, bool simplify)
{
    Run r = {0};
    size_t loglen;
    FILE *log = open_memstream(&r.log, &loglen);
    fl_options o = fl_default_options();
    RtStreams streams = {log, log};
    rt_log_to_files(&o, &streams);
    o.no_simplify = !simplify;
    fl_runtime *rt = fl_new(&o);
    Buf err = BUF_INIT;
    int rc = src ? rt_load_text(rt, "test.fl", src, strlen(src), &err) : rt_load(rt, path, &err);
    if (rc != 0) {
        fprintf(log, "%s", buf_cstr(&err));
    } else {
        for (int i = 0; i < frames; i++) fl_step(rt);
        Buf t = BUF_INIT;
        fmt_tree(&t, rt_root(rt), rt_symbols(rt));
        r.tree = strdup(buf_cstr(&t));
        buf_free(&t);
    }
    buf_free(&err);
    fl_free(rt);
    fclose(log);
    return r;
}

static Run run_program(const char *src, const char *path, int frames)
{
    return run_program_mode(src, path, frames, false);
}

static Run run_frames(const char *src, int frames) { return run_program(src, NULL, frames); }

static void expect(const char *src, const char *tree, const char *log)
{
    Run r = run_frames(src, 1);
    assert_non_null(r.tree);
    assert_string_equal(r.tree, tree);
    if (log) assert_string_equal(r.log, log);
    free(r.tree);
    free(r.log);
}

/* %pragma fps, tempo and quantum are the names of frame 0 already
 * (FORMATS.md §5; Flitter 1.0.0b28 shows the defaults there): tempo is
 * 60/period with period = 60/110, and frame 1 is 1/30 s later, at beat
 * (1/30)/(60/110). */
static void test_pragmas_from_frame_0(void **s)
{
    (void)s;
    const char *src = "%pragma fps 30\n%pragma tempo 110\n%pragma quantum 3\n"
                      "!a f=fps t=tempo q=quantum b=beat time=time\n";
    expect(src, "!root\n !a f=30 t=110.00000000000001 q=3 b=0 time=0\n", "");
    Run r = run_frames(src, 2);
    assert_string_equal(r.tree, "!root\n !a f=30 t=110.00000000000001 q=3 b=0.061111111111111116 "
                                "time=0.03333333333333333\n");
    free(r.tree);
    free(r.log);
}

static void test_shadowing(void **s)
{
    (void)s;
    expect("let x=10\nif x>5\n    let x=x*2\n    !foo x=x\n!bar x=x\n",
           "!root\n !foo x=20\n !bar x=10\n", "");
}

static void test_closures_capture_by_value(void **s)
{
    (void)s;
    expect("let x=10\nfunc add_x(y)\n    x+y\nlet x=20\n!t r=add_x(5)\n",
           "!root\n !t r=15\n", "");
}

static void test_program_a(void **s)
{
    (void)s;
    expect("let x=10\n"
           "func add_x(y, k=x*2)\n    x+y+k\n"
           "let x=20\n"
           "func f(a, b=2, c)\n    a*b+c\n"
           "!t1 r=add_x(5) s=f(3, c=1) t=f(1,2,3,4) u=f(1, d=5, c=2) v=f()\n"
           "let a;b;c = 1;2\n!t3 a=a b=b c=c\n"
           "!t4 #z #a y=1 x=2 y=3\n"
           "!t5\n    1\n    \"s\"\n    !c1\n    (!c2;!c3) #tag\n",
           "!root\n !t1 r=35 s=7 t=5 u=4\n !t3 a=1 b=2 c=1\n !t4 #a #z y=3 x=2\n"
           " !t5\n  !c1\n  !c2 #tag\n  !c3 #tag\n",
           NULL);
}

static void test_precedence_program_b(void **s)
{
    (void)s;
    expect("let x=20\n!t2 a=(x;y for x;y in 1;2;3) b=((x;y) for x in ..2 for y in 10;20)\n",
           "!root\n !t2 a=20;2;3 b=0;10;1;10;20\n", NULL);
}

static void test_recursion_limit(void **s)
{
    (void)s;
    expect("func rec(n)\n    rec(n+1)\nlet g = func(q) q*2\n!t6 r=rec(0)\n!t7 r=(g;g)(4) s=(g;5)(1)\n",
           "!root\n !t6\n !t7 r=8;8 s=2\n", NULL);
    Run r = run_frames("func rec(n)\n    rec(n+1)\n!t r=rec(0)\n", 1);
    assert_non_null(strstr(r.log, "Execution error: Recursion depth exceeded for func 'rec'\n"));
    free(r.tree);
    free(r.log);
    r = run_frames("let g = func(q) q*2\n!t s=(g;5)(1)\n", 1);
    assert_non_null(strstr(r.log, "Execution error: 5.0 is not callable\n"));
    free(r.tree);
    free(r.log);
}

static void test_errors_reported_once(void **s)
{
    (void)s;
    Run r = run_frames("!t r=sqrt(4, 5)\n", 3);
    const char *first = strstr(r.log, "Execution error: Error calling sqrtv");
    assert_non_null(first);
    assert_null(strstr(first + 1, "Execution error: Error calling sqrtv"));
    free(r.tree);
    free(r.log);
}

static void test_templates_program_d(void **s)
{
    (void)s;
    expect("func foo(nodes, x=10, y, z='world')\n"
           "    !foo x=x z='hello';z\n"
           "        nodes #test y=y\n"
           "@foo\n"
           "@foo y=5\n"
           "    @foo z='me' x=99\n"
           "        !baz\n",
           "!root\n !foo x=10 z=\"hello\";\"world\"\n !foo x=10 z=\"hello\";\"world\"\n"
           "  !foo #test x=99 z=\"hello\";\"me\" y=5\n   !baz #test\n",
           NULL);
}

static void test_append_program_e(void **s)
{
    (void)s;
    expect("let n=!leaf\n!a << !b x=1 << n\n    !c\n"
           "let s =\n    !x\n    !y\n"
           "let u;v =\n    1\n    2\n    3\n"
           "!t3 u=u v=v s=s\n!t4 x=(1 if 0 else 2 if 1 else 3)\n"
           "if 0\n    !no\nelif null\n    !no2\nelse\n    !yes\n"
           "!t5 p=(((!p1;1;!p2) #tg) x=3)\n"
           "!t6\n    ((!p1;1;!p2) #tg) x=3\n",
           "!root\n !a\n  !b x=1\n   !leaf\n    !c\n !t3 u=1 v=2 s=(!x);(!y)\n !t4 x=2\n !yes\n"
           " !t5 p=(!p1);1;(!p2)\n !t6\n  !p1 #tg x=3\n  !p2 #tg x=3\n",
           NULL);
}

static void test_unbound_name_warning(void **s)
{
    (void)s;
    Run r = run_frames("!t v=(x;y where x=1 y=2)\n", 1);
    assert_string_equal(r.tree, "!root\n !t v=2\n");
    assert_non_null(strstr(r.log, "Unbound name 'x'"));
    free(r.tree);
    free(r.log);
}

static void test_identity_and_nan(void **s)
{
    (void)s;
    expect("let q=0/0\n!t a=(nan == nan) b=(q == q) c=((0/0) == (0/0))\n",
           "!root\n !t a=1 b=1 c=0\n", NULL);
}

/* The same in Flitter's default mode: `nan` is one shared literal (equal
 * by identity), each use of a let-bound literal is its own copy, and an
 * error of a builtin call with literal arguments is a load-time warning. */
static void test_simplified_identity_and_errors(void **s)
{
    (void)s;
    Run r = run_program_mode("let q=0/0\n!t a=(nan == nan) b=(q == q) c=((0/0) == (0/0))\n", NULL, 1,
                             true);
    assert_string_equal(r.tree, "!root\n !t a=1 b=0 c=0\n");
    free(r.tree);
    free(r.log);
    r = run_program_mode("!t r=sqrt(4, 5)\n", NULL, 3, true);
    assert_string_equal(r.tree, "!root\n !t\n");
    assert_null(strstr(r.log, "Execution error"));
    const char *first = strstr(r.log, "test.fl: warning: Error calling sqrtv");
    assert_non_null(first);
    assert_null(strstr(first + strlen("test.fl: warning: Error calling sqrtv"), "Error calling sqrtv"));
    free(r.tree);
    free(r.log);
}

static void test_frame_names(void **s)
{
    (void)s;
    Run r = run_frames("%pragma fps 30\n%pragma tempo 110\n!t fps=fps tempo=tempo time=time frame=frame\n", 2);
    assert_string_equal(r.tree, "!root\n !t fps=30 tempo=110.00000000000001 time=0.03333333333333333 frame=1\n");
    free(r.tree);
    free(r.log);
}

static void test_syntax_error(void **s)
{
    (void)s;
    Run r = run_frames("!t a=1\n!t b=2**-1\n", 1);
    assert_null(r.tree);
    assert_non_null(strstr(r.log, "test.fl:2:"));
    assert_non_null(strstr(r.log, ": error: "));
    free(r.log);
}

/* Write [text] to [dir]/[name]. */
static void put_file(const char *dir, const char *name, const char *text)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
}

/* Run [dir]/main.fl for one frame. */
static Run run_file(const char *dir)
{
    char path[512];
    snprintf(path, sizeof path, "%s/main.fl", dir);
    return run_program(NULL, path, 1);
}

static void test_imports(void **s)
{
    (void)s;
    char dir[] = "/tmp/flitter-import-XXXXXX";
    assert_non_null(mkdtemp(dir));
    put_file(dir, "lib.fl", "let k=3\nfunc triple(x)\n    x*k\nlet hidden=beat\n!ignored\n");
    put_file(dir, "a.fl", "import b from \"b.fl\"\nlet a=1\n");
    put_file(dir, "b.fl", "import a from \"a.fl\"\nlet b=2\n");
    put_file(dir, "main.fl",
             "import triple;k;nope from \"lib.fl\"\nimport z from \"missing.fl\"\n"
             "import a from \"a.fl\"\n!t r=triple(5) k=k nope=nope z=z a=a\n");
    Run r = run_file(dir);
    assert_string_equal(r.tree, "!root\n !t r=15 k=3 a=1\n");
    assert_non_null(strstr(r.log, "Unable to import 'nope' from '"));
    assert_non_null(strstr(r.log, "Unable to import from '"));
    assert_non_null(strstr(r.log, "missing.fl'"));
    assert_non_null(strstr(r.log, "Circular import of '"));
    assert_non_null(strstr(r.log, "Unbound name 'beat'"));   /* modules see no frame names */
    free(r.tree);
    free(r.log);

    /* %include splices statements in the current scope, once per file */
    put_file(dir, "part.fl", "let local=x*2\n!inc v=local\n");
    put_file(dir, "main.fl", "let x=21\n%include \"part.fl\"\n!after l=local\n");
    r = run_file(dir);
    assert_string_equal(r.tree, "!root\n !inc v=42\n !after\n");
    free(r.tree);
    free(r.log);
    const char *names[] = {"lib.fl", "a.fl", "b.fl", "main.fl", "part.fl"};
    for (size_t i = 0; i < 5; i++) {
        char path[512];
        snprintf(path, sizeof path, "%s/%s", dir, names[i]);
        remove(path);
    }
    rmdir(dir);
}

static void test_runaway_scripts_end(void **s)
{
    (void)s;
    Run r = run_frames("!t r=len(..1e12)\n", 1);
    assert_string_equal(r.tree, "!root\n !t r=0\n");
    assert_non_null(strstr(r.log, "Range too long"));
    free(r.tree);
    free(r.log);
}

/* The interrupt flag (flitter.h): fl_step discards an interrupted frame
 * (returns 1; tree, state and frame count as before) and fl_eval binds and
 * prints nothing; with the flag clear both carry on normally. */
static void test_interrupt(void **s)
{
    (void)s;
    static volatile int stop;
    fl_options o = fl_default_options();
    RtStreams streams = {NULL, NULL};
    rt_log_to_files(&o, &streams);
    o.interrupt = &stop;
    fl_runtime *rt = fl_new(&o);
    Buf err = BUF_INIT, out = BUF_INIT, t = BUF_INIT;
    static const char src[] = "!a n=frame;len((i for i in 0..frame+10))\n";
    assert_int_equal(rt_load_text(rt, "test.fl", src, sizeof src - 1, &err), 0);
    assert_int_equal(fl_step(rt), 0);
    stop = 1;
    assert_int_equal(fl_step(rt), 1);
    assert_int_equal(fl_frame_count(rt), 1);
    fmt_tree(&t, rt_root(rt), rt_symbols(rt));
    assert_string_equal(buf_cstr(&t), "!root\n !a n=0;10\n");
    assert_int_equal(rt_eval(rt, "let q = (i for i in 0..3)\n", 26, &out, &err), -1);
    assert_string_equal(buf_cstr(&err), "<repl>: error: interrupted\n");
    assert_int_equal(out.len, 0);
    stop = 0;
    buf_reset(&err);
    assert_int_equal(rt_eval(rt, "q\n", 2, &out, &err), 0);
    assert_string_equal(buf_cstr(&out), "null\n");
    assert_int_equal(fl_step(rt), 0);
    buf_reset(&t);
    fmt_tree(&t, rt_root(rt), rt_symbols(rt));
    assert_string_equal(buf_cstr(&t), "!root\n !a n=1;11\n");
    buf_free(&err);
    buf_free(&out);
    buf_free(&t);
    fl_free(rt);
}

/* fl_options.transient_tree: the last frame's tree is read as usual
 * between steps; an interrupted step leaves the frame count as it was and
 * no tree (rt_root NULL, as before the first frame), with or without a
 * loop kernel; the next step carries on. */
static void interrupt_transient(const char *src, const char *tree0, const char *tree1)
{
    static volatile int stop;
    fl_options o = fl_default_options();
    RtStreams streams = {NULL, NULL};
    rt_log_to_files(&o, &streams);
    o.interrupt = &stop;
    o.transient_tree = true;
    fl_runtime *rt = fl_new(&o);
    Buf err = BUF_INIT, t = BUF_INIT;
    assert_int_equal(rt_load_text(rt, "test.fl", src, strlen(src), &err), 0);
    assert_int_equal(fl_step(rt), 0);
    fmt_tree(&t, rt_root(rt), rt_symbols(rt));
    assert_string_equal(buf_cstr(&t), tree0);
    stop = 1;
    assert_int_equal(fl_step(rt), 1);
    assert_int_equal(fl_frame_count(rt), 1);
    assert_null(rt_root(rt));
    stop = 0;
    assert_int_equal(fl_step(rt), 0);
    buf_reset(&t);
    fmt_tree(&t, rt_root(rt), rt_symbols(rt));
    assert_string_equal(buf_cstr(&t), tree1);
    buf_free(&err);
    buf_free(&t);
    fl_free(rt);
}

static void test_interrupt_transient(void **s)
{
    (void)s;
    interrupt_transient("!a n=frame;len((i for i in 0..frame+10))\n", "!root\n !a n=0;10\n",
                        "!root\n !a n=1;11\n");
    interrupt_transient("!a n=frame;sum((sin(i*0.001+time)*0+1 for i in ..3000+frame))>0\n", "!root\n !a n=0;1\n",
                        "!root\n !a n=1;1\n");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pragmas_from_frame_0),
        cmocka_unit_test(test_shadowing),
        cmocka_unit_test(test_closures_capture_by_value),
        cmocka_unit_test(test_program_a),
        cmocka_unit_test(test_precedence_program_b),
        cmocka_unit_test(test_recursion_limit),
        cmocka_unit_test(test_errors_reported_once),
        cmocka_unit_test(test_templates_program_d),
        cmocka_unit_test(test_append_program_e),
        cmocka_unit_test(test_unbound_name_warning),
        cmocka_unit_test(test_identity_and_nan),
        cmocka_unit_test(test_simplified_identity_and_errors),
        cmocka_unit_test(test_frame_names),
        cmocka_unit_test(test_syntax_error),
        cmocka_unit_test(test_imports),
        cmocka_unit_test(test_runaway_scripts_end),
        cmocka_unit_test(test_interrupt),
        cmocka_unit_test(test_interrupt_transient),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
