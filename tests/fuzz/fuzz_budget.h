/* fuzz_budget.h: a per-input time budget for the fuzz targets. A POSIX
 * timer (its own thread, so libFuzzer's SIGALRM is left alone) sets the
 * runtime's interrupt flag (flitter.h fl_options.interrupt) once an input
 * has run for FUZZ_BUDGET_MS, which ends the frame the way Ctrl-C does; an
 * input that still runs on for libFuzzer's -timeout is then a real hang. */
#ifndef FL_FUZZ_BUDGET_H
#define FL_FUZZ_BUDGET_H

#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define FUZZ_BUDGET_MS 2000

/* The flag the runtime polls; set by the timer thread. */
static volatile int fuzz_interrupt;

static void fuzz_budget_expired(union sigval sv)
{
    (void)sv;
    fuzz_interrupt = 1;
}

/* Clear the flag and (re)arm the timer for one input. */
static void fuzz_budget_start(void)
{
    static timer_t timer;
    static int made;
    if (!made) {
        struct sigevent ev;
        memset(&ev, 0, sizeof ev);
        ev.sigev_notify = SIGEV_THREAD;
        ev.sigev_notify_function = fuzz_budget_expired;
        if (timer_create(CLOCK_MONOTONIC, &ev, &timer) != 0)
            abort();
        made = 1;
    }
    fuzz_interrupt = 0;
    struct itimerspec its;
    memset(&its, 0, sizeof its);
    its.it_value.tv_sec = FUZZ_BUDGET_MS / 1000;
    its.it_value.tv_nsec = (long)(FUZZ_BUDGET_MS % 1000) * 1000000L;
    timer_settime(timer, 0, &its, NULL);
}

#endif
