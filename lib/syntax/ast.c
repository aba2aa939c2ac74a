/* ast.c: construction and destruction of the abstract syntax tree
 * (LANGUAGE.md §2.4, node shapes in ast.h).
 *
 * The grammar (grammar/parser.y) calls one builder per reduction; each builder
 * consumes every node, Str and Vec handed to it, so a tree is owned
 * by exactly one parent and freed with one ast_free() of its root. Lists that
 * the grammar grows left-recursively (statements, bindings, arguments,
 * parameters) are "holder" nodes: a node of the final kind (or AST_BINDING
 * for name lists) whose kids/names fill up before its fixed children are set.
 * Invariant: a node's fixed children (`a`, `b`, `c`) and kids are distinct
 * subtrees; names and values hold one reference each. Allocation failure
 * aborts, as everywhere in flitter (value.h).
 */
#include "ast.h"

#include <assert.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mem.h"
#include "pool.h"

/* {=====================================================================
 * Basic nodes
 * ===================================================================== */

AstNode *ast_new(AstKind kind, Loc loc)
{
    /* nodes and their kid and name arrays come from the active pool (the
     * runtime's while it loads a script): the simplifier makes and drops
     * several trees per unrolled iteration, and the pool's free lists reuse
     * their blocks where malloc and free cost far more; with no pool active
     * they are plain malloc blocks (pool.h) */
    AstNode *n = pool_alloc(sizeof *n);
    memset(n, 0, sizeof *n);
    n->kind = (uint8_t)kind;
    n->loc = loc;
    return n;
}

void ast_push(AstNode *n, AstNode *kid)
{
    if (n->nkids == UINT32_MAX) mem_oom();
    n->kids = pool_grow(n->kids, &n->cap_kids, n->nkids + 1, sizeof *n->kids);
    n->kids[n->nkids++] = kid;
}

void ast_push_name(AstNode *n, Str *s)
{
    if (n->nnames == UINT32_MAX) mem_oom();
    n->names = pool_grow(n->names, &n->cap_names, n->nnames + 1, sizeof *n->names);
    n->names[n->nnames++] = s;
}

/* Free the node itself and its owned scalars, not its subtrees. */
static void free_shallow(AstNode *n)
{
    for (uint32_t i = 0; i < n->nnames; i++)
        str_release(n->names[i]);
    pool_release(n->names, (size_t)n->cap_names * sizeof *n->names);
    vec_release(n->value);
    if (n->aux && n->aux_free)
        n->aux_free(n->aux);
    free(n->slots);
    pool_release(n->kids, (size_t)n->cap_kids * sizeof *n->kids);
    pool_release(n, sizeof *n);
}

/* Iterative so that long left-recursive chains (`1+1+1+...`) cannot
 * overflow the C stack: a work list of nodes still to free. */
void ast_free(AstNode *n)
{
    if (!n)
        return;
    /* small trees (the simplifier frees many) need no heap work list */
    AstNode *small[64];
    size_t len = 0, cap = sizeof small / sizeof small[0];
    AstNode **work = small;
    work[len++] = n;
    while (len) {
        AstNode *t = work[--len];
        size_t need = len + t->nkids + 3;
        if (need > cap) {
            while (cap < need)
                cap *= 2;
            if (work == small) {
                work = mem_realloc(NULL, cap * sizeof *work);
                memcpy(work, small, len * sizeof *work);
            } else {
                work = mem_realloc(work, cap * sizeof *work);
            }
        }
        if (t->a) work[len++] = t->a;
        if (t->b) work[len++] = t->b;
        if (t->c) work[len++] = t->c;
        for (uint32_t i = 0; i < t->nkids; i++)
            if (t->kids[i])
                work[len++] = t->kids[i];
        free_shallow(t);
    }
    if (work != small)
        free(work);
}

/* }===================================================================== */

/* {=====================================================================
 * Expression builders
 * ===================================================================== */

AstNode *ast_literal(Vec *value_take, Loc loc)
{
    AstNode *n = ast_new(AST_LITERAL, loc);
    n->value = value_take;
    return n;
}

AstNode *ast_literal_number(Vec *value_take, Loc loc)
{
    AstNode *n = ast_literal(value_take, loc);
    n->op = 1;
    return n;
}

AstNode *ast_name(Str *name_take, Loc loc)
{
    AstNode *n = ast_new(AST_NAME, loc);
    ast_push_name(n, name_take);
    return n;
}

AstNode *ast_unary(AstKind kind, AstNode *a, Loc loc)
{
    AstNode *n = ast_new(kind, loc);
    n->a = a;
    return n;
}

AstNode *ast_binary(AstKind kind, int op, AstNode *a, AstNode *b, Loc loc)
{
    AstNode *n = ast_new(kind, loc);
    n->op = (uint8_t)op;
    n->a = a;
    n->b = b;
    return n;
}

AstNode *ast_range(AstNode *start, AstNode *stop, AstNode *step, Loc loc)
{
    AstNode *n = ast_new(AST_RANGE, loc);
    n->a = start;
    n->b = stop;
    n->c = step;
    return n;
}

AstNode *ast_call(AstNode *callee, AstNode *args, Loc loc)
{
    uint32_t count = 0;
    while (count < args->nkids && args->kids[count]->kind != AST_BINDING)
        count++;
    args->kind = AST_CALL;
    args->a = callee;
    args->count = count;
    args->loc = loc;
    return args;
}

AstNode *ast_template(AstNode *callee, AstNode *attrs, AstNode *block, Loc loc)
{
    if (block) {
        ast_push(attrs, NULL);
        memmove(attrs->kids + 1, attrs->kids,
                (attrs->nkids - 1) * sizeof *attrs->kids);
        attrs->kids[0] = block;
    }
    attrs->kind = AST_CALL;
    attrs->op = 1;
    attrs->a = callee;
    attrs->count = block ? 1 : 0;
    attrs->loc = loc;
    return attrs;
}

AstNode *ast_tag(AstNode *node, Str *tag, Loc loc)
{
    AstNode *n = ast_new(AST_TAG, loc);
    n->a = node;
    ast_push_name(n, tag);
    return n;
}

AstNode *ast_attributes(AstNode *node, AstNode *binding, Loc loc)
{
    AstNode *n = ast_new(AST_ATTRIBUTES, loc);
    n->a = node;
    ast_push(n, binding);
    return n;
}

AstNode *ast_ifelse(AstNode *cond, AstNode *then, AstNode *els, Loc loc)
{
    AstNode *n = ast_new(AST_IFELSE, loc);
    ast_push(n, cond);
    ast_push(n, then);
    n->a = els;
    return n;
}

AstNode *ast_elif(AstNode *ifelse, AstNode *cond, AstNode *then, Loc loc)
{
    ast_push(ifelse, cond);
    ast_push(ifelse, then);
    ifelse->loc = loc;
    return ifelse;
}

AstNode *ast_else(AstNode *ifelse, AstNode *els, Loc loc)
{
    ifelse->a = els;
    ifelse->loc = loc;
    return ifelse;
}

/* }===================================================================== */

/* {=====================================================================
 * Lists, bindings and scoping constructs
 * ===================================================================== */

AstNode *ast_list(AstKind kind, AstNode *first, Loc loc)
{
    AstNode *n = ast_new(kind, loc);
    if (first)
        ast_push(n, first);
    return n;
}

AstNode *ast_add(AstNode *list, AstNode *kid, Loc loc)
{
    ast_push(list, kid);
    list->loc = loc;
    return list;
}

AstNode *ast_concat(AstNode *list, AstNode *more, Loc loc)
{
    for (uint32_t i = 0; i < more->nkids; i++)
        ast_push(list, more->kids[i]);
    more->nkids = 0;
    ast_free(more);
    list->loc = loc;
    return list;
}

AstNode *ast_names(Str *name, Loc loc)
{
    AstNode *n = ast_new(AST_BINDING, loc);
    ast_push_name(n, name);
    return n;
}

AstNode *ast_names_add(AstNode *holder, Str *name, Loc loc)
{
    ast_push_name(holder, name);
    holder->loc = loc;
    return holder;
}

AstNode *ast_binding(AstNode *names_holder, AstNode *value, Loc loc)
{
    AstNode *n = names_holder ? names_holder : ast_new(AST_BINDING, loc);
    n->kind = AST_BINDING;
    n->a = value;
    n->loc = loc;
    return n;
}

AstNode *ast_named(Str *name, AstNode *value, Loc loc)
{
    return ast_binding(ast_names(name, loc), value, loc);
}

AstNode *ast_param(Str *name, AstNode *dflt, Loc loc)
{
    return ast_named(name, dflt, loc);
}

AstNode *ast_let(AstNode *bindings, AstNode *body, int stable, Loc loc)
{
    bindings->kind = AST_LET;
    bindings->a = body;
    bindings->op = stable ? 1 : 0;
    bindings->loc = loc;
    return bindings;
}

AstNode *ast_let_block(AstNode *names, AstNode *block, AstNode *rest, Loc loc)
{
    AstNode *binding = ast_binding(names, block, loc);
    return ast_let(ast_list(AST_LET, binding, loc), rest, 0, loc);
}

AstNode *ast_function(Str *name, AstNode *params, AstNode *body, Loc loc)
{
    params->kind = AST_FUNCTION;
    ast_push_name(params, name ? name : str_from("<anon>"));
    params->a = body;
    params->loc = loc;
    return params;
}

AstNode *ast_func_let(Str *name, AstNode *params, AstNode *body,
                      AstNode *rest, Loc loc)
{
    AstNode *fn = ast_function(str_retain(name), params, body, loc);
    AstNode *binding = ast_named(name, fn, loc);
    return ast_let(ast_list(AST_LET, binding, loc), rest, 0, loc);
}

AstNode *ast_import(AstNode *names, AstNode *file, AstNode *rest, Loc loc)
{
    names->kind = AST_IMPORT;
    names->a = file;
    names->b = rest;
    names->loc = loc;
    return names;
}

AstNode *ast_for(AstNode *names, AstNode *source, AstNode *body, Loc loc)
{
    names->kind = AST_FOR;
    names->a = source;
    names->b = body;
    names->loc = loc;
    return names;
}

AstNode *ast_for_nest(AstNode *iterators, AstNode *body, Loc loc)
{
    assert(iterators->nkids > 0);
    for (uint32_t i = iterators->nkids; i-- > 0;) {
        AstNode *it = iterators->kids[i];
        it->b = body;
        it->loc.end = loc.end;
        body = it;
    }
    iterators->nkids = 0;
    ast_free(iterators);
    body->loc = loc;
    return body;
}

AstNode *ast_pragma(Str *name, AstNode *literal, Loc loc)
{
    AstNode *n = ast_names(name, loc);
    n->value = literal->value;
    literal->value = NULL;
    ast_free(literal);
    return n;
}

AstNode *ast_top(AstNode *pragmas, AstNode *body, Loc loc)
{
    pragmas->kind = AST_TOP;
    pragmas->a = body;
    pragmas->loc = loc;
    return pragmas;
}

/* }===================================================================== */

/* {=====================================================================
 * Flat sequences: heads and their bodies (ast.h, ast_sequence)
 * ===================================================================== */

/* Head kinds, in `scope` until ast_sequence() sets the body (0: no head). */
enum { HEAD_LET = 1, HEAD_LET_BLOCK, HEAD_FUNC, HEAD_ANON, HEAD_IMPORT, HEAD_DONE };

static AstNode *head(AstNode *n, int kind)
{
    n->scope = (uint8_t)kind;
    return n;
}

AstNode *ast_head_let(AstNode *bindings, int stable, Loc loc)
{
    return head(ast_let(bindings, NULL, stable, loc), HEAD_LET);
}

AstNode *ast_head_let_block(AstNode *names, AstNode *block, Loc loc)
{
    return head(ast_let_block(names, block, NULL, loc), HEAD_LET_BLOCK);
}

AstNode *ast_head_func(Str *name, AstNode *params, AstNode *body, Loc loc)
{
    return head(ast_func_let(name, params, body, NULL, loc), HEAD_FUNC);
}

AstNode *ast_head_anon(AstNode *params, AstNode *body, Loc loc)
{
    return head(ast_list(AST_SEQUENCE, ast_function(NULL, params, body, loc), loc), HEAD_ANON);
}

AstNode *ast_head_import(AstNode *names, AstNode *file, Loc loc)
{
    return head(ast_import(names, file, NULL, loc), HEAD_IMPORT);
}

AstNode *ast_sequence(AstNode *items, Loc loc)
{
    /* Right to left: the head at i takes items i+1.. (statements, then at
     * most the head folded before) as its rest. As in the right-recursive
     * rules, the rest starts where the head ends (an empty sequence sits
     * at the end of the symbol before it) and ends with the whole
     * sequence; the let_tail, and for `func` and `let x =` blocks its
     * binding and function, span from the keyword to that end. */
    uint32_t n = items->nkids;
    for (uint32_t i = n; i-- > 0;) {
        AstNode *h = items->kids[i];
        int kind = h ? h->scope : 0;
        if (!kind || kind == HEAD_DONE) {
            continue;
        }
        Loc rest_loc = {loc.file, h->loc.end, loc.end};
        Loc tail = {loc.file, h->loc.start, loc.end};
        AstNode *rest = ast_new(AST_SEQUENCE, rest_loc);
        for (uint32_t k = i + 1; k < n; k++)
            ast_push(rest, items->kids[k]);
        n = i + 1;
        h->scope = HEAD_DONE;
        h->loc = tail;
        switch (kind) {
        case HEAD_FUNC:
            h->kids[0]->a->loc = tail;
            /* fall through */
        case HEAD_LET_BLOCK:
            h->kids[0]->loc = tail;
            /* fall through */
        case HEAD_LET:
            h->a = rest;
            break;
        case HEAD_ANON:
            h->kids[0]->loc = tail;
            ast_push(h, rest);
            break;
        default:
            h->b = rest;
            break;
        }
    }
    items->nkids = n;
    /* Outermost first, merge each plain let whose rest is only another
     * plain let (let a=.. + (let b=.. + body) -> let a=.. b=.. + body):
     * every binding is moved once. Only the last item of a sequence can
     * be a head. */
    AstNode *seq = items;
    while (seq && seq->nkids) {
        AstNode *h = seq->kids[seq->nkids - 1];
        if (!h || h->scope != HEAD_DONE)
            break;
        h->scope = 0;
        if (h->kind == AST_LET) {
            AstNode *rest = h->a, *inner;
            while (h->op == 0 && rest->nkids == 1 && (inner = rest->kids[0])->scope == HEAD_DONE
                   && inner->kind == AST_LET && inner->op == 0) {
                for (uint32_t k = 0; k < inner->nkids; k++)
                    ast_push(h, inner->kids[k]);
                inner->nkids = 0;
                h->a = inner->a;
                inner->a = NULL;
                ast_free(rest);
                rest = h->a;
            }
            seq = h->a;
        } else if (h->kind == AST_IMPORT) {
            seq = h->b;
        } else {
            seq = h->kids[h->nkids - 1];
        }
    }
    items->loc = loc;
    return items;
}

static const char *const kind_names[] = {
    "Top", "Sequence", "Literal", "Name", "Lookup",
    "BinOp", "Neg", "Pos", "Not", "And", "Or", "Xor",
    "Compare", "Range", "Index", "Call", "Function", "Let",
    "Binding", "For", "IfElse", "Tag", "Attributes", "Append",
    "Import", "Include", "Export",
};
_Static_assert(sizeof kind_names / sizeof kind_names[0] == AST__COUNT,
               "kind_names must follow AstKind (ast.h)");

const char *ast_kind_name(AstKind kind)
{
    return (unsigned)kind < AST__COUNT ? kind_names[kind] : "?";
}
