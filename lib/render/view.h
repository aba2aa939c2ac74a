/* view.h: a picture of every `!physics` system, no drawing code needed
 * (`flitter run --view FILE`).
 *
 * Each system gets a panel (480x480 pixels; 480x160 for one dimension),
 * side by side in tree order, titled with its state prefix, dimensions and
 * particle count. Particles are discs of their radius (a 2-pixel dot when
 * the radius is 0), coloured by charge (grey for 0, towards red for the
 * largest positive charge of the system, towards blue for the most
 * negative); anchors are black crosses (over a pale disc when they have a
 * radius); `!distance` links grey lines;
 * barriers dark lines across the panel (1D: a vertical bar). One
 * dimension is drawn on a horizontal line; three and more are projected on
 * x/y. The view is fitted (same scale on both axes) to the bodies' extents
 * with a margin; in an animation it only grows, so the picture holds still.
 *
 * FILE ending in `.png` or `.svg` is one picture (each view_frame replaces
 * it); `.gif` is an animation, a frame appended per view_frame call.
 */
#ifndef FL_RENDER_VIEW_H
#define FL_RENDER_VIEW_H

#include <stdbool.h>
#include <stddef.h>

#include <cairo.h>

#include "systems.h"
#include "value.h"

typedef struct View View;

/* A view writing to [path] (.png, .svg or .gif, case-insensitive); GIF
 * frames last [delay_cs] hundredths of a second; [symbols] names symbols
 * in titles (borrowed, may be NULL).
 *   errors: NULL with a message in [err] for another extension. */
View *view_open(const char *path, int delay_cs, const SymTab *symbols, char *err, size_t errlen);
/* True for an animation (.gif). */
bool view_animated(const View *v);
/* Draw [n] [systems] as frame [frame] and write it (PNG/SVG: the file is
 * replaced; GIF: a frame appended; the picture's size is fixed by the
 * first call).
 *   errors: -1 with a message in [err] when the file cannot be written. */
int view_frame(View *v, long frame, const PsSystem *systems, size_t n, char *err, size_t errlen);
/* Draw [n] [systems] as a single view picture (the layout view_frame's
 * first frame takes) into the cairo image surface [target], scaled
 * uniformly to fit it and centred, with black bars beside it when the
 * shapes differ ([symbols] as for view_open) (fl_draw_view); returns the
 * number of systems drawn (at most 16, as in a view file). */
size_t view_draw_fit(cairo_surface_t *target, const PsSystem *systems, size_t n, const SymTab *symbols);
/* Finish and free [v] (NULL is a no-op); -1 when a GIF cannot be finished. */
int view_close(View *v);

#endif
