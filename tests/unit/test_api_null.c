/* test_api_null.c: the C interface keeps its contract (include/flitter.h, top:
 * "Errors"; issue 28 item 8). Every public function is called with NULL in
 * each pointer position, on a fresh runtime and on one with a program
 * loaded and stepped where that matters, and with sizes past its limits
 * (huge counts, counts whose byte size overflows, negative sizes); each
 * call must return the value its comment documents and, when it has a
 * runtime to hold one, leave an fl_error() message naming the function and
 * the argument. Nothing may crash or abort: the test runs under ASan+UBSan
 * in .ci/run's sanitizer phase and under valgrind in its valgrind phase.
 *
 * There is one test per public function, named null_<function>; the test
 * every_function_is_covered reads flitter.h (its path is the first
 * argument) and fails for any function declared FL_API without one, so a
 * new function cannot skip this contract. Only flitter.h is used. */
#include <limits.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>

#include "flitter.h"

static const char *header_path;   /* flitter.h, from argv[1] */

/* Log lines are counted, not printed: the refused calls must not need the log. */
static void quiet_log(void *ctx, int kind, const char *line)
{
    (void)kind;
    (void)line;
    ++*(int *)ctx;
}

static int log_count;

static fl_runtime *fresh(void)
{
    fl_options o = fl_default_options();
    o.log = quiet_log;
    o.ctx = &log_count;
    fl_runtime *rt = fl_new(&o);
    assert_non_null(rt);
    assert_string_equal(fl_error(rt), "");
    return rt;
}

static const char script[] =
    "!window size=16;8\n"
    "    !key name=\"space\" state=:sp\n"
    "    !pointer state=:ptr\n"
    "!physics dimensions=2 state=:dish\n"
    "    !particle id=1 position=0;0 velocity=1;0 radius=1\n"
    "    !particle id=2 position=5;0 radius=1\n";

/* A runtime with [script] loaded and two frames stepped. */
static fl_runtime *loaded(void)
{
    fl_runtime *rt = fresh();
    assert_int_equal(fl_load_text(rt, "null.fl", script, strlen(script)), 0);
    assert_int_equal(fl_step(rt), 0);
    assert_int_equal(fl_step(rt), 0);
    return rt;
}

/* fl_error(rt) names [fn] and holds [what], and ends in a newline. */
static void expect_error(const fl_runtime *rt, const char *fn, const char *what)
{
    const char *e = fl_error(rt);
    size_t n = strlen(e);
    if (!strstr(e, fn) || !strstr(e, what) || n == 0 || e[n - 1] != '\n')
        fail_msg("fl_error() is \"%s\", expected \"%s\" and \"%s\"", e, fn, what);
}

/* A runtime that cannot hold a message: fl_error(NULL)'s fixed text. */
static void expect_null_runtime_text(void)
{
    const char *e = fl_error(NULL);
    assert_non_null(e);
    assert_non_null(strstr(e, "NULL"));
    assert_int_equal(e[strlen(e) - 1], '\n');
}

/* A writer that must not be called. */
static void no_write(void *ctx, const char *text, size_t len)
{
    (void)ctx;
    (void)text;
    (void)len;
    fail_msg("a refused call wrote output");
}

/* A writer that counts bytes. */
static void count_write(void *ctx, const char *text, size_t len)
{
    (void)text;
    *(size_t *)ctx += len;
}

/* A writer that appends to a 32-byte string. */
static void text_write(void *ctx, const char *text, size_t len)
{
    char *s = ctx;
    size_t n = strlen(s);
    assert_true(n + len < 32);
    memcpy(s + n, text, len);
    s[n + len] = '\0';
}

#define NULL_TEST(fn) static void null_##fn(void **unused)

/* {=====================================================================
 * Version, options, runtimes, messages
 * ===================================================================== */

NULL_TEST(fl_version)
{
    (void)unused;
    assert_string_equal(fl_version(), FL_VERSION_STRING);
}

NULL_TEST(fl_default_options)
{
    (void)unused;
    fl_options o = fl_default_options();
    assert_true(o.fps == 60.0);
    assert_null(o.log);
    assert_null(o.interrupt);
}

/* [parse] refuses NULL in either position, leaving *out alone. */
static void parse_nulls(bool (*parse)(const char *, int *), const char *word, int value)
{
    int out = 12345;
    assert_false(parse(NULL, &out));
    assert_int_equal(out, 12345);
    assert_false(parse(word, NULL));
    assert_false(parse(NULL, NULL));
    assert_true(parse(word, &out));
    assert_int_equal(out, value);
}

NULL_TEST(fl_parse_pairs)
{
    (void)unused;
    parse_nulls(fl_parse_pairs, "naive", FL_PAIRS_NAIVE);
}

NULL_TEST(fl_parse_particles)
{
    (void)unused;
    parse_nulls(fl_parse_particles, "literal", FL_PARTICLES_LITERAL);
}

NULL_TEST(fl_parse_physics)
{
    (void)unused;
    parse_nulls(fl_parse_physics, "upstream", FL_PHYSICS_UPSTREAM);
}

NULL_TEST(fl_parse_view_axes)
{
    (void)unused;
    int out[2] = {12345, 12345};
    assert_false(fl_parse_view_axes(NULL, out));
    assert_true(out[0] == 12345 && out[1] == 12345);
    assert_false(fl_parse_view_axes("x;z", NULL));
    assert_false(fl_parse_view_axes(NULL, NULL));
    assert_false(fl_parse_view_axes("x;x", out));
    assert_true(out[0] == 12345 && out[1] == 12345);
    assert_true(fl_parse_view_axes("x;z", out));
    assert_true(out[0] == 0 && out[1] == 2);
}

NULL_TEST(fl_parse_memory)
{
    (void)unused;
    size_t out = 12345;
    assert_false(fl_parse_memory(NULL, &out));
    assert_int_equal(out, 12345);
    assert_false(fl_parse_memory("1K", NULL));
    assert_false(fl_parse_memory(NULL, NULL));
    /* sizes that overflow size_t are refused */
    assert_false(fl_parse_memory("18446744073709551616", &out));
    assert_false(fl_parse_memory("17179869184G", &out));
    assert_int_equal(out, 12345);
    assert_true(fl_parse_memory("2K", &out));
    assert_int_equal(out, 2048);
}

NULL_TEST(fl_new)
{
    (void)unused;
    fl_runtime *rt = fl_new(NULL);   /* NULL: the defaults */
    assert_non_null(rt);
    assert_true(fl_target_fps(rt) == 60.0);
    fl_free(rt);
    /* sizes out of range fall back to the defaults */
    fl_options o = fl_default_options();
    o.fps = -5;
    o.threads = -3;
    o.frames = LONG_MIN;
    o.max_physics_steps = LONG_MIN;
    o.log = quiet_log;
    o.ctx = &log_count;
    rt = fl_new(&o);
    assert_non_null(rt);
    assert_true(fl_target_fps(rt) == 60.0);
    assert_int_equal(fl_load_text(rt, "n.fl", script, strlen(script)), 0);
    assert_int_equal(fl_step(rt), 0);
    fl_free(rt);
}

NULL_TEST(fl_free)
{
    (void)unused;
    fl_free(NULL);   /* a no-op */
    fl_free(fresh());
}

NULL_TEST(fl_error)
{
    (void)unused;
    expect_null_runtime_text();
    assert_ptr_equal(fl_error(NULL), fl_error(NULL));   /* static storage */
    fl_runtime *rt = fresh();
    assert_string_equal(fl_error(rt), "");
    fl_free(rt);
}

NULL_TEST(fl_define)
{
    (void)unused;
    assert_int_equal(fl_define(NULL, "a", "1"), -1);
    fl_runtime *rt = fresh();
    assert_int_equal(fl_define(rt, NULL, "1"), -1);
    expect_error(rt, "fl_define", "[name]");
    assert_int_equal(fl_define(rt, "a", NULL), -1);
    expect_error(rt, "fl_define", "[value_text]");
    assert_int_equal(fl_define(rt, "1a", "1"), -1);
    expect_error(rt, "fl_define", "'1a' is not a name");
    assert_int_equal(fl_define(rt, "", "1"), -1);
    expect_error(rt, "fl_define", "is not a name");
    assert_int_equal(fl_define(rt, "a", "7"), 0);
    /* the refused defines bound nothing; `a` is 7 */
    char text[32] = "";
    assert_int_equal(fl_eval(rt, "a", 1, text_write, text), 0);
    assert_string_equal(text, "7\n");
    fl_free(rt);
}

NULL_TEST(fl_define_numbers)
{
    (void)unused;
    const double x[2] = {-3, 0.5};
    assert_int_equal(fl_define_numbers(NULL, "a", x, 2), -1);
    fl_runtime *rt = fresh();
    assert_int_equal(fl_define_numbers(rt, NULL, x, 2), -1);
    expect_error(rt, "fl_define_numbers", "[name]");
    assert_int_equal(fl_define_numbers(rt, "a", NULL, 2), -1);
    expect_error(rt, "fl_define_numbers", "[values]");
    assert_int_equal(fl_define_numbers(rt, "1a", x, 2), -1);
    expect_error(rt, "fl_define_numbers", "'1a' is not a name");
    const size_t huge[] = {((size_t)1 << 26) + 1, (size_t)UINT32_MAX + 1, SIZE_MAX};
    for (size_t i = 0; i < sizeof huge / sizeof huge[0]; i++) {
        assert_int_equal(fl_define_numbers(rt, "a", x, huge[i]), -1);
        expect_error(rt, "fl_define_numbers", "longest vector");
    }
    assert_int_equal(fl_define_numbers(rt, "b", NULL, 0), 0);   /* null */
    assert_int_equal(fl_define_numbers(rt, "a", x, 2), 0);
    char text[32] = "";
    assert_int_equal(fl_eval(rt, "a", 1, text_write, text), 0);
    assert_string_equal(text, "-3;0.5\n");
    text[0] = '\0';
    assert_int_equal(fl_eval(rt, "b", 1, text_write, text), 0);
    assert_string_equal(text, "null\n");
    fl_free(rt);
}

/* {=====================================================================
 * Loading and stepping
 * ===================================================================== */

NULL_TEST(fl_load)
{
    (void)unused;
    assert_int_equal(fl_load(NULL, "x.fl"), -1);
    fl_runtime *rt = loaded();
    assert_int_equal(fl_load(rt, NULL), -1);
    expect_error(rt, "fl_load", "[path]");
    assert_int_equal(fl_step(rt), 0);   /* the program stays loaded */
    fl_free(rt);
}

NULL_TEST(fl_load_text)
{
    (void)unused;
    assert_int_equal(fl_load_text(NULL, "x.fl", "!n\n", 3), -1);
    fl_runtime *rt = fresh();
    assert_int_equal(fl_load_text(rt, NULL, "!n\n", 3), -1);
    expect_error(rt, "fl_load_text", "[name]");
    assert_int_equal(fl_load_text(rt, "x.fl", NULL, 3), -1);
    expect_error(rt, "fl_load_text", "[text]");
    /* lengths past a script file's limit are refused before the text is read */
    assert_int_equal(fl_load_text(rt, "x.fl", "!n\n", SIZE_MAX), -1);
    expect_error(rt, "x.fl", "limit");
    assert_int_equal(fl_load_text(rt, "x.fl", "!n\n", ((size_t)256 << 20) + 1), -1);
    expect_error(rt, "x.fl", "limit");
    assert_int_equal(fl_step(rt), -1);   /* none of them loaded anything */
    /* NULL with length 0 is the empty program */
    assert_int_equal(fl_load_text(rt, "x.fl", NULL, 0), 0);
    assert_int_equal(fl_step(rt), 0);
    fl_free(rt);
}

NULL_TEST(fl_step)
{
    (void)unused;
    assert_int_equal(fl_step(NULL), -1);
    fl_runtime *rt = fresh();
    assert_int_equal(fl_step(rt), -1);
    expect_error(rt, "fl_step", "no program");
    assert_int_equal(fl_frame_count(rt), 0);
    fl_free(rt);
}

NULL_TEST(fl_frame_count)
{
    (void)unused;
    assert_int_equal(fl_frame_count(NULL), -1);
    fl_runtime *rt = loaded();
    assert_int_equal(fl_frame_count(rt), 2);
    fl_free(rt);
}

NULL_TEST(fl_frame_time)
{
    (void)unused;
    assert_true(isnan(fl_frame_time(NULL)));
    fl_runtime *rt = loaded();
    assert_true(fl_frame_time(rt) == 1.0 / 60);
    fl_free(rt);
}

NULL_TEST(fl_next_frame_time)
{
    (void)unused;
    assert_true(isnan(fl_next_frame_time(NULL)));
    fl_runtime *rt = loaded();   /* frames 0 and 1 run: the next is at 2/60 */
    double next = fl_next_frame_time(rt);
    assert_true(next == 1.0 / 60 + 1.0 / 60);
    assert_int_equal(fl_step(rt), 0);
    assert_true(fl_frame_time(rt) == next);
    assert_true(fl_next_frame_time(rt) == next + 1.0 / 60);
    fl_free(rt);
}

NULL_TEST(fl_target_fps)
{
    (void)unused;
    assert_true(isnan(fl_target_fps(NULL)));
}

NULL_TEST(fl_frame_wait)
{
    (void)unused;
    assert_true(isnan(fl_frame_wait(NULL)));
    fl_runtime *rt = fresh();
    assert_true(fl_frame_wait(rt) == 0);   /* lockstep */
    fl_free(rt);
}

NULL_TEST(fl_clock_pause)
{
    (void)unused;
    fl_clock_pause(NULL, true);   /* no-op */
    fl_clock_pause(NULL, false);
}

/* {=====================================================================
 * The state dictionary
 * ===================================================================== */

NULL_TEST(fl_state_get)
{
    (void)unused;
    char buf[32];
    assert_int_equal(fl_state_get(NULL, ":sp", buf, sizeof buf), -3);
    fl_runtime *rt = loaded();
    assert_int_equal(fl_state_get(rt, NULL, buf, sizeof buf), -3);
    expect_error(rt, "fl_state_get", "[key_text]");
    /* a NULL buffer receives nothing, whatever its capacity */
    assert_int_equal(fl_state_set(rt, "k", "1;2.5"), 0);
    assert_int_equal(fl_state_get(rt, "k", NULL, SIZE_MAX), 5);
    assert_int_equal(fl_state_get(rt, "k", buf, sizeof buf), 5);
    assert_string_equal(buf, "1;2.5");
    assert_int_equal(fl_state_get(rt, "", buf, sizeof buf), -1);   /* null: never stored */
    fl_free(rt);
}

NULL_TEST(fl_state_get_numbers)
{
    (void)unused;
    double x[4] = {0};
    assert_int_equal(fl_state_get_numbers(NULL, "k", x, 4), -3);
    fl_runtime *rt = fresh();
    assert_int_equal(fl_state_get_numbers(rt, NULL, x, 4), -3);
    expect_error(rt, "fl_state_get_numbers", "[key_text]");
    assert_int_equal(fl_state_set(rt, "k", "1;2;3"), 0);
    assert_int_equal(fl_state_get_numbers(rt, "k", NULL, SIZE_MAX), 3);
    assert_int_equal(fl_state_get_numbers(rt, "k", x, 4), 3);
    assert_true(x[0] == 1 && x[1] == 2 && x[2] == 3);
    fl_free(rt);
}

NULL_TEST(fl_state_set)
{
    (void)unused;
    assert_int_equal(fl_state_set(NULL, "k", "1"), -1);
    fl_runtime *rt = fresh();
    assert_int_equal(fl_state_set(rt, NULL, "1"), -1);
    expect_error(rt, "fl_state_set", "[key_text]");
    assert_int_equal(fl_state_set(rt, "k", NULL), -1);
    expect_error(rt, "fl_state_set", "[value_text]");
    assert_int_equal(fl_state_set(rt, "", "1"), -1);
    expect_error(rt, "fl_state_set", "key text is empty");
    assert_int_equal(fl_state_count(rt), 0);   /* state unchanged */
    fl_free(rt);
}

NULL_TEST(fl_state_set_numbers)
{
    (void)unused;
    const double x[3] = {1, 2, 3};
    assert_int_equal(fl_state_set_numbers(NULL, "k", x, 3), -1);
    fl_runtime *rt = fresh();
    assert_int_equal(fl_state_set_numbers(rt, NULL, x, 3), -1);
    expect_error(rt, "fl_state_set_numbers", "[key_text]");
    assert_int_equal(fl_state_set_numbers(rt, "k", NULL, 3), -1);
    expect_error(rt, "fl_state_set_numbers", "[values]");
    assert_int_equal(fl_state_set_numbers(rt, "", x, 3), -1);
    expect_error(rt, "fl_state_set_numbers", "key text is empty");
    /* counts past the longest vector, past 32 bits, and whose byte size
     * overflows: refused before [values] is read */
    const size_t huge[] = {((size_t)1 << 26) + 1, (size_t)UINT32_MAX + 1, SIZE_MAX / 8 + 1,
                           SIZE_MAX};
    for (size_t i = 0; i < sizeof huge / sizeof huge[0]; i++) {
        assert_int_equal(fl_state_set_numbers(rt, "k", x, huge[i]), -1);
        expect_error(rt, "fl_state_set_numbers", "longest vector");
    }
    assert_int_equal(fl_state_count(rt), 0);   /* state unchanged */
    assert_int_equal(fl_state_set_numbers(rt, "k", NULL, 0), 0);   /* n = 0 deletes */
    assert_int_equal(fl_state_set_numbers(rt, "k", x, 3), 0);
    assert_int_equal(fl_state_count(rt), 1);
    fl_free(rt);
}

NULL_TEST(fl_state_count)
{
    (void)unused;
    assert_int_equal(fl_state_count(NULL), 0);
}

static int count_entry(void *ctx, const char *key, const char *value)
{
    (void)key;
    (void)value;
    ++*(int *)ctx;
    return 0;
}

NULL_TEST(fl_state_iterate)
{
    (void)unused;
    int n = 0;
    assert_int_equal(fl_state_iterate(NULL, count_entry, &n), 0);
    fl_runtime *rt = loaded();
    assert_true(fl_state_count(rt) > 0);
    assert_int_equal(fl_state_iterate(rt, NULL, NULL), 0);
    expect_error(rt, "fl_state_iterate", "[fn]");
    assert_int_equal(fl_state_iterate(rt, count_entry, &n), fl_state_count(rt));
    assert_int_equal(n, (int)fl_state_count(rt));
    fl_free(rt);
}

NULL_TEST(fl_reset_state)
{
    (void)unused;
    fl_reset_state(NULL);   /* no-op */
}

NULL_TEST(fl_save_state)
{
    (void)unused;
    assert_int_equal(fl_save_state(NULL, "/nonexistent/s"), -1);
    fl_runtime *rt = loaded();
    assert_int_equal(fl_save_state(rt, NULL), -1);
    expect_error(rt, "fl_save_state", "[path]");
    fl_free(rt);
}

NULL_TEST(fl_restore_state)
{
    (void)unused;
    assert_int_equal(fl_restore_state(NULL, "/nonexistent/s"), -1);
    fl_runtime *rt = loaded();
    size_t before = fl_state_count(rt);
    assert_int_equal(fl_restore_state(rt, NULL), -1);
    expect_error(rt, "fl_restore_state", "[path]");
    assert_int_equal(fl_state_count(rt), before);
    assert_int_equal(fl_frame_count(rt), 2);
    fl_free(rt);
}

/* {=====================================================================
 * Dumps
 * ===================================================================== */

NULL_TEST(fl_dump_state)
{
    (void)unused;
    fl_dump_state(NULL, no_write, NULL);   /* writes nothing */
    fl_runtime *rt = loaded();
    fl_dump_state(rt, NULL, NULL);
    expect_error(rt, "fl_dump_state", "[fn]");
    size_t len = 0;
    fl_dump_state(rt, count_write, &len);
    assert_true(len > 0);
    fl_free(rt);
}

NULL_TEST(fl_dump_tree)
{
    (void)unused;
    assert_int_equal(fl_dump_tree(NULL, no_write, NULL), -1);
    fl_runtime *rt = fresh();
    assert_int_equal(fl_dump_tree(rt, no_write, NULL), -1);
    expect_error(rt, "fl_dump_tree", "no frame");
    fl_free(rt);
    rt = loaded();
    assert_int_equal(fl_dump_tree(rt, NULL, NULL), -1);
    expect_error(rt, "fl_dump_tree", "[fn]");
    fl_free(rt);
}

NULL_TEST(fl_dump_program)
{
    (void)unused;
    assert_int_equal(fl_dump_program(NULL, no_write, NULL), -1);
    fl_runtime *rt = fresh();
    assert_int_equal(fl_dump_program(rt, no_write, NULL), -1);
    expect_error(rt, "fl_dump_program", "no program");
    fl_free(rt);
    rt = loaded();
    assert_int_equal(fl_dump_program(rt, NULL, NULL), -1);
    expect_error(rt, "fl_dump_program", "[fn]");
    fl_free(rt);
}

/* fl_dump_tokens and fl_dump_ast: NULL runtime, path and writer. */
static void dump_syntax_nulls(int (*dump)(fl_runtime *, const char *, fl_write_fn, void *),
                              const char *name)
{
    assert_int_equal(dump(NULL, "x.fl", no_write, NULL), -1);
    fl_runtime *rt = fresh();
    assert_int_equal(dump(rt, NULL, no_write, NULL), -1);
    expect_error(rt, name, "[path]");
    assert_int_equal(dump(rt, "x.fl", NULL, NULL), -1);
    expect_error(rt, name, "[fn]");
    fl_free(rt);
}

NULL_TEST(fl_dump_tokens)
{
    (void)unused;
    dump_syntax_nulls(fl_dump_tokens, "fl_dump_tokens");
}

NULL_TEST(fl_dump_ast)
{
    (void)unused;
    dump_syntax_nulls(fl_dump_ast, "fl_dump_ast");
}

/* {=====================================================================
 * Evaluating text
 * ===================================================================== */

NULL_TEST(fl_eval)
{
    (void)unused;
    assert_int_equal(fl_eval(NULL, "1", 1, no_write, NULL), -1);
    fl_runtime *rt = loaded();
    assert_int_equal(fl_eval(rt, NULL, 3, no_write, NULL), -1);
    expect_error(rt, "fl_eval", "[text]");
    assert_int_equal(fl_eval(rt, "1+1", SIZE_MAX, no_write, NULL), -1);
    expect_error(rt, "fl_eval", "limit");
    /* a NULL writer drops the output; the binding is made */
    assert_int_equal(fl_eval(rt, "let zz=41", 9, NULL, NULL), 0);
    size_t len = 0;
    assert_int_equal(fl_eval(rt, "zz+1", 4, count_write, &len), 0);
    assert_int_equal(len, 3);   /* "42\n" */
    /* NULL with length 0 is the empty text */
    len = 0;
    assert_true(fl_eval(rt, NULL, 0, count_write, &len) >= 0);
    fl_free(rt);
}

NULL_TEST(fl_state_set_expr)
{
    (void)unused;
    assert_int_equal(fl_state_set_expr(NULL, ":k", "1", no_write, NULL), -1);
    fl_runtime *rt = loaded();
    assert_int_equal(fl_state_set_expr(rt, NULL, "1", no_write, NULL), -1);
    expect_error(rt, "fl_state_set_expr", "[key_expr]");
    assert_int_equal(fl_state_set_expr(rt, ":k", NULL, no_write, NULL), -1);
    expect_error(rt, "fl_state_set_expr", "[value_expr]");
    assert_int_equal(fl_state_set_expr(rt, ":k", "2*3", NULL, NULL), 0);   /* output dropped */
    double x = 0;
    assert_int_equal(fl_state_get_numbers(rt, ":k", &x, 1), 1);
    assert_true(x == 6);
    fl_free(rt);
}

NULL_TEST(fl_eval_reset)
{
    (void)unused;
    fl_eval_reset(NULL);   /* no-op */
}

static int count_name(void *ctx, const char *name)
{
    (void)name;
    ++*(int *)ctx;
    return 0;
}

NULL_TEST(fl_scope_names)
{
    (void)unused;
    int n = 0;
    assert_int_equal(fl_scope_names(NULL, count_name, &n), 0);
    fl_runtime *rt = loaded();
    assert_int_equal(fl_scope_names(rt, NULL, NULL), 0);
    expect_error(rt, "fl_scope_names", "[fn]");
    assert_true(fl_scope_names(rt, count_name, &n) > 0);
    fl_free(rt);
}

NULL_TEST(fl_builtin_name)
{
    (void)unused;
    assert_non_null(fl_builtin_name(0));
    assert_null(fl_builtin_name(SIZE_MAX));
}

NULL_TEST(fl_number_text)
{
    (void)unused;
    /* a NULL buffer receives nothing, whatever its capacity */
    assert_int_equal(fl_number_text(-2.5, NULL, SIZE_MAX), 4);
    char b[2] = {'x', 'x'};
    assert_int_equal(fl_number_text(-2.5, b, 1), 4);
    assert_int_equal(b[0], '\0');
    assert_int_equal(b[1], 'x');
}

/* {=====================================================================
 * Particles, pictures, outputs
 * ===================================================================== */

NULL_TEST(fl_particles)
{
    (void)unused;
    assert_int_equal(fl_particles(NULL, ":dish", NULL, NULL), -1);
    fl_runtime *rt = loaded();
    assert_int_equal(fl_particles(rt, NULL, NULL, NULL), -1);
    expect_error(rt, "fl_particles", "[system_text]");
    assert_int_equal(fl_particles(rt, "", NULL, NULL), -1);
    expect_error(rt, "", "empty");
    assert_int_equal(fl_particles(rt, ":dish", NULL, NULL), 2);   /* NULL fn: counts */
    fl_free(rt);
}

NULL_TEST(fl_outputs_open)
{
    (void)unused;
    assert_null(fl_outputs_open(NULL, NULL));
    fl_output_options o = {.view = "/nonexistent/v.png"};
    assert_null(fl_outputs_open(NULL, &o));
    fl_runtime *rt = fresh();
    fl_outputs *out = fl_outputs_open(rt, NULL);   /* NULL: no file outputs */
    assert_non_null(out);
    assert_int_equal(fl_outputs_close(out, rt), 0);
    fl_free(rt);
}

NULL_TEST(fl_outputs_frame)
{
    (void)unused;
    fl_runtime *rt = loaded();
    fl_outputs *out = fl_outputs_open(rt, NULL);
    assert_non_null(out);
    assert_int_equal(fl_outputs_frame(out, NULL), -1);
    assert_int_equal(fl_outputs_frame(NULL, rt), -1);
    expect_error(rt, "fl_outputs_frame", "[out]");
    assert_int_equal(fl_outputs_frame(out, rt), 0);
    assert_int_equal(fl_outputs_close(out, rt), 0);
    fl_free(rt);
}

NULL_TEST(fl_outputs_draws)
{
    (void)unused;
    assert_false(fl_outputs_draws(NULL, NULL));
    fl_runtime *rt = loaded();
    fl_outputs *out = fl_outputs_open(rt, NULL);
    assert_non_null(out);
    assert_false(fl_outputs_draws(NULL, rt));
    assert_false(fl_outputs_draws(out, NULL));
    assert_false(fl_outputs_draws(out, rt));   /* no !record */
    assert_int_equal(fl_outputs_close(out, rt), 0);
    fl_free(rt);
}

NULL_TEST(fl_outputs_close)
{
    (void)unused;
    assert_int_equal(fl_outputs_close(NULL, NULL), 0);   /* a no-op */
    fl_runtime *rt = loaded();
    assert_int_equal(fl_outputs_close(NULL, rt), 0);
    fl_outputs *out = fl_outputs_open(rt, NULL);
    assert_non_null(out);
    assert_int_equal(fl_outputs_frame(out, rt), 0);
    /* closed and freed all the same (LeakSanitizer and valgrind check) */
    assert_int_equal(fl_outputs_close(out, NULL), -1);
    fl_free(rt);
}

NULL_TEST(fl_view)
{
    (void)unused;
    assert_int_equal(fl_view(NULL, "/nonexistent/v.png", NULL), -1);
    fl_runtime *rt = loaded();
    assert_int_equal(fl_view(rt, NULL, NULL), -1);
    expect_error(rt, "fl_view", "[path]");
    char dir[] = "/tmp/test_api_null.XXXXXX";
    assert_non_null(mkdtemp(dir));
    char path[64];
    snprintf(path, sizeof path, "%s/v.png", dir);
    assert_int_equal(fl_view(rt, path, NULL), 0);   /* NULL [nsystems]: allowed */
    assert_int_equal(unlink(path), 0);
    assert_int_equal(rmdir(dir), 0);
    fl_free(rt);
}

NULL_TEST(fl_check_output)
{
    (void)unused;
    char err[64];
    assert_int_equal(fl_check_output(NULL, err, sizeof err), -1);
    assert_string_equal(err, "no file name");
    assert_int_equal(fl_check_output(NULL, NULL, SIZE_MAX), -1);
    assert_int_equal(fl_check_output("/nonexistent/x.png", NULL, SIZE_MAX), -1);
}

NULL_TEST(fl_windows)
{
    (void)unused;
    fl_window_info w[2];
    assert_int_equal(fl_windows(NULL, w, 2), 0);
    fl_runtime *rt = loaded();
    assert_int_equal(fl_windows(rt, NULL, SIZE_MAX), 1);   /* NULL [out]: counts */
    assert_int_equal(fl_windows(rt, w, 2), 1);
    assert_int_equal(w[0].width, 16);
    fl_free(rt);
}

NULL_TEST(fl_draw_window)
{
    (void)unused;
    uint32_t pix[16 * 8];
    assert_int_equal(fl_draw_window(NULL, 0, pix, 16, 8, 64), -1);
    fl_runtime *rt = loaded();
    assert_int_equal(fl_draw_window(rt, 0, NULL, 16, 8, 64), -1);
    expect_error(rt, "fl_draw_window", "no pixel buffer");
    assert_int_equal(fl_draw_window(rt, SIZE_MAX, pix, 16, 8, 64), -1);
    expect_error(rt, "fl_draw_window", "no window");
    assert_int_equal(fl_draw_window(rt, 0, pix, INT_MIN, INT_MAX, 64), -1);
    expect_error(rt, "fl_draw_window", "16x8");
    assert_int_equal(fl_draw_window(rt, 0, pix, 16, 8, SIZE_MAX), -1);
    expect_error(rt, "fl_draw_window", "stride");
    assert_int_equal(fl_draw_window(rt, 0, pix, 16, 8, 63), -1);
    expect_error(rt, "fl_draw_window", "stride");
    assert_int_equal(fl_draw_window(rt, 0, pix, 16, 8, 64), 0);
    fl_free(rt);
}

NULL_TEST(fl_gl_attach)
{
    (void)unused;
    assert_int_equal(fl_gl_attach(NULL), -1);
    fl_runtime *rt = loaded();
    /* no OpenGL context is current on this thread */
    assert_int_equal(fl_gl_attach(rt), -1);
    expect_error(rt, "fl_gl_attach", "fl_gl_attach");
    fl_free(rt);
}

NULL_TEST(fl_gl_window_texture)
{
    (void)unused;
    int w = 7, h = 9;
    assert_int_equal(fl_gl_window_texture(NULL, 0, &w, &h), 0);
    assert_int_equal(w, 0);
    assert_int_equal(h, 0);
    fl_runtime *rt = loaded();
    assert_int_equal(fl_gl_window_texture(rt, SIZE_MAX, NULL, NULL), 0);   /* no such window, NULL sizes */
    fl_free(rt);
}

/* The pictures drawn beside the frame loop (fl_picture_take): NULL
 * arguments, and no picture before the windows are shown (nothing drawn
 * here: test_pictures_thread draws them). */
NULL_TEST(fl_picture_take)
{
    (void)unused;
    assert_null(fl_picture_take(NULL));
    fl_runtime *rt = fresh();
    assert_null(fl_picture_take(rt));   /* no program, no frame */
    fl_free(rt);
    rt = loaded();
    assert_null(fl_picture_take(rt));   /* windows not shown */
    assert_string_equal(fl_error(rt), "");
    fl_free(rt);
}

NULL_TEST(fl_picture_draw)
{
    (void)unused;
    assert_int_equal(fl_picture_draw(NULL, NULL), -1);
    fl_runtime *rt = loaded();
    assert_int_equal(fl_picture_draw(rt, NULL), -1);
    assert_string_equal(fl_error(rt), "");   /* (fl_error is the frame loop's) */
    fl_free(rt);
}

NULL_TEST(fl_picture_texture)
{
    (void)unused;
    int w = 7, h = 9;
    assert_int_equal(fl_picture_texture(NULL, NULL, 0, &w, &h), 0);
    assert_int_equal(w, 0);
    assert_int_equal(h, 0);
    fl_runtime *rt = loaded();
    assert_int_equal(fl_picture_texture(rt, NULL, 0, NULL, NULL), 0);
    fl_free(rt);
}

NULL_TEST(fl_picture_read)
{
    (void)unused;
    uint32_t px[16 * 8];
    assert_int_equal(fl_picture_read(NULL, NULL, 0, px, 16, 8, 64), -1);
    fl_runtime *rt = loaded();
    assert_int_equal(fl_picture_read(rt, NULL, 0, px, 16, 8, 64), -1);
    assert_string_equal(fl_error(rt), "");
    fl_free(rt);
}

NULL_TEST(fl_picture_frame)
{
    (void)unused;
    assert_int_equal(fl_picture_frame(NULL), -1);
}

NULL_TEST(fl_picture_free)
{
    (void)unused;
    fl_picture_free(NULL, NULL);   /* a no-op */
    fl_runtime *rt = loaded();
    fl_picture_free(rt, NULL);
    fl_free(rt);
}

NULL_TEST(fl_set_window_scale)
{
    (void)unused;
    fl_set_window_scale(NULL, 0.5, 2);   /* a no-op */
    fl_runtime *rt = loaded();
    int samples = 7;
    assert_true(fl_window_scale(rt, &samples) == 1);   /* nothing drawn yet */
    assert_int_equal(samples, 0);
    fl_set_window_scale(rt, NAN, -3);   /* out of range: full size, no cap */
    fl_set_window_scale(rt, 0.5, 1);
    assert_true(fl_window_scale(rt, NULL) == 1);   /* not drawn yet: the last drawn is still whole */
    fl_free(rt);
}

NULL_TEST(fl_window_scale)
{
    (void)unused;
    int samples = 7;
    assert_true(fl_window_scale(NULL, &samples) == 1);
    assert_int_equal(samples, 0);
    assert_true(fl_window_scale(NULL, NULL) == 1);
}

NULL_TEST(fl_draw_view)
{
    (void)unused;
    uint32_t pix[16 * 8];
    size_t ns = 99;
    assert_int_equal(fl_draw_view(NULL, pix, 16, 8, 64, &ns), -1);
    assert_int_equal(ns, 0);
    fl_runtime *rt = loaded();
    assert_int_equal(fl_draw_view(rt, NULL, 16, 8, 64, NULL), -1);
    expect_error(rt, "fl_draw_view", "no pixel buffer");
    assert_int_equal(fl_draw_view(rt, pix, INT_MAX, 8, 64, NULL), -1);
    expect_error(rt, "fl_draw_view", "outside 1..16384");
    assert_int_equal(fl_draw_view(rt, pix, 16, -8, 64, NULL), -1);
    expect_error(rt, "fl_draw_view", "outside 1..16384");
    assert_int_equal(fl_draw_view(rt, pix, 16, 8, SIZE_MAX, NULL), -1);
    expect_error(rt, "fl_draw_view", "stride");
    assert_int_equal(fl_draw_view(rt, pix, 16, 8, 64, NULL), 0);   /* NULL [nsystems] */
    assert_int_equal(fl_draw_view(rt, pix, 16, 8, 64, &ns), 0);
    assert_int_equal(ns, 1);
    fl_free(rt);
}

NULL_TEST(fl_view_snapshot_take)
{
    (void)unused;
    assert_null(fl_view_snapshot_take(NULL, NULL));
    fl_runtime *rt = loaded();
    fl_view_snapshot *snap = fl_view_snapshot_take(rt, NULL);   /* NULL [reuse]: a new one */
    assert_non_null(snap);
    assert_null(fl_view_snapshot_take(NULL, snap));
    assert_ptr_equal(fl_view_snapshot_take(rt, snap), snap);
    fl_view_snapshot_free(snap);
    fl_free(rt);
}

NULL_TEST(fl_view_snapshot_free)
{
    (void)unused;
    fl_view_snapshot_free(NULL);
}

NULL_TEST(fl_view_painter_new)
{
    (void)unused;
    fl_view_painter *p = fl_view_painter_new();
    assert_non_null(p);
    fl_view_painter_free(p);
}

NULL_TEST(fl_view_painter_free)
{
    (void)unused;
    fl_view_painter_free(NULL);
}

NULL_TEST(fl_view_painter_draw)
{
    (void)unused;
    uint32_t pix[16 * 8];
    size_t ns = 99;
    fl_runtime *rt = loaded();
    fl_view_snapshot *snap = fl_view_snapshot_take(rt, NULL);
    fl_view_painter *p = fl_view_painter_new();
    assert_int_equal(fl_view_painter_draw(NULL, snap, pix, 16, 8, 64, &ns), -1);
    assert_int_equal(ns, 0);
    assert_int_equal(fl_view_painter_draw(p, NULL, pix, 16, 8, 64, NULL), -1);
    assert_int_equal(fl_view_painter_draw(p, snap, NULL, 16, 8, 64, NULL), -1);
    assert_int_equal(fl_view_painter_draw(p, snap, pix, INT_MAX, 8, 64, NULL), -1);
    assert_int_equal(fl_view_painter_draw(p, snap, pix, 16, -8, 64, NULL), -1);
    assert_int_equal(fl_view_painter_draw(p, snap, pix, 16, 8, SIZE_MAX, NULL), -1);
    assert_int_equal(fl_view_painter_draw(p, snap, pix, 16, 8, 63, NULL), -1);
    assert_int_equal(fl_view_painter_draw(p, snap, pix, 16, 8, 64, NULL), 0);   /* NULL [nsystems] */
    assert_int_equal(fl_view_painter_draw(p, snap, pix, 16, 8, 64, &ns), 0);
    assert_int_equal(ns, 1);
    fl_view_painter_free(p);
    fl_view_snapshot_free(snap);
    fl_free(rt);
}

/* {=====================================================================
 * Input
 * ===================================================================== */

NULL_TEST(fl_key)
{
    (void)unused;
    assert_int_equal(fl_key(NULL, 0, "space", true), -1);
    fl_runtime *rt = loaded();
    assert_int_equal(fl_key(rt, 0, NULL, true), -1);
    expect_error(rt, "fl_key", "[name]");
    assert_int_equal(fl_key(rt, SIZE_MAX, "space", true), 0);   /* no such window */
    assert_int_equal(fl_key(rt, 0, "space", true), 1);
    double x = 0;
    assert_int_equal(fl_state_get_numbers(rt, ":sp", &x, 1), 1);
    assert_true(x == 1);
    fl_free(rt);
}

NULL_TEST(fl_pointer)
{
    (void)unused;
    fl_pointer(NULL, 0, true, 0.5, 0.5);   /* no-op */
    fl_runtime *rt = loaded();
    size_t n = fl_state_count(rt);
    fl_pointer(rt, SIZE_MAX, true, 0.5, 0.5);   /* no such window: no-op */
    assert_int_equal(fl_state_count(rt), n);
    fl_pointer(rt, 0, true, 0.25, 0.5);
    double xy[2];
    assert_int_equal(fl_state_get_numbers(rt, ":ptr", xy, 2), 2);
    assert_true(xy[0] == 0.25 && xy[1] == 0.5);
    fl_free(rt);
}

NULL_TEST(fl_pointer_button)
{
    (void)unused;
    fl_pointer_button(NULL, 0, 0, true);   /* no-op */
    fl_runtime *rt = loaded();
    size_t n = fl_state_count(rt);
    fl_pointer_button(rt, SIZE_MAX, 0, true);
    assert_int_equal(fl_state_count(rt), n);
    fl_pointer_button(rt, 0, INT_MIN, true);   /* any button number is a key part */
    double b = 0;
    assert_int_equal(fl_state_get_numbers(rt, ":ptr;-2147483648", &b, 1), 1);
    assert_true(b == 1);
    fl_free(rt);
}

/* {=====================================================================
 * Program files and statistics
 * ===================================================================== */

NULL_TEST(fl_program_files)
{
    (void)unused;
    const char *paths[4];
    assert_int_equal(fl_program_files(NULL, paths, 4), 0);
    fl_runtime *rt = loaded();
    size_t n = fl_program_files(rt, NULL, 0);
    assert_int_equal(fl_program_files(rt, NULL, SIZE_MAX), n);   /* NULL [out]: counts */
    fl_free(rt);
}

NULL_TEST(fl_get_stats)
{
    (void)unused;
    fl_stats s;
    memset(&s, 0xff, sizeof s);
    fl_get_stats(NULL, &s);   /* all zero */
    assert_int_equal(s.frames, 0);
    assert_int_equal(s.mallocs, 0);
    assert_true(s.eval_seconds == 0);
    fl_runtime *rt = loaded();
    fl_get_stats(rt, NULL);   /* no-op */
    fl_get_stats(rt, &s);
    assert_int_equal(s.frames, 2);
    fl_free(rt);
}

/* {=====================================================================
 * Coverage: one null_<function> test per FL_API function of flitter.h
 * ===================================================================== */

static void every_function_is_covered(void **unused);

#define T(fn) cmocka_unit_test(null_##fn)
static const struct CMUnitTest tests[] = {
    T(fl_version), T(fl_default_options), T(fl_parse_memory), T(fl_parse_pairs),
    T(fl_parse_particles), T(fl_parse_physics), T(fl_parse_view_axes), T(fl_new), T(fl_free), T(fl_error), T(fl_define), T(fl_define_numbers),
    T(fl_load),
    T(fl_load_text), T(fl_step), T(fl_frame_count), T(fl_frame_time), T(fl_next_frame_time), T(fl_target_fps),
    T(fl_frame_wait), T(fl_clock_pause), T(fl_state_get), T(fl_state_get_numbers),
    T(fl_state_set), T(fl_state_set_numbers), T(fl_state_count), T(fl_state_iterate),
    T(fl_reset_state), T(fl_save_state), T(fl_restore_state), T(fl_dump_state),
    T(fl_dump_tree), T(fl_dump_program), T(fl_dump_tokens), T(fl_dump_ast), T(fl_eval),
    T(fl_state_set_expr), T(fl_eval_reset), T(fl_scope_names), T(fl_builtin_name),
    T(fl_number_text), T(fl_particles), T(fl_outputs_open), T(fl_outputs_frame), T(fl_outputs_draws),
    T(fl_outputs_close), T(fl_view), T(fl_check_output), T(fl_windows), T(fl_draw_window),
    T(fl_gl_attach), T(fl_gl_window_texture), T(fl_picture_take), T(fl_picture_draw), T(fl_picture_texture),
    T(fl_picture_read), T(fl_picture_frame), T(fl_picture_free), T(fl_set_window_scale), T(fl_window_scale), T(fl_draw_view), T(fl_view_snapshot_take), T(fl_view_snapshot_free),
    T(fl_view_painter_new), T(fl_view_painter_free), T(fl_view_painter_draw), T(fl_key), T(fl_pointer), T(fl_pointer_button), T(fl_program_files),
    T(fl_get_stats),
    cmocka_unit_test(every_function_is_covered),
};
#undef T
#define NTESTS (sizeof tests / sizeof tests[0])

/* Is there a test named null_[name]? */
static bool covered(const char *name)
{
    for (size_t i = 0; i < NTESTS; i++)
        if (strncmp(tests[i].name, "null_", 5) == 0 && strcmp(tests[i].name + 5, name) == 0)
            return true;
    return false;
}

static void every_function_is_covered(void **unused)
{
    (void)unused;
    if (!header_path) fail_msg("usage: test_api_null PATH/TO/flitter.h");
    FILE *f = fopen(header_path, "r");
    if (!f) fail_msg("cannot open %s", header_path);
    char line[1024], missing[2048] = "";
    int declared = 0;
    while (fgets(line, sizeof line, f)) {
        if (strncmp(line, "FL_API ", 7) != 0) continue;
        /* the name is the identifier just before the first '(' */
        char *paren = strchr(line, '(');
        if (!paren) continue;
        char *start = paren;
        while (start > line && (start[-1] == '_' || (start[-1] >= 'a' && start[-1] <= 'z') ||
                                (start[-1] >= '0' && start[-1] <= '9')))
            start--;
        *paren = '\0';
        declared++;
        if (!covered(start) && strlen(missing) + strlen(start) + 2 < sizeof missing) {
            strcat(missing, " ");
            strcat(missing, start);
        }
    }
    fclose(f);
    if (missing[0]) fail_msg("functions of flitter.h without a null_ test:%s", missing);
    /* the header was read: as many functions as tests (a test for a removed function fails) */
    assert_int_equal(declared, (int)NTESTS - 1);
}

int main(int argc, char **argv)
{
    header_path = argc > 1 ? argv[1] : NULL;
    return cmocka_run_group_tests(tests, NULL, NULL);
}
