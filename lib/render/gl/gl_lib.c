/* gl_lib.c: libepoxy loaded with dlopen (see gl_lib.h). */
#include "gl_lib.h"

#include "dynload.h"

#define EPOXY_SONAME "libepoxy.so.0"

/* epoxy_glFoo is a variable (epoxy's pointer): its address is stored;
 * epoxy's own functions: the function's. */
static const DynEntry entries[] = {
#define GL_POINTER_ENTRY(name) {"epoxy_" #name, offsetof(GlLib, p_##name)},
    FL_GL_POINTERS(GL_POINTER_ENTRY)
#undef GL_POINTER_ENTRY
#define GL_FUNCTION_ENTRY(name) {#name, offsetof(GlLib, f_##name)},
    FL_GL_FUNCTIONS(GL_FUNCTION_ENTRY)
#undef GL_FUNCTION_ENTRY
};

/* Process-wide, filled once (gl_lib.h says why). */
const void *fl_gl;
static GlLib table;

bool gl_lib_ready(Buf *why)
{
    static DynLib lib = DYNLIB_INIT;
    return dynload_ready(&lib, EPOXY_SONAME, "libepoxy", entries, sizeof entries / sizeof *entries, &table,
                         &fl_gl, why);
}
