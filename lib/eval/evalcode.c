/* evalcode.c: compiling the program's hot regions into contiguous record
 * blocks (evalcode.h). The records are run by eval.c (eval_code).
 */
#include "evalcode.h"

#include <stdlib.h>
#include <string.h>

#include "builtins.h"
#include "numexpr.h"
#include "program.h"

/* Most positional arguments of a compiled builtin call (eval_call's direct
 * route takes as many). */
#define CC_MAX_ARGS 8

typedef struct CC {
    unsigned char *buf;
    uint32_t len, cap;
    AstNode **later;        /* C_AST nodes whose subtrees are compiled next */
    uint32_t nlater, cap_later;
} CC;

/* [size] zeroed bytes at the end of the block (8-byte aligned); returns
 * their offset. */
static uint32_t reserve(CC *c, size_t size)
{
    size = (size + 7) & ~(size_t)7;
    while (c->len + size > c->cap) {
        c->cap = c->cap ? c->cap * 2 : 256;
        c->buf = realloc(c->buf, c->cap);
        if (!c->buf) abort();
    }
    uint32_t off = c->len;
    memset(c->buf + off, 0, size);
    c->len += (uint32_t)size;
    return off;
}

static CRec *rec(CC *c, uint32_t off) { return (CRec *)(void *)(c->buf + off); }

/* The builtin a callee resolves to at load time, or NULL. */
static const Builtin *const_builtin(const AstNode *fn)
{
    if (fn->kind != AST_LITERAL && (fn->kind != AST_NAME || fn->scope != SCOPE_CONST)) return NULL;
    const Vec *v = fn->value;
    if (!vec_is_obj(v) || v->len != 1 || vec_celems(v)[0].kind != EL_FUNC) return NULL;
    return vec_celems(v)[0].func->bi;
}

/* True when [n] has a record of its own kind (not C_AST). */
static bool compilable(const AstNode *n)
{
    if (n->fast || n->aux) return false;
    switch ((AstKind)n->kind) {
    case AST_SEQUENCE:
    case AST_APPEND:
        return true;
    case AST_LET:
        if (n->op != 0) return false;   /* `let stable`: stable.h */
        for (uint32_t i = 0; i < n->nkids; i++)
            if (!n->kids[i] || n->kids[i]->kind != AST_BINDING || n->kids[i]->nnames != 1) return false;
        return true;
    case AST_ATTRIBUTES:
        for (uint32_t i = 0; i < n->nkids; i++)
            if (!n->kids[i] || n->kids[i]->kind != AST_BINDING || n->kids[i]->nnames < 1) return false;
        return true;
    case AST_CALL:
        return n->count == n->nkids && n->nkids <= CC_MAX_ARGS && const_builtin(n->a);
    default:
        return false;
    }
}

static uint32_t emit(CC *c, const AstNode *n);

/* True when the bindings of [n] (AST_ATTRIBUTES) name pairwise different
 * attributes. */
static bool distinct_names(const AstNode *n)
{
    for (uint32_t i = 0; i < n->nkids; i++)
        for (uint32_t j = 0; j < i; j++)
            if (str_eq(n->kids[i]->names[0], n->kids[j]->names[0])) return false;
    return true;
}

/* True when [n] is a literal holding one node with no tags, attributes or
 * children (`!ellipse`). */
static bool bare_node(const AstNode *n)
{
    if (!n || n->kind != AST_LITERAL || !vec_is_obj(n->value) || n->value->len != 1) return false;
    const Elem *e = vec_celems(n->value);
    return e->kind == EL_NODE && !e->node->ntags && !e->node->nattrs && !e->node->nchildren;
}

static uint32_t emit_ast(CC *c, const AstNode *n)
{
    uint32_t off = reserve(c, sizeof(CRec));
    rec(c, off)->op = C_AST;
    rec(c, off)->p.node = n;
    if (c->nlater == c->cap_later) {
        c->cap_later = c->cap_later ? c->cap_later * 2 : 16;
        c->later = realloc(c->later, c->cap_later * sizeof *c->later);
        if (!c->later) abort();
    }
    c->later[c->nlater++] = (AstNode *)n;
    return off;
}

/* Emit the record of [n] (and below); returns its offset. */
static uint32_t emit(CC *c, const AstNode *n)
{
    uint32_t off, t;
    if (!n) {
        off = reserve(c, sizeof(CRec));
        rec(c, off)->op = C_LIT;
        return off;
    }
    if (n->fast == 1 || numexpr_compile((AstNode *)n)) {
        const NumExpr *x = numexpr_of(n);
        size_t size = numexpr_size(x);
        off = reserve(c, sizeof(CRec) + size);
        rec(c, off)->op = C_NUM;
        rec(c, off)->p.node = n;
        memcpy(c->buf + off + sizeof(CRec), x, size);
        return off;
    }
    switch ((AstKind)n->kind) {
    case AST_LITERAL:
        off = reserve(c, sizeof(CRec));
        rec(c, off)->op = C_LIT;
        rec(c, off)->p.lit = n->value;
        return off;
    case AST_NAME:
        off = reserve(c, sizeof(CRec));
        switch (n->scope) {
        case SCOPE_LOCAL: rec(c, off)->op = C_LOCAL; rec(c, off)->n = (uint32_t)n->slot; break;
        case SCOPE_GLOBAL: rec(c, off)->op = C_GLOBAL; rec(c, off)->n = (uint32_t)n->slot; break;
        case SCOPE_CONST: rec(c, off)->op = C_LIT; rec(c, off)->p.lit = n->value; break;
        default: rec(c, off)->op = C_LIT; break;
        }
        return off;
    default:
        break;
    }
    if (!compilable(n)) return emit_ast(c, n);
    switch ((AstKind)n->kind) {
    case AST_SEQUENCE:
        off = reserve(c, sizeof(CRec) + n->nkids * sizeof(uint32_t));
        rec(c, off)->op = C_SEQ;
        rec(c, off)->n = n->nkids;
        for (uint32_t i = 0; i < n->nkids; i++) {
            t = emit(c, n->kids[i]);
            ((uint32_t *)(void *)(c->buf + off + sizeof(CRec)))[i] = t;
        }
        return off;
    case AST_LET:
        off = reserve(c, sizeof(CRec) + sizeof(CLetTail) + n->nkids * sizeof(CBind));
        rec(c, off)->op = C_LET;
        rec(c, off)->n = n->nkids;
        for (uint32_t i = 0; i < n->nkids; i++) {
            t = emit(c, n->kids[i]->a);
            CLetTail *lt = (CLetTail *)(void *)(c->buf + off + sizeof(CRec));
            lt->binds[i].slot = n->kids[i]->slots[0];
            lt->binds[i].off = t;
        }
        t = emit(c, n->a);
        ((CLetTail *)(void *)(c->buf + off + sizeof(CRec)))->body = t;
        return off;
    case AST_ATTRIBUTES:
        off = reserve(c, sizeof(CRec) + sizeof(CAttrsTail) + n->nkids * sizeof(CAttr));
        rec(c, off)->n = n->nkids;
        if (bare_node(n->a) && distinct_names(n)) {
            rec(c, off)->op = C_NEWNODE;
            rec(c, off)->p.kind = vec_celems(n->a->value)[0].node->kind;
            t = 0;
        } else {
            rec(c, off)->op = C_ATTRS;
            t = emit(c, n->a);
        }
        ((CAttrsTail *)(void *)(c->buf + off + sizeof(CRec)))->node = t;
        for (uint32_t i = 0; i < n->nkids; i++) {
            t = emit(c, n->kids[i]->a);
            CAttrsTail *at = (CAttrsTail *)(void *)(c->buf + off + sizeof(CRec));
            at->attrs[i].name = n->kids[i]->names[0];
            at->attrs[i].off = t;
        }
        return off;
    case AST_CALL:
        off = reserve(c, sizeof(CRec) + n->nkids * sizeof(uint32_t));
        rec(c, off)->op = C_CALLBI;
        rec(c, off)->n = n->nkids;
        rec(c, off)->p.bi = const_builtin(n->a);
        for (uint32_t i = 0; i < n->nkids; i++) {
            t = emit(c, n->kids[i]);
            ((uint32_t *)(void *)(c->buf + off + sizeof(CRec)))[i] = t;
        }
        return off;
    case AST_APPEND:
        off = reserve(c, sizeof(CRec) + 2 * sizeof(uint32_t));
        rec(c, off)->op = C_APPEND;
        t = emit(c, n->a);
        ((uint32_t *)(void *)(c->buf + off + sizeof(CRec)))[0] = t;
        t = emit(c, n->b);
        ((uint32_t *)(void *)(c->buf + off + sizeof(CRec)))[1] = t;
        return off;
    default:
        return emit_ast(c, n);
    }
}

static void compile_children(AstNode *n);

void evalcode_compile_tree(AstNode *n)
{
    if (!n) return;
    if (numexpr_compile(n)) return;
    if (!compilable(n)) {
        compile_children(n);
        return;
    }
    CC c = {0};
    emit(&c, n);
    n->aux = realloc(c.buf, c.len);
    if (!n->aux) abort();
    n->aux_free = free;
    n->fast = 2;
    for (uint32_t i = 0; i < c.nlater; i++) compile_children(c.later[i]);
    free(c.later);
}

/* Compile the regions below [n] (whose own kind has no record). */
static void compile_children(AstNode *n)
{
    if (n->fast == 1) return;   /* a compiled numeric subtree: all done */
    evalcode_compile_tree(n->a);
    evalcode_compile_tree(n->b);
    evalcode_compile_tree(n->c);
    for (uint32_t i = 0; i < n->nkids; i++) evalcode_compile_tree(n->kids[i]);
}
