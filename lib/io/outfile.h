/* outfile.h: an output file written under a temporary name in its own
 * directory and renamed over the target when complete, so a reader (an
 * image viewer polling a !record PNG, a player opening a video) never
 * sees a half-written file: it sees the old file or the new one.
 *
 * The target is resolved first: a symbolic link is followed (to any
 * depth, up to 40 links) and the file it names is replaced, the link
 * itself staying in place; a target that exists and is not a regular file
 * (a directory, device, FIFO or socket) is refused. The temporary is
 * `.NAME.XXXXXX` next to the resolved target (same file system, so the
 * rename is atomic), created exclusively with mode 0666 less the umask,
 * or with the replaced file's permission bits when it existed.
 */
#ifndef FL_IO_OUTFILE_H
#define FL_IO_OUTFILE_H

#include <stdbool.h>
#include <stddef.h>

#include "buf.h"

typedef struct OutFile {
    char *target;   /* the resolved file to replace (malloc'd) */
    char *tmp;      /* the temporary being written (malloc'd) */
    int fd;         /* open on tmp for writing, or -1 once closed */
} OutFile;

/* Resolve [path] and create its temporary, open for writing in f->fd.
 *   errors: false, with "PATH: REASON" appended to [err], when
 *           the target is not a regular file, a link cannot be followed
 *           or the temporary cannot be created (e.g. no such directory);
 *           nothing is left behind and [f] needs no outfile_discard. */
bool outfile_open(OutFile *f, const char *path, Buf *err);
/* Close f->fd (unless already closed, -1), fsync the data first when
 * [durable] (once-per-run files: videos, animations; a PNG replaced every
 * frame is not synced, the rename alone keeps readers safe) and rename the
 * temporary over the target. [f] is released either way.
 *   errors: false with "PATH: REASON" in [err]; the temporary is removed
 *           and the target left as it was. */
bool outfile_commit(OutFile *f, bool durable, Buf *err);
/* Close and remove the temporary, leaving the target as it was, and
 * release [f] (a zeroed or already released OutFile is a no-op). */
void outfile_discard(OutFile *f);
/* Whether [path] could be written now: resolves it and creates and removes
 * its temporary, as outfile_open would, so an output that cannot be written
 * (no such directory, read-only, a device) is known before a run's first
 * frame instead of after its last.
 *   errors: false with outfile_open's "PATH: REASON" in [err]. */
bool outfile_check(const char *path, Buf *err);

#endif
