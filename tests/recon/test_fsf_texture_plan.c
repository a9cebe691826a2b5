/* FSF's plan for textured pixels (fsf_texture_area, fsf_budget_plan.h).
 *
 *   texture   a row of pixels sees an albedo step (0.8 left of it, 0.2 right) through pass 1's
 *             three samples per pixel; the step is swept across pixel 3. Pixel 3's area (50)
 *             must become FSF_TEXTURE_AREA_PX at every position (one of 2 stays 2), even where its samples all
 *             fall on one side; pixels two or more away keep theirs, and so does every pixel
 *             when a lens filter 1.5 px wide follows (it averages the edge); a lens filter that
 *             left the pixel out (width 0) does not
 *   plan      scale_range (its 0.5 m checks) at 64x64 under --spp 16: among the pixels whose
 *             shadow filter is wide (sigma >= 2 px), those with a texture edge get at least 1.1
 *             times the mean count of the others (measured: 14.4 against 12.0; before the rule
 *             12.0 against 12.0, pass 1's count for both) */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../check.h"
#include "albedo_row.h"
#include "recon/fsf/fsf_budget_plan.h"
#include "recon/pipeline.h"
#include "recon_test_util.h"

enum { PLAN_RES = 64 };

/* the albedo: 0.8 left of x_edge, 0.2 right of it */
static float step_albedo(float x, float x_edge) { return x < x_edge ? 0.8f : 0.2f; }

static void texture_area(void)
{
    int kept_at_edge = 0, far_zeroed = 0, lens_zeroed = 0, left_out_kept = 0, tried = 0;
    for (int j = 1; j < 60; ++j) {
        GBuffer g;
        CHECK(row_gbuffer(&g, step_albedo, 3.0f + (float)j / 60.0f));
        if (!g.sums) continue;
        ++tried;
        float area[ROW_PX];
        for (int px = 0; px < ROW_PX; ++px) area[px] = 50.0f;
        fsf_texture_area(&g, NULL, area);
        kept_at_edge += area[3] != FSF_TEXTURE_AREA_PX;
        for (int px = 0; px < ROW_PX; ++px) far_zeroed += abs(px - 3) >= 2 && area[px] != 50.0f;
        /* a narrower filter's area is already below the cap: kept */
        area[3] = 2.0f;
        fsf_texture_area(&g, NULL, area);
        kept_at_edge += area[3] != 2.0f;
        /* a lens filter 1.5 px wide averages the edge and its noise: nothing changes */
        FsfPixel lens[ROW_PX];
        for (int px = 0; px < ROW_PX; ++px) lens[px] = fsf_pixel_left_out(), lens[px].sigma_px[0] = lens[px].sigma_px[1] = 1.5f;
        for (int px = 0; px < ROW_PX; ++px) area[px] = 50.0f;
        fsf_texture_area(&g, lens, area);
        for (int px = 0; px < ROW_PX; ++px) lens_zeroed += area[px] != 50.0f;
        /* ... but one that left the pixel out (width 0) does not */
        lens[3] = fsf_pixel_left_out();
        area[3] = 50.0f;
        fsf_texture_area(&g, lens, area);
        left_out_kept += area[3] != FSF_TEXTURE_AREA_PX;
        gbuffer_free(&g);
    }
    CHECK(tried == 59);
    if (kept_at_edge || far_zeroed || lens_zeroed || left_out_kept)
        fprintf(stderr, "edge pixel wrong %d, far changed %d, under a lens changed %d, left out kept %d (of %d)\n",
                kept_at_edge, far_zeroed, lens_zeroed, left_out_kept, tried);
    CHECK(kept_at_edge == 0 && far_zeroed == 0 && lens_zeroed == 0 && left_out_kept == 0);
}

typedef struct {
    long textured, plain;           /* ground pixels with / without a texture edge */
    double textured_spp, plain_spp; /* their samples */
} TextureFrame;

static void count_frame(const ReconPipeline *p, void *ctx)
{
    TextureFrame *f = ctx;
    const GBuffer *g = recon_pipeline_gbuffer(p);
    const float *sigma = recon_test_frame_aov(p, "fsf.sigma_px", PLAN_RES);
    memset(f, 0, sizeof *f);
    for (size_t i = 0; sigma && i < (size_t)g->width * (size_t)g->height; ++i) {
        /* wide filters only (area 4 pi sigma^2 > 50 px, far above the cap): the rule's pixels */
        if (!g->hit[i] || g->mixed[i] || !(sigma[i] >= 2.0f)) continue;
        bool t = gbuffer_texture_needs_samples(g, i, 0.0f);
        if (t) f->textured++, f->textured_spp += g->frame.spp[i];
        else f->plain++, f->plain_spp += g->frame.spp[i];
    }
}

static void plan(void)
{
    char *text = recon_test_bench_scene_at("scale_range", PLAN_RES);
    CHECK(text != NULL);
    if (!text) return;
    TextureFrame f;
    float *img = recon_test_render_spp(text, "fsf", 7, 16, count_frame, &f);
    CHECK(img != NULL);
    double t = f.textured ? f.textured_spp / (double)f.textured : 0.0, o = f.plain ? f.plain_spp / (double)f.plain : 0.0;
    fprintf(stderr, "scale_range %dx%d --spp 16: %ld textured pixels at %.1f spp, %ld others at %.1f\n", PLAN_RES,
            PLAN_RES, f.textured, t, f.plain, o);
    CHECK(f.textured > PLAN_RES * PLAN_RES / 20 && f.plain > PLAN_RES * PLAN_RES / 20);
    CHECK(t >= 1.1 * o);
    free(img);
    free(text);
}

int main(void)
{
    texture_area();
    plan();
    CHECK_DONE();
}
