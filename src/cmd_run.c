/* cmd_run.c: `flitter run` (FORMATS.md §4), and Flitter's own command line
 * `flitter [options] SCRIPT...` (main.c passes it with argv[0] other than
 * "run"), which opens windows when there is a display. */
#include <signal.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "commands.h"
#include "exitcodes.h"
#include "prefault.h"
#include "runner.h"
#include "window.h"

static volatile int interrupted;

/* The flag holds the signal's number: a run cut short exits 128 + it. */
static void on_signal(int sig)
{
    /* an atomic store: the physics engine's worker threads read the flag
     * (lock-free, so safe in a signal handler) */
    __atomic_store_n(&interrupted, sig, __ATOMIC_RELAXED);
}

/* SIGINT, SIGTERM and SIGHUP end a run the same way: the interrupt flag,
 * polled by the library inside long work, then --state saved and the
 * dumps written on the way out. Without SA_RESTART, a system call that
 * is waiting returns (EINTR) instead of holding the run. */
static void catch_signals(void)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = 0;
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    sigaction(SIGHUP, &sa, NULL);
}

/* Whether a display is named (DISPLAY or WAYLAND_DISPLAY set and not
 * empty): a window was to be expected. */
static bool display_named(void)
{
    const char *x = getenv("DISPLAY"), *w = getenv("WAYLAND_DISPLAY");
    return (x && *x) || (w && *w);
}

/* A run with windows, or headless when there is no display: returns
 * WINDOW_NO_DISPLAY after saying so (on a terminal, where a display is
 * named, or always for an explicit --window), else window_run's status. */
static int run_window(RunSpec *spec)
{
    char why[256];
    /* the window draws every frame: its freed heap is kept for the next */
    prefault_keep_freed();
    int rc = window_run(spec, stdout, stderr, &interrupted, why, sizeof why);
    if (rc != WINDOW_NO_DISPLAY) return rc;
    /* headless output stays byte for byte what it was for scripts and CI
     * (no display): the notice goes to a person at a terminal, or to the
     * log of one whose display could not show the window (a module or
     * SDL that would not start: else the run would go on unseen) */
    if (spec->verbosity >= 0 && (!spec->implicit_window || isatty(STDERR_FILENO) || display_named()))
        fprintf(stderr, "flitter: %s: running headless%s\n", why,
                spec->nscripts > 1 ? " (the first SCRIPT only)" : "");
    return rc;
}

int cmd_run(int argc, char **argv)
{
    RunSpec spec;
    bool flitter_line = strcmp(argv[0], "run") != 0;
    int rc = runspec_parse(&spec, argc, argv, flitter_line ? RUNSPEC_PAGES : RUNSPEC_ONE_SCRIPT,
                           stderr);
    if (rc == 0 && spec.verbosity >= 1)   /* --verbose: Flitter logs its version */
        fprintf(stderr, "flitter: flitter-c %s\n", FLITTER_VERSION);
    /* Flitter's command line runs on the wall clock unless --lockstep,
     * in a window, --offscreen or headless */
    if (rc == 0 && flitter_line && !spec.clock_given) spec.realtime = true;
    if (rc == 0) rc = runspec_check_outputs(&spec, stderr);
    if (rc == 0) {
        catch_signals();
        rc = WINDOW_NO_DISPLAY;
        if (runspec_wants_window(&spec)) rc = run_window(&spec);
        if (rc == WINDOW_NO_DISPLAY) {
            /* a progress bar for a lockstep run of known length, else a status line */
            spec.progress = spec.verbosity >= 0 && isatty(STDERR_FILENO) &&
                            (spec.frames < 0 || !spec.realtime);
            spec.exiting = true;   /* cmd_run's return ends the process (main.c) */
            rc = runspec_execute(&spec, stdout, stderr, &interrupted);
        }
    } else if (rc < 0) {
        rc = EXIT_OK;
    }
    runspec_free(&spec);
    return rc;
}
