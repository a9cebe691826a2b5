/* Benchmark (not a test): the factored FSF filter (four 1D passes) against the brute-force
 * 4D sum on the same synthetic samples (fsf_synth.h), W x H pixels, 16 samples per pixel,
 * a 33-pixel footprint (sigma 8, the paper's cap) on both axes, the default grid (17 shift
 * nodes, 16 y2 bins). Warm: one untimed run, then the median of 3. Both use recon_parallel_for (2 cores).
 * FSF section 6 reports 40-50x for its GPU implementation. Then the OpenCL passes: the median
 * of 7 warm runs of fsf_cl_run and, per kernel (fsf_cl_profile), the median and the fastest.
 * Usage: bench_fsf [W H [factored|cl]] (factored: the C passes alone; cl: the OpenCL alone) */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "fsf_synth.h"
#include "recon/fsf/fsf_cl.h"

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

int main(int argc, char **argv)
{
    int w = argc > 2 ? atoi(argv[1]) : 96, h = argc > 2 ? atoi(argv[2]) : 96;
    /* a third argument: "cl" times the OpenCL passes alone, anything else the factored C filter
     * alone (profiling) */
    int cl_only = argc > 3 && strcmp(argv[3], "cl") == 0, factored_only = argc > 3 && !cl_only;
    FsfSynth f;
    fsf_synth_init(&f, w, h, 4);
    FsfGrid g = fsf_grid_default(0.8f, 0.8f);
    fsf_synth_light(&f, &g, 4, false, 5);
    for (size_t i = 0; i < (size_t)w * h * (size_t)f.cap; ++i)
        f.v[3 * i] = f.v[3 * i + 1] = f.v[3 * i + 2] = (float)(i % 3) * 0.5f;
    for (int i = 0; i < w * h; ++i) {
        f.px[i].eta_m[0] = 0.03f, f.px[i].eta_m[1] = 0.02f;
        f.px[i].sigma_px[0] = f.px[i].sigma_px[1] = 8.0f;
    }
    FsfGuides gd = fsf_guides_default(f.pos4, f.nrm4, f.usable);
    float *out = malloc(4 * sizeof(float) * (size_t)w * h);
    double tb[3], tf[3];
    if (!cl_only) fsf_filter_factored(&f.s, &g, f.px, &gd, out); /* untimed */
    for (int r = 0; r < 3 && !cl_only; ++r) {
        double t0 = now();
        fsf_filter_factored(&f.s, &g, f.px, &gd, out);
        tf[r] = now() - t0;
        t0 = now();
        if (!factored_only) fsf_filter_brute(&f.s, &g, f.px, &gd, out);
        tb[r] = now() - t0;
    }
    qsort(tb, 3, sizeof(double), cmp);
    qsort(tf, 3, sizeof(double), cmp);
    if (!cl_only)
        printf("%dx%d, 16 spp, 33 px footprint: factored %.4f s (%.2f us/pixel), brute force %.4f s, ratio %.1fx\n", w, h,
           tf[1], 1e6 * tf[1] / (w * h), tb[1], tb[1] / tf[1]);
    /* the OpenCL passes (fsf_cl_run, uploads included) and their device time */
    Diag d = {0};
    ClRuntime *rt = cl_runtime_create(NULL, &d);
    FsfCl *cl = rt ? fsf_cl_create(rt, &d) : NULL;
    if (cl) {
        enum { RUNS = 7 };
        double th[RUNS], tk[RUNS], kt[6][RUNS];
        fsf_cl_run(cl, &f.s, &g, f.px, &gd, out, NULL, &d); /* untimed: first launch */
        for (int r = 0; r < RUNS; ++r) {
            double t0 = now();
            fsf_cl_run(cl, &f.s, &g, f.px, &gd, out, &tk[r], &d);
            th[r] = now() - t0;
            FsfClProfile p = fsf_cl_profile(cl);
            double k6[6] = {p.taps, p.bins, p.pass1a, p.pass1b, p.pass2a, p.pass2b};
            for (int k = 0; k < 6; ++k) kt[k][r] = k6[k];
        }
        qsort(th, RUNS, sizeof(double), cmp);
        qsort(tk, RUNS, sizeof(double), cmp);
        printf("OpenCL: fsf_cl_run %.4f s (%.2f us/pixel), device %.4f s (medians of %d)\n", th[RUNS / 2],
               1e6 * th[RUNS / 2] / (w * h), tk[RUNS / 2], RUNS);
        const char *names[6] = {"taps", "bins", "pass1a", "pass1b", "pass2a", "pass2b"};
        printf("  per kernel, median (fastest):");
        for (int k = 0; k < 6; ++k) {
            qsort(kt[k], RUNS, sizeof(double), cmp);
            printf(" %s %.4f (%.4f)", names[k], kt[k][RUNS / 2], kt[k][0]);
        }
        printf("\n");
    } else {
        printf("OpenCL: not measured (%s)\n", d.message);
    }
    fsf_cl_destroy(cl);
    cl_runtime_destroy(rt);
    free(out);
    fsf_synth_free(&f);
    return 0;
}
