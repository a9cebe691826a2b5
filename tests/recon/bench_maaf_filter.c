/* Benchmark (not a test): the MAAF image pass (maaf_filter_run) on a recorded frame's input,
 * against the C reference (maaf_filter_reference). Prints the device time of both passes and
 * the wall time of maaf_filter_run (uploads and download included), best and median of REPS,
 * and the kernel's largest difference from the reference. The input file is what
 * maaf_filter_dump writes (maaf_filter.h; `WEDGE_MAAF_DUMP=PREFIX wedge render ...` writes
 * PREFIX.0, PREFIX.1, ... one per image pass). Build line and use: docs/benchmarks.md,
 * "MAAF's image pass, faster (issue 16)". Usage: bench_maaf_filter FILE [REPS] [--no-ref]
 * The reader is here, not in the library, so that the same source links against an older
 * build (the A/B runs of the benchmark). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "recon/cl/cl_runtime.h"
#include "recon/maaf/maaf_filter.h"

#ifndef MAAF_DUMP_MAGIC /* older builds' header */
#define MAAF_DUMP_MAGIC "MAAFDMP1"
#endif

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* maaf_filter_dump's layout: magic, width, height, pairs (int32), cos_normal_min,
 * depth_tol_rel (float), then ysum, pos4, nrm4, frame4, axis2_4, param as float arrays. */
static bool load(const char *path, MaafFilterInput *in, float **store)
{
    FILE *fp = fopen(path, "rb");
    char magic[8];
    int dims[3];
    float rules[2];
    bool ok = fp && fread(magic, 1, 8, fp) == 8 && memcmp(magic, MAAF_DUMP_MAGIC, 8) == 0 &&
              fread(dims, sizeof(int), 3, fp) == 3 && fread(rules, sizeof(float), 2, fp) == 2 && dims[0] > 0 &&
              dims[1] > 0 && dims[0] <= 8192 && dims[1] <= 8192 && dims[2] >= 1 && dims[2] <= MAAF_PAIRS_MAX;
    size_t n = ok ? (size_t)dims[0] * (size_t)dims[1] : 0, per = ok ? (size_t)maaf_component_count(dims[2]) * 8 : 0;
    size_t counts[6] = {n * per, 4 * n, 4 * n, 4 * n, 4 * n, n * MAAF_PARAM_STRIDE}, total = 0;
    for (int k = 0; k < 6; ++k) total += counts[k];
    float *s = ok ? malloc(total * sizeof(float)) : NULL;
    ok = ok && s && fread(s, sizeof(float), total, fp) == total;
    if (fp) fclose(fp);
    if (!ok) {
        free(s);
        return false;
    }
    const float *part[6];
    size_t at = 0;
    for (int k = 0; k < 6; ++k) part[k] = s + at, at += counts[k];
    *in = (MaafFilterInput){dims[0], dims[1], dims[2], part[0], part[1], part[2], part[3], part[4], part[5], rules[0], rules[1], 0.0f, NULL};
    *store = s;
    return true;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: bench_maaf_filter FILE [REPS] [--no-ref]\n");
        return 2;
    }
    int reps = argc > 2 && argv[2][0] != '-' ? atoi(argv[2]) : 5;
    bool ref = !(argc > 2 && strcmp(argv[argc - 1], "--no-ref") == 0);
    if (reps < 1 || reps > 100) reps = 5;
    MaafFilterInput in;
    float *store = NULL;
    Diag d = {0};
    if (!load(argv[1], &in, &store)) {
        fprintf(stderr, "bench_maaf_filter: cannot read %s (not a MAAF dump)\n", argv[1]);
        return 2;
    }
    size_t n = (size_t)in.width * (size_t)in.height;
    double taps = 0.0;
    long filtered = 0;
    for (size_t i = 0; i < n; ++i) {
        int r = (int)in.param[i * MAAF_PARAM_STRIDE];
        if (r > 0 && in.frame4[4 * i + 3] != 0.0f) taps += 2 * r + 1, ++filtered;
    }
    printf("%s: %dx%d, %d pairs, %ld filtered pixels, %.1f taps per pass on average\n", argv[1], in.width, in.height,
           in.pairs, filtered, filtered ? taps / (double)filtered : 0.0);
    float *out_ref = calloc(4 * n, sizeof(float)), *out_dev = calloc(4 * n, sizeof(float));
    ClRuntime *rt = cl_runtime_create(NULL, &d);
    MaafFilter *f = rt ? maaf_filter_create(rt, &d) : NULL;
    if (!out_ref || !out_dev || !f) {
        fprintf(stderr, "%s\n", d.message);
        return 3;
    }
    double ks[100], wall[100], each[3][100] = {{0}};
    for (int r = -1; r < reps; ++r) { /* one warm-up run */
        double k = 0.0, t0 = now();
        if (!maaf_filter_run(f, &in, out_dev, &k, &d)) {
            fprintf(stderr, "%s\n", d.message);
            return 3;
        }
        if (r >= 0) ks[r] = k, wall[r] = now() - t0;
#ifdef MAAF_FILTER_KERNELS
        double s3[MAAF_FILTER_KERNELS];
        maaf_filter_kernel_seconds(f, s3);
        for (int j = 0; j < 3 && r >= 0; ++j) each[j][r] = s3[j];
#endif
        if (r < 0) printf("first run (kernels loaded in this process): kernels %.4f s, wall %.4f s\n", k, now() - t0);
    }
    for (int j = 0; j < 3; ++j) qsort(each[j], (size_t)reps, sizeof each[j][0], cmp_double);
    if (each[1][0] > 0.0)
        printf("each kernel, best: unpack %.4f s, rows %.4f s, cols %.4f s\n", each[0][0], each[1][0], each[2][0]);
    qsort(ks, (size_t)reps, sizeof ks[0], cmp_double);
    qsort(wall, (size_t)reps, sizeof wall[0], cmp_double);
    printf("kernels: best %.4f s, median %.4f s; maaf_filter_run wall: best %.4f s, median %.4f s (%d runs)\n", ks[0],
           ks[reps / 2], wall[0], wall[reps / 2], reps);
    if (ref) {
        double t0 = now();
        maaf_filter_reference(&in, out_ref);
        double t_ref = now() - t0, diff = 0.0, scale = 0.0;
        long flags = 0;
        for (size_t i = 0; i < n; ++i) {
            flags += out_ref[4 * i + 3] != out_dev[4 * i + 3];
            for (int k = 0; k < 3; ++k) {
                diff = fmax(diff, fabs(out_ref[4 * i + k] - out_dev[4 * i + k]));
                scale = fmax(scale, fabs(out_ref[4 * i + k]));
            }
        }
        printf("reference: %.2f s; kernel vs reference: max |diff| %.3e (largest value %.3e), %ld flags differ\n", t_ref,
               diff, scale, flags);
    }
    maaf_filter_destroy(f);
    cl_runtime_destroy(rt);
    free(out_ref);
    free(out_dev);
    free(store);
    return 0;
}
