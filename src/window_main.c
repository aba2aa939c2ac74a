/* window_main.c: the frame loop of a run with live windows (Flitter's
 * everyday mode, `flitter SCRIPT...`). A Loop holds the pages (one
 * fl_runtime each, only the current one steps) and the open windows
 * (Slots): after each frame the slots follow the !window nodes of the
 * current page's tree (fl_windows, !offscreen ones excluded), each showing
 * its picture (fl_draw_window) or, with F2 or when the frame has no
 * !window, the physics view (fl_draw_view). Input (window_input.c) reaches
 * the runtime between frames. The clock follows Flitter's
 * EngineController.run: realtime frames are paced to fl_target_fps, and a
 * frame that finishes after the next one is due skips its picture
 * (counted as dropped) rather than hold the simulation up, unless nothing
 * was shown for 100 ms (or twice the last picture's cost, when longer);
 * in lockstep every frame is shown. */
#include "window.h"

#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "exitcodes.h"
#include "overlay.h"
#include "window_loop.h"

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static void *xrealloc(void *p, size_t n)
{
    p = realloc(p, n ? n : 1);
    if (!p) abort();
    return p;
}

static void write_file(void *ctx, const char *text, size_t len) { fwrite(text, 1, len, ctx); }

/* The last path component of [path]: a window's title when it has none. */
static const char *base_name(const char *path)
{
    const char *slash = strrchr(path, '/');
    return slash && slash[1] ? slash + 1 : path;
}

/* {=====================================================================
 * Pages: load, reload, state files
 * ===================================================================== */

/* Re-read the current page when one of its files changed: a good version
 * replaces the program (the state stays), a broken one is reported on the
 * log and over the windows, and the last good program keeps running. */
static void check_reload(Loop *L)
{
    Page *p = &L->pages[L->cur];
    if (!watch_changed(&p->watch)) return;
    if (fl_load(p->rt, p->script) == 0) {
        watch_set(&p->watch, p->rt, p->script);
        fprintf(L->log, "%s: reloaded\n", p->script);
        if (p->error) {
            free(p->error);
            p->error = NULL;
            L->overlay_gen++;
        }
    } else {
        const char *e = fl_error(p->rt);
        fputs(e, L->log);
        free(p->error);
        p->error = strdup(e);
        L->overlay_gen++;
    }
    fflush(L->log);
}

static int save_page(Loop *L, Page *p)
{
    if (!p->state_path || fl_frame_count(p->rt) == 0) return 0;
    if (fl_save_state(p->rt, p->state_path) == 0) return 0;
    fputs(fl_error(p->rt), L->log);
    return -1;
}

/* Make the pages: a runtime per script, loaded, its --state restored
 * (page 1 uses FILE, page N>1 FILE.N), its outputs opened (--view and
 * --trace on page 1 only). Returns an exit status (0: ready). */
static int open_pages(Loop *L)
{
    const RunSpec *spec = L->spec;
    L->pages = xrealloc(NULL, (size_t)spec->nscripts * sizeof *L->pages);
    memset(L->pages, 0, (size_t)spec->nscripts * sizeof *L->pages);
    for (int i = 0; i < spec->nscripts; i++) {
        Page *p = &L->pages[L->npages++];
        p->script = spec->scripts[i];
        p->rt = runspec_runtime(&L->runspec, &L->files, L->interrupt);
        if (!p->rt) return EXIT_USAGE;
        if (fl_load(p->rt, p->script) != 0) {
            fputs(fl_error(p->rt), L->log);
            return EXIT_LOAD;
        }
        watch_set(&p->watch, p->rt, p->script);
        if (spec->state_file) {
            size_t n = strlen(spec->state_file) + 16;
            p->state_path = xrealloc(NULL, n);
            if (i == 0)
                snprintf(p->state_path, n, "%s", spec->state_file);
            else
                snprintf(p->state_path, n, "%s.%d", spec->state_file, i + 1);
            if (access(p->state_path, F_OK) == 0 && fl_restore_state(p->rt, p->state_path) != 0) {
                fputs(fl_error(p->rt), L->log);
                free(p->state_path);
                p->state_path = NULL;   /* leave the file alone */
                return EXIT_LOAD;
            }
        }
        fl_output_options oo = {0};
        if (i == 0)
            oo = (fl_output_options){.view = spec->view, .view_every = spec->view_every,
                                     .trace = spec->trace, .trace_every = spec->trace_every,
                                     .debug = spec->verbosity >= 2, .record = spec->record};
        p->outs = fl_outputs_open(p->rt, &oo);
        if (!p->outs) {
            fprintf(L->log, "flitter run: %s", fl_error(p->rt));
            return EXIT_USAGE;
        }
    }
    return EXIT_OK;
}

/* Close every page: outputs finished, states saved; returns the status
 * to exit with given [rc] so far. */
static int close_pages(Loop *L, int rc)
{
    for (int i = 0; i < L->npages; i++) {
        Page *p = &L->pages[i];
        if (p->outs && fl_outputs_close(p->outs, p->rt) != 0) {
            if (*fl_error(p->rt)) fprintf(L->log, "flitter run: %s", fl_error(p->rt));
            rc = EXIT_LOAD;
        }
        if (save_page(L, p) != 0) rc = EXIT_LOAD;
        watch_free(&p->watch);
        free(p->error);
        free(p->state_path);
        fl_free(p->rt);
    }
    free(L->pages);
    return rc;
}

/* Leave the current page for page [to] (Flitter's switch_to_page): with
 * --resetonswitch the page left loses its state. */
static void switch_page(Loop *L, int to)
{
    if (to < 0 || to >= L->npages || to == L->cur) return;
    if (L->spec->reset_on_switch) fl_reset_state(L->pages[L->cur].rt);
    L->cur = to;
    L->overlay_gen++;
    fprintf(L->log, "page %d: %s\n", to + 1, L->pages[to].script);
    fflush(L->log);
}

/* {=====================================================================
 * Windows: follow the frame's !window nodes, draw, present
 * ===================================================================== */

static void close_slot(Slot *s) { winview_close(&s->view); }

/* Open or close windows so that there is one per visible !window of the
 * current page's last frame (one physics view window when it has none),
 * and make each follow its node's title, size, fullscreen and vsync.
 * Returns -1 (message logged) when a window cannot be opened. */
static int sync_windows(Loop *L)
{
    fl_runtime *rt = L->pages[L->cur].rt;
    size_t n = fl_windows(rt, NULL, 0);
    if (n > L->cap_info) {
        L->info = xrealloc(L->info, n * sizeof *L->info);
        L->cap_info = n;
    }
    n = fl_windows(rt, L->info, n);
    size_t want = 0;
    for (size_t i = 0; i < n; i++) want += !L->info[i].offscreen;
    bool view_only = want == 0;
    if (view_only) want = 1;
    while (L->nslots > want) close_slot(&L->slots[--L->nslots]);
    if (want > L->cap_slots) {
        L->slots = xrealloc(L->slots, want * sizeof *L->slots);
        L->cap_slots = want;
    }
    const char *name = base_name(L->pages[L->cur].script);
    size_t k = 0;
    for (size_t i = 0; k < want; i++) {
        const fl_window_info *w = view_only ? NULL : &L->info[i];
        if (w && w->offscreen) continue;
        const char *title = w && w->title[0] ? w->title : name;
        int width = w ? w->width : L->spec->view_width;
        int height = w ? w->height : L->spec->view_height;
        bool full = w && w->fullscreen >= 0 ? w->fullscreen : L->wopt.fullscreen;
        bool vsync = w && w->vsync >= 0 ? w->vsync : L->wopt.vsync;
        Slot *s = &L->slots[k];
        if (k == L->nslots) {
            *s = (Slot){0};
            if (winview_open(&s->view, title, width, height, &L->wopt, full, vsync) != 0) {
                fprintf(L->log, "flitter: cannot open a window: %s\n", SDL_GetError());
                return -1;
            }
            L->nslots++;
        } else if (view_only) {
            winview_update(&s->view, title, s->view.want_w, s->view.want_h, full, vsync);
        } else {
            winview_update(&s->view, title, width, height, full, vsync);
        }
        s->index = view_only ? NO_WINDOW : i;
        s->width = width;
        s->height = height;
        k++;
    }
    return 0;
}

/* Draw slot [s]'s picture into its texture: the window's picture, or the
 * physics view (at the picture's size, or at the output's for the view
 * window). */
static void draw_slot(Loop *L, Slot *s)
{
    fl_runtime *rt = L->pages[L->cur].rt;
    bool view = s->index == NO_WINDOW || L->show_view;
    int w = s->width, h = s->height;
    if (s->index == NO_WINDOW) winview_output_size(&s->view, &w, &h);
    int pitch;
    uint32_t *px = winview_lock(&s->view, w, h, &pitch);
    if (!px) {
        if (!s->warned) fprintf(L->log, "flitter: cannot show a %dx%d picture: %s\n", w, h, SDL_GetError());
        s->warned = true;
        return;
    }
    double t0 = now_seconds();
    int rc = view ? fl_draw_view(rt, px, w, h, (size_t)pitch, NULL)
                  : fl_draw_window(rt, s->index, px, w, h, (size_t)pitch);
    L->draw_seconds += now_seconds() - t0;
    winview_unlock(&s->view);
    if (rc != 0 && !s->warned) {
        fputs(fl_error(rt), L->log);
        s->warned = true;
    }
}

/* Repaint slot [s]'s overlay when the text or the output size changed. */
static void paint_overlay(Loop *L, Slot *s)
{
    const char *error = L->pages[L->cur].error;
    const char *status = L->show_status ? L->status : NULL;
    int W, H;
    winview_output_size(&s->view, &W, &H);
    if (s->overlay_gen == L->overlay_gen && W == s->view.ov_w && H == s->view.ov_h) return;
    s->overlay_gen = L->overlay_gen;
    if (!error && !status) {
        s->view.has_overlay = false;
        return;
    }
    int w, h, pitch;
    uint32_t *px = winview_overlay_lock(&s->view, &w, &h, &pitch);
    if (!px) return;
    int pw, ph;
    SDL_GetWindowSize(s->view.window, &pw, &ph);
    double scale = pw > 0 ? (double)w / pw : 1.0;
    overlay_paint(px, w, h, (size_t)pitch, scale, status, error);
    winview_overlay_done(&s->view, true);
}

/* Show the current frame in every window; [draw]: draw the pictures
 * anew (else only the overlay and the presentation). */
static int show_frame(Loop *L, bool draw)
{
    double t0 = now_seconds(), drawn = L->draw_seconds;
    if (draw && sync_windows(L) != 0) return -1;
    for (size_t i = 0; i < L->nslots; i++) {
        if (draw) draw_slot(L, &L->slots[i]);
        paint_overlay(L, &L->slots[i]);
        winview_present(&L->slots[i].view);
    }
    if (draw) {
        double t1 = now_seconds();
        /* the rest of the time is presenting: draw_slot counted its drawing */
        L->present_seconds += (t1 - t0) - (L->draw_seconds - drawn);
        L->shown++;
        L->last_shown = t1;
        L->last_show_cost = t1 - t0;
    }
    return 0;
}

/* {=====================================================================
 * The status overlay (F1)
 * ===================================================================== */

/* Every half second: the frame rate, clock and per-frame costs since the
 * last update, for the F1 overlay. */
static void update_status(Loop *L, bool force)
{
    double now = now_seconds();
    if (!force && now - L->stat_time < 0.5) return;
    fl_runtime *rt = L->pages[L->cur].rt;
    fl_stats st;
    fl_get_stats(rt, &st);
    double dt = now - L->stat_time;
    long frames = st.frames - L->stat.frames, shown = L->shown - L->stat_shown;
    double per = frames > 0 ? 1e3 / (double)frames : 0;
    double draw = shown > 0 ? (L->draw_seconds - L->stat_draw) * 1e3 / (double)shown : 0;
    double present = shown > 0 ? (L->present_seconds - L->stat_present) * 1e3 / (double)shown : 0;
    snprintf(L->status, sizeof L->status,
             "page %d/%d %s\n"
             "frame %ld  time %.2f s\n"
             "%.1f frames/s (target %g), shown %.1f/s\n"
             "dropped %ld frames\n"
             "eval %.2f ms  physics %.2f ms\n"
             "draw %.2f ms  present %.2f ms\n"
             "%s",
             L->cur + 1, L->npages, base_name(L->pages[L->cur].script), fl_frame_count(rt) - 1,
             fl_frame_time(rt), dt > 0 ? (double)frames / dt : 0.0, fl_target_fps(rt),
             dt > 0 ? (double)shown / dt : 0.0, L->dropped,
             (st.eval_seconds - L->stat.eval_seconds) * per,
             (st.physics_seconds - L->stat.physics_seconds) * per, draw, present,
             L->paused ? "paused (F5 resume, F6 one frame)" : "");
    L->stat = st;
    L->stat_shown = L->shown;
    L->stat_draw = L->draw_seconds;
    L->stat_present = L->present_seconds;
    L->stat_time = now;
    if (L->show_status) L->overlay_gen++;
}

/* The --stats report at the end of the run: each page's lines as a
 * headless run prints them (runspec_print_stats; a "page N" line first
 * when there are several), then the windows': drawing and presenting
 * milliseconds per frame shown, frames shown and dropped. [loop]: the
 * frame loop's wall time in seconds. */
static void print_stats(Loop *L, double loop)
{
    for (int i = 0; i < L->npages; i++) {
        Page *p = &L->pages[i];
        if (L->npages > 1) {
            if (p->ran == 0) continue;
            fprintf(L->log, "stats: page %d: %s\n", i + 1, p->script);
        }
        runspec_print_stats(p->rt, &p->first, &p->second, loop, L->log);
    }
    double n = L->shown > 0 ? (double)L->shown : 1;
    fprintf(L->log, "stats: window: per frame shown: draw %.3f ms, present %.3f ms\n",
            L->draw_seconds / n * 1e3, L->present_seconds / n * 1e3);
    fprintf(L->log, "stats: window: %ld frames shown, %ld dropped\n", L->shown, L->dropped);
    fflush(L->log);
}

/* {=====================================================================
 * The frame loop
 * ===================================================================== */

/* Wait until [due] (monotonic seconds), handling window events. */
static void wait_until(Loop *L, double due)
{
    for (;;) {
        double wait = due - now_seconds();
        if (wait <= 0 || L->quit || *L->interrupt) return;
        SDL_Event ev;
        int ms = (int)(wait * 1e3);
        if (SDL_WaitEventTimeout(&ev, ms > 0 ? ms : 1)) window_event(L, &ev);
    }
}

/* One pass: events, reload, a frame (unless paused), its picture, pacing.
 * Returns false when the run ends. */
static bool loop_once(Loop *L)
{
    const RunSpec *spec = L->spec;
    SDL_Event ev;
    while (SDL_PollEvent(&ev)) window_event(L, &ev);
    if (L->quit || *L->interrupt) return false;
    if (L->switch_to >= 0) {
        switch_page(L, L->switch_to);
        L->switch_to = -1;
        L->redraw = true;
    }
    check_reload(L);
    Page *p = &L->pages[L->cur];
    bool stepped = false;
    if (!L->paused || L->steps > 0) {
        if (L->steps > 0) L->steps--;
        if (fl_step(p->rt) != 0) return false;   /* interrupted inside the frame */
        stepped = true;
        L->ran++;
        p->ran++;
        if (p->ran == 1) fl_get_stats(p->rt, &p->first);
        if (p->ran == 2) fl_get_stats(p->rt, &p->second);
        L->dumped_last = false;
        if (fl_outputs_frame(p->outs, p->rt) != 0) fprintf(L->log, "flitter run: %s", fl_error(p->rt));
        long n = fl_frame_count(p->rt);
        if (spec->dump_state && spec->dump_every > 0 && n % spec->dump_every == 0) {
            fl_dump_state(p->rt, write_file, L->out);
            fflush(L->out);
            L->dumped_last = true;
        }
        double now = now_seconds();
        if (spec->state_file && now - L->last_save >= 5.0) {
            save_page(L, p);
            L->last_save = now;
        }
    }
    update_status(L, false);
    if (stepped || L->redraw) {
        double now = now_seconds();
        /* realtime: no time left to draw before the next frame is due;
         * a late frame is still shown when nothing was for 100 ms, or for
         * twice what the last picture cost to show when that is longer
         * (a picture that takes a second to draw, a large !canvas3d on a
         * CPU, then holds the simulation up for at most a third of the
         * time) */
        bool late = L->realtime && stepped && fl_frame_wait(p->rt) < 0.001;
        /* (a slow picture restarts the realtime schedule, so the frame
         * after it is not late: a picture slower than a frame counts as
         * late on its own) */
        bool slow = L->realtime && stepped && L->last_show_cost * fl_target_fps(p->rt) > 1;
        double gap = L->last_show_cost * 2 > 0.1 ? L->last_show_cost * 2 : 0.1;
        if ((late || slow) && now - L->last_shown < gap && !L->redraw) {
            L->dropped++;
        } else if (show_frame(L, true) != 0) {
            L->rc = EXIT_LOAD;
            return false;
        }
        L->redraw = false;
    } else if (L->represent) {
        show_frame(L, false);
    }
    L->represent = false;
    if (spec->frames >= 0 && L->ran >= spec->frames) return false;
    /* pacing (EngineController.run, through fl_frame_wait): realtime
     * frames 1/fps apart, a slow frame restarts the schedule from now;
     * lockstep and pause wait 1 ms */
    if (L->realtime && stepped) {
        double wait = fl_frame_wait(p->rt);
        if (wait >= 0.001)
            wait_until(L, now_seconds() + wait - 0.001);
    } else {
        wait_until(L, now_seconds() + (L->paused ? 0.02 : 0.001));
    }
    return true;
}

int window_run(const RunSpec *spec, FILE *out, FILE *log, volatile int *interrupt, char *why,
               size_t cap)
{
    if (winview_start(why, cap) != 0) return WINDOW_NO_DISPLAY;
    Loop L = {.spec = spec, .out = out, .log = log, .interrupt = interrupt,
              .switch_to = -1, .runspec = *spec,
              .wopt = {spec->screen, spec->fullscreen, spec->vsync}};
    if (!L.interrupt) L.interrupt = &L.never;
    /* Flitter's windows run on the realtime clock unless --lockstep */
    L.realtime = spec->clock_given ? spec->realtime : true;
    L.runspec.realtime = L.realtime;
    L.files = (RunLog){log, (spec->dump_state || spec->dump_tree) ? log : out};
    int rc = open_pages(&L);
    if (rc == EXIT_OK) {
        if (spec->dump_simplified) fl_dump_program(L.pages[0].rt, write_file, out);
        L.last_save = L.stat_time = L.start = now_seconds();
        L.last_shown = -1;
        while (loop_once(&L)) {}
        rc = L.rc;
        if (spec->stats) print_stats(&L, now_seconds() - L.start);
        Page *p = &L.pages[L.cur];
        if (fl_frame_count(p->rt) > 0) {
            if (spec->dump_state && !L.dumped_last) fl_dump_state(p->rt, write_file, out);
            if (spec->dump_tree) fl_dump_tree(p->rt, write_file, out);
        }
        fflush(out);
    }
    for (size_t i = 0; i < L.nslots; i++) close_slot(&L.slots[i]);
    free(L.slots);
    free(L.info);
    rc = close_pages(&L, rc);
    SDL_Quit();
    return rc;
}
