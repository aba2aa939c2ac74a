/* test_media.c: pictures and videos decoded from files (lib/render/media,
 * media.h). The fixtures are made here, in a scratch folder: PNGs written
 * byte by byte (stored deflate blocks, so every pixel is known exactly,
 * alpha included), and JPEGs, BMPs and videos made by the ffmpeg command
 * (run with an argument vector, never a shell). The videos' frames are
 * flat grey N*8 in their top 16 rows (frame N, 10 per second) over noise,
 * so the frame a call gives is read off its pixels.
 *
 * FFmpeg cannot be loaded under valgrind (avlib.h), so this test is in
 * its own suite (`media`), run once in CI's gcc phase. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <pthread.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "media.h"
#include "mem.h"

extern char **environ;

static char scratch[64];
static bool have_ffmpeg;

/* {===== helpers */

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* scratch/[name], in one of 8 buffers used in turn (main thread only). */
static const char *in_scratch(const char *name)
{
    static char paths[8][256];
    static int next;
    char *p = paths[next++ % 8];
    snprintf(p, 256, "%s/%s", scratch, name);
    return p;
}

/* Run [argv] (argv[0] looked up on PATH); its exit status, -1 when it
 * cannot start. */
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

/* ffmpeg -loglevel error -nostdin -y ARGS... */
static void ffmpeg(const char *const *args)
{
    char *argv[64] = {"ffmpeg", "-hide_banner", "-loglevel", "error", "-nostdin", "-y"};
    int n = 6;
    for (int i = 0; args[i]; i++) argv[n++] = (char *)args[i];
    argv[n] = NULL;
    assert_int_equal(run(argv), 0);
}

static void write_bytes(const char *path, const void *data, size_t n)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(data, 1, n, f), n);
    assert_int_equal(fclose(f), 0);
}

static uint8_t *read_bytes(const char *path, size_t *n)
{
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    fseek(f, 0, SEEK_END);
    *n = (size_t)ftell(f);
    fseek(f, 0, SEEK_SET);
    uint8_t *p = malloc(*n);
    assert_non_null(p);
    assert_int_equal(fread(p, 1, *n, f), *n);
    fclose(f);
    return p;
}

/* The first [keep] bytes of [from] into [to]. */
static void truncated_copy(const char *from, const char *to, double keep)
{
    size_t n;
    uint8_t *p = read_bytes(from, &n);
    write_bytes(to, p, (size_t)((double)n * keep));
    free(p);
}

static uint32_t crc32_of(const uint8_t *p, size_t n, uint32_t c)
{
    c = ~c;
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
    put32(out + *at + 8 + n, crc32_of(out + *at + 4, n + 4, 0));
    *at += n + 12;
}

/* A PNG of [w] x [h] 8-bit pixels of colour type [ctype] (0 grey, 2 RGB,
 * 6 RGBA), rows top first, its image data in stored (uncompressed)
 * deflate blocks. */
static void write_png(const char *path, int w, int h, int ctype, const uint8_t *pixels)
{
    int ch = ctype == 0 ? 1 : ctype == 2 ? 3 : 4;
    size_t row = (size_t)w * (size_t)ch, raw_n = (row + 1) * (size_t)h;
    uint8_t *raw = malloc(raw_n);
    for (int y = 0; y < h; y++) {
        raw[(row + 1) * (size_t)y] = 0;   /* filter: none */
        memcpy(raw + (row + 1) * (size_t)y + 1, pixels + row * (size_t)y, row);
    }
    size_t nblocks = raw_n / 65535 + 1, z_n = 2 + raw_n + nblocks * 5 + 4;
    uint8_t *z = malloc(z_n);
    size_t zi = 0;
    z[zi++] = 0x78;
    z[zi++] = 0x01;
    uint32_t a = 1, b = 0;
    for (size_t i = 0; i < raw_n; i++) {
        a = (a + raw[i]) % 65521;
        b = (b + a) % 65521;
    }
    for (size_t off = 0, k = 0; k < nblocks; k++) {
        size_t len = raw_n - off < 65535 ? raw_n - off : 65535;
        z[zi++] = k + 1 == nblocks;
        z[zi++] = (uint8_t)len;
        z[zi++] = (uint8_t)(len >> 8);
        z[zi++] = (uint8_t)~len;
        z[zi++] = (uint8_t)(~len >> 8);
        memcpy(z + zi, raw + off, len);
        zi += len;
        off += len;
    }
    put32(z + zi, b << 16 | a);
    zi += 4;
    uint8_t *out = malloc(zi + 64);
    size_t at = 0;
    memcpy(out, "\x89PNG\r\n\x1a\n", 8);
    at = 8;
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
    free(out);
    free(z);
    free(raw);
}

/* Give [path] a modification time [sec] seconds after the epoch, so that
 * a rewrite within one clock tick still counts as a change. */
static void set_mtime(const char *path, time_t sec)
{
    struct timespec t[2] = {{sec, 0}, {sec, 0}};
    assert_int_equal(utimensat(AT_FDCWD, path, t, 0), 0);
}

/* }===== */

/* {===== fixtures */

static const char *VIDEO = "frames.mkv";         /* 64x48, 10 fps, 30 frames, grey N*8 on top */
static const char *VIDEO_MP4 = "frames.mp4";     /* the same, MP4 with its index first */
static const char *LONG_VIDEO = "long.mkv";      /* 640x360, 25 fps, 250 frames, one key frame */

static int setup(void **st)
{
    (void)st;
    snprintf(scratch, sizeof scratch, "/tmp/test_media.XXXXXX");
    if (!mkdtemp(scratch)) return -1;
    char *probe[] = {"ffmpeg", "-hide_banner", "-version", NULL};
    have_ffmpeg = run(probe) == 0;
    if (!have_ffmpeg) {
        fprintf(stderr, "test_media: no ffmpeg command: the JPEG, BMP and video tests are skipped\n");
        return 0;
    }
    /* frame N: rows 0-15 grey N*8, the rest noise (so that the file is
     * big enough to cut); key frames every 5, B-frames (reordered) */
    const char *src = "color=black:s=64x48:r=10:d=3,format=gray,geq=lum='if(lt(Y\\,16)\\,N*8\\,random(1)*255)'";
    const char *mkv[] = {"-f", "lavfi", "-i", src, "-c:v", "mpeg4", "-q:v", "2", "-g", "5", "-bf", "2",
                         "-pix_fmt", "yuv420p", in_scratch(VIDEO), NULL};
    ffmpeg(mkv);
    const char *mp4[] = {"-f", "lavfi", "-i", src, "-c:v", "mpeg4", "-q:v", "2", "-g", "5", "-bf", "2",
                         "-pix_fmt", "yuv420p", "-movflags", "+faststart", in_scratch(VIDEO_MP4), NULL};
    ffmpeg(mp4);
    /* frame N: N % 16 * 16 in the first 16x16 block, N / 16 * 16 in the next */
    const char *longsrc = "color=black:s=640x360:r=25:d=10,format=gray,"
                          "geq=lum='if(lt(Y\\,16)\\,if(lt(X\\,16)\\,mod(N\\,16)*16\\,if(lt(X\\,32)\\,floor(N/16)*16\\,0))\\,0)'";
    const char *lng[] = {"-f", "lavfi", "-i", longsrc, "-c:v", "mpeg4", "-q:v", "2", "-g", "1000", "-bf", "0",
                         "-pix_fmt", "yuv420p", in_scratch(LONG_VIDEO), NULL};
    ffmpeg(lng);
    return 0;
}

static int teardown(void **st)
{
    (void)st;
    char *argv[] = {"rm", "-rf", scratch, NULL};
    return run(argv) == 0 ? 0 : -1;
}

/* }===== */

/* {===== pictures */

/* A 4x3 RGBA picture: every pixel different, alpha 0, 1, 128, 254, 255. */
static void rgba_4x3(uint8_t *p)
{
    for (int i = 0; i < 12; i++) {
        p[i * 4 + 0] = (uint8_t)(i * 20 + 3);
        p[i * 4 + 1] = (uint8_t)(250 - i * 17);
        p[i * 4 + 2] = (uint8_t)(i * i);
        p[i * 4 + 3] = (uint8_t)(i == 0 ? 0 : i == 1 ? 1 : i == 2 ? 128 : i == 3 ? 254 : 255 - i);
    }
}

static void test_png_exact(void **st)
{
    (void)st;
    uint8_t px[48];
    rgba_4x3(px);
    const char *path = in_scratch("rgba.png");
    write_png(path, 4, 3, 6, px);
    MemBudget b = {0};
    MediaCache *m = media_cache_new(&b, NULL);
    Buf err = BUF_INIT;
    bool fresh = true;
    const MediaImage *im = media_image(m, path, 0, 0, &err, &fresh);
    if (!im) fprintf(stderr, "%s", buf_cstr(&err));
    assert_non_null(im);
    assert_false(fresh);
    assert_string_equal(buf_cstr(&err), "");
    assert_int_equal(im->w, 4);
    assert_int_equal(im->h, 3);
    assert_memory_equal(im->rgba, px, 48);   /* straight alpha, top row first, exact */
    assert_true(im->version != 0);
    assert_int_equal(b.used, 48);             /* the held pixels are charged */
    uint64_t version = im->version;
    /* asked again: the same picture, not decoded again */
    const MediaImage *again = media_image(m, path, 4, 3, &err, NULL);
    assert_ptr_equal(again, im);
    assert_int_equal(again->version, version);
    assert_int_equal(b.used, 48);
    media_cache_free(m);
    assert_int_equal(b.used, 0);
    buf_free(&err);
}

static void test_png_opaque(void **st)
{
    (void)st;
    /* RGB and grey PNGs: no alpha in the file, so 255 */
    uint8_t rgb[2 * 2 * 3] = {255, 0, 0, 0, 255, 0, 0, 0, 255, 17, 34, 51};
    uint8_t grey[3] = {0, 100, 255};
    write_png(in_scratch("rgb.png"), 2, 2, 2, rgb);
    write_png(in_scratch("grey.png"), 3, 1, 0, grey);
    MediaCache *m = media_cache_new(NULL, NULL);
    Buf err = BUF_INIT;
    const MediaImage *im = media_image(m, in_scratch("rgb.png"), 0, 0, &err, NULL);
    assert_non_null(im);
    const uint8_t want_rgb[16] = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 17, 34, 51, 255};
    assert_memory_equal(im->rgba, want_rgb, 16);
    im = media_image(m, in_scratch("grey.png"), 0, 0, &err, NULL);
    assert_non_null(im);
    const uint8_t want_grey[12] = {0, 0, 0, 255, 100, 100, 100, 255, 255, 255, 255, 255};
    assert_memory_equal(im->rgba, want_grey, 12);
    media_cache_free(m);
    buf_free(&err);
}

static void test_jpeg_full_range(void **st)
{
    (void)st;
    if (!have_ffmpeg) skip();
    /* a flat colour: JPEG is full-range YCbCr; read as limited range,
     * 0x30 would come back near 0x25 and 0xc0 near 0xd2 */
    const char *path = in_scratch("flat.jpg");
    const char *args[] = {"-f", "lavfi", "-i", "color=c=0x3080c0:s=16x16", "-frames:v", "1", "-q:v", "1", path, NULL};
    ffmpeg(args);
    MediaCache *m = media_cache_new(NULL, NULL);
    Buf err = BUF_INIT;
    const MediaImage *im = media_image(m, path, 0, 0, &err, NULL);
    if (!im) fprintf(stderr, "%s", buf_cstr(&err));
    assert_non_null(im);
    assert_int_equal(im->w, 16);
    assert_int_equal(im->h, 16);
    for (int i = 0; i < 16 * 16; i++) {
        const uint8_t *p = im->rgba + i * 4;
        assert_in_range(p[0], 0x30 - 3, 0x30 + 3);
        assert_in_range(p[1], 0x80 - 3, 0x80 + 3);
        assert_in_range(p[2], 0xc0 - 3, 0xc0 + 3);
        assert_int_equal(p[3], 255);
    }
    media_cache_free(m);
    buf_free(&err);
}

static void test_bmp_gif(void **st)
{
    (void)st;
    if (!have_ffmpeg) skip();
    /* a BMP made from raw RGB bytes: lossless, so exact */
    uint8_t raw[3 * 2 * 3];
    for (int i = 0; i < 18; i++) raw[i] = (uint8_t)(i * 13 + 1);
    write_bytes(in_scratch("pic.rgb"), raw, sizeof raw);
    const char *args[] = {"-f", "rawvideo", "-pix_fmt", "rgb24", "-s", "3x2", "-i", in_scratch("pic.rgb"),
                          "-pix_fmt", "bgr24", in_scratch("pic.bmp"), NULL};
    ffmpeg(args);
    MediaCache *m = media_cache_new(NULL, NULL);
    Buf err = BUF_INIT;
    const MediaImage *im = media_image(m, in_scratch("pic.bmp"), 0, 0, &err, NULL);
    if (!im) fprintf(stderr, "%s", buf_cstr(&err));
    assert_non_null(im);
    assert_int_equal(im->w, 3);
    assert_int_equal(im->h, 2);
    for (int i = 0; i < 6; i++) {
        for (int k = 0; k < 3; k++) assert_int_equal(im->rgba[i * 4 + k], raw[i * 3 + k]);
        assert_int_equal(im->rgba[i * 4 + 3], 255);
    }
    /* a GIF's first frame: red, then blue, from raw bytes through a
     * palette of exactly those colours (no dithering) */
    uint8_t two[2 * 64 * 3];
    for (int i = 0; i < 128; i++) memcpy(two + i * 3, i < 64 ? (uint8_t[]){255, 0, 0} : (uint8_t[]){0, 0, 255}, 3);
    write_bytes(in_scratch("two.rgb"), two, sizeof two);
    const char *gif[] = {"-f", "rawvideo", "-pix_fmt", "rgb24", "-s", "8x8", "-r", "10", "-i", in_scratch("two.rgb"),
                         "-filter_complex", "split[a][b];[a]palettegen=reserve_transparent=0[p];[b][p]paletteuse=dither=none",
                         in_scratch("two.gif"), NULL};
    ffmpeg(gif);
    im = media_image(m, in_scratch("two.gif"), 0, 0, &err, NULL);
    if (!im) fprintf(stderr, "%s", buf_cstr(&err));
    assert_non_null(im);
    assert_int_equal(im->w, 8);
    for (int i = 0; i < 64; i++) assert_memory_equal(im->rgba + i * 4, ((uint8_t[]){255, 0, 0, 255}), 4);
    media_cache_free(m);
    buf_free(&err);
}

static void test_resize(void **st)
{
    (void)st;
    /* a flat colour stays that colour at any size, alpha included (to
     * the precision of 8-bit premultiplied values at alpha 128: 2 levels) */
    uint8_t flat[5 * 4 * 4];
    for (int i = 0; i < 20; i++) memcpy(flat + i * 4, (uint8_t[]){200, 100, 50, 128}, 4);
    write_png(in_scratch("flat.png"), 5, 4, 6, flat);
    /* left half opaque red, right half transparent green */
    uint8_t half[8 * 2 * 4];
    for (int y = 0; y < 2; y++)
        for (int x = 0; x < 8; x++)
            memcpy(half + (y * 8 + x) * 4, x < 4 ? (uint8_t[]){255, 0, 0, 255} : (uint8_t[]){0, 255, 0, 0}, 4);
    write_png(in_scratch("half.png"), 8, 2, 6, half);
    MemBudget b = {0};
    MediaCache *m = media_cache_new(&b, NULL);
    Buf err = BUF_INIT;
    const MediaImage *im = media_image(m, in_scratch("flat.png"), 11, 7, &err, NULL);
    assert_non_null(im);
    assert_int_equal(im->w, 11);
    assert_int_equal(im->h, 7);
    for (int i = 0; i < 11 * 7; i++) {
        assert_in_range(im->rgba[i * 4 + 0], 198, 202);
        assert_in_range(im->rgba[i * 4 + 1], 98, 102);
        assert_in_range(im->rgba[i * 4 + 2], 48, 52);
        assert_int_equal(im->rgba[i * 4 + 3], 128);
    }
    assert_int_equal(b.used, 5 * 4 * 4 + 11 * 7 * 4);   /* the file's size and the copy */
    uint64_t v_big = im->version;
    const MediaImage *small = media_image(m, in_scratch("flat.png"), 2, 3, &err, NULL);
    assert_non_null(small);
    assert_int_equal(small->w, 2);
    assert_int_equal(small->h, 3);
    assert_true(small->version != v_big);
    /* only one of w, h given: the file's size */
    const MediaImage *as_is = media_image(m, in_scratch("flat.png"), 9, 0, &err, NULL);
    assert_int_equal(as_is->w, 5);
    assert_int_equal(as_is->h, 4);

    /* premultiplied filtering: no green bleeds into the visible pixels */
    im = media_image(m, in_scratch("half.png"), 3, 2, &err, NULL);
    assert_non_null(im);
    assert_int_equal(im->w, 3);
    bool blended = false;
    for (int i = 0; i < 6; i++) {
        const uint8_t *p = im->rgba + i * 4;
        if (p[3] > 0) {
            assert_int_equal(p[0], 255);
            assert_int_equal(p[1], 0);
            assert_int_equal(p[2], 0);
        }
        blended |= p[3] > 0 && p[3] < 255;
    }
    assert_true(blended);                    /* the middle column mixes both halves */
    assert_int_equal(im->rgba[3], 255);      /* left: all red */
    assert_int_equal(im->rgba[2 * 4 + 3], 0);   /* right: all transparent */

    /* sizes past 16384 a side are refused */
    bool fresh = false;
    buf_reset(&err);
    assert_null(media_image(m, in_scratch("flat.png"), 16385, 2, &err, &fresh));
    assert_non_null(strstr(buf_cstr(&err), "16384"));
    assert_true(fresh);
    media_cache_free(m);
    assert_int_equal(b.used, 0);
    buf_free(&err);
}

static void test_not_a_picture(void **st)
{
    (void)st;
    const char *path = in_scratch("notes.txt");
    const char *text = "This is not a picture.\nIt is two lines of text.\n";
    write_bytes(path, text, strlen(text));
    MediaCache *m = media_cache_new(NULL, NULL);
    Buf err = BUF_INIT;
    bool fresh = false;
    assert_null(media_image(m, path, 0, 0, &err, &fresh));
    assert_true(fresh);
    assert_true(strncmp(buf_cstr(&err), path, strlen(path)) == 0);   /* "PATH: REASON" */
    assert_true(strncmp(buf_cstr(&err) + strlen(path), ": not a picture (", 17) == 0);
    /* the same failure again: not news */
    Buf err2 = BUF_INIT;
    assert_null(media_image(m, path, 0, 0, &err2, &fresh));
    assert_false(fresh);
    assert_string_equal(buf_cstr(&err2), buf_cstr(&err));
    /* a text file with a picture's name */
    const char *fake = in_scratch("fake.png");
    write_bytes(fake, text, strlen(text));
    buf_reset(&err);
    assert_null(media_image(m, fake, 0, 0, &err, &fresh));
    assert_true(fresh);
    assert_true(strncmp(buf_cstr(&err), fake, strlen(fake)) == 0);
    /* the file becomes a picture: read again */
    uint8_t px[48];
    rgba_4x3(px);
    write_png(path, 4, 3, 6, px);
    set_mtime(path, 1000000);
    const MediaImage *im = media_image(m, path, 0, 0, &err, &fresh);
    assert_non_null(im);
    assert_memory_equal(im->rgba, px, 48);
    media_cache_free(m);
    buf_free(&err);
    buf_free(&err2);
}

static void test_missing_and_changed(void **st)
{
    (void)st;
    const char *path = in_scratch("later.png");
    MemBudget b = {0};
    MediaCache *m = media_cache_new(&b, NULL);
    Buf err = BUF_INIT;
    bool fresh = false;
    assert_null(media_image(m, path, 0, 0, &err, &fresh));
    assert_true(fresh);
    char want[400];
    snprintf(want, sizeof want, "%s: no such file\n", path);
    assert_string_equal(buf_cstr(&err), want);
    buf_reset(&err);
    assert_null(media_image(m, path, 0, 0, &err, &fresh));
    assert_false(fresh);
    assert_string_equal(buf_cstr(&err), want);
    /* it appears */
    uint8_t a[4] = {1, 2, 3, 4}, c[4] = {5, 6, 7, 8};
    write_png(path, 1, 1, 6, a);
    const MediaImage *im = media_image(m, path, 0, 0, &err, &fresh);
    assert_non_null(im);
    assert_memory_equal(im->rgba, a, 4);
    uint64_t v1 = im->version;
    const MediaImage *big = media_image(m, path, 3, 3, &err, NULL);   /* and a copy */
    assert_non_null(big);
    assert_int_equal(b.used, 4 + 36);
    /* it changes (same size: the modification time tells) */
    write_png(path, 1, 1, 6, c);
    set_mtime(path, 2000000);
    im = media_image(m, path, 0, 0, &err, &fresh);
    assert_non_null(im);
    assert_memory_equal(im->rgba, c, 4);
    assert_true(im->version != v1);
    assert_int_equal(b.used, 4);   /* the old pixels and copy given back */
    /* it goes: reported afresh */
    assert_int_equal(unlink(path), 0);
    buf_reset(&err);
    assert_null(media_image(m, path, 0, 0, &err, &fresh));
    assert_true(fresh);
    assert_string_equal(buf_cstr(&err), want);
    assert_int_equal(b.used, 0);
    media_cache_free(m);
    buf_free(&err);
}

static void test_truncated_png(void **st)
{
    (void)st;
    uint8_t px[32 * 32 * 4];
    for (size_t i = 0; i < sizeof px; i++) px[i] = (uint8_t)(i * 7);
    write_png(in_scratch("whole.png"), 32, 32, 6, px);
    truncated_copy(in_scratch("whole.png"), in_scratch("cut.png"), 0.5);
    MemBudget b = {0};
    MediaCache *m = media_cache_new(&b, NULL);
    Buf err = BUF_INIT;
    bool fresh = false;
    assert_null(media_image(m, in_scratch("cut.png"), 0, 0, &err, &fresh));
    assert_true(fresh);
    const char *path = in_scratch("cut.png");
    assert_true(strncmp(buf_cstr(&err), path, strlen(path)) == 0 && buf_cstr(&err)[strlen(path)] == ':');
    assert_int_equal(b.used, 0);   /* nothing held, nothing left charged */
    /* the whole one reads */
    const MediaImage *im = media_image(m, in_scratch("whole.png"), 0, 0, &err, NULL);
    assert_non_null(im);
    assert_memory_equal(im->rgba, px, sizeof px);
    media_cache_free(m);
    buf_free(&err);
}

static void test_picture_limits(void **st)
{
    (void)st;
    /* the budget: 4x3 RGBA is 48 bytes */
    uint8_t px[48];
    rgba_4x3(px);
    write_png(in_scratch("b.png"), 4, 3, 6, px);
    MemBudget b = {.limit = 47};
    MediaCache *m = media_cache_new(&b, NULL);
    Buf err = BUF_INIT;
    bool fresh = false;
    assert_null(media_image(m, in_scratch("b.png"), 0, 0, &err, &fresh));
    assert_true(fresh);
    assert_non_null(strstr(buf_cstr(&err), "out of memory"));
    assert_int_equal(b.used, 0);
    assert_null(media_image(m, in_scratch("b.png"), 0, 0, &err, &fresh));
    assert_false(fresh);   /* said once */
    b.limit = 100;         /* room now: tried again */
    const MediaImage *im = media_image(m, in_scratch("b.png"), 0, 0, &err, &fresh);
    assert_non_null(im);
    assert_int_equal(b.used, 48);
    buf_reset(&err);
    assert_null(media_image(m, in_scratch("b.png"), 8, 8, &err, &fresh));   /* 256 bytes more */
    assert_non_null(strstr(buf_cstr(&err), "out of memory"));
    assert_int_equal(b.used, 48);
    /* expiry gives the memory back */
    media_cache_expire(m, 3600);
    assert_int_equal(b.used, 48);
    media_cache_expire(m, -1);
    assert_int_equal(b.used, 0);
    /* a picture past 16384 a side is refused before decoding */
    uint8_t *wide = calloc(16385, 1);
    write_png(in_scratch("wide.png"), 16385, 1, 0, wide);
    free(wide);
    buf_reset(&err);
    assert_null(media_image(m, in_scratch("wide.png"), 0, 0, &err, &fresh));
    assert_non_null(strstr(buf_cstr(&err), "past 16384"));
    /* bad arguments */
    assert_null(media_image(m, NULL, 0, 0, &err, &fresh));
    assert_null(media_image(NULL, in_scratch("b.png"), 0, 0, &err, &fresh));
    assert_null(media_image(m, "", 0, 0, NULL, NULL));
    assert_null(media_image(m, scratch, 0, 0, &err, &fresh));   /* a folder */
    media_cache_free(m);
    media_cache_free(NULL);
    media_cache_expire(NULL, 1);
    buf_free(&err);
}

/* }===== */

/* {===== videos
 *
 * (A position in seconds becomes ticks of the stream's time base as
 * Flitter divides it, position / time base in floating point, truncated:
 * 0.35 s is 349 ms there. Ratios are checked to a tick.) */

/* The frame number of a frame of the 10 fps fixtures (grey N*8 on top),
 * checking the top rows are that grey within 3 levels. */
static int frame_no(const MediaFrame *f)
{
    assert_non_null(f);
    assert_int_equal(f->w, 64);
    assert_int_equal(f->h, 48);
    int sum = 0;
    for (int x = 0; x < 64; x++) sum += f->rgba[(4 * 64 + x) * 4];
    int n = (sum / 64 + 4) / 8;
    for (int y = 0; y < 12; y++) {
        for (int x = 0; x < 64; x++) {
            const uint8_t *p = f->rgba + (y * 64 + x) * 4;
            for (int k = 0; k < 3; k++) assert_true(abs(p[k] - n * 8) <= 3);
            assert_int_equal(p[3], 255);
        }
    }
    return n;
}

/* The frame number of the long fixture (two blocks of greys on top). */
static int long_frame_no(const MediaFrame *f)
{
    assert_non_null(f);
    assert_int_equal(f->w, 640);
    assert_int_equal(f->h, 360);
    const uint8_t *lo = f->rgba + (8 * 640 + 8) * 4, *hi = f->rgba + (8 * 640 + 24) * 4;
    return (lo[0] + 8) / 16 + (hi[0] + 8) / 16 * 16;
}

typedef struct Got {
    bool ok;
    int f0, f1;       /* frame numbers, -1: none */
    double ratio;
} Got;

static Got frames_at(MediaVideo *v, double pos, bool loop, bool baf, double ts, double te)
{
    const MediaFrame *f0, *f1;
    double ratio = -1;
    Buf err = BUF_INIT;
    Got g = {false, -1, -1, 0};
    g.ok = media_video_frames(v, pos, loop, baf, ts, te, true, &ratio, &f0, &f1, &err);
    if (!g.ok) fprintf(stderr, "frames_at %g: %s\n", pos, buf_line(&err));
    buf_free(&err);
    if (g.ok) {
        g.f0 = frame_no(f0);
        g.f1 = f1 ? frame_no(f1) : -1;
        g.ratio = ratio;
    }
    return g;
}

#define assert_frames(g, a, b, r)                    \
    do {                                             \
        Got g_ = (g);                                \
        assert_true(g_.ok);                          \
        assert_int_equal(g_.f0, (a));                \
        assert_int_equal(g_.f1, (b));                \
        assert_true(fabs(g_.ratio - (r)) < 0.011);   \
    } while (0)

static MediaVideo *open_video(MediaCache *m, const char *name, bool threads)
{
    Buf err = BUF_INIT;
    MediaVideo *v = media_video_open(m, in_scratch(name), threads, &err);
    if (!v) fprintf(stderr, "%s", buf_cstr(&err));
    buf_free(&err);
    assert_non_null(v);
    return v;
}

static void test_video_positions(void **st)
{
    (void)st;
    if (!have_ffmpeg) skip();
    MemBudget b = {0};
    MediaCache *m = media_cache_new(&b, NULL);
    MediaVideo *v = open_video(m, VIDEO, false);
    assert_int_equal(b.used, 16 * 64 * 48 * 4);   /* 16 frames reserved */
    assert_true(media_video_current(v, in_scratch(VIDEO)));
    assert_false(media_video_current(v, in_scratch(VIDEO_MP4)));
    /* frames at 0.1 s each: the frame at or before, the next, and how far */
    assert_frames(frames_at(v, 0, false, false, 0, 0), 0, 1, 0);
    assert_frames(frames_at(v, 0.125, false, false, 0, 0), 1, 2, 0.25);
    assert_frames(frames_at(v, 1.25, false, false, 0, 0), 12, 13, 0.5);
    assert_frames(frames_at(v, 2.875, false, false, 0, 0), 28, 29, 0.75);
    /* the last frame has no next one; past the end and before the start
     * are clamped */
    assert_frames(frames_at(v, 2.95, false, false, 0, 0), 29, -1, 0);
    assert_frames(frames_at(v, 100, false, false, 0, 0), 29, -1, 0);
    assert_frames(frames_at(v, -5, false, false, 0, 0), 0, 1, 0);
    /* the same frame twice: the same serial; another frame: another */
    const MediaFrame *a0, *a1, *c0, *c1;
    double r;
    Buf err = BUF_INIT;
    assert_true(media_video_frames(v, 1.05, false, false, 0, 0, true, &r, &a0, &a1, &err));
    uint64_t s10 = a0->serial, s11 = a1->serial;
    assert_true(s10 != s11);
    /* the frames given stay as they are while the thread decodes ahead */
    uint8_t copy[64 * 48 * 4];
    memcpy(copy, a0->rgba, sizeof copy);
    struct timespec pause = {0, 100000000};
    nanosleep(&pause, NULL);
    assert_memory_equal(a0->rgba, copy, sizeof copy);
    assert_int_equal(a0->serial, s10);
    assert_int_equal(frame_no(a0), 10);
    assert_int_equal(frame_no(a1), 11);
    assert_true(media_video_frames(v, 1.15, false, false, 0, 0, true, &r, &c0, &c1, &err));
    assert_int_equal(c0->serial, s11);
    media_video_close(v);
    assert_int_equal(b.used, 0);
    media_cache_free(m);
    buf_free(&err);
}

static void test_video_loop_trim(void **st)
{
    (void)st;
    if (!have_ffmpeg) skip();
    MediaCache *m = media_cache_new(NULL, NULL);
    MediaVideo *v = open_video(m, VIDEO, false);
    /* loop: 3 s long; negative positions count from the end */
    assert_frames(frames_at(v, 3.25, true, false, 0, 0), 2, 3, 0.5);
    assert_frames(frames_at(v, 9.05, true, false, 0, 0), 0, 1, 0.5);
    assert_frames(frames_at(v, -0.25, true, false, 0, 0), 27, 28, 0.5);
    /* back and forth: the second pass runs backwards */
    assert_frames(frames_at(v, 3.25, true, true, 0, 0), 27, 28, 0.5);
    assert_frames(frames_at(v, 6.25, true, true, 0, 0), 2, 3, 0.5);
    assert_frames(frames_at(v, -0.25, true, true, 0, 0), 2, 3, 0.5);
    assert_frames(frames_at(v, 1.25, true, true, 0, 0), 12, 13, 0.5);
    /* trim 1 s at the start, 0.5 s at the end: 1.5 s from frame 10 */
    assert_frames(frames_at(v, 0, false, false, 1, 0.5), 10, 11, 0);
    assert_frames(frames_at(v, 0.525, false, false, 1, 0.5), 15, 16, 0.25);
    assert_frames(frames_at(v, 7, false, false, 1, 0.5), 25, 26, 0);    /* clamped to 2.5 s */
    assert_frames(frames_at(v, 1.65, true, false, 1, 0.5), 11, 12, 0.5);   /* 1.65 - 1.5 */
    assert_frames(frames_at(v, 1.65, true, true, 1, 0.5), 23, 24, 0.5);    /* 2.5 - 0.15 */
    /* trims past the length: the start of what is left */
    assert_frames(frames_at(v, 2, true, false, 2, 2), 20, 21, 0);
    /* not a number: the start */
    assert_frames(frames_at(v, NAN, true, true, NAN, INFINITY), 0, 1, 0);
    media_video_close(v);
    media_cache_free(m);
}

static void test_video_backwards(void **st)
{
    (void)st;
    if (!have_ffmpeg) skip();
    MediaCache *m = media_cache_new(NULL, NULL);
    for (int threads = 0; threads < 2; threads++) {
        MediaVideo *v = open_video(m, threads ? VIDEO_MP4 : VIDEO, threads);
        /* jumps both ways */
        assert_frames(frames_at(v, 2.05, false, false, 0, 0), 20, 21, 0.5);
        assert_frames(frames_at(v, 0.35, false, false, 0, 0), 3, 4, 0.5);
        assert_frames(frames_at(v, 2.55, false, false, 0, 0), 25, 26, 0.5);
        assert_frames(frames_at(v, 0.05, false, false, 0, 0), 0, 1, 0.5);
        /* played backwards, every frame, across key frames */
        for (int k = 29; k >= 0; k--) {
            Got g = frames_at(v, k * 0.1 + 0.05, false, false, 0, 0);
            assert_true(g.ok);
            assert_int_equal(g.f0, k);
            assert_int_equal(g.f1, k < 29 ? k + 1 : -1);
        }
        /* and forwards again */
        for (int k = 0; k < 30; k++) assert_int_equal(frames_at(v, k * 0.1 + 0.05, false, false, 0, 0).f0, k);
        media_video_close(v);
    }
    media_cache_free(m);
}

static void test_video_no_wait(void **st)
{
    (void)st;
    if (!have_ffmpeg) skip();
    MediaCache *m = media_cache_new(NULL, NULL);
    MediaVideo *v = open_video(m, LONG_VIDEO, false);
    const MediaFrame *f0, *f1;
    double r;
    Buf err = BUF_INIT;
    /* frame 240 needs all 240 frames before it decoded (one key frame):
     * without wait, the call returns at once with what there is */
    double t0 = now_s();
    bool ok = media_video_frames(v, 9.62, false, false, 0, 0, false, &r, &f0, &f1, &err);
    double took = now_s() - t0;
    assert_true(took < 0.05);
    assert_string_equal(buf_cstr(&err), "");
    assert_true(!ok || long_frame_no(f0) < 240);
    /* asked again and again, the thread gets there */
    double worst = took, deadline = now_s() + 30;
    int got = -1, calls = 0;
    while (now_s() < deadline) {
        t0 = now_s();
        ok = media_video_frames(v, 9.62, false, false, 0, 0, false, &r, &f0, &f1, &err);
        took = now_s() - t0;
        worst = took > worst ? took : worst;
        calls++;
        if (ok && (got = long_frame_no(f0)) == 240 && f1) break;   /* (240 may come before 241) */
        struct timespec ms = {0, 2000000};
        nanosleep(&ms, NULL);
    }
    assert_int_equal(got, 240);
    assert_non_null(f1);
    assert_int_equal(long_frame_no(f1), 241);
    assert_true(fabs(r - 0.5) < 0.03);   /* (a tick of 40) */
    assert_true(calls > 1);
    assert_true(worst < 0.05);
    media_video_close(v);
    /* the same with wait: exact at once */
    v = open_video(m, LONG_VIDEO, false);
    t0 = now_s();
    assert_true(media_video_frames(v, 9.62, false, false, 0, 0, true, &r, &f0, &f1, &err));
    took = now_s() - t0;
    fprintf(stderr, "test_video_no_wait: %.3f s to frame 240 with wait; %d calls without, the longest %.6f s\n", took,
            calls, worst);
    assert_int_equal(long_frame_no(f0), 240);
    media_video_close(v);
    media_cache_free(m);
    buf_free(&err);
}

static void test_video_truncated(void **st)
{
    (void)st;
    if (!have_ffmpeg) skip();
    MediaCache *m = media_cache_new(NULL, NULL);
    const char *names[] = {"cut.mkv", "cut.mp4"};
    const char *from[] = {VIDEO, VIDEO_MP4};
    for (int i = 0; i < 2; i++) {
        truncated_copy(in_scratch(from[i]), in_scratch(names[i]), 0.5);
        MediaVideo *v = open_video(m, names[i], false);
        /* the start plays */
        assert_frames(frames_at(v, 0.35, false, false, 0, 0), 3, 4, 0.5);
        /* somewhere past the damage: false with a message naming the
         * file, once; then false without */
        const MediaFrame *f0, *f1;
        double r;
        Buf err = BUF_INIT;
        assert_false(media_video_frames(v, 2.95, false, false, 0, 0, true, &r, &f0, &f1, &err));
        fprintf(stderr, "%s", buf_cstr(&err));
        assert_true(strncmp(buf_cstr(&err), in_scratch(names[i]), strlen(in_scratch(names[i]))) == 0);
        assert_null(f0);
        buf_reset(&err);
        assert_false(media_video_frames(v, 2.85, false, false, 0, 0, true, &r, &f0, &f1, &err));
        assert_string_equal(buf_cstr(&err), "");
        /* and before it, frames again, with their next ones */
        assert_frames(frames_at(v, 0.65, false, false, 0, 0), 6, 7, 0.5);
        assert_frames(frames_at(v, 0.05, false, false, 0, 0), 0, 1, 0.5);
        media_video_close(v);
        buf_free(&err);
    }
    media_cache_free(m);
}

static void test_video_bad_files(void **st)
{
    (void)st;
    MemBudget b = {0};
    MediaCache *m = media_cache_new(&b, NULL);
    Buf err = BUF_INIT;
    const char *text = in_scratch("notes.mp4");
    write_bytes(text, "not a video at all\n", 19);
    assert_null(media_video_open(m, text, false, &err));
    assert_true(strncmp(buf_cstr(&err), text, strlen(text)) == 0 && strstr(buf_cstr(&err), "not a video"));
    const char *txt = in_scratch("words.txt");
    write_bytes(txt, "some words\n", 11);
    buf_reset(&err);
    assert_null(media_video_open(m, txt, false, &err));
    assert_true(strncmp(buf_cstr(&err), txt, strlen(txt)) == 0 && strstr(buf_cstr(&err), "not a video"));
    const char *missing = in_scratch("missing.mp4");
    buf_reset(&err);
    assert_null(media_video_open(m, missing, false, &err));
    char want[400];
    snprintf(want, sizeof want, "%s: no such file\n", missing);
    assert_string_equal(buf_cstr(&err), want);
    assert_null(media_video_open(m, NULL, false, &err));
    assert_null(media_video_open(NULL, text, false, &err));
    assert_null(media_video_open(m, scratch, false, &err));
    assert_false(media_video_frames(NULL, 0, false, false, 0, 0, true, NULL, NULL, NULL, &err));
    assert_false(media_video_current(NULL, text));
    media_video_close(NULL);
    assert_int_equal(b.used, 0);
    if (have_ffmpeg) {
        /* the whole start gone: no frame at all */
        size_t n;
        uint8_t *p = read_bytes(in_scratch(VIDEO), &n);
        write_bytes(in_scratch("head.mkv"), p, 400);
        free(p);
        buf_reset(&err);
        MediaVideo *v = media_video_open(m, in_scratch("head.mkv"), false, &err);
        if (v) {   /* (the header may be whole: then no frame reads) */
            const MediaFrame *f0, *f1;
            double r;
            assert_false(media_video_frames(v, 0, false, false, 0, 0, true, &r, &f0, &f1, &err));
            assert_true(strncmp(buf_cstr(&err), in_scratch("head.mkv"), strlen(in_scratch("head.mkv"))) == 0);
            media_video_close(v);
        } else {
            assert_true(strncmp(buf_cstr(&err), in_scratch("head.mkv"), strlen(in_scratch("head.mkv"))) == 0);
        }
        /* a budget too small for 4 frames */
        b.limit = 3 * 64 * 48 * 4;
        buf_reset(&err);
        assert_null(media_video_open(m, in_scratch(VIDEO), false, &err));
        assert_non_null(strstr(buf_cstr(&err), "out of memory"));
        b.limit = 0;
        /* the file changes under an open video */
        const char *copy = in_scratch("copy.mkv");
        p = read_bytes(in_scratch(VIDEO), &n);
        write_bytes(copy, p, n);
        MediaVideo *w = open_video(m, "copy.mkv", false);
        assert_true(media_video_current(w, copy));
        write_bytes(copy, p, n);
        set_mtime(copy, 3000000);
        assert_false(media_video_current(w, copy));
        free(p);
        /* left open: media_cache_free stops and frees it */
    }
    media_cache_free(m);
    assert_int_equal(b.used, 0);
    buf_free(&err);
}

static void test_video_interrupt(void **st)
{
    (void)st;
    if (!have_ffmpeg) skip();
    volatile int flag = 0;
    MediaCache *m = media_cache_new(NULL, &flag);
    MediaVideo *v = open_video(m, LONG_VIDEO, false);
    const MediaFrame *f0, *f1;
    double r;
    Buf err = BUF_INIT;
    __atomic_store_n(&flag, 1, __ATOMIC_RELAXED);
    double t0 = now_s();
    bool ok = media_video_frames(v, 9.62, false, false, 0, 0, true, &r, &f0, &f1, &err);
    assert_true(now_s() - t0 < 0.5);   /* gave up at once, with what there was */
    assert_true(!ok || long_frame_no(f0) < 240);
    __atomic_store_n(&flag, 0, __ATOMIC_RELAXED);
    assert_true(media_video_frames(v, 9.62, false, false, 0, 0, true, &r, &f0, &f1, &err));
    assert_int_equal(long_frame_no(f0), 240);
    /* pictures too: an interrupted read is not kept as a failure */
    uint8_t px[48];
    rgba_4x3(px);
    write_png(in_scratch("i.png"), 4, 3, 6, px);
    __atomic_store_n(&flag, 1, __ATOMIC_RELAXED);
    bool fresh;
    buf_reset(&err);
    assert_null(media_image(m, in_scratch("i.png"), 0, 0, &err, &fresh));
    assert_non_null(strstr(buf_cstr(&err), "interrupted"));
    __atomic_store_n(&flag, 0, __ATOMIC_RELAXED);
    assert_non_null(media_image(m, in_scratch("i.png"), 0, 0, &err, &fresh));
    media_video_close(v);
    media_cache_free(m);
    buf_free(&err);
}

/* Two runtimes' caches used at once from two threads (paths made here:
 * in_scratch is the main thread's). */
static void *play(void *arg)
{
    int *bad = arg;
    MediaCache *m = media_cache_new(NULL, NULL);
    Buf err = BUF_INIT;
    char video[256], picture[256];
    snprintf(video, sizeof video, "%s/%s", scratch, VIDEO);
    snprintf(picture, sizeof picture, "%s/rgba.png", scratch);
    MediaVideo *v = media_video_open(m, video, false, &err);
    if (!v) {
        *bad = 1;
        buf_free(&err);
        return NULL;
    }
    for (int pass = 0; pass < 2; pass++) {
        for (int k = 0; k < 30; k++) {
            const MediaFrame *f0, *f1;
            double r;
            int kk = pass ? 29 - k : k;
            if (!media_video_frames(v, kk * 0.1 + 0.05, false, false, 0, 0, true, &r, &f0, &f1, &err) ||
                abs(f0->rgba[(4 * 64) * 4] - kk * 8) > 3)
                *bad = 1;
            /* and a frame without waiting, whatever it is */
            media_video_frames(v, (29 - kk) * 0.1, true, false, 0, 0, false, &r, &f0, &f1, &err);
        }
    }
    const MediaImage *im = media_image(m, picture, 2, 2, &err, NULL);
    if (!im || im->w != 2) *bad = 1;
    media_cache_free(m);   /* the video still open */
    buf_free(&err);
    return NULL;
}

static void test_two_caches(void **st)
{
    (void)st;
    if (!have_ffmpeg) skip();
    uint8_t px[48];
    rgba_4x3(px);
    write_png(in_scratch("rgba.png"), 4, 3, 6, px);
    pthread_t t[2];
    int bad[2] = {0, 0};
    for (int i = 0; i < 2; i++) assert_int_equal(pthread_create(&t[i], NULL, play, &bad[i]), 0);
    for (int i = 0; i < 2; i++) pthread_join(t[i], NULL);
    assert_int_equal(bad[0], 0);
    assert_int_equal(bad[1], 0);
}

/* }===== */

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_png_exact),
        cmocka_unit_test(test_png_opaque),
        cmocka_unit_test(test_jpeg_full_range),
        cmocka_unit_test(test_bmp_gif),
        cmocka_unit_test(test_resize),
        cmocka_unit_test(test_not_a_picture),
        cmocka_unit_test(test_missing_and_changed),
        cmocka_unit_test(test_truncated_png),
        cmocka_unit_test(test_picture_limits),
        cmocka_unit_test(test_video_positions),
        cmocka_unit_test(test_video_loop_trim),
        cmocka_unit_test(test_video_backwards),
        cmocka_unit_test(test_video_no_wait),
        cmocka_unit_test(test_video_truncated),
        cmocka_unit_test(test_video_bad_files),
        cmocka_unit_test(test_video_interrupt),
        cmocka_unit_test(test_two_caches),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
