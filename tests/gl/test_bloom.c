/* test_bloom.c: the `!bloom` window effect (the render graph's bloom pass, lib/render/gl/glsl/bloom.frag), pixels
 * checked at known places against values computed here by hand from
 * Flitter's filter (docs/shaders.md "!bloom"; glsl/bloom.frag and
 * filter_functions.glsl): down-sample by 2 (bilinear), exposure, a
 * separable normalised Gaussian of radius/2 taps and sigma 0.3 * radius/2
 * at half size, bilinear up-sampling, and the lighten blend with the
 * original, all in linear light; the window then encodes sRGB. Only
 * flitter.h is used. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>

#include "flitter.h"

#define W 64
#define H 64

static char scratch[64];
static char logged[4096];

static int setup(void **st)
{
    (void)st;
    snprintf(scratch, sizeof scratch, "/tmp/test_bloom.XXXXXX");
    return mkdtemp(scratch) ? 0 : -1;
}

static int teardown(void **st)
{
    (void)st;
    char path[256];
    snprintf(path, sizeof path, "%s/main.fl", scratch);
    unlink(path);
    return rmdir(scratch);
}

static void keep_log(void *ctx, int kind, const char *line)
{
    (void)ctx;
    (void)kind;
    size_t n = strlen(logged);
    snprintf(logged + n, sizeof logged - n, "%s\n", line);
}

/* A new runtime (logging into `logged`, emptied) with [script] written
 * to scratch/[name] and loaded. */
static fl_runtime *load_script(const char *name, const char *script)
{
    char path[256];
    snprintf(path, sizeof path, "%s/%s", scratch, name);
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(script, f);
    fclose(f);
    logged[0] = '\0';
    fl_options o = fl_default_options();
    o.log = keep_log;
    fl_runtime *rt = fl_new(&o);
    assert_int_equal(fl_load(rt, path), 0);
    return rt;
}

/* Run one frame of [script] and draw its window (W x H) into [pix]. */
static void draw(const char *script, uint32_t *pix)
{
    fl_runtime *rt = load_script("main.fl", script);
    assert_int_equal(fl_step(rt), 0);
    assert_int_equal(fl_draw_window(rt, 0, pix, W, H, W * 4), 0);
    assert_null(strstr(logged, "no OpenGL"));
    /* !bloom is drawn, not skipped */
    assert_null(strstr(logged, "bloom"));
    fl_free(rt);
}

static uint32_t at(const uint32_t *pix, int x, int y) { return pix[y * W + x]; }
static int chan(uint32_t p, int shift) { return (int)((p >> shift) & 0xff); }

/* The window's 8-bit sRGB encoding of linear light [x] (clamped). */
static int srgb(double x)
{
    x = x < 0 ? 0 : x > 1 ? 1 : x;
    double s = x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1 / 2.4) - 0.055;
    return (int)lround(s * 255);
}

static void assert_grey_near(uint32_t p, int want, int tol)
{
    for (int k = 0; k < 3; k++) {
        int got = chan(p, 16 - 8 * k);
        if (abs(got - want) > tol)
            fail_msg("pixel %08x: channel %d is %d, expected %d (+-%d)", p, k, got, want, tol);
    }
}

/* A white 2x2 square at 32..33 on black, radius=8 exposure=0. Half size
 * (32 x 32): pixel (16,16) samples the middle of the square, 1; every
 * other half-size pixel samples black, 0. r = 8/2 = 4 taps, sigma =
 * 4 * 0.3 = 1.2: weights g(i) = exp(-i^2 / 2.88) / S, S = sum over
 * |i| <= 4 (g = 0.33249, 0.23495, 0.08291, 0.01461, 0.00128), so the
 * blurred half-size picture is g(x - 16) g(y - 16). Full-size pixel X
 * samples half-size position X/2 - 0.25: pixel (36,32) is
 * (0.25 g(1) + 0.75 g(2)) * (0.25 g(1) + 0.75 g(0)) = 0.03726 of white
 * light, sRGB 54; beyond 4 half-size pixels (x = 50) nothing. */
static void glow_is_gaussian(void **st)
{
    (void)st;
    uint32_t pix[W * H];
    draw("!window size=64;64\n"
         "    !bloom radius=8 exposure=0\n"
         "        !canvas\n"
         "            !path\n"
         "                !rect point=32;32 size=2;2\n"
         "                !fill color=1\n", pix);
    double g[5], s = 0;
    for (int i = 0; i <= 4; i++) s += (i ? 2 : 1) * exp(-i * i / (2 * 1.2 * 1.2));
    for (int i = 0; i <= 4; i++) g[i] = exp(-i * i / (2 * 1.2 * 1.2)) / s;
    double glow = (0.25 * g[1] + 0.75 * g[2]) * (0.25 * g[1] + 0.75 * g[0]);
    assert_true(fabs(glow - 0.03726) < 1e-4);
    assert_int_equal(srgb(glow), 54);
    assert_grey_near(at(pix, 36, 32), srgb(glow), 2);
    assert_grey_near(at(pix, 32, 36), srgb(glow), 2);            /* the same along y */
    /* two full-size pixels nearer, half-size 16.75: (0.25 g(0) + 0.75 g(1))
     * times the same row factor = 0.0799, sRGB 80 */
    double nearer = (0.25 * g[0] + 0.75 * g[1]) * (0.25 * g[1] + 0.75 * g[0]);
    assert_int_equal(srgb(nearer), 80);
    assert_grey_near(at(pix, 34, 32), srgb(nearer), 2);
    /* its alpha is the light's coverage, linear: the glow over nothing */
    assert_in_range(chan(at(pix, 36, 32), 24), lround(glow * 255) - 1, lround(glow * 255) + 1);
    /* the square itself stays white (the lighten blend) */
    assert_int_equal(at(pix, 32, 32), 0xffffffffu);
    assert_int_equal(at(pix, 33, 33), 0xffffffffu);
    /* out of reach of the 4 taps (half-size 25 and 7) */
    assert_int_equal(at(pix, 50, 32), 0x00000000u);
    assert_int_equal(at(pix, 14, 32), 0x00000000u);
    assert_int_equal(at(pix, 0, 0), 0x00000000u);
}

/* With the default exposure of -1 the blurred copy is half the light, so
 * a scene whose brightest part is less than twice its darkest (sRGB 153
 * = 0.318 linear on sRGB 128 = 0.216; 0.318 / 2 < 0.216) comes out
 * exactly as it goes in. */
static void dark_scene_unchanged(void **st)
{
    (void)st;
    static const char scene[] = "        !canvas\n"
                                "            !path\n"
                                "                !rect point=0;0 size=64;64\n"
                                "                !fill color=0.5\n"
                                "            !path\n"
                                "                !rect point=20;20 size=10;30\n"
                                "                !fill color=0.6\n";
    char with[1024], without[1024];
    snprintf(with, sizeof with, "!window size=64;64\n    !bloom radius=16\n%s", scene);
    snprintf(without, sizeof without, "!window size=64;64\n%s", scene + 4);
    uint32_t a[W * H], b[W * H];
    draw(with, a);
    /* the unbloomed window: the canvas straight under it */
    fl_runtime *rt = load_script("main.fl", without);
    assert_int_equal(fl_step(rt), 0);
    assert_int_equal(fl_draw_window(rt, 0, b, W, H, W * 4), 0);
    fl_free(rt);
    assert_int_not_equal(at(b, 25, 25), at(b, 5, 5));   /* the scene has two greys */
    for (int i = 0; i < W * H; i++)
        if (a[i] != b[i]) fail_msg("pixel (%d,%d) is %08x with !bloom, %08x without", i % W, i / W, a[i], b[i]);
}

/* A !canvas3d box lit by an ambient light of 4: its face is 0.96 * 4 =
 * 3.84 linear (clamped to white when encoded). The bloom must take the
 * unclamped light: at exposure -1 the blurred copy is 1.92 inside the
 * face, and its glow 5 pixels beyond the face's edge (the face spans
 * 19..44, as test_canvas3d's ambient_box finds) is at least the weight
 * of the far tail (g(2) + g(3) + g(4) of radius=8: 0.0988) times 1.92 =
 * 0.19 (sRGB 120), more than the 0.5 a clamped input could give at most
 * times the whole side (g(1..4) = 0.334: 0.167, sRGB 114); without the
 * bloom the pixel is empty. (llvmpipe gives sRGB 120 there; a bloom of
 * the clamped light, 62.) */
static void canvas3d_light_unclamped(void **st)
{
    (void)st;
    uint32_t pix[W * H];
    draw("!window size=64;64\n"
         "    !bloom radius=8\n"
         "        !canvas3d\n"
         "            !light color=4\n"
         "            !box size=20 color=1\n", pix);
    assert_int_equal(at(pix, 32, 32), 0xffffffffu);
    int glow = chan(at(pix, 50, 32), 16);
    if (glow < 115 || glow > 140) fail_msg("glow at (50,32) is %d, expected 115..140", glow);
    assert_int_equal(chan(at(pix, 50, 32), 16), chan(at(pix, 50, 32), 0));    /* white light */
    /* the same distance below the face */
    int below = chan(at(pix, 32, 50), 16);
    if (abs(below - glow) > 3) fail_msg("glow below is %d, beside %d", below, glow);
    assert_int_equal(at(pix, 63, 0), 0x00000000u);                          /* out of reach */
}

/* The bloom takes over the canvas's linear light instead of copying it,
 * handing its own buffer to the canvas for the next drawing: frame after
 * frame in one runtime, a moving box's bloomed picture must be exactly
 * the one a fresh runtime draws for the box where it is. */
static void canvas3d_light_each_frame(void **st)
{
    (void)st;
    static uint32_t pix[W * H], fresh[W * H], first[W * H];
    char path[256], one[256];
    snprintf(path, sizeof path, "%s/moving.fl", scratch);
    fl_runtime *rt = load_script("moving.fl", "!window size=64;64\n"
                                              "    !bloom radius=8\n"
                                              "        !canvas3d\n"
                                              "            !light color=4\n"
                                              "            !box size=12 position=(frame*10-10);0;0 color=1\n");
    for (int frame = 0; frame < 3; frame++) {
        assert_int_equal(fl_step(rt), 0);
        for (int twice = 0; twice < 2; twice++) {
            assert_int_equal(fl_draw_window(rt, 0, pix, W, H, W * 4), 0);
            snprintf(one, sizeof one,
                     "!window size=64;64\n"
                     "    !bloom radius=8\n"
                     "        !canvas3d\n"
                     "            !light color=4\n"
                     "            !box size=12 position=%d;0;0 color=1\n",
                     frame * 10 - 10);
            draw(one, fresh);
            for (int i = 0; i < W * H; i++)
                if (pix[i] != fresh[i])
                    fail_msg("frame %d, drawing %d: pixel (%d,%d) is %08x, fresh %08x", frame, twice, i % W, i / W,
                             pix[i], fresh[i]);
        }
        if (frame == 0) memcpy(first, pix, sizeof first);
    }
    /* the box moved: the last frame differs from the first */
    int moved = 0;
    for (int i = 0; i < W * H; i++) moved += pix[i] != first[i];
    assert_true(moved > 200);
    fl_free(rt);
    unlink(path);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(glow_is_gaussian),
        cmocka_unit_test(dark_scene_unchanged),
        cmocka_unit_test(canvas3d_light_unclamped),
        cmocka_unit_test(canvas3d_light_each_frame),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
