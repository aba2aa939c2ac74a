/* media_decode.c: the decoding steps pictures and videos share (see
 * media_internal.h): opening a local file's best video stream with its
 * decoder, taking the next frame out of it, and the scaler that turns a
 * decoded frame into RGBA.
 *
 * FFmpeg's blocking work is interrupted through the format context's
 * interrupt callback, which reads the runtime's interrupt flag and the
 * video thread's stop flag (MediaStop): the only state it sees. */
#include "media_internal.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "mem.h"

bool media_flag_set(volatile int *flag) { return flag && __atomic_load_n(flag, __ATOMIC_RELAXED) != 0; }

bool media_stopped(const MediaStop *s)
{
    return s && (media_flag_set(s->interrupt) || (s->stop && atomic_load_explicit(s->stop, memory_order_relaxed)));
}

/* FFmpeg's interrupt callback: non-zero stops the blocking call. */
static int interrupt_cb(void *opaque) { return media_stopped(opaque); }

void media_av_error(const AvLib *L, int rc, char *buf, size_t len)
{
    if (L->av_strerror(rc, buf, len) < 0) snprintf(buf, len, "error %d", rc);
}

double media_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* Whether demuxer [name] reads single pictures (img2dec.c's image2 and
 * *_pipe demuxers, and the GIF and APNG ones, whose first frame is taken). */
static bool picture_demuxer(const char *name)
{
    size_t n = strlen(name);
    if (n > 5 && strcmp(name + n - 5, "_pipe") == 0) return true;
    return strcmp(name, "image2") == 0 || strcmp(name, "gif") == 0 || strcmp(name, "apng") == 0;
}

void media_input_close(const AvLib *L, MediaInput *in)
{
    if (in->cc) L->avcodec_free_context(&in->cc);
    if (in->fc) L->avformat_close_input(&in->fc);
    in->st = NULL;
    in->index = -1;
    in->draining = false;
}

bool media_input_open(const AvLib *L, const char *path, bool picture, bool threads, MediaStop *stop,
                      MediaInput *in, Buf *err)
{
    memset(in, 0, sizeof *in);
    in->index = -1;
    const char *what = picture ? "picture" : "video";
    char why[AV_ERROR_MAX_STRING_SIZE];
    AVFormatContext *fc = L->avformat_alloc_context();
    if (!fc) mem_oom();
    fc->interrupt_callback.callback = interrupt_cb;
    fc->interrupt_callback.opaque = stop;
    /* local files only (a name like http://... or concat:... is not
     * followed), and image2 takes the name as it is, not as a pattern */
    AVDictionary *opts = NULL;
    L->av_dict_set(&opts, "protocol_whitelist", "file", 0);
    L->av_dict_set(&opts, "pattern_type", "none", 0);
    char *url = mem_asprintf("file:%s", path);
    int rc = L->avformat_open_input(&fc, url, NULL, &opts);   /* frees fc on failure */
    free(url);
    L->av_dict_free(&opts);
    if (rc < 0) {
        if (media_stopped(stop)) {
            buf_printf(err, "%s: interrupted\n", path);
        } else if (rc == AVERROR(ENOENT) || rc == AVERROR(EACCES) || rc == AVERROR(EISDIR)) {
            media_av_error(L, rc, why, sizeof why);
            buf_printf(err, "%s: %s\n", path, why);
        } else {
            media_av_error(L, rc, why, sizeof why);
            buf_printf(err, "%s: not a %s (%s)\n", path, what, why);
        }
        return false;
    }
    in->fc = fc;
    const char *demuxer = fc->iformat->name;
    if (picture ? !picture_demuxer(demuxer) : strcmp(demuxer, "tty") == 0) {
        buf_printf(err, "%s: not a %s (a %s file)\n", path, what, strcmp(demuxer, "tty") == 0 ? "text" : demuxer);
        media_input_close(L, in);
        return false;
    }
    if ((rc = L->avformat_find_stream_info(fc, NULL)) < 0) {
        media_av_error(L, rc, why, sizeof why);
        buf_printf(err, "%s: %s\n", path, media_stopped(stop) ? "interrupted" : why);
        media_input_close(L, in);
        return false;
    }
    const AVCodec *codec = NULL;
    int index = L->av_find_best_stream(fc, AVMEDIA_TYPE_VIDEO, -1, -1, &codec, 0);
    if (index == AVERROR_DECODER_NOT_FOUND) {
        buf_printf(err, "%s: no decoder for its %s\n", path, what);
        media_input_close(L, in);
        return false;
    }
    if (index < 0 || !codec) {
        buf_printf(err, picture ? "%s: not a picture (no picture in it)\n" : "%s: no video stream\n", path);
        media_input_close(L, in);
        return false;
    }
    in->index = index;
    in->st = fc->streams[index];
    for (unsigned i = 0; i < fc->nb_streams; i++)   /* the demuxer drops the other streams' packets */
        if ((int)i != index) fc->streams[i]->discard = AVDISCARD_ALL;
    const AVCodecParameters *par = in->st->codecpar;
    if (par->width > MEDIA_MAX_SIDE || par->height > MEDIA_MAX_SIDE) {
        buf_printf(err, "%s: %dx%d pixels, past %d a side\n", path, par->width, par->height, MEDIA_MAX_SIDE);
        media_input_close(L, in);
        return false;
    }
    if (!(in->cc = L->avcodec_alloc_context3(codec))) mem_oom();
    if ((rc = L->avcodec_parameters_to_context(in->cc, par)) < 0) {
        media_av_error(L, rc, why, sizeof why);
        buf_printf(err, "%s: cannot read its %s: %s\n", path, what, why);
        media_input_close(L, in);
        return false;
    }
    in->cc->pkt_timebase = in->st->time_base;
    in->cc->thread_count = threads ? 0 : 1;   /* 0: as many as FFmpeg thinks fit */
    if (threads) in->cc->thread_type = FF_THREAD_FRAME | FF_THREAD_SLICE;
    if ((rc = L->avcodec_open2(in->cc, codec, NULL)) < 0) {
        media_av_error(L, rc, why, sizeof why);
        buf_printf(err, "%s: cannot open the %s decoder: %s\n", path, codec->name, why);
        media_input_close(L, in);
        return false;
    }
    return true;
}

/* Refused packets in a row that make a stream damaged. */
#define MEDIA_MAX_REFUSED 64

int media_decode_next(const AvLib *L, MediaInput *in, AVPacket *pkt, AVFrame *frame, const MediaStop *stop,
                      int *why)
{
    L->av_frame_unref(frame);
    int refused = 0;
    /* ends: each pass either takes a frame out, or reads a packet of the
     * file (finite), or counts a refusal; the flag is polled every pass */
    for (;;) {
        if (media_stopped(stop)) return MEDIA_STOP;
        int rc = L->avcodec_receive_frame(in->cc, frame);
        if (rc >= 0) return MEDIA_FRAME;
        if (rc == AVERROR_EOF) return MEDIA_END;
        if (rc != AVERROR(EAGAIN)) {   /* a frame the decoder could not make */
            in->last_error = rc;
            if (++refused >= MEDIA_MAX_REFUSED) {
                *why = rc;
                return MEDIA_DAMAGED;
            }
            continue;
        }
        if (in->draining) return MEDIA_END;   /* (a decoder asking for input after NULL) */
        rc = L->av_read_frame(in->fc, pkt);
        if (rc == AVERROR_EOF) {
            in->draining = true;
            L->avcodec_send_packet(in->cc, NULL);
            continue;
        }
        if (rc < 0) {
            if (media_stopped(stop)) return MEDIA_STOP;
            *why = rc;
            return MEDIA_DAMAGED;
        }
        if (pkt->stream_index != in->index) {
            L->av_packet_unref(pkt);
            continue;
        }
        rc = L->avcodec_send_packet(in->cc, pkt);
        L->av_packet_unref(pkt);
        if (rc < 0 && rc != AVERROR(EAGAIN)) {   /* a packet refused: skipped */
            in->last_error = rc;
            if (++refused >= MEDIA_MAX_REFUSED) {
                *why = rc;
                return MEDIA_DAMAGED;
            }
        }
    }
}

/* swscale's matrix for colour space [cs] (BT.601 when unknown). */
static int sws_matrix(enum AVColorSpace cs)
{
    switch (cs) {
    case AVCOL_SPC_BT709: return SWS_CS_ITU709;
    case AVCOL_SPC_FCC: return SWS_CS_FCC;
    case AVCOL_SPC_SMPTE240M: return SWS_CS_SMPTE240M;
    case AVCOL_SPC_BT2020_NCL:
    case AVCOL_SPC_BT2020_CL: return SWS_CS_BT2020;
    default: return SWS_CS_DEFAULT;   /* BT.470BG, SMPTE 170M and unspecified: BT.601 */
    }
}

struct SwsContext *media_scaler(const AvLib *L, const AVFrame *f, int dw, int dh)
{
    enum AVPixelFormat fmt = (enum AVPixelFormat)f->format;
    const AVPixFmtDescriptor *d = L->av_pix_fmt_desc_get(fmt);
    if (!d || f->width <= 0 || f->height <= 0) return NULL;
    struct SwsContext *s = L->sws_getContext(f->width, f->height, fmt, dw, dh, AV_PIX_FMT_RGBA,
                                             SWS_BILINEAR | SWS_ACCURATE_RND | SWS_FULL_CHR_H_INT, NULL, NULL, NULL);
    if (!s) return NULL;
    /* YUV: the frame's matrix and range (the deprecated yuvj formats are
     * JPEG's full range); grey and RGB need neither */
    bool yuv = !(d->flags & (AV_PIX_FMT_FLAG_RGB | AV_PIX_FMT_FLAG_PAL)) && d->nb_components >= 3;
    if (yuv) {
        bool full = f->color_range == AVCOL_RANGE_JPEG || fmt == AV_PIX_FMT_YUVJ420P || fmt == AV_PIX_FMT_YUVJ422P ||
                    fmt == AV_PIX_FMT_YUVJ444P || fmt == AV_PIX_FMT_YUVJ440P || fmt == AV_PIX_FMT_YUVJ411P;
        const int *coefs = L->sws_getCoefficients(sws_matrix(f->colorspace));
        L->sws_setColorspaceDetails(s, coefs, full, coefs, 1, 0, 1 << 16, 1 << 16);
    }
    return s;
}
