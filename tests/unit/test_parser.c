/* test_parser.c: unit tests of parse_program() (lib/syntax/parse.c,
 * grammar/parser.y, lib/syntax/ast.c): tree shapes of every construct of
 * LANGUAGE.md §2 written as S-expressions, precedence (§2.2, §2.3),
 * contextual keywords (§1.7), pragmas and the symbol list of AST_TOP, and
 * the error message format (parse.h).
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "node.h"
#include "parse.h"

/* {=====================================================================
 * AST dump: one S-expression per node
 * ===================================================================== */

static const char *const arith_ops[] = {"+", "-", "*", "/", "//", "%", "**"};
static const char *const cmp_ops[] = {"==", "!=", "<", ">", "<=", ">=", "in"};

static void dump(Buf *b, const AstNode *n);

static void dump_names(Buf *b, const AstNode *n)
{
    for (uint32_t i = 0; i < n->nnames; i++) {
        if (i)
            buf_putc(b, ';');
        buf_add(b, n->names[i]->bytes, n->names[i]->len);
    }
}

static void dump_number(Buf *b, double x)
{
    static const char *const symbols[] = {"a", "b", "s", "foo", "bar"};
    for (size_t i = 0; i < sizeof symbols / sizeof symbols[0]; i++) {
        if (x == symbol_value(symbols[i], strlen(symbols[i]))) {
            buf_printf(b, ":%s", symbols[i]);
            return;
        }
    }
    char text[40];
    if (x == floor(x) && fabs(x) < 1e15) {
        buf_printf(b, "%.0f", x);
        return;
    }
    for (int prec = 1; prec <= 17; prec++) {
        snprintf(text, sizeof text, "%.*g", prec, x);
        if (strtod(text, NULL) == x || isnan(x))
            break;
    }
    buf_puts(b, text);
}

static void dump_value(Buf *b, const Vec *v)
{
    if (!v) {
        buf_puts(b, "null");
        return;
    }
    for (uint32_t i = 0; i < v->len; i++) {
        if (i)
            buf_putc(b, ';');
        if (v->kind == VEC_NUM) {
            dump_number(b, vec_cnums(v)[i]);
            continue;
        }
        const Elem *e = &vec_celems(v)[i];
        if (e->kind == EL_NUM) {
            dump_number(b, e->num);
        } else if (e->kind == EL_STR) {
            buf_putc(b, '"');
            buf_add(b, e->str->bytes, e->str->len);
            buf_putc(b, '"');
        } else if (e->kind == EL_NODE) {
            buf_putc(b, '!');
            buf_add(b, e->node->kind->bytes, e->node->kind->len);
        } else {
            buf_puts(b, "<func>");
        }
    }
}

/* "(head kid kid ...)" */
static void dump_kids(Buf *b, const AstNode *n, uint32_t from)
{
    for (uint32_t i = from; i < n->nkids; i++) {
        buf_putc(b, ' ');
        dump(b, n->kids[i]);
    }
}

static void dump_opt(Buf *b, const AstNode *n)
{
    buf_putc(b, ' ');
    if (n)
        dump(b, n);
    else
        buf_putc(b, '_');
}

static void dump(Buf *b, const AstNode *n)
{
    if (!n) {
        buf_puts(b, "NULL");
        return;
    }
    switch ((AstKind)n->kind) {
    case AST_LITERAL:
        dump_value(b, n->value);
        return;
    case AST_NAME:
        dump_names(b, n);
        return;
    case AST_EXPORT:
        buf_puts(b, "EOF");
        return;
    case AST_BINDING:
        dump_names(b, n);
        if (n->value) {
            buf_putc(b, '=');
            dump_value(b, n->value);
        } else if (n->a) {
            buf_putc(b, '=');
            dump(b, n->a);
        }
        return;
    default:
        break;
    }
    buf_putc(b, '(');
    switch ((AstKind)n->kind) {
    case AST_TOP:
        buf_puts(b, "top");
        dump_kids(b, n, 0);
        dump_opt(b, n->a);
        break;
    case AST_SEQUENCE:
        buf_puts(b, "seq");
        dump_kids(b, n, 0);
        break;
    case AST_LOOKUP:
        buf_puts(b, "$");
        dump_opt(b, n->a);
        break;
    case AST_BINOP:
        buf_puts(b, arith_ops[n->op]);
        dump_opt(b, n->a);
        dump_opt(b, n->b);
        break;
    case AST_COMPARE:
        buf_puts(b, cmp_ops[n->op]);
        dump_opt(b, n->a);
        dump_opt(b, n->b);
        break;
    case AST_NEG: case AST_POS: case AST_NOT: case AST_INCLUDE:
        buf_puts(b, n->kind == AST_NEG ? "neg" : n->kind == AST_POS ? "pos"
                    : n->kind == AST_NOT ? "not" : "include");
        dump_opt(b, n->a);
        break;
    case AST_AND: case AST_OR: case AST_XOR: case AST_INDEX: case AST_APPEND:
        buf_puts(b, n->kind == AST_AND ? "and" : n->kind == AST_OR ? "or"
                    : n->kind == AST_XOR ? "xor" : n->kind == AST_INDEX ? "index"
                    : "append");
        dump_opt(b, n->a);
        dump_opt(b, n->b);
        break;
    case AST_RANGE:
        buf_puts(b, "range");
        dump_opt(b, n->a);
        dump_opt(b, n->b);
        dump_opt(b, n->c);
        break;
    case AST_CALL:
        buf_puts(b, n->op ? "template" : "call");
        buf_printf(b, "/%u", n->count);
        dump_opt(b, n->a);
        dump_kids(b, n, 0);
        break;
    case AST_FUNCTION:
        buf_puts(b, "func ");
        dump_names(b, n);
        buf_puts(b, " (");
        for (uint32_t i = 0; i < n->nkids; i++) {
            if (i)
                buf_putc(b, ' ');
            dump(b, n->kids[i]);
        }
        buf_putc(b, ')');
        dump_opt(b, n->a);
        break;
    case AST_LET:
        buf_puts(b, n->op ? "let-stable" : "let");
        dump_kids(b, n, 0);
        dump_opt(b, n->a);
        break;
    case AST_FOR:
        buf_puts(b, "for ");
        dump_names(b, n);
        dump_opt(b, n->a);
        dump_opt(b, n->b);
        break;
    case AST_IFELSE:
        buf_puts(b, "if");
        dump_kids(b, n, 0);
        dump_opt(b, n->a);
        break;
    case AST_TAG:
        buf_puts(b, "tag");
        dump_opt(b, n->a);
        buf_puts(b, " #");
        dump_names(b, n);
        break;
    case AST_ATTRIBUTES:
        buf_puts(b, "attrs");
        dump_opt(b, n->a);
        dump_kids(b, n, 0);
        break;
    case AST_IMPORT:
        buf_puts(b, "import ");
        dump_names(b, n);
        dump_opt(b, n->a);
        dump_opt(b, n->b);
        break;
    default:
        buf_puts(b, ast_kind_name((AstKind)n->kind));
        break;
    }
    buf_putc(b, ')');
}

/* }===================================================================== */

/* {=====================================================================
 * Helpers
 * ===================================================================== */

static AstNode *parse(const char *src, Buf *err)
{
    return parse_program("test.fl", src, strlen(src), 0, err);
}

/* The dump of the whole tree of [src] (which must parse). */
static char *shape_of(const char *src)
{
    Buf err = BUF_INIT, out = BUF_INIT;
    AstNode *top = parse(src, &err);
    if (!top) {
        print_error("unexpected parse error for:\n%s\n%s", src, buf_cstr(&err));
        fail();
    }
    dump(&out, top);
    ast_free(top);
    buf_free(&err);
    char *s = strdup(buf_cstr(&out));
    buf_free(&out);
    return s;
}

static void check_program(const char *src, const char *want)
{
    char *got = shape_of(src);
    if (strcmp(got, want) != 0) {
        print_error("source:\n%s\ngot:  %s\nwant: %s\n", src, got, want);
        free(got);
        fail();
    }
    free(got);
}

/* The shape of the single statement [src] (a program "src\n"). */
static void check_expr(const char *src, const char *want)
{
    Buf full = BUF_INIT, expect = BUF_INIT;
    buf_printf(&full, "%s\n", src);
    buf_printf(&expect, "(top (seq %s EOF))", want);
    check_program(buf_cstr(&full), buf_cstr(&expect));
    buf_free(&full);
    buf_free(&expect);
}

/* [src] must fail with exactly the message [want] (NULL: any message);
 * returns nothing, frees everything. */
static void check_error(const char *src, const char *want)
{
    Buf err = BUF_INIT;
    AstNode *top = parse(src, &err);
    if (top) {
        Buf out = BUF_INIT;
        dump(&out, top);
        print_error("expected an error for:\n%s\ngot tree %s\n", src, buf_cstr(&out));
        buf_free(&out);
        ast_free(top);
        fail();
    }
    assert_true(err.len > 0);
    if (want && strcmp(buf_cstr(&err), want) != 0) {
        print_error("source:\n%s\ngot:\n%s\nwant:\n%s\n", src, buf_cstr(&err), want);
        buf_free(&err);
        fail();
    }
    buf_free(&err);
}

/* The first line of the error message for [src] contains [part]. */
static void check_error_has(const char *src, const char *part)
{
    Buf err = BUF_INIT;
    AstNode *top = parse(src, &err);
    assert_null(top);
    if (!strstr(buf_cstr(&err), part)) {
        print_error("source:\n%s\nmessage:\n%s\nlacks: %s\n", src, buf_cstr(&err), part);
        buf_free(&err);
        fail();
    }
    buf_free(&err);
}

/* }===================================================================== */

/* {=====================================================================
 * Expressions and precedence (§2.2, §2.3)
 * ===================================================================== */

static void test_power_and_unary(void **state)
{
    (void)state;
    check_expr("2**3**2", "(** (** 2 3) 2)");
    check_expr("-2**2", "(neg (** 2 2))");
    check_expr("a*-b", "(* a (neg b))");
    check_expr("+-x", "(pos (neg x))");
    check_expr("2**(-1)", "(** 2 (neg 1))");
    check_error_has("2**-1\n", "test.fl:1:4: error: syntax error, unexpected '-'");
}

static void test_arithmetic(void **state)
{
    (void)state;
    check_expr("1+2*3-4", "(- (+ 1 (* 2 3)) 4)");
    check_expr("a/b//c%d", "(% (// (/ a b) c) d)");
    check_expr("f(x)[0]**2", "(** (index (call/1 f x) 0) 2)");
}

static void test_comparisons(void **state)
{
    (void)state;
    check_expr("a == b", "(== a b)");
    check_expr("a != b", "(!= a b)");
    check_expr("a <= b+1", "(<= a (+ b 1))");
    check_expr("a >= b", "(>= a b)");
    check_expr("a > b", "(> a b)");
    check_expr("3 in x", "(in 3 x)");
    check_expr("1;2 == 1;2", "(seq 1 (== 2 1) 2)");
    check_error_has("a < b < c\n", "1:7: error: syntax error, unexpected '<'");
    check_error_has("a == b == c\n", "unexpected '=='");
}

static void test_logic(void **state)
{
    (void)state;
    check_expr("not a and b or c xor d",
               "(xor (or (and (not a) b) c) d)");
    check_expr("not not a == b", "(not (not (== a b)))");
    check_expr("a or b and c", "(or a (and b c))");
}

static void test_ranges(void **state)
{
    (void)state;
    check_expr("..5", "(range _ 5 _)");
    check_expr("1..0|-0.25", "(range 1 0 (neg 0.25))");
    check_expr("..n|2", "(range _ n 2)");
    check_expr("a+1..b*2", "(range (+ a 1) (* b 2) _)");
    check_expr("0..1 == x", "(== (range 0 1 _) x)");
}

static void test_conditionals(void **state)
{
    (void)state;
    check_expr("5 if 0", "(if 0 5 _)");
    check_expr("1 if 0 else 2 if 1 else 3", "(if 0 1 (if 1 2 3))");
    check_expr("x if x > 3 for x in xs", "(for x xs (if (> x 3) x _))");
}

static void test_comprehensions(void **state)
{
    (void)state;
    /* ';' is looser than for/where; sources are level-6 expressions */
    check_expr("x;y for y in z", "(seq x (for y z y))");
    check_expr("y for x;y in 1;2;3", "(seq (for x;y 1 y) 2 3)");
    check_expr("(x;y) for x in A for y in B",
               "(for y B (for x A (seq x y)))");
    check_expr("x;x*x where x=2", "(seq x (let x=2 (* x x)))");
    check_expr("e where a=1 where b=2", "(let b=2 (let a=1 e))");
    check_expr("e where a=1 b=a+1", "(let a=1 b=(+ a 1) e)");
    check_expr("x;y where x=1 y=2", "(seq x (let x=1 y=2 y))");
    check_expr("v where a;b=1;2", "(seq (let a;b=1 v) 2)");
}

static void test_functions_inline(void **state)
{
    (void)state;
    check_expr("func (x) x;1;2", "(seq (func <anon> (x) x) 1 2)");
    check_expr("func (x, y=2) x*y", "(func <anon> (x y=2) (* x y))");
    check_expr("func () 1", "(func <anon> () 1)");
    check_expr("func (a) func (b) a+b", "(func <anon> (a) (func <anon> (b) (+ a b)))");
}

static void test_calls(void **state)
{
    (void)state;
    check_expr("f()", "(call/0 f)");
    check_expr("f(1, 2;3, x=4, y=5)", "(call/2 f 1 (seq 2 3) x=4 y=5)");
    check_expr("f(k=1)", "(call/0 f k=1)");
    check_expr("f(!a << !b, 1;2)", "(call/2 f (append !a !b) (seq 1 2))");
    check_expr("(sin;cos)(0.25)", "(call/1 (seq sin cos) 0.25)");
    check_expr("f(x)(y)", "(call/1 (call/1 f x) y)");
    check_expr("x[!a << !b]", "(index x (append !a !b))");
    check_error_has("f(1, x=2, 3)\n", "unexpected number");
}

static void test_lookup_and_literals(void **state)
{
    (void)state;
    check_expr("$x[0]", "(index ($ x) 0)");
    check_expr("$:a+1", "(+ ($ :a) 1)");
    check_expr("$($x)", "($ ($ x))");
    check_expr("\"x\";1;!node;1:30;10m",
               "(seq \"x\" 1 !node 90 0.01)");
    check_expr("'a\\tb'", "\"a\tb\"");
}

static void test_literal_flags(void **state)
{
    (void)state;
    Buf err = BUF_INIT;
    AstNode *top = parse("1;1:30;:s;'x';!n\n", &err);
    assert_non_null(top);
    AstNode *seq = top->a->kids[0];
    assert_int_equal(seq->kind, AST_SEQUENCE);
    assert_int_equal(seq->nkids, 5);
    assert_int_equal(seq->kids[0]->op, 1);
    assert_int_equal(seq->kids[1]->op, 1);
    assert_int_equal(seq->kids[2]->op, 1);
    assert_int_equal(seq->kids[3]->op, 0);
    assert_int_equal(seq->kids[4]->op, 0);
    /* the symbol literal is the number of §3.3 */
    assert_true(vec_scalar(seq->kids[2]->value) == symbol_value("s", 1));
    ast_free(top);
    buf_free(&err);
}

/* }===================================================================== */

/* {=====================================================================
 * Node expressions and statements
 * ===================================================================== */

static void test_nodes(void **state)
{
    (void)state;
    check_expr("!t #one #two a=1 a=2 b=3",
               "(attrs (tag (tag !t #one) #two) a=1 a=2 b=3)");
    /* a tag between attributes starts a new, nesting group */
    check_expr("!a x=1 #t y=2", "(attrs (tag (attrs !a x=1) #t) y=2)");
    check_expr("(!a x=1) y=2", "(attrs (attrs !a x=1) y=2)");
    /* attribute values are compositions */
    check_expr("!foo size=1;2 color=1;0;0",
               "(attrs !foo size=(seq 1 2) color=(seq 1 0 0))");
    /* a following name= stays in the where group */
    check_expr("!foo x=y where y=1 z=2", "(attrs !foo x=(let y=1 z=2 y))");
    check_expr("!foo x=y+z where y=z*2 where z=5",
               "(attrs !foo x=(let z=5 (let y=(* z 2) (+ y z))))");
    check_expr("!w v=(!a;!b)", "(attrs !w v=(seq !a !b))");
    check_expr("(!p1;1;!p2) #tg", "(tag (seq !p1 1 !p2) #tg)");
}

static void test_append(void **state)
{
    (void)state;
    check_expr("!a << !b << !c", "(append !a (append !b !c))");
    check_program("!a <<\n!b\n", "(top (seq (append !a !b) EOF))");
    check_program("!a << !b x=1 << n\n    !c\n",
                  "(top (seq (append !a (append (attrs !b x=1) (append n (seq !c)))) EOF))");
    check_program("!parent\n    !k1\n    !k2\n",
                  "(top (seq (append !parent (seq !k1 !k2)) EOF))");
    check_program("base << (!child id=1) << (!child id=2)\n",
                  "(top (seq (append base (append (attrs !child id=1) (attrs !child id=2))) EOF))");
}

static void test_let(void **state)
{
    (void)state;
    check_program("let x=1\n!foo x=x\n",
                  "(top (seq (let x=1 (seq (attrs !foo x=x) EOF))))");
    check_program("let y=1 y''=y+1\n    a;b=2 c=3\nc\n",
                  "(top (seq (let y=1 y''=(+ y 1) a;b=2 c=3 (seq c EOF))))");
    check_program("let stable s=1\ns\n", "(top (seq (let-stable s=1 (seq s EOF))))");
    check_program("!a\nlet x=1\n!b\n",
                  "(top (seq !a (let x=1 (seq !b EOF))))");
    /* binding values are compositions, not node expressions */
    check_program("let f = func(c) !light color=c\n",
                  "(top (seq (let f=(func <anon> (c) !light) color=c (seq EOF))))");
    /* sequence let */
    check_program("let s =\n    !x\n    !y\ns\n",
                  "(top (seq (let s=(seq !x !y) (seq s EOF))))");
    check_program("let u;v =\n    1\n    2\n!t u=u\n",
                  "(top (seq (let u;v=(seq 1 2) (seq (attrs !t u=u) EOF))))");
    /* scopes nest inside blocks */
    check_program("!outer\n    let z=1\n    !inner z=z\n!after\n",
                  "(top (seq (append !outer (seq (let z=1 (seq (attrs !inner z=z))))) !after EOF))");
}

static void test_func_statements(void **state)
{
    (void)state;
    check_program("func add(a, b=10)\n    a+b\nadd(1)\n",
                  "(top (seq (let add=(func add (a b=10) (seq (+ a b))) (seq (call/1 add 1) EOF))))");
    check_program("func f(x=1;2, y)\n    x\n",
                  "(top (seq (let f=(func f (x=(seq 1 2) y) (seq x)) (seq EOF))))");
    check_program("func (x)\n    x*2\n!a\n",
                  "(top (seq (seq (func <anon> (x) (seq (* x 2))) (seq !a EOF))))");
    check_program("func f(x=!a k=1, y)\n    x\n",
                  "(top (seq (let f=(func f (x=(attrs !a k=1) y) (seq x)) (seq EOF))))");
}

static void test_template_calls(void **state)
{
    (void)state;
    check_program("@foo\n", "(top (seq (template/0 foo) EOF))");
    check_program("@foo y=5 z='me'\n",
                  "(top (seq (template/0 foo y=5 z=\"me\") EOF))");
    check_program("@foo y=5\n    !baz\n    1\n",
                  "(top (seq (template/1 foo (seq !baz 1) y=5) EOF))");
    check_program("@box color=1;0;0\n", "(top (seq (template/0 box color=(seq 1 0 0)) EOF))");
    check_program("@(f;g)\n", "(top (seq (template/0 (seq f g)) EOF))");
}

static void test_for_statements(void **state)
{
    (void)state;
    check_program("for i in ..3\n    !dot i=i\n",
                  "(top (seq (for i (range _ 3 _) (seq (attrs !dot i=i))) EOF))");
    check_program("for a in X, b;c in Y\n    a\n",
                  "(top (seq (for a X (for b;c Y (seq a))) EOF))");
}

static void test_if_statements(void **state)
{
    (void)state;
    check_program("if 0\n    !no\nelif null\n    !no2\nelse\n    !yes\n",
                  "(top (seq (if 0 (seq !no) null (seq !no2) (seq !yes)) EOF))");
    check_program("if x\n    1\n!after\n", "(top (seq (if x (seq 1) _) !after EOF))");
    check_error_has("if x\n    1\nelse 2\n", "unexpected number");
    check_error_has("if x 1\n", "unexpected number");
}

static void test_import_include(void **state)
{
    (void)state;
    check_program("import a;b from 'm.fl'\na\n",
                  "(top (seq (import a;b \"m.fl\" (seq a EOF))))");
    check_program("%include 'x.fl'\n!a\n",
                  "(top (seq (include \"x.fl\") !a EOF))");
    check_program("!a << %include 'x'\n", "(top (seq (append !a (include \"x\")) EOF))");
}

static void test_top_and_pragmas(void **state)
{
    (void)state;
    check_program("", "(top (seq EOF))");
    check_program("\n\n-- only a comment\n", "(top (seq EOF))");
    check_program("#!/usr/bin/env flitter\n%pragma tempo 110\n%pragma fps 30\n\n!a\n",
                  "(top tempo=110 fps=30 (seq !a EOF))");
    check_program("-- c\n%pragma name 'x'\n", "(top name=\"x\" (seq EOF))");
    check_program("  !a\n", "(top (seq !a EOF))");
    check_error_has("%pragma x -1\n", "unexpected '-'");
    check_error_has("!a\n%pragma x 1\n", "unexpected '%pragma'");
    check_error_has("!a\n#!x\n", "unexpected '#!' line");
    /* blank lines, then an indented first line: measured, an error */
    check_error_has("\n  !a\n", "unexpected indent");
}

static void test_symbols_recorded(void **state)
{
    (void)state;
    Buf err = BUF_INIT;
    AstNode *top = parse("!a x=:foo;:bar y=:foo;:caf\xc3\xa9\n", &err);
    assert_non_null(top);
    assert_non_null(top->c);
    assert_int_equal(top->c->kind, AST_SEQUENCE);
    assert_int_equal(top->c->nkids, 3);
    const char *want[] = {"foo", "bar", "caf\xc3\xa9"};
    for (int i = 0; i < 3; i++) {
        const AstNode *lit = top->c->kids[i];
        assert_int_equal(lit->kind, AST_LITERAL);
        assert_int_equal(vec_len(lit->value), 1);
        const Elem *e = &vec_celems(lit->value)[0];
        assert_int_equal(e->kind, EL_STR);
        assert_string_equal(e->str->bytes, want[i]);
    }
    ast_free(top);
    /* many symbols: the set grows */
    Buf src = BUF_INIT;
    for (int i = 0; i < 500; i++)
        buf_printf(&src, ":s%d;:s%d\n", i, i % 7);
    top = parse(buf_cstr(&src), &err);
    assert_non_null(top);
    assert_int_equal(top->c->nkids, 500);
    ast_free(top);
    buf_free(&src);
    buf_free(&err);
}

/* }===================================================================== */

/* {=====================================================================
 * Contextual keywords (§1.7)
 * ===================================================================== */

static void test_keywords_as_names(void **state)
{
    (void)state;
    check_expr("!distance from=:a to=:b", "(attrs !distance from=:a to=:b)");
    check_program("let in=5\n", "(top (seq (let in=5 (seq EOF))))");
    check_expr("!foo let=in", "(attrs !foo let=in)");
    check_expr("!foo stable=1 import=2 elif=3 not=4 func=5",
               "(attrs !foo stable=1 import=2 elif=3 not=4 func=5)");
    check_program("let for=1 let=2\n    if=3\n",
                  "(top (seq (let for=1 let=2 if=3 (seq EOF))))");
    check_program("let stable stable=1\n", "(top (seq (let-stable stable=1 (seq EOF))))");
    check_expr("x where in=1 from=2", "(let in=1 from=2 x)");
    check_program("func for(in, if=1)\n    in\n",
                  "(top (seq (let for=(func for (in if=1) (seq in)) (seq EOF))))");
    check_expr("f(in=1, for=2)", "(call/0 f in=1 for=2)");
    check_expr("f(from)", "(call/1 f from)");
    check_expr("x for in in y", "(for in y x)");
    check_program("import from;in from 'f'\n",
                  "(top (seq (import from;in \"f\" (seq EOF))))");
    check_expr("where + or", "(+ where or)");
    /* elif/else read as names, except right after an if block */
    check_program("let else=1 elif=2\n!a x=else+elif\n",
                  "(top (seq (let else=1 elif=2 (seq (attrs !a x=(+ else elif)) EOF))))");
    check_expr("else", "else");
    check_program("if c\n    1\nelse\n    2\n", "(top (seq (if c (seq 1) (seq 2)) EOF))");
    /* right after a tag, operator keywords name attributes */
    check_expr("!foo #t for=1 let=2", "(attrs (tag !foo #t) for=1 let=2)");
    check_expr("!foo #t in=1 #u", "(tag (attrs (tag !foo #t) in=1) #u)");
    check_error_has("!foo #t in=1 for=2\n", "unexpected '='");
    /* where the keyword is acceptable it wins */
    check_error_has("!foo for=1\n", "unexpected '='");
    check_error_has("!foo if=1\n", "unexpected '='");
    check_error_has("!foo in=1\n", "unexpected '='");
    check_error_has("!foo and=1\n", "unexpected '='");
    check_error_has("let stable=1\n", "unexpected '='");
    check_error_has("f(not=1)\n", "unexpected '='");
}

/* }===================================================================== */

/* {=====================================================================
 * Errors
 * ===================================================================== */

static void test_error_format(void **state)
{
    (void)state;
    check_error("let x=1\n!foo x=x y=\n!bar\n",
                "test.fl:2:12: error: syntax error, unexpected newline\n"
                "!foo x=x y=\n"
                "           ^\n");
    check_error("%include 'x'\n\t!a\n",
                "test.fl:2:2: error: syntax error, unexpected indent\n"
                "\t!a\n"
                "\t^\n");
    check_error("!a x=caf\xc3\xa9 \xe2\x82\xac\n",
                "test.fl:1:11: error: unexpected character '\xe2\x82\xac'\n"
                "!a x=caf\xc3\xa9 \xe2\x82\xac\n"
                "          ^\n");
    check_error("!a x=\"abc\n",
                "test.fl:1:6: error: unterminated string\n"
                "!a x=\"abc\n"
                "     ^\n");
    check_error("x 1__0\n",
                "test.fl:1:3: error: invalid number '1__0'\n"
                "x 1__0\n"
                "  ^^^^\n");
    check_error("!a\n\t!b + let\n",
                "test.fl:2:7: error: syntax error, unexpected 'let'\n"
                "\t!b + let\n"
                "\t     ^^^\n");
    check_error("if x\n    a\n  b\n",
                "test.fl:3:3: error: unexpected dedent: indentation matches no enclosing block\n"
                "  b\n"
                "  ^\n");
    check_error_has("a ]\n", "syntax error, unexpected ']'");
}

static void test_error_end_of_input(void **state)
{
    (void)state;
    check_error_has("if x\n", "unexpected end of input");
    check_error_has("if x", "unexpected end of input");
    /* the right side of '<<' is a statement, and EOF is one (as in the
     * reference) */
    check_program("!a <<\n", "(top (seq (append !a EOF)))");
    check_error_has("!a x=(1 +\n", "unexpected end of input");
    check_error_has("f(1,\n  2\n", "unexpected end of input");
    check_error_has("let x =\n\n-- more\n", "unexpected end of input");
    check_error_has("for x in y\n", "unexpected end of input");
    check_error_has("1 +\n", "unexpected end of input");
    check_error_has("!a\n    !b <<\n", "unexpected end of input");
    /* not at the end */
    check_error_has("1 +\n2\n", "unexpected newline");
}

/* }===================================================================== */

/* {=====================================================================
 * Whole programs: LANGUAGE.md §7.6 and the project's .fl files
 * ===================================================================== */

static const char *const spec_programs[] = {
    /* A */
    "let x=10\nfunc add_x(y, k=x*2)\n    x+y+k\nlet x=20\nfunc f(a, b=2, c)\n"
    "    a*b+c\n!t1 r=add_x(5) s=f(3, c=1) t=f(1,2,3,4) u=f(1, d=5, c=2) v=f()\n"
    "let a;b;c = 1;2\n!t3 a=a b=b c=c\n!t4 #z #a y=1 x=2 y=3\n!t5\n    1\n"
    "    \"s\"\n    !c1\n    (!c2;!c3) #tag\n",
    /* B */
    "let x=20\n!t2 a=(x;y for x;y in 1;2;3) b=((x;y) for x in ..2 for y in 10;20)\n",
    /* C */
    "func rec(n)\n    rec(n+1)\nlet g = func(q) q*2\n!t6 r=rec(0)\n"
    "!t7 r=(g;g)(4) s=(g;5)(1)\n",
    /* D */
    "func foo(nodes, x=10, y, z='world')\n    !foo x=x z='hello';z\n"
    "        nodes #test y=y\n@foo\n@foo y=5\n    @foo z='me' x=99\n        !baz\n",
    /* E */
    "let n=!leaf\n!a << !b x=1 << n\n    !c\nlet s =\n    !x\n    !y\nlet u;v =\n"
    "    1\n    2\n    3\n!t3 u=u v=v s=s\n!t4 x=(1 if 0 else 2 if 1 else 3)\n"
    "if 0\n    !no\nelif null\n    !no2\nelse\n    !yes\n"
    "!t5 p=(((!p1;1;!p2) #tg) x=3)\n",
};

static void test_spec_programs(void **state)
{
    (void)state;
    for (size_t i = 0; i < sizeof spec_programs / sizeof spec_programs[0]; i++)
        free(shape_of(spec_programs[i]));
    /* Program D's template call shape */
    char *d = shape_of(spec_programs[3]);
    assert_non_null(strstr(d, "(template/1 foo (seq (template/1 foo (seq !baz) z=\"me\" x=99)) y=5)"));
    free(d);
}

/* Parse every .fl file of tests/lang and tests/golden when they can be
 * found from the test's working directory (the build tree or the source
 * tree); count what was parsed. */
static void test_project_files(void **state)
{
    (void)state;
    const char *dirs[] = {
        "tests/lang", "tests/golden", "../tests/lang", "../tests/golden",
        "../../tests/lang", "../../tests/golden",
    };
    int parsed = 0;
    for (size_t d = 0; d < sizeof dirs / sizeof dirs[0]; d++) {
        DIR *dir = opendir(dirs[d]);
        if (!dir)
            continue;
        struct dirent *e;
        while ((e = readdir(dir)) != NULL) {
            size_t n = strlen(e->d_name);
            if (n < 4 || strcmp(e->d_name + n - 3, ".fl") != 0)
                continue;
            char path[1024];
            snprintf(path, sizeof path, "%s/%s", dirs[d], e->d_name);
            FILE *f = fopen(path, "rb");
            if (!f)
                continue;
            Buf text = BUF_INIT, err = BUF_INIT;
            char chunk[4096];
            size_t got;
            while ((got = fread(chunk, 1, sizeof chunk, f)) > 0)
                buf_add(&text, chunk, got);
            fclose(f);
            AstNode *top = parse_program(path, text.data ? text.data : "", text.len, 0, &err);
            if (!top)
                print_error("%s", buf_cstr(&err));
            assert_non_null(top);
            ast_free(top);
            buf_free(&text);
            buf_free(&err);
            parsed++;
        }
        closedir(dir);
    }
    print_message("parsed %d project .fl files\n", parsed);
}

/* Deep left-leaning trees must not overflow anything. */
/* Into [src]: a program of [n] ones joined by [op] (`1+1+...+1`). */
static void chain(Buf *src, int n, const char *op)
{
    buf_puts(src, "1");
    for (int i = 1; i < n; i++) {
        buf_puts(src, op);
        buf_puts(src, "1");
    }
    buf_putc(src, '\n');
}

/* Long left-nested chains parse without exhausting the C stack; the AST
 * depth cap (config.h AST_MAX_DEPTH) accepts `1+1+...` of 3998 ones (TOP,
 * SEQUENCE, 3997 BINOPs, a literal: 4000 levels) and refuses 3999 with an
 * error at the deepest node, the first `1` (so does 4000 with `*`). A
 * 100000-long chain in an attribute is refused
 * the same way, without recursion in the parser, the check or ast_free. */
static void test_long_chains(void **state)
{
    (void)state;
    static const char head[] = "test.fl:1:1: error: program nested too deeply (limit 4000 levels)\n";
    for (int n = 3998; n <= 4000; n++) {
        Buf src = BUF_INIT, err = BUF_INIT;
        chain(&src, n, n == 4000 ? "*" : "+");
        AstNode *top = parse(buf_cstr(&src), &err);
        if (n == 3998) {
            assert_non_null(top);
            assert_int_equal(err.len, 0);
            ast_free(top);
        } else {
            assert_null(top);
            assert_true(err.len > sizeof head + 6);
            assert_memory_equal(buf_cstr(&err), head, sizeof head - 1);
            assert_memory_equal(buf_cstr(&err) + sizeof head - 1, n == 4000 ? "1*1*1*" : "1+1+1+", 6);
        }
        buf_free(&src);
        buf_free(&err);
    }
    Buf src = BUF_INIT, err = BUF_INIT;
    buf_puts(&src, "!a x=1");
    for (int i = 0; i < 100000; i++)
        buf_puts(&src, "+1");
    buf_putc(&src, '\n');
    assert_null(parse(buf_cstr(&src), &err));
    assert_memory_equal(buf_cstr(&err), "test.fl:1:6: error: program nested too deeply (limit 4000 levels)\n",
                        strlen("test.fl:1:6: error: program nested too deeply (limit 4000 levels)\n"));
    buf_free(&src);
    buf_free(&err);
}

/* }===================================================================== */

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_power_and_unary),
        cmocka_unit_test(test_arithmetic),
        cmocka_unit_test(test_comparisons),
        cmocka_unit_test(test_logic),
        cmocka_unit_test(test_ranges),
        cmocka_unit_test(test_conditionals),
        cmocka_unit_test(test_comprehensions),
        cmocka_unit_test(test_functions_inline),
        cmocka_unit_test(test_calls),
        cmocka_unit_test(test_lookup_and_literals),
        cmocka_unit_test(test_literal_flags),
        cmocka_unit_test(test_nodes),
        cmocka_unit_test(test_append),
        cmocka_unit_test(test_let),
        cmocka_unit_test(test_func_statements),
        cmocka_unit_test(test_template_calls),
        cmocka_unit_test(test_for_statements),
        cmocka_unit_test(test_if_statements),
        cmocka_unit_test(test_import_include),
        cmocka_unit_test(test_top_and_pragmas),
        cmocka_unit_test(test_symbols_recorded),
        cmocka_unit_test(test_keywords_as_names),
        cmocka_unit_test(test_error_format),
        cmocka_unit_test(test_error_end_of_input),
        cmocka_unit_test(test_spec_programs),
        cmocka_unit_test(test_project_files),
        cmocka_unit_test(test_long_chains),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
