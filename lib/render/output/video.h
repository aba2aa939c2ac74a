/* video.h: a video file written one frame at a time through FFmpeg's
 * libraries (libavformat, libavcodec, libswscale), for `!record
 * filename=NAME.mp4|.mov|.m4v|.mkv|.webm` (Flitter docs/windows.md,
 * "!record"; Flitter cache.py, write_video_frame).
 *
 * The container is chosen from the file name's extension; the encoder
 * from codec= (Flitter's default :h264) as FFmpeg names encoders or codecs
 * (:h264, :hevc, :vp9, :vp8, :mpeg4, :libx264, :prores_ks ...). Without
 * codec=, a .webm file gets VP9 (libvpx-vp9; VP8 where absent) and the
 * other containers H.264 (FFmpeg's default H.264 encoder, usually
 * libx264; MPEG-4 Part 2 where no H.264 encoder is built in). The frames
 * are converted to pixfmt= (default yuv420p, or yuva420p with
 * keep_alpha=true where the encoder takes it, e.g. VP9, else yuv420p),
 * BT.709 limited range and tagged so (as Flitter does); a frame whose size
 * differs from the first is scaled to the first's size; 4:2:0 formats need
 * even sides, so an odd side is encoded one pixel larger (scaled). A frame
 * has the presentation time its caller gives, in a time base of 1/fps (fps
 * truncated to an integer in 1..1000, as Flitter's int(fps)); frames are
 * encoded on a thread of the video's own. The other attributes are the encoder's
 * FFmpeg options (crf=, preset=, profile=, b= in bit/s, g=, ...; `__` in a
 * name stands for `-`), as in Flitter; bitrate= is taken as FFmpeg's `b`
 * (bits per second). Flitter sets no preset or crf of its own: the
 * encoder's defaults apply (libx264: preset medium, crf 23).
 *
 * The file is written under a temporary name in the target's directory
 * and renamed into place by video_close (outfile.h), after the encoder is
 * flushed and the trailer written: the video appears, complete, at the
 * end of the run.
 */
#ifndef FL_RENDER_VIDEO_H
#define FL_RENDER_VIDEO_H

#include <stdbool.h>
#include <stddef.h>

#include "buf.h"

typedef struct VideoOut VideoOut;

/* One FFmpeg option (codec-private or generic), as text. */
typedef struct VideoOption {
    const char *key, *value;
} VideoOption;

typedef struct VideoSpec {
    const char *format;         /* FFmpeg's muxer, or NULL: by the file name */
    const char *codec;          /* codec= or NULL: by container (see above) */
    const char *pixfmt;         /* pixfmt= or NULL: yuv420p / yuva420p */
    bool keep_alpha;            /* keep_alpha=: encode the alpha plane */
    const VideoOption *options; /* the other attributes, [noptions] of them */
    size_t noptions;
} VideoSpec;

/* True when [path] names a video container this module writes (.mp4,
 * .mov, .m4v, .mkv, .webm, case-insensitive). */
bool video_is_video_name(const char *path);

/* Start the video [path]: [width] x [height] pixels (each 1..16384), [fps]
 * frames per second (truncated to 1..1000), as [spec] asks (borrowed).
 *   errors: NULL with "PATH: REASON" appended to [err] when no
 *           encoder fits, the container cannot hold the codec, an option
 *           or the pixel format is refused, or the file cannot be created
 *           (nothing is left behind); an encoder that opens without the
 *           options but not with them refused them: an error, never a
 *           change to the next encoder. Unknown options are not an error
 *           (FFmpeg ignores them); their names are listed in [unused]
 *           (NULL: not wanted; emptied first, then the names separated
 *           by commas). */
VideoOut *video_open(const char *path, int width, int height, double fps, const VideoSpec *spec,
                     Buf *err, Buf *unused);
/* Queue one frame for [v]'s writer thread, which converts and encodes
 * it: [argb] is cairo's ARGB32 layout (native-endian 0xAARRGGBB words,
 * premultiplied alpha, [stride] bytes per row) of [width] x [height]
 * pixels, copied before the call returns; without alpha in the output it
 * is taken as composited over black (the colour bytes as they are). [pts]
 * is the frame's presentation time in frames (1/fps), greater than the
 * last frame's. When the writer is VIDEO_QUEUE frames behind, the call
 * waits for it, or with [drop_when_busy] drops the frame (returns 0).
 *   errors: -1 with [err] set once an earlier frame failed to encode or
 *           be written (the video is then discarded at video_close),
 *           else 0. */
int video_frame(VideoOut *v, const unsigned char *argb, int width, int height, int stride, long pts,
                bool drop_when_busy, Buf *err);
/* The FFmpeg name of [v]'s encoder (e.g. "libx264"; borrowed, lives as
 * long as the process). */
const char *video_encoder(const VideoOut *v);
/* Flush the encoder, write the trailer, rename the file into place and
 * free [v] (NULL is a no-op).
 *   errors: -1 with [err] set when a frame failed before or finishing
 *           fails: the temporary is removed, the target left as it was. */
int video_close(VideoOut *v, Buf *err);

#endif
