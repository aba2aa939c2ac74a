/* simplify_template.c: unrolled loops simplified once per group of
 * iterations, not once per iteration.
 *
 * Flitter's simplifier unrolls a loop over a literal source into one
 * simplified copy of the body per iteration (LANGUAGE.md §4.17), and the
 * copies of one loop differ mostly in their literal values: in
 * `for i in ..N` the copy for i=7 folds `i*0.07` to 0.49 where the copy
 * for i=8 folds it to 0.56, and is otherwise the same tree. A template
 * pass simplifies the body once for a group of iterations (its members)
 * in lockstep: the simplifier runs as for the first member (the
 * representative; every `->value` it reads is that member's), and every
 * literal it makes from the loop variables carries a Column of all the
 * members' values, computed with the same operations (the column helpers
 * below, called where simplify.c and simplify_scope.c fold). Every test a
 * rule makes on a literal's value goes through tdecide(): when the
 * members' outcomes differ (i*0.07 is 0 only for i=0, where S2 turns
 * `time + 0` into `+time`), the pass is abandoned and its group split by
 * that outcome, each part simplified by a pass of its own. A pass that
 * completes has treated every member alike, so the member's copy is the
 * pass's tree with the member's values put in its literals (tinst): the
 * same tree, value for value, that simplifying the body for that member
 * alone makes. Copies come out in iteration order, so what follows
 * (sequence packing, the evaluator, the dumps) sees exactly what it saw.
 *
 * A group of one member (canvas10k's i=0, where `time + 0` folds) takes
 * no column pass: it is simplified with the member's own values, as one
 * copy at a time would simplify it (so a loop inside it may make templates
 * of its own), what a column pass must not share aborting it alike
 * (Simp.talone).
 *
 * Better still, a run of consecutive members of one group need not be
 * copied at all: loop_form() makes it one loop over the members' column
 * values, bound to hidden names where the template had its column
 * literals, which the evaluator runs as it ran the copies (a name bound to
 * a single item evaluates as that item's literal, except in the places
 * collect_cols() refuses). 10,000 copies of canvas10k's body become one
 * loop body and a vector of their values.
 *
 * What a pass cannot share makes the loop unroll one copy at a time, as
 * before, with nothing of the pass left behind: a warning (written once
 * per message, in iteration order), a nested loop whose unrolling limit
 * would fall between members, a range or composition limit reached by
 * some members only, a file read (an import left in an inlined function:
 * shareable() turns away bodies that hold includes, imports or exports),
 * or too many groups.
 * FLITTER_NOTEMPLATES=1 unrolls every loop one copy at a time (the
 * reference route); FLITTER_TEMPLATE_CHECK=1 also simplifies every copy
 * alone and aborts when the two differ (tests/cli/templates.sh runs the
 * golden, language and bench scripts so).
 *
 * Most columns hold one number per member (the loop variable of `..N`,
 * and what arithmetic, indexing by it and sequences of numbers make of
 * it). Such a column is numeric (Column.num): its members are doubles and
 * a member's vector is made only when something asks for it (col_get),
 * so folding `i*0.07` for 10,000 members is 10,000 multiplications, not
 * 10,000 vectors made, tested and freed. The helpers that compute
 * numeric columns (simplify.c: binop_rules, col_unary, the index and
 * sequence folds; here: tdecide, colset_add, loop_form) perform the
 * operations the vector route performs on one-element vectors
 * (num_arith, vec_index_num1 in value.c), so every member's value keeps
 * its bits.
 *
 * Three more kinds spare a vector a member the same way (col_get makes
 * one when something asks): a flat column holds w numbers a member (a
 * composition of numbers, `(:v;i)` or a position `x;y`, and arithmetic
 * or a literal index on it: sequence_pack, col_arith_flat and
 * col_stream_index in simplify.c); a stream column holds a stream's key
 * a member (`normal(:v;i)`: stream_col in simplify_scope.c); a node
 * column holds the node a member of a literal bare node's attributes
 * (`!particle id=i ...`: col_node_attrs in simplify.c), and a loop of
 * them moves its nodes into the loop's literal (lit_items). discs20k's
 * 20,000 particles load without one vector of their velocity's key,
 * stream, pair of draws and product, or of their node, made a member.
 */
#include "simplify_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mem.h"
#include "node.h"

/* {===== columns */

void col_aux_free(void *p) { col_release(p); }

Vec *tval(const AstNode *n, uint32_t m)
{
    if (has_col(n)) return col_get(n->aux, m);
    return n ? n->value : NULL;
}

Column *col_new(uint32_t n)
{
    /* the vectors follow the column in one block */
    Column *c = mem_calloc(1, sizeof *c + (size_t)n * sizeof *c->v);
    c->refs = 1;
    c->n = n;
    c->v = (Vec **)(void *)(c + 1);
    return c;
}

Column *col_new_num(uint32_t n)
{
    /* the numbers follow the column in one block, left for the caller to
     * fill; the vectors come with the first col_get */
    Column *c = mem_realloc(NULL, sizeof *c + (size_t)n * sizeof *c->num);
    *c = (Column){.refs = 1, .n = n, .num = (double *)(void *)(c + 1)};
    return c;
}

Column *col_new_flat(uint32_t n, uint32_t w)
{
    /* as col_new_num: the numbers follow the column, left to the caller;
     * charged, as the members' vectors they stand for would be (mem_room:
     * a refusal here is no failure, the caller has another route) */
    size_t bytes = (size_t)n * w * sizeof(double);
    if (w > FLAT_MAX || !mem_room(bytes)) return NULL;
    mem_charge(bytes);
    Column *c = mem_realloc(NULL, sizeof *c + bytes);
    *c = (Column){.refs = 1, .n = n, .flat = (double *)(void *)(c + 1), .w = w, .charged = bytes};
    return c;
}

Column *col_new_keys(uint32_t n, uint8_t kind)
{
    Column *c = mem_realloc(NULL, sizeof *c + (size_t)n * sizeof *c->key);
    *c = (Column){.refs = 1, .n = n, .key = (uint64_t *)(void *)(c + 1), .stream = kind};
    return c;
}

Column *col_new_nodes(uint32_t n)
{
    Column *c = mem_realloc(NULL, sizeof *c + (size_t)n * sizeof *c->node);
    *c = (Column){.refs = 1, .n = n, .node = (Node **)(void *)(c + 1)};
    memset(c->node, 0, (size_t)n * sizeof *c->node);   /* a member left NULL is null */
    return c;
}

Vec *col_make(const Column *c, uint32_t m)
{
    if (c->v && c->v[m]) return vec_retain(c->v[m]);
    if (c->num) return vec_num1(c->num[m]);
    if (c->flat) return vec_from_nums(c->flat + (size_t)m * c->w, c->w);
    if (c->key) return vec_stream((StreamKind)c->stream, c->key[m]);
    if (c->node) return c->node[m] ? vec_node_take(node_retain(c->node[m])) : NULL;
    return NULL;
}

Vec *col_get(Column *c, uint32_t m)
{
    if (col_plain(c)) return c->v[m];
    if (!c->v) c->v = mem_calloc(c->n, sizeof *c->v);
    if (!c->v[m]) c->v[m] = col_make(c, m);
    return c->v[m];
}

Vec **col_all(Column *c)
{
    if (!col_plain(c))
        for (uint32_t m = 0; m < c->n; m++) col_get(c, m);
    return c->v;
}

Column *col_retain(Column *c)
{
    if (c) c->refs++;
    return c;
}

void col_release(Column *c)
{
    if (!c || --c->refs) return;
    for (uint32_t m = 0; c->v && m < c->n; m++) vec_release(c->v[m]);
    for (uint32_t m = 0; c->node && m < c->n; m++) node_release(c->node[m]);
    if (!col_plain(c)) free(c->v);
    if (c->charged) mem_unreserve(c->charged);
    free(c);
}

void col_attach(AstNode *n, Column *c)
{
    if (!c) return;
    if (n->aux && n->aux_free) n->aux_free(n->aux);
    n->aux = c;
    n->aux_free = col_aux_free;
}

/* }===== */

/* {===== tests and folds in a pass */

static int64_t outcome(const Vec *v, int kind, double x)
{
    switch (kind) {
    case TD_NUMERIC: return vec_is_num(v);
    case TD_EQUALS: return vec_is_scalar(v) && vec_scalar(v) == x;
    case TD_TRUTHY: return vec_truthy(v);
    case TD_LEN: return (int64_t)vec_len(v);
    case TD_SCALAR: return vec_is_scalar(v);
    case TD_OBJ: return vec_is_obj(v);
    case TD_NULL: return v == NULL;
    default: return 0;
    }
}

/* outcome() of the one-element numeric vector of [y]. */
static int64_t num_outcome(double y, int kind, double x)
{
    switch (kind) {
    case TD_NUMERIC: return 1;
    case TD_EQUALS: return y == x;
    case TD_TRUTHY: return y != 0.0 || isnan(y);   /* vec_truthy */
    case TD_LEN: return 1;
    case TD_SCALAR: return 1;
    default: return 0;   /* TD_OBJ, TD_NULL */
    }
}

/* outcome(TD_TRUTHY) of the numeric vector of the [w] numbers [y]
 * (vec_truthy's test). */
static int64_t flat_truthy(const double *y, uint32_t w)
{
    for (uint32_t j = 0; j < w; j++)
        if (y[j] != 0.0 || isnan(y[j])) return 1;
    return 0;
}

/* Member [m]'s outcome of test [kind] on column [c] (a flat column's
 * members differ on truthiness only: tdecide asks it nothing else). */
static int64_t col_outcome(Column *c, uint32_t m, int kind, double x)
{
    if (c->num) return num_outcome(c->num[m], kind, x);
    if (c->flat && kind == TD_TRUTHY) return flat_truthy(c->flat + (size_t)m * c->w, c->w);
    return outcome(col_get(c, m), kind, x);
}

int64_t tdecide(Simp *s, const AstNode *n, int kind, double x)
{
    int64_t r = outcome(n->value, kind, x);
    if (!s->tg || s->tkey || !has_col(n)) return r;
    Column *c = n->aux;
    /* a numeric column's members agree on every test but these two, a
     * flat column's on every test but truthiness, and a stream column's
     * (one kind of stream) and a node column's (one node) on every test */
    if (c->num && kind != TD_EQUALS && kind != TD_TRUTHY) return r;
    if ((c->flat && kind != TD_TRUTHY) || c->key || c->node) return r;
    if (c->num) {   /* the two on plain numbers, in one pass (num_outcome's) */
        const double *y = c->num;
        uint32_t m = 0;
        if (kind == TD_EQUALS)
            while (m < c->n && (int64_t)(y[m] == x) == r) m++;
        else
            while (m < c->n && (int64_t)(y[m] != 0.0 || isnan(y[m])) == r) m++;
        if (m == c->n) return r;
    }
    for (uint32_t m = 0; m < c->n; m++) {
        if (col_outcome(c, m, kind, x) == r) continue;
        s->tkey = mem_realloc(NULL, (size_t)c->n * sizeof *s->tkey);
        for (uint32_t j = 0; j < c->n; j++) s->tkey[j] = col_outcome(c, j, kind, x);
        break;
    }
    return r;
}

AstNode *tlit(Simp *s, Vec *rep_take, Column *c, Loc loc)
{
    AstNode *n = mk_lit(rep_take, loc);
    if (!c) return n;
    if (!s->tg) {
        col_release(c);
        return n;
    }
    col_attach(n, c);
    tdecide(s, n, TD_SCALAR, 0);   /* mk_lit's IndexLiteral flag must hold for all */
    return n;
}

/* The literal children of [e] that tcol_eval swaps: a, b, c, the kids and
 * the values of binding kids. */
static uint32_t literal_children(AstNode *e, AstNode **out, uint32_t cap)
{
    uint32_t n = 0;
    AstNode *fixed[3] = {e->a, e->b, e->c};
    for (int i = 0; i < 3; i++)
        if (has_col(fixed[i]) && n < cap) out[n++] = fixed[i];
    for (uint32_t i = 0; i < e->nkids; i++) {
        AstNode *k = e->kids[i];
        if (k && k->kind == AST_BINDING) k = k->a;
        if (has_col(k) && n < cap) out[n++] = k;
    }
    return n;
}

Column *tcol_eval(Simp *s, AstNode *e, TEvalFn f)
{
    if (!s->tg) return NULL;
    AstNode *small[8], **kids = small;
    uint32_t cap = 3 + e->nkids;
    if (cap > 8) kids = mem_realloc(NULL, cap * sizeof *kids);
    uint32_t nk = literal_children(e, kids, cap);
    Column *c = NULL;
    if (nk) {
        c = col_new(s->tg);
        Vec *saved[8], **rep = saved;
        if (nk > 8) rep = mem_realloc(NULL, nk * sizeof *rep);
        for (uint32_t i = 0; i < nk; i++) rep[i] = kids[i]->value;
        for (uint32_t m = 0; m < s->tg; m++) {
            /* borrowed for the call: the column keeps its reference */
            for (uint32_t i = 0; i < nk; i++) kids[i]->value = col_get(kids[i]->aux, m);
            c->v[m] = f(s, e);
        }
        for (uint32_t i = 0; i < nk; i++) kids[i]->value = rep[i];
        if (rep != saved) free(rep);
    }
    if (kids != small) free(kids);
    return c;
}

/* }===== */

/* {===== the driver */

/* A copy of template [t] in which each column literal is what [leaf]
 * makes of it ([ctx] passed on); the rest as ast_copy copies it. */
typedef AstNode *(*LeafFn)(const AstNode *lit, const void *ctx);

static AstNode *copy_with(const AstNode *t, LeafFn leaf, const void *ctx)
{
    if (!t) return NULL;
    if (has_col(t)) return leaf(t, ctx);
    AstNode *c = ast_new((AstKind)t->kind, t->loc);
    c->op = t->op;
    c->count = t->count;
    c->a = copy_with(t->a, leaf, ctx);
    c->b = copy_with(t->b, leaf, ctx);
    c->c = copy_with(t->c, leaf, ctx);
    for (uint32_t i = 0; i < t->nkids; i++) ast_push(c, copy_with(t->kids[i], leaf, ctx));
    for (uint32_t i = 0; i < t->nnames; i++) ast_push_name(c, str_retain(t->names[i]));
    c->value = vec_retain(t->value);
    return c;
}

/* [t] itself made what copy_with(t, leaf, ctx) would make, when nothing
 * needs [t] after: each column literal replaced by leaf() and freed, every
 * other node kept (consumes [t]). The fields copy_with leaves out (the
 * resolver's scope, fast, slot and slots, an aux other than a column) are
 * never set while the simplifier runs, so keeping them is the same. */
static AstNode *move_with(AstNode *t, LeafFn leaf, const void *ctx)
{
    if (!t) return NULL;
    if (has_col(t)) {
        AstNode *r = leaf(t, ctx);
        ast_free(t);
        return r;
    }
    t->a = move_with(t->a, leaf, ctx);
    t->b = move_with(t->b, leaf, ctx);
    t->c = move_with(t->c, leaf, ctx);
    for (uint32_t i = 0; i < t->nkids; i++) t->kids[i] = move_with(t->kids[i], leaf, ctx);
    return t;
}

/* A column literal holding member *[ctx]'s value. */
static AstNode *member_leaf(const AstNode *lit, const void *ctx)
{
    AstNode *c = ast_literal(vec_retain(col_get(lit->aux, *(const uint32_t *)ctx)), lit->loc);
    c->op = lit->op;
    return c;
}

/* Member [m]'s copy of template [t]: its literals hold the member's values. */
static AstNode *tinst(const AstNode *t, uint32_t m) { return copy_with(t, member_leaf, &m); }

/* False when the body holds what a pass must not share. */
static bool shareable(const AstNode *n)
{
    if (!n) return true;
    if (n->kind == AST_INCLUDE || n->kind == AST_IMPORT || n->kind == AST_EXPORT) return false;
    if (!shareable(n->a) || !shareable(n->b) || !shareable(n->c)) return false;
    for (uint32_t i = 0; i < n->nkids; i++)
        if (!shareable(n->kids[i])) return false;
    return true;
}

typedef struct KeyPos {
    int64_t key;
    uint32_t pos;
} KeyPos;

static int keypos_cmp(const void *a, const void *b)
{
    const KeyPos *x = a, *y = b;
    if (x->key != y->key) return x->key < y->key ? -1 : 1;
    return x->pos < y->pos ? -1 : x->pos > y->pos;
}

typedef struct Range {
    uint32_t start, n;
} Range;

/* {===== the loop form */

/* A column of a template to bind: the hidden name it takes (columns
 * whose members hold equal values, bit for bit and without NaN, share
 * one). */
typedef struct ColName {
    Column *col;        /* one reference: the template may go first */
    uint64_t hash;      /* of its members' values */
    uint32_t name;
    bool dedup;         /* NaN-free: may share a name */
} ColName;

/* A column whose members are numeric vectors of one length (2 to
 * SPLIT_MAX: a state key `(:cell;i)`, a slice `i*3..(i+1)*3`), taken
 * apart by position: a position where every member holds the same bits is
 * a constant, the others columns of their own (numeric, one number a
 * member), each bound to a hidden name. In the loop body the literal
 * becomes the sequence of its positions, which composes to the same
 * vector. */
#define SPLIT_MAX 16

typedef struct SplitCol {
    Column *col;            /* the column taken apart (the template's; one reference) */
    uint32_t len;
    Column *pos[SPLIT_MAX]; /* a position's column (one reference), or NULL: constant */
} SplitCol;

/* The distinct Column objects of a template, and how many names they take. */
typedef struct ColSet {
    ColName *e;
    uint32_t n, cap, names;
    SplitCol *sp;           /* the columns taken apart */
    uint32_t nsp, capsp;
    /* two open-addressed indexes of e (entry + 1, 0 empty; nindex slots, a
     * power of two, at most half full): by the column's address, and by
     * the hash of its members' values (NaN-free entries only) */
    uint32_t *by_col, *by_hash;
    uint32_t nindex;
    Str **hidden;           /* each name's hidden name, made once (NULL: not yet) */
} ColSet;

static void colset_free(ColSet *cs)
{
    for (uint32_t i = 0; i < cs->names && cs->hidden; i++) str_release(cs->hidden[i]);
    free(cs->hidden);
    free(cs->by_col);
    free(cs->by_hash);
    for (uint32_t i = 0; i < cs->n; i++) col_release(cs->e[i].col);
    for (uint32_t i = 0; i < cs->nsp; i++) {
        col_release(cs->sp[i].col);
        for (uint32_t p = 0; p < cs->sp[i].len; p++) col_release(cs->sp[i].pos[p]);
    }
    free(cs->sp);
    free(cs->e);
}

static bool nan_free(const Vec *v)
{
    if (!vec_is_num(v)) return true;
    for (uint32_t i = 0; i < v->len; i++)
        if (vec_cnums(v)[i] != vec_cnums(v)[i]) return false;
    return true;
}

/* Whether members [m] of [a] and [b] are the same value (vec_key_equal). */
static bool col_key_equal(Column *a, Column *b, uint32_t m)
{
    if (a->num && b->num) return num_bits(a->num[m]) == num_bits(b->num[m]);
    return vec_key_equal(col_get(a, m), col_get(b, m));
}

static uint32_t ptr_slot(const void *p, uint32_t mask)
{
    uint64_t x = (uint64_t)(uintptr_t)p;
    return (uint32_t)((x * 0x9e3779b97f4a7c15u) >> 32) & mask;
}

/* Entry [k] of [cs] into both indexes (which have room). */
static void colset_index(ColSet *cs, uint32_t k)
{
    uint32_t mask = cs->nindex - 1, i = ptr_slot(cs->e[k].col, mask);
    while (cs->by_col[i]) i = (i + 1) & mask;
    cs->by_col[i] = k + 1;
    if (!cs->e[k].dedup) return;
    i = (uint32_t)(cs->e[k].hash >> 32) & mask;
    while (cs->by_hash[i]) i = (i + 1) & mask;
    cs->by_hash[i] = k + 1;
}

static void colset_add(ColSet *cs, Column *c)
{
    uint64_t h = 1469598103934665603u;
    bool dedup = true;
    if (c->num) {
        /* vec_hash of a one-number vector, without making it */
        for (uint32_t m = 0; m < c->n; m++) {
            h = (h ^ vec_hash_num1(c->num[m])) * 1099511628211u;
            dedup = dedup && c->num[m] == c->num[m];
        }
    } else {
        col_all(c);
        for (uint32_t m = 0; m < c->n; m++) {
            h = (h ^ vec_hash(c->v[m], false)) * 1099511628211u;
            dedup = dedup && nan_free(c->v[m]);
        }
    }
    if (cs->n == cs->cap) {
        cs->cap = cs->cap ? 2 * cs->cap : 16;
        cs->e = mem_realloc(cs->e, cs->cap * sizeof *cs->e);
    }
    if (2 * (cs->n + 1) > cs->nindex) {   /* grow both indexes */
        cs->nindex = cs->nindex ? 2 * cs->nindex : 64;
        free(cs->by_col);
        free(cs->by_hash);
        cs->by_col = mem_calloc(cs->nindex, sizeof *cs->by_col);
        cs->by_hash = mem_calloc(cs->nindex, sizeof *cs->by_hash);
        for (uint32_t k = 0; k < cs->n; k++) colset_index(cs, k);
    }
    /* a NaN-free column equal to an earlier one, member for member, takes
     * its name (equal entries all have that one name, so any will do) */
    uint32_t name = cs->names, mask = cs->nindex - 1;
    for (uint32_t i = (uint32_t)(h >> 32) & mask; dedup && cs->by_hash[i]; i = (i + 1) & mask) {
        const ColName *o = &cs->e[cs->by_hash[i] - 1];
        if (o->hash != h) continue;
        bool same = true;
        for (uint32_t m = 0; m < c->n && same; m++) same = col_key_equal(c, o->col, m);
        if (same) {
            name = o->name;
            break;
        }
    }
    if (name == cs->names) cs->names++;
    cs->e[cs->n] = (ColName){col_retain(c), h, name, dedup};
    colset_index(cs, cs->n++);
}

/* The entry of column [c] in [cs], or NULL. */
static const ColName *colset_find(const ColSet *cs, const Column *c)
{
    if (!cs->nindex) return NULL;
    uint32_t mask = cs->nindex - 1;
    for (uint32_t i = ptr_slot(c, mask); cs->by_col[i]; i = (i + 1) & mask)
        if (cs->e[cs->by_col[i] - 1].col == c) return &cs->e[cs->by_col[i] - 1];
    return NULL;
}

/* The entry of split column [c] in [cs], or NULL. */
static const SplitCol *split_find(const ColSet *cs, const Column *c)
{
    for (uint32_t i = 0; i < cs->nsp; i++)
        if (cs->sp[i].col == c) return &cs->sp[i];
    return NULL;
}

/* Member [m]'s numbers of column [c], which split_col has found to be
 * numeric vectors of one length: a flat column's own, or its vector's. */
static const double *member_nums(const Column *c, uint32_t m)
{
    return c->flat ? c->flat + (size_t)m * c->w : vec_cnums(c->v[m]);
}

/* Take column [c] apart by position into [cs] (see SplitCol); false when
 * its members are not numeric vectors of one length from 2 to SPLIT_MAX
 * (a flat column's are, its numbers at hand). */
static bool split_col(ColSet *cs, Column *c)
{
    if (split_find(cs, c)) return true;
    uint32_t len = c->w;
    if (!c->flat) {
        col_all(c);
        const Vec *v0 = c->v[0];
        if (!v0 || v0->kind != VEC_NUM || v0->len < 2) return false;
        len = v0->len;
        for (uint32_t m = 1; m < c->n; m++)
            if (!c->v[m] || c->v[m]->kind != VEC_NUM || c->v[m]->len != len) return false;
    }
    if (len > SPLIT_MAX) return false;
    if (cs->nsp == cs->capsp) {
        cs->capsp = cs->capsp ? 2 * cs->capsp : 4;
        cs->sp = mem_realloc(cs->sp, cs->capsp * sizeof *cs->sp);
    }
    SplitCol *sc = &cs->sp[cs->nsp++];
    *sc = (SplitCol){.col = col_retain(c), .len = len};
    for (uint32_t p = 0; p < len; p++) {
        uint64_t b0 = num_bits(member_nums(c, 0)[p]);
        bool same = true;
        for (uint32_t m = 1; m < c->n && same; m++) same = num_bits(member_nums(c, m)[p]) == b0;
        if (same) continue;
        Column *pc = col_new_num(c->n);
        for (uint32_t m = 0; m < c->n; m++) pc->num[m] = member_nums(c, m)[p];
        sc->pos[p] = pc;
        colset_add(cs, pc);
    }
    return true;
}

/* Whether every member of index column [c] indexes as the literal index
 * does: numbers whose floor is a 32-bit int, where the evaluator's name
 * index (index32) and literal index (index64, LANGUAGE.md §3.11) agree. */
static bool index_col_safe(Column *c)
{
    for (uint32_t m = 0; m < c->n && c->num; m++) {
        double f = floor(c->num[m]);
        if (!(f >= -2147483648.0 && f < 2147483648.0)) return false;
    }
    for (uint32_t m = 0; m < c->n && !c->num; m++) {
        const Vec *v = col_get(c, m);
        if (!v || v->kind != VEC_NUM) return false;
        for (uint32_t i = 0; i < v->len; i++) {
            double f = floor(vec_cnums(v)[i]);
            if (!(f >= -2147483648.0 && f < 2147483648.0)) return false;
        }
    }
    return true;
}

/* The columns of [t] into [cs]; false when one sits where the evaluator
 * treats a literal unlike a name bound to the same value: a called
 * function, an index (IndexLiteral, LANGUAGE.md §3.11), the exponent of
 * `**` (F2), the base of attributes or appended children, or inside a
 * function (whose capture flags were made for literals), or when a
 * member's value is not a single item (the loop binds items). */
static bool collect_cols(const AstNode *t, bool in_fn, ColSet *cs)
{
    if (!t) return true;
    if (has_col(t)) {
        Column *c = t->aux;
        if (in_fn) return false;
        if (c->flat) return split_col(cs, c);
        if (!c->num) col_all(c);
        for (uint32_t m = 0; m < c->n && !c->num; m++)
            if (vec_len(c->v[m]) != 1) return split_col(cs, c);
        if (!colset_find(cs, c)) colset_add(cs, c);
        return true;
    }
    if ((t->kind == AST_CALL || t->kind == AST_ATTRIBUTES || t->kind == AST_APPEND) && has_col(t->a)) return false;
    if (t->kind == AST_INDEX && has_col(t->b) && !index_col_safe(t->b->aux)) return false;
    if (t->kind == AST_BINOP && t->op == OP_POW && has_col(t->b)) return false;
    bool fn = in_fn || t->kind == AST_FUNCTION;
    if (!collect_cols(t->a, fn, cs) || !collect_cols(t->b, fn, cs) || !collect_cols(t->c, fn, cs)) return false;
    for (uint32_t i = 0; i < t->nkids; i++)
        if (!collect_cols(t->kids[i], fn, cs)) return false;
    return true;
}

/* The hidden name of column [h] (no identifier can be written so). */
static Str *hidden_name(uint32_t h)
{
    char b[32];
    snprintf(b, sizeof b, "\xe2\x9f\xa8t%u\xe2\x9f\xa9", h);   /* ⟨tH⟩ */
    return str_from(b);
}

/* Name [h]'s hidden name (a new reference). */
static Str *colset_hidden(ColSet *cs, uint32_t h)
{
    if (!cs->hidden) cs->hidden = mem_calloc(cs->names, sizeof *cs->hidden);
    if (!cs->hidden[h]) cs->hidden[h] = hidden_name(h);
    return str_retain(cs->hidden[h]);
}

/* A column literal as the hidden name of its column in ColSet *[ctx], or,
 * for a column taken apart, the sequence of its positions. */
static AstNode *name_leaf(const AstNode *lit, const void *ctx)
{
    const SplitCol *sc = split_find(ctx, lit->aux);
    ColSet *cs = (ColSet *)(uintptr_t)ctx;   /* loop_form's own set: names are cached in it */
    if (!sc) return ast_name(colset_hidden(cs, colset_find(cs, lit->aux)->name), lit->loc);
    AstNode *seq = ast_new(AST_SEQUENCE, lit->loc);
    for (uint32_t p = 0; p < sc->len; p++) {
        if (sc->pos[p])
            ast_push(seq, ast_name(colset_hidden(cs, colset_find(cs, sc->pos[p])->name), lit->loc));
        else
            /* the position's number, alike in every member */
            ast_push(seq, mk_lit(vec_num1(member_nums(sc->col, 0)[p]), lit->loc));
    }
    return seq;
}

/* The copies of the group whose members are iterations order[0..g) (in
 * iteration order), from its template [t], into items: each run of
 * consecutive iterations as one loop over the run's column values, bound
 * to hidden names (`for ⟨t0⟩;⟨t1⟩ in v00;v10;v01;v11...`), which the
 * evaluator runs as it ran the copies; the run's other items are null
 * (dropped by the sequence packing). The last run's body is *[tp] itself
 * (set to NULL: consumed). False (nothing made, *[tp] untouched) when the
 * group is better copied: few members, short runs, a literal template
 * (its copies pack into one literal vector), or columns the loop cannot
 * bind (collect_cols). */
static bool loop_form(AstNode **tp, const uint32_t *order, uint32_t g, AstNode **items)
{
    const AstNode *t = *tp;
    uint32_t runs = 1;
    for (uint32_t m = 1; m < g; m++) runs += order[m] != order[m - 1] + 1;
    /* a literal template's copies pack into one literal: nothing to run */
    if (g < 16 || g < 8 * runs || is_lit(t)) return false;
    ColSet cs = {0};
    if (!collect_cols(t, false, &cs) || !cs.names) {
        colset_free(&cs);
        return false;
    }
    /* each name's column: the first column that takes it */
    Column **byname = mem_realloc(NULL, cs.names * sizeof *byname);
    for (uint32_t i = cs.n; i-- > 0;) byname[cs.e[i].name] = cs.e[i].col;
    uint32_t k = cs.names;
    bool all_num = true;
    for (uint32_t h = 0; h < k; h++) all_num = all_num && byname[h]->num;
    for (uint32_t m = 0; m < g;) {
        uint32_t e = m + 1;
        while (e < g && order[e] == order[e - 1] + 1) e++;
        Vec *src;
        if (all_num) {
            /* what vec_compose makes of one-number vectors: their numbers */
            src = vec_new_num((e - m) * k);
            double *x = vec_nums(src);
            for (uint32_t j = m; j < e; j++)
                for (uint32_t h = 0; h < k; h++) x[(j - m) * k + h] = byname[h]->num[j];
        } else {
            Vec **parts = mem_realloc(NULL, (size_t)(e - m) * k * sizeof *parts);
            for (uint32_t j = m; j < e; j++)
                for (uint32_t h = 0; h < k; h++) parts[(j - m) * k + h] = col_get(byname[h], j);
            src = vec_compose(parts, (e - m) * k);
            free(parts);
        }
        AstNode *f = ast_new(AST_FOR, t->loc);
        for (uint32_t h = 0; h < k; h++) ast_push_name(f, colset_hidden(&cs, h));
        f->a = mk_lit(src, t->loc);
        for (uint32_t j = m + 1; j < e; j++) items[order[j]] = mk_lit(NULL, t->loc);
        items[order[m]] = f;
        if (e < g) {
            f->b = copy_with(t, name_leaf, &cs);
        } else {
            f->b = move_with(*tp, name_leaf, &cs);
            *tp = NULL;
        }
        m = e;
    }
    free(byname);
    colset_free(&cs);
    return true;
}

/* }===== */

/* Bind loop [n]'s names to iteration [it]'s items of [values] (null past
 * its end), as one copy at a time binds them. */
static void push_member(Simp *s, const AstNode *n, const Vec *values, uint32_t it)
{
    uint32_t k = n->nnames ? n->nnames : 1, len = vec_len(values);
    for (uint32_t j = 0; j < n->nnames; j++) {
        uint32_t idx = it * k + j;
        Vec *item = idx < len ? vec_item(values, idx) : NULL;
        scope_push(s, n->names[j], NB_LITERAL, item, NULL, NULL);
        vec_release(item);
    }
}

/* FLITTER_TEMPLATE_CHECK: every copy against the body simplified for its
 * iteration alone; a difference is a bug in a column helper or a missing
 * tdecide, reported with both trees. An interrupt (Ctrl-C, the fuzz
 * targets' time budget) ends the check: the load is abandoned. */
static void check_copies(Simp *s, const AstNode *n, const Vec *values, uint32_t count, AstNode **items,
                         uint64_t u0)
{
    /* each copy alone counts its nested copies from where one copy at a
     * time would (u0: before the loop), not on top of the templates' */
    uint64_t u = s->unrolled;
    s->unrolled = u0;
    for (uint32_t it = 0; it < count; it++) {
        uint32_t mark = s->nnames;
        push_member(s, n, values, it);
        AstNode *alone = simp(s, n->b);
        scope_restore(s, mark);
        if (s->ev.interrupt && *s->ev.interrupt) s->ev.interrupted = true;
        if (s->ev.interrupted) {
            /* the load gives up: a copy cut short is not a difference */
            ast_free(alone);
            break;
        }
        Buf a = BUF_INIT, b = BUF_INIT;
        ast_dump(&a, items[it], s->symtab);
        ast_dump(&b, alone, s->symtab);
        if (a.len != b.len || memcmp(a.data, b.data, a.len) != 0) {
            fprintf(stderr, "flitter: template copy %u differs from its iteration alone\n--- template\n%.*s\n"
                            "--- alone\n%.*s\n", it, (int)a.len, a.data, (int)b.len, b.data);
            abort();
        }
        buf_free(&a);
        buf_free(&b);
        ast_free(alone);
    }
    s->unrolled = u;
}

/* The column of loop name [j] ([k] names a binding) of [values] for the
 * members order[0..gn): numeric when the source is and every member's
 * binding lies within it, else a column of the items (null past the end). */
static Column *loop_col(const Vec *values, uint32_t k, uint32_t j, const uint32_t *order, uint32_t gn)
{
    uint32_t len = vec_len(values);
    if (vec_is_num(values)) {
        Column *c = col_new_num(gn);
        uint32_t m = 0;
        for (; m < gn && order[m] * k + j < len; m++) c->num[m] = vec_cnums(values)[order[m] * k + j];
        if (m == gn) return c;
        col_release(c);
    }
    Column *c = col_new(gn);
    for (uint32_t m = 0; m < gn; m++) {
        uint32_t idx = order[m] * k + j;
        c->v[m] = idx < len ? vec_item(values, idx) : NULL;
    }
    return c;
}

/* The members whose copies are literals, kept as values until every group
 * is done (LitMembers): when every copy is a literal, the loop's sequence
 * packs them into one literal composed of their values in iteration order
 * (sequence_pack), which is made directly, without a literal node per
 * copy to make, pack and free (a loop of 20,000 particles); otherwise each
 * becomes the literal node tinst() makes. */
typedef struct LitMembers {
    Vec **v;            /* a member's value (one reference; NULL: null) */
    Node **node;        /* or, when v[it] is NULL, the one node of its
                           value (one reference) from a node column; NULL
                           until one is kept so */
    Loc *loc;           /* its literal's place and flags (mk_lit) */
    uint8_t *op;
    uint8_t *set;       /* 1: kept here, its item not made yet */
    bool all;           /* every member so far */
} LitMembers;

/* Whether [t] is a literal node and nothing else (its copies are
 * ast_literal of a value, its place and its flags), with or without a
 * column. */
static bool lit_plain(const AstNode *t)
{
    return t->kind == AST_LITERAL && !t->a && !t->b && !t->c && !t->nkids && !t->nnames && !t->count &&
           (!t->aux || has_col(t));
}

static void lit_keep(LitMembers *lm, uint32_t count, uint32_t it, Vec *v_take, const AstNode *lit)
{
    if (!lm->v) {
        lm->v = mem_calloc(count, sizeof *lm->v);
        lm->loc = mem_calloc(count, sizeof *lm->loc);
        lm->op = mem_calloc(count, sizeof *lm->op);
        lm->set = mem_calloc(count, sizeof *lm->set);
    }
    lm->v[it] = v_take;
    lm->loc[it] = lit->loc;
    lm->op[it] = lit->op;
    lm->set[it] = 1;
}

/* lit_keep of member [it]'s value, the vector of the one node [n_take]. */
static void lit_keep_node(LitMembers *lm, uint32_t count, uint32_t it, Node *n_take, const AstNode *lit)
{
    lit_keep(lm, count, it, NULL, lit);
    if (!lm->node) lm->node = mem_calloc(count, sizeof *lm->node);
    lm->node[it] = n_take;
}

/* Member [it]'s kept value (one reference, taken from [lm]). */
static Vec *lit_take(LitMembers *lm, uint32_t it)
{
    Vec *v = lm->v[it];
    lm->v[it] = NULL;
    if (!v && lm->node && lm->node[it]) {
        v = vec_node_take(lm->node[it]);
        lm->node[it] = NULL;
    }
    return v;
}

static void lit_free(LitMembers *lm, uint32_t count)
{
    for (uint32_t it = 0; lm->v && it < count; it++) vec_release(lm->v[it]);
    for (uint32_t it = 0; lm->node && it < count; it++) node_release(lm->node[it]);
    free(lm->node);
    free(lm->v);
    free(lm->loc);
    free(lm->op);
    free(lm->set);
    *lm = (LitMembers){0};
}

/* The kept members into [items]: one literal of their composition (in
 * items[0], *[nout] 1) when every member was kept and their lengths fit
 * sequence_pack's limit, as it would pack their copies; else each its own
 * literal node, as tinst makes it. */
static void lit_items(LitMembers *lm, uint32_t count, AstNode **items, uint32_t *nout)
{
    if (!lm->v) return;
    uint64_t total = 0;
    uint32_t nodes = 0;
    for (uint32_t it = 0; it < count && lm->all; it++) {
        bool node = !lm->v[it] && lm->node && lm->node[it];
        total += node ? 1 : vec_len(lm->v[it]);
        nodes += node;
    }
    if (lm->all && total <= SIMP_MAX_RANGE && nodes == count && count > 1 && mem_fits(sizeof(Vec) + total * sizeof(Elem))) {
        /* every member one node: vec_compose's vector of them (as it
         * checks the budget), the nodes moved in */
        Vec *r = vec_new_obj(count);
        for (uint32_t it = 0; it < count; it++) {
            vec_elems(r)[it].kind = EL_NODE;
            vec_elems(r)[it].node = lm->node[it];
            lm->node[it] = NULL;
        }
        items[0] = mk_lit(r, lm->loc[0]);
        *nout = 1;
    } else if (lm->all && total <= SIMP_MAX_RANGE) {
        for (uint32_t it = 0; it < count && nodes; it++)
            if (!lm->v[it]) lm->v[it] = lit_take(lm, it);
        items[0] = mk_lit(vec_compose(lm->v, count), lm->loc[0]);
        *nout = 1;
    } else {
        for (uint32_t it = 0; it < count; it++) {
            if (!lm->set[it]) continue;
            items[it] = ast_literal(lit_take(lm, it), lm->loc[it]);   /* takes the value */
            items[it]->op = lm->op[it];
        }
    }
    lit_free(lm, count);
}

bool simp_unroll_templates(Simp *s, const AstNode *n, const Vec *values, uint32_t count, AstNode **items,
                           uint32_t *nout)
{
    /* a pass already abandoned (a warning in the loop's source, in a
     * member simplified alone) stays abandoned: this call would clear it */
    if (s->no_templates || s->tg || s->tabort || count < 2 || !shareable(n->b)) return false;
    uint32_t k = n->nnames ? n->nnames : 1;
    uint64_t u0 = s->unrolled;
    bool deep0 = s->too_deep, unwinding0 = s->unwinding;
    memset(items, 0, count * sizeof *items);
    uint32_t *order = mem_realloc(NULL, (size_t)count * sizeof *order);
    for (uint32_t i = 0; i < count; i++) order[i] = i;
    Range *stack = mem_realloc(NULL, sizeof *stack);
    uint32_t nstack = 1, capstack = 1, groups = 1;
    stack[0] = (Range){0, count};
    KeyPos *kp = NULL;
    bool ok = true;
    /* the check compares every copy as made: none kept as a value */
    LitMembers lm = {.all = !s->check_templates};
    *nout = count;
    while (nstack && ok) {
        Range g = stack[--nstack];
        if (g.n == 1) {
            /* a group of one is simplified with its member's own values, as
             * one copy at a time would: no columns, no copy of a template,
             * and a loop inside it may make templates of its own */
            uint32_t it = order[g.start], mark = s->nnames;
            push_member(s, n, values, it);
            bool alone0 = s->talone;
            s->talone = true;
            AstNode *t = simp(s, n->b);
            s->talone = alone0;
            scope_restore(s, mark);
            if (s->tabort || s->too_deep != deep0 || s->unwinding != unwinding0 || s->ev.interrupted) {
                ast_free(t);
                ok = false;
                break;
            }
            if (lm.all && lit_plain(t)) {   /* no columns outside a column pass */
                lit_keep(&lm, count, it, vec_retain(t->value), t);
                ast_free(t);
            } else {
                lm.all = false;
                items[it] = t;
            }
            continue;
        }
        s->tg = g.n;
        s->tabort = false;
        s->tkey = NULL;
        uint64_t ub = s->unrolled;
        uint32_t mark = s->nnames;
        for (uint32_t j = 0; j < n->nnames; j++) {
            Column *c = loop_col(values, k, j, order + g.start, g.n);
            scope_push_col(s, n->names[j], col_get(c, 0), c);
            col_release(c);
        }
        AstNode *t = simp(s, n->b);
        scope_restore(s, mark);
        s->tg = 0;
        if (s->tabort || s->too_deep != deep0 || s->unwinding != unwinding0 || s->ev.interrupted) {
            ast_free(t);
            ok = false;
            break;
        }
        if (s->tkey) {
            /* split the group by the outcome, members in iteration order */
            s->unrolled = ub;
            ast_free(t);
            kp = mem_realloc(kp, (size_t)g.n * sizeof *kp);
            for (uint32_t m = 0; m < g.n; m++) kp[m] = (KeyPos){s->tkey[m], order[g.start + m]};
            free(s->tkey);
            s->tkey = NULL;
            qsort(kp, g.n, sizeof *kp, keypos_cmp);
            uint32_t parts = 0;
            for (uint32_t m = 0; m < g.n; m++) {
                order[g.start + m] = kp[m].pos;
                if (m == 0 || kp[m].key != kp[m - 1].key) parts++;
            }
            groups += parts - 1;
            /* as many groups as copies would cost more than copies */
            if (groups > 8 + count / 8) {
                ok = false;
                break;
            }
            if (nstack + parts > capstack) {
                capstack = 2 * (nstack + parts);
                stack = mem_realloc(stack, capstack * sizeof *stack);
            }
            for (uint32_t m = 0; m < g.n;) {
                uint32_t e = m + 1;
                while (e < g.n && kp[e].key == kp[m].key) e++;
                stack[nstack++] = (Range){g.start + m, e - m};
                m = e;
            }
            continue;
        }
        if (lm.all && lit_plain(t)) {
            Column *tc = has_col(t) ? t->aux : NULL;
            for (uint32_t m = 0; m < g.n && !s->ev.interrupted; m++) {
                if (s->ev.interrupt && *s->ev.interrupt) s->ev.interrupted = true;   /* SIGINT: the load gives up */
                if (tc && tc->node && !(tc->v && tc->v[m]) && tc->node[m]) {
                    lit_keep_node(&lm, count, order[g.start + m], node_retain(tc->node[m]), t);
                    continue;
                }
                Vec *v = tc ? col_get(tc, m) : t->value;
                lit_keep(&lm, count, order[g.start + m], vec_retain(v), t);
            }
            ast_free(t);
            if (s->ev.interrupted) ok = false;
            continue;
        }
        lm.all = false;
        if (s->check_templates || !loop_form(&t, order + g.start, g.n, items)) {
            for (uint32_t m = 0; m < g.n && !s->ev.interrupted; m++) {
                if (s->ev.interrupt && *s->ev.interrupt) s->ev.interrupted = true;   /* SIGINT: the load gives up */
                if (m + 1 < g.n) {
                    items[order[g.start + m]] = tinst(t, m);
                } else {   /* the last member takes the template itself */
                    items[order[g.start + m]] = move_with(t, member_leaf, &m);
                    t = NULL;
                }
            }
        }
        ast_free(t);
        if (s->ev.interrupted) ok = false;
    }
    s->tg = 0;
    s->tabort = false;
    free(s->tkey);
    s->tkey = NULL;
    free(kp);
    free(stack);
    free(order);
    if (!ok) {
        lit_free(&lm, count);
        for (uint32_t i = 0; i < count; i++) ast_free(items[i]);
        s->unrolled = u0;
        s->too_deep = deep0;
        s->unwinding = unwinding0;
        return false;
    }
    lit_items(&lm, count, items, nout);
    if (s->check_templates) {
        check_copies(s, n, values, count, items, u0);
        if (!s->ev.interrupted)
            fprintf(stderr, "flitter: template check: loop at byte %u of source %u: %u copies from %u groups, each as alone\n",
                    n->loc.start, n->loc.file, count, groups);
    }
    return true;
}

/* }===== */
