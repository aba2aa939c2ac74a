/* test_view3d.c: the physics view of a 3D system drawn in perspective
 * through the !canvas3d renderer (issue 25 item 4; lib/render/view.h),
 * through the public API only (fl_draw_view, fl_view, fl_outputs_*).
 *
 * The camera is the documented one: it looks at the middle c of the
 * bodies' box (positions +- radius) from the direction e = 1;-2;1
 * (normalised), z up, at the distance where the box's bounding sphere
 * (radius R, the box's half-diagonal) just fills the horizontal field of
 * view of 1/8 turn: R / sin(atan(g)), g = tan(pi/8). One panel drawn at
 * 480x508 is the picture itself: the 3D part is the 478x478 pixels from
 * (1, 29). Points are projected here by hand with that camera; the
 * light is an ambient 0.3 and a directional 0.9 from the camera's upper
 * left; colours are the flat view's (grey 0.55, red 0.85;0.15;0.1 for the
 * largest positive charge, blue 0.1;0.3;0.85 for the most negative) taken
 * as sRGB and lit in linear light. */
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

enum { VW = 480, VH = 508, AREA = 478, AX = 1, AY = 29 };

static char logged[4096];

static void keep_log(void *ctx, int kind, const char *line)
{
    (void)ctx;
    (void)kind;
    size_t n = strlen(logged);
    snprintf(logged + n, sizeof logged - n, "%s\n", line);
}

static fl_runtime *load(const char *src, const int axes[2])
{
    fl_options o = fl_default_options();
    o.log = keep_log;
    if (axes) o.view_axes[0] = axes[0], o.view_axes[1] = axes[1];
    logged[0] = '\0';
    fl_runtime *rt = fl_new(&o);
    assert_int_equal(fl_load_text(rt, "view3d.fl", src, strlen(src)), 0);
    assert_int_equal(fl_step(rt), 0);
    return rt;
}

static uint32_t *draw(fl_runtime *rt)
{
    uint32_t *pix = malloc((size_t)VW * VH * 4);
    assert_non_null(pix);
    size_t n = 0;
    assert_int_equal(fl_draw_view(rt, pix, VW, VH, VW * 4, &n), 0);
    assert_int_equal(n, 1);
    assert_null(strstr(logged, "drawn flat"));
    return pix;
}

static int chan(uint32_t p, int shift) { return (int)((p >> shift) & 0xff); }

/* The documented camera for the box [lo, hi]. */
typedef struct Cam {
    double pos[3], fwd[3], right[3], up[3], g;
} Cam;

static Cam camera(const double lo[3], const double hi[3])
{
    Cam k;
    double c[3], R = 0, e[3] = {1, -2, 1};
    double el = sqrt(6);
    k.g = tan(M_PI / 8);
    for (int i = 0; i < 3; i++) {
        c[i] = (lo[i] + hi[i]) / 2;
        R += (hi[i] - lo[i]) * (hi[i] - lo[i]) / 4;
        e[i] /= el;
    }
    R = sqrt(R);
    double dist = R * sqrt(1 + k.g * k.g) / k.g;
    for (int i = 0; i < 3; i++) k.pos[i] = c[i] + e[i] * dist, k.fwd[i] = -e[i];
    double rl = hypot(e[0], e[1]);
    k.right[0] = -e[1] / rl, k.right[1] = e[0] / rl, k.right[2] = 0;
    k.up[0] = k.right[1] * k.fwd[2] - k.right[2] * k.fwd[1];
    k.up[1] = k.right[2] * k.fwd[0] - k.right[0] * k.fwd[2];
    k.up[2] = k.right[0] * k.fwd[1] - k.right[1] * k.fwd[0];
    return k;
}

static double dot(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* Picture coordinates (continuous; pixel i covers i..i+1) of world point [x]. */
static void project(const Cam *k, const double x[3], double *px, double *py)
{
    double v[3] = {x[0] - k->pos[0], x[1] - k->pos[1], x[2] - k->pos[2]};
    double z = dot(v, k->fwd);
    double sx = dot(v, k->right) / z / k->g, sy = dot(v, k->up) / z / k->g;
    *px = AX + (sx + 1) / 2 * AREA;
    *py = AY + (1 - sy) / 2 * AREA;
}

/* The area in pixels of the picture of a sphere of radius [r] at [x]:
 * on the plane one unit in front of the eye it is an ellipse of area
 * pi r^2 sqrt(|c|^2 - r^2) / (cz^2 - r^2)^(3/2), c the centre from the
 * eye, cz its depth; a pixel there is 2g/478 wide. */
static double pixel_area(const Cam *k, const double x[3], double r)
{
    double c[3] = {x[0] - k->pos[0], x[1] - k->pos[1], x[2] - k->pos[2]};
    double cz = dot(c, k->fwd), px = 2 * k->g / AREA;
    return M_PI * r * r * sqrt(dot(c, c) - r * r) / pow(cz * cz - r * r, 1.5) / (px * px);
}

static double srgb_decode(double s) { return s <= 0.04045 ? s / 12.92 : pow((s + 0.055) / 1.055, 2.4); }

static int srgb(double x)
{
    x = x < 0 ? 0 : x > 1 ? 1 : x;
    double s = x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1 / 2.4) - 0.055;
    return (int)lround(s * 255);
}

/* Red and blue pixels: count and centroid. */
static void census(const uint32_t *pix, bool red, int *count, double *cx, double *cy)
{
    *count = 0;
    double sx = 0, sy = 0;
    for (int y = AY; y < AY + AREA; y++)
        for (int x = AX; x < AX + AREA; x++) {
            uint32_t p = pix[y * VW + x];
            int r = chan(p, 16), g = chan(p, 8), b = chan(p, 0);
            bool hit = red ? r > g + 40 && r > b + 40 : b > r + 40 && b > g + 40;
            if (hit) ++*count, sx += x + 0.5, sy += y + 0.5;
        }
    *cx = *count ? sx / *count : -1;
    *cy = *count ? sy / *count : -1;
}

/* Two particles of the same radius, one nearer the camera by 2*30 along
 * the view axis, 60 apart across it: the nearer one (red, charge +1) is
 * drawn larger, each with the area its perspective picture has (within
 * 8%: the anti-aliased edge pixels count whole; 2% and 3.5% here) and
 * where the camera puts its centre (within 2 pixels; 0.6 here: a sphere off the axis is drawn a little outwards). */
static void nearer_is_larger(void **st)
{
    (void)st;
    double e[3] = {1 / sqrt(6), -2 / sqrt(6), 1 / sqrt(6)}, r[3] = {2 / sqrt(5), 1 / sqrt(5), 0};
    double a[3], b[3], lo[3], hi[3], rad = 6;
    for (int i = 0; i < 3; i++) {
        a[i] = 30 * e[i] + 30 * r[i];
        b[i] = -a[i];
        lo[i] = fmin(a[i], b[i]) - rad;
        hi[i] = fmax(a[i], b[i]) + rad;
    }
    char src[512];
    snprintf(src, sizeof src,
             "!physics state=:s dimensions=3\n"
             "    !particle id=1 position=%.17g;%.17g;%.17g radius=6 charge=1\n"
             "    !particle id=2 position=%.17g;%.17g;%.17g radius=6 charge=-1\n",
             a[0], a[1], a[2], b[0], b[1], b[2]);
    fl_runtime *rt = load(src, NULL);
    uint32_t *pix = draw(rt);
    Cam k = camera(lo, hi);
    int nr, nb;
    double rx, ry, bx, by, ex, ey;
    census(pix, true, &nr, &rx, &ry);
    census(pix, false, &nb, &bx, &by);
    double wa = pixel_area(&k, a, rad), wb = pixel_area(&k, b, rad);
    if (fabs(nr / wa - 1) > 0.08 || fabs(nb / wb - 1) > 0.08)
        fail_msg("red %d, blue %d pixels, want about %.0f and %.0f", nr, nb, wa, wb);
    assert_true(nr > 1.5 * nb);
    /* the near one is on the right (+right), the far one on the left */
    project(&k, a, &ex, &ey);
    if (fabs(rx - ex) > 2 || fabs(ry - ey) > 2) fail_msg("red at %.1f,%.1f, want %.1f,%.1f", rx, ry, ex, ey);
    project(&k, b, &ex, &ey);
    if (fabs(bx - ex) > 2 || fabs(by - ey) > 2) fail_msg("blue at %.1f,%.1f, want %.1f,%.1f", bx, by, ex, ey);
    assert_true(rx > bx + 100);
    /* the title is the flat view's, and the background white */
    assert_int_equal(pix[(AY + 5) * VW + AX + 5], 0xffffffffu);
    free(pix);
    fl_free(rt);
}

/* One grey particle (radius 10 at the origin): the side towards the light
 * (the camera's upper left) is brighter than the other, which has the
 * ambient light only: (1 - F0) * albedo * 0.3 with F0 = 0.04 and albedo
 * the linear light of 0.55. The unlit pixel is found by casting the ray
 * through its centre onto the sphere here. */
static void lit_side_brighter(void **st)
{
    (void)st;
    fl_runtime *rt = load("!physics state=:s dimensions=3\n"
                          "    !particle id=1 position=0;0;0 radius=10\n", NULL);
    uint32_t *pix = draw(rt);
    double lo[3] = {-10, -10, -10}, hi[3] = {10, 10, 10}, o[3] = {0, 0, 0}, cx, cy;
    Cam k = camera(lo, hi);
    project(&k, o, &cx, &cy);
    assert_true(fabs(cx - 240) < 0.01 && fabs(cy - 268) < 0.01);
    uint32_t lit = pix[(268 - 60) * VW + 240 - 60], dark = pix[(268 + 70) * VW + 240 + 70];
    assert_true(chan(lit, 8) > chan(dark, 8) + 60);
    /* the dark pixel's surface point faces away from the light */
    double px = 240 + 70 + 0.5, py = 268 + 70 + 0.5;
    double sx = ((px - AX) / AREA * 2 - 1) * k.g, sy = (1 - (py - AY) / AREA * 2) * k.g;
    double d[3], oc[3];
    for (int i = 0; i < 3; i++) d[i] = k.fwd[i] + sx * k.right[i] + sy * k.up[i], oc[i] = k.pos[i];
    double qa = dot(d, d), qb = dot(oc, d), qc = dot(oc, oc) - 100;
    double t = (-qb - sqrt(qb * qb - qa * qc)) / qa;
    double n[3], L[3];
    for (int i = 0; i < 3; i++) n[i] = (oc[i] + t * d[i]) / 10, L[i] = -k.right[i] + k.up[i] - k.fwd[i];
    assert_true(qb * qb - qa * qc > 0);   /* the ray meets the sphere */
    assert_true(dot(n, L) < 0);
    int want = srgb(0.96 * srgb_decode(0.55) * 0.3);
    for (int sh = 0; sh <= 16; sh += 8)
        if (abs(chan(dark, sh) - want) > 2) fail_msg("unlit channel %d = %d, want %d", sh, chan(dark, sh), want);
    assert_int_equal(dark >> 24, 0xff);
    free(pix);
    fl_free(rt);
}

/* An anchor is a dark cross at its place; a !distance link a grey rod. */
static void anchor_cross(void **st)
{
    (void)st;
    fl_runtime *rt = load("!physics state=:s dimensions=3\n"
                          "    !anchor id=:a position=0;0;0\n"
                          "    !particle id=1 position=20;0;0 radius=2\n"
                          "    !particle id=2 position=-20;0;0 radius=2\n", NULL);
    uint32_t *pix = draw(rt);
    double lo[3] = {-22, -2, -2}, hi[3] = {22, 2, 2}, o[3] = {0, 0, 0}, x, y;
    Cam k = camera(lo, hi);
    project(&k, o, &x, &y);
    uint32_t p = pix[(int)y * VW + (int)x];
    assert_true(chan(p, 8) < 60);
    free(pix);
    fl_free(rt);
}

/* Bad input draws what it can and never crashes: NaN and infinite
 * positions are left out, a system of one point still shows it (a sphere
 * of 2 pixels at the middle), a huge radius fills the view. */
static void bad_input(void **st)
{
    (void)st;
    const char *srcs[] = {
        "!physics state=:s dimensions=3\n    !particle id=1 position=5;5;5\n",
        "!physics state=:s dimensions=3\n    !particle id=1 position=0/0;0;0 radius=3\n"
        "    !particle id=2 position=1/0;0;0\n    !particle id=3 position=1;2;3 radius=1\n",
        "!physics state=:s dimensions=3\n    !particle id=1 position=0;0;0 radius=1e300\n"
        "    !particle id=2 position=1e300;0;-1e300 radius=1e308\n    !anchor id=:a position=0/0\n",
        "!physics state=:s dimensions=3\n    !particle id=1 position=1e-300;0;0 radius=1e-300\n",
        "!physics state=:s dimensions=3\n    !barrier position=0 normal=0\n",
    };
    for (size_t i = 0; i < sizeof srcs / sizeof *srcs; i++) {
        fl_runtime *rt = load(srcs[i], NULL);
        uint32_t *pix = draw(rt);
        if (i == 0 || i == 3) assert_true(chan(pix[268 * VW + 240], 8) < 200);   /* the dot at the middle */
        free(pix);
        fl_free(rt);
    }
}

/* With --view-axes x;z (fl_options.view_axes) the 3D system is flat: the
 * particle is a disc of the flat view's grey (140), not a lit sphere, and
 * the title says the axes (the flat projection itself: test_view.c). */
static void axes_make_it_flat(void **st)
{
    (void)st;
    int axes[2] = {0, 2};
    fl_runtime *rt = load("!physics state=:s dimensions=3\n"
                          "    !particle id=1 position=0;0;0 radius=10\n", axes);
    uint32_t *pix = draw(rt);
    uint32_t p = pix[268 * VW + 240];
    for (int sh = 0; sh <= 16; sh += 8) assert_int_equal(chan(p, sh), 140);
    free(pix);
    fl_free(rt);
}

/* Two runtimes, each with its own view renderer, alternate; fl_view and a
 * GIF through fl_outputs write 3D pictures too. */
static void two_runtimes_and_files(void **st)
{
    (void)st;
    fl_runtime *a = load("!physics state=:s dimensions=3\n"
                         "    !particle id=1 position=0;0;0 radius=10 charge=1\n"
                         "    !particle id=2 position=0;0;40 radius=1\n", NULL);
    fl_runtime *b = load("!physics state=:s dimensions=3\n"
                         "    !particle id=1 position=0;0;0 radius=10 charge=-1\n"
                         "    !particle id=2 position=0;0;40 radius=1\n", NULL);
    for (int round = 0; round < 2; round++) {
        uint32_t *pa = draw(a), *pb = draw(b);
        int n, m;
        double x, y;
        census(pa, true, &n, &x, &y);
        census(pb, false, &m, &x, &y);
        assert_true(n > 1000 && m > 1000);
        census(pa, false, &n, &x, &y);
        assert_int_equal(n, 0);
        free(pa);
        free(pb);
        assert_int_equal(fl_step(a), 0);
    }
    char dir[] = "/tmp/test_view3d.XXXXXX", png[64], gif[64];
    assert_non_null(mkdtemp(dir));
    snprintf(png, sizeof png, "%s/v.png", dir);
    snprintf(gif, sizeof gif, "%s/v.gif", dir);
    assert_int_equal(fl_view(a, png, NULL), 0);
    fl_output_options oo = {.view = gif};
    fl_outputs *out = fl_outputs_open(b, &oo);
    assert_non_null(out);
    for (int f = 0; f < 3; f++) {
        assert_int_equal(fl_step(b), 0);
        assert_int_equal(fl_outputs_frame(out, b), 0);
    }
    assert_int_equal(fl_outputs_close(out, b), 0);
    FILE *f = fopen(gif, "rb");
    assert_non_null(f);
    fseek(f, 0, SEEK_END);
    assert_true(ftell(f) > 1000);
    fclose(f);
    f = fopen(png, "rb");
    assert_non_null(f);
    fclose(f);
    unlink(png);
    unlink(gif);
    rmdir(dir);
    assert_null(strstr(logged, "drawn flat"));
    fl_free(a);
    fl_free(b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(nearer_is_larger),
        cmocka_unit_test(lit_side_brighter),
        cmocka_unit_test(anchor_cross),
        cmocka_unit_test(bad_input),
        cmocka_unit_test(axes_make_it_flat),
        cmocka_unit_test(two_runtimes_and_files),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
