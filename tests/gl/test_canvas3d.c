/* test_canvas3d.c: `!canvas3d` drawn through OpenGL (EGL surfaceless,
 * llvmpipe without a GPU), pixels checked at known places for small
 * hand-built scenes: the default camera's scale, ambient light alone, a
 * directional light facing the camera (Lambert plus the GGX specular at
 * normal incidence), an orthographic camera's edges, fog at a known
 * depth, depth testing, transparency, MSAA on an edge, two runtimes in
 * one process, and one warning per unsupported 3D node kind. Expected
 * values are computed here from the documented equations (Flitter
 * docs/canvas3d.md; glsl/lighting_functions.glsl): dielectric F0 =
 * ((ior-1)/(ior+1))^2 = 0.04 at the default ior 1.5, diffuse
 * (1-F0) * albedo * light, and the window's sRGB encoding. Only flitter.h
 * is used. */
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
static char logged[4096];   /* the log lines of the last runtime */

static int setup(void **st)
{
    (void)st;
    snprintf(scratch, sizeof scratch, "/tmp/test_canvas3d.XXXXXX");
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

/* Run one frame of [script] and draw its window (W x H) into [pix]. */
static fl_runtime *draw(const char *script, uint32_t *pix)
{
    char path[256];
    snprintf(path, sizeof path, "%s/main.fl", scratch);
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(script, f);
    fclose(f);
    logged[0] = '\0';
    fl_options o = fl_default_options();
    o.log = keep_log;
    fl_runtime *rt = fl_new(&o);
    assert_int_equal(fl_load(rt, path), 0);
    assert_int_equal(fl_step(rt), 0);
    assert_int_equal(fl_draw_window(rt, 0, pix, W, H, W * 4), 0);
    assert_null(strstr(logged, "no OpenGL"));
    return rt;
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

static void assert_rgb_near(uint32_t p, double r, double g, double b, int tol)
{
    int want[3] = {srgb(r), srgb(g), srgb(b)};
    int got[3] = {chan(p, 16), chan(p, 8), chan(p, 0)};
    for (int k = 0; k < 3; k++) {
        if (abs(got[k] - want[k]) > tol)
            fail_msg("pixel %08x: channel %d is %d, expected %d (+-%d)", p, k, got[k], want[k], tol);
    }
}

#define F0 0.04   /* ((1.5 - 1) / (1.5 + 1))^2 */

/* Ambient light only: exactly (1 - F0) * albedo * light at the centre; the
 * default camera (0;0;W/2, horizontal fov 1/4 turn) shows W units across
 * at z=0, so a box of size 20 spans columns 22..41; a corner is empty. */
static void ambient_box(void **st)
{
    (void)st;
    uint32_t pix[W * H];
    fl_runtime *rt = draw("!window size=64;64\n"
                          "    !canvas3d\n"
                          "        !light color=1\n"
                          "        !box size=20 color=0.5;0.25;1\n", pix);
    assert_int_equal(chan(at(pix, 32, 32), 24), 255);
    assert_rgb_near(at(pix, 32, 32), (1 - F0) * 0.5, (1 - F0) * 0.25, (1 - F0) * 1, 1);
    assert_int_equal(at(pix, 0, 0), 0x00000000u);
    assert_int_equal(at(pix, 63, 63), 0x00000000u);
    /* the front face at z=10 is nearer: 20 * 32/22 = 29 pixels wide, centred */
    assert_int_equal(chan(at(pix, 32 - 13, 32), 24), 255);
    assert_int_equal(at(pix, 32 - 16, 32), 0x00000000u);
    assert_int_equal(at(pix, 32 + 16, 32), 0x00000000u);
    fl_free(rt);
}

/* A directional light shining straight at the front face: Lambert
 * (NdotL = 1) plus, at roughness 1, the specular term F0 * G * D / 4 with
 * D = G = 1 at normal incidence: light * ((1 - F0) * albedo + F0 / 4). */
static void directional_lambert(void **st)
{
    (void)st;
    uint32_t pix[W * H];
    fl_runtime *rt = draw("!window size=64;64\n"
                          "    !canvas3d\n"
                          "        !light color=0.5 direction=0;0;-1\n"
                          "        !box size=20 color=1;0.5;0\n", pix);
    double l = 0.5;
    assert_rgb_near(at(pix, 32, 32), l * ((1 - F0) * 1 + F0 / 4), l * ((1 - F0) * 0.5 + F0 / 4),
                    l * (F0 / 4), 2);
    /* turned away from the light: the side faces are dark; a light from behind gives nothing */
    fl_free(rt);
    rt = draw("!window size=64;64\n"
              "    !canvas3d\n"
              "        !light color=0.5 direction=0;0;1\n"
              "        !box size=20 color=1;0.5;0\n", pix);
    assert_int_equal(at(pix, 32, 32), 0xff000000u);
    fl_free(rt);
}

/* An orthographic camera W units wide: one unit per pixel, x=0 at the
 * left edge of column 32; a box from x=0 to x=20 fills columns 32..51. */
static void orthographic_edges(void **st)
{
    (void)st;
    uint32_t pix[W * H];
    fl_runtime *rt = draw("!window size=64;64\n"
                          "    !canvas3d orthographic=true width=64 viewpoint=0;0;100 far=1000\n"
                          "        !light color=1\n"
                          "        !box size=20 position=10;0;0 color=1\n", pix);
    assert_int_equal(at(pix, 31, 32), 0x00000000u);
    assert_int_equal(chan(at(pix, 32, 32), 24), 255);
    assert_int_equal(chan(at(pix, 51, 32), 24), 255);
    assert_int_equal(at(pix, 52, 32), 0x00000000u);
    /* rows: y from -10 to 10 is rows 22..41 (y up, rows down) */
    assert_int_equal(at(pix, 40, 21), 0x00000000u);
    assert_int_equal(chan(at(pix, 40, 22), 24), 255);
    assert_int_equal(chan(at(pix, 40, 41), 24), 255);
    assert_int_equal(at(pix, 40, 42), 0x00000000u);
    fl_free(rt);
}

/* Fog: the front face at distance 90 with fog_min=50, fog_max=150 mixes
 * 40% of the fog colour in; the empty picture is the fog colour. */
static void fog_mix(void **st)
{
    (void)st;
    uint32_t pix[W * H];
    fl_runtime *rt = draw("!window size=64;64\n"
                          "    !canvas3d orthographic=true width=64 viewpoint=0;0;100 far=1000"
                          " fog_color=1;0;0 fog_min=50 fog_max=150\n"
                          "        !light color=1\n"
                          "        !box size=20 color=0;0;1\n", pix);
    assert_int_equal(at(pix, 0, 0), 0xffff0000u);
    assert_rgb_near(at(pix, 32, 32), 0.4, 0, 0.6 * (1 - F0), 1);
    /* fog_curve=2: the mix is 0.4^(1/2) */
    fl_free(rt);
    rt = draw("!window size=64;64\n"
              "    !canvas3d orthographic=true width=64 viewpoint=0;0;100 far=1000"
              " fog_color=1;0;0 fog_min=50 fog_max=150 fog_curve=2\n"
              "        !light color=1\n"
              "        !box size=20 color=0;0;1\n", pix);
    double m = sqrt(0.4);
    assert_rgb_near(at(pix, 32, 32), m, 0, (1 - m) * (1 - F0), 1);
    fl_free(rt);
}

/* Depth: a box behind a nearer one is hidden whatever the tree order; a
 * transparent box in front lets the one behind show through. */
static void depth_and_transparency(void **st)
{
    (void)st;
    uint32_t pix[W * H];
    fl_runtime *rt = draw("!window size=64;64\n"
                          "    !canvas3d\n"
                          "        !light color=1\n"
                          "        !box size=10 position=0;0;10 color=1;0;0\n"
                          "        !box size=30 position=0;0;-10 color=0;1;0\n", pix);
    assert_rgb_near(at(pix, 32, 32), 1 - F0, 0, 0, 1);
    /* the big box's front face (z=5, 27 from the eye) spans rows 15..49 */
    assert_rgb_near(at(pix, 32, 17), 0, 1 - F0, 0, 1);   /* only the big one there */
    fl_free(rt);
    rt = draw("!window size=64;64\n"
              "    !canvas3d\n"
              "        !light color=1\n"
              "        !box size=10 position=0;0;10 color=1;0;0 transparency=0.5\n"
              "        !box size=30 position=0;0;-10 color=0;1;0\n", pix);
    /* premultiplied over: 0.5 * red diffuse + (1 - 0.5) * green behind */
    assert_rgb_near(at(pix, 32, 32), 0.5 * (1 - F0), 0.5 * (1 - F0), 0, 2);
    fl_free(rt);
}

/* samples=4: a box edge through the middle of a pixel column gives a
 * partly covered pixel; without samples it is all or nothing. */
static void msaa_edge(void **st)
{
    (void)st;
    uint32_t pix[W * H];
    const char *fmt = "!window size=64;64\n"
                      "    !canvas3d orthographic=true width=64 viewpoint=0;0;100 far=1000 samples=%d\n"
                      "        !light color=1\n"
                      "        !box size=20.5;20;20 position=10.25;0;0 rotation=0;0;0.01 color=1\n";
    char script[512];
    int partial[2] = {0, 0};
    for (int s = 0; s < 2; s++) {
        snprintf(script, sizeof script, fmt, s ? 4 : 0);
        fl_runtime *rt = draw(script, pix);
        for (int y = 20; y < 44; y++)
            for (int x = 48; x < 56; x++) {
                int a = chan(at(pix, x, y), 24);
                if (a > 0 && a < 255) partial[s]++;
            }
        fl_free(rt);
    }
    assert_int_equal(partial[0], 0);
    assert_true(partial[1] >= 10);
}

/* Smooth spheres are drawn as ray-cast impostors (one box per sphere, the
 * sphere's surface, normal and depth found per fragment, MSAA coverage per
 * sample): the picture must be the 64-segment mesh's, which
 * FLITTER_CANVAS3D_IMPOSTORS=0 draws, up to the facets: a sphere and a
 * rotated ellipsoid half sunk into a plane (depth), lit from the side
 * (the bright side faces +x), with samples=4 (partly covered edge pixels). */
static void impostor_spheres(void **st)
{
    (void)st;
    static uint32_t pix[2][W * H];
    const char *script = "!window size=64;64\n"
                         "    !canvas3d samples=4\n"
                         "        !light color=1 direction=-1;0;0\n"
                         "        !light color=0.1\n"
                         "        !box size=60;60;1 color=0;1;0\n"
                         "        !sphere size=8 position=-8;6;0 color=1;0;0\n"
                         "        !sphere size=10;5;5 rotation=0;0;0.1 position=6;-6;2 color=1;1;1\n";
    for (int k = 0; k < 2; k++) {
        setenv("FLITTER_CANVAS3D_IMPOSTORS", k ? "1" : "0", 1);
        fl_runtime *rt = draw(script, pix[k]);
        fl_free(rt);
    }
    unsetenv("FLITTER_CANVAS3D_IMPOSTORS");
    int worst = 0, close = 0, partial = 0;
    for (int i = 0; i < W * H; i++) {
        int d = 0;
        for (int sh = 0; sh < 32; sh += 8) {
            int e = abs(chan(pix[0][i], sh) - chan(pix[1][i], sh));
            if (e > d) d = e;
        }
        if (d > worst) worst = d;
        if (d <= 4) close++;
        int g = chan(pix[1][i], 8), r = chan(pix[1][i], 16);
        if (r > 0 && g > 0 && r < 250) partial++;   /* red sphere edge over the green plane */
    }
    assert_true(worst <= 64);
    assert_true(close >= W * H * 97 / 100);
    assert_true(partial >= 4);
    /* the red sphere's lit side faces the light (+x), its other side only ambient */
    assert_true(chan(at(pix[1], 32 - 8 * 32 / 32 + 5, 32 - 6), 16) > chan(at(pix[1], 32 - 8 * 32 / 32 - 5, 32 - 6), 16) + 100);
    /* the plane shows around the spheres */
    assert_rgb_near(at(pix[1], 2, 2), 0, 0.1 * (1 - F0), 0, 2);
}

/* Two runtimes, each with its own renderer and GL context, alternate. */
static void two_runtimes(void **st)
{
    (void)st;
    uint32_t a[W * H], b[W * H];
    fl_runtime *ra = draw("!window size=64;64\n"
                          "    !canvas3d\n"
                          "        !light color=1\n"
                          "        !sphere size=20 color=1;0;0\n", a);
    fl_runtime *rb = draw("!window size=64;64\n"
                          "    !canvas3d\n"
                          "        !light color=1\n"
                          "        !cone size=20 color=0;0;1 rotation=0.25;0;0\n", b);
    assert_rgb_near(at(a, 32, 32), 1 - F0, 0, 0, 1);
    assert_int_equal(fl_step(ra), 0);
    assert_int_equal(fl_draw_window(ra, 0, a, W, H, W * 4), 0);
    assert_rgb_near(at(a, 32, 32), 1 - F0, 0, 0, 1);
    assert_int_equal(fl_step(rb), 0);
    assert_int_equal(fl_draw_window(rb, 0, b, W, H, W * 4), 0);
    assert_rgb_near(at(b, 32, 32), 0, 0, 1 - F0, 1);
    fl_free(ra);
    assert_int_equal(fl_step(rb), 0);
    assert_int_equal(fl_draw_window(rb, 0, b, W, H, W * 4), 0);
    assert_rgb_near(at(b, 32, 32), 0, 0, 1 - F0, 1);
    fl_free(rb);
}

/* Unsupported kinds are reported once each, without --debug. */
static void unsupported_warned_once(void **st)
{
    (void)st;
    uint32_t pix[W * H];
    fl_runtime *rt = draw("!window size=64;64\n"
                          "    !canvas3d\n"
                          "        !light color=1\n"
                          "        !model filename=\"teapot.obj\"\n"
                          "        !model filename=\"cup.obj\"\n"
                          "        !box size=20 color=1\n"
                          "    !canvas\n"
                          "        !wibble\n", pix);
    assert_int_equal(fl_step(rt), 0);
    assert_int_equal(fl_draw_window(rt, 0, pix, W, H, W * 4), 0);
    const char *p = strstr(logged, "canvas3d: skipping unsupported !model");
    assert_non_null(p);
    assert_null(strstr(p + 1, "canvas3d: skipping unsupported !model"));
    assert_non_null(strstr(logged, "canvas: skipping unsupported !wibble"));
    assert_int_equal(chan(at(pix, 32, 32), 24), 255);   /* the box is drawn all the same */
    fl_free(rt);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(ambient_box),
        cmocka_unit_test(directional_lambert),
        cmocka_unit_test(orthographic_edges),
        cmocka_unit_test(fog_mix),
        cmocka_unit_test(depth_and_transparency),
        cmocka_unit_test(msaa_edge),
        cmocka_unit_test(impostor_spheres),
        cmocka_unit_test(two_runtimes),
        cmocka_unit_test(unsupported_warned_once),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
