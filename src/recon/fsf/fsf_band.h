/* FSF's band per source, at the pixel's sample count (docs/algorithms.md section 10, "The
 * width for a uniform light" and "The band of the lens and of the v-plane").
 *
 * FSF eq. 4 takes sigma_x = sigma_y / (k_hi - k_lo) with sigma_y = 2 / Omega_y, Omega_y where the
 * source's spectrum falls to the level the filter may discard. The paper fixes that level at
 * e^-2 for its 4-16 samples; a Monte Carlo amplitude falls as 1 / sqrt(n), so at n samples the
 * components weaker than e^-2 sqrt(16 / n) are below the noise and the rest must be kept
 * (fsf_band_threshold). Each source's spectrum envelope meets that threshold at its own Omega:
 *
 *   light  a uniform box of half extent L: envelope 1 / (W L)            (fsf_params.h)
 *   lens   the unit disk: 2 J1(W) / W, envelope 2 sqrt(2 / pi) W^-3/2    (fsf_lens_sigma_u)
 *   v      the cosine transfer (1 + |v|^2)^-2: spectrum W K1(W)           (fsf_bounce_sigma_v) */
#ifndef WEDGE_RECON_FSF_BAND_H
#define WEDGE_RECON_FSF_BAND_H

/* the paper's sample count, at which the threshold is its e^-2 */
#define FSF_BAND_REF_SPP 16

/* e^-2 sqrt(16 / n): the spectrum level below which the filter may cut (n < 1 counts as 1). */
float fsf_band_threshold(int samples);

/* sigma_u = 2 / Omega_u in unit-lens coordinates for the unit disk: 2 sqrt(2/pi) W^-3/2 =
 * threshold at W = (2 sqrt(2 / pi) e^2)^(2/3) (n / 16)^(1/3) = 5.18 (n / 16)^(1/3), so sigma_u =
 * 0.386 at 16 samples (the paper's Gaussian lens, sigma = A / 2: 0.5), falling as n^-1/3. */
float fsf_lens_sigma_u(int samples);

/* sigma_v = 2 / Omega_v in v units: Omega_v solves W K1(W) = threshold (the 2D spectrum of the
 * cosine transfer on the v-plane, 1 at W = 0); 2.87 at 16 samples (Mehta 2013's Omega_v_max
 * 2.8 is its e^-2 point: W K1(W) = 0.143 there), 3.27 at 32, 3.66 at 64. */
float fsf_bounce_sigma_v(int samples);

#endif
