/* simplify_dump.c: a program as Flitter-like source, to show what the
 * simplifier made of it (`flitter run --dump-simplified`).
 *
 * Statements go one per line, indented by four spaces per block level;
 * expressions are written inline with every operation in parentheses, so
 * that the grouping the evaluator will use (and hence the rounding) can be
 * read off directly. Literal nodes are written with their tags, attributes
 * and children. The text is for reading; it is not guaranteed to parse.
 */
#include "simplify.h"

#include "builtins.h"
#include "format.h"
#include "node.h"

static const char *const arith_ops[] = {"+", "-", "*", "/", "//", "%", "**"};
static const char *const cmp_ops[] = {"==", "!=", "<", ">", "<=", ">=", "in"};

static void expr(Buf *b, const AstNode *n, const SymTab *st);
static void stmt(Buf *b, const AstNode *n, const SymTab *st, int depth);

static void indent(Buf *b, int depth)
{
    for (int i = 0; i < depth; i++) buf_puts(b, "    ");
}

static void node_text(Buf *b, const Node *nd, const SymTab *st)
{
    buf_printf(b, "!%s", nd->kind->bytes);
    for (uint32_t i = 0; i < nd->ntags; i++) buf_printf(b, " #%s", nd->tags[i]->bytes);
    for (uint32_t i = 0; i < nd->nattrs; i++) {
        buf_printf(b, " %s=", nd->attrs[i].name->bytes);
        fmt_value(b, nd->attrs[i].value, st);
    }
    for (uint32_t i = 0; i < nd->nchildren; i++) {
        buf_puts(b, " << (");
        node_text(b, nd->children[i], st);
        buf_putc(b, ')');
    }
}

static void value_text(Buf *b, const Vec *v, const SymTab *st)
{
    if (!vec_is_obj(v)) {
        fmt_value(b, v, st);
        return;
    }
    for (uint32_t i = 0; i < v->len; i++) {
        const Elem *e = &vec_celems(v)[i];
        if (i) buf_putc(b, ';');
        if (e->kind == EL_NODE) {
            buf_putc(b, '(');
            node_text(b, e->node, st);
            buf_putc(b, ')');
        } else if (e->kind == EL_FUNC) {
            buf_puts(b, e->func->bi ? e->func->bi->name : func_name(e->func));
        } else {
            Vec *one = vec_item(v, i);
            fmt_value(b, one, st);
            vec_release(one);
        }
    }
}

static void names_text(Buf *b, const AstNode *n)
{
    for (uint32_t i = 0; i < n->nnames; i++) buf_printf(b, "%s%s", i ? ";" : "", n->names[i]->bytes);
}

static void params_text(Buf *b, const AstNode *fn, const SymTab *st)
{
    buf_printf(b, "func %s(", fn->names[0]->bytes);
    for (uint32_t i = 0; i < fn->nkids; i++) {
        const AstNode *p = fn->kids[i];
        buf_printf(b, "%s%s", i ? ", " : "", p->names[0]->bytes);
        if (p->a) {
            buf_putc(b, '=');
            expr(b, p->a, st);
        }
    }
    buf_putc(b, ')');
}

static void args_text(Buf *b, const AstNode *n, const SymTab *st)
{
    for (uint32_t i = 0; i < n->nkids; i++) {
        const AstNode *k = n->kids[i];
        if (i) buf_puts(b, ", ");
        if (k->kind == AST_BINDING) {
            buf_printf(b, "%s=", k->names[0]->bytes);
            expr(b, k->a, st);
        } else {
            expr(b, k, st);
        }
    }
}

static void expr(Buf *b, const AstNode *n, const SymTab *st)
{
    if (!n) {
        buf_puts(b, "null");
        return;
    }
    switch ((AstKind)n->kind) {
    case AST_LITERAL: value_text(b, n->value, st); return;
    case AST_NAME: buf_puts(b, n->names[0]->bytes); return;
    case AST_LOOKUP: buf_puts(b, "$("); expr(b, n->a, st); buf_putc(b, ')'); return;
    case AST_BINOP:
    case AST_COMPARE:
        buf_putc(b, '(');
        expr(b, n->a, st);
        buf_printf(b, " %s ", n->op < 7 ? (n->kind == AST_BINOP ? arith_ops : cmp_ops)[n->op] : "?");
        expr(b, n->b, st);
        buf_putc(b, ')');
        return;
    case AST_NEG: buf_puts(b, "(-"); expr(b, n->a, st); buf_putc(b, ')'); return;
    case AST_POS: buf_puts(b, "(+"); expr(b, n->a, st); buf_putc(b, ')'); return;
    case AST_NOT: buf_puts(b, "(not "); expr(b, n->a, st); buf_putc(b, ')'); return;
    case AST_AND:
    case AST_OR:
    case AST_XOR:
        buf_putc(b, '(');
        expr(b, n->a, st);
        buf_puts(b, n->kind == AST_AND ? " and " : n->kind == AST_OR ? " or " : " xor ");
        expr(b, n->b, st);
        buf_putc(b, ')');
        return;
    case AST_RANGE:
        buf_putc(b, '(');
        if (n->a) expr(b, n->a, st);
        buf_puts(b, "..");
        expr(b, n->b, st);
        if (n->c) {
            buf_putc(b, '|');
            expr(b, n->c, st);
        }
        buf_putc(b, ')');
        return;
    case AST_INDEX: expr(b, n->a, st); buf_putc(b, '['); expr(b, n->b, st); buf_putc(b, ']'); return;
    case AST_CALL:
        if (n->op) buf_putc(b, '@');
        expr(b, n->a, st);
        buf_putc(b, '(');
        args_text(b, n, st);
        buf_putc(b, ')');
        return;
    case AST_FUNCTION:
        buf_putc(b, '(');
        params_text(b, n, st);
        buf_putc(b, ' ');
        expr(b, n->a, st);
        buf_putc(b, ')');
        return;
    case AST_LET:
        buf_putc(b, '(');
        expr(b, n->a, st);
        buf_puts(b, n->op ? " where stable " : " where ");
        for (uint32_t i = 0; i < n->nkids; i++) {
            if (i) buf_puts(b, ", ");
            names_text(b, n->kids[i]);
            buf_putc(b, '=');
            expr(b, n->kids[i]->a, st);
        }
        buf_putc(b, ')');
        return;
    case AST_FOR:
        buf_putc(b, '(');
        expr(b, n->b, st);
        buf_puts(b, " for ");
        names_text(b, n);
        buf_puts(b, " in ");
        expr(b, n->a, st);
        buf_putc(b, ')');
        return;
    case AST_IFELSE:
        buf_putc(b, '(');
        for (uint32_t i = 0; i + 1 < n->nkids; i += 2) {
            expr(b, n->kids[i + 1], st);
            buf_puts(b, " if ");
            expr(b, n->kids[i], st);
            buf_puts(b, " else ");
        }
        expr(b, n->a, st);
        buf_putc(b, ')');
        return;
    case AST_TAG: expr(b, n->a, st); buf_printf(b, " #%s", n->names[0]->bytes); return;
    case AST_ATTRIBUTES:
        expr(b, n->a, st);
        for (uint32_t i = 0; i < n->nkids; i++) {
            buf_printf(b, " %s=", n->kids[i]->names[0]->bytes);
            expr(b, n->kids[i]->a, st);
        }
        return;
    case AST_APPEND:
        buf_putc(b, '(');
        expr(b, n->a, st);
        buf_puts(b, " << ");
        expr(b, n->b, st);
        buf_putc(b, ')');
        return;
    case AST_SEQUENCE:
        buf_putc(b, '(');
        for (uint32_t i = 0; i < n->nkids; i++) {
            if (i) buf_puts(b, "; ");
            expr(b, n->kids[i], st);
        }
        buf_putc(b, ')');
        return;
    case AST_INCLUDE: buf_puts(b, "%include "); expr(b, n->a, st); return;
    case AST_IMPORT:
    case AST_EXPORT:
    case AST_TOP:
    case AST_BINDING:
    case AST__COUNT:
        buf_printf(b, "<%s>", ast_kind_name((AstKind)n->kind));
        return;
    }
}

/* The tags and attributes of the chain from [n] down to [inner], innermost
 * first. */
static void modifiers(Buf *b, const AstNode *n, const AstNode *inner, const SymTab *st)
{
    if (n == inner) return;
    modifiers(b, n->a, inner, st);
    if (n->kind == AST_TAG) {
        buf_printf(b, " #%s", n->names[0]->bytes);
        return;
    }
    for (uint32_t i = 0; i < n->nkids; i++) {
        buf_printf(b, " %s=", n->kids[i]->names[0]->bytes);
        expr(b, n->kids[i]->a, st);
    }
}

static void stmt(Buf *b, const AstNode *n, const SymTab *st, int depth)
{
    if (!n) return;
    switch ((AstKind)n->kind) {
    case AST_TOP:
        for (uint32_t i = 0; i < n->nkids; i++) {
            buf_printf(b, "%%pragma %s ", n->kids[i]->names[0]->bytes);
            fmt_value(b, n->kids[i]->value, st);
            buf_putc(b, '\n');
        }
        stmt(b, n->a, st, depth);
        return;
    case AST_SEQUENCE:
        for (uint32_t i = 0; i < n->nkids; i++) stmt(b, n->kids[i], st, depth);
        return;
    case AST_LET:
        for (uint32_t i = 0; i < n->nkids; i++) {
            const AstNode *k = n->kids[i];
            indent(b, depth);
            if (k->a && k->a->kind == AST_FUNCTION && k->nnames == 1 &&
                str_eq(k->names[0], k->a->names[0])) {
                params_text(b, k->a, st);
                buf_putc(b, '\n');
                stmt(b, k->a->a, st, depth + 1);
                continue;
            }
            buf_puts(b, n->op ? "let stable " : "let ");
            names_text(b, k);
            buf_putc(b, '=');
            expr(b, k->a, st);
            buf_putc(b, '\n');
        }
        stmt(b, n->a, st, depth);
        return;
    case AST_FOR:
        indent(b, depth);
        buf_puts(b, "for ");
        names_text(b, n);
        buf_puts(b, " in ");
        expr(b, n->a, st);
        buf_putc(b, '\n');
        stmt(b, n->b, st, depth + 1);
        return;
    case AST_IFELSE:
        for (uint32_t i = 0; i + 1 < n->nkids; i += 2) {
            indent(b, depth);
            buf_puts(b, i ? "elif " : "if ");
            expr(b, n->kids[i], st);
            buf_putc(b, '\n');
            stmt(b, n->kids[i + 1], st, depth + 1);
        }
        if (n->a) {
            indent(b, depth);
            buf_puts(b, "else\n");
            stmt(b, n->a, st, depth + 1);
        }
        return;
    case AST_FUNCTION:
        indent(b, depth);
        params_text(b, n, st);
        buf_putc(b, '\n');
        stmt(b, n->a, st, depth + 1);
        return;
    case AST_APPEND:
        indent(b, depth);
        expr(b, n->a, st);
        buf_putc(b, '\n');
        stmt(b, n->b, st, depth + 1);
        return;
    case AST_ATTRIBUTES:
    case AST_TAG: {
        /* node #tags attrs with children: the children as a block */
        const AstNode *inner = n;
        while (inner->kind == AST_ATTRIBUTES || inner->kind == AST_TAG) inner = inner->a;
        if (inner->kind != AST_APPEND) break;
        indent(b, depth);
        expr(b, inner->a, st);
        modifiers(b, n, inner, st);
        buf_putc(b, '\n');
        stmt(b, inner->b, st, depth + 1);
        return;
    }
    case AST_IMPORT:
        indent(b, depth);
        buf_puts(b, "import ");
        names_text(b, n);
        buf_puts(b, " from ");
        expr(b, n->a, st);
        buf_putc(b, '\n');
        stmt(b, n->b, st, depth);
        return;
    case AST_EXPORT:
        return;
    default:
        break;
    }
    indent(b, depth);
    expr(b, n, st);
    buf_putc(b, '\n');
}

void ast_dump(Buf *out, const AstNode *n, const SymTab *st)
{
    stmt(out, n, st, 0);
}
