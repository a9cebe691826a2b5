/* Triangle corners welded into vertices (see vertex_weld.h). */
#include "recon/vertex_weld.h"

#include <stdlib.h>
#include <string.h>

typedef struct {
    double c[3];
    int slot; /* 3 t + k */
} CornerKey;

static int cmp_corner(const void *a, const void *b)
{
    int c = memcmp(((const CornerKey *)a)->c, ((const CornerKey *)b)->c, sizeof(double[3]));
    return c ? c : ((const CornerKey *)a)->slot - ((const CornerKey *)b)->slot;
}

int vertex_weld(int count, const double (*tri)[3][3], double (*pos)[3], int *vert)
{
    size_t slots = 3 * (size_t)(count > 0 ? count : 0);
    CornerKey *key = malloc((slots ? slots : 1) * sizeof *key);
    if (!key) return -1;
    for (size_t q = 0; q < slots; ++q) memcpy(key[q].c, tri[q / 3][q % 3], sizeof key[q].c), key[q].slot = (int)q;
    qsort(key, slots, sizeof *key, cmp_corner);
    int verts = 0;
    for (size_t q = 0; q < slots; ++q) {
        if (q == 0 || memcmp(key[q].c, key[q - 1].c, sizeof key[q].c) != 0) memcpy(pos[verts++], key[q].c, sizeof key[q].c);
        vert[key[q].slot] = verts - 1;
    }
    free(key);
    return verts;
}
