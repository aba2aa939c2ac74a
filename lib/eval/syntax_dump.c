/* syntax_dump.c: --dump-tokens and --dump-ast (syntax_dump.h). */
#include "syntax_dump.h"

#include <string.h>

#include "ast.h"
#include "format.h"
#include "lexer.h"
#include "parse.h"
#include "program.h"

/* The source text of a token: newlines, tabs and returns escaped so that
 * every token stays on its line. */
static void put_spelling(Buf *out, const char *s, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        switch (s[i]) {
        case '\n': buf_puts(out, "\\n"); break;
        case '\r': buf_puts(out, "\\r"); break;
        case '\t': buf_puts(out, "\\t"); break;
        default: buf_putc(out, s[i]); break;
        }
    }
}

/* How often (in tokens or nodes) the dumps look at the interrupt flag. */
enum { POLL_EVERY = 4096 };

static void put_token(Buf *out, const Lexer *lx, LineCursor *lc, const Token *t)
{
    unsigned line, col;
    line_cursor_at(lc, t->start, &line, &col);
    buf_printf(out, "%u:%u %s", line, col, parse_token_name(t->kind));
    if (t->end > t->start && t->kind != TK_NL) {
        buf_putc(out, ' ');
        put_spelling(out, lx->text + t->start, t->end - t->start);
    }
    buf_putc(out, '\n');
}

bool dump_tokens(Buf *out, Buf *err, const char *path, const char *text,
                 size_t len, volatile int *interrupt)
{
    Lexer lx;
    Indenter ind;
    lex_init(&lx, text, len);
    indent_init(&ind);
    LineCursor lc = {.text = lx.text, .len = lx.len};
    bool ok = true, done = false;
    for (size_t n = 0; ok && !done; n++) {
        if (n % POLL_EVERY == 0 && interrupt && *interrupt) {
            buf_printf(err, "%s: error: interrupted\n", path);
            ok = false;
            break;
        }
        Token t;
        while (indent_pop(&ind, &t)) {
            put_token(out, &lx, &lc, &t);
            token_clear(&t);
            done = t.kind == TK_END;
        }
        if (done)
            break;
        Token raw;
        if (lex_next(&lx, &raw) == TK_FLP_error) {
            source_error(err, path, lx.text, lx.len, raw.start, raw.end,
                         lex_message(&lx));
            token_clear(&raw);
            ok = false;
        } else if (!indent_feed(&ind, &raw)) {
            source_error(err, path, lx.text, lx.len, raw.end, raw.end,
                         "unexpected dedent: indentation matches no enclosing block");
            token_clear(&raw);
            ok = false;
        }
    }
    indent_free(&ind);
    lex_free(&lx);
    return ok;
}

static const char *const arith_ops[] = {"+", "-", "*", "/", "//", "%", "**"};
static const char *const compare_ops[] = {"==", "!=", "<", ">", "<=", ">=", "in"};

static void put_names(Buf *out, const AstNode *n)
{
    for (uint32_t i = 0; i < n->nnames; i++) {
        buf_putc(out, i ? ',' : ' ');
        buf_add(out, n->names[i]->bytes, n->names[i]->len);
    }
}

/* What node [n] holds beyond its children, after its kind. */
static void put_details(Buf *out, const AstNode *n, const SymTab *st)
{
    switch ((AstKind)n->kind) {
    case AST_BINOP:
        if (n->op < sizeof arith_ops / sizeof *arith_ops)
            buf_printf(out, " %s", arith_ops[n->op]);
        break;
    case AST_COMPARE:
        if (n->op < sizeof compare_ops / sizeof *compare_ops)
            buf_printf(out, " %s", compare_ops[n->op]);
        break;
    case AST_CALL:
        buf_printf(out, " positional=%u%s", n->count, n->op ? " template" : "");
        break;
    case AST_LET:
        if (n->op)
            buf_puts(out, " stable");
        break;
    default:
        break;
    }
    put_names(out, n);
    if (n->kind == AST_LITERAL || (n->kind == AST_BINDING && n->value)) {
        buf_putc(out, ' ');
        fmt_value(out, n->value, st);
    }
}

/* What put_node carries down the tree. */
typedef struct {
    Buf *out;
    LineCursor lc;
    const SymTab *st;
    volatile int *interrupt;
    size_t nodes;
    bool stopped;
} AstDump;

static void put_node(AstDump *d, const AstNode *n, const char *role, int depth)
{
    Buf *out = d->out;
    if (d->stopped || (++d->nodes % POLL_EVERY == 0 && d->interrupt && *d->interrupt)) {
        d->stopped = true;
        return;
    }
    for (int i = 0; i < depth; i++)
        buf_puts(out, "  ");
    if (!n) {
        buf_printf(out, "%snull\n", role);
        return;
    }
    buf_printf(out, "%s%s", role, ast_kind_name((AstKind)n->kind));
    put_details(out, n, d->st);
    unsigned line, col;
    line_cursor_at(&d->lc, n->loc.start, &line, &col);
    buf_printf(out, " @%u:%u\n", line, col);
    for (uint32_t i = 0; i < n->nkids; i++)
        put_node(d, n->kids[i], "", depth + 1);
    /* the parse depth cap (AST_MAX_DEPTH) bounds this recursion */
    if (n->a)
        put_node(d, n->a, "a: ", depth + 1);
    if (n->b)
        put_node(d, n->b, "b: ", depth + 1);
    if (n->c)
        put_node(d, n->c, "c: ", depth + 1);
}

bool dump_ast(Buf *out, Buf *err, const char *path, const char *text,
              size_t len, SymTab *st, volatile int *interrupt)
{
    AstNode *top = parse_program(path, text, len, 0, err);
    if (!top)
        return false;
    program_register_symbols(top, st);   /* literals print as :name */
    AstDump d = {.out = out, .lc = {.text = text, .len = len}, .st = st, .interrupt = interrupt};
    put_node(&d, top, "", 0);
    ast_free(top);
    if (d.stopped)
        buf_printf(err, "%s: error: interrupted\n", path);
    return !d.stopped;
}
