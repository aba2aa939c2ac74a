/* test_media_nodes.c: pictures and videos decoded from files, drawn through
 * the render graph: the window nodes !image (lib/render/gl/pass_image.c)
 * and !video (pass_video.c, glsl/video.vert and video.frag), and the
 * canvas's !image and !pattern (lib/render/canvas/canvas.c). Behaviour as
 * Flitter has it (docs/windows.md "!image" and "!video", docs/canvas.md;
 * render/window/image.py, video.py, canvas.pyx and cache.py).
 *
 * The fixtures are made here, in a scratch folder: PNGs written byte by
 * byte (stored deflate blocks, so every pixel is known exactly, alpha
 * included) and a small lossless video (FFV1, RGB) encoded by the ffmpeg
 * command from raw frames written here (run with an argument vector,
 * never a shell). Without the ffmpeg command the video tests are skipped.
 *
 * Pixels come back from fl_draw_window as 0xAARRGGBB: RGB the 8-bit sRGB
 * encoding of premultiplied linear light, A the linear alpha. Every
 * expected value is derived by hand in the comments; a picture's own 8-bit
 * sRGB colours come back within +-1 (the window's 16-bit float light and
 * the sRGB round trip). Only flitter.h is used. */
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <setjmp.h>
#include <spawn.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>
#include <cmocka.h>

#include "flitter.h"

extern char **environ;

static char scratch[64];
static char logged[16384];
static bool have_ffmpeg;

/* {===== helpers */

typedef struct Rgb {
    int r, g, b;
} Rgb;

/* scratch/[name], in one of 8 buffers used in turn. */
static const char *in_scratch(const char *name)
{
    static char paths[8][256];
    static int next;
    char *p = paths[next++ % 8];
    snprintf(p, 256, "%s/%s", scratch, name);
    return p;
}

/* Run [argv] (argv[0] looked up on PATH, stdin and stdout /dev/null); its
 * exit status, -1 when it cannot start. */
static int run(char *const argv[])
{
    pid_t pid;
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&fa, 1, "/dev/null", O_WRONLY, 0);
    int rc = posix_spawnp(&pid, argv[0], &fa, NULL, argv, environ);
    posix_spawn_file_actions_destroy(&fa);
    if (rc != 0) return -1;
    int status;
    while (waitpid(pid, &status, 0) < 0)
        if (errno != EINTR) return -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

static void write_bytes(const char *path, const void *data, size_t n)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(data, 1, n, f), n);
    assert_int_equal(fclose(f), 0);
}

static uint32_t crc32_of(const uint8_t *p, size_t n)
{
    uint32_t c = ~0u;
    for (size_t i = 0; i < n; i++) {
        c ^= p[i];
        for (int k = 0; k < 8; k++) c = c & 1 ? 0xEDB88320u ^ (c >> 1) : c >> 1;
    }
    return ~c;
}

static void put32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)(v >> 24);
    p[1] = (uint8_t)(v >> 16);
    p[2] = (uint8_t)(v >> 8);
    p[3] = (uint8_t)v;
}

/* Append chunk [type] with [n] bytes of [data] to [out] at *[at]. */
static void chunk(uint8_t *out, size_t *at, const char *type, const uint8_t *data, size_t n)
{
    put32(out + *at, (uint32_t)n);
    memcpy(out + *at + 4, type, 4);
    if (n) memcpy(out + *at + 8, data, n);
    put32(out + *at + 8 + n, crc32_of(out + *at + 4, n + 4));
    *at += n + 12;
}

/* A PNG of [w] x [h] 8-bit pixels (colour type [ctype]: 2 RGB, 6 RGBA),
 * rows top first, in one stored deflate block (small pictures only);
 * its length in bytes (the file is also kept in [copy] when given). */
static size_t write_png(const char *path, int w, int h, int ctype, const uint8_t *pixels, uint8_t *copy)
{
    size_t ch = ctype == 2 ? 3 : 4, row = (size_t)w * ch, raw_n = (row + 1) * (size_t)h;
    assert_true(raw_n < 65535);
    uint8_t raw[65535], z[65535 + 16], out[65535 + 128];
    for (int y = 0; y < h; y++) {
        raw[(row + 1) * (size_t)y] = 0;   /* filter: none */
        memcpy(raw + (row + 1) * (size_t)y + 1, pixels + row * (size_t)y, row);
    }
    size_t zi = 0;
    z[zi++] = 0x78;
    z[zi++] = 0x01;
    z[zi++] = 1;   /* the last block, stored */
    z[zi++] = (uint8_t)raw_n;
    z[zi++] = (uint8_t)(raw_n >> 8);
    z[zi++] = (uint8_t)~raw_n;
    z[zi++] = (uint8_t)(~raw_n >> 8);
    memcpy(z + zi, raw, raw_n);
    zi += raw_n;
    uint32_t a = 1, b = 0;
    for (size_t i = 0; i < raw_n; i++) {
        a = (a + raw[i]) % 65521;
        b = (b + a) % 65521;
    }
    put32(z + zi, b << 16 | a);
    zi += 4;
    size_t at = 8;
    memcpy(out, "\x89PNG\r\n\x1a\n", 8);
    uint8_t ihdr[13];
    put32(ihdr, (uint32_t)w);
    put32(ihdr + 4, (uint32_t)h);
    ihdr[8] = 8;
    ihdr[9] = (uint8_t)ctype;
    ihdr[10] = ihdr[11] = ihdr[12] = 0;
    chunk(out, &at, "IHDR", ihdr, 13);
    chunk(out, &at, "IDAT", z, zi);
    chunk(out, &at, "IEND", NULL, 0);
    write_bytes(path, out, at);
    if (copy) memcpy(copy, out, at);
    return at;
}

static void keep_log(void *ctx, int kind, const char *line)
{
    (void)ctx;
    (void)kind;
    size_t n = strlen(logged);
    snprintf(logged + n, sizeof logged - n, "%s\n", line);
}

/* How many times [what] occurs in the log. */
static int logged_times(const char *what)
{
    int n = 0;
    for (const char *p = strstr(logged, what); p; p = strstr(p + 1, what)) n++;
    return n;
}

/* [what] is in the log [times] times (else the log is shown). */
#define expect_logged(what, times) expect_logged_at(what, times, __LINE__)
static void expect_logged_at(const char *what, int times, int line)
{
    int n = logged_times(what);
    if (n != times) fail_msg("line %d: \"%s\" logged %d times, expected %d; the log:\n%s", line, what, n, times, logged);
}

/* A new runtime (logging into `logged`, emptied) with [script] written to
 * scratch/main.fl and loaded: its file names are relative to scratch. */
static fl_runtime *load(const char *script)
{
    const char *path = in_scratch("main.fl");
    write_bytes(path, script, strlen(script));
    logged[0] = '\0';
    fl_options o = fl_default_options();
    o.log = keep_log;
    fl_runtime *rt = fl_new(&o);
    assert_non_null(rt);
    assert_int_equal(fl_load(rt, path), 0);
    return rt;
}

/* Window [index] ([w] x [h]) of [rt]'s last frame into [pix]. */
static void window(fl_runtime *rt, size_t index, int w, int h, uint32_t *pix)
{
    assert_int_equal(fl_draw_window(rt, index, pix, w, h, (size_t)w * 4), 0);
    assert_null(strstr(logged, "no OpenGL"));
}

/* One frame of [script] and its first window ([w] x [h]) into [pix]. */
static void draw(const char *script, int w, int h, uint32_t *pix)
{
    fl_runtime *rt = load(script);
    assert_int_equal(fl_step(rt), 0);
    window(rt, 0, w, h, pix);
    fl_free(rt);
}

static int chan(uint32_t p, int shift) { return (int)((p >> shift) & 0xff); }

/* The window's 8-bit sRGB encoding of linear light [x] (clamped). */
static int srgb(double x)
{
    x = x < 0 ? 0 : x > 1 ? 1 : x;
    double s = x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1 / 2.4) - 0.055;
    return (int)lround(s * 255);
}

/* The linear light of 8-bit sRGB value [v]. */
static double lin(int v)
{
    double s = v / 255.0;
    return s <= 0.04045 ? s / 12.92 : pow((s + 0.055) / 1.055, 2.4);
}

/* The sRGB encoding of [k] of [a] and [1 - k] of [b], mixed in linear light. */
static Rgb mix_linear(Rgb a, Rgb b, double k)
{
    return (Rgb){srgb(k * lin(a.r) + (1 - k) * lin(b.r)), srgb(k * lin(a.g) + (1 - k) * lin(b.g)),
                 srgb(k * lin(a.b) + (1 - k) * lin(b.b))};
}

/* Pixel (x, y) of [pix] ([w] wide) is [want] with alpha [alpha], each
 * channel within [tol]. */
#define expect(pix, w, x, y, want, alpha, tol) expect_at(pix, w, x, y, want, alpha, tol, __LINE__)
static void expect_at(const uint32_t *pix, int w, int x, int y, Rgb want, int alpha, int tol, int line)
{
    uint32_t p = pix[y * w + x];
    int got[4] = {chan(p, 16), chan(p, 8), chan(p, 0), chan(p, 24)}, exp[4] = {want.r, want.g, want.b, alpha};
    for (int k = 0; k < 4; k++)
        if (abs(got[k] - exp[k]) > tol)
            fail_msg("line %d: pixel (%d,%d) is %08x, expected %02x%02x%02x%02x (+-%d)", line, x, y, p, alpha,
                     want.r, want.g, want.b, tol);
}

/* Pixel (x, y) is [want], opaque, within +-1. */
#define opaque(pix, w, x, y, want) expect_at(pix, w, x, y, want, 255, 1, __LINE__)
/* Pixel (x, y) holds nothing. */
#define empty(pix, w, x, y)                                                                                    \
    do {                                                                                                       \
        if ((pix)[(y) * (w) + (x)] != 0)                                                                       \
            fail_msg("line %d: pixel (%d,%d) is %08x, expected nothing", __LINE__, x, y, (pix)[(y) * (w) + (x)]); \
    } while (0)

static bool all_empty(const uint32_t *pix, int n)
{
    for (int i = 0; i < n; i++)
        if (pix[i]) return false;
    return true;
}

/* }===== */

/* {===== fixtures */

/* quad.png: 4x4, opaque, its 2x2 quadrants TL, TR, BL and BR. Colours
 * whose differences are multiples of 4, so that the 3/4 : 1/4 mixes of a
 * bilinear resize to 8x8 are whole numbers. */
static const Rgb TL = {200, 32, 60}, TR = {20, 180, 92}, BL = {92, 60, 228}, BR = {252, 248, 12};
static const Rgb BLACK = {0, 0, 0};

static Rgb quad_at(int x, int y) { return y < 2 ? (x < 2 ? TL : TR) : (x < 2 ? BL : BR); }

/* alpha.png: 2x2 RGBA, straight alpha. */
static const uint8_t ALPHA_PX[16] = {200, 100, 50, 128, 255, 255, 255, 64, 10, 220, 130, 200, 90, 90, 90, 0};

/* video.mkv: 32x16, 4 fps, 8 frames (pts 0, 0.25, ... 1.75 s; 2 s long),
 * FFV1 in RGB (lossless). Every frame: its left quarter (x < 8) colour E,
 * the rest T above (y < 8) and U below; second 0 (frames 0-3) and second
 * 1 (frames 4-7) have different colours. */
#define VW 32
#define VH 16
static const Rgb E0 = {230, 40, 40}, T0 = {40, 200, 60}, U0 = {50, 70, 220};
static const Rgb E1 = {240, 220, 30}, T1 = {200, 40, 220}, U1 = {30, 210, 210};

static int setup(void **st)
{
    (void)st;
    snprintf(scratch, sizeof scratch, "/tmp/test_media_nodes.XXXXXX");
    if (!mkdtemp(scratch)) return -1;
    uint8_t quad[4 * 4 * 3], png[256];
    for (int y = 0; y < 4; y++)
        for (int x = 0; x < 4; x++) {
            Rgb c = quad_at(x, y);
            uint8_t *q = quad + (y * 4 + x) * 3;
            q[0] = (uint8_t)c.r, q[1] = (uint8_t)c.g, q[2] = (uint8_t)c.b;
        }
    size_t n = write_png(in_scratch("quad.png"), 4, 4, 2, quad, png);
    write_png(in_scratch("alpha.png"), 2, 2, 6, ALPHA_PX, NULL);
    /* damaged pictures: text, and quad.png cut off in its image data */
    static const char text[] = "this is not a picture\n";
    write_bytes(in_scratch("text.png"), text, sizeof text - 1);
    write_bytes(in_scratch("cut.png"), png, n / 2);
    write_bytes(in_scratch("text.mkv"), text, sizeof text - 1);

    char *probe[] = {"ffmpeg", "-hide_banner", "-version", NULL};
    have_ffmpeg = run(probe) == 0;
    if (!have_ffmpeg) {
        fprintf(stderr, "test_media_nodes: no ffmpeg command: the !video tests are skipped\n");
        return 0;
    }
    static uint8_t frames[8 * VW * VH * 3];
    for (int f = 0; f < 8; f++)
        for (int y = 0; y < VH; y++)
            for (int x = 0; x < VW; x++) {
                bool one = f >= 4;
                Rgb c = x < 8 ? (one ? E1 : E0) : y < 8 ? (one ? T1 : T0) : (one ? U1 : U0);
                uint8_t *q = frames + ((f * VH + y) * VW + x) * 3;
                q[0] = (uint8_t)c.r, q[1] = (uint8_t)c.g, q[2] = (uint8_t)c.b;
            }
    write_bytes(in_scratch("frames.rgb"), frames, sizeof frames);
    char *enc[] = {"ffmpeg", "-hide_banner", "-loglevel", "error", "-nostdin", "-y", "-f", "rawvideo",
                   "-pix_fmt", "rgb24", "-s", "32x16", "-r", "4", "-i", (char *)in_scratch("frames.rgb"),
                   "-c:v", "ffv1", "-pix_fmt", "bgr0", (char *)in_scratch("video.mkv"), NULL};
    if (run(enc) != 0) {
        fprintf(stderr, "test_media_nodes: ffmpeg cannot make an FFV1 video\n");
        return -1;
    }
    return 0;
}

static int teardown(void **st)
{
    (void)st;
    char *argv[] = {"rm", "-rf", scratch, NULL};
    return run(argv) == 0 ? 0 : -1;
}

/* }===== */

/* {===== the window's !image */

/* The picture at its own size (a 4x4 window): every pixel is the file's
 * colour (the sRGB texture decodes it, the window encodes it again),
 * opaque, and the file's top row is the window's top row (Flitter flips
 * the rows for OpenGL, whose first row is the bottom one). */
static void image_exact(void **st)
{
    (void)st;
    uint32_t pix[16];
    draw("!window size=4;4\n"
         "    !image filename=\"quad.png\"\n", 4, 4, pix);
    expect_logged("\n", 0);
    for (int y = 0; y < 4; y++)
        for (int x = 0; x < 4; x++) opaque(pix, 4, x, y, quad_at(x, y));
}

/* Partial alpha: Flitter converts the picture to PIL's "RGBa", the sRGB
 * values multiplied by alpha (rounded: c * a / 255), and uploads them
 * into an sRGB texture; the window gives those values back with the
 * alpha: 200,100,50 at 128 -> 100,50,25 (100.4, 50.2, 25.1); white at
 * 64 -> 64; 10,220,130 at 200 -> 8,173,102 (7.8, 172.5, 102.0); alpha 0
 * -> nothing. */
static void image_alpha(void **st)
{
    (void)st;
    uint32_t pix[4];
    draw("!window size=2;2\n"
         "    !image filename=\"alpha.png\"\n", 2, 2, pix);
    expect(pix, 2, 0, 0, ((Rgb){100, 50, 25}), 128, 1);
    expect(pix, 2, 1, 0, ((Rgb){64, 64, 64}), 64, 1);
    expect(pix, 2, 0, 1, ((Rgb){8, 173, 102}), 200, 1);
    empty(pix, 2, 1, 1);
    /* each is c * a / 255 of its own pixel, computed */
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 3; k++) {
            int c = ALPHA_PX[i * 4 + k], a = ALPHA_PX[i * 4 + 3];
            int got = chan(pix[i], 16 - 8 * k), want = (int)lround(c * a / 255.0);
            if (abs(got - want) > 1) fail_msg("pixel %d channel %d is %d, expected %d", i, k, got, want);
        }
}

/* The 4x4 picture in a 64x64 window: the window samples it with linear
 * filtering, each picture pixel 16 window pixels wide. Window pixel x
 * samples the picture at (x + 0.5) / 16 pixels, i.e. between the centres
 * of picture pixels floor((x + 0.5) / 16 - 0.5) and the next: from 8 to
 * 23 both are in the left quadrant, so every pixel there is TL exactly.
 * Across the middle, pixel 31 samples 1.46875: 0.46875 of picture pixel 2
 * (TR) and 0.53125 of pixel 1 (TL), mixed in linear light (the texture is
 * sRGB); pixel 32, 0.53125 of TR. */
static void image_scaled(void **st)
{
    (void)st;
    static uint32_t pix[64 * 64];
    draw("!window size=64;64\n"
         "    !image filename=\"quad.png\"\n", 64, 64, pix);
    for (int y = 8; y < 24; y++)
        for (int x = 8; x < 24; x++) {
            opaque(pix, 64, x, y, TL);
            opaque(pix, 64, x + 32, y, TR);
            opaque(pix, 64, x, y + 32, BL);
            opaque(pix, 64, x + 32, y + 32, BR);
        }
    opaque(pix, 64, 31, 16, mix_linear(TL, TR, 0.53125));
    opaque(pix, 64, 32, 16, mix_linear(TL, TR, 0.46875));
    opaque(pix, 64, 16, 32, mix_linear(TL, BL, 0.46875));   /* the same downwards: not flipped */
    opaque(pix, 64, 47, 31, mix_linear(TR, BR, 0.53125));
}

/* size= resizes the picture itself, bilinearly, before it is uploaded
 * (Flitter: PIL's BILINEAR resize of the sRGB values): 4 -> 8, output
 * pixel i samples input i / 2 - 0.25, so pixel 3 is 3/4 of input pixel 1
 * and 1/4 of pixel 2, mixed as sRGB numbers: across TL | TR that is
 * 3/4 (200,32,60) + 1/4 (20,180,92) = (155,69,68); down TL / BL,
 * 3/4 (200,32,60) + 1/4 (92,60,228) = (173,39,102). Row and column 0
 * sample -0.25, the edge pixel alone. An 8x8 window shows the 8x8 picture
 * pixel for pixel.
 *
 * flip= flips it: :vertical top to bottom, :horizontal left to right,
 * :both both (each in a 4x4 window of its own). */
static void image_size_flip(void **st)
{
    (void)st;
    uint32_t pix[64];
    fl_runtime *rt = load("!window size=8;8\n"
                          "    !image filename=\"quad.png\" size=8;8\n"
                          "!window size=4;4\n"
                          "    !image filename=\"quad.png\" flip=:vertical\n"
                          "!window size=4;4\n"
                          "    !image filename=\"quad.png\" flip=:horizontal\n"
                          "!window size=4;4\n"
                          "    !image filename=\"quad.png\" flip=:both\n");
    assert_int_equal(fl_step(rt), 0);
    window(rt, 0, 8, 8, pix);
    opaque(pix, 8, 0, 0, TL);
    opaque(pix, 8, 2, 2, TL);
    opaque(pix, 8, 7, 0, TR);
    opaque(pix, 8, 0, 7, BL);
    opaque(pix, 8, 7, 7, BR);
    opaque(pix, 8, 3, 0, ((Rgb){155, 69, 68}));
    opaque(pix, 8, 4, 0, ((Rgb){65, 143, 84}));    /* 1/4 TL + 3/4 TR */
    opaque(pix, 8, 0, 3, ((Rgb){173, 39, 102}));
    window(rt, 1, 4, 4, pix);
    for (int y = 0; y < 4; y++)
        for (int x = 0; x < 4; x++) opaque(pix, 4, x, y, quad_at(x, 3 - y));
    window(rt, 2, 4, 4, pix);
    for (int y = 0; y < 4; y++)
        for (int x = 0; x < 4; x++) opaque(pix, 4, x, y, quad_at(3 - x, y));
    window(rt, 3, 4, 4, pix);
    for (int y = 0; y < 4; y++)
        for (int x = 0; x < 4; x++) opaque(pix, 4, x, y, quad_at(3 - x, 3 - y));
    expect_logged("\n", 0);
    fl_free(rt);
}

/* A file that is not there, one that is not a picture and one cut off in
 * its image data: each is said once ("image: PATH: REASON"), however many
 * frames ask for it, draws nothing, and the frames go on; a good picture
 * beside them in the same window is drawn. */
static void image_bad_files(void **st)
{
    (void)st;
    uint32_t pix[16];
    fl_runtime *rt = load("!window size=4;4\n"
                          "    !image filename=\"missing.png\"\n"
                          "!window size=4;4\n"
                          "    !image filename=\"text.png\"\n"
                          "!window size=4;4\n"
                          "    !image filename=\"cut.png\"\n"
                          "!window size=4;4\n"
                          "    !image filename=\"missing.png\"\n"
                          "    !image filename=\"quad.png\"\n");
    for (int frame = 0; frame < 3; frame++) {
        assert_int_equal(fl_step(rt), 0);
        for (size_t i = 0; i < 3; i++) {
            window(rt, i, 4, 4, pix);
            if (!all_empty(pix, 16)) fail_msg("frame %d: window %zu drew something", frame, i);
        }
        window(rt, 3, 4, 4, pix);
        for (int y = 0; y < 4; y++)
            for (int x = 0; x < 4; x++) opaque(pix, 4, x, y, quad_at(x, y));
    }
    char line[512];
    snprintf(line, sizeof line, "image: %s: no such file\n", in_scratch("missing.png"));
    expect_logged(line, 1);
    snprintf(line, sizeof line, "image: %s: cannot decode the picture (", in_scratch("text.png"));
    expect_logged(line, 1);
    snprintf(line, sizeof line, "image: %s: cannot decode the picture (", in_scratch("cut.png"));
    expect_logged(line, 1);
    /* three messages, nothing else */
    expect_logged("\n", 3);
    fl_free(rt);
}

/* }===== */

/* {===== the canvas's !image and !pattern */

/* A 64x64 canvas drawing quad.png four ways, and a window node's picture
 * by id; Flitter draws them with Skia's drawImageRect and its default
 * sampling (nearest: every output pixel is one picture pixel, no mixing)
 * onto the rectangle:
 *   A  point=8;8 size=16;16: x and y 8..23, each quadrant 8x8;
 *   B  point=32;0 fit=32;16: the square picture fitted in 32x16 is 16x16,
 *      centred: x 40..55, y 0..15 (x 32..39 and 56..63 stay empty);
 *   C  point=32;24 fill=32;16: the picture cropped to the 2:1 aspect, its
 *      rows 1 and 2 (the middle), onto x 32..63, y 24..39, each picture
 *      pixel 8x8: y 24..31 the top quadrants, 32..39 the bottom ones;
 *   D  image_id=:pic (a hidden !image of quad.png) point=8;40
 *      size=16;16: x 8..23, y 40..55, right side up;
 *   E  a !pattern of quad.png scale=2;2 filling x 32..47, y 48..63: a tile
 *      every 8 pixels from the canvas origin, pixel (x, y) the picture's
 *      pixel (floor((x + 0.5) / 2) mod 4, likewise y);
 * and a missing file, said once as "canvas: PATH: no such file". */
static void canvas_image(void **st)
{
    (void)st;
    static uint32_t pix[64 * 64];
    fl_runtime *rt = load("!window size=64;64\n"
                          "    !image id=:pic filename=\"quad.png\" hidden=true\n"
                          "    !canvas\n"
                          "        !image filename=\"quad.png\" point=8;8 size=16;16\n"
                          "        !image filename=\"quad.png\" point=32;0 fit=32;16\n"
                          "        !image filename=\"quad.png\" point=32;24 fill=32;16\n"
                          "        !image image_id=:pic point=8;40 size=16;16\n"
                          "        !image filename=\"gone.png\" point=0;0 size=8;8\n"
                          "        !group\n"
                          "            !pattern filename=\"quad.png\" scale=2;2\n"
                          "            !rect point=32;48 size=16;16 fill=true\n");
    for (int frame = 0; frame < 2; frame++) {
        assert_int_equal(fl_step(rt), 0);
        window(rt, 0, 64, 64, pix);
        /* A and D: the picture's pixels 4x4 each (nearest: the last row
         * and column of each quadrant too) */
        for (int y = 0; y < 16; y++)
            for (int x = 0; x < 16; x++) {
                opaque(pix, 64, 8 + x, 8 + y, quad_at(x / 4, y / 4));
                opaque(pix, 64, 8 + x, 40 + y, quad_at(x / 4, y / 4));
            }
        empty(pix, 64, 7, 8);
        empty(pix, 64, 24, 8);
        empty(pix, 64, 8, 7);
        empty(pix, 64, 8, 24);
        empty(pix, 64, 7, 40);
        empty(pix, 64, 24, 55);
        empty(pix, 64, 8, 56);
        /* B */
        for (int y = 0; y < 16; y++)
            for (int x = 0; x < 16; x++) opaque(pix, 64, 40 + x, y, quad_at(x / 4, y / 4));
        for (int y = 0; y < 16; y += 5) {
            empty(pix, 64, 32, y);
            empty(pix, 64, 39, y);
            empty(pix, 64, 56, y);
            empty(pix, 64, 63, y);
        }
        /* C */
        for (int y = 0; y < 16; y++)
            for (int x = 0; x < 32; x++) opaque(pix, 64, 32 + x, 24 + y, quad_at(x / 8, y < 8 ? 1 : 2));
        empty(pix, 64, 31, 30);
        empty(pix, 64, 40, 40);
        empty(pix, 64, 40, 23);
        /* E */
        for (int y = 48; y < 64; y++)
            for (int x = 32; x < 48; x++) opaque(pix, 64, x, y, quad_at(x / 2 % 4, y / 2 % 4));
        empty(pix, 64, 31, 50);
        empty(pix, 64, 48, 50);
        /* the missing file draws nothing; the hidden !image is not
         * composited into the window (it would show at (30,45)) */
        empty(pix, 64, 2, 2);
        empty(pix, 64, 30, 45);
    }
    char line[512];
    snprintf(line, sizeof line, "canvas: %s: no such file\n", in_scratch("gone.png"));
    expect_logged(line, 1);
    expect_logged("\n", 1);
    fl_free(rt);
}

/* }===== */

/* {===== the window's !video */

#define NEED_FFMPEG()                                                                                         \
    do {                                                                                                      \
        if (!have_ffmpeg) {                                                                                   \
            print_message("no ffmpeg command: skipped\n");                                                    \
            skip();                                                                                           \
        }                                                                                                     \
    } while (0)

/* Window [index] (64x32: the 32x16 video stretched 2x) shows second
 * [second]'s colours, right side up: window pixel (x, y) samples video
 * pixel ((x + 0.5) / 2, (y + 0.5) / 2), so x < 15 is E, x >= 17 T above
 * row 15 and U below row 16 (away from the linear mixes at the edges). */
static void expect_second(fl_runtime *rt, size_t index, int second, const char *what)
{
    static uint32_t pix[64 * 32];
    window(rt, index, 64, 32, pix);
    Rgb e = second ? E1 : E0, t = second ? T1 : T0, u = second ? U1 : U0;
    static const int probe[][2] = {{2, 2}, {12, 28}, {20, 2}, {60, 13}, {20, 18}, {60, 30}};
    for (int i = 0; i < 6; i++) {
        int x = probe[i][0], y = probe[i][1];
        Rgb want = x < 15 ? e : y < 15 ? t : u;
        uint32_t p = pix[y * 64 + x];
        int got[4] = {chan(p, 16), chan(p, 8), chan(p, 0), chan(p, 24)}, exp[4] = {want.r, want.g, want.b, 255};
        for (int k = 0; k < 4; k++)
            if (abs(got[k] - exp[k]) > 2)
                fail_msg("%s (window %zu): pixel (%d,%d) is %08x, expected ff%02x%02x%02x (second %d)", what, index,
                         x, y, p, want.r, want.g, want.b, second);
    }
}

/* position= picks the last frame at or before it (frames every 0.25 s);
 * without loop= a position past the end is clamped to the end (2 s: the
 * last frame, second 1's) and one before the start to the start. */
static void video_position(void **st)
{
    (void)st;
    NEED_FFMPEG();
    static const struct {
        const char *pos;
        int second;
    } cases[] = {{"0", 0}, {"0.5", 0}, {"0.99", 0}, {"1", 1}, {"1.5", 1}, {"1.99", 1}, {"5", 1}, {"-1", 0}};
    char script[4096] = "";
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        size_t n = strlen(script);
        snprintf(script + n, sizeof script - n, "!window size=64;32\n    !video filename=\"video.mkv\" position=%s\n",
                 cases[i].pos);
    }
    /* decoding on several threads gives the same frames */
    strcat(script, "!window size=64;32\n    !video filename=\"video.mkv\" position=1.25 thread=true\n");
    fl_runtime *rt = load(script);
    assert_int_equal(fl_step(rt), 0);
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        char what[64];
        snprintf(what, sizeof what, "position=%s", cases[i].pos);
        expect_second(rt, i, cases[i].second, what);
    }
    expect_second(rt, sizeof cases / sizeof *cases, 1, "thread=true position=1.25");
    expect_logged("\n", 0);
    fl_free(rt);
}

/* loop=true wraps the position around the 2 s: 2.5 -> 0.5, 3.5 -> 1.5,
 * -0.5 -> 1.5 (negative ones from the end); with back_and_forth=true
 * every other pass runs backwards: 2.5 -> 2 - 0.5 = 1.5, 3.25 -> 0.75,
 * 4.5 -> 0.5 (forwards again). trim=START;END cuts the ends off first:
 * trim=1;0 maps position 0.25 to 1.25; trim=0;1 with loop wraps around
 * the first second alone: 1.5 -> 0.5. */
static void video_loop_trim(void **st)
{
    (void)st;
    NEED_FFMPEG();
    static const struct {
        const char *attrs;
        int second;
    } cases[] = {
        {"position=2.5 loop=true", 0},
        {"position=3.5 loop=true", 1},
        {"position=-0.5 loop=true", 1},
        {"position=3.25 loop=true", 1},
        {"position=2.5 loop=true back_and_forth=true", 1},
        {"position=3.25 loop=true back_and_forth=true", 0},
        {"position=4.5 loop=true back_and_forth=true", 0},
        {"position=2.5", 1},                              /* without loop: the end */
        {"position=0.25 trim=1;0", 1},
        {"position=1.5 trim=0;1 loop=true", 0},
        {"position=1.5 loop=true", 1},                    /* untrimmed */
    };
    char script[4096] = "";
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        size_t n = strlen(script);
        snprintf(script + n, sizeof script - n, "!window size=64;32\n    !video filename=\"video.mkv\" %s\n",
                 cases[i].attrs);
    }
    fl_runtime *rt = load(script);
    assert_int_equal(fl_step(rt), 0);
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) expect_second(rt, i, cases[i].second, cases[i].attrs);
    expect_logged("\n", 0);
    fl_free(rt);
}

/* Playing: position=time in one runtime, frame after frame (lockstep at
 * 60 fps, each frame exact): the first frames show second 0, from
 * time 1 on second 1, and with loop=true past 2 s second 0 again. */
static void video_playing(void **st)
{
    (void)st;
    NEED_FFMPEG();
    fl_runtime *rt = load("!window size=64;32\n"
                          "    !video filename=\"video.mkv\" position=time*3 loop=true\n");
    for (int frame = 0; frame < 60; frame++) {
        assert_int_equal(fl_step(rt), 0);
        double t = fl_frame_time(rt) * 3;
        /* the frame at or before t (away from the steps) */
        double in = fmod(t, 2);
        if (fabs(in - 1) < 0.3 || in < 0.3 || in > 1.7) continue;
        char what[64];
        snprintf(what, sizeof what, "position=%.3f", t);
        expect_second(rt, 0, in >= 1, what);
    }
    expect_logged("\n", 0);
    fl_free(rt);
}

/* interpolate=true mixes the frames around the position by how far it is
 * between them: 0.875 is half way from frame 3 (0.75, second 0) to frame
 * 4 (1.0, second 1): half of each, in linear light (sRGB textures);
 * without it, frame 3 alone. alpha=0.5 halves the light and the alpha. */
static void video_interpolate_alpha(void **st)
{
    (void)st;
    NEED_FFMPEG();
    static uint32_t pix[64 * 32];
    fl_runtime *rt = load("!window size=64;32\n"
                          "    !video filename=\"video.mkv\" position=0.875 interpolate=true\n"
                          "!window size=64;32\n"
                          "    !video filename=\"video.mkv\" position=0.875\n"
                          "!window size=64;32\n"
                          "    !video filename=\"video.mkv\" position=1.5 alpha=0.5\n");
    assert_int_equal(fl_step(rt), 0);
    window(rt, 0, 64, 32, pix);
    expect(pix, 64, 4, 4, mix_linear(E0, E1, 0.5), 255, 2);
    expect(pix, 64, 40, 4, mix_linear(T0, T1, 0.5), 255, 2);
    expect(pix, 64, 40, 28, mix_linear(U0, U1, 0.5), 255, 2);
    expect_second(rt, 1, 0, "position=0.875 without interpolate");
    window(rt, 2, 64, 32, pix);
    /* half the light of T1 (200,40,220): 0.5 * linear, encoded */
    expect(pix, 64, 40, 4, mix_linear(T1, BLACK, 0.5), 128, 2);
    expect(pix, 64, 4, 28, mix_linear(E1, BLACK, 0.5), 128, 2);
    expect_logged("\n", 0);
    fl_free(rt);
}

/* aspect= (video.frag): the 2:1 video in a window of another shape.
 *   :fit in 64x16 (4:1): scaled to the window's height, 32x16, centred:
 *     window x 16..47 is video x 0..31 pixel for pixel (x 16..23 E,
 *     24..47 T in rows 0..7, U in 8..15); outside it the frame samples
 *     nothing (Flitter's samplers: a transparent border).
 *   :fill in 32x32: scaled to the height, 64x32, centred: window pixel x
 *     shows video x (x + 16.5) / 2, 8.25 .. 23.75: the E quarter is cut
 *     off (all but a quarter of it at x = 0); y 0..15 T, 16..31 U.
 *   no aspect= in 32x32: stretched, video x (x + 0.5): E for x < 7
 *     (rows 1..30: rows 0 and 31 are half border). */
static void video_aspect(void **st)
{
    (void)st;
    NEED_FFMPEG();
    static uint32_t pix[64 * 32];
    fl_runtime *rt = load("!window size=64;16\n"
                          "    !video filename=\"video.mkv\" position=0.5 aspect=:fit\n"
                          "!window size=32;32\n"
                          "    !video filename=\"video.mkv\" position=0.5 aspect=:fill\n"
                          "!window size=32;32\n"
                          "    !video filename=\"video.mkv\" position=0.5\n");
    assert_int_equal(fl_step(rt), 0);
    window(rt, 0, 64, 16, pix);
    for (int y = 0; y < 16; y++) {
        empty(pix, 64, 0, y);
        empty(pix, 64, 15, y);
        empty(pix, 64, 48, y);
        empty(pix, 64, 63, y);
        expect(pix, 64, 16, y, E0, 255, 2);
        expect(pix, 64, 22, y, E0, 255, 2);
        expect(pix, 64, 25, y, y < 8 ? T0 : U0, 255, 2);
        expect(pix, 64, 47, y, y < 8 ? T0 : U0, 255, 2);
    }
    window(rt, 1, 32, 32, pix);
    for (int x = 1; x < 32; x += 3) {
        expect(pix, 32, x, 2, T0, 255, 2);
        expect(pix, 32, x, 29, U0, 255, 2);
    }
    expect(pix, 32, 0, 2, mix_linear(E0, T0, 0.25), 255, 2);
    window(rt, 2, 32, 32, pix);
    for (int y = 1; y < 31; y += 3) expect(pix, 32, 3, y, E0, 255, 2);
    expect(pix, 32, 20, 2, T0, 255, 2);
    expect(pix, 32, 20, 29, U0, 255, 2);
    expect_logged("\n", 0);
    fl_free(rt);
}

/* A missing video and one that is not a video: said once each ("video:
 * PATH: REASON") over several frames, nothing drawn, the frames go on;
 * the good video beside them plays. */
static void video_bad_files(void **st)
{
    (void)st;
    NEED_FFMPEG();
    uint32_t pix[64 * 32];
    fl_runtime *rt = load("!window size=64;32\n"
                          "    !video filename=\"missing.mkv\" position=0.5\n"
                          "!window size=64;32\n"
                          "    !video filename=\"text.mkv\" position=0.5\n"
                          "!window size=64;32\n"
                          "    !video filename=\"missing.mkv\" position=0.5\n"
                          "    !video filename=\"video.mkv\" position=1.5\n");
    for (int frame = 0; frame < 3; frame++) {
        assert_int_equal(fl_step(rt), 0);
        for (size_t i = 0; i < 2; i++) {
            window(rt, i, 64, 32, pix);
            if (!all_empty(pix, 64 * 32)) fail_msg("frame %d: window %zu drew something", frame, i);
        }
        expect_second(rt, 2, 1, "beside a missing video");
    }
    char line[512];
    snprintf(line, sizeof line, "video: %s: no such file\n", in_scratch("missing.mkv"));
    expect_logged(line, 1);
    snprintf(line, sizeof line, "video: %s: not a video", in_scratch("text.mkv"));
    expect_logged(line, 1);
    expect_logged("\n", 2);
    fl_free(rt);
}

/* }===== */

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(image_exact),
        cmocka_unit_test(image_alpha),
        cmocka_unit_test(image_scaled),
        cmocka_unit_test(image_size_flip),
        cmocka_unit_test(image_bad_files),
        cmocka_unit_test(canvas_image),
        cmocka_unit_test(video_position),
        cmocka_unit_test(video_loop_trim),
        cmocka_unit_test(video_playing),
        cmocka_unit_test(video_interpolate_alpha),
        cmocka_unit_test(video_aspect),
        cmocka_unit_test(video_bad_files),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
