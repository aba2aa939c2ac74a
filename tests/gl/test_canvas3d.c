/* test_canvas3d.c: `!canvas3d` drawn through OpenGL (EGL surfaceless,
 * llvmpipe without a GPU), pixels checked at known places for small
 * hand-built scenes: the default camera's scale, ambient light alone, a
 * directional light facing the camera (Lambert plus the GGX specular at
 * normal incidence), an orthographic camera's edges, fog at a known
 * depth, depth testing, transparency, MSAA on an edge, line lights (both
 * passes, a radius, a line through the surface), translucency (light
 * from behind let through by thickness, thin edges brighter than thick
 * middles, translucency=0 unchanged), two runtimes in
 * one process, and one warning per unsupported 3D node kind and per
 * texture attribute kind. Expected
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
/* The routes of the runtimes draw() makes (fl_options.debug). */
static fl_debug_options routes;

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

/* A new runtime (logging into `logged`, emptied) with scratch/[name]
 * loaded: [script] written there first unless NULL, and the name F bound
 * to the value text [f] first unless NULL. */
static fl_runtime *load_script(const char *name, const char *script, const char *f)
{
    char path[256];
    snprintf(path, sizeof path, "%s/%s", scratch, name);
    if (script) {
        FILE *file = fopen(path, "w");
        assert_non_null(file);
        fputs(script, file);
        fclose(file);
    }
    logged[0] = '\0';
    fl_options o = fl_default_options();
    o.log = keep_log;
    o.debug = routes;
    fl_runtime *rt = fl_new(&o);
    if (f) assert_int_equal(fl_define(rt, "F", f), 0);
    assert_int_equal(fl_load(rt, path), 0);
    return rt;
}

/* The path of scratch/[name] removed. */
static void remove_script(const char *name)
{
    char path[256];
    snprintf(path, sizeof path, "%s/%s", scratch, name);
    unlink(path);
}

/* Run one frame of [script] and draw its window (W x H) into [pix]. */
static fl_runtime *draw(const char *script, uint32_t *pix)
{
    fl_runtime *rt = load_script("main.fl", script, NULL);
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

/* monochrome=true (Flitter docs/canvas3d.md, Cameras): the colour becomes
 * its luminance, 0.2126 R + 0.7152 G + 0.0722 B, in every channel, and
 * `tint` multiplies after that. The program is compiled for the kind of
 * camera (orthographic, fog, monochrome), so one canvas switching
 * between kinds from frame to frame must draw each frame as its camera
 * says: colour, monochrome tinted, fogged, then colour again. */
static void camera_kinds_per_frame(void **st)
{
    (void)st;
    uint32_t pix[W * H];
    fl_runtime *rt = load_script(
        "kinds.fl",
        "!window size=64;64\n"
        "    !canvas3d orthographic=true width=64 viewpoint=0;0;100 far=1000 monochrome=(frame == 1)"
        " tint=((1;0.5;0.25) if frame == 1 else 1) fog_color=1;0;0 fog_min=50 fog_max=(150 if frame == 2 else 0)\n"
        "        !light color=1\n"
        "        !box size=20 color=0.5;0.25;1\n",
        NULL);
    double luma = (1 - F0) * (0.2126 * 0.5 + 0.7152 * 0.25 + 0.0722 * 1);
    for (int frame = 0; frame < 4; frame++) {
        assert_int_equal(fl_step(rt), 0);
        assert_int_equal(fl_draw_window(rt, 0, pix, W, H, W * 4), 0);
        uint32_t p = at(pix, 32, 32);
        if (frame == 1)
            assert_rgb_near(p, luma, luma * 0.5, luma * 0.25, 1);
        else if (frame == 2)   /* 40% fog at distance 90 (fog_mix) */
            assert_rgb_near(p, 0.4 + 0.6 * (1 - F0) * 0.5, 0.6 * (1 - F0) * 0.25, 0.6 * (1 - F0), 1);
        else
            assert_rgb_near(p, (1 - F0) * 0.5, (1 - F0) * 0.25, (1 - F0) * 1, 1);
        assert_int_equal(at(pix, 0, 0), frame == 2 ? 0xffff0000u : 0u);
    }
    assert_null(strstr(logged, "compile"));
    fl_free(rt);
    remove_script("kinds.fl");
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
 * FL_IMPOSTORS_OFF draws, up to the facets: a sphere and a
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
        routes.impostors = k ? FL_IMPOSTORS_OCTAGONS : FL_IMPOSTORS_OFF;
        fl_runtime *rt = draw(script, pix[k]);
        fl_free(rt);
    }
    routes = (fl_debug_options){0};
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

/* An evenly scaled sphere's impostor is drawn on an octagon facing the
 * eye, around the circle where the cone of rays touching the sphere (a
 * cylinder, orthographic) meets the plane touching its near side: it must
 * cover every sample the sphere covers. The 64-segment mesh lies inside
 * the sphere, so every pixel a mesh sphere touches must be touched by its
 * impostor: large spheres far off the axis of a wide view and near the
 * camera, in perspective and orthographic views, with samples=4; one
 * sphere is so near (radius 0.3 of its distance) that the cone's circle
 * is 5% wider than (distance - r) r / distance, the circle of a cone
 * through the sphere's rim seen face on (caught without that term); and
 * a camera whose look-at fails (up along the line of sight), whose
 * picture comes from the identity view, not from its viewpoint. */
static void impostor_billboards(void **st)
{
    (void)st;
    static uint32_t pix[2][W * H];
    static const char *scripts[] = {
        "!window size=64;64\n"
        "    !canvas3d samples=4 viewpoint=0;0;40 fov=0.35 near=1\n"
        "        !light color=1\n"
        "        !sphere size=16 position=20;16;0 color=1;0;0\n"
        "        !sphere size=12 position=-18;-12;12 color=1;0;0\n"
        "        !sphere size=3 position=-9;13;25 color=1;0;0\n"
        "        !sphere size=5 position=2;-3;-30 color=1;0;0\n",
        "!window size=64;64\n"
        "    !canvas3d samples=4 viewpoint=10;5;40 focus=0 orthographic=true width=64 near=1\n"
        "        !light color=1\n"
        "        !sphere size=12 position=26;22;0 color=1;0;0\n"
        "        !sphere size=2.5 position=-20;-14;14 color=1;0;0\n",
        "!window size=64;64\n"
        "    !canvas3d samples=4 viewpoint=0;0;40 fov=0.15 near=1\n"
        "        !light color=1\n"
        "        !sphere size=4.9 position=-2;2;24 color=1;0;0\n",
        /* up along the line of sight: no look-at, the identity view (the
         * eye at the origin looking along -z), not the viewpoint */
        "!window size=64;64\n"
        "    !canvas3d samples=4 viewpoint=0;40;0 focus=0 near=1\n"
        "        !light color=1\n"
        "        !sphere size=6 position=8;5;-30 color=1;0;0\n"
        "        !sphere size=4 position=-6;-4;-20 color=1;0;0\n",
    };
    for (int s = 0; s < 4; s++) {
        for (int k = 0; k < 2; k++) {
            routes.impostors = k ? FL_IMPOSTORS_OCTAGONS : FL_IMPOSTORS_OFF;
            fl_runtime *rt = draw(scripts[s], pix[k]);
            fl_free(rt);
        }
        routes = (fl_debug_options){0};
        int mesh = 0, missed = 0, extra = 0;
        for (int i = 0; i < W * H; i++) {
            int m = chan(pix[0][i], 16), q = chan(pix[1][i], 16);
            mesh += m > 0;
            missed += m > 0 && q == 0;
            extra += q > 0 && m == 0;
        }
        if (missed) fail_msg("script %d: %d of the mesh spheres' %d pixels not drawn by the impostors", s, missed, mesh);
        assert_true(mesh > 300);
        assert_true(extra <= mesh / 10);   /* the facets' share */
    }
}

/* With samples, an octagon's coverage is decided per sample by whether
 * the sample's line passes within the sphere's radius, computed from the
 * pixel centre's line by updates linear in the sample's offset (Plücker
 * coordinates); fl_debug_options.impostors FL_IMPOSTORS_BOX draws the same spheres on
 * their boxes, each sample's own ray intersected exactly. The two must
 * agree on every pixel but a few at the rims, and both must smooth the
 * rims (partly covered pixels): spheres of several sizes and distances,
 * off the axis, in perspective and orthographic views, with 4 samples
 * and with 2 (the octagon program is made for the count). The octagon
 * program must compile (it would otherwise fall back to the box
 * impostor's test, with a warning). */
static void impostor_octagon_samples(void **st)
{
    (void)st;
    static uint32_t pix[2][W * H];
    static const char *scripts[] = {
        "!window size=64;64\n"
        "    !canvas3d samples=4 viewpoint=0;0;40 fov=0.15 near=1\n"
        "        !light color=1\n"
        "        !sphere size=6 position=9;7;0 color=1;0;0\n"
        "        !sphere size=4 position=-9;-6;6 color=0;1;0\n"
        "        !sphere size=1.5 position=-6;8;20 color=0;0;1\n"
        "        !sphere size=7 position=1;-3;-30 color=1;1;0\n",
        "!window size=64;64\n"
        "    !canvas3d samples=4 viewpoint=10;5;40 focus=0 orthographic=true width=64 near=1\n"
        "        !light color=1\n"
        "        !sphere size=9 position=16;12;0 color=1;0;0\n"
        "        !sphere size=2.5 position=-20;-14;14 color=0;1;0\n",
        "!window size=64;64\n"
        "    !canvas3d samples=2 viewpoint=0;0;40 fov=0.15 near=1\n"
        "        !light color=1\n"
        "        !sphere size=7 position=-8;6;0 color=1;0;0\n"
        "        !sphere size=3 position=8;-8;10 color=0;1;0\n",
    };
    for (int s = 0; s < 3; s++) {
        for (int k = 0; k < 2; k++) {
            routes.impostors = k ? FL_IMPOSTORS_BOX : FL_IMPOSTORS_OCTAGONS;
            fl_runtime *rt = draw(scripts[s], pix[k]);
            if (strstr(logged, "compile")) fail_msg("script %d: %s", s, logged);
            fl_free(rt);
        }
        routes = (fl_debug_options){0};
        int drawn = 0, partial[2] = {0, 0}, differ = 0, full[2] = {0, 0};
        for (int k = 0; k < 2; k++)   /* a covered pixel's value (the spheres' colours are 0 or 1) */
            for (int i = 0; i < W * H; i++)
                for (int sh = 0; sh < 24; sh += 8)
                    if (chan(pix[k][i], sh) > full[k]) full[k] = chan(pix[k][i], sh);
        for (int i = 0; i < W * H; i++) {
            int d = 0, lit = 0;
            for (int k = 0; k < 2; k++) {
                int top = 0;
                for (int sh = 0; sh < 24; sh += 8) {
                    int v = chan(pix[k][i], sh);
                    if (v > top) top = v;
                }
                if (top > 0 && top < full[k] - 8) partial[k]++;
                lit |= top > 0;
            }
            for (int sh = 0; sh < 24; sh += 8) {
                int e = abs(chan(pix[0][i], sh) - chan(pix[1][i], sh));
                if (e > d) d = e;
            }
            drawn += lit;
            differ += d > 8;
        }
        assert_true(drawn > 150);
        /* a covered pixel is (1 - F0) of its colour: every sample of it
         * written (2 samples asked: llvmpipe gives 4, all must be tested) */
        assert_true(full[0] >= srgb(1 - F0) - 1 && full[1] >= srgb(1 - F0) - 1);
        assert_true(partial[0] >= 12 && partial[1] >= 12);
        if (differ > 3) fail_msg("script %d: %d of %d pixels differ from the box impostors'", s, differ, drawn);
    }
}

/* Line lights (Flitter docs/canvas3d.md, Lights: `start`/`end`, `radius`;
 * glsl/lighting_functions.glsl, compute_pbr_lighting, the Line case). The
 * camera looks straight down at the top face (z=0) of a wide box from
 * above, orthographic, one unit per pixel: pixel (col, row) is the point
 * x = col - 31.5, y = 31.5 - row, with N = V = 0;0;1 (so the reflected
 * ray is 0;0;-1). A line 32 long at height h=8 runs along row 32 (y=-0.5)
 * from x=-15.5 to 16.5, centred over column 32. By hand, for a point at
 * distance x0 along the line from its middle (|x0| <= 16): the diffuse
 * pass's point is 3/4 of the way from the middle to the nearest point,
 * i.e. x0/4 from above the fragment: d = sqrt(h^2 + x0^2/16), NdotL = h/d;
 * the specular pass's point is straight above (the nearest to the ray):
 * NdotL = H.V = 1, D = G = 1 at roughness 1, so F0/4 of light/h^2.
 * Beyond the end (x0 > 16) the diffuse point is 3/4 of the way from the
 * middle to the end (the nearest point): 12 along; the specular point is
 * the end. */
static double ggx_rough1_spec(const double L[3])   /* V = N = z, roughness 1, light from L (unnormalised) */
{
    double d = sqrt(L[0] * L[0] + L[1] * L[1] + L[2] * L[2]);
    double nl = L[2] / d;
    double h[3] = {L[0] / d, L[1] / d, L[2] / d + 1};
    double hn = sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
    double hv = h[2] / hn;
    double f = F0 + (1 - F0) * pow(1 - hv, 5);
    double g = nl / (nl * 0.5 + 0.5);   /* k = (1+1)^2/8, G(V) = 1 */
    return f * g / 4 / (d * d);         /* times the light's colour */
}

static void line_light(void **st)
{
    (void)st;
    uint32_t pix[W * H];
    const char *head = "!window size=64;64\n"
                       "    !canvas3d orthographic=true width=64 viewpoint=0;0;100 far=1000\n"
                       "        !box size=64;64;2 position=0;0;-1 color=0.5\n";
    char script[1024];
    snprintf(script, sizeof script, "%s        !light start=-15.5;-0.5;8 end=16.5;-0.5;8 color=64\n", head);
    fl_runtime *rt = draw(script, pix);
    assert_null(strstr(logged, "line light"));
    double h = 8, c = 64, alb = 0.5;
    /* under the middle: light / h^2 * ((1-F0) albedo + F0/4) */
    double v = c / (h * h) * ((1 - F0) * alb + F0 / 4);
    assert_rgb_near(at(pix, 32, 32), v, v, v, 1);
    /* 8 along: the diffuse point is 2 back towards the fragment */
    double d = sqrt(h * h + 4);
    v = c * ((1 - F0) * alb * h / (d * d * d) + F0 / (4 * h * h));
    assert_rgb_near(at(pix, 40, 32), v, v, v, 1);
    assert_rgb_near(at(pix, 24, 32), v, v, v, 1);   /* symmetric */
    /* 24 along, beyond the end (16): the diffuse point 12 along, the
     * specular one the end itself, 8 back */
    d = sqrt(h * h + 12 * 12);
    double Ls[3] = {-8, 0, h};
    v = c * ((1 - F0) * alb * h / (d * d * d) + ggx_rough1_spec(Ls));
    assert_rgb_near(at(pix, 56, 32), v, v, v, 1);
    /* a point light at the middle is dimmer 8 along than the line is */
    int line8 = chan(at(pix, 40, 32), 0);
    fl_free(rt);
    snprintf(script, sizeof script, "%s        !light position=0.5;-0.5;8 color=64\n", head);
    rt = draw(script, pix);
    assert_true(chan(at(pix, 40, 32), 0) + 10 < line8);
    fl_free(rt);

    /* radius r=2 (a capsule): under the middle both passes have strength
     * 1 - r/h; the diffuse distance is h - r, the specular one h */
    snprintf(script, sizeof script, "%s        !light start=-15.5;-0.5;8 end=16.5;-0.5;8 radius=2 color=64\n",
             head);
    rt = draw(script, pix);
    double s = 1 - 2 / h;
    v = c * s * ((1 - F0) * alb / ((h - 2) * (h - 2)) + F0 / (4 * h * h));
    assert_rgb_near(at(pix, 32, 32), v, v, v, 1);
    fl_free(rt);

    /* a line through the surface (z from -10 to 10 at x=0.5, y=-0.5): only
     * the part above the tangent plane lights it. 4 columns away the
     * diffuse point is 3/4 of the way from the crossing (z=0) to the
     * middle of the part above (z=5): 1.25 high at distance 4 across; the
     * reflected ray runs along the line, whose nearest point is then the
     * crossing, in the plane: no specular light. */
    snprintf(script, sizeof script, "%s        !light start=0.5;-0.5;-10 end=0.5;-0.5;10 color=100\n", head);
    rt = draw(script, pix);
    d = sqrt(16 + 1.25 * 1.25);
    v = 100 * (1 - F0) * alb * (1.25 / d) / (d * d);
    assert_rgb_near(at(pix, 36, 32), v, v, v, 1);
    assert_rgb_near(at(pix, 32, 28), v, v, v, 1);
    fl_free(rt);
    /* the same line from its top down: the part above is now before the crossing */
    snprintf(script, sizeof script, "%s        !light start=0.5;-0.5;10 end=0.5;-0.5;-10 color=100\n", head);
    rt = draw(script, pix);
    assert_rgb_near(at(pix, 36, 32), v, v, v, 1);
    fl_free(rt);

    /* the specular point is the line's point nearest the reflected ray,
     * not the one nearest the fragment: a sloping line (x=4.5, z = 10 +
     * 0.4 y) over a metal surface (metal=1, albedo 1: no diffuse light,
     * F = 1). The ray from pixel (32,32) is vertical through 0.5;-0.5, so
     * its nearest line point is the one at y=-0.5: L = 4;0;9.8, and with
     * NdotV = 1, D = 1 at roughness 1: colour / d^2 * G(L) / 4 with G(L) =
     * NdotL / (NdotL/2 + 1/2). (The point nearest the fragment, y=-3.88,
     * would give 0.698 instead of 0.644.) */
    snprintf(script, sizeof script,
             "!window size=64;64\n"
             "    !canvas3d orthographic=true width=64 viewpoint=0;0;100 far=1000\n"
             "        !box size=64;64;2 position=0;0;-1 color=1 metal=1\n"
             "        !light start=4.5;-20;2 end=4.5;20;18 color=300\n");
    rt = draw(script, pix);
    double d2 = 16 + 9.8 * 9.8, nl = 9.8 / sqrt(d2);
    v = 300 / d2 * (nl / (nl / 2 + 0.5)) / 4;
    assert_rgb_near(at(pix, 32, 32), v, v, v, 1);
    fl_free(rt);

    /* start == end: a point light there (with its radius) */
    uint32_t point[W * H];
    snprintf(script, sizeof script, "%s        !light position=0.5;-0.5;8 radius=1 color=64\n", head);
    rt = draw(script, point);
    fl_free(rt);
    snprintf(script, sizeof script, "%s        !light start=0.5;-0.5;8 end=0.5;-0.5;8 radius=1 color=64\n", head);
    rt = draw(script, pix);
    assert_memory_equal(pix, point, sizeof pix);
    fl_free(rt);

    /* the full transform applies to both ends: a line scaled by 2 about
     * the origin from half-size coordinates is the first line */
    snprintf(script, sizeof script,
             "%s        !transform scale=2\n"
             "            !light start=-7.75;-0.25;4 end=8.25;-0.25;4 color=64\n", head);
    rt = draw(script, pix);
    v = c / (h * h) * ((1 - F0) * alb + F0 / 4);
    assert_rgb_near(at(pix, 32, 32), v, v, v, 1);
    fl_free(rt);

    /* bad input: infinite or NaN ends, huge radius; nothing crashes, the
     * box is still drawn (the ambient light keeps it visible) */
    const char *bad[] = {"start=0;0;1/0 end=0;0;8", "start=0/0 end=1;2;3", "start=0;0;8 end=1/0;0;8",
                         "start=-10;0;8 end=10;0;8 radius=1e30", "start=0;0;8 end=0;0;8 radius=-5"};
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        snprintf(script, sizeof script, "%s        !light color=0.1\n        !light %s color=64\n", head, bad[i]);
        rt = draw(script, pix);
        assert_int_equal(chan(at(pix, 10, 10), 24), 255);
        fl_free(rt);
    }
}

/* translucency= (Flitter docs/canvas3d.md, Materials; glsl/backface_lighting.frag
 * and lighting_functions.glsl, compute_translucency): a box of size 20 lit
 * only from behind (a directional light shining towards the camera). Its
 * front face gets no light of its own, so opaque it is black; translucent,
 * the light arriving on its back face, (1 - F0) (1 + albedo) / 2 of the
 * light, shows through it: back light * albedo * t (1 - t) for the share t
 * = 0.5^(thickness / translucency) that passes. Straight through the
 * middle the box is 20 thick; at translucency=1000 the sample cloud is a
 * small fraction of a pixel across, so t = 0.5^(20/1000) exactly; at
 * translucency=20, t = 0.5 in the middle of the back face (the cloud,
 * about three pixels across, stays almost all on it). */
static void translucency_backlit(void **st)
{
    (void)st;
    uint32_t pix[W * H];
    const char *fmt = "!window size=64;64\n"
                      "    !canvas3d\n"
                      "        !light color=1 direction=0;0;1\n"
                      "        !box size=20 color=1 translucency=%s\n";
    char script[512];
    snprintf(script, sizeof script, fmt, "0");
    fl_runtime *rt = draw(script, pix);
    assert_int_equal(at(pix, 32, 32), 0xff000000u);
    fl_free(rt);
    double back = (1 - F0) * (1 + 1) / 2;
    snprintf(script, sizeof script, fmt, "1000");
    rt = draw(script, pix);
    double t = pow(0.5, 20.0 / 1000);
    assert_rgb_near(at(pix, 32, 32), back * t * (1 - t), back * t * (1 - t), back * t * (1 - t), 1);
    assert_rgb_near(at(pix, 28, 36), back * t * (1 - t), back * t * (1 - t), back * t * (1 - t), 1);
    assert_null(strstr(logged, "translucency"));   /* no "drawn opaque" any more */
    fl_free(rt);
    snprintf(script, sizeof script, fmt, "20");
    rt = draw(script, pix);
    assert_rgb_near(at(pix, 32, 32), back * 0.25, back * 0.25, back * 0.25, 3);
    assert_int_equal(at(pix, 2, 2), 0x00000000u);   /* around it, nothing */
    fl_free(rt);
    /* a light from the front instead: the translucent box's front face is
     * lit as the opaque one's (the back faces get no light to let through) */
    uint32_t opaque[W * H];
    rt = draw("!window size=64;64\n"
              "    !canvas3d\n"
              "        !light color=0.5 direction=0;0;-1\n"
              "        !box size=20 color=1;0.5;0\n", opaque);
    fl_free(rt);
    rt = draw("!window size=64;64\n"
              "    !canvas3d\n"
              "        !light color=0.5 direction=0;0;-1\n"
              "        !box size=20 color=1;0.5;0 translucency=5\n", pix);
    for (int y = 26; y < 38; y++)
        for (int x = 26; x < 38; x++) assert_int_equal(at(pix, x, y), at(opaque, x, y));
    fl_free(rt);
}

/* A translucent sphere (radius 10, translucency 2) lit from behind glows
 * through its thin edges, not its thick middle (20 deep: 0.5^10 of the
 * light passes); drawn as a mesh whether or not spheres may be impostors.
 * The same sphere opaque is black all over. */
static void translucency_thin_edges(void **st)
{
    (void)st;
    static uint32_t pix[2][W * H];
    const char *script = "!window size=64;64\n"
                         "    !canvas3d\n"
                         "        !light color=1 direction=0;0;1\n"
                         "        !sphere size=10 color=1 translucency=2\n";
    for (int k = 0; k < 2; k++) {
        routes.impostors = k ? FL_IMPOSTORS_OCTAGONS : FL_IMPOSTORS_OFF;
        fl_runtime *rt = draw(script, pix[k]);
        fl_free(rt);
    }
    routes = (fl_debug_options){0};
    assert_memory_equal(pix[0], pix[1], sizeof pix[0]);
    int middle = 0, edge = 0;
    for (int d = -1; d <= 1; d++) {
        middle += chan(at(pix[1], 32 + d, 32), 8) + chan(at(pix[1], 32, 32 + d), 8);
        edge += chan(at(pix[1], 22, 32 + d), 8) + chan(at(pix[1], 41, 32 + d), 8);
    }
    middle /= 6, edge /= 6;
    if (!(middle < 12 && edge > middle + 8)) fail_msg("middle %d, edges %d", middle, edge);
    fl_runtime *rt = draw("!window size=64;64\n"
                          "    !canvas3d\n"
                          "        !light color=1 direction=0;0;1\n"
                          "        !sphere size=10 color=1\n", pix[0]);
    for (int d = -1; d <= 1; d++) {
        assert_int_equal(at(pix[0], 22, 32 + d) & 0xffffff, 0);
        assert_int_equal(at(pix[0], 32 + d, 32) & 0xffffff, 0);
    }
    fl_free(rt);
}

/* translucency=0 is no translucency: the picture is byte for byte the one
 * without the attribute (with impostor spheres, MSAA, a transparent box);
 * a translucent sphere in a corner leaves the rest of the picture as it
 * was; in a group without depth sorting translucent instances find no
 * back faces and keep only their specular light (Flitter binds an empty
 * texture there); bad values never crash. */
static void translucency_zero_unchanged(void **st)
{
    (void)st;
    static uint32_t plain[W * H], pix[W * H];
    const char *fmt = "!window size=64;64\n"
                      "    !canvas3d samples=4\n"
                      "        !light color=1 direction=-1;-1;-1\n"
                      "        !light color=0.1\n"
                      "        !box size=20 color=1;0.5;0 rotation=0.1;0.1;0 %s\n"
                      "        !sphere size=6 position=-15;15;5 color=0;1;1 %s\n"
                      "        !box size=8 position=15;-15;5 color=1 transparency=0.5 %s\n"
                      "%s";
    char script[1024];
    snprintf(script, sizeof script, fmt, "", "", "", "");
    fl_runtime *rt = draw(script, plain);
    fl_free(rt);
    snprintf(script, sizeof script, fmt, "translucency=0", "translucency=0", "translucency=0", "");
    rt = draw(script, pix);
    assert_memory_equal(pix, plain, sizeof pix);
    fl_free(rt);
    snprintf(script, sizeof script, fmt, "", "", "",
             "        !sphere size=4 position=25;25;0 color=1 translucency=3\n");
    rt = draw(script, pix);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            if (x < 48 || y > 16) assert_int_equal(at(pix, x, y), at(plain, x, y));
    fl_free(rt);

    rt = draw("!window size=64;64\n"
              "    !canvas3d\n"
              "        !light color=1 direction=0;0;1\n"
              "        !group depth_sort=false\n"
              "            !box size=20 color=1 translucency=20\n", pix);
    assert_int_equal(at(pix, 32, 32), 0x00000000u);
    fl_free(rt);

    const char *bad[] = {"1/0", "0/0", "-5", "1e-30", "1e30", "null", "1;2"};
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        snprintf(script, sizeof script,
                 "!window size=64;64\n"
                 "    !canvas3d samples=4\n"
                 "        !light color=0.1\n"
                 "        !light color=1 direction=0;0;1\n"
                 "        !box size=20 color=1 translucency=%s\n"
                 "        !box size=200;200;1 position=0;0;-25 color=1\n", bad[i]);
        rt = draw(script, pix);
        assert_int_equal(chan(at(pix, 2, 2), 24), 255);   /* the wall behind is drawn */
        fl_free(rt);
    }
}

/* A group of at most 8 lights gets a program with its lights compiled in
 * one by one (their types and passes known); more go through the loop
 * over the Lights block. The two must light alike: every kind of light
 * (ambient, directional, a point light with a radius (two passes) and
 * one without, a spot, a line with a radius) on a rough and a shiny
 * sphere and a box, drawn with the 6 lights listed and again with 4
 * lights too faint to add anything (10: the loop), pixel for pixel; the
 * programs compile. */
static void listed_lights_as_looped(void **st)
{
    (void)st;
    static uint32_t pix[2][W * H];
    const char *lights = "        !light color=0.03\n"
                         "        !light color=0.15 direction=-1;-0.5;-1\n"
                         "        !light color=40 position=-12;8;14 radius=2\n"
                         "        !light color=30 position=14;-6;10\n"
                         "        !light color=80 position=0;0;30 focus=4;0;0 outer=0.08 inner=0.03\n"
                         "        !light color=8 start=-14;-14;6 end=14;-14;6 radius=1\n";
    /* lights too faint to count (radiance under the shader's 1e-3 a2
     * threshold, exactly nothing added), but lights: 10 in all */
    const char *faint = "        !light color=0.000000001 position=1;1;30\n"
                        "        !light color=0.000000001 position=2;2;30 radius=1\n"
                        "        !light color=0.000000001 direction=0;0;-1\n"
                        "        !light color=0.000000001 position=4;4;30\n";
    const char *models = "        !sphere size=7 position=-7;4;0 color=1;0.5;0.2 roughness=0.3\n"
                         "        !sphere size=6 position=8;3;0 color=0.2;0.6;1 roughness=0.9 metal=0.5\n"
                         "        !box size=30;12;2 position=0;-10;-4 color=0.8\n";
    char script[2048];
    for (int k = 0; k < 2; k++) {
        snprintf(script, sizeof script, "!window size=64;64\n    !canvas3d samples=4 viewpoint=0;0;60 fov=0.12\n%s%s%s",
                 lights, k ? faint : "", models);
        fl_runtime *rt = draw(script, pix[k]);
        if (strstr(logged, "compile")) fail_msg("%s", logged);
        fl_free(rt);
    }
    int lit = 0;
    for (int i = 0; i < W * H; i++) {
        if (pix[0][i] != pix[1][i])
            fail_msg("pixel (%d,%d) is %08x with the lights listed, %08x looped", i % W, i / W, pix[0][i], pix[1][i]);
        lit += chan(pix[0][i], 16) > 20 || chan(pix[0][i], 0) > 20;
    }
    assert_true(lit > 1000);
}

/* A canvas compiles 16 programs with their lights listed at once, then
 * one more every 30 frames; lights without a program meanwhile are looped
 * over. 40 frames, each with its own list (1 to 8 point lights with and
 * without a radius and spots, in an order that shifts every 8 frames):
 * past the 16 (frames 16 to 28 loop, frame 29 lists again, then loop),
 * every frame's picture must be what a fresh runtime (its programs
 * listed) draws for that frame. */
static void listed_programs_capped(void **st)
{
    (void)st;
    static uint32_t pix[W * H], fresh[W * H];
    static const char script[] =
        "let f=(F if F else frame)\n"
        "!window size=64;64\n"
        "    !canvas3d viewpoint=0;0;60 fov=0.12\n"
        "        for i in ..(f % 8) + 1\n"
        "            let t=(i + f // 8) % 3\n"
        "            if t == 2\n"
        "                !light color=600 position=(i*3-10);5;25 focus=0 outer=0.1\n"
        "            else\n"
        "                !light color=300 position=(i*3-10);5;25 radius=t*2\n"
        "        !sphere size=9 color=1 roughness=0.4\n"
        "        !box size=40;40;1 position=0;0;-9 color=0.5\n";
    fl_runtime *rt = load_script("capped.fl", script, NULL);
    for (int frame = 0; frame < 40; frame++) {
        assert_int_equal(fl_step(rt), 0);
        assert_int_equal(fl_draw_window(rt, 0, pix, W, H, W * 4), 0);
        char value[16];
        snprintf(value, sizeof value, "%d", frame);
        fl_runtime *one = load_script("capped.fl", NULL, value);
        assert_int_equal(fl_step(one), 0);
        assert_int_equal(fl_draw_window(one, 0, fresh, W, H, W * 4), 0);
        fl_free(one);
        int lit = 0;
        for (int i = 0; i < W * H; i++) {
            if (pix[i] != fresh[i])
                fail_msg("frame %d: pixel (%d,%d) is %08x, fresh %08x", frame, i % W, i / W, pix[i], fresh[i]);
            lit += chan(pix[i], 16) > 10;
        }
        assert_true(lit > 300);
    }
    fl_free(rt);
    remove_script("capped.fl");
}

/* Each render group's program has the code of only the kinds of light it
 * sees (its own and its ancestors'), and a canvas keeps 8 programs. Nine
 * groups in a 3x3 grid, two by two sharing max_lights but not their kinds
 * of light (9 programs in one frame), under a canvas-level line light:
 * every group's box is drawn exactly as when its group is the canvas's
 * only one. */
static void light_kinds_per_group(void **st)
{
    (void)st;
    static const char *const lights[9] = {
        "!light color=3 position=%d;%d;12\n",
        "!light color=3 position=%d;%d;12 focus=%d;%d;0 outer=0.1\n",
        "!light color=1 direction=0;0.3;-1\n",
        "!light color=0.5\n",
        "!light color=2 position=%d;%d;12\n                !light color=2 position=%d;%d;14 focus=%d;%d;0\n",
        "!light color=1 direction=0.3;0;-1\n                !light color=2 position=%d;%d;14 focus=%d;%d;0\n",
        "!light color=2 start=%d;%d;10 end=%d;%d;12\n",
        "!light color=2 position=%d;%d;12 radius=2\n                !light color=1 direction=0;0;-1\n",
        ("!light color=1 position=%d;%d;12\n                !light color=1 position=%d;%d;14 focus=%d;%d;0\n"
         "                !light color=0.5 direction=-0.2;0;-1\n                !light color=1 start=%d;%d;9 end=%d;%d;9\n"),
    };
    char groups[9][600];
    for (int g = 0; g < 9; g++) {
        int x = (g % 3 - 1) * 20, y = (g / 3 - 1) * 20;
        char light[400];
        snprintf(light, sizeof light, lights[g], x, y, x, y, x + 1, y, x + 1, y, x - 2, y, x + 2, y);
        snprintf(groups[g], sizeof groups[g],
                 "        !group max_lights=%d\n"
                 "            !transform\n"
                 "                %s"
                 "                !box position=%d;%d;0 size=9 color=0.8;0.6;0.4\n",
                 2 + g / 2, light, x, y);
    }
    static const char head[] = "!window size=64;64\n"
                               "    !canvas3d\n"
                               "        !light color=0.3;0.3;0.5 start=-30;30;20 end=30;-30;20\n";
    char all[8192];
    int n = snprintf(all, sizeof all, "%s", head);
    for (int g = 0; g < 9; g++)
        n += snprintf(all + n, sizeof all - (size_t)n, "%s", groups[g]);
    uint32_t pix[W * H], one[W * H];
    fl_free(draw(all, pix));
    for (int g = 0; g < 9; g++) {
        char script[8192];
        snprintf(script, sizeof script, "%s%s", head, groups[g]);
        fl_free(draw(script, one));
        /* the box's face: 9 units at z=4.5, about 13 pixels, centred */
        int cx = 32 + (g % 3 - 1) * 20 * 32 / 27, cy = 32 - (g / 3 - 1) * 20 * 32 / 27;
        bool lit = false;
        for (int y = cy - 4; y <= cy + 4; y++)
            for (int x = cx - 4; x <= cx + 4; x++) {
                if (at(pix, x, y) != at(one, x, y))
                    fail_msg("group %d: pixel %d,%d is %08x, alone %08x", g, x, y, at(pix, x, y), at(one, x, y));
                lit = lit || chan(at(one, x, y), 16) > 20;
            }
        assert_true(lit);
    }
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
                          "        !teapot\n"
                          "        !teapot size=2\n"
                          "        !model filename=\"no-such-teapot.obj\"\n"
                          "        !model filename=\"no-such-teapot.obj\" size=2\n"
                          "        !box size=20 color=1\n"
                          "    !canvas\n"
                          "        !wibble\n", pix);
    assert_int_equal(fl_step(rt), 0);
    assert_int_equal(fl_draw_window(rt, 0, pix, W, H, W * 4), 0);
    const char *p = strstr(logged, "canvas3d: skipping unsupported !teapot");
    assert_non_null(p);
    assert_null(strstr(p + 1, "canvas3d: skipping unsupported !teapot"));
    /* a model file that cannot be read: said once, the rest drawn */
    p = strstr(logged, "no-such-teapot.obj: cannot load model: no such file");
    assert_non_null(p);
    assert_null(strstr(p + 1, "no-such-teapot.obj: cannot load model"));
    assert_non_null(strstr(logged, "canvas: skipping unsupported !wibble"));
    assert_int_equal(chan(at(pix, 32, 32), 24), 255);   /* the box is drawn all the same */
    fl_free(rt);
}

/* Texture attributes (Flitter docs/canvas3d.md, Texture Mapping) name
 * the picture of a window node with that id: a texture that no node has
 * is named once (over two frames and however many uses, under either of
 * a property's names, on a model, a !material, a !group or the canvas)
 * and the model is drawn with its plain colour; camera_id (also ending in
 * _id) is no texture. */
static void textures_missing_named_once(void **st)
{
    (void)st;
    uint32_t pix[W * H];
    fl_runtime *rt = draw("!window size=64;64\n"
                          "    !canvas3d camera_id=:nothing emissive_id=:glow\n"
                          "        !light color=1\n"
                          "        !group metal_texture_id=:m\n"
                          "            !material color_id=:pic\n"
                          "                !box size=20 color=1;0;0 texture_id=:other\n"
                          "                !sphere size=2 position=25;25;0 color=1 metal_id=:m2 texture_id=:x\n",
                          pix);
    assert_int_equal(fl_step(rt), 0);
    assert_int_equal(fl_draw_window(rt, 0, pix, W, H, W * 4), 0);
    const char *ids[] = {"glow", "m", "other", "x", "m2"};
    for (size_t i = 0; i < sizeof ids / sizeof *ids; i++) {
        char want[128];
        snprintf(want, sizeof want, "canvas3d: no window node with a picture has id %s (yet)", ids[i]);
        const char *p = strstr(logged, want);
        if (!p) fail_msg("no note for %s in:\n%s", ids[i], logged);
        assert_null(strstr(p + 1, want));   /* once */
    }
    assert_null(strstr(logged, "has id pic"));      /* texture_id= on the box wins */
    assert_null(strstr(logged, "has id nothing"));  /* camera_id is no texture */
    assert_rgb_near(at(pix, 32, 32), 1 - F0, 0, 0, 1);   /* the box in its own colour */
    fl_free(rt);
}

/* A texture that a window node has: the box's albedo is the picture's
 * light (a canvas filled with red, linear 1;0;0) instead of its own
 * green, lit by an ambient light of 1: (1 - F0) * 1 red at its centre;
 * the canvas itself shows in the corner, under the canvas3d. */
static void textures_drawn(void **st)
{
    (void)st;
    uint32_t pix[W * H];
    fl_runtime *rt = draw("!window size=64;64\n"
                          "    !canvas id=:pic\n"
                          "        !rect size=64;64\n"
                          "        !fill color=1;0;0\n"
                          "    !canvas3d\n"
                          "        !light color=1\n"
                          "        !box size=20 color=0;1;0 texture_id=:pic\n",
                          pix);
    assert_int_equal(fl_step(rt), 0);
    assert_int_equal(fl_draw_window(rt, 0, pix, W, H, W * 4), 0);
    assert_null(strstr(logged, "has id pic"));
    assert_rgb_near(at(pix, 32, 32), 1 - F0, 0, 0, 1);
    assert_int_equal(at(pix, 1, 1), 0xffff0000u);
    fl_free(rt);
}

/* uv_remap=:plane maps the texture across the box's x and y from its
 * lower left corner: the front face of a box drawn right of the middle
 * (pixels 32 to 54) shows the picture's left half (red) on its left,
 * where the picture itself, drawn behind, is blue, and its right half
 * (blue, darkened by the Fresnel term) on its right. The box's own uv_map
 * puts a sixth of the picture on each face, one colour only. */
static void uv_remap_plane(void **st)
{
    (void)st;
    uint32_t pix[W * H];
    const char *scene = "!window size=64;64\n"
                        "    !canvas id=:pic\n"
                        "        !group\n"
                        "            !rect size=32;64\n"
                        "            !fill color=1;0;0\n"
                        "        !group\n"
                        "            !rect point=32;0 size=32;64\n"
                        "            !fill color=0;0;1\n"
                        "    !canvas3d\n"
                        "        !light color=1\n"
                        "        !box size=16 position=8;0;0 color=0;1;0 texture_id=:pic uv_remap=:plane\n";
    fl_runtime *rt = draw(scene, pix);
    assert_int_equal(fl_step(rt), 0);
    assert_int_equal(fl_draw_window(rt, 0, pix, W, H, W * 4), 0);
    assert_null(strstr(logged, "uv_remap"));
    assert_int_equal(at(pix, 60, 32), 0xff0000ffu);   /* the picture */
    assert_rgb_near(at(pix, 37, 32), 1 - F0, 0, 0, 1);
    assert_rgb_near(at(pix, 48, 32), 0, 0, 1 - F0, 1);
    fl_free(rt);
}

/* Fail unless [got] equals [want] pixel for pixel ([what]: the scene and
 * route, [without]: what [want] was drawn without), and unless [want]
 * has 200 pixels or more unlike its first (a scene that drew something). */
static void assert_same_picture(const uint32_t *got, const uint32_t *want, const char *what, const char *without)
{
    int lit = 0;
    for (int i = 0; i < W * H; i++) {
        if (got[i] != want[i])
            fail_msg("%s: pixel %d,%d is %08x, without %s %08x", what, i % W, i / W, got[i], without, want[i]);
        lit += want[i] != want[0];
    }
    if (lit < 200) fail_msg("%s: only %d pixels drawn", what, lit);
}

/* With samples, a render group of opaque meshes lying two or more deep
 * under 12 lights or more is first drawn depth only (the occluders), and
 * its meshes discard the fragments hidden at every sample of their pixel
 * (canvas3d_occlusion.h). Each scene is drawn with
 * FL_OCCLUSION_ALWAYS (the pass wherever it can be) and FL_OCCLUSION_NEVER
 * (never), and the two pictures must be equal pixel for pixel: boxes stacked front to back and back to front, meshes
 * crossing one another at angles (the depth varies across a pixel at
 * their edges), two boxes sharing a face, fog, with transparent boxes
 * and impostor spheres among them, and, in a group whose composite is
 * "add" (no pass there: a hidden fragment drawn first has added its
 * light), boxes and cones each in front of the other kind. */
static void occlusion_as_without(void **st)
{
    (void)st;
    static uint32_t pix[2][W * H];
    static const char *lights =
        "        for i in ..8\n"
        "            !light color=0.4;0.3;0.2 position=(i-4)*10;(i%3-1)*15;40 falloff=0;0;1;0\n"
        "        !light color=0.05\n";
    static const char *bodies[] = {
        "        for i in ..6\n"
        "            !box size=14-i position=i-3;i-2;-i*4 rotation=0.05*i;0.1;0 color=0.2*i;0.5;1-0.1*i\n",
        "        for i in ..6\n"
        "            !box size=8+i position=3-i;2-i;i*4-20 rotation=0.1;0.05*i;0 color=1;0.2*i;0.3\n",
        "        !box size=30;4;4 rotation=0;0;0.1 color=1;0;0\n"
        "        !box size=4;30;4 rotation=0.2;0;0 color=0;1;0\n"
        "        !cylinder size=3;3;40 rotation=0.25;0.1;0 color=0;0;1\n"
        "        !cone size=8;8;20 position=0;0;5 rotation=0.1;0.3;0 color=1;1;0\n"
        "        !box size=12 position=4;4;-8 rotation=0.1;0.1;0.1 color=0.5\n",
        "        !box size=10 position=-5;0;0 color=1;0.5;0\n"
        "        !box size=10 position=5;0;0 color=0;0.5;1\n"
        "        !box size=20;20;2 position=0;0;-8 color=0.8\n"
        "        !box size=6 position=0;0;3 color=1\n",
        "        for i in ..5\n"
        "            !box size=12 position=i*2-4;0;-i*6 rotation=0;0.1*i;0 color=1;1-0.2*i;0.5\n"
        "        !box size=9 position=0;3;6 color=0;1;0 transparency=0.5\n"
        "        !sphere size=4 position=-5;-5;8 color=1;0;1\n"
        "        !sphere size=3 position=6;-4;2 color=0;1;1\n",
        /* each kind of mesh both in front of and behind the other, so that
         * whichever is drawn first, something far is drawn before what
         * hides it */
        "        !box size=26 position=0;0;-25 color=1;0;0\n"
        "        !cone size=22;22;10 position=1;1;10 color=0;1;0\n"
        "        !cone size=26;26;10 position=-1;0;-32 color=0;0;1\n"
        "        !box size=12 position=0;-1;18 color=1;1;0\n",
    };
    static const char *heads[] = {
        "!window size=64;64\n    !canvas3d samples=4 viewpoint=10;8;80 focus=0 fov=0.12 near=1 far=500\n",
        "!window size=64;64\n    !canvas3d samples=4 viewpoint=-6;10;70 focus=0 fov=0.12 near=1 far=500"
        " fog_color=0.2;0.3;0.4 fog_min=40 fog_max=120\n",
    };
    char script[2048];
    for (int s = 0; s < 7; s++) {
        const char *head = heads[s == 5];
        const char *body = bodies[s < 5 ? s : s == 5 ? 0 : 5];
        snprintf(script, sizeof script, "%s%s%s", head, lights, body);
        if (s == 6) {
            /* the same in a group of composite "add" (no pass there):
             * the lights and models one level deeper */
            char deeper[2048];
            size_t n = 0;
            n += (size_t)snprintf(deeper + n, sizeof deeper - n, "%s        !group composite=:add\n", head);
            for (const char *t = lights; *t;) {
                const char *e = strchr(t, '\n');
                n += (size_t)snprintf(deeper + n, sizeof deeper - n, "    %.*s\n", (int)(e - t), t);
                t = e + 1;
            }
            for (const char *t = body; *t;) {
                const char *e = strchr(t, '\n');
                n += (size_t)snprintf(deeper + n, sizeof deeper - n, "    %.*s\n", (int)(e - t), t);
                t = e + 1;
            }
            snprintf(script, sizeof script, "%s", deeper);
        }
        for (int k = 0; k < 2; k++) {
            routes.occlusion = k ? FL_OCCLUSION_NEVER : FL_OCCLUSION_ALWAYS;
            fl_runtime *rt = draw(script, pix[k]);
            if (strstr(logged, "compile") || strstr(logged, "link")) fail_msg("script %d: %s", s, logged);
            fl_free(rt);
        }
        routes = (fl_debug_options){0};
        char what[32];
        snprintf(what, sizeof what, "script %d", s);
        assert_same_picture(pix[0], pix[1], what, "occluders");
    }
}

/* Without multisampling, opaque spheres drawn on octagons, 8 or more in a
 * group (with FL_OCCLUSION_ALWAYS, one or more), first have proxies drawn
 * depth only (an octagon through each centre, within its great disc),
 * and their octagons discard the fragments hidden behind those
 * (canvas3d_occlusion.h). Each scene is drawn with FL_OCCLUSION_ALWAYS,
 * FL_OCCLUSION_NEVER and by default, and the pictures must be equal pixel
 * for pixel: a ball of spheres of many sizes seen from two sides;
 * spheres intersecting one another along the line of sight (their
 * surfaces within a fraction of a unit of each other's proxies), seen
 * from two sides; an orthographic camera with fog; spheres among boxes,
 * a transparent sphere and an ellipsoid (not a billboard); spheres seen
 * from close by, their octagons near the camera's near plane; and the
 * ball with 4 samples (no proxies there). */
static void proxies_as_without(void **st)
{
    (void)st;
    static uint32_t pix[3][W * H];
    static const char *ball =
        "        !light color=0.8 direction=-1;-1;-2\n"
        "        !light color=0.1\n"
        "        for i in ..90\n"
        "            !sphere position=(uniform(:p;i)[..3]-0.5)*30 size=1+uniform(:r)[i]*5 color=hsv(i/90;0.7;1)\n";
    static const char *chain =
        "        !light color=0.8 direction=-1;-1;-2\n"
        "        !light color=0.1\n"
        "        for i in ..12\n"
        "            !sphere position=(i-6)*0.9;(i%3-1)*0.7;10-i*1.6 size=2.5 color=i/12;1-i/12;0.5\n";
    static const char *mixed =
        "        !light color=0.8 position=10;20;40 falloff=0;0;0;0.0005\n"
        "        !light color=0.1\n"
        "        !box size=8 position=-6;0;6 rotation=0.1;0.2;0 color=1;1;0\n"
        "        !box size=20;20;2 position=0;0;-12 color=0.5\n"
        "        !sphere size=9 position=3;3;4 color=1 transparency=0.6\n"
        "        !sphere size=3;6;3 position=-3;-6;2 color=0;1;1\n"
        "        for i in ..30\n"
        "            !sphere position=(uniform(:q;i)[..3]-0.5)*24 size=1.5+uniform(:s)[i]*3 color=1;0.3;0\n";
    static const char *close =
        "        !light color=0.8 direction=0;-1;-2\n"
        "        for i in ..9\n"
        "            !sphere position=(i%3-1)*6;(i//3-1)*6;60+i size=4 color=0.2;0.5;1\n"
        "        !sphere position=0;0;90 size=3 color=1\n";
    struct {
        const char *head, *body;
    } scenes[] = {
        {"!window size=64;64\n    !canvas3d samples=1 viewpoint=10;8;80 focus=0 fov=0.12 near=1 far=500\n", ball},
        {"!window size=64;64\n    !canvas3d samples=1 viewpoint=-20;5;70 focus=0 fov=0.12 near=1 far=500\n", ball},
        {"!window size=64;64\n    !canvas3d samples=1 viewpoint=0;0;60 focus=0 fov=0.1 near=1 far=500\n", chain},
        {"!window size=64;64\n    !canvas3d samples=1 viewpoint=3;2;60 focus=0 fov=0.1 near=1 far=500\n", chain},
        {"!window size=64;64\n    !canvas3d samples=1 orthographic=true width=40 viewpoint=5;5;100 focus=0 far=500"
         " fog_color=0.2;0.3;0.4 fog_min=80 fog_max=120\n",
         ball},
        {"!window size=64;64\n    !canvas3d samples=1 viewpoint=-6;10;70 focus=0 fov=0.12 near=1 far=500\n", mixed},
        {"!window size=64;64\n    !canvas3d samples=1 viewpoint=0;0;100 focus=0 fov=0.2 near=1 far=500\n", close},
        {"!window size=64;64\n    !canvas3d samples=4 viewpoint=10;8;80 focus=0 fov=0.12 near=1 far=500\n", ball},
    };
    char script[2048];
    for (size_t s = 0; s < sizeof scenes / sizeof scenes[0]; s++) {
        snprintf(script, sizeof script, "%s%s", scenes[s].head, scenes[s].body);
        static const int modes[3] = {FL_OCCLUSION_ALWAYS, FL_OCCLUSION_NEVER, FL_OCCLUSION_AUTO};
        for (int k = 0; k < 3; k++) {
            routes.occlusion = modes[k];
            fl_runtime *rt = draw(script, pix[k]);
            if (strstr(logged, "compile") || strstr(logged, "link")) fail_msg("scene %zu: %s", s, logged);
            fl_free(rt);
        }
        routes = (fl_debug_options){0};
        char what[32];
        for (int k = 0; k < 3; k += 2) {
            snprintf(what, sizeof what, "scene %zu (%s)", s, k ? "auto" : "always");
            assert_same_picture(pix[k], pix[1], what, "proxies");
        }
    }
}

/* Lights culled per mesh (canvas3d_cull.h): a light behind every face of
 * a flat mesh adds nothing to it and is left out of its draw. Scenes with
 * more lights than a listed program holds (the looping program culls),
 * among them Flitter's examples/bounce.fl in small (its glass box's outer
 * wall cannot see the lights of the balls inside, the inner one can),
 * and opaque boxes drawn behind the occluders' pass with samples, drawn
 * with culling and without: equal pixel for pixel. */
static void lights_culled_as_without(void **st)
{
    (void)st;
    static uint32_t pix[2][W * H];
    static const char *glass =
        "        !light color=0.3\n"
        "        !material transparency=0.9 color=1 roughness=0.15\n"
        "            !transform translate=0;0;50\n"
        "                !box size=100 invert=true\n"
        "                !box size=102\n"
        "        for i in ..12\n"
        "            !light position=(uniform(:p;i)[..3]-0.5)*80+(0;0;50) falloff=1;0;1;0 color=hsv(i/12;0.9;1)*50"
        " radius=2+uniform(:r)[i]*5\n"
        "        for x in -1;1, y in -1;1\n"
        "            !light color=0.05 direction=x;y;0.5+0.1*y-0.05*x\n";
    static const char *spots =
        "        !light color=0.1\n"
        "        !box size=40 color=0.8 position=0;0;0\n"
        "        !box size=30 invert=true color=0.6;0.7;0.8 position=60;0;0\n"
        "        for i in ..6\n"
        "            !light position=(i%3-1)*8;(i//3-0.5)*10;3 focus=0;0;30 color=40 outer=0.2\n"
        "        for i in ..6\n"
        "            !light position=60+(i%3-1)*8;(i//3-0.5)*10;0 color=40;0;0 falloff=1;0;0.1;0\n"
        "        !light position=0;-60;60 color=2000 falloff=1;0;1;0\n";
    static const char *translucent =
        "        !light color=0.1\n"
        "        !box size=30 color=0.9 translucency=20 position=0;0;0\n"
        "        for i in ..10\n"
        "            !light position=(uniform(:q;i)[..3]-0.5)*20 color=hsv(i/10;1;1)*20 falloff=1;0;1;0\n"
        "        !light position=40;40;40 color=1000 falloff=1;0;1;0\n";
    /* opaque boxes two deep, with the occluders' pass (its occluded program culls too) */
    static const char *stacked =
        "        !light color=0.1\n"
        "        !box size=30 color=0.7 position=0;0;0 uv_map=:repeat\n"   /* (a mesh of its own) */
        "        for i in ..5\n"
        "            !box size=6 color=0.9;0.5;0.2 position=(i-2)*5;-25-i*4;(i%2)*4\n"
        "        for i in ..12\n"
        "            !light position=(uniform(:s;i)[..3]-0.5)*20 color=hsv(i/12;1;1)*20 falloff=1;0;1;0\n"
        "        !light position=30;-60;40 color=3000 falloff=1;0;1;0\n";
    struct {
        const char *head, *body;
        int occlusion;
    } scenes[] = {
        {"!window size=64;64\n    !canvas3d samples=1 viewpoint=150;60;120 focus=0;0;50 fov=0.2 far=1000\n", glass,
         FL_OCCLUSION_AUTO},
        {"!window size=64;64\n    !canvas3d samples=4 viewpoint=120;-90;100 focus=0;0;50 fov=0.2 far=1000"
         " fog_color=0 fog_min=100 fog_max=400\n",
         glass, FL_OCCLUSION_AUTO},
        {"!window size=64;64\n    !canvas3d samples=1 viewpoint=30;-80;50 focus=30;0;0 fov=0.25 far=500\n", spots,
         FL_OCCLUSION_AUTO},
        {"!window size=64;64\n    !canvas3d samples=1 viewpoint=20;-70;40 focus=0 fov=0.15 far=500\n", translucent,
         FL_OCCLUSION_AUTO},
        {"!window size=64;64\n    !canvas3d samples=4 viewpoint=10;-90;30 focus=0 fov=0.2 far=500\n", stacked,
         FL_OCCLUSION_ALWAYS},
    };
    char script[2048];
    for (size_t s = 0; s < sizeof scenes / sizeof scenes[0]; s++) {
        snprintf(script, sizeof script, "%s%s", scenes[s].head, scenes[s].body);
        for (int k = 0; k < 2; k++) {
            routes.no_light_culling = k == 1;
            routes.occlusion = scenes[s].occlusion;
            fl_runtime *rt = draw(script, pix[k]);
            if (strstr(logged, "compile") || strstr(logged, "link")) fail_msg("scene %zu: %s", s, logged);
            fl_free(rt);
        }
        routes = (fl_debug_options){0};
        char what[32];
        snprintf(what, sizeof what, "scene %zu", s);
        assert_same_picture(pix[0], pix[1], what, "culling");
    }
}

/* A group's meshes are drawn in the order of their first appearance in
 * it (Flitter iterates its group's models so), each mesh's instances
 * nearest first. In a group of composite "add", where the order shows: a
 * far box drawn before the nearer cylinder in front of it adds its light
 * under the cylinder's; drawn after, it fails the depth test there. */
static void mesh_order_first_appearance(void **st)
{
    (void)st;
    static uint32_t pix[W * H];
    static const char *far_box = "            !box size=30 position=0;0;-20 color=0;0;1\n";
    static const char *near_cylinder = "            !cylinder size=8;8;4 position=0;0;10 color=1;0;0\n";
    char script[1024];
    for (int order = 0; order < 2; order++) {
        snprintf(script, sizeof script,
                 "!window size=64;64\n"
                 "    !canvas3d samples=4 viewpoint=0;0;80 focus=0 fov=0.12 near=1 far=500\n"
                 "        !group composite=:add\n"
                 "            !light color=1\n"
                 "%s%s",
                 order ? near_cylinder : far_box, order ? far_box : near_cylinder);
        fl_runtime *rt = draw(script, pix);
        uint32_t centre = at(pix, 32, 32), side = at(pix, 32, 20);
        assert_true(chan(centre, 16) > 200);          /* the cylinder's red */
        assert_true(chan(side, 0) > 200);             /* the box's blue beside it */
        assert_int_equal(chan(side, 16), 0);
        if (order == 0)
            assert_true(chan(centre, 0) > 200);       /* the box first: its blue under the red */
        else
            assert_int_equal(chan(centre, 0), 0);     /* the cylinder first: the box hidden */
        fl_free(rt);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(ambient_box),
        cmocka_unit_test(directional_lambert),
        cmocka_unit_test(orthographic_edges),
        cmocka_unit_test(fog_mix),
        cmocka_unit_test(camera_kinds_per_frame),
        cmocka_unit_test(depth_and_transparency),
        cmocka_unit_test(msaa_edge),
        cmocka_unit_test(impostor_spheres),
        cmocka_unit_test(impostor_billboards),
        cmocka_unit_test(impostor_octagon_samples),
        cmocka_unit_test(line_light),
        cmocka_unit_test(translucency_backlit),
        cmocka_unit_test(translucency_thin_edges),
        cmocka_unit_test(translucency_zero_unchanged),
        cmocka_unit_test(listed_lights_as_looped),
        cmocka_unit_test(listed_programs_capped),
        cmocka_unit_test(occlusion_as_without),
        cmocka_unit_test(proxies_as_without),
        cmocka_unit_test(lights_culled_as_without),
        cmocka_unit_test(mesh_order_first_appearance),
        cmocka_unit_test(light_kinds_per_group),
        cmocka_unit_test(two_runtimes),
        cmocka_unit_test(unsupported_warned_once),
        cmocka_unit_test(textures_missing_named_once),
        cmocka_unit_test(textures_drawn),
        cmocka_unit_test(uv_remap_plane),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
