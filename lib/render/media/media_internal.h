/* media_internal.h: what the media files share: the MediaCache's fields
 * (media_cache.c makes and frees it, media_image.c keeps its pictures in
 * it, media_video.c lists its open videos there), opening a file's video
 * stream and its decoder, stepping the decoder one frame at a time, and
 * the conversion of decoded frames to RGBA. Not for other layers: they
 * see media.h. */
#ifndef FL_RENDER_MEDIA_INTERNAL_H
#define FL_RENDER_MEDIA_INTERNAL_H

#include <stdatomic.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "avlib.h"
#include "media.h"

/* The largest side of a picture or a video frame, in pixels. */
#define MEDIA_MAX_SIDE 16384

typedef struct ImageEntry ImageEntry;

struct MediaCache {
    MemBudget *budget;          /* charged for held pixels (NULL: none) */
    volatile int *interrupt;    /* polled by long decoding loops (NULL: none) */
    AvLib *L;                   /* FFmpeg, loaded on first need (NULL: not yet or failed) */
    char lib_failure[300];      /* why loading FFmpeg failed ("": not tried or loaded) */
    ImageEntry **buckets;       /* pictures by path (media_image.c) */
    size_t nbuckets, nentries;
    uint64_t next_version;      /* MediaImage.version of the next picture made */
    uint64_t next_video;        /* number of the next video opened (frame serials) */
    MediaVideo *videos;         /* the open videos, linked through their `next` */
};

/* FFmpeg, loaded for [m] the first time; NULL with "PATH: REASON"
 * appended to [err] when the libraries cannot be loaded (the same reason
 * every time, without trying again). */
const AvLib *media_lib(MediaCache *m, const char *path, Buf *err);

/* Whether *[flag] is set (NULL: never); an atomic read, as the flag is
 * written by a signal handler or another thread. */
bool media_flag_set(volatile int *flag);

/* What stops FFmpeg's blocking work (its interrupt callback and the
 * decoding loops): the runtime's interrupt flag and, for a video, its
 * thread's stop flag. */
typedef struct MediaStop {
    volatile int *interrupt;    /* may be NULL */
    atomic_int *stop;           /* may be NULL */
} MediaStop;

bool media_stopped(const MediaStop *s);

/* One file's best video stream and its open decoder. */
typedef struct MediaInput {
    AVFormatContext *fc;
    AVCodecContext *cc;
    AVStream *st;
    int index;                  /* st's index in fc */
    bool draining;              /* the demuxer is at its end: the decoder was sent NULL */
    int last_error;             /* the last decoder error (AVERROR), 0: none */
} MediaInput;

/* Open [path]'s best video stream and its decoder into [in]: for a
 * [picture] only the demuxers of single pictures are taken (FFmpeg's
 * image2, *_pipe, gif, apng), for a video any but the text one (tty, which
 * would play any text file); with [threads] the decoder runs on FFmpeg's
 * threads. Only local files are opened (protocol "file"), file names are
 * never patterns. [stop] (kept, must outlive [in]) interrupts FFmpeg's
 * reading.
 *   errors: false with "PATH: REASON" appended to [err], [in] left
 *           closed. */
bool media_input_open(const AvLib *L, const char *path, bool picture, bool threads, MediaStop *stop,
                      MediaInput *in, Buf *err);
/* Close what media_input_open opened (a closed [in] is a no-op). */
void media_input_close(const AvLib *L, MediaInput *in);

/* The result of media_decode_next besides a frame. */
enum { MEDIA_FRAME = 1, MEDIA_END = 0, MEDIA_STOP = -1, MEDIA_DAMAGED = -2 };

/* Decode the next frame of [in] into [frame] (unreferenced first), with
 * [pkt] as scratch. Packets the decoder refuses are skipped (it conceals
 * what it can); a read error, or 64 refused packets in a row, is damage.
 *   returns: MEDIA_FRAME, MEDIA_END at the end of the stream,
 *            MEDIA_STOP when [stop] said so (in is then in an unknown
 *            place: seek before going on), MEDIA_DAMAGED with the reason
 *            (AVERROR) in *[why]. */
int media_decode_next(const AvLib *L, MediaInput *in, AVPacket *pkt, AVFrame *frame, const MediaStop *stop,
                      int *why);

/* A scaler from [f]'s format and size to [dw] x [dh] RGBA (bilinear),
 * converting YUV with the frame's matrix and range (BT.601 and limited
 * range when the file does not say; JPEG's full range); NULL when swscale
 * cannot. Free with sws_freeContext. */
struct SwsContext *media_scaler(const AvLib *L, const AVFrame *f, int dw, int dh);

/* FFmpeg's text for error [rc] in [buf]. */
void media_av_error(const AvLib *L, int rc, char *buf, size_t len);

/* Seconds of the monotonic clock. */
double media_now(void);

/* Stop and free every video of [m] (media_video.c; media_cache_free). */
void media_videos_close_all(MediaCache *m);
/* Free every picture of [m] (media_image.c; media_cache_free). */
void media_images_free(MediaCache *m);
/* Forget [m]'s pictures and resized copies last asked for before
 * [before] (media_now seconds; media_cache_expire). */
void media_images_expire(MediaCache *m, double before);

#endif
