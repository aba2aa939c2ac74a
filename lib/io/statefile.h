/* statefile.h: saving and restoring the state dictionary (and the clock
 * needed to resume a run) in an exact, versioned text file.
 *
 * Format, version 1 (UTF-8 text, one record per line):
 *     flitter-state 1
 *     clock FRAME TIME LAST_TIME LAST_BEAT PERIOD QUANTUM START
 *     KEY = VALUE
 *     ...
 *     end COUNT
 * KEY and VALUE are vectors written as elements joined by `;`: numbers in
 * the shortest decimal form that reads back to the same double (`-0` keeps
 * its sign; `inf`, `-inf`, `nan`, or `nan:HHHHHHHHHHHHHHHH` for a NaN with
 * other bits), symbols as `:name`, strings in double quotes with the escapes
 * of FORMATS.md §1. COUNT is the number of entries; a file without its `end`
 * line (truncated) or with any malformed line is refused as a whole.
 * Nodes and functions cannot be stored; entries holding them are skipped.
 */
#ifndef FL_STATEFILE_H
#define FL_STATEFILE_H

#include <stdbool.h>

#include "buf.h"
#include "state.h"
#include "value.h"

/* The runtime clock saved with the state so a run resumes bit-identically. */
typedef struct StateClock {
    long frame;          /* frames evaluated so far */
    double time;         /* `time` of the next frame */
    double last_time;    /* `time` of the last evaluated frame */
    double last_beat;    /* beat of the last evaluated frame */
    double period;       /* beat clock: seconds per beat */
    double quantum;      /* beat clock: beats per bar */
    double start;        /* beat clock: time of beat 0 */
} StateClock;

/* Write [sd] and [clock] to [path] atomically (temporary file in the same
 * directory, fsync, rename), so a crash mid-write leaves the old file.
 *   errors: returns -1 with `PATH: error: REASON` in [err]; 0 on success;
 *           [*skipped] (if non-NULL) counts entries that could not be
 *           stored (nodes, functions). */
int statefile_save(const StateDict *sd, const SymTab *st, const StateClock *clock,
                   const char *path, size_t *skipped, Buf *err);

/* Read [path] into [sd] (replacing its contents) and [clock], registering
 * symbol names in [st].
 *   errors: returns -1 with `PATH:LINE: error: REASON` in [err] and leaves
 *           [sd] and [clock] untouched when the file is missing, truncated,
 *           of another version, or malformed; 0 on success. */
int statefile_load(StateDict *sd, SymTab *st, StateClock *clock, const char *path, Buf *err);

#endif
