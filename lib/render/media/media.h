/* media.h: pictures and videos read from files, decoded by FFmpeg's
 * libraries (avlib.h: loaded at run time), for `!image`, `!video` and the
 * canvas's `!image`/`!pattern filename=` (Flitter docs/windows.md, "!image"
 * and "!video"; render/window/image.py, video.py and cache.py for
 * behaviour).
 *
 * A MediaCache belongs to one render graph (one runtime): nothing is
 * global. Decoded pixels are charged to the runtime's memory budget
 * (mem_budget_reserve) while they are held; a picture or a frame that does
 * not fit is refused with a message, never aborted on. Bad input (a file
 * missing, truncated, not a picture or not a video, a decoder error) gives
 * NULL and a one-line message "PATH: REASON"; nothing here crashes, aborts
 * or writes a file.
 *
 * Pixels are 8-bit RGBA, straight (not premultiplied) alpha, the sRGB
 * values of the file, top row first, rows w*4 bytes apart.
 */
#ifndef FL_RENDER_MEDIA_H
#define FL_RENDER_MEDIA_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "buf.h"
#include "mem.h"

typedef struct MediaCache MediaCache;

/* A cache charging [budget] (may be NULL: no budget); decoding loops
 * whose length a file decides (decoding up to a far position) stop when
 * *[interrupt] is set (may be NULL), giving what they have. */
MediaCache *media_cache_new(MemBudget *budget, volatile int *interrupt);
/* Free every picture and video of [m] (NULL is a no-op); videos' decoding
 * threads are stopped and joined first. */
void media_cache_free(MediaCache *m);
/* Forget pictures not asked for in the last [age] seconds (monotonic
 * clock), giving their memory back. */
void media_cache_expire(MediaCache *m, double age);

/* {===== pictures */

typedef struct MediaImage {
    int w, h;                /* pixels */
    const uint8_t *rgba;     /* w*h*4 bytes, as above */
    uint64_t version;        /* changes whenever the pixels do (the file changed) */
} MediaImage;

/* The picture in file [path] (PNG, JPEG and what else FFmpeg's image
 * decoders read: BMP, TIFF, WebP, GIF's first frame, ...), resized to
 * [w] x [h] with bilinear filtering when both are above 0 and differ from
 * the file's size (else as it is). Decoded once and kept, with each
 * resized copy, until the file's modification time or size changes
 * (checked on every call, one stat) or it expires.
 *   returns: the picture, borrowed until the next media_image call for
 *            that path or media_cache_expire/free.
 *   errors: NULL with "PATH: REASON" appended to [err] (may be NULL: not
 *           told): no such file, not a picture, a decoder error, a size
 *           past 16384 a side or the memory budget, FFmpeg missing. The
 *           same failure is reported again only when the file changes (the
 *           caller logs it once: *[fresh] says whether this message is new;
 *           may be NULL). */
const MediaImage *media_image(MediaCache *m, const char *path, int w, int h, Buf *err, bool *fresh);

/* }===== */

/* {===== videos */

typedef struct MediaVideo MediaVideo;

/* One decoded frame. */
typedef struct MediaFrame {
    int w, h;                /* pixels */
    const uint8_t *rgba;     /* w*h*4 bytes, as above */
    uint64_t serial;         /* unique to this frame of this video (to tell frames apart) */
} MediaFrame;

/* Open video file [path] for one `!video` pass; with [threads] the codec
 * decodes on several threads (Flitter's thread=true). A thread of the
 * video's own decodes ahead of the position last asked for and keeps a
 * small cache of frames (at most 16), so that playing forwards rarely
 * waits for the decoder.
 *   errors: NULL with "PATH: REASON" appended to [err] (may be NULL: not
 *           told): no such file, not a video, no video stream, no decoder,
 *           FFmpeg missing. */
MediaVideo *media_video_open(MediaCache *m, const char *path, bool threads, Buf *err);
/* Whether [v] is still the file at [path] as it is now (same name,
 * modification time and size): else the caller opens it again. */
bool media_video_current(const MediaVideo *v, const char *path);
/* The frames around [position] seconds as Flitter's cache.py
 * read_video_frames maps it: [trim_start] and [trim_end] seconds cut off
 * the ends; with [loop] the position wraps around the trimmed duration
 * (negative ones from the end; with [back_and_forth] every other pass runs
 * backwards), else it is clamped to it. *[f0] is the last frame at or
 * before that time, *[f1] the next one (NULL at the end), *[ratio] how far
 * the time is from f0 to f1 (0 without f1). With [wait] the call decodes
 * (or waits for the decoding thread) until those frames are there: every
 * frame is exact, as a recording needs. Without it, a frame not decoded
 * yet gives the nearest frame the cache holds (or none yet: false) and the
 * decoding thread goes on to the position, so a live window never waits.
 * The frames are borrowed until the next call on [v].
 *   errors: false with a message appended to [err] (may be NULL: not
 *           told) when the video cannot be read there (a damaged or
 *           truncated file: the frames before the damage stay playable;
 *           the message is given once); false with nothing appended when
 *           no frame is ready yet (without [wait]). */
bool media_video_frames(MediaVideo *v, double position, bool loop, bool back_and_forth, double trim_start,
                        double trim_end, bool wait, double *ratio, const MediaFrame **f0, const MediaFrame **f1,
                        Buf *err);
/* Stop [v]'s thread and free it (NULL is a no-op). */
void media_video_close(MediaVideo *v);

/* }===== */

#endif
