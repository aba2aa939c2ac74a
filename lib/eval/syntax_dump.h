/* syntax_dump.h: a script's token stream and its AST as text, for
 * `flitter run --dump-tokens` and `--dump-ast` (what the lexer, the
 * indentation filter and the parser make of a script, before the
 * simplifier and the resolver touch it).
 */
#ifndef FL_SYNTAX_DUMP_H
#define FL_SYNTAX_DUMP_H

#include <stdbool.h>
#include <stddef.h>

#include "buf.h"
#include "value.h"

/* Append to [out] the tokens the parser would read from [text] ([len]
 * bytes; [path] names it in messages), after the indentation filter, one a
 * line: `LINE:COL KIND` and, for tokens with a spelling, a space and the
 * source text (a number's or string's as written), ending with the
 * `end of input` token.
 * Linear in the text (line and column from a moving LineCursor).
 *   errors: on a lexical error or an unmatched dedent returns false with
 *           the tokens before it in [out] and `PATH:LINE:COL: error: ...`
 *           (source line, caret line) in [err]; once *[interrupt] (NULL:
 *           never) is non-zero, false with `PATH: error: interrupted`
 *   source: LANGUAGE.md §1 (lexing, §1.10 indentation) */
bool dump_tokens(Buf *out, Buf *err, const char *path, const char *text,
                 size_t len, volatile int *interrupt);

/* Append to [out] the AST that parse_program() builds from [text], one
 * node a line, children indented by two spaces below their parent: the
 * kind (ast.h) and what it holds (operator, names, literal value in value
 * text, with symbols named through [st] when it knows them), then `@LINE:COL`
 * of its start; fixed children come after the listed ones, marked `a:`,
 * `b:` or `c:` as ast.h names them.
 *   errors: on a lexical or syntax error returns false with nothing in
 *           [out] and parse_program()'s message in [err]; once
 *           *[interrupt] (NULL: never) is non-zero, false with `PATH:
 *           error: interrupted` and the nodes so far in [out]
 *   source: LANGUAGE.md §2.4 (tree shapes) */
bool dump_ast(Buf *out, Buf *err, const char *path, const char *text,
              size_t len, SymTab *st, volatile int *interrupt);

#endif
