/* pictures.h: the last frame's windows for a front end that shows them
 * (flitter.h, "Windows: a frame's pictures and input"): their list
 * (fl_windows) and their pictures drawn into the caller's pixels
 * (fl_draw_window, with the !record compositing of render/window.h) and
 * the --view picture of the !physics systems (fl_draw_view, render/view.h).
 */
#ifndef FL_PICTURES_H
#define FL_PICTURES_H

#include "flitter.h"
#include "value.h"

/* What a runtime keeps for drawing pictures: the renderer, so that each
 * node kind that cannot be drawn is reported once per runtime. */
typedef struct Pictures Pictures;

/* A drawer naming symbols with [symbols] (borrowed, must outlive it) and
 * reporting skipped node kinds as warnings to [log] / [ctx]. */
Pictures *pictures_new(const SymTab *symbols, fl_log_fn log, void *ctx);
/* Free [p] (NULL is a no-op). */
void pictures_free(Pictures *p);

#endif
