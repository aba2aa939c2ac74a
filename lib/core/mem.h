/* mem.h: the library's one allocation-failure path.
 *
 * Every allocation in libflitter either cannot fail (the helpers below) or
 * checks its result and calls mem_oom(). Out of memory is the only abort in
 * the library; before aborting, mem_fail() hands its
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

#include <stdbool.h>
#include <stddef.h>

/* The library's thread-local variables (this failure handler, the pool's
 * active pointer, pool.h) in the initial-exec model: a read is one load at
 * a fixed offset from the thread pointer. In the default model a shared
 * object (libflitter.so, the Python module) calls __tls_get_addr for every
 * read, and every pool allocation reads the active pool: 8.7% of a
 * canvas10k load through libflitter.so. The cost is a few dozen bytes of
 * the static TLS block that glibc keeps spare for libraries loaded later
 * with dlopen (a library it cannot place there fails to load with a
 * message, it is never misread). TLS descriptors (-mtls-dialect=gnu2)
 * would need no spare room, but glibc before 2.40 may clobber vector
 * registers in their dynamic path (sourceware bug 31372). */
#if defined(__GNUC__) || defined(__clang__)
#define FL_THREAD_LOCAL _Thread_local __attribute__((tls_model("initial-exec")))
#else
#define FL_THREAD_LOCAL _Thread_local
#endif

/* A failure handler: receives the message ("out of memory", "string too
 * long", ...) without a trailing newline; must not return to the library
 * expecting it to continue (the library aborts when it returns). */
typedef void (*MemFailFn)(void *ctx, const char *message);

/* A memory budget: the bytes one
 * runtime may hold in the memory that input can make huge. It lives in the
 * runtime (runtime.c) and is reached from the allocators through this
 * thread's handler (mem_enter_budget), which the runtime installs on entry
 * to every public call: nothing is global.
 *
 * What is charged: every block the pool (pool.c) takes from malloc or
 * gives back to free (vectors, strings, nodes, attribute arrays: held
 * blocks stay charged while they wait on a free list), and the explicit
 * reservations of the other big arrays (the state-file reader's numbers,
 * !physics systems, the parser's estimate). The paths whose size the
 * input decides ask mem_fits() (or mem_reserve()) before allocating and
 * turn a refusal into Flitter's null-and-log, a load error or a physics
 * error; small allocations are not checked one by one. */
typedef struct MemBudget {
    size_t limit;    /* bytes; 0: no limit */
    size_t used;     /* bytes charged now: changed by atomic steps alone, so
                        that two threads may charge one budget (a runtime's
                        frame loop and its drawing thread, fl_picture_draw) */
} MemBudget;

typedef struct MemHandler {
    MemFailFn fn;        /* NULL: write to stderr */
    void *ctx;           /* passed to fn */
    MemBudget *budget;   /* the budget charged on this thread, or NULL */
} MemHandler;

/* Install [fn] with [ctx] as this thread's failure handler, with no
 * budget; returns the one it replaces, to be handed back to mem_leave(). */
MemHandler mem_enter(MemFailFn fn, void *ctx);
/* The same with [budget] (may be NULL) charged on this thread until
 * mem_leave; with a budget, clears this thread's mark of a refusal
 * (mem_take_refusal), so each public call starts afresh. */
MemHandler mem_enter_budget(MemFailFn fn, void *ctx, MemBudget *budget);

/* The text of an execution error for a request the budget refused
 * (LANGUAGE.md §4.16: the expression gives null, the frame goes on). */
#define MEM_OOM_MESSAGE "Out of memory (past the memory budget, --max-memory)"

/* True when [bytes] more fit in this thread's budget (always true without
 * one). A refusal marks this thread (mem_take_refusal); nothing is
 * charged (the pool
 * charges the block when it allocates it). */
bool mem_fits(size_t bytes);
/* The same question without marking a refusal: for a caller that has
 * another way to go on when the answer is no (nothing to report). */
bool mem_room(size_t bytes);
/* mem_fits([bytes]) and, when it fits, charge them (give them back with
 * mem_unreserve): for big arrays that do not come from the pool. */
bool mem_reserve(size_t bytes);
/* mem_reserve against budget [b] itself rather than this thread's (NULL:
 * no budget): for memory a runtime holds across calls and may release in
 * any of them (the render graph's framebuffers, textures and decoded
 * pictures). Nothing is charged when it does not fit. */
bool mem_budget_reserve(MemBudget *b, size_t bytes);
/* Give back [bytes] that mem_budget_reserve charged to [b]. */
void mem_budget_release(MemBudget *b, size_t bytes);
/* Give back [bytes] charged by mem_reserve (or by the pool). */
void mem_unreserve(size_t bytes);
/* Charge [bytes] without asking (the pool, for a block it has malloc'd). */
void mem_charge(size_t bytes);
/* True when a request of this thread's was refused since the last call
 * (or since the current public call began); clears the mark. The code that logs the
 * failure asks this to say "out of memory" rather than something else. */
bool mem_take_refusal(void);
/* The default budget in bytes: half of physical memory, and never more
 * than half of the address-space limit (RLIMIT_AS; the rest is for code,
 * stacks, the parser and uncharged allocations); 0 when neither is known. */
size_t mem_default_limit(void);
/* Parse a size "N", "NK", "NM" or "NG" (binary multiples, case-insensitive,
 * N a whole number > 0) into *[out]; false, leaving it alone, otherwise. */
bool mem_parse_size(const char *text, size_t *out);
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
/* The library's one growable-array helper: [p] (NULL, or *[cap] elements
 * of [size] bytes from these functions) with room for at least [need]
 * elements, its capacity in *[cap] doubled from 16 until it holds them
 * (unchanged when it already does); the contents are kept. An overflowing
 * size calls mem_oom(). (Arrays in a runtime's pool grow by pool_grow.) */
void *mem_grow(void *p, size_t *cap, size_t need, size_t size);
char *mem_strdup(const char *s);
char *mem_strndup(const char *s, size_t n);
char *mem_asprintf(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

/* Test hook: make the mem_* allocation after the next [n] on this thread
 * fail as if out of memory (n = 0: the very next one); n < 0 turns the
 * hook off (the default). Only tests call this. */
void mem_test_fail_after(long n);

#endif
