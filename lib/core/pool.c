/* pool.c: size-class free lists owned by a runtime (see pool.h). */
#include "pool.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mem.h"

#define SMALL_STEP 16
#define NSMALL (POOL_SMALL_MAX / SMALL_STEP) /* classes 0..15: 16..256 bytes */
#define BIG_MIN_LOG 9                     /* 512 */
#define BIG_MAX_LOG 22                    /* 4 MiB */
#define NO_CLASS (-1)

_Static_assert(POOL_NCLASS == NSMALL + BIG_MAX_LOG - BIG_MIN_LOG + 1, "pool classes");

FL_THREAD_LOCAL Pool *pool_active_;

/* The class of a [size]-byte request and the class's block size. */
static int size_class(size_t size, size_t *block)
{
    if (size <= POOL_SMALL_MAX) {
        size_t c = size ? (size + SMALL_STEP - 1) / SMALL_STEP : 1;
        *block = c * SMALL_STEP;
        return (int)c - 1;
    }
    int lg = BIG_MIN_LOG;
    while (lg <= BIG_MAX_LOG && ((size_t)1 << lg) < size) lg++;
    if (lg > BIG_MAX_LOG) {
        *block = size;
        return NO_CLASS;
    }
    *block = (size_t)1 << lg;
    return NSMALL + lg - BIG_MIN_LOG;
}

Pool *pool_new(bool off)
{
    Pool *p = calloc(1, sizeof *p);
    if (!p) mem_oom();
    p->off = off;
    return p;
}

void *pool_grow(void *p, uint32_t *cap, uint32_t need, size_t size)
{
    if (need <= *cap) return p;
    uint32_t c = *cap ? *cap : 4;
    while (c < need) {
        if (c > UINT32_MAX / 2) mem_oom();
        c *= 2;
    }
    if ((size_t)c > SIZE_MAX / size) mem_oom();
    void *q = pool_alloc((size_t)c * size);
    if (p) {
        memcpy(q, p, (size_t)*cap * size);
        pool_release(p, (size_t)*cap * size);
    }
    *cap = c;
    return q;
}

void pool_free(Pool *p)
{
    if (!p) return;
    for (int c = 0; c < POOL_NCLASS; c++) {
        for (uint32_t i = 0; i < p->free[c].n; i++) free(p->free[c].items[i]);
        free(p->free[c].items);
    }
    free(p);
}

void pool_trim(Pool *p, size_t keep)
{
    if (!p) return;
    for (int c = 0; c < POOL_NCLASS; c++) {
        size_t block = c < NSMALL ? (size_t)(c + 1) * SMALL_STEP : (size_t)1 << (BIG_MIN_LOG + c - NSMALL);
        PoolStack *s = &p->free[c];
        /* the stack's bottom blocks were released first: keep its top */
        uint32_t kept = (uint32_t)(keep / block < s->n ? keep / block : s->n);
        keep -= (size_t)kept * block;
        uint32_t drop = s->n - kept;
        for (uint32_t i = 0; i < drop; i++) {
            mem_unreserve(block);
            free(s->items[i]);
        }
        if (drop) memmove(s->items, s->items + drop, (size_t)kept * sizeof *s->items);
        p->stats.frees += drop;
        s->n = kept;
    }
}

Pool *pool_enter(Pool *p)
{
    Pool *prev = pool_active_;
    pool_active_ = p;
    return prev;
}

void pool_leave(Pool *prev) { pool_active_ = prev; }

PoolStats pool_stats(const Pool *p) { return p->stats; }

void pool_set_reclaim(Pool *p, void (*fn)(void *ctx), void *ctx, const size_t *kept)
{
    p->reclaim = fn;
    p->reclaim_ctx = ctx;
    p->reclaim_kept = kept;
}

void *pool_alloc_slow(size_t size)
{
    size_t block;
    int c = size_class(size, &block);
    Pool *p = pool_active_;
    if (p && c != NO_CLASS && !p->free[c].n && p->reclaim && (!p->reclaim_kept || *p->reclaim_kept) &&
        !p->reclaiming && !p->off) {
        p->reclaiming = 1;
        p->reclaim(p->reclaim_ctx);
        p->reclaiming = 0;
    }
    if (p && c != NO_CLASS && p->free[c].n) return p->free[c].items[--p->free[c].n];
    void *r = malloc(block);
    if (!r) {
        mem_oom();
    }
    mem_charge(block);   /* this thread's budget (mem.h) holds it until it is freed */
    if (p) p->stats.mallocs++;
    return r;
}

size_t pool_block_size(size_t size)
{
    size_t block;
    size_class(size, &block);
    return block;
}

void *pool_calloc(size_t size)
{
    void *r = pool_alloc(size);
    memset(r, 0, size);
    return r;
}

void pool_release_slow(void *ptr, size_t size)
{
    if (!ptr) return;
    size_t block;
    int c = size_class(size, &block);
    Pool *p = pool_active_;
    if (p && c != NO_CLASS && !p->off) {
        PoolStack *s = &p->free[c];
        if (s->n == s->cap) {
            uint32_t cap = s->cap ? s->cap * 2 : 64;
            s->items = mem_realloc_array(s->items, cap, sizeof *s->items);
            s->cap = cap;
            p->stats.stacks++;
        }
        s->items[s->n++] = ptr;
        return;
    }
    if (p) p->stats.frees++;
    mem_unreserve(block);
    free(ptr);
}
