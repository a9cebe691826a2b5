/* Zeroed, pre-faulted buffers (see zalloc.h). */
#include "core/zalloc.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

void *zalloc(size_t count, size_t size)
{
    if (size != 0 && count > SIZE_MAX / size) return NULL;
    size_t bytes = count * size;
    void *p = malloc(bytes ? bytes : 1);
    if (p) memset(p, 0, bytes);
    return p;
}
