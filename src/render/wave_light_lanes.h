/* A light's samples at the vertices of one stage of the wave (integrator.c), one lane per
 * path: what the light sampling batches fill, the shadow rays made ahead for them
 * (shadow_rays.h) and the Lambert receivers' estimates the vectorised loops compute. */
#ifndef WEDGE_RENDER_WAVE_LIGHT_LANES_H
#define WEDGE_RENDER_WAVE_LIGHT_LANES_H

#include <stdbool.h>

#include "render/integrator.h"

/* One delta light of LightSet.delta_every at the stage's vertices, one lane per path of the
 * wave (lane j: path j; lanes of dead or unlit paths hold values nothing keeps). A point or
 * spot light's samples (light_sample_point_batch: wi, dist, Li, ok) and shadow rays
 * (point_shadow_rays, ShadowRayAhead's o, dir, len and redo); a distant light's shadow rays
 * (distant_lambert_lanes: o, dir, len). Then every lit path's share: its shadow ray is kept
 * (kept), its unoccluded value f Li |cos| (value) and the ray's answer (occluded). A Lambert
 * receiver's lane is computed by a vectorised loop (point_lambert_lanes,
 * distant_lambert_lanes); a glossy receiver's, or a ray point_shadow_rays leaves to
 * shadow_ray_to (redo), by wave_vertex_rays path by path, whose ray goes to the occlusion
 * batch and whose answer is copied into the lane (Wave.delta_fix_*). */
typedef struct {
    float wi[3][WAVE_SAMPLES], dist[WAVE_SAMPLES], Li[3][WAVE_SAMPLES];
    int ok[WAVE_SAMPLES];
    float err_light; /* the light's LightSample.err_light (light_delta_offset), the same for all */
    /* their shadow rays (ShadowRayAhead); 16-byte aligned, as Embree's stream reads them in
     * place (tracer_occluded_arrays) */
    _Alignas(16) float o[3][WAVE_SAMPLES], dir[3][WAVE_SAMPLES], len[WAVE_SAMPLES];
    int redo[WAVE_SAMPLES];
    /* every lit path's share (above) */
    float value[3][WAVE_SAMPLES];
    int kept[WAVE_SAMPLES];
    bool occluded[WAVE_SAMPLES];
    int kept_count; /* how many lanes the loops kept (none: nothing to trace from the lanes) */
} WaveDeltaSamples;

/* The samples of one static triangle light picked by some of a stage's paths, one lane per
 * path: its receiver (position, geometric normal, offset) and position sample, the sample
 * (light_sample_triangle_batch) and its shadow ray (ShadowRayAhead). A constant sky
 * (light_is_constant_sky) is grouped the same way (sky): its sample is a direction
 * (light_sample_sky_batch: wi, pdf 1 / (4 pi), dist infinite, no p_light; at a Lambert
 * receiver made cosine-weighted about its normal by light_sky_cosine_batch, sky_by_cosine)
 * and its shadow ray leaves the receiver along it (sky_shadow_rays); every other lane is
 * used alike. */
typedef struct {
    int light, count; /* light: the group's light, or for a mesh the first triangle of its run */
    bool sky;
    bool mesh;             /* the triangles of one emitting mesh, lane k's in tri[k] */
    int tri[WAVE_SAMPLES]; /* lane k's light */
    float p[3][WAVE_SAMPLES], ng[3][WAVE_SAMPLES], err[WAVE_SAMPLES], u[2][WAVE_SAMPLES];
    float wi[3][WAVE_SAMPLES], dist[WAVE_SAMPLES], pl[3][WAVE_SAMPLES], pdf[WAVE_SAMPLES];
    int ok[WAVE_SAMPLES];
    float o[3][WAVE_SAMPLES], dir[3][WAVE_SAMPLES], len[WAVE_SAMPLES];
    int redo[WAVE_SAMPLES];
    /* a Lambert receiver's part (lambert_triangle_nee): in, its vertex's n, cos_o, albedo
     * and the pick's pmf; out, whether the shadow ray is sent (send) or guarded (send_guarded)
     * and the unoccluded estimate (light_finish's value, nee_guarded where it counts a
     * guarded event and gives 0). Lanes of glossy receivers hold values nothing reads. */
    float n[3][WAVE_SAMPLES], cos_o[WAVE_SAMPLES], albedo[3][WAVE_SAMPLES], pmf[WAVE_SAMPLES];
    int send[WAVE_SAMPLES], send_guarded[WAVE_SAMPLES];
    float nee[3][WAVE_SAMPLES];
    int nee_guarded[WAVE_SAMPLES];
    /* a Lambert receiver's shadow ray is traced from the lanes (tracer_occluded_arrays):
     * the lane's receiver is Lambert (lambert), its path's time, whether the ray is traced
     * there (traced: a Lambert receiver, the ray computed ahead and sent) and the answer */
    int lambert[WAVE_SAMPLES], traced[WAVE_SAMPLES];
    bool rays_ahead; /* triangle_shadow_rays made the lanes' rays (else none is traced here) */
    float time01[WAVE_SAMPLES];
    bool occluded[WAVE_SAMPLES];
} WaveTriangleSamples;

#endif
