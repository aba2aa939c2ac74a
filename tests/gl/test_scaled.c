/* test_scaled.c: the windows' pictures drawn at a scale (the live
 * window's dynamic resolution: fl_set_window_scale, lib/render/gl/graph.c
 * and the passes): the same picture at fewer pixels. A 32x32 window at
 * scale 0.5 is drawn 16x16 and read back (fl_draw_window) scaled up to
 * 32x32 by nearest texels, window pixel x showing texel x/2: a canvas
 * draws in the window's pixels, a !transform moves by them, a !blur
 * reaches as far in them; a !shader's `size` is its framebuffer's; a
 * frame whose !record writes a file is drawn whole. Only flitter.h is
 * used. Pixels are 0xAARRGGBB (sRGB of the premultiplied light). */
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

#define W 32
#define H 32

static char scratch[64];
static char logged[8192];

static int setup(void **st)
{
    (void)st;
    snprintf(scratch, sizeof scratch, "/tmp/test_scaled.XXXXXX");
    return mkdtemp(scratch) ? 0 : -1;
}

static int teardown(void **st)
{
    (void)st;
    char path[256];
    snprintf(path, sizeof path, "%s/main.fl", scratch);
    unlink(path);
    snprintf(path, sizeof path, "%s/rec.png", scratch);
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

/* A runtime with [script] loaded from scratch/main.fl. */
static fl_runtime *load_script(const char *script)
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
    return rt;
}

/* One frame of [script]'s first window drawn at [scale] with at most
 * [samples] samples into [pix]; the scale it was drawn at returned. */
static double draw_at(const char *script, double scale, int samples, uint32_t *pix)
{
    fl_runtime *rt = load_script(script);
    fl_set_window_scale(rt, scale, samples);
    assert_int_equal(fl_step(rt), 0);
    assert_int_equal(fl_draw_window(rt, 0, pix, W, H, W * 4), 0);
    if (logged[0]) fail_msg("unexpected log:\n%s", logged);
    double drawn = fl_window_scale(rt, NULL);
    fl_free(rt);
    return drawn;
}

static uint32_t at(const uint32_t *pix, int x, int y) { return pix[y * W + x]; }

static void expect_exact(const uint32_t *pix, int x, int y, uint32_t want)
{
    if (at(pix, x, y) != want) fail_msg("pixel (%d,%d) is %08x, expected %08x", x, y, at(pix, x, y), want);
}

/* A canvas's rectangle 8 window pixels wide covers the window's first 8
 * columns at scale 0.5 as at full size (drawn in a 16-pixel picture
 * scaled by 0.5: 4 texels); unscaled it would cover 16. */
static void canvas_in_window_pixels(void **st)
{
    (void)st;
    static const char script[] = "!window size=32;32\n"
                                 "    !canvas\n"
                                 "        !rect point=0;0 size=8;32\n"
                                 "        !fill color=1;0;0\n";
    uint32_t pix[W * H], whole[W * H];
    assert_true(draw_at(script, 0.5, 0, pix) == 0.5);
    assert_true(draw_at(script, 1, 0, whole) == 1);
    for (int y = 0; y < H; y += 3)
        for (int x = 0; x < W; x++) {
            uint32_t want = x < 8 ? 0xffff0000u : 0x00000000u;
            expect_exact(pix, x, y, want);
            expect_exact(whole, x, y, want);
        }
}

/* A !shader's `size` is its framebuffer's: 16;16 at scale 0.5, 32;32
 * whole (red size.x / 64: 0.25 and 0.5 of light: sRGB 137 and 187.5). */
static void shader_size_is_framebuffer(void **st)
{
    (void)st;
    static const char script[] = "let f = '''${HEADER}\n"
                                 "out vec4 color;\n"
                                 "uniform vec2 size;\n"
                                 "void main() {\n"
                                 "    color = vec4(size.x / 64.0, 0.0, 0.0, 1.0);\n"
                                 "}\n"
                                 "'''\n"
                                 "!window size=32;32\n"
                                 "    !shader fragment=f\n";
    uint32_t pix[W * H];
    draw_at(script, 0.5, 0, pix);
    expect_exact(pix, 5, 5, 0xff890000u);
    draw_at(script, 1, 0, pix);
    /* sRGB(0.5) is 187.5: the GL rounds either way */
    if (at(pix, 5, 5) != 0xffbb0000u && at(pix, 5, 5) != 0xffbc0000u)
        fail_msg("pixel (5,5) is %08x, expected ffbb0000 or ffbc0000", at(pix, 5, 5));
}

/* !transform translate=8;0 moves the picture 8 window pixels at either
 * scale: red from column 8, green from 24 (16 + 8), nothing before. */
static void transform_in_window_pixels(void **st)
{
    (void)st;
    static const char script[] = "let halves = '''${HEADER}\n"
                                 "in vec2 coord;\n"
                                 "out vec4 color;\n"
                                 "void main() {\n"
                                 "    color = coord.x < 0.5 ? vec4(1.0, 0.0, 0.0, 1.0) : vec4(0.0, 1.0, 0.0, 1.0);\n"
                                 "}\n"
                                 "'''\n"
                                 "!window size=32;32\n"
                                 "    !transform translate=8;0\n"
                                 "        !shader fragment=halves\n";
    for (int k = 0; k < 2; k++) {
        uint32_t pix[W * H];
        draw_at(script, k ? 1 : 0.5, 0, pix);
        for (int x = 0; x < W; x++) {
            uint32_t want = x < 8 ? 0 : x < 24 ? 0xffff0000u : 0xff00ff00u;
            expect_exact(pix, x, 9, want);
        }
    }
}

/* !blur radius=4 of white columns 0..15 reaches 4 window pixels at either
 * scale: column 18 takes some light, column 20 none (at scale 0.5 texel
 * 10 reads texels 8..12 with the radius halved to 2; with the radius
 * left at 4 texels it would read texels 6 and 7, white). */
static void blur_in_window_pixels(void **st)
{
    (void)st;
    static const char script[] = "let left = '''${HEADER}\n"
                                 "in vec2 coord;\n"
                                 "out vec4 color;\n"
                                 "void main() {\n"
                                 "    color = coord.x < 0.5 ? vec4(1.0) : vec4(0.0);\n"
                                 "}\n"
                                 "'''\n"
                                 "!window size=32;32\n"
                                 "    !blur radius=4\n"
                                 "        !shader fragment=left\n";
    for (int k = 0; k < 2; k++) {
        uint32_t pix[W * H];
        draw_at(script, k ? 1 : 0.5, 0, pix);
        if ((at(pix, 18, 9) >> 24) == 0) fail_msg("scale %g: column 18 is %08x: no light", k ? 1 : 0.5, at(pix, 18, 9));
        expect_exact(pix, 20, 9, 0x00000000u);
        expect_exact(pix, 2, 9, 0xffffffffu);
    }
}

/* A frame whose !record writes its file is drawn whole (and the file is
 * 32x32); the next, writing nothing, at the scale asked. */
static void record_frame_drawn_whole(void **st)
{
    (void)st;
    char script[512];
    snprintf(script, sizeof script,
             "!window size=32;32\n"
             "    !record filename=(\"%s/rec.png\" if frame == 0)\n"
             "        !canvas\n"
             "            !rect point=0;0 size=8;32\n"
             "            !fill color=1;0;0\n",
             scratch);
    fl_runtime *rt = load_script(script);
    fl_set_window_scale(rt, 0.5, 1);
    uint32_t pix[W * H];
    int samples = -1;
    assert_int_equal(fl_step(rt), 0);
    assert_int_equal(fl_draw_window(rt, 0, pix, W, H, W * 4), 0);
    assert_true(fl_window_scale(rt, &samples) == 1);
    assert_int_equal(samples, 0);
    expect_exact(pix, 7, 3, 0xffff0000u);
    expect_exact(pix, 8, 3, 0x00000000u);
    /* the PNG's header: 32x32 */
    char path[256];
    snprintf(path, sizeof path, "%s/rec.png", scratch);
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    unsigned char head[24];
    assert_int_equal(fread(head, 1, sizeof head, f), sizeof head);
    fclose(f);
    assert_int_equal(head[16] << 24 | head[17] << 16 | head[18] << 8 | head[19], 32);
    assert_int_equal(head[20] << 24 | head[21] << 16 | head[22] << 8 | head[23], 32);
    assert_int_equal(fl_step(rt), 0);
    assert_int_equal(fl_draw_window(rt, 0, pix, W, H, W * 4), 0);
    assert_true(fl_window_scale(rt, &samples) == 0.5);
    assert_int_equal(samples, 1);
    expect_exact(pix, 7, 3, 0xffff0000u);
    expect_exact(pix, 8, 3, 0x00000000u);
    if (logged[0]) fail_msg("unexpected log:\n%s", logged);
    fl_free(rt);
}

/* fl_outputs_frame alone (no window shown) draws whole: a headless run's
 * !record files never scale. */
static void outputs_frame_whole(void **st)
{
    (void)st;
    char script[512];
    snprintf(script, sizeof script,
             "!window size=32;32\n"
             "    !record filename=\"%s/rec.png\"\n"
             "        !canvas\n"
             "            !rect point=0;0 size=8;32\n"
             "            !fill color=1;0;0\n",
             scratch);
    fl_runtime *rt = load_script(script);
    fl_set_window_scale(rt, 0.25, 1);
    assert_int_equal(fl_step(rt), 0);
    fl_outputs *outs = fl_outputs_open(rt, NULL);
    assert_int_equal(fl_outputs_frame(outs, rt), 0);
    assert_true(fl_window_scale(rt, NULL) == 1);
    fl_outputs_close(outs, rt);
    fl_free(rt);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(canvas_in_window_pixels),
        cmocka_unit_test(shader_size_is_framebuffer),
        cmocka_unit_test(transform_in_window_pixels),
        cmocka_unit_test(blur_in_window_pixels),
        cmocka_unit_test(record_frame_drawn_whole),
        cmocka_unit_test(outputs_frame_whole),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
