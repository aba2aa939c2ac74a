/* mem.c: allocation helpers that cannot return NULL, and the one place
 * where an allocation failure is reported and the process aborted (see
 * mem.h for how the failure handler is found). */
#include "mem.h"

#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <errno.h>
#include <sys/resource.h>
#include <unistd.h>

static FL_THREAD_LOCAL MemHandler handler;     /* this thread's failure handler */
static FL_THREAD_LOCAL bool refused;           /* a request of this thread's was refused
                                                  since mem_enter_budget or mem_take_refusal */
static FL_THREAD_LOCAL long test_fail = -1;    /* mem_test_fail_after countdown */

MemHandler mem_enter(MemFailFn fn, void *ctx) { return mem_enter_budget(fn, ctx, NULL); }

MemHandler mem_enter_budget(MemFailFn fn, void *ctx, MemBudget *budget)
{
    MemHandler prev = handler;
    handler = (MemHandler){fn, ctx, budget};
    if (budget) refused = false;
    return prev;
}

void mem_leave(MemHandler prev) { handler = prev; }

/* {====================================================================
 * The budget
 * ===================================================================== */

/* The budget's count of bytes is shared by the threads that charge it
 * (a runtime's frame loop and its drawing thread, fl_picture_draw): every
 * change is one atomic step, saturating at both ends as before. */
static size_t used_now(const MemBudget *b) { return __atomic_load_n(&b->used, __ATOMIC_RELAXED); }

/* Whether [bytes] more fit under [b]'s limit with [used] charged. */
static bool under(const MemBudget *b, size_t used, size_t bytes)
{
    return !b->limit || (used <= b->limit && bytes <= b->limit - used);
}

/* Add [bytes] to [b]'s count (at most SIZE_MAX); with [check], only when
 * they fit under its limit: false, nothing charged, when not. */
static bool add_used(MemBudget *b, size_t bytes, bool check)
{
    size_t old = used_now(b), now;
    do {
        if (check && !under(b, old, bytes)) return false;
        now = bytes > SIZE_MAX - old ? SIZE_MAX : old + bytes;
    } while (!__atomic_compare_exchange_n(&b->used, &old, now, true, __ATOMIC_RELAXED, __ATOMIC_RELAXED));
    return true;
}

/* Take [bytes] off [b]'s count (at least 0). */
static void sub_used(MemBudget *b, size_t bytes)
{
    size_t old = used_now(b), now;
    do {
        now = bytes < old ? old - bytes : 0;
    } while (!__atomic_compare_exchange_n(&b->used, &old, now, true, __ATOMIC_RELAXED, __ATOMIC_RELAXED));
}

bool mem_fits(size_t bytes)
{
    const MemBudget *b = handler.budget;
    if (!b || under(b, used_now(b), bytes)) return true;
    refused = true;
    return false;
}

bool mem_room(size_t bytes)
{
    const MemBudget *b = handler.budget;
    return !b || under(b, used_now(b), bytes);
}

bool mem_reserve(size_t bytes)
{
    MemBudget *b = handler.budget;
    if (!b || add_used(b, bytes, true)) return true;
    refused = true;
    return false;
}

void mem_charge(size_t bytes)
{
    MemBudget *b = handler.budget;
    if (b) add_used(b, bytes, false);
}

void mem_unreserve(size_t bytes)
{
    MemBudget *b = handler.budget;
    /* a block made outside any runtime call may come back inside one */
    if (b) sub_used(b, bytes);
}

bool mem_budget_reserve(MemBudget *b, size_t bytes)
{
    return !b || add_used(b, bytes, true);
}

void mem_budget_release(MemBudget *b, size_t bytes)
{
    if (b) sub_used(b, bytes);
}

bool mem_take_refusal(void)
{
    if (!handler.budget || !refused) return false;
    refused = false;
    return true;
}

size_t mem_default_limit(void)
{
    size_t limit = 0;
    long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    if (pages > 0 && page > 0) limit = (size_t)pages / 2 * (size_t)page;
    struct rlimit rl;
    if (getrlimit(RLIMIT_AS, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY) {
        size_t as = rl.rlim_cur / 2 > SIZE_MAX ? SIZE_MAX : (size_t)(rl.rlim_cur / 2);
        if (!limit || as < limit) limit = as ? as : 1;
    }
    return limit;
}

bool mem_parse_size(const char *text, size_t *out)
{
    if (!text || !out || *text < '0' || *text > '9') return false;
    errno = 0;
    char *end;
    unsigned long long n = strtoull(text, &end, 10);
    if (errno || n == 0) return false;
    unsigned shift = 0;
    switch (*end) {
    case '\0': break;
    case 'k': case 'K': shift = 10; end++; break;
    case 'm': case 'M': shift = 20; end++; break;
    case 'g': case 'G': shift = 30; end++; break;
    default: return false;
    }
    if (*end || n > (SIZE_MAX >> shift)) return false;
    *out = (size_t)n << shift;
    return true;
}

/* }==================================================================== */

_Noreturn void mem_fail(const char *message)
{
    MemHandler h = handler;
    handler = (MemHandler){NULL, NULL, NULL};
    if (h.fn)
        h.fn(h.ctx, message);
    else
        fprintf(stderr, "flitter: %s\n", message);
    abort();
}

_Noreturn void mem_oom(void) { mem_fail("out of memory"); }

void mem_test_fail_after(long n) { test_fail = n; }

/* true when the test hook says this allocation fails */
static int forced_failure(void)
{
    if (test_fail < 0)
        return 0;
    return test_fail-- == 0;
}

void *mem_alloc(size_t size)
{
    void *p = forced_failure() ? NULL : malloc(size ? size : 1);
    if (!p)
        mem_oom();
    return p;
}

void *mem_calloc(size_t n, size_t size)
{
    void *p = forced_failure() ? NULL : calloc(n ? n : 1, size ? size : 1);
    if (!p)
        mem_oom();
    return p;
}

void *mem_realloc(void *p, size_t size)
{
    void *q = forced_failure() ? NULL : realloc(p, size ? size : 1);
    if (!q)
        mem_oom();
    return q;
}

void *mem_realloc_array(void *p, size_t n, size_t size)
{
    if (size && n > SIZE_MAX / size)
        mem_oom();
    return mem_realloc(p, n * size);
}

void *mem_grow(void *p, size_t *cap, size_t need, size_t size)
{
    if (need <= *cap)
        return p;
    size_t n = *cap ? *cap : 16;
    while (n < need) {
        if (n > SIZE_MAX / 2)
            mem_oom();
        n *= 2;
    }
    p = mem_realloc_array(p, n, size);
    *cap = n;
    return p;
}

char *mem_strdup(const char *s)
{
    return mem_strndup(s, strlen(s));
}

char *mem_strndup(const char *s, size_t n)
{
    size_t len = strnlen(s, n);
    char *r = mem_alloc(len + 1);
    memcpy(r, s, len);
    r[len] = '\0';
    return r;
}

char *mem_asprintf(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(NULL, 0, fmt, ap);
    va_end(ap);
    if (n < 0)
        mem_oom();
    char *r = mem_alloc((size_t)n + 1);
    va_start(ap, fmt);
    vsnprintf(r, (size_t)n + 1, fmt, ap);
    va_end(ap);
    return r;
}
