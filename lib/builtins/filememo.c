/* filememo.c: a runtime's memo of the files its file built-ins read
 * (builtins.h FileMemo; files.h for the built-ins' side).
 *
 * A script reads the same files every frame: a shader's source with
 * read(), a table with csv() once per row. Read afresh, each call opens,
 * reads and closes the file (and csv() parses it from the top). Flitter
 * keeps what it read until the file's modification time changes
 * (cache.py's CachePath, one stat() a use); so does this memo, comparing
 * more: the device, inode, size, modification and change times of the
 * file it read (the status of the open file, fileio.h
 * file_read_regular_stat) with the stat() of the path at each use. A file
 * replaced, rewritten, grown or touched is read again; what a call
 * returns is what reading the file then would give.
 *
 * A file's times have a grain (a few milliseconds of the kernel's coarse
 * clock; a second or two on some file systems), so a change made in the
 * same grain as the last one, keeping the size, would leave its status as
 * it was. As git does with its index, a file changed less than a window
 * (2 s) before it was read is "racy": it is read again at every use, as
 * without a memo, until a read comes a window after its last change.
 */
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#include "fileio.h"
#include "files.h"
#include "mem.h"
#include "utf8.h"

/* Most files kept (the least recently used goes first). */
#define FILE_MEMO_ENTRIES 16
/* Largest file kept; a larger one is read afresh at every use. */
#define FILE_MEMO_MAX ((size_t)16 << 20)
/* The racy window (nanoseconds). */
#define FILE_MEMO_WINDOW INT64_C(2000000000)

typedef struct FileMemoEntry {
    char *path;             /* as resolved (NULL: a free entry) */
    struct stat st;         /* the file's status as it was read */
    Buf data;               /* its bytes */
    Vec *text;              /* read()'s string of them, once made */
    bool text_done;         /* text made (NULL: not strict UTF-8) */
    bool racy;              /* changed within the window before it was read */
    CsvRows *rows;          /* csv()'s rows of the bytes, or NULL */
    uint64_t used;          /* the memo's clock at its last use */
} FileMemoEntry;

struct FileMemo {
    FileMemoEntry e[FILE_MEMO_ENTRIES];
    uint64_t clock;
    int64_t window;         /* the racy window (ns) */
};

FileMemo *file_memo_new(void)
{
    FileMemo *m = calloc(1, sizeof(FileMemo));
    if (m) m->window = FILE_MEMO_WINDOW;
    return m;
}

void file_memo_set_window(FileMemo *m, int64_t ns)
{
    if (m) m->window = ns;
}

static int64_t ns_of(struct timespec t) { return (int64_t)t.tv_sec * 1000000000 + t.tv_nsec; }

/* Whether a file of status [st], read at the time [now], changed within
 * [window] before it (or after it: a time in the future). */
static bool racy(const struct stat *st, struct timespec now, int64_t window)
{
    int64_t changed = ns_of(st->st_mtim) > ns_of(st->st_ctim) ? ns_of(st->st_mtim) : ns_of(st->st_ctim);
    return ns_of(now) - changed < window;
}

static void entry_clear(FileMemoEntry *e)
{
    csv_rows_free(e->rows);
    free(e->path);
    buf_free(&e->data);
    vec_release(e->text);
    memset(e, 0, sizeof *e);
}

void file_memo_free(FileMemo *m)
{
    if (!m) return;
    for (int i = 0; i < FILE_MEMO_ENTRIES; i++) entry_clear(&m->e[i]);
    free(m);
}

static bool same_file(const struct stat *a, const struct stat *b)
{
    return a->st_dev == b->st_dev && a->st_ino == b->st_ino && a->st_size == b->st_size &&
           a->st_mtim.tv_sec == b->st_mtim.tv_sec && a->st_mtim.tv_nsec == b->st_mtim.tv_nsec &&
           a->st_ctim.tv_sec == b->st_ctim.tv_sec && a->st_ctim.tv_nsec == b->st_ctim.tv_nsec;
}

/* The entry of [path] holding its current contents, reading them when it
 * has none or the file changed; NULL when the file cannot be read
 * (errno as file_read_regular's) or is too large to keep (*[big] true,
 * the caller reads it itself). */
static FileMemoEntry *lookup(FileMemo *m, const char *path, bool *big)
{
    *big = false;
    FileMemoEntry *e = NULL, *victim = &m->e[0];
    for (int i = 0; i < FILE_MEMO_ENTRIES; i++) {
        FileMemoEntry *x = &m->e[i];
        if (x->path && !strcmp(x->path, path)) e = x;
        if (!x->path || (victim->path && x->used < victim->used)) victim = x;
    }
    m->clock++;
    struct stat now;
    if (e && !e->racy && stat(path, &now) == 0 && same_file(&now, &e->st)) {
        e->used = m->clock;
        return e;
    }
    if (!e) e = victim;
    entry_clear(e);
    Buf data = BUF_INIT;
    struct stat st;
    struct timespec read_at;
    clock_gettime(CLOCK_REALTIME, &read_at);
    if (!file_read_regular_stat(path, &data, &st)) {
        int saved = errno;
        buf_free(&data);
        errno = saved;
        return NULL;
    }
    if (data.len > FILE_MEMO_MAX) {
        buf_free(&data);
        *big = true;
        return NULL;
    }
    e->path = mem_strdup(path);
    e->st = st;
    e->racy = racy(&st, read_at, m->window);
    e->data = data;
    e->used = m->clock;
    return e;
}

bool file_memo_bytes(FileMemo *m, const char *path, Buf *scratch, const char **data, size_t *len,
                     CsvRows ***rows)
{
    bool big = false;
    FileMemoEntry *e = m ? lookup(m, path, &big) : NULL;
    if (rows) *rows = e ? &e->rows : NULL;
    if (e) {
        *data = e->data.data ? e->data.data : "";
        *len = e->data.len;
        return true;
    }
    if (m && !big) return false;
    if (!file_read_regular(path, scratch)) return false;
    *data = scratch->data ? scratch->data : "";
    *len = scratch->len;
    return true;
}

/* read()'s string of the [len] bytes at [s] (strict UTF-8, universal
 * newlines: "\r\n" and "\r" become "\n"); NULL when they are not strict
 * UTF-8. */
static Vec *text_vec(const char *s, size_t len)
{
    if (!utf8_all_valid(s, len)) return NULL;
    Buf out = BUF_INIT;
    /* runs without a carriage return copied whole */
    size_t i = 0;
    while (i < len) {
        const char *cr = memchr(s + i, '\r', len - i);
        size_t run = cr ? (size_t)(cr - (s + i)) : len - i;
        buf_add(&out, s + i, run);
        i += run;
        if (i < len) {
            buf_add(&out, "\n", 1);
            i += (i + 1 < len && s[i + 1] == '\n') ? 2 : 1;
        }
    }
    Vec *v = vec_str(buf_cstr(&out), out.len);
    buf_free(&out);
    return v;
}

/* text_vec of the file [path] read now; NULL with *[ok] false when it
 * cannot be read (errno as file_read_regular's) or is not strict UTF-8
 * (errno 0: a silent null). */
static Vec *text_afresh(const char *path, bool *ok)
{
    Buf raw = BUF_INIT;
    Vec *v = NULL;
    errno = 0;
    if (file_read_regular(path, &raw)) {
        v = text_vec(buf_cstr(&raw), raw.len);
        if (!v) errno = 0;
    }
    buf_free(&raw);
    *ok = v != NULL;
    return v;
}

Vec *file_memo_text(FileMemo *m, const char *path, bool *ok)
{
    if (!m) return text_afresh(path, ok);
    bool big;
    errno = 0;
    FileMemoEntry *e = lookup(m, path, &big);
    if (!e) {
        if (big) return text_afresh(path, ok);
        *ok = false;
        return NULL;
    }
    if (!e->text_done) {
        e->text = text_vec(e->data.data ? e->data.data : "", e->data.len);
        e->text_done = true;
    }
    *ok = e->text != NULL;
    if (!*ok) errno = 0;   /* (not UTF-8: a silent null, as text_afresh's) */
    return vec_retain(e->text);
}
