/* trace.h: particle trajectories written for plotting (`flitter run
 * --trace FILE`), one row per particle or anchor per traced frame.
 *
 * CSV (any name not ending in `.jsonl`): a header line
 *   frame,time,system,id,kind,x,y,z,vx,vy,vz
 * (x0..xN-1 and v0..vN-1 when some system has more than 3 dimensions; the
 * column count is fixed by the first traced frame's largest `dimensions`,
 * shorter systems leave cells empty, longer ones are cut), then rows with
 * `system` and `id` as their string conversion (LANGUAGE.md §3.13: :cells
 * gives cells), `kind` particle or anchor, numbers in shortest round-trip
 * text (FORMATS.md §1). JSON Lines (`.jsonl`): one object per row,
 *   {"frame":0,"time":0,"system":"cells","id":3,"kind":"particle",
 *    "position":[x,...],"velocity":[vx,...]}
 * with a numeric id as a number, other ids (symbols too) as strings, nan/inf
 * as null.
 */
#ifndef FL_RENDER_TRACE_H
#define FL_RENDER_TRACE_H

#include <stddef.h>

#include "buf.h"
#include "systems.h"
#include "value.h"

typedef struct Trace Trace;

/* Create (truncate) [path]; [symbols] names symbols (borrowed, may be NULL).
 *   errors: NULL with a message appended to [err]. */
Trace *trace_open(const char *path, const SymTab *symbols, Buf *err);
/* Append the rows of frame [frame] at [time] for the [n] [systems].
 *   errors: -1 when writing fails, else 0. */
int trace_frame(Trace *t, long frame, double time, const PsSystem *systems, size_t n);
/* Flush, close and free [t] (NULL is a no-op); -1 when closing fails. */
int trace_close(Trace *t);

#endif
