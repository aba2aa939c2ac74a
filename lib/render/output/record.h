/* record.h: the files a `!record` node writes (Flitter docs/windows.md,
 * "!record"; Flitter render/window/record.py and cache.py): the picture
 * of one frame goes to
 *   - NAME.gif with codec=:gif (or codec=:gif with a name that is not a
 *     .png or .jpg): one frame appended to an animated GIF (gifout.h),
 *     which appears at the end of the run;
 *   - NAME.gif without codec=:gif: a one-frame GIF replaced every frame;
 *   - NAME.png: a PNG replaced every frame (RGBA with keep_alpha=true,
 *     else RGB over black);
 *   - NAME.jpg or NAME.jpeg: a JPEG replaced every frame (FFmpeg's
 *     encoder, quality= 1..100 as Flitter's, default 75 as PIL's);
 *   - NAME.mp4, .mov, .m4v, .mkv, .webm: one frame appended to a video
 *     (video.h), which appears at the end of the run, or once limit=
 *     seconds of it are written;
 *   - any other name: refused (the caller reports it).
 * Every file is written under a temporary name and renamed into place
 * (outfile.h), so a reader never sees a partial file; a link is written
 * through, a non-regular target refused.
 *
 * A Recorder holds the files that stay open across frames (animations and
 * videos, by file name) and belongs to one renderer.
 */
#ifndef FL_RENDER_RECORD_H
#define FL_RENDER_RECORD_H

#include <stdbool.h>
#include <stddef.h>

#include <cairo.h>

#include "buf.h"
#include "video.h"

typedef struct Recorder Recorder;

/* What one !record node asks for (all borrowed for the call). */
typedef struct RecordSpec {
    const char *path;           /* filename=, as given */
    const char *codec;          /* codec= as text, or NULL */
    const char *pixfmt;         /* pixfmt= as text, or NULL */
    bool keep_alpha;            /* keep_alpha= */
    int quality;                /* quality= of a JPEG, 1..100, or 0: the encoder's default */
    double limit;               /* limit= in seconds of video, or < 0: none */
    const VideoOption *options; /* the encoder options (video only) */
    size_t noptions;
} RecordSpec;

/* The clock of the frame a picture belongs to. */
typedef struct RecordClock {
    double fps;                 /* the frame rate (GIF delays, the video's time base) */
    double time;                /* the frame's `time`, seconds */
    bool realtime;              /* the clock follows the wall clock (a live run) */
} RecordClock;

/* A recorder with nothing open. */
Recorder *recorder_new(void);
/* Write picture [pic] (an ARGB32 image surface, premultiplied) of one
 * frame as [s] asks, on [clock]. A video's frames are one a frame in
 * lockstep; on a realtime clock each is stamped with its time since the
 * video's first frame (in frames of 1/fps, as Flitter's cache.py stamps
 * them), a frame in the same slot as the last is dropped, and one the
 * encoder is too far behind to take is dropped too, so the video lasts as
 * long as the run and recording never holds the frame loop.
 *   errors: -1 with one line "PATH: REASON" appended to [err]
 *           when the file cannot be written this frame (a video that could
 *           not be started fails each later frame too, without retrying);
 *           1 with a note "PATH: options not used by the ENCODER encoder:
 *           K1,K2" in [err] in the frame a video starts with options the
 *           encoder does not know (it is still written); else 0. Never
 *           aborts. */
int recorder_write(Recorder *rec, const RecordSpec *s, cairo_surface_t *pic, const RecordClock *clock,
                   Buf *err);
/* Finish the animations and videos still open (each renamed into place),
 * and free [rec] (NULL is a no-op).
 *   errors: -1 when any could not be finished, with a line for each
 *           appended to [err]; else 0. */
int recorder_free(Recorder *rec, Buf *err);

#endif
