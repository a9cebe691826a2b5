/* The blur probe: how many pixels the camera effects (defocus and motion) smear a frame,
 * measured before rendering from a sparse, fixed set of camera samples, so that --filter
 * auto can send those effects to layered reconstruction only where it pays (issue 18,
 * docs/benchmarks.md "The choice per effect"). Deterministic: a fixed grid of pixels and a
 * fixed seed, independent of --seed, --spp and the thread count, so `wedge info` and every
 * MPI rank of `wedge render` measure the same value without communicating. */
#ifndef WEDGE_RECON_BLUR_PROBE_H
#define WEDGE_RECON_BLUR_PROBE_H

#include "recon/gbuffer.h"
#include "render/renderer.h"

enum {
    BLUR_PROBE_GRID = 32,       /* probe pixels per image axis (fewer on a smaller image) */
    BLUR_PROBE_SPP = 4,         /* samples per probe pixel, spread over lens and shutter */
};

typedef struct {
    float median_blur_px;  /* median over the probe samples that hit a surface of the blur
                            * extent max(|motion over the shutter|, circle-of-confusion
                            * diameter), pixels of the renderer's resolution; 0 when none hit */
    int samples_hit;       /* probe samples that hit a surface */
    int samples_unbounded; /* of those, blurs that overflow a float (hits at the lens plane),
                            * counted as FLT_MAX px */
    int samples;           /* probe samples traced */
} BlurProbe;

/* Blur extent of one camera sample, pixels: the longer of the first hit's screen path over
 * the shutter (|motion_px|, the film moves by motion_px from open to close) and the diameter
 * of its circle of confusion (2 |coc slope|: lens coordinates span the unit disk); FLT_MAX
 * when that overflows (a hit at the lens plane). */
float blur_extent_px(const ReconCamera *cam, const SampleRecord *rec);

/* Traces the probe on r's scene and resolution. False only when out of memory. */
bool recon_blur_probe(const Renderer *r, BlurProbe *out);

#endif
