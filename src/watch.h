/* watch.h: the files of a loaded program, polled for changes (live reload). */
#ifndef FL_WATCH_H
#define FL_WATCH_H

#include <stdbool.h>
#include <stddef.h>
#include <sys/types.h>
#include <time.h>

#include "flitter.h"

/* What a file looked like when last polled: a save (in place, or by
 * writing a new file and renaming it over) changes at least one field. */
typedef struct FileStamp {
    struct timespec mtime;   /* modification time (st_mtim) */
    off_t size;              /* bytes */
    ino_t ino;               /* inode: changes when an editor renames over */
    bool exists;             /* false when stat() failed */
} FileStamp;

/* The watched files of one page's program. */
typedef struct Watch {
    char **paths;            /* owned copies of fl_program_files() */
    FileStamp *stamps;       /* paths[i] as last polled */
    size_t n;                /* number of paths */
} Watch;

/* Watch the files [rt]'s loaded program was read from (fl_program_files:
 * the script, its %includes and imports), replacing [w]'s list, with their
 * stamps as they are now; [script] is always watched, also when the
 * library lists no file. Call it after each successful fl_load.
 *   errors: none (a file that cannot be stat()ed is stamped as missing);
 *           aborts when out of memory. */
void watch_set(Watch *w, fl_runtime *rt, const char *script);

/* Poll [w]'s files: true when any of them changed since the last poll or
 * watch_set (saved, replaced, created or deleted) and every changed file
 * was last modified 20 ms ago or more, 500 ms for an empty file (a file
 * written in place is briefly empty or half written: it is taken once it
 * has settled, at most a frame or two later); the stamps are then
 * updated, so one save is reported once.
 *   source: Flitter re-reads a page whose file changed at each frame
 *           (engine/control.py run, read_flitter_program). */
bool watch_changed(Watch *w);

/* Free [w]'s list (the struct may be reused or dropped). */
void watch_free(Watch *w);

#endif
