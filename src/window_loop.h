/* window_loop.h: the state of a run with live windows. Three threads
 * share it: the frame loop (window_main.c, its own thread) steps the
 * runtimes and describes each shown frame's pictures; with OpenGL windows
 * the drawing thread (window_drawing.c) holds the frame loop's OpenGL
 * context and draws them, a frame's picture beside the frame loop's next
 * frame (fl_picture_take) or, what cannot be drawn beside it, while the
 * frame loop waits (without OpenGL windows the frame loop draws them into
 * plain pixel buffers itself, except a flat physics view, of which it
 * takes a snapshot, fl_view_snapshot); the display (window_display.c, the
 * thread that started SDL, as SDL's video wants) owns the SDL windows,
 * turns SDL events into Inputs for the frame loop (window_input.c applies
 * them), paints the snapshots (fl_view_painter) and presents the
 * pictures. The frame loop and the display meet only in a Handover
 * (window_handover.c), under its mutex; the frame loop and the drawing
 * thread in a Drawing, under its own. */
#ifndef FL_WINDOW_LOOP_H
#define FL_WINDOW_LOOP_H

#include <pthread.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "flitter.h"
#include "runner.h"
#include "watch.h"
#include "window_lost.h"
#include "window_scale.h"
#include "window_sdl.h"

/* The fl_windows index of a window that shows the physics view of a frame
 * without !window. */
#define NO_WINDOW SIZE_MAX

/* {=====================================================================
 * The handover between the frame loop and the display
 * ===================================================================== */

/* One window's part of a picture set: what its !window asks for, and its
 * picture (0xAARRGGBB words, premultiplied, rows pw*4 bytes apart). */
typedef struct ShownWindow {
    size_t index;            /* fl_windows index of its !window, or NO_WINDOW */
    char title[256];         /* the window's title */
    int width, height;       /* size= of the !window (the window's size), pixels */
    bool fullscreen, vsync;
    uint32_t *px;            /* the picture, pw x ph pixels (still to be painted
                                when [paint]), or NULL when not drawn */
    int pw, ph;
    size_t cap;              /* words allocated at px */
    fl_view_snapshot *snap;  /* the physics view to paint into px (kept for reuse) */
    bool paint;              /* px is still to be painted from snap, by the display */
    WinGlPicture glpic;      /* with OpenGL windows: the window's picture as a texture */
    bool gl;                 /* the picture is glpic (else px) */
} ShownWindow;

/* The pictures of one frame, one per window to show. */
typedef struct PictureSet {
    ShownWindow *win;
    size_t n, cap;
    long frame;              /* the frame they show (fl_frame_count - 1) */
} PictureSet;

/* What happened in a window, resolved by the display from an SDL event
 * (window_display.c) and applied by the frame loop (window_input.c). */
typedef enum InputKind {
    INPUT_KEY,               /* a key pressed or released (repeats left out) */
    INPUT_POINTER,           /* the pointer moved, or left the window */
    INPUT_BUTTON,            /* a pointer button pressed or released */
    INPUT_QUIT,              /* a window was closed */
    INPUT_RESIZED,           /* the physics view window's output size changed */
} InputKind;

typedef struct Input {
    InputKind kind;
    size_t index;            /* fl_windows index of the window, or NO_WINDOW */
    int scancode;            /* INPUT_KEY: the SDL_Scancode */
    bool pressed;            /* INPUT_KEY, INPUT_BUTTON */
    bool inside;             /* INPUT_POINTER: on the picture (else it left) */
    double fx, fy;           /* INPUT_POINTER: fractions of the picture, 0..1 */
    int button;              /* INPUT_BUTTON: GLFW's number, left 0 */
} Input;

enum { SET_FREE, SET_DRAWING, SET_PENDING, SET_SHOWING };

typedef struct Handover {
    WinGl *gl;               /* the windows' OpenGL (window_gl.h), or NULL: SDL's renderer */
    pthread_mutex_t mu;
    pthread_cond_t cond;     /* the frame loop waits on it: inputs came, a set was taken */
    pthread_cond_t display_cond; /* the display waits on it: a set or overlay text came,
                                    the frame loop ended */
    PictureSet sets[2];
    int state[2];            /* SET_* of each set */
    Input *inputs;           /* queued for the frame loop, oldest first */
    size_t ninputs, cap_inputs;
    int view_w, view_h;      /* output size of the physics view window (0: not open yet) */
    char *status;            /* the F1 text, or NULL when hidden */
    char *error;             /* the failed reload's message, or NULL */
    unsigned overlay_gen;    /* bumped whenever status or error changes */
    bool done;               /* the frame loop has ended */
    bool failed;             /* the display could not open a window */
    long shown;              /* sets presented */
    double present_seconds;  /* spent presenting them, in total */
    long painted;            /* physics views painted by the display (ShownWindow.paint) */
    double paint_seconds;    /* spent painting them, in total (not in present_seconds) */
    WinLost lost;            /* the window or the X display lost (window_lost.h) */
} Handover;

/* Make [h] (mutex, conditions on CLOCK_MONOTONIC, no sets drawn);
 * handover_free() frees it. Aborts when out of memory or when pthreads
 * cannot make a mutex. */
void handover_init(Handover *h);
void handover_free(Handover *h);
/* Wake the display (h->display_cond; the frame loop makes no SDL call:
 * SDL_PushEvent would wake SDL_WaitEvent with an X11 request from the
 * frame loop's thread, which killed a run with BadWindow). */
void handover_wake(Handover *h);
/* Queue [in] for the frame loop and wake it (display side). */
void handover_input(Handover *h, const Input *in);
/* Wait on h->cond until monotonic time [due] (seconds) or a signal;
 * h->mu must be held. */
void handover_wait(Handover *h, double due);
/* The same on condition [cond]. */
void handover_wait_on(Handover *h, pthread_cond_t *cond, double due);
/* Monotonic seconds. */
double handover_now(void);

/* {=====================================================================
 * The frame loop's state
 * ===================================================================== */

/* The drawing thread (window_drawing.c): the frame loop posts one job at
 * a time, a picture (drawn while the frame loop goes on) or a task (run
 * while it waits), and takes a picture's results back when it is done. */
typedef enum DrawKind { DRAW_NONE, DRAW_PICTURE, DRAW_TASK, DRAW_STOP } DrawKind;

struct Loop;

/* What the drawing of a picture gives back to the frame loop. */
typedef struct DrawResult {
    fl_runtime *rt;          /* the picture's runtime, to free it with */
    fl_picture *pic;         /* the picture drawn, for fl_picture_free */
    double seconds;          /* from the job's start to its end */
    double locked_seconds;   /* of which drawing, with the OpenGL turn held */
    double end;              /* when it ended (monotonic seconds) */
    double scale;            /* fl_window_scale of the picture drawn */
    int samples;
} DrawResult;

typedef struct Drawing {
    pthread_t thread;
    bool running;            /* the thread was started (and not yet joined) */
    bool ready;              /* it has the context and attached the pages */
    pthread_mutex_t mu;
    pthread_cond_t cond;     /* signalled on every change of what follows */
    DrawKind kind;           /* the job posted (DRAW_NONE: idle) */
    /* a DRAW_PICTURE job */
    fl_runtime *rt;
    fl_picture *pic;
    int set;                 /* the Handover's set it fills */
    bool scaling;            /* set the live scale first: */
    double scale;
    int samples;
    /* a DRAW_TASK job */
    void (*task)(struct Loop *L, void *ctx);
    void *task_ctx;
    /* the last picture drawn, until the frame loop takes it */
    bool done;
    DrawResult result;
} Drawing;

/* One script of the command line: its own runtime, state and clock. */
typedef struct Page {
    const char *script;      /* SCRIPT, borrowed from argv */
    fl_runtime *rt;
    Watch watch;             /* its program's files, for live reload */
    char *error;             /* the failed reload's message, shown until the next
                                good one; NULL when the last load succeeded */
    char *state_path;        /* --state file of this page, or NULL */
    fl_outputs *outs;        /* its !record pictures (and --view/--trace: page 1) */
    long ran;                /* frames stepped on this page in this run */
    fl_stats first, second;  /* its statistics after its first and second frames (--stats) */
    LoadTimes load;          /* its load and live reloads (--stats) */
    bool gl;                 /* its windows draw with the frame loop's OpenGL context (fl_gl_attach) */
} Page;

/* The contexts of the tasks the frame loop runs on the drawing thread
 * (window_main.c), kept in the Loop: a wait given up (the X display lost)
 * leaves the task nothing of the frame loop's stack to write to. */
typedef struct SetDraw {     /* a picture set drawn while the frame loop waits */
    PictureSet *set;
    int view_w, view_h;      /* the physics view window's output size */
    fl_runtime *rt;
    double locked;           /* seconds drawing, with the OpenGL turn */
    double scale;            /* fl_window_scale after it */
    int samples;
} SetDraw;

typedef struct OutputsRun {  /* fl_outputs_frame of a page */
    Page *p;
    int rc;
} OutputsRun;

typedef struct Loop {
    const RunSpec *spec;
    RunSpec runspec;         /* *spec with the window's clock (realtime) */
    FILE *out, *log;
    RunLog files;            /* the runtimes' log lines */
    volatile int *interrupt; /* set by SIGINT/SIGTERM */
    volatile int never;      /* *interrupt when the caller gives none */
    Handover *hand;
    Page *pages;
    int npages, cur;         /* pages and the current one */
    int switch_to;           /* page to switch to after this frame, or -1 */
    fl_window_info *info;    /* fl_windows of the last frame */
    size_t cap_info;
    bool warned;             /* a drawing failure was logged */
    bool gl;                 /* pictures go to the display as textures (window_gl.h) */
    bool realtime;           /* the clock: realtime, or lockstep */
    bool quit;               /* Escape or a window closed */
    bool ended;              /* the final dumps are printed (window_run) */
    bool closed;             /* the pages are closed and freed (window_run) */
    int rc;                  /* exit status so far */
    bool show_status;        /* F1: the status overlay */
    bool show_view;          /* F2: the physics view instead of the pictures */
    bool paused;             /* F5 */
    int steps;               /* F6: frames to step while paused */
    bool redraw;             /* draw the pictures again (page switch, F2, resize) */
    bool overlay_changed;    /* the status or error text changed */
    bool dumped_last;        /* --dump-every dumped the last frame */
    long ran;                /* frames stepped, every page */
    double clock_run;        /* seconds the clock ran over those frames, every page (--runtime) */
    long drawn, dropped;     /* frames whose pictures were drawn / dropped */
    double draw_seconds;     /* spent drawing pictures (fl_draw_window, fl_draw_view), in total */
    double wait_seconds;     /* the frame loop spent waiting (pacing, lockstep handover) */
    double start;            /* when the frame loop began */
    double last_drawn;       /* when a picture was last drawn */
    double last_draw_cost;   /* seconds that drawing it took */
    double last_save;        /* when --state was last saved */
    char status[512];        /* the F1 text */
    fl_stats stat;           /* statistics at the last status update */
    long stat_shown;
    double stat_draw, stat_present, stat_time;
    long stat_painted;       /* the display's painting at the last status update */
    double stat_paint;
    long stat_drawn;
    /* dynamic resolution (window_scale.h): realtime windows drawn
     * through OpenGL scale their pictures down to keep the rate */
    WinScale scale;
    bool scaling;            /* the scale is chosen (realtime, --min-scale below 1) */
    long scaled_pictures;    /* pictures drawn below full size */
    double scale_sum;        /* the sum of their scales, for the mean */
    double last_frame_end;   /* when the last frame's simulation ended (0: none) */
    double frame_period;     /* seconds from one frame's end to the next's, smoothed */
    double drawn_scale;      /* the scale and samples cap of the last picture drawn */
    int drawn_samples;
    Drawing draw;            /* the drawing thread, with OpenGL windows */
    SetDraw set_draw;        /* its tasks' contexts */
    OutputsRun outputs_run;
} Loop;

/* The drawing thread (window_drawing.c). drawing_start starts it with
 * the frame loop's OpenGL context (L->hand->gl) and attaches every page's
 * runtime to it (fl_gl_attach: Page.gl, L->gl); false, with nothing
 * started, when there is no context or the thread cannot start: the
 * frame loop then draws as without OpenGL windows. drawing_stop ends it
 * (after its job), its context left for the thread that frees the
 * runtimes. */
bool drawing_start(struct Loop *L);
/* Make the frame loop's OpenGL context current on the calling thread and
 * attach every page's runtime to it (Page.gl, L->gl; nothing without a
 * context): the drawing thread's first step, or the frame loop's own when
 * that thread could not start. */
void drawing_attach(struct Loop *L);
void drawing_stop(struct Loop *L);
/* Whether a picture or a task is being drawn or run; with the results of
 * the last picture drawn, if the frame loop has not taken them yet, in
 * [*out] ([*taken] true: the caller frees out->pic). One lock for both:
 * a picture is posted only after a poll that found the thread idle. */
bool drawing_poll(struct Loop *L, DrawResult *out, bool *taken);
/* Wait until the drawing thread is idle; false when the X display's
 * connection was lost first (the thread may be held in an X call for
 * good: the run ends). */
bool drawing_wait_idle(struct Loop *L);
/* For the end of a run whose X display was lost (end_lost): wait at most
 * [seconds] for the drawing thread to finish its job; whether it has (or
 * the caller is that thread, or there is none). */
bool drawing_settle(struct Loop *L, double seconds);
/* Run [fn](L, [ctx]) on the drawing thread, the frame loop waiting (after
 * the job before it) until it has run; false, [fn] perhaps still
 * running, only when the X connection was lost ([ctx] must outlive the
 * call: the Loop's). */
bool drawing_run(struct Loop *L, void (*fn)(struct Loop *L, void *ctx), void *ctx);
/* Hand picture [pic] of runtime [rt] to the idle drawing thread: it draws
 * each window of set [set] of the Handover (described by the frame loop,
 * state SET_DRAWING) at [scale] and [samples] when [scaling], copies them
 * for the display and marks the set SET_PENDING. */
void drawing_post(struct Loop *L, fl_runtime *rt, fl_picture *pic, int set, bool scaling, double scale,
                  int samples);

/* Apply input [in] to the current page of [L] (window_input.c): keys go
 * to the window's !key nodes first (fl_key), and only unclaimed ones act:
 * Escape ends the run, left/right arrows (on release) switch pages, F1
 * status, F2 picture/physics view, F5 pause, F6 one frame; pointer motion
 * and buttons go to its !pointer (fl_pointer, fl_pointer_button); closing
 * a window ends the run.
 *   source: Flitter render/window/__init__.py key_callback,
 *           pointer_movement_callback, pointer_button_callback. */
void window_input(Loop *L, const Input *in);

/* The display's side of a run (window_display.c), on the thread that
 * started SDL: handle SDL events (as Inputs to the frame loop), open and
 * close windows to follow each picture set, present it, until the frame
 * loop is done (h->done) and its last set is shown; then close the
 * windows. [wopt]: the command line's window options. A window that
 * cannot be opened is logged on [log] and sets h->failed (the frame loop
 * then ends). */
void window_display(Handover *h, const WinOptions *wopt, FILE *log);

#endif
