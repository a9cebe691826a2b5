/* huge_pages_alloc (src/core/huge_pages.h): page-aligned arrays, 2 MB aligned from 2 MB on,
 * whose whole 2 MB pages the kernel backs with huge pages when transparent huge pages are
 * available on request and free 2 MB blocks are to spare; the guard's count of free blocks. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "core/huge_pages.h"

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

/* the guard's reading of /proc/buddyinfo: free blocks of order 9 count 1, of order 10 count 2 */
static void buddyinfo_counts(void)
{
    const char *text = "Node 0, zone      DMA      0      0      0      0      0      0      0      0      1      1      3 \n"
                       "Node 0, zone    DMA32      2      2      4      2      5      4      3      3      4      2    752 \n"
                       "Node 0, zone   Normal   7676  13075   9892   8792   4703   2717   1133    408    121     68     76 \n";
    long blocks = huge_pages_free_blocks(text);
    printf("sample buddyinfo: %ld free 2 MB blocks (expected %d)\n", blocks, 1 + 2 * 3 + 2 + 2 * 752 + 68 + 2 * 76);
    CHECK(blocks == 1 + 2 * 3 + 2 + 2 * 752 + 68 + 2 * 76);
    /* a zone with nothing above order 8, and a text without zones */
    CHECK(huge_pages_free_blocks("Node 0, zone   Normal   5 5 5 5 5 5 5 5 5 0 0\n") == 0);
    CHECK(huge_pages_free_blocks("") == -1);
    CHECK(huge_pages_free_blocks("nothing here\n") == -1);
}

static long free_huge_blocks_now(void)
{
    FILE *f = fopen("/proc/buddyinfo", "r");
    if (!f) return -1;
    static char text[4096];
    size_t len = fread(text, 1, sizeof text - 1, f);
    fclose(f);
    text[len] = '\0';
    return huge_pages_free_blocks(text);
}

int main(void)
{
    buddyinfo_counts();
    /* alignment: 4 KB below 2 MB, 2 MB from 2 MB on (also for sizes that are not multiples) */
    const size_t sizes[6] = {1, 4095, 300000, 2 * MB - 1, 2 * MB, 9 * MB + 12345};
    for (int k = 0; k < 6; ++k) {
        unsigned char *p = huge_pages_alloc(sizes[k]);
        CHECK(p != NULL);
        if (!p) continue;
        size_t align = sizes[k] >= 2 * MB ? 2 * MB : 4096;
        CHECK((uintptr_t)p % align == 0);
        memset(p, 0xa5, sizes[k]); /* every byte asked for is writable (ASan: and no more is used) */
        CHECK(p[0] == 0xa5 && p[sizes[k] - 1] == 0xa5);
        free(p);
    }
    void *none = huge_pages_alloc(0); /* one byte at least */
    CHECK(none != NULL && (uintptr_t)none % 4096 == 0);
    free(none);
    /* an array of 8 whole 2 MB pages, written: where the kernel grants huge pages on request and
     * has free 2 MB blocks to spare it backs it with them (a mutant without the advice gets 0 kB
     * here); the guard is read just before, as huge_pages_alloc reads it */
    size_t bytes = 16 * MB;
    long spare = free_huge_blocks_now();
    unsigned char *big = huge_pages_alloc(bytes);
    CHECK(big != NULL);
    if (big) {
        memset(big, 1, bytes);
        long kb = huge_kb_at(big);
        int expect = huge_pages_on_request() && spare >= 2 * 8 + HUGE_PAGES_SPARE;
        printf("16 MB written: AnonHugePages %ld kB in its mapping (huge pages on request: %s, free 2 MB blocks %ld)\n",
               kb, huge_pages_on_request() ? "yes" : "no", spare);
        if (expect) CHECK(kb >= 2048);
        free(big);
    }
    CHECK_DONE();
}
