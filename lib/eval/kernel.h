/* kernel.h: loop kernels, the numbers of a loop's iterations computed
 * ahead of its body, on every thread.
 *
 * A `for` loop whose body is a compiled region (evalcode.h) evaluates, for
 * each iteration, the region's compiled numeric records (numexpr.h) one at
 * a time, between the allocations of the nodes and vectors they go into;
 * on a canvas of 10,000 time-dependent nodes, those numbers (sine, cosine,
 * the arithmetic) are half of a frame. The numbers of an iteration depend
 * only on the loop's names, on names bound before the loop (and the
 * frame's engine names, which stay the same while it runs) and on the
 * other numbers of the same iteration bound by the body's `let`s: no
 * allocation, no side effect, no order (numexpr.h). So they can all be
 * computed first, iteration by iteration, as pure arithmetic on arrays of
 * doubles that any thread may run; the body is then run as before, in
 * order, on the calling thread, and each of those records takes its
 * number from the array instead of computing it.
 *
 * At load, kernel_compile_for() turns every compiled numeric record of a
 * loop body (C_NUM) whose names are the loop's names, names bound outside
 * the loop, engine names or the body's own `let`s of such records into a
 * C_KNUM record, and gives the loop a LoopKernel: a register copy of each
 * such expression (numexpr_to_regs), in evaluation order, reading a
 * register file of [the loop's names | the names from outside | the
 * expressions' outputs]. A `let` bound to a memoized record (C_MEMO) of
 * engine names gives its number to the kernel as well (the record itself
 * is left alone: it keeps its memo).
 *
 * At run time (kernel_eval_for), a loop over a numeric source with enough
 * work splits its iterations into chunks; the threads lent by the runtime
 * (Eval.workers) and the caller compute the chunks' registers while the
 * caller runs the body over the finished chunks in order, exactly as
 * eval_for does (the same bindings, checks and composition). A C_KNUM
 * record whose number its iteration holds returns it in a new vector;
 * when the kernel could not compute it (an input was not one number, a
 * comparison met a NaN: numexpr_run's cases), or outside a kernel's run,
 * the record runs as C_NUM. The numbers are the same bits either way: the
 * same instructions on the same numbers (numexpr.h).
 *
 * KernelOptions.off (fl_debug_options.no_kernel, read when a program is
 * compiled) leaves loops without kernels: the reference for
 * tests/cli/fast_route.sh. For tests, KernelOptions.chunk = N makes chunks
 * of N iterations and lets every loop of two iterations or more take its
 * kernel, and KernelOptions.window = N computes at most N iterations ahead.
 */
#ifndef FL_KERNEL_H
#define FL_KERNEL_H

#include "ast.h"
#include "value.h"

typedef struct Eval Eval;
typedef struct LoopKernel LoopKernel;

/* How loops are compiled into kernels (fl_debug_options; all zero: the
 * default). */
typedef struct KernelOptions {
    bool off;           /* no kernels */
    uint32_t chunk;     /* iterations per chunk (0: the kernel's choice) */
    uint32_t window;    /* iterations computed ahead at most (0: the kernel's choice) */
} KernelOptions;
struct CRec;

/* Give the resolved AST_FOR [n], whose body n->b is a compiled region
 * (n->b->fast == 2), a kernel when the region has numeric records it can
 * take (see above): rewrites those records to C_KNUM and sets n->fast = 3
 * and n->aux to the kernel, with the chunk and window of [ko]. Leaves [n]
 * alone otherwise, and when ko->off. Never fails. */
void kernel_compile_for(AstNode *n, const KernelOptions *ko);

/* How many calls of an element function on a register the kernel of loop
 * [n] computes by expressions of their own (kernel.c, share_calls): once
 * for the several expressions that make them, or with their partner (sin
 * and cos of one register); 0 for a loop without a kernel. For tests. */
uint32_t kernel_shared_calls(const AstNode *n);

/* eval_for's route for an AST_FOR [n] with a kernel (n->fast == 3) over
 * the numeric source [src] (borrowed): the composed values of the body's
 * iterations, the same as eval_for's loop gives, errors and all, with
 * *[done] set; *[done] false (nothing evaluated, NULL returned) when the
 * loop is too small for the kernel to pay, and eval_for then runs it as
 * usual. */
Vec *kernel_eval_for(Eval *ev, const AstNode *n, const Vec *src, bool *done);

/* A runtime's scratch for the registers of its kernels' windows (a few
 * MB at most), kept from frame to frame and left out of the memory
 * budget: a loop with a kernel then meets the budget where it would
 * without one. The outermost running kernel uses it; one run inside
 * another's body takes a block from the pool. One per runtime, used by
 * one thread. */
typedef struct KernelScratch KernelScratch;
/* A new, empty scratch; [reuse] false: the kernels build their nodes
 * afresh each frame instead of refilling the last frame's
 * (fl_debug_options.no_kernel_reuse). Aborts when out of memory. */
KernelScratch *kernel_scratch_new(bool reuse);
/* Free [k] (NULL is a no-op), releasing the nodes its caches hold. */
void kernel_scratch_free(KernelScratch *k);
/* Whether the runtime releases a frame's tree before it evaluates the
 * next (fl_options.transient_tree): the last frame's nodes are then free
 * to refill, and a run keeps one cache of them, with a second for the
 * nodes something else still holds (KNodeCache.alt). */
void kernel_scratch_set_transient(KernelScratch *k, bool transient);
/* Release the nodes [k]'s caches hold (NULL is a no-op): a program load,
 * after which the loops they were built by are gone. */
void kernel_scratch_clear(KernelScratch *k);
/* The end of a frame: release the nodes kept for the loops that did not
 * run in it (NULL is a no-op). Kept, they would hold memory that other
 * nodes of their sizes could use (a branch that stopped running, say). */
void kernel_scratch_frame_done(KernelScratch *k);
/* The runtime's pool's reclaim hook (pool_set_reclaim; [ctx] the
 * scratch): at a block the pool lacks, when the memory budget has no
 * room for all the bytes the kept nodes hold, release (once a frame) the
 * kept nodes nothing else holds any more, but those the running loop has
 * still to refill. Without refills their blocks would be the pool's by
 * then (the tree they were built for released), free for any node or
 * vector of their sizes; so the memory budget bites where it would
 * without them. */
void kernel_scratch_reclaim(void *ctx);
/* About the bytes of blocks [k]'s kept nodes hold (0: nothing that
 * kernel_scratch_reclaim could give back), for pool_set_reclaim. */
const size_t *kernel_scratch_held(const KernelScratch *k);

/* The nodes one run of a loop's body built with its C_KNODE records, in
 * the order they were built, each held by the cache (one reference).
 * The outermost running kernel keeps two for each run of a loop in a
 * frame (its first, its second, ...) in the runtime's scratch, one for
 * even frames and one for odd, so a run finds the nodes of the same run
 * of the frame before the last, whose tree has been released. When the
 * runtime releases each tree before the next frame (kernel_scratch_set_
 * transient), a run keeps one cache, of the last frame's nodes, which it
 * refills (the second frame builds none); where something else still
 * holds a slot's node (a physics system keeps the particles it read), it
 * swaps the slot with that of the second cache (alt, knode_cache_swap_alt)
 * and so takes the node held the frame before, as with two caches by
 * frame parity. A node nothing else holds any more
 * (refs 1) that has the record's kind and attributes is then refilled in
 * place instead of built and freed (evalrun.c, run_knode): the same node
 * as a new one, value for value. The nodes of a loop that did not run in
 * a frame are released at its end (kernel_scratch_frame_done), and kept
 * nodes give their blocks back when the memory budget needs them
 * (kernel_scratch_reclaim). kernel_scratch_new(false) turns it off (the
 * route the tests compare against). */
typedef struct KNodeCache {
    struct Node **slot;
    uint32_t n, cap;    /* slots holding a node; allocated */
    uint32_t next;      /* the slot this run's next C_KNODE takes */
    size_t *held;       /* about the bytes of blocks the nodes of all the
                           scratch's caches hold */
    struct KNodeCache *alt; /* the same run's second cache, for the nodes
                               still held elsewhere, or NULL (see above) */
} KNodeCache;
/* Hold [node] (a new reference) in slot [s] of [c], releasing the node
 * there; [s] may be one past the last slot (the cache grows). False, with
 * nothing held, when [s] is further on or the slots cannot grow. */
bool knode_cache_put(KNodeCache *c, uint32_t s, struct Node *node);
/* Swap slot [s] of [c] with that of its alt cache, growing either (with
 * empty slots) to hold it. False, with nothing changed, when [c] has no
 * alt, [s] is more than one past [c]'s last slot, or the slots cannot
 * grow. */
bool knode_cache_swap_alt(KNodeCache *c, uint32_t s);

/* Most attributes of a C_KNODE whose nodes are kept (a node with more is
 * built anew every time). */
#define KNODE_REUSE_ATTRS 16

/* The node of C_KNODE record [r] of the code at [base] in a clean
 * iteration of the running kernel (ev->kbase == base, ev->kclean, ev->depth
 * at most MAX_EVAL_DEPTH - r->aux), a new reference: refilled from the
 * loop's cache (Eval.kcache) or built (evalrun.c). */
struct Node *knode_take(Eval *ev, const unsigned char *base, const struct CRec *r);

#endif
