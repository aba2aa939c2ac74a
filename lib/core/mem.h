/* mem.h: the library's one allocation-failure path.
 *
 * Every allocation in libflitter either cannot fail (the helpers below) or
 * checks its result and calls mem_oom(). Out of memory is the only abort in
 * the library (issue 13 item 4); before aborting, mem_fail() hands its
 * message to the error callback of the runtime that is active on the
 * calling thread, so an embedder can log it or save what it can.
 *
 * Which callback: a thread-local "failure handler" (function + context),
 * installed by mem_enter() and restored by mem_leave(). The runtime
 * (runtime.c) enters its own handler at the start of every public call
 * that can allocate and leaves it on return, so several runtimes may share
 * a process and even a thread. The pool's active pointer (pool.h) is not
 * used for this because a pool is active only while a frame is evaluated,
 * while loading, saving and dumping allocate too. With no handler on the
 * thread (the physics worker threads, or code called outside a runtime),
 * the message goes to stderr as `flitter: MESSAGE`.
 *
 * The handler is cleared before it is called, so an allocation failing
 * inside the callback falls through to stderr instead of recursing.
 */
#ifndef FL_MEM_H
#define FL_MEM_H

#include <stddef.h>

/* A failure handler: receives the message ("out of memory", "string too
 * long", ...) without a trailing newline; must not return to the library
 * expecting it to continue (the library aborts when it returns). */
typedef void (*MemFailFn)(void *ctx, const char *message);

typedef struct MemHandler {
    MemFailFn fn;   /* NULL: write to stderr */
    void *ctx;      /* passed to fn */
} MemHandler;

/* Install [fn] with [ctx] as this thread's failure handler; returns the one
 * it replaces, to be handed back to mem_leave(). */
MemHandler mem_enter(MemFailFn fn, void *ctx);
/* Restore [prev] (from mem_enter) as this thread's failure handler. */
void mem_leave(MemHandler prev);

/* Report [message] through this thread's failure handler (or stderr), then
 * abort(). For allocation failures and sizes past what can be allocated. */
_Noreturn void mem_fail(const char *message);
/* mem_fail("out of memory"). */
_Noreturn void mem_oom(void);

/* malloc/calloc/realloc/strdup/strndup/asprintf that never return NULL:
 * on failure (or a size that overflows size_t) they call mem_oom(). A
 * request of 0 bytes allocates 1, so the result is never NULL. Release
 * the results with free(). */
void *mem_alloc(size_t size);
void *mem_calloc(size_t n, size_t size);
void *mem_realloc(void *p, size_t size);
/* realloc to [n] elements of [size] bytes each, checking n * size. */
void *mem_realloc_array(void *p, size_t n, size_t size);
char *mem_strdup(const char *s);
char *mem_strndup(const char *s, size_t n);
char *mem_asprintf(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

/* Test hook: make the mem_* allocation after the next [n] on this thread
 * fail as if out of memory (n = 0: the very next one); n < 0 turns the
 * hook off (the default). Only tests call this. */
void mem_test_fail_after(long n);

#endif
