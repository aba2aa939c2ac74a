/* text.h: a growable NUL-terminated string for the command line's own
 * text building (the REPL's input block, completion paths, filtered
 * dumps). The CLI is a client of libflitter's public interface and keeps
 * its own small builder instead of the library's internal one. Allocation
 * failure aborts with a message, as in the library. */
#ifndef FL_CLI_TEXT_H
#define FL_CLI_TEXT_H

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct Text {
    char *data;     /* NUL-terminated contents (NULL until the first append) */
    size_t len;     /* bytes used, excluding the NUL */
    size_t cap;     /* bytes allocated */
} Text;

#define TEXT_INIT {NULL, 0, 0}

/* Make room for [extra] more bytes and the NUL. */
static inline void text_reserve(Text *t, size_t extra)
{
    if (t->len + extra + 1 <= t->cap) return;
    size_t cap = t->cap ? t->cap : 64;
    while (cap < t->len + extra + 1) cap *= 2;
    char *p = realloc(t->data, cap);
    if (!p) {
        fputs("flitter: out of memory\n", stderr);
        abort();
    }
    t->data = p;
    t->cap = cap;
}

/* Append [n] bytes at [s]. */
static inline void text_add(Text *t, const char *s, size_t n)
{
    text_reserve(t, n);
    if (n) memcpy(t->data + t->len, s, n);
    t->len += n;
    t->data[t->len] = '\0';
}

static inline void text_puts(Text *t, const char *s) { text_add(t, s, strlen(s)); }
static inline void text_putc(Text *t, char c) { text_add(t, &c, 1); }

__attribute__((format(printf, 2, 3)))
static inline void text_printf(Text *t, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(NULL, 0, fmt, ap);
    va_end(ap);
    if (n <= 0) return;
    text_reserve(t, (size_t)n);
    va_start(ap, fmt);
    vsnprintf(t->data + t->len, (size_t)n + 1, fmt, ap);
    va_end(ap);
    t->len += (size_t)n;
}

/* The contents as a C string ("" when empty); owned by [t]. */
static inline const char *text_cstr(const Text *t) { return t->data ? t->data : ""; }

/* Empty [t], keeping its memory. */
static inline void text_reset(Text *t)
{
    t->len = 0;
    if (t->data) t->data[0] = '\0';
}

static inline void text_free(Text *t)
{
    free(t->data);
    *t = (Text)TEXT_INIT;
}

#endif
