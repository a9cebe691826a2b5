/* Morton order of points (see morton_order.h). */
#include "recon/morton_order.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>

typedef struct {
    uint32_t key;
    int index;
} Keyed;

/* x's 10 low bits spread to every third bit */
static uint32_t spread10(uint32_t x)
{
    x &= 0x3ff;
    x = (x | (x << 16)) & 0x030000ff;
    x = (x | (x << 8)) & 0x0300f00f;
    x = (x | (x << 4)) & 0x030c30c3;
    return (x | (x << 2)) & 0x09249249;
}

static int cmp_keyed(const void *a, const void *b)
{
    const Keyed *x = a, *y = b;
    if (x->key != y->key) return x->key < y->key ? -1 : 1;
    return x->index - y->index;
}

int *morton_order(int n, const double (*pt)[3])
{
    if (n < 1) return NULL;
    Keyed *k = malloc((size_t)n * sizeof *k);
    int *order = malloc((size_t)n * sizeof *order);
    if (!k || !order) {
        free(k), free(order);
        return NULL;
    }
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a)
            if (isfinite(pt[i][a])) lo[a] = fmin(lo[a], pt[i][a]), hi[a] = fmax(hi[a], pt[i][a]);
    for (int i = 0; i < n; ++i) {
        uint32_t key = 0;
        for (int a = 0; a < 3; ++a) {
            double q = hi[a] > lo[a] ? (pt[i][a] - lo[a]) / (hi[a] - lo[a]) : 0.0;
            key |= spread10(isfinite(q) ? (uint32_t)fmin(fmax(q * 1023.0, 0.0), 1023.0) : 0) << a;
        }
        k[i] = (Keyed){key, i};
    }
    qsort(k, (size_t)n, sizeof *k, cmp_keyed);
    for (int i = 0; i < n; ++i) order[i] = k[i].index;
    free(k);
    return order;
}
