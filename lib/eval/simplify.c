/* simplify.c: the simplifier's driver, operators and node expressions
 * (LANGUAGE.md §4.17; the rule order follows tree.pyx `_simplify`).
 *
 * simp() returns a new, simplified copy of a node and never changes its
 * argument, so a loop body can be unrolled and a function body inlined as
 * often as needed. A rewrite builds the new expression from simplified
 * parts and simplifies it again (resimp), exactly as the reference does.
 * Literal folding evaluates with the evaluator's own vector operations, so
 * a folded value equals the value the evaluator would compute (S1).
 */
#include "simplify_internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "config.h"
#include "builtins.h"
#include "mem.h"

/* ====================================================================
 * Tree helpers
 * ==================================================================== */

AstNode *ast_copy(const AstNode *n)
{
    if (!n) return NULL;
    AstNode *c = ast_new((AstKind)n->kind, n->loc);
    c->op = n->op;
    c->count = n->count;
    c->a = ast_copy(n->a);
    c->b = ast_copy(n->b);
    c->c = ast_copy(n->c);
    for (uint32_t i = 0; i < n->nkids; i++) ast_push(c, ast_copy(n->kids[i]));
    for (uint32_t i = 0; i < n->nnames; i++) ast_push_name(c, str_retain(n->names[i]));
    c->value = vec_retain(n->value);
    if (has_col(n)) col_attach(c, col_retain(n->aux));
    return c;
}

AstNode *mk_lit(Vec *v_take, Loc loc)
{
    AstNode *n = ast_literal(v_take, loc);
    if (vec_is_scalar(v_take)) n->op = 1;   /* a single number: IndexLiteral (§3.11) */
    return n;
}

static AstNode *mk_noop(Loc loc) { return mk_lit(NULL, loc); }

static AstNode *mk_bin(AstKind kind, int op, AstNode *a, AstNode *b, Loc loc)
{
    return ast_binary(kind, op, a, b, loc);
}

static AstNode *mk_un(AstKind kind, AstNode *a, Loc loc) { return ast_unary(kind, a, loc); }

AstNode *resimp(Simp *s, AstNode *n_take)
{
    AstNode *r = simp(s, n_take);
    ast_free(n_take);
    return r;
}

static uint64_t warn_hash(const char *msg, size_t len)
{
    uint64_t h = 1469598103934665603u;
    for (size_t i = 0; i < len; i++) h = (h ^ (unsigned char)msg[i]) * 1099511628211u;
    return h ? h : 1;
}

/* Put line [start, len) with hash [h] into [t] (which has room). */
static void warn_put(WarnTable *t, uint64_t h, size_t start, size_t len)
{
    size_t i = (size_t)h & (t->cap - 1);
    while (t->hash[i]) i = (i + 1) & (t->cap - 1);
    t->hash[i] = h;
    t->start[i] = start;
    t->len[i] = len;
    t->n++;
}

void simp_warn(Simp *s, const char *msg)
{
    if (s->tg || s->talone) {   /* a template pass writes nothing: its loop is unrolled one copy at a time */
        s->tabort = true;
        return;
    }
    if (!s->warnings || !s->warned) return;
    WarnTable *t = s->warned;
    size_t len = strlen(msg);
    uint64_t h = warn_hash(msg, len);
    /* one line per message, each once */
    for (size_t i = t->cap ? (size_t)h & (t->cap - 1) : 0; t->cap && t->hash[i]; i = (i + 1) & (t->cap - 1))
        if (t->hash[i] == h && t->len[i] == len && memcmp(s->warnings->data + t->start[i], msg, len) == 0)
            return;
    if (2 * (t->n + 1) > t->cap) {   /* grow: keep the load under 1/2 */
        WarnTable old = *t;
        t->cap = old.cap ? old.cap * 2 : 64;
        t->n = 0;
        t->hash = calloc(t->cap, sizeof *t->hash);
        t->start = malloc(t->cap * sizeof *t->start);
        t->len = malloc(t->cap * sizeof *t->len);
        if (!t->hash || !t->start || !t->len) mem_oom();
        for (size_t i = 0; i < old.cap; i++)
            if (old.hash[i]) warn_put(t, old.hash[i], old.start[i], old.len[i]);
        free(old.hash);
        free(old.start);
        free(old.len);
    }
    size_t start = s->warnings->len;
    buf_printf(s->warnings, "%s\n", msg);
    warn_put(t, h, start, len);
}

void simp_share_warnings(Simp *sub, const Simp *s)
{
    if (sub->owns_warned) free(sub->warned);
    sub->warned = s->warned;
    sub->owns_warned = false;
}

/* Evaluate [n], whose operands are all literals, with the evaluator. */
static Vec *fold(Simp *s, const AstNode *n)
{
    Vec *v = eval_expr(&s->ev, n);
    for (uint32_t i = 0; i < s->errors.count; i++) simp_warn(s, s->errors.items[i]);
    msgset_clear(&s->errors);
    return v;
}

static Vec *fold_fn(Simp *s, AstNode *n) { return fold(s, n); }

/* [n] (all operands literal) folded into a literal at [loc], with the
 * members' values in a template pass. */
static AstNode *fold_lit(Simp *s, AstNode *n, Loc loc)
{
    Column *c = tcol_eval(s, n, fold_fn);
    return tlit(s, fold(s, n), c, loc);
}

static bool lit_numeric(Simp *s, const AstNode *n) { return tdecide(s, n, TD_NUMERIC, 0); }

/* The literal equals the one-element vector [x] (tree.pyx `eq(...) is true_`). */
static bool lit_equals(Simp *s, const AstNode *n, double x) { return tdecide(s, n, TD_EQUALS, x); }

/* In a template pass, [f] of each member's value of literal [n]; NULL
 * when [n] has no column. */
static Column *col_map(Simp *s, const AstNode *n, Vec *(*f)(const Vec *))
{
    if (!s->tg || !has_col(n)) return NULL;
    Column *c = col_new(s->tg);
    for (uint32_t m = 0; m < s->tg; m++) c->v[m] = f(tval(n, m));
    return c;
}

/* The numeric column of literal [n] in a template pass: its own column
 * when that is numeric, or a one-number value (every member's) in [*one]
 * with NULL returned; false when neither. */
static bool num_operand(const AstNode *n, const Column **col, double *one)
{
    *col = NULL;
    if (has_col(n)) {
        *col = n->aux;
        return (*col)->num != NULL;
    }
    if (!vec_is_scalar(n->value)) return false;
    *one = vec_cnums(n->value)[0];
    return true;
}

static Vec *vec_inverse(const Vec *v)
{
    Vec *one = vec_num1(1.0);
    Vec *inv = vec_arith(OP_DIV, one, v);
    vec_release(one);
    return inv;
}

static Vec *vec_neg_fn(const Vec *v) { return vec_neg(v); }
static Vec *vec_pos_fn(const Vec *v) { return vec_pos((Vec *)v); }

enum { MAP_NEG, MAP_POS, MAP_INV };

/* col_map of -x (vec_neg), +x (vec_pos) or 1/x (vec_inverse) of literal
 * [n]; a numeric column maps to a numeric column, with the operation
 * vec_neg or vec_arith performs on a one-number vector. */
static Column *col_unary(Simp *s, const AstNode *n, int how)
{
    if (!s->tg || !has_col(n)) return NULL;
    const Column *a = n->aux;
    if (!a->num) return col_map(s, n, how == MAP_NEG ? vec_neg_fn : how == MAP_POS ? vec_pos_fn : vec_inverse);
    Column *c = col_new_num(s->tg);
    for (uint32_t m = 0; m < s->tg; m++) {
        double x = a->num[m];
        c->num[m] = how == MAP_NEG ? -x : how == MAP_POS ? x : num_arith(OP_DIV, 1.0, x);
    }
    return c;
}

static bool is_maths(const AstNode *n) { return n && n->kind == AST_BINOP; }
static bool is_binop(const AstNode *n, int op) { return n && n->kind == AST_BINOP && n->op == op; }

/* ====================================================================
 * Arithmetic rewrites (S2-S17)
 * ==================================================================== */

/* The rule for a literal left operand [l] and other operand [r] (both
 * simplified; consumed when a rule applies), or NULL when none applies (l
 * and r then untouched). Sums and products use it for a literal on either
 * side, as tree.pyx does. */
static AstNode *constant_left(Simp *s, int op, AstNode *l, AstNode *r, Loc loc)
{
    if (!lit_numeric(s, l)) {
        if (op == OP_ADD || op == OP_SUB || op == OP_MUL || op == OP_DIV || op == OP_FLOORDIV ||
            op == OP_MOD || op == OP_POW) {
            ast_free(l);
            ast_free(r);
            return mk_noop(loc);            /* S17 */
        }
        return NULL;
    }
    switch (op) {
    case OP_ADD:
        if (lit_equals(s, l, 0.0)) {            /* S2 */
            ast_free(l);
            return mk_un(AST_POS, r, loc);
        }
        return NULL;
    case OP_SUB:
        if (lit_equals(s, l, 0.0)) {            /* S3 */
            ast_free(l);
            return mk_un(AST_NEG, r, loc);
        }
        return NULL;
    case OP_MUL:
        if (lit_equals(s, l, 1.0)) {            /* S5 */
            ast_free(l);
            return mk_un(AST_POS, r, loc);
        }
        if (lit_equals(s, l, -1.0)) {
            ast_free(l);
            return mk_un(AST_NEG, r, loc);
        }
        if ((is_binop(r, OP_ADD) || is_binop(r, OP_SUB)) && (is_lit(r->a) || is_lit(r->b))) {
            /* S7: L*(a+b) -> (L*a) + (L*b) */
            AstNode *la = mk_bin(AST_BINOP, OP_MUL, ast_copy(l), r->a, loc);
            AstNode *lb = mk_bin(AST_BINOP, OP_MUL, l, r->b, loc);
            AstNode *e = mk_bin(AST_BINOP, r->op, la, lb, loc);
            r->a = r->b = NULL;
            ast_free(r);
            return e;
        }
        if (is_binop(r, OP_MUL)) {           /* S8 */
            if (is_lit(r->a)) {
                AstNode *e = mk_bin(AST_BINOP, OP_MUL, mk_bin(AST_BINOP, OP_MUL, l, r->a, loc), r->b, loc);
                r->a = r->b = NULL;
                ast_free(r);
                return e;
            }
            if (is_lit(r->b)) {
                AstNode *e = mk_bin(AST_BINOP, OP_MUL, mk_bin(AST_BINOP, OP_MUL, l, r->b, loc), r->a, loc);
                r->a = r->b = NULL;
                ast_free(r);
                return e;
            }
            return NULL;
        }
        if (is_binop(r, OP_DIV)) {           /* S9 */
            if (is_lit(r->a)) {
                AstNode *e = mk_bin(AST_BINOP, OP_DIV, mk_bin(AST_BINOP, OP_MUL, l, r->a, loc), r->b, loc);
                r->a = r->b = NULL;
                ast_free(r);
                return e;
            }
            return NULL;
        }
        if (r->kind == AST_NEG) {            /* S10 */
            AstNode *e = mk_bin(AST_BINOP, OP_MUL, tlit(s, vec_neg(l->value), col_unary(s, l, MAP_NEG), loc), r->a, loc);
            r->a = NULL;
            ast_free(r);
            ast_free(l);
            return e;
        }
        return NULL;
    default:
        return NULL;
    }
}

/* The rule for a literal right operand [r] (S3-S6, S16), or NULL. */
static AstNode *constant_right(Simp *s, int op, AstNode *l, AstNode *r, Loc loc)
{
    switch (op) {
    case OP_ADD:
    case OP_MUL:
        return constant_left(s, op, r, l, loc);   /* commutative: same rules */
    case OP_SUB:
        if (lit_equals(s, r, 0.0)) {              /* S3 */
            ast_free(r);
            return mk_un(AST_POS, l, loc);
        }
        {                                      /* S4: x - L -> x + (-L) */
            AstNode *e = mk_bin(AST_BINOP, OP_ADD, l, tlit(s, vec_neg(r->value), col_unary(s, r, MAP_NEG), loc), loc);
            ast_free(r);
            return e;
        }
    default:
        break;
    }
    if (!lit_numeric(s, r)) {                  /* S17 */
        ast_free(l);
        ast_free(r);
        return mk_noop(loc);
    }
    if (!lit_equals(s, r, 1.0)) {
        if (op == OP_DIV) {                    /* S6: x / L -> (1/L) * x */
            Vec *inv = vec_inverse(r->value);
            Column *c = col_unary(s, r, MAP_INV);
            ast_free(r);
            return mk_bin(AST_BINOP, OP_MUL, tlit(s, inv, c, loc), l, loc);
        }
        return NULL;
    }
    ast_free(r);
    if (op == OP_FLOORDIV || op == OP_MOD) {   /* S16 */
        Str *name = str_from(op == OP_FLOORDIV ? "floor" : "fract");
        const Vec *fn = simp_builtin(s, name);
        str_release(name);
        AstNode *call = ast_new(AST_CALL, loc);
        call->a = mk_lit(vec_retain((Vec *)fn), loc);
        ast_push(call, l);
        call->count = 1;
        return call;
    }
    return mk_un(AST_POS, l, loc);             /* S5: x/1, x**1 */
}

/* Rules on the shapes of the operands (S13-S15), or NULL. */
static AstNode *additional_rules(int op, AstNode *l, AstNode *r, Loc loc)
{
    if (l->kind == AST_POS) {                   /* S13 */
        AstNode *e = mk_bin(AST_BINOP, op, l->a, r, loc);
        l->a = NULL;
        ast_free(l);
        return e;
    }
    if (r->kind == AST_POS) {
        AstNode *e = mk_bin(AST_BINOP, op, l, r->a, loc);
        r->a = NULL;
        ast_free(r);
        return e;
    }
    if (op == OP_ADD) {
        if (!is_binop(r, OP_MUL) && is_binop(l, OP_MUL))   /* S15 */
            return mk_bin(AST_BINOP, OP_ADD, r, l, loc);
        if (r->kind == AST_NEG) {                           /* S14 */
            AstNode *e = mk_bin(AST_BINOP, OP_SUB, l, r->a, loc);
            r->a = NULL;
            ast_free(r);
            return e;
        }
        if (l->kind == AST_NEG) {
            AstNode *e = mk_bin(AST_BINOP, OP_SUB, r, l->a, loc);
            l->a = NULL;
            ast_free(l);
            return e;
        }
    } else if (op == OP_SUB && r->kind == AST_NEG) {
        AstNode *e = mk_bin(AST_BINOP, OP_ADD, l, r->a, loc);
        r->a = NULL;
        ast_free(r);
        return e;
    }
    return NULL;
}

/* [n] members' numbers of [cl] OP [cr] into [out], each operand a
 * numeric column or, when NULL, the number [xl] or [xr] of every member:
 * arith_into's operation on two numbers for the four it writes out, then
 * num_arith's (value.c), with the loop inside the switch. */
static void col_num_arith(int op, const Column *cl, double xl, const Column *cr, double xr, uint32_t n,
                          double *out)
{
    const double *a = cl ? cl->num : &xl, *b = cr ? cr->num : &xr;
    size_t sa = cl != NULL, sb = cr != NULL;
    switch (op) {
    case OP_ADD: for (uint32_t m = 0; m < n; m++) out[m] = a[m * sa] + b[m * sb]; break;
    case OP_SUB: for (uint32_t m = 0; m < n; m++) out[m] = a[m * sa] - b[m * sb]; break;
    case OP_MUL: for (uint32_t m = 0; m < n; m++) out[m] = a[m * sa] * b[m * sb]; break;
    case OP_DIV: for (uint32_t m = 0; m < n; m++) out[m] = a[m * sa] / b[m * sb]; break;
    default: for (uint32_t m = 0; m < n; m++) out[m] = num_arith((ArithOp)op, a[m * sa], b[m * sb]);
    }
}

/* Where literal [n]'s numbers are, when they are numbers of a length
 * every member shares: member m's [len] numbers start at x + m*stride (a
 * numeric column's: stride 1, a flat column's: its width, the literal's
 * own numeric value: 0); false for other columns and values. */
static bool nums_of(const AstNode *n, const double **x, size_t *stride, uint32_t *len)
{
    if (has_col(n)) {
        const Column *c = n->aux;
        if (c->num) {
            *x = c->num;
            *stride = *len = 1;
        } else if (c->flat) {
            *x = c->flat;
            *stride = *len = c->w;
        } else {
            return false;
        }
        return true;
    }
    if (!vec_is_num(n->value) || !n->value->len) return false;
    *x = vec_cnums(n->value);
    *stride = 0;
    *len = n->value->len;
    return true;
}

/* In a template pass, the flat column of literals [l] OP [r] when one
 * of them is a flat column and the other numbers (nums_of): vec_arith's
 * numbers, broadcast as it broadcasts, each the operation arith_into
 * performs on two numbers (num_arith's); NULL otherwise, or when the
 * budget refuses the column. */
static Column *col_arith_flat(Simp *s, int op, const AstNode *l, const AstNode *r)
{
    const double *xa, *xb;
    size_t sa, sb;
    uint32_t na, nb;
    bool flat = (has_col(l) && ((const Column *)l->aux)->flat) || (has_col(r) && ((const Column *)r->aux)->flat);
    if (!flat || !nums_of(l, &xa, &sa, &na) || !nums_of(r, &xb, &sb, &nb)) return NULL;
    uint32_t w = na > nb ? na : nb;
    Column *c = col_new_flat(s->tg, w);
    if (!c) return NULL;
    double *d = c->flat;
    for (uint32_t m = 0; m < s->tg; m++, xa += sa, xb += sb, d += w) {
        switch (op) {   /* arith_into's four, then num_arith */
        case OP_ADD: for (uint32_t i = 0; i < w; i++) d[i] = xa[i % na] + xb[i % nb]; break;
        case OP_SUB: for (uint32_t i = 0; i < w; i++) d[i] = xa[i % na] - xb[i % nb]; break;
        case OP_MUL: for (uint32_t i = 0; i < w; i++) d[i] = xa[i % na] * xb[i % nb]; break;
        case OP_DIV: for (uint32_t i = 0; i < w; i++) d[i] = xa[i % na] / xb[i % nb]; break;
        default:
            for (uint32_t i = 0; i < w; i++) d[i] = num_arith((ArithOp)op, xa[i % na], xb[i % nb]);
        }
    }
    return c;
}

/* AST_BINOP with simplified operands [l] and [r] (consumed). */
static AstNode *binop_rules(Simp *s, int op, AstNode *l, AstNode *r, Loc loc)
{
    if (is_lit(l) && is_lit(r)) {               /* S1 (unfused) */
        Vec *v = vec_arith((ArithOp)op, l->value, r->value);
        Column *c = NULL;
        const Column *cl, *cr;
        double xl = 0, xr = 0;
        if (s->tg && (has_col(l) || has_col(r))) {
            if (num_operand(l, &cl, &xl) && num_operand(r, &cr, &xr)) {
                /* one number each in every member: vec_arith's number */
                c = col_new_num(s->tg);
                col_num_arith(op, cl, xl, cr, xr, s->tg, c->num);
            } else if (!(c = col_arith_flat(s, op, l, r))) {
                c = col_new(s->tg);
                for (uint32_t m = 0; m < s->tg; m++) c->v[m] = vec_arith((ArithOp)op, tval(l, m), tval(r, m));
            }
        }
        ast_free(l);
        ast_free(r);
        return tlit(s, v, c, loc);
    }
    AstNode *e = NULL;
    if (is_lit(l)) e = constant_left(s, op, l, r, loc);
    else if (is_lit(r)) e = constant_right(s, op, l, r, loc);
    if (!e) e = additional_rules(op, l, r, loc);
    if (e) return resimp(s, e);
    return mk_bin(AST_BINOP, op, l, r, loc);
}

static AstNode *simp_binop(Simp *s, const AstNode *n)
{
    AstNode *l = simp(s, n->a);
    AstNode *r = simp(s, n->b);
    return binop_rules(s, n->op, l, r, n->loc);
}

/* AST_NEG (S11, S12). */
static AstNode *simp_neg(Simp *s, const AstNode *n)
{
    AstNode *e = simp(s, n->a);
    Loc loc = n->loc;
    if (is_lit(e)) {
        Vec *v = vec_neg(e->value);
        Column *c = col_unary(s, e, MAP_NEG);
        ast_free(e);
        return tlit(s, v, c, loc);
    }
    if (e->kind == AST_NEG) {                   /* -(-y) -> +y */
        AstNode *p = mk_un(AST_POS, e->a, loc);
        e->a = NULL;
        ast_free(e);
        return resimp(s, p);
    }
    if (is_binop(e, OP_MUL) || is_binop(e, OP_DIV)) {   /* S11 */
        if (is_lit(e->a)) {
            e->a = mk_un(AST_NEG, e->a, loc);
            return resimp(s, e);
        }
        if (is_lit(e->b)) {
            e->b = mk_un(AST_NEG, e->b, loc);
            return resimp(s, e);
        }
    } else if (is_binop(e, OP_ADD)) {            /* S12 */
        if (is_lit(e->a) || is_lit(e->b)) {
            e->a = mk_un(AST_NEG, e->a, loc);
            e->b = mk_un(AST_NEG, e->b, loc);
            return resimp(s, e);
        }
    } else if (is_binop(e, OP_SUB)) {
        if (is_lit(e->a) || is_lit(e->b)) {
            e->a = mk_un(AST_NEG, e->a, loc);
            e->op = OP_ADD;
            return resimp(s, e);
        }
    }
    return mk_un(AST_NEG, e, loc);
}

/* AST_POS (S13). */
static AstNode *simp_pos(Simp *s, const AstNode *n)
{
    AstNode *e = simp(s, n->a);
    if (is_lit(e)) {
        Vec *v = vec_pos(e->value);
        Column *c = col_unary(s, e, MAP_POS);
        Loc loc = n->loc;
        ast_free(e);
        return tlit(s, v, c, loc);
    }
    if (e->kind == AST_NEG || e->kind == AST_POS || is_maths(e)) return resimp(s, e);
    return mk_un(AST_POS, e, n->loc);
}

/* AST_COMPARE: folded when both sides are literal; `null in y` is true (S18). */
static AstNode *simp_compare(Simp *s, const AstNode *n)
{
    AstNode *l = simp(s, n->a), *r = simp(s, n->b);
    AstNode *e = mk_bin(AST_COMPARE, n->op, l, r, n->loc);
    if (is_lit(l) && is_lit(r)) {
        AstNode *v = fold_lit(s, e, n->loc);
        ast_free(e);
        return v;
    }
    if (n->op == CMP_IN && is_lit(l) && tdecide(s, l, TD_LEN, 0) == 0) {
        ast_free(e);
        return mk_lit(vec_num1(1.0), n->loc);
    }
    return e;
}

/* AST_AND / AST_OR: a literal left side decides. */
static AstNode *simp_andor(Simp *s, const AstNode *n)
{
    AstNode *l = simp(s, n->a);
    if (is_lit(l)) {
        bool t = tdecide(s, l, TD_TRUTHY, 0);
        if (n->kind == AST_AND ? t : !t) {
            ast_free(l);
            return simp(s, n->b);
        }
        return l;
    }
    return mk_bin((AstKind)n->kind, 0, l, simp(s, n->b), n->loc);
}

static AstNode *simp_xor(Simp *s, const AstNode *n)
{
    AstNode *l = simp(s, n->a), *r = simp(s, n->b);
    if (is_lit(l) && !tdecide(s, l, TD_TRUTHY, 0)) {
        ast_free(l);
        return r;
    }
    if (is_lit(r) && !tdecide(s, r, TD_TRUTHY, 0)) {
        ast_free(r);
        return l;
    }
    if (is_lit(l) && is_lit(r)) {
        ast_free(l);
        ast_free(r);
        return mk_lit(vec_num1(0.0), n->loc);
    }
    return mk_bin(AST_XOR, 0, l, r, n->loc);
}

/* In a template pass, the column of stream column [ca] (a stream a
 * member: `normal(:v;i)`) indexed by the literal [index] (`[..2]`):
 * vec_index's numbers of each member's stream, one (a numeric column) or
 * more (a flat column); NULL when [index] is no numbers or the budget
 * refuses the column (the caller indexes member by member). */
static Column *col_stream_index(Simp *s, const Column *ca, const Vec *index)
{
    if (!vec_is_num(index) || !index->len) return NULL;
    uint32_t ni = index->len;
    Column *c = ni == 1 ? col_new_num(s->tg) : col_new_flat(s->tg, ni);
    if (!c) return NULL;
    double *out = ni == 1 ? c->num : c->flat;
    for (uint32_t m = 0; m < s->tg; m++)
        stream_index_into((StreamKind)ca->stream, ca->key[m], vec_cnums(index), ni, out + (size_t)m * ni);
    return c;
}

/* Any node whose listed children all become literal is folded with the
 * evaluator: AST_NOT, AST_RANGE, AST_INDEX, AST_TAG. */
static AstNode *simp_generic(Simp *s, const AstNode *n)
{
    AstNode *e = ast_new((AstKind)n->kind, n->loc);
    e->op = n->op;
    for (uint32_t i = 0; i < n->nnames; i++) ast_push_name(e, str_retain(n->names[i]));
    e->a = n->a ? simp(s, n->a) : NULL;
    e->b = n->b ? simp(s, n->b) : NULL;
    e->c = n->c ? simp(s, n->c) : NULL;
    bool all = (!e->a || is_lit(e->a)) && (!e->b || is_lit(e->b)) && (!e->c || is_lit(e->c));
    if (n->kind == AST_INDEX && is_lit(e->b)) e->b->op = tdecide(s, e->b, TD_SCALAR, 0) ? 1 : 0;
    if (!all) return e;
    bool cols = s->tg && (has_col(e->a) || has_col(e->b) || has_col(e->c));
    if (n->kind == AST_RANGE) {
        bool too_long = false;
        Vec *v = vec_range(e->a ? e->a->value : NULL, e->b->value, e->c ? e->c->value : NULL,
                           SIMP_MAX_RANGE, &too_long);
        Column *c = NULL;
        if (cols) {
            c = col_new(s->tg);
            for (uint32_t m = 0; m < s->tg; m++) {
                bool tl = false;
                c->v[m] = vec_range(e->a ? tval(e->a, m) : NULL, tval(e->b, m), e->c ? tval(e->c, m) : NULL,
                                    SIMP_MAX_RANGE, &tl);
                if (tl != too_long) s->tabort = true;   /* some members' ranges stay ranges */
            }
        }
        if (too_long) {
            vec_release(v);
            col_release(c);
            return e;
        }
        ast_free(e);
        return tlit(s, v, c, n->loc);
    }
    if (n->kind == AST_INDEX) {
        Vec *v = vec_index(e->a->value, e->b->value, false);
        Column *c = NULL;
        const Column *ci = has_col(e->b) ? e->b->aux : NULL;
        double x;
        const Column *ca = has_col(e->a) ? e->a->aux : NULL;
        if (cols && !has_col(e->a) && ci && ci->num && vec_index_num1(e->a->value, ci->num[0], false, &x)) {
            /* a stream or numbers indexed by one number per member */
            c = col_new_num(s->tg);
            if (vec_is_stream(e->a->value))
                stream_index_each((StreamKind)e->a->value->stream, e->a->value->key, ci->num, s->tg, c->num);
            else
                for (uint32_t m = 0; m < s->tg; m++) vec_index_num1(e->a->value, ci->num[m], false, &c->num[m]);
        } else if (cols) {
            if (ca && ca->key && !ci) c = col_stream_index(s, ca, e->b->value);
            if (!c) {
                c = col_new(s->tg);
                for (uint32_t m = 0; m < s->tg; m++) c->v[m] = vec_index(tval(e->a, m), tval(e->b, m), false);
            }
        }
        ast_free(e);
        return tlit(s, v, c, n->loc);
    }
    AstNode *r = fold_lit(s, e, n->loc);
    ast_free(e);
    return r;
}

/* ====================================================================
 * Node expressions
 * ==================================================================== */

/* Member [m]'s value of literal [n], a new reference (col_make: the
 * node's attribute is its only holder, so the column keeps no vector a
 * member for it). */
static Vec *member_value(const AstNode *n, uint32_t m)
{
    return has_col(n) ? col_make(n->aux, m) : vec_retain(n->value);
}

/* In a template pass, the column of attributes [e] (AST_ATTRIBUTES of
 * literal bindings) set on a literal bare node (`!particle`, no tags,
 * attributes or children) with no column: each member's node built as
 * eval_attributes builds it from such a node (a new node with room for
 * the attributes, each set in turn), from the members' values without
 * a call of the evaluator; NULL for other attribute folds. */
static Column *col_node_attrs(Simp *s, const AstNode *e)
{
    const Vec *v = e->a->value;
    if (!s->tg || has_col(e->a) || !v || v->kind != VEC_OBJ || v->len != 1 ||
        vec_celems(v)[0].kind != EL_NODE)
        return NULL;
    const Node *o = vec_celems(v)[0].node;
    if (o->ntags || o->nattrs || o->nchildren) return NULL;
    bool cols = false, distinct = true;
    for (uint32_t k = 0; k < e->nkids; k++) {
        cols = cols || has_col(e->kids[k]->a);
        for (uint32_t j = 0; j < k; j++) distinct = distinct && !str_eq(e->kids[j]->names[0], e->kids[k]->names[0]);
    }
    if (!cols) return NULL;
    Column *c = col_new_nodes(s->tg);
    for (uint32_t m = 0; m < s->tg && !s->ev.interrupted; m++) {
        if (s->ev.interrupt && *s->ev.interrupt) s->ev.interrupted = true;   /* SIGINT: the load gives up */
        Node *nn = node_new_sized(o->kind, e->nkids);
        for (uint32_t k = 0; k < e->nkids; k++) {
            /* names bound once each: node_set_attr's search would find none */
            if (distinct) node_add_new_attr(nn, e->kids[k]->names[0], member_value(e->kids[k]->a, m));
            else node_set_attr(nn, e->kids[k]->names[0], member_value(e->kids[k]->a, m));
        }
        c->node[m] = nn;
    }
    return c;
}

/* fold_lit of attributes [e] (AST_ATTRIBUTES, every operand literal). */
static AstNode *fold_attrs(Simp *s, AstNode *e, Loc loc)
{
    Column *c = col_node_attrs(s, e);
    if (!c) c = tcol_eval(s, e, fold_fn);
    return tlit(s, fold(s, e), c, loc);
}

/* AST_ATTRIBUTES: nested attribute groups are flattened; literal values are
 * set on a literal node from the innermost binding outwards. */
static AstNode *simp_attributes(Simp *s, const AstNode *n)
{
    /* bindings outermost-last-first, as tree.pyx collects them */
    AstNode *out = ast_new(AST_ATTRIBUTES, n->loc);
    const AstNode *node = n;
    uint32_t total = 0;
    for (const AstNode *t = n; t->kind == AST_ATTRIBUTES; t = t->a) total += t->nkids;
    AstNode **rev = malloc((total ? total : 1) * sizeof *rev);
    if (!rev) mem_oom();
    uint32_t k = 0;
    while (node->kind == AST_ATTRIBUTES) {
        for (uint32_t i = node->nkids; i-- > 0;) {
            const AstNode *b = node->kids[i];
            AstNode *sb = ast_new(AST_BINDING, b->loc);
            ast_push_name(sb, str_retain(b->names[0]));
            sb->a = simp(s, b->a);
            rev[k++] = sb;
        }
        node = node->a;
    }
    AstNode *base = simp(s, node);
    if (is_lit(base) && !tdecide(s, base, TD_OBJ, 0)) {
        for (uint32_t i = 0; i < k; i++) ast_free(rev[i]);
        free(rev);
        ast_free(out);
        return base;
    }
    if (is_lit(base) && k && is_lit(rev[k - 1]->a)) {
        /* set the literal bindings, innermost first, on copies of the nodes */
        AstNode *e = ast_new(AST_ATTRIBUTES, n->loc);
        e->a = base;
        while (k && is_lit(rev[k - 1]->a)) ast_push(e, rev[--k]);
        base = fold_attrs(s, e, n->loc);
        ast_free(e);
    }
    out->a = base;
    for (uint32_t i = k; i-- > 0;) ast_push(out, rev[i]);
    free(rev);
    if (!out->nkids) {
        AstNode *b = out->a;
        out->a = NULL;
        ast_free(out);
        return b;
    }
    return out;
}

/* AST_APPEND: children appended to literal nodes at load time. */
static AstNode *simp_append(Simp *s, const AstNode *n)
{
    AstNode *node = simp(s, n->a), *kids = simp(s, n->b);
    if ((is_lit(node) && !tdecide(s, node, TD_OBJ, 0)) || (is_lit(kids) && !tdecide(s, kids, TD_OBJ, 0))) {
        ast_free(kids);
        return node;
    }
    AstNode *e = mk_bin(AST_APPEND, 0, node, kids, n->loc);
    if (is_lit(node)) {
        if (is_lit(kids)) {
            AstNode *v = fold_lit(s, e, n->loc);
            ast_free(e);
            return v;
        }
        if (kids->kind == AST_SEQUENCE && kids->nkids && is_lit(kids->kids[0])) {
            /* (node << first) << rest */
            AstNode *first = kids->kids[0];
            memmove(kids->kids, kids->kids + 1, (kids->nkids - 1) * sizeof *kids->kids);
            kids->nkids--;
            e->a = mk_bin(AST_APPEND, 0, node, first, n->loc);
            return resimp(s, e);
        }
    } else if (node->kind == AST_ATTRIBUTES && is_lit(node->a)) {
        /* (literal attrs...) << kids -> (literal << kids) attrs... */
        e->a = node->a;
        node->a = e;
        return resimp(s, node);
    }
    return e;
}

/* ====================================================================
 * Sequences and conditionals
 * ==================================================================== */

/* Member [m]'s numbers of the [n] literals [items], each a numeric
 * column or numbers, one after another into [d]: vec_compose's numbers
 * of their values. */
static void run_numbers(AstNode *const *items, uint32_t n, uint32_t m, double *d)
{
    for (uint32_t k = 0; k < n; k++) {
        const AstNode *it = items[k];
        if (has_col(it)) {
            *d++ = ((const Column *)it->aux)->num[m];
        } else {
            memcpy(d, vec_cnums(it->value), it->value->len * sizeof *d);
            d += it->value->len;
        }
    }
}

/* tree.pyx sequence_pack: flatten nested sequences, compose runs of
 * literals, drop null literals. Consumes the [n] items of [items]; returns
 * the packed count (items reused in place). */
static uint32_t sequence_pack(Simp *s, AstNode ***itemsp, uint32_t n, uint32_t *cap)
{
    AstNode **items = *itemsp;
    /* flatten first */
    for (uint32_t i = 0; i < n; i++) {
        AstNode *e = items[i];
        if (e->kind != AST_SEQUENCE) continue;
        uint32_t m = e->nkids;
        if (n - 1 + m > *cap) {
            *cap = (n + m) * 2;
            items = realloc(items, *cap * sizeof *items);
            if (!items) mem_oom();
        }
        memmove(items + i + m, items + i + 1, (n - i - 1) * sizeof *items);
        for (uint32_t j = 0; j < m; j++) items[i + j] = e->kids[j];
        e->nkids = 0;
        ast_free(e);
        n = n - 1 + m;
        i--;   /* the spliced items may be sequences too */
    }
    uint32_t out = 0;
    for (uint32_t i = 0; i < n;) {
        AstNode *e = items[i];
        if (is_lit(e)) {
            uint32_t j = i + 1;
            while (j < n && is_lit(items[j])) j++;
            uint64_t total = 0;
            bool cols = false;
            for (uint32_t k = i; k < j; k++) {
                total += vec_len(items[k]->value);
                cols = cols || (s->tg && has_col(items[k]));
            }
            /* a run of numbers: numeric columns and numeric literals */
            bool nums = cols;
            for (uint32_t k = i; k < j && nums; k++) {
                const AstNode *it = items[k];
                nums = has_col(it) ? ((const Column *)it->aux)->num != NULL
                                   : it->value && it->value->kind == VEC_NUM && it->value->len;
            }
            if (cols && j - i > 1 && !nums) {   /* members must agree on the limit below */
                for (uint32_t m = 0; m < s->tg; m++) {
                    uint64_t tm = 0;
                    for (uint32_t k = i; k < j; k++) tm += vec_len(tval(items[k], m));
                    if ((tm > SIMP_MAX_RANGE) != (total > SIMP_MAX_RANGE)) s->tabort = true;
                }
            }
            /* past the evaluator's composition limit (eval.c MAX_COMPOSE_LEN,
             * 2^26) the run is left for the evaluator, which reports it */
            if (j - i > 1 && total > SIMP_MAX_RANGE) {
                for (uint32_t k = i; k < j; k++) {
                    if (!tdecide(s, items[k], TD_NULL, 0)) items[out++] = items[k];
                    else ast_free(items[k]);
                }
                i = j;
                continue;
            }
            if (j - i > 1) {
                Vec **parts = malloc((j - i) * sizeof *parts);
                if (!parts) mem_oom();
                for (uint32_t k = i; k < j; k++) parts[k - i] = items[k]->value;
                Vec *v = vec_compose(parts, j - i);
                Column *c = NULL;
                /* a run of numbers is [total] >= 2 numbers in every
                 * member (one per numeric column): vec_compose's vector
                 * of them (asking the budget as it asks), kept as the
                 * numbers (a flat column) while the budget has room */
                if (cols && nums && mem_fits(sizeof(Vec) + total * sizeof(double)) &&
                    (c = col_new_flat(s->tg, (uint32_t)total))) {
                    for (uint32_t m = 0; m < s->tg; m++) run_numbers(items + i, j - i, m, c->flat + (size_t)m * total);
                } else if (cols) {
                    c = col_new(s->tg);
                    for (uint32_t m = 0; m < s->tg; m++) {
                        /* too long a member for a flat column, or past the
                         * budget's room for one: a vector each, the budget
                         * asked for each as vec_compose asks */
                        if (nums && mem_fits(sizeof(Vec) + total * sizeof(double))) {
                            c->v[m] = vec_new_num((uint32_t)total);
                            run_numbers(items + i, j - i, m, vec_nums(c->v[m]));
                            continue;
                        }
                        for (uint32_t k = i; k < j; k++) parts[k - i] = tval(items[k], m);
                        c->v[m] = vec_compose(parts, j - i);
                    }
                }
                free(parts);
                Loc loc = e->loc;
                for (uint32_t k = i; k < j; k++) ast_free(items[k]);
                e = tlit(s, v, c, loc);
            }
            i = j;
            if (tdecide(s, e, TD_NULL, 0)) {
                ast_free(e);
                continue;
            }
        } else {
            i++;
        }
        items[out++] = e;
    }
    *itemsp = items;
    return out;
}

/* Build a node from packed items: null, the single item, or a sequence. */
AstNode *simp_sequence_of(Simp *s, AstNode **items, uint32_t n, uint32_t cap, Loc loc);
AstNode *simp_sequence_of(Simp *s, AstNode **items, uint32_t n, uint32_t cap, Loc loc)
{
    n = sequence_pack(s, &items, n, &cap);
    AstNode *r;
    if (n == 0) r = mk_noop(loc);
    else if (n == 1) r = items[0];
    else {
        r = ast_new(AST_SEQUENCE, loc);
        for (uint32_t i = 0; i < n; i++) ast_push(r, items[i]);
    }
    free(items);
    return r;
}

static AstNode *simp_sequence(Simp *s, const AstNode *n)
{
    uint32_t cap = n->nkids ? n->nkids : 1;
    AstNode **items = malloc(cap * sizeof *items);
    if (!items) mem_oom();
    for (uint32_t i = 0; i < n->nkids; i++) items[i] = simp(s, n->kids[i]);
    return simp_sequence_of(s, items, n->nkids, cap, n->loc);
}

/* AST_IFELSE: literal conditions select or drop their branches. */
static AstNode *simp_ifelse(Simp *s, const AstNode *n)
{
    AstNode *r = ast_new(AST_IFELSE, n->loc);
    for (uint32_t i = 0; i + 1 < n->nkids; i += 2) {
        AstNode *cond = simp(s, n->kids[i]);
        if (is_lit(cond)) {
            bool t = tdecide(s, cond, TD_TRUTHY, 0);
            ast_free(cond);
            if (t) {
                AstNode *then = simp(s, n->kids[i + 1]);
                if (!r->nkids) {
                    ast_free(r);
                    return then;
                }
                r->a = then;
                return r;
            }
            continue;
        }
        ast_push(r, cond);
        ast_push(r, simp(s, n->kids[i + 1]));
    }
    AstNode *els = n->a ? simp(s, n->a) : NULL;
    if (r->nkids) {
        r->a = els;
        return r;
    }
    ast_free(r);
    return els ? els : mk_noop(n->loc);
}

/* ====================================================================
 * Dispatch
 * ==================================================================== */

static AstNode *simp_kind(Simp *s, const AstNode *n);

AstNode *simp(Simp *s, const AstNode *n)
{
    if (!n) return NULL;
    if (s->unwinding || s->too_deep || s->tabort || s->tkey) return mk_noop(n->loc);
    if (s->ev.interrupted || (s->ev.interrupt && *s->ev.interrupt)) {
        s->ev.interrupted = true;   /* SIGINT at load: simplify_program gives up */
        return mk_noop(n->loc);
    }
    if (s->depth >= SIMP_MAX_DEPTH) {   /* too deep: the file is run as written */
        s->too_deep = true;
        return mk_noop(n->loc);
    }
    s->depth++;
    AstNode *r = simp_kind(s, n);
    s->depth--;
    return r;
}

static AstNode *simp_kind(Simp *s, const AstNode *n)
{
    switch ((AstKind)n->kind) {
    case AST_LITERAL: return ast_copy(n);
    case AST_NAME: return simp_name(s, n);
    case AST_LOOKUP: return mk_un(AST_LOOKUP, simp(s, n->a), n->loc);
    case AST_BINOP: return simp_binop(s, n);
    case AST_NEG: return simp_neg(s, n);
    case AST_POS: return simp_pos(s, n);
    case AST_AND:
    case AST_OR: return simp_andor(s, n);
    case AST_XOR: return simp_xor(s, n);
    case AST_COMPARE: return simp_compare(s, n);
    case AST_NOT:
    case AST_RANGE:
    case AST_INDEX:
    case AST_TAG: return simp_generic(s, n);
    case AST_CALL: return simp_call(s, n);
    case AST_FUNCTION: return simp_function(s, n);
    case AST_LET: return simp_let(s, n);
    case AST_FOR: return simp_for(s, n);
    case AST_IFELSE: return simp_ifelse(s, n);
    case AST_ATTRIBUTES: return simp_attributes(s, n);
    case AST_APPEND: return simp_append(s, n);
    case AST_SEQUENCE: return simp_sequence(s, n);
    case AST_IMPORT: return simp_import(s, n);
    case AST_INCLUDE: return simp_include(s, n);
    case AST_EXPORT: return simp_export(s, n);
    case AST_TOP: {
        AstNode *t = ast_new(AST_TOP, n->loc);
        for (uint32_t i = 0; i < n->nkids; i++) ast_push(t, ast_copy(n->kids[i]));
        t->c = ast_copy(n->c);
        t->a = simp(s, n->a);
        return t;
    }
    case AST_BINDING:
    case AST__COUNT:
        break;
    }
    return ast_copy(n);
}

void simp_init(Simp *s, SymTab *st, Buf *warnings, const char *dir, const char *path,
               uint32_t next_file)
{
    *s = (Simp){.symtab = st, .warnings = warnings, .next_file = next_file, .owns_warned = true};
    s->warned = calloc(1, sizeof *s->warned);
    if (!s->warned) mem_oom();
    s->ev = (Eval){.symtab = st, .errors = &s->errors, .debug = NULL};
    s->dir = strdup(dir ? dir : ".");
    s->path = path ? strdup(path) : NULL;
    if (!s->dir || (path && !s->path)) mem_oom();
}

void simp_fini(Simp *s)
{
    scope_restore(s, 0);
    free(s->names);
    free(s->heads);
    free(s->renames);
    for (uint32_t i = 0; i < s->ndeps; i++) free(s->deps[i]);
    free(s->deps);
    for (uint32_t i = 0; i < s->nbuiltins; i++) {
        vec_release(s->builtins[i]);
        str_release(s->builtin_names[i]);
    }
    free(s->builtins);
    free(s->builtin_names);
    for (uint32_t i = 0; i < s->nconsts; i++) {
        vec_release(s->consts[i]);
        str_release(s->const_names[i]);
    }
    free(s->consts);
    free(s->const_names);
    for (uint32_t i = 0; i < s->nexports; i++) {
        str_release(s->exports[i].name);
        vec_release(s->exports[i].value);
        ast_free(s->exports[i].fn);
    }
    free(s->exports);
    msgset_clear(&s->errors);
    if (s->owns_warned && s->warned) {
        free(s->warned->hash);
        free(s->warned->start);
        free(s->warned->len);
        free(s->warned);
    }
    s->warned = NULL;
    free(s->dir);
    free(s->path);
}

void simplify_number_stables(AstNode *n, uint32_t *last)
{
    if (!n || !last) return;
    if (n->kind == AST_LET && n->op == 1 && n->count == 0) n->count = ++*last;
    simplify_number_stables(n->a, last);
    simplify_number_stables(n->b, last);
    simplify_number_stables(n->c, last);
    for (uint32_t i = 0; i < n->nkids; i++) simplify_number_stables(n->kids[i], last);
}

AstNode *simplify_program(AstNode *top, const SimplifyEnv *env, Buf *warnings)
{
    Simp s;
    simp_init(&s, env->symtab, warnings, env->dir, NULL, env->first_file);
    s.stable_ids = env->stable_ids;
    s.stables = env->stables;
    s.is_module = env->is_module;
    s.no_templates = env->no_templates;
    s.check_templates = env->check_templates;
    s.files = env->files;
    s.ev.interrupt = env->interrupt;
    simplify_number_stables(top, s.stable_ids);
    for (uint32_t i = 0; i < env->nnames; i++) {
        const SimplifyName *nm = &env->names[i];
        scope_push(&s, (Str *)nm->name, nm->dynamic ? NB_DYNAMIC : NB_LITERAL, nm->value, NULL, NULL);
    }
    AstNode *r = simp(&s, top);
    if (s.ev.interrupted) {   /* the caller fails the load */
        ast_free(r);
        simp_fini(&s);
        return top;
    }
    if (s.too_deep) {
        ast_free(r);
        simp_warn(&s, "Program too deeply nested to simplify; running it as written");
        simp_fini(&s);
        return top;
    }
    ast_free(top);
    simp_fini(&s);
    return r;
}
