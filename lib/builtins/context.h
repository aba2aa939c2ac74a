/* context.h: the evaluator's services for built-in functions.
 *
 * An `Eval` is the context of one frame's evaluation of one program. Built-ins
 * use it to report run-time errors (LANGUAGE.md §4.16), to emit debug text,
 * to name symbols, and to find files relative to the running script.
 */
#ifndef FL_CONTEXT_H
#define FL_CONTEXT_H

#include "value.h"

typedef struct Eval Eval;

/* Record run-time error text [msg] for this frame (deduplicated per frame). */
void eval_error(Eval *ev, const char *msg);
/* Record debug text [msg] for this frame (printed when new). */
void eval_debug(Eval *ev, const char *msg);
/* The runtime's symbol table (for str and repr). */
const SymTab *eval_symtab(const Eval *ev);
/* True once the embedder's interrupt flag (fl_options.interrupt) is set:
 * a built-in whose work the input sizes (a noise grid, a glob walk) asks
 * now and then and gives up, returning null; the evaluation then stops and
 * the frame is discarded (flitter.h, fl_step). False for a NULL [ev]. */
bool eval_interrupted(Eval *ev);
/* Directory of the script being evaluated ("." when unknown), for read(),
 * csv() and friends. */
const char *eval_script_dir(const Eval *ev);
/* The runtime's memo of noise permutation tables (builtins.h), or NULL
 * when this evaluation has none (load-time folding): noise() then builds
 * each table it needs. */
struct NoisePerms *eval_noise_perms(Eval *ev);
/* The runtime's memo of the files the file built-ins read (builtins.h),
 * or NULL when this evaluation has none: they then read every file
 * afresh. */
struct FileMemo *eval_file_memo(Eval *ev);

#endif
