/* test_api.c: the public interface (include/flitter.h) as an embedder sees it:
 * value text for state keys and values, dumps through writer callbacks,
 * the log callback's kinds, fl_error, fl_target_fps, and the error
 * callback receiving an out-of-memory failure before the abort. Only
 * flitter.h is used, except the mem.h test hook that simulates the failed
 * allocation. */
#include <setjmp.h>
#include <signal.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>
#include <cmocka.h>

#include "flitter.h"
#include "mem.h"

/* A growing text sink for fl_write_fn and the log. */
typedef struct Text {
    char data[4096];
    size_t len;
} Text;

static void text_write(void *ctx, const char *s, size_t n)
{
    Text *t = ctx;
    assert_true(t->len + n < sizeof t->data);
    memcpy(t->data + t->len, s, n);
    t->len += n;
    t->data[t->len] = '\0';
}

static void text_clear(Text *t)
{
    t->len = 0;
    t->data[0] = '\0';
}

/* log lines as "KIND|LINE\n" with KIND E, W or D */
static void log_lines(void *ctx, int kind, const char *line)
{
    char k = kind == FL_LOG_ERROR ? 'E' : kind == FL_LOG_WARNING ? 'W' : kind == FL_LOG_DEBUG ? 'D' : '?';
    char buf[512];
    int n = snprintf(buf, sizeof buf, "%c|%s\n", k, line);
    text_write(ctx, buf, (size_t)n);
}

static const char script[] =
    "%pragma fps 30\n"
    "let x=$(:x;0)\n"
    "!node v=x*2 name=\"a;b\" n=debug(x+1)\n"
    "!other w=y s=sqrt(x, 5)\n";

static fl_runtime *open_runtime(Text *log)
{
    fl_options o = fl_default_options();
    o.log = log_lines;
    o.ctx = log;
    fl_runtime *rt = fl_new(&o);
    assert_non_null(rt);
    return rt;
}

static void test_version(void **st)
{
    (void)st;
    assert_string_equal(fl_version(), FL_VERSION_STRING);
    char v[32];
    snprintf(v, sizeof v, "%d.%d.%d", FL_VERSION_MAJOR, FL_VERSION_MINOR, FL_VERSION_PATCH);
    assert_string_equal(fl_version(), v);
}

static void test_numbers_and_builtins(void **st)
{
    (void)st;
    char b[32];
    assert_int_equal(fl_number_text(0.1 + 0.2, b, sizeof b), 19);
    assert_string_equal(b, "0.30000000000000004");
    assert_int_equal(fl_number_text(-2.5, b, sizeof b), 4);
    assert_string_equal(b, "-2.5");
    assert_int_equal(fl_number_text(3.0, b, sizeof b), 1);
    assert_string_equal(b, "3");
    assert_int_equal(fl_number_text(1.0 / 3.0, b, 5), 18);   /* 0.3333333333333333 */
    assert_string_equal(b, "0.33");
    assert_int_equal(fl_number_text(1e300 * 1e300, NULL, 0), 3);   /* inf */
    bool sin = false, zip = false;
    size_t n = 0;
    for (const char *name; (name = fl_builtin_name(n)) != NULL; n++) {
        sin |= strcmp(name, "sin") == 0;
        zip |= strcmp(name, "zip") == 0;
    }
    assert_true(sin && zip && n > 50);
    assert_null(fl_builtin_name(n + 1));
}

static void test_frames_state_and_dumps(void **st)
{
    (void)st;
    Text log = {0}, out = {0};
    fl_runtime *rt = open_runtime(&log);
    assert_true(fl_target_fps(rt) == 60.0);
    assert_int_equal(fl_load_text(rt, "api.fl", script, sizeof script - 1), 0);
    assert_string_equal(log.data, "W|api.fl: warning: Unbound name 'y'\n");
    text_clear(&log);
    double five = 5;
    assert_int_equal(fl_state_set_numbers(rt, ":x;0", &five, 1), 0);
    assert_int_equal(fl_state_set(rt, "label", ":on;2"), 0);
    assert_int_equal(fl_dump_tree(rt, text_write, &out), -1);   /* no frame yet */
    assert_int_equal(fl_step(rt), 0);
    assert_int_equal(fl_frame_count(rt), 1);
    assert_true(fl_frame_time(rt) == 0.0);
    assert_true(fl_target_fps(rt) == 30.0);   /* %pragma fps, applied by the frame */
    assert_int_equal(fl_step(rt), 0);
    assert_true(fl_frame_time(rt) == 1.0 / 30.0);
    /* a message is logged when it is new since the previous frame */
    assert_string_equal(log.data,
                        "E|Execution error: Error calling sqrtv: sqrtv() takes at most 1 "
                        "positional arguments (2 given)\n"
                        "D|6\n");
    assert_int_equal(fl_dump_tree(rt, text_write, &out), 0);
    assert_string_equal(out.data, "!root\n !node v=10 name=\"a;b\" n=6\n !other\n");
    text_clear(&out);
    fl_dump_state(rt, text_write, &out);
    assert_string_equal(out.data, "# frame 1 time 0.03333333333333333\n"
                                  "\"label\" = :on;2\n"   /* sorted by bytes */
                                  ":x;0 = 5\n");
    text_clear(&out);
    assert_int_equal(fl_dump_program(rt, text_write, &out), 0);
    assert_non_null(strstr(out.data, "!node"));
    fl_free(rt);
}

/* fl_state_iterate: collects "KEY=VALUE\n" */
static int collect(void *ctx, const char *key, const char *value)
{
    char buf[256];
    int n = snprintf(buf, sizeof buf, "%s=%s\n", key, value);
    text_write(ctx, buf, (size_t)n);
    return 0;
}

static int stop_after_one(void *ctx, const char *key, const char *value)
{
    (void)key;
    (void)value;
    ++*(int *)ctx;
    return 1;
}

static void test_state_values(void **st)
{
    (void)st;
    Text log = {0}, out = {0};
    fl_runtime *rt = open_runtime(&log);
    assert_int_equal(fl_state_set(rt, ":dish;0", "1.5;-2;3k"), 0);
    assert_int_equal(fl_state_set(rt, "name", "hello"), 0);
    assert_int_equal(fl_state_set(rt, ":a", ":b"), 0);
    assert_int_equal(fl_state_set(rt, "", "1"), -1);        /* null key */
    assert_int_equal(fl_state_count(rt), 3);
    double xy[4] = {0, 0, 0, 0};
    assert_int_equal(fl_state_get_numbers(rt, ":dish;0", xy, 2), 3);   /* all 3, 2 copied */
    assert_true(xy[0] == 1.5 && xy[1] == -2.0 && xy[2] == 0.0);
    assert_int_equal(fl_state_get_numbers(rt, ":dish;0", xy, 4), 3);
    assert_true(xy[2] == 3000.0);
    assert_int_equal(fl_state_get_numbers(rt, ":dish;1", xy, 4), -1);  /* absent */
    assert_int_equal(fl_state_get_numbers(rt, "name", xy, 4), -2);     /* a string */
    char buf[8];
    assert_int_equal(fl_state_get(rt, ":dish;0", buf, sizeof buf), 11);
    assert_string_equal(buf, "1.5;-2;");                               /* truncated */
    assert_int_equal(fl_state_get(rt, ":dish;0", NULL, 0), 11);
    char big[64];
    assert_int_equal(fl_state_get(rt, ":dish;0", big, sizeof big), 11);
    assert_string_equal(big, "1.5;-2;3000");
    assert_int_equal(fl_state_get(rt, "name", big, sizeof big), 7);
    assert_string_equal(big, "\"hello\"");
    assert_int_equal(fl_state_get(rt, "nothing", big, sizeof big), -1);
    assert_int_equal(fl_state_iterate(rt, collect, &out), 3);
    assert_string_equal(out.data, "\"name\"=\"hello\"\n:a=:b\n:dish;0=1.5;-2;3000\n");
    int calls = 0;
    assert_int_equal(fl_state_iterate(rt, stop_after_one, &calls), 1);
    assert_int_equal(calls, 1);
    assert_int_equal(fl_state_set(rt, ":a", ""), 0);                   /* delete */
    assert_int_equal(fl_state_set_numbers(rt, "name", NULL, 0), 0);    /* delete */
    assert_int_equal(fl_state_count(rt), 1);
    fl_reset_state(rt);
    assert_int_equal(fl_state_count(rt), 0);
    assert_string_equal(log.data, "");
    fl_free(rt);
}

static int add_name(void *ctx, const char *name)
{
    if (!strcmp(name, "frame") || !strcmp(name, "SIZE") || !strcmp(name, "k"))
        text_write(ctx, name, strlen(name)), text_write(ctx, " ", 1);
    return 0;
}

static void test_eval_defines_and_errors(void **st)
{
    (void)st;
    Text log = {0}, out = {0};
    fl_runtime *rt = open_runtime(&log);
    assert_string_equal(fl_error(rt), "");
    assert_int_equal(fl_define(rt, "SIZE", "2;3"), 0);
    assert_int_equal(fl_define(rt, "9x", "1"), -1);
    assert_int_equal(fl_step(rt), -1);                 /* no program */
    assert_int_equal(fl_load(rt, "/nonexistent/x.fl"), -1);
    assert_non_null(strstr(fl_error(rt), "/nonexistent/x.fl"));
    static const char bad[] = "let x=(1\n";
    assert_int_equal(fl_load_text(rt, "bad.fl", bad, sizeof bad - 1), -1);
    assert_true(strncmp(fl_error(rt), "bad.fl:", 7) == 0);
    assert_non_null(strstr(fl_error(rt), ": error: "));
    static const char ok[] = "!n s=SIZE\n";
    assert_int_equal(fl_load_text(rt, "ok.fl", ok, sizeof ok - 1), 0);
    assert_int_equal(fl_step(rt), 0);
    assert_int_equal(fl_eval(rt, "SIZE*2\n", 7, text_write, &out), 0);
    assert_string_equal(out.data, "4;6\n");
    text_clear(&out);
    assert_int_equal(fl_eval(rt, "let k=frame+1\n", 14, text_write, &out), 0);
    assert_string_equal(out.data, "k = 1\n");
    text_clear(&out);
    assert_int_equal(fl_eval(rt, "(1+\n", 4, text_write, &out), 1);   /* ended early */
    assert_int_equal(fl_eval(rt, "1)\n", 3, text_write, &out), -1);
    assert_true(strncmp(fl_error(rt), "<repl>:1:", 9) == 0);
    assert_string_equal(out.data, "");
    assert_int_equal(fl_scope_names(rt, add_name, &out) > 3, 1);
    assert_string_equal(out.data, "frame SIZE SIZE k ");   /* a define is in both layers */
    fl_eval_reset(rt);
    text_clear(&out);
    fl_scope_names(rt, add_name, &out);
    assert_string_equal(out.data, "frame SIZE SIZE ");
    assert_int_equal(fl_restore_state(rt, "/nonexistent/state"), -1);
    assert_true(strlen(fl_error(rt)) > 0);
    fl_free(rt);
}

/* Two runtimes in one process, stepped in turn: each keeps its own
 * program, state, clock and log. */
static void test_two_runtimes(void **st)
{
    (void)st;
    Text log_a = {0}, log_b = {0}, out = {0};
    fl_runtime *a = open_runtime(&log_a), *b = open_runtime(&log_b);
    static const char sa[] = "!a v=$(:n)+1 w=debug(frame)\n";
    static const char sb[] = "%pragma fps 10\n!b v=$(:n)*2 w=p\n";
    assert_int_equal(fl_load_text(a, "a.fl", sa, sizeof sa - 1), 0);
    assert_int_equal(fl_load_text(b, "b.fl", sb, sizeof sb - 1), 0);
    assert_int_equal(fl_state_set(a, ":n", "1"), 0);
    assert_int_equal(fl_state_set(b, ":n", "10"), 0);
    for (int i = 0; i < 3; i++) {
        assert_int_equal(fl_step(a), 0);
        assert_int_equal(fl_step(b), 0);
    }
    assert_int_equal(fl_step(a), 0);
    assert_int_equal(fl_frame_count(a), 4);
    assert_int_equal(fl_frame_count(b), 3);
    assert_true(fl_frame_time(a) == 1.0 / 60.0 + 1.0 / 60.0 + 1.0 / 60.0);   /* a running sum */
    assert_true(fl_frame_time(b) == 0.1 + 0.1);    /* %pragma fps 10 */
    assert_int_equal(fl_dump_tree(a, text_write, &out), 0);
    assert_string_equal(out.data, "!root\n !a v=2 w=3\n");
    text_clear(&out);
    assert_int_equal(fl_dump_tree(b, text_write, &out), 0);
    assert_string_equal(out.data, "!root\n !b v=20\n");
    assert_string_equal(log_a.data, "D|0\nD|1\nD|2\nD|3\n");
    assert_string_equal(log_b.data, "W|b.fl: warning: Unbound name 'p'\n");
    fl_free(a);
    fl_free(b);
}

/* {=====================================================================
 * Out of memory: the error callback runs, then the process aborts
 * ===================================================================== */

static int report_fd = -1;
/* The first [n] bytes of file [path] into [buf] (NUL-terminated); the
 * number of lines of the file in *lines. */
static size_t file_head(const char *path, char *buf, size_t n, int *lines)
{
    FILE *f = fopen(path, "rb");
    if (!f) return 0;
    size_t k = fread(buf, 1, n - 1, f);
    buf[k] = '\0';
    rewind(f);
    *lines = 0;
    for (int c; (c = fgetc(f)) != EOF;)
        if (c == '\n') ++*lines;
    fclose(f);
    return k;
}

/* fl_outputs_* and fl_view: pictures of the systems, trajectories, errors
 * in fl_error(). (The windows' !record files, drawn with OpenGL, and the
 * skipped drawing kinds: tests/unit/test_window_api.c, test_canvas.c and
 * tests/cli/flitter_figures.sh, suite gl.) */
static void test_outputs_and_view(void **st)
{
    (void)st;
    char dir[] = "/tmp/test_api.XXXXXX";
    assert_non_null(mkdtemp(dir));
    char view[64], trace[64], svg[64], bad[64], src[512];
    snprintf(view, sizeof view, "%s/v.png", dir);
    snprintf(trace, sizeof trace, "%s/t.csv", dir);
    snprintf(svg, sizeof svg, "%s/now.svg", dir);
    snprintf(bad, sizeof bad, "%s/v.jpg", dir);
    snprintf(src, sizeof src,
             "!physics state=:p dimensions=2\n"
             "    !particle id=1 position=0;0 radius=1\n"
             "    !particle id=2 position=3;4 radius=2\n");
    Text log = {0};
    fl_runtime *rt = open_runtime(&log);
    assert_int_equal(fl_load_text(rt, "out.fl", src, strlen(src)), 0);

    fl_output_options o = {.view = bad};
    assert_null(fl_outputs_open(rt, &o));
    char want[160];
    snprintf(want, sizeof want, "%s: a view is written to a .png, .svg or .gif file\n", bad);
    assert_string_equal(fl_error(rt), want);

    fl_output_options ok = {.view = view, .trace = trace, .trace_every = 2, .debug = true};
    fl_outputs *out = fl_outputs_open(rt, &ok);
    assert_non_null(out);
    for (int i = 0; i < 3; i++) {
        assert_int_equal(fl_step(rt), 0);
        assert_int_equal(fl_outputs_frame(out, rt), 0);
    }
    assert_int_equal(fl_outputs_close(out, rt), 0);
    assert_string_equal(log.data, "");   /* nothing to say */

    char head[16];
    int lines;
    assert_int_equal(file_head(view, head, 5, &lines), 4);
    assert_memory_equal(head, "\x89PNG", 4);
    /* the header, then frames 0 and 2 (every 2nd) with two particles each */
    assert_true(file_head(trace, head, 16, &lines) > 0);
    assert_memory_equal(head, "frame,time,", 11);
    assert_int_equal(lines, 1 + 2 * 2);

    size_t n = 99;
    assert_int_equal(fl_view(rt, svg, &n), 0);
    assert_int_equal(n, 1);
    assert_true(file_head(svg, head, 6, &lines) > 0);
    assert_memory_equal(head, "<?xml", 5);
    assert_int_equal(fl_view(rt, bad, NULL), -1);
    assert_string_equal(fl_error(rt), want);
    fl_free(rt);
    char cmd[96];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    assert_int_equal(system(cmd), 0);
}

static void on_error(void *ctx, const char *message)
{
    char line[200];
    int n = snprintf(line, sizeof line, "%s|%s", (const char *)ctx, message);
    if (write(report_fd, line, (size_t)n) != n) _exit(3);
}

static void test_out_of_memory_reaches_error_callback(void **st)
{
    (void)st;
    int rp[2];
    assert_int_equal(pipe(rp), 0);
    fflush(NULL);
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        close(rp[0]);
        report_fd = rp[1];
        fl_options o = fl_default_options();
        o.error = on_error;
        o.ctx = "other";
        fl_runtime *other = fl_new(&o);   /* its handler is not the active one */
        fl_load_text(other, "y.fl", "!m\n", 3);
        o.ctx = "embedder";
        fl_runtime *rt = fl_new(&o);
        mem_test_fail_after(0);     /* the load's first allocation fails */
        fl_load_text(rt, "x.fl", "!n\n", 3);
        fl_free(other);
        _exit(0);                   /* not reached */
    }
    close(rp[1]);
    char rep[256];
    ssize_t n = read(rp[0], rep, sizeof rep - 1);
    rep[n > 0 ? n : 0] = '\0';
    close(rp[0]);
    int status;
    assert_int_equal(waitpid(pid, &status, 0), pid);
    assert_true(WIFSIGNALED(status));
    assert_int_equal(WTERMSIG(status), SIGABRT);
    assert_string_equal(rep, "embedder|out of memory");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_version),
        cmocka_unit_test(test_numbers_and_builtins),
        cmocka_unit_test(test_frames_state_and_dumps),
        cmocka_unit_test(test_state_values),
        cmocka_unit_test(test_eval_defines_and_errors),
        cmocka_unit_test(test_two_runtimes),
        cmocka_unit_test(test_outputs_and_view),
        cmocka_unit_test(test_out_of_memory_reaches_error_callback),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
