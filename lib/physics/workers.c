/* workers.c: the physics engine's thread pool (workers.h).
 *
 * n - 1 threads sleep on a condition variable until a job is posted: the
 * job (function, context, task count) is published under the mutex together
 * with a new generation number, and every thread, the caller included,
 * takes tasks from one atomic counter until it runs past the count. The
 * caller then waits under the mutex until every started thread has
 * reported the job done, so all task writes happen before the job returns.
 * Scheduling decides only which thread runs a task, never what it writes.
 */
#include "workers.h"

#include <pthread.h>
#include <sched.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdlib.h>
#include <unistd.h>

/* What a thread is started with; owned by the pool (the thread does not
 * free it: a thread that is late to start would then free memory during
 * some later frame, which steady frames must not do). */
typedef struct WorkerArg {
    PhysWorkers *w;
    unsigned id;
} WorkerArg;

struct PhysWorkers {
    unsigned n;                 /* threads in all, the caller included */
    unsigned started;           /* threads actually running */
    pthread_t *th;
    WorkerArg *args;            /* one per started thread */
    pthread_mutex_t mu;
    pthread_cond_t go, done;
    uint64_t gen;               /* job generation, under mu */
    unsigned busy;              /* started threads still on the job */
    bool quit;
    PhysTaskFn fn;
    void *ctx;
    size_t ntasks;
    atomic_size_t next;         /* next task to hand out */
};


static void take_tasks(PhysWorkers *w, unsigned id)
{
    for (;;) {
        size_t t = atomic_fetch_add_explicit(&w->next, 1, memory_order_relaxed);
        if (t >= w->ntasks)
            break;
        w->fn(w->ctx, t, id);
    }
}

static void *worker_main(void *arg)
{
    WorkerArg a = *(const WorkerArg *)arg;
    PhysWorkers *w = a.w;
    uint64_t seen = 0;
    pthread_mutex_lock(&w->mu);
    for (;;) {
        while (w->gen == seen && !w->quit)
            pthread_cond_wait(&w->go, &w->mu);
        if (w->quit)
            break;
        seen = w->gen;
        pthread_mutex_unlock(&w->mu);
        take_tasks(w, a.id);
        pthread_mutex_lock(&w->mu);
        if (--w->busy == 0)
            pthread_cond_signal(&w->done);
    }
    pthread_mutex_unlock(&w->mu);
    return NULL;
}

PhysWorkers *phys_workers_new(unsigned n)
{
    if (n < 1)
        n = 1;
    PhysWorkers *w = calloc(1, sizeof *w);
    if (!w)
        return NULL;
    w->n = n;
    atomic_init(&w->next, 0);
    if (n == 1)
        return w;
    w->th = calloc(n - 1, sizeof *w->th);
    w->args = calloc(n - 1, sizeof *w->args);
    if (!w->th || !w->args) {
        free(w->th);
        free(w->args);
        free(w);
        return NULL;
    }
    pthread_mutex_init(&w->mu, NULL);
    pthread_cond_init(&w->go, NULL);
    pthread_cond_init(&w->done, NULL);
    /* the threads start with every signal blocked (they inherit the mask),
     * so a signal meant for the process (Ctrl-C: the REPL waits for it in
     * pselect on the calling thread) is never taken by a worker */
    sigset_t all, old;
    sigfillset(&all);
    pthread_sigmask(SIG_SETMASK, &all, &old);
    for (unsigned i = 0; i < n - 1; i++) {
        WorkerArg *a = &w->args[i];
        *a = (WorkerArg){w, i + 1};
        if (pthread_create(&w->th[i], NULL, worker_main, a) != 0)
            break;
        w->started++;
    }
    pthread_sigmask(SIG_SETMASK, &old, NULL);
    /* fewer threads than asked: the pool still works, task ids of the
     * missing threads are simply never used */
    w->n = w->started + 1;
    return w;
}

void phys_workers_free(PhysWorkers *w)
{
    if (!w)
        return;
    if (w->th) {
        pthread_mutex_lock(&w->mu);
        w->quit = true;
        pthread_cond_broadcast(&w->go);
        pthread_mutex_unlock(&w->mu);
        for (unsigned i = 0; i < w->started; i++)
            pthread_join(w->th[i], NULL);
        pthread_mutex_destroy(&w->mu);
        pthread_cond_destroy(&w->go);
        pthread_cond_destroy(&w->done);
        free(w->th);
        free(w->args);
    }
    free(w);
}

unsigned phys_workers_count(const PhysWorkers *w)
{
    return w ? w->n : 1;
}

void phys_workers_run(PhysWorkers *w, size_t ntasks, PhysTaskFn fn, void *ctx)
{
    if (!w || w->n == 1 || ntasks <= 1) {
        for (size_t t = 0; t < ntasks; t++)
            fn(ctx, t, 0);
        return;
    }
    pthread_mutex_lock(&w->mu);
    w->fn = fn;
    w->ctx = ctx;
    w->ntasks = ntasks;
    atomic_store_explicit(&w->next, 0, memory_order_relaxed);
    w->busy = w->started;
    w->gen++;
    pthread_cond_broadcast(&w->go);
    pthread_mutex_unlock(&w->mu);
    take_tasks(w, 0);
    pthread_mutex_lock(&w->mu);
    while (w->busy > 0)
        pthread_cond_wait(&w->done, &w->mu);
    pthread_mutex_unlock(&w->mu);
}

unsigned phys_available_cores(void)
{
    cpu_set_t set;
    if (sched_getaffinity(0, sizeof set, &set) == 0) {
        int n = CPU_COUNT(&set);
        if (n > 0)
            return (unsigned)n;
    }
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n > 0 ? (unsigned)n : 1;
}
