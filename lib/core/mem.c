/* mem.c: allocation helpers that cannot return NULL, and the one place
 * where an allocation failure is reported and the process aborted (see
 * mem.h for how the failure handler is found). */
#include "mem.h"

#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static _Thread_local MemHandler handler;     /* this thread's failure handler */
static _Thread_local long test_fail = -1;    /* mem_test_fail_after countdown */

MemHandler mem_enter(MemFailFn fn, void *ctx)
{
    MemHandler prev = handler;
    handler = (MemHandler){fn, ctx};
    return prev;
}

void mem_leave(MemHandler prev) { handler = prev; }

_Noreturn void mem_fail(const char *message)
{
    MemHandler h = handler;
    handler = (MemHandler){NULL, NULL};
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
