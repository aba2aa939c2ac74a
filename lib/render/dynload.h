/* dynload.h: a library's entry points gathered into a table with dlopen
 * and dlsym, for the libraries the render layer opens the first time it
 * draws (cairo_lib.c, gl_lib.c). */
#ifndef FL_RENDER_DYNLOAD_H
#define FL_RENDER_DYNLOAD_H

#include <pthread.h>
#include <stdbool.h>
#include <stddef.h>

#include "buf.h"

/* One symbol and where its address goes in the table. */
typedef struct DynEntry {
    const char *name;
    size_t offset;
} DynEntry;

/* Open [soname] (it stays loaded for the rest of the process, as a linked
 * library would) and store the address of each of the [n] entries' symbols
 * at [table] + its offset (a function's address, or a variable's).
 *   errors: false with "cannot load [what]: ..." appended to [why]:
 *           the library or a symbol missing; [table] may be part filled. */
bool dynload_fill(const char *soname, const char *what, const DynEntry *entries, size_t n,
                  void *table, Buf *why);

/* A library opened once per process: whether it was tried, and why it
 * failed. Static, initialised with DYNLIB_INIT. */
typedef struct DynLib {
    pthread_mutex_t mu;
    bool tried, ok;
    char failure[256];
} DynLib;
#define DYNLIB_INIT {PTHREAD_MUTEX_INITIALIZER, false, false, ""}

/* The first call fills [table] as dynload_fill does and, when that
 * succeeds, sets *[published] to [table]; every call (thread-safe) says
 * whether the library's entry points can be called.
 *   errors: false with the first call's reason appended to [why]
 *           (may be NULL), the same every time. */
bool dynload_ready(DynLib *lib, const char *soname, const char *what, const DynEntry *entries,
                   size_t n, void *table, const void **published, Buf *why);

#endif
