/* bench_canvas3d.c: milliseconds per frame of `!canvas3d` drawing, as a
 * front end draws a window every frame (fl_step + fl_draw_window).
 *
 *   bench_canvas3d [WIDTH HEIGHT [NSPHERES [SAMPLES [FRAMES]]]]
 *
 * The scene is examples/physics.fl's picture without its physics: NSPHERES
 * (default 500) lit spheres of radius 5..50 scattered in a ball of radius
 * 500, seen from 0;0;-1200 with a red ambient light and a negative
 * directional light, plus one transparent enclosing sphere; default
 * 1920x1080, samples=4, 20 frames after one warm-up frame. Prints the mean
 * step and draw times. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "flitter.h"

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec / 1e6;
}

static void print_log(void *ctx, int kind, const char *line)
{
    (void)ctx;
    (void)kind;
    fprintf(stderr, "%s\n", line);
}

int main(int argc, char **argv)
{
    int w = argc > 2 ? atoi(argv[1]) : 1920, h = argc > 2 ? atoi(argv[2]) : 1080;
    int n = argc > 3 ? atoi(argv[3]) : 500, samples = argc > 4 ? atoi(argv[4]) : 4;
    int frames = argc > 5 ? atoi(argv[5]) : 20;
    if (w < 1 || h < 1 || n < 0 || frames < 1) {
        fprintf(stderr, "usage: bench_canvas3d [WIDTH HEIGHT [NSPHERES [SAMPLES [FRAMES]]]]\n");
        return 2;
    }
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
        return 1;
    }
    unlink(path);
    uint32_t *pix = malloc((size_t)w * h * 4);
    if (!pix) return 1;
    double step = 0, drawn = 0;
    for (int i = 0; i <= frames; i++) {
        double t0 = now_ms();
        fl_step(rt);
        double t1 = now_ms();
        if (fl_draw_window(rt, 0, pix, w, h, (size_t)w * 4) != 0) {
            fprintf(stderr, "%s", fl_error(rt));
            return 1;
        }
        double t2 = now_ms();
        if (i > 0) step += t1 - t0, drawn += t2 - t1;   /* frame 0 warms up (context, meshes, shaders) */
    }
    printf("canvas3d %dx%d, %d spheres, samples=%d: %.1f ms/frame drawing (+ %.1f ms evaluating), %d frames\n",
           w, h, n, samples, drawn / frames, step / frames, frames);
    free(pix);
    fl_free(rt);
    return 0;
}
