/* watch.c: live reload by polling: a Watch holds the files of one page's
 * loaded program (fl_program_files) with their stat() stamps, and each
 * frame compares them with stat() again: a few system calls a frame, no
 * inotify descriptors to manage, and a save is seen within one frame.
 * Invariant: stamps[i] is what paths[i] looked like at the last poll. */
#include "watch.h"

#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static void *xcalloc(size_t n, size_t size)
{
    void *p = calloc(n ? n : 1, size);
    if (!p) abort();
    return p;
}

static char *xstrdup(const char *s)
{
    char *p = strdup(s);
    if (!p) abort();
    return p;
}

static FileStamp stamp_of(const char *path)
{
    struct stat sb;
    if (stat(path, &sb) != 0) return (FileStamp){.exists = false};
    return (FileStamp){sb.st_mtim, sb.st_size, sb.st_ino, true};
}

static bool same_stamp(FileStamp a, FileStamp b)
{
    return a.exists == b.exists && a.mtime.tv_sec == b.mtime.tv_sec &&
           a.mtime.tv_nsec == b.mtime.tv_nsec && a.size == b.size && a.ino == b.ino;
}

void watch_set(Watch *w, fl_runtime *rt, const char *script)
{
    watch_free(w);
    size_t n = fl_program_files(rt, NULL, 0);
    const char **files = xcalloc(n, sizeof *files);
    n = fl_program_files(rt, files, n);
    bool listed = false;
    for (size_t i = 0; i < n; i++) listed |= strcmp(files[i], script) == 0;
    w->paths = xcalloc(n + 1, sizeof *w->paths);
    w->stamps = xcalloc(n + 1, sizeof *w->stamps);
    if (!listed) w->paths[w->n++] = xstrdup(script);
    for (size_t i = 0; i < n; i++) w->paths[w->n++] = xstrdup(files[i]);
    free(files);
    for (size_t i = 0; i < w->n; i++) w->stamps[i] = stamp_of(w->paths[i]);
}

/* A file modified less than this long ago (seconds) may still be being
 * written in place (truncated, then written: an empty or half script in
 * between); its change is taken at a later poll. An empty file waits
 * longer: a writer preempted between the truncation and its write leaves
 * one for as long as it waits for the processor, and loading it would
 * replace the running program with nothing (a script emptied on purpose
 * is taken half a second later). */
#define WATCH_SETTLE 0.02
#define WATCH_SETTLE_EMPTY 0.5

/* True when [s] was last modified long enough ago (or is gone). */
static bool settled(FileStamp s)
{
    if (!s.exists) return true;
    struct timespec now;
    clock_gettime(CLOCK_REALTIME, &now);
    double age = (double)(now.tv_sec - s.mtime.tv_sec) + (double)(now.tv_nsec - s.mtime.tv_nsec) * 1e-9;
    if (age < -1.0) return true;   /* a clock step back: do not wait */
    return age >= (s.size == 0 ? WATCH_SETTLE_EMPTY : WATCH_SETTLE);
}

bool watch_changed(Watch *w)
{
    bool changed = false, fresh = false;
    FileStamp *now = xcalloc(w->n, sizeof *now);
    for (size_t i = 0; i < w->n; i++) {
        now[i] = stamp_of(w->paths[i]);
        if (!same_stamp(now[i], w->stamps[i])) {
            changed = true;
            fresh |= !settled(now[i]);
        }
    }
    /* report a save once it has settled; until then the stamps stay, so
     * the next poll looks again */
    if (changed && !fresh)
        for (size_t i = 0; i < w->n; i++) w->stamps[i] = now[i];
    free(now);
    return changed && !fresh;
}

void watch_free(Watch *w)
{
    for (size_t i = 0; i < w->n; i++) free(w->paths[i]);
    free(w->paths);
    free(w->stamps);
    *w = (Watch){0};
}
