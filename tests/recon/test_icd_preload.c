/* The OpenCL drivers opened ahead of the ICD loader (src/recon/cl/icd_preload.h): every
 * driver the vendor directory names that dlopen can load is loaded by cl_icd_preload and by
 * nothing before it; a second call opens nothing more; the ICD loader then finds those
 * drivers loaded (each file mapped once) and lists the same devices as a process without the
 * preload (tests/recon/icd_preload.sh compares the two processes' devices and images). */
#define _GNU_SOURCE /* RTLD_NOLOAD, dl_iterate_phdr */
#include <dirent.h>
#include <dlfcn.h>
#include <link.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "check.h"
#include "recon/cl/cl_runtime.h"
#include "recon/cl/icd_preload.h"

#define MAX_NAMES 16

/* The library names of the vendor directory's .icd files (their first line, trimmed: the
 * trimming is checked on its own in library_names). */
static int vendor_libraries(char names[MAX_NAMES][1024])
{
    DIR *dir = opendir(CL_ICD_VENDOR_DIR);
    if (!dir) return 0;
    int n = 0;
    for (struct dirent *e; n < MAX_NAMES && (e = readdir(dir)) != NULL;) {
        size_t len = strlen(e->d_name);
        if (len < 4 || strcmp(e->d_name + len - 4, ".icd") != 0) continue;
        char path[2048];
        snprintf(path, sizeof path, "%s/%s", CL_ICD_VENDOR_DIR, e->d_name);
        FILE *f = fopen(path, "r");
        if (!f) continue;
        char line[1024] = "";
        bool got = fgets(line, sizeof line, f) != NULL;
        fclose(f);
        if (got && cl_icd_library_name(line)) snprintf(names[n++], sizeof names[0], "%s", line);
    }
    closedir(dir);
    return n;
}

static bool is_loaded(const char *name)
{
    void *h = dlopen(name, RTLD_LAZY | RTLD_NOLOAD);
    if (!h) return false;
    dlclose(h); /* NOLOAD took a reference */
    return true;
}

/* How many loaded objects are the file at path (the same device and inode). */
typedef struct {
    dev_t dev;
    ino_t ino;
    int count;
} SameFile;

static int count_same_file(struct dl_phdr_info *info, size_t size, void *arg)
{
    (void)size;
    SameFile *sf = arg;
    struct stat st;
    if (info->dlpi_name && info->dlpi_name[0] && stat(info->dlpi_name, &st) == 0 && st.st_dev == sf->dev && st.st_ino == sf->ino)
        ++sf->count;
    return 0;
}

/* The path of the loaded object name resolves to (dladdr on one of its symbols is not
 * portable across drivers; the link map's name is). */
static bool loaded_path(const char *name, char *path, size_t cap)
{
    void *h = dlopen(name, RTLD_LAZY | RTLD_NOLOAD);
    if (!h) return false;
    struct link_map *map = NULL;
    bool ok = dlinfo(h, RTLD_DI_LINKMAP, &map) == 0 && map && map->l_name && map->l_name[0];
    if (ok) snprintf(path, cap, "%s", map->l_name);
    dlclose(h);
    return ok;
}

/* The .icd line's trimming, on the forms vendor files take. */
static void library_names(void)
{
    char a[] = "libpocl.so.2\n", b[] = "  /usr/lib/x86_64-linux-gnu/libfoo.so.1 \t\r\n", c[] = "libbar.so", d[] = " \n", e[] = "";
    CHECK(cl_icd_library_name(a));
    CHECK_STR(a, "libpocl.so.2");
    CHECK(cl_icd_library_name(b));
    CHECK_STR(b, "/usr/lib/x86_64-linux-gnu/libfoo.so.1");
    CHECK(cl_icd_library_name(c));
    CHECK_STR(c, "libbar.so");
    CHECK(!cl_icd_library_name(d));
    CHECK(!cl_icd_library_name(e));
}

int main(void)
{
    library_names();
    static char names[MAX_NAMES][1024];
    int n = vendor_libraries(names);
    bool elsewhere = getenv("OCL_ICD_VENDORS") || getenv("OCL_ICD_FILENAMES") || getenv("OPENCL_VENDOR_PATH") ||
                     (getenv("LD_PRELOAD") && *getenv("LD_PRELOAD"));
    const char *knob = getenv("WEDGE_CL_PRELOAD");
    bool off = knob && strcmp(knob, "0") == 0;
    if (n == 0) {
        printf("skip: no driver named in %s\n", CL_ICD_VENDOR_DIR);
        return 77;
    }
    bool before[MAX_NAMES];
    for (int i = 0; i < n; ++i) before[i] = is_loaded(names[i]);

    cl_icd_preload();
    int opened = cl_icd_preloaded();
    if (!cl_icd_preload_built_in() || elsewhere || off) {
        CHECK(opened == 0);
        printf("preload off here (%s): %d opened\n", !cl_icd_preload_built_in() ? "sanitizer build" : "environment", opened);
    } else {
        /* each name the directory gives, unless something had loaded it first, is loaded now */
        int expect = 0;
        for (int i = 0; i < n; ++i) {
            bool now = is_loaded(names[i]);
            if (!before[i] && now) ++expect;
            if (!before[i]) CHECK(now || dlopen(names[i], RTLD_LAZY | RTLD_LOCAL) == NULL); /* loadable => loaded */
        }
        CHECK(opened == expect);
        CHECK(opened >= 1); /* a machine with a vendor file and a loadable driver (PoCL here) */
    }
    cl_icd_preload(); /* once per process */
    CHECK(cl_icd_preloaded() == opened);

    /* the ICD loader finds the drivers already loaded: one mapping of each file */
    Diag d = {0};
    bool have_device = cl_runtime_check_device(NULL, &d);
    if (!have_device) fprintf(stderr, "no OpenCL device: %s\n", d.message);
    for (int i = 0; i < n; ++i) {
        char path[4096];
        if (!loaded_path(names[i], path, sizeof path)) continue;
        struct stat st;
        if (stat(path, &st) != 0) continue;
        SameFile sf = {st.st_dev, st.st_ino, 0};
        dl_iterate_phdr(count_same_file, &sf);
        CHECK(sf.count == 1);
    }
    CHECK(have_device);
    CHECK_DONE();
}
