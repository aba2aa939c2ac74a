/* prefault.c: the heap's new pages faulted in on another core (prefault.h). */
#include "prefault.h"

#include <errno.h>
#include <malloc.h>
#include <pthread.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

#ifndef MADV_POPULATE_WRITE
#define MADV_POPULATE_WRITE 23   /* Linux 5.14 */
#endif

/* How far malloc grows the heap past what it needs, and the largest
 * block it takes from the heap (glibc's own ceiling for the threshold it
 * otherwise adjusts as blocks are freed). */
#define PREFAULT_PAD ((size_t)2 << 20)
#define PREFAULT_MMAP_THRESHOLD ((size_t)32 << 20)
/* the least freed bytes at the heap's top that go back to the kernel */
#define PREFAULT_KEEP_FREED (512 << 20)
/* How much the heap grows before the thread starts: a script that needs
 * less (most) pays no fault on the other core, which its physics and
 * loop kernels may be using. */
#define PREFAULT_AFTER ((size_t)6 << 20)
/* Faulted in a call, so that a stop is seen soon. */
#define PREFAULT_STEP ((size_t)256 << 10)
/* At most this much in all. */
#define PREFAULT_MAX ((size_t)1 << 30)
/* The pause between looks at the heap's end, in nanoseconds. */
#define PREFAULT_NAP 100000L

struct Prefault {
    pthread_t thread;
    atomic_bool stop;
    uintptr_t from;   /* the heap's end when it started */
};

static uintptr_t page_down(uintptr_t a, uintptr_t page) { return a & ~(page - 1); }

static void *prefault_main(void *arg)
{
    Prefault *p = arg;
    const uintptr_t page = (uintptr_t)sysconf(_SC_PAGESIZE);
    /* The heap's end, sbrk(0), is a word malloc's thread writes when it
     * grows or trims the heap; read here without a lock, a stale value
     * only means faulting in a stretch a little late, or asking for one
     * that is gone (ENOMEM, skipped). */
    uintptr_t done = page_down(p->from, page);
    size_t total = 0;
    while (!atomic_load_explicit(&p->stop, memory_order_relaxed) && total < PREFAULT_MAX) {
        void *e = sbrk(0);
        if (e == (void *)-1) break;
        uintptr_t end = page_down((uintptr_t)e + page - 1, page);
        if (end <= done || end - p->from < PREFAULT_AFTER) {
            if (end < done) done = end;   /* trimmed */
            struct timespec nap = {0, PREFAULT_NAP};
            nanosleep(&nap, NULL);
            continue;
        }
        for (uintptr_t a = done; a < end && !atomic_load_explicit(&p->stop, memory_order_relaxed);) {
            size_t n = end - a < PREFAULT_STEP ? end - a : PREFAULT_STEP;
            if (madvise((void *)a, n, MADV_POPULATE_WRITE) != 0) {
                if (errno == EINVAL || errno == EPERM) return NULL;   /* not this kernel's */
                break;   /* trimmed meanwhile, or no memory: look again */
            }
            a += n;
            total += n;
        }
        done = end;
    }
    return NULL;
}

/* Whether the process's address space or data segment is limited
 * (`ulimit -v`, `ulimit -d`): the heap's padding and the larger blocks it
 * serves would then reach the limit sooner. */
static bool space_limited(void)
{
    struct rlimit r;
    return (getrlimit(RLIMIT_AS, &r) == 0 && r.rlim_cur != RLIM_INFINITY) ||
           (getrlimit(RLIMIT_DATA, &r) == 0 && r.rlim_cur != RLIM_INFINITY);
}

void prefault_keep_freed(void)
{
    if (!space_limited()) mallopt(M_TRIM_THRESHOLD, PREFAULT_KEEP_FREED);
}

Prefault *prefault_start(void)
{
    const char *e = getenv("FLITTER_PREFAULT");
    if ((e && !strcmp(e, "0")) || space_limited()) return NULL;
    Prefault *p = malloc(sizeof *p);
    if (!p) return NULL;
    atomic_init(&p->stop, false);
    void *end = sbrk(0);
    if (end == (void *)-1) {
        free(p);
        return NULL;
    }
    p->from = (uintptr_t)end;
    mallopt(M_MMAP_THRESHOLD, (int)PREFAULT_MMAP_THRESHOLD);
    mallopt(M_TOP_PAD, (int)PREFAULT_PAD);
    prefault_keep_freed();
    /* every signal blocked in the thread (it inherits the mask), so that
     * one meant for the process (Ctrl-C) is taken by the others */
    sigset_t all, old;
    sigfillset(&all);
    pthread_sigmask(SIG_SETMASK, &all, &old);
    int rc = pthread_create(&p->thread, NULL, prefault_main, p);
    pthread_sigmask(SIG_SETMASK, &old, NULL);
    if (rc != 0) {
        free(p);
        return NULL;
    }
    return p;
}

void prefault_stop(Prefault *p)
{
    if (!p) return;
    atomic_store_explicit(&p->stop, true, memory_order_relaxed);
    pthread_join(p->thread, NULL);
    free(p);
}
