/* runner.c: option parsing and the headless frame loop shared by
 * `flitter run` and `flitter test` (FORMATS.md §4). */
#include "runner.h"

#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "exitcodes.h"
#include "flitter.h"
#include "format.h"

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

static bool parse_count(const char *s, long *out)
{
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (errno || end == s || *end || v < 0) return false;
    *out = v;
    return true;
}

int runspec_parse(RunSpec *spec, int argc, char **argv, bool need_script, FILE *err)
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
    *spec = (RunSpec){.frames = -1, .fps = 60.0};
    spec->defines = calloc((size_t)argc + 1, sizeof(char *));
    if (!spec->defines) abort();
    optind = 0;   /* full re-initialisation of getopt */
    opterr = 0;
    int c;
    while ((c = getopt_long(argc, argv, "+D:h", longopts, NULL)) != -1) {
        char *end;
        switch (c) {
        case O_FRAMES:
            if (!parse_count(optarg, &spec->frames)) goto bad_value;
            break;
        case O_FPS:
            spec->fps = strtod(optarg, &end);
            if (end == optarg || *end || !(spec->fps > 0) || isinf(spec->fps)) goto bad_value;
            break;
        case O_LOCKSTEP: spec->realtime = false; break;
        case O_REALTIME: spec->realtime = true; break;
        case 'D':
            if (!strchr(optarg, '=')) goto bad_value;
            spec->defines[spec->ndefines++] = optarg;
            break;
        case O_DUMP_STATE: spec->dump_state = true; break;
        case O_DUMP_EVERY:
            if (!parse_count(optarg, &spec->dump_every) || spec->dump_every < 1) goto bad_value;
            spec->dump_state = true;
            break;
        case O_DUMP_TREE: spec->dump_tree = true; break;
        case 'h':
            run_usage(stdout);
            return -1;
        default:
            fprintf(err, "flitter run: unknown option or missing value: '%s'\n", argv[optind - 1]);
            run_usage(err);
            return EXIT_USAGE;
        }
        continue;
    bad_value:
        fprintf(err, "flitter run: bad value '%s' for option '%s'\n", optarg, argv[optind - 1]);
        return EXIT_USAGE;
    }
    if (need_script) {
        if (optind != argc - 1) {
            fputs(optind >= argc ? "flitter run: no SCRIPT given\n"
                                 : "flitter run: exactly one SCRIPT expected\n", err);
            run_usage(err);
            return EXIT_USAGE;
        }
        spec->script = argv[optind];
    } else if (optind != argc) {
        fprintf(err, "flitter: unexpected argument '%s' in run options\n", argv[optind]);
        return EXIT_USAGE;
    }
    return 0;
}

void runspec_free(RunSpec *spec)
{
    free(spec->defines);
    spec->defines = NULL;
}

static void dump_state(fl_runtime *rt, FILE *out, Buf *b)
{
    buf_reset(b);
    fmt_state_dump(b, fl_state(rt), fl_frame_count(rt) - 1, fl_frame_time(rt), fl_symbols(rt));
    fwrite(b->data, 1, b->len, out);
}

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

int runspec_execute(const RunSpec *spec, FILE *out, FILE *log, volatile int *interrupt)
{
    fl_options opts = fl_default_options();
    opts.fps = spec->fps;
    opts.frames = spec->frames;
    opts.realtime = spec->realtime;
    opts.log = log;
    opts.debug = (spec->dump_state || spec->dump_tree) ? log : out;
    fl_runtime *rt = fl_new(&opts);
    for (int i = 0; i < spec->ndefines; i++) {
        char *eq = strchr(spec->defines[i], '=');
        *eq = '\0';
        int bad = fl_define(rt, spec->defines[i], eq + 1);
        *eq = '=';
        if (bad) {
            fprintf(log, "flitter run: bad name in define '%s'\n", spec->defines[i]);
            fl_free(rt);
            return EXIT_USAGE;
        }
    }
    Buf err = BUF_INIT;
    if (fl_load(rt, spec->script, &err) != 0) {
        fputs(buf_cstr(&err), log);
        buf_free(&err);
        fl_free(rt);
        return EXIT_LOAD;
    }
    buf_free(&err);
    Buf b = BUF_INIT;
    bool dumped_last = false;
    double start = now_seconds();
    while (!(interrupt && *interrupt) && (spec->frames < 0 || fl_frame_count(rt) < spec->frames)) {
        fl_step(rt);
        long n = fl_frame_count(rt) - 1;
        dumped_last = false;
        if (spec->dump_state && spec->dump_every > 0 && (n + 1) % spec->dump_every == 0) {
            dump_state(rt, out, &b);
            dumped_last = true;
        }
        if (spec->realtime) {
            double due = start + (double)fl_frame_count(rt) / spec->fps, wait = due - now_seconds();
            if (wait > 0) {
                struct timespec ts = {(time_t)wait, (long)(fmod(wait, 1.0) * 1e9)};
                nanosleep(&ts, NULL);
            }
        }
    }
    if (fl_frame_count(rt) > 0) {
        if (spec->dump_state && !dumped_last) dump_state(rt, out, &b);
        if (spec->dump_tree) {
            buf_reset(&b);
            fmt_tree(&b, fl_root(rt), fl_symbols(rt));
            fwrite(b.data, 1, b.len, out);
        }
    }
    buf_free(&b);
    fflush(out);
    fl_free(rt);
    return EXIT_OK;
}
