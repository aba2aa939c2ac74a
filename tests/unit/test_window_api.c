/* test_window_api.c: the window side of flitter.h as a front end uses it
 * ("Windows: a frame's pictures and input"): the list of windows, a
 * window's picture drawn into a caller's buffer (pixels at known places,
 * and byte for byte what `!record` writes for the same frame), the
 * physics view drawn into a buffer, the key and pointer state writes of
 * Flitter's `!key` / `!pointer` (exact keys and values), and the files a
 * program was read from. Only flitter.h is used, and cairo to decode the
 * PNG files. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>

#include <cairo.h>

#include "flitter.h"

static char scratch[64];

static int setup(void **st)
{
    (void)st;
    snprintf(scratch, sizeof scratch, "/tmp/test_window_api.XXXXXX");
    return mkdtemp(scratch) ? 0 : -1;
}

static int teardown(void **st)
{
    (void)st;
    static const char *const made[] = {"main.fl", "inc.fl", "mod.fl", "sub.fl", "alpha.png",
                                       "opaque.png"};
    char path[256];
    for (size_t i = 0; i < sizeof made / sizeof made[0]; i++) {
        snprintf(path, sizeof path, "%s/%s", scratch, made[i]);
        unlink(path);
    }
    return rmdir(scratch);
}

/* Write [text] to scratch/[name]; its full path goes to [path]. */
static void write_file(const char *name, const char *text, char *path, size_t cap)
{
    snprintf(path, cap, "%s/%s", scratch, name);
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
}

static void quiet(void *ctx, int kind, const char *line)
{
    (void)ctx;
    (void)kind;
    (void)line;
}

static fl_runtime *load(const char *text, bool simplify)
{
    fl_options o = fl_default_options();
    o.log = quiet;
    o.no_simplify = !simplify;
    fl_runtime *rt = fl_new(&o);
    char path[256];
    write_file("main.fl", text, path, sizeof path);
    assert_int_equal(fl_load(rt, path), 0);
    return rt;
}

/* The state value text of [key] ("" when absent). */
static const char *get(fl_runtime *rt, const char *key)
{
    static char buf[128];
    if (fl_state_get(rt, key, buf, sizeof buf) < 0) buf[0] = '\0';
    return buf;
}

/* {=====================================================================
 * fl_windows
 * ===================================================================== */

static void test_windows_list(void **st)
{
    (void)st;
    fl_runtime *rt = load("!window size=64;48 title=\"Main \xc3\xa9\" fullscreen=true vsync=false\n"
                          "!physics state=:p dimensions=2\n"
                          "!offscreen size=32;16\n"
                          "!window size=0;10 title=:sym\n",
                          true);
    assert_int_equal(fl_windows(rt, NULL, 0), 0);   /* before the first frame */
    assert_int_equal(fl_step(rt), 0);
    fl_window_info w[2];
    memset(w, 0x55, sizeof w);
    assert_int_equal(fl_windows(rt, NULL, 0), 3);
    assert_int_equal(fl_windows(rt, w, 2), 3);       /* fills only what fits */
    assert_int_equal(w[0].width, 64);
    assert_int_equal(w[0].height, 48);
    assert_string_equal(w[0].title, "Main \xc3\xa9");
    assert_false(w[0].offscreen);
    assert_int_equal(w[0].fullscreen, 1);
    assert_int_equal(w[0].vsync, 0);
    assert_int_equal(w[1].width, 32);
    assert_int_equal(w[1].height, 16);
    assert_string_equal(w[1].title, "");
    assert_true(w[1].offscreen);
    assert_int_equal(w[1].fullscreen, -1);
    assert_int_equal(w[1].vsync, -1);
    fl_window_info all[3];
    assert_int_equal(fl_windows(rt, all, 3), 3);
    assert_int_equal(all[2].width, 512);   /* a side of 0: the default size */
    assert_int_equal(all[2].height, 512);
    assert_string_equal(all[2].title, "sym");   /* a symbol by its name */
    fl_free(rt);
}

static void test_title_truncated(void **st)
{
    (void)st;
    /* 254 'x' then a 2-byte character: it would end at byte 256, so it goes */
    char script[400] = "!window title=\"";
    size_t n = strlen(script);
    memset(script + n, 'x', 254);
    strcpy(script + n + 254, "\xc3\xa9\"\n");
    fl_runtime *rt = load(script, true);
    assert_int_equal(fl_step(rt), 0);
    fl_window_info w;
    assert_int_equal(fl_windows(rt, &w, 1), 1);
    assert_int_equal(strlen(w.title), 254);
    fl_free(rt);
}

/* {=====================================================================
 * fl_draw_window
 * ===================================================================== */

enum { W = 100, H = 80, STRIDE = W * 4 + 16 };

static uint32_t at(const uint32_t *pix, size_t stride, int x, int y)
{
    return pix[(size_t)y * (stride / 4) + (size_t)x];
}

static void test_draw_window_pixels_and_record(void **st)
{
    (void)st;
    char script[1024];
    snprintf(script, sizeof script,
             "!window size=100;80\n"
             "    !record filename=\"%s/alpha.png\" keep_alpha=true\n"
             "        !canvas\n"
             "            !rect point=10;10 size=30;20 fill=true color=1;0;0\n"
             "            !rect point=50;40 size=20;20 fill=true color=0;0;1;0.5\n"
             "!offscreen size=100;80\n"
             "    !record filename=\"%s/opaque.png\"\n"
             "        !canvas\n"
             "            !rect point=10;10 size=30;20 fill=true color=1;0;0\n"
             "            !rect point=50;40 size=20;20 fill=true color=0;0;1;0.5\n",
             scratch, scratch);
    fl_runtime *rt = load(script, true);
    uint32_t *pix = malloc((size_t)STRIDE * H);
    assert_int_equal(fl_draw_window(rt, 0, pix, W, H, STRIDE), -1);   /* no frame yet */
    fl_outputs *out = fl_outputs_open(rt, NULL);
    assert_non_null(out);
    assert_int_equal(fl_step(rt), 0);
    assert_int_equal(fl_outputs_frame(out, rt), 0);
    assert_int_equal(fl_outputs_close(out, rt), 0);

    memset(pix, 0x77, (size_t)STRIDE * H);   /* garbage: the drawing clears it */
    assert_int_equal(fl_draw_window(rt, 0, pix, W, H, STRIDE), 0);
    assert_int_equal(at(pix, STRIDE, 20, 20), 0xffff0000u);   /* inside the red rect */
    assert_int_equal(at(pix, STRIDE, 10, 10), 0xffff0000u);   /* its first pixel */
    assert_int_equal(at(pix, STRIDE, 39, 29), 0xffff0000u);   /* its last */
    assert_int_equal(at(pix, STRIDE, 40, 20), 0x00000000u);   /* transparent beside it */
    assert_int_equal(at(pix, STRIDE, 5, 5), 0x00000000u);
    /* half blue: the canvas's own premultiplied 128 at alpha 128, decoded
     * to light by the GPU's sRGB sampling and encoded again by the
     * record's sRGB framebuffer: an 8-bit canvas's pixels come through as
     * they are */
    assert_int_equal(at(pix, STRIDE, 60, 50), 0x80000080u);
    /* the padding after each row is left alone */
    assert_int_equal(pix[W], 0x77777777u);

    /* byte for byte what !record wrote: the RGBA file (whose colours are
     * those values as straight colour, read back here by cairo, which
     * premultiplies them: the window's pixels premultiplied the same way
     * must match) ... */
    char path[256];
    snprintf(path, sizeof path, "%s/alpha.png", scratch);
    cairo_surface_t *png = cairo_image_surface_create_from_png(path);
    assert_int_equal(cairo_surface_status(png), CAIRO_STATUS_SUCCESS);
    assert_int_equal(cairo_image_surface_get_format(png), CAIRO_FORMAT_ARGB32);
    assert_int_equal(cairo_image_surface_get_width(png), W);
    assert_int_equal(cairo_image_surface_get_height(png), H);
    const unsigned char *data = cairo_image_surface_get_data(png);
    size_t pstride = (size_t)cairo_image_surface_get_stride(png);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            uint32_t v = at(pix, STRIDE, x, y), a = v >> 24, want = a << 24;
            for (int k = 0; k < 24; k += 8) want |= (((v >> k) & 0xffu) * a + 127) / 255 << k;
            uint32_t got = ((const uint32_t *)(const void *)(data + (size_t)y * pstride))[x];
            if (got != want) fail_msg("alpha.png (%d,%d) = %08x, window %08x (premultiplied %08x)", x, y, got, v, want);
        }
    cairo_surface_destroy(png);

    /* ... and the opaque one: the same picture over black */
    uint32_t *off = malloc((size_t)W * 4 * H);
    assert_int_equal(fl_draw_window(rt, 1, off, W, H, W * 4), 0);
    for (int y = 0; y < H; y++)   /* the same drawing as window 0 */
        assert_memory_equal(off + (size_t)y * W, (const unsigned char *)pix + (size_t)y * STRIDE, W * 4);
    snprintf(path, sizeof path, "%s/opaque.png", scratch);
    png = cairo_image_surface_create_from_png(path);
    assert_int_equal(cairo_surface_status(png), CAIRO_STATUS_SUCCESS);
    assert_int_equal(cairo_image_surface_get_format(png), CAIRO_FORMAT_RGB24);
    data = cairo_image_surface_get_data(png);
    pstride = (size_t)cairo_image_surface_get_stride(png);
    int checked = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            uint32_t got = ((const uint32_t *)(const void *)(data + (size_t)y * pstride))[x];
            /* premultiplied colour over black is the colour channels as they are */
            if ((got & 0xffffffu) != (off[y * W + x] & 0xffffffu))
                fail_msg("opaque.png (%d,%d) = %06x, window %08x", x, y, got & 0xffffffu, off[y * W + x]);
            checked++;
        }
    assert_int_equal(checked, W * H);
    assert_int_equal(at(off, W * 4, 60, 50) & 0xffffffu, 0x000080u);
    cairo_surface_destroy(png);
    free(off);
    free(pix);
    fl_free(rt);
}

/* A window's pictures (a !record's, a !transform's, a canvas's) are kept
 * from frame to frame for reuse: each must start transparent again. Frame
 * 0 draws a red square at the top left, frame 1 one at the bottom right;
 * frame 1's picture must not keep frame 0's square, at either depth; nor
 * a later picture of the same size when sizes alternate. */
static void test_draw_window_pictures_reused(void **st)
{
    (void)st;
    fl_runtime *rt = load("!window size=100;80\n"
                          "    !record\n"
                          "        !transform\n"
                          "            !canvas\n"
                          "                !rect point=((10;10) if frame == 0 else (60;40)) size=20;20 "
                          "fill=true color=1;0;0\n",
                          true);
    uint32_t *pix = malloc((size_t)STRIDE * H);
    for (int frame = 0; frame < 3; frame++) {
        assert_int_equal(fl_step(rt), 0);
        assert_int_equal(fl_draw_window(rt, 0, pix, W, H, STRIDE), 0);
        bool first = frame == 0;
        assert_int_equal(at(pix, STRIDE, 20, 20), first ? 0xffff0000u : 0u);
        assert_int_equal(at(pix, STRIDE, 70, 50), first ? 0u : 0xffff0000u);
    }
    fl_free(rt);
    /* pictures of two sizes in turn: the square of frame 0 (a 100x80
     * picture) must not come back in frame 2 (a 100x80 picture again,
     * after a 50x40 one) */
    rt = load("!window size=100;80\n"
              "    !record size=((100;80) if frame % 2 == 0 else (50;40))\n"
              "        !canvas\n"
              "            !rect point=10;10 size=(20;20 if frame == 0 else 0) fill=true color=1;0;0\n",
              true);
    for (int frame = 0; frame < 4; frame++) {
        assert_int_equal(fl_step(rt), 0);
        assert_int_equal(fl_draw_window(rt, 0, pix, W, H, STRIDE), 0);
        assert_int_equal(at(pix, STRIDE, 20, 20), frame == 0 ? 0xffff0000u : 0u);
    }
    free(pix);
    fl_free(rt);
}

static void test_draw_window_errors(void **st)
{
    (void)st;
    fl_runtime *rt = load("!window size=100;80\n    !canvas\n        !rect size=5;5 fill=true\n", true);
    assert_int_equal(fl_step(rt), 0);
    uint32_t *pix = calloc((size_t)STRIDE * H, 1);
    assert_int_equal(fl_draw_window(rt, 1, pix, W, H, STRIDE), -1);   /* one window only */
    assert_non_null(strstr(fl_error(rt), "no window 1"));
    assert_int_equal(fl_draw_window(rt, (size_t)-1, pix, W, H, STRIDE), -1);
    assert_int_equal(fl_draw_window(rt, 0, pix, W - 1, H, STRIDE), -1);   /* not its size */
    assert_non_null(strstr(fl_error(rt), "100x80"));
    assert_int_equal(fl_draw_window(rt, 0, pix, W, H + 1, STRIDE), -1);
    assert_int_equal(fl_draw_window(rt, 0, pix, W, H, W * 4 - 4), -1);   /* stride too small */
    assert_non_null(strstr(fl_error(rt), "stride"));
    assert_int_equal(fl_draw_window(rt, 0, pix, W, H, W * 4 + 2), -1);    /* not whole pixels */
    assert_int_equal(fl_draw_window(rt, 0, NULL, W, H, STRIDE), -1);
    for (size_t i = 0; i < (size_t)STRIDE * H / 4; i++) assert_int_equal(pix[i], 0);   /* untouched */
    assert_int_equal(fl_draw_window(rt, 0, pix, W, H, W * 4), 0);   /* the tight stride */
    assert_string_equal(fl_error(rt), "");
    assert_int_equal(pix[0], 0xff000000u);   /* the 5x5 black square */
    assert_int_equal(pix[5], 0x00000000u);
    free(pix);
    fl_free(rt);
}

/* {=====================================================================
 * fl_draw_view
 * ===================================================================== */

static void test_draw_view(void **st)
{
    (void)st;
    fl_runtime *rt = load("!physics state=:s dimensions=2\n"
                          "    !particle id=1 position=0;0 radius=10\n",
                          true);
    assert_int_equal(fl_step(rt), 0);
    /* the view is one 480x508 panel: at 0.5 it is 240x254, centred in 600 */
    enum { VW = 600, VH = 254 };
    uint32_t *pix = malloc((size_t)VW * 4 * VH);
    size_t n = 99;
    assert_int_equal(fl_draw_view(rt, pix, VW, VH, VW * 4, &n), 0);
    assert_int_equal(n, 1);
    assert_int_equal(pix[100 * VW + 10], 0xff000000u);    /* the bar left of the view */
    assert_int_equal(pix[100 * VW + 590], 0xff000000u);   /* and right of it */
    uint32_t bg = pix[40 * VW + 200];                     /* inside the view, above the panel's body: white */
    assert_int_equal(bg, 0xffffffffu);
    /* the lone particle fills the panel's middle: grey (charge 0) at the
     * panel's centre (240, 28 + 240) / 2 + (180, 0) */
    uint32_t p = pix[134 * VW + 300];
    assert_int_equal(p >> 24, 0xff);
    for (int sh = 0; sh <= 16; sh += 8) {
        int c = (int)((p >> sh) & 0xff);
        if (c < 139 || c > 141) fail_msg("particle channel %d = %d, want 140", sh, c);
    }
    assert_int_equal(fl_draw_view(rt, pix, 0, VH, VW * 4, NULL), -1);
    assert_int_equal(fl_draw_view(rt, pix, 16385, 1, 16385 * 4, NULL), -1);
    assert_int_equal(fl_draw_view(rt, pix, VW, VH, VW * 4 - 4, &n), -1);
    assert_int_equal(n, 0);
    assert_non_null(strstr(fl_error(rt), "stride"));
    free(pix);
    fl_free(rt);
}

/* The view drawn away from the runtime (fl_view_snapshot_take on the
 * runtime's side, fl_view_painter_draw anywhere): every frame's snapshot,
 * drawn after the runtime has gone on to the next frame (and after it is
 * freed), gives fl_draw_view's pixels of its own frame, byte for byte,
 * whatever the painter drew before. */
static void test_view_snapshot(void **st)
{
    (void)st;
    static const char *const DISH =
        "!physics state=:dish dimensions=2\n"
        "    !anchor id=:centre position=0;0\n"
        "    for i in ..12\n"
        "        !particle id=i charge=i%3-1 radius=4 position=(i*37%50-25);(i*11%40-20) velocity=i;-i\n"
        "        !distance strength=50 max=60 from=i to=:centre\n"
        "    !barrier position=0;-40 normal=0;1\n"
        "    !electrostatic strength=500\n"
        "    !collision\n";
    fl_runtime *rt = load(DISH, true);
    enum { VW = 300, VH = 200 };
    size_t words = (size_t)VW * VH;
    uint32_t *want = malloc(words * 4), *got = malloc(words * 4);
    fl_view_painter *painter = fl_view_painter_new();
    assert_non_null(painter);
    fl_view_snapshot *snap = NULL;
    for (int frame = 0; frame < 20; frame++) {
        assert_int_equal(fl_step(rt), 0);
        size_t n = 0, m = 0;
        assert_int_equal(fl_draw_view(rt, want, VW, VH, VW * 4, &n), 0);
        fl_view_snapshot *again = fl_view_snapshot_take(rt, snap);
        assert_non_null(again);
        if (snap) assert_ptr_equal(again, snap);   /* refilled in place */
        snap = again;
        assert_int_equal(fl_step(rt), 0);         /* the runtime moves on */
        memset(got, 0x55, words * 4);
        assert_int_equal(fl_view_painter_draw(painter, snap, got, VW, VH, VW * 4, &m), 0);
        assert_int_equal(m, n);
        assert_int_equal(n, 1);
        if (memcmp(got, want, words * 4) != 0) fail_msg("frame %d: the snapshot's picture differs", frame);
    }
    /* the particles moved: the last picture is not the first frame's */
    assert_int_equal(fl_draw_view(rt, want, VW, VH, VW * 4, NULL), 0);
    assert_true(memcmp(got, want, words * 4) != 0);
    /* a picture has no history: after this dish, another page whose only
     * particle is lost (NaN) is painted as its own fl_draw_view paints it,
     * not fitted to the dish's extents */
    fl_runtime *lost = load("!physics state=:lost dimensions=2\n"
                            "    !particle id=1 position=0/0;0\n"
                            "    !barrier position=0;0 normal=0;1\n",
                            true);
    assert_int_equal(fl_step(lost), 0);
    fl_view_snapshot *other = fl_view_snapshot_take(lost, NULL);
    assert_non_null(other);
    assert_int_equal(fl_view_painter_draw(painter, other, got, VW, VH, VW * 4, NULL), 0);
    assert_int_equal(fl_draw_view(lost, want, VW, VH, VW * 4, NULL), 0);
    assert_memory_equal(got, want, words * 4);
    fl_view_snapshot_free(other);
    fl_free(lost);
    /* a snapshot outlives its runtime */
    assert_non_null(fl_view_snapshot_take(rt, snap));
    memcpy(want, got, words * 4);
    assert_int_equal(fl_view_painter_draw(painter, snap, want, VW, VH, VW * 4, NULL), 0);
    fl_free(rt);
    assert_int_equal(fl_view_painter_draw(painter, snap, got, VW, VH, VW * 4, NULL), 0);
    assert_memory_equal(got, want, words * 4);
    /* bad arguments: -1, nothing drawn */
    size_t n = 7;
    assert_int_equal(fl_view_painter_draw(NULL, snap, got, VW, VH, VW * 4, &n), -1);
    assert_int_equal(n, 0);
    assert_int_equal(fl_view_painter_draw(painter, NULL, got, VW, VH, VW * 4, NULL), -1);
    assert_int_equal(fl_view_painter_draw(painter, snap, NULL, VW, VH, VW * 4, NULL), -1);
    assert_int_equal(fl_view_painter_draw(painter, snap, got, 0, VH, VW * 4, NULL), -1);
    assert_int_equal(fl_view_painter_draw(painter, snap, got, VW, VH, VW * 4 - 4, NULL), -1);
    assert_int_equal(fl_view_painter_draw(painter, snap, got, VW, VH, VW * 4 + 2, NULL), -1);
    assert_null(fl_view_snapshot_take(NULL, snap));
    fl_view_snapshot_free(snap);
    fl_view_snapshot_free(NULL);
    fl_view_painter_free(painter);
    fl_view_painter_free(NULL);
    free(want);
    free(got);
}

/* A 3D system is drawn through the runtime's OpenGL renderer: no snapshot
 * (the one passed in stays as it was); drawn flat (--view-axes), it has
 * one, titled as fl_draw_view titles it. */
static void test_view_snapshot_3d(void **st)
{
    (void)st;
    static const char *const BOX = "!physics state=:box dimensions=3\n"
                                   "    !particle id=1 position=1;2;3 radius=1\n";
    fl_runtime *flat2d = load("!physics state=:p dimensions=2\n    !particle id=1 position=0;0\n", true);
    assert_int_equal(fl_step(flat2d), 0);
    fl_view_snapshot *snap = fl_view_snapshot_take(flat2d, NULL);
    assert_non_null(snap);
    fl_runtime *rt = load(BOX, true);
    assert_int_equal(fl_step(rt), 0);
    assert_null(fl_view_snapshot_take(rt, snap));
    fl_free(rt);
    fl_options o = fl_default_options();
    o.log = quiet;
    assert_true(fl_parse_view_axes("x;z", o.view_axes));
    rt = fl_new(&o);
    char path[256];
    write_file("main.fl", BOX, path, sizeof path);
    assert_int_equal(fl_load(rt, path), 0);
    assert_int_equal(fl_step(rt), 0);
    assert_ptr_equal(fl_view_snapshot_take(rt, snap), snap);
    enum { VW = 240, VH = 254 };
    uint32_t *want = malloc((size_t)VW * VH * 4), *got = malloc((size_t)VW * VH * 4);
    assert_int_equal(fl_draw_view(rt, want, VW, VH, VW * 4, NULL), 0);
    fl_view_painter *painter = fl_view_painter_new();
    assert_int_equal(fl_view_painter_draw(painter, snap, got, VW, VH, VW * 4, NULL), 0);
    assert_memory_equal(got, want, (size_t)VW * VH * 4);
    fl_view_painter_free(painter);
    fl_view_snapshot_free(snap);
    fl_free(rt);
    fl_free(flat2d);
    free(want);
    free(got);
}

/* {=====================================================================
 * fl_key, fl_pointer, fl_pointer_button
 * ===================================================================== */

static const char *const KEYS =
    "%pragma fps 4\n"
    "!window size=64;48\n"
    "    !key name=\"space\" state=:sp\n"
    "    !key name=:a state=:ka\n"
    "    !key name=\"nosuchkey\" state=:bad\n"
    "    !key name=$(:cname) state=:kc\n"
    "    !key name=\"d\" state=$(:dstate)\n"
    "    !pointer state=:ptr\n"
    "!offscreen size=32;16\n"
    "    !key name=\"Left_Shift\" state=:shift\n";

static void test_keys(void **st)
{
    (void)st;
    fl_runtime *rt = load(KEYS, true);
    assert_int_equal(fl_key(rt, 0, "space", true), 0);   /* no frame: nothing claims */
    assert_int_equal(fl_key(rt, 0, "space", false), 0);
    for (int i = 0; i < 3; i++) assert_int_equal(fl_step(rt), 0);
    /* every claimed key starts released, also in the offscreen window */
    assert_string_equal(get(rt, ":sp"), "0");
    assert_string_equal(get(rt, ":sp;:pushed"), "0");
    assert_string_equal(get(rt, ":sp;:released"), "1");
    assert_string_equal(get(rt, ":sp;:pushed;:beat"), "");
    assert_string_equal(get(rt, ":ka;:released"), "1");
    assert_string_equal(get(rt, ":shift;:released"), "1");
    assert_string_equal(get(rt, ":bad"), "");   /* not a GLFW key */
    assert_string_equal(get(rt, ":kc"), "");    /* no name yet */

    /* the last frame is frame 2: time 0.5, beat 1 (tempo 120) */
    assert_int_equal(fl_key(rt, 0, "space", true), 1);
    assert_string_equal(get(rt, ":sp"), "1");
    assert_string_equal(get(rt, ":sp;:pushed"), "1");
    assert_string_equal(get(rt, ":sp;:released"), "0");
    assert_string_equal(get(rt, ":sp;:pushed;:beat"), "1");
    assert_string_equal(get(rt, ":sp;:released;:beat"), "");
    assert_int_equal(fl_step(rt), 0);   /* beat 1.5 */
    assert_string_equal(get(rt, ":sp"), "1");   /* present: not initialised again */
    assert_int_equal(fl_key(rt, 0, "space", false), 1);
    assert_string_equal(get(rt, ":sp"), "0");
    assert_string_equal(get(rt, ":sp;:pushed"), "0");
    assert_string_equal(get(rt, ":sp;:released"), "1");
    assert_string_equal(get(rt, ":sp;:pushed;:beat"), "1");
    assert_string_equal(get(rt, ":sp;:released;:beat"), "1.5");

    assert_int_equal(fl_key(rt, 0, "a", true), 1);   /* name=:a, a symbol */
    assert_string_equal(get(rt, ":ka"), "1");
    assert_int_equal(fl_key(rt, 1, "left_shift", true), 1);   /* names in any case */
    assert_string_equal(get(rt, ":shift;:pushed"), "1");
    assert_int_equal(fl_key(rt, 0, "left_shift", true), 0);   /* window 0 has no such !key */
    assert_int_equal(fl_key(rt, 1, "space", true), 0);
    assert_int_equal(fl_key(rt, 7, "space", true), 0);         /* no window 7 */
    assert_int_equal(fl_key(rt, 0, "b", true), 0);             /* nobody claims b */
    assert_int_equal(fl_key(rt, 0, "nosuchkey", true), 0);     /* not a key */
    assert_string_equal(get(rt, ":bad"), "");
    assert_int_equal(fl_key(rt, 0, "", true), 0);
    assert_int_equal(fl_key(rt, 0, "unknown", true), 0);

    /* c held before its !key is first seen: it starts pushed; d was never
     * reported and starts released */
    assert_int_equal(fl_key(rt, 0, "c", true), 0);
    assert_int_equal(fl_state_set(rt, ":cname", "c"), 0);
    assert_int_equal(fl_state_set(rt, ":dstate", ":kd"), 0);
    assert_int_equal(fl_step(rt), 0);
    assert_string_equal(get(rt, ":kc"), "1");
    assert_string_equal(get(rt, ":kc;:pushed"), "1");
    assert_string_equal(get(rt, ":kc;:released"), "0");
    assert_string_equal(get(rt, ":kc;:pushed;:beat"), "");   /* no event yet */
    assert_string_equal(get(rt, ":kd"), "0");
    assert_string_equal(get(rt, ":kd;:released"), "1");
    assert_int_equal(fl_key(rt, 0, "c", false), 1);
    assert_string_equal(get(rt, ":kc"), "0");
    assert_string_equal(get(rt, ":kc;:released;:beat"), "2");   /* frame 4 */

    /* a held key in another window does not count: held per window */
    assert_int_equal(fl_key(rt, 1, "d", true), 0);
    fl_reset_state(rt);
    assert_int_equal(fl_state_set(rt, ":dstate", ":kd"), 0);
    assert_int_equal(fl_step(rt), 0);
    assert_string_equal(get(rt, ":kd"), "0");
    assert_string_equal(get(rt, ":sp"), "0");   /* a cleared state: initialised again */
    assert_string_equal(get(rt, ":ka"), "1");   /* a still held in window 0 */
    fl_free(rt);
}

static void test_pointer(void **st)
{
    (void)st;
    fl_runtime *rt = load(KEYS, true);
    fl_pointer(rt, 0, true, 0.25, 0.5);   /* no frame: no-op */
    assert_string_equal(get(rt, ":ptr"), "");
    assert_int_equal(fl_step(rt), 0);
    assert_string_equal(get(rt, ":ptr"), "");   /* nothing before an event */
    fl_pointer(rt, 0, true, 0.25, 0.5);
    assert_string_equal(get(rt, ":ptr"), "0.25;0.5");
    fl_pointer_button(rt, 0, 0, true);
    assert_string_equal(get(rt, ":ptr;0"), "1");
    fl_pointer_button(rt, 0, 2, true);
    assert_string_equal(get(rt, ":ptr;2"), "1");
    fl_pointer_button(rt, 0, 0, false);
    assert_string_equal(get(rt, ":ptr;0"), "0");
    fl_pointer(rt, 0, false, 2.0, 0.5);
    assert_string_equal(get(rt, ":ptr"), "");   /* outside: null */
    assert_string_equal(get(rt, ":ptr;2"), "1");
    size_t before = fl_state_count(rt);
    fl_pointer(rt, 1, true, 0.5, 0.5);   /* the offscreen window has no !pointer */
    fl_pointer_button(rt, 1, 0, true);
    fl_pointer(rt, 9, true, 0.5, 0.5);
    assert_int_equal(fl_state_count(rt), before);
    fl_free(rt);
}

/* {=====================================================================
 * fl_program_files
 * ===================================================================== */

static void check_files(bool simplify)
{
    char inc[256], mod[256], sub[256], main_path[256];
    write_file("inc.fl", "!included\n", inc, sizeof inc);
    write_file("sub.fl", "let h=3\n", sub, sizeof sub);
    write_file("mod.fl", "import h from \"sub.fl\"\nlet f=h+1\n", mod, sizeof mod);
    fl_runtime *rt = load("%include \"inc.fl\"\n"
                          "import f from \"mod.fl\"\n"
                          "!window size=8;8 title=f\n",
                          simplify);
    snprintf(main_path, sizeof main_path, "%s/main.fl", scratch);
    const char *files[8] = {0};
    if (simplify) {   /* literal imports: read while loading */
        assert_int_equal(fl_program_files(rt, files, 8), 4);
    } else {          /* imported when the program runs */
        assert_int_equal(fl_program_files(rt, files, 8), 2);
        assert_int_equal(fl_step(rt), 0);
        assert_int_equal(fl_program_files(rt, files, 8), 4);
    }
    assert_string_equal(files[0], main_path);
    assert_string_equal(files[1], inc);
    assert_string_equal(files[2], mod);
    assert_string_equal(files[3], sub);
    assert_null(files[4]);
    assert_int_equal(fl_program_files(rt, files, 1), 4);   /* the count past [cap] */
    assert_int_equal(fl_step(rt), 0);
    fl_window_info w;
    assert_int_equal(fl_windows(rt, &w, 1), 1);
    assert_string_equal(w.title, "4");   /* the files were really used */
    assert_int_equal(fl_windows(rt, NULL, 0), 1);
    /* a module cached by an earlier run is listed again after a reload */
    assert_int_equal(fl_load(rt, main_path), 0);
    assert_int_equal(fl_step(rt), 0);
    assert_int_equal(fl_program_files(rt, files, 8), 4);
    assert_string_equal(files[3], sub);
    fl_free(rt);

    fl_runtime *empty = fl_new(NULL);
    assert_int_equal(fl_program_files(empty, files, 8), 0);
    fl_free(empty);
}

static void test_program_files(void **st)
{
    (void)st;
    check_files(true);
}

static void test_program_files_nosimplify(void **st)
{
    (void)st;
    check_files(false);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_windows_list),
        cmocka_unit_test(test_title_truncated),
        cmocka_unit_test(test_draw_window_pixels_and_record),
        cmocka_unit_test(test_draw_window_pictures_reused),
        cmocka_unit_test(test_draw_window_errors),
        cmocka_unit_test(test_draw_view),
        cmocka_unit_test(test_view_snapshot),
        cmocka_unit_test(test_view_snapshot_3d),
        cmocka_unit_test(test_keys),
        cmocka_unit_test(test_pointer),
        cmocka_unit_test(test_program_files),
        cmocka_unit_test(test_program_files_nosimplify),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
