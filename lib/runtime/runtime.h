/* runtime.h: the runtime's internal interface (runtime.c), for the
 * library's public functions (api*.c, outputs.c) and its unit tests. The
 * runtime owns its pictures (pictures.h), input (input.h) and counters
 * (counter.h), which know nothing of it; nothing it calls calls back into
 * the files that include this header.
 *
 * Embedders, src/ and python/ use flitter.h only. The functions here take and return the
 * library's internal types (Buf, Node, StateDict, SymTab, Vec, Str) and
 * follow the ownership rule of value.h; the fl_ functions of the same
 * names in flitter.h are thin wrappers over them (api.c).
 */
#ifndef FL_RUNTIME_H
#define FL_RUNTIME_H

#include <stdio.h>

#include "buf.h"
#include "graph.h"
#include "flitter.h"
#include "mem.h"
#include "node.h"
#include "state.h"
#include "value.h"

/* The Buf-based forms of fl_load, fl_load_text, fl_dump_program, fl_eval,
 * fl_state_set_expr,
 * fl_save_state and fl_restore_state: the same behaviour, with messages
 * appended to [err] (and output to [out]) instead of fl_error() and a
 * callback. */
int rt_load(fl_runtime *rt, const char *path, Buf *err);
int rt_load_text(fl_runtime *rt, const char *name, const char *text, size_t len, Buf *err);
int rt_dump_program(const fl_runtime *rt, Buf *out);
int rt_dump_syntax(fl_runtime *rt, const char *path, bool ast, Buf *out, Buf *err);
int rt_eval(fl_runtime *rt, const char *text, size_t len, Buf *out, Buf *err);
int rt_state_set_expr(fl_runtime *rt, const char *key_expr, const char *value_expr, Buf *out,
                      Buf *err);
int rt_save_state(const fl_runtime *rt, const char *path, Buf *err);
int rt_restore_state(fl_runtime *rt, const char *path, Buf *err);

/* Names visible to rt_eval (script top level, frame names, defines, earlier
 * rt_eval bindings), for completion; borrowed until the next call, [*n]
 * entries. */
const Str *const *rt_scope_names(const fl_runtime *rt, size_t *n);

/* The node tree of the last evaluated frame (a !root node), or NULL;
 * borrowed until the next fl_step. */
const Node *rt_root(const fl_runtime *rt);
/* The render graph and view (pictures.h) and the held keys (input.h),
 * owned by the runtime, for api_windows.c and outputs.c. */
struct Pictures *rt_pictures(fl_runtime *rt);
struct Input *rt_input(fl_runtime *rt);
/* The beat of the last evaluated frame (0 before the first). */
double rt_beat(const fl_runtime *rt);
/* The value of engine name or define [name] ([len] bytes: `beat`,
 * `delta`, `time`, ... of the last frame, LANGUAGE.md §6.2; borrowed), or
 * NULL when there is none. */
const Vec *rt_global(const fl_runtime *rt, const char *name, size_t len);
/* Distances of an SDF's `function=` [fn] (Flitter docs/canvas3d.md,
 * "Signed Distance Fields") at [n] points (xyz: 3n doubles): each called
 * with the point as one 3-vector, as Flitter's renderer calls it, with
 * the engine names and defines of the last frame and an empty state; a
 * result that is not one number gives NaN. Run-time errors are logged
 * once each per runtime.
 *   errors: false when interrupted (the rest of out unset). */
bool rt_call_distances(fl_runtime *rt, const Vec *fn, const double *xyz, size_t n, double *out);
/* Draw the last frame through the runtime's pictures (pictures_render,
 * with the frame's engine names; nothing before the first frame, nor with
 * fl_debug_options.no_draw unless [windows] asks for them); returns
 * the number of record files that could not be written this frame. */
int rt_render(fl_runtime *rt, bool windows);
/* The values of the frame the last frame's pictures are drawn with
 * (rt_render's; its name lookup NULL). */
void rt_graph_frame(const fl_runtime *rt, GraphFrame *f);
/* A new reference to the last frame's tree (NULL before the first), for a
 * drawing thread (api_drawing.c): hold it while that thread reads it,
 * and give it back with rt_release_held on the runtime's thread. */
Node *rt_hold_root(fl_runtime *rt);
/* Whether fl_debug_options.no_draw is set (no pictures for files). */
bool rt_no_draw(const fl_runtime *rt);
/* The engine names and defines of the last frame, held: [*names] and
 * [*values] (new arrays of new references, malloc'd) of the returned
 * count, for a drawing thread's lookups; given back with rt_release_held. */
uint32_t rt_hold_globals(const fl_runtime *rt, Str ***names, Vec ***values);
/* Give back what rt_hold_root and rt_hold_globals held (any may be
 * NULL/0), on the runtime's thread, inside its budget and pool as a
 * frame releases its tree; frees the two arrays. */
void rt_release_held(fl_runtime *rt, Node *root, uint32_t n, Str **names, Vec **values);
/* The runtime's memory budget (fl_options.max_memory), for what it holds
 * across calls (the render graph's framebuffers). */
MemBudget *rt_budget(fl_runtime *rt);
/* The loaded script's path, or NULL. */
const char *rt_script_path(const fl_runtime *rt);
/* Whether the runtime runs on the wall clock (fl_options.realtime). */
bool rt_realtime(const fl_runtime *rt);
/* The state dictionary (mutable: controller values may be written). */
StateDict *rt_state(fl_runtime *rt);
/* The symbol table used for value text. */
const SymTab *rt_symbols(const fl_runtime *rt);
/* How many loop iterations the frames so far ran with their loop's
 * kernel (kernel.h): the tests' evidence that the kernel route ran. */
uint64_t rt_kernel_iterations(const fl_runtime *rt);
/* How many nodes the frames so far refilled in place instead of building
 * them (kernel.h KNodeCache): the tests' evidence that nodes were reused. */
uint64_t rt_kernel_reused(const fl_runtime *rt);
/* How many loop iterations the frames so far ran as a straight body's
 * nodes (kernel.c, straight_iteration) instead of its records one by one:
 * the tests' evidence that that route ran. */
uint64_t rt_kernel_straight(const fl_runtime *rt);
/* The options [rt] was made with (fl_new's copy, log defaulted). */
const fl_options *rt_options(const fl_runtime *rt);

/* The vector that value text [text] stands for (flitter.h, top: the `-D`
 * syntax of FORMATS.md §4, plus `-NUMBER` parts as negative numbers), new;
 * NULL for the empty text. Symbols are added to [rt]'s symbol table. */
Vec *rt_parse_value(fl_runtime *rt, const char *text);

/* The runtime's fl_error() text, to be filled by a failing call. */
Buf *rt_error_buf(fl_runtime *rt);
/* Replace [rt]'s fl_error() text with one formatted line (the newline is
 * added; at most 1023 bytes): a public call refusing an argument. Returns
 * -1, the usual error value. */
int rt_fail(fl_runtime *rt, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* Make this thread's allocation-failure handler (mem.h) [rt]'s error
 * callback (fl_options.error); returns the previous handler, for
 * mem_leave(). Every public call that allocates does this. */
MemHandler rt_enter(const fl_runtime *rt);

/* The runtime's log callback and its context (never NULL: the default
 * writes to stderr/stdout), for modules that log on its behalf. */
void rt_log_target(const fl_runtime *rt, fl_log_fn *fn, void **ctx);

/* Where the default log callback of rt_log_to_files writes. */
typedef struct RtStreams {
    FILE *log;     /* errors and warnings; NULL: nowhere */
    FILE *debug;   /* debug() lines; NULL: nowhere */
} RtStreams;
/* Set [o]'s log callback to write each line, with a newline, to [s]'s
 * files ([s] must outlive the runtime). */
void rt_log_to_files(fl_options *o, RtStreams *s);

#endif
