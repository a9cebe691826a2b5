/* The arrays of a synthetic frame for the MAAF image-pass tests (test_maaf_filter,
 * test_maaf_defocus, test_maaf_indirect): per pixel the component sums, the guides, the filter
 * parameters, the pixel's own mean and the exact value, and the error of a result against it. */
#ifndef WEDGE_TESTS_MAAF_TEST_PLANE_H
#define WEDGE_TESTS_MAAF_TEST_PLANE_H

#include <math.h>
#include <stdlib.h>

#include "check.h"
#include "recon/cl/cl_runtime.h"
#include "recon/maaf/maaf_defocus.h" /* MaafLens: a table of complex factors per component */
#include "recon/maaf/maaf_filter.h"

typedef struct {
    int width, height, pairs;
    float *ysum, *pos4, *nrm4, *frame4, *axis2, *param, *mean, *exact;
} MaafTestPlane;

/* Zeroed arrays for w x h pixels and N = pairs. */
static inline void maaf_test_plane_alloc(MaafTestPlane *s, int w, int h, int pairs)
{
    size_t n = (size_t)w * (size_t)h;
    s->width = w, s->height = h, s->pairs = pairs;
    s->ysum = calloc(n * (size_t)maaf_component_count(pairs) * 8, sizeof(float));
    s->pos4 = calloc(4 * n, sizeof(float));
    s->nrm4 = calloc(4 * n, sizeof(float));
    s->frame4 = calloc(4 * n, sizeof(float));
    s->axis2 = calloc(4 * n, sizeof(float));
    s->param = calloc(n * MAAF_PARAM_STRIDE, sizeof(float));
    s->mean = calloc(n, sizeof(float));
    s->exact = calloc(n, sizeof(float));
}

static inline void maaf_test_plane_free(MaafTestPlane *s)
{
    free(s->ysum), free(s->pos4), free(s->nrm4), free(s->frame4), free(s->axis2), free(s->param), free(s->mean),
        free(s->exact);
}

/* The image pass's input (depth tolerance 5%, as the method's). */
static inline MaafFilterInput maaf_test_plane_input(const MaafTestPlane *s, float cos_normal_min)
{
    MaafFilterInput in = {s->width,  s->height, s->pairs,        s->ysum, s->pos4, s->nrm4,
                          s->frame4, s->axis2,  s->param, cos_normal_min, 0.05f,
                          MAAF_SHARP_FACTOR_DEFAULT, NULL, NULL};
    return in;
}

/* RMS difference of v (every stride-th float) from exact over the plane's pixels. */
static inline double maaf_test_plane_rmse(const MaafTestPlane *s, const float *v, int stride)
{
    size_t n = (size_t)s->width * (size_t)s->height;
    double e2 = 0.0;
    for (size_t i = 0; i < n; ++i) e2 += (v[stride * i] - s->exact[i]) * (v[stride * i] - s->exact[i]);
    return sqrt(e2 / (double)n);
}

/* The OpenCL image pass on the plane against maaf_filter_reference, with the sharpness rule's
 * factor sharp_factor: the same flag on every pixel and rgb within 2e-4 (label names the case
 * in the output). */
static inline void maaf_test_plane_kernel_check_sharp(const MaafTestPlane *s, float cos_normal_min, float sharp_factor,
                                                      const char *label)
{
    size_t n = (size_t)s->width * (size_t)s->height;
    float *ref = malloc(4 * n * sizeof(float)), *dev = malloc(4 * n * sizeof(float));
    Diag dg = {0};
    ClRuntime *rt = cl_runtime_create(NULL, &dg);
    CHECK(rt != NULL);
    MaafFilter *f = rt ? maaf_filter_create(rt, &dg) : NULL;
    CHECK(f != NULL);
    MaafFilterInput in = maaf_test_plane_input(s, cos_normal_min);
    in.sharp_factor = sharp_factor;
    if (f && ref && dev) {
        maaf_filter_reference(&in, ref);
        double ks = 0.0, diff = 0.0;
        CHECK(maaf_filter_run(f, &in, dev, &ks, &dg));
        int flags = 0;
        for (size_t i = 0; i < n; ++i) {
            flags += ref[4 * i + 3] != dev[4 * i + 3];
            for (int k = 0; k < 3; ++k) diff = fmax(diff, fabs(ref[4 * i + k] - dev[4 * i + k]));
        }
        printf("%s: kernel vs reference max |diff| %.2e\n", label, diff);
        CHECK(flags == 0);
        CHECK(diff < 2e-4);
    }
    maaf_filter_destroy(f);
    if (rt) cl_runtime_destroy(rt);
    free(ref);
    free(dev);
}

/* The same with the light filter's factor (MAAF_SHARP_FACTOR_DEFAULT). */
static inline void maaf_test_plane_kernel_check(const MaafTestPlane *s, float cos_normal_min, const char *label)
{
    maaf_test_plane_kernel_check_sharp(s, cos_normal_min, MAAF_SHARP_FACTOR_DEFAULT, label);
}

/* A factor table against its brute-force integral: every component (p, q) of the half set (N = 3)
 * at every probe point; the largest |table - brute| and the largest |brute| over them. */
typedef void (*MaafBruteFactor)(const MaafLens *t, int p, int q, double a, double b, double out[2]);
typedef void (*MaafTableFactor)(const MaafLens *t, int c, float a, float b, float out[2]);
static inline void maaf_test_table_vs_brute(const MaafLens *t, const float (*probes)[2], size_t probe_count,
                                            MaafBruteFactor brute, MaafTableFactor table, double *worst,
                                            double *biggest)
{
    *worst = 0.0, *biggest = 0.0;
    int c = 0;
    for (int p = 0; p < 3; ++p)
        for (int q = -2; q < 3; ++q) {
            if (p == 0 && q < 0) continue;
            for (size_t k = 0; k < probe_count; ++k) {
                double b[2];
                float v[2];
                brute(t, p, q, probes[k][0], probes[k][1], b);
                table(t, c, probes[k][0], probes[k][1], v);
                *worst = fmax(*worst, hypot(v[0] - b[0], v[1] - b[1]));
                *biggest = fmax(*biggest, hypot(b[0], b[1]));
            }
            ++c;
        }
}

/* The reference filter on a plane built with the right wedge and on one built with the mirrored
 * wedge: rmse of the pixel means, of MAAF and of the mirrored MAAF against the exact values, and
 * how many pixels MAAF filtered. out: 4 floats per pixel of scratch. */
static inline int maaf_test_plane_right_wrong(const MaafTestPlane *right, const MaafTestPlane *wrong, float *out,
                                              double *e_mean, double *e_maaf, double *e_wrong)
{
    MaafFilterInput in = maaf_test_plane_input(right, 0.93969262f);
    maaf_filter_reference(&in, out);
    *e_mean = maaf_test_plane_rmse(right, right->mean, 1), *e_maaf = maaf_test_plane_rmse(right, out, 4);
    int filtered = 0;
    for (int i = 0; i < right->width * right->height; ++i) filtered += out[4 * i + 3] != 0.0f;
    in = maaf_test_plane_input(wrong, 0.93969262f);
    maaf_filter_reference(&in, out);
    *e_wrong = maaf_test_plane_rmse(wrong, out, 4);
    return filtered;
}

#endif
