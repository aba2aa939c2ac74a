/* dynload.c: a library's entry points gathered with dlopen (dynload.h). */
#include "dynload.h"

#include <dlfcn.h>
#include <stdio.h>
#include <string.h>

bool dynload_fill(const char *soname, const char *what, const DynEntry *entries, size_t n,
                  void *table, Buf *why)
{
    void *h = dlopen(soname, RTLD_NOW | RTLD_LOCAL);
    if (!h) {
        const char *e = dlerror();
        buf_printf(why, "cannot load %s: %s\n", what, e ? e : soname);
        return false;
    }
    for (size_t i = 0; i < n; i++) {
        void *p = dlsym(h, entries[i].name);
        if (!p) {
            buf_printf(why, "cannot load %s: no %s in %s\n", what, entries[i].name, soname);
            return false;
        }
        /* a data pointer stored as a function pointer's bits: POSIX
         * guarantees the two convert for dlsym */
        memcpy((char *)table + entries[i].offset, &p, sizeof p);
    }
    return true;
}

bool dynload_ready(DynLib *lib, const char *soname, const char *what, const DynEntry *entries,
                   size_t n, void *table, const void **published, Buf *why)
{
    pthread_mutex_lock(&lib->mu);
    if (!lib->tried) {
        lib->tried = true;
        Buf failure = BUF_INIT;
        lib->ok = dynload_fill(soname, what, entries, n, table, &failure);
        if (lib->ok)
            *published = table;
        else
            snprintf(lib->failure, sizeof lib->failure, "%s", buf_line(&failure));
        buf_free(&failure);
    }
    bool ok = lib->ok;
    if (!ok && why)
        buf_printf(why, "%s\n", lib->failure);
    pthread_mutex_unlock(&lib->mu);
    return ok;
}
