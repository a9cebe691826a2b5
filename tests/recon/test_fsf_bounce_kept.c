/* The plan's indirect-light parameters kept for the filter (fsf_bounce_kept.h): taken back
 * exactly while the store holds the samples they were found from; refused (nothing written)
 * once a pixel's count differs, for another frame size, or when nothing was kept. */
#include <stdint.h>

#include "check.h"
#include "recon/fsf/fsf_bounce_kept.h"

enum { W = 6, H = 5, SPP = 4 };

int main(void)
{
    size_t n = (size_t)W * H;
    SampleStore *st = NULL;
    Diag d = {0};
    CHECK(sample_store_create(SAMPLE_FIELD_BOUNCE, W, H, SPP, SIZE_MAX, &st, &d));
    if (!st) CHECK_DONE();
    SampleRecord r = {0};
    r.hit = true, r.bounce_count = 1;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            for (int k = 0; k < 1 + (x + y) % 3; ++k) sample_store_add(st, x, y, &r);
    FsfPixel px[W * H], got[W * H];
    float k_lo[W * H], k_hi[W * H], got_lo[W * H], got_hi[W * H];
    for (size_t i = 0; i < n; ++i) {
        px[i] = fsf_pixel_left_out();
        px[i].sigma_px[0] = 0.5f + (float)i, px[i].sigma_px[1] = 2.0f * (float)i, px[i].eta_m[0] = -0.01f * (float)i;
        k_lo[i] = 0.1f * (float)i, k_hi[i] = 1.0f + (float)i;
    }
    FsfBounceKept kept = {0};
    CHECK(!fsf_bounce_kept_take(&kept, st, got, got_lo, got_hi, n)); /* nothing kept */
    fsf_bounce_keep(&kept, st, px, k_lo, k_hi, n);
    memset(got, 0, sizeof got), memset(got_lo, 0, sizeof got_lo), memset(got_hi, 0, sizeof got_hi);
    CHECK(fsf_bounce_kept_take(&kept, st, got, got_lo, got_hi, n));
    CHECK(memcmp(got, px, sizeof px) == 0);
    CHECK(memcmp(got_lo, k_lo, sizeof k_lo) == 0 && memcmp(got_hi, k_hi, sizeof k_hi) == 0);
    CHECK(!fsf_bounce_kept_take(&kept, st, got, got_lo, got_hi, n - 1)); /* another frame */
    /* one more sample in the last pixel: the store is no longer the plan's */
    sample_store_add(st, W - 1, H - 1, &r);
    memset(got, 0, sizeof got);
    CHECK(!fsf_bounce_kept_take(&kept, st, got, got_lo, got_hi, n));
    FsfPixel zero[W * H];
    memset(zero, 0, sizeof zero);
    CHECK(memcmp(got, zero, sizeof got) == 0); /* nothing written */
    fsf_bounce_kept_free(&kept);
    CHECK(!fsf_bounce_kept_take(&kept, st, got, got_lo, got_hi, n));
    sample_store_destroy(st);
    CHECK_DONE();
}
