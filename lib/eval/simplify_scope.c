/* simplify_scope.c: the simplifier's names and scopes (LANGUAGE.md §4.17;
 * the rules follow tree.pyx `Name`, `Let`, `For`, `Function`, `Call`,
 * `Include`, `Import` and `Export._simplify`).
 *
 * While simplifying, every visible name stands for one of: a dynamic value
 * (known only when the program runs), a literal, another name (a rename
 * left by `let a=b`), or an inlineable function. Scopes are a stack of such
 * bindings; leaving a scope truncates the stack.
 */
#include "simplify_internal.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "builtins.h"
#include "mem.h"
#include "stable.h"

AstNode *simp_sequence_of(Simp *s, AstNode **items, uint32_t n, uint32_t cap, Loc loc);

/* ====================================================================
 * The scope stack
 * ==================================================================== */

static uint32_t name_hash(const Str *name)
{
    uint32_t h = 2166136261u;   /* FNV-1a */
    for (uint32_t i = 0; i < name->len; i++) h = (h ^ (unsigned char)name->bytes[i]) * 16777619u;
    return h;
}

/* Chain entry [i] into the bucket of its hash (entries are chained from
 * the innermost down). */
static void scope_link(Simp *s, uint32_t i)
{
    uint32_t *head = &s->heads[s->names[i].hash & (s->nheads - 1)];
    s->names[i].prev = *head;
    *head = i + 1;
}

/* The innermost entry binding [name] below index [below], or NULL. */
static NameBind *scope_find_below(Simp *s, const Str *name, uint32_t below)
{
    if (!s->nheads) return NULL;
    uint32_t h = name_hash(name);
    for (uint32_t i = s->heads[h & (s->nheads - 1)]; i; i = s->names[i - 1].prev) {
        NameBind *e = &s->names[i - 1];
        if (i - 1 < below && e->hash == h && str_eq(e->name, name)) return e;
    }
    return NULL;
}

NameBind *scope_find(Simp *s, const Str *name)
{
    return scope_find_below(s, name, s->nnames);
}

void scope_push(Simp *s, Str *name, int kind, const Vec *value, Str *target, const AstNode *fn)
{
    if (s->nnames == s->capnames) {
        s->capnames = s->capnames ? s->capnames * 2 : 64;
        s->names = realloc(s->names, s->capnames * sizeof *s->names);
        if (!s->names) mem_oom();
    }
    uint32_t i = s->nnames++;
    s->names[i] = (NameBind){str_retain(name), kind, vec_retain((Vec *)value),
                             str_retain(target), fn, name_hash(name), 0, NULL};
    if (kind == NB_RENAME) {
        if (s->nrenames == s->caprenames) {
            s->caprenames = s->caprenames ? s->caprenames * 2 : 16;
            s->renames = realloc(s->renames, s->caprenames * sizeof *s->renames);
            if (!s->renames) mem_oom();
        }
        s->renames[s->nrenames++] = i;
    }
    if (s->nnames > s->nheads) {   /* grow: at most one entry a bucket on average */
        s->nheads = s->nheads ? s->nheads * 2 : 64;
        free(s->heads);
        s->heads = calloc(s->nheads, sizeof *s->heads);
        if (!s->heads) mem_oom();
        for (uint32_t k = 0; k < s->nnames; k++) scope_link(s, k);
    } else {
        scope_link(s, i);
    }
}

void scope_push_col(Simp *s, Str *name, const Vec *value, Column *col)
{
    scope_push(s, name, NB_LITERAL, value, NULL, NULL);
    s->names[s->nnames - 1].col = col_retain(col);
}

void scope_restore(Simp *s, uint32_t mark)
{
    while (s->nnames > mark) {
        NameBind *b = &s->names[--s->nnames];
        s->heads[b->hash & (s->nheads - 1)] = b->prev;
        if (b->kind == NB_RENAME) s->nrenames--;
        str_release(b->name);
        vec_release(b->value);
        str_release(b->target);
        col_release(b->col);
    }
}

static bool is_dynamic_builtin(const Builtin *bi) { return bi && (bi->flags & BI_DYNAMIC); }

const Vec *simp_builtin(Simp *s, const Str *name)
{
    for (uint32_t i = 0; i < s->nbuiltins; i++)
        if (str_eq(s->builtin_names[i], name)) return s->builtins[i];
    const Builtin *bi = bi_lookup(name->bytes, name->len);
    if (!bi) return NULL;
    Func *f = calloc(1, sizeof *f);
    if (!f) mem_oom();
    f->refs = 1;
    f->bi = bi;
    f->bi_name = bi->internal;
    if (s->nbuiltins == s->capbuiltins) {
        s->capbuiltins = s->capbuiltins ? s->capbuiltins * 2 : 16;
        s->builtins = realloc(s->builtins, s->capbuiltins * sizeof *s->builtins);
        s->builtin_names = realloc(s->builtin_names, s->capbuiltins * sizeof *s->builtin_names);
        if (!s->builtins || !s->builtin_names) mem_oom();
    }
    s->builtins[s->nbuiltins] = vec_func_take(f);
    s->builtin_names[s->nbuiltins] = str_retain((Str *)name);
    return s->builtins[s->nbuiltins++];
}

/* Builtin constants (LANGUAGE.md §5.1): true with *out set, NULL for null. */
static bool builtin_constant(const Str *name, Vec **out)
{
    static const struct { const char *name; double value; } table[] = {
        {"true", 1.0}, {"false", 0.0}, {"inf", 1.0 / 0.0}, {"nan", 0.0 / 0.0},
        {"pi", 3.141592653589793}, {"\xcf\x80", 3.141592653589793},
        {"tau", 6.283185307179586}, {"\xf0\x9d\x9c\x8f", 6.283185307179586},
    };
    if (strcmp(name->bytes, "null") == 0) {
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

/* True when [name] is a builtin (static or dynamic). */
static bool is_builtin_name(const Str *name)
{
    Vec *v;
    if (builtin_constant(name, &v)) {
        vec_release(v);
        return true;
    }
    return bi_lookup(name->bytes, name->len) != NULL;
}

/* ====================================================================
 * Free names (tree.pyx unbound_names)
 * ==================================================================== */

bool nameset_has(const NameSet *set, const Str *name)
{
    if (set->index) {
        uint32_t mask = set->nindex - 1;
        for (uint32_t i = name_hash(name) & mask; set->index[i]; i = (i + 1) & mask)
            if (str_eq(set->v[set->index[i] - 1], name)) return true;
        return false;
    }
    for (uint32_t i = 0; i < set->n; i++)
        if (str_eq(set->v[i], name)) return true;
    return false;
}

/* Put v[k] into the hash index (which has room). */
static void nameset_index(NameSet *set, uint32_t k)
{
    uint32_t mask = set->nindex - 1, i = name_hash(set->v[k]) & mask;
    while (set->index[i]) i = (i + 1) & mask;
    set->index[i] = k + 1;
}

static void nameset_add(NameSet *set, const Str *name)
{
    if (nameset_has(set, name)) return;
    if (set->n == set->cap) {
        set->cap = set->cap ? set->cap * 2 : 8;
        set->v = realloc(set->v, set->cap * sizeof *set->v);
        if (!set->v) mem_oom();
    }
    set->v[set->n++] = name;
    if (set->n <= 16) return;   /* a linear search is quicker */
    if (2 * set->n > set->nindex) {   /* keep the load under 1/2 */
        set->nindex = set->nindex ? set->nindex * 2 : 64;
        free(set->index);
        set->index = calloc(set->nindex, sizeof *set->index);
        if (!set->index) mem_oom();
        for (uint32_t k = 0; k < set->n; k++) nameset_index(set, k);
    } else {
        nameset_index(set, set->n - 1);
    }
}

void nameset_free(NameSet *set)
{
    free(set->v);
    free(set->index);
    *set = (NameSet){0};
}

typedef struct Bound {
    const Str **v;
    uint32_t n, cap;
} Bound;

static void bound_push(Bound *b, const Str *name)
{
    if (b->n == b->cap) {
        b->cap = b->cap ? b->cap * 2 : 16;
        b->v = realloc(b->v, b->cap * sizeof *b->v);
        if (!b->v) mem_oom();
    }
    b->v[b->n++] = name;
}

static bool bound_has(const Bound *b, const Str *name)
{
    for (uint32_t i = b->n; i-- > 0;)
        if (str_eq(b->v[i], name)) return true;
    return false;
}

static void walk_free(const AstNode *n, NameSet *out, Bound *b)
{
    if (!n) return;
    uint32_t mark = b->n;
    switch (n->kind) {
    case AST_NAME:
        if (!bound_has(b, n->names[0])) nameset_add(out, n->names[0]);
        return;
    case AST_EXPORT:
        if (n->op != EXPORT_MAIN) out->all = true;
        return;
    case AST_LET:
        for (uint32_t i = 0; i < n->nkids; i++) {
            walk_free(n->kids[i]->a, out, b);
            for (uint32_t j = 0; j < n->kids[i]->nnames; j++) bound_push(b, n->kids[i]->names[j]);
        }
        walk_free(n->a, out, b);
        b->n = mark;
        return;
    case AST_FOR:
    case AST_IMPORT:
        walk_free(n->a, out, b);
        for (uint32_t j = 0; j < n->nnames; j++) bound_push(b, n->names[j]);
        walk_free(n->b, out, b);
        b->n = mark;
        return;
    case AST_FUNCTION:
        for (uint32_t i = 0; i < n->nkids; i++) walk_free(n->kids[i]->a, out, b);
        bound_push(b, n->names[0]);
        for (uint32_t i = 0; i < n->nkids; i++) bound_push(b, n->kids[i]->names[0]);
        walk_free(n->a, out, b);
        b->n = mark;
        return;
    case AST_TOP:
        walk_free(n->a, out, b);
        return;
    default:
        break;
    }
    walk_free(n->a, out, b);
    walk_free(n->b, out, b);
    walk_free(n->c, out, b);
    for (uint32_t i = 0; i < n->nkids; i++) {
        const AstNode *k = n->kids[i];
        if (k && k->kind == AST_BINDING) walk_free(k->a, out, b);
        else walk_free(k, out, b);
    }
}

void free_names(const AstNode *n, NameSet *out)
{
    Bound b = {0};
    walk_free(n, out, &b);
    free(b.v);
}

/* ====================================================================
 * Names
 * ==================================================================== */

/* A numeric vector as a new object equal to [v] (tree.pyx Name gives each
 * use of a let-bound literal its own copy, so `q == q` with q = nan is
 * false: no identity shortcut, §3.6); other vectors are shared. */
static Vec *vec_fresh(const Vec *v)
{
    if (vec_is_num(v)) return vec_from_nums(vec_cnums(v), v->len);
    return vec_retain((Vec *)v);
}

/* The shared value of builtin constant [name] (one Vec per name, so that
 * `nan == nan` is true by identity as in the reference). */
static bool constant_value(Simp *s, const Str *name, Vec **out)
{
    Vec *v;
    if (!builtin_constant(name, &v)) return false;
    if (!v) {
        *out = NULL;
        return true;
    }
    for (uint32_t i = 0; i < s->nconsts; i++) {
        if (str_eq(s->const_names[i], name)) {
            vec_release(v);
            *out = vec_retain(s->consts[i]);
            return true;
        }
    }
    if (s->nconsts == s->capconsts) {
        s->capconsts = s->capconsts ? s->capconsts * 2 : 8;
        s->consts = realloc(s->consts, s->capconsts * sizeof *s->consts);
        s->const_names = realloc(s->const_names, s->capconsts * sizeof *s->const_names);
        if (!s->consts || !s->const_names) mem_oom();
    }
    s->consts[s->nconsts] = v;
    s->const_names[s->nconsts++] = str_retain((Str *)name);
    *out = vec_retain(v);
    return true;
}

AstNode *simp_name(Simp *s, const AstNode *n)
{
    const Str *name = n->names[0];
    NameBind *nb = scope_find(s, name);
    if (nb) {
        switch (nb->kind) {
        case NB_LITERAL: {
            Column *c = NULL;
            if (s->tg && nb->col && nb->col->num) {
                /* numbers: nothing shared to copy */
                c = col_new_num(s->tg);
                memcpy(c->num, nb->col->num, (size_t)s->tg * sizeof *c->num);
            } else if (s->tg && nb->col && nb->col->flat && (c = col_new_flat(s->tg, nb->col->w))) {
                /* fresh numbers, as vec_fresh makes */
                memcpy(c->flat, nb->col->flat, (size_t)s->tg * nb->col->w * sizeof *c->flat);
            } else if (s->tg && nb->col && (nb->col->key || nb->col->node)) {
                c = col_retain(nb->col);   /* streams and nodes: vec_fresh shares them */
            } else if (s->tg && nb->col) {   /* a plain column, or a flat one past the budget */
                c = col_new(s->tg);
                for (uint32_t m = 0; m < s->tg; m++) {
                    const Vec *x = col_get(nb->col, m);
                    c->v[m] = x ? vec_fresh(x) : NULL;
                }
            }
            return tlit(s, nb->value ? vec_fresh(nb->value) : NULL, c, n->loc);
        }
        case NB_RENAME: {
            AstNode *t = ast_name(str_retain(nb->target), n->loc);
            return resimp(s, t);
        }
        default: return ast_copy(n);
        }
    }
    /* a builtin function met before (every unrolled iteration names the
     * same ones): its shared vector, without the scans below; builtin
     * functions and constants have no name in common */
    for (uint32_t i = 0; i < s->nbuiltins; i++)
        if (str_eq(s->builtin_names[i], name)) return mk_lit(vec_retain(s->builtins[i]), n->loc);
    Vec *v;
    if (constant_value(s, name, &v)) return mk_lit(v, n->loc);
    const Builtin *bi = bi_lookup(name->bytes, name->len);
    if (bi && !is_dynamic_builtin(bi)) return mk_lit(vec_retain((Vec *)simp_builtin(s, name)), n->loc);
    if (bi) return ast_copy(n);
    char msg[300];
    snprintf(msg, sizeof msg, "Unbound name '%s'", name->bytes);
    simp_warn(s, msg);
    return mk_lit(NULL, n->loc);
}

/* ====================================================================
 * let
 * ==================================================================== */

AstNode *mk_binding1(Str *name, AstNode *value, Loc loc)
{
    AstNode *b = ast_new(AST_BINDING, loc);
    ast_push_name(b, str_retain(name));
    b->a = value;
    return b;
}

/* A growable list of AST_BINDING nodes. */
typedef struct BList {
    AstNode **v;
    uint32_t n, cap;
    uint32_t id;     /* `let stable` id for mk_let (0: none) */
} BList;

static void blist_push(BList *l, AstNode *b)
{
    if (l->n == l->cap) {
        l->cap = l->cap ? l->cap * 2 : 8;
        l->v = realloc(l->v, l->cap * sizeof *l->v);
        if (!l->v) mem_oom();
    }
    l->v[l->n++] = b;
}

static bool names_has(const AstNode *binding, const Str *name)
{
    for (uint32_t j = 0; j < binding->nnames; j++)
        if (str_eq(binding->names[j], name)) return true;
    return false;
}

static AstNode *mk_let(BList *rem, AstNode *body, int op, Loc loc)
{
    AstNode *l = ast_new(AST_LET, loc);
    l->op = (uint8_t)op;
    l->count = rem->id;
    for (uint32_t i = 0; i < rem->n; i++) ast_push(l, rem->v[i]);
    rem->n = 0;
    l->a = body;
    return l;
}

/* A `let stable` [let] (consumed) whose keys ([id], i) are known stable:
 * its body simplified again with those values as literals (tree.pyx
 * LetStable._simplify). */
static AstNode *stable_body(Simp *s, AstNode *let, uint32_t id)
{
    let->count = id;
    if (!s->stables || !id) return let;
    uint32_t mark = s->nnames;
    for (uint32_t i = 0; i < let->nkids; i++) {
        if (!stable_is_stable(s->stables, id, i)) continue;
        const Vec *v = stable_value(s->stables, id, i);
        const AstNode *b = let->kids[i];
        for (uint32_t j = 0; j < b->nnames; j++) {
            Vec *item = b->nnames == 1 ? vec_retain((Vec *)v) : vec_item(v, j);
            scope_push(s, b->names[j], NB_LITERAL, item, NULL, NULL);
            vec_release(item);
        }
    }
    if (s->nnames != mark) {
        AstNode *body = let->a;
        let->a = simp(s, body);
        ast_free(body);
    }
    scope_restore(s, mark);
    return let;
}

AstNode *simp_let(Simp *s, const AstNode *n)
{
    uint32_t mark = s->nnames;
    /* gather the bindings of directly nested lets of the same kind */
    const AstNode **bind = NULL;
    uint32_t nb = 0, capb = 0;
    const AstNode *body = n;
    while (body && body->kind == AST_LET && body->op == n->op) {
        for (uint32_t i = 0; i < body->nkids; i++) {
            if (nb == capb) {
                capb = capb ? capb * 2 : 8;
                bind = realloc(bind, capb * sizeof *bind);
                if (!bind) mem_oom();
            }
            bind[nb++] = body->kids[i];
        }
        body = body->a;
    }
    BList rem = {.id = n->op == 1 ? n->count : 0};
    NameSet shadowed = {0}, discarded = {0};
    /* names currently standing for other names (renames) */
    for (uint32_t i = 0; i < nb; i++) {
        const AstNode *b = bind[i];
        for (uint32_t j = 0; j < b->nnames; j++) {
            const Str *target = b->names[j];
            if (nameset_has(&shadowed, target)) continue;
            bool any = false;
            uint32_t top = s->nrenames;
            for (uint32_t r = 0; r < top; r++) {
                NameBind *e = &s->names[s->renames[r]];
                if (!str_eq(e->target, target)) continue;
                if (scope_find(s, e->name) != e) continue;   /* not the visible binding */
                Str *alias = str_retain(e->name);
                blist_push(&rem, mk_binding1(alias, ast_name(str_retain((Str *)target), b->loc), b->loc));
                scope_push(s, alias, NB_DYNAMIC, NULL, NULL, NULL);
                str_release(alias);
                any = true;
            }
            if (any) nameset_add(&shadowed, target);
        }
        AstNode *expr = simp(s, b->a);
        if (b->nnames == 1 && expr->kind == AST_FUNCTION && (expr->op & FN_INLINEABLE)) {
            AstNode *nbnd = mk_binding1(b->names[0], expr, b->loc);
            blist_push(&rem, nbnd);
            scope_push(s, b->names[0], NB_FUNCTION, NULL, NULL, expr);
            continue;
        }
        if (is_lit(expr)) {
            Column *ec = s->tg && has_col(expr) ? (Column *)expr->aux : NULL;
            if (b->nnames == 1) {
                scope_push_col(s, b->names[0], expr->value, ec);
                nameset_add(&discarded, b->names[0]);
            } else {
                for (uint32_t j = 0; j < b->nnames; j++) {
                    Vec *item = vec_item(expr->value, j);
                    Column *c = NULL;
                    if (ec) {
                        c = col_new(s->tg);
                        for (uint32_t m = 0; m < s->tg; m++) c->v[m] = vec_item(col_get(ec, m), j);
                    }
                    scope_push_col(s, b->names[j], item, c);
                    col_release(c);
                    vec_release(item);
                    nameset_add(&discarded, b->names[j]);
                }
            }
            ast_free(expr);
            continue;
        }
        if (b->nnames == 1 && expr->kind == AST_NAME) {
            const Str *target = expr->names[0];
            if (str_eq(target, b->names[0])) {
                ast_free(expr);
                continue;
            }
            bool later = false;
            for (uint32_t k = i + 1; k < nb && !later; k++) later = names_has(bind[k], target);
            if (later) {
                nameset_add(&shadowed, target);
            } else {
                scope_push(s, b->names[0], NB_RENAME, NULL, (Str *)target, NULL);
                nameset_add(&discarded, b->names[0]);
                ast_free(expr);
                continue;
            }
        }
        AstNode *nbnd = ast_new(AST_BINDING, b->loc);
        for (uint32_t j = 0; j < b->nnames; j++) {
            ast_push_name(nbnd, str_retain(b->names[j]));
            scope_push(s, b->names[j], NB_DYNAMIC, NULL, NULL, NULL);
        }
        nbnd->a = expr;
        blist_push(&rem, nbnd);
    }
    bool resimplify = false;
    for (uint32_t i = 0; i < shadowed.n && !resimplify; i++)
        resimplify = nameset_has(&discarded, shadowed.v[i]);
    AstNode *sbody = simp(s, body);
    scope_restore(s, mark);
    free(bind);
    nameset_free(&shadowed);
    nameset_free(&discarded);
    if (is_lit(sbody)) {
        for (uint32_t i = 0; i < rem.n; i++) ast_free(rem.v[i]);
        free(rem.v);
        return sbody;
    }
    /* drop bindings nothing uses (none left: no names to gather) */
    NameSet used = {0};
    if (rem.n) free_names(sbody, &used);
    if (rem.n && !used.all) {
        uint32_t keep = rem.n;
        for (uint32_t i = rem.n; i-- > 0;) {
            AstNode *b = rem.v[i];
            bool needed = false;
            for (uint32_t j = 0; j < b->nnames && !needed; j++) needed = nameset_has(&used, b->names[j]);
            if (needed) {
                free_names(b->a, &used);
            } else {
                ast_free(b);
                rem.v[i] = NULL;
                keep--;
            }
        }
        uint32_t k = 0;
        for (uint32_t i = 0; i < rem.n; i++)
            if (rem.v[i]) rem.v[k++] = rem.v[i];
        rem.n = keep;
    }
    nameset_free(&used);
    if (sbody->kind == AST_LET && sbody->op == n->op) {
        for (uint32_t i = 0; i < sbody->nkids; i++) blist_push(&rem, sbody->kids[i]);
        sbody->nkids = 0;
        AstNode *inner = sbody->a;
        sbody->a = NULL;
        ast_free(sbody);
        sbody = inner;
        resimplify = true;
    }
    if (rem.n) {
        if (sbody->kind == AST_SEQUENCE && sbody->nkids >= 2 && is_lit(sbody->kids[0])) {
            AstNode *seq = ast_new(AST_SEQUENCE, sbody->loc);
            ast_push(seq, sbody->kids[0]);
            AstNode *rest;
            if (sbody->nkids > 2) {
                rest = ast_new(AST_SEQUENCE, sbody->loc);
                for (uint32_t i = 1; i < sbody->nkids; i++) ast_push(rest, sbody->kids[i]);
            } else {
                rest = sbody->kids[1];
                if (rest->kind == AST_LET && rest->op == n->op) resimplify = true;
            }
            sbody->nkids = 0;
            ast_free(sbody);
            ast_push(seq, mk_let(&rem, rest, n->op, n->loc));
            sbody = seq;
        } else {
            sbody = mk_let(&rem, sbody, n->op, n->loc);
        }
    }
    free(rem.v);
    if (resimplify) sbody = resimp(s, sbody);
    if (n->op == 1 && sbody->kind == AST_LET && sbody->op == 1) return stable_body(s, sbody, n->count);
    return sbody;
}

/* ====================================================================
 * for
 * ==================================================================== */

AstNode *simp_for(Simp *s, const AstNode *n)
{
    AstNode *src = simp(s, n->a);
    uint32_t mark = s->nnames;
    bool unroll = is_lit(src);
    if (unroll) {
        uint64_t copies = (uint64_t)tdecide(s, src, TD_LEN, 0) / (n->nnames ? n->nnames : 1) + 1;
        /* in a template pass each member unrolls its own copies */
        uint64_t members = s->tg ? s->tg : 1;
        if (s->unrolled + copies * members > SIMP_MAX_UNROLL) {
            if (s->tg) s->tabort = true;   /* members would differ in where the limit falls */
            simp_warn(s, "Loop too long to unroll at load time; it is run as a loop");
            unroll = false;
        } else {
            s->unrolled += copies * members;
        }
    }
    if (!unroll) {
        for (uint32_t j = 0; j < n->nnames; j++) scope_push(s, n->names[j], NB_DYNAMIC, NULL, NULL, NULL);
        AstNode *body = simp(s, n->b);
        scope_restore(s, mark);
        AstNode *f = ast_new(AST_FOR, n->loc);
        for (uint32_t j = 0; j < n->nnames; j++) ast_push_name(f, str_retain(n->names[j]));
        f->a = src;
        f->b = body;
        return f;
    }
    const Vec *values = src->value;
    uint32_t len = vec_len(values), k = n->nnames ? n->nnames : 1;
    uint32_t cap = len / k + 1, count = 0;
    AstNode **items = malloc(cap * sizeof *items);
    if (!items) mem_oom();
    uint32_t nitems = (len + k - 1) / k;
    if (!s->tg && nitems > 1 && simp_unroll_templates(s, n, values, nitems, items, &nitems)) {
        ast_free(src);
        return simp_sequence_of(s, items, nitems, cap, n->loc);
    }
    Column *scol = s->tg && has_col(src) ? (Column *)src->aux : NULL;
    for (uint32_t i = 0; i < len;) {
        for (uint32_t j = 0; j < n->nnames; j++, i++) {
            Vec *item = i < len ? vec_item(values, i) : NULL;
            Column *c = NULL;
            if (scol) {   /* a nested loop over a source that differs between members */
                c = col_new(s->tg);
                for (uint32_t m = 0; m < s->tg; m++) c->v[m] = i < len ? vec_item(col_get(scol, m), i) : NULL;
            }
            scope_push_col(s, n->names[j], item, c);
            col_release(c);
            vec_release(item);
        }
        if (!n->nnames) i++;
        items[count++] = simp(s, n->b);
        scope_restore(s, mark);
    }
    ast_free(src);
    return simp_sequence_of(s, items, count, cap, n->loc);
}

/* ====================================================================
 * Functions and calls
 * ==================================================================== */

AstNode *simp_function(Simp *s, const AstNode *n)
{
    AstNode *f = ast_new(AST_FUNCTION, n->loc);
    bool literal = true;
    for (uint32_t i = 0; i < n->nkids; i++) {
        const AstNode *p = n->kids[i];
        AstNode *np = ast_new(AST_BINDING, p->loc);
        ast_push_name(np, str_retain(p->names[0]));
        np->a = p->a ? simp(s, p->a) : NULL;
        if (np->a && !is_lit(np->a)) literal = false;
        ast_push(f, np);
    }
    ast_push_name(f, str_retain(n->names[0]));
    uint32_t mark = s->nnames;
    scope_push(s, n->names[0], NB_DYNAMIC, NULL, NULL, NULL);
    for (uint32_t i = 0; i < n->nkids; i++)
        scope_push(s, n->kids[i]->names[0], NB_DYNAMIC, NULL, NULL, NULL);
    f->a = simp(s, n->a);
    /* captures: free names of the body that are neither parameters nor
     * builtins visible as builtins here (shadowed builtins count) */
    NameSet fr = {0};
    free_names(f->a, &fr);
    bool captures = false;
    for (uint32_t i = 0; i < fr.n && !captures; i++) {
        const Str *name = fr.v[i];
        if (str_eq(name, n->names[0])) continue;   /* recursion */
        bool param = false;
        for (uint32_t j = 0; j < n->nkids && !param; j++) param = str_eq(n->kids[j]->names[0], name);
        if (param) continue;
        /* a builtin name counts as bound unless the enclosing scope binds it */
        bool outer = scope_find_below(s, name, mark) != NULL;
        if (is_builtin_name(name) && !outer) continue;
        captures = true;
    }
    nameset_free(&fr);
    scope_restore(s, mark);
    f->op = (uint8_t)((captures ? FN_CAPTURES : 0) | (literal && !captures ? FN_INLINEABLE : 0));
    return f;
}

/* Inline the call of the capture-free function [fn] with simplified
 * arguments; NULL when the inlining depth limit was reached. */
static AstNode *inline_call(Simp *s, const AstNode *fn, AstNode **args, uint32_t nargs,
                            AstNode **kw, uint32_t nkw, Loc loc)
{
    BList binds = {0}, renames = {0};
    int j = 0;
    for (uint32_t i = 0; i < fn->nkids; i++) {
        const AstNode *p = fn->kids[i];
        AstNode *expr = NULL;
        if (i < nargs) {
            expr = ast_copy(args[i]);
        } else {
            for (uint32_t k = 0; k < nkw && !expr; k++)
                if (str_eq(kw[k]->names[0], p->names[0])) expr = ast_copy(kw[k]->a);
            if (!expr) expr = p->a ? ast_copy(p->a) : mk_lit(NULL, loc);
        }
        Str *name = str_retain(p->names[0]);
        while (scope_find(s, name)) {
            char tmp[32];
            snprintf(tmp, sizeof tmp, "__t%d", j++);
            str_release(name);
            name = str_from(tmp);
        }
        blist_push(&binds, mk_binding1(name, expr, loc));
        if (!str_eq(name, p->names[0]))
            blist_push(&renames, mk_binding1(p->names[0], ast_name(str_retain(name), loc), loc));
        str_release(name);
    }
    for (uint32_t i = 0; i < renames.n; i++) blist_push(&binds, renames.v[i]);
    free(renames.v);
    AstNode *let = mk_let(&binds, ast_copy(fn->a), 0, loc);
    free(binds.v);
    if (s->call_depth == SIMP_MAX_INLINE_DEPTH) {
        ast_free(let);
        s->unwinding = true;
        return NULL;
    }
    s->call_depth++;
    AstNode *r = resimp(s, let);
    s->call_depth--;
    if (s->unwinding) {
        ast_free(r);
        if (s->call_depth == 0) s->unwinding = false;   /* the outermost call gives up */
        return NULL;
    }
    return r;
}

/* Call every builtin of the literal [fn] with literal arguments at load
 * time (errors become warnings). */
static Vec *call_value(Simp *s, AstNode *call)
{
    Vec *v = eval_expr(&s->ev, call);
    for (uint32_t i = 0; i < s->errors.count; i++) simp_warn(s, s->errors.items[i]);
    msgset_clear(&s->errors);
    return v;
}

/* In a template pass, the stream column of `uniform(x)`, `normal(x)` or
 * `beta(x)` called at load time with one argument [x] whose members are
 * numbers (a numeric or flat column): each member's stream keyed by the
 * seed hash of its numbers, as the builtin keys it (random.c), without a
 * call or a vector a member; NULL for any other call. */
static Column *stream_col(Simp *s, const AstNode *call)
{
    if (!s->tg || call->nkids != 1 || call->count != 1 || has_col(call->a) || !has_col(call->kids[0]))
        return NULL;
    const Vec *fn = call->a->value;
    if (!vec_is_obj(fn) || fn->len != 1 || vec_celems(fn)[0].kind != EL_FUNC) return NULL;
    int kind = bi_stream_kind(vec_celems(fn)[0].func->bi);
    const Column *a = call->kids[0]->aux;
    if (kind < 0 || (!a->num && !a->flat)) return NULL;
    const double *x = a->num ? a->num : a->flat;
    uint32_t w = a->num ? 1 : a->w;
    Column *c = col_new_keys(s->tg, (uint8_t)kind);
    for (uint32_t m = 0; m < s->tg; m++) c->key[m] = vec_hash_nums(x + (size_t)m * w, w, true);
    return c;
}

static AstNode *call_now(Simp *s, AstNode *call)
{
    Column *c = stream_col(s, call);
    if (!c) c = tcol_eval(s, call, call_value);
    return tlit(s, call_value(s, call), c, call->loc);
}

AstNode *simp_call(Simp *s, const AstNode *n)
{
    AstNode *fn = simp(s, n->a);
    const AstNode *fexpr = NULL;
    if (fn->kind == AST_FUNCTION) {
        if (!(fn->op & FN_CAPTURES)) fexpr = fn;
    } else if (fn->kind == AST_NAME) {
        NameBind *nb = scope_find(s, fn->names[0]);
        if (nb && nb->kind == NB_FUNCTION) fexpr = nb->fn;
    }
    if (is_lit(fn) && tdecide(s, fn, TD_NULL, 0)) return fn;
    AstNode *c = ast_new(AST_CALL, n->loc);
    c->op = n->op;
    c->count = n->count;
    bool all_lit = true;
    for (uint32_t i = 0; i < n->nkids; i++) {
        const AstNode *k = n->kids[i];
        AstNode *sk;
        if (k->kind == AST_BINDING) {
            sk = ast_new(AST_BINDING, k->loc);
            ast_push_name(sk, str_retain(k->names[0]));
            sk->a = simp(s, k->a);
            if (!is_lit(sk->a)) all_lit = false;
        } else {
            sk = simp(s, k);
            if (!is_lit(sk)) all_lit = false;
        }
        ast_push(c, sk);
    }
    c->a = fn;
    if (is_lit(fn) && all_lit) {
        AstNode *r = call_now(s, c);
        ast_free(c);
        return r;
    }
    if (fexpr) {
        AstNode *r = inline_call(s, fexpr, c->kids, c->count,
                                 c->kids ? c->kids + c->count : NULL,
                                 c->nkids - c->count, n->loc);
        if (r) {
            ast_free(c);
            return r;
        }
        if (s->unwinding) return c;   /* an enclosing call gives up too */
    }
    return c;
}
