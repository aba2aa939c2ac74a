/* simplify_dump.c: an indented text dump of an AST, to show what the
 * simplifier made of a program (`flitter run --dump-simplified`). */
#include "simplify.h"

#include "format.h"

static const char *const arith_ops[] = {"+", "-", "*", "/", "//", "%", "**"};
static const char *const cmp_ops[] = {"==", "!=", "<", ">", "<=", ">=", "in"};

static void dump(Buf *out, const AstNode *n, const SymTab *st, int depth, const char *role)
{
    for (int i = 0; i < depth; i++) buf_puts(out, "  ");
    if (role) buf_printf(out, "%s: ", role);
    if (!n) {
        buf_puts(out, "-\n");
        return;
    }
    buf_puts(out, ast_kind_name((AstKind)n->kind));
    if (n->kind == AST_BINOP && n->op < 7) buf_printf(out, " %s", arith_ops[n->op]);
    if (n->kind == AST_COMPARE && n->op < 7) buf_printf(out, " %s", cmp_ops[n->op]);
    if (n->kind == AST_LET && n->op) buf_puts(out, " stable");
    if (n->kind == AST_CALL && n->op) buf_puts(out, " template");
    for (uint32_t i = 0; i < n->nnames; i++) buf_printf(out, " %s", n->names[i]->bytes);
    if (n->kind == AST_LITERAL) {
        buf_putc(out, ' ');
        fmt_repr(out, n->value, st);
    }
    buf_putc(out, '\n');
    if (n->kind == AST_TOP) {
        dump(out, n->a, st, depth + 1, NULL);
        return;
    }
    if (n->a) dump(out, n->a, st, depth + 1, NULL);
    if (n->b) dump(out, n->b, st, depth + 1, NULL);
    if (n->c) dump(out, n->c, st, depth + 1, NULL);
    for (uint32_t i = 0; i < n->nkids; i++) dump(out, n->kids[i], st, depth + 1, NULL);
}

void ast_dump(Buf *out, const AstNode *n, const SymTab *st)
{
    dump(out, n, st, 0, NULL);
}
