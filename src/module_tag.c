/* module_tag.c: a module's build tag (module.h), built into each module of
 * the `flitter` command and checked by module_open before it is used. */
#include "module.h"

#include "runner.h"

const ModuleTag flitter_module_tag = {FLITTER_VERSION, sizeof(RunSpec)};
