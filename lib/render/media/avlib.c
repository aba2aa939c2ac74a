/* avlib.c: FFmpeg loaded with dlopen (see avlib.h). */
#include "avlib.h"

#include <dlfcn.h>
#include <stdlib.h>
#include <string.h>

#include <libavutil/macros.h>

#include "mem.h"

enum { LIB_avutil, LIB_swscale, LIB_avcodec, LIB_avformat, NLIBS };

/* The sonames of the major versions the headers describe, in load order
 * (each after the libraries it needs). */
static const char *const sonames[NLIBS] = {
    "libavutil.so." AV_STRINGIFY(LIBAVUTIL_VERSION_MAJOR),
    "libswscale.so." AV_STRINGIFY(LIBSWSCALE_VERSION_MAJOR),
    "libavcodec.so." AV_STRINGIFY(LIBAVCODEC_VERSION_MAJOR),
    "libavformat.so." AV_STRINGIFY(LIBAVFORMAT_VERSION_MAJOR),
};

typedef struct Entry {
    int lib;          /* LIB_* */
    const char *name; /* the symbol */
    size_t offset;    /* of its pointer in AvLib */
} Entry;

static const Entry entries[] = {
#define AVLIB_ENTRY(lib, name) {LIB_##lib, #name, offsetof(AvLib, name)},
    AVLIB_FUNCTIONS(AVLIB_ENTRY)
#undef AVLIB_ENTRY
};

AvLib *avlib_load(Buf *err)
{
    void *h[NLIBS];
    for (int i = 0; i < NLIBS; i++) {
        if (!(h[i] = dlopen(sonames[i], RTLD_NOW | RTLD_LOCAL))) {
            const char *why = dlerror();
            buf_printf(err, "cannot load FFmpeg: %s\n", why ? why : sonames[i]);
            return NULL;   /* what was opened stays loaded (avlib.h) */
        }
    }
    AvLib *L = calloc(1, sizeof *L);
    if (!L) mem_oom();
    for (size_t i = 0; i < sizeof entries / sizeof *entries; i++) {
        void *f = dlsym(h[entries[i].lib], entries[i].name);
        if (!f) {
            buf_printf(err, "cannot load FFmpeg: no %s in %s\n", entries[i].name, sonames[entries[i].lib]);
            free(L);
            return NULL;
        }
        /* a data pointer to a function pointer: POSIX guarantees dlsym's */
        memcpy((char *)L + entries[i].offset, &f, sizeof f);
    }
    return L;
}
