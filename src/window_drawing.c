/* window_drawing.c: the drawing thread of a run with OpenGL windows
 * (window_loop.h). It makes the frame loop's OpenGL context current once,
 * attaches the pages' runtimes to it, and from then on every drawing of
 * their render graphs happens here:
 * - a frame's picture (fl_picture_take) is drawn while the frame loop
 *   steps the next frame: neither waits for the other (issue 58: before,
 *   the simulation waited for every picture drawn);
 * - what cannot be drawn beside the next frame (the physics view, a page
 *   without the window's OpenGL, a frame whose !record writes a file, a
 *   tree that calls back into the runtime) is a task the frame loop posts
 *   and waits for.
 * One job at a time: the frame loop posts only to an idle thread. */
#include "window.h"

#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "window_loop.h"

/* Whether the X display's connection is lost: the drawing thread may
 * then be held in an X call for good (window_lost.h), and the frame loop
 * stops waiting for it (the run ends: its stack frames then no longer
 * matter, nor do the task contexts, which live in the Loop). */
static bool lost(Loop *L) { return winlost_kind(&L->hand->lost) == LOST_CONNECTION; }

/* Wait on [d]'s condition for at most 20 ms; d->mu must be held. */
static void wait_a_little(Drawing *d)
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    ts.tv_nsec += 20000000;
    if (ts.tv_nsec >= 1000000000) {
        ts.tv_sec++;
        ts.tv_nsec -= 1000000000;
    }
    pthread_cond_timedwait(&d->cond, &d->mu, &ts);
}

/* Draw the picture of [d]'s job (see drawing_post) into [*r]. */
static void draw_picture(Loop *L, Drawing *d, DrawResult *r)
{
    Handover *h = L->hand;
    double t0 = handover_now();
    PictureSet *set = &h->sets[d->set];
    if (d->scaling) fl_set_window_scale(d->rt, d->scale, d->samples);
    wingl_lock(h->gl);
    double locked = handover_now();
    for (size_t k = 0; k < set->n; k++) {
        ShownWindow *s = &set->win[k];
        s->paint = false;
        s->gl = true;
        fl_view_snapshot_free(s->snap);   /* (no physics view in this set) */
        s->snap = NULL;
        int tw, th;
        unsigned tex = fl_picture_texture(d->rt, d->pic, s->index, &tw, &th);
        if (!tex || !wingl_frame_copy(h->gl, &s->glpic, tex, tw, th)) s->glpic.w = s->glpic.h = 0;
        s->pw = s->glpic.w;
        s->ph = s->glpic.h;
    }
    wingl_unlock(h->gl);
    double t1 = handover_now();
    int samples = 0;
    double scale = fl_window_scale(d->rt, &samples);
    pthread_mutex_lock(&h->mu);
    h->state[d->set] = SET_PENDING;
    pthread_mutex_unlock(&h->mu);
    handover_wake(h);
    *r = (DrawResult){.rt = d->rt, .pic = d->pic, .seconds = t1 - t0, .locked_seconds = t1 - locked,
                      .end = t1, .scale = scale, .samples = samples};
}

void drawing_attach(Loop *L)
{
    Handover *h = L->hand;
    wingl_lock(h->gl);
    if (h->gl && wingl_frame_enter(h->gl)) {
        L->gl = true;
        for (int i = 0; i < L->npages; i++) {
            Page *p = &L->pages[i];
            p->gl = fl_gl_attach(p->rt) == 0;
            if (!p->gl && L->spec->verbosity >= 1)
                fprintf(L->log, "flitter: page %d draws without the window's OpenGL: %s", i + 1, fl_error(p->rt));
        }
    }
    wingl_unlock(h->gl);
}

static void *drawing_thread(void *arg)
{
    Loop *L = arg;
    Drawing *d = &L->draw;
    Handover *h = L->hand;
    drawing_attach(L);
    pthread_mutex_lock(&d->mu);
    d->ready = true;
    pthread_cond_broadcast(&d->cond);
    for (;;) {
        while (d->kind == DRAW_NONE) pthread_cond_wait(&d->cond, &d->mu);
        DrawKind kind = d->kind;
        if (kind == DRAW_STOP) break;
        pthread_mutex_unlock(&d->mu);
        DrawResult r;
        if (kind == DRAW_TASK) d->task(L, d->task_ctx);
        else draw_picture(L, d, &r);
        pthread_mutex_lock(&d->mu);
        if (kind == DRAW_PICTURE) {
            d->result = r;
            d->done = true;
        }
        d->kind = DRAW_NONE;
        pthread_cond_broadcast(&d->cond);
    }
    d->kind = DRAW_NONE;
    pthread_mutex_unlock(&d->mu);
    if (L->gl) wingl_frame_leave(h->gl);
    return NULL;
}

bool drawing_start(Loop *L)
{
    Drawing *d = &L->draw;
    if (!L->hand->gl) return false;
    pthread_mutex_init(&d->mu, NULL);
    pthread_cond_init(&d->cond, NULL);
    if (pthread_create(&d->thread, NULL, drawing_thread, L) != 0) {
        pthread_cond_destroy(&d->cond);
        pthread_mutex_destroy(&d->mu);
        return false;
    }
    d->running = true;
    pthread_mutex_lock(&d->mu);
    while (!d->ready) pthread_cond_wait(&d->cond, &d->mu);
    pthread_mutex_unlock(&d->mu);
    return true;
}

void drawing_stop(Loop *L)
{
    Drawing *d = &L->draw;
    if (!d->running) return;
    pthread_mutex_lock(&d->mu);
    while (d->kind != DRAW_NONE) pthread_cond_wait(&d->cond, &d->mu);
    d->kind = DRAW_STOP;
    pthread_cond_broadcast(&d->cond);
    pthread_mutex_unlock(&d->mu);
    pthread_join(d->thread, NULL);
    d->running = false;
    DrawResult r;
    bool taken;
    drawing_poll(L, &r, &taken);
    if (taken) fl_picture_free(r.rt, r.pic);
    pthread_cond_destroy(&d->cond);
    pthread_mutex_destroy(&d->mu);
}

bool drawing_poll(Loop *L, DrawResult *out, bool *taken)
{
    Drawing *d = &L->draw;
    bool running = d->running;   /* (stopped: its last picture, without the lock) */
    if (running) pthread_mutex_lock(&d->mu);
    bool busy = running && d->kind != DRAW_NONE;
    *taken = d->done;
    if (d->done) {
        *out = d->result;
        d->done = false;
    }
    if (running) pthread_mutex_unlock(&d->mu);
    return busy;
}

bool drawing_wait_idle(Loop *L)
{
    Drawing *d = &L->draw;
    if (!d->running) return true;
    pthread_mutex_lock(&d->mu);
    while (d->kind != DRAW_NONE && !lost(L)) wait_a_little(d);
    bool idle = d->kind == DRAW_NONE;
    pthread_mutex_unlock(&d->mu);
    return idle;
}

bool drawing_settle(Loop *L, double seconds)
{
    Drawing *d = &L->draw;
    if (!d->running || pthread_equal(pthread_self(), d->thread)) return true;
    double until = handover_now() + seconds;
    pthread_mutex_lock(&d->mu);
    while (d->kind != DRAW_NONE && handover_now() < until) wait_a_little(d);
    bool idle = d->kind == DRAW_NONE;
    pthread_mutex_unlock(&d->mu);
    return idle;
}

bool drawing_run(Loop *L, void (*fn)(Loop *L, void *ctx), void *ctx)
{
    Drawing *d = &L->draw;
    if (!d->running) {
        fn(L, ctx);
        return true;
    }
    if (!drawing_wait_idle(L)) return false;
    pthread_mutex_lock(&d->mu);
    d->task = fn;
    d->task_ctx = ctx;
    d->kind = DRAW_TASK;
    pthread_cond_broadcast(&d->cond);
    while (d->kind != DRAW_NONE && !lost(L)) wait_a_little(d);
    bool ran = d->kind == DRAW_NONE;
    pthread_mutex_unlock(&d->mu);
    return ran;
}

void drawing_post(Loop *L, fl_runtime *rt, fl_picture *pic, int set, bool scaling, double scale, int samples)
{
    Drawing *d = &L->draw;
    pthread_mutex_lock(&d->mu);
    /* (the caller has taken the last picture's results: drawing_poll) */
    d->rt = rt;
    d->pic = pic;
    d->set = set;
    d->scaling = scaling;
    d->scale = scale;
    d->samples = samples;
    d->kind = DRAW_PICTURE;
    pthread_cond_broadcast(&d->cond);
    pthread_mutex_unlock(&d->mu);
}

