/* The factored FSF filter (four 1D passes, FSF eqs. 12-15) against the brute-force 4D sum
 * (FSF eq. 9): equal where the factoring loses nothing, converging with the bin count where
 * it discretises, and close where only the separation into two 2D filters differs. */
#include <string.h>

#include "check.h"
#include "fsf_synth.h"

/* Largest |factored - brute| relative to the brute-force weight, over rgb and weight. */
static double max_rel_diff(const FsfSynth *f, const FsfGrid *g)
{
    size_t n = (size_t)f->w * (size_t)f->h;
    float *a = malloc(4 * n * sizeof(float)), *b = malloc(4 * n * sizeof(float));
    FsfGuides gd = fsf_guides_default(f->pos4, f->nrm4, f->usable);
    fsf_filter_brute(&f->s, g, f->px, &gd, a);
    bool ok = fsf_filter_factored(&f->s, g, f->px, &gd, b);
    double worst = ok ? 0.0 : INFINITY;
    for (size_t i = 0; ok && i < n; ++i)
        for (int c = 0; c < 4; ++c) {
            double d = fabs((double)a[4 * i + c] - b[4 * i + c]) / fmax(a[4 * i + 3], 1e-6);
            if (d > worst) worst = d;
        }
    free(a), free(b);
    return worst;
}

/* RMS over pixels of the difference of the normalised results (rgb / weight, channel 0). */
static double rms_normalised(const FsfSynth *f, const FsfGrid *g)
{
    size_t n = (size_t)f->w * (size_t)f->h;
    float *a = malloc(4 * n * sizeof(float)), *b = malloc(4 * n * sizeof(float));
    FsfGuides gd = fsf_guides_default(f->pos4, f->nrm4, f->usable);
    fsf_filter_brute(&f->s, g, f->px, &gd, a);
    bool ok = fsf_filter_factored(&f->s, g, f->px, &gd, b);
    double sum = 0.0;
    for (size_t i = 0; i < n; ++i) {
        double d = (double)a[4 * i] / a[4 * i + 3] - (double)b[4 * i] / b[4 * i + 3];
        sum += d * d;
    }
    free(a), free(b);
    return ok ? sqrt(sum / (double)n) : INFINITY;
}

/* Values: a soft edge at a slanted line, so every pixel's samples differ. */
static void values_edge(FsfSynth *f, float k_m_per_px)
{
    size_t n = (size_t)f->w * (size_t)f->h;
    for (size_t i = 0; i < n; ++i) {
        float x = (float)(i % (size_t)f->w) - 0.5f * (float)f->w, y = (float)(i / (size_t)f->w);
        for (int s = 0; s < f->cap; ++s) {
            size_t slot = i * (size_t)f->cap + (size_t)s;
            float y1 = f->y[2 * slot], y2 = f->y[2 * slot + 1];
            float vis = y1 + 0.3f * y2 > -k_m_per_px * (x + 0.2f * y) ? 1.0f : 0.0f;
            f->v[3 * slot] = vis, f->v[3 * slot + 1] = 0.5f * vis, f->v[3 * slot + 2] = 0.25f + 0.5f * vis;
        }
    }
}

static void uniform_params(FsfSynth *f, float eta1, float eta2, float sigma1, float sigma2)
{
    for (int i = 0; i < f->w * f->h; ++i) {
        f->px[i].eta_m[0] = eta1, f->px[i].eta_m[1] = eta2;
        f->px[i].sigma_px[0] = sigma1, f->px[i].sigma_px[1] = sigma2;
    }
}

/* fsf_density's run of taps (|z - eta t| <= L, its ends (z -+ L) / eta rounded inwards) against
 * the taps counted one by one in double: over many coordinates and shears the run may differ
 * only by an end tap, and only where that tap's bound is within a few float ulps of the
 * integer (the float quotient's rounding); with no shear it keeps every tap or none. */
static void density_run(void)
{
    const float L = 0.6f, sigma = 5.0f;
    int r = fsf_radius_reach(sigma, FSF_RADIUS_SIGMAS);
    float cum[FSF_CUM];
    fsf_tap_prefix(sigma, r, cum);
    unsigned st = 5;
    long long tried = 0, moved = 0, far = 0, moved_random = 0;
    for (int k = 0; k < 200000; ++k) {
        float eta = (fsf_rand01(&st) - 0.5f) * 0.4f, z = (fsf_rand01(&st) * 2.0f - 1.0f) * 2.0f * L;
        if (k % 4 == 0) /* a bound on an integer, the quotient's rounding at stake */
            z = (float)((int)(fsf_rand01(&st) * 2.0f * (float)r) - r) * eta + L;
        if (eta == 0.0f) continue;
        double lo = ((double)z - L) / eta, hi = ((double)z + L) / eta, a = lo < hi ? lo : hi, b = lo < hi ? hi : lo;
        double near_tol = 8.0 * 1.2e-7 * (fabs(a) + fabs(b) + 1.0), exact = 0.0;
        int near = 0;
        for (int t = -r; t <= r; ++t) {
            if ((double)t >= a && (double)t <= b) exact += cum[t + r + 1] - cum[t + r];
            near |= fabs(t - a) <= near_tol || fabs(t - b) <= near_tol;
        }
        double diff = fabs(fsf_density(z, eta, L, r, cum) - exact);
        ++tried;
        if (diff > 1e-5) ++moved, far += !near, moved_random += k % 4 != 0;
    }
    printf("density: %lld of %lld runs differ from the exact count (%lld of the random ones), %lld of them not at a "
           "bound within 8 ulp of a tap\n",
           moved, tried, moved_random, far);
    CHECK(far == 0);
    CHECK(moved_random * 1000 < tried); /* away from the constructed bounds a run end almost never sits on a tap */
    /* no shear: every tap or none */
    CHECK(fsf_density(0.1f, 0.0f, L, r, cum) == cum[2 * r + 1] - cum[0]);
    CHECK(fsf_density(0.7f, 0.0f, L, r, cum) == 0.0f);
}

/* fsf_density_mean against the mean of fsf_density over the profile box by quadrature, for
 * shears and widths from none to wide, a profile narrower than the grid (the lens') and as wide
 * (the light's); and at least 1 (the centre tap covers the box). */
static void density_mean(void)
{
    double worst = 0.0;
    for (int shape = 0; shape < 2; ++shape) {
        FsfGrid g = fsf_grid_default(1.0f, 1.0f);
        if (shape) g.profile_half[0] = 0.8862269f;
        const float etas[] = {0.0f, -0.05f, 0.13f, -0.4f, 1.7f}, sigmas[] = {0.0f, 0.7f, 3.0f, 8.0f};
        for (int a = 0; a < 5; ++a)
            for (int b = 0; b < 4; ++b) {
                float cum[FSF_CUM], h = g.profile_half[0];
                int r = fsf_tap_radius(&g, sigmas[b]);
                fsf_tap_prefix(sigmas[b], r, cum);
                const int steps = 20000;
                double sum = 0.0;
                for (int k = 0; k < steps; ++k)
                    sum += fsf_density(-h + 2.0f * h * ((float)k + 0.5f) / (float)steps, etas[a], g.half_m[0], r, cum);
                double want = sum / steps, got = fsf_density_mean(&g, 0, etas[a], sigmas[b]);
                worst = fmax(worst, fabs(got - want) / want);
                CHECK(got >= 1.0f - 1e-6f);
            }
    }
    printf("density mean: largest relative difference from quadrature %.3g\n", worst);
    CHECK(worst < 1e-3); /* the quadrature's steps of 1e-4 of the box against breaks in rho */
}

int main(void)
{
    density_run();
    density_mean();

    const int W = 48, H = 40, l = 4;
    FsfSynth f;
    fsf_synth_init(&f, W, H, l);
    FsfGrid g = fsf_grid_default(0.8f, 0.6f);

    /* 1. Exact case: samples at y2-bin centres, shears that land on shift-grid nodes at every
     * step (eta = m * node spacing), one parameter set for the whole image, a flat receiver:
     * the factored passes are a reordering of the brute-force sum (float rounding only). */
    fsf_synth_light(&f, &g, l, true, 1);
    values_edge(&f, 0.02f);
    float dY1 = 4.0f * g.half_m[0] / (float)(g.shift_nodes - 1), dY2 = 4.0f * g.half_m[1] / (float)(g.shift_nodes - 1);
    uniform_params(&f, dY1, -2.0f * dY2, 3.0f, 5.0f);
    double exact = max_rel_diff(&f, &g);
    printf("bin-centred, on-node shears: max relative difference %.3g\n", exact);
    CHECK(exact < 1e-5);
    /* the same with the shadows' and the lens' taps to 1.5 sigma (FsfGrid.reach_sigmas): the
     * oracle and the passes stop at the same tap */
    {
        FsfGrid narrow = g;
        narrow.reach_sigmas = FSF_REACH_SIGMAS_NARROW;
        double exact_narrow = max_rel_diff(&f, &narrow);
        printf("bin-centred, on-node shears, taps to 1.5 sigma: max relative difference %.3g\n", exact_narrow);
        CHECK(exact_narrow < 1e-5);
    }
    /* pixels left out (sigma 0) get their own samples' sum in both */
    uniform_params(&f, dY1, dY2, 0.0f, 0.0f);
    CHECK(max_rel_diff(&f, &g) < 1e-6);

    /* fsf_scale_samples: the scaled values, and a product that overflows or is NaN written as
     * 0 and counted, never passed on or dropped unsaid */
    {
        const float rgb[6] = {1.0f, 2.0f, 3.0f, 3.0e38f, NAN, 0.5f}, scale[3] = {2.0f, 4.0f, 0.5f};
        float out[6];
        long long bad = fsf_scale_samples(rgb, 2, scale, out);
        CHECK(bad == 2);
        CHECK(out[0] == 2.0f && out[1] == 8.0f && out[2] == 1.5f);
        CHECK(out[3] == 0.0f && out[4] == 0.0f && out[5] == 0.25f);
        /* a pixel's worth of samples (the vectorised body, not only its tail): each value as the
         * product one at a time, every 7th value NaN, infinite or overflowing in turn */
        enum { K = 37 };
        float many[3 * K], got[3 * K];
        long long want_bad = 0, differ = 0;
        const float odd[4] = {NAN, 3.0e38f, INFINITY, -INFINITY};
        for (int e = 0; e < 3 * K; ++e) many[e] = e % 7 == 3 ? odd[(e / 7) % 4] : 0.1f * (float)e - 1.0f;
        bad = fsf_scale_samples(many, K, scale, got);
        for (int e = 0; e < 3 * K; ++e) {
            float v = many[e] * scale[e % 3], want = isfinite(v) ? v : 0.0f;
            want_bad += !isfinite(v);
            differ += memcmp(&want, &got[e], sizeof want) != 0;
        }
        CHECK(bad == want_bad && want_bad > 0 && differ == 0);
    }

    /* 2. Jittered samples and a shear between nodes: the factored filter discretises y1 (the
     * shift grid, linear between nodes) and y2 (bin centres); its difference from the brute
     * force shrinks as the grids refine. */
    fsf_synth_light(&f, &g, l, false, 7);
    values_edge(&f, 0.02f);
    uniform_params(&f, 0.037f, 0.029f, 4.0f, 4.0f);
    double prev = INFINITY;
    const int nodes[3] = {9, 17, 65};
    for (int r = 0; r < 3; ++r) {
        FsfGrid gr = g;
        gr.shift_nodes = nodes[r];
        gr.y2_bins = nodes[r] - 1;
        double e = rms_normalised(&f, &gr);
        printf("%d shift nodes, %d y2 bins: rms difference %.4f\n", gr.shift_nodes, gr.y2_bins, e);
        CHECK(e < prev);
        if (r == 1) CHECK(e < 0.02); /* the default grid: within 2% of the light (penumbra units) */
        prev = e;
    }
    CHECK(prev < 0.006);

    /* 3. The separation alone: bin-centred samples, on-node shears, but a width that varies
     * smoothly over the image. The second pass then uses each intermediate pixel's own width
     * for the first axis (FSF section 4.2: exact only for a constant filter); on a smooth
     * field the difference stays small. */
    fsf_synth_light(&f, &g, l, true, 1);
    values_edge(&f, 0.02f);
    for (int i = 0; i < W * H; ++i) {
        /* the first axis' width varies along the second axis: pass 2b gathers pixels
         * whose pass 1b used another width than the centre's */
        float y = (float)(i / W) / (float)H;
        f.px[i].eta_m[0] = dY1, f.px[i].eta_m[1] = dY2;
        f.px[i].sigma_px[0] = 3.0f + 2.0f * y, f.px[i].sigma_px[1] = 3.0f;
    }
    double sep = rms_normalised(&f, &g);
    printf("smoothly varying width: rms separation difference %.5f\n", sep);
    CHECK(sep > 0.0 && sep < 0.01); /* > 0: the case does exercise the separation */

    /* 3b. The second axis's density at the gathering pixel: as case 1 (exact), but the second
     * axis's width and on-node shear vary from pixel to pixel. Pass 2b divides by the density
     * of the gathering pixel's own filter, as the brute force does, so the two still agree to
     * rounding (with pass 2a's density, the intermediate pixel's filter, by up to 0.95 of a
     * pixel's weight). */
    fsf_synth_light(&f, &g, l, true, 1);
    values_edge(&f, 0.02f);
    for (int i = 0; i < W * H; ++i) {
        int x = i % W, y = i / W;
        f.px[i].eta_m[0] = dY1, f.px[i].eta_m[1] = (float)(1 + (x / 5 + y / 7) % 3) * dY2;
        f.px[i].sigma_px[0] = 3.0f, f.px[i].sigma_px[1] = 1.5f + 0.25f * (float)((x + 2 * y) % 13);
    }
    double dens2 = max_rel_diff(&f, &g);
    printf("second axis's width and shear varying per pixel: max relative difference %.3g\n", dens2);
    CHECK(dens2 < 1e-5);

    /* 4. Pixels that are not usable (no surface, mixed, another light's): nobody's neighbour
     * and their result unused, so no pass reads their samples: with NaN in those samples the
     * usable pixels' results are bit for bit the same, and theirs are 0, in both filters. */
    fsf_synth_light(&f, &g, l, true, 1);
    values_edge(&f, 0.02f);
    uniform_params(&f, dY1, -2.0f * dY2, 3.0f, 5.0f);
    for (int i = 0; i < W * H; ++i) f.usable[i] = i % 7 != 3 && !(i / W > 30 && i % W < 12);
    {
        size_t n = (size_t)W * H;
        float *out[2][2];
        FsfGuides gd = fsf_guides_default(f.pos4, f.nrm4, f.usable);
        for (int pass = 0; pass < 2; ++pass) {
            if (pass == 1) fsf_synth_poison_unusable(&f);
            out[pass][0] = malloc(4 * n * sizeof(float)), out[pass][1] = malloc(4 * n * sizeof(float));
            fsf_filter_brute(&f.s, &g, f.px, &gd, out[pass][0]);
            CHECK(fsf_filter_factored(&f.s, &g, f.px, &gd, out[pass][1]));
        }
        long long changed = 0, nonzero = 0;
        for (size_t i = 0; i < n; ++i)
            for (int c = 0; c < 4; ++c)
                for (int m = 0; m < 2; ++m) {
                    if (f.usable[i]) changed += memcmp(&out[0][m][4 * i + c], &out[1][m][4 * i + c], sizeof(float)) != 0;
                    else nonzero += out[1][m][4 * i + c] != 0.0f;
                }
        printf("unusable pixels' samples set to NaN: %lld usable values changed, %lld unusable values not 0\n", changed,
               nonzero);
        CHECK(changed == 0 && nonzero == 0);
        for (int pass = 0; pass < 2; ++pass) free(out[pass][0]), free(out[pass][1]);
    }

    fsf_synth_free(&f);
    return check_failures ? 1 : 0;
}
