/* repl_module.c: the `flitter` command's side of the REPL module
 * (module.h): cmd_repl as main.c calls it, loading flitter-repl.so (the
 * REPL, with libedit) and calling the module's cmd_repl, so that no other
 * command loads libedit. $FLITTER_REPL_MODULE overrides where it is. */
#include <dlfcn.h>
#include <stdio.h>

#include "commands.h"
#include "exitcodes.h"
#include "module.h"

int cmd_repl(int argc, char **argv)
{
    char why[512];
    void *h = module_open("REPL", "flitter-repl.so", "FLITTER_REPL_MODULE", why, sizeof why);
    int (*repl)(int, char **) = NULL;
    if (h) *(void **)&repl = dlsym(h, "cmd_repl");   /* POSIX's conversion */
    if (!repl) {
        fprintf(stderr, "flitter: %s\n", h ? "the REPL module lacks cmd_repl" : why);
        return EXIT_LOAD;
    }
    return repl(argc, argv);
}
