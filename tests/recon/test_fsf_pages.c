/* fsf_pages_alloc (src/recon/fsf/fsf_pages.h): page-aligned arrays, 2 MB aligned from 2 MB on,
 * whose whole 2 MB pages the kernel backs with huge pages when transparent huge pages are
 * available on request. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "recon/fsf/fsf_pages.h"

#define MB ((size_t)1 << 20)

/* "always" or "madvise" selected in the kernel's setting (false when it is absent or "never") */
static int huge_pages_on_request(void)
{
    FILE *f = fopen("/sys/kernel/mm/transparent_hugepage/enabled", "r");
    if (!f) return 0;
    char line[128] = {0};
    int on = fgets(line, sizeof line, f) && (strstr(line, "[always]") || strstr(line, "[madvise]"));
    fclose(f);
    return on;
}

/* AnonHugePages (kB) of the mapping that holds address p, from /proc/self/smaps; -1 if not found */
static long huge_kb_at(const void *p)
{
    FILE *f = fopen("/proc/self/smaps", "r");
    if (!f) return -1;
    char line[512];
    int inside = 0;
    long kb = -1;
    uintptr_t a = (uintptr_t)p;
    while (fgets(line, sizeof line, f)) {
        unsigned long lo, hi;
        if (sscanf(line, "%lx-%lx ", &lo, &hi) == 2 && strchr(line, '-') < strchr(line, ' ')) {
            inside = a >= lo && a < hi;
            continue;
        }
        if (inside && sscanf(line, "AnonHugePages: %ld kB", &kb) == 1) break;
    }
    fclose(f);
    return inside ? kb : -1;
}

int main(void)
{
    /* alignment: 4 KB below 2 MB, 2 MB from 2 MB on (also for sizes that are not multiples) */
    const size_t sizes[6] = {1, 4095, 300000, 2 * MB - 1, 2 * MB, 9 * MB + 12345};
    for (int k = 0; k < 6; ++k) {
        unsigned char *p = fsf_pages_alloc(sizes[k]);
        CHECK(p != NULL);
        if (!p) continue;
        size_t align = sizes[k] >= 2 * MB ? 2 * MB : 4096;
        CHECK((uintptr_t)p % align == 0);
        memset(p, 0xa5, sizes[k]); /* every byte asked for is writable (ASan: and no more is used) */
        CHECK(p[0] == 0xa5 && p[sizes[k] - 1] == 0xa5);
        free(p);
    }
    void *none = fsf_pages_alloc(0); /* one byte at least */
    CHECK(none != NULL && (uintptr_t)none % 4096 == 0);
    free(none);
    /* an array of 8 whole 2 MB pages, written: where the kernel grants huge pages on request it
     * backs it with them (a mutant without the advice gets 0 kB here) */
    size_t bytes = 16 * MB;
    unsigned char *big = fsf_pages_alloc(bytes);
    CHECK(big != NULL);
    if (big) {
        memset(big, 1, bytes);
        long kb = huge_kb_at(big);
        printf("16 MB written: AnonHugePages %ld kB in its mapping (huge pages on request: %s)\n", kb,
               huge_pages_on_request() ? "yes" : "no");
        if (huge_pages_on_request()) CHECK(kb >= 2048);
        free(big);
    }
    CHECK_DONE();
}
