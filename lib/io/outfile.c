/* outfile.c: write to a temporary, rename over the target (see outfile.h).
 *
 * The temporary's name takes six letters from a hash of the process id,
 * the clock and the attempt number; it is created with O_EXCL, so two
 * writers (two runtimes, two processes) never share one, and a clash only
 * costs another attempt.
 */
#include "outfile.h"

#include <errno.h>
#include <fcntl.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "mem.h"

enum { MAX_LINKS = 40, MAX_ATTEMPTS = 100 };

static char *dup_or_die(const char *s)
{
    char *d = strdup(s);
    if (!d) mem_oom();
    return d;
}

/* [dir of path] joined with [rel]; [rel] absolute stands alone. */
static char *join_dir(const char *path, const char *rel)
{
    if (rel[0] == '/') return dup_or_die(rel);
    const char *slash = strrchr(path, '/');
    if (!slash) return dup_or_die(rel);
    size_t d = (size_t)(slash - path) + 1, n = strlen(rel);
    char *out = malloc(d + n + 1);
    if (!out) mem_oom();
    memcpy(out, path, d);
    memcpy(out + d, rel, n + 1);
    return out;
}

/* Follow symbolic links from [path]: the file to replace (malloc'd), or
 * NULL with [err] set. [*st_out] / [*exists] describe it. */
static char *resolve(const char *path, struct stat *st_out, bool *exists, Buf *err)
{
    char *cur = dup_or_die(path);
    for (int hops = 0;; hops++) {
        struct stat st;
        if (lstat(cur, &st) != 0) {
            *exists = false;   /* a new file (or a dangling link's target) */
            return cur;
        }
        if (!S_ISLNK(st.st_mode)) {
            if (!S_ISREG(st.st_mode)) {
                buf_printf(err, "%s: not a regular file (%s); not replaced\n", path,
                         S_ISDIR(st.st_mode) ? "a directory" : S_ISFIFO(st.st_mode) ? "a FIFO"
                         : S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode) ? "a device" : "a special file");
                free(cur);
                return NULL;
            }
            *exists = true;
            *st_out = st;
            return cur;
        }
        if (hops == MAX_LINKS) {
            buf_printf(err, "%s: too many levels of symbolic links\n", path);
            free(cur);
            return NULL;
        }
        char link[4096];
        ssize_t n = readlink(cur, link, sizeof link - 1);
        if (n < 0 || (size_t)n >= sizeof link - 1) {
            buf_printf(err, "%s: cannot read the symbolic link %s\n", path, cur);
            free(cur);
            return NULL;
        }
        link[n] = '\0';
        char *next = join_dir(cur, link);
        free(cur);
        cur = next;
    }
}

bool outfile_open(OutFile *f, const char *path, Buf *err)
{
    *f = (OutFile){.fd = -1};
    struct stat st;
    bool exists = false;
    char *target = resolve(path, &st, &exists, err);
    if (!target) return false;
    const char *slash = strrchr(target, '/');
    int dlen = slash ? (int)(slash - target) + 1 : 0;
    const char *base = target + dlen;
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    uint64_t seed = ((uint64_t)getpid() << 32) ^ (uint64_t)ts.tv_nsec ^ ((uint64_t)ts.tv_sec << 20) ^
                    (uint64_t)(uintptr_t)f;
    static const char letters[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789";
    int fd = -1, saved = 0;
    char *tmp = NULL;
    for (int attempt = 0; attempt < MAX_ATTEMPTS && fd < 0; attempt++) {
        uint64_t h = seed + (uint64_t)attempt * 0x9E3779B97F4A7C15u;
        h ^= h >> 33;
        h *= 0xFF51AFD7ED558CCDu;
        h ^= h >> 33;
        char suffix[7];
        for (int i = 0; i < 6; i++, h /= 62) suffix[i] = letters[h % 62];
        suffix[6] = '\0';
        free(tmp);
        if (asprintf(&tmp, "%.*s.%s.%s", dlen, target, base, suffix) < 0) mem_oom();
        fd = open(tmp, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        saved = errno;
        if (fd < 0 && saved != EEXIST) break;
    }
    if (fd < 0) {
        buf_printf(err, "%s: cannot create a file in %.*s: %s\n", path, dlen > 1 ? dlen - 1 : 1,
                 dlen ? target : ".", strerror(saved));
        free(tmp);
        free(target);
        return false;
    }
    if (exists) (void)fchmod(fd, st.st_mode & 07777);   /* keep the replaced file's permissions */
    f->target = target;
    f->tmp = tmp;
    f->fd = fd;
    return true;
}

static void release(OutFile *f)
{
    free(f->target);
    free(f->tmp);
    *f = (OutFile){.fd = -1};
}

bool outfile_commit(OutFile *f, bool durable, Buf *err)
{
    bool ok = true;
    int saved = 0;
    if (f->fd >= 0) {
        if (durable && fsync(f->fd) != 0) ok = false, saved = errno;
        if (close(f->fd) != 0 && ok) ok = false, saved = errno;
        f->fd = -1;
    } else if (durable) {   /* written and closed by another library: sync by name */
        int fd = open(f->tmp, O_RDONLY | O_CLOEXEC);
        if (fd >= 0) {
            (void)fsync(fd);
            close(fd);
        }
    }
    if (ok && rename(f->tmp, f->target) != 0) ok = false, saved = errno;
    if (!ok) {
        buf_printf(err, "%s: cannot finish the file: %s\n", f->target, strerror(saved));
        unlink(f->tmp);
    }
    release(f);
    return ok;
}

void outfile_discard(OutFile *f)
{
    if (f->fd >= 0) close(f->fd);
    if (f->tmp) unlink(f->tmp);
    release(f);
}

bool outfile_check(const char *path, Buf *err)
{
    OutFile f;
    if (!outfile_open(&f, path, err)) return false;
    outfile_discard(&f);
    return true;
}
