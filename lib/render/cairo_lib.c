/* cairo_lib.c: cairo loaded with dlopen (see cairo_lib.h). */
#include "cairo_lib.h"

#include <dlfcn.h>
#include <pthread.h>
#include <stdio.h>
#include <string.h>

/* The soname of the major version the headers describe. */
#define CAIRO_SONAME "libcairo.so.2"

static const struct {
    const char *name; /* the symbol */
    size_t offset;    /* of its pointer in CairoLib */
} entries[] = {
#define CAIRO_ENTRY(name) {#name, offsetof(CairoLib, f_##name)},
    FL_CAIRO_FUNCTIONS(CAIRO_ENTRY)
#undef CAIRO_ENTRY
};

/* Process-wide and written once, under [once] (cairo_lib.h says why):
 * the table, and the reason when the load failed. */
const CairoLib *fl_cairo;
static CairoLib table;
static char failure[256];
static pthread_once_t once = PTHREAD_ONCE_INIT;

static void load(void)
{
    /* stays loaded for the rest of the process, as a linked library would */
    void *h = dlopen(CAIRO_SONAME, RTLD_NOW | RTLD_LOCAL);
    if (!h) {
        const char *why = dlerror();
        snprintf(failure, sizeof failure, "cannot load cairo: %s", why ? why : CAIRO_SONAME);
        return;
    }
    for (size_t i = 0; i < sizeof entries / sizeof *entries; i++) {
        void *f = dlsym(h, entries[i].name);
        if (!f) {
            snprintf(failure, sizeof failure, "cannot load cairo: no %s in %s", entries[i].name, CAIRO_SONAME);
            return;
        }
        /* a data pointer to a function pointer: POSIX guarantees dlsym's */
        memcpy((char *)&table + entries[i].offset, &f, sizeof f);
    }
    fl_cairo = &table;
}

bool cairo_lib_ready(char *why, size_t cap)
{
    pthread_once(&once, load);
    if (fl_cairo) return true;
    if (why && cap) snprintf(why, cap, "%s", failure);
    return false;
}
