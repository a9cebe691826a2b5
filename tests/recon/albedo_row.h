/* A row of pixels on one flat surface whose albedo varies along x, seen through pass 1's
 * stratified samples (PASS1_PER_PX per pixel along x, at the strata's centres, as a 3 x 3
 * pass 1 sees a vertical edge): the guides the texture-edge rules read
 * (gbuffer_texture_needs_samples), for test_texture_edge_samples and test_fsf_texture_plan. */
#ifndef WEDGE_TESTS_RECON_ALBEDO_ROW_H
#define WEDGE_TESTS_RECON_ALBEDO_ROW_H

#include "recon/gbuffer.h"

enum { ROW_PX = 8, PASS1_PER_PX = 3 };

static inline SampleRecord surface_at(float x, float albedo)
{
    SampleRecord r = {0};
    r.hit = true;
    r.p_world = v3(x, 0.0f, 2.0f);
    r.n_shading = v3(0.0f, 0.0f, -1.0f);
    r.depth_cam = 2.0f;
    r.object_id = 3;
    r.albedo = v3(albedo, albedo, albedo);
    return r;
}

/* Feeds the row's pass 1: albedo(x, param) at the strata centres of each pixel; false when
 * out of memory. */
static inline bool row_gbuffer(GBuffer *g, float (*albedo)(float x, float param), float param)
{
    ReconCamera cam = {0.0f, 1.0f, 0.001f};
    if (!gbuffer_init(g, ROW_PX, 1, cam)) return false;
    for (int px = 0; px < ROW_PX; ++px) {
        for (int k = 0; k < PASS1_PER_PX; ++k) {
            float x = (float)px + ((float)k + 0.5f) / (float)PASS1_PER_PX;
            SampleRecord r = surface_at(x, albedo(x, param));
            gbuffer_add(g, px, 0, &r);
            g->frame.spp[px] += 1.0f;
        }
    }
    gbuffer_resolve_guides(g);
    return true;
}

#endif
