/* fsf_slope_windows against a brute-force oracle: per pixel and level, the min and max of the
 * stored slopes over the square window, counting a pixel (x', q) for the centre (x, y) when
 * it is on the object of (x, q) and (x, q) is on the centre's (a row, then a column, on the
 * centre's object). Random slopes with samples missing (NaN) and pixels without any, random
 * object patches, a frame that is not square; with and without object ids. min and max are
 * exact, so the results must be equal, not close. Then fsf_slope_windows_update after some
 * object ids change: equal to the windows found anew. */
#include "check.h"
#include "recon/fsf/fsf_slope_window.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

enum { W = 41, H = 29, CAP = 3 };

static float slope_of(const void *ctx, size_t slot) { return ((const float *)ctx)[slot]; }

static uint32_t rng(uint32_t *s)
{
    *s = *s * 1664525u + 1013904223u;
    return *s >> 8;
}

/* the oracle's range of pixel (x, y) at radius r */
static void brute(const SampleStore *st, const float *slopes, const float *obj, int x, int y, int r, float *lo,
                  float *hi)
{
    *lo = INFINITY, *hi = -INFINITY;
    size_t c = (size_t)y * W + (size_t)x;
    for (int q = y - r; q <= y + r; ++q) {
        if (q < 0 || q >= H) continue;
        size_t mid = (size_t)q * W + (size_t)x; /* the column step's pixel */
        if (obj && obj[mid] != obj[c]) continue;
        for (int p = x - r; p <= x + r; ++p) {
            if (p < 0 || p >= W) continue;
            size_t k = (size_t)q * W + (size_t)p;
            if (obj && obj[k] != obj[mid]) continue;
            for (int s = 0; s < sample_store_count(st, k); ++s) {
                float v = slopes[k * CAP + (size_t)s];
                if (isnan(v)) continue;
                *lo = fminf(*lo, v), *hi = fmaxf(*hi, v);
            }
        }
    }
}

int main(void)
{
    SampleStore *st = NULL;
    Diag d = {0};
    CHECK(sample_store_create(SAMPLE_FIELD_DEPTH, W, H, CAP, SIZE_MAX, &st, &d));
    if (!st) return 1;
    float *slopes = malloc(sizeof(float) * W * H * CAP), *obj = malloc(sizeof(float) * W * H);
    uint32_t s = 17;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            size_t i = (size_t)y * W + (size_t)x;
            obj[i] = (float)((x / 7 + (y / 5) * 3 + (rng(&s) % 9 == 0)) % 4); /* patches, some stray pixels */
            int n = (int)(rng(&s) % (CAP + 1)); /* 0 .. CAP samples */
            for (int k = 0; k < n; ++k) {
                SampleRecord r = {0};
                r.hit = true;
                sample_store_add(st, x, y, &r);
                float v = (float)(rng(&s) % 20001) * 1e-3f - 10.0f;
                slopes[i * CAP + (size_t)k] = rng(&s) % 7 == 0 ? NAN : v;
            }
        }
    for (int with_obj = 0; with_obj < 2; ++with_obj) {
        const float *o = with_obj ? obj : NULL;
        FsfSlopeWindows w;
        CHECK(fsf_slope_windows(st, W, H, slope_of, slopes, o, &w));
        long mismatches = 0, empty = 0;
        for (int l = 0; l < FSF_LEVELS; ++l)
            for (int y = 0; y < H; ++y)
                for (int x = 0; x < W; ++x) {
                    float lo, hi;
                    brute(st, slopes, o, x, y, FSF_LEVEL_RADIUS_PX[l], &lo, &hi);
                    size_t i = (size_t)y * W + (size_t)x;
                    mismatches += w.lo[l][i] != lo || w.hi[l][i] != hi;
                    empty += lo > hi;
                }
        printf("objects %s: %ld of %d ranges differ from the brute force (%ld empty windows)\n", with_obj ? "on" : "off",
               mismatches, FSF_LEVELS * W * H, empty);
        CHECK(mismatches == 0);
        CHECK(empty > 0 || !with_obj); /* the oracle's empty case is exercised (pixels without slopes) */
        if (with_obj) { /* some object ids change in rows 9 .. 12 (pass 2's first hits): updated,
                         * the windows must equal those found anew, bit for bit */
            float *obj2 = malloc(sizeof(float) * W * H);
            memcpy(obj2, obj, sizeof(float) * W * H);
            for (int y = 9; y <= 12; ++y)
                for (int x = y; x < W; x += 6) obj2[(size_t)y * W + (size_t)x] = (float)(x % 3 == 0 ? -1 : 5);
            FsfSlopeWindows fresh;
            CHECK(fsf_slope_windows(st, W, H, slope_of, slopes, obj2, &fresh));
            fsf_slope_windows_update(&w, W, H, obj2, 9, 12);
            long differ = 0, moved = 0;
            for (int l = 0; l < FSF_LEVELS; ++l)
                for (size_t i = 0; i < (size_t)W * H; ++i) {
                    differ += memcmp(&w.lo[l][i], &fresh.lo[l][i], sizeof(float)) != 0 ||
                              memcmp(&w.hi[l][i], &fresh.hi[l][i], sizeof(float)) != 0;
                    float lo, hi;
                    brute(st, slopes, obj, (int)(i % W), (int)(i / W), FSF_LEVEL_RADIUS_PX[l], &lo, &hi);
                    moved += fresh.lo[l][i] != lo || fresh.hi[l][i] != hi;
                }
            printf("object ids changed in rows 9-12: %ld ranges moved, %ld differ after the update\n", moved, differ);
            CHECK(differ == 0);
            CHECK(moved > 0); /* the change reaches the windows */
            fsf_slope_windows_free(&fresh);
            free(obj2);
        }
        fsf_slope_windows_free(&w);
    }
    free(slopes), free(obj);
    sample_store_destroy(st);
    return check_failures ? 1 : 0;
}
