/* The sheared filter's effective sample count and the collapsed pixels' extras
 * (fsf_budget_plan.h: fsf_shear_overlap, fsf_pixel_area_sheared_px, fsf_blend_collapsed).
 *
 *   overlap    over the filter's own taps, to its reach (1.5 sigma for the shadows' and the
 *              lens' grids, 2 for the default and the bounce's): no shear: 1; a shear moving every tap's light off the centre's (|eta| > 2 L):
 *              the centre tap alone, sum w^2 / (sum w)^2 of the unsheared taps; between: the
 *              brute-force count (sum W)^2 / sum W^2 of 2000 samples per tap spread evenly
 *              over each neighbour's light, W = w(t) / rho(z) for those the box keeps (the
 *              filter's own weights, fsf_density), over the unsheared count; always in (0, 1]
 *              and not rising with |eta|; the area over a grid multiplies the overlaps at
 *              that grid's reach (a 2-sigma count for a 1.5-sigma filter is caught: the
 *              centre-tap case differs by 9% at sigma 2.5 and 16% at 8 between the reaches)
 *   blend      a collapsed pixel with extras moves from the filter's value towards its mean
 *              by extra / (n1 A + extra); a pixel that is not collapsed, has no extras, was
 *              passed through or is not usable keeps its value */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../check.h"
#include "recon/fsf/fsf_budget_plan.h"
#include "recon/fsf/fsf_filter.h"
#include "recon/gbuffer.h"

static float gauss(int t, float sigma) { return expf(-0.5f * (float)(t * t) / (sigma * sigma)); }

/* (sum W)^2 / sum W^2 over samples spread evenly on each tap's light, divided by the same
 * without shear: the oracle for fsf_shear_overlap. */
static double brute_overlap(float sigma, float eta, float half, float reach)
{
    enum { PER_TAP = 2000 };
    int r = fsf_radius_reach(sigma, reach);
    float cum[FSF_CUM];
    fsf_tap_prefix(sigma, r, cum);
    double s1 = 0, s2 = 0, u1 = 0, u2 = 0;
    for (int t = -r; t <= r; ++t) {
        for (int k = 0; k < PER_TAP; ++k) {
            float y = -half + ((float)k + 0.5f) / PER_TAP * 2.0f * half;
            float z = y + eta * (float)t;
            if (fabsf(z) <= half) {
                double W = gauss(t, sigma) / fsf_density(z, eta, half, r, cum);
                s1 += W, s2 += W * W;
            }
            double U = gauss(t, sigma) / fsf_density(y, 0.0f, half, r, cum);
            u1 += U, u2 += U * U;
        }
    }
    return (s1 * s1 / s2) / (u1 * u1 / u2);
}

static void overlap(float reach)
{
    const float half = 0.8f;
    CHECK(fsf_shear_overlap(3.0f, 0.0f, half, reach) == 1.0f);
    /* |eta| > 2 L: only the centre tap covers any light coordinate */
    for (int i = 0; i < 3; ++i) {
        float sigma = (float[]){0.7f, 2.5f, 8.0f}[i];
        int r = fsf_radius_reach(sigma, reach);
        double a = 0, b = 0;
        for (int t = -r; t <= r; ++t) a += gauss(t, sigma), b += (double)gauss(t, sigma) * gauss(t, sigma);
        CHECK_NEAR(fsf_shear_overlap(sigma, 2.1f * half, half, reach), b / (a * a), 1e-5);
        CHECK_NEAR(fsf_shear_overlap(sigma, -3.0f * half, half, reach), b / (a * a), 1e-5);
    }
    /* between: against the brute-force count. The overlap integrates a piecewise-constant
     * function of z (its steps at +-L + eta t) with 32 midpoints, each step costing at most
     * half a cell of one run's value: a few percent (measured: at most 1.1%) */
    double worst = 0;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 6; ++j) {
            float sigma = (float[]){0.6f, 1.5f, 4.0f, 8.0f}[i];
            float eta = (float[]){0.01f, 0.05f, 0.15f, 0.4f, -0.9f, 1.5f}[j] * half;
            double want = brute_overlap(sigma, eta, half, reach), got = fsf_shear_overlap(sigma, eta, half, reach);
            double rel = fabs(got - want) / want;
            worst = rel > worst ? rel : worst;
            CHECK(rel < 0.03);
            CHECK(got > 0.0 && got <= 1.0);
            if (rel >= 0.03) fprintf(stderr, "sigma %g eta %g: overlap %g, brute force %g\n", sigma, eta, got, want);
        }
    fprintf(stderr, "reach %g sigma: overlap against the brute-force count: worst relative error %.4f\n", reach,
            worst);
    /* not rising with the shear */
    for (int i = 0; i < 3; ++i) {
        float sigma = (float[]){1.0f, 3.0f, 8.0f}[i], last = 1.0f;
        for (int j = 0; j <= 40; ++j) {
            float o = fsf_shear_overlap(sigma, (float)j * 0.05f * half, half, reach);
            CHECK(o <= last + 0.02f);
            last = o;
        }
    }
    /* the area: the unsheared one with no shear, smaller with it, never below one pixel */
    FsfGrid g = fsf_grid_default(half, half);
    g.reach_sigmas = reach;
    FsfPixel p = fsf_pixel_left_out();
    p.sigma_px[0] = 4.0f, p.sigma_px[1] = 2.0f;
    CHECK_NEAR(fsf_pixel_area_sheared_px(&p, &g), fsf_pixel_area_px(&p), 1e-3 * fsf_pixel_area_px(&p));
    p.eta_m[0] = 0.3f * half;
    CHECK(fsf_pixel_area_sheared_px(&p, &g) < 0.8f * fsf_pixel_area_px(&p));
    /* both axes sheared: the product of the brute-force overlaps over the grid's own taps */
    p.sigma_px[0] = 3.0f, p.eta_m[0] = 0.15f * half, p.sigma_px[1] = 2.5f, p.eta_m[1] = -2.5f * half;
    double want = fsf_pixel_area_px(&p) * brute_overlap(3.0f, 0.15f * half, half, reach) *
                  brute_overlap(2.5f, -2.5f * half, half, reach);
    CHECK_NEAR(fsf_pixel_area_sheared_px(&p, &g), want, 0.03 * want);
    p.sigma_px[0] = p.sigma_px[1] = 0.2f, p.eta_m[0] = 5.0f;
    CHECK(fsf_pixel_area_sheared_px(&p, &g) == 1.0f);
}

/* The shadows' grid (fsf_light_grid) is the one the plan's blend models: its overlap is its
 * own 1.5-sigma taps' count, not the 2-sigma one, which differs by more than the tolerance
 * (so the check above would catch a count to the wrong reach). */
static void light_grid_reach(void)
{
    const float half = 0.8f, sigma = 2.5f;
    CHECK(FSF_REACH_SIGMAS_NARROW != FSF_RADIUS_SIGMAS);
    double narrow = brute_overlap(sigma, 2.1f * half, half, FSF_REACH_SIGMAS_NARROW);
    double wide = brute_overlap(sigma, 2.1f * half, half, FSF_RADIUS_SIGMAS);
    CHECK(fabs(narrow - wide) > 0.05 * narrow);
    FsfLight light;
    memset(&light, 0, sizeof light);
    light.half_m[0] = light.half_m[1] = half;
    FsfGrid g = fsf_light_grid(&light);
    CHECK(g.reach_sigmas == FSF_REACH_SIGMAS_NARROW);
    FsfPixel p = fsf_pixel_left_out();
    p.sigma_px[0] = p.sigma_px[1] = sigma, p.eta_m[0] = 2.1f * half;
    CHECK_NEAR(fsf_pixel_area_sheared_px(&p, &g), fsf_pixel_area_px(&p) * narrow, 1e-4 * fsf_pixel_area_px(&p));
}

static void blend(void)
{
    enum { W = 5 };
    GBuffer g;
    ReconCamera cam = {0.0f, 5.0f, 0.001f};
    CHECK(gbuffer_init(&g, W, 1, cam));
    FsfPixel px[W];
    unsigned char usable[W] = {1, 1, 1, 1, 0};
    int stored[W] = {12, 12, 12, 12, 12}, hits[W] = {60, 60, 12, 60, 60};
    float mean4[4 * W], value4[4 * W], before[4 * W];
    for (int i = 0; i < W; ++i) {
        px[i] = fsf_pixel_left_out();
        px[i].sigma_px[0] = 0.3f, px[i].sigma_px[1] = 4.0f; /* collapsed along the first axis */
        px[i].eta_m[0] = 0.5f;
        g.sums[i].hits = hits[i];
        for (int ch = 0; ch < 4; ++ch) mean4[4 * i + ch] = 0.2f + 0.1f * (float)ch, value4[4 * i + ch] = 0.5f;
    }
    px[1].sigma_px[0] = 2.0f;                       /* not collapsed */
    px[3].sigma_px[0] = px[3].sigma_px[1] = 0.0f;   /* passed through */
    memcpy(before, value4, sizeof value4);
    FsfGrid grid = fsf_grid_default(0.8f, 0.8f);
    grid.reach_sigmas = FSF_REACH_SIGMAS_NARROW;
    fsf_blend_collapsed(px, usable, stored, &g, &grid, mean4, value4);
    float a = fsf_pixel_area_sheared_px(&px[0], &grid), w = 48.0f / (12.0f * a + 48.0f);
    for (int ch = 0; ch < 3; ++ch) CHECK_NEAR(value4[ch], 0.5f + w * (mean4[ch] - 0.5f), 1e-6);
    CHECK(value4[3] == before[3]);
    CHECK(w > 0.2f); /* a collapsed, sheared filter averages few samples: the extras count */
    CHECK(memcmp(value4 + 4, before + 4, 4 * (W - 1) * sizeof(float)) == 0);
    gbuffer_free(&g);
}

int main(void)
{
    overlap(FSF_RADIUS_SIGMAS);
    overlap(FSF_REACH_SIGMAS_NARROW);
    light_grid_reach();
    blend();
    CHECK_DONE();
}
