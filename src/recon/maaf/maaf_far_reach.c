/* The far pixels' reach (maaf_far_reach.h). */
#include "recon/maaf/maaf_far_reach.h"

#include <stdlib.h>

void maaf_far_marks(size_t n, const unsigned char *occluder, const unsigned char *albedo_varies,
                    const unsigned char *hit, const int *shadow_rays, unsigned char *marks)
{
    for (size_t j = 0; j < n; ++j) marks[j] = occluder[j] || albedo_varies[j] || (hit[j] && shadow_rays[j] == 0);
}

bool maaf_far_reach(const unsigned char *seen, int width, int height, int cap_px, unsigned char *reach_px)
{
    int far = cap_px + 1; /* any distance beyond the cap counts as this */
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) { /* along the row: reach_px holds the distance for now */
            int d = far;
            for (int k = 0; k < far && k < d; ++k)
                if ((x - k >= 0 && seen[(size_t)y * width + x - k]) || (x + k < width && seen[(size_t)y * width + x + k])) d = k;
            reach_px[(size_t)y * width + x] = (unsigned char)d;
        }
    unsigned char *column = malloc(height > 0 ? (size_t)height : 1);
    if (!column) return false;
    for (int x = 0; x < width; ++x) {
        for (int y = 0; y < height; ++y) column[y] = reach_px[(size_t)y * width + x];
        for (int y = 0; y < height; ++y) {
            int d = far;
            for (int k = 0; k < d; ++k) { /* rows k away: their distance is at least k */
                int a = y - k >= 0 ? column[y - k] : far, b = y + k < height ? column[y + k] : far;
                int m = a < b ? a : b;
                if (m < k) m = k;
                if (m < d) d = m;
            }
            reach_px[(size_t)y * width + x] = (unsigned char)(d > cap_px ? cap_px : d - 1 < 0 ? 0 : d - 1);
        }
    }
    free(column);
    return true;
}
