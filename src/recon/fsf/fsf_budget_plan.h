/* FSF under a --spp budget: a reduced pass 1, and the rest of the budget by the Lagrange
 * allocation of recon/sample_rate.h (docs/algorithms.md section 10, "Under a budget").
 *
 * FSF's store keeps pass 1's samples only, so extra samples reach the image through each
 * pixel's own mean (the value its stored samples are scaled to, fsf_match_pixel), which the
 * pixel's filter and its neighbours' read. A pixel whose filter averages the samples of A
 * pixels then has the variance v / (n A) of recon/sample_rate.h when the counts vary slowly
 * over the filter, and the allocation n ~ sqrt(v / A) minimises the frame's summed variance.
 * A is the effective pixel count of FSF's filter at the pixel: 4 pi sigma_1 sigma_2 from its
 * two screen-space widths (fsf_pixel_area_px; what the shear leaves of it,
 * fsf_pixel_area_sheared_px, changed the errors by 1-1.4% either way and cost a plan of 65k
 * pixels 0.1-0.2 s of CPU: not used here); 1 where FSF leaves the pixel to Monte Carlo: a
 * width under FSF_COLLAPSED_SIGMA_PX along either axis (near a contact line the slope range
 * explodes, FSF eq. 4 goes to 0), a mixed pixel (several surfaces: passed through), a pixel
 * the light-share test leaves out (FSF_MIN_LIGHT_SHARE), a defocus range straddling the focal
 * plane (fsf_lens_straddles); at most FSF_TEXTURE_AREA_PX at a texture edge (fsf_texture_area).
 * Where FSF filters defocus, the lens filter blurs the shading
 * filters' output and the areas add (docs/algorithms.md). v is the relative variance of one
 * pass-1 sample over the pixel's 3 x 3 window. Pass 1 takes a fixed share of the budget
 * (FSF_BUDGET_PASS1_SHARE, or _LENS with defocus): it is every pixel's floor. */
#ifndef WEDGE_RECON_FSF_BUDGET_PLAN_H
#define WEDGE_RECON_FSF_BUDGET_PLAN_H

#include <stdbool.h>
#include <stddef.h>

#include "recon/fsf/fsf_filter.h"
#include "recon/fsf/fsf_light.h"
#include "recon/fsf/fsf_scratch.h"
#include "recon/fsf/fsf_slope_window.h"
#include "recon/gbuffer.h"
#include "recon/sample_store.h"

/* Below this width (pixel steps) the first taps weigh at most exp(-2) of the centre. Along
 * either axis, not both: on soft_shadows and thin_occluders at 16 spp the two tests gave the
 * same error within 1.5% (2 seeds), and either is what the AOV fsf.sigma_px shows. */
#define FSF_COLLAPSED_SIGMA_PX 0.5f
/* A pixel's cap, in pass-1 counts: sqrt(F), F the effective footprint of a filtered pixel at
 * the width cap (sigma = 8 px on both axes), 4 pi sigma^2, so sqrt(F) = 2 sqrt(pi) sigma = 28:
 * the allocation's own ratio between a Monte Carlo pixel and one at the cap of equal variance.
 * It keeps a window whose variance is one outlier's (a firefly in pass 1) from taking the
 * frame's budget. (Under the earlier even share per collapsed pixel a cap of 4 lost 8-25%,
 * docs/benchmarks.md.) */
#define FSF_BUDGET_CAP_RATIO (2.0f * 1.7724539f * (float)FSF_RADIUS_CAP_PX / FSF_RADIUS_SIGMAS)
/* FSF's light's share of the scene's power (fsf_light_power_share) below FSF_MIN_LIGHT_SHARE:
 * the shadow filter leaves the pixels another light dominates to Monte Carlo, often most of
 * the frame (c near 1), and a pixel's samples in two stratified sets (pass 1's and pass 2's
 * are drawn apart, docs/sampling.md) are worth fewer than one set of as many: on
 * test_filter_assumptions' two lights, 12 + 4 had 1.78x the error of 16 in one pass. There
 * pass 1 takes the whole budget (fsf_method.c's budget_pass1_share). */

/* Pass 1's share of the budget. The variance model's own optimum, n_1 = budget / (1 - c +
 * c sqrt(F)), would be 0.35 of it at c = 7%, but a filtered pixel's error is not only its
 * variance (the slope windows and the widths come from pass 1's samples too): measured over
 * 0.5 to 0.875 on soft_shadows and thin_occluders at 8, 16 and 32 spp, 0.75 was the best
 * but once, within 2% (docs/benchmarks.md). Pass 1 counts with a balanced rows x cols grid
 * (6 = 2 x 3, 12 = 3 x 4, 24 = 4 x 6) stratify the light better than primes (11, 13). Under
 * the Lagrange allocation again (seeds 1-2): 0.75 best on soft_shadows at 8, 16 and 32 spp (the
 * others 3-62% worse); on thin_occluders 0.5 was 5-11% better at 16 and 32 but 45% worse at 8. */
#define FSF_BUDGET_PASS1_SHARE 0.75f
/* ... and where FSF filters defocus: the lens filter, after the shading filters, filters
 * nearly every pixel from its stored samples (its collapsed share, the straddlers, is 5-8%
 * and holds 15-22% of the error, against 57% on soft_shadows), so pass 1 keeps more. On
 * defocus and combined at 8, 16 and 32 spp, 0.875 was up to 12% better than 0.75, at worst
 * 0.5% worse (combined at 16: 8.6e-4 with 0.75, 8.0e-4 with 0.875, fixed count 8.4e-4). Under
 * the Lagrange allocation 0.75 was 2-7% better on defocus and 2-6% worse on combined. */
#define FSF_BUDGET_PASS1_SHARE_LENS 0.875f
/* ... and where FSF's only shading filter is the indirect light's (no soft shadows): its
 * filter reads nearly every pixel's stored samples, as the lens'. With those pixels keeping pass
 * 1's count (fsf11) 7/8 was 0.77x / 0.79x / 0.73x / 0.92x 0.75's relMSE on indirect.pbrt at 8 /
 * 16 / 32 / 64 spp. Since fsf12 they take extras by the allocation (fsf_method.c's plan), and 13/16
 * did best (indirect.pbrt, 256x256, relMSE at 16 spp seeds 1-3 / 4-6, 32 and 64 spp seeds 1-3):
 * 0.75: 2.58e-4 / 2.56e-4, 1.30e-4, 6.57e-5; 0.8125: 2.21e-4 / 2.25e-4, 1.10e-4, 6.47e-5; 0.875:
 * 2.58e-4 / 2.58e-4, 1.20e-4, 6.77e-5; 0.9375 2.61e-4 and 7.38e-5 at 16 and 64; hotspot_bounce
 * 0.87x / 0.94x 7/8's at 16 / 64 (docs/benchmarks.md, "FSF on indirect light: the transfer
 * weight measured"). At 8 spp both round to 7. */
#define FSF_BUDGET_PASS1_SHARE_BOUNCE 0.8125f

/* Whether a pixel's filter (FsfPixel) has collapsed. */
bool fsf_pixel_collapsed(const FsfPixel *px);
/* The effective pixel count of a pixel's filter (1 / sum of its squared normalised screen
 * weights): 4 pi sigma_1 sigma_2 (recon/sample_rate.h), its two gathers' widths in pixel steps
 * (each step a neighbouring pixel, whatever the axes' directions); 0 where it has collapsed. */
float fsf_pixel_area_px(const FsfPixel *px);

/* Under a shear the taps no longer all weigh every light coordinate: the samples of the
 * neighbour t steps away cover [-L + eta t, L + eta t] seen from the centre, so at a light
 * coordinate z only the run of taps that covers it averages (fsf_density's run). A sample's
 * weight is w(t) / rho(z), and with n samples spread evenly over each neighbour's light the
 * filter's effective count along the axis is 1 / mean_z(sum_run w^2 / (sum_run w)^2) taps
 * (at eta = 0: (sum w)^2 / sum w^2). This is the ratio of that count to the unsheared one,
 * in (0, 1]: near 1 while eta r << L, about (2 L / |eta|) / (2 sqrt(pi) sigma) once a tap
 * moves the light by more than its length. The taps are the filter's own: to reach_sigmas
 * each side (fsf_radius_reach; FsfGrid.reach_sigmas of the filter modelled). */
#define FSF_OVERLAP_NODES 32
float fsf_shear_overlap(float sigma_px, float eta_m, float half_m, float reach_sigmas);
/* fsf_pixel_area_px times both axes' fsf_shear_overlap over the filter's grid g (its half_m,
 * the light's half extents, and its reach), at least 1, also where the filter has collapsed
 * (what the taps that remain average). */
float fsf_pixel_area_sheared_px(const FsfPixel *px, const FsfGrid *g);

/* area_px[i] = min(area_px[i], the soft-shadow filter's fsf_pixel_area_px at pixel i, 0 where
 * it passes the pixel through: mixed, or FSF's light's share below FSF_MIN_LIGHT_SHARE), at
 * the pixels with samples on a surface, from the store's pass-1 samples and the guides as the
 * filter will see them (share: FSF's light's share of the pixel's light, NULL: all; windows:
 * fsf_shadow_windows of st and g, NULL: found here). The filter's parameters are found in
 * scratch (the frame's arrays for g and st, fsf_scratch.h: its usable, px, k_lo and k_hi are
 * overwritten). false when out of memory. */
bool fsf_shadow_area(const GBuffer *g, const SampleStore *st, const FsfLight *light, const float *share, float mu,
                     const FsfSlopeWindows *windows, FsfScratch *scratch, float *area_px);
/* The same for the indirect light's filter (also overwriting scratch's count, y, v and out4).
 * false when out of memory or the store lacks the bounce or indirect field. */
bool fsf_bounce_area(const GBuffer *g, const SampleStore *st, float mu, FsfScratch *scratch, float *area_px);

/* The extra samples of a collapsed pixel (fsf_pixel_collapsed) in its own image. The filter
 * reads pass 1's stored samples only; the extras reach it through each pixel's mean, which
 * fsf_match_pixel scales the stored samples to. A wide, unsheared filter averages those means,
 * but a collapsed one keeps few taps, the box drops the samples its shear moves off the light
 * and 1 / rho reweights the rest, so its value stays about as noisy as pass 1's samples while
 * the plan gave the pixel a Monte Carlo pixel's count. Two estimates of the same pixel: the
 * filter's f, worth the n1 A samples of its effective count (n1 stored samples,
 * A = fsf_pixel_area_sheared_px over the filter's grid), and the pixel's mean m over all its n samples, whose
 * extra = n - n1 the filter has not read; with equal per-sample variance their inverse-variance
 * combination is f + (m - f) extra / (n1 A + extra). value4 (rgb of 4 floats per pixel) holds f, mean4 m;
 * stored: the filter's samples per pixel; g->sums[].hits: all of them. Pixels that are not
 * collapsed, have no extras or were passed through keep value4. */
void fsf_blend_collapsed(const FsfPixel *px, const unsigned char *usable, const int *stored, const GBuffer *g,
                         const FsfGrid *grid, const float *mean4, float *value4);

/* The area (pixels) the plan counts at most for a pixel whose texture needs samples: the
 * shading filters divide the light by the pixel's mean albedo and multiply it back, so the
 * texture's own sampling noise (its antialiasing) stays at the pixel's count whatever the
 * filter's area. On scale_range at 16 spp the wide-filtered ground pixels kept pass 1's 12
 * samples and held FSF above Monte Carlo's error. AAF's and MAAF's plans give such pixels the
 * mixed pixels' count (area 1); here that (0 in the plan: a Monte Carlo pixel) cost wire_screen
 * 8-13% at 16 spp (seeds 100 / 200): its checks' edges took the samples of the slats' contact
 * shadows, while pass 1 and 2 are stratified, so an edge pixel's albedo mean converges faster
 * than the plan's v / n. Measured (relMSE against the base at 16 / 64 spp, two seeds): area 2
 * still +5% at 16 on wire_screen, 4 within 1% of the base there and on moving_shadow, 8 kept
 * 0.62-0.71x on scale_range where 4 kept 0.50-0.60x (docs/benchmarks.md, branch fsf10). */
#define FSF_TEXTURE_AREA_PX 4.0f
/* area_px[i] = min(area_px[i], FSF_TEXTURE_AREA_PX) where pixel i's texture needs samples
 * (gbuffer_texture_needs_samples: its albedo varies inside it or against a 4-neighbour) and
 * no lens filter ALBEDO_VARIES_DEFOCUS_STD_PX wide or more follows (lens_px: the lens filter's
 * parameters per pixel, NULL: none; a lens filter blurs the texture and its noise). */
void fsf_texture_area(const GBuffer *g, const FsfPixel *lens_px, float *area_px);

/* The totals: want_spp[i] (the real counts of the Lagrange allocation, sample_rate_counts with
 * pass 1's count as the floor and FSF_BUDGET_CAP_RATIO times it as the cap), never below
 * spp_now[i]; integers by error diffusion in scan order, within a sample of the room in all
 * (the pipeline scales the extras to the budget exactly). */
void fsf_budget_plan(const float *want_spp, size_t n, const float *spp_now, int *spp_total);

#endif
