/* Large per-frame arrays in 2 MB pages, guarded (huge_pages.h). */
#include "core/huge_pages.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>

enum { SMALL_PAGE = 4096, HUGE_ORDER = 9 /* 2 MB in 4 KB pages: 2^9 */ };
#define HUGE_PAGE ((size_t)2 << 20)

long huge_pages_free_blocks(const char *text)
{
    long blocks = -1;
    for (const char *line = text; line && *line; line = strchr(line, '\n'), line = line ? line + 1 : NULL) {
        /* "Node 0, zone   Normal   c0 c1 ... c10": the counts of free blocks per order */
        const char *p = strstr(line, "zone");
        const char *end = strchr(line, '\n');
        if (!p || (end && p > end)) continue;
        p += 4;
        while (*p == ' ') ++p;
        while (*p && *p != ' ' && *p != '\n') ++p; /* the zone's name */
        if (blocks < 0) blocks = 0;
        for (int order = 0; order <= 20; ++order) {
            char *next;
            long count = strtol(p, &next, 10);
            if (next == p || (end && next > end)) break;
            if (order >= HUGE_ORDER && count > 0) blocks += count << (order - HUGE_ORDER);
            p = next;
        }
    }
    return blocks;
}

/* free 2 MB blocks now (-1: unknown) */
static long free_huge_blocks_now(void)
{
    FILE *f = fopen("/proc/buddyinfo", "r");
    if (!f) return -1;
    char text[4096];
    size_t len = fread(text, 1, sizeof text - 1, f);
    fclose(f);
    text[len] = '\0';
    return huge_pages_free_blocks(text);
}

/* Advises the whole 2 MB pages inside [p, p + bytes) while the machine has free 2 MB blocks to
 * spare for them (huge_pages.h). A refusal (EINVAL where the kernel has no transparent huge
 * pages) leaves 4 KB pages: nothing to undo. */
static void advise_whole_pages(void *p, size_t bytes)
{
#ifdef MADV_HUGEPAGE
    uintptr_t first = ((uintptr_t)p + HUGE_PAGE - 1) & ~(uintptr_t)(HUGE_PAGE - 1);
    uintptr_t end = ((uintptr_t)p + bytes) & ~(uintptr_t)(HUGE_PAGE - 1);
    size_t whole = end > first ? (end - first) / HUGE_PAGE : 0;
    if (whole > 0 && free_huge_blocks_now() >= 2 * (long)whole + HUGE_PAGES_SPARE)
        (void)madvise((void *)first, whole * HUGE_PAGE, MADV_HUGEPAGE);
#else
    (void)p, (void)bytes;
#endif
}

void *huge_pages_malloc(size_t bytes)
{
    void *p = malloc(bytes ? bytes : 1);
    if (p) advise_whole_pages(p, bytes);
    return p;
}

void *huge_pages_alloc(size_t bytes)
{
    if (bytes == 0) bytes = 1;
    size_t align = bytes >= HUGE_PAGE ? HUGE_PAGE : SMALL_PAGE;
    if (bytes > SIZE_MAX - align) return NULL;
    /* aligned_alloc wants a multiple of the alignment: the rounding is address space only, the
     * tail past `bytes` is never touched */
    void *p = aligned_alloc(align, (bytes + align - 1) / align * align);
    if (p) advise_whole_pages(p, bytes); /* p is 2 MB aligned when bytes >= 2 MB */
    return p;
}
