/* Benchmark (not a test): LR's reconstruction on a synthetic light field (lr_scene.h: a
 * defocused, moving disk over a defocused plane) at W x H for 4, 8 and 16 spp: OpenCL device
 * time of the kernels, host wall time of lr_cl_run (partitions, uploads included) and
 * of the C version, warm (each configuration run 3 times after one untimed run; median), and
 * where lr_cl_run's time goes (host partitions, each kernel).
 * Prints the ratios to the 8-spp time, for the paper's Figure 8 (cost linear in spp).
 * Build as bench_aaf_filter (docs/algorithms.md 5.1). Usage: bench_lr [W H] */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "lr_scene.h"
#include "recon/lr/lr_cl.h"

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
    int w = argc > 2 ? atoi(argv[1]) : 256, h = argc > 2 ? atoi(argv[2]) : 192;
    Diag d = {0};
    ClRuntime *rt = cl_runtime_create(NULL, &d);
    LrCl *lr = rt ? lr_cl_create(rt, &d) : NULL;
    if (!lr) {
        fprintf(stderr, "%s\n", d.message);
        return 1;
    }
    LrTestLayer layers[2] = {{2.0f, -6.0f, {20.0f, 4.0f}, 0.4f * w, 0.5f * h, 0.2f * h, 0.5f},
                             {9.0f, 4.0f, {0.0f, 0.0f}, 0, 0, 0, 0.3f}};
    LrConfig cfg = lr_config_default();
    int spps[3] = {4, 8, 16};
    double dev[3], host[3], cref[3];
    LrClTimes parts[3];
    float *rgb = malloc(sizeof(float) * 3 * (size_t)w * h);
    for (int k = 0; k < 3; ++k) {
        int spp = spps[k];
        LrSample *s = malloc(sizeof(LrSample) * (size_t)w * h * spp);
        lr_test_scene(s, w, h, spp, layers, 2, 1);
        LrSamples img = lr_samples_split(w, h, spp, s);
        LrOutput out = {rgb, NULL, NULL, 0};
        double kt[3], ht[3], ct[3];
        LrClTimes pt[3];
        lr_cl_run(lr, &img, &cfg, &out, NULL, &d); /* untimed: builds at this size */
        for (int r = 0; r < 3; ++r) {
            double t0 = now();
            if (!lr_cl_run(lr, &img, &cfg, &out, &kt[r], &d)) {
                fprintf(stderr, "%s\n", d.message);
                return 1;
            }
            ht[r] = now() - t0;
            pt[r] = lr_cl_last_times(lr);
            t0 = now();
            lr_reconstruct_c(&img, &cfg, &out);
            ct[r] = now() - t0;
        }
        qsort(kt, 3, sizeof(double), cmp), qsort(ht, 3, sizeof(double), cmp), qsort(ct, 3, sizeof(double), cmp);
        /* the breakdown of the run whose kernel time is the median */
        for (int r = 0; r < 3; ++r)
            if (pt[r].kernel_s[0] + pt[r].kernel_s[1] + pt[r].kernel_s[2] + pt[r].kernel_s[3] == kt[1]) parts[k] = pt[r];
        dev[k] = kt[1], host[k] = ht[1], cref[k] = ct[1];
        lr_samples_free(&img);
        free(s);
    }
    printf("LR at %dx%d (synthetic, 2 layers), median of 3 warm runs\n", w, h);
    printf("spp  kernels_s  lr_cl_run_s  c_ref_s   kernels/8spp  run/8spp\n");
    for (int k = 0; k < 3; ++k)
        printf("%3d  %9.4f  %11.4f  %7.4f   %12.2f  %8.2f\n", spps[k], dev[k], host[k], cref[k], dev[k] / dev[1], host[k] / host[1]);
    printf("spp  partition_s (stats_s)  tile_filter_s  along_s  across_s  (partitions, most layers; lr_tile_filter runs both passes)\n");
    for (int k = 0; k < 3; ++k)
        printf("%3d  %11.4f (%7.4f)  %11.4f  %7.4f  %8.4f  (%zu, %d)\n", spps[k], parts[k].partition_s, parts[k].kernel_s[0],
               parts[k].kernel_s[1], parts[k].kernel_s[2], parts[k].kernel_s[3], parts[k].partitions, parts[k].max_layers);
    free(rgb);
    lr_cl_destroy(lr);
    cl_runtime_destroy(rt);
    return 0;
}
