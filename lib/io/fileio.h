/* fileio.h: reading a whole file and replacing a file atomically, for
 * scripts, modules, included files, state files and expected outputs. */
#ifndef FL_FILEIO_H
#define FL_FILEIO_H

#include <stdbool.h>
#include <stddef.h>

#include "config.h"
#include "buf.h"

/* Append the whole contents of the file at [path] to [out].
 *   errors: returns false with errno set when it cannot be opened or read
 *           (EISDIR for a directory, EFBIG for a file larger than
 *           FILE_READ_MAX; [out] may then hold part of the file). */
bool file_read(const char *path, Buf *out);

/* file_read() for the file built-ins, which run inside a frame: anything
 * but a regular file (a FIFO, a terminal, a device such as /dev/stdin or
 * /dev/zero) is refused with errno EINVAL instead of being read, so a
 * script cannot make a frame wait for input or read without end. Opening
 * never blocks.
 *   errors: as file_read(), plus EINVAL for a file that is not regular. */
bool file_read_regular(const char *path, Buf *out);

struct stat;
/* file_read_regular(), and the status of the file it opened (fstat: its
 * device, inode, size and times as it was opened) in *[st] (zeroed when
 * unknown; may be NULL), so that a caller keeping the contents can tell
 * later whether the file at [path] is still that file, unchanged. */
bool file_read_regular_stat(const char *path, Buf *out, struct stat *st);

/* Replace the file at [path] with the [len] bytes at [data] atomically
 * through outfile.h: a symbolic link is written through to its target,
 * a temporary is created exclusively (O_EXCL) next to the target with the
 * replaced file's permission bits (else 0666 less the umask), written,
 * fsync'd and renamed over it, then the directory is fsync'd, so a crash
 * leaves either the old or the new contents.
 *   errors: returns false with `PATH: REASON` appended to [err]:
 *           a target that is not a regular file (directory, FIFO, device)
 *           is refused; the temporary file is removed and [path] is
 *           untouched. */
bool file_write_atomic(const char *path, const char *data, size_t len, Buf *err);

#endif
