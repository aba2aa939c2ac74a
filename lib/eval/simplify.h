/* simplify.h: Flitter's load-time simplifier (LANGUAGE.md §4.17).
 *
 * The simplifier is a partial evaluation of a parsed (not yet resolved)
 * program, run between parsing and name resolution unless the user asks for
 * `--nosimplify`. Names whose values are known at load time (defines and the
 * static engine names such as `realtime` and `run_time`, let-bound literals,
 * loop variables over literal sources, builtin constants and functions) are
 * replaced by literals; literal operations and builtin calls are folded;
 * loops over literal sources are unrolled; branches with literal conditions
 * are selected; functions that capture nothing are inlined; unused bindings
 * are dropped; `%include` with a literal path is spliced in; and the algebraic
 * rewrites S2-S18 are applied bottom-up, each rewritten expression being
 * simplified again. Where the spec is silent the rules follow the reference
 * implementation's `simplify` methods (jonathanhogg/flitter,
 * src/flitter/language/tree.pyx).
 */
#ifndef FL_SIMPLIFY_H
#define FL_SIMPLIFY_H

#include <stdbool.h>

#include "ast.h"
#include "buf.h"
#include "value.h"

/* A name the simplifier knows before the program runs. */
typedef struct SimplifyName {
    const Str *name;   /* borrowed */
    bool dynamic;      /* true: changes per frame (time, beat, ...) */
    const Vec *value;  /* static value (borrowed; NULL is null) */
} SimplifyName;

/* What the simplifier needs to know about the program's surroundings. */
typedef struct SimplifyEnv {
    const SimplifyName *names;  /* engine names and defines */
    uint32_t nnames;
    SymTab *symtab;             /* symbols of included files are added here */
    const char *dir;            /* directory of the main file, for %include */
    uint32_t first_file;        /* source index given to the first included file */
    uint32_t *stable_ids;       /* last `let stable` id given out (stable.h): each
                                   AST_LET with op 1 and count 0 is numbered */
    const struct StableCache *stables;  /* values of stable keys, bound as
                                   literals in their `let stable` bodies; NULL:
                                   none (the first simplification) */
    bool is_module;             /* an imported module: every top-level name is
                                   exported, so no top-level binding is unused */
    struct PathList *files;     /* files read (%include, literal imports) are
                                   added here (program.h; NULL: nowhere) */
    volatile int *interrupt;    /* the embedder's flag (NULL: none): once set,
                                   simplification stops and the program is
                                   returned as written (the caller fails the
                                   load) */
    bool no_templates;          /* fl_debug_options.no_templates */
    bool check_templates;       /* fl_debug_options.check_templates */
} SimplifyEnv;

/* Simplify the program [top] (an AST_TOP from parse_program; consumes it) and
 * return the simplified AST_TOP (never NULL).
 *   errors: load-time messages (`Unbound name 'x'`, errors of builtin calls
 *           folded at load time, repeated includes) are appended to
 *           [warnings], one per line; an included file that cannot be read
 *           or parsed is left as an AST_INCLUDE for the resolver to report.
 *   source: LANGUAGE.md §4.17; tree.pyx `_simplify` methods */
AstNode *simplify_program(AstNode *top, const SimplifyEnv *env, Buf *warnings);

/* A deep copy of the unresolved tree [n] (kinds, operators, names, values,
 * children; not the resolver's slots and data). NULL gives NULL. */
AstNode *ast_copy(const AstNode *n);

/* Give every `let stable` (AST_LET with op 1) of [n] that has no id yet
 * (count 0) the next id from [*last]. */
void simplify_number_stables(AstNode *n, uint32_t *last);

/* Append the program or expression [n] to [out] as Flitter-like source:
 * statements one per line, indented four spaces per block; expressions
 * inline with every operation parenthesised; literals as value text
 * (FORMATS.md §1, symbols named with [st]), literal nodes with their tags,
 * attributes and children. For reading (`flitter run --dump-simplified`);
 * the text need not parse. */
void ast_dump(Buf *out, const AstNode *n, const SymTab *st);

#endif
