/* test_canvas.c: the 2D canvas drawn through the render graph (lib/render:
 * cairo, uploaded into a texture, composited by the !record's OpenGL pass
 * and written). Each test evaluates a small script whose !record writes a
 * PNG (or GIF) into a scratch directory, reads the file back and checks
 * pixel values at chosen places, worked out by hand from the geometry
 * (fills, strokes, transforms, paths mapped at draw time, gradients,
 * layers, text). Pixels well inside or well outside a shape are exact;
 * anti-aliased values get a tolerance, and so do values that go through
 * the GPU's sRGB encoding (the GL rule allows 0.6 of a step off).
 *
 * A !record with keep_alpha=true writes, as Flitter's does, the sRGB
 * encoding of the premultiplied light as the straight colour beside its
 * alpha: cairo, reading the file back, premultiplies it again, so a
 * half-transparent white comes back as 128 * 128 / 255 = 64. */
#include <math.h>
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

static char scratch[64];

static int setup(void **st)
{
    (void)st;
    snprintf(scratch, sizeof scratch, "/tmp/test_canvas.XXXXXX");
    return mkdtemp(scratch) ? 0 : -1;
}

static int teardown(void **st)
{
    (void)st;
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", scratch);
    cairo_debug_reset_static_data();   /* cairo's font caches, so valgrind sees no leak */
    return system(cmd) == 0 ? 0 : -1;
}

/* Run [frames] frames of [src] with OUT bound to scratch/[name]; returns
 * what the renderer logged (skipped kinds with debug on). */
static char *render_with(const char *src, const char *name, int frames, char *path, size_t pathlen,
                         volatile int *interrupt);

static char *render(const char *src, const char *name, int frames, char *path, size_t pathlen)
{
    return render_with(src, name, frames, path, pathlen, NULL);
}

/* render() with fl_options.interrupt = [interrupt] (NULL: none). */
static char *render_with(const char *src, const char *name, int frames, char *path, size_t pathlen,
                         volatile int *interrupt)
{
    snprintf(path, pathlen, "%s/%s", scratch, name);
    char *log = NULL;
    size_t loglen;
    FILE *lf = open_memstream(&log, &loglen);
    fl_options o = fl_default_options();
    o.fps = 10;   /* a GIF delay of 10 hundredths of a second */
    o.interrupt = interrupt;
    RtStreams streams = {lf, lf};
    rt_log_to_files(&o, &streams);
    fl_runtime *rt = fl_new(&o);
    assert_int_equal(fl_define(rt, "OUT", path), 0);
    Buf err = BUF_INIT;
    int rc = rt_load_text(rt, "test.fl", src, strlen(src), &err);
    if (rc != 0) fprintf(stderr, "%s", buf_cstr(&err));
    assert_int_equal(rc, 0);
    fl_output_options oo = {.debug = true};
    fl_outputs *out = fl_outputs_open(rt, &oo);
    assert_non_null(out);
    for (int i = 0; i < frames; i++) {
        fl_step(rt);
        assert_int_equal(fl_outputs_frame(out, rt), 0);
    }
    assert_true(fl_windows(rt, NULL, 0) > 0);
    assert_int_equal(fl_outputs_close(out, rt), 0);
    buf_free(&err);
    fl_free(rt);
    fclose(lf);
    return log;
}

typedef struct Pic {
    cairo_surface_t *s;
    int w, h, stride;
    const unsigned char *data;
} Pic;

static Pic load_png(const char *path)
{
    Pic p;
    p.s = cairo_image_surface_create_from_png(path);
    assert_int_equal(cairo_surface_status(p.s), CAIRO_STATUS_SUCCESS);
    p.w = cairo_image_surface_get_width(p.s);
    p.h = cairo_image_surface_get_height(p.s);
    p.stride = cairo_image_surface_get_stride(p.s);
    p.data = cairo_image_surface_get_data(p.s);
    return p;
}

/* The (premultiplied) pixel at x,y as 0xAARRGGBB; opaque for RGB24 files. */
static uint32_t px(const Pic *p, int x, int y)
{
    uint32_t v;
    memcpy(&v, p->data + (size_t)y * (size_t)p->stride + 4 * (size_t)x, 4);
    if (cairo_image_surface_get_format(p->s) == CAIRO_FORMAT_RGB24) v |= 0xff000000u;
    return v;
}

static int chan(uint32_t v, int shift) { return (int)((v >> shift) & 0xff); }

static void assert_near(int got, int want, int tol)
{
    if (got < want - tol || got > want + tol) fail_msg("channel %d, want %d +- %d", got, want, tol);
}

static void test_fill_stroke_transform(void **st)
{
    (void)st;
    char path[256];
    char *log = render(
        "!window size=100;100\n"
        "    !record filename=OUT keep_alpha=true\n"
        "        !canvas\n"
        "            !rect point=10;10 size=30;20 fill=true color=1;0;0\n"
        "            !path\n"
        "                !line points=0;80;100;80\n"
        "                !stroke stroke_width=4 color=0;0;1\n"
        "            !group translate=50;50 rotate=0.25 color=0;1;0\n"
        "                !rect size=20;10 fill=true\n"
        "            !ellipse point=80;20 radius=8 fill=true color=1\n",
        "a.png", 1, path, sizeof path);
    free(log);
    Pic p = load_png(path);
    assert_int_equal(p.w, 100);
    assert_int_equal(p.h, 100);
    assert_int_equal(px(&p, 20, 20), 0xffff0000u);   /* inside the red rect */
    assert_int_equal(px(&p, 39, 29), 0xffff0000u);   /* its last pixel, (39..40, 29..30) */
    assert_int_equal(px(&p, 40, 20), 0x00000000u);   /* just right of it: transparent */
    assert_int_equal(px(&p, 5, 5), 0x00000000u);
    /* 4-pixel stroke centred on y=80 covers rows 78..81 exactly */
    assert_int_equal(px(&p, 90, 78), 0xff0000ffu);
    assert_int_equal(px(&p, 90, 81), 0xff0000ffu);
    assert_int_equal(px(&p, 90, 77), 0x00000000u);
    assert_int_equal(px(&p, 90, 82), 0x00000000u);
    /* rotate=0.25 turns clockwise: the 20x10 rect's x axis points down the
     * screen and its y axis left: it covers x 40..50, y 50..70 */
    assert_int_equal(px(&p, 45, 65), 0xff00ff00u);
    assert_int_equal(px(&p, 55, 55), 0x00000000u);
    assert_int_equal(px(&p, 45, 45), 0x00000000u);
    /* white disc of radius 8 at 80;20 */
    assert_int_equal(px(&p, 80, 20), 0xffffffffu);
    assert_int_equal(px(&p, 84, 24), 0xffffffffu);
    assert_int_equal(px(&p, 80, 30), 0x00000000u);
    cairo_surface_destroy(p.s);
}

/* A path is built in local coordinates and mapped by the transform in
 * force where it is filled (Flitter's Skia semantics), so a square added
 * at the origin and filled inside a !transform lands translated. A
 * !gradient child changes the paint for the siblings after it. */
static void test_path_transform_gradient(void **st)
{
    (void)st;
    char path[256];
    char *log = render(
        "!window size=100;100\n"
        "    !record filename=OUT\n"
        "        !canvas\n"
        "            !path\n"
        "                !rect size=10;10\n"
        "                !transform translate=80;0\n"
        "                    !fill color=0;1;0\n"
        "            !group\n"
        "                !gradient start=0;0 end=100;0\n"
        "                    !stop color=0\n"
        "                    !stop color=1\n"
        "                !rect point=0;50 size=100;50 fill=true\n",
        "b.png", 1, path, sizeof path);
    free(log);
    Pic p = load_png(path);
    assert_int_equal(cairo_image_surface_get_format(p.s), CAIRO_FORMAT_RGB24);   /* no keep_alpha */
    assert_int_equal(px(&p, 85, 5), 0xff00ff00u);
    assert_int_equal(px(&p, 5, 5), 0xff000000u);    /* over black */
    assert_int_equal(px(&p, 85, 15), 0xff000000u);
    /* linear ramp 0..1 over x 0..100: pixel centre 49.5 -> 0.495 */
    assert_near(chan(px(&p, 49, 75), 16), 126, 2);
    assert_near(chan(px(&p, 49, 75), 0), 126, 2);
    assert_near(chan(px(&p, 89, 75), 8), 228, 2);
    assert_near(chan(px(&p, 2, 75), 8), 6, 2);
    cairo_surface_destroy(p.s);
}

static void test_layer_arc_text_skip(void **st)
{
    (void)st;
    char path[256];
    char *log = render(
        "!window size=200;100\n"
        "    !record filename=OUT keep_alpha=true\n"
        "        !canvas\n"
        "            !group\n"
        "                !layer size=50;50 alpha=0.5\n"
        "                    !rect size=100;100 fill=true color=1\n"
        "            !path\n"
        "                !arc point=100;50 radius=20 start=0 end=0.5\n"
        "                !close\n"
        "                !fill color=1;1;0\n"
        "            !text text=\"WWW\" point=160;50 font_size=30 color=1\n"
        "            !gizmo\n",
        "c.png", 1, path, sizeof path);
    assert_non_null(strstr(log, "skipping unsupported !gizmo"));
    free(log);
    Pic p = load_png(path);
    /* the layer is clipped to 0..50 and painted at half alpha (its clip
     * outlives it, as in Flitter, hence the !group around it) */
    assert_near(chan(px(&p, 25, 25), 24), 128, 1);
    assert_near(chan(px(&p, 25, 25), 16), 64, 1);   /* half-transparent white, read back (above) */
    assert_int_equal(px(&p, 60, 25), 0x00000000u);
    /* half-turn arc from angle 0 clockwise: the half disc below y=50 */
    assert_int_equal(px(&p, 100, 60), 0xffffff00u);
    assert_int_equal(px(&p, 100, 40), 0x00000000u);
    /* text present around its centred point and nothing far from it */
    int ink = 0;
    for (int y = 30; y < 70; y++)
        for (int x = 120; x < 200; x++) ink += chan(px(&p, x, y), 24) > 128;
    assert_true(ink > 100);
    assert_int_equal(px(&p, 160, 5), 0x00000000u);
    assert_int_equal(px(&p, 160, 95), 0x00000000u);
    cairo_surface_destroy(p.s);
}

/* !line curve=C smooths a corner when it turns by at most C turns, the
 * turn measured as Flitter does (clamped to a quarter turn): a 127-degree
 * turn counts as 0.25 <= 0.3 and is curved, a quadratic through the
 * segment midpoints (30;50) and (70;50) with apex at (50;30). */
static void test_line_curve(void **st)
{
    (void)st;
    char path[256];
    char *log = render(
        "!window size=100;100\n"
        "    !record filename=OUT keep_alpha=true\n"
        "        !canvas\n"
        "            !line points=10;90;50;10;90;90 curve=0.3 stroke=true stroke_width=4 color=1\n",
        "e.png", 1, path, sizeof path);
    free(log);
    Pic p = load_png(path);
    assert_int_equal(px(&p, 50, 30), 0xffffffffu);   /* the curve's apex */
    assert_int_equal(px(&p, 50, 14), 0x00000000u);   /* no sharp corner at (50;10) */
    assert_int_equal(px(&p, 50, 40), 0x00000000u);
    assert_true(chan(px(&p, 20, 70), 24) > 0);       /* the straight start, (10;90)..(30;50) */
    cairo_surface_destroy(p.s);
}

/* A canvas of its own size is stretched over its window (Flitter's window
 * shader samples each child over the whole output): a 50x50 canvas with
 * its top-left quarter filled fills the top-left quarter of 100x100. */
static void test_canvas_stretched(void **st)
{
    (void)st;
    char path[256];
    char *log = render(
        "!window size=100;100\n"
        "    !record filename=OUT keep_alpha=true\n"
        "        !canvas size=50;50\n"
        "            !rect size=25;25 fill=true color=1\n",
        "f.png", 1, path, sizeof path);
    free(log);
    Pic p = load_png(path);
    assert_int_equal(p.w, 100);
    assert_int_equal(px(&p, 10, 10), 0xffffffffu);
    assert_int_equal(px(&p, 47, 47), 0xffffffffu);
    assert_int_equal(px(&p, 53, 53), 0x00000000u);
    assert_int_equal(px(&p, 90, 10), 0x00000000u);
    cairo_surface_destroy(p.s);
}

/* A window-level effect (here !blur, Flitter docs/shaders.md: a
 * horizontal then a vertical normalised Gaussian of sigma 0.3 radius,
 * clamped at the edges) is drawn, nothing is said about it, and a !record
 * inside an effect is found. The red left half blurred across its edge at
 * x = 10: pixel 9 keeps the weights of offsets -5..0, pixel 10 those of
 * -5..-1, of the kernel exp(-i^2 / (2 1.5^2)) (sum 3.7599; 0..5: 2.3799,
 * -5..-1: 1.3799), i.e. light 0.63296 and 0.36702, sRGB 207.2 and 163.7;
 * far from the edge the red is whole. */
static void test_effect_drawn(void **st)
{
    (void)st;
    char path[256];
    char *log = render(
        "!window size=20;20\n"
        "    !shader\n"
        "        !record filename=OUT\n"
        "            !blur radius=5\n"
        "                !canvas\n"
        "                    !rect size=10;20 fill=true color=1;0;0\n",
        "g.png", 2, path, sizeof path);
    assert_null(strstr(log, "blur"));
    free(log);
    Pic p = load_png(path);
    assert_int_equal(px(&p, 2, 10), 0xffff0000u);
    assert_near(chan(px(&p, 9, 10), 16), 207, 1);
    assert_near(chan(px(&p, 10, 10), 16), 164, 1);
    assert_int_equal(px(&p, 17, 10), 0xff000000u);
    cairo_surface_destroy(p.s);
}

/* Headless, every frame of a tree with a !record is drawn, also those
 * whose record writes nothing (filename null until the last frame, as
 * Flitter's examples record), as Flitter draws every frame: a !feedback
 * of mixer=0.5 at 10 frames a second (delta 0.2 beats: the last picture
 * keeps 0.5^0.2 = 0.87055) over a white shader that is white only at
 * frame 1: frame 0 nothing, frame 1 0.12945 white, frame 2 0.87055 of
 * that = 0.11269 (sRGB 95), the picture written. Frames 0 and 1 not
 * drawn would leave frame 2 nothing (its input is black then). */
static void test_headless_every_frame(void **st)
{
    (void)st;
    char path[256];
    char *log = render(
        "let solid = '''${HEADER}\n"
        "out vec4 color;\n"
        "uniform vec4 rgba;\n"
        "void main() {\n"
        "    color = rgba;\n"
        "}\n"
        "'''\n"
        "!window size=8;8\n"
        "    !record filename=(OUT if frame == 2 else null)\n"
        "        !feedback mixer=0.5\n"
        "            !shader fragment=solid rgba=(1 if frame == 1 else 0)\n",
        "fb.png", 3, path, sizeof path);
    free(log);
    double keep = pow(0.5, 0.2), light = (1 - keep) * keep;
    assert_true(fabs(light - 0.11269) < 1e-5);
    Pic p = load_png(path);
    assert_near(chan(px(&p, 4, 4), 16), 95, 1);
    assert_near(chan(px(&p, 4, 4), 0), 95, 1);
    cairo_surface_destroy(p.s);
}

/* !dash makes the strokes after it dashed; !mask clips to the outside of
 * the path. */
static void test_dash_mask(void **st)
{
    (void)st;
    char path[256];
    char *log = render(
        "!window size=100;100\n"
        "    !record filename=OUT keep_alpha=true\n"
        "        !canvas\n"
        "            !group\n"
        "                !dash intervals=10;10\n"
        "                !line points=0;10;100;10 stroke=true stroke_width=4 color=1\n"
        "            !group\n"
        "                !path\n"
        "                    !rect point=40;40 size=20;20\n"
        "                    !mask\n"
        "                !rect point=0;30 size=100;70 fill=true color=0;0;1\n",
        "h.png", 1, path, sizeof path);
    free(log);
    Pic p = load_png(path);
    assert_int_equal(px(&p, 5, 10), 0xffffffffu);    /* dash 0..10 */
    assert_int_equal(px(&p, 15, 10), 0x00000000u);   /* gap 10..20 */
    assert_int_equal(px(&p, 25, 10), 0xffffffffu);
    assert_int_equal(px(&p, 50, 50), 0x00000000u);   /* masked out */
    assert_int_equal(px(&p, 30, 50), 0xff0000ffu);
    assert_int_equal(px(&p, 50, 70), 0xff0000ffu);
    cairo_surface_destroy(p.s);
}

/* `!canvas linear=true` (Flitter docs/canvas.md; canvas.pyx Canvas.create:
 * a linear-sRGB surface on an 8-bit texture the window reads as linear
 * light): colours are linear values, stored rounded to 8 bits, blended in
 * linear light, and the window's sRGB output encodes them. Worked by hand
 * with enc(x) = 255 (1.055 x^(1/2.4) - 0.055) and dec its inverse:
 *   - white at alpha 0.5 over black: premultiplied round(127.5) = 128, so
 *     linear 128/255 = 0.50196 and enc = 187.9 -> 188, where a non-linear
 *     canvas gives 128;
 *   - colour 0.01: round(2.55) = 3 (Flitter's GPU rounds; cairo alone
 *     would truncate to 2, enc 21.7 -> 22), 3/255 = 0.011765, enc 28.2 ->
 *     28; drawn twice with composite=:add, 6/255, enc 42.4 -> 42;
 *   - a gradient's stop colours are sRGB colours (Flitter passes them to
 *     Skia as 8-bit colours): two stops of 0.5 decode to round(127.5) =
 *     128 -> dec(128/255) = 0.2159, stored round(55.04) = 55, enc(55/255)
 *     = 127.9 -> 128: the same grey as on a non-linear canvas, not 188. */
static void test_linear_canvas(void **st)
{
    (void)st;
    char path[256];
    const char *body =
        "            !rect size=40;20 fill=true color=0\n"
        "            !rect size=10;10 fill=true color=1;1;1;0.5\n"
        "            !rect point=10;0 size=10;10 fill=true color=0.01\n"
        "            !group composite=:add\n"
        "                !rect point=10;10 size=10;10 fill=true color=0.01\n"
        "                !rect point=10;10 size=10;10 fill=true color=0.01\n"
        "            !group\n"
        "                !gradient start=20;0 end=40;0\n"
        "                    !stop color=0.5\n"
        "                    !stop color=0.5\n"
        "                !rect point=20;0 size=20;20 fill=true\n";
    char src[1024];
    snprintf(src, sizeof src, "!window size=40;20\n    !record filename=OUT\n        !canvas linear=true\n%s", body);
    char *log = render(src, "lin.png", 1, path, sizeof path);
    free(log);
    Pic p = load_png(path);
    assert_int_equal(px(&p, 5, 5), 0xffbcbcbcu);    /* 188 */
    assert_int_equal(px(&p, 5, 15), 0xff000000u);   /* black stays black */
    assert_int_equal(px(&p, 15, 5), 0xff1c1c1cu);   /* 28 */
    assert_near(chan(px(&p, 15, 15), 16), 42, 1);  /* 42.4: the GPU's encoding may give 43 */
    assert_near(chan(px(&p, 30, 10), 16), 128, 1);
    cairo_surface_destroy(p.s);
    /* the same canvas without linear: the colours are sRGB values */
    snprintf(src, sizeof src, "!window size=40;20\n    !record filename=OUT\n        !canvas\n%s", body);
    log = render(src, "nonlin.png", 1, path, sizeof path);
    free(log);
    p = load_png(path);
    assert_near(chan(px(&p, 5, 5), 16), 128, 1);
    assert_near(chan(px(&p, 30, 10), 16), 128, 1);
    cairo_surface_destroy(p.s);
}

/* In a !bloom, a linear canvas gives its linear light as it is (Flitter
 * reads its 8-bit linear texture): white at alpha 0.5 alone is linear
 * 128/255 at alpha 128/255, and the bloom (radius 0: the original, which
 * is lighter than its darkened copy) leaves it so; the record encodes it
 * as 188 = enc(0.50196) at alpha 128, read back premultiplied as
 * 188 * 128 / 255 = 94. Decoding an encoded picture instead would give
 * enc(enc(0.502)) = 224 and 112. */
static void test_linear_canvas_bloom(void **st)
{
    (void)st;
    char path[256];
    char *log = render(
        "!window size=40;40\n"
        "    !record filename=OUT keep_alpha=true\n"
        "        !bloom\n"
        "            !canvas linear=true\n"
        "                !rect size=40;40 fill=true color=1;1;1;0.5\n",
        "linbloom.png", 1, path, sizeof path);
    free(log);
    Pic p = load_png(path);
    uint32_t v = px(&p, 20, 20);
    assert_near(chan(v, 24), 128, 1);
    assert_near(chan(v, 16), 94, 1);
    cairo_surface_destroy(p.s);
}

/* A !transform under !window (Flitter docs/shaders.md "!transform";
 * shaders.py Transform and glsl/transform.frag): its children are
 * scaled, rotated and translated about the picture's centre with y up,
 * the last attribute applied first, transparent outside. Here a canvas
 * of 100x100 (red top-left quarter, white elsewhere) under
 * translate=20;10 scale=0.5: a canvas point s lands at
 * 0.5 (s - 50) + (20;-10) + 50 = 0.5 s + (45;15), so the canvas covers
 * x 45..95, y 15..65 (10 up from the centred 25..75), its red quarter x
 * 45..70, y 15..40. At scale 0.5 each pixel centre samples exactly
 * between four canvas pixels, so every pixel is exact. */
static void test_window_transform(void **st)
{
    (void)st;
    char path[256];
    char *log = render(
        "!window size=100;100\n"
        "    !record filename=OUT keep_alpha=true\n"
        "        !transform translate=20;10 scale=0.5\n"
        "            !canvas\n"
        "                !rect size=100;100 fill=true color=1\n"
        "                !rect size=50;50 fill=true color=1;0;0\n",
        "xf.png", 1, path, sizeof path);
    assert_null(strstr(log, "unsupported !transform"));
    free(log);
    Pic p = load_png(path);
    assert_int_equal(px(&p, 45, 15), 0xffff0000u);
    assert_int_equal(px(&p, 69, 39), 0xffff0000u);
    assert_int_equal(px(&p, 70, 39), 0xffffffffu);
    assert_int_equal(px(&p, 69, 40), 0xffffffffu);
    assert_int_equal(px(&p, 94, 64), 0xffffffffu);
    assert_int_equal(px(&p, 44, 30), 0x00000000u);
    assert_int_equal(px(&p, 50, 14), 0x00000000u);
    assert_int_equal(px(&p, 95, 50), 0x00000000u);
    assert_int_equal(px(&p, 80, 65), 0x00000000u);
    assert_int_equal(px(&p, 10, 90), 0x00000000u);
    cairo_surface_destroy(p.s);
}

/* rotate=0.25 turns the picture a quarter turn anticlockwise on screen
 * (Flitter's Matrix33.rotate in y-up space): the red top-left quarter
 * goes to the bottom-left (centred (-25;-25) y down is (-25;25) y up,
 * turned to (-25;-25) y up, (25;75) on screen). alpha=0.5 halves the
 * light: 0.5, enc 188, at alpha 128, read back as 94. */
static void test_window_transform_rotate(void **st)
{
    (void)st;
    char path[256];
    char *log = render(
        "!window size=100;100\n"
        "    !record filename=OUT keep_alpha=true\n"
        "        !transform rotate=0.25 alpha=0.5\n"
        "            !canvas\n"
        "                !rect size=100;100 fill=true color=1\n"
        "                !rect size=50;50 fill=true color=1;0;0\n",
        "xfr.png", 1, path, sizeof path);
    assert_null(strstr(log, "transform"));
    free(log);
    Pic p = load_png(path);
    uint32_t red = px(&p, 25, 75), white = px(&p, 25, 25);
    assert_near(chan(red, 24), 128, 1);
    assert_near(chan(red, 16), 94, 1);
    assert_int_equal(chan(red, 8), 0);
    assert_near(chan(white, 24), 128, 1);
    assert_near(chan(white, 8), 94, 1);
    assert_near(chan(px(&p, 75, 25), 8), 94, 1);   /* white: red is not top-right (clockwise) */
    assert_near(chan(px(&p, 75, 75), 8), 94, 1);
    cairo_surface_destroy(p.s);
}

/* A .gif with codec=:gif is an animation, a frame a frame (Flitter
 * docs/windows.md, !record); without it, a still picture, written once
 * (the first frame's). */
static void test_gif_frames(void **st)
{
    (void)st;
    char path[256];
    char *log = render(
        "!window size=40;30\n"
        "    !record filename=OUT\n"
        "        !canvas\n"
        "            !rect size=frame*10+10;30 fill=true color=1\n",
        "still.gif", 4, path, sizeof path);
    free(log);
    int code = 0;
    GifFileType *g = DGifOpenFileName(path, &code);
    assert_non_null(g);
    assert_int_equal(DGifSlurp(g), GIF_OK);
    assert_int_equal(g->ImageCount, 1);
    DGifCloseFile(g, &code);
    log = render(
        "!window size=40;30\n"
        "    !record filename=OUT codec=:gif\n"
        "        !canvas\n"
        "            !rect size=frame*10+10;30 fill=true color=1\n",
        "d.gif", 4, path, sizeof path);
    free(log);
    g = DGifOpenFileName(path, &code);
    assert_non_null(g);
    assert_int_equal(DGifSlurp(g), GIF_OK);
    assert_int_equal(g->ImageCount, 4);
    assert_int_equal(g->SWidth, 40);
    assert_int_equal(g->SHeight, 30);
    /* frame 2 (third): white up to x=30, black after */
    SavedImage *im = &g->SavedImages[2];
    ColorMapObject *map = im->ImageDesc.ColorMap ? im->ImageDesc.ColorMap : g->SColorMap;
    GifColorType in = map->Colors[im->RasterBits[5 * 40 + 25]];
    GifColorType out = map->Colors[im->RasterBits[5 * 40 + 35]];
    assert_true(in.Red > 240 && in.Green > 240 && in.Blue > 240);
    assert_true(out.Red < 16 && out.Green < 16 && out.Blue < 16);
    GraphicsControlBlock gcb;
    assert_int_equal(DGifSavedExtensionToGCB(g, 0, &gcb), GIF_OK);
    assert_int_equal(gcb.DelayTime, 10);   /* 10 fps */
    DGifCloseFile(g, &code);
}

/* A path of more than 10,000 operations is stroked on a thread of its own
 * when the runtime has an interrupt flag to poll (canvas.c, fill_or_stroke):
 * the same cairo call, so the same pixels as the stroke made in place (no
 * flag): a zigzag of 12,000 segments, compared pixel for pixel, and red
 * where the zigzag lies, black beyond its end. */
static void test_long_path_thread(void **st)
{
    (void)st;
    const char *src =
        "!window size=220;400\n"
        "    !record filename=OUT\n"
        "        !canvas\n"
        "            !path\n"
        "                !move_to point=10;0\n"
        "                for i in ..12000\n"
        "                    !line_to point=(i%2)*200+10;i*0.03\n"
        "                !stroke stroke_width=1 color=1;0;0\n";
    char here[256], there[256];
    volatile int never = 0;
    free(render_with(src, "in_place.png", 1, here, sizeof here, NULL));
    free(render_with(src, "threaded.png", 1, there, sizeof there, &never));
    Pic a = load_png(here), b = load_png(there);
    assert_int_equal(a.w, 220);
    assert_int_equal(b.w, 220);
    assert_int_equal(a.h, b.h);
    long differ = 0;
    for (int y = 0; y < a.h; y++)
        for (int x = 0; x < a.w; x++) differ += px(&a, x, y) != px(&b, x, y);
    assert_int_equal(differ, 0);
    assert_int_equal(px(&b, 100, 100) & 0xffffff, 0xff0000);
    assert_int_equal(px(&b, 100, 390) & 0xffffff, 0x000000);
    cairo_surface_destroy(a.s);
    cairo_surface_destroy(b.s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fill_stroke_transform),
        cmocka_unit_test(test_path_transform_gradient),
        cmocka_unit_test(test_layer_arc_text_skip),
        cmocka_unit_test(test_line_curve),
        cmocka_unit_test(test_canvas_stretched),
        cmocka_unit_test(test_effect_drawn),
        cmocka_unit_test(test_headless_every_frame),
        cmocka_unit_test(test_dash_mask),
        cmocka_unit_test(test_gif_frames),
        cmocka_unit_test(test_linear_canvas),
        cmocka_unit_test(test_linear_canvas_bloom),
        cmocka_unit_test(test_window_transform),
        cmocka_unit_test(test_window_transform_rotate),
        cmocka_unit_test(test_long_path_thread),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
