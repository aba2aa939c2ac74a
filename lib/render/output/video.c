/* video.c: video files through FFmpeg's libraries (see video.h).
 *
 * One VideoOut is one output file: a format context (the container,
 * guessed from the target's name) writing to a temporary (outfile.h), one
 * video stream, its encoder context, a scaler converting cairo's ARGB32
 * pictures to the encoder's pixel format and size, and one reusable frame
 * and packet. The encoder's time base is 1/fps and each frame carries the
 * pts its caller gives (its time in frames); packets are rescaled to the
 * stream's time base, which the muxer may change at avformat_write_header
 * (MP4 does).
 *
 * The converting, encoding and writing run on a writer thread of the
 * VideoOut's own, as Flitter's video writer does: video_frame copies the
 * picture into a queue of VIDEO_QUEUE frames and returns. A full queue
 * makes the caller wait (every frame encoded: lockstep) or, when asked,
 * drops the frame (the live window's clock never waits for the encoder).
 * The writer alone touches the scaler, encoder and container between
 * video_open and video_close; the queue, the failure flag and its message
 * are under the VideoOut's lock.
 *
 * FFmpeg logs through its own process-wide callback to stderr; libx264
 * alone prints a dozen information lines per file. When the level is still
 * FFmpeg's default (AV_LOG_INFO) it is lowered to AV_LOG_ERROR the first
 * time a video is opened: the only process-wide setting this module
 * touches, and a host that chose its own level keeps it.
 */
#include "video.h"

#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "avlib.h"
#include "mem.h"
#include "outfile.h"

/* Frames waiting for the writer (Flitter's writer queue holds fps frames;
 * these are whole ARGB pictures, so fewer). */
#define VIDEO_QUEUE 8

/* One picture waiting for the writer: a copy of the caller's ARGB32. */
typedef struct QueuedFrame {
    uint8_t *argb;              /* width*4 bytes a row, malloc'd */
    int width, height;
    long pts;
} QueuedFrame;

struct VideoOut {
    AvLib *L;                   /* FFmpeg's functions (avlib.h) */
    OutFile out;                /* the temporary and the target */
    AVFormatContext *oc;        /* the container, writing to out.tmp */
    AVCodecContext *cc;         /* the encoder (time base 1/fps) */
    AVStream *st;               /* the one video stream */
    struct SwsContext *sws;     /* ARGB32 of the last source size -> cc's format and size */
    int sws_w, sws_h;           /* the source size sws was made for (0: none yet) */
    AVFrame *frame;             /* the converted frame handed to the encoder */
    AVPacket *pkt;              /* reused for every packet */
    bool alpha;                 /* the output keeps alpha: sources are unpremultiplied first */
    uint8_t *straight;          /* unpremultiplied copy of a source (alpha only) */
    size_t straight_cap;        /* its size in bytes */
    long frames;                /* frames queued for the encoder */
    long dropped;               /* frames dropped on a full queue */
    /* the writer thread and its queue */
    pthread_t writer;
    bool writer_started;
    pthread_mutex_t lock;
    pthread_cond_t changed;     /* a frame queued or taken, or closing */
    QueuedFrame queue[VIDEO_QUEUE];
    int qhead, qcount;
    bool closing;               /* no more frames: the writer ends */
    bool failed;                /* a frame failed: discard the file at close (locked) */
    char why[600];              /* the first failure's message (locked) */
};

static const char *const containers[] = {".mp4", ".mov", ".m4v", ".mkv", ".webm"};

static bool ends_with(const char *s, const char *tail)
{
    size_t a = strlen(s), b = strlen(tail);
    return a >= b && strcasecmp(s + a - b, tail) == 0;
}

bool video_is_video_name(const char *path)
{
    for (size_t i = 0; i < sizeof containers / sizeof *containers; i++)
        if (ends_with(path, containers[i])) return true;
    return false;
}

/* An encoder by FFmpeg encoder name (libx264) or codec name (h264, whose
 * default encoder is taken), as PyAV's Codec(name, 'w'); NULL if none or
 * not a video encoder. */
static const AVCodec *find_encoder(const AvLib *L, const char *name)
{
    const AVCodec *c = L->avcodec_find_encoder_by_name(name);
    if (!c) {
        const AVCodecDescriptor *d = L->avcodec_descriptor_get_by_name(name);
        if (d) c = L->avcodec_find_encoder(d->id);
    }
    return c && c->type == AVMEDIA_TYPE_VIDEO ? c : NULL;
}

static bool takes_format(const AVCodec *c, enum AVPixelFormat f)
{
    if (!c->pix_fmts) return true;   /* the encoder does not say */
    for (const enum AVPixelFormat *p = c->pix_fmts; *p != AV_PIX_FMT_NONE; p++)
        if (*p == f) return true;
    return false;
}

/* The pixel format for [c]: [asked] (pixfmt=) if given, else packed RGB
 * (ARGB with alpha) for an encoder that lists no formats when [raw_rgb]
 * (the container's raw video is RGB), else yuva420p
 * with alpha where taken, else yuv420p, else the encoder's nearest to
 * ARGB; AV_PIX_FMT_NONE with [err] set if [asked] is unknown or refused. */
static enum AVPixelFormat choose_format(const AvLib *L, const AVCodec *c, const char *asked, bool alpha, bool raw_rgb,
                                        const char *path,
                                        Buf *err)
{
    if (asked) {
        enum AVPixelFormat f = L->av_get_pix_fmt(asked);
        if (f == AV_PIX_FMT_NONE) {
            buf_printf(err, "%s: unknown pixel format '%s'\n", path, asked);
            return AV_PIX_FMT_NONE;
        }
        if (!takes_format(c, f)) {
            buf_printf(err, "%s: encoder %s does not take pixel format '%s'\n", path, c->name, asked);
            return AV_PIX_FMT_NONE;
        }
        /* QuickTime's raw video holds packed RGB and two packed YUV
         * layouts; FFmpeg writes any other format unreadable (or read
         * back as another) with only a warning */
        static const enum AVPixelFormat quicktime_raw[] = {
            AV_PIX_FMT_RGB24, AV_PIX_FMT_BGR24, AV_PIX_FMT_ARGB, AV_PIX_FMT_BGRA, AV_PIX_FMT_RGBA,
            AV_PIX_FMT_ABGR, AV_PIX_FMT_UYVY422, AV_PIX_FMT_YUYV422};
        bool held = !raw_rgb || c->pix_fmts;
        for (size_t i = 0; !held && i < sizeof quicktime_raw / sizeof *quicktime_raw; i++)
            held = quicktime_raw[i] == f;
        if (!held) {
            buf_printf(err, "%s: a QuickTime file holds raw video as rgb24, bgr24, argb, bgra, rgba, abgr, "
                     "uyvy422 or yuyv422, not '%s'\n", path, asked);
            return AV_PIX_FMT_NONE;
        }
        return f;
    }
    /* an encoder that lists no formats (rawvideo) into a QuickTime file:
     * the picture's own packed RGB, which QuickTime's raw video holds (a
     * yuv420p rawvideo .mov was written unreadable, exit 0; Matroska
     * holds raw YUV, not RGB) */
    if (!c->pix_fmts && raw_rgb) return alpha ? AV_PIX_FMT_RGB32 : AV_PIX_FMT_RGB24;
    if (alpha && takes_format(c, AV_PIX_FMT_YUVA420P)) return AV_PIX_FMT_YUVA420P;
    if (takes_format(c, AV_PIX_FMT_YUV420P)) return AV_PIX_FMT_YUV420P;
    return L->avcodec_find_best_pix_fmt_of_list(c->pix_fmts, AV_PIX_FMT_RGB32, alpha, NULL);
}

/* [n] rounded up to a multiple of 2^[log2]. */
static int round_up(int n, int log2) { return ((n + (1 << log2) - 1) >> log2) << log2; }

/* The options dictionary from [spec]: `__` becomes `-`, bitrate is `b`. */
static AVDictionary *options_of(const AvLib *L, const VideoSpec *spec)
{
    AVDictionary *d = NULL;
    for (size_t i = 0; i < spec->noptions; i++) {
        const char *k = spec->options[i].key;
        char key[128];
        size_t n = 0;
        for (const char *p = k; *p && n + 1 < sizeof key; p++) {
            if (p[0] == '_' && p[1] == '_') {
                key[n++] = '-';
                p++;
            } else {
                key[n++] = *p;
            }
        }
        key[n] = '\0';
        L->av_dict_set(&d, strcmp(key, "bitrate") == 0 ? "b" : key, spec->options[i].value, 0);
    }
    return d;
}

/* Free [v] and what it holds; a temporary still there is removed (the
 * paths that reach here before video_close: failures). */
static void free_video(VideoOut *v)
{
    const AvLib *L = v->L;
    if (!L) {
        outfile_discard(&v->out);
        free(v);
        return;
    }
    L->avcodec_free_context(&v->cc);
    if (v->oc) {
        if (v->oc->pb) L->avio_closep(&v->oc->pb);
        L->avformat_free_context(v->oc);
    }
    outfile_discard(&v->out);   /* after avio closed its descriptor */
    L->sws_freeContext(v->sws);
    L->av_frame_free(&v->frame);
    L->av_packet_free(&v->pkt);
    free(v->straight);
    for (int i = 0; i < v->qcount; i++) free(v->queue[(v->qhead + i) % VIDEO_QUEUE].argb);
    if (v->writer_started) {
        pthread_mutex_destroy(&v->lock);
        pthread_cond_destroy(&v->changed);
    }
    free(v->L);
    free(v);
}

/* Open encoder [c] on [v] for a [w] x [h] picture at [fps]; false with
 * the reason appended to [err]. The names of the options it did not use
 * are appended to [unused] (NULL: not wanted), separated by commas. */
static bool open_encoder(VideoOut *v, const AVCodec *c, const VideoSpec *spec, int w, int h, int fps,
                         const char *path, Buf *err, Buf *unused)
{
    const AvLib *L = v->L;
    if (L->avformat_query_codec(v->oc->oformat, c->id, FF_COMPLIANCE_NORMAL) != 1) {
        buf_printf(err, "%s: a %s file cannot hold %s video\n", path, v->oc->oformat->name, c->name);
        return false;
    }
    enum AVPixelFormat fmt = choose_format(L, c, spec->pixfmt, spec->keep_alpha,
                                           strcmp(v->oc->oformat->name, "mov") == 0, path, err);
    if (fmt == AV_PIX_FMT_NONE) return false;
    const AVPixFmtDescriptor *desc = L->av_pix_fmt_desc_get(fmt);
    AVCodecContext *cc = L->avcodec_alloc_context3(c);
    if (!cc) mem_oom();
    cc->width = round_up(w, desc->log2_chroma_w);
    cc->height = round_up(h, desc->log2_chroma_h);
    cc->pix_fmt = fmt;
    cc->time_base = (AVRational){1, fps};
    cc->framerate = (AVRational){fps, 1};
    cc->color_primaries = AVCOL_PRI_BT709;   /* as Flitter's defaults */
    cc->color_trc = AVCOL_TRC_BT709;
    cc->colorspace = AVCOL_SPC_BT709;
    cc->color_range = AVCOL_RANGE_MPEG;
    if (c->id == AV_CODEC_ID_MJPEG) {   /* a JPEG picture: JFIF's full-range BT.601 */
        cc->color_primaries = AVCOL_PRI_UNSPECIFIED;
        cc->color_trc = AVCOL_TRC_UNSPECIFIED;
        cc->colorspace = AVCOL_SPC_BT470BG;
        cc->color_range = AVCOL_RANGE_JPEG;
    }
    if (v->oc->oformat->flags & AVFMT_GLOBALHEADER) cc->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
    if (c->id == AV_CODEC_ID_HEVC && (ends_with(path, ".mp4") || ends_with(path, ".mov") || ends_with(path, ".m4v")))
        cc->codec_tag = MKTAG('h', 'v', 'c', '1');   /* what Apple's players expect (Flitter) */
    AVDictionary *opts = options_of(L, spec);
    int rc = L->avcodec_open2(cc, c, &opts);
    if (rc < 0) {
        char why[AV_ERROR_MAX_STRING_SIZE];
        L->av_strerror(rc, why, sizeof why);
        buf_printf(err, "%s: cannot open the %s encoder: %s\n", path, c->name, why);
        L->av_dict_free(&opts);
        L->avcodec_free_context(&cc);
        return false;
    }
    const AVDictionaryEntry *e = NULL;
    while (unused && (e = L->av_dict_get(opts, "", e, AV_DICT_IGNORE_SUFFIX)) != NULL)
        buf_printf(unused, "%s%s", unused->len ? "," : "", e->key);
    L->av_dict_free(&opts);
    v->cc = cc;
    v->alpha = (desc->flags & AV_PIX_FMT_FLAG_ALPHA) != 0;
    return true;
}

static void *writer_main(void *arg);

VideoOut *video_open(const char *path, int width, int height, double fps, const VideoSpec *spec, Buf *err,
                     Buf *unused)
{
    if (unused) buf_reset(unused);
    VideoOut *v = calloc(1, sizeof *v);
    if (!v) mem_oom();
    /* the file first: a target that cannot be written fails without
     * loading FFmpeg */
    if (!outfile_open(&v->out, path, err)) {
        free(v);
        return NULL;
    }
    Buf lwhy = BUF_INIT;
    const AvLib *L = v->L = avlib_load(&lwhy);
    if (!L) {
        buf_printf(err, "%s: %s\n", path, buf_line(&lwhy));
        buf_free(&lwhy);
        free_video(v);
        return NULL;
    }
    if (L->av_log_get_level() == AV_LOG_INFO) L->av_log_set_level(AV_LOG_ERROR);
    int ifps = fps >= 1 && fps <= 1000 ? (int)fps : fps > 1000 ? 1000 : 1;   /* Flitter: int(fps) */
    if (L->avformat_alloc_output_context2(&v->oc, NULL, spec->format, path) < 0 || !v->oc) {
        buf_printf(err, "%s: no video container for this file name\n", path);
        free_video(v);
        return NULL;
    }
    /* the encoders to try, best first: codec= alone, else by container */
    const AVCodec *cands[4] = {NULL};
    int ncand = 0;
    bool webm = ends_with(path, ".webm");
    if (spec->codec) {
        if (!(cands[ncand++] = find_encoder(L, spec->codec))) {
            buf_printf(err, "%s: no video encoder '%s' in this FFmpeg\n", path, spec->codec);
            free_video(v);
            return NULL;
        }
    } else {
        static const char *const webm_names[] = {"libvpx-vp9", "vp9", "libvpx", "vp8"};
        static const char *const other_names[] = {"libx264", "h264", "mpeg4", NULL};
        const char *const *names = webm ? webm_names : other_names;
        for (int i = 0; i < 4 && names[i]; i++) {
            const AVCodec *c = find_encoder(L, names[i]);
            bool seen = false;
            for (int k = 0; k < ncand; k++) seen |= cands[k] == c;
            if (c && !seen) cands[ncand++] = c;
        }
        if (ncand == 0) {
            buf_printf(err, "%s: no %s encoder in this FFmpeg\n", path, webm ? "VP9 or VP8" : "H.264 or MPEG-4");
            free_video(v);
            return NULL;
        }
    }
    /* the first encoder that opens; if none does, the first one's reason */
    bool opened = false, refused = false;
    Buf first = BUF_INIT, why = BUF_INIT;
    for (int i = 0; i < ncand && !opened && !refused; i++) {
        if (unused) buf_reset(unused);
        buf_reset(&why);
        opened = open_encoder(v, cands[i], spec, width, height, ifps, path, &why, unused);
        if (!opened && i == 0) buf_puts(&first, buf_line(&why));
        if (!opened && spec->noptions > 0) {
            /* an encoder that opens without the options refused them: an
             * error, never a quiet change of encoder */
            VideoSpec plain = *spec;
            plain.noptions = 0;
            Buf ignored = BUF_INIT;
            if (open_encoder(v, cands[i], &plain, width, height, ifps, path, &ignored, NULL)) {
                L->avcodec_free_context(&v->cc);
                buf_printf(err, "%.300s (the %s encoder refused the options given)\n",
                           first.len ? buf_cstr(&first) : buf_line(&why), cands[i]->name);
                refused = true;
            }
            buf_free(&ignored);
        }
    }
    if (!opened && !refused) buf_printf(err, "%s\n", buf_cstr(&first));
    buf_free(&first);
    buf_free(&why);
    if (!opened) {
        free_video(v);
        return NULL;
    }
    v->st = L->avformat_new_stream(v->oc, NULL);
    v->frame = L->av_frame_alloc();
    v->pkt = L->av_packet_alloc();
    if (!v->st || !v->frame || !v->pkt) mem_oom();
    if (L->avcodec_parameters_from_context(v->st->codecpar, v->cc) < 0) mem_oom();
    v->st->time_base = v->cc->time_base;
    v->st->avg_frame_rate = v->st->r_frame_rate = v->cc->framerate;
    v->frame->format = v->cc->pix_fmt;
    v->frame->width = v->cc->width;
    v->frame->height = v->cc->height;
    v->frame->color_primaries = v->cc->color_primaries;
    v->frame->color_trc = v->cc->color_trc;
    v->frame->colorspace = v->cc->colorspace;
    v->frame->color_range = v->cc->color_range;
    if (L->av_frame_get_buffer(v->frame, 0) < 0) mem_oom();
    char *url;
    if (asprintf(&url, "file:%s", v->out.tmp) < 0) mem_oom();
    int rc = L->avio_open(&v->oc->pb, url, AVIO_FLAG_WRITE);
    free(url);
    if (rc >= 0) rc = L->avformat_write_header(v->oc, NULL);
    if (rc < 0) {
        char why[AV_ERROR_MAX_STRING_SIZE];
        L->av_strerror(rc, why, sizeof why);
        buf_printf(err, "%s: cannot start the video: %s\n", path, why);
        free_video(v);
        return NULL;
    }
    pthread_mutex_init(&v->lock, NULL);
    pthread_cond_init(&v->changed, NULL);
    if (pthread_create(&v->writer, NULL, writer_main, v) != 0) {
        pthread_mutex_destroy(&v->lock);
        pthread_cond_destroy(&v->changed);
        buf_printf(err, "%s: cannot start the video's writer thread\n", path);
        free_video(v);
        return NULL;
    }
    v->writer_started = true;
    return v;
}

/* Send [f] (NULL: flush) to the encoder and write the packets it gives;
 * -1 with [err] set on failure. */
static int encode(VideoOut *v, AVFrame *f, Buf *err)
{
    const AvLib *L = v->L;
    int rc = L->avcodec_send_frame(v->cc, f);
    while (rc >= 0) {
        rc = L->avcodec_receive_packet(v->cc, v->pkt);
        if (rc == AVERROR(EAGAIN) || rc == AVERROR_EOF) return 0;
        if (rc < 0) break;
        L->av_packet_rescale_ts(v->pkt, v->cc->time_base, v->st->time_base);
        v->pkt->stream_index = v->st->index;
        rc = L->av_interleaved_write_frame(v->oc, v->pkt);   /* takes the packet's data */
    }
    char why[AV_ERROR_MAX_STRING_SIZE];
    L->av_strerror(rc, why, sizeof why);
    buf_printf(err, "%s: cannot encode a video frame: %s\n", v->out.target, why);
    return -1;
}

/* Undo premultiplication of [n] ARGB32 words from [src] into [dst]. */
static void unpremultiply(uint32_t *dst, const uint32_t *src, int n)
{
    for (int i = 0; i < n; i++) {
        uint32_t p = src[i], a = p >> 24;
        if (a == 0 || a == 255) {
            dst[i] = a == 0 ? 0 : p;
            continue;
        }
        uint32_t r = ((p >> 16 & 255) * 255 + a / 2) / a, g = ((p >> 8 & 255) * 255 + a / 2) / a,
                 b = ((p & 255) * 255 + a / 2) / a;
        dst[i] = a << 24 | (r > 255 ? 255 : r) << 16 | (g > 255 ? 255 : g) << 8 | (b > 255 ? 255 : b);
    }
}

/* Convert and encode queued picture [q] (on the writer thread); -1 with
 * [err] set on failure. */
static int encode_picture(VideoOut *v, const QueuedFrame *q, Buf *err)
{
    const AvLib *L = v->L;
    int width = q->width, height = q->height, stride = width * 4;
    if (!v->sws || v->sws_w != width || v->sws_h != height) {
        L->sws_freeContext(v->sws);
        v->sws = L->sws_getContext(width, height, AV_PIX_FMT_RGB32, v->cc->width, v->cc->height, v->cc->pix_fmt,
                                SWS_BICUBIC | SWS_ACCURATE_RND | SWS_FULL_CHR_H_INT, NULL, NULL, NULL);
        if (!v->sws) {
            buf_printf(err, "%s: cannot convert %dx%d frames to %s\n", v->out.target, width, height,
                     L->av_get_pix_fmt_name(v->cc->pix_fmt));
            return -1;
        }
        /* full-range RGB in; YUV out as the stream's tags say: BT.709
         * limited range, or a JPEG's full-range BT.601 */
        bool jfif = v->cc->color_range == AVCOL_RANGE_JPEG;
        const int *cs = L->sws_getCoefficients(jfif ? SWS_CS_ITU601 : SWS_CS_ITU709);
        L->sws_setColorspaceDetails(v->sws, cs, 1, cs, jfif ? 1 : 0, 0, 1 << 16, 1 << 16);
        v->sws_w = width;
        v->sws_h = height;
    }
    const uint8_t *src = q->argb;
    if (v->alpha) {
        size_t need = (size_t)width * 4 * (size_t)height;
        if (need > v->straight_cap) {
            free(v->straight);
            if (!(v->straight = malloc(need))) mem_oom();
            v->straight_cap = need;
        }
        for (int y = 0; y < height; y++)
            unpremultiply((uint32_t *)(void *)(v->straight + (size_t)y * (size_t)stride),
                          (const uint32_t *)(const void *)(q->argb + (size_t)y * (size_t)stride), width);
        src = v->straight;
    }
    if (L->av_frame_make_writable(v->frame) < 0) mem_oom();
    L->sws_scale(v->sws, &src, &stride, 0, height, v->frame->data, v->frame->linesize);
    v->frame->pts = q->pts;
    return encode(v, v->frame, err);
}

/* The writer thread: encode the queued pictures in order until closing
 * and the queue is empty; after a failure, the rest are taken and freed
 * unencoded. */
static void *writer_main(void *arg)
{
    VideoOut *v = arg;
    pthread_mutex_lock(&v->lock);
    for (;;) {
        while (v->qcount == 0 && !v->closing) pthread_cond_wait(&v->changed, &v->lock);
        if (v->qcount == 0) break;
        QueuedFrame q = v->queue[v->qhead];
        v->qhead = (v->qhead + 1) % VIDEO_QUEUE;
        v->qcount--;
        bool failed = v->failed;
        pthread_cond_broadcast(&v->changed);
        pthread_mutex_unlock(&v->lock);
        Buf why = BUF_INIT;
        int rc = failed ? 0 : encode_picture(v, &q, &why);
        free(q.argb);
        pthread_mutex_lock(&v->lock);
        if (rc != 0 && !v->failed) {
            v->failed = true;
            snprintf(v->why, sizeof v->why, "%s", buf_line(&why));
        }
        buf_free(&why);
    }
    pthread_mutex_unlock(&v->lock);
    return NULL;
}

int video_frame(VideoOut *v, const unsigned char *argb, int width, int height, int stride, long pts,
                bool drop_when_busy, Buf *err)
{
    pthread_mutex_lock(&v->lock);
    bool failed = v->failed, full = v->qcount == VIDEO_QUEUE;
    if (failed) buf_printf(err, "%s\n", v->why);
    pthread_mutex_unlock(&v->lock);
    if (failed) return -1;
    if (full && drop_when_busy) {
        v->dropped++;
        return 0;
    }
    QueuedFrame q = {malloc((size_t)width * 4 * (size_t)height), width, height, pts};
    if (!q.argb) mem_oom();
    for (int y = 0; y < height; y++)
        memcpy(q.argb + (size_t)y * (size_t)width * 4, argb + (size_t)y * (size_t)stride, (size_t)width * 4);
    pthread_mutex_lock(&v->lock);
    while (v->qcount == VIDEO_QUEUE) pthread_cond_wait(&v->changed, &v->lock);
    v->queue[(v->qhead + v->qcount) % VIDEO_QUEUE] = q;
    v->qcount++;
    pthread_cond_broadcast(&v->changed);
    pthread_mutex_unlock(&v->lock);
    v->frames++;
    return 0;
}

const char *video_encoder(const VideoOut *v) { return v->cc->codec->name; }

int video_close(VideoOut *v, Buf *err)
{
    if (!v) return 0;
    const AvLib *L = v->L;
    pthread_mutex_lock(&v->lock);
    v->closing = true;
    pthread_cond_broadcast(&v->changed);
    pthread_mutex_unlock(&v->lock);
    pthread_join(v->writer, NULL);   /* every queued frame encoded */
    int rc = v->failed ? -1 : 0;
    if (rc != 0)
        buf_printf(err, "%s; the video is not written\n", v->why);
    if (rc == 0 && v->frames == 0) {   /* (limit=0): an empty container is no video */
        buf_printf(err, "%s: no frame was recorded; the video is not written\n", v->out.target);
        rc = -1;
    }
    if (rc == 0) rc = encode(v, NULL, err);
    if (rc == 0 && L->av_write_trailer(v->oc) < 0) {
        buf_printf(err, "%s: cannot finish the video\n", v->out.target);
        rc = -1;
    }
    if (v->oc->pb && L->avio_closep(&v->oc->pb) < 0 && rc == 0) {
        buf_printf(err, "%s: cannot write the video\n", v->out.target);
        rc = -1;
    }
    if (rc == 0) rc = outfile_commit(&v->out, true, err) ? 0 : -1;
    else outfile_discard(&v->out);
    free_video(v);
    return rc;
}
