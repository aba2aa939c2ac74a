/* gl_lib.c: libepoxy loaded with dlopen (see gl_lib.h). */
#include "gl_lib.h"

#include <dlfcn.h>
#include <pthread.h>
#include <stdio.h>
#include <string.h>

#define EPOXY_SONAME "libepoxy.so.0"

static const struct {
    const char *name; /* the symbol */
    size_t offset;    /* of its pointer in GlLib */
} entries[] = {
#define GL_POINTER_ENTRY(name) {"epoxy_" #name, offsetof(GlLib, p_##name)},
    FL_GL_POINTERS(GL_POINTER_ENTRY)
#undef GL_POINTER_ENTRY
#define GL_FUNCTION_ENTRY(name) {#name, offsetof(GlLib, f_##name)},
    FL_GL_FUNCTIONS(GL_FUNCTION_ENTRY)
#undef GL_FUNCTION_ENTRY
};

/* Process-wide and written once, under [once] (gl_lib.h says why): the
 * table, and the reason when the load failed. */
const GlLib *fl_gl;
static GlLib table;
static char failure[256];
static pthread_once_t once = PTHREAD_ONCE_INIT;

static void load(void)
{
    /* stays loaded for the rest of the process, as a linked library would */
    void *h = dlopen(EPOXY_SONAME, RTLD_NOW | RTLD_LOCAL);
    if (!h) {
        const char *why = dlerror();
        snprintf(failure, sizeof failure, "cannot load libepoxy: %s", why ? why : EPOXY_SONAME);
        return;
    }
    for (size_t i = 0; i < sizeof entries / sizeof *entries; i++) {
        /* epoxy_glFoo is a variable (epoxy's pointer): its address; epoxy's
         * functions: the function. Either way a data pointer, as dlsym gives. */
        void *p = dlsym(h, entries[i].name);
        if (!p) {
            snprintf(failure, sizeof failure, "cannot load libepoxy: no %s in %s", entries[i].name, EPOXY_SONAME);
            return;
        }
        memcpy((char *)&table + entries[i].offset, &p, sizeof p);
    }
    fl_gl = &table;
}

bool gl_lib_ready(char *why, size_t cap)
{
    pthread_once(&once, load);
    if (fl_gl) return true;
    if (why && cap) snprintf(why, cap, "%s", failure);
    return false;
}
