/* Atomic file replacement: write everything into a temporary file in the destination
 * folder, flush it to disk, then rename it over the destination. rename() within one
 * folder is atomic on POSIX file systems, so a reader sees either the old file or the
 * complete new one, never a half-written image; a crash or error leaves no partial file
 * at the destination, and every failure path removes the temporary file. */
#ifndef WEDGE_IO_ATOMIC_FILE_H
#define WEDGE_IO_ATOMIC_FILE_H

#include <stdbool.h>

#include "core/diag.h"

typedef struct {
    char *final_path; /* the destination (malloc'd copy) */
    char *temp_path;  /* ".NAME.tmp-PID-N" next to it (malloc'd) */
    int fd;           /* open for writing while the file is in flight; -1 after close */
} AtomicFile;

/* Creates the temporary file next to path. On failure fills err (exit 3), nothing is
 * left on disk and af needs no cleanup. */
bool atomic_file_open(AtomicFile *af, const char *path, Diag *err);
/* fsyncs and closes the temporary, renames it onto the destination and fsyncs the folder
 * (so the rename itself survives a crash). On failure the temporary is removed and err
 * filled. af is released either way. */
bool atomic_file_commit(AtomicFile *af, Diag *err);
/* Gives up: closes and removes the temporary; af is released. Safe to call twice. */
void atomic_file_abort(AtomicFile *af);

/* Writes all of size bytes at offset (pwrite loop that survives short writes/EINTR). */
bool atomic_file_pwrite(AtomicFile *af, const void *data, size_t size, long long offset);

#endif
