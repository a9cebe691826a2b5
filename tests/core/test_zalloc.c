/* zalloc: zeroed memory, NULL on a size overflow instead of a short buffer. */
#include <stdint.h>
#include <stdlib.h>

#include "check.h"
#include "core/zalloc.h"

int main(void)
{
    /* large enough to come from mmap (fresh pages), small enough for any machine */
    size_t n = (size_t)3 << 20;
    float *f = zalloc(n, sizeof(float));
    CHECK(f != NULL);
    size_t nonzero = 0;
    for (size_t i = 0; f && i < n; ++i) nonzero += f[i] != 0.0f;
    CHECK(nonzero == 0);
    free(f);
    CHECK(zalloc(SIZE_MAX / 2, 4) == NULL); /* count * size overflows */
    void *z = zalloc(0, 8);                 /* empty buffers are valid and freeable */
    CHECK(z != NULL);
    free(z);
    CHECK_DONE();
}
