/* window_display.c: the display's side of a run with live windows, on
 * the thread that started SDL (window_loop.h). It takes SDL events,
 * which it turns into Inputs for the frame loop (keys, the pointer as
 * fractions of the picture it falls on, buttons, closing), and waits for
 * picture sets the frame loop hands over (h->display_cond): the open windows (Slots) follow each set's descriptions, take
 * its pictures into their textures (the set is then free for the frame
 * loop again), paint the overlay text when it changed, and present. All
 * the time spent presenting is off the frame loop's thread. It looks at
 * SDL's events at least every 4 ms (SDL_PollEvent; waking SDL_WaitEvent
 * from the frame loop would make an X11 request on that thread). */
#include <stdlib.h>
#include <string.h>

#include "exitcodes.h"
#include "overlay.h"
#include "window_loop.h"

/* One open window. */
typedef struct Slot {
    WinView view;
    size_t index;            /* fl_windows index of its !window, or NO_WINDOW */
    unsigned overlay_gen;    /* Display.overlay_gen its overlay was painted for */
} Slot;

typedef struct Display {
    Handover *h;
    const WinOptions *wopt;
    FILE *log;
    Slot *slots;
    size_t nslots, cap;
    char *status, *error;    /* copies of the handover's overlay text */
    unsigned overlay_gen;    /* bumped when they change (never 0 once copied) */
    bool represent;          /* present again (exposed, resized) */
    int view_w, view_h;      /* the view window's output size last told the frame loop */
    bool screen_told;        /* a missing --screen was reported */
    fl_view_painter *painter; /* paints the physics view's snapshots (made when first needed) */
    bool gone;               /* a window was destroyed by another X client: nothing more drawn */
} Display;

/* The slot of the SDL window [id], or NULL (a window already closed). */
static Slot *slot_of(Display *D, Uint32 id)
{
    for (size_t i = 0; i < D->nslots; i++)
        if (D->slots[i].view.id == id) return &D->slots[i];
    return NULL;
}

/* SDL button numbers to GLFW's: left 0, right 1, middle 2, then 3, 4. */
static int glfw_button(Uint8 b)
{
    switch (b) {
    case SDL_BUTTON_LEFT: return 0;
    case SDL_BUTTON_RIGHT: return 1;
    case SDL_BUTTON_MIDDLE: return 2;
    default: return b - 1;   /* SDL_BUTTON_X1 (4) -> 3, X2 (5) -> 4 */
    }
}

/* Tell the frame loop the physics view window's output size when it
 * changed (it draws the view at that size). */
static void tell_view_size(Display *D)
{
    int w = 0, h = 0;
    if (D->nslots == 1 && D->slots[0].index == NO_WINDOW)
        winview_output_size(&D->slots[0].view, &w, &h);
    if (w == D->view_w && h == D->view_h) return;
    bool was_open = D->view_w > 0;
    D->view_w = w;
    D->view_h = h;
    pthread_mutex_lock(&D->h->mu);
    D->h->view_w = w;
    D->h->view_h = h;
    pthread_mutex_unlock(&D->h->mu);
    if (was_open && w > 0) handover_input(D->h, &(Input){.kind = INPUT_RESIZED, .index = NO_WINDOW});
}

/* Whether X window [xid] is one of the run's: a shown window or one that
 * holds an OpenGL context (those SDL closed itself are no longer here). */
static bool ours(Display *D, unsigned long xid)
{
    SDL_Window *a, *b;
    wingl_windows(D->h->gl, &a, &b);
    if (winlost_xid(a) == xid || winlost_xid(b) == xid) return true;
    for (size_t i = 0; i < D->nslots; i++)
        if (winlost_xid(D->slots[i].view.window) == xid) return true;
    return false;
}

/* A window of the run was destroyed by another X client: the run ends
 * (exit status 3, window_lost.h) and nothing more is drawn. */
static void window_gone(Display *D)
{
    if (D->gone) return;
    D->gone = true;
    if (winlost_set_destroyed(&D->h->lost))
        fprintf(D->log, "flitter: the window was destroyed by another X client: the run ends "
                "(exit status %d)\n", EXIT_WINDOW_LOST);
    handover_input(D->h, &(Input){.kind = INPUT_QUIT, .index = NO_WINDOW});
}

/* Turn SDL event [ev] into an Input for the frame loop, or act on it. */
static void sdl_event(Display *D, const SDL_Event *ev)
{
    Slot *s;
    Input in = {.index = NO_WINDOW};
    unsigned long xid;
    switch (ev->type) {
    case SDL_QUIT:
        in.kind = INPUT_QUIT;
        break;
    case SDL_SYSWMEVENT:
        xid = winlost_destroyed(ev);
        if (xid && ours(D, xid)) window_gone(D);
        return;
    case SDL_KEYDOWN:
    case SDL_KEYUP:
        if (ev->key.repeat) return;
        s = slot_of(D, ev->key.windowID);
        in = (Input){.kind = INPUT_KEY, .index = s ? s->index : NO_WINDOW,
                     .scancode = ev->key.keysym.scancode, .pressed = ev->type == SDL_KEYDOWN};
        break;
    case SDL_MOUSEMOTION:
        s = slot_of(D, ev->motion.windowID);
        if (!s || s->index == NO_WINDOW) return;
        in = (Input){.kind = INPUT_POINTER, .index = s->index};
        in.inside = winview_pointer(&s->view, ev->motion.x, ev->motion.y, &in.fx, &in.fy);
        break;
    case SDL_MOUSEBUTTONDOWN:
    case SDL_MOUSEBUTTONUP:
        s = slot_of(D, ev->button.windowID);
        if (!s || s->index == NO_WINDOW) return;
        in = (Input){.kind = INPUT_BUTTON, .index = s->index, .button = glfw_button(ev->button.button),
                     .pressed = ev->type == SDL_MOUSEBUTTONDOWN};
        break;
    case SDL_WINDOWEVENT:
        switch (ev->window.event) {
        case SDL_WINDOWEVENT_CLOSE: in.kind = INPUT_QUIT; break;
        case SDL_WINDOWEVENT_LEAVE:
            s = slot_of(D, ev->window.windowID);
            if (!s || s->index == NO_WINDOW) return;
            in = (Input){.kind = INPUT_POINTER, .index = s->index, .inside = false};
            break;
        case SDL_WINDOWEVENT_EXPOSED:
        case SDL_WINDOWEVENT_SIZE_CHANGED:
            D->represent = true;
            tell_view_size(D);
            return;
        default: return;
        }
        break;
    default: return;
    }
    handover_input(D->h, &in);
}

/* Open or close windows so that there is one per window of [set], each
 * following its title, size, fullscreen and vsync. Returns -1 (message
 * logged) when a window cannot be opened. */
static int sync_windows(Display *D, const PictureSet *set)
{
    while (D->nslots > set->n) winview_close(&D->slots[--D->nslots].view);
    if (set->n > D->cap) {
        D->slots = realloc(D->slots, set->n * sizeof *D->slots);
        if (!D->slots) abort();
        D->cap = set->n;
    }
    for (size_t k = 0; k < set->n; k++) {
        const ShownWindow *w = &set->win[k];
        Slot *s = &D->slots[k];
        /* a physics view is a picture of the CPU's: with a renderer on the
         * CPU too (llvmpipe), SDL's renderer shows it for less than an
         * upload into OpenGL and a draw would cost; a window that changes
         * kind is opened again */
        WinGl *gl = w->index == NO_WINDOW && wingl_software(D->h->gl) ? NULL : D->h->gl;
        if (k < D->nslots && s->view.gl != gl) {
            winview_close(&s->view);
            for (size_t j = k + 1; j < D->nslots; j++) winview_close(&D->slots[j].view);
            D->nslots = k;
        }
        if (k == D->nslots) {
            int screens = SDL_GetNumVideoDisplays();
            if (!D->screen_told && (D->wopt->screen < 0 || D->wopt->screen >= screens)) {
                /* Flitter takes the first monitor for a screen it lacks */
                fprintf(D->log, "flitter: no screen %d (%d screen%s): using screen 0\n",
                        D->wopt->screen, screens, screens == 1 ? "" : "s");
                D->screen_told = true;
            }
            *s = (Slot){0};
            if (winview_open(&s->view, w->title, w->width, w->height, D->wopt, w->fullscreen,
                             w->vsync, gl) != 0) {
                fprintf(D->log, "flitter: cannot open a window: %s\n", SDL_GetError());
                return -1;
            }
            winlost_watch(&D->h->lost, s->view.window);
            s->view.lost = &D->h->lost;
            D->nslots++;
        } else if (w->index == NO_WINDOW) {
            /* the view window keeps the size the user gave it */
            winview_update(&s->view, w->title, s->view.want_w, s->view.want_h, w->fullscreen,
                           w->vsync);
        } else {
            winview_update(&s->view, w->title, w->width, w->height, w->fullscreen, w->vsync);
        }
        s->index = w->index;
    }
    tell_view_size(D);
    return 0;
}

/* Repaint slot [s]'s overlay when the text or the output size changed. */
static void paint_overlay(Display *D, Slot *s)
{
    int W, H;
    winview_output_size(&s->view, &W, &H);
    if (s->overlay_gen == D->overlay_gen && W == s->view.ov_w && H == s->view.ov_h) return;
    s->overlay_gen = D->overlay_gen;
    if (!D->error && !D->status) {
        s->view.has_overlay = false;
        return;
    }
    int w, h, pitch;
    uint32_t *px = winview_overlay_lock(&s->view, &w, &h, &pitch);
    if (!px) return;
    int pw, ph;
    SDL_GetWindowSize(s->view.window, &pw, &ph);
    double scale = pw > 0 ? (double)w / pw : 1.0;
    overlay_paint(px, w, h, (size_t)pitch, scale, D->status, D->error);
    winview_overlay_done(&s->view, true);
}

/* Present slot [s] unless the windows are gone (a present that finds its
 * window destroyed ends the run as its DestroyNotify would). */
static void present(Display *D, Slot *s)
{
    if (D->gone) return;
    paint_overlay(D, s);
    winview_present(&s->view);
    if (s->view.gone) window_gone(D);
}

/* Give picture set [i] back to the frame loop (SET_FREE) and wake it. */
static void give_back(Handover *h, int i)
{
    pthread_mutex_lock(&h->mu);
    h->state[i] = SET_FREE;
    pthread_cond_signal(&h->cond);
    pthread_mutex_unlock(&h->mu);
}

/* Show picture set [i] of the handover (taken: SET_SHOWING): physics
 * views painted from their snapshots, windows followed, pictures
 * uploaded, the set given back, overlays, present. Returns -1 when a
 * window cannot be opened. */
static int show_set(Display *D, int i)
{
    Handover *h = D->h;
    PictureSet *set = &h->sets[i];
    /* the physics views the frame loop left to paint (its snapshots) */
    double t0 = handover_now(), painted = 0;
    long npainted = 0;
    for (size_t k = 0; k < set->n; k++) {
        ShownWindow *w = &set->win[k];
        if (!w->paint) continue;
        w->paint = false;
        if (!D->painter) D->painter = fl_view_painter_new();
        if (fl_view_painter_draw(D->painter, w->snap, w->px, w->pw, w->ph, (size_t)w->pw * 4, NULL) != 0)
            w->pw = w->ph = 0;   /* not shown (cannot happen for a picture the frame loop sized) */
        npainted++;
    }
    if (npainted) {
        double t1 = handover_now();
        painted = t1 - t0;
        t0 = t1;
    }
    if (D->gone) {   /* the set goes back unshown */
        give_back(h, i);
        return 0;
    }
    int rc = sync_windows(D, set);
    if (rc == 0)
        for (size_t k = 0; k < set->n; k++) {
            ShownWindow *w = &set->win[k];
            if (w->gl) winview_show_texture(&D->slots[k].view, &w->glpic);
            else if (w->pw > 0 && winview_upload(&D->slots[k].view, w->px, w->pw, w->ph) != 0)
                fprintf(D->log, "flitter: cannot show a %dx%d picture: %s\n", w->pw, w->ph,
                        SDL_GetError());
        }
    /* OpenGL windows are drawn before the set goes back: drawing fences
     * each texture for the frame loop */
    bool drawn = rc == 0 && h->gl;
    if (drawn)
        for (size_t k = 0; k < D->nslots; k++) {
            present(D, &D->slots[k]);
        }
    give_back(h, i);
    if (rc != 0) return -1;
    for (size_t k = 0; k < D->nslots && !drawn; k++) {
        present(D, &D->slots[k]);
    }
    double t1 = handover_now();
    pthread_mutex_lock(&h->mu);
    h->shown++;
    h->present_seconds += t1 - t0;
    h->painted += npainted;
    h->paint_seconds += painted;
    pthread_mutex_unlock(&h->mu);
    return 0;
}

void window_display(Handover *h, const WinOptions *wopt, FILE *log)
{
    Display D = {.h = h, .wopt = wopt, .log = log};
    bool failed = false;
    for (;;) {
        SDL_Event ev;
        while (SDL_PollEvent(&ev)) sdl_event(&D, &ev);
        pthread_mutex_lock(&h->mu);
        /* nothing from the frame loop: wait for it up to 4 ms, then look
         * at the window events again */
        if (h->state[0] != SET_PENDING && h->state[1] != SET_PENDING && !h->done &&
            h->overlay_gen + 1 == D.overlay_gen && !D.represent)
            handover_wait_on(h, &h->display_cond, handover_now() + 0.004);
        int take = -1;
        for (int i = 0; i < 2; i++)
            if (h->state[i] == SET_PENDING) take = i;
        if (take >= 0 && failed) {
            h->state[take] = SET_FREE;   /* nothing to show it in */
            take = -1;
        }
        if (take >= 0) h->state[take] = SET_SHOWING;
        bool done = h->done;
        bool overlay = h->overlay_gen + 1 != D.overlay_gen;
        if (overlay) {
            free(D.status);
            free(D.error);
            D.status = h->status ? strdup(h->status) : NULL;
            D.error = h->error ? strdup(h->error) : NULL;
            D.overlay_gen = h->overlay_gen + 1;
        }
        pthread_mutex_unlock(&h->mu);
        if (take >= 0) {
            if (show_set(&D, take) != 0) {
                failed = true;
                pthread_mutex_lock(&h->mu);
                h->failed = true;
                pthread_cond_signal(&h->cond);
                pthread_mutex_unlock(&h->mu);
            }
        } else if ((D.represent || overlay) && !failed) {
            for (size_t k = 0; k < D.nslots; k++) {
                present(&D, &D.slots[k]);
            }
        }
        D.represent = false;
        if (done) break;   /* (its last set was taken with done) */
    }
    /* (after a destroy the windows are left to the process's end: see
     * window_run) */
    for (size_t k = 0; k < D.nslots && !D.gone; k++) winview_close(&D.slots[k].view);
    fl_view_painter_free(D.painter);
    free(D.slots);
    free(D.status);
    free(D.error);
}
