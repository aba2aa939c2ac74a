/* fuzz_budget.h: a per-input time budget for the fuzz targets. A POSIX
 * timer signalling SIGRTMIN (libFuzzer's -timeout keeps SIGALRM) sets the
 * runtime's interrupt flag (flitter.h fl_options.interrupt) from a signal
 * handler, as Ctrl-C does in `flitter run`, once an input has run for
 * FUZZ_BUDGET_MS; an input that still runs on for libFuzzer's -timeout is
 * then a real hang. */
#ifndef FL_FUZZ_BUDGET_H
#define FL_FUZZ_BUDGET_H

#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define FUZZ_BUDGET_MS 2000

/* The flag the runtime polls; set by the timer's signal handler. */
static volatile int fuzz_interrupt;

static void fuzz_budget_expired(int sig)
{
    (void)sig;
    fuzz_interrupt = 1;
}

/* Clear the flag and (re)arm the timer for one input. */
static void fuzz_budget_start(void)
{
    static timer_t timer;
    static int made;
    if (!made) {
        struct sigaction sa;
        memset(&sa, 0, sizeof sa);
        sa.sa_handler = fuzz_budget_expired;
        sa.sa_flags = SA_RESTART;
        sigemptyset(&sa.sa_mask);
        struct sigevent ev;
        memset(&ev, 0, sizeof ev);
        ev.sigev_notify = SIGEV_SIGNAL;
        ev.sigev_signo = SIGRTMIN;
        if (sigaction(SIGRTMIN, &sa, NULL) != 0 || timer_create(CLOCK_MONOTONIC, &ev, &timer) != 0)
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
