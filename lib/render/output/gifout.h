/* gifout.h: an animated GIF written one frame at a time (giflib). */
#ifndef FL_RENDER_GIFOUT_H
#define FL_RENDER_GIFOUT_H

#include <stdint.h>

#include "buf.h"

typedef struct GifOut GifOut;

/* Start [path] as a looping animated GIF of [width] x [height] pixels, each
 * frame shown for [delay_cs] hundredths of a second (clamped to 1..65535).
 * The frames go to a temporary in [path]'s directory (outfile.h: a link is
 * written through); [path] appears, complete, at gifout_close.
 *   errors: returns NULL (its message appended to [err]) when the file
 *           cannot be created or [path] exists and is not a regular file. */
GifOut *gifout_open(const char *path, int width, int height, int delay_cs, Buf *err);
/* Append one frame: [argb] is cairo's ARGB32 layout (premultiplied, native
 * endian, [stride] bytes per row), composited over black; its colours are
 * reduced to a 256-entry palette of its own by giflib's median cut.
 *   errors: returns -1 when writing fails, else 0. */
int gifout_frame(GifOut *g, const unsigned char *argb, int stride);
/* Number of frames appended so far. */
int gifout_frames(const GifOut *g);
/* Finish the file, rename it over the target and free [g] (NULL is a
 * no-op); -1 when a frame could not be written or closing fails: the
 * temporary is then removed and the target left as it was. */
int gifout_close(GifOut *g);

#endif
