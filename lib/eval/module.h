/* module.h: `import NAMES from FILE` (LANGUAGE.md §4.13).
 *
 * A ModuleCache belongs to one runtime. Each module file is loaded and run
 * once (again when the file changes on disk) as a program of its own: empty
 * state, no engine or define names, top-level nodes discarded. What it
 * exports is the value of every name bound at its top level when evaluation
 * reaches the end of the file. */
#ifndef FL_MODULE_H
#define FL_MODULE_H

#include "program.h"

typedef struct ModuleCache ModuleCache;

ModuleCache *module_cache_new(void);
void module_cache_free(ModuleCache *mc);

/* Bind [n] [names] from the module at [path] (already resolved against the
 * importing file's directory) into [values] (new references; NULL for a
 * missing name).
 *   errors: recorded in [ev]: `Unable to import from 'FILE'` (missing or
 *           unparseable module, names all null), `Unable to import 'NAME'
 *           from 'FILE'`, `Circular import of 'FILE'`. */
void module_import(ModuleCache *mc, Eval *ev, const char *path, Str *const *names,
                   uint32_t n, Vec **values);

#endif
