/* The frame's planes (render/frame.h): frame_init_planes holds the colour and the counts
 * always, the parts and the guides only when asked (the others NULL), every held sum zero;
 * frame_clear zeroes what it holds; frame_free leaves an empty frame. */
#include <math.h>

#include "check.h"
#include "render/frame.h"

static bool all_zero(const float *a, size_t n)
{
    for (size_t i = 0; i < n; ++i)
        if (a[i] != 0.0f || signbit(a[i])) return false;
    return true;
}

static void test_planes(void)
{
    enum { W = 33, H = 7 };
    const size_t n = (size_t)W * H;
    const unsigned asked[] = {0, FRAME_PLANES_PARTS, FRAME_PLANES_GUIDES, FRAME_PLANES_ALL};
    for (size_t k = 0; k < sizeof asked / sizeof asked[0]; ++k) {
        Frame f;
        CHECK(frame_init_planes(&f, W, H, asked[k]));
        CHECK(frame_planes(&f) == asked[k]);
        bool parts = asked[k] & FRAME_PLANES_PARTS, guides = asked[k] & FRAME_PLANES_GUIDES;
        CHECK(f.color && f.spp && f.width == W && f.height == H);
        CHECK(!!f.direct == parts && !!f.indirect == parts && !!f.emission == parts);
        CHECK(!!f.albedo == guides && !!f.normal == guides && !!f.depth == guides && !!f.hits == guides);
        float *const sums3[] = {f.color, f.direct, f.indirect, f.emission, f.albedo, f.normal};
        float *const sums1[] = {f.depth, f.hits, f.spp};
        for (int s = 0; s < 6; ++s)
            if (sums3[s]) {
                CHECK(all_zero(sums3[s], 3 * n));
                for (size_t i = 0; i < 3 * n; ++i) sums3[s][i] = (float)(i + 1);
            }
        for (int s = 0; s < 3; ++s)
            if (sums1[s]) {
                CHECK(all_zero(sums1[s], n));
                for (size_t i = 0; i < n; ++i) sums1[s][i] = -(float)(i + 1);
            }
        f.guides_skipped = true;
        frame_clear(&f);
        CHECK(!f.guides_skipped && frame_planes(&f) == asked[k]);
        for (int s = 0; s < 6; ++s)
            if (sums3[s]) CHECK(all_zero(sums3[s], 3 * n));
        for (int s = 0; s < 3; ++s)
            if (sums1[s]) CHECK(all_zero(sums1[s], n));
        frame_free(&f);
        CHECK(!f.color && !f.spp && !f.direct && !f.albedo && f.width == 0);
    }
    /* frame_init is every plane */
    Frame all;
    CHECK(frame_init(&all, 4, 3) && frame_planes(&all) == FRAME_PLANES_ALL);
    frame_free(&all);
    Frame bad;
    CHECK(!frame_init_planes(&bad, 0, 3, 0) && !bad.color);
}

int main(void)
{
    test_planes();
    CHECK_DONE();
}
