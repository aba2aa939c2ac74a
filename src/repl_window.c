/* repl_window.c: `:window` of `flitter repl`: a live window on the
 * session's runtime. It shares window_sdl.c with `flitter SCRIPT`
 * (window_main.c): the picture is the first !window of the last frame
 * (fl_draw_window, the very picture !record writes), or the physics view
 * (fl_draw_view) at the window's output size when the frame has none. The
 * session draws after each :step frame at most 60 times a second, and
 * always after the last; events are handled between frames and between
 * input lines. */
#include "repl_window.h"

#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "exitcodes.h"
#include "window_lost.h"
#include "window_sdl.h"

struct ReplWindow {
    WinView view;
    WinLost lost;       /* the window or the X display lost (window_lost.h) */
    volatile int interrupt; /* (the loss handler's to set: the session has no frame loop) */
    void (*on_lost)(void *);
    void *ctx;
    char name[256];     /* the title when the !window has none */
    double last_shown;  /* monotonic seconds of the last picture, or -1 */
    bool warned;        /* a drawing failure was reported */
    /* the session's signal mask before the window: SIGPIPE is blocked
     * while it is open (winlost_block_sigpipe), so that a killed
     * connection writes the recovery file (status 3) */
    sigset_t old_mask;
};

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* The first shown !window of [rt]'s last frame: sets *[info] and returns
 * its fl_windows index, or SIZE_MAX (physics view) when there is none. */
static size_t first_window(fl_runtime *rt, fl_window_info *info)
{
    size_t n = fl_windows(rt, NULL, 0);
    if (n == 0) return SIZE_MAX;
    fl_window_info *all = malloc(n * sizeof *all);
    if (!all) abort();
    n = fl_windows(rt, all, n);
    size_t found = SIZE_MAX;
    for (size_t i = 0; i < n && found == SIZE_MAX; i++)
        if (!all[i].offscreen) {
            *info = all[i];
            found = i;
        }
    free(all);
    return found;
}

/* The X connection lost, in the window's own X call (the session's only
 * thread, between frames): the session saves what it keeps, then the
 * process exits with status 3. */
static _Noreturn void end_lost(void *arg)
{
    ReplWindow *w = arg;
    fflush(stdout);
    fprintf(stderr, "window: the connection to the X display was lost: the session ends "
            "(exit status %d)\n", EXIT_WINDOW_LOST);
    if (w->on_lost) w->on_lost(w->ctx);
    fflush(stdout);
    fflush(stderr);
    _exit(EXIT_WINDOW_LOST);
}

ReplWindow *repl_window_open(fl_runtime *rt, const char *name, void (*lost)(void *ctx), void *ctx,
                             char *why, size_t cap)
{
    sigset_t old;
    winlost_block_sigpipe(&old);
    if (winview_start(why, cap) != 0) {
        winlost_unblock_sigpipe(&old);
        return NULL;
    }
    ReplWindow *w = calloc(1, sizeof *w);
    if (!w) abort();
    w->old_mask = old;
    w->on_lost = lost;
    w->ctx = ctx;
    winlost_init(&w->lost, &w->interrupt, NULL, end_lost, w);
    snprintf(w->name, sizeof w->name, "%s", name);
    w->last_shown = -1;
    fl_window_info info = {0};
    size_t index = first_window(rt, &info);
    const char *title = index != SIZE_MAX && info.title[0] ? info.title : w->name;
    int width = index != SIZE_MAX ? info.width : 512, height = index != SIZE_MAX ? info.height : 512;
    WinOptions o = {0, false, false};
    bool full = index != SIZE_MAX && info.fullscreen > 0, vsync = index != SIZE_MAX && info.vsync > 0;
    if (winview_open(&w->view, title, width, height, &o, full, vsync, NULL) != 0) {
        snprintf(why, cap, "cannot open a window: %s", SDL_GetError());
        free(w);
        SDL_Quit();
        winlost_unblock_sigpipe(&old);
        return NULL;
    }
    winlost_watch(&w->lost, w->view.window);
    repl_window_frame(w, rt, true);
    return w;
}

bool repl_window_poll(ReplWindow *w)
{
    bool keep = true;
    SDL_Event ev;
    while (SDL_PollEvent(&ev)) {
        switch (ev.type) {
        case SDL_QUIT: keep = false; break;
        case SDL_WINDOWEVENT:
            if (ev.window.windowID != w->view.id) break;
            if (ev.window.event == SDL_WINDOWEVENT_CLOSE) keep = false;
            else if (ev.window.event == SDL_WINDOWEVENT_EXPOSED ||
                     ev.window.event == SDL_WINDOWEVENT_SIZE_CHANGED)
                winview_present(&w->view);
            break;
        case SDL_KEYDOWN:
            if (ev.key.windowID == w->view.id && ev.key.keysym.sym == SDLK_ESCAPE) keep = false;
            break;
        case SDL_SYSWMEVENT:
            if (keep && winlost_destroyed(&ev) == winlost_xid(w->view.window) &&
                winlost_set_destroyed(&w->lost)) {
                fprintf(stderr, "window: destroyed by another X client: closed (the session goes on)\n");
                keep = false;
            }
            break;
        default: break;
        }
    }
    return keep;
}

void repl_window_frame(ReplWindow *w, fl_runtime *rt, bool force)
{
    double now = now_seconds();
    if (!force && w->last_shown >= 0 && now - w->last_shown < 1.0 / 60) return;
    fl_window_info info = {0};
    size_t index = first_window(rt, &info);
    int width, height;
    if (index == SIZE_MAX) {
        winview_update(&w->view, w->name, w->view.want_w, w->view.want_h, w->view.fullscreen,
                       w->view.vsync);
        winview_output_size(&w->view, &width, &height);
    } else {
        width = info.width;
        height = info.height;
        winview_update(&w->view, info.title[0] ? info.title : w->name, width, height,
                       info.fullscreen >= 0 ? info.fullscreen : w->view.fullscreen,
                       info.vsync >= 0 ? info.vsync : w->view.vsync);
    }
    int pitch;
    uint32_t *px = winview_lock(&w->view, width, height, &pitch);
    if (!px) {
        if (!w->warned) fprintf(stderr, "window: cannot show a %dx%d picture: %s\n", width, height,
                                SDL_GetError());
        w->warned = true;
        return;
    }
    int rc = index == SIZE_MAX ? fl_draw_view(rt, px, width, height, (size_t)pitch, NULL)
                               : fl_draw_window(rt, index, px, width, height, (size_t)pitch);
    winview_unlock(&w->view);
    if (rc != 0 && !w->warned) {
        fputs(fl_error(rt), stderr);
        w->warned = true;
    }
    winview_present(&w->view);
    w->last_shown = now_seconds();
}

void repl_window_close(ReplWindow *w)
{
    if (!w) return;
    winview_close(&w->view);
    winlost_sync(&w->lost);   /* (a destroyed window's errors, under window_lost.c's handler) */
    SDL_Quit();
    winlost_free(&w->lost);
    sigset_t old = w->old_mask;
    free(w);
    winlost_unblock_sigpipe(&old);
}
