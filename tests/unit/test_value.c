/* test_value.c: the vector model (LANGUAGE.md §3) with hand-checked values. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "node.h"
#include "value.h"

static Vec *nums(int n, ...)
{
    va_list ap;
    va_start(ap, n);
    Vec *v = vec_new_num((uint32_t)n);
    for (int i = 0; i < n; i++) vec_nums(v)[i] = va_arg(ap, double);
    va_end(ap);
    return v;
}

static void assert_nums(Vec *v, int n, ...)
{
    assert_non_null(v);
    assert_int_equal(v->kind, VEC_NUM);
    assert_int_equal(v->len, n);
    va_list ap;
    va_start(ap, n);
    for (int i = 0; i < n; i++) {
        double want = va_arg(ap, double), got = vec_nums(v)[i];
        if (isnan(want)) assert_true(isnan(got));
        else assert_true(memcmp(&want, &got, sizeof want) == 0);
    }
    va_end(ap);
    vec_release(v);
}

static uint64_t bits(double x)
{
    uint64_t u;
    memcpy(&u, &x, sizeof u);
    return u;
}

static void test_symbol_bits(void **s)
{
    (void)s;
    assert_true(fnv1a_utf8("foo", 3) == UINT64_C(0xdcb27518fed9d577));
    assert_true(bits(symbol_value("foo", 3)) == UINT64_C(0xffedcb27518fed9d));
    SymTab *st = symtab_new();
    double x = symtab_add(st, "foo", 3);
    assert_string_equal(symtab_name(st, x)->bytes, "foo");
    assert_null(symtab_name(st, 1.0));
    for (int i = 0; i < 200; i++) {   /* growth keeps every entry */
        char name[16];
        snprintf(name, sizeof name, "s%d", i);
        symtab_add(st, name, strlen(name));
    }
    assert_string_equal(symtab_name(st, symbol_value("s137", 4))->bytes, "s137");
    assert_string_equal(symtab_name(st, x)->bytes, "foo");
    symtab_free(st);
}

static void test_broadcast(void **s)
{
    (void)s;
    Vec *a = nums(4, 1.0, 2.0, 3.0, 4.0), *b = nums(2, 1.0, -1.0);
    assert_nums(vec_arith(OP_ADD, a, b), 4, 2.0, 1.0, 4.0, 3.0);
    Vec *c = nums(3, 1.0, 2.0, 3.0), *d = nums(2, 2.0, 3.0);
    assert_nums(vec_arith(OP_MUL, c, d), 3, 2.0, 6.0, 6.0);
    /* F1 fused broadcast: (1;2;3;4;5;6) + (1;2)*(1;2;3) */
    Vec *six = nums(6, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0), *two = nums(2, 1.0, 2.0);
    assert_nums(vec_add_mul(six, two, c), 6, 2.0, 6.0, 6.0, 6.0, 7.0, 12.0);
    Vec *str = vec_str("a", 1);
    assert_null(vec_arith(OP_ADD, str, a));
    assert_null(vec_arith(OP_ADD, NULL, a));
    vec_release(a); vec_release(b); vec_release(c); vec_release(d);
    vec_release(six); vec_release(two); vec_release(str);
}

static void test_division_and_modulo(void **s)
{
    (void)s;
    assert_true(num_floordiv(-7, 2) == -4);
    assert_true(num_mod(-7, 2) == 1);
    assert_true(num_mod(7, -2) == -1);
    assert_true(isnan(num_mod(5, 0)));
    Vec *x = vec_num1(0.5), *z = vec_num1(-0.0);
    Vec *r = vec_arith(OP_MUL, x, z);
    assert_true(bits(vec_nums(r)[0]) == UINT64_C(0x8000000000000000));   /* -0 */
    vec_release(r);
    vec_release(x);
    vec_release(z);
}

static void test_hash(void **s)
{
    (void)s;
    assert_true(vec_hash(NULL, true) == UINT64_C(0xe220a8397b1dcdaf));
    Vec *one = vec_num1(1.0), *onefive = vec_num1(1.5);
    assert_true(vec_hash(one, true) == UINT64_C(0x03953eea0e693074));
    assert_true(vec_hash(onefive, true) == vec_hash(one, true));
    assert_true(vec_hash(onefive, false) != vec_hash(one, false));
    vec_release(one);
    vec_release(onefive);
}

static void test_ranges(void **s)
{
    (void)s;
    Vec *a = vec_num1(0.1), *b = vec_num1(0.5), *c = vec_num1(0.1);
    assert_nums(vec_range(a, b, c, 1000, NULL), 4, 0.1, 0.2, 0.30000000000000004, 0.4);
    Vec *stop = vec_num1(2.5);
    assert_nums(vec_range(NULL, stop, NULL, 1000, NULL), 3, 0.0, 1.0, 2.0);
    Vec *one = vec_num1(1.0), *zero = vec_num1(0.0), *step = vec_num1(-0.25);
    assert_nums(vec_range(one, zero, step, 1000, NULL), 4, 1.0, 0.75, 0.5, 0.25);
    assert_null(vec_range(zero, one, zero, 1000, NULL));
    assert_null(vec_range(NULL, zero, NULL, 1000, NULL));
    Vec *big = vec_num1(1e12);
    bool too_long = false;
    assert_null(vec_range(NULL, big, NULL, 1000, &too_long));
    assert_true(too_long);
    vec_release(a); vec_release(b); vec_release(c); vec_release(stop);
    vec_release(one); vec_release(zero); vec_release(step); vec_release(big);
}

static void test_indexing(void **s)
{
    (void)s;
    Vec *v = nums(3, 10.0, 20.0, 30.0), *m1 = vec_num1(-1), *f = vec_num1(1.7);
    assert_nums(vec_index(v, m1, false), 1, 30.0);
    assert_nums(vec_index(v, f, false), 1, 20.0);
    Vec *five = vec_num1(5), *three = vec_num1(3);
    Vec *r3 = vec_range(NULL, three, NULL, 100, NULL);
    assert_nums(vec_index(five, r3, false), 3, 5.0, 5.0, 5.0);
    assert_null(vec_index(v, NULL, false));
    /* object source: all-number selections become numeric */
    Vec *parts[2] = {vec_str("a", 1), v};
    Vec *mixed = vec_compose(parts, 2);
    Vec *r = vec_index(mixed, m1, false);
    assert_int_equal(r->kind, VEC_NUM);
    vec_release(r);
    /* item wraps around */
    assert_nums(vec_item(v, 4), 1, 20.0);
    /* indexes as numbers, in range (truncated) and out of it (floored,
     * wrapped; NaN and 1e10 convert to INT32_MIN, 2**31 too unless the
     * index is a literal range, 64-bit: INT32_MIN wraps to 1 of 3, 1e10 to
     * 1, 2**31 to 2) */
    const double k[] = {2.9, -0.0, 3.0, -0.5, NAN, 1e10, 2147483648.0, 2147483647.5, 0.0, 4.5e15};
    assert_nums(vec_index_nums(v, k, 10, false), 10, 30.0, 10.0, 10.0, 30.0, 20.0, 20.0, 20.0, 20.0, 10.0,
                20.0);
    assert_nums(vec_index_nums(v, k, 10, true), 10, 30.0, 10.0, 10.0, 30.0, 20.0, 20.0, 30.0, 20.0, 10.0,
                10.0);
    double y;
    assert_true(vec_index_num1(v, 2147483647.5, false, &y) && y == 20.0);
    assert_true(vec_index_num1(v, 2147483648.0, true, &y) && y == 30.0);
    assert_true(vec_index_num1(v, -1e-300, false, &y) && y == 30.0);
    vec_release(parts[0]); vec_release(mixed);
    vec_release(v); vec_release(m1); vec_release(f); vec_release(five); vec_release(three); vec_release(r3);
}

static void test_compare(void **s)
{
    (void)s;
    Vec *a = nums(2, 1.0, 2.0), *b = nums(3, 1.0, 2.0, 0.0), *z = vec_num1(0.0), *one = vec_num1(1.0);
    assert_int_equal(vec_cmp(a, b), -1);
    assert_int_equal(vec_cmp(NULL, z), -1);
    assert_int_equal(vec_cmp(one, NULL), 1);
    Vec *sa = vec_str("a", 1), *sabc = vec_str("abc", 3), *sabd = vec_str("abd", 3);
    assert_int_equal(vec_cmp(sa, one), CMP_INCOMPARABLE);
    assert_int_equal(vec_cmp(sabc, sabd), -1);
    Vec *nan1 = vec_num1(NAN);
    assert_int_equal(vec_cmp(nan1, one), 1);
    assert_int_equal(vec_cmp(one, nan1), 1);
    assert_false(vec_equal(z, NULL));
    assert_true(vec_equal(NULL, NULL));
    assert_false(vec_equal(nan1, nan1));
    Vec *negz = vec_num1(-0.0);
    assert_true(vec_equal(z, negz));
    assert_false(vec_key_equal(z, negz));
    vec_release(a); vec_release(b); vec_release(z); vec_release(one); vec_release(sa);
    vec_release(sabc); vec_release(sabd); vec_release(nan1); vec_release(negz);
}

static void test_contains_truth_compose(void **s)
{
    (void)s;
    Vec *r5 = nums(5, 0.0, 1.0, 2.0, 3.0, 4.0), *x = nums(2, 2.0, 3.0), *y = nums(2, 3.0, 2.0);
    assert_true(vec_contains(x, r5));
    assert_false(vec_contains(y, r5));
    assert_true(vec_contains(NULL, x));
    Vec *nan1 = vec_num1(NAN), *negz = vec_num1(-0.0), *empty = vec_str("", 0);
    assert_true(vec_truthy(nan1));
    assert_false(vec_truthy(negz));
    assert_false(vec_truthy(empty));
    assert_false(vec_truthy(NULL));
    Vec *st = vec_stream(STREAM_UNIFORM, 1);
    assert_true(vec_truthy(st));
    Vec *parts[4] = {x, NULL, st, y};
    assert_nums(vec_compose(parts, 4), 4, 2.0, 3.0, 3.0, 2.0);
    Vec *o[2] = {x, empty};
    Vec *c = vec_compose(o, 2);
    assert_int_equal(c->kind, VEC_OBJ);
    assert_int_equal(c->len, 3);
    vec_release(c);
    vec_release(r5); vec_release(x); vec_release(y); vec_release(nan1);
    vec_release(negz); vec_release(empty); vec_release(st);
}

static void test_nodes(void **s)
{
    (void)s;
    Str *k = str_from("a"), *y = str_from("y"), *xn = str_from("x"), *tz = str_from("z"), *tb = str_from("b");
    Node *n = node_new(k);
    node_set_attr(n, y, vec_num1(1));
    node_set_attr(n, xn, vec_num1(2));
    node_set_attr(n, y, vec_num1(3));       /* keeps its position */
    node_add_tag(n, tz);
    node_add_tag(n, tb);
    node_add_tag(n, tz);
    assert_int_equal(n->nattrs, 2);
    assert_string_equal(n->attrs[0].name->bytes, "y");
    assert_true(vec_nums(n->attrs[0].value)[0] == 3.0);
    assert_int_equal(n->ntags, 2);
    assert_string_equal(n->tags[0]->bytes, "b");
    Node *shared = node_retain(n);
    Node *m = node_mut(shared);              /* copy-on-write */
    assert_ptr_not_equal(m, n);
    node_set_attr(m, xn, NULL);              /* empty value removes */
    assert_int_equal(m->nattrs, 1);
    assert_int_equal(n->nattrs, 2);
    assert_false(node_equal(m, n));
    node_set_attr(m, xn, vec_num1(2));
    assert_true(node_equal(m, n));           /* attribute order is irrelevant */
    assert_true(node_hash(m) == node_hash(n));
    /* node_mut_room: the same copy, with room for 2 more attributes in the
     * node's own block (no array of their own as they are added); an
     * unshared node is itself */
    Node *r = node_mut_room(node_retain(n), 2);
    assert_ptr_not_equal(r, n);
    assert_true(node_equal(r, n));
    assert_int_equal(r->cap_attrs, 4);
    assert_ptr_equal(r->attrs, node_inline_attrs(r));
    Str *w = str_from("w");
    node_set_attr(r, w, vec_num1(5));
    node_set_attr(r, tz, vec_num1(6));
    assert_int_equal(r->nattrs, 4);
    assert_ptr_equal(r->attrs, node_inline_attrs(r));
    assert_string_equal(r->attrs[3].name->bytes, "z");
    assert_int_equal(n->nattrs, 2);
    assert_ptr_equal(node_mut_room(r, 3), r);
    /* node_mut_children: a copy with room for its children and 2 more in
     * its own block, after its attribute slots; a third child moves them
     * to an array of their own, in order */
    Node *c1 = node_new(tb), *c2 = node_new(tz), *c3 = node_new(w);
    node_append(r, c1);
    Node *rc = node_mut_children(node_retain(r), 2);
    assert_ptr_not_equal(rc, r);
    assert_int_equal(rc->inline_kids, 3);
    assert_int_equal(rc->cap_children, 3);
    assert_ptr_equal(rc->children, node_inline_kids(rc));
    assert_ptr_equal((void *)rc->children, (void *)(node_inline_attrs(rc) + rc->inline_attrs));
    assert_int_equal(node_block_bytes(rc), sizeof(Node) + 4 * sizeof(Attr) + 3 * sizeof(Node *));
    node_append(rc, c2);
    node_append(rc, c3);
    assert_ptr_equal(rc->children, node_inline_kids(rc));
    assert_int_equal(rc->nchildren, 3);
    node_append(rc, c1);
    assert_ptr_not_equal(rc->children, node_inline_kids(rc));
    assert_int_equal(rc->nchildren, 4);
    assert_ptr_equal(rc->children[0], c1);
    assert_ptr_equal(rc->children[1], c2);
    assert_ptr_equal(rc->children[2], c3);
    assert_ptr_equal(rc->children[3], c1);
    assert_int_equal(c1->refs, 4);             /* c1, r, rc twice */
    assert_int_equal(r->nchildren, 1);
    node_release(rc);
    assert_int_equal(c1->refs, 2);
    assert_int_equal(c2->refs, 1);
    /* a room past NODE_INLINE_MAX is left out of the block */
    Node *big = node_new_room(k, NODE_INLINE_MAX + 1, NODE_INLINE_MAX + 1);
    assert_int_equal(big->inline_attrs, 0);
    assert_int_equal(big->inline_kids, 0);
    assert_null(big->children);
    node_append(big, c2);
    assert_int_equal(big->nchildren, 1);
    node_release(big);
    node_release(c1); node_release(c2); node_release(c3);
    node_release(r);
    str_release(w);
    node_release(m);
    node_release(n);
    str_release(k); str_release(y); str_release(xn); str_release(tz); str_release(tb);
}

/* vec_arith_take computes what vec_arith does, reusing an unshared operand
 * of the result's length, and never leaves a stale cached key hash. */
static void test_arith_take_and_key_hash(void **st)
{
    (void)st;
    Vec *a = nums(2, 1.5, -2.0), *b = nums(1, 4.0);
    uint64_t ha = vec_key_hash(a);
    assert_true(ha == vec_hash(a, false));
    assert_true(vec_key_hash(a) == ha);              /* kept */
    Vec *r = vec_arith_take(OP_MUL, a, b);             /* a is unshared: reused */
    assert_ptr_equal(r, a);
    assert_true(vec_key_hash(r) == vec_hash(r, false));
    assert_true(vec_key_hash(r) != ha);
    Vec *keep = vec_retain(r);                         /* shared: not reused */
    Vec *b2 = nums(2, 1.0, 1.0);
    Vec *r2 = vec_arith_take(OP_SUB, r, b2);
    assert_ptr_equal(r2, b2);                          /* b was reused instead */
    assert_nums(keep, 2, 6.0, -8.0);
    assert_nums(r2, 2, 5.0, -9.0);
    Vec *x = nums(1, 3.0), *y = nums(3, 1.0, 2.0, 3.0);
    assert_nums(vec_arith_take(OP_POW, x, y), 3, 3.0, 9.0, 27.0);
    assert_null(vec_arith_take(OP_ADD, nums(1, 1.0), NULL));
    /* string keys keep their hash; node-holding vectors are never cached */
    Vec *s = vec_str("k", 1);
    assert_true(vec_key_hash(s) == vec_hash(s, false));
    assert_int_equal(s->hashed, 1);
    vec_release(s);
}

/* num_arith_into's routes (the AVX copy of long spans where the processor
 * has one, the tiles of a short repeated operand, the literal loops)
 * give, for every operation, length and broadcast, the bits num_arith
 * gives number by number: signed zeros, infinities, NaNs, subnormals and
 * numbers past 2**52 among them; also written over either operand. (A NaN
 * is any NaN: which operand's a sum of two NaNs keeps is the compiler's
 * choice, on every route as in num_arith, and no output shows it.) */
static bool same(double x, double y) { return isnan(y) ? isnan(x) : bits(x) == bits(y); }

static void test_arith_routes(void **st)
{
    (void)st;
    static const double special[] = {0.0, -0.0, INFINITY, -INFINITY, NAN, 1e300, -1e-310, 4503599627370497.0,
                                     -4503599627370495.5, 7.0, -7.0, 0.5, -2.5, 3.0};
    const uint32_t nspecial = sizeof special / sizeof special[0];
    static const uint32_t lens[][2] = {
        {1, 1}, {3, 3}, {7, 7}, {8, 8}, {9, 9}, {13, 13}, {70, 70}, {1, 9}, {9, 1}, {1, 70}, {70, 1},
        {2, 70}, {70, 2}, {3, 67}, {67, 3}, {32, 100}, {100, 32}, {33, 100}, {100, 33}, {5, 12}, {64, 65},
    };
    double xa[128], xb[128], r[128], w[128];
    uint64_t seed = 12345;
    for (int op = OP_ADD; op <= OP_POW; op++) {
        for (size_t c = 0; c < sizeof lens / sizeof lens[0]; c++) {
            const uint32_t na = lens[c][0], nb = lens[c][1], n = na > nb ? na : nb;
            for (int rep = 0; rep < 4; rep++) {
                for (uint32_t i = 0; i < 256; i++) {
                    seed = seed * UINT64_C(6364136223846793005) + UINT64_C(1442695040888963407);
                    uint32_t u = (uint32_t)(seed >> 33);
                    double x = (u % 4 == 0) ? special[u / 4 % nspecial] : ((double)(u % 20001) - 10000.0) / 64.0;
                    if (i % 2) xb[i / 2] = i % 8 == 1 ? -x / 3.0 : x;
                    else xa[i / 2] = x;
                }
                for (uint32_t i = 0; i < n; i++) w[i] = num_arith((ArithOp)op, xa[i % na], xb[i % nb]);
                num_arith_into((ArithOp)op, r, xa, na, xb, nb);
                for (uint32_t i = 0; i < n; i++) assert_true(same(r[i], w[i]));
                /* over the longer operand (or one number) */
                double *into = na == n ? xa : xb;
                num_arith_into((ArithOp)op, into, xa, na, xb, nb);
                for (uint32_t i = 0; i < n; i++) assert_true(same(into[i], w[i]));
            }
        }
    }
    /* by hand: the last numbers of a long vector mod a repeated pair */
    double v[11], m[2] = {4.0, -3.0}, out[11];
    for (int i = 0; i < 11; i++) v[i] = 10.5 - i;
    num_arith_into(OP_MOD, out, v, 11, m, 2);
    assert_true(out[0] == 2.5 && out[1] == -2.5 && out[9] == -1.5 && out[10] == 0.5);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_symbol_bits),
        cmocka_unit_test(test_broadcast),
        cmocka_unit_test(test_division_and_modulo),
        cmocka_unit_test(test_hash),
        cmocka_unit_test(test_ranges),
        cmocka_unit_test(test_indexing),
        cmocka_unit_test(test_compare),
        cmocka_unit_test(test_contains_truth_compose),
        cmocka_unit_test(test_nodes),
        cmocka_unit_test(test_arith_take_and_key_hash),
        cmocka_unit_test(test_arith_routes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
