/* window_loop.h: the state of a run with live windows, shared by the
 * frame loop (window_main.c) and the input handler (window_input.c). */
#ifndef FL_WINDOW_LOOP_H
#define FL_WINDOW_LOOP_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "flitter.h"
#include "runner.h"
#include "watch.h"
#include "window_sdl.h"

/* Slot.index of the window that shows the physics view of a frame
 * without !window. */
#define NO_WINDOW SIZE_MAX

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
} Page;

/* One open window. */
typedef struct Slot {
    WinView view;
    size_t index;            /* fl_windows index of its !window, or NO_WINDOW */
    int width, height;       /* its picture's size in pixels (size=) */
    unsigned overlay_gen;    /* Loop.overlay_gen its overlay was painted for */
    bool warned;             /* a drawing failure was logged */
} Slot;

typedef struct Loop {
    const RunSpec *spec;
    RunSpec runspec;         /* *spec with the window's clock (realtime) */
    FILE *out, *log;
    RunLog files;            /* the runtimes' log lines */
    volatile int *interrupt; /* set by SIGINT/SIGTERM */
    volatile int never;      /* *interrupt when the caller gives none */
    Page *pages;
    int npages, cur;         /* pages and the current one */
    int switch_to;           /* page to switch to after this frame, or -1 */
    Slot *slots;
    size_t nslots, cap_slots;
    fl_window_info *info;    /* fl_windows of the last frame */
    size_t cap_info;
    WinOptions wopt;
    bool realtime;           /* the clock: realtime, or lockstep */
    bool quit;               /* Escape or a window closed */
    int rc;                  /* exit status so far */
    bool show_status;        /* F1: the status overlay */
    bool show_view;          /* F2: the physics view instead of the pictures */
    bool paused;             /* F5 */
    int steps;               /* F6: frames to step while paused */
    bool redraw;             /* draw the pictures again (page switch, F2) */
    bool represent;          /* present again (exposed, resized, overlay changed) */
    bool dumped_last;        /* --dump-every dumped the last frame */
    long ran;                /* frames stepped, every page */
    long shown, dropped;     /* frames whose pictures were shown / dropped */
    double draw_seconds;     /* spent drawing pictures (fl_draw_window, fl_draw_view), in total */
    double present_seconds;  /* spent showing them (windows followed, texture upload,
                                overlay, copy, present), in total */
    double start;            /* when the frame loop began */
    double last_shown;       /* when a picture was last shown */
    double last_show_cost;   /* seconds that showing it took (drawing included) */
    double last_save;        /* when --state was last saved */
    unsigned overlay_gen;    /* bumped whenever the overlay text changes */
    char status[512];        /* the F1 text */
    fl_stats stat;           /* statistics at the last status update */
    long stat_shown;
    double stat_draw, stat_present, stat_time;
} Loop;

/* Handle one SDL event [ev] of a run (window_input.c): keys go to the
 * window's !key nodes first (fl_key), and only unclaimed ones act: Escape
 * ends the run, left/right arrows (on release) switch pages, F1 status,
 * F2 picture/physics view, F5 pause, F6 one frame; pointer motion and
 * buttons go to its !pointer (fl_pointer, fl_pointer_button); closing a
 * window ends the run.
 *   source: Flitter render/window/__init__.py key_callback,
 *           pointer_movement_callback, pointer_button_callback. */
void window_event(Loop *L, const SDL_Event *ev);

#endif
