/* workers.c: the thread pool of workers.h.
 *
 * n - 1 threads wait for a job. A job is published as one 64-bit ticket of
 * its generation, its task count and the next task to hand out: the caller
 * writes the job (function, context) and zeroes the count of
 * finished tasks, then stores the ticket (g, 0) (release). A thread claims
 * task k < count by changing the ticket from (g, k) to (g, k + 1) with a
 * compare-and-swap (acquire), runs it, and adds one to the finished count;
 * the caller takes tasks the same way and then waits until
 * every task is finished (acquire). A thread that wakes late, after the
 * job is done, claims nothing (the ticket has moved on or its tasks are
 * all handed out), so the caller never waits for a thread to wake: only
 * for tasks that a running thread holds. The job's fields are not
 * rewritten before all its tasks are finished, and a claim of (g, k) can
 * only succeed while job g is the current one, so a task always runs with
 * its own job's function. Scheduling decides only which thread runs a
 * task, never what it writes.
 *
 * Waiting spins first and sleeps after: a frame posts several short jobs
 * back to back (a pair level, then the particle pass, for each step), and
 * waking a sleeping thread through the kernel costs tens of microseconds,
 * as much as a small scene's whole job. A worker polls the ticket for up
 * to SPIN_NS after its last job before it sleeps on the condition
 * variable; the caller polls the finished count for up to SPIN_NS before
 * it sleeps. The sleeping side announces itself (`sleepers`, `waiting`,
 * sequentially consistent) and then checks again under the mutex; the
 * waking side changes the value (sequentially consistent), then looks for
 * a sleeper and signals under the mutex: one of the two always sees the
 * other, so no wake-up is lost.
 */
#include "workers.h"

#include <pthread.h>
#include <sched.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdlib.h>
#include <time.h>
#include <unistd.h>

/* How long a waiting thread polls before it sleeps, in nanoseconds: past
 * the gap between one frame's last job and the next frame's first where
 * the caller alone works. canvas10k's worker finishes the numbers of its
 * loop kernel while the caller still builds nodes; with a shorter poll it
 * slept in every frame, the caller waking it and computing the next
 * frame's first chunks alone, and with this one it did not
 * (bench/PROFILE.md, "lib/core/workers.c: how long a waiting thread
 * polls"). The price: an idle worker keeps its core busy for 300 us
 * after each job (at 60 frames a second, about 2% of each worker's
 * core). */
#define SPIN_NS 300000

/* What a thread is started with; owned by the pool (the thread does not
 * free it: a thread that is late to start would then free memory during
 * some later frame, which steady frames must not do). */
typedef struct WorkerArg {
    Workers *w;
    unsigned id;
} WorkerArg;

struct Workers {
    unsigned n;                 /* threads in all, the caller included */
    unsigned started;           /* threads actually running */
    pthread_t *th;
    WorkerArg *args;            /* one per started thread */
    pthread_mutex_t mu;
    pthread_cond_t go, done;
    atomic_uint_fast64_t ticket; /* the current job: generation, task count, next task */
    atomic_size_t finished;     /* tasks of the current job done */
    atomic_uint sleepers;       /* workers asleep (or about to be) on go */
    atomic_bool waiting;        /* the caller asleep (or about to be) on done */
    atomic_bool quit;
    WorkersJob *bg;             /* the background job, until it ends */
    atomic_bool *bg_stop;       /* its stop flag */
    WorkersTaskFn fn;              /* the job (its task count is in the ticket):
                                   written before the ticket moves */
    void *ctx;
};

/* The ticket's fields: generation (24 bits), task count (20), next task
 * to hand out (20). Jobs of more tasks run on the caller alone. Should the
 * generation wrap while a thread holds an old ticket value, a claim with
 * it can only succeed when the ticket holds exactly that value again:
 * then it claims that task of the job that is current, with that job's
 * count, which is what a fresh read would have done. */
#define T_BITS 20
#define T_MASK (((uint64_t)1 << T_BITS) - 1)
#define T_GEN(x) ((x) >> (2 * T_BITS))
#define T_COUNT(x) (((x) >> T_BITS) & T_MASK)
#define T_NEXT(x) ((x) & T_MASK)
#define T_MAKE(gen, count) ((((gen) & 0xffffffu) << (2 * T_BITS)) | ((uint64_t)(count) << T_BITS))

/* One polling pause. */
static inline void spin_pause(void)
{
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#endif
}

static uint64_t now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000000000u + (uint64_t)ts.tv_nsec;
}

/* Whether the generation of *v stays [gen] for SPIN_NS (false as soon as
 * it changes). */
static bool spin_while_gen(atomic_uint_fast64_t *v, uint64_t gen)
{
    uint64_t until = 0;
    for (unsigned i = 0;; i++) {
        if (T_GEN(atomic_load_explicit(v, memory_order_relaxed)) != gen)
            return false;
        spin_pause();
        if ((i & 63) == 63) {
            uint64_t t = now_ns();
            if (!until)
                until = t + SPIN_NS;
            else if (t >= until)
                return true;
        }
    }
}

/* Claim one task of the job of ticket value *[cur] (read before) and run
 * it; false when none is left to hand out or another job is current.
 * *[cur] is left at the ticket's value after the claim (or as last seen). */
static bool take_one(Workers *w, unsigned id, uint64_t *cur)
{
    const uint64_t gen = T_GEN(*cur), n = T_COUNT(*cur);
    for (;;) {
        if (T_GEN(*cur) != gen || T_NEXT(*cur) >= n)
            return false;
        /* a claim succeeds only while the job is current and the task is
         * not yet handed out; the job's fields are then the ones stored
         * before the ticket (acquire pairs with the caller's store), and
         * they stay until this task is counted finished */
        if (atomic_compare_exchange_weak_explicit(&w->ticket, cur, *cur + 1,
                                                  memory_order_acquire,
                                                  memory_order_relaxed))
            break;
    }
    w->fn(w->ctx, (size_t)T_NEXT(*cur), id);
    /* sequentially consistent, as the look at `waiting` after it: the
     * caller stores `waiting` and then looks at the count, so one of
     * the two sees the other and no wake-up is lost */
    size_t done = atomic_fetch_add(&w->finished, 1) + 1;
    if (done == n && id != 0 && atomic_load(&w->waiting)) {
        pthread_mutex_lock(&w->mu);
        pthread_cond_signal(&w->done);
        pthread_mutex_unlock(&w->mu);
    }
    (*cur)++;
    return true;
}

/* Claim and run tasks of the job of ticket value [cur] (read before)
 * until none is left to hand out or another job is current. */
static void take_tasks(Workers *w, unsigned id, uint64_t cur)
{
    while (take_one(w, id, &cur)) {
    }
}

static void *worker_main(void *arg)
{
    WorkerArg a = *(const WorkerArg *)arg;
    Workers *w = a.w;
    uint64_t seen = 0;          /* the last generation this thread joined */
    for (;;) {
        if (spin_while_gen(&w->ticket, seen)) {
            pthread_mutex_lock(&w->mu);
            atomic_fetch_add(&w->sleepers, 1);
            while (T_GEN(atomic_load(&w->ticket)) == seen && !atomic_load(&w->quit))
                pthread_cond_wait(&w->go, &w->mu);
            atomic_fetch_sub(&w->sleepers, 1);
            pthread_mutex_unlock(&w->mu);
        }
        if (atomic_load_explicit(&w->quit, memory_order_acquire))
            break;
        uint64_t cur = atomic_load_explicit(&w->ticket, memory_order_relaxed);
        seen = T_GEN(cur);
        take_tasks(w, a.id, cur);
    }
    return NULL;
}

Workers *workers_new(unsigned n)
{
    if (n < 1)
        n = 1;
    Workers *w = calloc(1, sizeof *w);
    if (!w)
        return NULL;
    w->n = n;
    atomic_init(&w->ticket, 0);
    atomic_init(&w->finished, 0);
    atomic_init(&w->sleepers, 0);
    atomic_init(&w->waiting, false);
    atomic_init(&w->quit, false);
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

/* End [w]'s background job, if one runs: its stop flag (with [stop]),
 * then its tasks. */
static void end_background(Workers *w, bool stop)
{
    WorkersJob *j = w->bg;
    if (!j)
        return;
    w->bg = NULL;
    if (stop)
        atomic_store_explicit(w->bg_stop, true, memory_order_relaxed);
    workers_finish(j);
}

void workers_free(Workers *w)
{
    if (!w)
        return;
    end_background(w, true);
    if (w->th) {
        pthread_mutex_lock(&w->mu);
        atomic_store(&w->quit, true);
        atomic_store(&w->ticket, T_MAKE(T_GEN(atomic_load(&w->ticket)) + 1, 0));
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

unsigned workers_count(const Workers *w)
{
    return w ? w->n : 1;
}

void workers_start(Workers *w, WorkersJob *j, size_t ntasks, WorkersTaskFn fn, void *ctx)
{
    const bool threads = w && w->n > 1 && ntasks > 1 && ntasks <= T_MASK;
    /* before *j is written: [j] may be the background job itself */
    if (threads)
        end_background(w, true);
    *j = (WorkersJob){w, ntasks, 0, fn, ctx};
    if (!threads) {
        j->w = NULL;
        return;
    }
    /* every task of the job before is finished, so no thread reads these
     * now: a claim needs the new ticket, stored after them */
    w->fn = fn;
    w->ctx = ctx;
    atomic_store_explicit(&w->finished, 0, memory_order_relaxed);
    const uint64_t ticket = T_MAKE(T_GEN(atomic_load_explicit(&w->ticket, memory_order_relaxed)) + 1,
                                   ntasks);
    /* publishes the job (sequentially consistent, so the look at
     * `sleepers` below cannot come before it) */
    atomic_store(&w->ticket, ticket);
    if (atomic_load(&w->sleepers) > 0) {
        pthread_mutex_lock(&w->mu);
        pthread_cond_broadcast(&w->go);
        pthread_mutex_unlock(&w->mu);
    }
}

bool workers_background(Workers *w, WorkersJob *j, size_t ntasks, WorkersTaskFn fn, void *ctx,
                        atomic_bool *stop)
{
    if (!w || w->n == 1 || ntasks <= 1 || ntasks > T_MASK)
        return false;
    workers_start(w, j, ntasks, fn, ctx);   /* ends the one before */
    w->bg = j;
    w->bg_stop = stop;
    return true;
}

void workers_end_background(Workers *w, WorkersJob *j, bool stop)
{
    if (w && w->bg == j)
        end_background(w, stop);
}

bool workers_help(WorkersJob *j)
{
    if (!j->w) {
        if (j->next >= j->ntasks)
            return false;
        j->fn(j->ctx, j->next++, 0);
        return true;
    }
    uint64_t cur = atomic_load_explicit(&j->w->ticket, memory_order_relaxed);
    return take_one(j->w, 0, &cur);
}

void workers_finish(WorkersJob *j)
{
    Workers *w = j->w;
    if (!w) {
        while (workers_help(j)) {
        }
        return;
    }
    const size_t ntasks = j->ntasks;
    take_tasks(w, 0, atomic_load_explicit(&w->ticket, memory_order_relaxed));
    uint64_t until = 0;
    for (unsigned i = 0; atomic_load_explicit(&w->finished, memory_order_acquire) < ntasks; i++) {
        spin_pause();
        if ((i & 63) != 63)
            continue;
        uint64_t t = now_ns();
        if (!until) {
            until = t + SPIN_NS;
            continue;
        }
        if (t < until)
            continue;
        pthread_mutex_lock(&w->mu);
        atomic_store(&w->waiting, true);
        while (atomic_load(&w->finished) < ntasks)
            pthread_cond_wait(&w->done, &w->mu);
        atomic_store(&w->waiting, false);
        pthread_mutex_unlock(&w->mu);
        break;
    }
}

void workers_run(Workers *w, size_t ntasks, WorkersTaskFn fn, void *ctx)
{
    WorkersJob j;
    workers_start(w, &j, ntasks, fn, ctx);
    workers_finish(&j);
}

size_t workers_split(size_t n, size_t min_chunk, size_t *chunk)
{
    size_t c = (n + WORKERS_MAX_TASKS - 1) / WORKERS_MAX_TASKS;
    *chunk = c > min_chunk ? c : min_chunk > 0 ? min_chunk : 1;
    return (n + *chunk - 1) / *chunk;
}

unsigned workers_available_cores(void)
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
