/* OpenCL drivers opened with their own libraries bound first (see icd_preload.h). */
#define _GNU_SOURCE /* RTLD_DEEPBIND */
#include "recon/cl/icd_preload.h"

#include <ctype.h>
#include <dirent.h>
#include <dlfcn.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/env_knob.h"

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define PRELOAD_REFUSED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || __has_feature(memory_sanitizer)
#define PRELOAD_REFUSED 1
#endif
#endif
#ifndef PRELOAD_REFUSED
#define PRELOAD_REFUSED 0
#endif

#define MAX_DRIVERS 16

static pthread_once_t preload_once = PTHREAD_ONCE_INIT;
static int drivers_opened;

bool cl_icd_library_name(char *line)
{
    size_t n = strlen(line);
    while (n > 0 && isspace((unsigned char)line[n - 1])) line[--n] = '\0';
    size_t lead = 0;
    while (isspace((unsigned char)line[lead])) ++lead;
    memmove(line, line + lead, n - lead + 1);
    return line[0] != '\0';
}

/* The .icd file's library name (cl_icd_library_name of its first line) into name. */
static bool icd_file_library(const char *dir, const char *file, char *name, size_t cap)
{
    char path[4096];
    if (snprintf(path, sizeof path, "%s/%s", dir, file) >= (int)sizeof path) return false;
    FILE *f = fopen(path, "r");
    if (!f) return false;
    bool got = fgets(name, (int)cap, f) != NULL;
    fclose(f);
    return got && cl_icd_library_name(name);
}

static bool ends_with(const char *s, const char *tail)
{
    size_t n = strlen(s), m = strlen(tail);
    return n >= m && strcmp(s + n - m, tail) == 0;
}

static void preload_drivers(void)
{
    if (PRELOAD_REFUSED || !env_knob_switch("WEDGE_CL_PRELOAD", true)) return;
    /* a loader pointed elsewhere reads other files: leave the choice to it */
    if (getenv("OCL_ICD_VENDORS") || getenv("OCL_ICD_FILENAMES") || getenv("OPENCL_VENDOR_PATH")) return;
    /* an interposing library (a malloc replacement, a tracing shim) would no longer see the
     * driver's calls that its own libraries resolve first (libc's malloc among them) */
    if (getenv("LD_PRELOAD") && *getenv("LD_PRELOAD")) return;
    DIR *dir = opendir(CL_ICD_VENDOR_DIR);
    if (!dir) return;
    struct dirent *e;
    while ((e = readdir(dir)) != NULL && drivers_opened < MAX_DRIVERS) {
        char name[1024];
        if (!ends_with(e->d_name, ".icd") || !icd_file_library(CL_ICD_VENDOR_DIR, e->d_name, name, sizeof name)) continue;
        /* the handle is never closed: the driver stays for the process, and the ICD loader's
         * dlopen of the same name finds it loaded, with the scopes set here */
        if (!dlopen(name, RTLD_LAZY | RTLD_LOCAL | RTLD_DEEPBIND)) {
            (void)dlerror();
            continue;
        }
        ++drivers_opened;
        if (env_knob_switch("WEDGE_CL_LOG", false))
            fprintf(stderr, "wedge: cl driver %s opened ahead of the ICD loader, bound to its own libraries first\n", name);
    }
    closedir(dir);
}

void cl_icd_preload(void) { pthread_once(&preload_once, preload_drivers); }

int cl_icd_preloaded(void) { return drivers_opened; }

bool cl_icd_preload_built_in(void) { return !PRELOAD_REFUSED; }
