/* parse.h: source text to AST (grammar/lexer.re, lib/syntax/indent.c,
 * grammar/parser.y). */
#ifndef FL_PARSE_H
#define FL_PARSE_H

#include <stddef.h>
#include <stdint.h>

#include "config.h"
#include "ast.h"
#include "buf.h"

/* Parse the Flitter program in [text] ([len] bytes of UTF-8, need not end in
 * a newline or NUL) into an AST_TOP tree whose locations carry [file_index].
 *   errors: on a lexical or syntax error returns NULL and appends to [err]
 *           `PATH:LINE:COL: error: MESSAGE\n` followed by the source line and
 *           a caret line, where PATH is [path], LINE and COL are 1-based
 *           (COL counts code points). A message for input that ended too
 *           early contains "unexpected end of input" (the REPL uses this to
 *           ask for more lines).
 *   source: LANGUAGE.md §1 (lexing, indentation), §2 (grammar, tree shapes) */
AstNode *parse_program(const char *path, const char *text, size_t len,
                       uint32_t file_index, Buf *err);

/* Append to [err] the message `PATH:LINE:COL: error: MSG`, the source
 * line of byte [start] of [text] and a caret line under [start, end), as
 * parse_program() reports errors. */
void source_error(Buf *err, const char *path, const char *text, size_t len,
                  uint32_t start, uint32_t end, const char *msg);

/* The grammar's name of token kind [kind] (a TK_* of parser.h): "name",
 * "'('", "indent", ... (grammar/parser.y). */
const char *parse_token_name(int kind);

/* 1-based line and code-point column of byte [offset] in [text]. */
void source_line_col(const char *text, size_t len, size_t offset,
                     unsigned *line, unsigned *col);

/* A position in a text that source_line_col() moves on from instead of
 * counting from the start: the dumps ask for every token's and node's line
 * and column, mostly in increasing order, so the whole dump is linear in the
 * text (counting from the start made one line of 200,000 tokens take
 * minutes). Zero it, then set text and len. */
typedef struct LineCursor {
    const char *text;
    size_t len;
    size_t pos;          /* the byte the cursor is at */
    size_t line_start;   /* the first byte of its line */
    unsigned line, col;  /* of pos, 1-based (0: not started) */
} LineCursor;

/* source_line_col() of [offset] through [c]: forward from the cursor, or
 * from the start of the cursor's line (from the text's start when
 * [offset] is on an earlier line); the same results as source_line_col. */
void line_cursor_at(LineCursor *c, size_t offset, unsigned *line, unsigned *col);

#endif
