/* FSF's indirect-light filter as two spatial passes (fsf_flat.h): on each pixel's value (its
 * samples' mean) and count, the same result as the four factored passes (fsf_filter_factored)
 * on its samples with the shear set to 0, up to rounding, on v-plane samples with per-pixel
 * widths (left out, narrow, at the cap), rotated gather directions, pixels that are not usable
 * and neighbours the guides reject; the shear it ignores; and the closed form of
 * test_fsf_bounce_factored (a receiver under a uniformly lit disk, whose irradiance is the
 * disk's view factor): within noise and far less noisy than the pixels' own means; NaN and
 * infinite channels of usable pixels filtered as 0 and counted (fsf_flat_nonfinite_inputs, which
 * FSF's warning reports), those of unusable pixels neither. */
#include "check.h"
#include "fsf_synth.h"
#include "recon/fsf/fsf_flat.h"

#include <string.h>

/* A 3 x 2 frame, each pixel a width of 1 px along x and y, no guides: non-finite channels of
 * usable pixels give what zeros give, bit for bit, and are counted; an unusable pixel's are not. */
static void check_nonfinite_inputs(const FsfGrid *g)
{
    enum { NW = 3, NH = 2, NP = NW * NH };
    unsigned char usable[NP] = {1, 1, 1, 1, 1, 0};
    int count[NP] = {4, 2, 7, 1, 3, 5};
    FsfPixel px[NP];
    memset(px, 0, sizeof px);
    float bad[4 * NP], zero[4 * NP];
    for (int i = 0; i < NP; ++i) {
        px[i].dir[0][0] = 1.0f, px[i].dir[1][1] = 1.0f, px[i].sigma_px[0] = px[i].sigma_px[1] = 1.0f;
        for (int c = 0; c < 4; ++c) bad[4 * i + c] = zero[4 * i + c] = 0.25f * (float)(i + c + 1);
    }
    bad[4 * 0 + 1] = NAN, zero[4 * 0 + 1] = 0.0f;
    bad[4 * 3 + 0] = INFINITY, zero[4 * 3 + 0] = 0.0f;
    bad[4 * 3 + 2] = -INFINITY, zero[4 * 3 + 2] = 0.0f;
    bad[4 * 5 + 0] = bad[4 * 5 + 1] = bad[4 * 5 + 2] = NAN; /* unusable: never read, not counted */
    CHECK(fsf_flat_nonfinite_inputs(bad, usable, NP) == 3);
    CHECK(fsf_flat_nonfinite_inputs(zero, usable, NP) == 0);
    FsfGuides gd = fsf_guides_unguided(usable);
    float out_bad[4 * NP], out_zero[4 * NP];
    CHECK(fsf_filter_flat(bad, count, NW, NH, g, px, &gd, out_bad));
    CHECK(fsf_filter_flat(zero, count, NW, NH, g, px, &gd, out_zero));
    CHECK(memcmp(out_bad, out_zero, sizeof out_bad) == 0);
}

enum { W = 48, H = 40, L = 4 };
static const float H_M = 0.2f, R_M = 1.0f, CX_M = 0.24f, CY_M = 0.20f;

/* The largest difference between the filtered values rgb / weight of a and b (pass 2b's
 * divisor, one per pixel, cancels there only); pixels whose weights are not both positive must
 * both be 0. */
static double worst_diff(const float *a, const float *b, size_t n)
{
    double worst = 0.0;
    for (size_t i = 0; i < n; ++i) {
        if (!(a[4 * i + 3] > 0.0f && b[4 * i + 3] > 0.0f)) {
            for (int c = 0; c < 4; ++c) worst = a[4 * i + c] == 0.0f && b[4 * i + c] == 0.0f ? worst : INFINITY;
            continue;
        }
        for (int c = 0; c < 3; ++c) {
            double d = fabs((double)a[4 * i + c] / a[4 * i + 3] - (double)b[4 * i + c] / b[4 * i + 3]);
            worst = isnan(d) ? INFINITY : fmax(worst, d);
        }
    }
    return worst;
}

/* Each pixel's value: its samples' mean (rgb; the pipeline's demodulated value, to which the
 * method scales the stored samples, fsf_match_pixel), so that count value is their sum. */
static void pixel_means(const FsfSynth *f, float *value4)
{
    for (size_t i = 0; i < (size_t)f->w * (size_t)f->h; ++i) {
        double sum[3] = {0, 0, 0};
        for (int k = 0; k < f->count[i]; ++k)
            for (int c = 0; c < 3; ++c) sum[c] += f->v[3 * (i * (size_t)f->cap + (size_t)k) + (size_t)c];
        for (int c = 0; c < 3; ++c) value4[4 * i + (size_t)c] = (float)(sum[c] / f->count[i]);
        value4[4 * i + 3] = 1.0f;
    }
}

int main(void)
{
    const size_t n = (size_t)W * H;
    const FsfGrid g = fsf_bounce_grid(); /* only its tap reach matters to the flat passes */
    float *flat = malloc(4 * n * sizeof(float)), *fact = malloc(4 * n * sizeof(float));
    float *value4 = malloc(4 * n * sizeof(float));
    FsfSynth f;
    fsf_synth_init(&f, W, H, L);
    fsf_synth_bounce_disk(&f, L, H_M, R_M, CX_M, CY_M, true, 1);

    /* (a) against the factored passes without shear: widths per pixel from 0 (left out) to
     * past the cap, gathers along directions turned by 0 to 40 degrees, a few unusable pixels
     * (NaN values: never read) and neighbours off the plane or turned away (rejected) */
    unsigned st = 7;
    for (size_t i = 0; i < n; ++i) {
        FsfPixel *p = &f.px[i];
        float turn = 0.7f * fsf_rand01(&st), c = cosf(turn), s = sinf(turn);
        p->dir[0][0] = c, p->dir[0][1] = s, p->dir[1][0] = -s, p->dir[1][1] = c;
        p->sigma_px[0] = i % 11 == 0 ? 0.0f : 20.0f * fsf_rand01(&st);
        p->sigma_px[1] = i % 13 == 0 ? 0.0f : 10.0f * fsf_rand01(&st);
        p->eta_m[0] = p->eta_m[1] = 0.0f;
        if (i % 17 == 5) f.usable[i] = 0;
        if (i % 19 == 3) f.pos4[4 * i + 2] = 1.0f;                  /* off the plane */
        if (i % 23 == 4) f.nrm4[4 * i] = 0.6f, f.nrm4[4 * i + 2] = 0.8f; /* turned 37 degrees */
    }
    fsf_synth_poison_unusable(&f);
    FsfGuides gd = fsf_guides_default(f.pos4, f.nrm4, f.usable);
    pixel_means(&f, value4);
    CHECK(fsf_filter_flat(value4, f.count, W, H, &g, f.px, &gd, flat));
    CHECK(fsf_filter_factored(&f.s, &g, f.px, &gd, fact));
    double diff = worst_diff(fact, flat, n);
    printf("flat vs factored without shear: largest difference %.3g (values 0.25 .. 1)\n", diff);
    CHECK(diff < 1e-5); /* rounding: sums of up to 33 x 33 pixels' 16 samples in other orders */
    size_t unusable_nonzero = 0, left_out_own = 0, left_out = 0;
    for (size_t i = 0; i < n; ++i) {
        for (int c = 0; c < 4; ++c) unusable_nonzero += !f.usable[i] && flat[4 * i + c] != 0.0f;
        if (f.usable[i] && f.px[i].sigma_px[0] == 0.0f && f.px[i].sigma_px[1] == 0.0f) {
            ++left_out;
            left_out_own += flat[4 * i + 3] == (float)f.count[i];
        }
    }
    CHECK(unusable_nonzero == 0);
    CHECK(left_out > 0 && left_out_own == left_out); /* a pixel left out: its own samples */

    /* (b) the shear is not read */
    for (size_t i = 0; i < n; ++i) f.px[i].eta_m[0] = 0.02f, f.px[i].eta_m[1] = -0.03f;
    float *sheared = malloc(4 * n * sizeof(float));
    CHECK(fsf_filter_flat(value4, f.count, W, H, &g, f.px, &gd, sheared));
    CHECK(memcmp(sheared, flat, 4 * n * sizeof(float)) == 0);
    free(sheared);

    /* (c) the disk's view factor (test_fsf_bounce_factored's set-up: every pixel usable on the
     * plane, sigma 4 x 3): unbiased within noise, 5x less rms error than the pixels' own means */
    fsf_synth_free(&f);
    fsf_synth_init(&f, W, H, L);
    for (size_t i = 0; i < n; ++i) f.px[i].sigma_px[0] = 4.0f, f.px[i].sigma_px[1] = 3.0f;
    gd = fsf_guides_default(f.pos4, f.nrm4, f.usable);
    double mean_bias = 0.0;
    for (unsigned seed = 1; seed <= 4; ++seed) {
        fsf_synth_bounce_disk(&f, L, H_M, R_M, CX_M, CY_M, true, seed);
        pixel_means(&f, value4);
        CHECK(fsf_filter_flat(value4, f.count, W, H, &g, f.px, &gd, flat));
        FsfDiskErr e = fsf_disk_errors(&f, flat, H_M, R_M, CX_M, CY_M);
        printf("seed %u: filtered - view factor: mean %+.5f rms %.5f (own means rms %.5f)\n", seed, e.mean, e.rms,
               e.rms_own);
        CHECK(e.rms < e.rms_own / 5.0);
        mean_bias += e.mean / 4.0;
    }
    printf("mean error over 4 seeds %+.5f\n", mean_bias);
    CHECK(fabs(mean_bias) < 0.004);
    check_nonfinite_inputs(&g);
    free(flat), free(fact), free(value4);
    fsf_synth_free(&f);
    CHECK_DONE();
}
