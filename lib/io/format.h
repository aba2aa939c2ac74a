/* format.h: value text, str conversion, repr, node trees and state dumps
 * (FORMATS.md §1-3, LANGUAGE.md §3.13-3.14). All append to a Buf; the symbol
 * table [st] names numbers that are registered symbols (may be NULL). */
#ifndef FL_FORMAT_H
#define FL_FORMAT_H

#include "buf.h"
#include "node.h"
#include "state.h"
#include "value.h"

/* Shortest decimal text that reads back (strtod) to exactly [x], in the
 * FORMATS.md §1 layout (`0`, `nan`, `inf`, positional for exponents -4..15,
 * else `d.ddde±XX`). */
void fmt_double(Buf *b, double x);
/* fmt_double by the route [literal] names: printf's digits read back with
 * strtod (true), or exact integer arithmetic where it reaches (false,
 * fmt_double's: |x| from 2^-30 to 2^53, else the literal route): the same
 * text for every x (test_format compares them). */
void fmt_double_route(Buf *b, double x, bool literal);
/* C/Python "%.9g" with `nan` for any NaN (LANGUAGE.md §3.13). */
void fmt_g9(Buf *b, double x);
/* A string in value text (FORMATS.md §1): double quotes, `\"` `\\` `\n`
 * `\r` `\t`, other control bytes and 0x7f as `\xHH`, the rest as is. */
void fmt_quoted(Buf *b, const Str *s);
/* Value text ("full repr", FORMATS.md §1); null → `null`. */
void fmt_value(Buf *b, const Vec *v, const SymTab *st);
/* String conversion (LANGUAGE.md §3.13); null → "". */
void fmt_str(Buf *b, const Vec *v, const SymTab *st);
/* Debug repr (LANGUAGE.md §3.14). */
void fmt_repr(Buf *b, const Vec *v, const SymTab *st);
/* Node-tree dump of [root] (FORMATS.md §3), each line ending in '\n'. */
void fmt_tree(Buf *b, const Node *root, const SymTab *st);
/* One state-dump block (FORMATS.md §2) for frame [frame] at [time]: sorted
 * by the bytes of each key's value text; string keys starting with '_' are
 * left out. */
void fmt_state_dump(Buf *b, const StateDict *sd, long frame, double time,
                    const SymTab *st);

#endif
