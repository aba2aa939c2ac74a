/* evalrun.c: running the compiled regions of evalcode.h.
 *
 * Each record does what the eval_* function of its AST kind in eval.c does,
 * in the same order, with the same helpers (eval_internal.h) and the same
 * depth accounting; anything else is handed back to the tree walk.
 */
#include "eval_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "builtins.h"
#include "evalcode.h"
#include "kernel.h"
#include "mem.h"
#include "node.h"
#include "pool.h"

static Vec *run_rec(Eval *ev, const unsigned char *base, const CRec *r);

/* C_MEMO: C_NUM, its result kept in the block's memo cell and handed out
 * again while the engine names it reads hold the same numbers. A kept
 * vector is shared, which nothing can tell from a new one with the same
 * numbers (§3.6 rule 1 only matters for NaN, never kept). */
__attribute__((noinline)) static Vec *run_memo(Eval *ev, const unsigned char *base, const CRec *r)
{
    CMemo *m = &ev->memos[r->n];
    /* in a loop kernel's body: the engine names stay as they are while the
     * loop runs, so the value kept at its first use in the loop is the
     * one the cell would hand out (kernel.h, Eval.kmemo) */
    Vec **km = ev->kbase == base ? ev->kmemo : NULL;
    if (km && km[r->n] && ev->depth + r->aux <= MAX_EVAL_DEPTH) return vec_retain(km[r->n]);
    uint64_t keys[NUMEXPR_MEMO_KEYS];
    /* the cells (and their values) the coming C_MEMO records will read are
     * usually cold: ask for them now (evalcode.h CMemoHint) */
    const CMemoHint *h = (const CMemoHint *)(const void *)(r + 1);
    if (h->cell_far != CMEMO_NONE) __builtin_prefetch(&ev->memos[h->cell_far]);
    if (h->cell_near != CMEMO_NONE) __builtin_prefetch(ev->memos[h->cell_near].value, 1);
    const NumExpr *x = (const NumExpr *)(const void *)(base + m->expr);
    if (!ev->globals || ev->depth + r->aux > MAX_EVAL_DEPTH)
        return run_num(ev, r->p.node, x);
    bool same = m->value != NULL;
    for (int32_t k = 0; k < m->nkeys; k++) {
        const Vec *g = ev->globals->values[m->names[k]];
        if (!vec_is_scalar(g)) return run_num(ev, r->p.node, x);
        memcpy(&keys[k], vec_cnums(g), sizeof keys[k]);
        same = same && keys[k] == m->keys[k];
    }
    if (same) {
        if (km) km[r->n] = vec_retain(m->value);
        return vec_retain(m->value);
    }
    Vec *v = run_num(ev, r->p.node, x);
    if (vec_is_num(v)) {
        for (uint32_t i = 0; i < v->len; i++)
            if (isnan(vec_cnums(v)[i])) return v;
        vec_release(m->value);
        m->value = vec_retain(v);
        for (int32_t k = 0; k < m->nkeys; k++) m->keys[k] = keys[k];
        if (km) km[r->n] = vec_retain(v);
    }
    return v;
}

/* C_KNUM: the number its loop kernel computed for this iteration
 * (kernel.h), or, when there is none, C_NUM. */
__attribute__((noinline)) static Vec *run_knum(Eval *ev, const unsigned char *base, const CRec *r)
{
    const NumExpr *x = (const NumExpr *)(const void *)(r + 1);
    if (ev->kbase == base && ev->kok[r->n] && ev->depth + numexpr_depth(x) <= MAX_EVAL_DEPTH) {
        uint32_t n = numexpr_outputs(x);
        Vec *v = vec_new_num(n);
        double *d = vec_nums(v);
        const double *s = ev->kregs + r->n;
        for (uint32_t i = 0; i < n; i++) d[i] = s[i];
        return v;
    }
    return run_num(ev, r->p.node, x);
}

/* eval_node's depth guard; false (with the error) on overflow. */
static inline bool depth_enter(Eval *ev)
{
    if (++ev->depth > MAX_EVAL_DEPTH) {
        ev->depth--;
        ev->overflow = true;
        eval_error(ev, "Stack overflow in program");
        return false;
    }
    return true;
}

static const uint32_t *rec_offs(const CRec *r) { return (const uint32_t *)(const void *)(r + 1); }

/* The value of the record at [off]: the leaves here, inline in the
 * composite records' loops; the composite records in run_rec (out of line,
 * with the depth guard eval_node would apply). */
static inline Vec *run_val(Eval *ev, const unsigned char *base, uint32_t off)
{
    const CRec *r = crec(base, off);
    switch (r->op) {
    case C_LIT: return vec_retain(r->p.lit);
    case C_LOCAL: return vec_retain(ev->frame[r->n]);
    case C_GLOBAL: return ev->globals ? vec_retain(ev->globals->values[r->n]) : NULL;
    case C_NUM: return run_num(ev, r->p.node, (const NumExpr *)(const void *)(r + 1));
    case C_MEMO: return run_memo(ev, base, r);
    case C_KNUM: return run_knum(ev, base, r);
    /* a C_AST node is never a literal, a name or compiled (those have
     * records of their own): eval() would call eval_node */
    case C_AST: return eval_node(ev, r->p.node);
    default: return run_rec(ev, base, r);
    }
}

/* C_SEQ: eval_sequence */
__attribute__((noinline)) static Vec *run_seq(Eval *ev, const unsigned char *base, const CRec *r)
{
    const uint32_t *k = rec_offs(r);
    if (r->n == 1) return run_val(ev, base, k[0]);
    Parts parts;
    parts_init(&parts);
    for (uint32_t i = 0; i < r->n; i++) parts_push(&parts, run_val(ev, base, k[i]));
    return parts_finish(ev, &parts);
}

/* C_LET: eval_let of single-name, non-stable bindings; then, unlike
 * eval_let (which leaves a value in its slot until the slot is bound again
 * or the frame ends), the bound values are released as soon as the body is
 * done. Nothing can read them any more: the names are lexically scoped
 * (program.c resolves nothing outside the body to these slots). A block
 * released now is reused while it is still in the cache, and an unrolled
 * program (a slot per copy of a loop body) does not keep every copy's
 * values alive, and cold, until the end of the frame. */
static inline __attribute__((always_inline)) Vec *run_let(Eval *ev, const unsigned char *base, const CRec *r)
{
    const CLetTail *t = (const CLetTail *)(const void *)(r + 1);
    for (uint32_t i = 0; i < r->n; i++) set_slot(ev, t->binds[i].slot, run_val(ev, base, t->binds[i].off));
    Vec *v = run_val(ev, base, t->body);
    for (uint32_t i = 0; i < r->n; i++) set_slot(ev, t->binds[i].slot, NULL);
    return v;
}

/* C_KLET: run_let without the bindings that only the loop kernel's
 * records read, while the kernel holds every number of this iteration
 * (kernel.h); its values are pure numbers, so nothing else changes */
__attribute__((noinline)) static Vec *run_klet(Eval *ev, const unsigned char *base, const CRec *r)
{
    if (ev->kbase != base || !ev->kclean || ev->depth + r->aux > MAX_EVAL_DEPTH) return run_let(ev, base, r);
    const CLetTail *t = (const CLetTail *)(const void *)(r + 1);
    const uint32_t skip = t->pad;
    for (uint32_t i = 0; i < r->n; i++)
        if (i >= 32 || !(skip >> i & 1)) set_slot(ev, t->binds[i].slot, run_val(ev, base, t->binds[i].off));
    Vec *v = run_val(ev, base, t->body);
    for (uint32_t i = 0; i < r->n; i++)
        if (i >= 32 || !(skip >> i & 1)) set_slot(ev, t->binds[i].slot, NULL);
    return v;
}

/* C_ATTRS: eval_attributes */
__attribute__((noinline)) static Vec *run_attrs(Eval *ev, const unsigned char *base, const CRec *r)
{
    const CAttrsTail *t = (const CAttrsTail *)(const void *)(r + 1);
    const CRec *nr = crec(base, t->node);
    Vec *v = run_val(ev, base, t->node);
    Vec *small[16];
    Vec **vals = r->n > 16 ? malloc(r->n * sizeof(Vec *)) : small;
    if (!vals) mem_oom();
    for (uint32_t k = 0; k < r->n; k++) vals[k] = run_val(ev, base, t->attrs[k].off);
    if (nr->op == C_LIT && v && v->kind == VEC_OBJ && v->len == 1 && vec_celems(v)[0].kind == EL_NODE) {
        /* one literal node with attributes, tags or children of its own
         * (a bare one is C_NEWNODE): its copy with room for these, in a
         * vector of its own, as vec_unshare and node_mut_room below make
         * them, each value handed to the node (one node: no retain and
         * release for each) */
        Node *nn = node_mut_room(node_retain(vec_celems(v)[0].node), r->n);
        vec_release(v);
        if (r->pad) {
            /* names of its own, none the literal's (evalcode.c): each added
             * without a search */
            for (uint32_t k = 0; k < r->n; k++) node_add_new_attr(nn, t->attrs[k].name, vals[k]);
        } else {
            for (uint32_t k = 0; k < r->n; k++) node_set_attr(nn, t->attrs[k].name, vals[k]);
        }
        if (vals != small) free(vals);
        return vec_node_take(nn);
    }
    if (has_nodes(v)) {
        v = vec_unshare(v);
        Elem *e = vec_elems(v);
        for (uint32_t i = 0; i < v->len; i++) {
            if (e[i].kind != EL_NODE) continue;
            e[i].node = node_mut_room(e[i].node, r->n);
            for (uint32_t k = 0; k < r->n; k++)
                node_set_attr(e[i].node, t->attrs[k].name, vec_retain(vals[k]));
        }
    }
    for (uint32_t k = 0; k < r->n; k++) vec_release(vals[k]);
    if (vals != small) free(vals);
    return v;
}

/* C_NEWNODE: eval_attributes on a literal bare node, which it would copy
 * (it is shared) before setting the attributes: the same node, built
 * directly, with its attribute slots in its own block. The values are
 * evaluated in order, as there; the names are distinct (evalcode.c
 * checks), so each one is set without a search. */
static inline __attribute__((always_inline)) Vec *run_newnode(Eval *ev, const unsigned char *base,
                                                              const CRec *r)
{
    const CAttrsTail *t = (const CAttrsTail *)(const void *)(r + 1);
    Node *nn = node_new_sized(r->p.kind, r->n);
    for (uint32_t k = 0; k < r->n; k++) node_add_new_attr(nn, t->attrs[k].name, run_val(ev, base, t->attrs[k].off));
    return vec_node_take(nn);
}

/* The numbers attribute record [a] of a C_KNODE takes from the kernel's
 * registers (a C_KCALL or C_KNUM). */
static inline uint32_t knode_outputs(const CRec *a)
{
    return a->op == C_KCALL ? a->aux : numexpr_outputs((const NumExpr *)(const void *)(a + 1));
}

/* C_KNODE's new node, its attributes in order: a C_MEMO record's value
 * (memo[k] when [memo] is given: evaluated already), or the numbers
 * copied from the kernel's registers. */
static inline __attribute__((always_inline)) Node *knode_new(Eval *ev, const unsigned char *base, const CRec *r, Vec *const *memo)
{
    const CAttrsTail *t = (const CAttrsTail *)(const void *)(r + 1);
    Node *nn = node_new_sized(r->p.kind, r->n);
    for (uint32_t k = 0; k < r->n; k++) {
        const CRec *a = crec(base, t->attrs[k].off);
        Vec *v;
        if (a->op == C_MEMO) {
            v = memo ? memo[k] : run_memo(ev, base, a);
        } else {
            uint32_t n = knode_outputs(a);
            v = vec_new_num(n);
            double *d = vec_nums(v);
            const double *s = ev->kregs + a->n;
            for (uint32_t i = 0; i < n; i++) d[i] = s[i];
        }
        node_add_new_attr(nn, t->attrs[k].name, v);
    }
    return nn;
}

/* run_knode with the loop's cache of nodes [c]: the node of this slot
 * from the run before the last, refilled in place when nothing but the
 * cache holds it and it has the record's kind and attributes (names in
 * order, none dropped, each register attribute a number vector of the
 * record's length held by the node alone); else a new node, kept in the
 * slot. Either way the node is the one run_knode builds, value for
 * value. The memo attributes (the only ones whose evaluation can do
 * anything) are evaluated first, in order, as run_knode evaluates them. */
__attribute__((noinline)) static Node *run_knode_cached(Eval *ev, const unsigned char *base, const CRec *r,
                                                        KNodeCache *c)
{
    const CAttrsTail *t = (const CAttrsTail *)(const void *)(r + 1);
    const uint32_t s = c->next++;
    Node *o = s < c->n ? c->slot[s] : NULL;
    /* the last frame's node, still held elsewhere (or none): the one of
     * the frame before, from the second cache (kernel.h KNodeCache.alt) */
    if (c->alt && !(o && o->refs == 1) && knode_cache_swap_alt(c, s)) o = c->slot[s];
    Vec *memo[KNODE_REUSE_ATTRS];
    bool same = o && o->refs == 1 && o->kind == r->p.kind && !o->ntags && !o->nchildren && o->nattrs == r->n;
    for (uint32_t k = 0; k < r->n; k++) {
        const CRec *a = crec(base, t->attrs[k].off);
        if (a->op == C_MEMO) {
            memo[k] = run_memo(ev, base, a);
            same = same && vec_len(memo[k]) > 0 && o->attrs[k].name == t->attrs[k].name;
        } else {
            memo[k] = NULL;
            const Vec *v = same ? o->attrs[k].value : NULL;
            same = same && o->attrs[k].name == t->attrs[k].name && v->refs == 1 && v->kind == VEC_NUM &&
                   v->len == knode_outputs(a) && v->len > 0;
        }
    }
    if (!same) {
        Node *nn = knode_new(ev, base, r, memo);
        if (!knode_cache_put(c, s, nn)) ev->kcache = NULL;
        return nn;
    }
    for (uint32_t k = 0; k < r->n; k++) {
        if (memo[k]) {
            vec_release(o->attrs[k].value);
            o->attrs[k].value = memo[k];
            continue;
        }
        const CRec *a = crec(base, t->attrs[k].off);
        Vec *v = o->attrs[k].value;
        double *d = vec_nums(v);
        const double *src = ev->kregs + a->n;
        /* a few numbers each: a call to memcpy costs more */
        for (uint32_t i = 0; i < v->len; i++) d[i] = src[i];
        v->hashed = 0;
    }
    ev->kreused++;
    return node_retain(o);
}

Node *knode_take(Eval *ev, const unsigned char *base, const CRec *r)
{
    if (ev->kcache && r->n <= KNODE_REUSE_ATTRS) return run_knode_cached(ev, base, r, ev->kcache);
    return knode_new(ev, base, r, NULL);
}

/* C_KNODE (inside run_rec's depth guard, the kernel's clean iteration
 * and depth checked): run_newnode with each attribute's record done here,
 * the numbers copied from the kernel's registers */
__attribute__((noinline)) static Vec *run_knode(Eval *ev, const unsigned char *base, const CRec *r)
{
    if (ev->kbase != base || !ev->kclean || ev->depth + r->aux > MAX_EVAL_DEPTH) return run_newnode(ev, base, r);
    return vec_node_take(knode_take(ev, base, r));
}

/* Most numbers a record is run into on the C stack (run_nums: a C_LOOKUP
 * key, a C_INDEX index, a C_IF condition, a call's argument); longer ones
 * take the generic way. The records with such arrays stay out of
 * run_rec's frame (noinline), as run_rec's comment says. */
#define RUN_NUMS_MAX BI_NUMS_MAX
_Static_assert(NUMEXPR_VEC_MAX <= RUN_NUMS_MAX, "run_nums takes numexpr_run_vec's vectors");

/* The numbers of a leaf record [x] (a constant, a name, a compiled
 * expression: C_NUM as run_num would compute them before making its
 * vector, on one number each or on vectors), 1 to RUN_NUMS_MAX of them,
 * into [out], without a vector: their count, when its value is such a
 * numeric vector; 0 (nothing reported) otherwise, and when its numexpr
 * gives up or would pass the depth limit, where the caller evaluates it
 * generically. Pure: reading a name or running a compiled expression has
 * no effect to repeat. */
static inline __attribute__((always_inline)) uint32_t run_nums(Eval *ev, const CRec *x, double *out)
{
    const Vec *v;
    switch (x->op) {
    case C_LIT: v = x->p.lit; break;
    case C_LOCAL: v = ev->frame[x->n]; break;
    case C_GLOBAL: v = ev->globals ? ev->globals->values[x->n] : NULL; break;
    case C_NUM: {
        const NumExpr *e = (const NumExpr *)(const void *)(x + 1);
        uint32_t n = numexpr_outputs(e);
        if (n > RUN_NUMS_MAX || ev->depth + numexpr_depth(e) > MAX_EVAL_DEPTH) return 0;
        if (numexpr_small(e)) {
            const NxSmall y = numexpr_run_small(e, ev);
            if (y.ok) {
                out[0] = y.v;
                return 1;
            }
        } else {
            /* (a vector read first: numexpr_run would give up at once) */
            const int32_t lead = numexpr_lead_slot(e);
            if ((lead < 0 || vec_is_scalar(ev->frame[lead])) && numexpr_run(e, ev, out)) return n;
        }
        return numexpr_run_vec(e, ev, out, &n) ? n : 0;
    }
    default: return 0;
    }
    if (!vec_is_num(v) || !v->len || v->len > RUN_NUMS_MAX) return 0;
    /* one number, most often: without a call of memcpy */
    if (v->len == 1) out[0] = vec_cnums(v)[0];
    else memcpy(out, vec_cnums(v), v->len * sizeof(double));
    return v->len;
}

/* run_nums, and C_BINOP of two leaves (a - b) or its square (x**2), as
 * run_binop computes it (num_arith_into: vec_arith's numbers; F2 x**2 as
 * x*x), at the depth its run_rec would be: the numbers of a call's
 * argument without the argument's vector. */
static bool arg_nums(Eval *ev, const unsigned char *base, uint32_t off, double *out, uint32_t *n)
{
    const CRec *r = crec(base, off);
    if (r->op != C_BINOP) return (*n = run_nums(ev, r, out)) != 0;
    if (r->pad != BINOP_PLAIN && r->pad != BINOP_SQUARE) return false;
    if (ev->depth + 1 > MAX_EVAL_DEPTH) return false;
    const uint32_t *k = rec_offs(r);
    double a[RUN_NUMS_MAX], b[RUN_NUMS_MAX];
    uint32_t na, nb = 0;
    ev->depth++;
    na = run_nums(ev, crec(base, k[0]), a);
    if (na && r->pad != BINOP_SQUARE) nb = run_nums(ev, crec(base, k[1]), b);
    ev->depth--;
    if (!na || (r->pad != BINOP_SQUARE && !nb)) return false;
    if (r->pad == BINOP_SQUARE) num_arith_into(OP_MUL, out, a, na, a, na);
    else num_arith_into((ArithOp)r->n, out, a, na, b, nb);
    *n = na > nb ? na : nb;
    return true;
}

/* A new numeric vector of the [n] numbers [y] (a call's result, a few
 * numbers; one, most often, stored without a call of memcpy). */
static inline __attribute__((always_inline)) Vec *nums_vec(const double *y, uint32_t n)
{
    Vec *v = vec_new_num(n);
    if (n == 1) vec_nums(v)[0] = y[0];
    else memcpy(vec_nums(v), y, n * sizeof(double));
    return v;
}

/* C_CALLBI pad 2 (map, clamp, noise): each argument run into numbers on
 * the C stack (run_nums) and the call's numbers computed from them
 * (bi_call_nums_args) into a new vector; false, with nothing done that
 * shows, when an argument is not such numbers or the builtin's result
 * would not be (the caller then calls the builtin). Kept out of
 * run_callbi's frame (its arrays). */
__attribute__((noinline)) static bool run_callbi_args(Eval *ev, const unsigned char *base, const CRec *r,
                                                      Vec **v)
{
    const uint32_t *k = rec_offs(r);
    double x[BI_ARGS_MAX][RUN_NUMS_MAX], y[BI_NUMS_MAX];
    const double *xp[BI_ARGS_MAX];
    uint32_t n[BI_ARGS_MAX], ny;
    for (uint32_t i = 0; i < r->n; i++) {
        if (!(n[i] = run_nums(ev, crec(base, k[i]), x[i]))) return false;
        xp[i] = x[i];
    }
    if (!bi_call_nums_args(ev, r->p.bi, xp, n, r->n, y, &ny)) return false;
    *v = nums_vec(y, ny);
    return true;
}

/* C_CALLBI: eval_call's direct route for a builtin callee; a builtin of
 * one argument with a numeric route (pad 1: bi_call_nums) takes the
 * argument's numbers from the C stack when it can (arg_nums), without
 * the argument's vector or the call's checks (one positional argument,
 * which the builtin takes); one with a route for all its arguments (pad
 * 2) takes them so too (run_callbi_args) */
__attribute__((noinline)) static Vec *run_callbi(Eval *ev, const unsigned char *base, const CRec *r)
{
    const uint32_t *k = rec_offs(r);
    if (r->pad == 2) {
        Vec *v;
        if (run_callbi_args(ev, base, r, &v)) return v;
    } else if (r->pad) {
        double x[RUN_NUMS_MAX], y[BI_NUMS_MAX];
        uint32_t nx, ny;
        if (arg_nums(ev, base, k[0], x, &nx) && bi_call_nums_id(r->aux, x, nx, y, &ny)) return nums_vec(y, ny);
    }
    Vec *args[8];
    for (uint32_t i = 0; i < r->n; i++) args[i] = run_val(ev, base, k[i]);
    Args a = {args, r->n, NULL, NULL, 0};
    Vec *v = call_builtin(ev, r->p.bi, &a);
    for (uint32_t i = 0; i < r->n; i++) vec_release(args[i]);
    return v;
}

/* C_KCALL (inside run_rec's depth guard): the numbers the loop kernel
 * computed for this iteration, or, when it holds none, C_CALLBI of its
 * one argument */
__attribute__((noinline)) static Vec *run_kcall(Eval *ev, const unsigned char *base, const CRec *r)
{
    if (ev->kbase == base && ev->kok[r->n] && ev->depth + r->pad <= MAX_EVAL_DEPTH) {
        Vec *v = vec_new_num(r->aux);
        double *d = vec_nums(v);
        const double *s = ev->kregs + r->n;
        for (uint32_t i = 0; i < r->aux; i++) d[i] = s[i];
        return v;
    }
    Vec *arg = run_val(ev, base, rec_offs(r)[0]);
    Args a = {&arg, 1, NULL, NULL, 0};
    Vec *v = call_builtin(ev, r->p.bi, &a);
    vec_release(arg);
    return v;
}

/* C_APPEND of the parent [p] (evaluated) and a C_SEQ [c] of at most
 * APPEND_PARTS_MAX parts: run_rec's C_SEQ, its parts appended as they are
 * (append_parts) instead of composed first. Kept out of run_rec's frame
 * (its array). */
__attribute__((noinline)) static Vec *run_append_parts(Eval *ev, const unsigned char *base, Vec *p,
                                                       const CRec *c)
{
    if (!depth_enter(ev)) return append_nodes(p, NULL);
    Vec *parts[APPEND_PARTS_MAX];
    const uint32_t *k = rec_offs(c);
    for (uint32_t i = 0; i < c->n; i++) parts[i] = run_val(ev, base, k[i]);
    ev->depth--;
    return append_parts(ev, p, parts, c->n);
}

/* C_APPEND: eval_append */
static Vec *run_append(Eval *ev, const unsigned char *base, const CRec *r)
{
    const uint32_t *k = rec_offs(r);
    Vec *p = run_val(ev, base, k[0]);
    const CRec *cr = crec(base, k[1]);
    if (cr->op == C_SEQ && cr->n >= 2 && cr->n <= APPEND_PARTS_MAX) return run_append_parts(ev, base, p, cr);
    Vec *c = run_val(ev, base, k[1]);
    return append_nodes(p, c);
}

/* C_LOOKUP: eval_node's AST_LOOKUP */
__attribute__((noinline)) static Vec *run_lookup(Eval *ev, const unsigned char *base, const CRec *r)
{
    const uint32_t *k = rec_offs(r);
    const CRec *kr = crec(base, k[0]);
    if (kr->op == C_NUM) {
        /* a computed key, looked up by its numbers (a key vector that
         * exists already, a constant's or a name's, is looked up as it
         * is: it keeps its hash, vec_hash); one of constants and names
         * alone (pad 1) read without running its expression, which would
         * give up where this does (a name not one number: the generic
         * route then) */
        double key[RUN_NUMS_MAX];
        const NumExpr *e = (const NumExpr *)(const void *)(kr + 1);
        uint32_t n;
        if (!r->pad) n = run_nums(ev, kr, key);
        else if (numexpr_outputs(e) <= RUN_NUMS_MAX && ev->depth + numexpr_depth(e) <= MAX_EVAL_DEPTH)
            n = numexpr_run_leaves(e, ev, key);
        else n = 0;
        if (n) return ev->state ? vec_share(state_get_nums(ev->state, key, n)) : NULL;
    } else if (r->n != CLOOK_NONE) {
        /* a literal key, through its lookup cell */
        StateCached *sc = (StateCached *)(void *)((unsigned char *)ev->memos + r->n);
        return ev->state ? vec_share(state_get_cached(ev->state, kr->p.lit, sc)) : NULL;
    }
    Vec *a = run_val(ev, base, k[0]);
    Vec *v = ev->state ? vec_share(state_get(ev->state, a)) : NULL;
    vec_release(a);
    return v;
}

/* C_INDEX of a random stream made from numbers, `uniform(KEY)[INDEX]`
 * (also normal, beta) with a KEY of up to RUN_NUMS_MAX numbers that
 * numexpr computes: the stream's seed is hashed from the numbers (random.c's
 * stream(): vec_hash of the numeric vector, floats floored) without making
 * the key or the stream, and an INDEX that numexpr computes too draws into
 * the result, stream_index_into as vec_index_nums would; evaluated in
 * run_index's order (the call and its argument, then the index) and at its
 * depths (the call one level below the index, its argument two). False,
 * with nothing evaluated, when [call] is no such call or its key is not
 * numbers; else *out is the value. */
static bool run_stream_index(Eval *ev, const unsigned char *base, const CRec *call, uint32_t index_off,
                             bool literal, Vec **out)
{
    if (call->op != C_CALLBI || call->n != 1) return false;
    int kind = bi_stream_kind(call->p.bi);
    if (kind < 0 || ev->depth + 1 > MAX_EVAL_DEPTH) return false;
    double key[RUN_NUMS_MAX];
    ev->depth++;   /* (the call's level) */
    uint32_t nk = run_nums(ev, crec(base, rec_offs(call)[0]), key);
    ev->depth--;
    if (!nk) return false;
    uint64_t seed = vec_hash_nums(key, nk, true);
    double index[RUN_NUMS_MAX];
    uint32_t n = run_nums(ev, crec(base, index_off), index);
    if (n) {
        Vec *v = vec_new_num(n);
        stream_index_into((StreamKind)kind, seed, index, n, vec_nums(v));
        *out = v;
    } else {
        Vec *a = vec_stream((StreamKind)kind, seed), *b = run_val(ev, base, index_off);
        *out = vec_index(a, b, literal);
        vec_release(a);
        vec_release(b);
    }
    return true;
}

/* C_INDEX: eval_node's AST_INDEX */
__attribute__((noinline)) static Vec *run_index(Eval *ev, const unsigned char *base, const CRec *r)
{
    const uint32_t *k = rec_offs(r);
    Vec *v;
    if (run_stream_index(ev, base, crec(base, k[0]), k[1], r->pad, &v)) return v;
    Vec *a = run_val(ev, base, k[0]);
    double index[RUN_NUMS_MAX];
    uint32_t n = run_nums(ev, crec(base, k[1]), index);
    if (n) {
        v = vec_index_nums(a, index, n, r->pad);
    } else {
        Vec *b = run_val(ev, base, k[1]);
        v = vec_index(a, b, r->pad);
        vec_release(b);
    }
    vec_release(a);
    return v;
}

/* The truth of the condition record at [off] from its numbers, when
 * run_nums gives them: 1 or 0 (vec_truthy's: a number not 0, a NaN too,
 * which is unequal to 0); -1 when it does not (the caller evaluates the
 * condition). Kept out of run_if's frame (its array): run_if is on every
 * level of a deep chain of ifs, up to MAX_EVAL_DEPTH. */
__attribute__((noinline)) static int cond_nums(Eval *ev, const unsigned char *base, uint32_t off)
{
    double x[RUN_NUMS_MAX];
    const uint32_t n = run_nums(ev, crec(base, off), x);
    if (!n) return -1;
    for (uint32_t j = 0; j < n; j++)
        if (x[j] != 0.0) return 1;
    return 0;
}

/* C_IF: eval_ifelse */
__attribute__((noinline)) static Vec *run_if(Eval *ev, const unsigned char *base, const CRec *r)
{
    const uint32_t *k = rec_offs(r);
    for (uint32_t i = 0; i < r->n; i++) {
        /* a small condition (`d < D`) here, else cond_nums */
        const CRec *cr = crec(base, k[2 * i]);
        int c = -1;
        if (cr->op == C_NUM) {
            const NumExpr *e = (const NumExpr *)(const void *)(cr + 1);
            if (numexpr_small(e) && ev->depth + numexpr_depth(e) <= MAX_EVAL_DEPTH) {
                const NxSmall y = numexpr_run_small(e, ev);
                if (y.ok) c = y.v != 0.0;
            }
        }
        if (c < 0) c = cond_nums(ev, base, k[2 * i]);
        bool t = c > 0;
        if (c < 0) {
            Vec *v = run_val(ev, base, k[2 * i]);
            t = vec_truthy(v);
            vec_release(v);
        }
        if (t) return run_val(ev, base, k[2 * i + 1]);
    }
    return k[2 * r->n] != CREC_NONE ? run_val(ev, base, k[2 * r->n]) : NULL;
}

/* C_BINOP: eval_binop */
__attribute__((noinline)) static Vec *run_binop(Eval *ev, const unsigned char *base, const CRec *r)
{
    const uint32_t *k = rec_offs(r);
    Vec *a = run_val(ev, base, k[0]), *b, *c, *v;
    switch (r->pad) {
    case BINOP_SQUARE:
        v = vec_arith(OP_MUL, a, a);
        vec_release(a);
        return v;
    case BINOP_ADD_MUL:
    case BINOP_ADD_SQUARE:
        b = run_val(ev, base, k[1]);
        c = r->pad == BINOP_ADD_MUL ? run_val(ev, base, k[2]) : vec_retain(b);
        v = vec_add_mul(a, b, c);
        vec_release(a);
        vec_release(b);
        vec_release(c);
        return v;
    default:
        return vec_arith_take((ArithOp)r->n, a, run_val(ev, base, k[1]));
    }
}

/* A composite record (C_SEQ, C_LET, C_ATTRS, C_CALLBI, C_APPEND,
 * C_NEWNODE, C_LOOKUP, C_INDEX, C_IF, C_BINOP), inside eval_node's depth guard. Every level of a deep
 * program (up to MAX_EVAL_DEPTH) has this frame on the C stack: the
 * records with arrays of their own (run_seq, run_attrs, run_callbi) are
 * kept out of it, so it stays small (also under the sanitizers, which pad
 * every local array). */
__attribute__((noinline)) static Vec *run_rec(Eval *ev, const unsigned char *base, const CRec *r)
{
    Vec *v;
    if (!depth_enter(ev)) return NULL;
    switch (r->op) {
    case C_SEQ: v = run_seq(ev, base, r); break;
    case C_LET: v = run_let(ev, base, r); break;
    case C_KLET: v = run_klet(ev, base, r); break;
    case C_ATTRS: v = run_attrs(ev, base, r); break;
    case C_CALLBI: v = run_callbi(ev, base, r); break;
    case C_APPEND: v = run_append(ev, base, r); break;
    case C_NEWNODE: v = run_newnode(ev, base, r); break;
    case C_KNODE: v = run_knode(ev, base, r); break;
    case C_KCALL: v = run_kcall(ev, base, r); break;
    case C_LOOKUP: v = run_lookup(ev, base, r); break;
    case C_INDEX: v = run_index(ev, base, r); break;
    case C_IF: v = run_if(ev, base, r); break;
    case C_BINOP: v = run_binop(ev, base, r); break;
    default: v = NULL; break;
    }
    ev->depth--;
    return v;
}

Vec *eval_code(Eval *ev, const AstNode *n)
{
    CBlock *b = n->aux;
    CMemo *saved = ev->memos;
    ev->memos = b->memos;
    Vec *v = run_val(ev, b->code, 0);
    ev->memos = saved;
    return v;
}

