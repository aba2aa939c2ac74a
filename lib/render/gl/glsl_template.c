/* glsl_template.c: Flitter's shader templates, a subset of Mako (see
 * glsl_template.h).
 *
 * A template is split into lines, each a control line (if, elif, else,
 * endif, for, endfor), an include or text; blocks are matched once, then
 * the lines are run, a loop's body once per item. An expression is parsed
 * into a small tree of nodes in an arena and then evaluated, so that
 * `a if c else b`, `and` and `or` evaluate only what Python would. */
#include "glsl_template.h"

#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "format.h"
#include "mem.h"

#define MAX_DEPTH 64        /* nested blocks and includes */
#define MAX_NODES 512       /* nodes of one expression */
#define MAX_ARGS 8          /* items of a tuple or a call's arguments */

/* {===== values */

void tpl_value_free(TplValue *v)
{
    vec_release(v->v);
    v->v = NULL;
    v->style = TPL_NONE;
}

static TplValue val(Vec *v, TplStyle style) { return (TplValue){v, style}; }
static TplValue num_val(double x, TplStyle style) { return val(vec_num1(x), style); }
static TplValue str_val(const char *s, size_t n) { return val(vec_str(s, n), TPL_STR); }
static TplValue bool_val(bool b) { return num_val(b ? 1 : 0, TPL_BOOL); }

/* Python's truth of [v]: Flitter's for vectors; a list is true when it has
 * items, a str when it has characters. */
static bool truthy(const TplValue *v)
{
    if (v->style == TPL_LIST) return vec_len(v->v) > 0;
    return vec_truthy(v->v);
}

/* The one number of [v], or NaN. */
static double number(const TplValue *v)
{
    return vec_is_num(v->v) && vec_len(v->v) == 1 ? vec_cnums(v->v)[0] : NAN;
}

/* The one string of [v] (borrowed), or NULL. */
static const Str *string(const TplValue *v)
{
    if (!vec_is_obj(v->v) || vec_len(v->v) != 1) return NULL;
    const Elem *e = vec_celems(v->v);
    return e->kind == EL_STR ? e->str : NULL;
}

/* Python's repr of a float: the shortest text that reads back, with a
 * point when it would look like an int. */
static void put_float(Buf *b, double x)
{
    if (isnan(x)) {
        buf_puts(b, "nan");
        return;
    }
    if (isinf(x)) {
        buf_puts(b, x < 0 ? "-inf" : "inf");
        return;
    }
    size_t at = b->len;
    fmt_double(b, x);
    bool point = false;
    for (size_t i = at; i < b->len; i++)
        if (b->data[i] == '.' || b->data[i] == 'e' || b->data[i] == 'E') point = true;
    if (!point) buf_puts(b, ".0");
}

/* The text of [v] as Python's str() gives it. */
static void put_value(Buf *b, const TplValue *v, const SymTab *st)
{
    switch (v->style) {
    case TPL_INT: buf_printf(b, "%.0f", number(v)); return;
    case TPL_FLOAT: put_float(b, number(v)); return;
    case TPL_BOOL: buf_puts(b, vec_truthy(v->v) ? "True" : "False"); return;
    case TPL_NONE: buf_puts(b, "None"); return;
    case TPL_LIST:
        buf_putc(b, '[');
        for (uint32_t i = 0; i < vec_len(v->v); i++) {
            Vec *item = vec_item(v->v, i);
            const Str *s = vec_is_obj(item) ? vec_celems(item)->str : NULL;
            if (i) buf_puts(b, ", ");
            if (s) {
                buf_putc(b, '\'');
                buf_add(b, s->bytes, s->len);
                buf_putc(b, '\'');
            } else {
                fmt_str(b, item, st);
            }
            vec_release(item);
        }
        buf_putc(b, ']');
        return;
    default: fmt_str(b, v->v, st); return;
    }
}

/* }===== */

/* {===== expressions: tokens, a tree, evaluation */

typedef enum {
    N_NUM, N_STR, N_NAME, N_TUPLE, N_LIST, N_NEG, N_POS, N_NOT, N_BIN, N_CMP, N_AND, N_OR, N_COND,
    N_CALL, N_INDEX, N_ATTR,
} NodeKind;

enum { C_EQ, C_NE, C_LT, C_LE, C_GT, C_GE, C_IN, C_NOTIN };

typedef struct ENode {
    NodeKind kind;
    int op;                  /* ArithOp of N_BIN, C_* of N_CMP */
    double num;              /* N_NUM */
    const char *text;        /* N_STR (escapes already taken), N_NAME, N_CALL, N_ATTR */
    size_t len;
    int a, b, c;             /* operands (node indices), -1: none */
    int args[MAX_ARGS];      /* N_TUPLE, N_LIST, N_CALL items */
    int nargs;
    bool is_float;           /* N_NUM written with a point or exponent */
} ENode;

typedef struct Parser {
    const char *p, *end;
    ENode nodes[MAX_NODES];
    int n;
    char *strings;           /* unescaped string literals, back to back */
    size_t nstr, capstr;
    const char *error;       /* NULL while all is well */
    char msg[160];
} Parser;

static void perr(Parser *P, const char *fmt, ...)
{
    if (P->error) return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(P->msg, sizeof P->msg, fmt, ap);
    va_end(ap);
    P->error = P->msg;
}

static int new_node(Parser *P, NodeKind kind)
{
    if (P->n == MAX_NODES) {
        perr(P, "expression too long");
        return -1;
    }
    ENode *e = &P->nodes[P->n];
    memset(e, 0, sizeof *e);
    e->kind = kind;
    e->a = e->b = e->c = -1;
    return P->n++;
}

static void skip_space(Parser *P)
{
    while (P->p < P->end && (*P->p == ' ' || *P->p == '\t')) P->p++;
}

static bool is_ident(char c) { return c == '_' || (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9'); }

/* The keyword or punctuation [w] next (words must end there). */
static bool accept(Parser *P, const char *w)
{
    skip_space(P);
    size_t n = strlen(w);
    if ((size_t)(P->end - P->p) < n || memcmp(P->p, w, n) != 0) return false;
    if (is_ident(w[0]) && P->p + n < P->end && is_ident(P->p[n])) return false;
    P->p += n;
    return true;
}

static void expect(Parser *P, const char *w)
{
    if (!accept(P, w)) perr(P, "expected '%s'", w);
}

static int parse_expr(Parser *P);

/* A string literal's text, its escapes taken, kept in P->strings. */
static int parse_string(Parser *P)
{
    char q = *P->p++;
    /* the literal's offset, not a pointer: P->strings may move as it grows */
    size_t start = P->nstr;
    while (P->p < P->end && *P->p != q) {
        char c = *P->p++;
        if (c == '\\' && P->p < P->end) {
            c = *P->p++;
            c = c == 'n' ? '\n' : c == 't' ? '\t' : c;
        }
        if (P->nstr + 1 >= P->capstr) {
            P->capstr = P->capstr ? 2 * P->capstr : 256;
            P->strings = mem_realloc(P->strings, P->capstr);
        }
        P->strings[P->nstr++] = c;
    }
    if (P->p >= P->end) {
        perr(P, "string not closed");
        return -1;
    }
    P->p++;
    int k = new_node(P, N_STR);
    if (k < 0) return -1;
    P->nodes[k].num = (double)start;   /* resolved into text once parsing is over */
    P->nodes[k].len = P->nstr - start;
    return k;
}

/* Items up to [close] into node [k]'s args. */
static void parse_items(Parser *P, int k, const char *close)
{
    while (!accept(P, close)) {
        if (P->nodes[k].nargs == MAX_ARGS) {
            perr(P, "more than %d items", MAX_ARGS);
            return;
        }
        int item = parse_expr(P);
        if (item < 0) return;
        P->nodes[k].args[P->nodes[k].nargs++] = item;
        if (!accept(P, ",")) {
            expect(P, close);
            return;
        }
    }
}

static int parse_atom(Parser *P)
{
    skip_space(P);
    if (P->p >= P->end) {
        perr(P, "expression ends too soon");
        return -1;
    }
    char c = *P->p;
    if (c == '\'' || c == '"') return parse_string(P);
    if ((c >= '0' && c <= '9') || (c == '.' && P->p + 1 < P->end && P->p[1] >= '0' && P->p[1] <= '9')) {
        char buf[64];
        size_t n = 0;
        bool fl = false;
        while (P->p < P->end && n + 1 < sizeof buf &&
               (is_ident(*P->p) || *P->p == '.' ||
                ((*P->p == '+' || *P->p == '-') && n && (buf[n - 1] == 'e' || buf[n - 1] == 'E')))) {
            if (*P->p == '.' || *P->p == 'e' || *P->p == 'E') fl = true;
            buf[n++] = *P->p++;
        }
        buf[n] = '\0';
        char *endp;
        double x = strtod(buf, &endp);
        if (*endp) {
            perr(P, "bad number '%s'", buf);
            return -1;
        }
        int k = new_node(P, N_NUM);
        if (k < 0) return -1;
        P->nodes[k].num = x;
        P->nodes[k].is_float = fl;
        return k;
    }
    if (c == '(' || c == '[') {
        P->p++;
        bool list = c == '[';
        int k = new_node(P, list ? N_LIST : N_TUPLE);
        if (k < 0) return -1;
        if (!list) {
            /* (x) is x; (x,) and (x, y) are tuples */
            if (accept(P, ")")) return k;
            int first = parse_expr(P);
            if (first < 0) return -1;
            if (accept(P, ")")) return first;
            expect(P, ",");
            P->nodes[k].args[P->nodes[k].nargs++] = first;
        }
        parse_items(P, k, list ? "]" : ")");
        return k;
    }
    if (is_ident(c)) {
        const char *s = P->p;
        while (P->p < P->end && is_ident(*P->p)) P->p++;
        int k = new_node(P, N_NAME);
        if (k < 0) return -1;
        P->nodes[k].text = s;
        P->nodes[k].len = (size_t)(P->p - s);
        return k;
    }
    perr(P, "unexpected '%c'", c);
    return -1;
}

static int parse_postfix(Parser *P)
{
    int k = parse_atom(P);
    for (;;) {
        if (k < 0 || P->error) return -1;
        skip_space(P);
        if (P->p < P->end && *P->p == '(' && P->nodes[k].kind == N_NAME) {
            P->p++;
            P->nodes[k].kind = N_CALL;
            parse_items(P, k, ")");
        } else if (accept(P, "[")) {
            int i = new_node(P, N_INDEX);
            if (i < 0) return -1;
            P->nodes[i].a = k;
            P->nodes[i].b = parse_expr(P);
            expect(P, "]");
            k = i;
        } else if (P->p < P->end && *P->p == '.' && P->p + 1 < P->end && is_ident(P->p[1])) {
            P->p++;
            int i = new_node(P, N_ATTR);
            if (i < 0) return -1;
            const char *s = P->p;
            while (P->p < P->end && is_ident(*P->p)) P->p++;
            P->nodes[i].a = k;
            P->nodes[i].text = s;
            P->nodes[i].len = (size_t)(P->p - s);
            k = i;
        } else {
            return k;
        }
    }
}

static int parse_unary(Parser *P);

static int parse_power(Parser *P)
{
    int a = parse_postfix(P);
    if (a >= 0 && accept(P, "**")) {
        int k = new_node(P, N_BIN);
        if (k < 0) return -1;
        P->nodes[k].op = OP_POW;
        P->nodes[k].a = a;
        P->nodes[k].b = parse_unary(P);   /* right-associative, binds tighter than unary on its left */
        return k;
    }
    return a;
}

static int parse_unary(Parser *P)
{
    if (accept(P, "-") || accept(P, "+")) {
        bool neg = P->p[-1] == '-';
        int k = new_node(P, neg ? N_NEG : N_POS);
        if (k < 0) return -1;
        P->nodes[k].a = parse_unary(P);
        return k;
    }
    return parse_power(P);
}

static int binary(Parser *P, int op, int a, int (*next)(Parser *))
{
    int k = new_node(P, N_BIN);
    if (k < 0) return -1;
    P->nodes[k].op = op;
    P->nodes[k].a = a;
    P->nodes[k].b = next(P);
    return k;
}

static int parse_term(Parser *P)
{
    int a = parse_unary(P);
    while (a >= 0 && !P->error) {
        skip_space(P);
        if (accept(P, "//")) a = binary(P, OP_FLOORDIV, a, parse_unary);
        else if (P->p < P->end && *P->p == '*' && !(P->p + 1 < P->end && P->p[1] == '*')) {
            P->p++;
            a = binary(P, OP_MUL, a, parse_unary);
        } else if (accept(P, "/")) a = binary(P, OP_DIV, a, parse_unary);
        else if (accept(P, "%")) a = binary(P, OP_MOD, a, parse_unary);
        else break;
    }
    return a;
}

static int parse_sum(Parser *P)
{
    int a = parse_term(P);
    while (a >= 0 && !P->error) {
        if (accept(P, "+")) a = binary(P, OP_ADD, a, parse_term);
        else if (accept(P, "-")) a = binary(P, OP_SUB, a, parse_term);
        else break;
    }
    return a;
}

static int parse_comparison(Parser *P)
{
    int a = parse_sum(P);
    /* a chain (a < b < c) is a and-chain of its pairs, as in Python; the
     * middle operand is evaluated twice, which is harmless here */
    int chain = -1;
    while (a >= 0 && !P->error) {
        int op;
        if (accept(P, "==")) op = C_EQ;
        else if (accept(P, "!=")) op = C_NE;
        else if (accept(P, "<=")) op = C_LE;
        else if (accept(P, ">=")) op = C_GE;
        else if (accept(P, "<")) op = C_LT;
        else if (accept(P, ">")) op = C_GT;
        else if (accept(P, "in")) op = C_IN;
        else if (accept(P, "not")) {
            expect(P, "in");
            op = C_NOTIN;
        } else break;
        int k = new_node(P, N_CMP);
        if (k < 0) return -1;
        P->nodes[k].op = op;
        P->nodes[k].a = a;
        P->nodes[k].b = parse_sum(P);
        if (chain < 0) {
            chain = k;
        } else {
            int both = new_node(P, N_AND);
            if (both < 0) return -1;
            P->nodes[both].a = chain;
            P->nodes[both].b = k;
            chain = both;
        }
        a = P->nodes[k].b;
    }
    return chain >= 0 ? chain : a;
}

static int parse_not(Parser *P)
{
    if (accept(P, "not")) {
        int k = new_node(P, N_NOT);
        if (k < 0) return -1;
        P->nodes[k].a = parse_not(P);
        return k;
    }
    return parse_comparison(P);
}

static int parse_and(Parser *P)
{
    int a = parse_not(P);
    while (a >= 0 && !P->error && accept(P, "and")) {
        int k = new_node(P, N_AND);
        if (k < 0) return -1;
        P->nodes[k].a = a;
        P->nodes[k].b = parse_not(P);
        a = k;
    }
    return a;
}

static int parse_or(Parser *P)
{
    int a = parse_and(P);
    while (a >= 0 && !P->error && accept(P, "or")) {
        int k = new_node(P, N_OR);
        if (k < 0) return -1;
        P->nodes[k].a = a;
        P->nodes[k].b = parse_and(P);
        a = k;
    }
    return a;
}

static int parse_expr(Parser *P)
{
    int a = parse_or(P);
    if (a >= 0 && !P->error && accept(P, "if")) {
        int k = new_node(P, N_COND);
        if (k < 0) return -1;
        P->nodes[k].a = a;
        P->nodes[k].c = parse_or(P);
        expect(P, "else");
        P->nodes[k].b = parse_expr(P);
        return k;
    }
    return a;
}

/* The evaluation of one parsed expression. */
typedef struct Eval {
    const Parser *P;
    const TplEnv *env;
    const struct Frame *frames;   /* the loops around the expression */
    const char *error;
    char msg[160];
} Eval;

/* One running `for`: its variable and item, and where it is. */
typedef struct Frame {
    const char *name;
    size_t len;
    TplValue item;
    long index, count;
    const struct Frame *outer;
} Frame;

static TplValue fail_eval(Eval *E, const char *fmt, ...)
{
    if (!E->error) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(E->msg, sizeof E->msg, fmt, ap);
        va_end(ap);
        E->error = E->msg;
    }
    return val(NULL, TPL_NONE);
}

static TplValue eval(Eval *E, int k);

static TplValue copy(const TplValue *v) { return val(vec_share(v->v), v->style); }

static TplValue lookup(Eval *E, const char *name, size_t len)
{
    for (const Frame *f = E->frames; f; f = f->outer)
        if (f->len == len && memcmp(f->name, name, len) == 0) return copy(&f->item);
    if (len == 4 && memcmp(name, "True", 4) == 0) return bool_val(true);
    if (len == 5 && memcmp(name, "False", 5) == 0) return bool_val(false);
    if (len == 4 && memcmp(name, "None", 4) == 0) return val(NULL, TPL_NONE);
    TplValue out = val(NULL, TPL_NONE);
    if (E->env->lookup && E->env->lookup(E->env->ctx, name, len, &out)) return out;
    return fail_eval(E, "name '%.*s' is not defined", (int)len, name);
}

/* Item [i] of [v] (negative from the end), as Python indexes a list, a
 * str or a Flitter Vector. */
static TplValue index_of(Eval *E, const TplValue *v, const TplValue *i)
{
    double x = number(i);
    if (isnan(x)) return fail_eval(E, "index is not a number");
    const Str *s = v->style == TPL_STR ? string(v) : NULL;
    long n = s ? (long)s->len : (long)vec_len(v->v);
    long k = (long)floor(x);
    if (k < 0) k += n;
    if (k < 0 || k >= n) return fail_eval(E, "index out of range");
    if (s) return str_val(s->bytes + k, 1);
    Vec *item = vec_item(v->v, k);
    TplStyle st = v->style == TPL_LIST ? (vec_is_obj(item) ? TPL_STR : TPL_FLOAT) : TPL_VEC;
    if (v->style == TPL_VEC) st = vec_is_obj(item) ? TPL_STR : TPL_FLOAT;   /* Vector[i]: a float or a str */
    return val(item, st);
}

static bool int_style(const TplValue *a) { return a->style == TPL_INT || a->style == TPL_BOOL; }

static TplValue arith(Eval *E, int op, TplValue *a, TplValue *b)
{
    const Str *sa = string(a), *sb = string(b);
    if (op == OP_ADD && sa && sb) {
        Buf t = BUF_INIT;
        buf_add(&t, sa->bytes, sa->len);
        buf_add(&t, sb->bytes, sb->len);
        TplValue r = str_val(t.data, t.len);
        buf_free(&t);
        return r;
    }
    Vec *r = vec_arith((ArithOp)op, a->v, b->v);
    if (!r) return fail_eval(E, "arithmetic on values that are not numbers");
    /* Python keeps ints int but for true division; a Vector operand makes a Vector */
    TplStyle st = a->style == TPL_VEC || b->style == TPL_VEC           ? TPL_VEC
                  : int_style(a) && int_style(b) && op != OP_DIV ? TPL_INT
                                                                       : TPL_FLOAT;
    return val(r, st);
}

/* Whether [x] is in [y]: a substring of a str, else an item of the vector. */
static bool contains(const TplValue *x, const TplValue *y)
{
    const Str *sx = string(x), *sy = y->style == TPL_STR ? string(y) : NULL;
    if (sx && sy) {
        if (sx->len == 0) return true;
        for (size_t i = 0; i + sx->len <= sy->len; i++)
            if (memcmp(sy->bytes + i, sx->bytes, sx->len) == 0) return true;
        return false;
    }
    for (uint32_t i = 0; i < vec_len(y->v); i++) {
        Vec *item = vec_item(y->v, i);
        bool eq = vec_equal(item, x->v);
        vec_release(item);
        if (eq) return true;
    }
    return false;
}

static TplValue compare(Eval *E, int op, const TplValue *a, const TplValue *b)
{
    switch (op) {
    case C_EQ: return bool_val(vec_equal(a->v, b->v));
    case C_NE: return bool_val(!vec_equal(a->v, b->v));
    case C_IN: return bool_val(contains(a, b));
    case C_NOTIN: return bool_val(!contains(a, b));
    default: break;
    }
    if (!a->v || !b->v) return fail_eval(E, "comparison with None");
    int c = vec_cmp(a->v, b->v);
    switch (op) {
    case C_LT: return bool_val(c < 0);
    case C_LE: return bool_val(c <= 0);
    case C_GT: return bool_val(c > 0);
    default: return bool_val(c >= 0);
    }
}

static TplValue call(Eval *E, const ENode *n)
{
    TplValue args[MAX_ARGS];
    int na = n->nargs;
    for (int i = 0; i < na; i++) args[i] = eval(E, n->args[i]);
    TplValue r = val(NULL, TPL_NONE);
#define IS(s) (n->len == sizeof s - 1 && memcmp(n->text, s, sizeof s - 1) == 0)
    if (E->error) {
        /* an argument failed */
    } else if ((IS("int") || IS("float") || IS("bool") || IS("abs") || IS("round") || IS("str") || IS("len")) &&
               na != 1) {
        fail_eval(E, "%.*s() takes one argument", (int)n->len, n->text);
    } else if (IS("int")) {
        double x = number(&args[0]);
        const Str *s = string(&args[0]);
        if (s) x = strtod(s->bytes, NULL);
        /* Vector.__int__ floors; Python's int() truncates */
        r = isnan(x) ? num_val(0, TPL_INT) : num_val(args[0].style == TPL_VEC ? floor(x) : trunc(x), TPL_INT);
    } else if (IS("float")) {
        const Str *s = string(&args[0]);
        r = num_val(s ? strtod(s->bytes, NULL) : number(&args[0]), TPL_FLOAT);
    } else if (IS("bool")) {
        r = bool_val(truthy(&args[0]));
    } else if (IS("abs")) {
        double x = number(&args[0]);
        r = num_val(fabs(x), args[0].style == TPL_INT ? TPL_INT : TPL_FLOAT);
    } else if (IS("round")) {
        r = num_val(nearbyint(number(&args[0])), TPL_INT);
    } else if (IS("str")) {
        Buf t = BUF_INIT;
        put_value(&t, &args[0], E->env->symbols);
        r = str_val(t.data ? t.data : "", t.len);
        buf_free(&t);
    } else if (IS("len")) {
        const Str *s = args[0].style == TPL_STR ? string(&args[0]) : NULL;
        r = num_val(s ? (double)s->len : (double)vec_len(args[0].v), TPL_INT);
    } else if (IS("min") || IS("max")) {
        if (na < 1) {
            fail_eval(E, "%.*s() needs arguments", (int)n->len, n->text);
        } else {
            int best = 0;
            for (int i = 1; i < na; i++) {
                int c = vec_cmp(args[i].v, args[best].v);
                if (IS("min") ? c < 0 : c > 0) best = i;
            }
            r = copy(&args[best]);
        }
    } else {
        fail_eval(E, "unknown function %.*s()", (int)n->len, n->text);
    }
#undef IS
    for (int i = 0; i < na; i++) tpl_value_free(&args[i]);
    return r;
}

static TplValue eval(Eval *E, int k)
{
    if (E->error || k < 0) return val(NULL, TPL_NONE);
    const ENode *n = &E->P->nodes[k];
    TplValue a, b, r;
    switch (n->kind) {
    case N_NUM: return num_val(n->num, n->is_float ? TPL_FLOAT : TPL_INT);
    case N_STR: return str_val(n->text, n->len);
    case N_NAME: return lookup(E, n->text, n->len);
    case N_TUPLE:
    case N_LIST: {
        Vec *parts[MAX_ARGS];
        for (int i = 0; i < n->nargs; i++) {
            a = eval(E, n->args[i]);
            parts[i] = a.v ? a.v : vec_num1(0);
        }
        r = val(vec_compose_take(parts, (size_t)n->nargs), TPL_LIST);
        return r;
    }
    case N_NEG:
    case N_POS:
        a = eval(E, n->a);
        r = n->kind == N_POS ? copy(&a) : val(vec_neg(a.v), a.style == TPL_BOOL ? TPL_INT : a.style);
        if (!r.v && !E->error) fail_eval(E, "unary %c of a value that is not a number", n->kind == N_NEG ? '-' : '+');
        tpl_value_free(&a);
        return r;
    case N_NOT:
        a = eval(E, n->a);
        r = bool_val(!truthy(&a));
        tpl_value_free(&a);
        return r;
    case N_BIN:
        a = eval(E, n->a);
        b = eval(E, n->b);
        r = E->error ? val(NULL, TPL_NONE) : arith(E, n->op, &a, &b);
        tpl_value_free(&a);
        tpl_value_free(&b);
        return r;
    case N_CMP:
        a = eval(E, n->a);
        b = eval(E, n->b);
        r = E->error ? val(NULL, TPL_NONE) : compare(E, n->op, &a, &b);
        tpl_value_free(&a);
        tpl_value_free(&b);
        return r;
    case N_AND:
    case N_OR:
        a = eval(E, n->a);
        if (truthy(&a) == (n->kind == N_OR) || E->error) return a;
        tpl_value_free(&a);
        return eval(E, n->b);
    case N_COND:
        a = eval(E, n->c);
        r = eval(E, truthy(&a) ? n->a : n->b);
        tpl_value_free(&a);
        return r;
    case N_CALL: return call(E, n);
    case N_INDEX:
        a = eval(E, n->a);
        b = eval(E, n->b);
        r = E->error ? val(NULL, TPL_NONE) : index_of(E, &a, &b);
        tpl_value_free(&a);
        tpl_value_free(&b);
        return r;
    case N_ATTR: {
        const ENode *base = &E->P->nodes[n->a];
        if (base->kind != N_NAME || base->len != 4 || memcmp(base->text, "loop", 4) != 0 || !E->frames)
            return fail_eval(E, "attribute .%.*s not supported", (int)n->len, n->text);
        const Frame *f = E->frames;
        if (n->len == 5 && memcmp(n->text, "index", 5) == 0) return num_val((double)f->index, TPL_INT);
        if (n->len == 5 && memcmp(n->text, "first", 5) == 0) return bool_val(f->index == 0);
        if (n->len == 4 && memcmp(n->text, "last", 4) == 0) return bool_val(f->index == f->count - 1);
        return fail_eval(E, "loop.%.*s not supported", (int)n->len, n->text);
    }
    }
    return val(NULL, TPL_NONE);
}

/* Parse and evaluate the expression [s] .. [end]. */
static TplValue evaluate(const char *s, const char *end, const TplEnv *env, const Frame *frames, Buf *err,
                         bool *ok)
{
    Parser *P = mem_alloc(sizeof *P);
    P->p = s;
    P->end = end;
    P->n = 0;
    P->strings = NULL;
    P->nstr = P->capstr = 0;
    P->error = NULL;
    int root = parse_expr(P);
    skip_space(P);
    if (!P->error && P->p != P->end) perr(P, "unexpected text '%.*s'", (int)(P->end - P->p), P->p);
    TplValue r = val(NULL, TPL_NONE);
    if (P->error) {
        buf_printf(err, "%s\n", P->error);
        *ok = false;
    } else {
        for (int i = 0; i < P->n; i++)
            if (P->nodes[i].kind == N_STR) P->nodes[i].text = P->strings + (size_t)P->nodes[i].num;
        Eval E = {.P = P, .env = env, .frames = frames};
        r = eval(&E, root);
        if (E.error) {
            buf_printf(err, "%s\n", E.error);
            tpl_value_free(&r);
            *ok = false;
        } else {
            *ok = true;
        }
    }
    free(P->strings);
    free(P);
    return r;
}

/* }===== */

/* {===== lines and blocks */

typedef enum { L_TEXT, L_IF, L_ELIF, L_ELSE, L_ENDIF, L_FOR, L_ENDFOR, L_INCLUDE, L_COMMENT } LineKind;

typedef struct Line {
    LineKind kind;
    const char *s, *e;       /* L_TEXT: the text with its newline; control lines:
                                the expression (L_FOR: after "in"); L_INCLUDE: the file name */
    const char *var;         /* L_FOR: the variable */
    size_t varlen;
    int next;                /* L_IF/L_ELIF/L_ELSE: the next branch or endif; L_FOR: its endfor */
    int no;                  /* line number, from 1 */
    bool join;               /* L_TEXT ends with a backslash: no newline */
} Line;

typedef struct Template {
    Line *lines;
    int n, cap;
} Template;

static bool starts(const char *s, const char *e, const char *w)
{
    size_t n = strlen(w);
    return (size_t)(e - s) >= n && memcmp(s, w, n) == 0 && ((size_t)(e - s) == n || !is_ident(s[n]));
}

static const char *trim_left(const char *s, const char *e)
{
    while (s < e && (*s == ' ' || *s == '\t')) s++;
    return s;
}

static const char *trim_right(const char *s, const char *e)
{
    while (e > s && (e[-1] == ' ' || e[-1] == '\t' || e[-1] == '\r' || e[-1] == '\n')) e--;
    return e;
}

/* Split [src] into lines and classify them. */
static int split_lines(Template *t, const char *src, size_t len, Buf *err)
{
    const char *p = src, *end = src + len;
    int no = 0;
    while (p < end) {
        const char *nl = memchr(p, '\n', (size_t)(end - p));
        const char *le = nl ? nl + 1 : end;
        no++;
        if (t->n == t->cap) {
            t->cap = t->cap ? 2 * t->cap : 64;
            t->lines = mem_realloc_array(t->lines, (size_t)t->cap, sizeof *t->lines);
        }
        Line *L = &t->lines[t->n++];
        memset(L, 0, sizeof *L);
        L->no = no;
        L->next = -1;
        const char *s = trim_left(p, le);
        if (s < le && *s == '%' && !(s + 1 < le && s[1] == '%')) {
            s = trim_left(s + 1, le);
            const char *e = trim_right(s, le);
            if (e > s && e[-1] == ':') e = trim_right(s, e - 1);
            if (starts(s, e, "endif")) L->kind = L_ENDIF;
            else if (starts(s, e, "endfor")) L->kind = L_ENDFOR;
            else if (starts(s, e, "else")) L->kind = L_ELSE;
            else if (starts(s, e, "elif")) L->kind = L_ELIF, L->s = s + 4, L->e = e;
            else if (starts(s, e, "if")) L->kind = L_IF, L->s = s + 2, L->e = e;
            else if (starts(s, e, "for")) {
                L->kind = L_FOR;
                const char *v = trim_left(s + 3, e), *ve = v;
                while (ve < e && is_ident(*ve)) ve++;
                const char *in = trim_left(ve, e);
                if (ve == v || !starts(in, e, "in")) {
                    buf_printf(err, "line %d: expected '%% for NAME in EXPR:'\n", no);
                    return -1;
                }
                L->var = v;
                L->varlen = (size_t)(ve - v);
                L->s = in + 2;
                L->e = e;
            } else {
                buf_printf(err, "line %d: unsupported control line '%%%.*s'\n", no, (int)(e - s), s);
                return -1;
            }
        } else if (s + 1 < le && s[0] == '#' && s[1] == '#') {
            L->kind = L_COMMENT;
        } else if (starts(s, le, "<%include")) {
            const char *f = strstr(s, "file=");
            const char *e = trim_right(s, le);
            if (!f || f > e || (f[5] != '"' && f[5] != '\'') || e - s < 2 || memcmp(e - 2, "/>", 2) != 0) {
                buf_printf(err, "line %d: expected <%%include file=\"NAME\"/>\n", no);
                return -1;
            }
            const char *q = memchr(f + 6, f[5], (size_t)(e - f - 6));
            if (!q) {
                buf_printf(err, "line %d: include file name not closed\n", no);
                return -1;
            }
            L->kind = L_INCLUDE;
            L->s = f + 6;
            L->e = q;
        } else if (s < le && *s == '<' && s + 1 < le && s[1] == '%') {
            buf_printf(err, "line %d: unsupported template tag (only <%%include file=\"...\"/>)\n", no);
            return -1;
        } else {
            L->kind = L_TEXT;
            L->s = p;
            L->e = le;
            /* a backslash just before the newline joins the next line on */
            const char *e = nl ? nl : le;
            if (e > p && e[-1] == '\r') e--;
            if (nl && e > p && e[-1] == '\\') {
                L->join = true;
                L->e = e - 1;
            }
            /* a %% at the start stands for one % */
            if (s + 1 < le && s[0] == '%' && s[1] == '%') L->s = s + 1;
        }
        p = le;
    }
    return 0;
}

/* Link each block's branches and ends. */
static int match_blocks(Template *t, Buf *err)
{
    int stack[MAX_DEPTH], depth = 0;
    for (int i = 0; i < t->n; i++) {
        Line *L = &t->lines[i];
        switch (L->kind) {
        case L_IF:
        case L_FOR:
            if (depth == MAX_DEPTH) {
                buf_printf(err, "line %d: blocks nested deeper than %d\n", L->no, MAX_DEPTH);
                return -1;
            }
            stack[depth++] = i;
            break;
        case L_ELIF:
        case L_ELSE:
        case L_ENDIF:
            if (!depth || (t->lines[stack[depth - 1]].kind != L_IF && t->lines[stack[depth - 1]].kind != L_ELIF &&
                           t->lines[stack[depth - 1]].kind != L_ELSE)) {
                buf_printf(err, "line %d: %s without if\n", L->no,
                         L->kind == L_ENDIF ? "endif" : L->kind == L_ELSE ? "else" : "elif");
                return -1;
            }
            if (t->lines[stack[depth - 1]].kind == L_ELSE && L->kind != L_ENDIF) {
                buf_printf(err, "line %d: branch after else\n", L->no);
                return -1;
            }
            t->lines[stack[depth - 1]].next = i;
            if (L->kind == L_ENDIF) depth--;
            else stack[depth - 1] = i;
            break;
        case L_ENDFOR:
            if (!depth || t->lines[stack[depth - 1]].kind != L_FOR) {
                buf_printf(err, "line %d: endfor without for\n", L->no);
                return -1;
            }
            t->lines[stack[--depth]].next = i;
            break;
        default: break;
        }
    }
    if (depth) {
        buf_printf(err, "line %d: block not closed\n", t->lines[stack[depth - 1]].no);
        return -1;
    }
    return 0;
}

typedef struct Run {
    const TplEnv *env;
    Buf *out;
    Buf *err;
    int includes;            /* include depth */
} Run;

static int render_text(Run *R, const char *src, size_t len, const Frame *frames);

/* Text line [L] with its ${...} replaced. */
static int text_line(Run *R, const Line *L, const Frame *frames)
{
    const char *p = L->s, *e = L->e;
    while (p < e) {
        const char *d = p;
        while (d + 1 < e && !(d[0] == '$' && d[1] == '{')) d++;
        if (d + 1 >= e) {
            buf_add(R->out, p, (size_t)(e - p));
            break;
        }
        buf_add(R->out, p, (size_t)(d - p));
        /* the matching brace, past strings and nested brackets */
        const char *q = d + 2;
        int nest = 0;
        char quote = 0;
        for (; q < e; q++) {
            if (quote) {
                if (*q == '\\') q++;
                else if (*q == quote) quote = 0;
            } else if (*q == '\'' || *q == '"') {
                quote = *q;
            } else if (*q == '{') {
                nest++;
            } else if (*q == '}') {
                if (nest-- == 0) break;
            }
        }
        if (q >= e) {
            buf_printf(R->err, "line %d: ${ not closed\n", L->no);
            return -1;
        }
        Buf why = BUF_INIT;
        bool ok;
        TplValue v = evaluate(d + 2, q, R->env, frames, &why, &ok);
        if (!ok) {
            buf_printf(R->err, "line %d: %s\n", L->no, buf_line(&why));
            buf_free(&why);
            return -1;
        }
        put_value(R->out, &v, R->env->symbols);
        tpl_value_free(&v);
        p = q + 1;
    }
    return 0;
}

static bool cond(Run *R, const Line *L, const Frame *frames, bool *ok)
{
    Buf why = BUF_INIT;
    TplValue v = evaluate(L->s, L->e, R->env, frames, &why, ok);
    if (!*ok) {
        buf_printf(R->err, "line %d: %s\n", L->no, buf_line(&why));
        buf_free(&why);
        return false;
    }
    bool b = truthy(&v);
    tpl_value_free(&v);
    return b;
}

static int run_lines(Run *R, const Template *t, int from, int to, const Frame *frames)
{
    for (int i = from; i < to; i++) {
        const Line *L = &t->lines[i];
        switch (L->kind) {
        case L_TEXT:
            if (text_line(R, L, frames) != 0) return -1;
            break;
        case L_COMMENT: break;
        case L_INCLUDE: {
            char file[128];
            snprintf(file, sizeof file, "%.*s", (int)(L->e - L->s), L->s);
            const char *text = R->env->include ? R->env->include(file) : NULL;
            if (!text) {
                buf_printf(R->err, "line %d: no include file \"%s\"\n", L->no, file);
                return -1;
            }
            if (R->includes == 8) {
                buf_printf(R->err, "line %d: includes nested deeper than 8\n", L->no);
                return -1;
            }
            R->includes++;
            size_t mark = R->err->len;
            int rc = render_text(R, text, strlen(text), frames);
            R->includes--;
            if (rc != 0) {
                /* name the include the message came from */
                char *inner = mem_strdup(R->err->data ? R->err->data + mark : "");
                size_t n = strlen(inner);
                while (n && inner[n - 1] == '\n') inner[--n] = '\0';
                buf_truncate(R->err, mark);
                buf_printf(R->err, "line %d: in %s: %s\n", L->no, file, inner);
                free(inner);
                return -1;
            }
            break;
        }
        case L_IF: {
            int b = i;
            bool ok;
            while (t->lines[b].kind != L_ENDIF) {
                const Line *B = &t->lines[b];
                bool take = B->kind == L_ELSE || cond(R, B, frames, &ok);
                if (B->kind != L_ELSE && !ok) return -1;
                if (take) {
                    if (run_lines(R, t, b + 1, B->next, frames) != 0) return -1;
                    break;
                }
                b = B->next;
            }
            while (t->lines[b].kind != L_ENDIF) b = t->lines[b].next;
            i = b;
            break;
        }
        case L_FOR: {
            Buf why = BUF_INIT;
            bool ok;
            TplValue seq = evaluate(L->s, L->e, R->env, frames, &why, &ok);
            if (!ok) {
                buf_printf(R->err, "line %d: %s\n", L->no, buf_line(&why));
                buf_free(&why);
                return -1;
            }
            const Str *s = seq.style == TPL_STR ? string(&seq) : NULL;
            long n = s ? (long)s->len : (long)vec_len(seq.v);
            Frame f = {.name = L->var, .len = L->varlen, .count = n, .outer = frames};
            int rc = 0;
            for (long k = 0; k < n && rc == 0; k++) {
                f.index = k;
                if (s) {
                    f.item = str_val(s->bytes + k, 1);
                } else {
                    Vec *item = vec_item(seq.v, k);
                    f.item = val(item, vec_is_obj(item) ? TPL_STR : seq.style == TPL_LIST ? TPL_INT : TPL_FLOAT);
                    if (vec_is_num(item) && seq.style == TPL_LIST && floor(vec_cnums(item)[0]) != vec_cnums(item)[0])
                        f.item.style = TPL_FLOAT;
                }
                rc = run_lines(R, t, i + 1, L->next, &f);
                tpl_value_free(&f.item);
            }
            tpl_value_free(&seq);
            if (rc != 0) return -1;
            i = L->next;
            break;
        }
        default:
            /* a branch or end reached by falling off a taken branch */
            return 0;
        }
    }
    return 0;
}

static int render_text(Run *R, const char *src, size_t len, const Frame *frames)
{
    Template t = {0};
    int rc = split_lines(&t, src, len, R->err);
    if (rc == 0) rc = match_blocks(&t, R->err);
    if (rc == 0) rc = run_lines(R, &t, 0, t.n, frames);
    free(t.lines);
    return rc;
}

int tpl_render(const char *src, size_t len, const TplEnv *env, Buf *out, Buf *err)
{
    Run R = {.env = env, .out = out, .err = err};
    return render_text(&R, src, len, NULL);
}

/* }===== */
