/* pool.h: size-class free lists for the per-frame values (vectors, strings,
 * nodes and their arrays, evaluator scratch arrays).
 *
 * A `Pool` belongs to one runtime (fl_runtime). Every block it hands out is
 * a separate malloc() chunk of its class size, so a block may be returned to
 * any pool, or to free() when no pool is active; a pool only keeps released
 * blocks on per-class free lists and reuses them, so that a steady frame
 * makes no malloc/free calls at all.
 *
 * Which pool serves pool_alloc()/pool_free() is the one made active on the
 * calling thread by pool_enter() (the runtime does this around each frame
 * and restores the previous one afterwards, so several runtimes may share a
 * process and even a thread); with no active pool the calls fall through to
 * malloc/free. A pool must be active on at most one thread at a time.
 *
 * Classes: multiples of 16 bytes up to 256, then powers of two up to 4 MiB;
 * larger blocks always go straight to malloc/free. A pool made with [off]
 * (fl_debug_options.no_pool) keeps no free lists, for memory checkers that
 * should see every block's life.
 */
#ifndef FL_POOL_H
#define FL_POOL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "mem.h"

typedef struct Pool Pool;

#define POOL_SMALL_MAX 256   /* largest request of the 16-byte-step classes */
#define POOL_NCLASS 30       /* 16 small classes, then 512 B .. 4 MiB */
#define POOL_PREFETCH 4      /* how many allocations ahead a class prefetches */

/* Counts of real allocator calls made on behalf of pooled blocks. */
typedef struct PoolStats {
    uint64_t mallocs;   /* malloc calls (free-list misses and big blocks) */
    uint64_t frees;     /* free calls */
    uint64_t stacks;    /* realloc calls growing a class's stack of
                           released blocks (bookkeeping, not blocks) */
} PoolStats;

/* A new, empty pool; [off]: one that passes every call through to
 * malloc/free. Aborts when out of memory. */
Pool *pool_new(bool off);
/* Free every cached block and the pool (NULL is a no-op). The pool must not
 * be active. */
void pool_free(Pool *p);
/* Give cached blocks of [p] back to free() until at most [keep] bytes of
 * blocks stay cached (NULL is a no-op): after a load, whose trees leave
 * blocks behind. The smallest classes (a frame's vectors and nodes) are
 * kept first, and within a class the most recently released blocks; the
 * first frames then take them instead of calling malloc, and the trim
 * itself frees fewer. Kept blocks stay charged to the memory budget
 * (mem.h), so the caller sizes [keep] from it. */
void pool_trim(Pool *p, size_t keep);
/* Make [p] (may be NULL) the active pool of this thread; returns the one it
 * replaces, to be handed back to pool_leave(). */
Pool *pool_enter(Pool *p);
/* Restore [prev] as the active pool of this thread. */
void pool_leave(Pool *prev);
/* The counters of [p] (since pool_new). */
PoolStats pool_stats(const Pool *p);
/* Have [p] call [fn]([ctx]) when a class it is asked for has no released
 * block, before it calls malloc, while *[kept] (the bytes [fn] might give
 * back; NULL: always) is not 0: [fn] may release blocks that something
 * keeps only for reuse (the runtime's kept nodes, kernel.h) into the pool,
 * so that they serve the request as released blocks would. [fn] must not
 * allocate from the pool; NULL removes it. */
void pool_set_reclaim(Pool *p, void (*fn)(void *ctx), void *ctx, const size_t *kept);

/* The slow paths of pool_alloc and pool_release (big blocks, empty lists,
 * no active pool). */
void *pool_alloc_slow(size_t size);
void pool_release_slow(void *ptr, size_t size);

/* Internal: the pool's layout, for the inline fast paths below. Released
 * blocks of a class are kept in a stack of pointers (not a list threaded
 * through the blocks): taking one reads a dense array instead of the
 * block's own (usually cold) memory, so a run of allocations does not wait
 * on one cache miss after another. */
typedef struct PoolStack {
    void **items;    /* released blocks, the most recent last */
    uint32_t n, cap;
} PoolStack;

struct Pool {
    PoolStack free[POOL_NCLASS];     /* released blocks per class */
    PoolStats stats;
    int off;                         /* FLITTER_NOPOOL: no free lists */
    void (*reclaim)(void *ctx);      /* pool_set_reclaim, or NULL */
    void *reclaim_ctx;
    const size_t *reclaim_kept;      /* ... called while this is not 0 */
    int reclaiming;                  /* reclaim is running */
};

/* Internal: the pool active on this thread (pool_enter). */
extern FL_THREAD_LOCAL Pool *pool_active_;

/* A block of at least [size] bytes (uninitialised). Aborts when out of
 * memory. Release it with pool_release(ptr, size) with the same [size]. */
static inline void *pool_alloc(size_t size)
{
    Pool *p = pool_active_;
    if (p && size - 1 < POOL_SMALL_MAX) {
        PoolStack *s = &p->free[(size - 1) / 16];
        if (s->n) {
            void *b = s->items[--s->n];
            /* blocks kept here are usually cold (released a frame ago):
             * fetch the one this class hands out POOL_PREFETCH calls from
             * now, so that it has arrived by then */
            if (s->n >= POOL_PREFETCH) __builtin_prefetch(s->items[s->n - POOL_PREFETCH], 1);
            return b;
        }
    }
    return pool_alloc_slow(size);
}

/* Return block [ptr] of [size] bytes (as given to pool_alloc); NULL is a
 * no-op. */
static inline void pool_release(void *ptr, size_t size)
{
    Pool *p = pool_active_;
    if (p && ptr && !p->off && size - 1 < POOL_SMALL_MAX) {
        PoolStack *s = &p->free[(size - 1) / 16];
        if (s->n < s->cap) {
            s->items[s->n++] = ptr;
            return;
        }
    }
    pool_release_slow(ptr, size);
}

/* The bytes of the block pool_alloc([size]) gives (its class's size),
 * which the memory budget is charged while the block lives. */
size_t pool_block_size(size_t size);

/* A zero-filled block of [size] bytes. */
void *pool_calloc(size_t size);

/* [p] (NULL, or a pool block of *[cap] elements of [size] bytes) with
 * room for at least [need] elements, in a pool block of a capacity
 * doubled from 4 (stored in *[cap]); the contents are moved. Arrays that
 * live in the runtime's pool (nodes' attributes and children, syntax
 * trees' lists) grow by this; heap arrays by mem_grow (mem.h). */
void *pool_grow(void *p, uint32_t *cap, uint32_t need, size_t size);

#endif
