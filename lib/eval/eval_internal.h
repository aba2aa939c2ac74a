/* eval_internal.h: what the evaluator's two halves share (internal to
 * lib/eval): eval.c, the tree walk, and evalrun.c, which runs the compiled
 * regions of evalcode.h and falls back on the tree walk. Every function
 * here keeps the ownership rule of value.h.
 */
#ifndef FL_EVAL_INTERNAL_H
#define FL_EVAL_INTERNAL_H

#include <stdbool.h>
#include <stdint.h>

#include "builtins.h"
#include "config.h"
#include "numexpr.h"
#include "program.h"

/* Evaluate [n] (not NULL) by its AST kind, with the depth guard (§4.16). */
Vec *eval_node(Eval *ev, const AstNode *n);
/* Run the compiled region rooted at [n] (n->fast == 2; evalrun.c). */
Vec *eval_code(Eval *ev, const AstNode *n);

/* numexpr_run_vec's numbers in a new vector, or NULL where it gives up
 * (then nothing was reported). */
Vec *run_num_vec(Eval *ev, const NumExpr *x);

/* A compiled numeric subtree (numexpr.h): run on doubles; when an operand
 * is not a single number, on vectors of numbers (numexpr_run_vec); when
 * neither can, or the generic route would hit the depth limit inside it,
 * evaluate it generically instead. */

static inline Vec *run_num(Eval *ev, const AstNode *n, const NumExpr *x)
{
    if (ev->depth + numexpr_depth(x) <= MAX_EVAL_DEPTH) {
        const int32_t lead = numexpr_lead_slot(x);
        if (numexpr_small(x)) {
            const NxSmall y = numexpr_run_small(x, ev);
            if (y.ok) return vec_num1(y.v);
        } else if (lead < 0 || vec_is_scalar(ev->frame[lead])) {
            /* (a vector read first: numexpr_run would give up at once) */
            Vec *v = vec_new_num(numexpr_outputs(x));
            if (numexpr_run(x, ev, vec_nums(v))) return v;
            vec_release(v);
        }
        Vec *v = run_num_vec(ev, x);
        if (v) return v;
    }
    return eval_node(ev, n);
}

/* True once the embedder's interrupt flag is set (then ev->interrupted):
 * loops and calls stop early so a long frame ends promptly (flitter.h). */
static inline bool stop_requested(Eval *ev)
{
    if (ev->interrupt && *ev->interrupt)
        ev->interrupted = true;
    return ev->interrupted;
}

/* Bind slot [slot] of the current frame to [v_take] (consumed). */
static inline void set_slot(Eval *ev, int32_t slot, Vec *v_take)
{
    Vec *old = ev->frame[slot];
    ev->frame[slot] = v_take;
    vec_release(old);
}

/* Bind the [j]-th name of the AST_FOR [n] to item p + j of [src]
 * (borrowed; null past its end), as the loop's iteration from item [p]
 * does. */
static inline void bind_loop_name(Eval *ev, const AstNode *n, const Vec *src, uint32_t p, uint32_t j)
{
    uint32_t len = vec_len(src);
    Vec *cur = ev->frame[n->slots[j]];
    if (p + j < len && src->kind == VEC_NUM && cur && cur->refs == 1 &&
        cur->kind == VEC_NUM && cur->len == 1) {
        /* the previous item is held by nothing else: reuse it */
        cur->hashed = 0;
        vec_nums(cur)[0] = vec_cnums(src)[p + j];
    } else {
        set_slot(ev, n->slots[j], p + j < len ? vec_item(src, p + j) : NULL);
    }
}

/* Bind every name of the AST_FOR [n] so. */
void bind_loop_names(Eval *ev, const AstNode *n, const Vec *src, uint32_t p);

/* Parts composed at a time into one (parts_collapse). */
#define PARTS_CHUNK 64

/* A growable list of parts to compose. A long list is composed as it
 * grows, PARTS_CHUNK parts at a time, into chunks that stand for them:
 * composition is associative (the same elements in the same order, numeric
 * exactly when every part is, the one non-empty part itself when there is
 * only one), and the parts are then released while they are still in the
 * cache instead of all at the end (a sequence of 10,000 nodes). */
typedef struct Parts {
    Vec *small[8];
    Vec **v;            /* v[0..chunks): chunks; v[chunks..n): parts */
    size_t n, cap;
    size_t chunks;      /* leading entries that are composed chunks */
    size_t pushed;      /* non-null parts pushed so far */
    uint64_t total;     /* elements pushed so far */
    bool too_long;      /* total passed MAX_COMPOSE_LEN: later parts dropped */
} Parts;

void parts_init(Parts *p);
/* Grow [p] (full) to twice its capacity. */
void parts_grow(Parts *p);
/* Compose the PARTS_CHUNK parts after the chunks of [p] into one chunk. */
void parts_collapse(Parts *p);

static inline void parts_push(Parts *p, Vec *x)
{
    if (!x) return;
    p->total += vec_len(x);
    /* a single part passes whole (builtins bound their own results) */
    if (p->too_long || (p->pushed > 0 && p->total > MAX_COMPOSE_LEN)) {
        p->too_long = true;
        vec_release(x);
        return;
    }
    if (p->n == p->cap) parts_grow(p);
    p->v[p->n++] = x;
    p->pushed++;
    if (p->n - p->chunks == PARTS_CHUNK) parts_collapse(p);
}

/* Compose the parts and release them; null with an execution error when
 * they were too long. */
Vec *parts_finish(Eval *ev, Parts *p);

/* An unshared copy of [v] (consumes [v]); object vectors only. */
Vec *vec_unshare(Vec *v);
/* True when [v] holds a node. */
bool has_nodes(const Vec *v);
/* `p << c` (LANGUAGE.md §3.12): every node element of [c] appended to each
 * node of [p] (copied on write); consumes both, returns the result. */
Vec *append_nodes(Vec *p, Vec *c);
/* append_nodes([p], the composition of [parts][0..m)), consuming all
 * (m <= APPEND_PARTS_MAX): for a parent of one node, the parts' node
 * elements go straight into its children (moved from a part held only
 * here, else retained), without the composed vector; the same tree,
 * values and errors (where composing would refuse, it composes and
 * appends). */
Vec *append_parts(Eval *ev, Vec *p, Vec **parts, uint32_t m);
/* Most parts append_parts takes from a compiled sequence at once. */
#define APPEND_PARTS_MAX 8

/* The arguments of a call. */
typedef struct Args {
    Vec **pos;             /* positional values */
    uint32_t npos;
    const AstNode **kwn;   /* AST_BINDING of each named argument */
    Vec **kw;              /* named values */
    uint32_t nkw;
} Args;

/* Call builtin [bi] with [a] (checks the argument counts and names). */
Vec *call_builtin(Eval *ev, const Builtin *bi, const Args *a);

#endif
