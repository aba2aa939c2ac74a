/* halves.h: a picture's rows worked on by two threads, the caller and one
 * started for the call, for the CPU passes of the window's pictures (the
 * bloom's passes, the sRGB encoding), which run while OpenGL's own
 * rasteriser threads wait. Each row is computed by exactly one thread
 * with the same operations as on one, so results do not depend on the
 * split. */
#ifndef FL_RENDER_HALVES_H
#define FL_RENDER_HALVES_H

/* Work on rows y0..y1-1 of a picture; [part] is 0 or 1, which thread's
 * scratch to use. */
typedef void (*RowsFn)(void *ctx, int y0, int y1, int part);

/* Run fn over rows 0..h-1: rows h/2.. on a new thread (part 1) while the
 * caller does 0..h/2-1 (part 0), then wait for it. A picture of fewer than
 * [min_rows] rows, or a thread that cannot be started, is done by the
 * caller alone as fn(ctx, 0, h, 0).
 *   errors: none (h < 1 does nothing). */
void rows_in_halves(int h, int min_rows, RowsFn fn, void *ctx);

#endif
