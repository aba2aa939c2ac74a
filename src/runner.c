/* runner.c: option parsing and the headless frame loop shared by
 * `flitter run` and `flitter test` (FORMATS.md §4). */
#include "runner.h"
#include "prefault.h"

#include <ctype.h>
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <sys/stat.h>
#include <unistd.h>

#include "exitcodes.h"
#include "flitter.h"
#include "memcheck.h"

/* Whether a run's runtime may be left to the process's exit instead of
 * freed: [spec] says the process ends with the run, and no memory checker
 * is there to expect every block back. Freeing it is only giving memory
 * back block by block (every file is written and closed by then, and the
 * physics threads are idle); for a loaded program of 20,000 particles it
 * took a tenth of the run. */
static bool left_to_exit(const RunSpec *spec) { return spec->exiting && !memory_checked(); }

static void run_usage(FILE *f)
{
    fputs("usage: flitter run [options] SCRIPT...\n"
          "  --frames N          stop after N frames (default: run until interrupted)\n"
          "  --fps F             target frame rate (default 60; %pragma fps overrides it)\n"
          "  --lockstep          non-realtime clock (the default)\n"
          "  --realtime          pace frames on the wall clock\n"
          "  -D, --define NAME=VALUE  bind NAME before evaluation; VALUE as Flitter reads\n"
          "                      it: ;-separated :symbols, numbers (-3, 1e3, 10k, 90deg),\n"
          "                      time codes (1:30) or else text (empty: the empty string)\n"
          "  --dump-state        write the state of the last frame to stdout\n"
          "  --dump-every K      also dump the state after every K-th frame\n"
          "  --dump-tree         write the last frame's node tree to stdout\n"
          "  --state FILE        load the state from FILE at start (if it exists) and save\n"
          "                      it back atomically at exit and every 5 seconds\n"
          "  --max-steps N       at most N physics steps per system per frame (default\n"
          "                      10000; 0: no limit); beyond, the simulation slows down\n"
          "  --threads N         threads for physics and loop kernels (default:\n"
          "                      FLITTER_THREADS, else all cores)\n"
          "  --max-memory SIZE   memory budget, SIZE bytes or with K, M or G (default: half\n"
          "                      of physical memory, at most half of ulimit -v); past it\n"
          "                      an expression gives null with an error, a load fails\n"
          "                      with `out of memory` (exit 1)\n"
          "  --pairs naive|fast  physics pair loop: the reference all-pairs loop, or the\n"
          "                      neighbour grid and threads (default fast; same results)\n"
          "  --particles literal|fast  physics particle pass: PHYSICS-ENGINE.md as written,\n"
          "                      one particle at a time, or compiled per dimension count\n"
          "                      (default fast; same results)\n"
          "  --physics documented|upstream  PHYSICS.md's physics (default), or Flitter\n"
          "                      1.0.0b28's where it departs from PHYSICS.md (eases,\n"
          "                      !field, barrier max; README); %pragma physics overrides it\n"
          "  --nosimplify        run the program as parsed, without Flitter's load-time\n"
          "                      simplifier (also --no-simplify)\n"
          "  --dump-simplified   print the program as it will run (after simplification)\n"
          "                      to stdout before the first frame; without --frames,\n"
          "                      stop there\n"
          "  --dump-tokens       print the script's tokens (after the indentation\n"
          "                      filter) to stdout and stop\n"
          "  --dump-ast          print the script's syntax tree as parsed (before the\n"
          "                      simplifier) to stdout and stop\n"
          "  --runtime T         run T seconds of the clock: round(T*fps) frames in\n"
          "                      lockstep, T seconds of wall clock when realtime; T\n"
          "                      is seconds (2.5) or Flitter's time code M:S or H:M:S\n"
          "                      (0:05, 1:02:03.5)\n"
          "  Log levels (Flitter's; give at most one):\n"
          "  --quiet             warnings and errors only: no progress bar or status\n"
          "                      line, no notes\n"
          "  --verbose           also informational lines (the version at start)\n"
          "  --debug             also the debug lines (drawing details; the skipped,\n"
          "                      unsupported node kinds are named at every level)\n"
          "  --trace             everything --debug says, and a line per frame\n"
          "                      (frame, clock, eval and physics ms)\n"
          "  --stats             at exit, print frames/s, allocations per frame, the\n"
          "                      eval/physics/state split and the load's ms to stderr\n"
          "  --view FILE         draw the physics systems: FILE.png or .svg (last frame),\n"
          "                      FILE.gif (an animation frame every --view-every K frames);\n"
          "                      a 3D system in perspective with lit spheres (OpenGL)\n"
          "  --view-axes A;B     draw the physics view flat on coordinates A and B (two of\n"
          "                      x, y, z, w), e.g. x;z, for every system that has both\n"
          "                      (also the window's physics view)\n"
          "  --trace-file FILE   write particle positions and velocities each frame (or\n"
          "                      every --trace-every K) to FILE.csv or FILE.jsonl; also\n"
          "                      --trace=FILE, with the '=' only: a bare --trace is the\n"
          "                      log level and never takes the next word (in Flitter,\n"
          "                      `flitter --trace a.fl b.fl` runs two pages)\n"
          "  --record FILE       record the first window to FILE (.png, .gif, or a video:\n"
          "                      .mp4, .mov, .m4v, .mkv, .webm; written at exit)\n"
          "  --window            show each !window in a window (SDL) as it is drawn; a\n"
          "                      script without !window shows its physics systems. The\n"
          "                      clock is realtime unless --lockstep is given (then\n"
          "                      every frame is shown). `flitter [options] SCRIPT...`\n"
          "                      (Flitter's command line) opens windows too when there\n"
          "                      is a display, else runs headless as `flitter run`\n"
          "  --offscreen         never open a window (Flitter's option)\n"
          "  --fullscreen        windows fill the screen (a !window's fullscreen= wins)\n"
          "  --screen N          open windows on display N (from 0)\n"
          "  --vsync             present frames in step with the display (a !window's\n"
          "                      vsync= wins)\n"
          "  --resetonswitch     empty a page's state when switching away from it\n"
          "  --vmstats           the same as --stats (Flitter's VM statistics)\n"
          "  --modelcache T      keep a 3D model no frame uses (a file, CSG, an SDF) and\n"
          "                      its mesh cached for T (seconds or a timecode; default 300)\n"
          "  --profile, --opengles   Flitter's options, accepted; they have no effect\n"
          "                      here (a note says so, unless --quiet)\n"
          "  --min-scale F       the live window draws its pictures at fewer pixels when\n"
          "                      they cannot keep its frame rate, never fewer than the\n"
          "                      fraction F of them (0 < F <= 1; default 0.25; 1: always\n"
          "                      the full size); files (!record, --record) are always\n"
          "                      drawn whole. F1 shows the scale in use\n"
          "  --window-size WxH   the physics view window's size in pixels when a frame\n"
          "                      has no !window (default 512x512; a !window's size= sets\n"
          "                      its own window's)\n"
          "  In a window: several SCRIPTs are pages, switched with the left and right\n"
          "  arrows; saving a script or a file it includes or imports reloads it (an\n"
          "  error is shown and the last good version keeps running); Escape or\n"
          "  closing the window ends the run (--state saved, --dump-state printed);\n"
          "  F1 status overlay (frame rate, clock, eval/physics/draw ms, dropped\n"
          "  frames), F2 picture or physics view, F5 pause, F6 one frame when paused.\n"
          "  A !key of the script claims a key first. Without a window, windows are\n"
          "  drawn offscreen and !record filename=F (.png, .gif or a video: .mp4, .mov,\n"
          "  .m4v, .mkv, .webm) written (README: Drawing).\n",
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

/* The long name of the option whose getopt code is [c] ("frames";
 * "define" for -D), for messages. */
static const char *option_name(const struct option *opts, int c)
{
    for (; opts->name; opts++)
        if (opts->val == c)
            return opts->name;
    return "?";
}

/* True (with a message on [err]) when an output option of [spec] would
 * write over a script or another Flitter script: `flitter --trace a.fl
 * b.fl` (in Flitter --trace is a log level) must not replace a.fl. */
static bool output_clobbers(const RunSpec *spec, FILE *err)
{
    const struct { const char *option, *path; } outs[] = {
        {"--trace-file", spec->trace}, {"--view", spec->view}, {"--record", spec->record},
    };
    for (size_t i = 0; i < sizeof outs / sizeof outs[0]; i++) {
        const char *path = outs[i].path;
        if (!path) continue;
        size_t n = strlen(path);
        bool script = n >= 3 && strcmp(path + n - 3, ".fl") == 0;
        struct stat a, b;
        for (int k = 0; !script && k < spec->nscripts; k++)
            script = stat(path, &a) == 0 && stat(spec->scripts[k], &b) == 0 && a.st_dev == b.st_dev &&
                     a.st_ino == b.st_ino;
        if (script) {
            fprintf(err, "flitter run: %s %s would write over a Flitter script; refused (the "
                         "option takes an output file: .csv/.jsonl for --trace-file, .png/.svg/.gif "
                         "for --view, a picture or video for --record)\n", outs[i].option, path);
            return true;
        }
    }
    return false;
}

/* Flitter's time code (language/parser.py, convert_timecode_to_float):
 * SECONDS, M:SECONDS or H:M:SECONDS, the hours and minutes whole numbers,
 * the seconds any decimal number ("0:05", "1:02:03.5", "2.5"). */
static bool parse_timecode(const char *s, double *out)
{
    double total = 0;
    const char *p = s;
    int colons = 0;
    for (const char *q = s; *q; q++) colons += *q == ':';
    if (colons > 2) return false;
    for (int i = 0; i < colons; i++) {
        char *end;
        if (!isdigit((unsigned char)*p)) return false;
        errno = 0;
        long v = strtol(p, &end, 10);
        if (errno || *end != ':' || v > 1000000000L) return false;
        total += (double)v * (colons - i == 2 ? 3600.0 : 60.0);
        p = end + 1;
    }
    char *end;
    if (!*p || isspace((unsigned char)*p)) return false;
    double sec = strtod(p, &end);
    if (end == p || *end || !(sec >= 0) || isinf(sec)) return false;
    *out = total + sec;
    return true;
}

/* The one-line notes of Flitter's options that do nothing here. */
static const char *const no_effect_note[] = {
    "--profile has no effect in flitter-c (use --stats for the time per frame)",
    "--opengles has no effect in flitter-c (pictures are drawn with desktop OpenGL 3.3 "
    "through EGL or the window's context, not OpenGL ES)",
};

int runspec_parse(RunSpec *spec, int argc, char **argv, int scripts, FILE *err)
{
    enum { O_FRAMES = 256, O_FPS, O_LOCKSTEP, O_REALTIME, O_DUMP_STATE, O_DUMP_EVERY, O_DUMP_TREE,
           O_STATE, O_THREADS, O_PAIRS, O_RUNTIME, O_OFFSCREEN, O_QUIET, O_VERBOSE, O_DEBUG,
           O_NOSIMPLIFY, O_VIEW, O_VIEW_EVERY, O_VIEW_AXES, O_TRACE, O_TRACE_EVERY, O_DUMP_SIMPLIFIED, O_DUMP_TOKENS, O_DUMP_AST, O_STATS,
           O_MAX_STEPS, O_PARTICLES, O_PHYSICS, O_WINDOW, O_FULLSCREEN, O_SCREEN, O_VSYNC,
           O_RESETONSWITCH, O_RECORD, O_WINDOW_SIZE, O_MIN_SCALE, O_TRACE_FILE, O_PROFILE, O_OPENGLES,
           O_MODELCACHE, O_VMSTATS, O_MAX_MEMORY };
    static const struct option longopts[] = {
        {"frames", required_argument, NULL, O_FRAMES},
        {"fps", required_argument, NULL, O_FPS},
        {"lockstep", no_argument, NULL, O_LOCKSTEP},
        {"realtime", no_argument, NULL, O_REALTIME},
        {"define", required_argument, NULL, 'D'},
        {"dump-state", no_argument, NULL, O_DUMP_STATE},
        {"dump-every", required_argument, NULL, O_DUMP_EVERY},
        {"dump-tree", no_argument, NULL, O_DUMP_TREE},
        {"state", required_argument, NULL, O_STATE},
        {"max-steps", required_argument, NULL, O_MAX_STEPS},
        {"threads", required_argument, NULL, O_THREADS},
        {"max-memory", required_argument, NULL, O_MAX_MEMORY},
        {"pairs", required_argument, NULL, O_PAIRS},
        {"particles", required_argument, NULL, O_PARTICLES},
        {"physics", required_argument, NULL, O_PHYSICS},
        {"stats", no_argument, NULL, O_STATS},
        {"nosimplify", no_argument, NULL, O_NOSIMPLIFY},
        {"no-simplify", no_argument, NULL, O_NOSIMPLIFY},
        {"dump-simplified", no_argument, NULL, O_DUMP_SIMPLIFIED},
        {"dump-tokens", no_argument, NULL, O_DUMP_TOKENS},
        {"dump-ast", no_argument, NULL, O_DUMP_AST},
        {"help", no_argument, NULL, 'h'},
        {"runtime", required_argument, NULL, O_RUNTIME},
        {"offscreen", no_argument, NULL, O_OFFSCREEN},
        {"quiet", no_argument, NULL, O_QUIET},
        {"verbose", no_argument, NULL, O_VERBOSE},
        {"debug", no_argument, NULL, O_DEBUG},
        {"view", required_argument, NULL, O_VIEW},
        {"view-every", required_argument, NULL, O_VIEW_EVERY},
        {"view-axes", required_argument, NULL, O_VIEW_AXES},
        /* a bare --trace is Flitter's log level; only --trace=FILE (an
         * explicit '=') names a trace file, so no script is ever taken */
        {"trace", optional_argument, NULL, O_TRACE},
        {"trace-file", required_argument, NULL, O_TRACE_FILE},
        {"profile", no_argument, NULL, O_PROFILE},
        {"opengles", no_argument, NULL, O_OPENGLES},
        {"modelcache", required_argument, NULL, O_MODELCACHE},
        {"vmstats", no_argument, NULL, O_VMSTATS},
        {"trace-every", required_argument, NULL, O_TRACE_EVERY},
        {"record", required_argument, NULL, O_RECORD},
        {"window", no_argument, NULL, O_WINDOW},
        {"fullscreen", no_argument, NULL, O_FULLSCREEN},
        {"screen", required_argument, NULL, O_SCREEN},
        {"vsync", no_argument, NULL, O_VSYNC},
        {"resetonswitch", no_argument, NULL, O_RESETONSWITCH},
        {"window-size", required_argument, NULL, O_WINDOW_SIZE},
        {"min-scale", required_argument, NULL, O_MIN_SCALE},
        {NULL, 0, NULL, 0},
    };
    *spec = (RunSpec){.frames = -1, .fps = 60.0, .runtime = -1, .max_steps = 10000,
                      .view_width = 512, .view_height = 512, .min_scale = 0.25,
                      .window = scripts == RUNSPEC_PAGES,
                      .implicit_window = scripts == RUNSPEC_PAGES};
    bool frames_given = false;
    bool notes[2] = {false, false};
    int level = 0;                /* the log level option given, 0: none */
    const char *level_name = NULL;
    spec->defines = calloc((size_t)argc + 1, sizeof(char *));
    if (!spec->defines) abort();
    optind = 0;   /* full re-initialisation of getopt */
    opterr = 0;
    int c;
    /* options anywhere, before or after the SCRIPTs, as Flitter's argparse
     * takes them (GNU getopt moves the SCRIPTs to the end) */
    while ((c = getopt_long(argc, argv, "D:h", longopts, NULL)) != -1) {
        char *end;
        switch (c) {
        case O_FRAMES:
            if (!parse_count(optarg, &spec->frames)) goto bad_value;
            frames_given = true;
            break;
        case O_FPS:
            spec->fps = strtod(optarg, &end);
            /* a positive rate whose clock reaches frame 2^53 (the last a
             * state file holds) at a finite time */
            if (end == optarg || *end || !(spec->fps > 0) || isinf(spec->fps)) goto bad_value;
            if (isinf((double)(INT64_C(1) << 53) / spec->fps)) {
                fprintf(err, "flitter run: --fps %s is too small: the clock's time would pass the "
                        "largest finite number before frame 2^53, and a state file could not hold "
                        "it\n", optarg);
                return EXIT_USAGE;
            }
            break;
        case O_LOCKSTEP: spec->realtime = false; spec->clock_given = true; break;
        case O_REALTIME: spec->realtime = true; spec->clock_given = true; break;
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
        case O_STATE: spec->state_file = optarg; break;
        case O_MAX_STEPS:
            if (!parse_count(optarg, &spec->max_steps)) goto bad_value;
            break;
        case O_THREADS: {
            long n;
            if (!parse_count(optarg, &n) || n < 1 || n > 1024) goto bad_value;
            spec->threads = (int)n;
            break;
        }
        case O_MAX_MEMORY:
            if (!fl_parse_memory(optarg, &spec->max_memory)) goto bad_value;
            break;
        case O_PAIRS:
            if (!fl_parse_pairs(optarg, &spec->pairs)) goto bad_value;
            break;
        case O_PARTICLES:
            if (!fl_parse_particles(optarg, &spec->particles)) goto bad_value;
            break;
        case O_PHYSICS:
            if (!fl_parse_physics(optarg, &spec->physics)) goto bad_value;
            break;
        case O_STATS: spec->stats = true; break;
        case O_NOSIMPLIFY: spec->no_simplify = true; break;
        case O_DUMP_SIMPLIFIED: spec->dump_simplified = true; break;
        case O_DUMP_TOKENS: spec->dump_syntax = 1; break;
        case O_DUMP_AST: spec->dump_syntax = 2; break;
        case O_RUNTIME:
            if (!parse_timecode(optarg, &spec->runtime)) goto bad_value;
            break;
        case O_MODELCACHE: {
            double t;
            if (!parse_timecode(optarg, &t) || !(t >= 0) || t > 1e9) goto bad_value;
            spec->model_cache = t > 0 ? t : 1e-9;   /* 0: drop an unused model at once */
            break;
        }
        case O_PROFILE: notes[0] = true; break;
        case O_OPENGLES: notes[1] = true; break;
        case O_VMSTATS: spec->stats = true; break;
        case O_OFFSCREEN: spec->offscreen = true; break;
        case O_WINDOW: spec->window = true; spec->implicit_window = false; break;
        case O_FULLSCREEN: spec->fullscreen = true; break;
        case O_VSYNC: spec->vsync = true; break;
        case O_RESETONSWITCH: spec->reset_on_switch = true; break;
        case O_WINDOW_SIZE: {
            /* WxH, each 1..16384 pixels */
            long w = strtol(optarg, &end, 10), h;
            if (end == optarg || *end != 'x' || w < 1 || w > 16384) goto bad_value;
            const char *hs = end + 1;
            h = strtol(hs, &end, 10);
            if (end == hs || *end || h < 1 || h > 16384 || !isdigit((unsigned char)*optarg) ||
                !isdigit((unsigned char)*hs))
                goto bad_value;
            spec->view_width = (int)w;
            spec->view_height = (int)h;
            break;
        }
        case O_MIN_SCALE: {
            double f = strtod(optarg, &end);
            if (end == optarg || *end || !(f > 0 && f <= 1)) goto bad_value;
            spec->min_scale = f;
            break;
        }
        case O_SCREEN: {
            long n;
            if (!parse_count(optarg, &n) || n > 255) goto bad_value;
            spec->screen = (int)n;
            break;
        }
        case O_TRACE:
            if (optarg) {   /* --trace=FILE: the trace file */
                spec->trace = optarg;
                break;
            }
            __attribute__((fallthrough));   /* a bare --trace: the log level */
        case O_QUIET:
        case O_VERBOSE:
        case O_DEBUG: {
            /* Flitter's log levels, mutually exclusive as in its argparse */
            const char *name = option_name(longopts, c);
            if (level && level != c) {
                fprintf(err, "flitter run: --%s and --%s are both log levels: give one\n", level_name,
                        name);
                return EXIT_USAGE;
            }
            level = c;
            level_name = name;
            spec->verbosity = c == O_QUIET ? -1 : c == O_VERBOSE ? 1 : c == O_DEBUG ? 2 : 3;
            break;
        }
        case O_VIEW: spec->view = optarg; break;
        case O_VIEW_AXES:
            if (!fl_parse_view_axes(optarg, spec->view_axes)) goto bad_value;
            break;
        case O_TRACE_FILE: spec->trace = optarg; break;
        case O_RECORD: spec->record = optarg; break;
        case O_VIEW_EVERY:
            if (!parse_count(optarg, &spec->view_every) || spec->view_every < 1) goto bad_value;
            break;
        case O_TRACE_EVERY:
            if (!parse_count(optarg, &spec->trace_every) || spec->trace_every < 1) goto bad_value;
            break;
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
        fprintf(err, "flitter run: bad value '%s' for option '--%s'\n", optarg, option_name(longopts, c));
        return EXIT_USAGE;
    }
    for (int i = 0; i < 2; i++)
        if (notes[i] && spec->verbosity >= 0) fprintf(err, "flitter: %s\n", no_effect_note[i]);
    spec->runtime_clock = spec->runtime >= 0 && !frames_given;
    if (spec->runtime >= 0 && !frames_given) {   /* as Flitter: round(T*fps) frames */
        double frames = spec->runtime * spec->fps;
        if (!(frames < 1e15)) {
            fprintf(err, "flitter run: --runtime %g is too long at %g frames/s\n", spec->runtime, spec->fps);
            return EXIT_USAGE;
        }
        spec->frames = lround(frames);
    }
    if (scripts != RUNSPEC_NO_SCRIPT) {
        /* several SCRIPTs are pages, which only a window can switch */
        bool pages = spec->window;
        if (optind >= argc || (optind != argc - 1 && !pages)) {
            fputs(optind >= argc ? "flitter run: no SCRIPT given\n"
                                 : "flitter run: exactly one SCRIPT expected\n", err);
            run_usage(err);
            return EXIT_USAGE;
        }
        spec->scripts = argv + optind;
        spec->nscripts = argc - optind;
        spec->script = argv[optind];
        if (output_clobbers(spec, err)) return EXIT_USAGE;
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

bool runspec_wants_window(const RunSpec *spec)
{
    return spec->window && !spec->offscreen && !spec->dump_syntax &&
           !(spec->dump_simplified && spec->frames < 0);
}

/* fl_write_fn: append to the FILE [ctx]. */
static void write_file(void *ctx, const char *text, size_t len) { fwrite(text, 1, len, ctx); }

/* fl_log_fn: message lines to the RunLog [ctx]. */
static void log_lines(void *ctx, int kind, const char *line)
{
    const RunLog *f = ctx;
    fprintf(kind == FL_LOG_DEBUG ? f->debug : f->log, "%s\n", line);
}

/* The library's fatal error (out of memory): report it before the abort. */
static void fatal(void *ctx, const char *message)
{
    const RunLog *f = ctx;
    fprintf(f->log, "flitter: %s\n", message);
    fflush(f->log);
}

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* The modification time of [path] (zero when it cannot be read). */
static struct timespec file_mtime(const char *path)
{
    struct stat sb;
    if (stat(path, &sb) != 0) return (struct timespec){0, 0};
    return sb.st_mtim;
}

static bool same_time(struct timespec a, struct timespec b)
{
    return a.tv_sec == b.tv_sec && a.tv_nsec == b.tv_nsec;
}

/* One line of progress on stderr: bar, frames, frames per second, ETA. */
static void show_progress(long done, long total, double elapsed)
{
    const int width = 30;
    int filled = total ? (int)((double)done / (double)total * width) : width;
    double rate = elapsed > 0 ? (double)done / elapsed : 0;
    double eta = rate > 0 ? (double)(total - done) / rate : 0;
    char bar[64];
    for (int i = 0; i < width; i++) bar[i] = i < filled ? '#' : '.';
    bar[width] = '\0';
    fprintf(stderr, "\r[%s] %ld/%ld frames  %.0f frames/s  ETA %.1fs ", bar, done, total, rate, eta);
    fflush(stderr);
}

bool runspec_runtime_over(const RunSpec *spec, double elapsed, double fps)
{
    return round(elapsed * fps) >= round(spec->runtime * fps);
}

void runspec_print_stats(fl_runtime *rt, const fl_stats *first, const fl_stats *second,
                         double loop, const LoadTimes *load, FILE *log)
{
    fl_stats s;
    fl_get_stats(rt, &s);
    double n = s.frames > 0 ? (double)s.frames : 1;
    double steady = s.frames > 2 ? (double)(s.frames - 2) : 1;
    if (s.frames < 2) second = &s;
    fprintf(log, "stats: %ld frames in %.3f s: %.1f frames/s\n", s.frames, loop,
            loop > 0 ? (double)s.frames / loop : 0.0);
    fprintf(log, "stats: per frame: eval %.3f ms, physics %.3f ms, other %.3f ms\n",
            s.eval_seconds / n * 1e3, s.physics_seconds / n * 1e3, s.other_seconds / n * 1e3);
    if (s.frames > 2)   /* without the first two, which fill the free lists and caches; to the
                         * nanosecond, as a static scene evaluates in well under a microsecond */
        fprintf(log, "stats: per steady frame: eval %.6f ms, physics %.6f ms, other %.6f ms\n",
                (s.eval_seconds - second->eval_seconds) / steady * 1e3,
                (s.physics_seconds - second->physics_seconds) / steady * 1e3,
                (s.other_seconds - second->other_seconds) / steady * 1e3);
    fprintf(log, "stats: allocations: first frame %llu mallocs %llu frees; second %llu mallocs "
            "%llu frees; after them %.2f mallocs %.2f frees per frame; last frame %llu mallocs "
            "%llu frees\n",
            first->mallocs, first->frees, second->mallocs - first->mallocs,
            second->frees - first->frees, (double)(s.mallocs - second->mallocs) / steady,
            (double)(s.frees - second->frees) / steady, s.last_mallocs, s.last_frees);
    fprintf(log, "stats: state per frame: %.1f reads, %.1f writes\n", (double)s.state_gets / n,
            (double)s.state_sets / n);
    if (!load) return;
    fprintf(log, "stats: load %.3f ms", load->first * 1e3);
    if (load->reloads > 0)
        fprintf(log, "; %ld live reload%s, the last %.3f ms", load->reloads,
                load->reloads == 1 ? "" : "s", load->last * 1e3);
    fputc('\n', log);
}

/* The status line of a run without --frames: frame, frames/s, clock. */
static void show_status(long frame, double rate, double time)
{
    fprintf(stderr, "\rframe %ld  %.0f frames/s  time %.2fs ", frame, rate, time);
    fflush(stderr);
}

/* Flush [out] (the dumps' stream): a write that failed there (a full disk,
 * /dev/full, a closed pipe) is reported on [log] and gives EXIT_LOAD, so a
 * lost dump never exits 0. */
static int finish_out(FILE *out, FILE *log, int rc)
{
    errno = 0;
    if (fflush(out) != 0 || ferror(out)) {
        int e = errno;
        fprintf(log, "flitter run: the output is incomplete: a write to it failed%s%s\n",
                e ? ": " : "", e ? strerror(e) : "");
        clearerr(out);
        return rc == EXIT_OK ? EXIT_LOAD : rc;
    }
    return rc;
}

int runspec_check_outputs(const RunSpec *spec, FILE *err)
{
    const struct { const char *option, *path; } outs[] = {
        {"--view", spec->view}, {"--trace-file", spec->trace}, {"--record", spec->record},
        {"--state", spec->state_file},
    };
    for (size_t i = 0; i < sizeof outs / sizeof outs[0]; i++) {
        char why[700];
        if (outs[i].path && fl_check_output(outs[i].path, why, sizeof why) != 0) {
            fprintf(err, "flitter run: %s %s cannot be written (%s); nothing was run\n",
                    outs[i].option, outs[i].path, why);
            return EXIT_USAGE;
        }
    }
    return 0;
}

static int save_state(fl_runtime *rt, const char *path, FILE *log)
{
    int rc = fl_save_state(rt, path);
    if (rc != 0) fputs(fl_error(rt), log);
    return rc;
}

/* Whether environment variable [name] is set, not empty and not "0". */
static bool env_on(const char *name)
{
    const char *e = getenv(name);
    return e && *e && strcmp(e, "0") != 0;
}

/* Environment variable [name] as a whole number 0..UINT32_MAX, else 0. */
static unsigned env_count(const char *name)
{
    const char *e = getenv(name);
    if (!e || !isdigit((unsigned char)*e)) return 0;
    errno = 0;
    char *end;
    unsigned long n = strtoul(e, &end, 10);
    return *end || errno || n > UINT32_MAX ? 0 : (unsigned)n;
}

/* Whether environment variable [name] is exactly [value]. */
static bool env_is(const char *name, const char *value)
{
    const char *e = getenv(name);
    return e && strcmp(e, value) == 0;
}

void runspec_options_from_env(fl_options *o)
{
    if (!o) return;
    unsigned threads = env_count("FLITTER_THREADS");
    if (o->threads == 0 && threads >= 1 && threads <= 1024) o->threads = (int)threads;
    if (o->pairs == FL_PAIRS_DEFAULT && env_is("FLITTER_PAIRS", "naive")) o->pairs = FL_PAIRS_NAIVE;
    if (o->particles == FL_PARTICLES_DEFAULT && env_is("FLITTER_PARTICLES", "literal"))
        o->particles = FL_PARTICLES_LITERAL;
    fl_debug_options *d = &o->debug;
    const char *e = getenv("FLITTER_NOPOOL");
    d->no_pool = e && *e;
    e = getenv("FLITTER_NOFAST");
    d->no_fast = e && *e;
    e = getenv("FLITTER_NOKERNEL");
    d->no_kernel = e && *e;
    d->no_kernel_reuse = env_is("FLITTER_KERNEL_REUSE", "0");
    d->kernel_chunk = env_count("FLITTER_KERNEL_CHUNK");
    d->kernel_window = env_count("FLITTER_KERNEL_WINDOW");
    d->no_templates = env_on("FLITTER_NOTEMPLATES");
    d->no_draw = env_on("FLITTER_NODRAW");
    d->check_templates = env_on("FLITTER_TEMPLATE_CHECK");
    e = getenv("FLITTER_SIMD");
    d->simd = !e                           ? FL_SIMD_AUTO
              : !strcmp(e, "portable")      ? FL_SIMD_PORTABLE
              : !strcmp(e, "avx2")          ? FL_SIMD_AVX2
              : !strcmp(e, "avx2-avx512vl") ? FL_SIMD_AVX2_VL
                                            : FL_SIMD_AVX512;
    d->impostors = env_is("FLITTER_CANVAS3D_IMPOSTORS", "0")     ? FL_IMPOSTORS_OFF
                   : env_is("FLITTER_CANVAS3D_IMPOSTORS", "box") ? FL_IMPOSTORS_BOX
                                                                 : FL_IMPOSTORS_OCTAGONS;
    d->occlusion = env_is("FLITTER_CANVAS3D_OCCLUSION", "0")   ? FL_OCCLUSION_NEVER
                   : env_is("FLITTER_CANVAS3D_OCCLUSION", "1") ? FL_OCCLUSION_ALWAYS
                                                               : FL_OCCLUSION_AUTO;
    d->no_light_culling = env_is("FLITTER_CANVAS3D_CULLING", "0");
}

fl_runtime *runspec_runtime(const RunSpec *spec, RunLog *files, volatile int *interrupt)
{
    fl_options opts = fl_default_options();
    opts.fps = spec->fps;
    opts.frames = spec->frames;
    opts.realtime = spec->realtime;
    opts.threads = spec->threads;
    opts.max_memory = spec->max_memory;
    opts.model_cache = spec->model_cache;
    opts.pairs = spec->pairs;
    opts.view_axes[0] = spec->view_axes[0];
    opts.view_axes[1] = spec->view_axes[1];
    opts.particles = spec->particles;
    opts.physics = spec->physics;
    opts.no_simplify = spec->no_simplify;
    opts.log = log_lines;
    opts.error = fatal;
    opts.ctx = files;
    opts.max_physics_steps = spec->max_steps;
    opts.interrupt = interrupt;
    /* a headless run that writes no tree dump, view or trace at its end
     * reads each frame's tree only before the next (its physics, counters
     * and !window pictures), so the tree may go when the next frame starts
     * (flitter.h); a window keeps its last tree to draw */
    opts.transient_tree = !spec->dump_tree && !spec->view && !spec->trace && !spec->record && !spec->window &&
                          !spec->offscreen && spec->nscripts <= 1;
    runspec_options_from_env(&opts);
    fl_runtime *rt = fl_new(&opts);
    for (int i = 0; i < spec->ndefines; i++) {
        char *eq = strchr(spec->defines[i], '=');
        *eq = '\0';
        int bad = fl_define(rt, spec->defines[i], eq + 1);
        *eq = '=';
        if (bad) {
            fprintf(files->log, "flitter run: bad name in define '%s'\n", spec->defines[i]);
            fl_free(rt);
            return NULL;
        }
    }
    return rt;
}

static int execute(const RunSpec *spec, FILE *out, FILE *log, volatile int *interrupt, bool *finished);

int runspec_execute(const RunSpec *spec, FILE *out, FILE *log, volatile int *interrupt)
{
    bool finished = false;
    int rc = execute(spec, out, log, interrupt, &finished);
    /* a run of known length cut short by a signal says so, as a shell's
     * job does: 128 + the signal number (the flag holds it; the saves and
     * dumps were done as usual). A run without --frames ends that way by
     * design (as Flitter's does) and keeps its status. */
    int sig = interrupt ? *interrupt : 0;
    if (sig > 0 && sig < 128 && !finished && (spec->frames >= 0 || spec->dump_syntax) &&
        (rc == EXIT_OK || rc == EXIT_LOAD))
        rc = 128 + sig;
    return rc;
}

/* runspec_execute's run; [*finished] is set once the last frame asked for
 * (or the dump) is done. */
static int execute(const RunSpec *spec, FILE *out, FILE *log, volatile int *interrupt, bool *finished)
{
    RunLog files = {log, (spec->dump_state || spec->dump_tree) ? log : out};
    fl_runtime *rt = runspec_runtime(spec, &files, interrupt);
    if (!rt) return EXIT_USAGE;
    if (spec->dump_syntax) {
        int bad = (spec->dump_syntax == 1 ? fl_dump_tokens : fl_dump_ast)(
            rt, spec->script, write_file, out);
        if (bad) fputs(fl_error(rt), log);
        *finished = !bad;
        fl_free(rt);
        return finish_out(out, log, bad ? EXIT_LOAD : EXIT_OK);
    }
    LoadTimes load = {0};
    /* the heap's new pages faulted in on another core until the second
     * frame is done (prefault.h), when this run is the process's */
    Prefault *pf = spec->exiting && !memory_checked() ? prefault_start() : NULL;
    double t0 = now_seconds();
    if (fl_load(rt, spec->script) != 0) {
        prefault_stop(pf);
        fputs(fl_error(rt), log);
        fl_free(rt);
        return EXIT_LOAD;
    }
    load.first = now_seconds() - t0;
    if (spec->state_file && access(spec->state_file, F_OK) == 0 &&
        fl_restore_state(rt, spec->state_file) != 0) {
        prefault_stop(pf);
        fputs(fl_error(rt), log);
        fl_free(rt);
        return EXIT_LOAD;
    }
    if (spec->dump_simplified) {
        fl_dump_program(rt, write_file, out);
        if (spec->frames < 0) {
            prefault_stop(pf);
            fl_free(rt);
            *finished = true;
            return finish_out(out, log, EXIT_OK);
        }
    }
    fl_output_options oo = {spec->view, spec->view_every, spec->trace, spec->trace_every,
                            spec->verbosity >= 2, spec->record};
    fl_outputs *outs = fl_outputs_open(rt, &oo);
    if (!outs) {
        prefault_stop(pf);
        fprintf(log, "flitter run: %s", fl_error(rt));
        fl_free(rt);
        return EXIT_USAGE;
    }
    bool dumped_last = false;
    double start = now_seconds(), last_save = start, last_progress = 0;
    long ran = 0;
    bool clock_ended = false;
    fl_stats first = {0}, second = {0}, traced = {0};
    struct timespec mtime = file_mtime(spec->script), bad_mtime = {0, 0};
    /* --runtime on a realtime clock counts the clock's seconds, not frames */
    bool by_clock = spec->realtime && spec->runtime_clock;
    double clock_start = fl_next_frame_time(rt);
    while (!(interrupt && *interrupt) &&
           (by_clock ? !runspec_runtime_over(spec, fl_next_frame_time(rt) - clock_start, fl_target_fps(rt))
                     : spec->frames < 0 || ran < spec->frames)) {
        if (spec->realtime) {
            /* live reload: re-read the script when it changes; a broken
             * version is reported once and the last good one keeps running */
            struct timespec m = file_mtime(spec->script);
            if (!same_time(m, mtime) && !same_time(m, bad_mtime)) {
                t0 = now_seconds();
                if (fl_load(rt, spec->script) == 0) {
                    load.last = now_seconds() - t0;
                    load.reloads++;
                    mtime = m;
                    fprintf(log, "%s: reloaded\n", spec->script);
                } else {
                    bad_mtime = m;
                    fputs(fl_error(rt), log);
                }
            }
        }
        int step = fl_step(rt);
        if (step == 1)
            break;   /* interrupted: the frame was discarded */
        if (step < 0) {   /* the clock at its limit: the run ends there */
            fprintf(log, "%s: error: %s", spec->script, fl_error(rt));
            clock_ended = true;
            break;
        }
        ran++;
        if (ran == 1) fl_get_stats(rt, &first);
        if (ran == 2) {
            fl_get_stats(rt, &second);
            prefault_stop(pf);
            pf = NULL;
        }
        long n = fl_frame_count(rt) - 1;
        if (fl_outputs_frame(outs, rt) != 0) fprintf(log, "flitter run: %s", fl_error(rt));
        if (spec->verbosity >= 3) {   /* --trace: a line per frame */
            fl_stats st;
            fl_get_stats(rt, &st);
            fprintf(log, "trace: frame %ld time %.17g eval %.3f ms physics %.3f ms\n", n,
                    fl_frame_time(rt), (st.eval_seconds - traced.eval_seconds) * 1e3,
                    (st.physics_seconds - traced.physics_seconds) * 1e3);
            traced = st;
        }
        dumped_last = false;
        if (spec->dump_state && spec->dump_every > 0 && (n + 1) % spec->dump_every == 0) {
            fl_dump_state(rt, write_file, out);
            dumped_last = true;
        }
        double now = now_seconds();
        if (spec->progress && spec->frames > 0 && (now - last_progress > 0.1 || ran == spec->frames)) {
            show_progress(ran, spec->frames, now - start);
            last_progress = now;
        } else if (spec->progress && spec->frames < 0 && now - last_progress > 0.25) {
            show_status(n, now > start ? (double)ran / (now - start) : 0, fl_frame_time(rt));
            last_progress = now;
        }
        if (spec->state_file && now - last_save >= 5.0) {
            save_state(rt, spec->state_file, log);
            last_save = now;
        }
        if (spec->realtime) {
            /* Flitter's pacing: sleep until a millisecond before the next
             * frame is due (fl_frame_wait) */
            double wait = fl_frame_wait(rt) - 0.001;
            if (wait > 0) {
                struct timespec ts = {(time_t)wait, (long)(fmod(wait, 1.0) * 1e9)};
                nanosleep(&ts, NULL);
            }
        }
    }
    prefault_stop(pf);
    *finished = by_clock ? runspec_runtime_over(spec, fl_next_frame_time(rt) - clock_start, fl_target_fps(rt))
                         : spec->frames >= 0 && ran >= spec->frames;
    /* a signal during the last frame's drawing (polled between shapes)
     * left its pictures unwritten: the run did not finish */
    if (interrupt && *interrupt) *finished = false;
    if (spec->progress && ran > 0) fputs("\n", stderr);
    if (spec->stats) runspec_print_stats(rt, &first, &second, now_seconds() - start, &load, log);
    int rc = clock_ended ? EXIT_LOAD : EXIT_OK;
    if (ran > 0) {
        if (spec->dump_state && !dumped_last) fl_dump_state(rt, write_file, out);
        if (spec->dump_tree) fl_dump_tree(rt, write_file, out);
    }
    if (spec->state_file && save_state(rt, spec->state_file, log) != 0) rc = EXIT_LOAD;
    if (fl_outputs_close(outs, rt) != 0) {
        if (*fl_error(rt)) fprintf(log, "flitter run: %s", fl_error(rt));
        rc = EXIT_LOAD;
    }
    rc = finish_out(out, log, rc);
    if (!left_to_exit(spec)) fl_free(rt);
    return rc;
}
