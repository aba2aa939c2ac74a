/* record.c: !record's PNG, GIF and video files (see record.h).
 *
 * The recorder keeps one slot per file name that stays open across frames:
 * an animated GIF or a video, or a video that could not be started (kept
 * so that it is not retried every frame). Slots are found by the name as
 * written in the script; they are finished in recorder_free, or, for a
 * video with limit=, once limit*fps frames are written.
 */
#include "record.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include "gifout.h"
#include "mem.h"
#include "outfile.h"

/* last: it turns the library's names into calls through its table */
#include "cairo_lib.h"

typedef struct Slot {
    char *path;       /* the file name as given */
    GifOut *gif;      /* an animation, or NULL */
    VideoOut *video;  /* a video, or NULL */
    long max_frames;  /* video frames to write (limit=), or -1: no limit */
    double start;     /* the frame clock's time at the video's first frame */
    long last_pts;    /* the last frame's presentation time, in frames */
    bool done;        /* finished by its limit: later frames are ignored */
    char *error;      /* the video could not be started: this message */
} Slot;

struct Recorder {
    Slot *slots;
    size_t nslots;
};

Recorder *recorder_new(void)
{
    Recorder *rec = calloc(1, sizeof *rec);
    if (!rec) mem_oom();
    return rec;
}

static bool ends_with(const char *s, const char *tail)
{
    size_t a = strlen(s), b = strlen(tail);
    return a >= b && strcasecmp(s + a - b, tail) == 0;
}

static Slot *find_slot(Recorder *rec, const char *path)
{
    for (size_t i = 0; i < rec->nslots; i++)
        if (strcmp(rec->slots[i].path, path) == 0) return &rec->slots[i];
    return NULL;
}

static Slot *add_slot(Recorder *rec, const char *path)
{
    Slot *s = realloc(rec->slots, (rec->nslots + 1) * sizeof *s);
    if (!s) mem_oom();
    rec->slots = s;
    s = &rec->slots[rec->nslots++];
    *s = (Slot){.path = strdup(path), .max_frames = -1};
    if (!s->path) mem_oom();
    return s;
}

/* cairo's PNG writer output: to the temporary's descriptor. */
static cairo_status_t write_fd(void *closure, const unsigned char *data, unsigned int len)
{
    int fd = *(const int *)closure;
    while (len > 0) {
        ssize_t w = write(fd, data, len);
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) return CAIRO_STATUS_WRITE_ERROR;
        data += w;
        len -= (unsigned int)w;
    }
    return CAIRO_STATUS_SUCCESS;
}

static int write_png(const RecordSpec *s, cairo_surface_t *pic, Buf *err)
{
    OutFile f;
    if (!outfile_open(&f, s->path, err)) return -1;
    cairo_status_t st;
    if (s->keep_alpha) {
        st = cairo_surface_write_to_png_stream(pic, write_fd, &f.fd);
    } else {   /* opaque: premultiplied colour over black */
        int w = cairo_image_surface_get_width(pic), h = cairo_image_surface_get_height(pic);
        cairo_surface_t *rgb = cairo_image_surface_create(CAIRO_FORMAT_RGB24, w, h);
        cairo_t *cr = cairo_create(rgb);
        cairo_set_source_surface(cr, pic, 0, 0);
        cairo_paint(cr);
        cairo_destroy(cr);
        st = cairo_surface_write_to_png_stream(rgb, write_fd, &f.fd);
        cairo_surface_destroy(rgb);
    }
    if (st != CAIRO_STATUS_SUCCESS) {
        buf_printf(err, "%s: %s\n", s->path, cairo_status_to_string(st));
        outfile_discard(&f);
        return -1;
    }
    return outfile_commit(&f, false, err) ? 0 : -1;
}

/* A still JPEG of [pic] (over black), through FFmpeg's MJPEG encoder and
 * its raw muxer (one frame is a whole JPEG file), quality= mapped from
 * Pillow's 1..100 (default 75) onto MJPEG's quantiser 31..2. */
static int write_jpeg(const RecordSpec *s, cairo_surface_t *pic, Buf *err)
{
    int quality = s->quality >= 1 && s->quality <= 100 ? s->quality : 75;
    char q[16];
    snprintf(q, sizeof q, "%d", 2 + (100 - quality) * 29 / 99);
    VideoOption opts[2] = {{"qmin", q}, {"qmax", q}};
    VideoSpec vs = {.format = "mjpeg", .codec = "mjpeg", .pixfmt = "yuvj420p", .options = opts, .noptions = 2};
    int w = cairo_image_surface_get_width(pic), h = cairo_image_surface_get_height(pic);
    VideoOut *v = video_open(s->path, w, h, 25, &vs, err, NULL);
    if (!v) return -1;
    int rc = video_frame(v, cairo_image_surface_get_data(pic), w, h, cairo_image_surface_get_stride(pic), 0,
                         false, err);
    Buf why = BUF_INIT;   /* the first failure is reported */
    if (video_close(v, &why) != 0) {
        if (rc == 0) buf_add(err, why.data, why.len);
        rc = -1;
    }
    buf_free(&why);
    return rc;
}

/* A still GIF of [pic]: an animation of one frame, replaced every frame
 * (Flitter writes a .gif without codec=:gif as a picture). */
static int write_still_gif(const RecordSpec *s, cairo_surface_t *pic, Buf *err)
{
    GifOut *g = gifout_open(s->path, cairo_image_surface_get_width(pic), cairo_image_surface_get_height(pic), 10,
                            err);
    if (!g) return -1;
    int rc = gifout_frame(g, cairo_image_surface_get_data(pic), cairo_image_surface_get_stride(pic));
    if (gifout_close(g) != 0 || rc != 0) {
        buf_printf(err, "%s: cannot write the GIF\n", s->path);
        return -1;
    }
    return 0;
}

/* Remember that the file at [path] could not be started (the message
 * just appended to [err], its last line): its later frames report the
 * same error without trying again. */
static void fail_slot(Recorder *rec, const char *path, const Buf *err)
{
    Slot *slot = add_slot(rec, path);
    const char *text = err->data ? err->data : "";
    size_t end = err->len;
    while (end && text[end - 1] == '\n') end--;
    size_t start = end;
    while (start && text[start - 1] != '\n') start--;
    if (!(slot->error = strndup(text + start, end - start))) mem_oom();
}

/* Frames that limit= [limit] seconds allows at [fps] (Flitter: up to
 * round(limit * fps), fps taken whole), or -1: no limit. */
static long limit_frames(double limit, double fps)
{
    if (!(limit >= 0)) return -1;
    double ifps = fps >= 1 && fps <= 1000 ? floor(fps) : fps > 1000 ? 1000 : 1;
    double m = round(limit * ifps);
    return m < 1e15 ? (long)m : -1;
}

static int write_gif(Recorder *rec, const RecordSpec *s, cairo_surface_t *pic, double fps, Buf *err)
{
    Slot *slot = find_slot(rec, s->path);
    if (slot && slot->error) {
        buf_printf(err, "%s\n", slot->error);
        return -1;
    }
    if (slot && slot->done) return 0;
    if (!slot) {
        /* limit= as for a video (Flitter writes animated GIFs as videos) */
        long max_frames = limit_frames(s->limit, fps);
        if (max_frames == 0) {
            buf_printf(err, "%s: no frame was recorded (limit=%g); the animation is not written\n",
                     s->path, s->limit);
            fail_slot(rec, s->path, err);
            return -1;
        }
        double cs = 100.0 / fps;   /* GIF delays are 1..65535 hundredths of a second */
        int delay = cs >= 65535 ? 65535 : cs <= 1 ? 1 : (int)lround(cs);
        GifOut *g = gifout_open(s->path, cairo_image_surface_get_width(pic), cairo_image_surface_get_height(pic),
                                delay, err);
        if (!g) {
            fail_slot(rec, s->path, err);
            return -1;
        }
        slot = add_slot(rec, s->path);
        slot->gif = g;
        slot->max_frames = max_frames;
    }
    if (gifout_frame(slot->gif, cairo_image_surface_get_data(pic), cairo_image_surface_get_stride(pic)) != 0) {
        buf_printf(err, "%s: cannot write a GIF frame\n", s->path);
        return -1;
    }
    if (slot->max_frames >= 0 && gifout_frames(slot->gif) >= slot->max_frames) {   /* its limit: finished now */
        slot->done = true;
        int closed = gifout_close(slot->gif);
        slot->gif = NULL;
        if (closed != 0) {
            buf_printf(err, "%s: cannot finish the GIF\n", s->path);
            return -1;
        }
    }
    return 0;
}

/* Finish [slot]'s video now (its limit), as Flitter does. */
static int finish_video(Slot *slot, Buf *err)
{
    slot->done = true;
    int closed = video_close(slot->video, err);
    slot->video = NULL;
    return closed != 0 ? -1 : 0;
}

/* write_video's work: 1 with the note of options the encoder did not use
 * in [note] (in the frame the video starts), -1 with the failure in
 * [err], else 0. */
static int video_step(Recorder *rec, const RecordSpec *s, cairo_surface_t *pic, const RecordClock *clock,
                      Buf *err, Buf *note)
{
    Slot *slot = find_slot(rec, s->path);
    if (slot && slot->error) {
        buf_printf(err, "%s\n", slot->error);
        return -1;
    }
    if (slot && slot->done) return 0;
    int rc = 0;
    double fps = clock->fps, ifps = fps >= 1 && fps <= 1000 ? floor(fps) : fps > 1000 ? 1000 : 1;
    if (!slot) {
        Buf unused = BUF_INIT;
        VideoSpec vs = {.codec = s->codec, .pixfmt = s->pixfmt, .keep_alpha = s->keep_alpha,
                        .options = s->options, .noptions = s->noptions};
        VideoOut *v = video_open(s->path, cairo_image_surface_get_width(pic), cairo_image_surface_get_height(pic),
                                 fps, &vs, err, &unused);
        if (!v) {
            fail_slot(rec, s->path, err);
            buf_free(&unused);
            return -1;
        }
        slot = add_slot(rec, s->path);
        slot->video = v;
        slot->start = clock->time;
        slot->last_pts = -1;
        slot->max_frames = limit_frames(s->limit, fps);
        if (unused.len) {
            buf_printf(note, "%s: options not used by the %s encoder: %s\n", s->path, video_encoder(v),
                       buf_line(&unused));
            rc = 1;
        }
        buf_free(&unused);
    }
    /* the frame's presentation time: one frame a frame in lockstep; on
     * the wall clock its time since the first frame (Flitter cache.py),
     * so the video lasts as long as the run; a frame in the same slot of
     * time as the last is dropped */
    long pts = slot->last_pts + 1;
    if (clock->realtime) {
        double t = round((clock->time - slot->start) * ifps);
        if (!(t > (double)slot->last_pts)) return rc;
        pts = t < 1e15 ? (long)t : slot->last_pts + 1;
        if (slot->max_frames >= 0 && pts >= slot->max_frames) {   /* past the limit */
            int closed = finish_video(slot, err);
            return closed != 0 ? closed : rc;
        }
    }
    if (slot->max_frames < 0 || pts < slot->max_frames) {
        if (video_frame(slot->video, cairo_image_surface_get_data(pic), cairo_image_surface_get_width(pic),
                        cairo_image_surface_get_height(pic), cairo_image_surface_get_stride(pic), pts,
                        clock->realtime, err) != 0)
            return -1;
        slot->last_pts = pts;
    }
    if (!clock->realtime && slot->max_frames >= 0 && slot->last_pts + 1 >= slot->max_frames) {
        int closed = finish_video(slot, err);
        if (closed != 0) return closed;
    }
    return rc;
}

/* One frame of a video: a failure replaces the note of unused options
 * (one message, as recorder_write promises). */
static int write_video(Recorder *rec, const RecordSpec *s, cairo_surface_t *pic, const RecordClock *clock,
                       Buf *err)
{
    Buf note = BUF_INIT;
    int rc = video_step(rec, s, pic, clock, err, &note);
    if (rc == 1) buf_add(err, note.data, note.len);
    buf_free(&note);
    return rc;
}

/* What a file about to be replaced must already be (by its first bytes). */
typedef enum { KIND_PNG, KIND_GIF, KIND_VIDEO, KIND_JPEG } FileKind;

/* False, with a message, when [path] exists, is a non-empty regular file
 * and does not start as a file of [kind] does: !record replaces pictures
 * and videos, never a script, a text file or anything else a name may
 * point at (`!record filename="notes.txt" codec=:gif`). A missing or empty
 * file is fine; other cases (directories, FIFOs) are left to outfile.h. */
static bool replaceable(const char *path, FileKind kind, Buf *err)
{
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) return true;
    struct stat st;
    unsigned char b[12] = {0};
    bool check = fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && st.st_size > 0;
    ssize_t n = check ? read(fd, b, sizeof b) : 0;
    close(fd);
    if (!check) return true;
    static const char *const what[] = {"a PNG picture", "a GIF picture or animation", "a video", "a JPEG picture"};
    bool ok;
    switch (kind) {
    case KIND_PNG: ok = n >= 8 && memcmp(b, "\x89PNG\r\n\x1a\n", 8) == 0; break;
    case KIND_JPEG: ok = n >= 3 && memcmp(b, "\xff\xd8\xff", 3) == 0; break;
    case KIND_GIF: ok = n >= 6 && (memcmp(b, "GIF87a", 6) == 0 || memcmp(b, "GIF89a", 6) == 0); break;
    default:       /* ISO media (MP4, MOV: a box type at byte 4) or Matroska/WebM (EBML) */
        ok = (n >= 8 && (memcmp(b + 4, "ftyp", 4) == 0 || memcmp(b + 4, "moov", 4) == 0 ||
                         memcmp(b + 4, "mdat", 4) == 0 || memcmp(b + 4, "wide", 4) == 0 ||
                         memcmp(b + 4, "free", 4) == 0)) ||
             (n >= 4 && memcmp(b, "\x1a\x45\xdf\xa3", 4) == 0);
    }
    if (!ok)
        buf_printf(err, "%s: exists and is not %s; not replaced (!record writes only over "
                 "its own kind of file)\n", path, what[kind]);
    return ok;
}

int recorder_write(Recorder *rec, const RecordSpec *s, cairo_surface_t *pic, const RecordClock *clock, Buf *err)
{
    double fps = clock->fps;
    cairo_surface_flush(pic);
    /* Flitter record.py: a .gif with codec=:gif is an animation, without
     * it a picture; a .png or .jpg name stays a still picture whatever the
     * codec; a video's name with codec=:gif is a video of the GIF codec,
     * which no container of ours holds (refused by name, never a GIF file
     * under a video's name) */
    bool codec_gif = s->codec && strcmp(s->codec, "gif") == 0;
    bool png = ends_with(s->path, ".png"), jpeg = ends_with(s->path, ".jpg") || ends_with(s->path, ".jpeg");
    bool gif = ends_with(s->path, ".gif");
    bool anim = codec_gif && gif, still_gif = gif && !codec_gif;
    /* files kept open across frames are checked when they are started */
    bool started = find_slot(rec, s->path) != NULL;
    FileKind kind = anim || still_gif ? KIND_GIF : png ? KIND_PNG : jpeg ? KIND_JPEG : KIND_VIDEO;
    if (!started && (anim || still_gif || png || jpeg || video_is_video_name(s->path)) &&
        !replaceable(s->path, kind, err)) {
        if (anim || kind == KIND_VIDEO) fail_slot(rec, s->path, err);   /* not retried every frame */
        return -1;
    }
    if (anim) return write_gif(rec, s, pic, fps, err);
    if (still_gif) return write_still_gif(s, pic, err);
    if (png) return write_png(s, pic, err);
    if (jpeg) return write_jpeg(s, pic, err);
    if (video_is_video_name(s->path)) return write_video(rec, s, pic, clock, err);
    buf_printf(err, "%s: only .png, .jpg and .gif pictures and .gif animations are written, and .mp4, .mov, "
             ".m4v, .mkv and .webm videos; !record skipped\n", s->path);
    return -1;
}

int recorder_free(Recorder *rec, Buf *err)
{
    if (!rec) return 0;
    int rc = 0;
    for (size_t i = 0; i < rec->nslots; i++) {
        Slot *s = &rec->slots[i];
        if (s->gif && gifout_close(s->gif) != 0) {
            buf_printf(err, "%s: cannot finish GIF\n", s->path);
            rc = -1;
        }
        if (s->video && video_close(s->video, err) != 0) rc = -1;
        free(s->path);
        free(s->error);
    }
    free(rec->slots);
    free(rec);
    return rc;
}
