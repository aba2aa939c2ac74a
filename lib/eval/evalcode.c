/* evalcode.c: compiling the program's hot regions into contiguous record
 * blocks (evalcode.h). The records are run by eval.c (eval_code).
 */
#include "evalcode.h"

#include <stdlib.h>
#include <string.h>

#include "builtins.h"
#include "kernel.h"
#include "mem.h"
#include "numexpr.h"
#include "program.h"

/* Most positional arguments of a compiled builtin call (eval_call's direct
 * route takes as many). */
#define CC_MAX_ARGS 8

typedef struct CC {
    unsigned char *buf;
    uint32_t len, cap;
    AstNode **later;        /* C_AST nodes whose subtrees are compiled next */
    uint32_t nlater, cap_later;
    uint32_t *memo_at;      /* hash table: offset of a C_MEMO record + 1 (0: empty) */
    uint32_t memo_cap;      /* its size (a power of two, or 0) */
    uint32_t nmemos;        /* memo cells given out */
    uint32_t *memo_recs;    /* offsets of the C_MEMO records */
    uint32_t nmemo_recs, cap_memo_recs;
    uint32_t *look_recs;    /* offsets of the C_LOOKUP records of literal keys */
    uint32_t nlook_recs, cap_look_recs;
} CC;

static CRec *rec(CC *c, uint32_t off) { return (CRec *)(void *)(c->buf + off); }

/* FNV-1a over [len] bytes. */
static uint64_t hash_bytes(const unsigned char *p, size_t len)
{
    uint64_t h = UINT64_C(0xcbf29ce484222325);
    for (size_t i = 0; i < len; i++) h = (h ^ p[i]) * UINT64_C(0x100000001b3);
    return h;
}

/* The memo cell for the NumExpr just copied to the C_MEMO record at
 * [off]: that of an earlier record with the same instructions, else a new
 * one. */
static uint32_t memo_cell(CC *c, uint32_t off)
{
    if (2 * (c->nmemos + 1) > c->memo_cap) {
        uint32_t cap = c->memo_cap ? 2 * c->memo_cap : 64;
        uint32_t *t = mem_calloc(cap, sizeof *t);
        for (uint32_t i = 0; i < c->memo_cap; i++) {
            if (!c->memo_at[i]) continue;
            const NumExpr *x = (const NumExpr *)(const void *)(c->buf + c->memo_at[i] - 1 + sizeof(CRec));
            uint32_t h = (uint32_t)hash_bytes((const unsigned char *)x, numexpr_size(x)) & (cap - 1);
            while (t[h]) h = (h + 1) & (cap - 1);
            t[h] = c->memo_at[i];
        }
        free(c->memo_at);
        c->memo_at = t;
        c->memo_cap = cap;
    }
    const NumExpr *x = (const NumExpr *)(const void *)(c->buf + off + sizeof(CRec));
    size_t size = numexpr_size(x);
    uint32_t h = (uint32_t)hash_bytes((const unsigned char *)x, size) & (c->memo_cap - 1);
    for (; c->memo_at[h]; h = (h + 1) & (c->memo_cap - 1)) {
        uint32_t o = c->memo_at[h] - 1;
        const NumExpr *y = (const NumExpr *)(const void *)(c->buf + o + sizeof(CRec));
        if (numexpr_size(y) == size && memcmp(x, y, size) == 0) return rec(c, o)->n;
    }
    c->memo_at[h] = off + 1;
    return c->nmemos++;
}

/* [size] zeroed bytes at the end of the block (8-byte aligned); returns
 * their offset. */
static uint32_t reserve(CC *c, size_t size)
{
    size = (size + 7) & ~(size_t)7;
    while (c->len + size > c->cap) {
        c->cap = c->cap ? c->cap * 2 : 256;
        c->buf = mem_realloc(c->buf, c->cap);
    }
    uint32_t off = c->len;
    memset(c->buf + off, 0, size);
    c->len += (uint32_t)size;
    return off;
}


/* The builtin a callee resolves to at load time, or NULL. */
static const Builtin *const_builtin(const AstNode *fn)
{
    if (fn->kind != AST_LITERAL && (fn->kind != AST_NAME || fn->scope != SCOPE_CONST)) return NULL;
    const Vec *v = fn->value;
    if (!vec_is_obj(v) || v->len != 1 || vec_celems(v)[0].kind != EL_FUNC) return NULL;
    return vec_celems(v)[0].func->bi;
}

/* True when [n] has a record of its own kind (not C_AST). */
static bool compilable(const AstNode *n)
{
    if (n->fast || n->aux) return false;
    switch ((AstKind)n->kind) {
    case AST_SEQUENCE:
    case AST_APPEND:
        return true;
    case AST_LET:
        if (n->op != 0) return false;   /* `let stable`: stable.h */
        for (uint32_t i = 0; i < n->nkids; i++)
            if (!n->kids[i] || n->kids[i]->kind != AST_BINDING || n->kids[i]->nnames != 1) return false;
        return true;
    case AST_ATTRIBUTES:
        for (uint32_t i = 0; i < n->nkids; i++)
            if (!n->kids[i] || n->kids[i]->kind != AST_BINDING || n->kids[i]->nnames < 1) return false;
        return true;
    case AST_CALL:
        return n->count == n->nkids && n->nkids <= CC_MAX_ARGS && const_builtin(n->a);
    case AST_LOOKUP:
        return n->a != NULL;
    case AST_INDEX:
        return n->a && n->b;
    case AST_IFELSE:
        for (uint32_t i = 0; i < n->nkids; i++)
            if (!n->kids[i]) return false;
        return true;
    case AST_BINOP:
        return n->a && n->b && (n->b->kind != AST_BINOP || (n->b->a && n->b->b));
    default:
        return false;
    }
}

static uint32_t emit(CC *c, const AstNode *n);

/* True when the bindings of [n] (AST_ATTRIBUTES) name pairwise different
 * attributes. */
static bool distinct_names(const AstNode *n)
{
    for (uint32_t i = 0; i < n->nkids; i++)
        for (uint32_t j = 0; j < i; j++)
            if (str_eq(n->kids[i]->names[0], n->kids[j]->names[0])) return false;
    return true;
}

/* The node of [n] when it is a literal holding one node, else NULL. */
static const Node *literal_node(const AstNode *n)
{
    if (!n || n->kind != AST_LITERAL || !vec_is_obj(n->value) || n->value->len != 1) return NULL;
    const Elem *e = vec_celems(n->value);
    return e->kind == EL_NODE ? e->node : NULL;
}

/* True when [n] (AST_ATTRIBUTES) sets attributes of a literal holding one
 * node, pairwise different and none of them the node's own: each is then
 * added to its copy without a search (C_ATTRS pad 1). */
static bool new_names_on_literal(const AstNode *n)
{
    const Node *l = literal_node(n->a);
    if (!l || !distinct_names(n)) return false;
    for (uint32_t i = 0; i < n->nkids; i++)
        for (uint32_t j = 0; j < l->nattrs; j++)
            if (str_eq(n->kids[i]->names[0], l->attrs[j].name)) return false;
    return true;
}

/* True when [n] is a literal holding one node with no tags, attributes or
 * children (`!ellipse`). */
static bool bare_node(const AstNode *n)
{
    const Node *l = literal_node(n);
    return l && !l->ntags && !l->nattrs && !l->nchildren;
}

static uint32_t emit_ast(CC *c, const AstNode *n)
{
    uint32_t off = reserve(c, sizeof(CRec));
    rec(c, off)->op = C_AST;
    rec(c, off)->p.node = n;
    if (c->nlater == c->cap_later) {
        c->cap_later = c->cap_later ? c->cap_later * 2 : 16;
        c->later = mem_realloc_array(c->later, c->cap_later, sizeof *c->later);
    }
    c->later[c->nlater++] = (AstNode *)n;
    return off;
}

/* Emit the record of [n] (and below); returns its offset. */
static uint32_t emit(CC *c, const AstNode *n)
{
    uint32_t off, t;
    if (!n) {
        off = reserve(c, sizeof(CRec));
        rec(c, off)->op = C_LIT;
        return off;
    }
    if (n->fast == 1 || numexpr_compile((AstNode *)n)) {
        const NumExpr *x = numexpr_of(n);
        size_t size = numexpr_size(x);
        bool memo = numexpr_memoizable(x);
        off = reserve(c, sizeof(CRec) + size + (memo ? sizeof(CMemoHint) : 0));
        rec(c, off)->op = C_NUM;
        rec(c, off)->p.node = n;
        memcpy(c->buf + off + sizeof(CRec), x, size);
        if (memo) {
            rec(c, off)->op = C_MEMO;
            rec(c, off)->n = memo_cell(c, off);
            if (c->nmemo_recs == c->cap_memo_recs) {
                c->cap_memo_recs = c->cap_memo_recs ? 2 * c->cap_memo_recs : 64;
                c->memo_recs = mem_realloc_array(c->memo_recs, c->cap_memo_recs, sizeof *c->memo_recs);
            }
            c->memo_recs[c->nmemo_recs++] = off;
        }
        return off;
    }
    switch ((AstKind)n->kind) {
    case AST_LITERAL:
        off = reserve(c, sizeof(CRec));
        rec(c, off)->op = C_LIT;
        rec(c, off)->p.lit = n->value;
        return off;
    case AST_NAME:
        off = reserve(c, sizeof(CRec));
        switch (n->scope) {
        case SCOPE_LOCAL: rec(c, off)->op = C_LOCAL; rec(c, off)->n = (uint32_t)n->slot; break;
        case SCOPE_GLOBAL: rec(c, off)->op = C_GLOBAL; rec(c, off)->n = (uint32_t)n->slot; break;
        case SCOPE_CONST: rec(c, off)->op = C_LIT; rec(c, off)->p.lit = n->value; break;
        default: rec(c, off)->op = C_LIT; break;
        }
        return off;
    default:
        break;
    }
    if (!compilable(n)) return emit_ast(c, n);
    switch ((AstKind)n->kind) {
    case AST_SEQUENCE:
        off = reserve(c, sizeof(CRec) + n->nkids * sizeof(uint32_t));
        rec(c, off)->op = C_SEQ;
        rec(c, off)->n = n->nkids;
        for (uint32_t i = 0; i < n->nkids; i++) {
            t = emit(c, n->kids[i]);
            ((uint32_t *)(void *)(c->buf + off + sizeof(CRec)))[i] = t;
        }
        return off;
    case AST_LET:
        off = reserve(c, sizeof(CRec) + sizeof(CLetTail) + n->nkids * sizeof(CBind));
        rec(c, off)->op = C_LET;
        rec(c, off)->n = n->nkids;
        for (uint32_t i = 0; i < n->nkids; i++) {
            t = emit(c, n->kids[i]->a);
            CLetTail *lt = (CLetTail *)(void *)(c->buf + off + sizeof(CRec));
            lt->binds[i].slot = n->kids[i]->slots[0];
            lt->binds[i].off = t;
        }
        t = emit(c, n->a);
        ((CLetTail *)(void *)(c->buf + off + sizeof(CRec)))->body = t;
        return off;
    case AST_ATTRIBUTES:
        off = reserve(c, sizeof(CRec) + sizeof(CAttrsTail) + n->nkids * sizeof(CAttr));
        rec(c, off)->n = n->nkids;
        if (bare_node(n->a) && distinct_names(n)) {
            rec(c, off)->op = C_NEWNODE;
            rec(c, off)->p.kind = vec_celems(n->a->value)[0].node->kind;
            t = 0;
        } else {
            rec(c, off)->op = C_ATTRS;
            rec(c, off)->pad = new_names_on_literal(n);
            t = emit(c, n->a);
        }
        ((CAttrsTail *)(void *)(c->buf + off + sizeof(CRec)))->node = t;
        for (uint32_t i = 0; i < n->nkids; i++) {
            t = emit(c, n->kids[i]->a);
            CAttrsTail *at = (CAttrsTail *)(void *)(c->buf + off + sizeof(CRec));
            at->attrs[i].name = n->kids[i]->names[0];
            at->attrs[i].off = t;
        }
        return off;
    case AST_CALL:
        off = reserve(c, sizeof(CRec) + n->nkids * sizeof(uint32_t));
        rec(c, off)->op = C_CALLBI;
        rec(c, off)->n = n->nkids;
        rec(c, off)->p.bi = const_builtin(n->a);
        /* one argument to a builtin with a numeric route, or several to
         * one with a route for them all (evalrun.c) */
        rec(c, off)->pad = n->nkids == 1 && bi_nums_route(const_builtin(n->a)) ? 1
                         : bi_args_route(const_builtin(n->a), n->nkids)       ? 2 : 0;
        /* (pad 1: its route kept, bi_nums_route_id) */
        rec(c, off)->aux = rec(c, off)->pad == 1 ? bi_nums_route_id(const_builtin(n->a)) : 0;
        for (uint32_t i = 0; i < n->nkids; i++) {
            t = emit(c, n->kids[i]);
            ((uint32_t *)(void *)(c->buf + off + sizeof(CRec)))[i] = t;
        }
        return off;
    case AST_LOOKUP:
        off = reserve(c, sizeof(CRec) + sizeof(uint32_t));
        rec(c, off)->op = C_LOOKUP;
        rec(c, off)->p.node = n;
        rec(c, off)->n = CLOOK_NONE;   /* (a cell is given when relocated) */
        t = emit(c, n->a);
        ((uint32_t *)(void *)(c->buf + off + sizeof(CRec)))[0] = t;
        /* a key of constants and names alone (`:dot;i`): read directly */
        rec(c, off)->pad = rec(c, t)->op == C_NUM && numexpr_leaves((const NumExpr *)(const void *)(rec(c, t) + 1));
        return off;
    case AST_INDEX:
        off = reserve(c, sizeof(CRec) + 2 * sizeof(uint32_t));
        rec(c, off)->op = C_INDEX;
        rec(c, off)->p.node = n;
        /* eval_node's AST_INDEX: a literal range index converts to 64 bits */
        rec(c, off)->pad = ast_index_is_range(n->b);
        t = emit(c, n->a);
        ((uint32_t *)(void *)(c->buf + off + sizeof(CRec)))[0] = t;
        t = emit(c, n->b);
        ((uint32_t *)(void *)(c->buf + off + sizeof(CRec)))[1] = t;
        return off;
    case AST_IFELSE: {
        uint32_t pairs = n->nkids / 2;
        off = reserve(c, sizeof(CRec) + (2 * pairs + 1) * sizeof(uint32_t));
        rec(c, off)->op = C_IF;
        rec(c, off)->n = pairs;
        for (uint32_t i = 0; i < 2 * pairs; i++) {
            t = emit(c, n->kids[i]);
            ((uint32_t *)(void *)(c->buf + off + sizeof(CRec)))[i] = t;
        }
        t = n->a ? emit(c, n->a) : CREC_NONE;
        ((uint32_t *)(void *)(c->buf + off + sizeof(CRec)))[2 * pairs] = t;
        return off;
    }
    case AST_BINOP: {
        /* eval_binop's forms, its operands in its order */
        const AstNode *opnd[3] = {n->a, n->b, NULL};
        uint8_t form = BINOP_PLAIN;
        const AstNode *rb = n->b;
        if (n->op == OP_POW && ast_literal_two(rb)) {
            form = BINOP_SQUARE;
            opnd[1] = NULL;
        } else if (n->op == OP_ADD && rb->kind == AST_BINOP && rb->op == OP_MUL) {
            form = BINOP_ADD_MUL;
            opnd[1] = rb->a;
            opnd[2] = rb->b;
        } else if (n->op == OP_ADD && rb->kind == AST_BINOP && rb->op == OP_POW && ast_literal_two(rb->b)) {
            form = BINOP_ADD_SQUARE;
            opnd[1] = rb->a;
        }
        uint32_t count = form == BINOP_SQUARE ? 1 : form == BINOP_ADD_MUL ? 3 : 2;
        off = reserve(c, sizeof(CRec) + count * sizeof(uint32_t));
        rec(c, off)->op = C_BINOP;
        rec(c, off)->pad = form;
        rec(c, off)->n = n->op;
        for (uint32_t i = 0; i < count; i++) {
            t = emit(c, opnd[i]);
            ((uint32_t *)(void *)(c->buf + off + sizeof(CRec)))[i] = t;
        }
        return off;
    }
    case AST_APPEND:
        off = reserve(c, sizeof(CRec) + 2 * sizeof(uint32_t));
        rec(c, off)->op = C_APPEND;
        t = emit(c, n->a);
        ((uint32_t *)(void *)(c->buf + off + sizeof(CRec)))[0] = t;
        t = emit(c, n->b);
        ((uint32_t *)(void *)(c->buf + off + sizeof(CRec)))[1] = t;
        return off;
    default:
        return emit_ast(c, n);
    }
}

static void compile_children(AstNode *n, const KernelOptions *ko);

/* Keep memo cells only where several records share them (the same
 * expression of engine names at several places, e.g. in the bodies of an
 * unrolled loop): a record of its own is run once a frame and would only
 * pay for the bookkeeping. Those go back to C_NUM; the cells left are
 * numbered again from 0. */
static void share_memos(CC *c)
{
    uint32_t *uses = mem_calloc(c->nmemos ? c->nmemos : 1, sizeof *uses);
    uint32_t *renum = mem_calloc(c->nmemos ? c->nmemos : 1, sizeof *renum);
    for (uint32_t i = 0; i < c->nmemo_recs; i++) uses[rec(c, c->memo_recs[i])->n]++;
    uint32_t kept = 0;
    for (uint32_t m = 0; m < c->nmemos; m++) renum[m] = uses[m] >= 2 ? kept++ : UINT32_MAX;
    for (uint32_t i = 0; i < c->nmemo_recs; i++) {
        CRec *r = rec(c, c->memo_recs[i]);
        if (renum[r->n] == UINT32_MAX) {
            r->op = C_NUM;
            r->n = 0;
        } else {
            r->n = renum[r->n];
        }
    }
    c->nmemos = kept;
    free(uses);
    free(renum);
}

/* Append offset [off] to [c]'s list of C_MEMO records. */
static void push_memo_rec(CC *c, uint32_t off)
{
    if (c->nmemo_recs == c->cap_memo_recs) {
        c->cap_memo_recs = c->cap_memo_recs ? 2 * c->cap_memo_recs : 64;
        c->memo_recs = mem_realloc_array(c->memo_recs, c->cap_memo_recs, sizeof *c->memo_recs);
    }
    c->memo_recs[c->nmemo_recs++] = off;
}

/* Copy the record at [off] of [c], and the records below it in the same
 * order, to the end of [d]; returns its offset there. A C_MEMO record
 * keeps only its header and gets room for its CMemoHint: its NumExpr,
 * which [expr_src] (per cell) records the first place of, is kept once per
 * cell after the code (finish_memos). The records that C_MEMOs went back
 * to C_NUM (share_memos) lose the room they had for it. */
static uint32_t relocate(const CC *c, CC *d, uint32_t off, uint32_t *expr_src)
{
    const CRec *r = crec(c->buf, off);
    const uint32_t *k = (const uint32_t *)(const void *)(r + 1);
    uint32_t o, t, count;
    size_t size;
    switch (r->op) {
    case C_MEMO:
        o = reserve(d, sizeof(CRec) + sizeof(CMemoHint));
        *rec(d, o) = *r;
        rec(d, o)->aux = (uint16_t)numexpr_depth((const NumExpr *)(const void *)(r + 1));
        if (expr_src[r->n] == UINT32_MAX) expr_src[r->n] = off + (uint32_t)sizeof(CRec);
        push_memo_rec(d, o);
        return o;
    case C_NUM:
        size = sizeof(CRec) + numexpr_size((const NumExpr *)(const void *)(r + 1));
        o = reserve(d, size);
        memcpy(d->buf + o, r, size);
        return o;
    case C_SEQ:
    case C_CALLBI:
    case C_APPEND:
    case C_LOOKUP:
    case C_INDEX:
    case C_IF:
    case C_BINOP:
        count = r->op == C_APPEND || r->op == C_INDEX ? 2
              : r->op == C_BINOP ? binop_operands(r)
              : r->op == C_LOOKUP ? 1 : r->op == C_IF ? 2 * r->n + 1 : r->n;
        o = reserve(d, sizeof(CRec) + count * sizeof(uint32_t));
        *rec(d, o) = *r;
        for (uint32_t i = 0; i < count; i++) {
            t = k[i] == CREC_NONE ? CREC_NONE : relocate(c, d, k[i], expr_src);
            ((uint32_t *)(void *)(d->buf + o + sizeof(CRec)))[i] = t;
        }
        if (r->op == C_LOOKUP && rec(d, ((uint32_t *)(void *)(d->buf + o + sizeof(CRec)))[0])->op == C_LIT) {
            /* a literal key: a lookup cell (finish_cells) */
            if (d->nlook_recs == d->cap_look_recs) {
                d->cap_look_recs = d->cap_look_recs ? 2 * d->cap_look_recs : 16;
                d->look_recs = mem_realloc_array(d->look_recs, d->cap_look_recs, sizeof *d->look_recs);
            }
            d->look_recs[d->nlook_recs++] = o;
        }
        return o;
    case C_LET: {
        const CLetTail *lt = (const CLetTail *)(const void *)(r + 1);
        o = reserve(d, sizeof(CRec) + sizeof(CLetTail) + r->n * sizeof(CBind));
        *rec(d, o) = *r;
        for (uint32_t i = 0; i < r->n; i++) {
            t = relocate(c, d, lt->binds[i].off, expr_src);
            CLetTail *dt = (CLetTail *)(void *)(d->buf + o + sizeof(CRec));
            dt->binds[i].slot = lt->binds[i].slot;
            dt->binds[i].off = t;
        }
        t = relocate(c, d, lt->body, expr_src);
        ((CLetTail *)(void *)(d->buf + o + sizeof(CRec)))->body = t;
        return o;
    }
    case C_ATTRS:
    case C_NEWNODE: {
        const CAttrsTail *at = (const CAttrsTail *)(const void *)(r + 1);
        o = reserve(d, sizeof(CRec) + sizeof(CAttrsTail) + r->n * sizeof(CAttr));
        *rec(d, o) = *r;
        t = r->op == C_ATTRS ? relocate(c, d, at->node, expr_src) : 0;
        ((CAttrsTail *)(void *)(d->buf + o + sizeof(CRec)))->node = t;
        for (uint32_t i = 0; i < r->n; i++) {
            t = relocate(c, d, at->attrs[i].off, expr_src);
            CAttrsTail *dt = (CAttrsTail *)(void *)(d->buf + o + sizeof(CRec));
            dt->attrs[i].name = at->attrs[i].name;
            dt->attrs[i].off = t;
        }
        return o;
    }
    default:   /* C_AST, C_LIT, C_LOCAL, C_GLOBAL */
        o = reserve(d, sizeof(CRec));
        *rec(d, o) = *r;
        return o;
    }
}

/* The CMemoHint of each C_MEMO record of [c] (relocated). */
static void memo_hints(CC *c)
{
    uint32_t n = c->nmemo_recs;
    for (uint32_t i = 0; i < n; i++) {
        CMemoHint *h = (CMemoHint *)(void *)(c->buf + c->memo_recs[i] + sizeof(CRec));
        h->cell_near = i + MEMO_AHEAD < n ? rec(c, c->memo_recs[i + MEMO_AHEAD])->n : CMEMO_NONE;
        h->cell_far = i + 2 * MEMO_AHEAD < n ? rec(c, c->memo_recs[i + 2 * MEMO_AHEAD])->n : CMEMO_NONE;
    }
}

/* The [nmemos] memo cells of the relocated block [d]: each cell's NumExpr
 * (at [expr_src] in [c]) copied once after the code, the names it reads;
 * then, in the same allocation, a zeroed lookup cell for each C_LOOKUP
 * record of a literal key, whose n becomes its cell's byte offset. */
static CMemo *finish_cells(const CC *c, CC *d, uint32_t nmemos, const uint32_t *expr_src)
{
    const uint32_t nlooks = d->nlook_recs;
    if (!nmemos && !nlooks) return NULL;
    size_t size = nmemos * sizeof(CMemo) + nlooks * sizeof(StateCached);
    size = (size + 63) & ~(size_t)63;   /* (aligned_alloc's rule) */
    CMemo *m = aligned_alloc(64, size);
    if (!m) mem_oom();
    memset(m, 0, size);
    for (uint32_t i = 0; i < nlooks; i++) {
        size_t at = nmemos * sizeof(CMemo) + i * sizeof(StateCached);
        rec(d, d->look_recs[i])->n = at < CLOOK_NONE ? (uint32_t)at : CLOOK_NONE;
    }
    for (uint32_t i = 0; i < nmemos; i++) {
        const NumExpr *x = (const NumExpr *)(const void *)(c->buf + expr_src[i]);
        size_t xs = numexpr_size(x);
        uint32_t o = reserve(d, xs);
        memcpy(d->buf + o, x, xs);
        m[i].expr = o;
        m[i].nkeys = numexpr_globals((const NumExpr *)(const void *)(d->buf + o), m[i].names);
    }
    return m;
}

/* AstNode.aux_free of a region: the kept results, then the block. */
static void cblock_free(void *p)
{
    CBlock *b = p;
    for (uint32_t i = 0; i < b->nmemos; i++) vec_release(b->memos[i].value);
    if (b->nlooks) {   /* (memos is NULL without cells of either kind) */
        StateCached *looks = (StateCached *)(void *)(b->memos + b->nmemos);
        for (uint32_t i = 0; i < b->nlooks; i++) state_cached_release(&looks[i]);
    }
    free(b->memos);
    free(b);
}

void evalcode_compile_tree(AstNode *n, const KernelOptions *ko)
{
    if (!n) return;
    if (numexpr_compile(n)) return;
    if (!compilable(n)) {
        compile_children(n, ko);
        return;
    }
    CC c = {0}, d = {0};
    emit(&c, n);
    share_memos(&c);
    /* the block as it will run: the same records, C_MEMO ones without
     * their NumExpr */
    uint32_t *expr_src = mem_alloc((c.nmemos ? c.nmemos : 1) * sizeof *expr_src);
    for (uint32_t i = 0; i < c.nmemos; i++) expr_src[i] = UINT32_MAX;
    relocate(&c, &d, 0, expr_src);
    memo_hints(&d);
    CMemo *memos = finish_cells(&c, &d, c.nmemos, expr_src);
    CBlock *b = mem_alloc(sizeof *b + d.len);
    b->nmemos = c.nmemos;
    b->nlooks = d.nlook_recs;
    b->len = d.len;
    b->memos = memos;
    memcpy(b->code, d.buf, d.len);
    free(expr_src);
    free(c.buf);
    free(c.memo_at);
    free(c.memo_recs);
    free(d.buf);
    free(d.memo_recs);
    free(d.look_recs);
    n->aux = b;
    n->aux_free = cblock_free;
    n->fast = 2;
    for (uint32_t i = 0; i < c.nlater; i++) compile_children(c.later[i], ko);
    free(c.later);
}

/* Compile the regions below [n] (whose own kind has no record). */
static void compile_children(AstNode *n, const KernelOptions *ko)
{
    if (n->fast == 1) return;   /* a compiled numeric subtree: all done */
    evalcode_compile_tree(n->a, ko);
    evalcode_compile_tree(n->b, ko);
    evalcode_compile_tree(n->c, ko);
    for (uint32_t i = 0; i < n->nkids; i++) evalcode_compile_tree(n->kids[i], ko);
    if (n->kind == AST_FOR && n->b && n->b->fast == 2) kernel_compile_for(n, ko);
}
