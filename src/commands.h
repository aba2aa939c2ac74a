/* commands.h: the `flitter` subcommands; each takes the arguments after
 * its own name (argv[0] is the subcommand) and returns an exit status. */
#ifndef FL_COMMANDS_H
#define FL_COMMANDS_H

int cmd_run(int argc, char **argv);
int cmd_repl(int argc, char **argv);
int cmd_test(int argc, char **argv);
int cmd_sweep(int argc, char **argv);

#endif
