/* pool.c: size-class free lists owned by a runtime (see pool.h). */
#include "pool.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SMALL_STEP 16
#define SMALL_MAX 256                     /* classes 0..15: 16..256 bytes */
#define NSMALL (SMALL_MAX / SMALL_STEP)
#define BIG_MIN_LOG 9                     /* 512 */
#define BIG_MAX_LOG 22                    /* 4 MiB */
#define NCLASS (NSMALL + BIG_MAX_LOG - BIG_MIN_LOG + 1)
#define NO_CLASS (-1)

typedef struct FreeBlock {
    struct FreeBlock *next;
} FreeBlock;

struct Pool {
    FreeBlock *lists[NCLASS];   /* released blocks per class */
    PoolStats stats;
    int off;                    /* FLITTER_NOPOOL: no free lists */
};

/* The pool active on this thread (set by the runtime around each frame). */
static _Thread_local Pool *active;

/* The class of a [size]-byte request and the class's block size. */
static int size_class(size_t size, size_t *block)
{
    if (size <= SMALL_MAX) {
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

Pool *pool_new(void)
{
    Pool *p = calloc(1, sizeof *p);
    if (!p) abort();
    const char *e = getenv("FLITTER_NOPOOL");
    p->off = e && *e;
    return p;
}

void pool_free(Pool *p)
{
    if (!p) return;
    for (int c = 0; c < NCLASS; c++) {
        FreeBlock *b = p->lists[c];
        while (b) {
            FreeBlock *next = b->next;
            free(b);
            b = next;
        }
    }
    free(p);
}

Pool *pool_enter(Pool *p)
{
    Pool *prev = active;
    active = p;
    return prev;
}

void pool_leave(Pool *prev) { active = prev; }

PoolStats pool_stats(const Pool *p) { return p->stats; }

void *pool_alloc(size_t size)
{
    size_t block;
    int c = size_class(size, &block);
    Pool *p = active;
    if (p && c != NO_CLASS && p->lists[c]) {
        FreeBlock *b = p->lists[c];
        p->lists[c] = b->next;
        return b;
    }
    void *r = malloc(block);
    if (!r) {
        fputs("flitter: out of memory\n", stderr);
        abort();
    }
    if (p) p->stats.mallocs++;
    return r;
}

void *pool_calloc(size_t size)
{
    void *r = pool_alloc(size);
    memset(r, 0, size);
    return r;
}

void pool_release(void *ptr, size_t size)
{
    if (!ptr) return;
    size_t block;
    int c = size_class(size, &block);
    Pool *p = active;
    if (p && c != NO_CLASS && !p->off) {
        FreeBlock *b = ptr;
        b->next = p->lists[c];
        p->lists[c] = b;
        return;
    }
    if (p) p->stats.frees++;
    free(ptr);
}
