/* simplify_internal.h: what the simplifier's modules share (simplify.c:
 * expressions and operators; simplify_scope.c: names, bindings, loops,
 * functions, calls and files). Internal to libflitter. */
#ifndef FL_SIMPLIFY_INTERNAL_H
#define FL_SIMPLIFY_INTERNAL_H

#include "config.h"
#include "program.h"
#include "simplify.h"

/* One value per member of a template pass's group (simplify_template.c):
 * the values a literal takes in each of the loop iterations simplified
 * together. Reference-counted: copies of a literal share it, as they share
 * their value. */
typedef struct Column {
    uint32_t refs;
    uint32_t n;            /* members */
    double *num;           /* a numeric column (col_new_num): every member
                              is one number, num[m], and v[m] is that
                              number's vector once col_get has made it;
                              NULL: another kind (col_plain: a column of
                              v[]) */
    Vec **v;               /* one reference each (NULL: null); read them
                              with col_get, which makes a numeric, flat,
                              stream or node column's on demand (its v
                              itself NULL until then); col_all makes them
                              all */
    double *flat;          /* a flat column (col_new_flat): every member
                              is a vector of w >= 2 numbers,
                              flat[m*w .. m*w+w) */
    size_t charged;        /* bytes of flat[] charged to the memory
                              budget (mem.h), given back on release */
    uint32_t w;            /* flat: numbers a member */
    uint8_t stream;        /* keys: the members' StreamKind */
    uint64_t *key;         /* a stream column (col_new_keys): every member
                              is the stream of kind [stream] and seed key
                              key[m], as vec_stream makes it */
    Node **node;           /* a node column (col_new_nodes): every member
                              is the vector of the one node node[m] (one
                              reference each) */
} Column;

/* What a name stands for while simplifying (tree.pyx Context.names). */
enum { NB_DYNAMIC, NB_LITERAL, NB_RENAME, NB_FUNCTION };

typedef struct NameBind {
    Str *name;             /* one reference */
    int kind;              /* NB_* */
    Vec *value;            /* NB_LITERAL: the value (one reference) */
    Str *target;           /* NB_RENAME: the name it stands for (one reference) */
    const AstNode *fn;     /* NB_FUNCTION: an inlineable AST_FUNCTION (borrowed
                              from the Let being simplified) */
    uint32_t hash;         /* of the name (name_hash) */
    uint32_t prev;         /* the entry of the same name it shadows + 1, or 0 */
    Column *col;           /* NB_LITERAL in a template pass: the members'
                              values (one reference), or NULL: [value] */
} NameBind;

/* AST_EXPORT `op` after simplification: the main program's end, which does
 * not keep unused bindings alive (a module's does). */
enum { EXPORT_MAIN = 1 };

/* AST_FUNCTION flags in `op` after simplification. */
enum { FN_INLINEABLE = 1, FN_CAPTURES = 2 };

/* A name a module ends with, bound to a literal or an inlineable function. */
typedef struct SimpExport {
    Str *name;
    Vec *value;      /* literal value, or NULL with fn */
    AstNode *fn;     /* owned copy of an inlineable AST_FUNCTION, or NULL */
} SimpExport;

/* The lines simp_warn has written to a warnings buffer, hashed, so that
 * each message is written once in time linear in their number (a scan of
 * the buffer per message made 50,000 unbound names take 8 s). */
typedef struct WarnTable {
    uint64_t *hash;     /* FNV-1a of the line, 0: empty slot */
    size_t *start;      /* the line's offset in the buffer */
    size_t *len;
    size_t n, cap;      /* cap a power of two, or 0 */
} WarnTable;

typedef struct Simp Simp;
struct Simp {
    NameBind *names;        /* scope stack: later entries shadow earlier */
    uint32_t nnames, capnames;
    uint32_t *heads;        /* hash of names[] by name: the innermost entry
                               + 1 (0 empty; nheads slots, a power of two);
                               each entry links to the one it shadows
                               (NameBind.prev), so lookups are O(1) however
                               many names are bound */
    uint32_t nheads;
    uint32_t *renames;      /* indexes of the NB_RENAME entries of names[],
                               ascending (a `let` looks only at these) */
    uint32_t nrenames, caprenames;
    SymTab *symtab;
    Buf *warnings;
    WarnTable *warned;      /* lines written to warnings (shared with the
                               simplifiers of included and imported files) */
    bool owns_warned;
    MsgSet errors;          /* messages of load-time builtin calls */
    Eval ev;                /* evaluator context for load-time folding */
    uint32_t call_depth;    /* functions being inlined */
    uint32_t depth;         /* simp() nesting */
    bool too_deep;          /* the nesting limit was hit: give up */
    bool unwinding;         /* the inline depth limit was hit: abandon */
    bool in_include;        /* simplifying an included file (no exports) */
    uint64_t unrolled;      /* loop-body copies made so far (SIMP_MAX_UNROLL) */
    char *dir;              /* directory of the file being simplified */
    char **deps;            /* files included so far */
    uint32_t ndeps;
    uint32_t next_file;     /* source index for the next included file */
    Vec **builtins;         /* cache: one function vector per builtin name */
    Str **builtin_names;
    uint32_t nbuiltins, capbuiltins;
    Vec **consts;           /* cache: one value per builtin constant name */
    Str **const_names;
    uint32_t nconsts, capconsts;
    const Simp *parent;     /* the importing program's simplifier, or NULL */
    char *path;             /* path of the module being simplified, or NULL */
    bool collect_exports;   /* a module: record its static names at the end */
    bool is_module;         /* a module: the end of the file uses every name */
    SimpExport *exports;
    uint32_t nexports, capexports;
    uint32_t *stable_ids;   /* the program's `let stable` id counter */
    const struct StableCache *stables;  /* known stable values, or NULL */
    PathList *files;        /* files read are added here (shared with
                               module sub-simplifiers; NULL: nowhere) */
    /* template passes (simplify_template.c) */
    uint32_t tg;            /* members of the group being simplified
                               together, 0: not in a template pass */
    bool tabort;            /* the pass met what it cannot share (a
                               warning, a nested limit): unroll one copy
                               at a time */
    int64_t *tkey;          /* the first test whose outcome differs between
                               members: each member's outcome, or NULL */
    bool talone;            /* a group of one member simplified with its
                               plain values (simp_unroll_templates): what
                               a column pass must not share aborts it too */
    bool no_templates;      /* fl_debug_options.no_templates: one copy at a time */
    bool check_templates;   /* fl_debug_options.check_templates: compare every
                               templated copy with its one-at-a-time twin */
};

/* ---- simplify_template.c ---- */
/* Tests a template pass must agree on across its members (tdecide). */
enum { TD_NUMERIC, TD_EQUALS, TD_TRUTHY, TD_LEN, TD_SCALAR, TD_OBJ, TD_NULL };
/* The aux_free of a literal's Column (col_attach). */
void col_aux_free(void *p);
/* True when [n] is a literal carrying a Column (in a template pass). */
static inline bool has_col(const AstNode *n)
{
    return n && n->kind == AST_LITERAL && n->aux && n->aux_free == col_aux_free;
}
/* Member [m]'s value of literal [n] (borrowed): its column's, or its own. */
Vec *tval(const AstNode *n, uint32_t m);
/* A new column of [n] members, all NULL, one reference. */
Column *col_new(uint32_t n);
/* A new numeric column of [n] members (their numbers in num[], to be
 * filled by the caller), one reference. Numeric columns carry a template
 * pass's one-number values without a vector each: the column helpers
 * compute them with the operations the vector route performs on
 * one-element vectors, so every member's value has the same bits. */
Column *col_new_num(uint32_t n);
/* The most numbers a member of a flat column: positions, colours,
 * state keys (`(:cell;i)`); a longer vector a member takes the route of
 * a vector a member, whose memory its own numbers dwarf. */
#define FLAT_MAX 16
/* A new flat column of [n] members of [w] >= 2 numbers each (flat[],
 * to be filled by the caller), one reference; NULL, with nothing marked
 * refused, when [w] is past FLAT_MAX or its numbers do not fit in the
 * memory budget (mem.h, which they are charged to while the column
 * lives): the caller then takes the route of a vector a member, which
 * meets the budget as it always did. Like numeric columns, flat ones spare a template pass a
 * vector a member until something asks for it: composing numbers
 * (`(:v;i)`, a position `x;y`), indexing a stream column by a literal
 * (`[..2]`) and arithmetic on them make flat columns with the operations
 * the vector route performs, number for number. */
Column *col_new_flat(uint32_t n, uint32_t w);
/* A new stream column of [n] members of stream kind [kind] (key[], to be
 * filled by the caller), one reference: `normal(:v;i)` in a pass. */
Column *col_new_keys(uint32_t n, uint8_t kind);
/* A new node column of [n] members (node[], to be filled by the caller
 * with a reference each), one reference: `!particle id=i ...` in a pass,
 * whose nodes go into the loop's literal without a vector each. */
Column *col_new_nodes(uint32_t n);
/* True when [c] keeps its members' vectors in c->v only (col_new), not
 * as numbers, flat numbers, keys or nodes made into vectors on demand. */
static inline bool col_plain(const Column *c) { return !c->num && !c->flat && !c->key && !c->node; }
/* Member [m]'s value (borrowed; NULL: null), made now for a numeric,
 * flat, stream or node column's member whose vector was not asked for
 * before (NULL too when the memory budget refuses it). */
Vec *col_get(Column *c, uint32_t m);
/* Member [m]'s value as a new reference (NULL: null): the vector col_get
 * keeps, or, when it has made none, the one it would make, not kept in
 * the column (for a holder that is the value's only one: a node's
 * attribute). */
Vec *col_make(const Column *c, uint32_t m);
/* Every member's value, made now where col_get has not made it (the
 * array is the column's: borrowed, as its vectors are). */
Vec **col_all(Column *c);
Column *col_retain(Column *c);
void col_release(Column *c);
/* Attach [c] (consumed; NULL: none) to literal [n]. */
void col_attach(AstNode *n, Column *c);
/* The outcome of test [kind] (TD_*, [x] for TD_EQUALS) on literal [n]'s
 * value; in a template pass where members' outcomes differ, the first
 * such test is recorded (s->tkey) and the group is split. */
int64_t tdecide(Simp *s, const AstNode *n, int kind, double x);
/* The literal of [rep_take] with column [c] (consumed; NULL: none). */
AstNode *tlit(Simp *s, Vec *rep_take, Column *c, Loc loc);
/* In a template pass, [f] applied to [e] once per member with each
 * literal child (a, b, c, kids and the values of binding kids) holding
 * that member's value: the results' column; NULL when no child has a
 * column (or outside a pass). */
typedef Vec *(*TEvalFn)(Simp *s, AstNode *e);
Column *tcol_eval(Simp *s, AstNode *e, TEvalFn f);
/* Unroll the body of for-loop [n] for the [count] bindings of literal
 * [values] ([k] names each) into items[0..count) by template passes: the
 * body is simplified once for each group of iterations that every test
 * treats alike, and copied for its members. *[nout] is how many of the
 * items to pack: [count], or 1 when every copy was a literal and items[0]
 * is already what sequence_pack makes of them. False, with no warning
 * written and nothing in items[0..count) for the caller to free, when the
 * loop must be unrolled one copy at a time (at once when a pass it is in
 * was abandoned already). */
bool simp_unroll_templates(Simp *s, const AstNode *n, const Vec *values, uint32_t count, AstNode **items,
                           uint32_t *nout);

/* Set up [s] for a file in [dir] ([path]: the module's path, or NULL). */
void simp_init(Simp *s, SymTab *st, Buf *warnings, const char *dir, const char *path,
               uint32_t next_file);
/* Release everything [s] holds. */
void simp_fini(Simp *s);

/* ---- simplify.c ---- */
/* The simplified copy of [n] (a new tree; [n] untouched). */
AstNode *simp(Simp *s, const AstNode *n);
/* simp() of [n_take], which is then freed. */
AstNode *resimp(Simp *s, AstNode *n_take);
/* A new literal of [v_take]. */
AstNode *mk_lit(Vec *v_take, Loc loc);
/* True when [n] is an AST_LITERAL. */
static inline bool is_lit(const AstNode *n) { return n && n->kind == AST_LITERAL; }
/* Record a load-time warning line. */
void simp_warn(Simp *s, const char *msg);
/* Make [sub] (an included or imported file's simplifier, writing to the
 * same warnings buffer) share [s]'s record of the lines written. */
void simp_share_warnings(Simp *sub, const Simp *s);

/* ---- simplify_scope.c ---- */
/* The innermost binding of [name], or NULL. */
NameBind *scope_find(Simp *s, const Str *name);
/* Bind [name] (retained) to the given meaning in the current scope. */
void scope_push(Simp *s, Str *name, int kind, const Vec *value, Str *target, const AstNode *fn);
/* The same for NB_LITERAL [value] with column [col] (retained; may be NULL). */
void scope_push_col(Simp *s, Str *name, const Vec *value, Column *col);
/* Drop every binding made after [mark]. */
void scope_restore(Simp *s, uint32_t mark);
AstNode *simp_name(Simp *s, const AstNode *n);
AstNode *simp_let(Simp *s, const AstNode *n);
AstNode *simp_for(Simp *s, const AstNode *n);
AstNode *simp_function(Simp *s, const AstNode *n);
AstNode *simp_call(Simp *s, const AstNode *n);
/* A new AST_BINDING of the single name [name] (retained) to [value]. */
AstNode *mk_binding1(Str *name, AstNode *value, Loc loc);

/* ---- simplify_files.c ---- */
AstNode *simp_include(Simp *s, const AstNode *n);
AstNode *simp_import(Simp *s, const AstNode *n);
AstNode *simp_export(Simp *s, const AstNode *n);
/* The builtin function vector for [name] (shared, borrowed), or NULL when
 * [name] is no builtin function. */
const Vec *simp_builtin(Simp *s, const Str *name);

/* A set of free names (tree.pyx `unbound_names`); `all` stands for the
 * reference's None member: an export that uses every name in scope. */
typedef struct NameSet {
    const Str **v;
    uint32_t n, cap;
    bool all;
    uint32_t *index;     /* past a few names: open-addressed hash of v
                            (index + 1, 0 empty; nindex slots, a power of
                            two), so that a set of N names is built in
                            O(N), not O(N^2) */
    uint32_t nindex;
} NameSet;
void free_names(const AstNode *n, NameSet *out);
bool nameset_has(const NameSet *set, const Str *name);
void nameset_free(NameSet *set);

#endif
