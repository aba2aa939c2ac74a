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
 * dimension is drawn on a horizontal line; three dimensions in
 * perspective through the `!canvas3d` renderer (canvas3d_draw_scene; issue
 * 25): particles as lit spheres of their radius (at least 2 pixels), in the
 * same colours, anchors as dark three-axis crosses (in a pale glassy ball
 * when they have a radius), links as thin grey rods, barriers as dark glassy
 * squares; an ambient and a directional light (from the upper left, in
 * front); the camera looks at the middle of the bodies' box from the
 * direction 1;-2;1 (z up), at the distance where the box's bounding sphere
 * just fills the 1/8-turn field of view. Four dimensions and more, a 3D
 * system when no OpenGL context can be made (said once per view), and
 * every system of 2 or more dimensions when a flat projection is asked for
 * (view_set_style; a system without one of its axes keeps its own) are
 * projected on two coordinates (default x/y). The flat view is fitted
 * (same scale on both axes) to the bodies' extents with a margin; in an
 * animation it only grows, so the picture holds still (the 3D camera too).
 *
 * FILE ending in `.png` or `.svg` is one picture (each view_frame replaces
 * it); `.gif` is an animation, a frame appended per view_frame call.
 */
#ifndef FL_RENDER_VIEW_H
#define FL_RENDER_VIEW_H

#include <stdbool.h>
#include <stddef.h>

#include <cairo.h>

#include "buf.h"
#include "canvas.h"
#include "systems.h"
#include "value.h"

typedef struct View View;

/* Parse a flat projection, two coordinate names separated by ';' out of
 * x, y, z, w (the first to fourth coordinates), e.g. "x;z", into [axes]
 * (0..3); false, [axes] untouched, for anything else (a NULL [text], the
 * same name twice). */
bool view_parse_axes(const char *text, int axes[2]);

/* A view writing to [path] (.png, .svg or .gif, case-insensitive); GIF
 * frames last [delay_cs] hundredths of a second; [symbols] names symbols
 * in titles (borrowed, may be NULL).
 *   errors: NULL with a message in [err] for another extension. */
View *view_open(const char *path, int delay_cs, const SymTab *symbols, Buf *err);
/* A view for view_draw_fit only (no file). */
View *view_new_fit(const SymTab *symbols);
/* Draw systems of 2 dimensions or more flat on the coordinates [axes]
 * (view_parse_axes; NULL, {0, 0} or anything but two different numbers of
 * 0..3: 3D systems in perspective, the others on x/y); [log] (copied; NULL: nowhere) receives the one warning of a 3D
 * system drawn flat for want of OpenGL. */
void view_set_style(View *v, const int axes[2], const RenderLog *log);
/* True for an animation (.gif). */
bool view_animated(const View *v);
/* Draw [n] [systems] as frame [frame] and write it (PNG/SVG: the file is
 * replaced; GIF: a frame appended; the picture's size is fixed by the
 * first call).
 *   errors: -1 with a message in [err] when the file cannot be written. */
int view_frame(View *v, long frame, const PsSystem *systems, size_t n, Buf *err);
/* Draw [n] [systems] with [v] (a view_new_fit view) as a single view
 * picture (laid out anew for these systems, as view_frame's first frame
 * is, fitted to the bodies as they are now) into the cairo image surface
 * [target], scaled uniformly to fit it and centred, with black bars beside
 * it when the shapes differ (fl_draw_view); returns the number of systems
 * drawn (at most 16, as in a view file). */
size_t view_draw_fit(View *v, cairo_surface_t *target, const PsSystem *systems, size_t n);
/* True when one of [n] [systems] (of the first 16, those a view shows)
 * would be drawn in 3D (through OpenGL)
 * by a view whose flat projection is [axes] (view_set_style; NULL or
 * {0, 0}: none): a drawing that needs the GL context of the thread it is
 * drawn on, not only its own data (api_windows.c, fl_view_snapshot). */
bool view_draws_3d(const int axes[2], const PsSystem *systems, size_t n);
/* Finish and free [v] (NULL is a no-op); -1 when a GIF cannot be finished. */
int view_close(View *v);

#endif
