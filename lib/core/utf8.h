/* utf8.h: decoding and encoding UTF-8, shared by strings (FNV-1a over code
 * points, LANGUAGE.md §3.3), value text, the text built-ins and file reading.
 */
#ifndef FL_UTF8_H
#define FL_UTF8_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "buf.h"

/* Length (1-4) of the valid UTF-8 sequence at [s] ([n] > 0 bytes) with its
 * code point in *[cp], or 0 when the bytes are not valid UTF-8 (overlong
 * forms, surrogates and values over U+10FFFF are invalid, as in Python's
 * strict decoder; *[cp] is then unchanged). */
size_t utf8_decode_strict(const unsigned char *s, size_t n, uint32_t *cp);
/* As utf8_decode_strict, except that an invalid sequence decodes as its
 * first byte's value, one byte long; always returns 1-4. */
size_t utf8_decode(const unsigned char *s, size_t n, uint32_t *cp);
/* True when all [n] bytes at [s] are strict UTF-8 (utf8_decode_strict). */
bool utf8_all_valid(const char *s, size_t n);
/* Append the UTF-8 encoding of code point [c] (<= U+10FFFF) to [b]. */
void utf8_put(Buf *b, uint32_t c);

#endif
