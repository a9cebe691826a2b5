/* Benchmark (not a test): device time of the two AAF filter passes at 720x720 for a few
 * uniform filter radii, on a plane seen by a camera (world-distance mode) and in pixel mode.
 * Build: see docs/algorithms.md ("Performance"). Usage: bench_aaf_filter [W H] */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "recon/aaf/aaf_filter.h"
#include "recon/cl/cl_runtime.h"

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

int main(int argc, char **argv)
{
    int w = argc > 2 ? atoi(argv[1]) : 720, h = argc > 2 ? atoi(argv[2]) : 720;
    size_t n = (size_t)w * h;
    float *pos = malloc(16 * n), *nrm = malloc(16 * n), *val = malloc(16 * n), *out = malloc(16 * n);
    float *beta = malloc(4 * n), *pw = malloc(4 * n), *param = malloc(8 * n);
    for (size_t i = 0; i < n; ++i) {
        int x = (int)(i % w), y = (int)(i / w);
        pos[4 * i] = x * 0.01f;
        pos[4 * i + 1] = 0.0f;
        pos[4 * i + 2] = 2.0f + y * 0.01f;
        pos[4 * i + 3] = 2.0f + y * 0.01f;
        nrm[4 * i] = 0;
        nrm[4 * i + 1] = 1;
        nrm[4 * i + 2] = 0;
        nrm[4 * i + 3] = (float)(x / 200);
        for (int k = 0; k < 3; ++k) val[4 * i + k] = (float)rand() / RAND_MAX;
        val[4 * i + 3] = 1;
        pw[i] = 0.01f;
    }
    Diag d;
    ClRuntime *rt = cl_runtime_create(NULL, &d);
    if (!rt) {
        fprintf(stderr, "%s\n", d.message);
        return 3;
    }
    AafFilter *f = aaf_filter_create(rt, &d);
    if (!f || !aaf_filter_set_guides(f, w, h, pos, nrm, &d)) {
        fprintf(stderr, "%s\n", d.message);
        return 3;
    }
    printf("device: %s, image %dx%d\n", cl_runtime_device_label(rt), w, h);
    int radii[] = {4, 8, 16, 32};
    for (int mode = 0; mode < 2; ++mode) {
        AafFilterRules rules = aaf_filter_rules_default(mode);
        for (int r = 0; r < 4; ++r) {
            for (size_t i = 0; i < n; ++i) beta[i] = radii[r] * 0.5f * (mode == 0 ? 0.01f : 1.0f);
            aaf_filter_make_params((int)n, beta, mode == 0 ? pw : NULL, 2.0f, 64, param);
            double best = 1e9, best_wall = 1e9;
            for (int rep = 0; rep < 3; ++rep) {
                double k = 0, t0 = now();
                if (!aaf_filter_run(f, val, NULL, param, &rules, out, &k, &d)) {
                    fprintf(stderr, "%s\n", d.message);
                    return 3;
                }
                double wall = now() - t0;
                if (k < best) best = k;
                if (wall < best_wall) best_wall = wall;
            }
            printf("%s radius %2d px: kernels %.1f ms, with transfers %.1f ms\n", mode == 0 ? "world" : "pixel",
                   radii[r], best * 1e3, best_wall * 1e3);
        }
    }
    aaf_filter_destroy(f);
    cl_runtime_destroy(rt);
    return 0;
}
