/* main.c: the `flitter` command: dispatches to a subcommand. */
#include <stdio.h>
#include <string.h>

#include "commands.h"
#include "exitcodes.h"

static const struct {
    const char *name;
    int (*fn)(int argc, char **argv);
    const char *summary;
} commands[] = {
    {"run", cmd_run, "run a script headless (lockstep) or in realtime"},
    {"repl", cmd_repl, "step a script's frames and evaluate expressions interactively"},
    {"test", cmd_test, "compare scripts' outputs with their golden files"},
};

static void usage(FILE *f)
{
    fputs("usage: flitter COMMAND [options] ...\n\ncommands:\n", f);
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
        fprintf(f, "  %-6s %s\n", commands[i].name, commands[i].summary);
    fputs("\n`flitter COMMAND --help` describes a command's options.\n", f);
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        usage(stderr);
        return EXIT_USAGE;
    }
    if (strcmp(argv[1], "-h") == 0 || strcmp(argv[1], "--help") == 0) {
        usage(stdout);
        return EXIT_OK;
    }
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
        if (strcmp(argv[1], commands[i].name) == 0) return commands[i].fn(argc - 1, argv + 1);
    fprintf(stderr, "flitter: unknown command '%s'\n", argv[1]);
    usage(stderr);
    return EXIT_USAGE;
}
