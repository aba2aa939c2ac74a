/* kernel.c: loop kernels (kernel.h): compiling a loop body's numeric
 * records into register expressions, and running a loop with them.
 */
#include "kernel.h"

#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "builtins.h"
#include "eval_internal.h"
#include "evalcode.h"
#include "mem.h"
#include "numexpr.h"
#include "pool.h"
#include "workers.h"

/* Most registers an expression of a kernel may read (more: not taken). */
#define K_MAX_IN 16
/* Most registers of an iteration (past it, no kernel). */
#define K_MAX_REGS (1u << 20)
/* Work (numexpr_cost units) below which a loop runs without its kernel:
 * setting up the chunks would cost about as much as it saves. */
#define K_MIN_WORK 2048
/* Work of a chunk, the unit handed to a thread: large enough that taking
 * it costs little, small enough that the caller soon has one to run. */
#define K_CHUNK_WORK 24576
/* Most bytes of registers computed ahead (a loop longer than this in
 * registers is run as several windows, one after the other). */
#define K_WINDOW_BYTES (2u << 20)
/* Registers of the file during compilation: outer names are numbered
 * from K_OUTER_TAG, outputs from 0 (renumbered at the end). */
#define K_OUTER_TAG (1 << 30)
#define K_NAME_TAG (1 << 29)

typedef struct KExpr {
    NumExpr *x;         /* register copy (numexpr_to_regs), or NULL: */
    const BiVecKernel *vk;  /* a builtin's numeric kernel, of the outputs of
                               expression [arg] (its inputs) */
    uint32_t arg;
    uint32_t out;       /* its first output register */
    uint32_t nout;
    uint32_t in;        /* its inputs: kernel->in[in .. in + nin) */
    uint32_t nin;
} KExpr;

struct LoopKernel {
    uint32_t k;         /* the loop's names per iteration: registers 0..k */
    uint32_t nouter;    /* names from outside: registers k .. k + nouter */
    int32_t *outer;     /* each one's local slot, or -1 - its global index */
    uint32_t nregs;     /* registers of an iteration */
    KExpr *ex;          /* in evaluation order */
    uint32_t nex;
    int32_t *in;        /* the expressions' input registers */
    uint64_t cost;      /* numexpr_cost of an iteration */
    uint8_t *name_read; /* per loop name: read by a record the kernel does not
                           hold (else a clean iteration need not bind it) */
    uint32_t nread;     /* how many are */
    uint32_t name_guard; /* the depth above the loop's at which a C_KNUM
                            record would read a name itself */
    uint32_t chunk;     /* KernelOptions.chunk, or 0 */
    uint32_t window;    /* KernelOptions.window, or 0 */
    /* A straight body (see straight()): its C_KNODE records in order, the
     * depth of each above the body's (run_rec's levels to it), and the
     * depth above the body's within which every level's guard passes */
    uint32_t *knode;    /* NULL: the body is not straight */
    uint32_t *knode_level;
    uint32_t nknode, knode_need;
    uint32_t nshared;   /* calls computed once for several (share_calls) */
};

static void kernel_free(void *p)
{
    LoopKernel *k = p;
    for (uint32_t i = 0; i < k->nex; i++) free(k->ex[i].x);
    free(k->ex);
    free(k->in);
    free(k->outer);
    free(k->name_read);
    free(k->knode);
    free(k->knode_level);
    free(k);
}

/* ====================================================================
 * Compiling
 * ==================================================================== */

/* What a name read by the body's expressions is, as a register
 * (compilation numbering): a map from the name's key (a slot, or -1 - an
 * engine name's index) to its register, or -1 for a `let` the kernel
 * does not hold. Every binding has a slot of its own (program.c) and a
 * record reads a let's slot only inside its scope, so one map serves the
 * whole walk: a slot in none of the loop's names and lets is bound
 * outside the loop. */
typedef struct KMapEnt {
    int32_t key;
    int32_t reg;
    bool used;
} KMapEnt;

typedef struct KMap {
    KMapEnt *t;
    uint32_t cap, n;    /* cap a power of two */
} KMap;

static KMapEnt *kmap_find(KMap *m, int32_t key, bool add)
{
    if (add && 2 * (m->n + 1) > m->cap) {
        uint32_t cap = m->cap ? 2 * m->cap : 64;
        KMapEnt *t = mem_calloc(cap, sizeof *t);
        for (uint32_t i = 0; i < m->cap; i++) {
            if (!m->t[i].used) continue;
            uint32_t h = (uint32_t)m->t[i].key * 2654435761u & (cap - 1);
            while (t[h].used) h = (h + 1) & (cap - 1);
            t[h] = m->t[i];
        }
        free(m->t);
        m->t = t;
        m->cap = cap;
    }
    if (!m->cap) return NULL;
    uint32_t h = (uint32_t)key * 2654435761u & (m->cap - 1);
    while (m->t[h].used && m->t[h].key != key) h = (h + 1) & (m->cap - 1);
    if (m->t[h].used) return &m->t[h];
    if (!add) return NULL;
    m->t[h] = (KMapEnt){key, -1, true};
    m->n++;
    return &m->t[h];
}

typedef struct KNum {
    uint32_t off;       /* the record */
    uint32_t ex;        /* its expression */
} KNum;

typedef struct KB {
    const AstNode *loop;
    CBlock *b;
    KMap names;         /* the names read, as registers */
    bool dry;           /* map_name only looks: whether an expression can
                           be taken, before it is */
    int32_t *outer;     /* names from outside, as LoopKernel.outer */
    uint32_t nouter, capouter;
    KExpr *ex;
    uint32_t nex, capex;
    int32_t *in;
    uint32_t nin, capin;
    uint32_t nouts;     /* outputs so far */
    KNum *knum;         /* the C_NUM records taken */
    uint32_t nknum, capknum;
    KNum *kcall;        /* the C_CALLBI records taken */
    uint32_t nkcall, capkcall;
    uint32_t *nodes;    /* the C_NEWNODE records */
    uint32_t nnodes, capnodes;
    bool full;          /* a limit was reached: take nothing more */
} KB;

#define GROW(p, n, cap)                                                \
    do {                                                               \
        if ((n) == (cap)) {                                            \
            (cap) = (cap) ? 2 * (cap) : 16;                            \
            (p) = mem_realloc_array((p), (cap), sizeof *(p));          \
        }                                                              \
    } while (0)

static CRec *krec(KB *kb, uint32_t off) { return (CRec *)(void *)(kb->b->code + off); }

/* The register of name [arg] for numexpr_to_regs (compilation
 * numbering), or -1; a name from outside is given a register (unless
 * kb->dry: then 0). */
static int32_t map_name(void *ctx, bool global, int32_t arg)
{
    KB *kb = ctx;
    const int32_t key = global ? -1 - arg : arg;
    KMapEnt *e = kmap_find(&kb->names, key, false);
    if (e) return e->reg;
    if (kb->dry) return 0;
    GROW(kb->outer, kb->nouter, kb->capouter);
    kb->outer[kb->nouter] = key;
    e = kmap_find(&kb->names, key, true);
    e->reg = K_OUTER_TAG + (int32_t)kb->nouter++;
    return e->reg;
}

/* Take the compiled expression [x] into the kernel; its expression index,
 * or -1 when it reads a name the kernel cannot hold. */
static int32_t take_expr(KB *kb, const NumExpr *x)
{
    if (kb->full) return -1;
    /* first whether it can be taken, so that a name from outside is not
     * given a register by an expression left out */
    kb->dry = true;
    NumExpr *y = numexpr_to_regs(x, map_name, kb);
    kb->dry = false;
    if (!y) return -1;
    free(y);
    y = numexpr_to_regs(x, map_name, kb);
    int32_t in[K_MAX_IN];
    uint32_t nin = numexpr_reg_reads(y, in, K_MAX_IN);
    uint32_t nout = numexpr_outputs(y);
    if (nin == UINT32_MAX || kb->nouts + nout + kb->nouter + kb->loop->nnames > K_MAX_REGS) {
        free(y);
        kb->full = true;
        return -1;
    }
    GROW(kb->ex, kb->nex, kb->capex);
    for (uint32_t i = 0; i < nin; i++) {
        GROW(kb->in, kb->nin, kb->capin);
        kb->in[kb->nin++] = in[i];
    }
    kb->ex[kb->nex] = (KExpr){y, NULL, 0, kb->nouts, nout, kb->nin - nin, nin};
    kb->nouts += nout;
    return (int32_t)kb->nex++;
}

/* Take a call of numeric kernel [vk] on the outputs of expression [arg]
 * into the kernel; its expression index, or -1. */
static int32_t take_call(KB *kb, const BiVecKernel *vk, uint32_t arg)
{
    uint32_t nout = vk->nout(kb->ex[arg].nout);
    if (kb->full || nout < 1 || nout > 16 || kb->nouts + nout + kb->nouter + kb->loop->nnames > K_MAX_REGS)
        return -1;
    GROW(kb->ex, kb->nex, kb->capex);
    kb->ex[kb->nex] = (KExpr){NULL, vk, arg, kb->nouts, nout, 0, 0};
    kb->nouts += nout;
    return (int32_t)kb->nex++;
}

/* The NumExpr of a C_MEMO record (kept once per cell after the code). */
static const NumExpr *memo_expr(KB *kb, const CRec *r)
{
    return (const NumExpr *)(const void *)(kb->b->code + kb->b->memos[r->n].expr);
}

static void walk(KB *kb, uint32_t off);

/* The output register (compilation numbering) a `let` of the record at
 * [off] binds its name to, or -1: a one-number expression the kernel
 * took. */
static int32_t let_reg(KB *kb, uint32_t off)
{
    const CRec *r = krec(kb, off);
    int32_t e = -1;
    if (r->op == C_NUM && kb->nknum && kb->knum[kb->nknum - 1].off == off)
        e = (int32_t)kb->knum[kb->nknum - 1].ex;
    else if (r->op == C_MEMO && numexpr_outputs(memo_expr(kb, r)) == 1)
        e = take_expr(kb, memo_expr(kb, r));
    if (e < 0 || kb->ex[e].nout != 1) return -1;
    return (int32_t)kb->ex[e].out;
}

static void walk(KB *kb, uint32_t off)
{
    const CRec *r = krec(kb, off);
    const uint32_t *k = (const uint32_t *)(const void *)(r + 1);
    switch (r->op) {
    case C_NUM: {
        int32_t e = take_expr(kb, (const NumExpr *)(const void *)(r + 1));
        if (e >= 0) {
            GROW(kb->knum, kb->nknum, kb->capknum);
            kb->knum[kb->nknum++] = (KNum){off, (uint32_t)e};
        }
        break;
    }
    case C_SEQ:
        for (uint32_t i = 0; i < r->n; i++) walk(kb, k[i]);
        break;
    case C_CALLBI: {
        for (uint32_t i = 0; i < r->n; i++) walk(kb, k[i]);
        const BiVecKernel *vk = r->n == 1 ? bi_vec_kernel(r->p.bi) : NULL;
        if (vk && kb->nknum && kb->knum[kb->nknum - 1].off == k[0]) {
            int32_t e = take_call(kb, vk, kb->knum[kb->nknum - 1].ex);
            if (e >= 0) {
                GROW(kb->kcall, kb->nkcall, kb->capkcall);
                kb->kcall[kb->nkcall++] = (KNum){off, (uint32_t)e};
            }
        }
        break;
    }
    case C_APPEND:
        walk(kb, k[0]);
        walk(kb, k[1]);
        break;
    case C_LET: {
        const CLetTail *t = (const CLetTail *)(const void *)(r + 1);
        for (uint32_t i = 0; i < r->n; i++) {
            walk(kb, t->binds[i].off);
            int32_t reg = let_reg(kb, t->binds[i].off);
            kmap_find(&kb->names, t->binds[i].slot, true)->reg = reg;
        }
        walk(kb, t->body);
        break;
    }
    case C_ATTRS:
    case C_NEWNODE: {
        const CAttrsTail *t = (const CAttrsTail *)(const void *)(r + 1);
        if (r->op == C_ATTRS) walk(kb, t->node);
        for (uint32_t i = 0; i < r->n; i++) walk(kb, t->attrs[i].off);
        break;
    }
    default:   /* C_AST, C_LIT, C_LOCAL, C_GLOBAL, C_MEMO; C_LOOKUP, C_INDEX,
                  C_IF and C_BINOP, which run their numbers themselves */
        break;
    }
}

/* The slots the body's records read, for C_KLET and the loop names a
 * clean iteration need not bind: a map from slot to whether a record the
 * kernel does not hold reads it (`other`), and the depth [need] (above the
 * loop's) from which a kernel record reading it would fall back and read
 * it itself. Depths: the body's root record runs at the loop's depth, a
 * composite record's parts one deeper (run_rec's depth_enter). */
typedef struct SlotUse {
    int32_t slot;       /* -1: empty */
    bool other;
    uint32_t need;
} SlotUse;

typedef struct Uses {
    SlotUse *t;
    uint32_t cap, n;    /* cap a power of two */
    bool all;           /* a function may capture any slot: every one is read */
} Uses;

static SlotUse *use_of(Uses *u, int32_t slot)
{
    if (2 * (u->n + 1) > u->cap) {
        uint32_t cap = u->cap ? 2 * u->cap : 64;
        SlotUse *t = mem_alloc(cap * sizeof *t);
        for (uint32_t i = 0; i < cap; i++) t[i].slot = -1;
        for (uint32_t i = 0; i < u->cap; i++) {
            if (u->t[i].slot < 0) continue;
            uint32_t h = (uint32_t)u->t[i].slot * 2654435761u & (cap - 1);
            while (t[h].slot >= 0) h = (h + 1) & (cap - 1);
            t[h] = u->t[i];
        }
        free(u->t);
        u->t = t;
        u->cap = cap;
    }
    uint32_t h = (uint32_t)slot * 2654435761u & (u->cap - 1);
    while (u->t[h].slot >= 0 && u->t[h].slot != slot) h = (h + 1) & (u->cap - 1);
    if (u->t[h].slot < 0) {
        u->t[h] = (SlotUse){slot, false, 0};
        u->n++;
    }
    return &u->t[h];
}

/* What [u] knows of [slot] (all zero when nothing reads it). */
static SlotUse use_find(const Uses *u, int32_t slot)
{
    if (u->all) return (SlotUse){slot, true, 0};
    if (!u->cap) return (SlotUse){slot, false, 0};
    uint32_t h = (uint32_t)slot * 2654435761u & (u->cap - 1);
    while (u->t[h].slot >= 0 && u->t[h].slot != slot) h = (h + 1) & (u->cap - 1);
    return u->t[h].slot < 0 ? (SlotUse){slot, false, 0} : u->t[h];
}

/* The slots [x] reads, read by a record the kernel does not hold
 * (other) or by a kernel record that falls back at depth [need]. */
static void use_expr(Uses *u, const NumExpr *x, bool other, uint32_t need)
{
    int32_t slots[K_MAX_IN];
    uint32_t n = numexpr_local_reads(x, slots, K_MAX_IN);
    if (n == UINT32_MAX) {
        u->all = true;
        return;
    }
    for (uint32_t i = 0; i < n; i++) {
        SlotUse *e = use_of(u, slots[i]);
        if (other) e->other = true;
        else if (need > e->need) e->need = need;
    }
}

/* The slots the AST [n] reads (a function may capture any). */
static void use_ast(Uses *u, const AstNode *n)
{
    if (!n || u->all) return;
    if (n->kind == AST_FUNCTION) {
        u->all = true;
        return;
    }
    if (n->kind == AST_NAME && n->scope == SCOPE_LOCAL) use_of(u, n->slot)->other = true;
    use_ast(u, n->a);
    use_ast(u, n->b);
    use_ast(u, n->c);
    for (uint32_t i = 0; i < n->nkids; i++) use_ast(u, n->kids[i]);
}

/* A C_LET record and its depth. */
typedef struct LetAt {
    uint32_t off, depth;
} LetAt;

/* Walk the record at [off], run at [depth] above the loop's, into [u],
 * listing the C_LETs in *[lets]. */
static void use_walk(KB *kb, Uses *u, uint32_t off, uint32_t depth, LetAt **lets, uint32_t *nlets,
                     uint32_t *caplets)
{
    const CRec *r = krec(kb, off);
    const uint32_t *k = (const uint32_t *)(const void *)(r + 1);
    const NumExpr *x = (const NumExpr *)(const void *)(r + 1);
    switch (r->op) {
    case C_LOCAL:
        use_of(u, (int32_t)r->n)->other = true;
        break;
    case C_NUM:
        use_expr(u, x, true, 0);
        break;
    case C_KNUM:
        use_expr(u, x, false, depth + numexpr_depth(x));
        break;
    case C_AST:
        use_ast(u, r->p.node);
        break;
    case C_KCALL:
        /* its argument runs only when the call falls back, one deeper */
        use_expr(u, (const NumExpr *)(const void *)(krec(kb, k[0]) + 1), false, depth + 1 + r->pad);
        break;
    case C_SEQ:
    case C_CALLBI:
        for (uint32_t i = 0; i < r->n; i++) use_walk(kb, u, k[i], depth + 1, lets, nlets, caplets);
        break;
    case C_APPEND:
    case C_INDEX:
        use_walk(kb, u, k[0], depth + 1, lets, nlets, caplets);
        use_walk(kb, u, k[1], depth + 1, lets, nlets, caplets);
        break;
    case C_LOOKUP:
        use_walk(kb, u, k[0], depth + 1, lets, nlets, caplets);
        break;
    case C_BINOP:
        for (uint32_t i = 0; i < binop_operands(r); i++) use_walk(kb, u, k[i], depth + 1, lets, nlets, caplets);
        break;
    case C_IF:
        for (uint32_t i = 0; i <= 2 * r->n; i++)
            if (k[i] != CREC_NONE) use_walk(kb, u, k[i], depth + 1, lets, nlets, caplets);
        break;
    case C_LET: {
        const CLetTail *t = (const CLetTail *)(const void *)(r + 1);
        GROW(*lets, *nlets, *caplets);
        (*lets)[(*nlets)++] = (LetAt){off, depth};
        for (uint32_t i = 0; i < r->n; i++) use_walk(kb, u, t->binds[i].off, depth + 1, lets, nlets, caplets);
        use_walk(kb, u, t->body, depth + 1, lets, nlets, caplets);
        break;
    }
    case C_ATTRS:
    case C_NEWNODE: {
        const CAttrsTail *t = (const CAttrsTail *)(const void *)(r + 1);
        if (r->op == C_ATTRS) use_walk(kb, u, t->node, depth + 1, lets, nlets, caplets);
        for (uint32_t i = 0; i < r->n; i++) use_walk(kb, u, t->attrs[i].off, depth + 1, lets, nlets, caplets);
        if (r->op == C_NEWNODE) {
            GROW(kb->nodes, kb->nnodes, kb->capnodes);
            kb->nodes[kb->nnodes++] = off;
        }
        break;
    }
    default:   /* C_LIT, C_GLOBAL, C_MEMO (engine names only) */
        break;
    }
}

/* Turn the C_NEWNODE records whose attributes are all kernel numbers or
 * memoized values into C_KNODE (evalcode.h), with the depth their
 * attributes need above the node's. */
static void mark_nodes(KB *kb)
{
    for (uint32_t i = 0; i < kb->nnodes; i++) {
        CRec *r = krec(kb, kb->nodes[i]);
        const CAttrsTail *t = (const CAttrsTail *)(const void *)(r + 1);
        uint32_t guard = 0;
        bool all = true;
        for (uint32_t k = 0; k < r->n && all; k++) {
            const CRec *a = krec(kb, t->attrs[k].off);
            uint32_t g;
            if (a->op == C_KNUM) g = numexpr_depth((const NumExpr *)(const void *)(a + 1));
            else if (a->op == C_KCALL) g = 1u + a->pad;   /* its run_rec, then its argument */
            else if (a->op == C_MEMO) g = a->aux;
            else all = false, g = 0;
            if (g > guard) guard = g;
        }
        if (all && guard <= UINT16_MAX) {
            r->op = C_KNODE;
            r->aux = (uint16_t)guard;
        }
    }
}

/* Turn the `let`s [lets] whose bindings of kernel numbers only the
 * kernel's records read into C_KLET (evalcode.h); every binding has a slot
 * of its own (program.c), so a slot's readers are in its scope. */
static void mark_lets(KB *kb, const Uses *u, const LetAt *lets, uint32_t nlets)
{
    for (uint32_t l = 0; l < nlets; l++) {
        CRec *r = krec(kb, lets[l].off);
        CLetTail *t = (CLetTail *)(void *)(r + 1);
        /* the let's parts run at depth d + 1, where run_klet checks
         * ev->depth (= the loop's + d + 1) + guard */
        const uint32_t d = lets[l].depth + 1;
        uint32_t mask = 0, guard = 0;
        for (uint32_t i = 0; i < r->n && i < 32; i++) {
            const CRec *v = krec(kb, t->binds[i].off);
            if (v->op != C_KNUM && v->op != C_MEMO) continue;
            SlotUse e = use_find(u, t->binds[i].slot);
            if (e.other) continue;
            uint32_t need = e.need;
            /* the value itself runs at the let's parts' depth (a memo's
             * record falls back past aux, as run_memo does) */
            if (v->op == C_KNUM && d + numexpr_depth((const NumExpr *)(const void *)(v + 1)) > need)
                need = d + numexpr_depth((const NumExpr *)(const void *)(v + 1));
            if (v->op == C_MEMO && d + v->aux > need)
                need = d + v->aux;
            uint32_t g = need > d ? need - d : 0;
            if (g > UINT16_MAX) continue;
            mask |= UINT32_C(1) << i;
            if (g > guard) guard = g;
        }
        if (mask) {
            r->op = C_KLET;
            r->aux = (uint16_t)guard;
            t->pad = mask;
        }
    }
}

/* A straight body's records (LoopKernel.knode), as straight() finds
 * them. */
typedef struct Straight {
    uint32_t *off, *level;
    uint32_t n, cap, need;
} Straight;

/* Whether the record at [off], run by run_rec at [level] levels above
 * the body's depth, builds the same C_KNODE records, in the same order, in
 * every clean iteration, and does nothing else: a C_KNODE that the loop's
 * cache may keep, or a sequence or a C_KLET that makes no binding (each
 * one read by the kernel's records only) of such records. Then a clean
 * iteration's value is those nodes composed (run_seq's composition of
 * one-node vectors), and only their memo attributes evaluate anything.
 * Adds the records to [st] with their levels, and to st->need each
 * level's depth guard (run_rec's level itself, run_klet's and run_knode's
 * aux above it). */
static bool straight(KB *kb, uint32_t off, uint32_t level, Straight *st)
{
    const CRec *r = krec(kb, off);
    switch (r->op) {
    case C_KNODE:
        if (r->n > KNODE_REUSE_ATTRS) return false;
        if (st->n == st->cap) {
            st->cap = st->cap ? 2 * st->cap : 16;
            st->off = mem_realloc_array(st->off, st->cap, sizeof *st->off);
            st->level = mem_realloc_array(st->level, st->cap, sizeof *st->level);
        }
        st->off[st->n] = off;
        st->level[st->n++] = level;
        if (level + r->aux > st->need) st->need = level + r->aux;
        return true;
    case C_SEQ:
        /* run_seq of one record returns its value as it is, of more the
         * composition of their values */
        for (uint32_t i = 0; i < r->n; i++)
            if (!straight(kb, ((const uint32_t *)(const void *)(r + 1))[i], level + 1, st)) return false;
        return r->n > 0;
    case C_KLET: {
        const CLetTail *t = (const CLetTail *)(const void *)(r + 1);
        if (r->n > 32 || t->pad != (r->n == 32 ? UINT32_MAX : (UINT32_C(1) << r->n) - 1)) return false;
        if (level + r->aux > st->need) st->need = level + r->aux;
        return straight(kb, t->body, level + 1, st);
    }
    default:
        return false;
    }
}

/* One call of an element function on a register that the kernel's
 * expressions make (share_calls): how many times, whether it is computed
 * with a partner (bi_kernel_pair), and the register it gets. */
typedef struct CallUse CallUse;
struct CallUse {
    NumExprCall c;
    uint32_t count;
    int32_t reg;          /* -1: not made by an expression of its own (yet) */
    CallUse *partner;     /* the other call of a pair, or NULL */
    BiKernelPair fn2;     /* on the pair's first call (a): f(x) = a(x), b(x) */
};

static uint64_t call_hash(NumExprCall c)
{
    uint64_t h = (uint64_t)(uint32_t)c.reg * 0x9e3779b97f4a7c15u;
    return h ^ ((uint64_t)(uintptr_t)c.fn * 0xc2b2ae3d27d4eb4fu);
}

/* The entry of call [c] in the open-addressing table [t] of [cap] (a power
 * of two) entries, an empty one (count 0) when it has none. */
static CallUse *call_find(CallUse *t, uint32_t cap, NumExprCall c)
{
    for (uint32_t i = (uint32_t)(call_hash(c) >> 32) & (cap - 1);; i = (i + 1) & (cap - 1))
        if (!t[i].count || (t[i].c.reg == c.reg && t[i].c.fn == c.fn)) return &t[i];
}

/* Common calls of the kernel [lk] (compiled, its registers final): an
 * element function called on the same register by two expressions of an
 * iteration, or twice by one (canvas10k's sin(phase) in a node's point and
 * in its colour), is computed once, by an expression of its own just
 * before the first that calls it, into a new register, which those
 * expressions read instead. Two functions of one register that have a
 * pair function (bi_kernel_pair: sin and cos of canvas10k's phase) are
 * computed together by one expression into two registers. The same
 * numbers: the functions', of the same argument, computed once instead of
 * twice. The expressions' inputs (for careful_iteration) are found again,
 * and the cost. */
static void share_calls(LoopKernel *lk)
{
    uint32_t ncalls = 0;
    for (uint32_t e = 0; e < lk->nex; e++)
        if (lk->ex[e].x) ncalls += numexpr_reg_calls(lk->ex[e].x, NULL, 0);
    if (ncalls < 2) return;
    uint32_t cap = 16;
    while (cap < 2 * ncalls) cap *= 2;
    CallUse *t = mem_calloc(cap, sizeof *t);
    NumExprCall *calls = NULL;
    uint32_t capcalls = 0;
    for (uint32_t e = 0; e < lk->nex; e++) {
        if (!lk->ex[e].x) continue;
        uint32_t n = numexpr_reg_calls(lk->ex[e].x, NULL, 0);
        if (n > capcalls) calls = mem_realloc_array(calls, capcalls = n, sizeof *calls);
        numexpr_reg_calls(lk->ex[e].x, calls, n);
        for (uint32_t i = 0; i < n; i++) {
            CallUse *u = call_find(t, cap, calls[i]);
            if (!u->count) *u = (CallUse){.c = calls[i], .reg = -1};
            u->count++;
        }
    }
    /* the pairs, then the registers the shared calls need */
    uint32_t nshared = 0;   /* calls made by expressions of their own: a register each */
    for (uint32_t i = 0; i < cap; i++) {
        CallUse *u = &t[i];
        BiKernel b;
        BiKernelPair f;
        if (!u->count || u->partner || !(f = bi_kernel_pair(u->c.fn, &b))) continue;
        CallUse *v = call_find(t, cap, (NumExprCall){u->c.reg, b});
        if (!v->count || v->partner) continue;
        u->partner = v;
        v->partner = u;
        u->fn2 = f;
    }
    for (uint32_t i = 0; i < cap; i++) {
        const CallUse *u = &t[i];
        if (!u->count || (u->count < 2 && !u->partner)) continue;
        nshared++;
    }
    if (!nshared || lk->nregs + nshared > K_MAX_REGS) {
        free(t);
        free(calls);
        return;
    }
    /* the new expressions, each before the first expression that makes its
     * call, their registers after the others */
    KExpr *ex = mem_calloc(lk->nex + nshared, sizeof *ex);
    uint32_t *moved = mem_alloc(lk->nex * sizeof *moved);
    uint32_t nex = 0;
    for (uint32_t e = 0; e < lk->nex; e++) {
        if (lk->ex[e].x) {
            uint32_t n = numexpr_reg_calls(lk->ex[e].x, calls, capcalls);
            for (uint32_t i = 0; i < n; i++) {
                CallUse *u = call_find(t, cap, calls[i]);
                if ((u->count < 2 && !u->partner) || u->reg >= 0) continue;
                NumExpr *x;
                uint32_t nout = 1;
                int32_t out = (int32_t)lk->nregs;
                if (u->partner) {
                    /* a(x) into out, b(x) into out + 1 */
                    CallUse *a = u->fn2 ? u : u->partner;
                    a->reg = out;
                    a->partner->reg = out + 1;
                    x = numexpr_new_call2(a->c.reg, a->fn2);
                    nout = 2;
                } else {
                    u->reg = out;
                    x = numexpr_new_call(u->c);
                }
                lk->nregs += nout;
                numexpr_set_out(x, (uint32_t)out);
                ex[nex++] = (KExpr){.x = x, .out = (uint32_t)out, .nout = nout};
            }
            for (uint32_t i = 0; i < n; i++) {
                const CallUse *u = call_find(t, cap, calls[i]);
                if (u->reg >= 0) numexpr_share_call(lk->ex[e].x, u->c, u->reg);
            }
        }
        moved[e] = nex;
        ex[nex++] = lk->ex[e];
    }
    /* a builtin's kernel names its argument's expression by index */
    for (uint32_t e = 0; e < nex; e++)
        if (!ex[e].x) ex[e].arg = moved[ex[e].arg];
    /* every expression's inputs again, and the cost */
    int32_t *in = NULL, *reads = NULL;
    uint32_t nin = 0, capin = 0, capreads = 0;
    lk->cost = 0;
    for (uint32_t e = 0; e < nex; e++) {
        KExpr *x = &ex[e];
        if (x->x) {
            const uint32_t most = ((const NumExprHead *)(const void *)x->x)->nins;
            if (most > capreads) reads = mem_realloc_array(reads, capreads = most, sizeof *reads);
            uint32_t n = numexpr_reg_reads(x->x, reads, most);
            x->in = nin;
            x->nin = n;
            for (uint32_t i = 0; i < n; i++) {
                GROW(in, nin, capin);
                in[nin++] = reads[i];
            }
            lk->cost += numexpr_cost(x->x) + x->nout;
        } else {
            lk->cost += 24 + x->nout;
        }
    }
    lk->cost += lk->nregs / 4 + 1;
    free(lk->ex);
    free(lk->in);
    lk->ex = ex;
    lk->nex = nex;
    lk->in = in;
    lk->nshared = nshared;
    free(reads);
    free(moved);
    free(calls);
    free(t);
}

/* Final register of compilation-numbered register [reg]. */
static int32_t final_reg(const KB *kb, int32_t reg)
{
    if (reg >= K_OUTER_TAG) return (int32_t)kb->loop->nnames + (reg - K_OUTER_TAG);
    if (reg >= K_NAME_TAG) return reg - K_NAME_TAG;
    return (int32_t)(kb->loop->nnames + kb->nouter) + reg;
}

static int32_t renumber(void *ctx, int32_t reg)
{
    return final_reg(ctx, reg);
}

void kernel_compile_for(AstNode *n, const KernelOptions *ko)
{
    if (ko->off || n->fast || n->aux || !n->b || n->b->fast != 2) return;
    KB kb = {.loop = n, .b = n->b->aux};
    for (uint32_t j = 0; j < n->nnames; j++)
        kmap_find(&kb.names, n->slots[j], true)->reg = K_NAME_TAG + (int32_t)j;
    walk(&kb, 0);
    free(kb.names.t);
    if (!kb.nknum) {
        for (uint32_t i = 0; i < kb.nex; i++) free(kb.ex[i].x);
        free(kb.ex);
        free(kb.in);
        free(kb.outer);
        free(kb.knum);
        free(kb.kcall);
        free(kb.nodes);
        return;
    }
    LoopKernel *lk = mem_calloc(1, sizeof *lk);
    lk->k = n->nnames;
    lk->nouter = kb.nouter;
    lk->outer = kb.outer;
    lk->nregs = n->nnames + kb.nouter + kb.nouts;
    lk->nex = kb.nex;
    lk->ex = kb.ex;
    lk->in = kb.in;
    for (uint32_t i = 0; i < kb.nin; i++) lk->in[i] = final_reg(&kb, lk->in[i]);
    for (uint32_t i = 0; i < kb.nex; i++) {
        KExpr *e = &lk->ex[i];
        e->out = (uint32_t)final_reg(&kb, (int32_t)e->out);
        if (e->x) {
            numexpr_renumber_regs(e->x, renumber, &kb);
            numexpr_set_out(e->x, e->out);
            lk->cost += numexpr_cost(e->x) + e->nout;
        } else {
            lk->cost += 24 + e->nout;
        }
    }
    lk->cost += lk->nregs / 4 + 1;
    for (uint32_t i = 0; i < kb.nknum; i++) {
        CRec *r = krec(&kb, kb.knum[i].off);
        r->op = C_KNUM;
        r->n = lk->ex[kb.knum[i].ex].out;
    }
    for (uint32_t i = 0; i < kb.nkcall; i++) {
        CRec *r = krec(&kb, kb.kcall[i].off);
        const KExpr *e = &lk->ex[kb.kcall[i].ex];
        const CRec *a = krec(&kb, ((const uint32_t *)(const void *)(r + 1))[0]);
        r->op = C_KCALL;
        r->n = e->out;
        r->aux = (uint16_t)e->nout;
        r->pad = (uint8_t)numexpr_depth((const NumExpr *)(const void *)(a + 1));
    }
    /* what reads which slot: the lets and the loop's names that only
     * the kernel's records read */
    Uses u = {0};
    LetAt *lets = NULL;
    uint32_t nlets = 0, caplets = 0;
    use_walk(&kb, &u, 0, 0, &lets, &nlets, &caplets);
    mark_lets(&kb, &u, lets, nlets);
    mark_nodes(&kb);
    free(kb.nodes);
    Straight st = {0};
    if (straight(&kb, 0, 1, &st) && st.n) {
        lk->knode = st.off;
        lk->knode_level = st.level;
        lk->nknode = st.n;
        lk->knode_need = st.need;
    } else {
        free(st.off);
        free(st.level);
    }
    lk->name_read = mem_alloc(n->nnames ? n->nnames : 1);
    for (uint32_t j = 0; j < n->nnames; j++) {
        SlotUse e = use_find(&u, n->slots[j]);
        lk->name_read[j] = e.other;
        if (e.other) lk->nread++;
        else if (e.need > lk->name_guard) lk->name_guard = e.need;
    }
    free(u.t);
    free(lets);
    free(kb.knum);
    free(kb.kcall);
    share_calls(lk);
    lk->chunk = ko->chunk;
    lk->window = ko->window;
    n->aux = lk;
    n->aux_free = kernel_free;
    n->fast = 3;
}

uint32_t kernel_shared_calls(const AstNode *n)
{
    return n->kind == AST_FOR && n->fast == 3 && n->aux ? ((const LoopKernel *)n->aux)->nshared : 0;
}

/* ====================================================================
 * Running
 * ==================================================================== */

/* Runs of loops whose nodes a scratch keeps (the least recently used
 * makes way for a new one). */
#define K_NODE_LOOPS 64

/* The caches of nodes (kernel.h KNodeCache) of one loop's [idx]-th run in
 * a frame (a loop in a function called three times a frame has three):
 * the one of even frames and the one of odd frames, or, with transient
 * trees, the one of every frame and its second (KNodeCache.alt). */
typedef struct KNodeLoop {
    const AstNode *key;     /* the loop (NULL: a free entry) */
    uint32_t idx;
    KNodeCache run[2];
    uint64_t used;          /* KernelScratch.clock at that run */
    uint64_t frame;         /* KernelScratch.frame at that run */
} KNodeLoop;

struct KernelScratch {
    unsigned char *buf;     /* malloc'd, outside the memory budget */
    size_t cap;
    bool busy;              /* a kernel's run is using it */
    bool reuse;             /* keep nodes (not FLITTER_KERNEL_REUSE=0) */
    bool transient;         /* kernel_scratch_set_transient */
    uint64_t clock;         /* loop runs that used the caches */
    uint64_t frame;         /* kernel_scratch_frame_done calls */
    bool stale;             /* kept nodes may have lost their trees since the
                               last kernel_scratch_reclaim */
    size_t held;            /* about how many bytes of blocks the kept nodes
                               hold (knode_bytes) */
    const KNodeCache *running; /* the cache the running loop fills */
    bool keyed;             /* some entry of [loops] may have a key (false:
                               none has; a frame without loop kernels then
                               does not read the 64 entries) */
    KNodeLoop loops[K_NODE_LOOPS];
};

KernelScratch *kernel_scratch_new(bool reuse)
{
    KernelScratch *k = mem_calloc(1, sizeof(KernelScratch));
    k->reuse = reuse;
    return k;
}

/* The pool block of a [size]-byte request (pool_block_size, whose
 * classes step by 16 bytes up to POOL_SMALL_MAX). */
static inline size_t knode_block(size_t size)
{
    return size <= POOL_SMALL_MAX ? (size + 15) & ~(size_t)15 : pool_block_size(size);
}

/* About the bytes of pool blocks [n] and its number attributes hold. */
static size_t knode_bytes(const Node *n)
{
    size_t b = knode_block(node_block_bytes(n));
    for (uint32_t k = 0; k < n->nattrs; k++) {
        const Vec *v = n->attrs[k].value;
        if (v && v->kind == VEC_NUM) b += knode_block(sizeof(Vec) + (size_t)v->len * sizeof(double));
    }
    return b;
}

/* Release the node of slot [s] of [c] (if any). */
static void knode_drop(KNodeCache *c, uint32_t s)
{
    Node *n = c->slot[s];
    if (!n) return;
    /* a refill may have swapped a memo value of another length: an
     * estimate, kept from going below zero */
    size_t b = knode_bytes(n);
    *c->held -= *c->held < b ? *c->held : b;
    c->slot[s] = NULL;
    node_release(n);
}

/* Release the nodes of [c] from slot [from] on. */
static void knode_trim(KNodeCache *c, uint32_t from)
{
    for (uint32_t i = from; i < c->n; i++) knode_drop(c, i);
    if (from < c->n) c->n = from;
}

static void knode_loop_clear(KNodeLoop *l)
{
    for (int r = 0; r < 2; r++) {
        knode_trim(&l->run[r], 0);
        free(l->run[r].slot);
    }
    *l = (KNodeLoop){0};
}

void kernel_scratch_clear(KernelScratch *k)
{
    if (!k) return;
    for (int i = 0; i < K_NODE_LOOPS; i++) knode_loop_clear(&k->loops[i]);
}

const size_t *kernel_scratch_held(const KernelScratch *k) { return &k->held; }

void kernel_scratch_reclaim(void *ctx)
{
    KernelScratch *k = ctx;
    /* with room in the budget for all of them, nothing the kept nodes
     * hold can make a request fail that would succeed without them */
    if (!k || !k->stale || mem_room(k->held)) return;
    k->stale = false;
    for (int i = 0; i < K_NODE_LOOPS; i++) {
        for (int r = 0; r < 2; r++) {
            KNodeCache *c = &k->loops[i].run[r];
            /* the running loop's nodes still to come are refilled, not
             * built: they need no memory (a second cache's, with transient
             * trees, are spares, released like any other cache's) */
            for (uint32_t s = c == k->running ? c->next : 0; s < c->n; s++)
                if (c->slot[s] && c->slot[s]->refs == 1) knode_drop(c, s);
        }
    }
}

void kernel_scratch_frame_done(KernelScratch *k)
{
    if (!k) return;
    k->stale = true;
    if (k->keyed) {
        bool keyed = false;
        for (int i = 0; i < K_NODE_LOOPS; i++) {
            if (k->loops[i].key && k->loops[i].frame != k->frame) knode_loop_clear(&k->loops[i]);
            keyed |= k->loops[i].key != NULL;
        }
        k->keyed = keyed;
    }
    k->frame++;
}

void kernel_scratch_set_transient(KernelScratch *k, bool transient) { k->transient = transient; }

void kernel_scratch_free(KernelScratch *k)
{
    if (!k) return;
    kernel_scratch_clear(k);
    free(k->buf);
    free(k);
}

/* The cache this run of loop [n] fills, holding the nodes of its run
 * before the last (with transient trees, of its last run, and run[1] as
 * its second cache). */
static KNodeCache *knode_cache(KernelScratch *k, const AstNode *n)
{
    /* the loop's runs so far in this frame, each of which took an entry */
    uint32_t idx = 0;
    for (int i = 0; i < K_NODE_LOOPS; i++) idx += k->loops[i].key == n && k->loops[i].frame == k->frame;
    KNodeLoop *l = NULL, *oldest = &k->loops[0];
    for (int i = 0; i < K_NODE_LOOPS && !l; i++) {
        if (k->loops[i].key == n && k->loops[i].idx == idx) l = &k->loops[i];
        else if (k->loops[i].used < oldest->used) oldest = &k->loops[i];
    }
    if (!l) {
        l = oldest;
        knode_loop_clear(l);
        l->key = n;
        l->idx = idx;
        k->keyed = true;
    }
    l->used = ++k->clock;
    l->frame = k->frame;
    KNodeCache *c = &l->run[k->transient ? 0 : k->frame & 1];
    c->alt = k->transient ? &l->run[1] : NULL;
    c->next = 0;
    l->run[0].held = l->run[1].held = &k->held;
    k->running = c;
    return c;
}

/* Room in [c] for slots up to [s] (new ones empty); false when it cannot
 * grow. */
static bool knode_cache_reach(KNodeCache *c, uint32_t s)
{
    if (s < c->n) return true;
    if (s >= c->cap) {
        uint32_t cap = c->cap ? c->cap : 256;
        while (cap <= s && cap < UINT32_MAX / 2) cap *= 2;
        if (cap <= s) return false;
        Node **slot = realloc(c->slot, cap * sizeof *slot);
        if (!slot) return false;
        c->slot = slot;
        c->cap = cap;
    }
    while (c->n <= s) c->slot[c->n++] = NULL;
    return true;
}

bool knode_cache_swap_alt(KNodeCache *c, uint32_t s)
{
    KNodeCache *a = c->alt;
    if (!a || s > c->n || !knode_cache_reach(c, s) || !knode_cache_reach(a, s)) return false;
    Node *n = c->slot[s];
    c->slot[s] = a->slot[s];
    a->slot[s] = n;
    return true;
}

/* The end of a run that filled [c] up to slot [next]: the nodes past it
 * are not built again this run. Released, or with a second cache (alt),
 * moved to its slots that are empty, so that a frame whose iterations
 * were not clean (which take no slot) leaves the next frame the nodes to
 * refill, as the cache of the other frame parity does. */
static void knode_trim_run(KNodeCache *c, uint32_t next)
{
    for (uint32_t s = next; c->alt && s < c->n; s++) {
        if (!c->slot[s] || !knode_cache_reach(c->alt, s) || c->alt->slot[s]) continue;
        c->alt->slot[s] = c->slot[s];
        c->slot[s] = NULL;
    }
    knode_trim(c, next);
}

bool knode_cache_put(KNodeCache *c, uint32_t s, struct Node *node)
{
    if (s > c->n || !knode_cache_reach(c, s)) return false;
    knode_drop(c, s);
    c->slot[s] = node_retain(node);
    *c->held += knode_bytes(node);
    return true;
}

/* A window of iterations being computed (the context of the tasks). */
typedef struct KRun {
    const LoopKernel *lk;
    const double *src;          /* the source's numbers */
    uint32_t len;               /* how many */
    uint32_t first;             /* the window's first iteration */
    uint32_t iters;             /* iterations in the window */
    uint32_t chunk;             /* iterations a task */
    double *regs;               /* iters x nregs */
    uint8_t *ok;                /* iters x nregs */
    const double *outer;        /* the names from outside */
    const uint8_t *outer_ok;
    bool outer_clean;           /* every one of them holds a number */
    uint8_t *clean;             /* per iteration: compute_iteration's answer */
    atomic_uchar *done;         /* per task: its registers are ready */
    atomic_bool cancel;         /* the caller stopped: compute nothing more */
} KRun;

/* The registers of iteration [it] into [regs] and which of them hold
 * their numbers into [ok], one expression at a time: for an iteration
 * that lacks a name or a name from outside, or where an expression gave
 * up. */
static void careful_iteration(const KRun *kr, uint32_t it, double *regs, uint8_t *ok)
{
    const LoopKernel *lk = kr->lk;
    const uint32_t k = lk->k, p = it * (k ? k : 1);
    for (uint32_t j = 0; j < k; j++) {
        ok[j] = p + j < kr->len;
        regs[j] = ok[j] ? kr->src[p + j] : 0.0;
    }
    for (uint32_t i = 0; i < lk->nouter; i++) {
        regs[k + i] = kr->outer[i];
        ok[k + i] = kr->outer_ok[i];
    }
    for (uint32_t e = 0; e < lk->nex; e++) {
        const KExpr *x = &lk->ex[e];
        bool good;
        if (x->x) {
            good = true;
            for (uint32_t i = 0; i < x->nin; i++) good = good && ok[lk->in[x->in + i]];
            if (good) good = numexpr_run_regs(x->x, regs, regs + x->out);
        } else {
            const KExpr *a = &lk->ex[x->arg];
            good = ok[a->out] && x->vk->run(regs + a->out, a->nout, regs + x->out);
        }
        memset(ok + x->out, good, x->nout);
    }
}

/* The registers of iterations [i0, i0 + n) of the window (n at most
 * NUMEXPR_LANES), all at once, each expression for every lane in turn;
 * the lanes that lack an input or where an expression gave up are done
 * again one at a time, carefully. Sets their clean flags. */
static void compute_lanes(KRun *kr, uint32_t i0, uint32_t n)
{
    const LoopKernel *lk = kr->lk;
    const uint32_t k = lk->k, nregs = lk->nregs;
    double *regs = kr->regs + (size_t)i0 * nregs;
    uint8_t fail[NUMEXPR_LANES] = {0};
    for (uint32_t l = 0; l < n; l++) {
        double *r = regs + (size_t)l * nregs;
        const uint32_t p = (kr->first + i0 + l) * (k ? k : 1);
        fail[l] = !kr->outer_clean || p + k > kr->len;
        for (uint32_t j = 0; j < k; j++) r[j] = p + j < kr->len ? kr->src[p + j] : 0.0;
        for (uint32_t i = 0; i < lk->nouter; i++) r[k + i] = kr->outer[i];
    }
    for (uint32_t e = 0; e < lk->nex; e++) {
        const KExpr *x = &lk->ex[e];
        if (x->x) {
            numexpr_run_lanes(x->x, regs, nregs, n, fail);
        } else {
            const KExpr *a = &lk->ex[x->arg];
            for (uint32_t l = 0; l < n; l++) {
                double *r = regs + (size_t)l * nregs;
                if (!fail[l] && !x->vk->run(r + a->out, a->nout, r + x->out)) fail[l] = 1;
            }
        }
    }
    for (uint32_t l = 0; l < n; l++) {
        kr->clean[i0 + l] = !fail[l];
        if (fail[l])
            careful_iteration(kr, kr->first + i0 + l, regs + (size_t)l * nregs,
                              kr->ok + (size_t)(i0 + l) * nregs);
    }
}

/* A clean iteration of a straight body (LoopKernel.knode), within its
 * depth guards: what eval_code gives for it, without running its records
 * one by one (nothing to bind, no one-node vectors to compose): the nodes
 * of its C_KNODE records in order (knode_take, at the depth where run_rec
 * would run each: its memo attributes evaluate in the same order and at
 * the same depth). NULL, with nothing evaluated, when their vector does
 * not fit in the memory budget (eval_code then reports it). */
static Vec *straight_iteration(Eval *ev, const LoopKernel *lk, const CBlock *blk)
{
    const uint32_t nk = lk->nknode;
    if (!mem_fits(sizeof(Vec) + (size_t)nk * sizeof(Elem))) return NULL;
    Vec *v = vec_new_obj_raw(nk);
    Elem *e = vec_elems(v);
    CMemo *saved = ev->memos;
    const uint32_t depth = ev->depth;
    ev->memos = blk->memos;
    for (uint32_t j = 0; j < nk; j++) {
        ev->depth = depth + lk->knode_level[j];
        e[j].node = knode_take(ev, blk->code, crec(blk->code, lk->knode[j]));
        e[j].kind = EL_NODE;
    }
    ev->depth = depth;
    ev->memos = saved;
    ev->kstraight++;
    return v;
}

/* The first iteration (of the window) of task [t]; the window's end for
 * t = the task count. */
static uint32_t task_start(const KRun *kr, uint32_t t)
{
    uint64_t s = (uint64_t)t * kr->chunk;
    return s < kr->iters ? (uint32_t)s : kr->iters;
}

/* A task: the registers of one chunk of the window. */
static void chunk_task(void *ctx, size_t t, unsigned thread)
{
    (void)thread;
    KRun *kr = ctx;
    if (!atomic_load_explicit(&kr->cancel, memory_order_relaxed)) {
        uint32_t a = task_start(kr, (uint32_t)t), b = task_start(kr, (uint32_t)t + 1);
        for (uint32_t i = a; i < b; i += NUMEXPR_LANES)
            compute_lanes(kr, i, b - i < NUMEXPR_LANES ? b - i : NUMEXPR_LANES);
    }
    atomic_store_explicit(&kr->done[t], 1, memory_order_release);
}

Vec *kernel_eval_for(Eval *ev, const AstNode *n, const Vec *src, bool *done)
{
    const LoopKernel *lk = n->aux;
    const uint32_t len = src->len, k = n->nnames ? n->nnames : 1;
    const uint32_t iters = len / k + (len % k != 0);
    if (iters < 2 || (!lk->chunk && (uint64_t)iters * lk->cost < K_MIN_WORK)) {
        *done = false;
        return NULL;
    }
    const uint32_t nregs = lk->nregs;
    const uint64_t iter_bytes = (uint64_t)nregs * 9;
    uint64_t per_chunk = lk->chunk ? lk->chunk : K_CHUNK_WORK / lk->cost;
    if (!lk->chunk && per_chunk < NUMEXPR_LANES) per_chunk = NUMEXPR_LANES;
    /* no more than a window's bytes a chunk, whatever the lanes want */
    if (!lk->chunk && per_chunk * iter_bytes > K_WINDOW_BYTES) per_chunk = K_WINDOW_BYTES / iter_bytes;
    uint32_t chunk = per_chunk < 1 ? 1 : per_chunk > iters ? iters : (uint32_t)per_chunk;
    /* whole chunks, all of the window's bytes (flags and task ends too)
     * within K_WINDOW_BYTES (one pool block of that size, not the next) */
    uint64_t per_window = lk->window ? lk->window
                                     : (K_WINDOW_BYTES - 4096 - nregs) / (iter_bytes + 2) / chunk * chunk;
    uint32_t window = per_window < chunk ? chunk : per_window > iters ? iters : (uint32_t)per_window;
    window = (window + chunk - 1) / chunk * chunk;
    const uint32_t maxtasks = (window + chunk - 1) / chunk;
    /* the window's registers, their flags, a flag file of all ones (for a
     * clean iteration), each iteration's cleanness, each task's end */
    const size_t nr = (size_t)window * nregs;
    size_t bytes = nr * (sizeof(double) + 1) + nregs + window + maxtasks;
    const size_t outer_bytes = lk->nouter * (sizeof(double) + 1);
    /* The window's registers go to the runtime's scratch (kernel.h),
     * left out of the memory budget, so that the body's own allocations
     * meet the budget where they would without a kernel; a kernel run
     * inside another's body takes a pool block. When they do not fit in
     * what is left of the budget at all, the loop runs as eval_for does. */
    if (!mem_room(bytes + (lk->nouter > 16 ? outer_bytes : 0))) {
        *done = false;
        return NULL;
    }
    *done = true;
    /* the names from outside, as they are while the loop runs */
    double outer_small[16];
    uint8_t outer_ok_small[16];
    unsigned char *outer_big = lk->nouter > 16 ? pool_alloc(outer_bytes) : NULL;
    double *outer = outer_big ? (double *)(void *)outer_big : outer_small;
    uint8_t *outer_ok = outer_big ? outer_big + lk->nouter * sizeof(double) : outer_ok_small;
    for (uint32_t i = 0; i < lk->nouter; i++) {
        int32_t w = lk->outer[i];
        const Vec *v = w >= 0 ? ev->frame[w] : ev->globals ? ev->globals->values[-1 - w] : NULL;
        outer_ok[i] = vec_is_scalar(v);
        outer[i] = outer_ok[i] ? vec_scalar(v) : 0.0;
    }
    KernelScratch *ks = ev->kscratch && !ev->kscratch->busy ? ev->kscratch : NULL;
    unsigned char *buf;
    if (ks) {
        if (ks->cap < bytes) {
            free(ks->buf);
            ks->buf = mem_alloc(bytes);
            ks->cap = bytes;
        }
        ks->busy = true;
        buf = ks->buf;
    } else {
        buf = pool_alloc(bytes);
    }
    /* the nodes of its run before the last (kernel.h KNodeCache); a
     * kernel run inside this one's body keeps none */
    KNodeCache *kcache = ev->kcache;
    ev->kcache = ks && ks->reuse ? knode_cache(ks, n) : NULL;
    KRun kr = {
        .lk = lk, .src = vec_cnums(src), .len = len, .chunk = chunk,
        .regs = (double *)(void *)buf, .ok = buf + nr * sizeof(double),
        .outer = outer, .outer_ok = outer_ok, .outer_clean = true,
        .clean = buf + nr * (sizeof(double) + 1) + nregs,
        .done = (atomic_uchar *)(buf + nr * (sizeof(double) + 1) + nregs + window),
    };
    uint8_t *ones = buf + nr * (sizeof(double) + 1);
    memset(ones, 1, nregs);
    for (uint32_t i = 0; i < lk->nouter; i++) kr.outer_clean = kr.outer_clean && outer_ok[i];
    Workers *pool = ev->workers;
    const unsigned char *kbase = ev->kbase;
    const double *kregs = ev->kregs;
    const uint8_t *kok = ev->kok;
    const bool kclean = ev->kclean;
    Vec **kmemo = ev->kmemo;
    const CBlock *blk = n->b->aux;
    const unsigned char *base = blk->code;
    /* the body's memo values for this run of the loop (evalrun.c) */
    Vec *kmemo_small[8] = {0};
    const size_t kmemo_bytes = blk->nmemos * sizeof(Vec *);
    Vec **km = blk->nmemos > 8 ? pool_calloc(kmemo_bytes) : kmemo_small;
    ev->kmemo = km;
    Parts parts;
    parts_init(&parts);
    bool stop = false;
    for (uint32_t first = 0; first < iters && !stop; first += window) {
        kr.first = first;
        kr.iters = iters - first < window ? iters - first : window;
        const uint32_t ntasks = (kr.iters + chunk - 1) / chunk;
        for (uint32_t t = 0; t < ntasks; t++) atomic_init(&kr.done[t], 0);
        atomic_init(&kr.cancel, false);
        WorkersJob job;
        workers_start(pool, &job, ntasks, chunk_task, &kr);
        /* the pool runs one job at a time: a kernel run by this one's
         * body (a nested loop, a recursive call) runs on this thread */
        ev->workers = NULL;
        for (uint32_t t = 0; t < ntasks && !stop; t++) {
            /* the chunk's registers: take later chunks meanwhile */
            while (!atomic_load_explicit(&kr.done[t], memory_order_acquire))
                if (!workers_help(&job)) workers_pause();
            uint32_t a = task_start(&kr, t), b = task_start(&kr, t + 1);
            for (uint32_t i = a; i < b; i++) {
                /* eval_for's iteration, the body's C_KNUM records reading
                 * this iteration's registers */
                uint32_t p = (first + i) * k;
                if (parts.too_long || stop_requested(ev)) {
                    stop = true;
                    break;
                }
                if (!mem_fits(0)) {
                    parts.too_long = true;
                    stop = true;
                    break;
                }
                if (kr.clean[i] && lk->nread < lk->k && ev->depth + lk->name_guard <= MAX_EVAL_DEPTH) {
                    /* the names that records other than the kernel's read */
                    for (uint32_t j = 0; lk->nread && j < lk->k; j++)
                        if (lk->name_read[j]) bind_loop_name(ev, n, src, p, j);
                } else {
                    bind_loop_names(ev, n, src, p);
                }
                ev->kbase = base;
                ev->kregs = kr.regs + (size_t)i * nregs;
                ev->kok = kr.clean[i] ? ones : kr.ok + (size_t)i * nregs;
                ev->kclean = kr.clean[i];
                ev->kiters++;
                Vec *v = kr.clean[i] && lk->nknode && ev->depth + lk->knode_need <= MAX_EVAL_DEPTH
                             ? straight_iteration(ev, lk, blk)
                             : NULL;
                parts_push(&parts, v ? v : eval_code(ev, n->b));
            }
        }
        if (stop) atomic_store_explicit(&kr.cancel, true, memory_order_relaxed);
        workers_finish(&job);
        ev->workers = pool;
    }
    ev->kbase = kbase;
    ev->kregs = kregs;
    ev->kok = kok;
    ev->kclean = kclean;
    ev->kmemo = kmemo;
    /* nodes past this run's last are not built again */
    if (ev->kcache) knode_trim_run(ev->kcache, ev->kcache->next);
    if (ks) ks->running = NULL;
    ev->kcache = kcache;
    for (uint32_t i = 0; i < blk->nmemos; i++) vec_release(km[i]);
    if (km != kmemo_small) pool_release(km, kmemo_bytes);
    if (ks) ks->busy = false;
    else pool_release(buf, bytes);
    if (outer_big) pool_release(outer_big, outer_bytes);
    return parts_finish(ev, &parts);
}
