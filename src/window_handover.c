/* window_handover.c: where the frame loop and the display of a run with
 * live windows meet (window_loop.h): the input queue, the two picture
 * sets passed from one to the other, the overlay text, the counters. */
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "window_loop.h"

double handover_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

void handover_init(Handover *h)
{
    *h = (Handover){0};
    pthread_condattr_t ca;
    if (pthread_mutex_init(&h->mu, NULL) != 0 || pthread_condattr_init(&ca) != 0 ||
        pthread_condattr_setclock(&ca, CLOCK_MONOTONIC) != 0 || pthread_cond_init(&h->cond, &ca) != 0 ||
        pthread_cond_init(&h->display_cond, &ca) != 0)
        abort();
    pthread_condattr_destroy(&ca);
}

void handover_free(Handover *h)
{
    for (int i = 0; i < 2; i++) {
        PictureSet *s = &h->sets[i];
        for (size_t k = 0; k < s->cap; k++) {
            free(s->win[k].px);
            fl_view_snapshot_free(s->win[k].snap);
        }
        free(s->win);
    }
    free(h->inputs);
    free(h->status);
    free(h->error);
    pthread_cond_destroy(&h->cond);
    pthread_cond_destroy(&h->display_cond);
    pthread_mutex_destroy(&h->mu);
}

void handover_wake(Handover *h)
{
    pthread_mutex_lock(&h->mu);
    pthread_cond_signal(&h->display_cond);
    pthread_mutex_unlock(&h->mu);
}

void handover_input(Handover *h, const Input *in)
{
    pthread_mutex_lock(&h->mu);
    if (h->ninputs == h->cap_inputs) {
        h->cap_inputs = h->cap_inputs ? h->cap_inputs * 2 : 64;
        h->inputs = realloc(h->inputs, h->cap_inputs * sizeof *h->inputs);
        if (!h->inputs) abort();
    }
    h->inputs[h->ninputs++] = *in;
    pthread_cond_signal(&h->cond);
    pthread_mutex_unlock(&h->mu);
}

void handover_wait_on(Handover *h, pthread_cond_t *cond, double due)
{
    struct timespec ts = {(time_t)due, 0};
    ts.tv_nsec = (long)((due - (double)ts.tv_sec) * 1e9);
    if (ts.tv_nsec < 0) ts.tv_nsec = 0;
    if (ts.tv_nsec >= 1000000000L) ts.tv_nsec = 999999999L;
    int rc = pthread_cond_timedwait(cond, &h->mu, &ts);
    (void)rc;   /* ETIMEDOUT or a signal: the caller checks what it waits for */
}

void handover_wait(Handover *h, double due) { handover_wait_on(h, &h->cond, due); }
