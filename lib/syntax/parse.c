/* parse.c: the parser driver, from source text to an AST_TOP tree
 * (LANGUAGE.md §1 and §2), and the mapping of byte offsets to positions.
 *
 * Pipeline, pulled one token at a time by the bison parser through
 * parse_lex(): the re2c lexer (grammar/lexer.re) produces raw tokens, the
 * indentation filter (lib/syntax/indent.c) turns newlines into NL/INDENT/DEDENT, and
 * parse_lex() gives each token its semantic value (names as Str, literals as
 * Vec) and its Loc. The `ParseCtx` below holds all of it for one parse, so
 * parses are independent and reentrant. Every symbol literal met on the way
 * is collected (distinct names, first-seen order, with a small hash set) and
 * handed to the caller in the AST_TOP node's `c` list (ast.h).
 *
 * Errors: the first lexical, indentation or syntax error stops the parse and
 * is written once as `PATH:LINE:COL: error: MESSAGE`, the source line and a
 * caret line under the offending span (FORMATS.md §4). A syntax error whose
 * unexpected token is the end of the input, or a newline/dedent followed by
 * nothing but layout, reads "unexpected end of input" so that a REPL can ask
 * for more lines.
 */
#include "parse.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lexer.h"
#include "mem.h"
#include "node.h"

struct ParseCtx {
    Lexer lx;              /* raw tokens */
    Indenter ind;          /* NL -> NL/INDENT/DEDENT */
    const char *path;      /* file name for messages */
    uint32_t file;         /* Loc.file of every location */
    Buf *err;              /* where messages go */
    bool reported;         /* a message was written: report no more */
    bool ended;            /* TK_END was handed to the parser */
    int last_kind;         /* kind of the last token handed to the parser */
    Str **syms;            /* distinct symbol names, first-seen order */
    size_t nsyms, cap_syms;
    uint32_t *slots;       /* hash set over syms: index + 1, 0 = empty */
    size_t nslots;         /* power of two, > 2 * nsyms */
};

/* {=====================================================================
 * Positions and messages
 * ===================================================================== */

static bool is_continuation(unsigned char c)
{
    return (c & 0xc0) == 0x80;
}

void source_line_col(const char *text, size_t len, size_t offset,
                     unsigned *line, unsigned *col)
{
    unsigned l = 1, c = 1;
    if (offset > len)
        offset = len;
    for (size_t i = 0; i < offset; i++) {
        if (text[i] == '\n') {
            l++;
            c = 1;
        } else if (!is_continuation((unsigned char)text[i])) {
            c++;
        }
    }
    *line = l;
    *col = c;
}

void line_cursor_at(LineCursor *c, size_t offset, unsigned *line, unsigned *col)
{
    if (offset > c->len)
        offset = c->len;
    if (c->line == 0 || offset < c->line_start) {   /* (re)start at the top */
        c->pos = c->line_start = 0;
        c->line = c->col = 1;
    } else if (offset < c->pos) {                     /* back within the line */
        c->pos = c->line_start;
        c->col = 1;
    }
    for (size_t i = c->pos; i < offset; i++) {
        if (c->text[i] == '\n') {
            c->line++;
            c->col = 1;
            c->line_start = i + 1;
        } else if (!is_continuation((unsigned char)c->text[i])) {
            c->col++;
        }
    }
    c->pos = offset;
    *line = c->line;
    *col = c->col;
}

/* The length of the control character at [s] ([n] bytes left) that an
 * echoed source line escapes: 1 for C0 (but tab) and DEL, 2 for a C1
 * character in UTF-8 (U+0080-U+009F); 0 for anything else. */
static size_t control_len(const char *s, size_t n)
{
    unsigned char c = (unsigned char)s[0];
    if ((c < 0x20 && c != '\t') || c == 0x7f) return 1;
    if (c == 0xc2 && n >= 2 && (unsigned char)s[1] >= 0x80 && (unsigned char)s[1] <= 0x9f) return 2;
    return 0;
}

/* The columns the byte at [s] takes in the echoed line: 4 for `\xHH`, 6
 * for `\u00HH` (on its first byte), 0 for the rest of a UTF-8 sequence,
 * else 1. */
static size_t shown_width(const char *s, size_t n)
{
    size_t k = control_len(s, n);
    if (k == 1) return 4;
    if (k == 2) return 6;
    return is_continuation((unsigned char)s[0]) ? 0 : 1;
}

/* Write the error [msg] at bytes [start, end) of the lexer's text. */
static void report(ParseCtx *pc, uint32_t start, uint32_t end, const char *msg)
{
    if (pc->reported)
        return;
    pc->reported = true;
    source_error(pc->err, pc->path, pc->lx.text, pc->lx.len, start, end, msg);
}

void source_error(Buf *err, const char *path, const char *text, size_t len,
                  uint32_t start, uint32_t end, const char *msg)
{
    unsigned line, col;
    if (start > len)
        start = (uint32_t)len;
    source_line_col(text, len, start, &line, &col);
    buf_printf(err, "%s:%u:%u: error: %s\n", path, line, col, msg);

    size_t ls = start, le = start;
    while (ls > 0 && text[ls - 1] != '\n')
        ls--;
    while (le < len && text[le] != '\n')
        le++;
    size_t shown = le > ls && text[le - 1] == '\r' ? le - 1 : le;
    /* the line as written, but for its control characters (C0, DEL and
     * C1, which a terminal would obey): `\xHH` and `\u00HH` instead */
    for (size_t i = ls; i < shown;) {
        size_t k = control_len(text + i, shown - i);
        if (k == 1) buf_printf(err, "\\x%02x", (unsigned char)text[i]);
        else if (k == 2) buf_printf(err, "\\u00%02x", (unsigned char)text[i + 1]);
        else buf_putc(err, text[i]);
        i += k ? k : 1;
    }
    buf_putc(err, '\n');
    for (size_t i = ls; i < start && i < shown; i++) {
        if (text[i] == '\t')
            buf_putc(err, '\t');
        else
            for (size_t k = shown_width(text + i, shown - i); k > 0; k--) buf_putc(err, ' ');
    }
    size_t stop = end < shown ? end : shown;
    size_t carets = 0;
    for (size_t i = start; i < stop; i++)
        carets += shown_width(text + i, stop - i);
    if (carets == 0)
        carets = 1;
    for (size_t i = 0; i < carets; i++)
        buf_putc(err, '^');
    buf_putc(err, '\n');
}

static bool is_layout(int kind)
{
    return kind == TK_NL || kind == TK_INDENT || kind == TK_DEDENT
        || kind == TK_END || kind == TK_YYEOF;
}

/* After an error at a layout token: is the rest of the input only layout?
 * (Consumes tokens; the parse is over anyway.) */
static bool rest_is_layout(ParseCtx *pc)
{
    Token t;
    while (indent_pop(&pc->ind, &t)) {
        token_clear(&t);
        if (!is_layout(t.kind))
            return false;
        if (t.kind == TK_END)
            return true;
    }
    for (;;) {
        int kind = lex_next(&pc->lx, &t);
        token_clear(&t);
        if (kind == TK_END || kind == TK_YYEOF)
            return true;
        if (kind != TK_NL)
            return false;
    }
}

void parse_syntax_error(ParseCtx *pc, Loc loc, const char *unexpected,
                        const char *const *expected, int nexpected)
{
    if (pc->reported)
        return;
    bool at_end = pc->last_kind == TK_END || pc->last_kind == TK_YYEOF
        || (is_layout(pc->last_kind) && rest_is_layout(pc));
    Buf msg = BUF_INIT;
    buf_puts(&msg, "syntax error, unexpected ");
    buf_puts(&msg, at_end ? "end of input" : unexpected);
    for (int i = 0; i < nexpected; i++) {
        buf_puts(&msg, i == 0 ? ", expecting " : i == nexpected - 1 ? " or " : ", ");
        buf_puts(&msg, expected[i]);
    }
    report(pc, loc.start, loc.end, buf_cstr(&msg));
    buf_free(&msg);
}

void parse_failure(ParseCtx *pc, Loc loc, const char *msg)
{
    /* bison's stack limit: YYMAXDEPTH, left at bison's default of 10000 */
    if (strcmp(msg, "memory exhausted") == 0)
        msg = "program nested too deeply (parser stack limit 10000 entries)";
    report(pc, loc.start, loc.end, msg);
}

Loc parse_start(ParseCtx *pc)
{
    return (Loc){pc->file, 0, 0};
}

/* }===================================================================== */

/* {=====================================================================
 * Tokens for the parser
 * ===================================================================== */

/* Remember the symbol :[name] (distinct names only). */
static void add_symbol(ParseCtx *pc, const char *name, size_t len)
{
    if (2 * (pc->nsyms + 1) >= pc->nslots) {
        size_t n = pc->nslots ? 2 * pc->nslots : 64;
        free(pc->slots);
        pc->slots = mem_realloc(NULL, n * sizeof *pc->slots);
        memset(pc->slots, 0, n * sizeof *pc->slots);
        pc->nslots = n;
        for (size_t i = 0; i < pc->nsyms; i++) {
            size_t h = (size_t)fnv1a_utf8(pc->syms[i]->bytes, pc->syms[i]->len);
            while (pc->slots[h & (n - 1)])
                h++;
            pc->slots[h & (n - 1)] = (uint32_t)(i + 1);
        }
    }
    size_t h = (size_t)fnv1a_utf8(name, len);
    for (;; h++) {
        uint32_t s = pc->slots[h & (pc->nslots - 1)];
        if (!s)
            break;
        Str *old = pc->syms[s - 1];
        if (old->len == len && memcmp(old->bytes, name, len) == 0)
            return;
    }
    if (pc->nsyms == pc->cap_syms) {
        pc->cap_syms = pc->cap_syms ? 2 * pc->cap_syms : 16;
        pc->syms = mem_realloc(pc->syms, pc->cap_syms * sizeof *pc->syms);
    }
    pc->syms[pc->nsyms++] = str_new(name, len);
    pc->slots[h & (pc->nslots - 1)] = (uint32_t)pc->nsyms;
}

int parse_lex(FLP_STYPE *value, Loc *loc, ParseCtx *pc)
{
    Token t;
    if (pc->ended) {
        *loc = (Loc){pc->file, pc->lx.last_end, pc->lx.last_end};
        return pc->last_kind = TK_YYEOF;
    }
    while (!indent_pop(&pc->ind, &t)) {
        Token raw;
        if (lex_next(&pc->lx, &raw) == TK_FLP_error) {
            report(pc, raw.start, raw.end, lex_message(&pc->lx));
            return pc->last_kind = TK_FLP_error;
        }
        if (!indent_feed(&pc->ind, &raw)) {
            report(pc, raw.end, raw.end,
                   "unexpected dedent: indentation matches no enclosing block");
            return pc->last_kind = TK_FLP_error;
        }
    }
    *loc = (Loc){pc->file, t.start, t.end};
    const char *text = pc->lx.text + t.start;
    size_t len = t.end - t.start;
    switch (t.kind) {
    case TK_NAME:
        value->str = str_new(text, len);
        break;
    case TK_TAG:
        value->str = str_new(text + 1, len - 1);
        break;
    case TK_NODE: {
        Str *kind = str_new(text + 1, len - 1);
        value->vec = vec_node_take(node_new(kind));
        str_release(kind);
        break;
    }
    case TK_SYMBOL:
        add_symbol(pc, text + 1, len - 1);
        value->vec = vec_num1(symbol_value(text + 1, len - 1));
        break;
    case TK_NUMBER:
    case TK_TIMECODE:
        value->vec = vec_num1(t.num);
        break;
    case TK_STRING:
        value->vec = vec_str_take(t.str);
        break;
    case TK_END:
        pc->ended = true;
        break;
    default:
        break;
    }
    return pc->last_kind = t.kind;
}

/* }===================================================================== */

/* The symbol list of AST_TOP's `c`: literals of the names collected. */
static AstNode *symbol_list(ParseCtx *pc)
{
    Loc loc = {pc->file, 0, 0};
    AstNode *list = ast_new(AST_SEQUENCE, loc);
    for (size_t i = 0; i < pc->nsyms; i++) {
        ast_push(list, ast_literal(vec_str_take(pc->syms[i]), loc));
        pc->syms[i] = NULL;
    }
    pc->nsyms = 0;
    return list;
}

/* The first node (depth-first, children in a, b, c, kids order) lying more
 * than AST_MAX_DEPTH levels below [root], or NULL when the tree is within
 * the limit. Iterative with an explicit work list, so a tree of any depth can
 * be measured without recursion. */
static const AstNode *too_deep(const AstNode *root)
{
    typedef struct { const AstNode *n; uint32_t depth; } Item;
    size_t len = 0, cap = 64;
    Item *work = mem_realloc(NULL, cap * sizeof *work);
    const AstNode *found = NULL;
    work[len++] = (Item){root, 1};
    while (len && !found) {
        Item it = work[--len];
        if (it.depth > AST_MAX_DEPTH) {
            found = it.n;
            break;
        }
        const AstNode *t = it.n;
        size_t need = len + t->nkids + 3;
        if (need > cap) {
            while (cap < need)
                cap *= 2;
            work = mem_realloc(work, cap * sizeof *work);
        }
        /* pushed in reverse so that the first child is visited first */
        for (uint32_t i = t->nkids; i-- > 0;)
            if (t->kids[i])
                work[len++] = (Item){t->kids[i], it.depth + 1};
        if (t->c) work[len++] = (Item){t->c, it.depth + 1};
        if (t->b) work[len++] = (Item){t->b, it.depth + 1};
        if (t->a) work[len++] = (Item){t->a, it.depth + 1};
    }
    free(work);
    return found;
}

AstNode *parse_program(const char *path, const char *text, size_t len,
                       uint32_t file_index, Buf *err)
{
    ParseCtx pc;
    memset(&pc, 0, sizeof pc);
    lex_init(&pc.lx, text, len);
    indent_init(&pc.ind);
    pc.path = path ? path : "<input>";
    pc.file = file_index;
    pc.err = err;
    pc.last_kind = TK_FLP_EMPTY;

    AstNode *top = NULL;
    int status = flp_parse(&pc, &top);
    if (status != 0 || !top) {
        if (!pc.reported)
            report(&pc, pc.lx.last_end, pc.lx.last_end, "syntax error");
        ast_free(top);
        top = NULL;
    } else {
        const AstNode *deep = too_deep(top);
        if (deep) {
            char msg[96];
            snprintf(msg, sizeof msg, "program nested too deeply (limit %d levels)",
                     AST_MAX_DEPTH);
            report(&pc, deep->loc.start, deep->loc.end, msg);
            ast_free(top);
            top = NULL;
        } else {
            top->c = symbol_list(&pc);
        }
    }

    for (size_t i = 0; i < pc.nsyms; i++)
        str_release(pc.syms[i]);
    free(pc.syms);
    free(pc.slots);
    indent_free(&pc.ind);
    lex_free(&pc.lx);
    return top;
}
