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
} fl_options;

/* The defaults: 60 fps, unknown frames, lockstep, log to stderr, debug to stdout. */
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

/* Evaluate and simulate one frame: compute the frame names (FORMATS.md §5),
 * evaluate the program into a node tree, run every top-level !physics node,
 * write the beat counter, then advance the clock.
 *   errors: new run-time errors of this frame are written to the log as
 *           `Execution error: MESSAGE`; returns -1 when no program is
 *           loaded, else 0. */
int fl_step(fl_runtime *rt);

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
