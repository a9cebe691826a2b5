/* FSF on a penumbra with a closed form: a straight occluder edge at one depth over a uniform
 * square light. With the shear k = (d_light - d_occ) / d_occ (light metres per receiver metre)
 * a sample at receiver X with light coordinate y1 is lit iff y1 > -k X, so the pixel's lit
 * fraction is the ramp clamp((L + k X) / (2 L), 0, 1). The sheared filter reprojects every
 * neighbour's samples onto the pixel and must follow the ramp with 16 samples per pixel; the
 * opposite shear, or none, with the same width, must not. */
#include "check.h"
#include "fsf_synth.h"

enum { W = 160, H = 24, L_SAMPLES = 4 };
static const float PIXEL_M = 0.01f; /* fsf_synth: one world unit per 100 pixels */
static const float HALF_M = 0.5f, EDGE_PX = 80.0f;
static float K = 1.0f; /* the occluder's shear, set per case */

static float receiver_m(int x) { return ((float)x + 0.5f - EDGE_PX) * PIXEL_M; }

static float ramp(int x)
{
    float h = (HALF_M + K * receiver_m(x)) / (2.0f * HALF_M);
    return h < 0.0f ? 0.0f : h > 1.0f ? 1.0f : h;
}

/* RMS error against the ramp over the rows, with shear eta (light metres per pixel step);
 * sigma 0: the pixel's own samples (Monte Carlo). */
static double rms_error(FsfSynth *f, const FsfGrid *g, float eta, float sigma)
{
    size_t n = (size_t)W * H;
    for (size_t i = 0; i < n; ++i) {
        f->px[i].eta_m[0] = eta, f->px[i].eta_m[1] = eta; /* one occluder depth: the same k on both axes */
        f->px[i].sigma_px[0] = f->px[i].sigma_px[1] = sigma;
    }
    float *out = malloc(4 * n * sizeof(float));
    FsfGuides gd = fsf_guides_default(f->pos4, f->nrm4, f->usable);
    bool ok = fsf_filter_factored(&f->s, g, f->px, &gd, out);
    double sum = 0.0;
    for (size_t i = 0; i < n; ++i) {
        double e = (double)out[4 * i] / out[4 * i + 3] - ramp((int)(i % W));
        sum += e * e;
    }
    free(out);
    return ok ? sqrt(sum / (double)n) : INFINITY;
}

int main(void)
{
    FsfSynth f;
    fsf_synth_init(&f, W, H, L_SAMPLES);
    /* the default grid (the paper's 16 bins), and a coarser one (8 bins), whose error
     * test_fsf_factored covers and this edge shows too: see the end */
    FsfGrid g = fsf_grid_default(HALF_M, HALF_M), coarse = g;
    coarse.shift_nodes = 9, coarse.y2_bins = 8;
    fsf_synth_light(&f, &g, L_SAMPLES, false, 3);
    /* k = 1: occluder halfway, a 100 px penumbra; k = 4: occluder near the floor, 25 px */
    const float ks[2] = {1.0f, 4.0f};
    for (int c = 0; c < 2; ++c) {
        K = ks[c];
        for (size_t i = 0; i < (size_t)W * H; ++i)
            for (int s = 0; s < f.cap; ++s) {
                size_t slot = i * (size_t)f.cap + (size_t)s;
                float lit = f.y[2 * slot] > -K * receiver_m((int)(i % W)) ? 1.0f : 0.0f;
                f.v[3 * slot] = f.v[3 * slot + 1] = f.v[3 * slot + 2] = lit;
            }
        /* one depth: no slope spread, so the width is the paper's cap (2 sigma = 16 px) */
        float sigma = 8.0f, eta = K * PIXEL_M;
        double mc = rms_error(&f, &g, 0.0f, 0.0f);
        double fsf = rms_error(&f, &g, eta, sigma);
        double flipped = rms_error(&f, &g, -eta, sigma);
        double unsheared = rms_error(&f, &g, 0.0f, sigma);
        printf("k = %g: rms error against the ramp: Monte Carlo %.4f, FSF %.4f, opposite shear %.4f, no shear %.4f\n",
               K, mc, fsf, flipped, unsheared);
        /* What is left is the shift grid's interpolation and the noise of 16 x 33 x 33 samples
         * (measured 0.003-0.004); without the density correction (fsf_density) the tapered
         * light profile alone gave 0.013 at k = 1. */
        CHECK(fsf < 0.006);
        CHECK(fsf < mc / 5.0);
        /* the wrong shear misplaces the neighbours' samples on the light */
        CHECK(flipped > 2.5 * fsf);
        /* with no shear the same width is a plain blur: it rounds the ramp's ends */
        CHECK(unsheared > 2.0 * fsf);
        /* coarser shift nodes cost accuracy on a clean edge, yet stay far below Monte
         * Carlo (measured 0.0068 and 0.0054) */
        double fsf_coarse = rms_error(&f, &coarse, eta, sigma);
        printf("  coarser grid (%d nodes): FSF %.4f\n", coarse.shift_nodes, fsf_coarse);
        CHECK(fsf_coarse < mc / 2.5 && fsf_coarse >= fsf);
    }
    fsf_synth_free(&f);
    return check_failures ? 1 : 0;
}
