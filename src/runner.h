/* runner.h: what `flitter run` does, as a function that `flitter test` and
 * the REPL can call too: parse run options, then load a script, run its
 * frames and write its dumps to a stream. */
#ifndef FL_RUNNER_H
#define FL_RUNNER_H

#include <stdbool.h>
#include <stdio.h>

#include "flitter.h"

typedef struct RunSpec {
    long frames;          /* --frames N, or -1 (until interrupted) */
    double fps;           /* --fps F (default 60) */
    double model_cache;   /* --modelcache T seconds (0: the library's default) */
    bool realtime;        /* --realtime */
    bool dump_state;      /* --dump-state (implied by --dump-every) */
    long dump_every;      /* --dump-every K, or 0 */
    bool dump_tree;       /* --dump-tree */
    bool no_simplify;     /* --nosimplify / --no-simplify */
    bool dump_simplified; /* --dump-simplified: print the program as run */
    int dump_syntax;      /* --dump-tokens (1) / --dump-ast (2): print the
                             script's tokens or syntax tree and stop */
    const char *state_file; /* --state FILE, or NULL */
    long max_steps;       /* --max-steps N: physics steps per frame (0: no limit) */
    bool progress;        /* on stderr (a terminal): a progress bar when --frames is given,
                           * else a status line (frame, frames/s, clock) */
    bool stats;           /* --stats: print frame rate, allocations and the
                             eval/physics/state split to the log at exit */
    char **defines;       /* NAME=VALUE strings (borrowed from argv) */
    int ndefines;
    const char *script;   /* SCRIPT */
    int threads;          /* --threads N, or 0 (FLITTER_THREADS, else every core:
                             runspec_options_from_env) */
    size_t max_memory;    /* --max-memory SIZE in bytes, or 0 (the default budget) */
    int pairs;            /* --pairs naive|fast: FL_PAIRS_*, default FL_PAIRS_DEFAULT */
    int particles;        /* --particles literal|fast: FL_PARTICLES_*, default FL_PARTICLES_DEFAULT */
    int physics;          /* --physics documented|upstream: FL_PHYSICS_* */
    double runtime;       /* --runtime T seconds (sets frames), or -1 */
    bool runtime_clock;   /* --runtime without --frames: on a realtime clock the
                             run ends when the clock has run T seconds
                             (runspec_runtime_over), in lockstep after
                             round(T*fps) frames */
    int verbosity;        /* Flitter's log levels: --quiet -1, default 0,
                             --verbose 1, --debug 2, --trace 3 */
    const char *view;     /* --view FILE (.png/.svg/.gif), or NULL */
    long view_every;      /* --view-every K (animations), or 0 */
    int view_axes[2];     /* --view-axes A;B: fl_options.view_axes ({0, 0}: none) */
    const char *trace;    /* --trace-file FILE or --trace=FILE (.csv/.jsonl),
                             or NULL (a bare --trace is the log level) */
    long trace_every;     /* --trace-every K, or 0 */
    const char *record;   /* --record FILE: the first window to FILE, or NULL */
    /* the live window (window_main.c) */
    bool window;          /* --window, or Flitter's `flitter [options] SCRIPT...` */
    bool implicit_window; /* the window comes from Flitter's command line, not
                             --window: falling back to headless is quiet unless
                             stderr is a terminal */
    bool offscreen;       /* --offscreen: never open a window */
    bool clock_given;     /* --lockstep or --realtime was given */
    bool fullscreen;      /* --fullscreen */
    bool vsync;           /* --vsync */
    int screen;           /* --screen N, display index from 0 */
    int view_width, view_height; /* --window-size WxH: the physics view window's
                                    size (default 512x512) */
    bool reset_on_switch; /* --resetonswitch: a page left loses its state */
    double min_scale;     /* --min-scale F: the live window's least fraction of
                             pixels when it scales its pictures down to keep its
                             rate (window_scale.h; default 0.25, 1: never) */
    bool exiting;         /* the process ends after runspec_execute returns (`flitter
                             run`, not `flitter test`): the runtime is left to the
                             exit, not freed piece by piece (runner.c, left_to_exit) */
    char **scripts;       /* the SCRIPTs (pages), borrowed from argv; script is scripts[0] */
    int nscripts;
} RunSpec;

/* What runspec_parse() expects after the options. */
enum {
    RUNSPEC_NO_SCRIPT = 0,   /* nothing (`flitter test` options) */
    RUNSPEC_ONE_SCRIPT = 1,  /* `flitter run`: one SCRIPT, or pages with --window */
    RUNSPEC_PAGES = 2,       /* Flitter's `flitter [options] SCRIPT...`: a window
                                (unless --offscreen) and one or more pages */
};

/* Where a runtime's message lines go (fl_options.log). */
typedef struct RunLog {
    FILE *log;     /* errors and warnings */
    FILE *debug;   /* debug() lines */
} RunLog;

/* Parse `flitter run` options from [argv][0..argc) (argv[0] is ignored).
 * [scripts] (RUNSPEC_*) says what follows the options: nothing, exactly
 * one SCRIPT (several with --window), or one or more (pages).
 *   errors: prints a message and usage to [err] and returns 2 (usage);
 *           returns -1 after printing help for --help; 0 on success.
 *   [spec]->defines is allocated: free it with runspec_free(). */
int runspec_parse(RunSpec *spec, int argc, char **argv, int scripts, FILE *err);
void runspec_free(RunSpec *spec);

/* Whether [spec] asks for a window: --window or Flitter's command line,
 * without --offscreen, and not a run that only prints the script
 * (--dump-tokens, --dump-ast, --dump-simplified without --frames). */
bool runspec_wants_window(const RunSpec *spec);

/* A new runtime for [spec] (its fps, frames, clock, physics options, the
 * defines, [interrupt]), logging through [files] (which must outlive it).
 *   errors: NULL after printing `flitter run: bad name in define ...` to
 *           files->log for a define with a bad name. */
fl_runtime *runspec_runtime(const RunSpec *spec, RunLog *files, volatile int *interrupt);
/* The environment's FLITTER_* route switches onto [o] (the library reads
 * none itself; COMMAND-LINE.md, "Environment"): FLITTER_THREADS (a whole
 * number 1..1024), FLITTER_PAIRS=naive and FLITTER_PARTICLES=literal where
 * [o] has the defaults (an option given on the command line wins), and
 * every field of fl_debug_options from the variable its comment names
 * (flitter.h). A variable set to something else is ignored. */
void runspec_options_from_env(fl_options *o);

/* Refuse a run whose output files (--view, --trace-file, --record,
 * --state) could not be written, before anything runs (fl_check_output):
 *   errors: 2 with `flitter run: OPTION PATH cannot be written (REASON)`
 *           on [err]; 0 when every one can be. */
int runspec_check_outputs(const RunSpec *spec, FILE *err);

/* Run [spec]: load the script, evaluate frames, write state dumps and the
 * node tree to [out]; run-time messages go to [log].
 *   errors: returns 1 when the script cannot be loaded (message on [log]),
 *           when a write to [out] failed (a full disk: checked at the end),
 *           when --state could not be saved or an output (--view, a
 *           !record file...) could not be written; 2 for a bad define; 0 on
 *           success. [interrupt], when non-NULL, is polled between frames
 *           and inside evaluation loops, calls and physics steps (flitter.h)
 *           to stop early; --state is still saved and the dumps written on
 *           the way out, from the last complete frame. When *interrupt holds
 *           a signal number (1..127) and it cut short a run of known length
 *           (--frames or --runtime, or a --dump-tokens/--dump-ast), the
 *           status is 128 + that number, as a shell reports a job ended by
 *           a signal; a run without --frames ended by a signal returns as
 *           usual (that is how it is meant to end, as Flitter's run). */
int runspec_execute(const RunSpec *spec, FILE *out, FILE *log, volatile int *interrupt);

/* Wall time of a run's loads (fl_load: reading, parsing, simplifying and
 * compiling the script), for --stats. */
typedef struct LoadTimes {
    double first;       /* the load before the first frame, seconds */
    double last;        /* the last good live reload, seconds */
    long reloads;       /* good live reloads */
} LoadTimes;

/* The --stats report of [rt] on [log] ("stats: " lines: frames and
 * frames/s, eval/physics/other ms per frame, allocations, state reads and
 * writes, load milliseconds): [first] and [second] hold its statistics
 * after the first and second frames of the run (which fill the free
 * lists: the first frame's tree is still alive while the second is built,
 * and physics builds its tables), [loop] the wall time of the frame loop
 * in seconds, [load] the times of its loads (NULL: no load line). */
/* A realtime run's --runtime: true once the clock has run [elapsed]
 * seconds, T or more in frames of [fps], as Flitter's EngineController.run
 * counts: round(elapsed * fps) >= round(T * fps). */
bool runspec_runtime_over(const RunSpec *spec, double elapsed, double fps);

void runspec_print_stats(fl_runtime *rt, const fl_stats *first, const fl_stats *second,
                         double loop, const LoadTimes *load, FILE *log);

#endif
