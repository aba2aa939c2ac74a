/* define_value.h: the value a script receives for a defined name's text
 * (`-D NAME=VALUE`, `flitter sweep -D`, fl_define, the Python module's
 * text values), by Flitter's own rule (Flitter 1.0.0b28's
 * engine/__main__.py `keyvalue`, which reads
 * numbers with Python's float(), so `-3`, `+2.5` and `inf` are numbers and
 * an empty VALUE is the empty string, not null).
 */
#ifndef FLITTER_DEFINE_VALUE_H
#define FLITTER_DEFINE_VALUE_H

#include <stdbool.h>
#include <stddef.h>

#include "value.h"

/* The value of the define text [text] ([len] bytes): the text split at
 * every `;` (so "" is one empty part and "a;" two), each part
 *   - a symbol when it starts with `:` (":" alone is the empty name's),
 *   - else a number as Python's float() reads it (sign, `inf`, `nan`,
 *     exponent, `_` between digits, surrounding blanks), optionally with
 *     one SI or angle suffix (p n u µ m k M G T, ° and deg: turns),
 *   - else a time code `[[H:]M:]S` (H and M integers, S a number),
 *   - else the text of the part itself, unchanged;
 * the parts composed into one vector (numbers and strings mixed as they
 * come). Symbols are added to [st]. Never fails (any text is a value);
 * aborts only when out of memory. */
Vec *define_value(SymTab *st, const char *text, size_t len);

/* True when the [len] bytes at [s] read as one number by Python's float()
 * (see define_value), with the number in *[out]; *[out] untouched
 * otherwise. */
bool define_float(const char *s, size_t len, double *out);

#endif
