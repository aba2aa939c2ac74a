/* pictures.h: what a runtime keeps for drawing its frames' pictures: the
 * render graph (render/gl/graph.h, made by the first frame that draws, so
 * that passes, framebuffers and decoded media live from frame to frame and
 * each node kind that cannot be drawn is reported once per runtime) and
 * the view of the `!physics` systems (render/view/view.h). It knows
 * nothing of the runtime: the runtime makes it from a GraphEnv and hands
 * it each frame's tree and names (runtime.c, rt_render); the public
 * functions that show windows are api_windows.c's.
 */
#ifndef FL_PICTURES_H
#define FL_PICTURES_H

#include <stdint.h>

#include "graph.h"
#include "node.h"
#include "view.h"

typedef struct Pictures Pictures;

/* Whether windows are shown (pictures_show_windows was called). */
bool pictures_shown(const Pictures *p);
/* Whether pictures_render, asked for no windows, would draw the frame of
 * [root] (graph_draws_for_files with this runtime's --record and shown
 * windows); reads the tree and these settings alone, never the graph. */
bool pictures_draws_for_files(const Pictures *p, const Node *root);
/* Whether drawing a window of [root] may call back into the runtime (a
 * window's tree holds a function: an SDF's `function=`, evaluated while
 * it is drawn), so that the pictures must be drawn on the runtime's
 * thread, not beside its next frame; once true, true from then on. */
bool pictures_calls_back(Pictures *p, const Node *root);
/* Pictures drawn with [env] (copied; what it points to must outlive the
 * pictures). Skipped node kinds are logged as warnings: a shown window
 * lacks them. */
Pictures *pictures_new(const GraphEnv *env);
/* Free [p] (NULL is a no-op): animated GIFs and videos still open are
 * finished. */
void pictures_free(Pictures *p);
/* Draw the frame [root] (a !root node; NULL draws nothing) named by [f]
 * through the graph, once per frame (a second call in the same frame only
 * composites the windows when [windows] asks for them), writing its
 * !record files: when the frame has records (or pictures_record_first),
 * or [windows] (a front end wants the windows' pictures); see graph_frame
 * for which frames are drawn. [f]'s folder is ignored: relative file
 * names are taken from [f]'s script's folder. Returns the number of
 * record files that could not be written this frame. */
int pictures_render(Pictures *p, const Node *root, const GraphFrame *f, bool windows);
/* The graph, made the first time. */
Graph *pictures_graph(Pictures *p);
/* The graph when a frame or pictures_graph has made it, else NULL. */
Graph *pictures_graph_made(const Pictures *p);
/* Windows are shown from now on: each is composited every frame. */
void pictures_show_windows(Pictures *p);
/* Record the first window of every later frame to [path] (--record; NULL
 * or "" stops). */
void pictures_record_first(Pictures *p, const char *path);
/* Finish the animated GIFs and videos the records opened (each renamed
 * into place); -1 when one could not be (logged), else 0. */
int pictures_finish_records(Pictures *p);
/* The live window's scale and sample cap (graph_set_scale), kept until
 * the graph is made. */
void pictures_set_scale(Pictures *p, double scale, int max_samples);
/* The view of the physics systems (view_new_fit, its extents kept from
 * picture to picture) and the log its warnings go to. */
View *pictures_view(Pictures *p, const RenderLog **log);

#endif
