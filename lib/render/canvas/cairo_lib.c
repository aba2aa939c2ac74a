/* cairo_lib.c: cairo loaded with dlopen (see cairo_lib.h). */
#include "cairo_lib.h"

#include "dynload.h"

/* The soname of the major version the headers describe. */
#define CAIRO_SONAME "libcairo.so.2"

static const DynEntry entries[] = {
#define CAIRO_ENTRY(name) {#name, offsetof(CairoLib, f_##name)},
    FL_CAIRO_FUNCTIONS(CAIRO_ENTRY)
#undef CAIRO_ENTRY
};

/* Process-wide, filled once (cairo_lib.h says why). */
const void *fl_cairo;
static CairoLib table;

bool cairo_lib_ready(Buf *why)
{
    static DynLib lib = DYNLIB_INIT;
    return dynload_ready(&lib, CAIRO_SONAME, "cairo", entries, sizeof entries / sizeof *entries, &table,
                         &fl_cairo, why);
}
