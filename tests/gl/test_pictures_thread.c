/* test_pictures_thread.c: pictures drawn beside the frame loop
 * (flitter.h, fl_picture_take; the live window's drawing thread, issue
 * 58): a runtime's frame N drawn on a thread of its own while its frame
 * N+1 is stepped gives the very pixels of frame N drawn in turn
 * (fl_draw_window) by a second runtime of the same script: a lit,
 * bloomed 3D scene of a sphere, a box and a !model of vertices moving
 * with the frame, a !shader reading engine names, state and a symbol,
 * and a 2D canvas. Also: which frames are not handed over (before the
 * first, before the windows are shown, a tree with a function), and
 * fl_outputs_draws. Run under ThreadSanitizer by tests/tsan.sh. Only
 * flitter.h is used. */
#include <pthread.h>
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

#define W 48
#define H 48
#define FRAMES 12

static char logged[8192];
static pthread_mutex_t log_lock = PTHREAD_MUTEX_INITIALIZER;

static void keep_log(void *ctx, int kind, const char *line)
{
    (void)ctx;
    if (kind == FL_LOG_DEBUG) return;
    pthread_mutex_lock(&log_lock);
    size_t n = strlen(logged);
    snprintf(logged + n, sizeof logged - n, "%s\n", line);
    pthread_mutex_unlock(&log_lock);
}

static const char scene[] =
    "%pragma tempo 60\n"
    "let frag = '''${HEADER}\n"
    "in vec2 coord;\n"
    "out vec4 color;\n"
    "uniform float beat;\n"
    "uniform float level;\n"
    "uniform float mode;\n"
    "void main() {\n"
    "    color = vec4(fract(beat), level, mode == 0.0 ? 1.0 : 0.5, 1.0) * (coord.x < 0.25 ? 1.0 : 0.0);\n"
    "}\n"
    "'''\n"
    "!counter state=:t rate=3\n"
    "!window size=48;48\n"
    "    !bloom radius=3\n"
    "        !canvas3d viewpoint=0;0;5 samples=1 max_lights=4\n"
    "            !light color=0.5 direction=0;0;-1\n"
    "            !light color=2;1;0.5 position=sin(frame/7);0;1 radius=0.2\n"
    "            !sphere position=frame/10-0.6;0.2;0 size=0.6 color=0.8;0.2;0.2\n"
    "            !box size=0.5 position=0;(frame%5)/5-0.5;0 color=0.2;0.2;1 roughness=0.3\n"
    "            !model vertices=0;0;0;1;0;0;0;1;0 faces=0;1;2 position=-1.2;-1;0 color=0;1;0\n"
    "    !shader fragment=frag level=($(:t) or 0)/10 mode=:add\n"
    "    !canvas\n"
    "        !rect point=frame*3;30 size=10;10\n"
    "        !fill color=1;1;0\n";

static fl_runtime *load(const char *text)
{
    fl_options o = fl_default_options();
    o.log = keep_log;
    fl_runtime *rt = fl_new(&o);
    assert_non_null(rt);
    assert_int_equal(fl_load_text(rt, "scene.fl", text, strlen(text)), 0);
    return rt;
}

/* The drawing thread of pictures_beside_frames: reads back each picture
 * it is handed, while the test's thread steps the next frame. */
typedef struct Drawer {
    pthread_mutex_t mu;
    pthread_cond_t cond;
    fl_runtime *rt;
    fl_picture *pic;     /* handed over; NULL when done with it */
    bool stop;
    uint32_t (*pix)[W * H];
    int rc[FRAMES];
    long frame[FRAMES];
    int drawn;
} Drawer;

static void *drawer(void *arg)
{
    Drawer *d = arg;
    pthread_mutex_lock(&d->mu);
    for (;;) {
        while (!d->pic && !d->stop) pthread_cond_wait(&d->cond, &d->mu);
        if (!d->pic) break;
        fl_picture *pic = d->pic;
        int k = d->drawn;
        pthread_mutex_unlock(&d->mu);
        d->frame[k] = fl_picture_frame(pic);
        d->rc[k] = fl_picture_read(d->rt, pic, 0, d->pix[k], W, H, W * 4);
        pthread_mutex_lock(&d->mu);
        d->drawn++;
        d->pic = NULL;
        pthread_cond_broadcast(&d->cond);
    }
    pthread_mutex_unlock(&d->mu);
    return NULL;
}

static void pictures_beside_frames(void **st)
{
    (void)st;
    static uint32_t ref[FRAMES][W * H], got[FRAMES][W * H];
    logged[0] = '\0';
    /* the reference: each frame stepped, then drawn */
    fl_runtime *b = load(scene);
    for (int k = 0; k < FRAMES; k++) {
        assert_int_equal(fl_step(b), 0);
        assert_int_equal(fl_draw_window(b, 0, ref[k], W, H, W * 4), 0);
    }
    fl_free(b);
    /* frame 0 drawn in turn (the windows shown), then each frame drawn by
     * the drawer while the next is stepped */
    fl_runtime *a = load(scene);
    assert_int_equal(fl_step(a), 0);
    assert_int_equal(fl_draw_window(a, 0, got[0], W, H, W * 4), 0);
    Drawer d = {.rt = a, .pix = got + 1};
    pthread_mutex_init(&d.mu, NULL);
    pthread_cond_init(&d.cond, NULL);
    pthread_t t;
    assert_int_equal(pthread_create(&t, NULL, drawer, &d), 0);
    assert_int_equal(fl_step(a), 0);
    for (int k = 1; k < FRAMES; k++) {
        fl_picture *pic = fl_picture_take(a);
        assert_non_null(pic);
        assert_int_equal(fl_picture_frame(pic), k);
        pthread_mutex_lock(&d.mu);
        d.pic = pic;
        pthread_cond_broadcast(&d.cond);
        pthread_mutex_unlock(&d.mu);
        if (k + 1 < FRAMES) assert_int_equal(fl_step(a), 0);   /* beside the drawing */
        pthread_mutex_lock(&d.mu);
        while (d.pic) pthread_cond_wait(&d.cond, &d.mu);
        pthread_mutex_unlock(&d.mu);
        fl_picture_free(a, pic);
    }
    pthread_mutex_lock(&d.mu);
    d.stop = true;
    pthread_cond_broadcast(&d.cond);
    pthread_mutex_unlock(&d.mu);
    pthread_join(t, NULL);
    fl_free(a);
    if (logged[0]) fail_msg("unexpected log:\n%s", logged);
    for (int k = 1; k < FRAMES; k++) {
        assert_int_equal(d.rc[k - 1], 0);
        assert_int_equal(d.frame[k - 1], k);
    }
    for (int k = 0; k < FRAMES; k++)
        for (int i = 0; i < W * H; i++)
            if (got[k][i] != ref[k][i])
                fail_msg("frame %d pixel (%d,%d): %08x drawn beside the next frame, %08x in turn", k, i % W,
                         i / W, got[k][i], ref[k][i]);
    /* the pictures are not empty, and move: the canvas's yellow square
     * (x = 3 frame .. 3 frame + 10) and the shader's strip on the left */
    for (int k = 0; k < FRAMES; k += 5) {
        uint32_t sq = ref[k][35 * W + 3 * k + 5];
        if ((sq & 0x00ffff00u) != 0x00ffff00u) fail_msg("frame %d: no yellow square (%08x)", k, sq);
    }
    if ((ref[4][24 * W + 2] >> 24) != 0xff) fail_msg("no shader strip: %08x", ref[4][24 * W + 2]);
    if (memcmp(ref[2], ref[9], sizeof ref[2]) == 0) fail_msg("frames 2 and 9 are the same picture");
}

/* Frames that are not handed over: before the first frame, before the
 * windows are shown, and, from the first frame whose windows hold a
 * function (an SDF's `function=`, called while it is drawn, and kept with
 * its model by the graph), every frame, whether that frame was taken or
 * drawn in turn. */
static void frames_drawn_in_turn(void **st)
{
    (void)st;
    logged[0] = '\0';
    fl_runtime *rt = load("!window size=16;16\n    !canvas\n        !rect point=0;0 size=8;8\n"
                          "        !fill color=1\n");
    assert_null(fl_picture_take(rt));                 /* no frame yet */
    assert_int_equal(fl_step(rt), 0);
    assert_null(fl_picture_take(rt));                 /* windows not shown yet */
    uint32_t pix[16 * 16];
    assert_int_equal(fl_draw_window(rt, 0, pix, 16, 16, 64), 0);
    fl_picture *pic = fl_picture_take(rt);
    assert_non_null(pic);
    assert_int_equal(fl_picture_read(rt, pic, 1, pix, 16, 16, 64), -1);   /* no window 1 */
    assert_int_equal(fl_picture_read(rt, pic, 0, pix, 8, 16, 64), -1);    /* not its size */
    assert_int_equal(fl_picture_read(rt, pic, 0, NULL, 16, 16, 64), -1);
    assert_int_equal(fl_picture_read(rt, pic, 0, pix, 16, 16, 60), -1);
    assert_int_equal(fl_picture_read(rt, pic, 0, pix, 16, 16, 64), 0);
    assert_int_equal(pix[0], 0xffffffffu);
    assert_int_equal(pix[15 * 16 + 15], 0);
    fl_picture_free(rt, pic);
    fl_free(rt);

    const char *sdf = "func ball(p)\n    hypot(p) - 0.5\n"
                      "!window size=16;16\n    !canvas3d viewpoint=0;0;3\n"
                      "        !light color=1 direction=0;0;-1\n"
                      "        if frame == 1\n"
                      "            !sdf function=ball resolution=0.1\n";
    rt = load(sdf);
    assert_int_equal(fl_step(rt), 0);
    assert_int_equal(fl_draw_window(rt, 0, pix, 16, 16, 64), 0);
    pic = fl_picture_take(rt);
    assert_non_null(pic);                             /* frame 0: no function */
    fl_picture_free(rt, pic);
    assert_int_equal(fl_step(rt), 0);
    assert_null(fl_picture_take(rt));                 /* frame 1: ball */
    assert_int_equal(fl_step(rt), 0);
    assert_null(fl_picture_take(rt));                 /* and from then on */
    fl_free(rt);
    /* the same when the frame with the function is drawn in turn (its
     * model, and the function, kept by the graph) and never taken */
    rt = load(sdf);
    assert_int_equal(fl_step(rt), 0);
    assert_int_equal(fl_draw_window(rt, 0, pix, 16, 16, 64), 0);
    assert_int_equal(fl_step(rt), 0);
    assert_int_equal(fl_draw_window(rt, 0, pix, 16, 16, 64), 0);   /* frame 1: ball */
    assert_int_equal(fl_step(rt), 0);
    assert_null(fl_picture_take(rt));                 /* frame 2, without it */
    fl_free(rt);
    if (logged[0]) fail_msg("unexpected log:\n%s", logged);
    assert_null(fl_picture_take(NULL));
    assert_int_equal(fl_picture_draw(NULL, NULL), -1);
    assert_int_equal(fl_picture_frame(NULL), -1);
    fl_picture_free(NULL, NULL);
}

/* fl_outputs_draws: true for the frame whose !record writes a file alone
 * (the windows shown); headless, with no window shown, a !record draws
 * every frame. */
static void outputs_draws(void **st)
{
    (void)st;
    char dir[64];
    snprintf(dir, sizeof dir, "/tmp/test_pictures_thread.XXXXXX");
    assert_non_null(mkdtemp(dir));
    char text[512], png[128];
    snprintf(png, sizeof png, "%s/rec.png", dir);
    snprintf(text, sizeof text,
             "!window size=16;16\n    !record filename=(\"%s\" if frame == 3 else null)\n"
             "        !canvas\n            !rect point=0;0 size=8;8\n            !fill color=1\n",
             png);
    for (int shown = 0; shown < 2; shown++) {
        logged[0] = '\0';
        fl_runtime *rt = load(text);
        fl_outputs *out = fl_outputs_open(rt, NULL);
        assert_non_null(out);
        assert_false(fl_outputs_draws(out, rt));     /* no frame yet */
        uint32_t pix[16 * 16];
        for (int k = 0; k < 5; k++) {
            assert_int_equal(fl_step(rt), 0);
            if (shown && k == 0) assert_int_equal(fl_draw_window(rt, 0, pix, 16, 16, 64), 0);
            bool draws = fl_outputs_draws(out, rt);
            if (draws != (!shown || k == 3)) fail_msg("shown %d, frame %d: fl_outputs_draws %d", shown, k, draws);
            assert_int_equal(fl_outputs_frame(out, rt), 0);
        }
        assert_int_equal(access(png, F_OK), 0);
        unlink(png);
        assert_int_equal(fl_outputs_close(out, rt), 0);
        fl_free(rt);
        if (logged[0]) fail_msg("unexpected log:\n%s", logged);
    }
    assert_false(fl_outputs_draws(NULL, NULL));
    rmdir(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(pictures_beside_frames),
        cmocka_unit_test(frames_drawn_in_turn),
        cmocka_unit_test(outputs_draws),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
