/* bench_canvas3d.c: milliseconds per frame of `!canvas3d` drawing, as a
 * front end draws a window every frame (fl_step + fl_draw_window).
 *
 *   bench_canvas3d [WIDTH HEIGHT [NSPHERES [SAMPLES [FRAMES]]]]
 *   bench_canvas3d --script FILE [--fps F] [--frames N] [--physics P] [--occlusion O] [--culling C]
 *                  [-D NAME=VALUE]...
 *
 * The first form draws examples/physics.fl's picture without its physics:
 * NSPHERES (default 500) lit spheres of radius 5..50 scattered in a ball of
 * radius 500, seen from 0;0;-1200 with a red ambient light and a negative
 * directional light, plus one transparent enclosing sphere; default
 * 1920x1080, samples=4, 20 frames after one warm-up frame.
 *
 * The second runs a script (bench/canvas3d.sh gives it Flitter's
 * examples) at F frames a second (default 10, as Flitter's
 * examples/Makefile renders them) for N frames (default 10) and draws its
 * first window after each frame; frame 0 is a warm-up (GL context,
 * meshes, shaders) and is not counted. --physics is flitter's option
 * (documented or upstream); --occlusion (auto, always or never) is
 * FLITTER_CANVAS3D_OCCLUSION's choice of !canvas3d's occluders' pass
 * (unset, 1, 0), and --culling (on or off) FLITTER_CANVAS3D_CULLING's of
 * its lights culled per mesh (unset, 0), for measuring them.
 *
 * Prints the mean drawing and stepping (evaluation and physics) wall times,
 * the fastest frame's drawing time and the mean CPU time of drawing (all
 * threads: a steadier figure than wall time on a busy machine), on one
 * line. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

#include "flitter.h"

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec / 1e6;
}

/* CPU time of the whole process (every thread: llvmpipe's too), ms. */
static double cpu_ms(void)
{
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return (double)(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) * 1e3 +
           (double)(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec) / 1e3;
}

static void print_log(void *ctx, int kind, const char *line)
{
    (void)ctx;
    (void)kind;
    fprintf(stderr, "%s\n", line);
}

/* Step [rt] frames+1 times, drawing window 0 after each; prints the line. */
static int run(fl_runtime *rt, const char *what, int frames)
{
    uint32_t *pix = NULL;
    int w = 0, h = 0;
    double step = 0, drawn = 0, best = 0, cpu = 0;
    for (int i = 0; i <= frames; i++) {
        double t0 = now_ms();
        if (fl_step(rt) != 0) {
            fprintf(stderr, "%s", fl_error(rt));
            free(pix);
            return 1;
        }
        double t1 = now_ms(), c1 = cpu_ms();
        fl_window_info win;
        if (fl_windows(rt, &win, 1) < 1) {
            fprintf(stderr, "bench_canvas3d: the script has no !window\n");
            free(pix);
            return 1;
        }
        if (!pix || win.width != w || win.height != h) {
            free(pix);
            w = win.width, h = win.height;
            pix = malloc((size_t)w * h * 4);
            if (!pix) return 1;
        }
        if (fl_draw_window(rt, 0, pix, w, h, (size_t)w * 4) != 0) {
            fprintf(stderr, "%s", fl_error(rt));
            free(pix);
            return 1;
        }
        double t2 = now_ms();
        if (i > 0) {   /* frame 0 warms up (context, meshes, shaders) */
            step += t1 - t0, drawn += t2 - t1, cpu += cpu_ms() - c1;
            if (i == 1 || t2 - t1 < best) best = t2 - t1;
        }
    }
    printf("%s %dx%d: %.1f ms/frame drawing (fastest %.1f; CPU time %.1f ms) + %.1f ms stepping, %d frames\n",
           what, w, h, drawn / frames, best, cpu / frames, step / frames, frames);
    free(pix);
    return 0;
}

static int usage(void)
{
    fprintf(stderr, "usage: bench_canvas3d [WIDTH HEIGHT [NSPHERES [SAMPLES [FRAMES]]]]\n"
                    "       bench_canvas3d --script FILE [--fps F] [--frames N] [--physics P] [--occlusion O]"
                    " [--culling on|off] [-D NAME=VALUE]...\n");
    return 2;
}

static int script_mode(int argc, char **argv)
{
    const char *path = NULL;
    int frames = 10;
    fl_options o = fl_default_options();
    o.log = print_log;
    o.fps = 10;
    const char *defines[64];
    int ndefines = 0;
    for (int i = 1; i < argc; i += 2) {   /* options and their values in pairs */
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!v) return usage();
        if (strcmp(a, "--script") == 0) path = v;
        else if (strcmp(a, "--fps") == 0) o.fps = atof(v);
        else if (strcmp(a, "--frames") == 0) frames = atoi(v);
        else if (strcmp(a, "--physics") == 0) {
            if (!fl_parse_physics(v, &o.physics)) return usage();
        } else if (strcmp(a, "--occlusion") == 0) {
            if (strcmp(v, "auto") == 0) o.debug.occlusion = FL_OCCLUSION_AUTO;
            else if (strcmp(v, "always") == 0) o.debug.occlusion = FL_OCCLUSION_ALWAYS;
            else if (strcmp(v, "never") == 0) o.debug.occlusion = FL_OCCLUSION_NEVER;
            else return usage();
        } else if (strcmp(a, "--culling") == 0) {
            if (strcmp(v, "on") == 0) o.debug.no_light_culling = false;
            else if (strcmp(v, "off") == 0) o.debug.no_light_culling = true;
            else return usage();
        } else if (strcmp(a, "-D") == 0 && ndefines < 64) defines[ndefines++] = v;
        else return usage();
    }
    if (!path || frames < 1 || !(o.fps > 0)) return usage();
    o.frames = frames + 1;
    fl_runtime *rt = fl_new(&o);
    for (int i = 0; i < ndefines; i++) {
        char name[256];
        const char *eq = strchr(defines[i], '=');
        if (!eq || eq - defines[i] >= (long)sizeof name) return usage();
        memcpy(name, defines[i], (size_t)(eq - defines[i]));
        name[eq - defines[i]] = '\0';
        if (fl_define(rt, name, eq + 1) != 0) {
            fprintf(stderr, "%s", fl_error(rt));
            return 1;
        }
    }
    if (fl_load(rt, path) != 0) {
        fprintf(stderr, "%s", fl_error(rt));
        fl_free(rt);
        return 1;
    }
    const char *base = strrchr(path, '/');
    int rc = run(rt, base ? base + 1 : path, frames);
    fl_free(rt);
    return rc;
}

int main(int argc, char **argv)
{
    if (argc > 1 && strcmp(argv[1], "--script") == 0) return script_mode(argc, argv);
    int w = argc > 2 ? atoi(argv[1]) : 1920, h = argc > 2 ? atoi(argv[2]) : 1080;
    int n = argc > 3 ? atoi(argv[3]) : 500, samples = argc > 4 ? atoi(argv[4]) : 4;
    int frames = argc > 5 ? atoi(argv[5]) : 20;
    if (w < 1 || h < 1 || n < 0 || frames < 1) return usage();
    char path[] = "/tmp/bench_canvas3d.XXXXXX";
    int fd = mkstemp(path);
    if (fd < 0) return 1;
    FILE *f = fdopen(fd, "w");
    fprintf(f,
            "let N=%d\n"
            "    P=(beta(:start)[..3*N]-0.5)*1000\n"
            "    R=5+uniform(:r)[..N]*45\n"
            "!window size=%d;%d\n"
            "    !canvas3d viewpoint=0;0;-1200 focus=0 near=1 far=2000 fov=60/360 samples=%d\n"
            "        !light color=2;0;0\n"
            "        !light color=-1.9;0;0 direction=0;0;1\n"
            "        !sphere color=0.01 size=500 transparency=0.05\n"
            "        for i in ..N\n"
            "            !sphere position=P[i*3..(i+1)*3]+(frame%%10) color=1 size=R[i]\n",
            n, w, h, samples);
    fclose(f);
    fl_options o = fl_default_options();
    o.log = print_log;
    fl_runtime *rt = fl_new(&o);
    if (fl_load(rt, path) != 0) {
        fprintf(stderr, "%s", fl_error(rt));
        unlink(path);
        fl_free(rt);
        return 1;
    }
    unlink(path);
    char what[64];
    snprintf(what, sizeof what, "canvas3d %d spheres samples=%d", n, samples);
    int rc = run(rt, what, frames);
    fl_free(rt);
    return rc;
}
