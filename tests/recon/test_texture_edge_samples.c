/* Which pixels the adaptive plans give the mixed pixels' count for a texture edge
 * (gbuffer_texture_needs_samples, gbuffer.h), against the pixels an albedo step really
 * crosses. A row of pixels sees a step (albedo 0.8 left of x_edge, 0.2 right of it) through
 * pass 1's stratified samples (3 per pixel along x, at the strata's centres, as a 3 x 3 pass 1
 * sees a vertical edge); the step is swept across a pixel in steps of 1/60. The pixel that
 * holds the step must always be marked, even where all its samples fall on one side (a
 * step in the outer sixth of a pixel); pixels two or more away never are, nor the neighbours
 * of a pixel whose own samples saw the step. */
#include <stdlib.h>

#include "check.h"
#include "albedo_row.h"

static float step_albedo(float x, float x_edge) { return x < x_edge ? 0.8f : 0.2f; }

/* a smooth texture: the albedo changes by 5% of itself per pixel */
static float ramp_albedo(float x, float unused)
{
    (void)unused;
    return 0.3f * powf(1.05f, x);
}

static void test_step_swept_across_a_pixel(void)
{
    int missed = 0, far_marked = 0, beside_seen = 0, tried = 0;
    for (int j = 1; j < 60; ++j) {
        float x_edge = 3.0f + (float)j / 60.0f; /* inside pixel 3, never on a border */
        GBuffer g;
        CHECK(row_gbuffer(&g, step_albedo, x_edge));
        if (!g.sums) continue;
        ++tried;
        if (!gbuffer_texture_needs_samples(&g, 3, 0.0f)) ++missed;
        for (int px = 0; px < ROW_PX; ++px)
            if (abs(px - 3) >= 2 && gbuffer_texture_needs_samples(&g, (size_t)px, 0.0f)) ++far_marked;
        /* where pixel 3's own samples straddle the step, it alone holds it: no neighbour marked */
        if (g.albedo_varies[3] &&
            (gbuffer_texture_needs_samples(&g, 2, 0.0f) || gbuffer_texture_needs_samples(&g, 4, 0.0f)))
            ++beside_seen;
        /* a lens filter a pixel wide or more averages the edge instead (unchanged) */
        CHECK(!gbuffer_texture_needs_samples(&g, 3, 1.0f));
        gbuffer_free(&g);
    }
    CHECK(tried == 59);
    /* a step within a sixth of the pixel's border leaves all three samples on one side (a
     * third of the positions: 19 of 59 went unmarked with the within-pixel test alone);
     * pixel 3 must be marked at every one of them */
    if (missed) fprintf(stderr, "pixel holding the step unmarked at %d of %d positions\n", missed, tried);
    CHECK(missed == 0);
    CHECK(far_marked == 0);
    CHECK(beside_seen == 0);
}

static void test_step_on_a_border(void)
{
    /* the step on the border of pixels 3 and 4: both marked (one more than needed), no other */
    GBuffer g;
    CHECK(row_gbuffer(&g, step_albedo, 4.0f));
    if (!g.sums) return;
    for (int px = 0; px < ROW_PX; ++px)
        CHECK(gbuffer_texture_needs_samples(&g, (size_t)px, 0.0f) == (px == 3 || px == 4));
    gbuffer_free(&g);
}

static void test_smooth_texture_unmarked(void)
{
    /* neighbours 5% apart: |a - b| = 0.024 (a + b), below ALBEDO_VARIES_REL_STD (a + b) */
    GBuffer g;
    CHECK(row_gbuffer(&g, ramp_albedo, 0.0f));
    if (!g.sums) return;
    for (int px = 0; px < ROW_PX; ++px) CHECK(!gbuffer_texture_needs_samples(&g, (size_t)px, 0.0f));
    gbuffer_free(&g);
}

static void test_threshold(void)
{
    /* two pixels of one albedo each: marked when |a - b| > ALBEDO_VARIES_REL_STD (a + b), the
     * within-pixel rule over the two pixels' samples taken together */
    const float pairs[][3] = {{0.56f, 0.44f, 1.0f}, {0.54f, 0.46f, 0.0f}, {0.105f, 0.095f, 0.0f}, {0.12f, 0.08f, 1.0f}};
    for (size_t k = 0; k < sizeof pairs / sizeof pairs[0]; ++k) {
        GBuffer g;
        ReconCamera cam = {0.0f, 1.0f, 0.001f};
        CHECK(gbuffer_init(&g, 2, 1, cam));
        if (!g.sums) continue;
        for (int px = 0; px < 2; ++px) {
            SampleRecord r = surface_at((float)px + 0.5f, pairs[k][px]);
            for (int s = 0; s < 4; ++s) {
                gbuffer_add(&g, px, 0, &r);
                g.frame.spp[px] += 1.0f;
            }
        }
        gbuffer_resolve_guides(&g);
        bool want = pairs[k][2] != 0.0f;
        CHECK(gbuffer_texture_needs_samples(&g, 0, 0.0f) == want);
        CHECK(gbuffer_texture_needs_samples(&g, 1, 0.0f) == want);
        gbuffer_free(&g);
    }
}

int main(void)
{
    test_step_swept_across_a_pixel();
    test_step_on_a_border();
    test_smooth_texture_unmarked();
    test_threshold();
    return check_failures ? 1 : 0;
}
