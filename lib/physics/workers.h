/* workers.h: a small pool of threads for the physics engine.
 *
 * A PhysWorkers runs "tasks 0 .. n-1" of one job on its threads and the
 * calling thread, handing tasks out in any order; the job returns when all
 * tasks are done. Tasks must write disjoint memory, so results never depend
 * on which thread ran which task. The pool belongs to one PhysicsWorld (no
 * process-wide state).
 */
#ifndef FL_PHYS_WORKERS_H
#define FL_PHYS_WORKERS_H

#include <stddef.h>

typedef struct PhysWorkers PhysWorkers;

/* One task: [task] in 0 .. ntasks-1, [thread] in 0 .. count-1 (the index of
 * the running thread, for per-thread scratch). */
typedef void (*PhysTaskFn)(void *ctx, size_t task, unsigned thread);

/* A pool of [n] threads in all, the caller included (n - 1 are started).
 *   errors: n < 1 is taken as 1; returns NULL when memory or threads cannot
 *           be had (callers then run single-threaded) */
PhysWorkers *phys_workers_new(unsigned n);
/* Stop and join the threads and free [w] (NULL is a no-op). */
void phys_workers_free(PhysWorkers *w);
/* Number of threads, the caller included (1 for NULL). */
unsigned phys_workers_count(const PhysWorkers *w);
/* Run fn(ctx, t, thread) for every t < ntasks and wait for all of them.
 * With NULL or one thread, runs them in order on the caller (thread 0). */
void phys_workers_run(PhysWorkers *w, size_t ntasks, PhysTaskFn fn, void *ctx);
/* The most tasks phys_workers_split() makes, so per-task results fit in
 * fixed arrays (no allocation per frame). */
#define PHYS_MAX_TASKS 64
/* Split [n] items into tasks of [*chunk] consecutive items each (the last
 * one shorter): at least [min_chunk] items a task, at most PHYS_MAX_TASKS
 * tasks. Returns the number of tasks (0 when n is 0). */
size_t phys_workers_split(size_t n, size_t min_chunk, size_t *chunk);
/* One past the last item of task [t] of [n] items split in [chunk]s. */
static inline size_t phys_task_end(size_t t, size_t chunk, size_t n)
{
    return (t + 1) * chunk < n ? (t + 1) * chunk : n;
}
/* The number of processors this process may run on (at least 1). */
unsigned phys_available_cores(void);

#endif
