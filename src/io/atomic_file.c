#include "io/atomic_file.h"

#include <errno.h>
#include <fcntl.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static atomic_uint temp_counter;

static char *dup_string(const char *s)
{
    size_t n = strlen(s) + 1;
    char *d = malloc(n);
    if (d) memcpy(d, s, n);
    return d;
}

/* Folder part of path ("." when there is none), malloc'd. */
static char *folder_of(const char *path)
{
    const char *slash = strrchr(path, '/');
    if (!slash) return dup_string(".");
    if (slash == path) return dup_string("/");
    size_t n = (size_t)(slash - path);
    char *d = malloc(n + 1);
    if (!d) return NULL;
    memcpy(d, path, n);
    d[n] = '\0';
    return d;
}

static void release(AtomicFile *af)
{
    free(af->final_path);
    free(af->temp_path);
    af->final_path = af->temp_path = NULL;
    af->fd = -1;
}

bool atomic_file_open(AtomicFile *af, const char *path, Diag *err)
{
    af->final_path = af->temp_path = NULL;
    af->fd = -1;
    SrcLoc loc = {path, 0, 0};
    if (!path || !*path || path[strlen(path) - 1] == '/') {
        diag_set(err, WEDGE_EXIT_RUNTIME, loc, "not a file name");
        return false;
    }
    char *folder = folder_of(path);
    const char *slash = strrchr(path, '/');
    const char *base = slash ? slash + 1 : path;
    size_t cap = strlen(path) + 64;
    af->final_path = dup_string(path);
    af->temp_path = malloc(cap);
    if (!folder || !af->final_path || !af->temp_path) {
        free(folder);
        release(af);
        diag_set(err, WEDGE_EXIT_RUNTIME, loc, "out of memory");
        return false;
    }
    /* Hidden name in the same folder (rename must not cross file systems); O_EXCL with a
     * per-process counter avoids clashes between threads and concurrent processes. Mode
     * 0666 lets the umask decide the final permissions, as for any ordinary file. */
    int saved_errno = 0;
    for (int attempt = 0; attempt < 100; ++attempt) {
        unsigned n = atomic_fetch_add(&temp_counter, 1u);
        snprintf(af->temp_path, cap, "%s/.%s.tmp-%ld-%u", folder, base, (long)getpid(), n);
        af->fd = open(af->temp_path, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (af->fd >= 0) break;
        saved_errno = errno;
        if (errno != EEXIST) break;
    }
    if (af->fd < 0) {
        diag_set(err, WEDGE_EXIT_RUNTIME, loc, "cannot create a file in folder '%s': %s", folder,
                 strerror(saved_errno));
        free(folder);
        release(af);
        return false;
    }
    free(folder);
    return true;
}

bool atomic_file_pwrite(AtomicFile *af, const void *data, size_t size, long long offset)
{
    const char *p = data;
    while (size > 0) {
        ssize_t n = pwrite(af->fd, p, size, (off_t)offset);
        if (n < 0) {
            if (errno == EINTR) continue;
            return false;
        }
        if (n == 0) {
            errno = EIO;
            return false;
        }
        p += n;
        size -= (size_t)n;
        offset += n;
    }
    return true;
}

void atomic_file_abort(AtomicFile *af)
{
    if (af->fd >= 0) close(af->fd);
    if (af->temp_path) unlink(af->temp_path);
    release(af);
}

bool atomic_file_commit(AtomicFile *af, Diag *err)
{
    SrcLoc loc = {af->final_path, 0, 0};
    /* Data must be on disk before the rename makes it visible, or a crash could leave a
     * complete-looking name with empty content. */
    if (fsync(af->fd) != 0) {
        diag_set(err, WEDGE_EXIT_RUNTIME, loc, "cannot flush to disk: %s", strerror(errno));
        atomic_file_abort(af);
        return false;
    }
    int rc = close(af->fd);
    af->fd = -1;
    if (rc != 0) {
        diag_set(err, WEDGE_EXIT_RUNTIME, loc, "cannot close: %s", strerror(errno));
        atomic_file_abort(af);
        return false;
    }
    if (rename(af->temp_path, af->final_path) != 0) {
        diag_set(err, WEDGE_EXIT_RUNTIME, loc, "cannot rename '%s' into place: %s", af->temp_path,
                 strerror(errno));
        atomic_file_abort(af);
        return false;
    }
    /* Persist the directory entry too; failure here is harmless for correctness of the
     * content, so it is not reported (some file systems refuse fsync on folders). */
    char *folder = folder_of(af->final_path);
    if (folder) {
        int dfd = open(folder, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
        if (dfd >= 0) {
            (void)fsync(dfd);
            close(dfd);
        }
        free(folder);
    }
    release(af);
    return true;
}
