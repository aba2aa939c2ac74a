/* workers.h: a small pool of threads (the physics engine's, which the
 * runtime also lends to the evaluator).
 *
 * A Workers runs "tasks 0 .. n-1" of one job on its threads and the
 * calling thread, handing tasks out in any order; the job returns when all
 * tasks are done. Tasks must write disjoint memory, so results never depend
 * on which thread ran which task. The pool belongs to one PhysicsWorld (no
 * process-wide state); it is in core so that other layers may run jobs on it.
 */
#ifndef FL_WORKERS_H
#define FL_WORKERS_H

#include <stdatomic.h>
#include <stdbool.h>
#include <stddef.h>

typedef struct Workers Workers;

/* One task: [task] in 0 .. ntasks-1, [thread] in 0 .. count-1 (the index of
 * the running thread, for per-thread scratch). */
typedef void (*WorkersTaskFn)(void *ctx, size_t task, unsigned thread);

/* A pool of [n] threads in all, the caller included (n - 1 are started).
 *   errors: n < 1 is taken as 1; returns NULL when memory or threads cannot
 *           be had (callers then run single-threaded) */
Workers *workers_new(unsigned n);
/* Stop and join the threads and free [w] (NULL is a no-op). */
void workers_free(Workers *w);
/* Number of threads, the caller included (1 for NULL). */
unsigned workers_count(const Workers *w);
/* Run fn(ctx, t, thread) for every t < ntasks and wait for all of them.
 * With NULL or one thread, runs them in order on the caller (thread 0). */
void workers_run(Workers *w, size_t ntasks, WorkersTaskFn fn, void *ctx);
/* A job started with workers_start(): the caller may take its tasks one
 * at a time (workers_help) while the other threads take theirs, and must
 * end it with workers_finish(). Filled by workers_start; the caller only
 * keeps it. */
typedef struct WorkersJob {
    Workers *w;             /* the pool running it, or NULL: the caller runs
                               every task (no pool, one thread, one task) */
    size_t ntasks;
    size_t next;            /* without a pool: the next task to run */
    WorkersTaskFn fn;
    void *ctx;
} WorkersJob;
/* Start fn(ctx, t, thread) for every t < ntasks on the pool's other threads
 * and return at once (with NULL or one thread, nothing runs yet). Tasks are
 * handed out in increasing order of t. The caller must call
 * workers_finish(j) before it starts another job on [w] or frees anything
 * the tasks use. */
void workers_start(Workers *w, WorkersJob *j, size_t ntasks, WorkersTaskFn fn, void *ctx);
/* Take the next task of [j] not yet handed out and run it on the caller
 * (thread 0); false when every task has been handed out (some may still be
 * running on other threads). */
bool workers_help(WorkersJob *j);
/* Run the tasks of [j] not yet handed out on the caller and wait until
 * every task of [j] is finished. */
void workers_finish(WorkersJob *j);
/* Start [j] as the pool's background job: fn(ctx, t, thread) for every
 * t < ntasks runs on the pool's other threads while the caller goes on
 * with other work, across returns to its own caller. The job ends, its
 * tasks finished, before any later job that runs on [w]'s threads starts
 * (workers_start, workers_run; a job of one task, or on one thread, runs
 * on the caller alone and leaves it), before another background job, in
 * workers_end_background() and in workers_free(): *[stop] is then set
 * first, and a task should return soon after it sees it (tasks not yet
 * handed out then run on the ending thread, and should return at once).
 * [j], [ctx] and [stop] must stay until the job has ended. Only the thread
 * that starts jobs on [w] may call it.
 *   returns: false, having run nothing, with NULL or one thread or when
 *            [ntasks] is not in 2 .. 2^20 - 1 (the work is then the
 *            caller's to do or skip) */
bool workers_background(Workers *w, WorkersJob *j, size_t ntasks, WorkersTaskFn fn, void *ctx,
                        atomic_bool *stop);
/* End [j] if it is still [w]'s background job: with [stop], set its stop
 * flag, then wait for its tasks; without, wait for them to end on their
 * own (tasks not yet handed out run on the caller). Nothing when a later
 * job already ended it. After it returns, every write of j's tasks is
 * visible to the caller. */
void workers_end_background(Workers *w, WorkersJob *j, bool stop);
/* A pause for a thread polling a flag another thread will set (a spin
 * loop's hint to the processor). */
static inline void workers_pause(void)
{
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#endif
}
/* The most tasks workers_split() makes, so per-task results fit in
 * fixed arrays (no allocation per frame). */
#define WORKERS_MAX_TASKS 64
/* Split [n] items into tasks of [*chunk] consecutive items each (the last
 * one shorter): at least [min_chunk] items a task, at most WORKERS_MAX_TASKS
 * tasks. Returns the number of tasks (0 when n is 0). */
size_t workers_split(size_t n, size_t min_chunk, size_t *chunk);
/* One past the last item of task [t] of [n] items split in [chunk]s. */
static inline size_t workers_task_end(size_t t, size_t chunk, size_t n)
{
    return (t + 1) * chunk < n ? (t + 1) * chunk : n;
}
/* The number of processors this process may run on (at least 1). */
unsigned workers_available_cores(void);

#endif
