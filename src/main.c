/* main.c: the `flitter` command: dispatches to a subcommand. */
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "commands.h"
#include "exitcodes.h"

static const struct {
    const char *name;
    int (*fn)(int argc, char **argv);
    const char *summary;
} commands[] = {
    {"run", cmd_run, "run a script headless (lockstep) or in realtime, or in a window"},
    {"repl", cmd_repl, "step a script's frames and evaluate expressions interactively"},
    {"test", cmd_test, "compare scripts' outputs with their golden files"},
    {"sweep", cmd_sweep, "list, run and collect parameter sweeps (GNU parallel, Slurm)"},
};

static void usage(FILE *f)
{
    fputs("usage: flitter COMMAND [options] ...\n\ncommands:\n", f);
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
        fprintf(f, "  %-6s %s\n", commands[i].name, commands[i].summary);
    fputs("\n`flitter help COMMAND` describes a command's options; `flitter [run options]\n"
          "SCRIPT...` is Flitter's command line: `flitter run --window` when there is a\n"
          "display (else headless `flitter run`); `flitter --version`.\n", f);
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        usage(stderr);
        return EXIT_USAGE;
    }
    if (strcmp(argv[1], "-h") == 0 || strcmp(argv[1], "--help") == 0) {
        /* Flitter's -h lists its options: those of `flitter run`, which
         * Flitter's command line `flitter [options] SCRIPT...` takes */
        usage(stdout);
        fputs("\n", stdout);
        fflush(stdout);
        char *args[] = {"run", "--help", NULL};
        return cmd_run(2, args);
    }
    if (strcmp(argv[1], "--version") == 0) {
        printf("flitter-c %s\n", FLITTER_VERSION);
        return EXIT_OK;
    }
    if (strcmp(argv[1], "help") == 0) {   /* flitter help [COMMAND] */
        if (argc < 3) {
            usage(stdout);
            return EXIT_OK;
        }
        for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
            if (strcmp(argv[2], commands[i].name) == 0) {
                char *args[] = {argv[2], "--help", NULL};
                return commands[i].fn(2, args);
            }
        fprintf(stderr, "flitter: unknown command '%s'\n", argv[2]);
        return EXIT_USAGE;
    }
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
        if (strcmp(argv[1], commands[i].name) == 0) return commands[i].fn(argc - 1, argv + 1);
    /* Flitter's own command line, `flitter [options] SCRIPT...`: cmd_run
     * sees argv[0] "flitter", not "run", and opens windows (cmd_run.c) */
    if (argv[1][0] == '-' || strchr(argv[1], '.') || strchr(argv[1], '/') || access(argv[1], F_OK) == 0)
        return cmd_run(argc, argv);
    fprintf(stderr, "flitter: unknown command '%s'\n", argv[1]);
    usage(stderr);
    return EXIT_USAGE;
}
