/* outputs.h: what a run writes besides dumps, after every frame: the
 * windows' pictures and !record files (lib/render/window.h), the --view
 * picture or animation of the physics systems (view.h) and the --trace
 * trajectories (trace.h). */
#ifndef FL_OUTPUTS_H
#define FL_OUTPUTS_H

#include <stdio.h>

#include "flitter.h"
#include "runner.h"

typedef struct Outputs Outputs;

/* Open what [spec] asks for; messages go to [log].
 *   errors: NULL (message on [log]) when the --view or --trace file cannot
 *           be created or has an unknown extension. */
Outputs *outputs_new(const RunSpec *spec, fl_runtime *rt, FILE *log);
/* After frame [frame] (0-based) of [rt]: render windows, append the trace
 * and animation frames due (every K-th frame, counted from frame 0).
 * A write error is reported once and that output stops. */
void outputs_frame(Outputs *o, fl_runtime *rt, long frame);
/* Write the final --view picture (PNG/SVG, of the last frame) and close
 * everything; [o] is freed (NULL is a no-op).
 *   errors: -1 when some file could not be written, else 0. */
int outputs_finish(Outputs *o, fl_runtime *rt, long frames_run);

#endif
