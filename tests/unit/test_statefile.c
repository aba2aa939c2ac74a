/* test_statefile.c: the exact state file round-trips every double bit for
 * bit (including -0 and NaN payloads), strings and symbols, and refuses a
 * malformed file without touching the dictionary. A property test saves
 * random states (keys and values with every byte class, ` = ` inside
 * strings, odd symbol names, infinities, NaNs, subnormals, the largest
 * frame and clock) and loads them back equal; every single-bit flip of a
 * saved file is refused (checksum); the script line comes back. */
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
    assert_int_equal(statefile_save(sd, st, &c, NULL, path, NULL, &err), 0);
    StateDict *back = state_new();
    SymTab *st2 = symtab_new();
    assert_int_equal(statefile_load(back, st2, &c2, NULL, path, &err), 0);
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
    assert_int_equal(statefile_load(back, st2, &c2, NULL, path, &err), -1);
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
        assert_int_equal(statefile_load(sd, st, &c, NULL, path, &err), -1);
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
        if (statefile_load(sd, st, &c, NULL, path, &err) != -1)
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
        assert_int_equal(statefile_load(sd, st, &c, NULL, path, &err), -1);
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
    assert_int_equal(statefile_load(sd, st, &c, NULL, path, &err), 0);
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

/* splitmix64, for reproducible random states */
static uint64_t next_u64(uint64_t *x)
{
    uint64_t z = (*x += 0x9E3779B97F4A7C15u);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9u;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBu;
    return z ^ (z >> 31);
}

/* A number from the classes that break text round trips. */
static double odd_number(uint64_t *r)
{
    static const double fixed[] = {0.0, -0.0, 1.0, -1.5, 0.1, 1e300, -1e-300, 5e-324,
                                   -2.2250738585072009e-308, 1.7976931348623157e308,
                                   9007199254740993.0, 123456789.123456789};
    switch (next_u64(r) % 6) {
    case 0: return fixed[next_u64(r) % (sizeof fixed / sizeof fixed[0])];
    case 1: return next_u64(r) % 2 ? INFINITY : -INFINITY;
    case 2: {   /* a NaN with any payload and sign */
        uint64_t u = next_u64(r) | UINT64_C(0x7ff0000000000001);
        return from_bits(u);
    }
    case 3: return from_bits(next_u64(r) & UINT64_C(0x800fffffffffffff));   /* subnormal or 0 */
    default: {
        double x = from_bits(next_u64(r));
        return isnan(x) ? 0.5 : x;
    }
    }
}

/* A string with bytes of every class: printable ASCII (quotes, backslash,
 * `;`, `=`, spaces, ` = `), control bytes and NUL, and valid 2-, 3- and
 * 4-byte UTF-8. */
static Vec *odd_string(uint64_t *r)
{
    char b[64];
    size_t n = 0, want = next_u64(r) % 12;
    for (size_t i = 0; i < want; i++) {
        switch (next_u64(r) % 6) {
        case 0: b[n++] = (char)(0x20 + next_u64(r) % 0x5f); break;
        case 1: b[n++] = (char)(next_u64(r) % 0x20); break;
        case 2: b[n++] = 0x7f; break;
        case 3: memcpy(b + n, " = ", 3); n += 3; break;
        case 4: { static const char q[] = "\";\\"; b[n++] = q[next_u64(r) % 3]; break; }
        default: {
            static const char *const u[] = {"\xc3\xa9", "\xe2\x82\xac", "\xf0\x9f\x98\x80",
                                            "\xe2\x80\xa8", "\xef\xbb\xbf"};
            const char *c = u[next_u64(r) % 5];
            memcpy(b + n, c, strlen(c));
            n += strlen(c);
        }
        }
    }
    return vec_str(b, n);
}

/* A vector of 1..4 elements: numbers, symbols (plain names and names
 * that cannot stand as `:NAME`), strings. */
static Vec *odd_vector(uint64_t *r, SymTab *st)
{
    static const char *const names[] = {"dish", "velocity", "x'", "a b", "semi;colon", "eq=ual",
                                        "quo\"te", "new\nline", "caf\xc3\xa9"};
    size_t n = 1 + next_u64(r) % 4;
    Vec *parts[4];
    for (size_t i = 0; i < n; i++) {
        switch (next_u64(r) % 3) {
        case 0: parts[i] = vec_num1(odd_number(r)); break;
        case 1: {
            const char *name = names[next_u64(r) % 9];
            parts[i] = vec_num1(symtab_add(st, name, strlen(name)));
            break;
        }
        default: parts[i] = odd_string(r);
        }
    }
    Vec *v = vec_compose(parts, n);
    for (size_t i = 0; i < n; i++) vec_release(parts[i]);
    return v;
}

/* [a] and [b] hold the same elements, numbers bit for bit. */
static bool same_bits(const Vec *a, const Vec *b)
{
    if (!a || !b || a->len != b->len) return false;
    for (uint32_t i = 0; i < a->len; i++) {
        Elem x = a->kind == VEC_NUM ? (Elem){.kind = EL_NUM, .num = vec_cnums(a)[i]} : vec_celems(a)[i];
        Elem y = b->kind == VEC_NUM ? (Elem){.kind = EL_NUM, .num = vec_cnums(b)[i]} : vec_celems(b)[i];
        if (x.kind != y.kind) return false;
        if (x.kind == EL_NUM ? memcmp(&x.num, &y.num, sizeof x.num) != 0 : !str_eq(x.str, y.str))
            return false;
    }
    return true;
}

/* Make an empty scratch file, its name in [path] ([cap] bytes), on a
 * memory file system when there is one (each save syncs the file:
 * thousands of them on a disk take long). */
static void scratch_file(char *path, size_t cap)
{
    snprintf(path, cap, "%s/flitter-statefile-XXXXXX",
             access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp");
    int fd = mkstemp(path);
    assert_true(fd >= 0);
    close(fd);
}

static void test_round_trip_property(void **s)
{
    (void)s;
    char path[64];
    scratch_file(path, sizeof path);
    uint64_t r = 2026;
    static const double clocks[] = {0.0, -0.0, 1e300, -1e300, 5e-324, 1.7976931348623157e308,
                                    0.016666666666666666};
    size_t entries = 0;
    for (int round = 0; round < 2000; round++) {
        SymTab *st = symtab_new();
        StateDict *sd = state_new();
        size_t n = next_u64(&r) % 12;
        for (size_t i = 0; i < n; i++) {
            Vec *k = odd_vector(&r, st), *v = odd_vector(&r, st);
            state_set(sd, k, v);
            vec_release(k);
            vec_release(v);
        }
        StateClock c = {(long)(next_u64(&r) % 2 ? INT64_C(9007199254740992) : next_u64(&r) % 1000),
                        clocks[next_u64(&r) % 7], clocks[next_u64(&r) % 7],
                        clocks[next_u64(&r) % 7], 1e-300, 1e300, clocks[next_u64(&r) % 7]};
        StateOrigin o = {"/tmp/a \"b\" = c;\n.fl", next_u64(&r)}, o2 = {NULL, 0};
        Buf err = BUF_INIT;
        assert_int_equal(statefile_save(sd, st, &c, round % 2 ? &o : NULL, path, NULL, &err), 0);
        SymTab *st2 = symtab_new();
        StateDict *back = state_new();
        StateClock c2;
        if (statefile_load(back, st2, &c2, &o2, path, &err) != 0)
            fail_msg("round %d: %s", round, buf_cstr(&err));
        assert_int_equal(state_count(back), state_count(sd));
        size_t m;
        StateEntry *e = state_entries(sd, &m);
        for (size_t i = 0; i < m; i++) {
            if (!same_bits(state_get(back, e[i].key), e[i].value))
                fail_msg("round %d: entry %zu differs after the round trip", round, i);
        }
        entries += m;
        free(e);
        assert_memory_equal(&c2, &c, sizeof c);
        if (round % 2) {
            assert_non_null(o2.script);
            assert_string_equal(o2.script, o.script);
            assert_true(o2.hash == o.hash);
        } else {
            assert_null(o2.script);
        }
        free(o2.script);
        buf_free(&err);
        state_free(sd);
        state_free(back);
        symtab_free(st);
        symtab_free(st2);
    }
    assert_true(entries > 5000);
    unlink(path);
}

/* The saver writes only what its loader reads (issue 59): clocks drawn
 * from the extremes of every field (frames around 0 and 2^53 and past
 * them; times, beats, periods and quanta at 0, -0, the smallest and
 * largest doubles, infinities, NaN) are either saved and read back bit
 * for bit, or refused by the saver with the loader's reason, leaving the
 * file that was there as it was. */
static void test_clock_extremes_property(void **s)
{
    (void)s;
    char path[64];
    scratch_file(path, sizeof path);
    static const long frames[] = {0, 1, (long)(INT64_C(1) << 53) - 1, (long)(INT64_C(1) << 53),
                                  (long)(INT64_C(1) << 53) + 1, -1, (long)INT64_MAX, (long)INT64_MIN};
    static const double xs[] = {0.0, -0.0, 5e-324, -5e-324, 1.7976931348623157e308,
                                -1.7976931348623157e308, INFINITY, -INFINITY, NAN, 0.5, 60.0};
    const size_t nx = sizeof xs / sizeof xs[0];
    uint64_t r = 59;
    int saved = 0, refused = 0;
    for (int round = 0; round < 3000; round++) {
        SymTab *st = symtab_new();
        StateDict *sd = state_new();
        Vec *k = vec_num1(1), *v = vec_num1((double)round);
        state_set(sd, k, v);
        vec_release(k);
        vec_release(v);
        /* each field an extreme one time in four, else an ordinary value */
#define PICK(ordinary) (next_u64(&r) % 4 ? (ordinary) : xs[next_u64(&r) % nx])
        StateClock c = {next_u64(&r) % 2 ? frames[next_u64(&r) % (sizeof frames / sizeof frames[0])] : 42,
                        PICK(2.5), PICK(2.25), PICK(5.0), PICK(0.5), PICK(4.0), PICK(0.0)};
#undef PICK
        /* a file saved before, which a refused save must leave alone */
        StateClock good = {7, 1, 0.5, 1, 0.5, 4, 0};
        Buf err = BUF_INIT;
        assert_int_equal(statefile_save(sd, st, &good, NULL, path, NULL, &err), 0);
        const char *why = statefile_clock_refused(&c);
        int rc = statefile_save(sd, st, &c, NULL, path, NULL, &err);
        SymTab *st2 = symtab_new();
        StateDict *back = state_new();
        StateClock c2;
        Buf lerr = BUF_INIT;
        int lrc = statefile_load(back, st2, &c2, NULL, path, &lerr);
        if (lrc != 0) fail_msg("round %d: the saved file does not load: %s", round, buf_cstr(&lerr));
        if (rc == 0) {
            if (why) fail_msg("round %d: saved a clock the loader refuses (%s)", round, why);
            assert_memory_equal(&c2, &c, sizeof c);
            saved++;
        } else {
            assert_non_null(why);
            assert_non_null(strstr(buf_cstr(&err), why));
            assert_memory_equal(&c2, &good, sizeof good);   /* the old file */
            refused++;
        }
        buf_free(&err);
        buf_free(&lerr);
        state_free(sd);
        state_free(back);
        symtab_free(st);
        symtab_free(st2);
    }
    /* both outcomes are exercised */
    assert_true(saved > 100 && refused > 100);
    unlink(path);
}

/* Every single-bit flip of a saved file is refused, and leaves the
 * dictionary as it was. */
static void test_bit_flips(void **s)
{
    (void)s;
    char path[64];
    scratch_file(path, sizeof path);
    SymTab *st = symtab_new();
    StateDict *sd = state_new();
    Vec *k = vec_num1(symtab_add(st, "dish", 4));
    double xy[2] = {12.5, -0.25};
    Vec *v = vec_from_nums(xy, 2), *k2 = vec_str("a = b", 5), *v2 = vec_num1(7);
    state_set(sd, k, v);
    state_set(sd, k2, v2);
    StateClock c = {3, 0.05, 0.03333333333333333, 0.1, 0.5, 4, 0};
    StateOrigin o = {"/tmp/dish.fl", 0x0123456789abcdefu};
    Buf err = BUF_INIT;
    assert_int_equal(statefile_save(sd, st, &c, &o, path, NULL, &err), 0);
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    char text[1024];
    size_t len = fread(text, 1, sizeof text, f);
    fclose(f);
    assert_true(len > 100 && len < sizeof text);
    StateDict *back = state_new();
    Vec *mark = vec_num1(99);
    size_t flips = 0;
    for (size_t i = 0; i < len; i++) {
        for (int bit = 0; bit < 8; bit++) {
            char copy[1024];
            memcpy(copy, text, len);
            copy[i] = (char)(copy[i] ^ (1 << bit));
            f = fopen(path, "wb");
            assert_non_null(f);
            fwrite(copy, 1, len, f);
            fclose(f);
            state_clear(back);
            state_set(back, mark, mark);
            StateClock c2 = {0};
            buf_reset(&err);
            if (statefile_load(back, st, &c2, NULL, path, &err) != -1)
                fail_msg("flipping bit %d of byte %zu ('%c') was accepted", bit, i, text[i]);
            assert_int_equal(state_count(back), 1);
            flips++;
        }
    }
    assert_int_equal(flips, len * 8);
    vec_release(mark);
    vec_release(k);
    vec_release(v);
    vec_release(k2);
    vec_release(v2);
    buf_free(&err);
    state_free(sd);
    state_free(back);
    symtab_free(st);
    unlink(path);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_round_trip),
        cmocka_unit_test(test_malformed),
        cmocka_unit_test(test_range_checks),
        cmocka_unit_test(test_round_trip_property),
        cmocka_unit_test(test_bit_flips),
        cmocka_unit_test(test_clock_extremes_property),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
