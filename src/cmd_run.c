/* cmd_run.c: `flitter run` (FORMATS.md §4): load a script, run frames in
 * lockstep (default) or realtime, and write state dumps / the node tree. */
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "commands.h"
#include "exitcodes.h"
#include "flitter.h"
#include "format.h"

static volatile sig_atomic_t interrupted;

static void on_signal(int sig)
{
    (void)sig;
    interrupted = 1;
}

static void run_usage(FILE *f)
{
    fputs("usage: flitter run [options] SCRIPT\n"
          "  --frames N          stop after N frames (default: run until interrupted)\n"
          "  --fps F             target frame rate (default 60; %pragma fps overrides it)\n"
          "  --lockstep          non-realtime clock (the default)\n"
          "  --realtime          pace frames on the wall clock\n"
          "  -D, --define NAME=VALUE  bind NAME before evaluation\n"
          "  --dump-state        write the state of the last frame to stdout\n"
          "  --dump-every K      also dump the state after every K-th frame\n"
          "  --dump-tree         write the last frame's node tree to stdout\n",
          f);
}

static bool parse_long(const char *s, long *out)
{
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (errno || end == s || *end || v < 0) return false;
    *out = v;
    return true;
}

static void dump_state(fl_runtime *rt, Buf *b)
{
    buf_reset(b);
    fmt_state_dump(b, fl_state(rt), fl_frame_count(rt) - 1, fl_frame_time(rt), fl_symbols(rt));
    fputs(buf_cstr(b), stdout);
}

int cmd_run(int argc, char **argv)
{
    enum { O_FRAMES = 256, O_FPS, O_LOCKSTEP, O_REALTIME, O_DUMP_STATE, O_DUMP_EVERY, O_DUMP_TREE };
    static const struct option longopts[] = {
        {"frames", required_argument, NULL, O_FRAMES},
        {"fps", required_argument, NULL, O_FPS},
        {"lockstep", no_argument, NULL, O_LOCKSTEP},
        {"realtime", no_argument, NULL, O_REALTIME},
        {"define", required_argument, NULL, 'D'},
        {"dump-state", no_argument, NULL, O_DUMP_STATE},
        {"dump-every", required_argument, NULL, O_DUMP_EVERY},
        {"dump-tree", no_argument, NULL, O_DUMP_TREE},
        {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0},
    };
    fl_options opts = fl_default_options();
    long frames = -1, every = 0;
    bool dump_st = false, dump_tree = false;
    char **defines = calloc((size_t)argc + 1, sizeof(char *));
    int ndefines = 0, c;
    if (!defines) return EXIT_USAGE;
    optind = 1;
    opterr = 0;
    while ((c = getopt_long(argc, argv, "D:h", longopts, NULL)) != -1) {
        char *end;
        switch (c) {
        case O_FRAMES:
            if (!parse_long(optarg, &frames)) goto bad_value;
            break;
        case O_FPS:
            opts.fps = strtod(optarg, &end);
            if (*end || !(opts.fps > 0) || isinf(opts.fps)) goto bad_value;
            break;
        case O_LOCKSTEP: opts.realtime = false; break;
        case O_REALTIME: opts.realtime = true; break;
        case 'D':
            if (!strchr(optarg, '=')) goto bad_value;
            defines[ndefines++] = optarg;
            break;
        case O_DUMP_STATE: dump_st = true; break;
        case O_DUMP_EVERY:
            if (!parse_long(optarg, &every) || every < 1) goto bad_value;
            dump_st = true;
            break;
        case O_DUMP_TREE: dump_tree = true; break;
        case 'h':
            run_usage(stdout);
            free(defines);
            return EXIT_OK;
        default:
            fprintf(stderr, "flitter run: unknown or incomplete option '%s'\n", argv[optind - 1]);
            run_usage(stderr);
            free(defines);
            return EXIT_USAGE;
        }
        continue;
    bad_value:
        fprintf(stderr, "flitter run: bad value '%s' for option '%s'\n", optarg, argv[optind - 1]);
        free(defines);
        return EXIT_USAGE;
    }
    if (optind != argc - 1) {
        fputs(optind >= argc ? "flitter run: no SCRIPT given\n" : "flitter run: more than one SCRIPT given\n",
              stderr);
        run_usage(stderr);
        free(defines);
        return EXIT_USAGE;
    }
    const char *script = argv[optind];
    opts.frames = frames;
    if (dump_st || dump_tree) opts.debug = stderr;   /* keep stdout for the dumps */
    fl_runtime *rt = fl_new(&opts);
    for (int i = 0; i < ndefines; i++) {
        char *eq = strchr(defines[i], '=');
        *eq = '\0';
        int bad = fl_define(rt, defines[i], eq + 1);
        *eq = '=';
        if (bad) {
            fprintf(stderr, "flitter run: bad name in define '%s'\n", defines[i]);
            fl_free(rt);
            free(defines);
            return EXIT_USAGE;
        }
    }
    free(defines);
    Buf err = BUF_INIT;
    if (fl_load(rt, script, &err) != 0) {
        fputs(buf_cstr(&err), stderr);
        buf_free(&err);
        fl_free(rt);
        return EXIT_LOAD;
    }
    buf_free(&err);

    signal(SIGINT, on_signal);
    signal(SIGTERM, on_signal);
    Buf out = BUF_INIT;
    bool dumped_last = false;
    while (!interrupted && (frames < 0 || fl_frame_count(rt) < frames)) {
        fl_step(rt);
        long n = fl_frame_count(rt) - 1;
        dumped_last = false;
        if (dump_st && every > 0 && (n + 1) % every == 0) {
            dump_state(rt, &out);
            dumped_last = true;
        }
        if (opts.realtime) {
            /* sleep until the next frame is due */
            double due = (double)fl_frame_count(rt) / opts.fps, now = fl_frame_time(rt);
            if (due > now) {
                struct timespec ts = {(time_t)(due - now), (long)(fmod(due - now, 1.0) * 1e9)};
                nanosleep(&ts, NULL);
            }
        }
    }
    if (fl_frame_count(rt) > 0) {
        if (dump_st && !dumped_last) dump_state(rt, &out);
        if (dump_tree) {
            buf_reset(&out);
            fmt_tree(&out, fl_root(rt), fl_symbols(rt));
            fputs(buf_cstr(&out), stdout);
        }
    }
    buf_free(&out);
    fflush(stdout);
    fl_free(rt);
    return EXIT_OK;
}
