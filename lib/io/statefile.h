/* statefile.h: saving and restoring the state dictionary (and the clock
 * needed to resume a run) in an exact, versioned text file.
 *
 * Format, version 2 (UTF-8 text, one record per line):
 *     flitter-state 2
 *     script "PATH" HASH            (optional)
 *     clock FRAME TIME LAST_TIME LAST_BEAT PERIOD QUANTUM START
 *     KEY = VALUE
 *     ...
 *     end COUNT
 *     checksum SUM
 * KEY and VALUE are vectors written as elements joined by `;`: numbers in
 * the shortest decimal form that reads back to the same double (`-0` keeps
 * its sign; `inf`, `-inf`, `nan`, or `nan:HHHHHHHHHHHHHHHH` for a NaN with
 * other bits), symbols as `:name` (a symbol whose name holds a space, `;`,
 * `=`, a quote, a backslash or a control byte is written as its number,
 * the same value), strings in double quotes with the escapes of FORMATS.md
 * §1 (`\"`, `\\`, `\n`, `\r`, `\t`, `\xHH` for other control bytes), so a
 * string may hold anything, ` = ` included: the key ends at the first
 * ` = ` after a whole element. COUNT is the number of entries. The
 * `script` line names the script whose run saved the file (its path as
 * given, quoted, and HASH, the FNV-1a 64 hash of its bytes then, 16 hex
 * digits); SUM is the FNV-1a 64 hash of every byte of the file before
 * the checksum line (16 hex digits). A file without its `end` or
 * `checksum` line (truncated), with a checksum that does not match
 * (damaged) or with any malformed line is refused as a whole. Version 1
 * files (`flitter-state 1`: no script and no checksum line) still load.
 * Nodes and functions cannot be stored; entries holding them are skipped.
 */
#ifndef FL_STATEFILE_H
#define FL_STATEFILE_H

#include <stdbool.h>
#include <stdint.h>

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

/* The script a state file was saved from: [script] (NULL: unknown) and
 * [hash], statefile_hash() of its bytes when it was saved. */
typedef struct StateOrigin {
    char *script;
    uint64_t hash;
} StateOrigin;

/* FNV-1a 64 of [len] bytes of [data] (the checksum and script hash). */
uint64_t statefile_hash(const char *data, size_t len);

/* Why the loader refuses a state file whose clock is [c] (a static text:
 * frame beyond 0..2^53, a time or beat that is not finite, a period or
 * quantum that is not positive and finite), or NULL when it reads it. */
const char *statefile_clock_refused(const StateClock *c);

/* Write [sd] and [clock] to [path] atomically (temporary file in the same
 * directory, fsync, rename), so a crash mid-write leaves the old file;
 * [origin] (may be NULL) names the script in the file's `script` line.
 * A clock the loader would refuse (statefile_clock_refused) is not
 * written: the file is left as it was.
 *   errors: returns -1 with `PATH: error: REASON` in [err]; 0 on success;
 *           [*skipped] (if non-NULL) counts entries that could not be
 *           stored (nodes, functions). */
int statefile_save(const StateDict *sd, const SymTab *st, const StateClock *clock,
                   const StateOrigin *origin, const char *path, size_t *skipped, Buf *err);

/* Read [path] into [sd] (replacing its contents) and [clock], registering
 * symbol names in [st]; [origin] (may be NULL) gets the file's script
 * line (origin->script malloc'd, the caller frees it; NULL when the file
 * has none).
 *   errors: returns -1 with `PATH:LINE: error: REASON` in [err] and leaves
 *           [sd], [clock] and [origin] untouched when the file is missing,
 *           truncated, damaged (checksum), of another version, or
 *           malformed; 0 on success. */
int statefile_load(StateDict *sd, SymTab *st, StateClock *clock, StateOrigin *origin,
                   const char *path, Buf *err);

#endif
