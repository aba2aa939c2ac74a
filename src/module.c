/* module.c: finding and loading the `flitter` command's modules
 * (module.h): a path search from the executable's own folder, dlopen with
 * every symbol bound at once (a module that lacks one fails here, not in
 * the middle of a run), and the check of the module's tag. */
#include "module.h"

#include <dlfcn.h>
#include <limits.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "runner.h"

#ifndef FLITTER_MODULE_REL
#define FLITTER_MODULE_REL "../lib/flitter"
#endif
#ifndef FLITTER_MODULE_DIR
#define FLITTER_MODULE_DIR "/usr/local/lib/flitter"
#endif

/* Load the module at [path] when the file exists: 1 loaded (*[handle]), 0
 * no such file, -1 found but not loadable (the reason in [why]). */
static int try_path(const char *what, const char *path, void **handle, char *why, size_t cap)
{
    if (access(path, F_OK) != 0) return 0;
    void *h = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!h) {
        snprintf(why, cap, "cannot load the %s module: %s", what, dlerror());
        return -1;
    }
    const ModuleTag *tag = dlsym(h, "flitter_module_tag");
    if (!tag) {
        snprintf(why, cap, "%s is not a flitter %s module", path, what);
        dlclose(h);
        return -1;
    }
    if (strcmp(tag->version, FLITTER_VERSION) != 0 || tag->runspec_size != sizeof(RunSpec)) {
        snprintf(why, cap,
                 "%s was built for another flitter-c (%s, a RunSpec of %zu bytes; this is %s, %zu)",
                 path, tag->version, tag->runspec_size, FLITTER_VERSION, sizeof(RunSpec));
        dlclose(h);
        return -1;
    }
    *handle = h;
    return 1;
}

void *module_open(const char *what, const char *file, const char *env_var, char *why, size_t cap)
{
    void *h = NULL;
    const char *env = getenv(env_var);
    if (env && *env) {
        int got = try_path(what, env, &h, why, cap);
        if (got == 0) snprintf(why, cap, "no %s module %s (%s)", what, env, env_var);
        return h;
    }
    char exe[PATH_MAX], path[PATH_MAX + 256];
    ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    bool found_exe = n > 0 && exe[0] == '/';
    if (found_exe) {
        exe[n] = '\0';
        *strrchr(exe, '/') = '\0';
        snprintf(path, sizeof path, "%s/%s", exe, file);
        int got = try_path(what, path, &h, why, cap);
        if (got == 0) {
            snprintf(path, sizeof path, "%s/%s/%s", exe, FLITTER_MODULE_REL, file);
            got = try_path(what, path, &h, why, cap);
        }
        if (got != 0) return h;
    }
    snprintf(path, sizeof path, "%s/%s", FLITTER_MODULE_DIR, file);
    if (try_path(what, path, &h, why, cap) == 0)
        snprintf(why, cap, "no %s module (%s) beside %s or in %s", what, file, found_exe ? exe : "the executable",
                 FLITTER_MODULE_DIR);
    return h;
}
