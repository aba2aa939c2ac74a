/* embed.c: libflitter from a host program, through flitter.h only.
 *
 * Loads a Flitter script, steps it FRAMES frames in lockstep, then reads
 * one particle's position from the state dictionary, both as the value text
 * the state dump would print and as numbers.
 *
 *   usage: embed SCRIPT FRAMES KEY      e.g.  embed petri.fl 120 ':dish;0'
 *
 * Build against an installed libflitter (samples/embed/Makefile):
 *   cc -o embed embed.c $(pkg-config --cflags --libs libflitter)
 */
#include <flitter.h>

#include <stdio.h>
#include <stdlib.h>

/* Script messages: run-time errors and warnings to stderr, debug() lines
 * to stdout (what the library does by default, made explicit here). */
static void on_log(void *ctx, int kind, const char *line)
{
    (void)ctx;
    fprintf(kind == FL_LOG_DEBUG ? stdout : stderr, "%s\n", line);
}

/* Called before the library aborts when it runs out of memory. */
static void on_fatal(void *ctx, const char *message)
{
    fprintf(stderr, "%s: libflitter: %s\n", (const char *)ctx, message);
}

int main(int argc, char **argv)
{
    if (argc != 4) {
        fprintf(stderr, "usage: %s SCRIPT FRAMES KEY\n", argv[0]);
        return 2;
    }
    const char *script = argv[1], *key = argv[3];
    long frames = strtol(argv[2], NULL, 10);

    fl_options opts = fl_default_options();
    opts.log = on_log;
    opts.error = on_fatal;
    opts.ctx = argv[0];
    fl_runtime *rt = fl_new(&opts);
    if (fl_load(rt, script) != 0) {
        fputs(fl_error(rt), stderr);
        fl_free(rt);
        return 1;
    }
    for (long i = 0; i < frames; i++)
        fl_step(rt);

    char text[256];
    double position[3];
    long n = fl_state_get_numbers(rt, key, position, 3);
    if (n < 0 || fl_state_get(rt, key, text, sizeof text) < 0) {
        fprintf(stderr, "%s: no particle position under %s\n", argv[0], key);
        fl_free(rt);
        return 1;
    }
    printf("libflitter %s\n", fl_version());
    printf("frame %ld time %.17g fps %g\n", fl_frame_count(rt) - 1, fl_frame_time(rt),
           fl_target_fps(rt));
    printf("%s = %s\n", key, text);
    printf("position");
    for (long i = 0; i < n && i < 3; i++)
        printf(" %.17g", position[i]);
    printf("\n");
    fl_free(rt);
    return 0;
}
