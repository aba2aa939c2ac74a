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

/* A compiled numeric subtree (numexpr.h): run on doubles; when an operand
 * is not a single number, or the generic route would hit the depth limit
 * inside it, evaluate it generically instead. */
static inline Vec *run_num(Eval *ev, const AstNode *n, const NumExpr *x)
{
    if (ev->depth + numexpr_depth(x) <= MAX_EVAL_DEPTH) {
        Vec *v = vec_new_num(numexpr_outputs(x));
        if (numexpr_run(x, ev, vec_nums(v))) return v;
        vec_release(v);
    }
    return eval_node(ev, n);
}

/* A growable list of parts to compose. */
typedef struct Parts {
    Vec *small[8];
    Vec **v;
    size_t n, cap;
    uint64_t total;     /* elements pushed so far */
    bool too_long;      /* total passed MAX_COMPOSE_LEN: later parts dropped */
} Parts;

void parts_init(Parts *p);
/* Grow [p] (full) to twice its capacity. */
void parts_grow(Parts *p);

static inline void parts_push(Parts *p, Vec *x)
{
    if (!x) return;
    p->total += vec_len(x);
    /* a single part passes whole (builtins bound their own results) */
    if (p->too_long || (p->n > 0 && p->total > MAX_COMPOSE_LEN)) {
        p->too_long = true;
        vec_release(x);
        return;
    }
    if (p->n == p->cap) parts_grow(p);
    p->v[p->n++] = x;
}

/* Compose the parts and release them; null with an execution error when
 * they were too long. */
Vec *parts_finish(Eval *ev, Parts *p);

/* Bind slot [slot] of the current frame to [v_take] (consumed). */
void set_slot(Eval *ev, int32_t slot, Vec *v_take);
/* An unshared copy of [v] (consumes [v]); object vectors only. */
Vec *vec_unshare(Vec *v);
/* True when [v] holds a node. */
bool has_nodes(const Vec *v);
/* `p << c` (LANGUAGE.md §3.12): every node element of [c] appended to each
 * node of [p] (copied on write); consumes both, returns the result. */
Vec *append_nodes(Vec *p, Vec *c);

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
