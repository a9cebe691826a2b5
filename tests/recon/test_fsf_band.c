/* FSF's width for a uniform light (fsf_params.h, fsf_light_sigma_y_m): the band narrows with
 * the samples, so the error keeps falling where a fixed band has a floor.
 *
 * Closed form: a slit between two straight occluder edges at two depths, over a uniform
 * square light. Edge 1 (shear k1) lets through the light coordinates y1 > -k1 X, edge 2 (k2)
 * those with y1 < c - k2 X (receiver X in metres), so the lit fraction at X is the length of
 * [max(-L, -k1 X), min(L, c - k2 X)] over 2 L. Every pixel's footprint holds both slopes: the
 * filter shears with their mean and FSF eq. 4 gives the width sigma_y / (k2 - k1); a sample of
 * either edge is misplaced on the light by (k - k_mean) t per tap, a bias that grows with the
 * width (docs/algorithms.md 10, "The width for a uniform light"). */
#include "check.h"
#include "fsf_synth.h"
#include "recon/fsf/fsf_params.h"

enum { W = 160, H = 24 };
static const float PIXEL_M = 0.01f; /* fsf_synth: one world unit per 100 pixels */
static const float HALF_M = 0.5f, EDGE_PX = 80.0f, K1 = 1.0f, K2 = 3.0f, C_M = 0.2f;

static float receiver_m(int x) { return ((float)x + 0.5f - EDGE_PX) * PIXEL_M; }

static float lo_m(float X) { return fmaxf(-HALF_M, -K1 * X); }
static float hi_m(float X) { return fminf(HALF_M, C_M - K2 * X); }
static float lit_fraction(float X) { return fmaxf(0.0f, hi_m(X) - lo_m(X)) / (2.0f * HALF_M); }

/* RMS error against the closed form with l x l samples per pixel and sigma_y (metres); sigma_y
 * 0: each pixel's own samples (Monte Carlo). Averaged over `seeds` sample sets. */
static double rms_error(int l, float sigma_y, int seeds)
{
    FsfSynth f;
    fsf_synth_init(&f, W, H, l);
    FsfGrid g = fsf_grid_default(HALF_M, HALF_M);
    size_t n = (size_t)W * H;
    float sigma_px = sigma_y / (K2 - K1) / PIXEL_M, eta = 0.5f * (K1 + K2) * PIXEL_M;
    if (sigma_px > 8.0f) sigma_px = 8.0f; /* the 32-pixel cap */
    float *out = malloc(4 * n * sizeof(float));
    double sum = 0.0;
    bool ok = out != NULL;
    for (int seed = 1; ok && seed <= seeds; ++seed) {
        fsf_synth_light(&f, &g, l, false, 7u * (unsigned)seed);
        for (size_t i = 0; i < n; ++i) {
            float X = receiver_m((int)(i % W));
            f.px[i].eta_m[0] = f.px[i].eta_m[1] = sigma_y > 0.0f ? eta : 0.0f;
            f.px[i].sigma_px[0] = f.px[i].sigma_px[1] = sigma_y > 0.0f ? sigma_px : 0.0f;
            for (int s = 0; s < f.cap; ++s) {
                size_t slot = i * (size_t)f.cap + (size_t)s;
                float y1 = f.y[2 * slot], lit = y1 > -K1 * X && y1 < C_M - K2 * X ? 1.0f : 0.0f;
                f.v[3 * slot] = f.v[3 * slot + 1] = f.v[3 * slot + 2] = lit;
            }
        }
        /* the slit does not depend on y2 or on the row: the second axis' taps add samples
         * whose y2 shift moves them on the light but not across an edge */
        FsfGuides gd = fsf_guides_default(f.pos4, f.nrm4, f.usable);
        ok = fsf_filter_factored(&f.s, &g, f.px, &gd, out);
        for (size_t i = 0; ok && i < n; ++i) {
            int x = (int)(i % W);
            if (x < 16 || x >= W - 16) continue; /* away from the image's ends */
            double e = (double)out[4 * i] / out[4 * i + 3] - lit_fraction(receiver_m(x));
            sum += e * e;
        }
    }
    free(out);
    fsf_synth_free(&f);
    return ok ? sqrt(sum / ((double)(W - 32) * H * seeds)) : INFINITY;
}

/* W K1(W) from the series of K1 (Abramowitz and Stegun 9.6.11), for the check of fsf_bounce_sigma_v. */
static double w_k1_series(double w)
{
    double x = 0.5 * w, lx = log(x), euler = 0.5772156649015329;
    /* K1(w) = 1/w + ln(w/2) I1(w) - (w/4) sum_k (psi(k+1) + psi(k+2)) (w^2/4)^k / (k! (k+1)!) */
    double i1 = 0.0, rest = 0.0, term = x, psi1 = -euler, psi2 = 1.0 - euler;
    for (int k = 0; k < 40; ++k) {
        i1 += term;
        rest += (psi1 + psi2) * term;
        term *= x * x / ((k + 1.0) * (k + 2.0));
        psi1 += 1.0 / (k + 1.0), psi2 += 1.0 / (k + 2.0);
    }
    double k1 = 1.0 / w + lx * i1 - 0.5 * rest;
    return w * k1;
}

int main(void)
{
    /* the closed forms of the band: 2 L / e^2 at FSF's 16 samples, halving per 4x samples */
    CHECK(fabsf(fsf_light_sigma_y_m(0.5f, 16) - expf(-2.0f)) < 1e-6f);
    CHECK(fabsf(fsf_light_sigma_y_m(1.0f, 64) - 0.5f * fsf_light_sigma_y_m(1.0f, 16)) < 1e-6f);
    CHECK(fabsf(fsf_light_sigma_y_m(1.0f, 4) - 2.0f * fsf_light_sigma_y_m(1.0f, 16)) < 1e-6f);
    CHECK(isfinite(fsf_light_sigma_y_m(1.0f, 0)) && fsf_light_sigma_y_m(1.0f, 0) > 0.0f);
    /* the v-plane's band: the root of W K1(W) = e^-2 sqrt(16 / n); K1 from its series
     * independently of fsf_band.c's integral: at 16 samples W = 2.865 (Mehta's 2.8 is where
     * W K1(W) = 0.143), at 64 W = 3.659 */
    CHECK(fabs(2.0 / fsf_bounce_sigma_v(16) - 2.865) < 2e-3);
    CHECK(fabs(2.0 / fsf_bounce_sigma_v(64) - 3.659) < 2e-3);
    CHECK(fabs(w_k1_series(2.0 / fsf_bounce_sigma_v(32)) - fsf_band_threshold(32)) < 1e-4);
    CHECK(fsf_bounce_sigma_v(8) > fsf_bounce_sigma_v(16) && fsf_bounce_sigma_v(16) > fsf_bounce_sigma_v(1024));

    const int seeds = 3;
    /* l x l samples: 16 and 64 per pixel */
    double mc16 = rms_error(4, 0.0f, seeds), mc64 = rms_error(8, 0.0f, seeds);
    double band16 = rms_error(4, fsf_light_sigma_y_m(HALF_M, 16), seeds);
    double band64 = rms_error(8, fsf_light_sigma_y_m(HALF_M, 64), seeds);
    /* the paper's band, FSF's Gaussian light sigma_y = L / 2 at every count */
    double fixed16 = rms_error(4, 0.5f * HALF_M, seeds), fixed64 = rms_error(8, 0.5f * HALF_M, seeds);
    printf("rms error against the slit: Monte Carlo %.4f / %.4f, band %.4f / %.4f, fixed band (L/2) %.4f / "
           "%.4f (16 / 64 samples)\n",
           mc16, mc64, band16, band64, fixed16, fixed64);
    /* both filters far below Monte Carlo */
    CHECK(band16 < mc16 / 2.0 && band64 < mc64 / 2.0);
    /* the band's error falls with the samples (Monte Carlo's halves) */
    CHECK(band64 < 0.75 * band16);
    /* the fixed band does not fall as far: its bias stays */
    CHECK(fixed64 > 0.8 * fixed16);
    CHECK(band64 < 0.75 * fixed64);
    CHECK_DONE();
}
