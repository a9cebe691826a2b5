/* The camera filters' footprint: how many independent samples a defocus or motion filter
 * (MAAF's or AAF's lens, FSF's lens, LR) can average for one sample, from the blur that
 * sample's first hit has (its circle of confusion and its path over the shutter), read by
 * auto's fallback to judge the camera filters (auto_fallback.h; docs/algorithms.md, "auto's
 * fallback to Monte Carlo", the camera effects).
 *
 * A sample's radiance is spread over the pixels its blur reaches: the Minkowski sum of the
 * pixel (1 x 1), its circle of confusion (a disk of diameter c pixels) and its motion (a
 * segment of length m pixels). Mixed areas (Steiner's formula for convex sets):
 *
 *     A(c, m) = 1 + pi c^2 / 4 + 2 c + m + m c        (pixels)
 *
 * (the pixel's area, the disk's, the disk swept round the pixel's perimeter 4 x c/2, the
 * pixel swept along the segment, about m x 1, and the disk swept along it, m x c). An ideal
 * camera filter gives every pixel the mean of the samples whose blur reaches it, so it
 * averages about A samples' worth of the pixel's own: its variance falls by A. A real filter
 * reaches part of that (its kernel's tails, the samples it rejects at depth or velocity
 * edges): F = 1 + efficiency (A - 1), at most a cap. */
#ifndef WEDGE_RECON_CAMERA_GAIN_H
#define WEDGE_RECON_CAMERA_GAIN_H

#include <stdbool.h>

#include "recon/gbuffer.h"
#include "render/sample_record.h"

/* The camera effects whose blur counts (those whose filters are judged). sharpest_lens: the
 * defocus filter sets a pixel's width from the sharpest circle of confusion among the pixel's
 * samples (MAAF's lens filter: camera_lens_sharpest_diameter_px). lr_motion_rule: the motion
 * filter is LR's, whose layers keep no motion filter where their speeds disagree: a sample's
 * motion counts only where LR would shear it (probe_motion_rule.h). */
typedef struct {
    bool defocus, motion, sharpest_lens, lr_motion_rule;
} CameraBlurKinds;

/* The area, in pixels, a sample's blur covers: A(c, m) above. c: the circle of confusion's
 * diameter, m: the motion's length, both pixels (>= 0; a non-finite blur counts as 0: nothing
 * to average that can be trusted). */
double camera_blur_area_px(double coc_diameter_px, double motion_px);

/* The real filter's footprint for a blur area A: 1 + efficiency (A - 1), at most cap (and at
 * least 1). */
double camera_footprint(double area_px, double efficiency, double cap);

/* A pixel's footprint from its n samples' (n > 0): their harmonic mean. Each sample's variance
 * falls by its own footprint, so the pixel's by the harmonic mean: a pixel half sharp and half
 * blurred keeps about twice the sharp half's variance, not an average of the two. */
double camera_pixel_footprint(const float *footprints, int n);

/* The blur area of one probe sample as the camera filters of the frame see it: the circle of
 * confusion counts when kinds.defocus, the motion when kinds.motion (1 on a miss). */
double camera_sample_area_px(const ReconCamera *cam, const SampleRecord *rec, CameraBlurKinds kinds);

/* The circle of confusion, diameter in pixels, a lens filter designed from the pixel's sharpest
 * slope averages every one of the pixel's samples over: 2 min |s| over the n samples' signed
 * slopes s (recon_coc_slope_px, px per unit lens coordinate; NaN for a miss, skipped), and 0 when
 * the slopes straddle the focal plane (both signs) or no sample hit. MAAF's filter
 * (maaf_defocus_pixel; Mehta et al. 2014, "Multiple axis-aligned filters", Sec. 6) takes the
 * pixel's slope range and its width from the smallest |slope| in it: a sharp surface in the
 * pixel (a background in focus behind a defocused fence) narrows the filter for the blurred
 * one too (docs/algorithms.md, "auto's fallback to Monte Carlo", the camera effects). */
double camera_lens_sharpest_diameter_px(const float *coc_slope_px, int n);

/* A pixel's footprint under such a filter from its n samples' signed slopes (as above) and
 * motion lengths (px; 0 for a miss or without motion): the harmonic mean (camera_pixel_footprint)
 * of camera_footprint(A(c, m_k)), c the pixel's sharpest diameter above. The width is the
 * pixel's, so every sample of it, a miss too, is averaged over c. */
double camera_pixel_footprint_sharpest_lens(const float *coc_slope_px, const float *motion_px, int n, double efficiency,
                                            double cap);

#endif
