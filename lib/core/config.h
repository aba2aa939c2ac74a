/* config.h: every size, depth and work limit of libflitter, in one place.
 *
 * Flitter itself has none of these (it runs until memory or the Python stack
 * runs out); each one turns a hostile or runaway script into an error with a
 * message instead of a crash, a hang or unbounded memory. Past a run-time
 * limit the operation gives null with an `Execution error:` (LANGUAGE.md
 * §4.16); past a load-time limit the script is refused or left unsimplified
 * with a warning, as each comment says.
 */
#ifndef FL_CONFIG_H
#define FL_CONFIG_H

#include <stddef.h>
#include <stdint.h>

/* {====================================================================
 * Syntax
 * ===================================================================== */

/* The deepest AST a parse may produce: a tree with a node more than this
 * many levels below its root (left- or right-nested operators, calls,
 * indexing, blocks, statement chains) is refused with a syntax-style error,
 * so that no later pass (resolve, simplify, evaluate, dump) recurses deeper.
 * Kept below what bison's own stack limit lets through (about 5000 nested
 * parentheses) and small enough for the recursive passes to fit an 8 MiB
 * stack under ASan. */
#define AST_MAX_DEPTH 4000

/* The loader's peak memory per byte of source (tokens, the syntax tree,
 * its names, the simplified and compiled copies), with a margin: measured
 * (peak RSS of `flitter run --frames 1`) at 126-128 bytes per byte with
 * the simplifier and 144 without on 2.6 and 13 MB scripts of node lines,
 * 58 on 6 MB of `let` lines. A script whose size times this does not fit
 * the memory budget (mem.h) is refused at load with `PATH:1:1: error:
 * out of memory` instead of aborting half-way through parsing. */
#define PARSE_BYTES_PER_BYTE ((size_t)160)

/* }==================================================================== */

/* {====================================================================
 * Memory budget
 * ===================================================================== */

/* The budget itself is a run-time setting, not a limit here:
 * fl_options.max_memory (`--max-memory SIZE`), by default half of physical
 * memory and at most half of RLIMIT_AS (mem.h mem_default_limit). Past it
 * an expression gives null with an execution error, a load fails with
 * `out of memory`, a state file is refused, a !physics system is skipped
 * with a physics error. */

/* }==================================================================== */

/* {====================================================================
 * Simplifier (load time)
 * ===================================================================== */

/* Longest range folded at load time (longer ones are left to the evaluator,
 * which reports them). */
#define SIMP_MAX_RANGE (UINT64_C(1) << 26)
/* Nesting limit of simp(), guarding the C stack: a program nested deeper
 * is left unsimplified (with a warning). */
#define SIMP_MAX_DEPTH 10000
/* Depth limit of function inlining (tree.pyx MAX_INLINE_DEPTH). */
#define SIMP_MAX_INLINE_DEPTH 20
/* Most loop-body copies one simplification may make by unrolling loops over
 * literal sources (2^20). Flitter has no such limit; it bounds the load-time
 * work and memory of hostile scripts (`for i in 0..2**26`). A loop that would
 * go past it is kept as a loop, evaluated every frame, with one warning. */
#define SIMP_MAX_UNROLL (1u << 20)

/* }==================================================================== */

/* {====================================================================
 * Evaluator (run time)
 * ===================================================================== */

/* Recursion limit per function value (§4.8). */
#define MAX_ACTIVE_CALLS 500
/* Nesting limit of eval_expr, guarding the C stack (§4.16 stack overflow). */
#define MAX_EVAL_DEPTH 12000
/* Deepest eval_expr nesting at which an import may load a module (whose
 * evaluation then continues from that depth, up to MAX_EVAL_DEPTH). */
#define MAX_IMPORT_DEPTH (MAX_EVAL_DEPTH / 2)
/* Longest vector a range may build (bounded memory for `..1e12`). */
#define MAX_RANGE_LEN (UINT64_C(1) << 26)
/* Longest vector a composition (sequence, loop, multi-function call) may
 * build: past it the result is null with an execution error (§4.16) rather
 * than an abort or unbounded memory. */
#define MAX_COMPOSE_LEN (UINT64_C(1) << 26)

/* }==================================================================== */

/* {====================================================================
 * Built-in functions
 * ===================================================================== */

/* Largest result (elements) a numeric built-in builds; beyond it: an
 * execution error and null (the reference would exhaust memory). */
#define MAX_RESULT ((uint64_t)1 << 28)
/* Most octaves the noise functions accept; beyond: error, null. */
#define MAX_OCTAVES 65536
/* Longest string (bytes) chr() and concat() build; beyond it: an execution
 * error and null (LANGUAGE.md §4.16) instead of an abort in str_new(). The
 * same bound as a file read by `read` (FILE_READ_MAX). */
#define MAX_STRING ((size_t)1 << 28)
/* The largest file file_read() accepts, in bytes (256 MiB): scripts,
 * modules, state files and files read by `read`/`csv` beyond this are
 * refused rather than exhausting memory. */
#define FILE_READ_MAX ((size_t)256 << 20)

/* }==================================================================== */

/* {====================================================================
 * State and physics
 * ===================================================================== */

/* Largest frame number a state file may hold (2^53: every frame count up
 * to it is exact as the double `frame` name, and the counter cannot
 * overflow a long). */
#define MAX_FRAME (INT64_C(1) << 53)
/* Largest accepted `dimensions` of a !physics system (larger systems are
 * skipped). */
#define PHYS_MAX_DIMENSIONS (1u << 20)

/* }==================================================================== */

#endif
