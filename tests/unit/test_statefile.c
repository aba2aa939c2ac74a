/* test_statefile.c: the exact state file round-trips every double bit for
 * bit (including -0 and NaN payloads), strings and symbols, and refuses a
 * malformed file without touching the dictionary. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "statefile.h"

static double from_bits(uint64_t u)
{
    double x;
    memcpy(&x, &u, sizeof x);
    return x;
}

static void test_round_trip(void **s)
{
    (void)s;
    char path[] = "/tmp/flitter-statefile-XXXXXX";
    int fd = mkstemp(path);
    assert_true(fd >= 0);
    close(fd);
    SymTab *st = symtab_new();
    StateDict *sd = state_new();
    double odd[] = {-0.0, 5e-324, 0.1 + 0.2, -1.2345678901234568e+17, INFINITY, -INFINITY,
                    from_bits(UINT64_C(0x7ff8000000000000)), from_bits(UINT64_C(0xfff0000000000123)),
                    symtab_add(st, "velocity", 8)};
    Vec *k1 = vec_num1(symtab_add(st, "dish", 4)), *v1 = vec_from_nums(odd, 9);
    Vec *k2 = vec_str("_counter", 8), *v2 = vec_str("tab\there \"q\" ;=\n\x01", 17);
    state_set(sd, k1, v1);
    state_set(sd, k2, v2);
    StateClock c = {42, 0.7000000000000001, 0.6833333333333333, 1.4, 0.5, 4, -0.0}, c2;
    Buf err = BUF_INIT;
    assert_int_equal(statefile_save(sd, st, &c, path, NULL, &err), 0);
    StateDict *back = state_new();
    SymTab *st2 = symtab_new();
    assert_int_equal(statefile_load(back, st2, &c2, path, &err), 0);
    assert_int_equal(state_count(back), 2);
    const Vec *r1 = state_get(back, k1);
    assert_non_null(r1);
    assert_int_equal(r1->len, 9);
    assert_memory_equal(vec_cnums(r1), odd, sizeof odd);   /* bit for bit */
    assert_true(vec_key_equal(state_get(back, k2), v2));
    assert_int_equal(c2.frame, 42);
    assert_memory_equal(&c2.time, &c.time, sizeof(double));
    assert_true(signbit(c2.start));
    assert_string_equal(symtab_name(st2, odd[8])->bytes, "velocity");

    /* a truncated copy is refused and leaves the dictionary alone */
    FILE *f = fopen(path, "r+");
    assert_non_null(f);
    fseek(f, 0, SEEK_END);
    long size = ftell(f);
    fclose(f);
    assert_int_equal(truncate(path, size - 8), 0);
    buf_reset(&err);
    assert_int_equal(statefile_load(back, st2, &c2, path, &err), -1);
    assert_non_null(strstr(buf_cstr(&err), "refused"));
    assert_int_equal(state_count(back), 2);
    assert_int_equal(c2.frame, 42);

    unlink(path);
    buf_free(&err);
    vec_release(k1); vec_release(v1); vec_release(k2); vec_release(v2);
    state_free(sd); state_free(back); symtab_free(st); symtab_free(st2);
}

static void test_malformed(void **s)
{
    (void)s;
    static const char *const bad[] = {
        "flitter-state 2\nclock 0 0 0 0 0.5 4 0\nend 0\n",          /* other version */
        "flitter-state 1\nclock 0 0 0 0 0.5 4 0\n1 = \nend 1\n",    /* empty value */
        "flitter-state 1\nclock 0 0 0 0 0.5 4 0\n1 = 2;x\nend 1\n", /* bad number */
        "flitter-state 1\nclock 0 0 0 0 0.5 4 0\n1 = \"open\nend 1\n", /* open string */
        "flitter-state 1\nclock 0 0 0 0 0.5 4 0\n1 = 2\nend 2\n",   /* wrong count */
        "flitter-state 1\n1 = 2\nend 1\n",                         /* no clock */
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        char path[] = "/tmp/flitter-statefile-XXXXXX";
        int fd = mkstemp(path);
        assert_true(fd >= 0);
        assert_int_equal(write(fd, bad[i], strlen(bad[i])), (ssize_t)strlen(bad[i]));
        close(fd);
        StateDict *sd = state_new();
        SymTab *st = symtab_new();
        Vec *k = vec_num1(7), *v = vec_num1(8);
        state_set(sd, k, v);
        StateClock c = {0};
        Buf err = BUF_INIT;
        assert_int_equal(statefile_load(sd, st, &c, path, &err), -1);
        assert_int_equal(state_count(sd), 1);
        buf_free(&err);
        vec_release(k); vec_release(v);
        state_free(sd);
        symtab_free(st);
        unlink(path);
    }
}

/* Write the [len] bytes at [text] to a fresh temporary file; its path in
 * [path] (a "/tmp/flitter-statefile-XXXXXX" buffer). */
static void temp_file(char *path, const char *text, size_t len)
{
    int fd = mkstemp(path);
    assert_true(fd >= 0);
    assert_int_equal(write(fd, text, len), (ssize_t)len);
    close(fd);
}

/* Every field is range-checked: each bad file is refused with its exact
 * message and the dictionary and clock are left as they were; the
 * boundary values are accepted. */
static void test_range_checks(void **s)
{
    (void)s;
#define HEAD "flitter-state 1\n"
#define CLOCK "clock 3 0 0 0 0.5 4 0\n"
    static const struct { const char *text; size_t len; int line; const char *why; } bad[] = {
#define CASE(t, line, why) {t, sizeof t - 1, line, why}
        CASE(HEAD "clock 9223372036854775807 0 0 0 0.5 4 0\nend 0\n", 2,
             "frame number out of range (0 to 2^53)"),
        CASE(HEAD "clock 9007199254740993 0 0 0 0.5 4 0\nend 0\n", 2,
             "frame number out of range (0 to 2^53)"),
        CASE(HEAD "clock -1 0 0 0 0.5 4 0\nend 0\n", 2, "frame number out of range (0 to 2^53)"),
        CASE(HEAD "clock +1 0 0 0 0.5 4 0\nend 0\n", 2, "frame number out of range (0 to 2^53)"),
        CASE(HEAD "clock  1 0 0 0 0.5 4 0\nend 0\n", 2, "frame number out of range (0 to 2^53)"),
        CASE(HEAD "clock 1 inf 0 0 0.5 4 0\nend 0\n", 2, "clock time out of range (not finite)"),
        CASE(HEAD "clock 1 0 0 nan 0.5 4 0\nend 0\n", 2, "clock time out of range (not finite)"),
        CASE(HEAD "clock 1 0 0 0 0 4 0\nend 0\n", 2,
             "clock period or quantum out of range (not positive and finite)"),
        CASE(HEAD "clock 1 0 0 0 0.5 -4 0\nend 0\n", 2,
             "clock period or quantum out of range (not positive and finite)"),
        CASE(HEAD "clock 1 0 0 0 0.5 4 0 \nend 0\n", 2, "malformed clock line"),
        CASE(HEAD "clock 1 0x10 0 0 0.5 4 0\nend 0\n", 2, "malformed clock line"),
        CASE(HEAD CLOCK CLOCK "end 0\n", 3, "second clock line"),
        CASE(HEAD CLOCK "1 = 1e999\nend 1\n", 3, "malformed value"),
        CASE(HEAD CLOCK "1 = 1.\nend 1\n", 3, "malformed value"),
        CASE(HEAD CLOCK "1 = 1e\nend 1\n", 3, "malformed value"),
        CASE(HEAD CLOCK "1 = .5\nend 1\n", 3, "malformed value"),
        CASE(HEAD CLOCK "1 = 2\n1 = 3\nend 2\n", 4, "duplicate key"),
        /* an escape making invalid UTF-8 (found by tests/fuzz) */
        CASE(HEAD CLOCK "1 = \"a\\xbe\"\nend 1\n", 3, "malformed value"),
        CASE(HEAD CLOCK "end -1\n", 3, "entry count does not match (truncated file?)"),
        CASE(HEAD CLOCK "end 18446744073709551616\n", 3,
             "entry count does not match (truncated file?)"),
        CASE(HEAD CLOCK "end 0\nx", 4, "truncated line"),
#undef CASE
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        char path[] = "/tmp/flitter-statefile-XXXXXX";
        temp_file(path, bad[i].text, bad[i].len);
        StateDict *sd = state_new();
        SymTab *st = symtab_new();
        Vec *k = vec_num1(7), *v = vec_num1(8);
        state_set(sd, k, v);
        StateClock c = {42, 1, 2, 3, 4, 5, 6};
        Buf err = BUF_INIT;
        if (statefile_load(sd, st, &c, path, &err) != -1)
            fail_msg("case %zu accepted", i);
        char want[256];
        snprintf(want, sizeof want, "%s:%d: error: %s; state file refused\n", path, bad[i].line,
                 bad[i].why);
        assert_string_equal(buf_cstr(&err), want);
        assert_int_equal(state_count(sd), 1);
        assert_true(c.frame == 42 && c.time == 1 && c.start == 6);
        buf_free(&err);
        vec_release(k); vec_release(v);
        state_free(sd);
        symtab_free(st);
        unlink(path);
    }

    /* NUL bytes and invalid UTF-8 anywhere (even after the end line) */
    static const struct { const char *text; size_t len; } binary[] = {
        {HEAD CLOCK "end 0\n\0junk\n", sizeof HEAD CLOCK "end 0\n\0junk\n" - 1},
        {HEAD CLOCK "1 = \"a\xff\"\nend 1\n", sizeof HEAD CLOCK "1 = \"a\xff\"\nend 1\n" - 1},
    };
    for (size_t i = 0; i < 2; i++) {
        char path[] = "/tmp/flitter-statefile-XXXXXX";
        temp_file(path, binary[i].text, binary[i].len);
        StateDict *sd = state_new();
        SymTab *st = symtab_new();
        StateClock c = {0};
        Buf err = BUF_INIT;
        assert_int_equal(statefile_load(sd, st, &c, path, &err), -1);
        char want[256];
        snprintf(want, sizeof want, "%s: error: not a flitter state file (NUL byte or invalid "
                 "UTF-8); state file refused\n", path);
        assert_string_equal(buf_cstr(&err), want);
        buf_free(&err);
        state_free(sd);
        symtab_free(st);
        unlink(path);
    }

    /* the boundaries are accepted */
    static const char good[] = HEAD "clock 9007199254740992 1e300 -1e300 5e-324 1e-300 1e300 -0\n"
                               "1 = -0;1.5e-7;2e+20\nend 1\n";
    char path[] = "/tmp/flitter-statefile-XXXXXX";
    temp_file(path, good, sizeof good - 1);
    StateDict *sd = state_new();
    SymTab *st = symtab_new();
    StateClock c = {0};
    Buf err = BUF_INIT;
    assert_int_equal(statefile_load(sd, st, &c, path, &err), 0);
    assert_int_equal(err.len, 0);
    assert_true(c.frame == INT64_C(9007199254740992));
    assert_true(c.time == 1e300 && c.last_time == -1e300 && c.last_beat == 5e-324);
    assert_true(c.period == 1e-300 && c.quantum == 1e300 && c.start == 0 && signbit(c.start));
    assert_int_equal(state_count(sd), 1);
    buf_free(&err);
    state_free(sd);
    symtab_free(st);
    unlink(path);
#undef HEAD
#undef CLOCK
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_round_trip),
        cmocka_unit_test(test_malformed),
        cmocka_unit_test(test_range_checks),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
