/* Spectra -> linear Rec.709 rgb. See spectrum.h for the conventions. */
#include "scene/spectrum.h"

#include <math.h>
#include <string.h>

enum { LAMBDA_MIN_NM = 360, LAMBDA_MAX_NM = 830 };

/* Piecewise Gaussian with different widths left and right of the mean. */
static double lobe(double lambda_nm, double mu, double sigma_left, double sigma_right)
{
    double s = lambda_nm < mu ? sigma_left : sigma_right;
    double t = (lambda_nm - mu) / s;
    return exp(-0.5 * t * t);
}

/* CIE 1931 2-degree colour matching functions: the multi-lobe analytic fit of Wyman, Sloan
 * and Shirley 2013 (JCGT 2(2), eq. 2); within a few percent of the tabulated functions,
 * which is well below what an rgb renderer can resolve. */
static void cie_xyz_bar(double lambda_nm, double xyz[3])
{
    xyz[0] = 1.056 * lobe(lambda_nm, 599.8, 37.9, 31.0) + 0.362 * lobe(lambda_nm, 442.0, 16.0, 26.7) -
             0.065 * lobe(lambda_nm, 501.1, 20.4, 26.2);
    xyz[1] = 0.821 * lobe(lambda_nm, 568.8, 46.9, 40.5) + 0.286 * lobe(lambda_nm, 530.9, 16.3, 31.1);
    xyz[2] = 1.217 * lobe(lambda_nm, 437.0, 11.8, 36.0) + 0.681 * lobe(lambda_nm, 459.0, 26.0, 13.8);
}

/* XYZ -> linear sRGB / Rec.709 primaries, D65 white (IEC 61966-2-1). */
static void xyz_to_rgb(const double xyz[3], double rgb[3])
{
    rgb[0] = 3.2404542 * xyz[0] - 1.5371385 * xyz[1] - 0.4985314 * xyz[2];
    rgb[1] = -0.9692660 * xyz[0] + 1.8760108 * xyz[1] + 0.0415560 * xyz[2];
    rgb[2] = 0.0556434 * xyz[0] - 0.2040259 * xyz[1] + 1.0572252 * xyz[2];
}

float rgb_luminance(const float rgb[3])
{
    return 0.2126729f * rgb[0] + 0.7151522f * rgb[1] + 0.0721750f * rgb[2];
}

typedef double (*SpectrumFn)(double lambda_nm, const void *ctx);

/* rgb of a spectrum with Y normalised by the integral of y-bar (so the constant 1 has
 * Y = 1), 1 nm steps over 360..830 nm. */
static void spectrum_fn_to_rgb_raw(SpectrumFn f, const void *ctx, double rgb[3])
{
    double xyz[3] = {0, 0, 0}, y_integral = 0.0;
    for (int l = LAMBDA_MIN_NM; l <= LAMBDA_MAX_NM; ++l) {
        double bar[3];
        cie_xyz_bar(l, bar);
        double s = f(l, ctx);
        for (int c = 0; c < 3; ++c) xyz[c] += s * bar[c];
        y_integral += bar[1];
    }
    for (int c = 0; c < 3; ++c) xyz[c] /= y_integral;
    xyz_to_rgb(xyz, rgb);
}

static double constant_one(double lambda_nm, const void *ctx)
{
    (void)lambda_nm;
    (void)ctx;
    return 1.0;
}

/* Reflectance-style conversion: balanced so that the constant spectrum is grey. */
static void spectrum_fn_to_rgb_balanced(SpectrumFn f, const void *ctx, float out[3])
{
    double rgb[3], white[3];
    spectrum_fn_to_rgb_raw(f, ctx, rgb);
    spectrum_fn_to_rgb_raw(constant_one, NULL, white);
    for (int c = 0; c < 3; ++c) {
        double v = rgb[c] / white[c];
        out[c] = (float)(v > 0.0 && isfinite(v) ? v : 0.0);
    }
}

/* Illuminant-style conversion: sRGB white is D65, as in pbrt-v4's RGB film. */
static void spectrum_fn_to_rgb_illuminant(SpectrumFn f, const void *ctx, float out[3])
{
    double rgb[3];
    spectrum_fn_to_rgb_raw(f, ctx, rgb);
    for (int c = 0; c < 3; ++c) out[c] = (float)(rgb[c] > 0.0 && isfinite(rgb[c]) ? rgb[c] : 0.0);
}

typedef struct {
    const float *v;
    int pairs;
} Samples;

static double samples_eval(double lambda_nm, const void *ctx)
{
    const Samples *s = ctx;
    const float *v = s->v;
    int n = s->pairs;
    if (lambda_nm < v[0] || lambda_nm > v[2 * (n - 1)]) return 0.0;
    if (n == 1) return v[1];
    /* Binary search for the segment [i, i+1] containing lambda. */
    int lo = 0, hi = n - 1;
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (v[2 * mid] <= lambda_nm) lo = mid;
        else hi = mid;
    }
    double l0 = v[2 * lo], l1 = v[2 * hi];
    double t = l1 > l0 ? (lambda_nm - l0) / (l1 - l0) : 0.0;
    return v[2 * lo + 1] * (1.0 - t) + v[2 * hi + 1] * t;
}

static bool samples_valid(const float *values, int count)
{
    if (count < 2 || count % 2 != 0) return false;
    for (int i = 2; i < count; i += 2)
        if (!(values[i] > values[i - 2])) return false;
    return true;
}

bool spectrum_samples_to_rgb(const float *values, int count, float rgb[3])
{
    if (count == 1) {
        float c = values[0] > 0.0f ? values[0] : 0.0f;
        rgb[0] = rgb[1] = rgb[2] = c;
        return true;
    }
    if (!samples_valid(values, count)) return false;
    Samples s = {values, count / 2};
    spectrum_fn_to_rgb_balanced(samples_eval, &s, rgb);
    return true;
}

bool spectrum_samples_to_rgb_illuminant(const float *values, int count, float rgb[3])
{
    if (count == 1) {
        /* A constant emission spectrum is illuminant E. */
        Samples s = {(const float[]){(float)LAMBDA_MIN_NM, values[0], (float)LAMBDA_MAX_NM, values[0]}, 2};
        spectrum_fn_to_rgb_illuminant(samples_eval, &s, rgb);
        return true;
    }
    if (!samples_valid(values, count)) return false;
    Samples s = {values, count / 2};
    spectrum_fn_to_rgb_illuminant(samples_eval, &s, rgb);
    return true;
}

/* Planck's law, B(lambda, T) = 2 h c^2 / (lambda^5 (exp(h c / (lambda k T)) - 1)). */
static double planck(double lambda_nm, double temperature_k)
{
    const double c = 299792458.0, h = 6.62606957e-34, kb = 1.3806488e-23;
    double l = lambda_nm * 1e-9;
    return (2.0 * h * c * c) / (pow(l, 5) * (exp((h * c) / (l * kb * temperature_k)) - 1.0));
}

static double blackbody_normalised(double lambda_nm, const void *ctx)
{
    double t = *(const double *)ctx;
    double lambda_max_nm = 2.8977721e-3 / t * 1e9; /* Wien's displacement law */
    return planck(lambda_nm, t) / planck(lambda_max_nm, t);
}

void spectrum_blackbody_rgb(float temperature_k, float rgb[3])
{
    if (!(temperature_k > 0.0f) || !isfinite(temperature_k)) {
        rgb[0] = rgb[1] = rgb[2] = 0.0f;
        return;
    }
    double t = temperature_k;
    spectrum_fn_to_rgb_illuminant(blackbody_normalised, &t, rgb);
}

/* Sellmeier dispersion formula n^2 = 1 + sum B_i lambda^2 / (lambda^2 - C_i), lambda in um,
 * with the manufacturer's (Schott) coefficients; used for the glass-* spectra. */
typedef struct {
    const char *name;
    double b[3], c[3];
} Sellmeier;

static const Sellmeier glasses[] = {
    {"glass-BK7", {1.03961212, 0.231792344, 1.01046945}, {0.00600069867, 0.0200179144, 103.560653}},
    {"glass-BAF10", {1.5851495, 0.143559385, 1.08521269}, {0.00926681282, 0.0424489805, 105.613573}},
    {"glass-FK51A", {0.971247817, 0.216901417, 0.904651666}, {0.00472301995, 0.0153575612, 168.68133}},
    {"glass-LASF9", {2.00029547, 0.298926886, 1.80691843}, {0.0121426017, 0.0538736236, 156.530829}},
    /* pbrt-v4's "glass-F5/F10/F11" hold the dense flints Schott SF5, SF10, SF11. */
    {"glass-F5", {1.52481889, 0.187085527, 1.42729015}, {0.011254756, 0.0588995392, 129.141675}},
    {"glass-F10", {1.62153902, 0.256287842, 1.64447552}, {0.0122241457, 0.0595736775, 147.468793}},
    {"glass-F11", {1.73759695, 0.313747346, 1.89878101}, {0.013188707, 0.0623068142, 155.23629}},
};

/* Wavelengths (nm) at which index-of-refraction spectra are sampled for r, g, b: the
 * dominant wavelengths of the Rec.709 primaries. */
static const double channel_lambda_nm[3] = {612.0, 549.0, 465.0};

static double sellmeier_eta(const Sellmeier *g, double lambda_nm)
{
    double l2 = (lambda_nm * 1e-3) * (lambda_nm * 1e-3);
    double n2 = 1.0;
    for (int i = 0; i < 3; ++i) n2 += g->b[i] * l2 / (l2 - g->c[i]);
    return sqrt(n2);
}

/* Complex refractive indices of metals at the channel wavelengths above (real part eta,
 * extinction k).
 * - Cu: derived here from the measured copper table that pbrt distributes (56 samples,
 *   299-886 nm; pbrt-v4's "metal-Cu-eta"/"metal-Cu-k"), interpolated linearly in wavelength
 *   at 612/549/465 nm and rounded to 2 decimals.
 * - Au, Ag, Al: rounded literature values at the same wavelengths (Au and Ag: Johnson and
 *   Christy 1972, Phys. Rev. B 6, 4370; Al: Rakic 1995, Appl. Opt. 34, 4755), not recomputed
 *   from pbrt-v4's tables, so expect differences of a few percent from pbrt-v4's colours. */
typedef struct {
    const char *name;
    float rgb[3];
} NamedRgb;

static const NamedRgb metals[] = {
    {"metal-Cu-eta", {0.31f, 0.97f, 1.16f}},  {"metal-Cu-k", {3.12f, 2.58f, 2.46f}},
    {"metal-Au-eta", {0.19f, 0.43f, 1.45f}},  {"metal-Au-k", {3.10f, 2.34f, 1.80f}},
    {"metal-Ag-eta", {0.13f, 0.12f, 0.13f}},  {"metal-Ag-k", {3.90f, 3.45f, 2.71f}},
    {"metal-Al-eta", {1.26f, 0.96f, 0.64f}},  {"metal-Al-k", {7.30f, 6.69f, 5.64f}},
};

/* Standard illuminants. sRGB white is D65, so D65 is (1, 1, 1); A is by definition a
 * 2856 K Planckian radiator; D50 is approximated by a 5003 K blackbody (its CCT).
 * Each is normalised to luminance 1, as pbrt-v4 normalises its named illuminants. */
static bool illuminant_rgb(const char *name, float rgb[3])
{
    double t;
    if (!strcmp(name, "stdillum-D65")) {
        rgb[0] = rgb[1] = rgb[2] = 1.0f;
        return true;
    } else if (!strcmp(name, "stdillum-A")) {
        t = 2856.0;
    } else if (!strcmp(name, "stdillum-D50")) {
        t = 5003.0;
    } else {
        return false;
    }
    spectrum_blackbody_rgb((float)t, rgb);
    float y = rgb_luminance(rgb);
    for (int c = 0; c < 3; ++c) rgb[c] /= y;
    return true;
}

bool spectrum_named_rgb(const char *name, float rgb[3])
{
    for (size_t i = 0; i < sizeof glasses / sizeof glasses[0]; ++i)
        if (!strcmp(name, glasses[i].name)) {
            for (int c = 0; c < 3; ++c) rgb[c] = (float)sellmeier_eta(&glasses[i], channel_lambda_nm[c]);
            return true;
        }
    for (size_t i = 0; i < sizeof metals / sizeof metals[0]; ++i)
        if (!strcmp(name, metals[i].name)) {
            memcpy(rgb, metals[i].rgb, 3 * sizeof(float));
            return true;
        }
    return illuminant_rgb(name, rgb);
}

void spectrum_unknown_substitute(const char *name, float rgb[3])
{
    size_t n = strlen(name);
    float v = 1.0f;
    if (n >= 4 && !strcmp(name + n - 4, "-eta")) v = 1.5f;
    else if (n >= 2 && !strcmp(name + n - 2, "-k")) v = 0.0f;
    rgb[0] = rgb[1] = rgb[2] = v;
}
