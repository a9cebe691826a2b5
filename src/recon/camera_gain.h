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

/* The camera effects whose blur counts (those whose filters are judged). */
typedef struct {
    bool defocus, motion;
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

#endif
