/* buf.h: a growable byte buffer for building text.
 *
 * It is also the library's one way of reporting why a call failed: a
 * function that can fail returns its failure value and appends the reason
 * to the caller's `Buf *err`, each line ending in a newline (ARCHITECTURE.md,
 * "Errors"). */
#ifndef FL_BUF_H
#define FL_BUF_H

#include <stdarg.h>
#include <stddef.h>

typedef struct Buf {
    char *data;     /* NUL-terminated contents (NULL until the first append) */
    size_t len;     /* bytes used, excluding the NUL */
    size_t cap;     /* bytes allocated */
} Buf;

#define BUF_INIT {NULL, 0, 0}

void buf_add(Buf *b, const char *s, size_t n);
void buf_puts(Buf *b, const char *s);
void buf_putc(Buf *b, char c);
void buf_printf(Buf *b, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* The contents as a C string ("" when empty); owned by [b]. */
const char *buf_cstr(Buf *b);
void buf_reset(Buf *b);
/* Cut [b] back to its first [len] bytes (no-op when it is not longer): a
 * caller that wrote a message's prefix before a call that did not fail
 * takes it back. */
void buf_truncate(Buf *b, size_t len);
/* The contents without trailing newlines, which are removed from [b]: an
 * error message for a log line or a text that adds its own newline. "" when
 * empty; owned by [b]. */
const char *buf_line(Buf *b);
void buf_free(Buf *b);

#endif
