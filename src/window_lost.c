/* window_lost.c: the run's window or X display lost (window_lost.h).
 *
 * Xlib's I/O error path (libX11 1.8, _XIOError) holds the display's user
 * lock across both of its handlers, so any other thread blocks at its
 * next X call and never reaches a handler of its own; the process-wide
 * handler (XSetIOErrorHandler) is called first, and its default exits,
 * then the display's exit handler (XSetIOErrorExitHandler, which takes
 * user data); if that returns, Xlib exits. So the process-wide handler
 * here returns, and the exit handler never does: on the frame loop's
 * thread (a GL call that reached X) it ends the run at once, the frame
 * loop being outside any step; on the display's thread it gives up the
 * OpenGL turn, sets the interrupt so that a frame in progress ends, and
 * waits for the frame loop's thread to end the run (winlost_frame_ending);
 * should that thread stay blocked (in an X call of its own), it ends the
 * run itself after 3 s, the frame loop then being in no step. */
#include "window_lost.h"

#include <dlfcn.h>
#include <pthread.h>
#include <stdio.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include <SDL_syswm.h>

#include "exitcodes.h"

#ifdef SDL_VIDEO_DRIVER_X11

typedef int (*ErrorHandler)(Display *, XErrorEvent *);
typedef int (*IOErrorHandler)(Display *);
typedef void (*ExitHandler)(Display *, void *);

/* libX11 as SDL loaded it (NULL when it is not loaded: not X11). */
static void *x11_library(void) { return dlopen("libX11.so.6", RTLD_LAZY | RTLD_NOLOAD); }

/* Process-wide (Xlib keeps one): a protocol error is logged and the run
 * goes on; Xlib's default handler would exit. The errors that calls on
 * a window destroyed by another client raise (BadWindow, BadDrawable)
 * are expected until the run ends, and not logged. Stateless: any
 * number of runs or windows may share it. */
static int on_protocol_error(Display *dpy, XErrorEvent *e)
{
    if (e->error_code == BadWindow || e->error_code == BadDrawable) return 0;
    char text[160] = "";
    void *lib = x11_library();
    if (lib) {
        int (*get_text)(Display *, int, char *, int);
        *(void **)&get_text = dlsym(lib, "XGetErrorText");
        if (get_text) get_text(dpy, e->error_code, text, (int)sizeof text);
        dlclose(lib);
    }
    fprintf(stderr, "flitter: X error ignored: %s (error %d, request %d.%d)\n", text[0] ? text : "?",
            e->error_code, e->request_code, e->minor_code);
    return 0;
}

/* Process-wide: returns, so that Xlib goes on to the display's own exit
 * handler (on_connection_lost for a watched display; Xlib's default,
 * which exits with status 1, for any other). */
static int on_io_error(Display *dpy)
{
    (void)dpy;
    return 0;
}

static bool is_self(atomic_uintptr_t *t) { return atomic_load(t) == (uintptr_t)pthread_self(); }

/* Take the ending of the run for this thread: true when taken; false when
 * another thread has it (a second loss on the finisher's own thread, while
 * it ends the run, exits at once: its state was saved first). */
static bool claim(WinLost *w)
{
    int expect = 0;
    if (atomic_compare_exchange_strong(&w->claimed, &expect, 1)) {
        atomic_store(&w->finisher, (uintptr_t)pthread_self());
        return true;
    }
    if (is_self(&w->finisher)) _exit(EXIT_WINDOW_LOST);
    return false;
}

static _Noreturn void park(void)
{
    for (;;) pause();   /* the finisher _exits the process */
}

static _Noreturn void finish_here(WinLost *w)
{
    if (!claim(w)) park();
    w->finish(w->ctx);
    _exit(EXIT_WINDOW_LOST);   /* (finish does not return) */
}

/* The watched display's exit handler (see the top of the file). */
static void on_connection_lost(Display *dpy, void *data)
{
    (void)dpy;
    WinLost *w = data;
    int none = LOST_NONE;
    atomic_compare_exchange_strong(&w->kind, &none, LOST_CONNECTION);
    *w->interrupt = 1;
    if (atomic_load(&w->frame_running) && is_self(&w->frame_thread)) finish_here(w);
    wingl_give_up_turn(w->gl);
    /* the frame loop ends the run at its next stop; 3 s at most */
    for (int i = 0; i < 300 && atomic_load(&w->frame_running) && !atomic_load(&w->claimed); i++)
        nanosleep(&(struct timespec){0, 10000000}, NULL);
    finish_here(w);
}

void winlost_watch(WinLost *w, SDL_Window *win)
{
    if (w->dpy || !win) return;
    SDL_SysWMinfo info;
    SDL_VERSION(&info.version);
    if (!SDL_GetWindowWMInfo(win, &info) || info.subsystem != SDL_SYSWM_X11) return;
    void *lib = x11_library();
    if (!lib) return;
    ErrorHandler (*set_error)(ErrorHandler);
    IOErrorHandler (*set_io_error)(IOErrorHandler);
    void (*set_exit)(Display *, ExitHandler, void *);
    *(void **)&set_error = dlsym(lib, "XSetErrorHandler");
    *(void **)&set_io_error = dlsym(lib, "XSetIOErrorHandler");
    *(void **)&set_exit = dlsym(lib, "XSetIOErrorExitHandler");   /* libX11 >= 1.7 */
    if (!set_error || !set_io_error || !set_exit) {
        dlclose(lib);
        return;
    }
    w->x11 = lib;
    w->dpy = info.info.x11.display;
    w->get_geometry = dlsym(lib, "XGetGeometry");
    w->sync = dlsym(lib, "XSync");
    w->grab = dlsym(lib, "XGrabServer");
    w->ungrab = dlsym(lib, "XUngrabServer");
    w->flush = dlsym(lib, "XFlush");
    set_exit(info.info.x11.display, on_connection_lost, w);
    set_io_error(on_io_error);
    set_error(on_protocol_error);
    SDL_EventState(SDL_SYSWMEVENT, SDL_ENABLE);
}

bool winlost_window_exists(WinLost *w, SDL_Window *win)
{
    unsigned long xid = winlost_xid(win);
    if (!w->dpy || !w->get_geometry || !xid) return true;
    Status (*get_geometry)(Display *, Drawable, Window *, int *, int *, unsigned *, unsigned *,
                           unsigned *, unsigned *);
    *(void **)&get_geometry = w->get_geometry;
    Window root;
    int x, y;
    unsigned width, height, border, depth;
    return get_geometry(w->dpy, xid, &root, &x, &y, &width, &height, &border, &depth) != 0;
}

bool winlost_hold_server(WinLost *w, bool hold)
{
    if (!w->dpy || !w->grab || !w->ungrab || !w->flush) return false;
    int (*call)(Display *);
    *(void **)&call = hold ? w->grab : w->ungrab;
    call(w->dpy);
    if (!hold) {
        *(void **)&call = w->flush;
        call(w->dpy);
    }
    return true;
}

void winlost_sync(WinLost *w)
{
    if (!w->dpy || !w->sync) return;
    int (*sync)(Display *, Bool);
    *(void **)&sync = w->sync;
    sync(w->dpy, False);
}

unsigned long winlost_xid(SDL_Window *win)
{
    SDL_SysWMinfo info;
    SDL_VERSION(&info.version);
    if (!win || !SDL_GetWindowWMInfo(win, &info) || info.subsystem != SDL_SYSWM_X11) return 0;
    return info.info.x11.window;
}

unsigned long winlost_destroyed(const SDL_Event *ev)
{
    if (ev->type != SDL_SYSWMEVENT || !ev->syswm.msg || ev->syswm.msg->subsystem != SDL_SYSWM_X11)
        return 0;
    const XEvent *x = &ev->syswm.msg->msg.x11.event;
    return x->type == DestroyNotify ? x->xdestroywindow.window : 0;
}

#else   /* SDL without X11: nothing to watch */

void winlost_watch(WinLost *w, SDL_Window *win) { (void)w, (void)win; }
unsigned long winlost_xid(SDL_Window *win) { (void)win; return 0; }
unsigned long winlost_destroyed(const SDL_Event *ev) { (void)ev; return 0; }
bool winlost_window_exists(WinLost *w, SDL_Window *win) { (void)w, (void)win; return true; }
bool winlost_hold_server(WinLost *w, bool hold) { (void)w, (void)hold; return false; }
void winlost_sync(WinLost *w) { (void)w; }
static _Noreturn void finish_here(WinLost *w) { w->finish(w->ctx); _exit(EXIT_WINDOW_LOST); }

#endif

void winlost_init(WinLost *w, volatile int *interrupt, WinGl *gl, void (*finish)(void *), void *ctx)
{
    memset(w, 0, sizeof *w);
    atomic_init(&w->kind, LOST_NONE);
    atomic_init(&w->claimed, 0);
    atomic_init(&w->finisher, 0);
    atomic_init(&w->frame_running, false);
    atomic_init(&w->frame_thread, 0);
    w->interrupt = interrupt;
    w->gl = gl;
    w->finish = finish;
    w->ctx = ctx;
}

void winlost_free(WinLost *w)
{
    if (w->x11) dlclose(w->x11);
    w->x11 = NULL;
    w->dpy = NULL;
}

bool winlost_set_destroyed(WinLost *w)
{
    int none = LOST_NONE;
    return atomic_compare_exchange_strong(&w->kind, &none, LOST_DESTROYED);
}

void winlost_frame_started(WinLost *w)
{
    atomic_store(&w->frame_thread, (uintptr_t)pthread_self());
    atomic_store(&w->frame_running, true);
}

void winlost_frame_ending(WinLost *w)
{
    if (atomic_load(&w->kind) == LOST_CONNECTION) finish_here(w);
    atomic_store(&w->frame_running, false);
    /* (a loss between the test and the store: the handler saw the loop
     * running and waits for it; look again) */
    if (atomic_load(&w->kind) == LOST_CONNECTION) finish_here(w);
}

LostKind winlost_kind(WinLost *w) { return (LostKind)atomic_load(&w->kind); }

void winlost_block_sigpipe(sigset_t *old)
{
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, SIGPIPE);
    pthread_sigmask(SIG_BLOCK, &set, old);
}

void winlost_unblock_sigpipe(const sigset_t *old)
{
    if (!sigismember(old, SIGPIPE)) {
        sigset_t set;
        sigemptyset(&set);
        sigaddset(&set, SIGPIPE);
        struct timespec none = {0, 0};
        while (sigtimedwait(&set, NULL, &none) == SIGPIPE) {}
    }
    pthread_sigmask(SIG_SETMASK, old, NULL);
}
