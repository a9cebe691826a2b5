/* The gain probe: before a frame under --filter auto is traced, a sparse grid of its pixels
 * with two independent sets of a few samples each, read by the filter-gain estimate
 * (filter_gain.h) and timed, so that auto can predict whether a shading filter pays on this
 * frame (auto_fallback.h; docs/algorithms.md, "auto's fallback to Monte Carlo").
 *
 * Deterministic: a fixed grid and a fixed seed, independent of --seed and the thread count, and
 * no clock (the cost it reports is rays per sample), so a frame's decision is the same on every
 * run and every MPI rank, and the image with it. */
#ifndef WEDGE_RECON_GAIN_PROBE_H
#define WEDGE_RECON_GAIN_PROBE_H

#include "recon/filter_gain.h"
#include "recon/select.h"
#include "render/renderer.h"

enum {
    GAIN_PROBE_GRID = 32,   /* probe pixels per image axis at most ... */
    GAIN_PROBE_STRIDE = 4,  /* ... and at most one pixel in this many per axis (a small image) */
    GAIN_PROBE_SET_SPP = 4, /* samples per pixel in each of the two sets */
};

typedef struct {
    FilterGainTotals totals;
    double rays_per_sample; /* rays traced per sample (primary, shadow, indirect, BSDF): the
                             * frame's Monte Carlo cost in rays */
    int samples;            /* samples traced */
    int samples_nonfinite;  /* of those, samples with a non-finite value (radiance, light or
                             * albedo), left out of the totals */
} GainProbe;

/* Traces the probe on r's scene and resolution (one thread, the renderer's sampler kind).
 * split_direct, split_indirect: whether the frame's filters take that light of a mixed
 * pixel's first surface (recon_choice_splits_pixels): the probe then splits its pixels as the
 * G-buffer will, and such a pixel's samples off its first surface keep their light. camera:
 * the blur whose footprint each pixel's variance is divided by in the totals' camera sums (the
 * harmonic mean of its samples' footprints; with camera.sharpest_lens every sample blurred by
 * the pixel's sharpest circle of confusion, camera_pixel_footprint_sharpest_lens). Samples with
 * a non-finite value are skipped and counted; a set left with fewer than two samples drops its
 * pixel. False only when out of memory. */
bool recon_gain_probe(const Renderer *r, bool split_direct, bool split_indirect, CameraBlurKinds camera, GainProbe *out);

/* The blur the probe measures for choice c's camera filters: recon_select_fallback_blur's, and
 * sharpest_lens when the defocus filter is MAAF's (its width from the pixel's sharpest slope,
 * camera_gain.h). */
CameraBlurKinds recon_gain_probe_blur(const ReconChoice *c);

/* auto's fallback judged on r's frame and applied to c (recon_select_fallback): the probe is
 * traced when auto chose a shading filter the fallback may take back
 * (recon_select_wants_fallback), unless WEDGE_AUTO_FALLBACK=0 (tests of the filters' pipeline
 * on tiny frames, measurements of what the fallback changes). spp: the frame's samples per
 * pixel. `wedge render` (the pipeline) and `wedge info` both call it, so they agree. False
 * only when out of memory. */
bool recon_gain_probe_judge(const Renderer *r, int spp, ReconChoice *c);

#endif
