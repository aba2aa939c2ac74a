/* media_video.c: videos read from files (media.h, media_video_*): one
 * decoding thread per open video, a cache of at most 16 RGBA frames, and
 * the mapping of a position (with loop, back_and_forth and trim) to the
 * frames around it, as Flitter's cache.py read_video_frames does.
 *
 * The cache is a list of frames decoded one after the other since the
 * last seek, in presentation order (list[]), over NSLOT slots (fewer when
 * the memory budget cannot hold 16 frames, never fewer than MIN_SLOTS).
 * The thread works towards the timestamp last asked for (target): a
 * timestamp before the list's first frame seeks back (to the key frame at
 * or before it) and decodes forwards from there, dropping the oldest
 * frames as it goes; one after the list's last frame decodes on, or seeks
 * when the last frame decoded is a key frame and the timestamp lies
 * further ahead than the list spans (Flitter's rule); once the frames
 * around the target are there it decodes ahead, up to AHEAD frames past
 * it, so that playing forwards finds them ready. A seek whose first frame
 * comes after the target (a key frame whose leading B-frames need the one
 * before, as MP4's index by decoding time gives) is done again from a
 * second earlier, then two, ..., then from the start. The frames a caller
 * was given are pinned until its next call: the thread neither reuses nor
 * rewrites them.
 *
 * Locking: every field below `mu` in MediaVideo is read and written under
 * it, by the caller and the thread; the FFmpeg objects and the scaler are
 * the thread's alone after media_video_open; a slot's pixels are written
 * by the thread only while it is `filling` (neither listed nor pinned), so
 * a caller reads a pinned slot's pixels without the lock. The thread
 * sleeps on `work` (a new target, stop) and wakes waiting callers with
 * `done` (the list changed); callers wait with a timeout, polling the
 * interrupt flag.
 *
 * A read error (a damaged or truncated file) ends the list as the end of
 * the file would, and marks the time past the last good frame as damaged:
 * positions there give false and the message, once; the frames before it
 * stay playable. A file cut short often ends without an error: when the
 * video stream's own duration (or, in a file of one stream, the file's)
 * says it goes on for more than a quarter of a second (two frames at
 * least) past the last frame, that is damage too. The memory budget is charged on the caller's thread
 * only (media_video_open reserves the slots, media_video_close gives them
 * back): the decoding thread never touches the budget. */
#include "media_internal.h"

#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#include "mem.h"

/* Frames the cache holds at most (media.h), and at least: the two a
 * caller holds and two consecutive ones around a new position. */
#define NSLOT 16
#define MIN_SLOTS 4
/* Frames decoded ahead of the target's, out of [n] slots. */
#define AHEAD(n) ((n) - 4 > 1 ? (n) - 4 : 1)
/* How long a waiting caller sleeps between looks at the interrupt flag. */
#define WAIT_POLL_NS 20000000L

typedef struct Slot {
    MediaFrame f;         /* f.rgba == buf once filled */
    uint8_t *buf;         /* w*h*4 bytes, allocated by the thread when first filled */
    int64_t pts;          /* presentation time, stream time base */
    bool key;             /* a key frame */
    bool listed;          /* in list[] */
    bool filling;         /* the thread is writing it (not listed) */
    bool pinned;          /* given to the caller until its next call */
} Slot;

struct MediaVideo {
    MediaVideo *next;            /* in the cache's list of videos */
    MediaCache *m;
    const AvLib *L;
    char *path;
    dev_t dev;                   /* the file's identity when opened */
    ino_t ino;
    off_t size;
    struct timespec mtime;
    bool threads;                /* the decoder runs on FFmpeg's threads */
    int w, h;                    /* frame size (the stream's) */
    size_t frame_bytes;          /* w*h*4 */
    int nslots;                  /* MIN_SLOTS..NSLOT, as the budget allowed */
    size_t charged;              /* nslots * frame_bytes, reserved at open */
    AVRational tb;               /* the stream's time base */
    int64_t start;               /* its first timestamp */
    int64_t duration;            /* its duration (tb), -1: unknown */
    int64_t declared_end;        /* where the file says the video ends (tb), -1: it does not say */
    int64_t frame_dur;           /* one frame's nominal duration (tb), >= 1 */
    uint64_t serial_base;        /* this video's number, in the serials' top bits */

    /* the thread's alone */
    MediaStop stopper;           /* the interrupt flag and `stop` */
    atomic_int stop;             /* set by media_video_close */
    MediaInput in;
    AVPacket *pkt;
    AVFrame *frame;
    struct SwsContext *sws;      /* for sws_key's frames */
    int sws_key[5];              /* format, width, height, colour space, range */
    int64_t dec_last_pts;        /* the last frame decoded since the seek */
    pthread_t thread;

    pthread_mutex_t mu;
    pthread_cond_t work;         /* to the thread: a new target, or stop */
    pthread_cond_t done;         /* to callers: the list or its end changed */
    Slot slots[NSLOT];
    int list[NSLOT];             /* slot numbers, by presentation time */
    int nlist;
    bool at_end;                 /* the list's last frame is the last there is (end or damage) */
    bool positioned;             /* the decoder goes on from the list's last frame (or the seek) */
    int64_t floor_ts;            /* INT64_MIN: the list begins at the start of the file, so
                                    targets before list[0] get list[0]; else INT64_MAX */
    int64_t seek_ts;             /* the timestamp the decoder was last sought to
                                    (INT64_MIN: the start) */
    int64_t seeked_for;          /* the target of the last seek */
    bool seek_start;             /* the next seek goes to the start (one to the
                                    target found no frame) */
    int64_t backoff;             /* the next seek goes this far before the target (a
                                    seek to it gave a later frame first), 0: none */
    bool damage_known;           /* timestamps from damage_ts on cannot be read */
    int64_t damage_ts;
    char damage[512];            /* why, "PATH: ..." */
    bool damage_told;            /* given to a caller once */
    int64_t target;              /* the timestamp last asked for */
    bool idle;                   /* the thread gave up on target (interrupt) until the next call */
    int pins[2];                 /* slots given to the caller (-1: none) */
};

/* {===== time */

/* [seconds] in ticks of [tb], computed as Flitter does (a float divided
 * by the time base as a float, truncated towards zero), within what
 * int64_t holds. */
static int64_t ticks(double seconds, AVRational tb)
{
    double t = seconds / ((double)tb.num / (double)tb.den);
    if (!(t == t)) return 0;
    if (t > 4e18) return INT64_C(4000000000000000000);
    if (t < -4e18) return -INT64_C(4000000000000000000);
    return (int64_t)t;
}

/* A finite number of seconds from [x] (NaN: 0), within +-1e12. */
static double seconds(double x)
{
    if (isnan(x)) return 0;
    return x > 1e12 ? 1e12 : x < -1e12 ? -1e12 : x;
}

/* The timestamp read_video_frames gives [position] (see media.h). */
static int64_t timestamp_of(const MediaVideo *v, double position, bool loop, bool back_and_forth, double trim_start,
                            double trim_end)
{
    trim_start = seconds(trim_start) > 0 ? seconds(trim_start) : 0;
    trim_end = seconds(trim_end) > 0 ? seconds(trim_end) : 0;
    int64_t start = v->start + ticks(trim_start, v->tb);
    int64_t pos = ticks(seconds(position), v->tb);
    if (v->duration < 0) return start + (pos > 0 ? pos : 0);   /* unknown length: no wrapping, no end */
    int64_t duration = v->duration - ticks(trim_start + trim_end, v->tb);
    if (duration < 0) duration = 0;
    if (loop && duration > 0) {
        int64_t q = pos / duration, pd = pos % duration;
        if (pd < 0) {   /* Python's floor division and modulo */
            pd += duration;
            q--;
        }
        if (back_and_forth && q % 2 != 0) pd = duration - pd;
        return start + pd;
    }
    return start + (pos < 0 ? 0 : pos > duration ? duration : pos);
}

/* }===== */

/* {===== the list (under mu) */

enum { LOC_EXACT, LOC_DAMAGED, LOC_SEEK, LOC_DECODE };

static Slot *listed(MediaVideo *v, int i) { return &v->slots[v->list[i]]; }

/* Where timestamp [t] stands: LOC_EXACT with the list indices of its
 * frame and the next one (*i1 = -1: none) in *i0 and *i1; LOC_DAMAGED
 * past the damage; LOC_SEEK or LOC_DECODE: what the thread does next to
 * get there. */
static int locate(MediaVideo *v, int64_t t, int *i0, int *i1)
{
    *i0 = *i1 = -1;
    if (v->damage_known && t >= v->damage_ts) return LOC_DAMAGED;
    if (v->nlist == 0) {
        if (v->at_end || !v->positioned || t < v->seek_ts) return LOC_SEEK;
        return LOC_DECODE;
    }
    const Slot *first = listed(v, 0), *last = listed(v, v->nlist - 1);
    if (t < first->pts) {
        if (t >= v->floor_ts) {   /* nothing before list[0] is there */
            *i0 = 0;
            return LOC_EXACT;
        }
        return LOC_SEEK;
    }
    int i = v->nlist - 1;
    while (listed(v, i)->pts > t) i--;   /* stops at 0 at the latest */
    if (i + 1 < v->nlist || v->at_end) {
        *i0 = i;
        *i1 = i + 1 < v->nlist ? i + 1 : -1;
        return LOC_EXACT;
    }
    if (!v->positioned) return LOC_SEEK;
    /* Flitter's rule: at a key frame, a target further on than the list
     * spans is sought rather than decoded to (once per target) */
    if (v->nlist >= 2 && last->key && t - last->pts > last->pts - first->pts && v->seeked_for != t) return LOC_SEEK;
    return LOC_DECODE;
}

/* Take list[0] off the list (its slot is free unless pinned). */
static void drop_first(MediaVideo *v)
{
    v->slots[v->list[0]].listed = false;
    memmove(v->list, v->list + 1, (size_t)(v->nlist - 1) * sizeof *v->list);
    v->nlist--;
    v->floor_ts = INT64_MAX;   /* list[0] no longer begins a seek */
}

static void clear_list(MediaVideo *v)
{
    for (int i = 0; i < v->nlist; i++) listed(v, i)->listed = false;
    v->nlist = 0;
    v->at_end = false;
    v->floor_ts = INT64_MAX;
}

/* A slot for the next frame: a free one, else list[0]'s; when
 * [keep] >= 0 the list's frames from index [keep] on are kept. -1: none. */
static int free_slot(MediaVideo *v, int keep)
{
    for (;;) {
        for (int s = 0; s < v->nslots; s++) {
            const Slot *sl = &v->slots[s];
            if (!sl->listed && !sl->filling && !sl->pinned) return s;
        }
        /* the last frame listed stays: the next one follows it */
        if (v->nlist <= 1 || (keep >= 0 && keep == 0)) return -1;
        drop_first(v);
        if (keep > 0) keep--;
    }
}

/* }===== */

/* {===== the decoding thread */

/* Seek the decoder to the key frame at or before [ts] (else to the
 * start, reopening the file if it cannot seek at all); false when
 * stopped or the file cannot be read again (with the reason appended to
 * [why]). *[floor] is [ts], or INT64_MIN when the decoder went to the
 * start. */
static bool seek_to(MediaVideo *v, int64_t ts, bool from_start, int64_t *floor, Buf *why)
{
    const AvLib *L = v->L;
    int rc = -1;
    *floor = ts;
    if (!from_start) rc = L->av_seek_frame(v->in.fc, v->in.index, ts, AVSEEK_FLAG_BACKWARD);
    if (rc < 0 && !media_stopped(&v->stopper)) {
        rc = L->av_seek_frame(v->in.fc, v->in.index, v->start, AVSEEK_FLAG_BACKWARD);
        *floor = INT64_MIN;
    }
    if (rc >= 0) {
        L->avcodec_flush_buffers(v->in.cc);
        v->in.draining = false;
        return true;
    }
    if (media_stopped(&v->stopper)) return false;
    /* a file that cannot seek: read it again from the start */
    media_input_close(L, &v->in);
    *floor = INT64_MIN;
    return media_input_open(L, v->path, false, v->threads, &v->stopper, &v->in, why);
}

/* Convert v->frame into slot [s] (thread, without the lock: the slot is
 * filling). False when the pixels cannot be converted. */
static bool convert(MediaVideo *v, Slot *s)
{
    const AvLib *L = v->L;
    const AVFrame *f = v->frame;
    int key[5] = {f->format, f->width, f->height, f->colorspace, f->color_range};
    if (!v->sws || memcmp(key, v->sws_key, sizeof key) != 0) {
        L->sws_freeContext(v->sws);
        v->sws = media_scaler(L, f, v->w, v->h);
        memcpy(v->sws_key, key, sizeof key);
        if (!v->sws) return false;
    }
    if (!s->buf) s->buf = mem_alloc(v->frame_bytes);
    uint8_t *dst[4] = {s->buf, NULL, NULL, NULL};
    int stride[4] = {v->w * 4, 0, 0, 0};
    L->sws_scale(v->sws, (const uint8_t *const *)f->data, f->linesize, 0, f->height, dst, stride);
    return true;
}

static bool key_frame(const AVFrame *f)
{
#if LIBAVUTIL_VERSION_INT >= AV_VERSION_INT(58, 7, 100)
    return (f->flags & AV_FRAME_FLAG_KEY) != 0;
#else
    return f->key_frame != 0;
#endif
}

/* Mark the time from [ts] on as damaged, with [reason] (an AVERROR, or 0
 * with [text]). Under mu. */
static void mark_damage(MediaVideo *v, int64_t ts, int reason, const char *text)
{
    if (v->damage_known && v->damage_ts <= ts) return;
    bool first = !v->damage_known;
    v->damage_known = true;
    v->damage_ts = ts;
    if (!first) return;
    char why[AV_ERROR_MAX_STRING_SIZE];
    if (reason) media_av_error(v->L, reason, why, sizeof why);
    if (text) {
        snprintf(v->damage, sizeof v->damage, "%s", text);
    } else if (ts <= v->start) {
        snprintf(v->damage, sizeof v->damage, "%s: no frame can be read (%s)", v->path, reason ? why : "no frame");
    } else {
        double at = (double)(ts - v->start) * v->tb.num / v->tb.den;
        snprintf(v->damage, sizeof v->damage, "%s: the video is damaged or truncated after %.3f s (%s)", v->path,
                 at, reason ? why : "no frame");
    }
}

/* One step towards target: seek, or decode a frame into a slot. Called
 * and returns with mu held; false when there is nothing to do. */
static bool step(MediaVideo *v)
{
    int i0, i1, keep = -1;
    int loc = v->idle ? LOC_DAMAGED : locate(v, v->target, &i0, &i1);
    if (loc == LOC_EXACT) {   /* decode ahead, keeping the target's frames */
        if (v->at_end || !v->positioned || v->nlist - 1 - i0 >= AHEAD(v->nslots)) return false;
        keep = i0;
    } else if (loc == LOC_DAMAGED) {
        return false;
    }
    const AvLib *L = v->L;
    int64_t target = v->target;
    if (loc == LOC_SEEK) {
        bool from_start = v->seek_start;
        int64_t seek_ts = target;
        if (v->backoff > 0) {
            if (target - v->start <= v->backoff) from_start = true;
            else seek_ts = target - v->backoff;
        }
        clear_list(v);
        v->positioned = false;
        v->seeked_for = target;
        v->seek_start = false;
        pthread_mutex_unlock(&v->mu);
        int64_t floor;
        Buf why = BUF_INIT;
        bool ok = seek_to(v, seek_ts, from_start, &floor, &why);
        v->dec_last_pts = INT64_MIN;
        pthread_mutex_lock(&v->mu);
        if (ok) {
            v->positioned = true;
            v->seek_ts = floor;
            v->floor_ts = floor == INT64_MIN ? INT64_MIN : INT64_MAX;
        } else if (why.len) {
            mark_damage(v, INT64_MIN, 0, buf_line(&why));
        } else {
            v->idle = true;   /* stopped: the next call tries again */
        }
        buf_free(&why);
        pthread_cond_broadcast(&v->done);
        return true;
    }
    int s = free_slot(v, keep);
    if (s < 0) return false;
    Slot *slot = &v->slots[s];
    slot->filling = true;
    int64_t prev = v->nlist ? listed(v, v->nlist - 1)->pts : INT64_MIN;
    pthread_mutex_unlock(&v->mu);

    int why = 0;
    int rc = media_decode_next(L, &v->in, v->pkt, v->frame, &v->stopper, &why);
    int64_t pts = 0;
    bool usable = false;
    if (rc == MEDIA_FRAME) {
        /* the frame's own pts (as PyAV gives Flitter): FFmpeg's best
         * effort switches to decoding times after a seek into B-frames */
        pts = v->frame->pts;
        if (pts == AV_NOPTS_VALUE) pts = v->frame->best_effort_timestamp;
        if (pts == AV_NOPTS_VALUE) pts = v->dec_last_pts == INT64_MIN ? v->start : v->dec_last_pts + v->frame_dur;
        /* frames out of order (a broken file) are dropped */
        usable = (v->dec_last_pts == INT64_MIN || pts > v->dec_last_pts) && convert(v, slot);
        if (usable) {
            v->dec_last_pts = pts;
            uint64_t offset = (uint64_t)pts - (uint64_t)v->start;   /* (wraps, never overflows) */
            slot->f = (MediaFrame){v->w, v->h, slot->buf, v->serial_base | (offset & ((UINT64_C(1) << 44) - 1))};
            slot->pts = pts;
            slot->key = key_frame(v->frame);
        }
        L->av_frame_unref(v->frame);
    }

    pthread_mutex_lock(&v->mu);
    slot->filling = false;
    if (usable && v->nlist == 0 && v->floor_ts != INT64_MIN && v->target == v->seeked_for && pts > v->target) {
        /* the seek overshot (to a key frame whose leading B-frames cannot
         * be decoded without the one before): again, from further back */
        int64_t first = ticks(1.0, v->tb) > 4 * v->frame_dur ? ticks(1.0, v->tb) : 4 * v->frame_dur;
        v->backoff = v->backoff == 0 ? first : v->backoff < INT64_MAX / 4 ? 2 * v->backoff : v->backoff;
        v->positioned = false;
        usable = false;
    } else if (usable && v->nlist == 0) {
        v->backoff = 0;
    }
    if (usable) {
        v->slots[s].listed = true;
        v->list[v->nlist++] = s;
    } else if (rc == MEDIA_END) {
        v->at_end = true;
        if (v->nlist == 0) {
            if (v->floor_ts != INT64_MIN) {   /* no frame after a seek: read on from the start */
                v->seek_start = true;
                v->positioned = false;
            } else {   /* none in the whole file */
                mark_damage(v, INT64_MIN, 0, NULL);
            }
        } else if (v->declared_end >= 0) {   /* a file cut short ends early, without an error */
            int64_t end = prev + v->frame_dur, slack = ticks(0.25, v->tb);
            if (slack < 2 * v->frame_dur) slack = 2 * v->frame_dur;
            if (end < v->declared_end - slack) {
                char text[512];
                snprintf(text, sizeof text, "%s: the video is truncated: it ends at %.3f s of %.3f s", v->path,
                         (double)(end - v->start) * v->tb.num / v->tb.den,
                         (double)(v->declared_end - v->start) * v->tb.num / v->tb.den);
                mark_damage(v, end, 0, text);
            }
        }
    } else if (rc == MEDIA_DAMAGED) {
        v->at_end = true;
        int64_t at = v->nlist ? prev + v->frame_dur : v->seek_ts;
        mark_damage(v, at, why, NULL);
    } else if (rc == MEDIA_STOP) {
        v->positioned = false;   /* the demuxer may be anywhere: seek first */
        v->idle = true;
    }
    pthread_cond_broadcast(&v->done);
    return true;
}

static void *thread_main(void *arg)
{
    MediaVideo *v = arg;
    pthread_mutex_lock(&v->mu);
    while (!atomic_load_explicit(&v->stop, memory_order_relaxed)) {
        if (!step(v)) pthread_cond_wait(&v->work, &v->mu);
    }
    pthread_mutex_unlock(&v->mu);
    return NULL;
}

/* }===== */

/* {===== the caller's side */

static void video_free(MediaVideo *v)
{
    const AvLib *L = v->L;
    for (int s = 0; s < NSLOT; s++) free(v->slots[s].buf);
    if (L) {
        L->sws_freeContext(v->sws);
        L->av_frame_free(&v->frame);
        L->av_packet_free(&v->pkt);
        media_input_close(L, &v->in);
    }
    if (v->m) mem_budget_release(v->m->budget, v->charged);
    free(v->path);
    free(v);
}

/* media_video_open with [err] not NULL. */
static MediaVideo *open_video(MediaCache *m, const char *path, bool threads, Buf *err)
{
    if (!m || !path || !*path) {
        buf_printf(err, "%s: no such file\n", path && *path ? path : "(no file name)");
        return NULL;
    }
    struct stat sb;
    if (stat(path, &sb) != 0) {
        buf_printf(err, "%s: %s\n", path, errno == ENOENT ? "no such file" : strerror(errno));
        return NULL;
    }
    if (S_ISDIR(sb.st_mode)) {
        buf_printf(err, "%s: not a video (a folder)\n", path);
        return NULL;
    }
    const AvLib *L = media_lib(m, path, err);
    if (!L) return NULL;
    MediaVideo *v = mem_calloc(1, sizeof *v);
    v->L = L;
    v->path = mem_strdup(path);
    v->dev = sb.st_dev;
    v->ino = sb.st_ino;
    v->size = sb.st_size;
    v->mtime = sb.st_mtim;
    atomic_init(&v->stop, 0);
    v->stopper = (MediaStop){m->interrupt, &v->stop};
    v->in.index = -1;
    v->threads = threads;
    if (!media_input_open(L, path, false, threads, &v->stopper, &v->in, err)) {
        video_free(v);
        return NULL;
    }
    const AVStream *st = v->in.st;
    v->w = v->in.cc->width;
    v->h = v->in.cc->height;
    if (v->w <= 0 || v->h <= 0) {
        buf_printf(err, "%s: the video has no picture size\n", path);
        video_free(v);
        return NULL;
    }
    v->frame_bytes = (size_t)v->w * (size_t)v->h * 4;
    for (v->nslots = NSLOT; v->nslots >= MIN_SLOTS; v->nslots--) {
        if (mem_budget_reserve(m->budget, (size_t)v->nslots * v->frame_bytes)) break;
    }
    if (v->nslots < MIN_SLOTS) {
        buf_printf(err, "%s: out of memory for %dx%d frames (past the memory budget, --max-memory)\n", path,
                   v->w, v->h);
        video_free(v);
        return NULL;
    }
    v->m = m;
    v->charged = (size_t)v->nslots * v->frame_bytes;
    v->tb = st->time_base.num > 0 && st->time_base.den > 0 ? st->time_base : (AVRational){1, AV_TIME_BASE};
    v->start = st->start_time != AV_NOPTS_VALUE ? st->start_time : 0;
    v->duration = v->declared_end = -1;
    if (st->duration != AV_NOPTS_VALUE && st->duration > 0) {
        v->duration = st->duration;
        v->declared_end = v->start + v->duration;
    } else if (v->in.fc->duration != AV_NOPTS_VALUE && v->in.fc->duration > 0) {
        /* (Matroska keeps no stream durations: the file's, from its start;
         * with other streams, such as a longer sound track, that is not
         * where the video must end) */
        int64_t fstart = v->in.fc->start_time != AV_NOPTS_VALUE ? v->in.fc->start_time : 0;
        int64_t end = L->av_rescale_q(fstart + v->in.fc->duration, AV_TIME_BASE_Q, v->tb);
        if (end > v->start) v->duration = end - v->start;
        if (end > v->start && v->in.fc->nb_streams == 1) v->declared_end = end;
    }
    AVRational rate = st->avg_frame_rate.num > 0 && st->avg_frame_rate.den > 0 ? st->avg_frame_rate : st->r_frame_rate;
    v->frame_dur = 1;
    if (rate.num > 0 && rate.den > 0) {
        int64_t d = L->av_rescale_q(1, (AVRational){rate.den, rate.num}, v->tb);
        if (d > 1) v->frame_dur = d;
    }
    v->serial_base = m->next_video++ << 44;
    if (!(v->pkt = L->av_packet_alloc()) || !(v->frame = L->av_frame_alloc())) mem_oom();
    v->dec_last_pts = INT64_MIN;
    /* the file is open at its start: the first frames come without a seek */
    v->positioned = true;
    v->floor_ts = v->seek_ts = INT64_MIN;
    v->seeked_for = INT64_MIN;
    v->target = v->start;
    v->pins[0] = v->pins[1] = -1;
    pthread_condattr_t ca;
    pthread_condattr_init(&ca);
    pthread_condattr_setclock(&ca, CLOCK_MONOTONIC);
    pthread_mutex_init(&v->mu, NULL);
    pthread_cond_init(&v->work, &ca);
    pthread_cond_init(&v->done, &ca);
    pthread_condattr_destroy(&ca);
    int rc = pthread_create(&v->thread, NULL, thread_main, v);
    if (rc != 0) {
        buf_printf(err, "%s: cannot start a decoding thread: %s\n", path, strerror(rc));
        pthread_cond_destroy(&v->work);
        pthread_cond_destroy(&v->done);
        pthread_mutex_destroy(&v->mu);
        video_free(v);
        return NULL;
    }
    v->next = m->videos;
    m->videos = v;
    return v;
}

MediaVideo *media_video_open(MediaCache *m, const char *path, bool threads, Buf *err)
{
    if (err) return open_video(m, path, threads, err);
    Buf ignored = BUF_INIT;
    MediaVideo *v = open_video(m, path, threads, &ignored);
    buf_free(&ignored);
    return v;
}

bool media_video_current(const MediaVideo *v, const char *path)
{
    struct stat sb;
    return v && path && strcmp(v->path, path) == 0 && stat(path, &sb) == 0 && sb.st_dev == v->dev &&
           sb.st_ino == v->ino && sb.st_size == v->size && sb.st_mtim.tv_sec == v->mtime.tv_sec &&
           sb.st_mtim.tv_nsec == v->mtime.tv_nsec;
}

/* The slot whose frame is nearest [t] among the listed and the pinned
 * ones (-1: none). Under mu. */
static int nearest(MediaVideo *v, int64_t t)
{
    int best = -1;
    uint64_t best_d = UINT64_MAX;
    for (int s = 0; s < v->nslots; s++) {
        const Slot *sl = &v->slots[s];
        if (!sl->listed && !sl->pinned) continue;
        uint64_t d = sl->pts > t ? (uint64_t)sl->pts - (uint64_t)t : (uint64_t)t - (uint64_t)sl->pts;
        if (d < best_d) best = s, best_d = d;
    }
    return best;
}

bool media_video_frames(MediaVideo *v, double position, bool loop, bool back_and_forth, double trim_start,
                        double trim_end, bool wait, double *ratio, const MediaFrame **f0, const MediaFrame **f1,
                        Buf *err)
{
    if (ratio) *ratio = 0;
    if (f0) *f0 = NULL;
    if (f1) *f1 = NULL;
    if (!v) {
        if (err) buf_printf(err, "no video\n");
        return false;
    }
    int64_t t = timestamp_of(v, position, loop, back_and_forth, trim_start, trim_end);
    pthread_mutex_lock(&v->mu);
    if (t != v->target || v->idle) {
        v->target = t;
        v->idle = false;
        pthread_cond_signal(&v->work);
    }
    int i0, i1, loc;
    /* ends: the thread settles every target (frames, damage, or idle
     * when interrupted), and the interrupt flag is polled */
    for (;;) {
        loc = locate(v, t, &i0, &i1);
        if (loc == LOC_EXACT || loc == LOC_DAMAGED || !wait || v->idle || media_flag_set(v->m->interrupt)) break;
        struct timespec until;
        clock_gettime(CLOCK_MONOTONIC, &until);
        until.tv_nsec += WAIT_POLL_NS;
        if (until.tv_nsec >= 1000000000L) {
            until.tv_sec++;
            until.tv_nsec -= 1000000000L;
        }
        pthread_cond_timedwait(&v->done, &v->mu, &until);
    }
    int s0 = -1, s1 = -1;
    double r = 0;
    bool ok = true;
    if (loc == LOC_EXACT) {
        s0 = v->list[i0];
        if (i1 >= 0) {
            s1 = v->list[i1];
            const Slot *a = &v->slots[s0], *b = &v->slots[s1];
            if (t > a->pts) r = (double)(t - a->pts) / (double)(b->pts - a->pts);
        }
    } else if (loc == LOC_DAMAGED) {
        ok = false;
        if (!v->damage_told) {
            if (err) buf_printf(err, "%s\n", v->damage);
            v->damage_told = true;
        }
    } else if ((s0 = nearest(v, t)) < 0) {
        ok = false;   /* nothing decoded yet */
    }
    for (int k = 0; k < 2; k++)
        if (v->pins[k] >= 0) v->slots[v->pins[k]].pinned = false;
    v->pins[0] = s0;
    v->pins[1] = s1;
    if (s0 >= 0) v->slots[s0].pinned = true;
    if (s1 >= 0) v->slots[s1].pinned = true;
    pthread_cond_signal(&v->work);   /* slots may have come free for decoding ahead */
    if (ok) {
        if (f0) *f0 = &v->slots[s0].f;
        if (f1 && s1 >= 0) *f1 = &v->slots[s1].f;
        if (ratio) *ratio = r;
    }
    pthread_mutex_unlock(&v->mu);
    return ok;
}

void media_video_close(MediaVideo *v)
{
    if (!v) return;
    pthread_mutex_lock(&v->mu);
    atomic_store_explicit(&v->stop, 1, memory_order_relaxed);
    pthread_cond_broadcast(&v->work);
    pthread_mutex_unlock(&v->mu);
    pthread_join(v->thread, NULL);
    pthread_cond_destroy(&v->work);
    pthread_cond_destroy(&v->done);
    pthread_mutex_destroy(&v->mu);
    for (MediaVideo **link = &v->m->videos; *link; link = &(*link)->next) {
        if (*link == v) {
            *link = v->next;
            break;
        }
    }
    video_free(v);
}

void media_videos_close_all(MediaCache *m)
{
    while (m->videos) media_video_close(m->videos);
}

/* }===== */
