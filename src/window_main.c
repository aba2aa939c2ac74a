/* window_main.c: a run with live windows (Flitter's everyday mode,
 * `flitter SCRIPT...`) and its frame loop. The frame loop runs on a thread
 * of its own: a Loop holds the pages (one fl_runtime each, only the
 * current one steps); after each frame it describes the windows to show,
 * one per !window of the current page's tree (fl_windows, !offscreen ones
 * excluded), into a picture set for the display (window_display.c), which
 * presents it on the thread that started SDL while the next frames run:
 * presenting never holds the simulation up. With OpenGL windows the
 * drawing thread (window_drawing.c) draws the set: a frame's render-graph
 * pictures beside the next frames (fl_picture_take), so that drawing does
 * not hold the simulation up either, and what cannot be drawn beside them
 * (the physics view, with F2 or when the frame has no !window; a frame
 * whose !record writes a file) while the frame loop waits. Without them
 * the frame loop draws each window's picture (fl_draw_window) or the
 * physics view (fl_draw_view) itself. Input (window_input.c) reaches the
 * runtime between frames. The clock follows Flitter's
 * EngineController.run: realtime frames are paced to fl_target_fps; a
 * frame's picture is skipped (counted as dropped) while the drawing thread
 * or the display has not yet taken the last one, or, for a picture drawn
 * while the frame loop waits, when the frame finished after the next one
 * was due, unless nothing was drawn for twice the last picture's cost, at
 * least 100 ms. A window that scales its pictures down (window_scale.h)
 * waits only for the last picture's cost, and not at all while its frames
 * still come at half the frame rate or more: then, as in Flitter, every
 * frame is drawn. In lockstep every frame is shown: the frame loop waits
 * for the drawing thread and the display to take a picture before it
 * draws the next. */
#include "window.h"

#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "exitcodes.h"
#include "window_loop.h"

static double now_seconds(void) { return handover_now(); }

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
    if (!drawing_wait_idle(L)) return;   /* (fl_load: no picture out) */
    double t0 = now_seconds();
    wingl_lock(L->hand->gl);   /* (a runtime freed or made draws) */
    int rc = fl_load(p->rt, p->script);
    wingl_unlock(L->hand->gl);
    if (rc == 0) {
        p->load.last = now_seconds() - t0;
        p->load.reloads++;
        watch_set(&p->watch, p->rt, p->script);
        fprintf(L->log, "%s: reloaded\n", p->script);
        if (p->error) {
            free(p->error);
            p->error = NULL;
            L->overlay_changed = true;
        }
    } else {
        const char *e = fl_error(p->rt);
        fputs(e, L->log);
        free(p->error);
        p->error = strdup(e);
        L->overlay_changed = true;
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
        double t0 = now_seconds();
        if (fl_load(p->rt, p->script) != 0) {
            fputs(fl_error(p->rt), L->log);
            return EXIT_LOAD;
        }
        p->load.first = now_seconds() - t0;
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
    L->pages = NULL;
    L->npages = 0;
    L->closed = true;
    return rc;
}

/* Leave the current page for page [to] (Flitter's switch_to_page): with
 * --resetonswitch the page left loses its state. */
static void switch_page(Loop *L, int to)
{
    if (to < 0 || to >= L->npages || to == L->cur) return;
    if (L->spec->reset_on_switch) fl_reset_state(L->pages[L->cur].rt);
    L->cur = to;
    L->overlay_changed = true;
    fprintf(L->log, "page %d: %s\n", to + 1, L->pages[to].script);
    fflush(L->log);
}

/* {=====================================================================
 * Pictures: describe the windows of a frame, draw, hand over
 * ===================================================================== */

/* Make [set] describe the windows to show for the current page's last
 * frame: one per visible !window, or one physics view window when it has
 * none, with the title, size, fullscreen and vsync each asks for. */
static void describe_windows(Loop *L, PictureSet *set)
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
    if (want > set->cap) {
        set->win = xrealloc(set->win, want * sizeof *set->win);
        memset(set->win + set->cap, 0, (want - set->cap) * sizeof *set->win);
        set->cap = want;
    }
    set->n = want;
    set->frame = fl_frame_count(rt) - 1;
    const char *name = base_name(L->pages[L->cur].script);
    size_t k = 0;
    for (size_t i = 0; k < want; i++) {
        const fl_window_info *w = view_only ? NULL : &L->info[i];
        if (w && w->offscreen) continue;
        ShownWindow *s = &set->win[k++];
        s->index = view_only ? NO_WINDOW : i;
        snprintf(s->title, sizeof s->title, "%s", w && w->title[0] ? w->title : name);
        s->width = w ? w->width : L->spec->view_width;
        s->height = w ? w->height : L->spec->view_height;
        s->fullscreen = w && w->fullscreen >= 0 ? w->fullscreen : L->spec->fullscreen;
        s->vsync = w && w->vsync >= 0 ? w->vsync : L->spec->vsync;
    }
}

/* Draw window [s]'s picture: the window's picture, or the physics view
 * (at the picture's size, or at the window's output size [view_w] x
 * [view_h] for the view window when the display has told it). */
static void draw_window(Loop *L, ShownWindow *s, int view_w, int view_h)
{
    fl_runtime *rt = L->pages[L->cur].rt;
    bool view = s->index == NO_WINDOW || L->show_view;
    int w = s->width, h = s->height;
    if (s->index == NO_WINDOW && view_w > 0 && view_h > 0) {
        w = view_w;
        h = view_h;
    }
    size_t words = (size_t)w * (size_t)h;
    if (words > s->cap) {
        free(s->px);
        s->px = malloc(words * sizeof *s->px);
        s->cap = s->px ? words : 0;
    }
    if (!s->px) {
        if (!L->warned) fprintf(L->log, "flitter: no memory for a %dx%d picture\n", w, h);
        L->warned = true;
        s->pw = s->ph = 0;
        return;
    }
    s->pw = w;
    s->ph = h;
    s->paint = false;
    if (!view) {   /* its snapshot, if it had one, is not needed now */
        fl_view_snapshot_free(s->snap);
        s->snap = NULL;
    } else {
        /* the physics view is painted by the display from a copy of the
         * systems, so that drawing it never holds the simulation up; a 3D
         * system needs the runtime's renderer: drawn here */
        fl_view_snapshot *snap = fl_view_snapshot_take(rt, s->snap);
        if (snap) {
            s->snap = snap;
            s->paint = true;
            return;
        }
    }
    if (!view && L->pages[L->cur].gl) {
        /* the window's own picture, a texture of the frame loop's context:
         * copied for the display, never read back */
        int tw, th;
        unsigned tex = fl_gl_window_texture(rt, s->index, &tw, &th);
        s->gl = true;
        if (!tex || !wingl_frame_copy(L->hand->gl, &s->glpic, tex, tw, th)) s->glpic.w = s->glpic.h = 0;
        s->pw = s->glpic.w;
        s->ph = s->glpic.h;
        return;
    }
    s->gl = false;
    /* a thread cannot have the library's own EGL context current beside
     * the frame loop's (a 3D view, a window drawn without it) */
    if (L->gl) wingl_frame_leave(L->hand->gl);
    int rc = view ? fl_draw_view(rt, s->px, w, h, (size_t)w * 4, NULL)
                  : fl_draw_window(rt, s->index, s->px, w, h, (size_t)w * 4);
    if (L->gl) wingl_frame_enter(L->hand->gl);
    if (rc != 0 && !L->warned) {
        fputs(fl_error(rt), L->log);
        L->warned = true;
    }
}

/* Count a picture set drawn: [seconds] from its description to its end
 * at [end], [locked] of them drawing (with the OpenGL turn), at the
 * scale [scale] and samples cap [samples] it was drawn with; [graph]:
 * it holds a window's picture drawn by the render graph (not the physics
 * view). For the dynamic resolution, such a set counts its drawing time
 * unless it was drawn whole for a file. */
static void count_picture(Loop *L, bool graph, double seconds, double locked, double end, double scale, int samples)
{
    L->draw_seconds += seconds;
    L->last_drawn = end;
    L->last_draw_cost = seconds;
    L->drawn++;
    L->drawn_scale = scale;
    L->drawn_samples = samples;
    if (!L->scaling || L->show_view || !graph) return;
    if (scale < 1) {
        L->scaled_pictures++;
        L->scale_sum += scale;
    }
    /* a picture drawn whole for a file says nothing about the scale's cost */
    if (scale == winscale_scale(&L->scale) && winscale_picture(&L->scale, locked, 1 / fl_target_fps(L->pages[L->cur].rt)))
        L->overlay_changed |= L->show_status;
}

/* Whether the drawing thread is busy; the picture it has drawn since the
 * last call, if it has, counted and given back. */
static bool poll_drawing(Loop *L)
{
    DrawResult r;
    bool taken, busy = drawing_poll(L, &r, &taken);
    if (taken) {
        fl_picture_free(r.rt, r.pic);
        count_picture(L, true, r.seconds, r.locked_seconds, r.end, r.scale, r.samples);
    }
    return busy;
}

/* Draw every window of a SetDraw [ctx] (on the drawing thread, or on the
 * frame loop's without one). */
static void draw_set(Loop *L, void *ctx)
{
    SetDraw *a = ctx;
    if (L->scaling) fl_set_window_scale(a->rt, winscale_scale(&L->scale), winscale_samples(&L->scale));
    wingl_lock(L->hand->gl);
    double locked = now_seconds();
    for (size_t k = 0; k < a->set->n; k++) draw_window(L, &a->set->win[k], a->view_w, a->view_h);
    wingl_unlock(L->hand->gl);
    a->locked = now_seconds() - locked;
    a->scale = fl_window_scale(a->rt, &a->samples);
}

/* Draw the current frame's pictures into a free set and hand it to the
 * display: with the drawing thread, a picture of the render graph's
 * windows is handed to it and drawn beside the next frames (it marks the
 * set for the display); anything else is drawn now. In lockstep, first
 * wait until the drawing thread and the display have taken the last one;
 * in realtime, return false (nothing drawn) when either has not. */
static bool draw_frame(Loop *L)
{
    Handover *h = L->hand;
    if (poll_drawing(L)) {
        if (L->realtime || h->failed || !drawing_wait_idle(L)) return false;
        poll_drawing(L);
    }
    pthread_mutex_lock(&h->mu);
    for (;;) {
        bool pending = h->state[0] == SET_PENDING || h->state[1] == SET_PENDING;
        if (!pending) break;
        if (L->realtime || h->failed || *L->interrupt) {
            pthread_mutex_unlock(&h->mu);
            return false;
        }
        double t0 = now_seconds();
        handover_wait(h, t0 + 0.02);
        L->wait_seconds += now_seconds() - t0;
    }
    int i = h->state[0] == SET_FREE ? 0 : 1;   /* the other is shown, if either */
    h->state[i] = SET_DRAWING;
    int view_w = h->view_w, view_h = h->view_h;
    pthread_mutex_unlock(&h->mu);

    double t0 = now_seconds();
    PictureSet *set = &h->sets[i];
    describe_windows(L, set);
    fl_runtime *rt = L->pages[L->cur].rt;
    bool graph = false, graph_only = !L->show_view && L->pages[L->cur].gl;
    for (size_t k = 0; k < set->n; k++) {
        graph |= set->win[k].index != NO_WINDOW;
        graph_only &= set->win[k].index != NO_WINDOW;
    }
    fl_picture *pic = graph_only && L->draw.running ? fl_picture_take(rt) : NULL;
    if (pic) {
        drawing_post(L, rt, pic, i, L->scaling, winscale_scale(&L->scale), winscale_samples(&L->scale));
        return true;
    }
    SetDraw *a = &L->set_draw;
    *a = (SetDraw){.set = set, .view_w = view_w, .view_h = view_h, .rt = rt};
    bool drawn = drawing_run(L, draw_set, a);
    pthread_mutex_lock(&h->mu);
    h->state[i] = drawn ? SET_PENDING : SET_FREE;
    pthread_mutex_unlock(&h->mu);
    if (!drawn) return false;   /* (the X display lost) */
    double t1 = now_seconds();
    count_picture(L, graph, t1 - t0, a->locked, t1, a->scale, a->samples);
    handover_wake(h);
    return true;
}

/* Hand the overlay's text (the F1 status when shown, the page's reload
 * error) to the display when it changed. */
static void publish_overlay(Loop *L)
{
    if (!L->overlay_changed) return;
    L->overlay_changed = false;
    const char *error = L->pages[L->cur].error;
    char *status = L->show_status ? strdup(L->status) : NULL;
    char *err = error ? strdup(error) : NULL;
    Handover *h = L->hand;
    pthread_mutex_lock(&h->mu);
    free(h->status);
    free(h->error);
    h->status = status;
    h->error = err;
    h->overlay_gen++;
    pthread_mutex_unlock(&h->mu);
    handover_wake(h);
}

/* Apply the inputs the display queued, oldest first. Returns false when
 * the display failed (no window could be opened). */
static bool take_inputs(Loop *L, Input **buf, size_t *cap)
{
    Handover *h = L->hand;
    pthread_mutex_lock(&h->mu);
    Input *in = h->inputs;
    size_t n = h->ninputs, c = h->cap_inputs;
    h->inputs = *buf;
    h->cap_inputs = *cap;
    h->ninputs = 0;
    bool failed = h->failed;
    pthread_mutex_unlock(&h->mu);
    *buf = in;
    *cap = c;
    for (size_t i = 0; i < n; i++) window_input(L, &in[i]);
    return !failed;
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
    pthread_mutex_lock(&L->hand->mu);
    long all_shown = L->hand->shown, all_painted = L->hand->painted;
    double all_present = L->hand->present_seconds, all_paint = L->hand->paint_seconds;
    pthread_mutex_unlock(&L->hand->mu);
    double dt = now - L->stat_time;
    long frames = st.frames - L->stat.frames, shown = all_shown - L->stat_shown;
    long drawn = L->drawn - L->stat_drawn;
    double per = frames > 0 ? 1e3 / (double)frames : 0;
    double draw = drawn > 0 ? (L->draw_seconds - L->stat_draw) * 1e3 / (double)drawn : 0;
    double present = shown > 0 ? (all_present - L->stat_present) * 1e3 / (double)shown : 0;
    long painted = all_painted - L->stat_painted;
    double paint = painted > 0 ? (all_paint - L->stat_paint) * 1e3 / (double)painted : 0;
    /* the dynamic resolution of the last picture: its scale, the share of
     * pixels and the cap on samples */
    char scale_line[96] = "";
    if (L->scaling) {
        int samples = L->drawn_samples;
        double sc = L->drawn_scale;
        if (samples > 0)
            snprintf(scale_line, sizeof scale_line, "scale %.4g (%.0f%% of pixels), samples <= %d\n", sc,
                     sc * sc * 100, samples);
        else
            snprintf(scale_line, sizeof scale_line, "scale %.4g (%.0f%% of pixels)\n", sc, sc * sc * 100);
    }
    snprintf(L->status, sizeof L->status,
             "page %d/%d %s\n"
             "frame %ld  time %.2f s\n"
             "%.1f frames/s (target %g), shown %.1f/s\n"
             "dropped %ld frames\n"
             "eval %.2f ms  physics %.2f ms\n"
             "draw %.2f ms  paint %.2f ms  present %.2f ms\n"
             "%s"
             "%s",
             L->cur + 1, L->npages, base_name(L->pages[L->cur].script), fl_frame_count(rt) - 1,
             fl_frame_time(rt), dt > 0 ? (double)frames / dt : 0.0, fl_target_fps(rt),
             dt > 0 ? (double)shown / dt : 0.0, L->dropped,
             (st.eval_seconds - L->stat.eval_seconds) * per,
             (st.physics_seconds - L->stat.physics_seconds) * per, draw, paint, present, scale_line,
             L->paused ? "paused (F5 resume, F6 one frame)" : "");
    L->stat = st;
    L->stat_shown = all_shown;
    L->stat_drawn = L->drawn;
    L->stat_draw = L->draw_seconds;
    L->stat_present = all_present;
    L->stat_painted = all_painted;
    L->stat_paint = all_paint;
    L->stat_time = now;
    if (L->show_status) L->overlay_changed = true;
}

/* The --stats report at the end of the run: each page's lines as a
 * headless run prints them (runspec_print_stats; a "page N" line first
 * when there are several), then the windows': drawing milliseconds per
 * picture drawn and presenting milliseconds per picture shown, frames
 * shown and dropped, and the frame loop's busy milliseconds per frame
 * (its wall time less its waits: what a frame costs the simulation).
 * [loop]: the frame loop's wall time in seconds. */
static void print_stats(Loop *L, double loop)
{
    for (int i = 0; i < L->npages; i++) {
        Page *p = &L->pages[i];
        if (L->npages > 1) {
            if (p->ran == 0) continue;
            fprintf(L->log, "stats: page %d: %s\n", i + 1, p->script);
        }
        runspec_print_stats(p->rt, &p->first, &p->second, loop, &p->load, L->log);
    }
    Handover *h = L->hand;
    double drawn = L->drawn > 0 ? (double)L->drawn : 1, shown = h->shown > 0 ? (double)h->shown : 1;
    fprintf(L->log, "stats: window: per frame shown: draw %.3f ms, present %.3f ms\n",
            L->draw_seconds / drawn * 1e3, h->present_seconds / shown * 1e3);
    if (h->painted > 0)
        fprintf(L->log, "stats: window: physics view painted by the display: %.3f ms per picture, "
                "%ld pictures\n", h->paint_seconds / (double)h->painted * 1e3, h->painted);
    fprintf(L->log, "stats: window: %ld frames shown, %ld dropped\n", h->shown, L->dropped);
    if (L->scaling) {
        double least = (double)L->scale.least_step / 16;
        fprintf(L->log, "stats: window: scale: %ld pictures below full size (mean scale %.3f), least %.4g "
                "(%.0f%% of pixels), now %.4g; %ld changes\n", L->scaled_pictures,
                L->scaled_pictures > 0 ? L->scale_sum / (double)L->scaled_pictures : 1.0, least, least * least * 100,
                winscale_scale(&L->scale), L->scale.changes);
    }
    double ran = L->ran > 0 ? (double)L->ran : 1;
    fprintf(L->log, "stats: window: frame loop busy %.3f ms per frame, %ld pictures drawn\n",
            (loop - L->wait_seconds) / ran * 1e3, L->drawn);
    fflush(L->log);
}

/* {=====================================================================
 * The frame loop
 * ===================================================================== */

/* fl_outputs_frame of a page (an OutputsRun), run where its pictures are
 * drawn. */
static void outputs_frame(Loop *L, void *ctx)
{
    OutputsRun *o = ctx;
    wingl_lock(L->hand->gl);
    o->rc = fl_outputs_frame(o->p->outs, o->p->rt);
    wingl_unlock(L->hand->gl);
}

/* Wait until [due] (monotonic seconds), applying inputs as they come;
 * returns early when the run ends. */
static void wait_until(Loop *L, double due, Input **buf, size_t *cap)
{
    Handover *h = L->hand;
    double t0 = now_seconds();
    for (;;) {
        if (!take_inputs(L, buf, cap) || L->quit || *L->interrupt) break;
        pthread_mutex_lock(&h->mu);
        if (h->ninputs == 0 && !h->failed && now_seconds() < due) handover_wait(h, due);
        bool more = h->ninputs > 0 || h->failed;
        pthread_mutex_unlock(&h->mu);
        if (!more && now_seconds() >= due) break;
    }
    L->wait_seconds += now_seconds() - t0;
}

/* One pass: inputs, reload, a frame (unless paused), its pictures,
 * pacing. Returns false when the run ends. */
static bool loop_once(Loop *L, Input **buf, size_t *cap)
{
    const RunSpec *spec = L->spec;
    if (!take_inputs(L, buf, cap)) {
        L->rc = EXIT_LOAD;
        return false;
    }
    if (L->quit || *L->interrupt) return false;
    if (L->switch_to >= 0 && !drawing_wait_idle(L)) return false;   /* (no picture out) */
    if (L->switch_to >= 0) {
        wingl_lock(L->hand->gl);   /* (a runtime freed or made draws) */
        switch_page(L, L->switch_to);
        wingl_unlock(L->hand->gl);
        L->switch_to = -1;
        L->redraw = true;
    }
    check_reload(L);
    Page *p = &L->pages[L->cur];
    bool stepped = false;
    if (!L->paused || L->steps > 0) {
        if (L->steps > 0) L->steps--;
        double before = fl_next_frame_time(p->rt);
        double sim0 = now_seconds();
        int rc = fl_step(p->rt);
        if (rc < 0) fprintf(L->log, "%s: error: %s", p->script, fl_error(p->rt));   /* the clock's limit */
        if (rc != 0) return false;   /* interrupted inside the frame, or no further frame */
        stepped = true;
        L->clock_run += fl_next_frame_time(p->rt) - before;
        L->ran++;
        p->ran++;
        if (p->ran == 1) fl_get_stats(p->rt, &p->first);
        if (p->ran == 2) fl_get_stats(p->rt, &p->second);
        L->dumped_last = false;
        int orc;
        if (L->draw.running && !fl_outputs_draws(p->outs, p->rt)) {
            orc = fl_outputs_frame(p->outs, p->rt);   /* (draws nothing: beside the drawing thread) */
        } else {
            L->outputs_run = (OutputsRun){p, 0};
            if (!drawing_run(L, outputs_frame, &L->outputs_run)) return false;   /* (the X display lost) */
            orc = L->outputs_run.rc;
        }
        if (orc != 0) fprintf(L->log, "flitter run: %s", fl_error(p->rt));
        double sim1 = now_seconds();
        winscale_frame(&L->scale, sim1 - sim0);
        /* the frames' period, smoothed (the time from one frame's end to
         * the next's: its simulation, drawing and waits; a gap of a second
         * or more, a pause, is not a frame's) */
        if (L->last_frame_end > 0 && sim1 - L->last_frame_end < 1) {
            double dt = sim1 - L->last_frame_end;
            L->frame_period = L->frame_period > 0 ? 0.9 * L->frame_period + 0.1 * dt : dt;
        }
        L->last_frame_end = sim1;
        long n = fl_frame_count(p->rt);
        if (spec->dump_state && spec->dump_every > 0 && n % spec->dump_every == 0) {
            fl_dump_state(p->rt, write_file, L->out);
            fflush(L->out);
            L->dumped_last = true;
            if (ferror(L->out)) {
                /* (SIGPIPE is blocked in window runs: a closed pipe
                 * ends the run here, as Escape does) */
                fprintf(L->log, "flitter: cannot write the state dumps (standard output closed?): the run ends\n");
                L->quit = true;
            }
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
         * a late frame is still drawn when nothing was for twice what the
         * last picture cost to draw, at least 100 ms (a picture that takes
         * a second to draw, a large !canvas3d on a CPU, then holds the
         * simulation up for at most a third of the time); in a window
         * that scales its pictures down to keep its rate, which has made
         * them as cheap as it may, for what the last one cost (drawing
         * then takes at most half the time), or not at all while the
         * frames keep half the frame rate. A picture the drawing thread
         * draws beside the next frames holds nothing up: it is drawn
         * whenever that thread is free (draw_frame) */
        bool beside = L->draw.running && !L->show_view && p->gl;
        bool late = !beside && L->realtime && stepped && fl_frame_wait(p->rt) < 0.001;
        /* (a slow picture restarts the realtime schedule, so the frame
         * after it is not late: a picture slower than a frame counts as
         * late on its own) */
        bool slow = !beside && L->realtime && stepped && L->last_draw_cost * fl_target_fps(p->rt) > 1;
        double gap = L->scaling ? L->last_draw_cost : L->last_draw_cost * 2 > 0.1 ? L->last_draw_cost * 2 : 0.1;
        /* a scaling window whose frames still come at half the rate or
         * more draws every frame, as Flitter does */
        if (L->scaling && L->frame_period > 0 && L->frame_period * fl_target_fps(p->rt) <= 2) gap = 0;
        if ((late || slow) && now - L->last_drawn < gap && !L->redraw) {
            L->dropped++;
        } else if (draw_frame(L)) {
            L->redraw = false;
        } else if (L->realtime && !L->redraw) {
            L->dropped++;   /* the drawing thread or the display is still busy with the last picture */
        }
        /* (a redraw the display could not take yet stays asked for) */
    } else if (L->overlay_changed) {
        update_status(L, true);
    }
    publish_overlay(L);
    if (L->realtime && spec->runtime_clock) {   /* --runtime: seconds of the clock */
        if (runspec_runtime_over(spec, L->clock_run, fl_target_fps(p->rt))) return false;
    } else if (spec->frames >= 0 && L->ran >= spec->frames) {
        return false;
    }
    /* pacing (EngineController.run, through fl_frame_wait): realtime
     * frames 1/fps apart, a slow frame restarts the schedule from now;
     * lockstep (which also waits for the display in draw_frame) 1 ms,
     * so that a window shows at most 1,000 frames a second; paused 20 ms
     * or until the next input */
    if (L->realtime && stepped) {
        double wait = fl_frame_wait(p->rt);
        if (wait >= 0.001) wait_until(L, now_seconds() + wait - 0.001, buf, cap);
    } else {
        wait_until(L, now_seconds() + (stepped ? 0.001 : 0.02), buf, cap);
    }
    return true;
}

/* Print the dumps that end a run (--dump-state unless the last frame
 * was dumped, --dump-tree), as Escape leaves them. */
static void final_dumps(Loop *L)
{
    Page *p = &L->pages[L->cur];
    if (fl_frame_count(p->rt) > 0) {
        if (L->spec->dump_state && !L->dumped_last) fl_dump_state(p->rt, write_file, L->out);
        if (L->spec->dump_tree) fl_dump_tree(p->rt, write_file, L->out);
    }
    fflush(L->out);
}

/* End the run after the X display was lost (window_lost.h), on whichever
 * thread window_lost.c chose, the frame loop being in no step: what
 * Escape leaves (stats, dumps, outputs finished, states saved; no X or
 * OpenGL call), then exit status 3. */
static _Noreturn void end_lost(void *ctx)
{
    Loop *L = ctx;
    if (winlost_kind(&L->hand->lost) == LOST_CONNECTION)   /* (a destroy was said by the display) */
        fprintf(L->log, "flitter: the connection to the X display was lost: the run ends "
                "(exit status %d)\n", EXIT_WINDOW_LOST);
    if (!L->ended && L->npages > 0) {
        if (L->spec->stats) print_stats(L, now_seconds() - L->start);
        final_dumps(L);
    }
    /* the outputs are finished where nothing draws any more: a drawing
     * thread held in an X call for good leaves them unfinished */
    bool settled = drawing_settle(L, 2.0);
    if (!settled)
        fprintf(L->log, "flitter: the drawing thread did not finish its picture: the outputs are left "
                "unfinished\n");
    for (int i = 0; i < L->npages; i++) {
        Page *p = &L->pages[i];
        if (p->outs && settled && fl_outputs_close(p->outs, p->rt) != 0 && *fl_error(p->rt))
            fprintf(L->log, "flitter run: %s", fl_error(p->rt));
        p->outs = NULL;
        save_page(L, p);
    }
    fflush(L->out);
    fflush(L->log);
    _exit(EXIT_WINDOW_LOST);
}

/* The frame loop's thread: frames until the run ends, then tell the
 * display. */
static void *frame_thread(void *arg)
{
    Loop *L = arg;
    Input *buf = NULL;
    size_t cap = 0;
    winlost_frame_started(&L->hand->lost);
    /* the runtimes draw their windows with the frame loop's OpenGL
     * context, on the drawing thread; without it (the thread could not
     * start), on this one */
    if (!drawing_start(L)) drawing_attach(L);
    while (loop_once(L, &buf, &cap)) {}
    free(buf);
    winlost_frame_ending(&L->hand->lost);   /* (the X display lost: ends the run here) */
    if (L->draw.running) drawing_stop(L);
    else if (L->gl) wingl_frame_leave(L->hand->gl);
    pthread_mutex_lock(&L->hand->mu);
    L->hand->done = true;
    pthread_mutex_unlock(&L->hand->mu);
    handover_wake(L->hand);
    return NULL;
}

static int run_windows(const RunSpec *spec, FILE *out, FILE *log, volatile int *interrupt, char *why,
                       size_t cap)
{
    if (winview_start(why, cap) != 0) return WINDOW_NO_DISPLAY;
    Handover hand;
    handover_init(&hand);
    char glwhy[300];
    /* FLITTER_WINDOW_READBACK=1: the pictures read back and shown
     * through SDL's renderer, as a machine without OpenGL windows shows
     * them (for comparison: bench/window.sh) */
    const char *rb = getenv("FLITTER_WINDOW_READBACK");
    if (rb && strcmp(rb, "1") == 0) {
        hand.gl = NULL;
        snprintf(glwhy, sizeof glwhy, "FLITTER_WINDOW_READBACK=1");
    } else {
        hand.gl = wingl_start(glwhy, sizeof glwhy);
    }
    if (!hand.gl && spec->verbosity >= 1)
        fprintf(log, "flitter: windows shown through SDL's renderer (pictures read back): %s\n", glwhy);
    Loop L = {.spec = spec, .out = out, .log = log, .interrupt = interrupt, .hand = &hand,
              .switch_to = -1, .runspec = *spec, .drawn_scale = 1};
    WinOptions wopt = {spec->screen, spec->fullscreen, spec->vsync};
    if (!L.interrupt) L.interrupt = &L.never;
    winlost_init(&hand.lost, L.interrupt, hand.gl, end_lost, &L);
    /* Flitter's windows run on the realtime clock unless --lockstep */
    L.realtime = spec->clock_given ? spec->realtime : true;
    L.runspec.realtime = L.realtime;
    /* dynamic resolution: realtime only (in lockstep every frame is
     * shown whole, whatever it costs) */
    winscale_init(&L.scale, spec->min_scale);
    L.scaling = L.realtime && L.scale.floor_step < 16;
    L.files = (RunLog){log, (spec->dump_state || spec->dump_tree) ? log : out};
    int rc = open_pages(&L);
    if (rc == EXIT_OK) {
        if (spec->dump_simplified) fl_dump_program(L.pages[0].rt, write_file, out);
        L.last_save = L.stat_time = L.start = now_seconds();
        L.last_drawn = -1;
        /* Xlib's error handlers are the process's, and SDL's GLX
         * make-current saves and puts back the one it finds (SDL 2.26,
         * X11_GL_MakeCurrent): ours go in before the frame loop's thread
         * first makes its context current, or that thread may put SDL's
         * exiting handler back over them (window/lost's destroy then ended
         * with status 1 about once in a thousand runs) */
        if (hand.gl) {
            SDL_Window *gl_display, *gl_frame;
            wingl_windows(hand.gl, &gl_display, &gl_frame);
            winlost_watch(&hand.lost, gl_display);
        }
        pthread_t thread;
        if (pthread_create(&thread, NULL, frame_thread, &L) != 0) {
            fprintf(log, "flitter: cannot start the frame loop's thread\n");
            L.rc = EXIT_LOAD;
        } else {
            window_display(&hand, &wopt, log);
            pthread_join(thread, NULL);
        }
        rc = L.rc;
        if (hand.failed) rc = EXIT_LOAD;
        if (spec->stats) print_stats(&L, now_seconds() - L.start);
        final_dumps(&L);
        L.ended = true;
        /* a window destroyed by another client: the pages are saved and the
         * process ends here, its OpenGL and SDL left to the exit (making a
         * context current on a destroyed window, or SDL_Quit, which puts
         * Xlib's exiting error handler back before it frees the windows'
         * X objects, would end it with status 1) */
        if (winlost_kind(&hand.lost) == LOST_DESTROYED) end_lost(&L);
    }
    free(L.info);
    /* the runtimes' graphs were drawn with the frame loop's context: freed with it current */
    bool gl_current = hand.gl && wingl_frame_enter(hand.gl);
    if (gl_current)   /* the sets' textures, now that the display is done with them */
        for (int i = 0; i < 2; i++)
            for (size_t k = 0; k < hand.sets[i].cap; k++) wingl_picture_free(&hand.sets[i].win[k].glpic);
    rc = close_pages(&L, rc);
    if (gl_current) wingl_frame_leave(hand.gl);
    wingl_stop(hand.gl);
    handover_free(&hand);
    winlost_sync(&hand.lost);   /* (the errors of a destroyed window's requests, under our handler) */
    SDL_Quit();
    winlost_free(&hand.lost);
    return rc;
}

int window_run(const RunSpec *spec, FILE *out, FILE *log, volatile int *interrupt, char *why,
               size_t cap)
{
    /* SIGPIPE blocked on the threads that talk to X (window/lost's
     * `kill --lockstep` died of it about once in 25 runs); a write to a
     * closed standard output then fails too, and the frame loop ends the
     * run */
    sigset_t old;
    winlost_block_sigpipe(&old);
    int rc = run_windows(spec, out, log, interrupt, why, cap);
    winlost_unblock_sigpipe(&old);
    return rc;
}
