/* program.c: loading a program and resolving its names (LANGUAGE.md §4.2).
 *
 * program_load() reads a script, parses it (parse.h), registers every symbol
 * literal in the runtime's symbol table, collects the pragmas, and runs the
 * resolver: one pass over the AST in source order that keeps, per function
 * context, a stack of the names visible at each point. A `let`, `for`,
 * `import` or function parameter pushes names for the extent of its body and
 * pops them after, which is exactly Flitter's lexical scoping. A name not
 * found in the current function is looked up in the enclosing ones and, if
 * found there, becomes a capture: a slot of the inner frame filled from the
 * outer frame when the function value is created (capture by value at
 * definition time, §4.8). Names found nowhere are engine/define names
 * (Globals), builtin constants and functions (§5), or unbound (warning,
 * value null).
 */
#include "program.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "builtins.h"
#include "config.h"
#include "evalcode.h"
#include "fileio.h"
#include "mem.h"
#include "parse.h"
#include "pool.h"
#include "simplify.h"
#include "stable.h"

/* ====================================================================
 * Globals and message sets
 * ==================================================================== */

int globals_find(const Globals *g, const char *name, size_t len)
{
    if (!g) return -1;
    for (uint32_t i = 0; i < g->count; i++)
        if (g->names[i]->len == len && memcmp(g->names[i]->bytes, name, len) == 0) return (int)i;
    return -1;
}

int globals_add(Globals *g, const char *name)
{
    int i = globals_find(g, name, strlen(name));
    if (i >= 0) return i;
    if (g->count == g->cap) {
        g->cap = g->cap ? g->cap * 2 : 32;
        g->names = realloc(g->names, g->cap * sizeof(Str *));
        g->values = realloc(g->values, g->cap * sizeof(Vec *));
        if (!g->names || !g->values) mem_oom();
    }
    g->names[g->count] = str_from(name);
    g->values[g->count] = NULL;
    return (int)g->count++;
}

void globals_set(Globals *g, int index, Vec *value)
{
    Vec *old = g->values[index];
    g->values[index] = vec_retain(value);
    vec_release(old);
}

void globals_free(Globals *g)
{
    for (uint32_t i = 0; i < g->count; i++) {
        str_release(g->names[i]);
        vec_release(g->values[i]);
    }
    free(g->names);
    free(g->values);
    *g = (Globals){0};
}

bool msgset_has(const MsgSet *s, const char *msg)
{
    for (uint32_t i = 0; i < s->count; i++)
        if (strcmp(s->items[i], msg) == 0) return true;
    return false;
}

bool msgset_add(MsgSet *s, const char *msg)
{
    if (msgset_has(s, msg)) return false;
    if (s->count == s->cap) {
        s->cap = s->cap ? s->cap * 2 : 8;
        s->items = realloc(s->items, s->cap * sizeof(char *));
        if (!s->items) mem_oom();
    }
    s->items[s->count] = strdup(msg);
    if (!s->items[s->count]) mem_oom();
    s->count++;
    return true;
}

void msgset_clear(MsgSet *s)
{
    for (uint32_t i = 0; i < s->count; i++) free(s->items[i]);
    free(s->items);
    *s = (MsgSet){0};
}

/* ====================================================================
 * The resolver
 * ==================================================================== */

typedef struct Visible {
    const Str *name;   /* bound name */
    int32_t slot;      /* its slot in the function frame */
    uint32_t hash;     /* of the name (name_hash) */
    uint32_t prev;     /* the entry before it in its hash bucket + 1, or 0 */
} Visible;

typedef struct FnCtx {
    struct FnCtx *parent;   /* enclosing function context, or NULL at top */
    Visible *scope;         /* visible names, innermost last */
    uint32_t nscope, capscope;
    uint32_t *heads;        /* hash buckets of scope[]: the innermost entry
                               + 1 (0 empty; nheads, a power of two), chained
                               through Visible.prev, so that a name is found
                               in O(1) among any number bound */
    uint32_t nheads;
    uint32_t nslots;        /* frame size so far */
    const Str **cap_names;  /* names captured from outer frames */
    int32_t *cap_src, *cap_dst;
    uint32_t ncaps, capcaps;
} FnCtx;

typedef struct Constant {
    Str *name;
    Vec *value;
} Constant;

typedef struct Resolver {
    Globals *globals;       /* engine/define names (NULL for modules) */
    SymTab *symtab;         /* where symbols of included files go */
    const char *dir;        /* directory of the main file, for %include */
    char **included;        /* paths already included */
    uint32_t nincluded;
    Buf *err;               /* load errors (included files) */
    bool failed;            /* an included file did not parse */
    Buf *warnings;          /* load-time warnings */
    Constant *consts;       /* shared builtin values, one Vec per name */
    uint32_t nconsts, capconsts;
    const char **unbound;   /* names already warned about, in order */
    uint32_t nunbound, capunbound;
    uint32_t *unbound_index;  /* open-addressed hash of unbound[]: index + 1,
                                 0 empty; capunbound * 2 slots */
    uint32_t depth;         /* resolve() nesting: bounded by AST_MAX_DEPTH
                               across %include splices too */
    PathList *files;        /* the program's files: included ones are added */
} Resolver;

static uint32_t name_hash(const char *s);

static void link_visible(FnCtx *c, uint32_t i)
{
    uint32_t *head = &c->heads[c->scope[i].hash & (c->nheads - 1)];
    c->scope[i].prev = *head;
    *head = i + 1;
}

static void push_visible(FnCtx *c, const Str *name, int32_t slot)
{
    if (c->nscope == c->capscope) {
        c->capscope = c->capscope ? c->capscope * 2 : 16;
        c->scope = realloc(c->scope, c->capscope * sizeof(Visible));
        if (!c->scope) mem_oom();
    }
    uint32_t i = c->nscope++;
    c->scope[i] = (Visible){name, (int32_t)slot, name_hash(name->bytes), 0};
    if (c->nscope > c->nheads) {   /* grow: about one entry a bucket */
        c->nheads = c->nheads ? c->nheads * 2 : 16;
        free(c->heads);
        c->heads = calloc(c->nheads, sizeof *c->heads);
        if (!c->heads) mem_oom();
        for (uint32_t k = 0; k < c->nscope; k++) link_visible(c, k);
    } else {
        link_visible(c, i);
    }
}

/* Drop the names made visible after [mark]. */
static void pop_visible(FnCtx *c, uint32_t mark)
{
    while (c->nscope > mark) {
        const Visible *v = &c->scope[--c->nscope];
        c->heads[v->hash & (c->nheads - 1)] = v->prev;
    }
}

/* The innermost entry of scope[] binding [name] + 1, or 0. */
static uint32_t find_visible(const FnCtx *c, const Str *name)
{
    if (!c->nheads) return 0;
    uint32_t h = name_hash(name->bytes);
    for (uint32_t i = c->heads[h & (c->nheads - 1)]; i; i = c->scope[i - 1].prev)
        if (c->scope[i - 1].hash == h && str_eq(c->scope[i - 1].name, name)) return i;
    return 0;
}

static void add_capture(FnCtx *c, const Str *name, int32_t src, int32_t dst)
{
    if (c->ncaps == c->capcaps) {
        c->capcaps = c->capcaps ? c->capcaps * 2 : 8;
        c->cap_names = realloc(c->cap_names, c->capcaps * sizeof(Str *));
        c->cap_src = realloc(c->cap_src, c->capcaps * sizeof(int32_t));
        c->cap_dst = realloc(c->cap_dst, c->capcaps * sizeof(int32_t));
        if (!c->cap_names || !c->cap_src || !c->cap_dst) mem_oom();
    }
    c->cap_names[c->ncaps] = name;
    c->cap_src[c->ncaps] = src;
    c->cap_dst[c->ncaps] = dst;
    c->ncaps++;
}

/* The slot of [name] visible in [c], capturing from outer contexts; -1 if
 * no function context binds it. */
static int32_t lookup_local(FnCtx *c, const Str *name)
{
    uint32_t found = find_visible(c, name);
    if (found) return c->scope[found - 1].slot;
    if (!c->parent) return -1;
    for (uint32_t i = 0; i < c->ncaps; i++)
        if (str_eq(c->cap_names[i], name)) return c->cap_dst[i];
    int32_t src = lookup_local(c->parent, name);
    if (src < 0) return -1;
    int32_t dst = (int32_t)c->nslots++;
    add_capture(c, name, src, dst);
    return dst;
}

/* Builtin constants of LANGUAGE.md §5.1; NULL value means null. */
static bool builtin_constant(const Str *name, Vec **out)
{
    static const struct { const char *name; double value; } table[] = {
        {"true", 1.0}, {"false", 0.0}, {"inf", 1.0 / 0.0}, {"nan", 0.0 / 0.0},
        {"pi", 3.141592653589793}, {"\xcf\x80", 3.141592653589793},
        {"tau", 6.283185307179586}, {"\xf0\x9d\x9c\x8f", 6.283185307179586},
    };
    if (name->len == 4 && memcmp(name->bytes, "null", 4) == 0) {
        *out = NULL;
        return true;
    }
    for (size_t i = 0; i < sizeof table / sizeof table[0]; i++) {
        if (strcmp(table[i].name, name->bytes) == 0) {
            *out = vec_num1(table[i].value);
            return true;
        }
    }
    return false;
}

/* The shared value of builtin constant or function [name]; false if none. */
static bool builtin_value(Resolver *r, const Str *name, Vec **out)
{
    for (uint32_t i = 0; i < r->nconsts; i++) {
        if (str_eq(r->consts[i].name, name)) {
            *out = vec_retain(r->consts[i].value);
            return true;
        }
    }
    Vec *v;
    if (!builtin_constant(name, &v)) {
        const Builtin *bi = bi_lookup(name->bytes, name->len);
        if (!bi) return false;
        Func *f = pool_calloc(sizeof *f);
        f->refs = 1;
        f->bi = bi;
    f->bi_name = bi->internal;
        v = vec_func_take(f);
    }
    if (r->nconsts == r->capconsts) {
        r->capconsts = r->capconsts ? r->capconsts * 2 : 16;
        r->consts = realloc(r->consts, r->capconsts * sizeof(Constant));
        if (!r->consts) mem_oom();
    }
    r->consts[r->nconsts++] = (Constant){str_retain((Str *)name), v};
    *out = vec_retain(v);
    return true;
}

static uint32_t name_hash(const char *s)
{
    uint32_t h = 2166136261u;   /* FNV-1a */
    for (; *s; s++) h = (h ^ (unsigned char)*s) * 16777619u;
    return h;
}

/* Warn once per distinct unbound name, in the order first met. The names
 * met are hashed (a linear search made 50,000 distinct names take 10 s
 * with --nosimplify). */
static void warn_unbound(Resolver *r, const Str *name)
{
    uint32_t mask = r->capunbound * 2 - 1, h = name_hash(name->bytes);
    if (r->unbound_index)
        for (uint32_t i = h & mask; r->unbound_index[i]; i = (i + 1) & mask)
            if (strcmp(r->unbound[r->unbound_index[i] - 1], name->bytes) == 0) return;
    if (r->nunbound == r->capunbound) {
        r->capunbound = r->capunbound ? r->capunbound * 2 : 8;
        r->unbound = realloc(r->unbound, r->capunbound * sizeof(char *));
        free(r->unbound_index);
        r->unbound_index = calloc((size_t)r->capunbound * 2, sizeof(uint32_t));
        if (!r->unbound || !r->unbound_index) mem_oom();
        mask = r->capunbound * 2 - 1;
        for (uint32_t k = 0; k < r->nunbound; k++) {
            uint32_t i = name_hash(r->unbound[k]) & mask;
            while (r->unbound_index[i]) i = (i + 1) & mask;
            r->unbound_index[i] = k + 1;
        }
    }
    uint32_t i = h & mask;
    while (r->unbound_index[i]) i = (i + 1) & mask;
    r->unbound_index[i] = r->nunbound + 1;
    r->unbound[r->nunbound++] = name->bytes;
    buf_printf(r->warnings, "Unbound name '%s'\n", name->bytes);
}

static void resolve_name(Resolver *r, FnCtx *c, AstNode *n)
{
    const Str *name = n->names[0];
    int32_t slot = lookup_local(c, name);
    if (slot >= 0) {
        n->scope = SCOPE_LOCAL;
        n->slot = slot;
        return;
    }
    int g = globals_find(r->globals, name->bytes, name->len);
    if (g >= 0) {
        n->scope = SCOPE_GLOBAL;
        n->slot = g;
        return;
    }
    Vec *v;
    if (builtin_value(r, name, &v)) {
        n->scope = SCOPE_CONST;
        vec_release(n->value);
        n->value = v;
        return;
    }
    n->scope = SCOPE_UNBOUND;
    warn_unbound(r, name);
}

/* Give each name of [n] a new slot in [c] and make it visible. */
static void bind_names(FnCtx *c, AstNode *n)
{
    if (!n->nnames) return;
    free(n->slots);
    n->slots = malloc(n->nnames * sizeof(int32_t));
    if (!n->slots) mem_oom();
    for (uint32_t i = 0; i < n->nnames; i++) {
        n->slots[i] = (int32_t)c->nslots++;
        push_visible(c, n->names[i], n->slots[i]);
    }
}

static void fninfo_free(void *p)
{
    FnInfo *fi = p;
    free(fi->cap_src);
    free(fi);
}

static void resolve(Resolver *r, FnCtx *c, AstNode *n);

static void exportinfo_free(void *p)
{
    ExportInfo *x = p;
    free(x->names);
    free(x->slots);
    free(x);
}

/* AST_EXPORT at the top level: remember the innermost binding of every
 * visible name. */
static void resolve_export(FnCtx *c, AstNode *n)
{
    if (c->parent) return;
    ExportInfo *x = calloc(1, sizeof *x);
    if (!x) mem_oom();
    x->names = malloc((c->nscope ? c->nscope : 1) * sizeof(Str *));
    x->slots = malloc((c->nscope ? c->nscope : 1) * sizeof(int32_t));
    if (!x->names || !x->slots) mem_oom();
    for (uint32_t i = c->nscope; i-- > 0;) {
        if (find_visible(c, c->scope[i].name) != i + 1) continue;   /* shadowed */
        x->names[x->count] = c->scope[i].name;
        x->slots[x->count] = c->scope[i].slot;
        x->count++;
    }
    if (n->aux_free) n->aux_free(n->aux);
    n->aux = x;
    n->aux_free = exportinfo_free;
}

/* AST_INCLUDE with a literal file name: parse the file and splice its
 * statements in as n->b, resolved in the current scope (§4.14). A
 * non-literal name is left for the evaluator to report. */
static void resolve_include(Resolver *r, FnCtx *c, AstNode *n)
{
    if (!n->a || n->a->kind != AST_LITERAL) return;
    const Vec *v = n->a->value;
    if (!v) return;   /* null: directive ignored */
    if (!vec_is_obj(v) || v->len != 1 || vec_celems(v)[0].kind != EL_STR) return;
    const Str *name = vec_celems(v)[0].str;
    char *path;
    if (name->bytes[0] == '/' || !r->dir) path = strdup(name->bytes);
    else if (asprintf(&path, "%s/%s", r->dir, name->bytes) < 0) path = NULL;
    if (!path) mem_oom();
    for (uint32_t i = 0; i < r->nincluded; i++) {
        if (strcmp(r->included[i], path) == 0) {
            buf_printf(r->warnings, "Cannot include path '%s' multiple times\n", path);
            free(path);
            n->op = 1;   /* evaluates to null */
            return;
        }
    }
    r->included = realloc(r->included, (r->nincluded + 1) * sizeof(char *));
    if (!r->included) mem_oom();
    r->included[r->nincluded++] = path;
    Buf text = BUF_INIT;
    if (!file_read_regular(path, &text)) {
        buf_printf(r->err, "%s: error: cannot read included file: %s\n", path,
                   errno == EINVAL ? "not a regular file" : strerror(errno));
        buf_free(&text);
        r->failed = true;
        return;
    }
    if (r->files) pathlist_add(r->files, path);
    AstNode *top = parse_program(path, text.data ? text.data : "", text.len, r->nincluded, r->err);
    buf_free(&text);
    if (!top) {
        r->failed = true;
        return;
    }
    program_register_symbols(top, r->symtab);
    n->b = top->a;     /* the included statements; pragmas are discarded */
    top->a = NULL;
    ast_free(top);
    resolve(r, c, n->b);
}

/* AST_FUNCTION: defaults in the defining context, body in a new one. */
static void resolve_function(Resolver *r, FnCtx *c, AstNode *n)
{
    for (uint32_t i = 0; i < n->nkids; i++)
        if (n->kids[i] && n->kids[i]->a) resolve(r, c, n->kids[i]->a);
    FnCtx inner = {.parent = c, .nslots = 1};
    const Str *fname = n->nnames ? n->names[0] : NULL;
    if (fname && strcmp(fname->bytes, "<anon>") != 0) push_visible(&inner, fname, 0);
    for (uint32_t i = 0; i < n->nkids; i++) {
        AstNode *p = n->kids[i];
        if (!p || !p->nnames) continue;
        free(p->slots);
        p->slots = malloc(sizeof(int32_t));
        if (!p->slots) mem_oom();
        p->slots[0] = (int32_t)inner.nslots++;
        push_visible(&inner, p->names[0], p->slots[0]);
    }
    if (n->a) resolve(r, &inner, n->a);
    FnInfo *fi = calloc(1, sizeof *fi);
    if (!fi) mem_oom();
    fi->nslots = inner.nslots;
    fi->nparams = n->nkids;
    fi->ncaps = inner.ncaps;
    /* cap_src and cap_dst in one allocation: src[0..ncaps), dst after */
    fi->cap_src = malloc((inner.ncaps ? inner.ncaps : 1) * 2 * sizeof(int32_t));
    if (!fi->cap_src) mem_oom();
    for (uint32_t i = 0; i < inner.ncaps; i++) {
        fi->cap_src[i] = inner.cap_src[i];
        fi->cap_src[inner.ncaps + i] = inner.cap_dst[i];
    }
    if (n->aux_free) n->aux_free(n->aux);
    n->aux = fi;
    n->aux_free = fninfo_free;
    free(inner.scope);
    free(inner.heads);
    free(inner.cap_names);
    free(inner.cap_src);
    free(inner.cap_dst);
}

static void resolve_node(Resolver *r, FnCtx *c, AstNode *n);

/* Resolve [n] and below. parse_program caps each file's tree at
 * AST_MAX_DEPTH; an %include splices a file's tree in below the include,
 * so the depth is checked again here, where the trees are joined, before
 * any recursive pass (this one, evaluation) could go deeper. */
static void resolve(Resolver *r, FnCtx *c, AstNode *n)
{
    if (!n || r->failed) return;
    if (r->depth >= AST_MAX_DEPTH) {
        const char *path = n->loc.file >= 1 && n->loc.file <= r->nincluded
                               ? r->included[n->loc.file - 1] : "<program>";
        buf_printf(r->err, "%s: error: program nested too deeply through %%include "
                   "(limit %d levels)\n", path, AST_MAX_DEPTH);
        r->failed = true;
        return;
    }
    r->depth++;
    resolve_node(r, c, n);
    r->depth--;
}

static void resolve_node(Resolver *r, FnCtx *c, AstNode *n)
{
    uint32_t mark = c->nscope;
    switch (n->kind) {
    case AST_NAME:
        resolve_name(r, c, n);
        return;
    case AST_LET:
        for (uint32_t i = 0; i < n->nkids; i++) {
            AstNode *b = n->kids[i];
            resolve(r, c, b->a);
            bind_names(c, b);
        }
        resolve(r, c, n->a);
        pop_visible(c, mark);
        return;
    case AST_FOR:
        resolve(r, c, n->a);
        bind_names(c, n);
        resolve(r, c, n->b);
        pop_visible(c, mark);
        return;
    case AST_IMPORT:
        resolve(r, c, n->a);
        bind_names(c, n);
        resolve(r, c, n->b);
        pop_visible(c, mark);
        return;
    case AST_FUNCTION:
        resolve_function(r, c, n);
        return;
    case AST_TOP:
        resolve(r, c, n->a);
        return;
    case AST_EXPORT:
        resolve_export(c, n);
        return;
    case AST_INCLUDE:
        resolve(r, c, n->a);
        resolve_include(r, c, n);
        return;
    default:
        break;
    }
    resolve(r, c, n->a);
    resolve(r, c, n->b);
    resolve(r, c, n->c);
    for (uint32_t i = 0; i < n->nkids; i++) {
        AstNode *k = n->kids[i];
        if (k && k->kind == AST_BINDING) resolve(r, c, k->a);
        else resolve(r, c, k);
    }
}

/* ====================================================================
 * Loading
 * ==================================================================== */

/* Register the symbol literals that the parser listed under AST_TOP.c. */
void program_register_symbols(const AstNode *top, SymTab *st)
{
    if (!top) return;
    const AstNode *list = top->c;
    if (!list) return;
    for (uint32_t i = 0; i < list->nkids; i++) {
        const AstNode *k = list->kids[i];
        if (!k || !vec_is_obj(k->value)) continue;
        const Elem *e = &vec_celems(k->value)[0];
        if (e->kind == EL_STR) symtab_add(st, e->str->bytes, e->str->len);
    }
}

/* Simplify [top] (consumed) for [p] with the static names of [g] and the
 * stable values of [sc] (NULL: none) known. */
static AstNode *simplify_top(Program *p, AstNode *top, const Globals *g, SymTab *st,
                             const StableCache *sc)
{
    SimplifyName *names = calloc(g->count ? g->count : 1, sizeof *names);
    if (!names) mem_oom();
    for (uint32_t i = 0; i < g->count; i++)
        names[i] = (SimplifyName){g->names[i], i < g->ndynamic, g->values[i]};
    SimplifyEnv env = {.names = names, .nnames = g->count, .symtab = st, .dir = p->dir,
                       .first_file = 1000, .stable_ids = &p->stable_ids, .stables = sc,
                       .is_module = g->module, .files = &p->files, .interrupt = g->interrupt,
                       .no_templates = g->routes.no_templates, .check_templates = g->routes.check_templates};
    top = simplify_program(top, &env, &p->warnings);
    free(names);
    return top;
}

/* Resolve the names of p->top against [globals]; frees [p] and returns
 * NULL when an included file failed to load. */
static Program *resolve_program(Program *p, Globals *globals, SymTab *st, Buf *err)
{
    Resolver r = {.globals = globals, .warnings = &p->warnings, .symtab = st, .dir = p->dir, .err = err,
                  .files = &p->files};
    FnCtx ctx = {0};
    resolve(&r, &ctx, p->top);
    for (uint32_t i = 0; i < r.nincluded; i++) free(r.included[i]);
    free(r.included);
    p->nslots = ctx.nslots;
    free(ctx.scope);
    free(ctx.heads);
    free(ctx.cap_names);
    free(ctx.cap_src);
    free(ctx.cap_dst);
    for (uint32_t i = 0; i < r.nconsts; i++) {
        str_release(r.consts[i].name);
        vec_release(r.consts[i].value);
    }
    free(r.consts);
    free(r.unbound);
    free(r.unbound_index);
    if (r.failed) {
        program_release(p);
        return NULL;
    }
    static const KernelOptions default_kernels = {0};
    if (!globals || !globals->routes.no_fast)
        evalcode_compile_tree(p->top, globals ? &globals->routes.kernel : &default_kernels);
    return p;
}

static char *dir_of(const char *path)
{
    const char *slash = strrchr(path, '/');
    if (!slash) return strdup(".");
    if (slash == path) return strdup("/");
    return strndup(path, (size_t)(slash - path));
}

Program *program_load_text(const char *path, const char *text, size_t len,
                           Globals *globals, SymTab *st, Buf *err)
{
    /* the parser's memory, estimated from the size of the source (its
     * measured cost per byte, config.h), must fit the budget (mem.h) */
    if (len > SIZE_MAX / PARSE_BYTES_PER_BYTE || !mem_fits(len * PARSE_BYTES_PER_BYTE)) {
        mem_take_refusal();
        buf_printf(err, "%s:1:1: error: out of memory (parsing %zu bytes of source needs about "
                   "%zu MiB, past the memory budget)\n", path, len, len / (1u << 20) * PARSE_BYTES_PER_BYTE);
        return NULL;
    }
    AstNode *top = parse_program(path, text, len, 0, err);
    if (!top) return NULL;
    Program *p = calloc(1, sizeof *p);
    if (!p) mem_oom();
    p->refs = 1;
    p->top = top;
    p->path = strdup(path);
    p->dir = dir_of(path);
    if (!p->path || !p->dir) mem_oom();
    pathlist_add(&p->files, path);
    program_register_symbols(top, st);
    if (top->nkids) {
        p->pragmas = calloc(top->nkids, sizeof(Pragma));
        if (!p->pragmas) mem_oom();
        for (uint32_t i = 0; i < top->nkids; i++) {
            const AstNode *b = top->kids[i];
            if (!b || !b->nnames) continue;
            p->pragmas[p->npragmas].name = str_retain(b->names[0]);
            p->pragmas[p->npragmas].value = vec_retain(b->value);
            p->npragmas++;
        }
    }
    if (globals && globals->simplify) {
        p->top = top = simplify_top(p, top, globals, st, NULL);
        /* kept only for simplifying again with stable values, which only
         * `let stable` bindings (numbered in stable_ids) can produce */
        if (p->stable_ids) p->simplified = ast_copy(top);
        if (globals->interrupt && *globals->interrupt) {   /* the simplifier gave up */
            buf_printf(err, "%s: error: interrupted while loading\n", path);
            program_release(p);
            return NULL;
        }
        if (mem_take_refusal()) {   /* a value folded at load time did not fit the budget */
            buf_printf(err, "%s:1:1: error: out of memory (a value computed while simplifying "
                       "is past the memory budget)\n", path);
            program_release(p);
            return NULL;
        }
    }
    return resolve_program(p, globals, st, err);
}

Program *program_resimplify(const Program *cur, Globals *globals, SymTab *st, const StableCache *sc)
{
    if (!cur->simplified) return NULL;
    Program *p = calloc(1, sizeof *p);
    if (!p) mem_oom();
    p->refs = 1;
    p->path = strdup(cur->path);
    p->dir = strdup(cur->dir);
    if (!p->path || !p->dir) mem_oom();
    p->stable_ids = cur->stable_ids;
    pathlist_add_all(&p->files, &cur->files);
    if (cur->npragmas) {
        p->pragmas = calloc(cur->npragmas, sizeof(Pragma));
        if (!p->pragmas) mem_oom();
        for (uint32_t i = 0; i < cur->npragmas; i++)
            p->pragmas[i] = (Pragma){str_retain(cur->pragmas[i].name), vec_retain(cur->pragmas[i].value)};
        p->npragmas = cur->npragmas;
    }
    p->nasserted = stable_count(sc);
    p->asserted = malloc((p->nasserted ? p->nasserted : 1) * 2 * sizeof(uint32_t));
    if (!p->asserted) mem_oom();
    for (uint32_t i = 0; i < p->nasserted; i++) stable_key(sc, i, &p->asserted[2 * i], &p->asserted[2 * i + 1]);
    p->top = simplify_top(p, ast_copy(cur->simplified), globals, st, sc);
    Buf err = BUF_INIT;
    p = resolve_program(p, globals, st, &err);
    buf_free(&err);
    return p;
}

const char *program_read(const char *path, Buf *text, Buf *err)
{
    /* regular files only, opened without blocking: a FIFO named as the
     * script must not hold the run in open() */
    if (!file_read_regular(path, text)) {
        buf_printf(err, "%s: error: cannot read: %s\n", path,
                   errno == EINVAL ? "not a regular file" : strerror(errno));
        return NULL;
    }
    return text->data ? text->data : "";
}

Program *program_load(const char *path, Globals *globals, SymTab *st, Buf *err)
{
    Buf text = BUF_INIT;
    const char *src = program_read(path, &text, err);
    Program *p = src ? program_load_text(path, src, text.len, globals, st, err) : NULL;
    buf_free(&text);
    return p;
}

void program_release(Program *p)
{
    if (!p || --p->refs) return;
    ast_free(p->top);
    ast_free(p->simplified);
    free(p->asserted);
    for (uint32_t i = 0; i < p->npragmas; i++) {
        str_release(p->pragmas[i].name);
        vec_release(p->pragmas[i].value);
    }
    free(p->pragmas);
    free(p->path);
    free(p->dir);
    buf_free(&p->warnings);
    pathlist_clear(&p->files);
    free(p);
}

void pathlist_add(PathList *l, const char *path)
{
    for (uint32_t i = 0; i < l->count; i++)
        if (strcmp(l->paths[i], path) == 0) return;
    if (l->count == l->cap) {
        l->cap = l->cap ? l->cap * 2 : 4;
        l->paths = mem_realloc(l->paths, l->cap * sizeof *l->paths);
    }
    l->paths[l->count++] = mem_strdup(path);
}

void pathlist_add_all(PathList *l, const PathList *from)
{
    for (uint32_t i = 0; i < from->count; i++) pathlist_add(l, from->paths[i]);
}

void pathlist_clear(PathList *l)
{
    for (uint32_t i = 0; i < l->count; i++) free(l->paths[i]);
    free(l->paths);
    *l = (PathList){0};
}
