/* A writable place for the OpenCL driver's compiled kernels (see kernel_cache.h). */
#define _XOPEN_SOURCE 700 /* nftw */
#include "recon/cl/kernel_cache.h"

#include "core/cache_home.h"

#include <stdbool.h>

#include <errno.h>
#include <ftw.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static char temp_cache[512];

/* Whether dir exists and is writable, or could be created (its nearest existing ancestor
 * is a writable directory). */
static bool usable_dir(const char *dir)
{
    char path[4096];
    snprintf(path, sizeof path, "%s", dir);
    for (;;) {
        struct stat st;
        if (stat(path, &st) == 0) return S_ISDIR(st.st_mode) && access(path, W_OK | X_OK) == 0;
        if (errno != ENOENT) return false;
        char *slash = strrchr(path, '/');
        if (!slash || slash == path) return false;
        *slash = 0;
    }
}

static int remove_entry(const char *path, const struct stat *st, int flag, struct FTW *ftw)
{
    (void)st, (void)flag, (void)ftw;
    remove(path);
    return 0;
}

static void remove_temp_cache(void)
{
    if (temp_cache[0]) nftw(temp_cache, remove_entry, 16, FTW_DEPTH | FTW_PHYS);
}

static void choose_cache(void)
{
    if (getenv("POCL_CACHE_DIR")) return; /* the user's choice */
    char dir[4096];
    if (!cache_home("pocl", dir, sizeof dir)) dir[0] = 0;
    if (dir[0] && usable_dir(dir)) return;
    const char *tmp = getenv("TMPDIR");
    snprintf(temp_cache, sizeof temp_cache, "%s/wedge-kernels-XXXXXX", tmp && tmp[0] ? tmp : "/tmp");
    if (!mkdtemp(temp_cache)) {
        temp_cache[0] = 0;
        return;
    }
    setenv("POCL_CACHE_DIR", temp_cache, 1);
    atexit(remove_temp_cache);
    fprintf(stderr,
            "wedge: note: the OpenCL kernel cache %s is not writable ($HOME or $XDG_CACHE_HOME); compiled kernels go "
            "to %s for this run (set $POCL_CACHE_DIR to a writable directory to keep them)\n",
            dir[0] ? dir : "(no $HOME)", temp_cache);
}

void kernel_cache_prepare(void)
{
    static pthread_once_t once = PTHREAD_ONCE_INIT;
    pthread_once(&once, choose_cache);
}
