/* zalloc: zeroed memory, already backed by written pages, NULL on a size overflow instead of
 * a short buffer. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

#include "check.h"
#include "core/zalloc.h"

static long minor_faults(void)
{
    struct rusage r;
    getrusage(RUSAGE_SELF, &r);
    return r.ru_minflt;
}

int main(void)
{
    /* large enough to come from mmap (fresh pages), small enough for any machine */
    size_t n = (size_t)3 << 20;
    float *f = zalloc(n, sizeof(float));
    CHECK(f != NULL);
    /* pre-faulted: writing every page (sum += x reads, then writes) takes almost no page
     * faults; with plain calloc it takes one per 4 KB page (3072 here), or more. The bound
     * leaves room for AddressSanitizer's shadow memory (a byte per 8, faulted on first
     * check: 384 pages here; 0 faults without it). */
    long pages = (long)(n * sizeof(float) / 4096);
    long before = minor_faults();
    for (size_t i = 0; f && i < n; i += 1024) f[i] += 0.0f;
    long faults = minor_faults() - before;
    fprintf(stderr, "%ld minor faults writing %ld pages\n", faults, pages);
    CHECK(faults < pages / 4);
    size_t nonzero = 0;
    for (size_t i = 0; f && i < n; ++i) nonzero += f[i] != 0.0f;
    CHECK(nonzero == 0);
    free(f);
    /* a block reused from the heap (written before) comes back zeroed too */
    for (int round = 0; round < 4; ++round) {
        size_t m = 1000 + 37 * (size_t)round;
        unsigned char *junk = malloc(m);
        CHECK(junk != NULL);
        if (junk) memset(junk, 0xab, m);
        free(junk);
        unsigned char *z = zalloc(m, 1);
        CHECK(z != NULL);
        size_t bad = 0;
        for (size_t i = 0; z && i < m; ++i) bad += z[i] != 0;
        CHECK(bad == 0);
        free(z);
    }
    CHECK(zalloc(SIZE_MAX / 2, 4) == NULL); /* count * size overflows */
    void *z = zalloc(0, 8);                 /* empty buffers are valid and freeable */
    CHECK(z != NULL);
    free(z);
    CHECK_DONE();
}
