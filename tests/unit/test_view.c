/* test_view.c: physics systems read from tree + state (systems.h), their
 * --view picture (view.h) and --trace rows (trace.h). A small 2D system
 * with no moving forces keeps its particles where they start, so pixel
 * places and trace values can be worked out by hand; a 3D one drawn flat
 * by --view-axes x;z, or for want of OpenGL. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cairo.h>
#include <gif_lib.h>

#include "runtime.h"
#include "systems.h"
#include "trace.h"
#include "view.h"

static char scratch[64];

static const char *const SCRIPT =
    "!physics state=:s dimensions=2\n"
    "    !anchor id=:a position=0;0\n"
    "    !particle id=1 position=100;0 radius=10 charge=1\n"
    "    !particle id=2 position=-100;0 radius=10 charge=-1\n"
    "    !particle id=3 position=0;50 radius=10\n"
    "    !distance from=1 to=:a strength=0\n"
    "    !barrier position=0;-30 normal=0;1\n";

static int setup(void **st)
{
    (void)st;
    snprintf(scratch, sizeof scratch, "/tmp/test_view.XXXXXX");
    return mkdtemp(scratch) ? 0 : -1;
}

static int teardown(void **st)
{
    (void)st;
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", scratch);
    cairo_debug_reset_static_data();
    return system(cmd) == 0 ? 0 : -1;
}

static fl_runtime *run(const char *src, int frames)
{
    fl_options o = fl_default_options();
    fl_runtime *rt = fl_new(&o);
    Buf err = BUF_INIT;
    assert_int_equal(rt_load_text(rt, "test.fl", src, strlen(src), &err), 0);
    buf_free(&err);
    for (int i = 0; i < frames; i++) fl_step(rt);
    return rt;
}

static void test_collect(void **st)
{
    (void)st;
    fl_runtime *rt = run(SCRIPT, 2);
    PsSystem *sys;
    size_t n;
    ps_collect(rt_root(rt), rt_state(rt), &sys, &n);
    assert_int_equal(n, 1);
    assert_int_equal(sys[0].dims, 2);
    assert_int_equal(sys[0].nbodies, 4);
    assert_true(sys[0].bodies[0].anchor);
    assert_false(sys[0].bodies[1].anchor);
    assert_true(ps_coord(sys[0].bodies[1].pos, 0) == 100.0);
    assert_true(sys[0].bodies[1].radius == 10.0);
    assert_true(sys[0].bodies[2].charge == -1.0);
    assert_non_null(sys[0].bodies[1].vel);   /* stored by the engine after frame 0 */
    assert_int_equal(sys[0].nlinks, 1);
    assert_true(ps_coord(sys[0].links[0].from, 0) == 100.0);
    assert_true(ps_coord(sys[0].links[0].to, 0) == 0.0);
    assert_int_equal(sys[0].nbarriers, 1);
    /* a one-number vector stands for every coordinate */
    Vec *one = vec_num1(7);
    assert_true(ps_coord(one, 0) == 7.0 && ps_coord(one, 3) == 7.0);
    vec_release(one);
    assert_true(ps_coord(NULL, 1) == 0.0);
    ps_free(sys, n);
    fl_free(rt);
}

static uint32_t px(cairo_surface_t *s, int x, int y)
{
    uint32_t v;
    memcpy(&v, cairo_image_surface_get_data(s) + (size_t)y * (size_t)cairo_image_surface_get_stride(s) + 4 * (size_t)x, 4);
    return v & 0xffffffu;
}

static void assert_rgb(uint32_t got, int r, int g, int b)
{
    int gr = (int)(got >> 16 & 0xff), gg = (int)(got >> 8 & 0xff), gb = (int)(got & 0xff);
    if (abs(gr - r) > 1 || abs(gg - g) > 1 || abs(gb - b) > 1)
        fail_msg("pixel %d,%d,%d, want %d,%d,%d", gr, gg, gb, r, g, b);
}

/* Bounds x -110..110, y -10..60: scale 432/220 = 1.963636..., centre
 * (0, 25) at panel pixel (240, 28 + 240). */
static void test_view_png(void **st)
{
    (void)st;
    fl_runtime *rt = run(SCRIPT, 2);
    PsSystem *sys;
    size_t n;
    ps_collect(rt_root(rt), rt_state(rt), &sys, &n);
    char path[128];
    Buf err = BUF_INIT;
    snprintf(path, sizeof path, "%s/v.png", scratch);
    View *v = view_open(path, 10, rt_symbols(rt), &err);
    assert_non_null(v);
    assert_false(view_animated(v));
    assert_int_equal(view_frame(v, 1, sys, n, &err), 0);
    assert_int_equal(view_close(v), 0);
    cairo_surface_t *s = cairo_image_surface_create_from_png(path);
    assert_int_equal(cairo_surface_status(s), CAIRO_STATUS_SUCCESS);
    assert_int_equal(cairo_image_surface_get_width(s), 480);
    assert_int_equal(cairo_image_surface_get_height(s), 508);
    double k = 432.0 / 220.0;
    int y0 = (int)(268 + (0 - 25) * k);   /* world y = 0 */
    assert_rgb(px(s, (int)(240 + 100 * k), y0), 217, 38, 26);    /* charge +1: red */
    assert_rgb(px(s, (int)(240 - 100 * k), y0), 26, 77, 217);    /* charge -1: blue */
    assert_rgb(px(s, 240, (int)(268 + 25 * k)), 140, 140, 140);  /* charge 0: grey */
    assert_rgb(px(s, 240, y0), 0, 0, 0);                         /* anchor cross */
    assert_rgb(px(s, 240, 470), 255, 255, 255);                  /* background */
    assert_rgb(px(s, 330, y0 - 12), 255, 255, 255);
    /* the distance link: a light line along y=0 between anchor and particle 1 */
    uint32_t a = px(s, 330, y0), b = px(s, 330, y0 + 1);
    assert_true((a & 0xff) < 250 || (b & 0xff) < 250);
    /* the barrier: a dark 3-pixel line along world y = -30 */
    assert_true((px(s, 100, (int)(268 + (-30 - 25) * k)) & 0xff) < 80);
    cairo_surface_destroy(s);
    ps_free(sys, n);
    fl_free(rt);
}

static void test_view_gif(void **st)
{
    (void)st;
    fl_runtime *rt = run(SCRIPT, 0);
    char path[128];
    Buf err = BUF_INIT;
    snprintf(path, sizeof path, "%s/v.gif", scratch);
    View *v = view_open(path, 5, rt_symbols(rt), &err);
    assert_non_null(v);
    assert_true(view_animated(v));
    for (int f = 0; f < 3; f++) {
        fl_step(rt);
        PsSystem *sys;
        size_t n;
        ps_collect(rt_root(rt), rt_state(rt), &sys, &n);
        assert_int_equal(view_frame(v, f, sys, n, &err), 0);
        ps_free(sys, n);
    }
    assert_int_equal(view_close(v), 0);
    int code = 0;
    GifFileType *g = DGifOpenFileName(path, &code);
    assert_non_null(g);
    assert_int_equal(DGifSlurp(g), GIF_OK);
    assert_int_equal(g->ImageCount, 3);
    assert_int_equal(g->SWidth, 480);
    DGifCloseFile(g, &code);
    /* SVG: one picture, written as an SVG document */
    char svg[128];
    snprintf(svg, sizeof svg, "%s/v.svg", scratch);
    v = view_open(svg, 5, rt_symbols(rt), &err);
    assert_non_null(v);
    PsSystem *sys;
    size_t n;
    ps_collect(rt_root(rt), rt_state(rt), &sys, &n);
    assert_int_equal(view_frame(v, 2, sys, n, &err), 0);
    ps_free(sys, n);
    assert_int_equal(view_close(v), 0);
    FILE *f = fopen(svg, "r");
    assert_non_null(f);
    char head[256] = {0};
    assert_true(fread(head, 1, sizeof head - 1, f) > 0);
    fclose(f);
    assert_non_null(strstr(head, "<svg"));
    assert_non_null(strstr(head, "width=\"480"));   /* 480pt: cairo writes points */
    assert_null(view_open("x.jpg", 5, NULL, &err));
    assert_non_null(strstr(buf_cstr(&err), ".png, .svg or .gif"));
    buf_free(&err);
    fl_free(rt);
}

/* --view-axes x;z (view_set_style): a 3D system drawn flat on x and z,
 * z down the panel as y is in the x/y view. Particle 3 is displaced along
 * z (50) and a little along y (7, which x;z leaves out): the bounds are
 * x -110..110, z -10..60, so the pixels are test_view_png's with z for y. */
static const char *const SCRIPT3 =
    "!physics state=:s dimensions=3\n"
    "    !particle id=1 position=100;0;0 radius=10 charge=1\n"
    "    !particle id=2 position=-100;0;0 radius=10 charge=-1\n"
    "    !particle id=3 position=0;7;50 radius=10\n"
    "    !barrier position=0;0;-30 normal=0;0;1\n";

static cairo_surface_t *view_png(fl_runtime *rt, const int axes[2], const char *name, const RenderLog *log)
{
    PsSystem *sys;
    size_t n;
    ps_collect(rt_root(rt), rt_state(rt), &sys, &n);
    char path[128];
    Buf err = BUF_INIT;
    snprintf(path, sizeof path, "%s/%s", scratch, name);
    View *v = view_open(path, 10, rt_symbols(rt), &err);
    assert_non_null(v);
    view_set_style(v, axes, log);
    assert_int_equal(view_frame(v, 1, sys, n, &err), 0);
    assert_int_equal(view_frame(v, 2, sys, n, &err), 0);
    assert_int_equal(view_close(v), 0);
    ps_free(sys, n);
    cairo_surface_t *s = cairo_image_surface_create_from_png(path);
    assert_int_equal(cairo_surface_status(s), CAIRO_STATUS_SUCCESS);
    return s;
}

static void test_view_axes(void **st)
{
    (void)st;
    fl_runtime *rt = run(SCRIPT3, 2);
    int xz[2] = {0, 2};
    cairo_surface_t *s = view_png(rt, xz, "xz.png", NULL);
    double k = 432.0 / 220.0;
    int z0 = (int)(268 + (0 - 25) * k);   /* world z = 0 */
    assert_rgb(px(s, (int)(240 + 100 * k), z0), 217, 38, 26);
    assert_rgb(px(s, (int)(240 - 100 * k), z0), 26, 77, 217);
    assert_rgb(px(s, 240, (int)(268 + 25 * k)), 140, 140, 140);   /* z = 50: below the middle */
    assert_rgb(px(s, 240, (int)(268 - 18 * k)), 255, 255, 255);  /* where x;y would put it: nothing */
    /* the barrier's plane z = -30 is a line across */
    assert_true((px(s, 100, (int)(268 + (-30 - 25) * k)) & 0xff) < 80);
    cairo_surface_destroy(s);
    /* a 2D system has no z: x;z leaves it on x;y, the same picture */
    fl_free(rt);
    rt = run(SCRIPT, 2);
    cairo_surface_t *a = view_png(rt, xz, "a.png", NULL), *b = view_png(rt, NULL, "b.png", NULL);
    assert_memory_equal(cairo_image_surface_get_data(a), cairo_image_surface_get_data(b),
                        (size_t)cairo_image_surface_get_stride(a) * (size_t)cairo_image_surface_get_height(a));
    cairo_surface_destroy(a);
    cairo_surface_destroy(b);
    fl_free(rt);
    /* axes out of 0..3 (an embedder's fl_options) are none: a 6D system on x;y */
    rt = run("!physics state=:s dimensions=6\n"
             "    !particle id=1 position=1;2;3;4;5;6 radius=1\n"
             "    !particle id=2 position=-9;8;7;6;5;40 radius=1\n", 2);
    int far[2] = {0, 5}, xy[2] = {0, 1};
    a = view_png(rt, far, "far.png", NULL);
    b = view_png(rt, xy, "xy6.png", NULL);
    assert_memory_equal(cairo_image_surface_get_data(a), cairo_image_surface_get_data(b),
                        (size_t)cairo_image_surface_get_stride(a) * (size_t)cairo_image_surface_get_height(a));
    cairo_surface_destroy(a);
    cairo_surface_destroy(b);
    fl_free(rt);
}

static void test_view_parse_axes(void **st)
{
    (void)st;
    int ax[2] = {7, 7};
    assert_true(view_parse_axes("x;z", ax) && ax[0] == 0 && ax[1] == 2);
    assert_true(view_parse_axes("w;y", ax) && ax[0] == 3 && ax[1] == 1);
    const char *bad[] = {"x;x", "x", "x;", ";z", "xz", "x;z;y", "X;Z", "x,z", "a;b", "", "x;\0"};
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        ax[0] = ax[1] = 7;
        assert_false(view_parse_axes(bad[i], ax));
        assert_true(ax[0] == 7 && ax[1] == 7);
    }
    assert_false(view_parse_axes(NULL, ax));
    assert_true(fl_parse_view_axes("z;x", ax) && ax[0] == 2 && ax[1] == 0);
    assert_false(fl_parse_view_axes("z;x", NULL));
}

static int nsaid;
static char said[512];

static void keep(void *ctx, int kind, const char *line)
{
    (void)ctx;
    assert_int_equal(kind, RLOG_WARNING);
    nsaid++;
    snprintf(said, sizeof said, "%s", line);
}

/* Without OpenGL (main() hides EGL's vendors, so no context can be made):
 * a 3D system is drawn flat on x;y, said once per view, and the picture is
 * the one --view-axes x;y asks for. */
static void test_view_3d_without_gl(void **st)
{
    (void)st;
    fl_runtime *rt = run(SCRIPT3, 2);
    RenderLog log = {keep, NULL, false};
    nsaid = 0;
    cairo_surface_t *a = view_png(rt, NULL, "nogl.png", &log);   /* two frames, one message */
    assert_int_equal(nsaid, 1);
    assert_non_null(strstr(said, "view: 3D systems are drawn flat on x;y: canvas3d: no OpenGL"));
    int xy[2] = {0, 1};
    cairo_surface_t *b = view_png(rt, xy, "xy.png", &log);
    assert_int_equal(nsaid, 1);   /* asked for: nothing to say */
    assert_memory_equal(cairo_image_surface_get_data(a), cairo_image_surface_get_data(b),
                        (size_t)cairo_image_surface_get_stride(a) * (size_t)cairo_image_surface_get_height(a));
    cairo_surface_destroy(a);
    cairo_surface_destroy(b);
    fl_free(rt);
}

static char *slurp(const char *path)
{
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    static char text[4096];
    size_t len = fread(text, 1, sizeof text - 1, f);
    text[len] = '\0';
    fclose(f);
    return text;
}

static void test_trace(void **st)
{
    (void)st;
    fl_runtime *rt = run(SCRIPT, 0);
    char csv[128], jsonl[128];
    Buf err = BUF_INIT;
    snprintf(csv, sizeof csv, "%s/t.csv", scratch);
    snprintf(jsonl, sizeof jsonl, "%s/t.jsonl", scratch);
    Trace *tc = trace_open(csv, rt_symbols(rt), &err);
    Trace *tj = trace_open(jsonl, rt_symbols(rt), &err);
    assert_non_null(tc);
    assert_non_null(tj);
    for (int f = 0; f < 2; f++) {
        fl_step(rt);
        PsSystem *sys;
        size_t n;
        ps_collect(rt_root(rt), rt_state(rt), &sys, &n);
        assert_int_equal(trace_frame(tc, f, fl_frame_time(rt), sys, n), 0);
        if (f == 1) assert_int_equal(trace_frame(tj, f, fl_frame_time(rt), sys, n), 0);
        ps_free(sys, n);
    }
    assert_int_equal(trace_close(tc), 0);
    assert_int_equal(trace_close(tj), 0);
    /* at 60 fps frame 1 is at time 1/60; nothing moves (no forces) */
    assert_string_equal(slurp(csv),
        "frame,time,system,id,kind,x,y,vx,vy\n"
        "0,0,s,a,anchor,0,0,0,0\n"
        "0,0,s,1,particle,100,0,0,0\n"
        "0,0,s,2,particle,-100,0,0,0\n"
        "0,0,s,3,particle,0,50,0,0\n"
        "1,0.016666666666666666,s,a,anchor,0,0,0,0\n"
        "1,0.016666666666666666,s,1,particle,100,0,0,0\n"
        "1,0.016666666666666666,s,2,particle,-100,0,0,0\n"
        "1,0.016666666666666666,s,3,particle,0,50,0,0\n");
    const char *j = slurp(jsonl);
    assert_non_null(strstr(j, "{\"frame\":1,\"time\":0.016666666666666666,\"system\":\"s\",\"id\":\"a\","
                              "\"kind\":\"anchor\",\"position\":[0,0],\"velocity\":[0,0]}\n"));
    assert_non_null(strstr(j, "{\"frame\":1,\"time\":0.016666666666666666,\"system\":\"s\",\"id\":2,"
                              "\"kind\":\"particle\",\"position\":[-100,0],\"velocity\":[0,0]}\n"));
    fl_free(rt);
}

int main(void)
{
    /* no OpenGL here: glvnd finds no EGL vendor, so a 3D system's view is
     * drawn flat (Mesa's JIT is no business of the unit tests, which also
     * run under valgrind; tests/gl draws the 3D view) */
    setenv("__EGL_VENDOR_LIBRARY_FILENAMES", "/nonexistent", 1);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_collect),
        cmocka_unit_test(test_view_png),
        cmocka_unit_test(test_view_gif),
        cmocka_unit_test(test_view_axes),
        cmocka_unit_test(test_view_parse_axes),
        cmocka_unit_test(test_view_3d_without_gl),
        cmocka_unit_test(test_trace),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
