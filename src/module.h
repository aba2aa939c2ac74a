/* module.h: the parts of the `flitter` command that are shared modules,
 * loaded with dlopen only when used, so that a headless run does not pay
 * for loading libraries it does not use:
 *   flitter-window.so  the live window (window.h, repl_window.h): SDL2 and
 *                      the ~50 libraries it pulls in (X11, Wayland, audio);
 *   flitter-repl.so    `flitter repl` (commands.h cmd_repl): libedit.
 * Each module defines its entry points with their usual names and
 * signatures and exports only them and its tag (window_module.map,
 * repl_module.map). The executable defines the same entry points, with the
 * same signatures (window_module.c, repl_module.c): each loads its module
 * on first use (module_open) and calls the module's own. The modules call
 * back into the executable for the fl_ API, runner.c's runspec_ functions
 * and the window's entry points, which the executable exports
 * (flitter.dynamic), and nothing else. */
#ifndef FL_MODULE_H
#define FL_MODULE_H

#include <stddef.h>

/* What a module was built against: a module of another flitter-c version,
 * or built with another RunSpec (passed by pointer to the window), is
 * refused rather than called. */
typedef struct ModuleTag {
    const char *version;     /* FLITTER_VERSION */
    size_t runspec_size;     /* sizeof(RunSpec) */
} ModuleTag;

/* Each module's tag (module_tag.c, built into each), found with dlsym. */
extern const ModuleTag flitter_module_tag;

/* Load the [what] ("window") module [file] ("flitter-window.so"), looking,
 * first found first:
 *   1. at $[env_var] when that is set (tests), and only there;
 *   2. beside the executable (/proc/self/exe): the build tree, uninstalled;
 *   3. at FLITTER_MODULE_REL (LIBDIR/flitter relative to BINDIR, baked in
 *      at configure time) from the executable's folder: installed, wherever
 *      the install tree was moved or staged (meson install --destdir);
 *   4. in FLITTER_MODULE_DIR, the absolute LIBDIR/flitter configured.
 * A module found but not loadable (a library it needs missing, a symbol
 * missing, another version's module) ends the search. The module stays
 * loaded for the rest of the process (SDL2 does not unload cleanly).
 *   shapes: dlopen's handle, for dlsym.
 *   errors: NULL with the reason, one line naming the [what] module, in
 *           [why] ([cap] bytes). */
void *module_open(const char *what, const char *file, const char *env_var, char *why, size_t cap);

#endif
