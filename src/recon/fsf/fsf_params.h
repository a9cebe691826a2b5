/* FSF's per-pixel filter: slope range, shear, widths and gather directions (fsf_filter.h's
 * FsfPixel) from the pixel's shadow-ray samples and the guides.
 *
 *   slopes   k = (d_light - d_occ) / d_occ per occluded sample (light metres per receiver
 *            metre; FSF's s = d1/d2 - 1 with d2 measured from the light is 1 / k); the pixel's
 *            range [k_lo, k_hi] is taken over a window, not over its own samples: the filter
 *            reprojects every sample under its footprint, so the range must hold their
 *            occluders too. Windows of radius 2 (5 x 5: FSF section 5's slope smoothing,
 *            which also gives unoccluded pixels their neighbours' slopes), 4, 8 and 16 each
 *            give a width (below) capped so that its taps stay inside the window; the widest
 *            wins, with its window's range. A window without occluded samples allows its full
 *            radius without shear (every sample in it is lit).
 *   shear    the mean slope (k_lo + k_hi) / 2: the primal counterpart of the harmonic mean of
 *            FSF's s_min, s_max (section 3.1), times the receiver metres along the light axis
 *            of one pixel step (eta, light metres per step).
 *   width    sigma_x = sigma_y / (k_hi - k_lo) (FSF eq. 4: s_min s_max / (s_max - s_min) =
 *            1 / (k_hi - k_lo)), divided by mu, in pixel steps, capped at 8 (taps to 2 sigma:
 *            the 32-pixel cap); sigma_y = 2 / Omega_y from our light's band
 *            (fsf_light_sigma_y_m), which narrows as the pixel's samples grow.
 *   axes     the screen direction whose receiver displacement follows light axis u (v): the
 *            least-squares solution of J a = u_t, J the pixel's world Jacobian (from its
 *            neighbours' positions), u_t the axis projected on the receiver (FSF Fig. 5a). */
#ifndef WEDGE_RECON_FSF_PARAMS_H
#define WEDGE_RECON_FSF_PARAMS_H

#include "recon/fsf/fsf_band.h"
#include "recon/fsf/fsf_filter.h"
#include "recon/fsf/fsf_light.h"
#include "recon/fsf/fsf_slope_window.h"
#include "recon/gbuffer.h"
#include "recon/sample_store.h"


/* sigma_y = 2 / Omega_y (metres) for FSF eq. 4, for a uniform light of half extent half_m seen
 * through `samples` samples per pixel. FSF assumes a Gaussian light (sigma_y = L / 2) and cuts
 * its spectrum exp(-sigma_y^2 W^2 / 2) at Omega_y = 2 / sigma_y, where it has fallen to e^-2;
 * the paper's counts are 4-16 samples. Our lights are uniform: the spectrum sin(W L) / (W L)
 * has no band, only the envelope 1 / (W L), so the cut is where the envelope falls to the
 * level the filter may discard, and that level is the noise's: e^-2 at FSF's 16 samples, and
 * a Monte Carlo amplitude falls as 1 / sqrt(n), so e^-2 sqrt(16 / n). Omega_y = e^2 sqrt(n /
 * 16) / L: sigma_y = 0.27 L at 16 samples, halving when they quadruple. With a fixed band the
 * filter's bias (the shear's misplacement of slopes other than the mean, growing with the
 * width) is a floor no sample count lowers (docs/algorithms.md 10, "The width for a uniform
 * light"). */
float fsf_light_sigma_y_m(float half_m, int samples);

typedef struct {
    const GBuffer *g;
    const SampleStore *store;    /* with SAMPLE_FIELD_LIGHT */
    const FsfLight *light;
    const unsigned char *usable; /* pixels to filter */
    float mu;                    /* width divisor (> 0) */
    const FsfSlopeWindows *windows; /* fsf_shadow_windows of this store and these guides' object
                                     * ids (an earlier call's, e.g. the plan's), or NULL: found
                                     * here */
} FsfParamsIn;

/* The slope windows fsf_pixel_params reads (fsf_slope_window.h): they depend on the store's
 * samples and the guides' object ids only, so a plan and a filter that share both can share
 * them. false when out of memory; fsf_slope_windows_free releases them. */
bool fsf_shadow_windows(const GBuffer *g, const SampleStore *st, FsfSlopeWindows *out);

/* px and the AOVs (each width * height; k_lo/k_hi are 0 where no slope is known). false when
 * out of memory. */
bool fsf_pixel_params(const FsfParamsIn *in, FsfPixel *px, float *k_lo, float *k_hi);

#endif
