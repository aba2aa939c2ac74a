/* program.h: a loaded program, its resolved names, closures, and the
 * evaluator entry points (internal to libflitter).
 *
 * Loading (program.c) parses a file, registers its symbols, reads its
 * pragmas and resolves every name statically (LANGUAGE.md §4.2): each name
 * use becomes a frame slot, an engine/define name, a builtin constant, or
 * unbound. A function body gets its own frame of slots laid out as
 *   [0] the function itself (for recursion), [1..P] parameters,
 *   [P+1..P+C] captured values (copied at definition time), then locals.
 * Every binding gets its own slot, so later shadowing never disturbs a value
 * that a closure captured.
 */
#ifndef FL_PROGRAM_H
#define FL_PROGRAM_H

#include <stdbool.h>

#include "ast.h"
#include "buf.h"
#include "kernel.h"
#include "context.h"
#include "node.h"
#include "state.h"
#include "value.h"

/* Where a name lives (AstNode.scope). */
enum { SCOPE_NONE, SCOPE_LOCAL, SCOPE_GLOBAL, SCOPE_CONST, SCOPE_UNBOUND };

/* The routes a program is loaded for (fl_debug_options; all zero, and a
 * NULL Globals: the defaults), passed on to the modules it imports. */
typedef struct LoadRoutes {
    bool no_fast;       /* no compiled routes: the tree-walking evaluator alone */
    bool no_templates, check_templates;  /* the simplifier's (SimplifyEnv) */
    KernelOptions kernel;                /* the loop kernels' (kernel.h) */
} LoadRoutes;

/* The engine names and --define names a program may read (LANGUAGE.md §6.2).
 * The runtime owns the values; the evaluator reads values[index]. */
typedef struct Globals {
    Str **names;        /* name per index */
    Vec **values;       /* current value per index (owned) */
    uint32_t count, cap;
    bool simplify;      /* run the simplifier on programs loaded against these
                           names (simplify.h) */
    uint32_t ndynamic;  /* names [0, ndynamic) change per frame; the others
                           (static engine names, defines) are known at load */
    bool module;        /* programs loaded against these are imported modules
                           (their top-level names are all exported) */
    volatile int *interrupt; /* the embedder's flag (NULL: none): the load-time
                           simplifier stops once it is set, and the load
                           fails with `PATH: error: interrupted while loading` */
    LoadRoutes routes;  /* the routes programs loaded against these take */
} Globals;

/* Index of [name] in [g], or -1. */
int globals_find(const Globals *g, const char *name, size_t len);
/* Index of [name], added (with value null) when missing. */
int globals_add(Globals *g, const char *name);
/* Set global [index] to [value] (retained). */
void globals_set(Globals *g, int index, Vec *value);
void globals_free(Globals *g);

/* Resolver data hung on an AST_FUNCTION (AstNode.aux). */
typedef struct FnInfo {
    uint32_t nslots;      /* frame size */
    uint32_t nparams;     /* parameters, slots 1..nparams */
    uint32_t ncaps;       /* captures, slots nparams+1.. */
    int32_t *cap_src;     /* slot in the defining frame of each capture */
} FnInfo;

typedef struct Program Program;

/* File paths, each once, in the order first met (the files a program was
 * read from: Program.files, fl_program_files). */
typedef struct PathList {
    char **paths;
    uint32_t count, cap;
} PathList;

/* Append a copy of [path] to [l] unless it is there already. */
void pathlist_add(PathList *l, const char *path);
/* Append every path of [from] to [l] (pathlist_add). */
void pathlist_add_all(PathList *l, const PathList *from);
/* Free every path and empty [l]. */
void pathlist_clear(PathList *l);

/* A pragma `%pragma NAME VALUE` of the main file. */
typedef struct Pragma {
    Str *name;
    Vec *value;
} Pragma;

struct Program {
    uint32_t refs;         /* closures keep their program alive */
    AstNode *top;          /* AST_TOP */
    char *path;            /* the script's path */
    char *dir;             /* its directory */
    uint32_t nslots;       /* top-level frame size */
    Pragma *pragmas;
    uint32_t npragmas;
    Buf warnings;          /* load-time warnings, one per line */
    AstNode *simplified;   /* unresolved copy of the simplified tree, for
                              simplifying again (NULL without the simplifier,
                              or without `let stable` bindings) */
    uint32_t stable_ids;   /* `let stable` ids given out (stable.h) */
    uint32_t *asserted;    /* stable keys (id, index pairs) whose values this
                              program was simplified with */
    uint32_t nasserted;
    PathList files;        /* the files it was read from: [0] the script, then
                              every %include'd file and every module a
                              literal `import` names that the simplifier read */
};

/* Load, parse and resolve the script at [path] against [globals] (engine
 * and define names; NULL for a module, which sees none) and register its
 * symbols in [st].
 *   errors: returns NULL and appends `PATH:LINE:COL: error: ...` to [err]
 *           on a syntax error, or `PATH: error: cannot read: REASON` when
 *           the file cannot be read. Unbound names are warnings
 *           (`Unbound name 'N'`) kept in program->warnings.
 * With globals->simplify the parsed program is simplified (simplify.h)
 * before its names are resolved; the simplifier's messages are warnings. */
Program *program_load(const char *path, Globals *globals, SymTab *st, Buf *err);
/* Read the script file [path] into [text] (the caller frees it); returns
 * its bytes ([text]'s data, or "" for an empty file).
 *   errors: returns NULL with `PATH: error: cannot read: REASON` in [err]. */
const char *program_read(const char *path, Buf *text, Buf *err);
/* Add the symbol names a parsed program uses (AST_TOP's `c`) to [st], so
 * value text names them (`:dish`). */
void program_register_symbols(const AstNode *top, SymTab *st);
/* The same from text in memory ([path] names it in messages). */
Program *program_load_text(const char *path, const char *text, size_t len,
                           Globals *globals, SymTab *st, Buf *err);
void program_release(Program *p);

struct StableCache;
/* The program [cur] (loaded with the simplifier) simplified again from its
 * simplified tree with the values of the stable keys of [sc] known, and
 * asserting them (stable.h); NULL when [cur] was not simplified. */
Program *program_resimplify(const Program *cur, Globals *globals, SymTab *st,
                            const struct StableCache *sc);

/* A set of message strings (per-frame errors and debug lines). */
typedef struct MsgSet {
    char **items;
    uint32_t count, cap;
} MsgSet;

bool msgset_add(MsgSet *s, const char *msg);   /* false when present */
bool msgset_has(const MsgSet *s, const char *msg);
void msgset_clear(MsgSet *s);

/* The values a module exports: every name bound at its top level when
 * evaluation reaches the end of the file (LANGUAGE.md §4.13). */
typedef struct Exports {
    Str **names;
    Vec **values;
    uint32_t count, cap;
} Exports;

/* Resolver data hung on an AST_EXPORT (AstNode.aux): the top-level names
 * visible at the end of the file and their slots. */
typedef struct ExportInfo {
    uint32_t count;
    const Str **names;   /* borrowed from the AST */
    int32_t *slots;
} ExportInfo;

struct ModuleCache;

/* The evaluator's context for one frame of one program. */
struct Eval {
    Program *prog;          /* program being evaluated */
    const Globals *globals; /* engine and define names */
    StateDict *state;       /* state for $ lookups (NULL: empty state) */
    const SymTab *symtab;   /* symbol names for str/repr */
    MsgSet *errors;         /* this frame's run-time errors */
    MsgSet *debug;          /* this frame's debug lines */
    Vec **frame;            /* slots of the current function frame */
    uint32_t depth;         /* C recursion depth guard */
    bool overflow;          /* the stack limit was hit this frame */
    struct ModuleCache *modules; /* imported modules (NULL: imports fail) */
    Exports *exports;       /* when running a module: where EOF exports go */
    volatile int *interrupt; /* polled by loops and calls (NULL: none) */
    bool interrupted;       /* *interrupt was seen: results are incomplete */
    struct StableCache *stables; /* `let stable` values (NULL: not tracked) */
    bool stable_changed;    /* an asserted stable value changed: the frame
                               must be evaluated again (stable.h) */
    struct CMemo *memos;    /* memo cells of the compiled region being run
                               (evalcode.h) */
    PathList *files;        /* where the files of modules imported while
                               running are recorded (NULL: nowhere) */
    struct NoisePerms *noise_perms; /* the runtime's noise tables (builtins.h;
                                       NULL: none kept) */
    struct FileMemo *file_memo; /* the runtime's files read (builtins.h;
                                   NULL: none kept) */
    struct Workers *workers; /* threads the runtime lends to loop kernels
                                (kernel.h; NULL: the caller alone) */
    struct KernelScratch *kscratch; /* the runtime's scratch for their
                                       registers (kernel.h; NULL: the pool) */
    const unsigned char *kbase; /* the code of the loop body whose kernel is
                                   running (kernel.h: its C_KNUM records take
                                   their numbers from kregs), or NULL */
    const double *kregs;    /* that kernel's registers of this iteration */
    const uint8_t *kok;     /* which of them hold their number */
    bool kclean;            /* all of them do */
    struct Vec **kmemo;     /* per memo cell of that body: the value its
                               C_MEMO records gave in this run of the loop
                               (NULL: none yet) */
    uint64_t kiters;        /* iterations run with their loop's kernel */
    struct KNodeCache *kcache; /* that run's nodes of an earlier run, for
                                  its C_KNODE records to refill (kernel.h;
                                  NULL: none) */
    uint64_t kreused;       /* nodes refilled from it */
    uint64_t kstraight;     /* iterations run as a straight body (kernel.c) */
};

/* Evaluate the whole program: compose the top-level sequence and append
 * every node element to a fresh !root node (LANGUAGE.md §4.1).
 *   errors: run-time errors go to ev->errors; never fails. */
Node *eval_program(Eval *ev);
/* Evaluate the whole program and return the composed value of its top-level
 * sequence (null after a stack overflow). */
Vec *eval_program_value(Eval *ev);
/* Release every name and value in [x] and empty it. */
void exports_clear(Exports *x);
/* Release every name and value in [x] but keep its arrays for reuse. */
void exports_empty(Exports *x);
/* Evaluate one expression in the current frame (new reference). */
Vec *eval_expr(Eval *ev, const AstNode *n);
/* Call value [fn] with the [nargs] positional values [args] as a call
 * expression does (LANGUAGE.md §4.8: every function of it called, the
 * results composed; anything else null with an error), from outside any
 * frame: an SDF's `function=` called by the renderer. A new reference.
 *   errors: run-time errors go to ev->errors; never fails. */
Vec *eval_call_value(Eval *ev, const Vec *fn, Vec **args, uint32_t nargs);
/* A key of function value [fn] that is the same for two values exactly
 * when they compute the same: a user function by its definition's place
 * in its program, its defaults and its captured values; a builtin by
 * itself; anything else by its hash (for caches of what a function made,
 * frame after frame, when each frame makes the closure anew). */
uint64_t eval_function_key(const Vec *fn);

#endif
