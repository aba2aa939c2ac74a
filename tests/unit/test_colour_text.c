/* test_colour_text.c: the colour, text and file built-ins (LANGUAGE.md
 * §5.10-5.12) against the §7.4 test vectors and the values of
 * tests/golden/lang/builtins.tree; results are compared as value text
 * (FORMATS.md §1), which is exact. File built-ins run in a scratch
 * directory standing in for the script's directory. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "buf.h"
#include "builtins.h"
#include "context.h"
#include "format.h"
#include "node.h"
#include "program.h"
#include "value.h"

/* ------------------------------------------------------------------ */
/* Fixture: an evaluator context with a symbol table and a directory   */
/* ------------------------------------------------------------------ */

typedef struct {
    SymTab *st;
    MsgSet errors, debug;
    Program prog;
    Eval ev;
    char dir[64];
} Fx;

static int fx_setup(void **state)
{
    Fx *fx = calloc(1, sizeof *fx);
    if (!fx)
        return -1;
    fx->st = symtab_new();
    strcpy(fx->dir, "/tmp/flitter-test-XXXXXX");
    if (!mkdtemp(fx->dir))
        return -1;
    fx->prog.dir = fx->dir;
    fx->ev.prog = &fx->prog;
    fx->ev.symtab = fx->st;
    fx->ev.errors = &fx->errors;
    fx->ev.debug = &fx->debug;
    *state = fx;
    return 0;
}

static void rm_tree(const char *path)
{
    char cmd[256];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", path);
    if (system(cmd) != 0)
        fprintf(stderr, "could not remove %s\n", path);
}

static int fx_teardown(void **state)
{
    Fx *fx = *state;
    rm_tree(fx->dir);
    msgset_clear(&fx->errors);
    msgset_clear(&fx->debug);
    symtab_free(fx->st);
    free(fx);
    return 0;
}

static const Builtin *find(const char *name)
{
    const Builtin *tables[] = {bi_colour_table, bi_text_table, bi_file_table};
    for (size_t t = 0; t < 3; t++)
        for (const Builtin *b = tables[t]; b->name; b++)
            if (!strcmp(b->name, name))
                return b;
    fail_msg("no builtin %s", name);
    return NULL;
}

/* Call builtin [name] with [n] arguments (consumed). */
static Vec *call(Fx *fx, const char *name, int n, ...)
{
    const Builtin *bi = find(name);
    Vec *args[8] = {NULL};
    va_list ap;
    va_start(ap, n);
    for (int i = 0; i < n; i++)
        args[i] = va_arg(ap, Vec *);
    va_end(ap);
    assert_true(n >= bi->min_args && (bi->max_args == BI_VARIADIC || n <= bi->max_args));
    Vec *r = bi->fn(&fx->ev, bi, n, args);
    for (int i = 0; i < n; i++)
        vec_release(args[i]);
    return r;
}

/* Compare [v] (consumed) with value text [want]. */
static void check(Fx *fx, Vec *v, const char *want)
{
    Buf b = BUF_INIT;
    fmt_value(&b, v, fx->st);
    if (strcmp(buf_cstr(&b), want) != 0)
        fail_msg("got %s, want %s", buf_cstr(&b), want);
    buf_free(&b);
    vec_release(v);
}

/* The frame recorded exactly the error [msg] (then forget it). */
static void check_error(Fx *fx, const char *msg)
{
    if (fx->errors.count != 1 || strcmp(fx->errors.items[0], msg) != 0)
        fail_msg("errors: %u, first \"%s\"; want \"%s\"", fx->errors.count,
                 fx->errors.count ? fx->errors.items[0] : "", msg);
    msgset_clear(&fx->errors);
}

static void check_no_error(Fx *fx)
{
    if (fx->errors.count)
        fail_msg("unexpected error \"%s\"", fx->errors.items[0]);
}

static Vec *nums(int n, ...)
{
    va_list ap;
    va_start(ap, n);
    Vec *v = vec_new_num((uint32_t)n);
    for (int i = 0; i < n; i++)
        vec_nums(v)[i] = va_arg(ap, double);
    va_end(ap);
    return v;
}

static Vec *num(double x)
{
    return vec_num1(x);
}

static Vec *str(const char *s)
{
    return vec_str(s, strlen(s));
}

/* Compose [n] parts (consumed). */
static Vec *compose(int n, ...)
{
    Vec *parts[8];
    va_list ap;
    va_start(ap, n);
    for (int i = 0; i < n; i++)
        parts[i] = va_arg(ap, Vec *);
    va_end(ap);
    Vec *v = vec_compose(parts, (size_t)n);
    for (int i = 0; i < n; i++)
        vec_release(parts[i]);
    return v;
}

static Vec *node_vec(const char *kind)
{
    Str *k = str_from(kind);
    Vec *v = vec_node_take(node_new(k));
    str_release(k);
    return v;
}

/* Write [len] bytes to file [name] in the fixture directory. */
static void write_file(Fx *fx, const char *name, const char *data, size_t len)
{
    char path[256];
    snprintf(path, sizeof path, "%s/%s", fx->dir, name);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(data, 1, len, f), len);
    fclose(f);
}

static void write_text(Fx *fx, const char *name, const char *text)
{
    write_file(fx, name, text, strlen(text));
}

/* ------------------------------------------------------------------ */
/* Colour                                                              */
/* ------------------------------------------------------------------ */

static void test_hsv_hsl(void **state)
{
    Fx *fx = *state;
    /* §7.4 #64 */
    check(fx, call(fx, "hsv", 1, nums(3, 0.0, 1.0, 1.0)), "1;0;0");
    check(fx, call(fx, "hsv", 1, num(1.0 / 3)), "0;1;0");
    check(fx, call(fx, "hsl", 1, nums(3, 0.5, 1.0, 0.5)), "0;1;1");
    check(fx, call(fx, "hsl", 1, nums(3, 1.25, 1.0, 0.5)), "0.5;1;0");
    /* negative hues wrap; saturation and lightness clamp */
    check(fx, call(fx, "hsl", 1, nums(3, -0.75, 1.0, 0.5)), "0.5;1;0");
    check(fx, call(fx, "hsl", 1, nums(3, 0.0, 2.0, 0.5)), "1;0;0");
    check(fx, call(fx, "hsl", 1, nums(3, 0.0, 1.0, 7.0)), "1;1;1");
    check(fx, call(fx, "hsl", 1, nums(3, 0.0, 1.0, 0.25)), "0.5;0;0");
    check(fx, call(fx, "hsv", 1, nums(2, 0.5, 0.0)), "1;1;1");
    check(fx, call(fx, "hsv", 1, nums(3, 0.0, 1.0, 0.0)), "0;0;0");
    check(fx, call(fx, "hsv", 1, nums(3, 2.0 / 3, 0.5, 1.0)), "0.5;0.5;1");
    /* wrong shapes give null silently */
    check(fx, call(fx, "hsl", 1, nums(2, 0.0, 1.0)), "null");
    check(fx, call(fx, "hsl", 1, NULL), "null");
    check(fx, call(fx, "hsv", 1, nums(4, 0.0, 1.0, 1.0, 1.0)), "null");
    check(fx, call(fx, "hsv", 1, str("red")), "null");
    check_no_error(fx);
}

/* hsl/hsv as written before the remainder shortcut (colour.c mod6): every
 * hue through fmod, the rest the same operations in the same order. */
static double ref_hue_to_rgb(double m1, double m2, double t)
{
    t = fmod(t, 6);
    if (t < 0)
        t += 6;
    if (t < 1)
        return m1 + (m2 - m1) * t;
    if (t < 3)
        return m2;
    if (t < 4)
        return m1 + (m2 - m1) * (4 - t);
    return m1;
}

/* hsl of [s] and [l] in [0, 1] (no clamping needed) */
static void ref_hsl(double h, double s, double l, double out[3])
{
    double m2 = (l <= 0.5) ? l * (s + 1) : l + s - l * s;
    double m1 = l * 2 - m2;
    h *= 6;
    out[0] = ref_hue_to_rgb(m1, m2, h + 2);
    out[1] = ref_hue_to_rgb(m1, m2, h);
    out[2] = ref_hue_to_rgb(m1, m2, h - 2);
}

/* hsl() bit for bit against the fmod formulation, at the edges of the
 * remainder's shortcuts (|6h +- 2| near 0, 6, 12, multiples of 6 far
 * beyond, 2^48 where the quotient's route ends, signed zeros, huge,
 * infinite and NaN hues), at random hues and at random hues of every
 * magnitude up to 2^60. */
static void test_hsl_fmod_bits(void **state)
{
    Fx *fx = *state;
    double hues[4000];
    size_t n = 0;
    const double edges[] = {0.0, -0.0, 1.0, -1.0, 2.0, -2.0, 4.0, -4.0, 6.0, -6.0, 8.0, -8.0,
                            10.0, -10.0, 12.0, -12.0, 14.0, -14.0, 18.0, -18.0, 600.0, -6000.0,
                            6.0 * 123456789, -6.0 * 987654321, 6.0 * 0x1p40, 0x1p47, -0x1p47,
                            0x1p48, -0x1p48, 0x1p48 - 6, -0x1p48 + 6, 1e300, -1e300, INFINITY,
                            -INFINITY, NAN};
    for (size_t i = 0; i < sizeof edges / sizeof edges[0]; i++) {
        /* hues whose 6h, 6h+2 or 6h-2 land on or next to the edge */
        for (int d = -2; d <= 2; d += 2) {
            double h = (edges[i] - d) / 6;
            hues[n++] = h;
            hues[n++] = nextafter(h, INFINITY);
            hues[n++] = nextafter(h, -INFINITY);
        }
    }
    uint64_t x = 0x9e3779b97f4a7c15u;
    while (n < sizeof hues / sizeof hues[0]) {
        x ^= x << 13; x ^= x >> 7; x ^= x << 17;
        double u = (double)(x >> 11) / 9007199254740992.0;
        if (n % 2)
            hues[n++] = u * 6 - 3;   /* [-3, 3) */
        else   /* +-[1, 2^60), log-uniform */
            hues[n++] = (x & 1 ? -1 : 1) * exp2(u * 60);
    }
    for (size_t i = 0; i < n; i++) {
        double ref[3];
        ref_hsl(hues[i], 0.8, 0.4, ref);
        Vec *v = call(fx, "hsl", 1, nums(3, hues[i], 0.8, 0.4));
        assert_non_null(v);
        assert_int_equal(v->len, 3);
        for (int k = 0; k < 3; k++) {
            uint64_t a, b;
            memcpy(&a, &vec_nums(v)[k], sizeof a);
            memcpy(&b, &ref[k], sizeof b);
            if (a != b)
                fail_msg("hsl(%a;0.8;0.4)[%d]: %a, fmod gives %a", hues[i], k, vec_nums(v)[k], ref[k]);
        }
        vec_release(v);
    }
    check_no_error(fx);
}

static void test_colortemp(void **state)
{
    Fx *fx = *state;
    /* §7.4 #65, full precision from builtins.tree */
    check(fx, call(fx, "colortemp", 1, num(6503.5)),
          "1.0423314544166828;0.9838395450633467;1.035433507588856");
    /* Y is exactly 1 at 6503.5, so normalising changes nothing */
    check(fx, call(fx, "colortemp", 2, num(6503.5), num(1.0)),
          "1.0423314544166828;0.9838395450633467;1.035433507588856");
    /* three outputs per element; each branch of the polynomials */
    Vec *r = call(fx, "colortemp", 2, nums(4, 1000.0, 3000.0, 5000.0, 1e6), num(1.0));
    assert_non_null(r);
    assert_int_equal(r->len, 12);
    for (int i = 0; i < 12; i++) {
        double c = vec_nums(r)[i];
        assert_true(c >= 0 && c < 3);
    }
    /* warm is red-heavy, cold is blue-heavy */
    assert_true(vec_nums(r)[0] > vec_nums(r)[2]);
    assert_true(vec_nums(r)[11] > vec_nums(r)[9]);
    /* clamped below 1667: the same chromaticity as 1667 */
    Vec *low = call(fx, "colortemp", 2, num(1667.0), num(1.0));
    assert_memory_equal(vec_nums(low), vec_nums(r), 3 * sizeof(double));
    vec_release(low);
    vec_release(r);
    /* not normalised, zero temperature is black */
    check(fx, call(fx, "colortemp", 1, num(0.0)), "0;0;0");
    check(fx, call(fx, "colortemp", 1, str("x")), "null");
    check(fx, call(fx, "colortemp", 1, NULL), "null");
    check_no_error(fx);
}

static void test_oklab(void **state)
{
    Fx *fx = *state;
    /* §7.4 #66, full precision from builtins.tree */
    check(fx, call(fx, "oklch", 1, nums(3, 0.5, 0.0, 0.0)),
          "0.12503333720335766;0.1250067611739981;0.12490931173138914");
    check(fx, call(fx, "oklab", 1, nums(3, 0.5, 0.0, 0.0)),
          "0.12503333720335766;0.1250067611739981;0.12490931173138914");
    /* L = 1 is (close to) white, L = 0 black */
    Vec *w = call(fx, "oklab", 1, nums(3, 1.0, 0.0, 0.0));
    for (int i = 0; i < 3; i++)
        assert_true(fabs(vec_nums(w)[i] - 1) < 1e-3);
    vec_release(w);
    check(fx, call(fx, "oklab", 1, nums(3, 0.0, 0.0, 0.0)), "0;0;0");
    /* oklch at hue 0.25 turns is oklab with a = C*cos_t = 0 exactly */
    Vec *a = call(fx, "oklch", 1, nums(3, 0.7, 0.1, 0.25));
    Vec *b = call(fx, "oklab", 1, nums(3, 0.7, 0.0, 0.1));
    assert_memory_equal(vec_nums(a), vec_nums(b), 3 * sizeof(double));
    vec_release(a);
    vec_release(b);
    check(fx, call(fx, "oklab", 1, nums(2, 0.5, 0.0)), "null");
    check(fx, call(fx, "oklch", 1, compose(2, str("a"), nums(2, 0.0, 0.0))), "null");
    check_no_error(fx);
}

/* ------------------------------------------------------------------ */
/* Text                                                                */
/* ------------------------------------------------------------------ */

static void test_chr_ord(void **state)
{
    Fx *fx = *state;
    /* §7.4 #68 */
    check(fx, call(fx, "chr", 1, nums(2, 72.0, 105.0)), "\"Hi\"");
    check(fx, call(fx, "ord", 1, str("AB")), "65;66");
    Vec *codes = call(fx, "ord", 1, str("h\xc3\xa9llo"));
    check(fx, vec_retain(codes), "104;233;108;108;111");
    Vec *idx = nums(2, 1.0, 2.0);
    Vec *sub = vec_index(codes, idx, false);
    vec_release(idx);
    vec_release(codes);
    check(fx, call(fx, "chr", 1, sub), "\"\xc3\xa9l\"");
    /* floors, multi-byte encodings */
    check(fx, call(fx, "chr", 1, num(65.9)), "\"A\"");
    check(fx, call(fx, "chr", 1, nums(2, 8364.0, 128512.0)), "\"\xe2\x82\xac\xf0\x9f\x98\x80\"");
    check(fx, call(fx, "ord", 1, str("\xe2\x82\xac\xf0\x9f\x98\x80")), "8364;128512");
    check(fx, call(fx, "chr", 1, num(0.0)), "\"\\x00\"");
    /* ord takes str() of anything */
    double foo = symtab_add(fx->st, "foo", 3);
    check(fx, call(fx, "ord", 1, num(foo)), "102;111;111");
    check(fx, call(fx, "ord", 1, num(12.0)), "49;50");
    check(fx, call(fx, "ord", 1, NULL), "null");
    check(fx, call(fx, "ord", 1, str("")), "null");
    check(fx, call(fx, "chr", 1, str("A")), "null");
    check(fx, call(fx, "chr", 1, NULL), "null");
    check_no_error(fx);
    /* invalid code points are errors */
    check(fx, call(fx, "chr", 1, num(-1.0)), "null");
    check_error(fx, "Error calling chrv: chr() arg not in range(0x110000)");
    check(fx, call(fx, "chr", 1, nums(2, 65.0, 1114112.0)), "null");
    check_error(fx, "Error calling chrv: chr() arg not in range(0x110000)");
    check(fx, call(fx, "chr", 1, num(NAN)), "null");
    check_error(fx, "Error calling chrv: chr() arg not in range(0x110000)");
    check(fx, call(fx, "chr", 1, num(1e300)), "null");
    check_error(fx, "Error calling chrv: chr() arg not in range(0x110000)");
}

static void test_split_concat(void **state)
{
    Fx *fx = *state;
    double b = symtab_add(fx->st, "b", 1);
    /* §7.4 #69 */
    check(fx, call(fx, "split", 2, str("a,b,,"), str(",")), "\"a\";\"b\"");
    check(fx, call(fx, "split", 1, str("a\nb\n")), "\"a\";\"b\"");
    check(fx, call(fx, "concat", 1, compose(3, num(1.0), str("a"), num(b))), "\"1ab\"");
    /* inner empty pieces stay; multi-byte separators; str() of numbers */
    check(fx, call(fx, "split", 2, str(",x,,y"), str(",")), "\"\";\"x\";\"\";\"y\"");
    check(fx, call(fx, "split", 2, str("a--b--"), str("--")), "\"a\";\"b\"");
    check(fx, call(fx, "split", 2, num(1.5), str(".")), "\"1\";\"5\"");
    check(fx, call(fx, "split", 2, str("a\xc3\xa9" "b"), str("\xc3\xa9")), "\"a\";\"b\"");
    check(fx, call(fx, "split", 2, str("abc"), str(",")), "\"abc\"");
    /* empty inputs are null without an error */
    check(fx, call(fx, "split", 1, NULL), "null");
    check(fx, call(fx, "split", 2, str("a,b"), NULL), "null");
    check_no_error(fx);
    /* the reference's failures */
    check(fx, call(fx, "split", 2, str(""), str(",")), "null");
    check_error(fx, "Error calling split: list index out of range");
    check(fx, call(fx, "split", 2, str(",,"), str(",")), "null");
    check_error(fx, "Error calling split: list index out of range");
    check(fx, call(fx, "split", 2, str("abc"), str("")), "null");
    check_error(fx, "Error calling split: empty separator");
    /* concat */
    check(fx, call(fx, "concat", 1, NULL), "null");
    check(fx, call(fx, "concat", 1, str("")), "\"\"");
    check(fx, call(fx, "concat", 1, nums(3, 1.0, -0.0, 0.25)), "\"1-00.25\"");
    check(fx, call(fx, "concat", 1, compose(2, node_vec("n"), str("x"))), "\"nx\"");
    check_no_error(fx);
}

/* ------------------------------------------------------------------ */
/* Files                                                               */
/* ------------------------------------------------------------------ */

static void test_debug(void **state)
{
    Fx *fx = *state;
    double y = symtab_add(fx->st, "y", 1);
    check(fx, call(fx, "debug", 1, compose(3, str("x"), num(1.0), num(y))), "\"x\";1;:y");
    check(fx, call(fx, "debug", 1, nums(2, -0.0, 0.5)), "0;0.5");
    check(fx, call(fx, "debug", 1, NULL), "null");
    assert_int_equal(fx->debug.count, 3);
    assert_true(msgset_has(&fx->debug, "'x';1;:y"));
    assert_true(msgset_has(&fx->debug, "0;0.5"));
    assert_true(msgset_has(&fx->debug, "null"));
    check_no_error(fx);
}

static void read_checks(Fx *fx)
{
    write_text(fx, "t.txt", "a\r\nb\rc\n\xc3\xa9");
    write_file(fx, "bad.txt", "ok\xff", 3);
    write_file(fx, "empty.txt", "", 0);
    write_file(fx, "b.bin", "\x00\xff\n", 3);
    check(fx, call(fx, "read", 1, str("t.txt")), "\"a\\nb\\nc\\n\xc3\xa9\"");
    check(fx, call(fx, "read", 1, str("empty.txt")), "\"\"");
    check(fx, call(fx, "read", 1, str("bad.txt")), "null");
    check(fx, call(fx, "read", 1, str("missing.txt")), "null");
    check(fx, call(fx, "read", 1, str("")), "null");
    check(fx, call(fx, "read", 1, NULL), "null");
    char abs[256];
    snprintf(abs, sizeof abs, "%s/t.txt", fx->dir);
    check(fx, call(fx, "read", 1, str(abs)), "\"a\\nb\\nc\\n\xc3\xa9\"");
    check(fx, call(fx, "read_bytes", 1, str("b.bin")), "0;255;10");
    check(fx, call(fx, "read_bytes", 1, str("bad.txt")), "111;107;255");
    check(fx, call(fx, "read_bytes", 1, str("empty.txt")), "null");
    check(fx, call(fx, "read_bytes", 1, str("missing")), "null");
    check_no_error(fx);
}

static void csv_checks(Fx *fx)
{
    write_text(fx, "d.csv",
               "1,2.5,x\n"
               "\"quoted, comma\",\"say \"\"hi\"\"\",3\n"
               "\n"
               " 7 ,1_000,nan,-Infinity,,\n"
               "\"multi\n"
               "line\",end\n"
               "1e3,1_,_1,0x10,\"\"\n"
               "\"open");
    write_text(fx, "crlf.csv", "a,b\r\nc,d\r\n");
    check(fx, call(fx, "csv", 2, str("d.csv"), num(0.0)), "1;2.5;\"x\"");
    check(fx, call(fx, "csv", 2, str("d.csv"), num(1.0)), "\"quoted, comma\";\"say \\\"hi\\\"\";3");
    check(fx, call(fx, "csv", 2, str("d.csv"), num(2.0)), "null");
    check(fx, call(fx, "csv", 2, str("d.csv"), num(3.0)), "7;1000;nan;-inf");
    check(fx, call(fx, "csv", 2, str("d.csv"), num(4.0)), "\"multi\\nline\";\"end\"");
    check(fx, call(fx, "csv", 2, str("d.csv"), num(5.0)), "1000;\"1_\";\"_1\";\"0x10\"");
    check(fx, call(fx, "csv", 2, str("d.csv"), num(6.0)), "\"open\"");
    check(fx, call(fx, "csv", 2, str("d.csv"), num(7.0)), "null");
    check(fx, call(fx, "csv", 2, str("d.csv"), num(1.7)), "\"quoted, comma\";\"say \\\"hi\\\"\";3");
    check(fx, call(fx, "csv", 2, str("d.csv"), str("0")), "1;2.5;\"x\"");
    check(fx, call(fx, "csv", 2, str("d.csv"), num(-1.0)), "null");
    check(fx, call(fx, "csv", 2, str("crlf.csv"), num(1.0)), "\"c\";\"d\"");
    check(fx, call(fx, "csv", 2, str("missing.csv"), num(0.0)), "null");
    check(fx, call(fx, "csv", 2, str(""), num(0.0)), "null");
    check(fx, call(fx, "csv", 2, str("d.csv"), NULL), "null");
    check(fx, call(fx, "csv", 2, str("d.csv"), str("x")), "null");
    double sym = symtab_add(fx->st, "row", 3);
    check(fx, call(fx, "csv", 2, str("d.csv"), num(sym)), "null");
    check_no_error(fx);
    check(fx, call(fx, "csv", 2, str("d.csv"), num(NAN)), "null");
    check_error(fx, "Error calling read_csv: cannot convert float NaN to integer");
}

static void srt_checks(Fx *fx)
{
    write_text(fx, "s.srt",
               "1\n"
               "00:00:01,000 --> 00:00:02,500\n"
               "Hello\n"
               "world\n"
               "\n"
               "2\n"
               "00:00:02,000 --> 00:01:00\n"
               "Second\n");
    write_text(fx, "trailing.srt",
               "1\n00:00:01,000 --> 00:00:02,000\nHi\n\n");
    write_text(fx, "crlf.srt",
               "1\r\n00:00:00,000 --> 00:00:01,000\r\nA\r\n\r\n2\r\n0:1 --> 0:2\r\nB\r\n");
    check(fx, call(fx, "srt", 2, str("s.srt"), num(0.5)), "null");
    check(fx, call(fx, "srt", 2, str("s.srt"), num(1.0)), "\"Hello\";\"world\"");
    check(fx, call(fx, "srt", 2, str("s.srt"), num(2.2)), "\"Hello\";\"world\";\"Second\"");
    check(fx, call(fx, "srt", 2, str("s.srt"), num(2.5)), "\"Second\"");
    check(fx, call(fx, "srt", 2, str("s.srt"), str("59.5")), "\"Second\"");
    check(fx, call(fx, "srt", 2, str("s.srt"), num(60.0)), "null");
    check(fx, call(fx, "srt", 2, str("crlf.srt"), num(0.5)), "\"A\"");
    check(fx, call(fx, "srt", 2, str("crlf.srt"), num(1.5)), "\"B\"");
    /* a trailing blank line makes the reference reject the file */
    check(fx, call(fx, "srt", 2, str("trailing.srt"), num(1.5)), "null");
    check(fx, call(fx, "srt", 2, str("missing.srt"), num(1.5)), "null");
    check(fx, call(fx, "srt", 2, str("s.srt"), NULL), "null");
    check(fx, call(fx, "srt", 2, str(""), num(1.5)), "null");
    check_no_error(fx);
}

/* The file built-ins' checks without a memo of the files read, then with
 * one (filememo.c; no racy window, so that files just written are kept),
 * twice: the second time from what it keeps. */
#define WITH_AND_WITHOUT_MEMO(name)                                         \
    static void test_##name(void **state)                                   \
    {                                                                       \
        Fx *fx = *state;                                                    \
        name##_checks(fx);                                                  \
        fx->ev.file_memo = file_memo_new();                                 \
        assert_non_null(fx->ev.file_memo);                                  \
        file_memo_set_window(fx->ev.file_memo, 0);                          \
        name##_checks(fx);                                                  \
        name##_checks(fx);                                                  \
        file_memo_free(fx->ev.file_memo);                                   \
        fx->ev.file_memo = NULL;                                            \
    }
WITH_AND_WITHOUT_MEMO(read)
WITH_AND_WITHOUT_MEMO(csv)
WITH_AND_WITHOUT_MEMO(srt)
#undef WITH_AND_WITHOUT_MEMO

/* Set file [name]'s modification time to [t] (its change time moves to
 * now, as every change does). */
static void set_mtime(Fx *fx, const char *name, struct timespec t)
{
    char path[256];
    snprintf(path, sizeof path, "%s/%s", fx->dir, name);
    struct timespec ts[2] = {t, t};
    assert_int_equal(utimensat(AT_FDCWD, path, ts, 0), 0);
}

static struct timespec mtime_of(Fx *fx, const char *name)
{
    char path[256];
    struct stat st;
    snprintf(path, sizeof path, "%s/%s", fx->dir, name);
    assert_int_equal(stat(path, &st), 0);
    return st.st_mtim;
}

/* A memo hands out the same string while the file is unchanged, and what
 * reading it afresh gives once it changed: replaced by another file,
 * grown, shrunk, removed; a file that stops being UTF-8 and becomes it
 * again; bytes and rows likewise, a table's rows asked for in any order. With the racy window of 2 s, a file
 * just written is read afresh at every use: rewritten with the same size
 * and its old modification time put back, in the same grain of the
 * kernel's clock, it still reads as it is. */
static void test_file_memo(void **state)
{
    Fx *fx = *state;
    fx->ev.file_memo = file_memo_new();
    file_memo_set_window(fx->ev.file_memo, 0);
    write_text(fx, "m.txt", "one");
    Vec *a = call(fx, "read", 1, str("m.txt")), *b = call(fx, "read", 1, str("m.txt"));
    assert_ptr_equal(a, b);
    check(fx, a, "\"one\"");
    vec_release(b);
    write_text(fx, "n.txt", "three");
    char from[256], to[256];
    snprintf(from, sizeof from, "%s/n.txt", fx->dir);
    snprintf(to, sizeof to, "%s/m.txt", fx->dir);
    assert_int_equal(rename(from, to), 0);
    check(fx, call(fx, "read", 1, str("m.txt")), "\"three\"");
    check(fx, call(fx, "read_bytes", 1, str("m.txt")), "116;104;114;101;101");
    write_text(fx, "m.txt", "three\r\nfour");
    check(fx, call(fx, "read", 1, str("m.txt")), "\"three\\nfour\"");
    write_file(fx, "m.txt", "bad\xff", 4);
    check(fx, call(fx, "read", 1, str("m.txt")), "null");
    check(fx, call(fx, "read", 1, str("m.txt")), "null");
    check(fx, call(fx, "read_bytes", 1, str("m.txt")), "98;97;100;255");
    write_text(fx, "m.txt", "goodness");
    check(fx, call(fx, "read", 1, str("m.txt")), "\"goodness\"");
    assert_int_equal(unlink(to), 0);
    check(fx, call(fx, "read", 1, str("m.txt")), "null");
    check(fx, call(fx, "read_bytes", 1, str("m.txt")), "null");
    write_text(fx, "r.csv", "1,2\n3,4\n");
    check(fx, call(fx, "csv", 2, str("r.csv"), num(1.0)), "3;4");
    write_text(fx, "r.csv", "1,2\n5,6,7\n");
    check(fx, call(fx, "csv", 2, str("r.csv"), num(1.0)), "5;6;7");

    /* a table's rows, kept as they are parsed, in any order, and parsed
     * afresh once the file changed */
    Buf table = BUF_INIT;
    for (int i = 0; i < 3000; i++)
        buf_printf(&table, "%d,r%d\n", i, i);
    write_text(fx, "t.csv", buf_cstr(&table));
    check(fx, call(fx, "csv", 2, str("t.csv"), num(2999.0)), "2999;\"r2999\"");
    check(fx, call(fx, "csv", 2, str("t.csv"), num(5.0)), "5;\"r5\"");
    check(fx, call(fx, "csv", 2, str("t.csv"), num(3000.0)), "null");
    check(fx, call(fx, "csv", 2, str("t.csv"), num(1234.5)), "1234;\"r1234\"");
    buf_printf(&table, "x\n");
    write_text(fx, "t.csv", buf_cstr(&table));
    check(fx, call(fx, "csv", 2, str("t.csv"), num(3000.0)), "\"x\"");
    check(fx, call(fx, "csv", 2, str("t.csv"), num(7.0)), "7;\"r7\"");
    buf_free(&table);

    /* the racy window */
    file_memo_set_window(fx->ev.file_memo, INT64_C(2000000000));
    write_text(fx, "w.txt", "one");
    check(fx, call(fx, "read", 1, str("w.txt")), "\"one\"");
    struct timespec t = mtime_of(fx, "w.txt");
    write_text(fx, "w.txt", "two");
    set_mtime(fx, "w.txt", t);
    a = call(fx, "read", 1, str("w.txt"));
    b = call(fx, "read", 1, str("w.txt"));
    assert_ptr_not_equal(a, b);
    check(fx, a, "\"two\"");
    check(fx, b, "\"two\"");
    /* more files than it keeps: each still reads as it is */
    for (int i = 0; i < 40; i++) {
        char name[32], text[32], want[40];
        snprintf(name, sizeof name, "f%d.txt", i % 20);
        snprintf(text, sizeof text, "%d", i);
        write_text(fx, name, text);
        snprintf(want, sizeof want, "\"%d\"", i);
        check(fx, call(fx, "read", 1, str(name)), want);
    }
    check_no_error(fx);
    file_memo_free(fx->ev.file_memo);
    fx->ev.file_memo = NULL;
}

static void test_glob(void **state)
{
    Fx *fx = *state;
    char real[4096], path[4200];
    assert_non_null(realpath(fx->dir, real));
    snprintf(path, sizeof path, "%s/sub", fx->dir);
    assert_int_equal(mkdir(path, 0700), 0);
    snprintf(path, sizeof path, "%s/sub/deeper", fx->dir);
    assert_int_equal(mkdir(path, 0700), 0);
    write_text(fx, "b.txt", "");
    write_text(fx, "a.txt", "");
    write_text(fx, ".hidden.txt", "");
    write_text(fx, "c.dat", "");
    write_text(fx, "sub/d.txt", "");
    write_text(fx, "sub/deeper/e.txt", "");

    Buf want = BUF_INIT;
    buf_printf(&want, "\"%s/.hidden.txt\";\"%s/a.txt\";\"%s/b.txt\"", real, real, real);
    check(fx, call(fx, "glob", 1, str("*.txt")), buf_cstr(&want));
    buf_reset(&want);
    buf_printf(&want, "\"%s/sub/d.txt\"", real);
    check(fx, call(fx, "glob", 1, str("sub/?.txt")), buf_cstr(&want));
    check(fx, call(fx, "glob", 1, str("./sub//[a-d].txt")), buf_cstr(&want));
    buf_reset(&want);
    buf_printf(&want, "\"%s/.hidden.txt\";\"%s/a.txt\";\"%s/b.txt\";\"%s/sub/d.txt\";"
                      "\"%s/sub/deeper/e.txt\"", real, real, real, real, real);
    check(fx, call(fx, "glob", 1, str("**/*.txt")), buf_cstr(&want));
    buf_reset(&want);
    buf_printf(&want, "\"%s/sub\"", real);
    check(fx, call(fx, "glob", 1, str("*/")), buf_cstr(&want));
    check(fx, call(fx, "glob", 1, str("sub")), buf_cstr(&want));
    buf_reset(&want);
    buf_printf(&want, "\"%s/c.dat\"", real);
    check(fx, call(fx, "glob", 1, str("sub/../c.*")), buf_cstr(&want));
    buf_free(&want);
    check(fx, call(fx, "glob", 1, str("*.none")), "null");
    check(fx, call(fx, "glob", 1, str("nothing/*")), "null");
    check_no_error(fx);
    check(fx, call(fx, "glob", 1, str("/etc/*")), "null");
    check_error(fx, "Error calling glob: Non-relative patterns are unsupported");
    check(fx, call(fx, "glob", 1, str("")), "null");
    check_error(fx, "Error calling glob: Unacceptable pattern: ''");
}

static void test_tables(void **state)
{
    (void)state;
    /* internal names used in messages and str() */
    assert_string_equal(find("chr")->internal, "chrv");
    assert_string_equal(find("ord")->internal, "ordv");
    assert_string_equal(find("read")->internal, "read_text");
    assert_string_equal(find("csv")->internal, "read_csv");
    assert_string_equal(find("srt")->internal, "read_srt");
    assert_string_equal(find("hsv")->internal, "hsv");
    /* keyword names */
    assert_string_equal(find("split")->params[1], "separator");
    assert_string_equal(find("colortemp")->params[1], "normalize");
    /* only the file family is dynamic */
    assert_true(find("debug")->flags & BI_DYNAMIC);
    assert_true(find("glob")->flags & BI_DYNAMIC);
    assert_false(find("split")->flags & BI_DYNAMIC);
    assert_false(find("oklch")->flags & BI_DYNAMIC);
}

int main(void)
{
#define T(f) cmocka_unit_test_setup_teardown(f, fx_setup, fx_teardown)
    const struct CMUnitTest tests[] = {
        T(test_hsv_hsl),
        T(test_hsl_fmod_bits),
        T(test_colortemp),
        T(test_oklab),
        T(test_chr_ord),
        T(test_split_concat),
        T(test_debug),
        T(test_read),
        T(test_csv),
        T(test_srt),
        T(test_file_memo),
        T(test_glob),
        cmocka_unit_test(test_tables),
    };
#undef T
    return cmocka_run_group_tests(tests, NULL, NULL);
}
