/* window_module.c: the `flitter` command's side of the window module
 * (module.h): window_run and repl_window_open, _poll, _frame, _close as the
 * command calls them, each loading flitter-window.so on first use
 * ($FLITTER_WINDOW_MODULE overrides where) and calling the module's
 * function of the same name and signature. A module that cannot be loaded
 * (or SDL2, which it links) is answered as when there is no display:
 * window_run returns WINDOW_NO_DISPLAY and repl_window_open NULL with the
 * reason in [why], and the run goes on headless.
 *
 * The entry points found are kept for the rest of the process: like the
 * dynamic loader's own state they are per process, not per runtime, and
 * only the command's main thread calls in here. */
#include <dlfcn.h>
#include <stdlib.h>

#include "module.h"
#include "repl_window.h"
#include "window.h"

typedef struct WindowModule {
    void *handle;            /* module_open's, or NULL until loaded */
    int (*run)(const RunSpec *, FILE *, FILE *, volatile int *, char *, size_t);
    ReplWindow *(*open)(fl_runtime *, const char *, void (*)(void *), void *, char *, size_t);
    bool (*poll)(ReplWindow *);
    void (*frame)(ReplWindow *, fl_runtime *, bool);
    void (*close)(ReplWindow *);
} WindowModule;

static WindowModule module;

/* The same text as winview_start's (window_sdl.c) when there is no display:
 * checked here first so that a run without one does not load SDL2 only to
 * learn it. */
static bool no_display(char *why, size_t cap)
{
    const char *x = getenv("DISPLAY"), *w = getenv("WAYLAND_DISPLAY");
    if ((x && *x) || (w && *w)) return false;   /* (set but empty: none) */
    snprintf(why, cap, "no display (DISPLAY and WAYLAND_DISPLAY are not set or empty)");
    return true;
}

/* Load the module and find its entry points, once: 0, or -1 with the
 * reason in [why]. */
static int load(char *why, size_t cap)
{
    if (module.handle) return 0;
    void *h = module_open("window", "flitter-window.so", "FLITTER_WINDOW_MODULE", why, cap);
    if (!h) return -1;
    /* POSIX: a function's address converts from dlsym's void * this way */
    *(void **)&module.run = dlsym(h, "window_run");
    *(void **)&module.open = dlsym(h, "repl_window_open");
    *(void **)&module.poll = dlsym(h, "repl_window_poll");
    *(void **)&module.frame = dlsym(h, "repl_window_frame");
    *(void **)&module.close = dlsym(h, "repl_window_close");
    if (!module.run || !module.open || !module.poll || !module.frame || !module.close) {
        snprintf(why, cap, "the window module lacks an entry point");
        return -1;
    }
    module.handle = h;
    return 0;
}

int window_run(const RunSpec *spec, FILE *out, FILE *log, volatile int *interrupt, char *why,
               size_t cap)
{
    if (no_display(why, cap) || load(why, cap) != 0) return WINDOW_NO_DISPLAY;
    return module.run(spec, out, log, interrupt, why, cap);
}

ReplWindow *repl_window_open(fl_runtime *rt, const char *name, void (*lost)(void *), void *ctx,
                             char *why, size_t cap)
{
    if (no_display(why, cap) || load(why, cap) != 0) return NULL;
    return module.open(rt, name, lost, ctx, why, cap);
}

/* A ReplWindow exists only when the module was loaded to open it. */
bool repl_window_poll(ReplWindow *w)
{
    return module.poll(w);
}

void repl_window_frame(ReplWindow *w, fl_runtime *rt, bool force)
{
    module.frame(w, rt, force);
}

void repl_window_close(ReplWindow *w)
{
    if (w) module.close(w);
}
