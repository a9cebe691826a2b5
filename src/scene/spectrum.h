/* Spectra as the scene file gives them (sampled pairs, blackbody temperatures, named
 * spectra) reduced to linear Rec.709 rgb, the only colour representation wedge renders.
 *
 * Conversion: XYZ = integral of s(lambda) times the CIE 1931 2-degree matching functions
 * (analytic multi-lobe fit of Wyman, Sloan and Shirley 2013, JCGT 2(2), eq. 2), then the
 * standard XYZ -> linear sRGB matrix, then divided channel by channel by the rgb of the
 * constant spectrum 1 (a von Kries white balance in rgb), so that a constant spectrum c
 * gives exactly (c, c, c). Negative channels (out-of-gamut spectra) are clamped to 0. */
#ifndef WEDGE_SCENE_SPECTRUM_H
#define WEDGE_SCENE_SPECTRUM_H

#include <stdbool.h>

/* Piecewise-linear spectrum from n (lambda_nm, value) pairs sorted by lambda (zero outside
 * their range, like pbrt-v4's PiecewiseLinearSpectrum). n == 1 value (count 1) is a
 * constant spectrum. Returns false when the count is odd (> 1) or lambdas are unsorted. */
bool spectrum_samples_to_rgb(const float *values, int count, float rgb[3]);

/* The same for an emission spectrum: no white balance (sRGB white is D65, as in pbrt-v4's
 * RGB film), a constant spectrum is illuminant E. */
bool spectrum_samples_to_rgb_illuminant(const float *values, int count, float rgb[3]);

/* Planck's law at temperature_k, normalised so the spectrum's peak (Wien's wavelength) is 1,
 * as pbrt-v4's BlackbodySpectrum. Non-positive temperatures give black. */
void spectrum_blackbody_rgb(float temperature_k, float rgb[3]);

/* A named pbrt-v4 spectrum ("metal-Cu-eta", "glass-BK7", "stdillum-D65", ...) as rgb
 * constants derived as documented in spectrum.c. Returns false for unknown names. */
bool spectrum_named_rgb(const char *name, float rgb[3]);

/* The rgb used in place of an unknown named spectrum (with a warning by the parser):
 * a plausible value for the kind the name suggests ("-eta" -> 1.5, "-k" -> 0, else 1). */
void spectrum_unknown_substitute(const char *name, float rgb[3]);

/* Photometric luminance Y of linear Rec.709 rgb (the middle row of rgb -> XYZ). */
float rgb_luminance(const float rgb[3]);

#endif
