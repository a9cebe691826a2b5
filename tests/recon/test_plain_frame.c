/* A frame no filter reads (--filter none) holds the frame's sums alone: the guides' per-pixel
 * arrays (GBufferSums, hit, mixed, positions, normals, ...: 150-odd bytes a pixel, 315 MB at
 * 1920x1080) are never allocated, while a filtered frame of the same scene has them. Every
 * pixel still gets its samples, and the image is the frame's plain mean. Checked to fail: with
 * render_plain back on gbuffer_init the first group of checks fails. */
#include <math.h>
#include <stdlib.h>

#include "../check.h"
#include "recon/pipeline.h"
#include "recon_test_util.h"

enum { SPP = 4 };

static void check_plain(const ReconPipeline *p, void *ctx)
{
    (void)ctx;
    const GBuffer *g = recon_pipeline_gbuffer(p);
    CHECK(g->sums == NULL && g->hit == NULL && g->mixed == NULL && g->pos4 == NULL && g->nrm4 == NULL &&
          g->pixel_world == NULL && g->lobe4 == NULL);
    const Frame *f = &g->frame;
    const ReconResult *res = recon_pipeline_result(p);
    int short_px = 0, off_mean = 0;
    for (int i = 0; i < f->width * f->height; ++i) {
        if (f->spp[i] != (float)SPP) ++short_px;
        for (int c = 0; c < 3; ++c) {
            float mean = f->color[3 * i + c] / f->spp[i];
            if (fabsf(res->rgb[3 * i + c] - mean) > 1e-6f * (1.0f + fabsf(mean))) ++off_mean;
        }
    }
    CHECK(short_px == 0);
    CHECK(off_mean == 0);
}

static void check_filtered(const ReconPipeline *p, void *ctx)
{
    (void)ctx;
    const GBuffer *g = recon_pipeline_gbuffer(p);
    CHECK(g->sums != NULL && g->hit != NULL && g->pos4 != NULL && g->nrm4 != NULL);
}

int main(void)
{
    ReconOptions plain = {.filter = "none", .spp = SPP};
    free(recon_test_render_pipeline(SHADOW_SCENE, 1, &plain, check_plain, NULL));
    ReconOptions filtered = {.filter = "aaf", .spp = 0};
    free(recon_test_render_pipeline(SHADOW_SCENE, 1, &filtered, check_filtered, NULL));
    CHECK_DONE();
}
