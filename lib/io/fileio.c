/* fileio.c: whole-file reads and atomic replacement (see fileio.h). */
#include "fileio.h"
#include "outfile.h"

#include <errno.h>
#include <fcntl.h>
#include <libgen.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "mem.h"

/* Read the file open on [fd] (closed here) into [out]; with [regular_only],
 * anything but a regular file is refused (EINVAL). [stat_out] (may be
 * NULL) gets the file's status as it was opened (zeroed when unknown). */
static bool read_fd(int fd, Buf *out, bool regular_only, struct stat *stat_out)
{
    struct stat st;
    if (stat_out) memset(stat_out, 0, sizeof *stat_out);
    if (fstat(fd, &st) == 0) {
        if (stat_out) *stat_out = st;
        int refuse = 0;
        if (S_ISDIR(st.st_mode)) refuse = EISDIR;
        else if (S_ISREG(st.st_mode) && (uint64_t)st.st_size > FILE_READ_MAX) refuse = EFBIG;
        else if (regular_only && !S_ISREG(st.st_mode)) refuse = EINVAL;
        if (refuse) {
            close(fd);
            errno = refuse;
            return false;
        }
    }
    FILE *f = fdopen(fd, "rb");
    if (!f) {
        int saved = errno;
        close(fd);
        errno = saved;
        return false;
    }
    char chunk[65536];
    size_t n, total = 0;
    bool big = false;
    while ((n = fread(chunk, 1, sizeof chunk, f)) > 0) {
        if (n > FILE_READ_MAX - total) {
            big = true;
            break;
        }
        total += n;
        buf_add(out, chunk, n);
    }
    bool ok = !big && !ferror(f);
    fclose(f);
    if (!ok) errno = big ? EFBIG : EIO;
    return ok;
}

bool file_read(const char *path, Buf *out)
{
    int fd = open(path, O_RDONLY | O_CLOEXEC);
    if (fd < 0) return false;
    return read_fd(fd, out, false, NULL);
}

bool file_read_regular(const char *path, Buf *out)
{
    /* O_NONBLOCK: opening a FIFO with no writer must not wait; a regular
     * file ignores the flag */
    return file_read_regular_stat(path, out, NULL);
}

bool file_read_regular_stat(const char *path, Buf *out, struct stat *st)
{
    int fd = open(path, O_RDONLY | O_CLOEXEC | O_NONBLOCK);
    if (fd < 0) return false;
    return read_fd(fd, out, true, st);
}

static bool write_all(int fd, const char *p, size_t n)
{
    while (n) {
        ssize_t w = write(fd, p, n);
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) return false;
        p += w;
        n -= (size_t)w;
    }
    return true;
}

bool file_write_atomic(const char *path, const char *data, size_t len, Buf *err)
{
    OutFile f;
    if (!outfile_open(&f, path, err)) return false;
    if (!write_all(f.fd, data, len)) {
        buf_printf(err, "%s: %s\n", path, strerror(errno));
        outfile_discard(&f);
        return false;
    }
    char *dirc = mem_strdup(f.target);
    if (!outfile_commit(&f, true, err)) {
        free(dirc);
        return false;
    }
    /* make the rename itself durable */
    int dfd = open(dirname(dirc), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dfd >= 0) {
        fsync(dfd);
        close(dfd);
    }
    free(dirc);
    return true;
}
