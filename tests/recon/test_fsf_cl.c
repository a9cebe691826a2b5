/* FSF's OpenCL kernels (fsf.cl) against the C passes (fsf_filter.c) on the same synthetic
 * samples: a varying shear, width and gather direction field and some rejected pixels, so
 * that every branch of the kernels runs; then the same on indirect-light samples
 * (fsf_bounce.h's grid, v-plane coordinates clamped inside the box). Skipped (77) without an
 * OpenCL device. */
#include <string.h>

#include "cl_test_device.h"
#include "check.h"
#include "fsf_synth.h"
#include "recon/fsf/fsf_cl.h"
#include "recon/fsf/fsf_light.h"

/* The largest |OpenCL - C| over f's pixels relative to the pixel's weight (rgb and weight);
 * geo: the light's geometric term (form 4 in passes 1a and 2a) or NULL. */
static double cl_vs_c(FsfCl *cl, const FsfSynth *f, const FsfGrid *g, const FsfGeoTerm *geo, double *secs)
{
    FsfGuides gd = fsf_guides_default(f->pos4, f->nrm4, f->usable);
    gd.geo = geo;
    size_t n = (size_t)f->w * (size_t)f->h;
    float *c_out = malloc(4 * n * sizeof(float)), *cl_out = malloc(4 * n * sizeof(float));
    Diag d = {0};
    bool ok = cl && fsf_filter_factored(&f->s, g, f->px, &gd, c_out) && fsf_cl_run(cl, &f->s, g, f->px, &gd, cl_out, secs, &d);
    double worst = ok ? 0.0 : INFINITY;
    for (size_t i = 0; ok && i < n; ++i)
        for (int c = 0; c < 4; ++c)
            worst = fmax(worst, fabs((double)c_out[4 * i + c] - cl_out[4 * i + c]) / fmax(fabs(c_out[4 * i + 3]), 1e-3));
    free(c_out), free(cl_out);
    return worst;
}

/* Indirect-light samples (a receiver under a lit disk whose rim crosses the box's edge) with
 * shears and widths varying as fsf_bounce_params makes them: both signs, up to the parallax
 * bound's 1 v over the taps, some pixels left out. */
static void indirect_samples(FsfCl *cl)
{
    const int W = 45, H = 38, l = 4;
    FsfSynth f;
    fsf_synth_init(&f, W, H, l);
    fsf_synth_bounce_disk(&f, l, 0.2f, 1.0f, 0.2f, 0.15f, true, 3);
    for (int i = 0; i < W * H; ++i) {
        float x = (float)(i % W) / W, y = (float)(i / W) / H, ang = 0.4f * y;
        if (i % 9 == 4) f.count[i] = 7;
        if (i % 29 == 3) f.usable[i] = 0;
        f.px[i].dir[0][0] = cosf(ang), f.px[i].dir[0][1] = sinf(ang);
        f.px[i].dir[1][0] = -sinf(ang), f.px[i].dir[1][1] = cosf(ang);
        f.px[i].eta_m[0] = 0.02f + 0.05f * x, f.px[i].eta_m[1] = (i % 3 == 0 ? -1.0f : 1.0f) * 0.04f * y;
        f.px[i].sigma_px[0] = i % 13 == 0 ? 0.0f : 0.5f + 7.5f * y;
        f.px[i].sigma_px[1] = 1.0f + 6.0f * x;
    }
    FsfGrid g = fsf_bounce_grid();
    double secs = 0.0, worst = cl_vs_c(cl, &f, &g, NULL, &secs);
    printf("indirect samples: OpenCL against C: largest difference %.3g of the pixel's weight (kernels %.4f s)\n", worst,
           secs);
    CHECK(worst < 1e-5); /* rounding only, as below (4e-7 measured) */
    /* a flat receiver's guides accept every usable neighbour, so guides that are not read
     * (fsf_guides_unguided, defocus') give the same floats, on the device and in C */
    {
        size_t n = (size_t)W * H;
        float *out[4];
        FsfGuides gd[2] = {fsf_guides_default(f.pos4, f.nrm4, f.usable), fsf_guides_unguided(f.usable)};
        Diag d = {0};
        for (int k = 0; k < 4; ++k) out[k] = malloc(4 * n * sizeof(float));
        for (int k = 0; k < 2; ++k) {
            CHECK(fsf_cl_run(cl, &f.s, &g, f.px, &gd[k], out[k], NULL, &d));
            CHECK(fsf_filter_factored(&f.s, &g, f.px, &gd[k], out[2 + k]));
        }
        CHECK(memcmp(out[0], out[1], 4 * n * sizeof(float)) == 0);
        CHECK(memcmp(out[2], out[3], 4 * n * sizeof(float)) == 0);
        for (int k = 0; k < 4; ++k) free(out[k]);
    }
    fsf_synth_free(&f);
}

/* A W x H frame of 4 x 4 light samples per pixel (light_seed) with noisy values (noise_seed),
 * on a light of half extents 0.6 m: the directions, shears and widths are the caller's. */
static FsfGrid noisy_frame(FsfSynth *f, int W, int H, unsigned light_seed, unsigned noise_seed)
{
    fsf_synth_init(f, W, H, 4);
    FsfGrid g = fsf_grid_default(0.6f, 0.6f);
    fsf_synth_light(f, &g, 4, false, light_seed);
    unsigned st = noise_seed;
    for (size_t v = 0; v < 3 * (size_t)W * H * (size_t)f->cap; ++v) f->v[v] = fsf_rand01(&st);
    return g;
}

/* A frame taller than pass 1's ring of P rows (fsf_cl.c: bands of 8 rows, a ring of the band
 * and twice the largest halo, here 16 rows), 23 px wide so that no band is a whole number of 64-item work groups, with
 * first-axis gathers turning from horizontal to vertical (taps reaching the full 16 rows up
 * and down, across band and ring boundaries) at the widest width. A tap read from a stale or
 * unfilled ring row would differ by a whole sample's weight. */
static void tall_frame(FsfCl *cl)
{
    const int W = 23, H = 150;
    FsfSynth f;
    FsfGrid g = noisy_frame(&f, W, H, 7, 9);
    for (int i = 0; i < W * H; ++i) {
        float x = (float)(i % W) / W, y = (float)(i / W) / H;
        float ang = 1.5707964f * (0.5f + 0.5f * sinf(7.0f * y + 3.0f * x));
        f.px[i].dir[0][0] = cosf(ang), f.px[i].dir[0][1] = sinf(ang);
        f.px[i].dir[1][0] = -sinf(ang), f.px[i].dir[1][1] = cosf(ang);
        f.px[i].eta_m[0] = (i % 2 ? 0.03f : -0.02f) * (0.5f + y), f.px[i].eta_m[1] = 0.02f * x;
        f.px[i].sigma_px[0] = i % 19 == 0 ? 0.0f : 8.0f - 4.0f * x;
        f.px[i].sigma_px[1] = 3.0f;
        if (i % 23 == 11) f.usable[i] = 0;
    }
    double secs = 0.0, worst = cl_vs_c(cl, &f, &g, NULL, &secs);
    printf("150 rows (pass 1 in bands): OpenCL against C: largest difference %.3g of the pixel's weight\n", worst);
    CHECK(worst < 1e-5);
    fsf_synth_free(&f);
}

/* Bands whose halos differ (fsf_cl.c's band_halo_rows): rows 0-29 gather exactly along the
 * rows on the first axis (defocus' screen axes: halo 0, P's ring is the band alone), rows
 * 30-59 nearly so (one row of reach), rows 60-89 along the columns (16 rows, reaching back
 * into the bands without a halo); the second axis turns the other way. Widths from 0 (a
 * pixel left out: 8 slots in the packed tap tables) to the cap (40) side by side. A halo too
 * small reads a stale ring row, a packed table too short overwrites the next pixel's taps:
 * either differs by a whole sample's weight. */
static void mixed_halos(FsfCl *cl)
{
    const int W = 31, H = 90;
    FsfSynth f;
    FsfGrid g = noisy_frame(&f, W, H, 13, 17);
    for (int i = 0; i < W * H; ++i) {
        int x = i % W, y = i / W;
        float ang = y < 30 ? 0.0f : y < 60 ? 0.05f : 1.5707964f;
        f.px[i].dir[0][0] = y < 30 ? 1.0f : cosf(ang), f.px[i].dir[0][1] = y < 30 ? 0.0f : sinf(ang);
        f.px[i].dir[1][0] = -f.px[i].dir[0][1], f.px[i].dir[1][1] = f.px[i].dir[0][0];
        f.px[i].eta_m[0] = (i % 2 ? 0.03f : -0.02f), f.px[i].eta_m[1] = 0.01f * (float)(x % 5);
        f.px[i].sigma_px[0] = x % 3 == 0 ? 0.0f : x % 3 == 1 ? 8.0f : 1.5f;
        f.px[i].sigma_px[1] = y % 4 == 0 ? 0.0f : 0.5f + 0.25f * (float)(x % 31);
        if (i % 37 == 7) f.usable[i] = 0;
    }
    double secs = 0.0, worst = cl_vs_c(cl, &f, &g, NULL, &secs);
    printf("bands with halos 0, 1 and 16, packed taps: OpenCL against C: largest difference %.3g\n", worst);
    CHECK(worst < 1e-5);
    fsf_synth_free(&f);
}

/* fsf_cl.c keeps its scratch buffers and tap offsets from one run to the next: a frame run
 * after larger ones (whose data fills those buffers) gives the floats a fresh FsfCl gives, bit
 * for bit. */
static void kept_buffers(ClRuntime *rt, FsfCl *used)
{
    const int W = 29, H = 41;
    FsfSynth f;
    FsfGrid g = noisy_frame(&f, W, H, 21, 23);
    for (int i = 0; i < W * H; ++i) {
        float x = (float)(i % W) / W, y = (float)(i / W) / H, ang = 1.2f * x * y;
        f.px[i].dir[0][0] = cosf(ang), f.px[i].dir[0][1] = sinf(ang);
        f.px[i].dir[1][0] = -sinf(ang), f.px[i].dir[1][1] = cosf(ang);
        f.px[i].eta_m[0] = 0.04f * (y - 0.3f), f.px[i].eta_m[1] = 0.02f * x;
        f.px[i].sigma_px[0] = i % 7 == 0 ? 0.0f : 1.0f + 5.0f * y;
        f.px[i].sigma_px[1] = 0.5f + 6.0f * x;
        if (i % 11 == 6) f.usable[i] = 0;
    }
    size_t n = (size_t)W * H;
    float *kept = malloc(4 * n * sizeof(float)), *fresh_out = malloc(4 * n * sizeof(float));
    FsfGuides gd = fsf_guides_default(f.pos4, f.nrm4, f.usable);
    Diag d = {0};
    FsfCl *fresh = fsf_cl_create(rt, &d);
    CHECK(fresh && fsf_cl_run(used, &f.s, &g, f.px, &gd, kept, NULL, &d) &&
          fsf_cl_run(fresh, &f.s, &g, f.px, &gd, fresh_out, NULL, &d));
    long long differ = 0;
    for (size_t e = 0; e < 4 * n; ++e) differ += memcmp(&kept[e], &fresh_out[e], sizeof(float)) != 0;
    printf("after larger frames, against a fresh FsfCl: %lld of %zu values differ\n", differ, 4 * n);
    CHECK(differ == 0);
    fsf_cl_destroy(fresh);
    free(kept), free(fresh_out);
    fsf_synth_free(&f);
}

int main(void)
{
    Diag d = {0};
    ClRuntime *rt = cl_test_device_or_skip();
    FsfCl *cl = fsf_cl_create(rt, &d);
    CHECK(cl != NULL);
    const int W = 53, H = 37, l = 4;
    FsfSynth f;
    fsf_synth_init(&f, W, H, l);
    FsfGrid g = fsf_grid_default(0.7f, 0.5f);
    fsf_synth_light(&f, &g, l, false, 11);
    unsigned st = 5;
    for (int i = 0; i < W * H; ++i) {
        float x = (float)(i % W) / W, y = (float)(i / W) / H;
        for (int k = 0; k < f.cap; ++k) {
            size_t slot = (size_t)i * f.cap + (size_t)k;
            float lit = f.y[2 * slot] - 0.2f * f.y[2 * slot + 1] > 0.4f * (x - 0.5f) ? 1.0f : 0.0f;
            f.v[3 * slot] = lit, f.v[3 * slot + 1] = 0.3f + lit, f.v[3 * slot + 2] = fsf_rand01(&st);
        }
        if (i % 7 == 3) f.count[i] = 9;         /* fewer samples than slots */
        if (i % 31 == 5) f.usable[i] = 0;       /* passed through, never a source */
        if (i % 17 == 2) f.nrm4[4 * i + 2] = -1; /* another orientation: rejected */
        float ang = 0.3f * x;
        f.px[i].dir[0][0] = cosf(ang), f.px[i].dir[0][1] = sinf(ang);
        f.px[i].dir[1][0] = -sinf(ang), f.px[i].dir[1][1] = cosf(ang);
        f.px[i].eta_m[0] = 0.01f + 0.05f * y, f.px[i].eta_m[1] = 0.03f * x;
        /* pass 1a's densities without a shear and with the opposite one (fsf.cl has its own
         * branch for eta 0 and orders the interval ends of a negative eta) */
        if (i % 13 == 4) f.px[i].eta_m[0] = 0.0f;
        if (i % 5 == 1) f.px[i].eta_m[0] = -f.px[i].eta_m[0], f.px[i].eta_m[1] = -f.px[i].eta_m[1];
        f.px[i].sigma_px[0] = i % 11 == 0 ? 0.0f : 1.0f + 7.0f * x;
        f.px[i].sigma_px[1] = 2.0f + 5.0f * y;
    }
    /* the default grid (16 bins: pass 1a fills 4 slices per launch here), one whose bins do
     * not divide into those launches (10: 4 + 4 + 2), one whose samples reach 17 nodes
     * (three float8 chunks in 1a, 96 densities in 2a), and the shadows' (fsf_light_grid: 12
     * bins, taps to 1.5 sigma, which the kernels take from FsfGrid.reach_sigmas as the C passes
     * do: a kernel reaching 2 sigma overruns the packed tap tables, differences of hundreds of
     * a pixel's weight) */
    const int nodes[4] = {17, 11, 33, FSF_LIGHT_SHIFT_NODES};
    const float reach[4] = {FSF_RADIUS_SIGMAS, FSF_RADIUS_SIGMAS, FSF_RADIUS_SIGMAS, FSF_REACH_SIGMAS_NARROW};
    for (int gi = 0; gi < 4; ++gi) {
        g.shift_nodes = nodes[gi], g.y2_bins = nodes[gi] - 1, g.reach_sigmas = reach[gi];
        double secs = 0.0, worst = cl_vs_c(cl, &f, &g, NULL, &secs);
        printf("%d shift nodes, taps to %.1f sigma: OpenCL against C: largest difference %.3g of the pixel's weight "
               "(kernels %.4f s)\n",
               nodes[gi], reach[gi], worst, secs);
        /* the same float arithmetic in another order and exp vs expf: rounding only (3e-7
         * measured; a node or tap lost or shifted would show as a whole sample's weight, ~1e-2) */
        CHECK(worst < 1e-5);
        /* form 4 (fsf_geo_term.h) in passes 1a and 2a: a light as large as the frame 0.4 m above it, so
         * that its geometric term varies about 3:1 over the light; the pixels whose normal
         * turns away get no mean term and keep the plain weight */
        float *mean_g = malloc((size_t)W * H * sizeof(float));
        FsfGeoTerm geo = fsf_synth_geo(&f, &g, 0.26f, 0.18f, 0.4f, mean_g);
        double worst_geo = cl_vs_c(cl, &f, &g, &geo, &secs);
        printf("%d shift nodes, with the geometric term: OpenCL against C: largest difference %.3g\n", nodes[gi],
               worst_geo);
        CHECK(worst_geo < 1e-5);
        /* a light that moves (fsf_swept_profile): its samples' density ramps along both axes,
         * in passes 1a and 2b's weights and form 4's mean and marginals; the samples stay where
         * they are (the kernels and the C passes read the same ones) */
        FsfGrid swept = g;
        swept.ramp_m[0] = 0.5f, swept.ramp_m[1] = 0.3f;
        FsfGeoTerm geo_swept = geo;
        geo_swept.ramp_m[0] = swept.ramp_m[0], geo_swept.ramp_m[1] = swept.ramp_m[1];
        fsf_geo_mean(&geo_swept, f.pos4, f.nrm4, f.usable, swept.half_m, (size_t)W * H, mean_g);
        double worst_swept = cl_vs_c(cl, &f, &swept, NULL, &secs), worst_swept_geo = cl_vs_c(cl, &f, &swept, &geo_swept, &secs);
        printf("%d shift nodes, a moving light's density: OpenCL against C: largest difference %.3g, %.3g with the "
               "geometric term\n",
               nodes[gi], worst_swept, worst_swept_geo);
        CHECK(worst_swept < 1e-5 && worst_swept_geo < 1e-5);
        free(mean_g);
    }
    /* pixels that are not usable are skipped by every kernel: NaN in their samples changes no
     * usable pixel's result (bit for bit) and theirs stay 0 */
    {
        size_t n = (size_t)W * H;
        float *clean = malloc(4 * n * sizeof(float)), *poisoned = malloc(4 * n * sizeof(float));
        FsfGuides gd = fsf_guides_default(f.pos4, f.nrm4, f.usable);
        CHECK(fsf_cl_run(cl, &f.s, &g, f.px, &gd, clean, NULL, &d));
        fsf_synth_poison_unusable(&f);
        CHECK(fsf_cl_run(cl, &f.s, &g, f.px, &gd, poisoned, NULL, &d));
        long long changed = 0, nonzero = 0;
        for (size_t e = 0; e < 4 * n; ++e) {
            if (f.usable[e / 4]) changed += memcmp(&clean[e], &poisoned[e], sizeof(float)) != 0;
            else nonzero += poisoned[e] != 0.0f;
        }
        printf("unusable pixels' samples set to NaN: %lld usable values changed, %lld unusable values not 0\n", changed,
               nonzero);
        CHECK(changed == 0 && nonzero == 0);
        free(clean), free(poisoned);
    }
    fsf_synth_free(&f);
    indirect_samples(cl);
    tall_frame(cl);
    mixed_halos(cl);
    kept_buffers(rt, cl);
    fsf_cl_destroy(cl);
    cl_runtime_destroy(rt);
    return check_failures ? 1 : 0;
}
