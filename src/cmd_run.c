/* cmd_run.c: `flitter run` (FORMATS.md §4). */
#include <signal.h>
#include <stdio.h>
#include <unistd.h>

#include "commands.h"
#include "exitcodes.h"
#include "runner.h"

static volatile int interrupted;

static void on_signal(int sig)
{
    (void)sig;
    interrupted = 1;
}

int cmd_run(int argc, char **argv)
{
    RunSpec spec;
    int rc = runspec_parse(&spec, argc, argv, true, stderr);
    if (rc == 0) {
        /* a progress bar for a lockstep run of known length, else a status line */
        spec.progress = spec.verbosity >= 0 && isatty(STDERR_FILENO) && (spec.frames < 0 || !spec.realtime);
        signal(SIGINT, on_signal);
        signal(SIGTERM, on_signal);
        rc = runspec_execute(&spec, stdout, stderr, &interrupted);
    } else if (rc < 0) {
        rc = EXIT_OK;
    }
    runspec_free(&spec);
    return rc;
}
