/* pictures.h: the runtime's render graph and the last frame's windows for
 * a front end that shows them (flitter.h, "Windows: a frame's pictures
 * and input"): their list (fl_windows), their pictures read back into the
 * caller's pixels (fl_draw_window) or as textures of the caller's OpenGL
 * context (fl_gl_attach, fl_gl_window_texture), and the --view picture of
 * the !physics systems (fl_draw_view, render/view/view.h). The !record
 * files of fl_outputs are written by the same graph (pictures_render).
 */
#ifndef FL_PICTURES_H
#define FL_PICTURES_H

#include "flitter.h"
#include "value.h"

/* What a runtime keeps for drawing pictures: its render graph (made by
 * the first frame that draws), so that passes, framebuffers and decoded
 * media live from frame to frame and each node kind that cannot be drawn
 * is reported once per runtime. */
typedef struct Pictures Pictures;

/* The pictures of [rt] (its symbols, log, memory budget and interrupt). */
Pictures *pictures_new(fl_runtime *rt);
/* Free [p] (NULL is a no-op): animated GIFs and videos still open are
 * finished. */
void pictures_free(Pictures *p);
/* Draw [rt]'s last frame through the graph, once per frame (a second call
 * in the same frame only composites the windows when [windows] asks for
 * them), writing its !record files: when the frame has records (or
 * --record), or [windows] (a front end wants the windows' pictures); see
 * graph_frame for which frames are drawn. Returns the number of record
 * files that could not be written this frame. */
int pictures_render(fl_runtime *rt, bool windows);
/* Record the first window of every later frame to [path] (--record; NULL
 * or "" stops). */
void pictures_record_first(fl_runtime *rt, const char *path);
/* Finish the animated GIFs and videos the records opened (each renamed
 * into place); -1 when one could not be (logged), else 0. */
int pictures_finish_records(fl_runtime *rt);

#endif
