/* FSF for defocus (fsf_lens.h) on synthetic lens samples of a textured plane, built the way
 * the camera makes them (film x = x0 + c u, y = y0 - c v; docs/algorithms.md section 10,
 * "Defocus") and fed through the real store, gather and parameter code:
 *
 *   1. constant depth (a known circle of confusion): the texture is a sinusoid, so the
 *      defocused pixel value is known in closed form (the pixel box's and the lens disk's
 *      transfer functions); at 4 and 8 samples per pixel FSF's error against it is well below
 *      the pixel mean's
 *   2. a depth that varies smoothly over the image (c from 3 to 7 px): the factored passes
 *      agree with the brute-force 4D sum (fsf_filter_brute) up to their discretisation, and
 *      the OpenCL kernels with the factored C passes up to rounding
 *   3. lens radius 0 (a pinhole): every pixel gets its own samples' mean */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "recon/fsf/fsf_band.h"
#include "recon/fsf/fsf_cl.h"
#include "recon/fsf/fsf_lens.h"
#include "render/warp.h"

#define PI 3.14159265358979323846

enum { W = 64, H = 56 };
static const double FX = 1.0 / 13.0, FY = 1.0 / 29.0; /* texture frequency, cycles per pixel */

/* The texture at film position (x0, y0) of the pinhole image. */
static double texture(double x0, double y0) { return 0.5 + 0.4 * cos(2.0 * PI * (FX * x0 + FY * y0)); }

static double sinc(double x) { return x == 0.0 ? 1.0 : sin(PI * x) / (PI * x); }

/* The pixel (px, py) of the defocused plane with circle-of-confusion slope c: the box pixel
 * and the uniform disk lens (mean of exp(i k.c (u, -v)) over the unit disk: 2 J1(r) / r). */
static double analytic(int px, int py, double c)
{
    double r = 2.0 * PI * fabs(c) * sqrt(FX * FX + FY * FY), lens = r > 0.0 ? 2.0 * j1(r) / r : 1.0;
    return 0.5 + 0.4 * cos(2.0 * PI * (FX * (px + 0.5) + FY * (py + 0.5))) * sinc(FX) * sinc(FY) * lens;
}

typedef struct {
    ReconCamera cam;
    GBuffer g;
    SampleStore *st;
    float *value4;       /* the pixel means */
    int spp;
} Plane;

/* What a ray through film (x, y) and lens point (u, v) sees: its radiance, and its camera depth
 * in *depth. */
typedef double (*SceneFn)(const ReconCamera *cam, float x, float y, float u, float v, float *depth);

static float (*plane_depth)(int x, int y);
/* the textured plane at plane_depth(pixel) */
static double textured_plane(const ReconCamera *cam, float x, float y, float u, float v, float *depth)
{
    *depth = plane_depth((int)x, (int)y);
    float c = recon_coc_slope_px(cam, *depth);
    return texture(x - c * u, y + c * v);
}

/* spp samples per pixel of scene, stratified over film and lens (the lens strata warped to the
 * disk, as the renderer's sampler does). */
static void scene_make(Plane *f, float lens_radius, int spp, SceneFn scene, unsigned seed)
{
    f->cam = (ReconCamera){lens_radius, 2.0f, 0.01f};
    f->spp = spp;
    CHECK(gbuffer_init(&f->g, W, H, f->cam));
    Diag d = {0};
    CHECK(sample_store_create(SAMPLE_FIELD_LENS | SAMPLE_FIELD_DEPTH | SAMPLE_FIELD_RADIANCE, W, H, spp, (size_t)1 << 30,
                              &f->st, &d));
    f->value4 = calloc(4 * (size_t)W * H, sizeof(float));
    int l = (int)lround(sqrt((double)spp));
    unsigned s = seed;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            double sum = 0.0;
            for (int k = 0; k < spp; ++k) {
                SampleRecord r;
                memset(&r, 0, sizeof r);
                s = s * 1664525u + 1013904223u;
                float j1r = (float)(s >> 8) / 16777216.0f;
                s = s * 1664525u + 1013904223u;
                float j2r = (float)(s >> 8) / 16777216.0f;
                s = s * 1664525u + 1013904223u;
                float j3r = (float)(s >> 8) / 16777216.0f;
                s = s * 1664525u + 1013904223u;
                float j4r = (float)(s >> 8) / 16777216.0f;
                /* lens strata l x l; film jittered independently (a shuffled pairing) */
                vec2 lens = warp_disk_concentric((vec2){((float)(k % l) + j1r) / (float)l, ((float)(k / l) + j2r) / (float)l});
                r.px_raster = (float)x + j3r, r.py_raster = (float)y + j4r;
                /* the camera records lens 0 for a pinhole */
                r.lens_u = lens_radius > 0.0f ? lens.x : 0.0f, r.lens_v = lens_radius > 0.0f ? lens.y : 0.0f;
                double L = scene(&f->cam, r.px_raster, r.py_raster, r.lens_u, r.lens_v, &r.depth_cam);
                r.hit = true;
                r.L = v3((float)L, (float)L, (float)L);
                sample_store_add(f->st, x, y, &r);
                sum += L;
            }
            float *v = f->value4 + 4 * ((size_t)y * W + (size_t)x);
            v[0] = v[1] = v[2] = (float)(sum / spp), v[3] = 1.0f;
        }
}

/* depth(x, y) of the textured plane at pixel (x, y) */
static void plane_make(Plane *f, float lens_radius, int spp, float (*depth)(int x, int y), unsigned seed)
{
    plane_depth = depth;
    scene_make(f, lens_radius, spp, textured_plane, seed);
}

static void plane_free(Plane *f)
{
    gbuffer_free(&f->g);
    sample_store_destroy(f->st);
    free(f->value4);
}

/* The filter's inputs from the frame, as fsf_method.c builds them. */
typedef struct {
    unsigned char *usable;
    int *count;
    float *y, *v, *k_lo, *k_hi;
    FsfPixel *px;
    FsfSamples s;
    FsfGuides gd;
    FsfGrid grid;
} Inputs;

static void inputs_make_mu(Inputs *in, const Plane *f, float mu)
{
    size_t n = (size_t)W * H, slots = n * (size_t)f->spp;
    in->usable = malloc(n), in->count = malloc(n * sizeof(int));
    in->y = malloc(slots * 2 * sizeof(float)), in->v = malloc(slots * 3 * sizeof(float));
    in->k_lo = malloc(n * sizeof(float)), in->k_hi = malloc(n * sizeof(float));
    in->px = malloc(n * sizeof(FsfPixel));
    long long nonfinite = 0;
    CHECK(fsf_lens_samples(f->st, W, H, f->value4, in->usable, in->y, in->v, in->count, &nonfinite));
    CHECK(nonfinite == 0);
    FsfLensIn li = {&f->g, f->st, in->usable, mu, false};
    CHECK(fsf_lens_params(&li, in->px, in->k_lo, in->k_hi));
    in->s = (FsfSamples){W, H, f->spp, in->count, in->y, in->v};
    in->gd = fsf_guides_unguided(in->usable);
    in->grid = fsf_lens_grid();
}

static void inputs_make(Inputs *in, const Plane *f) { inputs_make_mu(in, f, 1.0f); }

static void inputs_free(Inputs *in)
{
    free(in->usable), free(in->count), free(in->y), free(in->v), free(in->k_lo), free(in->k_hi);
    free(in->px);
}

/* Mean squared error of channel 0 of out4 (rgb / weight) against analytic, and of the pixel means. */
static double mse_filtered(const float *out4, double c)
{
    double sum = 0.0;
    for (int i = 0; i < W * H; ++i) {
        double e = (double)out4[4 * i] / out4[4 * i + 3] - analytic(i % W, i / W, c);
        sum += e * e;
    }
    return sum / (W * H);
}
static double mse_mean(const Plane *f, double c)
{
    double sum = 0.0;
    for (int i = 0; i < W * H; ++i) {
        double e = (double)f->value4[4 * i] - analytic(i % W, i / W, c);
        sum += e * e;
    }
    return sum / (W * H);
}

static float depth_const(int x, int y)
{
    (void)x, (void)y;
    return 8.0f;
}
/* c from about 3 to 7 px per unit lens across the image (lens radius 0.16): a smooth field */
static float depth_ramp(int x, int y)
{
    float c = 3.0f + 4.0f * ((float)x + 0.5f * (float)y) / (float)(W + H / 2);
    return 1.0f / (0.5f - c * 0.01f / 0.16f);
}

/* RMS over pixels at least margin from the border of the difference of two filters'
 * normalised channel 0, and their largest difference relative to the pixel's weight over all
 * four channels. */
static void compare(const float *a, const float *b, int margin, double *rms, double *rel_max)
{
    double sum = 0.0, worst = 0.0;
    int count = 0;
    for (int i = 0; i < W * H; ++i) {
        int x = i % W, y = i / W;
        if (x < margin || y < margin || x >= W - margin || y >= H - margin) continue;
        double d = (double)a[4 * i] / a[4 * i + 3] - (double)b[4 * i] / b[4 * i + 3];
        sum += d * d, count++;
        for (int c = 0; c < 4; ++c)
            worst = fmax(worst, fabs((double)a[4 * i + c] - b[4 * i + c]) / fmax(fabs(a[4 * i + 3]), 1e-3));
    }
    *rms = sqrt(sum / count), *rel_max = worst;
}

/* 4. A bright strip of the background seen between a dark foreground edge and the strip's own
 * far edge, both out of focus behind the focal plane: the foreground covers pinhole positions
 * x0 < STRIP_E1 at c = STRIP_C1, the background is bright for x0 < STRIP_E2 at c = STRIP_C2. A
 * ray through film x and lens u is lit iff x - C1 u >= E1 and x - C2 u < E2: u in ((x - E2) / C2,
 * (x - E1) / C1]. The footprints near the strip hold both slopes, so the filter shears with their
 * mean and misplaces each edge's samples by (k - k_mean) per step: the bias grows with the
 * width (docs/algorithms.md section 10, "The band of the lens and of the v-plane"). */
static const float STRIP_C1 = 3.5f, STRIP_C2 = 7.0f, STRIP_E1 = 24.0f, STRIP_E2 = 40.0f;

/* the camera depth at which the plane_make camera's circle of confusion is c px */
static float depth_of_coc(const ReconCamera *cam, float c)
{
    return 1.0f / (1.0f / cam->focal_distance_world - c * cam->pixel_angle / cam->lens_radius_world);
}

static double strip(const ReconCamera *cam, float x, float y, float u, float v, float *depth)
{
    (void)y, (void)v;
    if (x - STRIP_C1 * u < STRIP_E1) {
        *depth = depth_of_coc(cam, STRIP_C1);
        return 0.0;
    }
    *depth = depth_of_coc(cam, STRIP_C2);
    return x - STRIP_C2 * u < STRIP_E2 ? 1.0 : 0.0;
}

/* The share of the unit disk with u <= t (the semicircle's distribution). */
static double disk_cdf(double t)
{
    t = fmax(-1.0, fmin(1.0, t));
    return 0.5 + (t * sqrt(1.0 - t * t) + asin(t)) / PI;
}

/* The strip's pixel px: the box pixel's mean of the disk's share that is lit (quadrature). */
static double strip_analytic(int px)
{
    const int steps = 256;
    double sum = 0.0;
    for (int k = 0; k < steps; ++k) {
        double x = px + (k + 0.5) / steps;
        sum += fmax(0.0, disk_cdf((x - STRIP_E1) / STRIP_C1) - disk_cdf((x - STRIP_E2) / STRIP_C2));
    }
    return sum / steps;
}

/* RMS error over the strip's pixels (away from the border) of FSF at spp samples with width
 * divisor mu (0: the pixel means), factored or brute force, over `seeds` sample sets. */
static double strip_rms(int spp, float mu, bool brute, int seeds)
{
    const int margin = 10;
    size_t n = (size_t)W * H;
    float *out = malloc(4 * n * sizeof(float));
    double sum = 0.0;
    int count = 0;
    for (int seed = 1; seed <= seeds; ++seed) {
        Plane f;
        scene_make(&f, 0.16f, spp, strip, 31u * (unsigned)seed);
        Inputs in;
        inputs_make_mu(&in, &f, mu > 0.0f ? mu : 1.0f);
        if (mu > 0.0f && brute) fsf_filter_brute(&in.s, &in.grid, in.px, &in.gd, out);
        else if (mu > 0.0f) CHECK(fsf_filter_factored(&in.s, &in.grid, in.px, &in.gd, out));
        for (size_t i = 0; i < n; ++i) {
            int x = (int)(i % W), y = (int)(i / W);
            if (x < margin || y < margin || x >= W - margin || y >= H - margin) continue;
            double got = mu > 0.0f ? (double)out[4 * i] / out[4 * i + 3] : f.value4[4 * i];
            double e = got - strip_analytic(x);
            sum += e * e, count++;
        }
        inputs_free(&in);
        plane_free(&f);
    }
    free(out);
    return sqrt(sum / count);
}

int main(void)
{
    size_t n = (size_t)W * H;
    float *out = malloc(4 * n * sizeof(float)), *brute = malloc(4 * n * sizeof(float));

    /* 1. the defocused textured plane: R = 0.16, F = 2, pixel angle 0.01, depth 8: c = 12 px */
    for (int spp = 4; spp <= 8; spp *= 2) {
        double e_fsf = 0.0, e_mean = 0.0, c = 0.0;
        for (unsigned seed = 1; seed <= 2; ++seed) {
            Plane f;
            plane_make(&f, 0.16f, spp == 8 ? 9 : spp, depth_const, seed * 77u);
            c = recon_coc_slope_px(&f.cam, depth_const(0, 0));
            Inputs in;
            inputs_make(&in, &f);
            CHECK(fsf_filter_factored(&in.s, &in.grid, in.px, &in.gd, out));
            e_fsf += mse_filtered(out, c), e_mean += mse_mean(&f, c);
            /* one depth: no spread, so the widest window; the shear is -1/c */
            size_t mid = (size_t)(H / 2) * W + W / 2; /* 28 px from every border */
            CHECK_NEAR(in.px[mid].eta_m[0], -1.0 / c, 1e-5);
            CHECK_NEAR(in.px[mid].sigma_px[0], FSF_RADIUS_CAP_PX / FSF_RADIUS_SIGMAS, 1e-6);
            inputs_free(&in);
            plane_free(&f);
        }
        printf("textured plane, c = %.1f px, %d spp: MSE fsf %.3g, pixel mean %.3g (ratio %.3f)\n", c,
               spp == 8 ? 9 : spp, e_fsf / 2, e_mean / 2, e_fsf / e_mean);
        CHECK(e_fsf < 0.5 * e_mean);
    }

    /* 2. a smooth slope field: brute force against the factored passes and the kernels */
    {
        Plane f;
        plane_make(&f, 0.16f, 9, depth_ramp, 5u);
        Inputs in;
        inputs_make(&in, &f);
        float lo = INFINITY, hi = -INFINITY;
        for (size_t i = 0; i < n; ++i) lo = fminf(lo, in.px[i].eta_m[0]), hi = fmaxf(hi, in.px[i].eta_m[0]);
        printf("ramp: shear from %.3f to %.3f unit lens per pixel\n", (double)lo, (double)hi);
        CHECK(lo < -0.2f && hi > -0.4f && hi - lo > 0.1f); /* the field does vary */
        fsf_filter_brute(&in.s, &in.grid, in.px, &in.gd, brute);
        CHECK(fsf_filter_factored(&in.s, &in.grid, in.px, &in.gd, out));
        double rms, rel;
        compare(brute, out, 0, &rms, &rel);
        double rms_in, rel_in;
        compare(brute, out, 24, &rms_in, &rel_in);
        double e_brute = 0.0;
        for (size_t i = 0; i < n; ++i) e_brute = fmax(e_brute, fabs((double)brute[4 * i] / brute[4 * i + 3]));
        printf("ramp: factored against brute force: rms %.4g, %.4g 24 px inside the border (texture amplitude 0.4)\n",
               rms, rms_in);
        /* the factored passes move a sample's lens coordinate by at most half a y2 bin (1/16)
         * and interpolate the shift grid (node spacing 1/4) linearly: at c <= 7 px a film
         * offset of under 0.45 px, where the texture changes by at most 0.4 * 2 pi * 0.087 *
         * 0.45 = 0.1; averaged over the footprint's many samples (signs at random), an rms of
         * a few percent of that: 0.01 is 10% of the bound. Only where the width field is
         * smooth (24 px from the border; nearer it the border cap makes the width vary by 0.5
         * px per px and the separation of the two passes, FSF section 4.2, adds its own) */
        CHECK(rms_in < 0.01);
        /* and over the whole image 0.011 (0.018 with pass 1a's density from the sample's own
         * pixel, whose width the border caps: fsf_density_mean) */
        CHECK(rms < 0.014);
        Diag d = {0};
        ClRuntime *rt = cl_runtime_create(NULL, &d);
        if (!rt) {
            printf("OpenCL part skipped: %s\n", d.message);
        } else {
            FsfCl *cl = fsf_cl_create(rt, &d);
            CHECK(cl != NULL);
            float *dev = malloc(4 * n * sizeof(float));
            if (cl) CHECK(fsf_cl_run(cl, &in.s, &in.grid, in.px, &in.gd, dev, NULL, &d));
            compare(out, dev, 0, &rms, &rel);
            printf("ramp: OpenCL against factored C: largest difference %.3g of the weight\n", rel);
            CHECK(rel < 1e-4); /* the same arithmetic in another order: rounding only */
            free(dev);
            fsf_cl_destroy(cl);
            cl_runtime_destroy(rt);
        }
        inputs_free(&in);
        plane_free(&f);
    }

    /* 3. a pinhole: lens radius 0, so c = 0 and no neighbour shares a lens ray */
    {
        Plane f;
        plane_make(&f, 0.0f, 8, depth_const, 9u);
        Inputs in;
        inputs_make(&in, &f);
        CHECK(fsf_filter_factored(&in.s, &in.grid, in.px, &in.gd, out));
        double worst = 0.0;
        for (size_t i = 0; i < n; ++i) worst = fmax(worst, fabs((double)out[4 * i] / out[4 * i + 3] - f.value4[4 * i]));
        printf("pinhole: largest difference from the pixel mean %.3g\n", worst);
        CHECK(worst < 1e-6);
        inputs_free(&in);
        plane_free(&f);
    }
    /* 4. the strip between two depths: the band (fsf_lens_sigma_u) narrows the width as the
     * samples grow, and the error falls; with the paper's fixed sigma_u = 1/2 (mu = 2 sigma_u
     * gives that width) the bias of the shear stays. The 4D filter (fsf_filter_brute, on
     * fsf_lens_params' widths) shows the model. The factored passes follow it: pass 1a's density
     * from the sample's own pixel, whose filter is narrow beside the strip, made them 1.8x its
     * error (0.020 rms at 64 and 256 spp, the far edge too bright) until each density was taken
     * over its mean and the gatherer's mean put back (fsf_density_mean) */
    {
        /* the band's closed form: 0.386 at 16 samples, falling as n^-1/3 */
        CHECK(fabsf(fsf_lens_sigma_u(16) - 0.3861f) < 1e-3f);
        CHECK(fabsf(fsf_lens_sigma_u(128) - 0.5f * fsf_lens_sigma_u(16)) < 1e-5f);
        const int seeds = 2;
        double mc16 = strip_rms(16, 0.0f, false, seeds), mc64 = strip_rms(64, 0.0f, false, seeds);
        double band16 = strip_rms(16, 1.0f, true, seeds), band64 = strip_rms(64, 1.0f, true, seeds);
        double fixed16 = strip_rms(16, 2.0f * fsf_lens_sigma_u(16), true, seeds);
        double fixed64 = strip_rms(64, 2.0f * fsf_lens_sigma_u(64), true, seeds);
        double f_band64 = strip_rms(64, 1.0f, false, seeds), f_band16 = strip_rms(16, 1.0f, false, seeds);
        double f_fixed64 = strip_rms(64, 2.0f * fsf_lens_sigma_u(64), false, seeds);
        printf("strip between two depths, rms error (16 / 64 spp): Monte Carlo %.4f / %.4f; 4D filter: band %.4f / "
               "%.4f, fixed band (1/2) %.4f / %.4f; factored: band %.4f / %.4f, fixed at 64 %.4f\n",
               mc16, mc64, band16, band64, fixed16, fixed64, f_band16, f_band64, f_fixed64);
        CHECK(band16 < 0.75 * mc16);
        /* the band's error falls with the samples (Monte Carlo's halves), the fixed band's stays */
        CHECK(band64 < 0.6 * band16);
        CHECK(fixed64 > 0.85 * fixed16);
        CHECK(band64 < 0.6 * fixed64);
        CHECK(f_band64 < 0.8 * f_fixed64);
        /* the factored passes within their discretisation of the 4D filter (0.92x and 0.95x of
         * its error here; the density from the sample's own filter gave 1.8x and 1.1x) */
        CHECK(f_band64 < 1.2 * band64);
        CHECK(f_band16 < 1.05 * band16);
    }
    free(out), free(brute);
    CHECK_DONE();
}
