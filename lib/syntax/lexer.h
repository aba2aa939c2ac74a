/* lexer.h: the token stream between source text and the grammar
 * (LANGUAGE.md §1): the `Token` record, the re2c lexer (grammar/lexer.re)
 * and the NL -> NL/INDENT/DEDENT filter (lib/syntax/indent.c, §1.10).
 *
 * Token kinds are the bison token kinds of grammar/parser.y (`TK_NAME`,
 * `TK_NL`, `TK_INDENT`, ... in the generated parser.h). Positions are byte
 * offsets into the lexer's copy of the source (the original text plus the
 * '\n' that §1.1 appends when missing); source_line_col() (parse.h) turns
 * them into line:column.
 */
#ifndef FL_LEXER_H
#define FL_LEXER_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "buf.h"
#include "parser.h"
#include "value.h"

typedef struct Token {
    int kind;          /* TK_* token kind (TK_FLP_error: lexical error) */
    uint32_t start;    /* byte offset of the first character */
    uint32_t end;      /* byte offset just past the last character */
    uint32_t indent;   /* TK_NL: indentation column of the next line
                          (spaces + 8 * tabs after the last '\n') */
    double num;        /* TK_NUMBER, TK_TIMECODE: the converted value */
    Str *str;          /* TK_STRING: the decoded text (owned by the token) */
} Token;

/* Release what [t] owns (its decoded string) and set t->str to NULL. */
void token_clear(Token *t);

/* {=====================================================================
 * Lexer (grammar/lexer.re)
 * ===================================================================== */

typedef struct Lexer {
    char *text;                 /* owned copy: source, '\n' if missing, NUL */
    size_t len;                 /* bytes of text before the NUL */
    const unsigned char *cur;   /* next byte to scan */
    const unsigned char *mark;  /* re2c backtracking marker */
    int prev;                   /* kind of the previous token (TK_FLP_EMPTY at
                                   the start); decides %include/%pragma */
    uint32_t last_end;          /* end offset of the last token that is not
                                   TK_NL (where TK_END is placed) */
    bool done;                  /* TK_END has been returned */
    Buf msg;                    /* message of the last TK_FLP_error token */
} Lexer;

/* Start lexing the [len] bytes of UTF-8 at [text] (copied; need not end in
 * '\n' or NUL). Release with lex_free().
 *   errors: none here (a source of 4 GiB or more is reported by the first
 *           lex_next() as a TK_FLP_error token)
 *   source: LANGUAGE.md §1.1 */
void lex_init(Lexer *lx, const char *text, size_t len);
/* Release the memory of [lx] (not of tokens already returned). */
void lex_free(Lexer *lx);

/* Scan the next token into [t] and return its kind.
 *   shapes: TK_NL carries `indent`; TK_NUMBER/TK_TIMECODE `num`; TK_STRING
 *           `str` (caller owns: token_clear() or take it); NAME, NODE, TAG
 *           and SYMBOL carry only their span (the text after '!', '#', ':'
 *           is text[start+1 .. end)). Keywords come back as keyword tokens;
 *           `%include`/`%pragma` only at the start of a statement (after
 *           the start of the file, a newline, a hashbang or '<<'), else
 *           '%' and a name. After the last token comes TK_END (at the end
 *           of the last non-newline token), then TK_YYEOF forever.
 *   errors: returns TK_FLP_error with the span of the bad text; the message
 *           ("unterminated string", "invalid number '1__0'", ...) is
 *           lex_message(). Scanning may continue after the bad text.
 *   source: LANGUAGE.md §1.2-§1.9, §1.11 */
int lex_next(Lexer *lx, Token *t);

/* The message of the last TK_FLP_error token (owned by [lx]). */
const char *lex_message(Lexer *lx);

/* True when the [len] bytes at [s] are exactly one NUMBER or TIMECODE
 * token (LANGUAGE.md §1.3-1.4), with its value in *[out]; used for
 * `--define` values. */
bool lex_number_text(const char *s, size_t len, double *out);

/* The bison token kind for a keyword spelled [s] ([len] bytes), or -1. */
int lex_keyword(const char *s, size_t len);

/* }===================================================================== */

/* {=====================================================================
 * Indentation filter (lib/syntax/indent.c)
 * ===================================================================== */

typedef struct Indenter {
    int parens;          /* '(' still open (never below 0) */
    uint32_t *stack;     /* indentation columns of open blocks, stack[0] = 0 */
    size_t depth;        /* entries used in stack (>= 1) */
    size_t cap;          /* entries allocated in stack */
    Token *queue;        /* tokens ready to be read, oldest at qhead */
    size_t qhead;        /* index of the next token to read */
    size_t qlen;         /* index just past the last queued token */
    size_t qcap;         /* tokens allocated in queue */
} Indenter;

/* Start an empty filter (stack [0], no parentheses open). */
void indent_init(Indenter *in);
/* Release [in] and the strings of tokens still queued. */
void indent_free(Indenter *in);

/* Feed the next lexer token [t]; the filter takes t->str. Queues what the
 * parser should see: nothing for a TK_NL inside '(' ... ')'; otherwise the
 * token itself, and after a TK_NL one TK_INDENT or some TK_DEDENTs (placed
 * at the start of the next line, zero width). TK_END first closes every
 * open block with TK_DEDENTs.
 *   errors: returns false when a TK_NL dedents to a column that matches no
 *           enclosing block ("unexpected dedent"); nothing is queued.
 *   source: LANGUAGE.md §1.10 (Lark's Indenter, tab = 8 columns) */
bool indent_feed(Indenter *in, Token *t);

/* Move the oldest queued token to [out]; false when the queue is empty. */
bool indent_pop(Indenter *in, Token *out);

/* }===================================================================== */

#endif
