/* flitter.h: the public interface of libflitter.
 *
 * A `fl_runtime` is one interpreter: a loaded program, its state dictionary,
 * its physics systems, its symbol table and its clock. Nothing is global, so
 * an embedder may run several runtimes in one process (one thread each).
 *
 * Typical use:
 *     fl_options o = fl_default_options();  o.frames = 300;
 *     fl_runtime *rt = fl_new(&o);
 *     if (fl_load(rt, "petri.fl", &err) != 0) { print err; }
 *     while (fl_frame_count(rt) < 300) fl_step(rt);
 *     fl_free(rt);
 *
 * Ownership follows value.h: getters return borrowed pointers that stay valid
 * until the next call that changes the runtime.
 */
#ifndef FLITTER_H
#define FLITTER_H

#include <stdbool.h>
#include <stdio.h>

#include "buf.h"
#include "node.h"
#include "state.h"
#include "value.h"

typedef struct fl_runtime fl_runtime;

typedef struct fl_options {
    double fps;          /* target frame rate (--fps), frames per second; default 60 */
    long frames;         /* planned frame count for `run_time`, or -1 (unknown) */
    bool realtime;       /* pace on the wall clock instead of lockstep */
    FILE *log;           /* where run-time errors and warnings go (stderr); NULL: nowhere */
    FILE *debug;         /* where debug() lines go (stdout); NULL: nowhere */
    long max_physics_steps; /* most simulation steps one !physics system may
                               take in one frame (default 10000; 0: no limit);
                               past it the simulation clock falls behind
                               `time` (logged once per runtime) */
    volatile int *interrupt; /* polled inside loops, calls and physics steps;
                                when *interrupt becomes non-zero fl_step ends
                                the frame early and discards it (NULL: none) */
    int threads;         /* physics threads (--threads); 0: FLITTER_THREADS, else every core */
    int pairs;           /* physics pair route (--pairs): FL_PAIRS_* */
    bool no_simplify;    /* --nosimplify: run the program as parsed, without the
                            load-time simplifier (LANGUAGE.md §4.17) */
} fl_options;

/* fl_options.pairs: the physics pair loop. Every route gives the same bits. */
enum {
    FL_PAIRS_DEFAULT = 0,  /* FLITTER_PAIRS=naive selects naive, else fast */
    FL_PAIRS_FAST,         /* neighbour grid and threads where they apply */
    FL_PAIRS_NAIVE         /* the reference all-pairs loop, one thread */
};

/* Parse a --pairs value ("naive" or "fast") into *[out] (FL_PAIRS_*);
 * returns false, leaving *[out] alone, for anything else. */
bool fl_parse_pairs(const char *text, int *out);

/* The defaults: 60 fps, unknown frames, lockstep, log to stderr, debug to
 * stdout, 10000 physics steps per frame, no interrupt flag. */
fl_options fl_default_options(void);

/* A new runtime with empty state and no program.
 *   errors: aborts only when out of memory. */
fl_runtime *fl_new(const fl_options *opts);
/* Free [rt] and everything it owns (NULL is a no-op). */
void fl_free(fl_runtime *rt);

/* Bind [name] to [value_text] for every frame (-D NAME=VALUE, FORMATS.md
 * §4): the text is split on `;`; each part is a `:symbol`, a number with
 * optional `_` separators and SI/angle suffix (LANGUAGE.md §1.3), a time
 * code, or else a string; empty text is null. Must be called before fl_load.
 *   errors: returns -1 for an empty or invalid name, else 0. */
int fl_define(fl_runtime *rt, const char *name, const char *value_text);

/* Load (or reload, keeping the state) the script at [path]. Pragmas take
 * effect at the next fl_step (LANGUAGE.md §6.4).
 *   errors: returns -1 and appends `PATH:LINE:COL: error: MESSAGE` (with the
 *           source line and a caret) to [err]; the previous program, if
 *           any, stays loaded. Load-time warnings (unbound names) go to the
 *           log. */
int fl_load(fl_runtime *rt, const char *path, Buf *err);
/* Load program text from memory; [name] is used in messages and to
 * resolve relative files. Same errors as fl_load. */
int fl_load_text(fl_runtime *rt, const char *name, const char *text, size_t len, Buf *err);

/* Append the loaded program, as it will run (after the simplifier unless
 * no_simplify), to [out] as Flitter-like source (simplify.h ast_dump).
 *   errors: returns -1 when no program is loaded, else 0. */
int fl_dump_program(const fl_runtime *rt, Buf *out);

/* Evaluate and simulate one frame: compute the frame names (FORMATS.md §5),
 * evaluate the program into a node tree, run every top-level !physics node,
 * write the beat counter, then advance the clock.
 *   errors: new run-time errors of this frame are written to the log as
 *           `Execution error: MESSAGE`; a !physics system with a non-finite
 *           `time`/`resolution` skips the frame and one needing more than
 *           opts.max_physics_steps steps is cut short (each logged once per
 *           runtime); returns -1 when no program is loaded, 1 when
 *           *opts.interrupt stopped the evaluation (the frame is discarded:
 *           tree, state, clock and frame count stay as they were; an
 *           interrupt during physics steps keeps the frame, with fewer
 *           steps), else 0. */
int fl_step(fl_runtime *rt);

/* Evaluate [text] ([len] bytes: an expression, or `let` bindings) in the
 * scope of the loaded script's top level as of the last frame (its `let`
 * and `func` names, the frame names, defines) plus the names bound by
 * earlier fl_eval calls; state lookups see the current state.
 *   output: the value text (FORMATS.md §1) of an expression's result, or
 *           `NAME = VALUE` lines for the names a `let` bound, appended to
 *           [out] with a final newline.
 *   errors: returns -1 with `<repl>:LINE:COL: error: ...` in [err] on a
 *           syntax error; returns 1 (and appends nothing) when the text
 *           ended early, so a caller may read more lines; run-time errors
 *           go to the log; returns -1 with `<repl>: error: interrupted`
 *           (nothing bound or printed) when *opts.interrupt stopped the
 *           evaluation; 0 on success. */
int fl_eval(fl_runtime *rt, const char *text, size_t len, Buf *out, Buf *err);
/* Forget the names bound by fl_eval. */
void fl_eval_reset(fl_runtime *rt);
/* Names visible to fl_eval (script top level, frame names, defines, earlier
 * fl_eval bindings), for completion; borrowed, [*n] entries. */
const Str *const *fl_scope_names(const fl_runtime *rt, size_t *n);

/* Save the state dictionary and the clock to [path] atomically (see
 * statefile.h for the format).
 *   errors: returns -1 with a message in [err]; 0 on success. */
int fl_save_state(const fl_runtime *rt, const char *path, Buf *err);
/* Restore the state dictionary and the clock from [path], so that the run
 * continues exactly where the saved one stopped.
 *   errors: returns -1 with a message in [err], leaving everything
 *           untouched, when the file is missing, truncated or malformed. */
int fl_restore_state(fl_runtime *rt, const char *path, Buf *err);
/* Empty the state dictionary (the clock keeps running). */
void fl_reset_state(fl_runtime *rt);

/* Counters and timers of a runtime since fl_new (fl_get_stats). */
typedef struct fl_stats {
    long frames;              /* frames stepped */
    unsigned long long mallocs, frees;           /* malloc/free calls made for
                                                    pooled values, in total */
    unsigned long long last_mallocs, last_frees; /* the same during the last frame */
    unsigned long long state_gets, state_sets;   /* state dictionary reads and writes */
    double eval_seconds;      /* evaluating the program into a tree (and
                                 releasing the previous frame's tree) */
    double physics_seconds;   /* the physics engine, its state reads/writes included */
    double other_seconds;     /* the rest of fl_step: frame names, pragmas,
                                 messages, beat counter */
} fl_stats;

/* Fill [out] with [rt]'s statistics (wall-clock seconds, monotonic clock).
 * Allocation counts cover the values the runtime pools (vectors, strings,
 * nodes and their arrays, evaluator scratch): a steady frame makes none. */
void fl_get_stats(const fl_runtime *rt, fl_stats *out);

/* The node tree of the last evaluated frame (a !root node), or NULL. */
const Node *fl_root(const fl_runtime *rt);
/* The state dictionary (mutable: embedders may write controller values). */
StateDict *fl_state(fl_runtime *rt);
/* The symbol table used for value text. */
const SymTab *fl_symbols(const fl_runtime *rt);
/* Number of frames evaluated so far. */
long fl_frame_count(const fl_runtime *rt);
/* The `time` of the last evaluated frame (seconds). */
double fl_frame_time(const fl_runtime *rt);

#endif
