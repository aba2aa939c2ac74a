/* test_prefault.c: src/prefault.c, the heap's new pages faulted in on
 * another thread: a heap block nobody touches becomes resident (mincore),
 * what the program writes meanwhile stays written, and FLITTER_PREFAULT=0
 * or a data limit starts nothing. Skipped (77) under a memory checker,
 * whose allocator is not the heap's, under an address-space or data limit,
 * and on a kernel without MADV_POPULATE_WRITE. */
#include <errno.h>
#include <malloc.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

#include "memcheck.h"
#include "prefault.h"

#ifndef MADV_POPULATE_WRITE
#define MADV_POPULATE_WRITE 23
#endif

static int failures;

#define CHECK(cond, ...)                                   \
    do {                                                   \
        if (!(cond)) {                                     \
            fprintf(stderr, "test_prefault: " __VA_ARGS__); \
            fputc('\n', stderr);                           \
            failures++;                                    \
        }                                                  \
    } while (0)

/* Whether this kernel knows MADV_POPULATE_WRITE. */
static bool kernel_populates(void)
{
    long page = sysconf(_SC_PAGESIZE);
    void *m = mmap(NULL, (size_t)page, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (m == MAP_FAILED) return false;
    bool ok = madvise(m, (size_t)page, MADV_POPULATE_WRITE) == 0;
    munmap(m, (size_t)page);
    return ok;
}

/* The part of the block [p, p + n) past [from] (the heap's end before), as
 * its start and length in *[len]. */
static const void *past_from(const void *p, size_t n, const void *from, size_t *len)
{
    const uintptr_t b0 = (uintptr_t)p, f = (uintptr_t)from;
    const uintptr_t start = p && b0 < f && f < b0 + n ? f : b0;
    *len = p ? (size_t)(b0 + n - start) : 0;
    return (const void *)start;
}

/* How many of the whole pages inside [p, p + n) are resident. */
static size_t resident(const void *p, size_t n, size_t *pages)
{
    const uintptr_t page = (uintptr_t)sysconf(_SC_PAGESIZE);
    uintptr_t a = ((uintptr_t)p + page - 1) & ~(page - 1), b = ((uintptr_t)p + n) & ~(page - 1);
    *pages = b > a ? (b - a) / page : 0;
    if (!*pages) return 0;
    unsigned char *v = malloc(*pages);
    if (!v || mincore((void *)a, b - a, v) != 0) {
        free(v);
        return 0;
    }
    size_t r = 0;
    for (size_t i = 0; i < *pages; i++) r += v[i] & 1;
    free(v);
    return r;
}

int main(void)
{
    if (memory_checked()) {
        puts("SKIP: a memory checker's allocator is not the heap's");
        return 77;
    }
    /* malloc leaves new blocks untouched (meson sets MALLOC_PERTURB_, which
     * would fill them, making every page resident) */
    mallopt(M_PERTURB, 0);
    if (!kernel_populates()) {
        puts("SKIP: this kernel has no MADV_POPULATE_WRITE (Linux 5.14)");
        return 77;
    }
    struct rlimit as, data;
    if (getrlimit(RLIMIT_AS, &as) != 0 || getrlimit(RLIMIT_DATA, &data) != 0 ||
        as.rlim_cur != RLIM_INFINITY || data.rlim_cur != RLIM_INFINITY) {
        puts("SKIP: run under an address-space or data limit");
        return 77;
    }
    setenv("FLITTER_PREFAULT", "0", 1);
    CHECK(prefault_start() == NULL, "FLITTER_PREFAULT=0 started a prefaulter");
    unsetenv("FLITTER_PREFAULT");
    /* under a data limit (ulimit -d), however large, none starts */
    struct rlimit lim = {(rlim_t)1 << 40, data.rlim_max};
    if (setrlimit(RLIMIT_DATA, &lim) == 0) {
        Prefault *q = prefault_start();
        CHECK(q == NULL, "a prefaulter started under a data limit");
        prefault_stop(q);
        CHECK(setrlimit(RLIMIT_DATA, &data) == 0, "the data limit could not be lifted again");
    }

    /* the heap's end now: the thread faults in what lies beyond */
    unsigned char *from = sbrk(0);
    Prefault *p = prefault_start();
    CHECK(p != NULL, "no prefaulter started");
    /* 1 MiB: the heap grows less than the 6 MiB the thread waits for, so
     * this block stays as malloc leaves it, untouched */
    unsigned char *small_block = malloc((size_t)1 << 20);
    struct timespec wait = {0, 30 * 1000 * 1000};
    nanosleep(&wait, NULL);
    size_t slen, spages = 0;
    const void *spast = past_from(small_block, (size_t)1 << 20, from, &slen);
    size_t sr = resident(spast, slen, &spages);
    CHECK(spages >= 128 && sr < spages, "a 1 MiB block: %zu of %zu pages resident", sr, spages);
    /* 16 MiB: under the 32 MiB threshold, so from the heap, which grows
     * for it (past the 6 MiB the thread waits for); nothing here touches
     * it */
    const size_t n = (size_t)16 << 20;
    unsigned char *block = malloc(n);
    CHECK(block != NULL, "malloc failed");
    /* written meanwhile, page by page, while the thread faults pages in */
    const size_t m = (size_t)2 << 20;
    unsigned char *mine = malloc(m);
    for (size_t i = 0; mine && i < m; i++) mine[i] = (unsigned char)(i * 131 + 7);
    size_t pages = 0, r = 0;
    /* its part past the heap's old end (malloc may have placed its start
     * in the free end of the heap as it was) */
    size_t npast;
    const void *past = past_from(block, n, from, &npast);
    for (int tries = 0; tries < 500; tries++) {   /* up to 5 s */
        r = resident(past, npast, &pages);
        if (pages && r == pages) break;
        struct timespec ts = {0, 10 * 1000 * 1000};
        nanosleep(&ts, NULL);
    }
    CHECK(pages >= 512 && r == pages, "%zu of the untouched block's %zu pages resident", r, pages);
    bool same = mine != NULL;
    for (size_t i = 0; mine && i < m; i++) same = same && mine[i] == (unsigned char)(i * 131 + 7);
    CHECK(same, "a block written meanwhile changed");
    prefault_stop(p);
    prefault_stop(NULL);
    free(block);
    free(mine);
    free(small_block);
    if (failures) return 1;
    puts("test_prefault: ok");
    return 0;
}
