/* The MAAF image pass's OpenCL layout (maaf.cl: 8 pixels per work item, padded planes, taps
 * gathered per work item) against the C reference (maaf_filter_reference), where the layout can
 * go wrong and test_maaf_filter.c's 24x20 plane does not look:
 *   - widths that are not a multiple of 8 (the last work item's lanes past the image);
 *   - radii at MAAF_RADIUS_CAP_PX, wider than the image (every tap in the padding);
 *   - 1 to MAAF_PAIRS_MAX pairs (the per-tap factor tables);
 *   - non-finite sums in pixels that the reference never reads (unusable) and in usable pixels
 *     that some neighbours reject (another object): a lane that rejects one must not see it
 *     (0 x NaN), a lane that uses it must (the reference's NaN), in both passes;
 *   - screen-space guides as defocus uses them (maaf_screen_guides: one offset is exactly 0,
 *     the kernel skips its sincos/exp);
 *   - plain pixels (the central component alone) around a band of designed rows: the row pass
 *     sums every component only in the work items that a designed column reader reaches
 *     (row_needs), and the rows exactly its radius away must be among them.
 * Oracle: same flags everywhere, the same NaN pixels, and values within float rounding. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cl_test_device.h"
#include "check.h"
#include "recon/cl/cl_runtime.h"
#include "recon/maaf/maaf_defocus.h"
#include "recon/maaf/maaf_filter.h"
#include "recon/maaf/maaf_shadow.h"

#define PIXEL_WORLD 0.05f
/* float rounding: the kernel's sincos/exp/fma against libm's, over up to 65 taps and 2 passes */
#define REL_TOL 2e-5

static unsigned rng = 12345u;
static float frand(void)
{
    rng = rng * 1664525u + 1013904223u;
    return (float)(rng >> 8) / 16777216.0f;
}

typedef struct {
    int w, h, pairs;
    float *ysum, *pos4, *nrm4, *frame4, *axis2, *param;
} Input;

static void input_free(Input *in)
{
    free(in->ysum);
    free(in->pos4);
    free(in->nrm4);
    free(in->frame4);
    free(in->axis2);
    free(in->param);
}

/* in's arrays for w x h pixels (guides and parameters zero); returns the floats of sums per pixel. */
static size_t input_alloc(Input *in, int w, int h, int pairs)
{
    size_t n = (size_t)w * h, per = (size_t)maaf_component_count(pairs) * 8;
    in->w = w, in->h = h, in->pairs = pairs;
    in->ysum = malloc(n * per * sizeof(float));
    in->pos4 = calloc(4 * n, sizeof(float));
    in->nrm4 = calloc(4 * n, sizeof(float));
    in->frame4 = calloc(4 * n, sizeof(float));
    in->axis2 = calloc(4 * n, sizeof(float));
    in->param = calloc(n * MAAF_PARAM_STRIDE, sizeof(float));
    return per;
}

/* World guides: a gently curved surface of two objects, light axes along x and y, designs from
 * random wedges; screen guides: maaf_screen_guides with a random side. Some pixels unusable,
 * some unfiltered, some at the radius cap; non-finite sums planted as described above. */
static void input_build(Input *in, int w, int h, int pairs, bool screen)
{
    size_t per = input_alloc(in, w, h, pairs);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            size_t i = (size_t)y * w + x;
            float *p4 = in->pos4 + 4 * i, *n4 = in->nrm4 + 4 * i, *f4 = in->frame4 + 4 * i, *a4 = in->axis2 + 4 * i;
            float *pr = in->param + i * MAAF_PARAM_STRIDE;
            bool usable = frand() > 0.1f;
            if (screen) {
                maaf_screen_guides(x, y, frand() < 0.8f ? 1.0f : -1.0f, usable, p4, n4, f4, a4);
                /* slopes -coc: circles of confusion of 2-12 px per unit lens coordinate */
                float s0 = 2.0f + 10.0f * frand(), side = n4[3];
                maaf_pixel_param_signed(side * s0, side * s0 * (1.1f + 0.5f * frand()), 12.0f, pairs, pr);
            } else {
                p4[0] = x * PIXEL_WORLD, p4[1] = y * PIXEL_WORLD, p4[2] = 0.02f * sinf(0.3f * x) + 0.001f * frand();
                p4[3] = 3.0f;
                n4[2] = 1.0f;
                if (frand() < 0.05f) n4[0] = 0.6f, n4[2] = 0.8f; /* a normal discontinuity */
                n4[3] = x > w / 2 + (y % 5) ? 1.0f : 0.0f;         /* two objects */
                f4[0] = 1.0f, f4[3] = usable ? 1.0f : 0.0f;
                a4[1] = 1.0f;
                float s0 = 0.3f + frand();
                maaf_pixel_param(s0, s0 * (1.2f + frand()), 8.0f, pairs, 1.0f, PIXEL_WORLD, pr);
            }
            float r = frand();
            if (r < 0.05f) pr[0] = 0.0f;                            /* not filtered */
            /* every tap to the cap; not in the 131-row frames, whose smaller largest radius
             * gives the column pass a shorter ring of row-pass output (maaf_filter_run) */
            else if (r < 0.12f && pr[0] > 0.0f && h != 131) pr[0] = MAAF_RADIUS_CAP_PX;
            float *ys = in->ysum + i * per;
            for (size_t c = 0; c < per; ++c) ys[c] = frand() - 0.3f;
            for (size_t c = 3; c < per; c += 4) ys[c] = 0.5f + frand(); /* weights: the w channel */
            if (!usable && frand() < 0.5f) ys[(size_t)(frand() * (float)per)] = NAN; /* never read */
        }
    /* usable pixels with a non-finite sum at object 1's edge (world) or on the -1 side (screen):
     * neighbours on the other object reject them, their own object's use them */
    for (int k = 0; k < 3; ++k) {
        int x = w / 2 + 1 + k, y = 3 + 5 * k;
        if (x >= w || y >= h) continue;
        size_t i = (size_t)y * w + x;
        in->frame4[4 * i + 3] = 1.0f;
        if (screen) in->nrm4[4 * i + 3] = -in->nrm4[4 * i + 3];
        in->ysum[i * per + 1 + 8 * k] = k == 1 ? INFINITY : NAN;
    }
}

/* Plain pixels (maaf_pixel_param_plain, std 2 px: radius 4) on one surface, all usable, with
 * designed pixels in rows [y0, y0 + 4) and columns [x0, x1) whose radius is 6 (std 3 px: a tap
 * 6 pixels away still weighs e^-2, and the plain neighbours are wide enough for the sharpness
 * rule to keep them). */
static void input_build_plain(Input *in, int w, int h, int pairs, int y0, int x0, int x1)
{
    size_t per = input_alloc(in, w, h, pairs);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            size_t i = (size_t)y * w + x;
            float *pr = in->param + i * MAAF_PARAM_STRIDE;
            in->pos4[4 * i] = x * PIXEL_WORLD, in->pos4[4 * i + 1] = y * PIXEL_WORLD, in->pos4[4 * i + 3] = 3.0f;
            in->nrm4[4 * i + 2] = 1.0f;
            in->frame4[4 * i] = 1.0f, in->frame4[4 * i + 3] = 1.0f;
            in->axis2[4 * i + 1] = 1.0f;
            if (y >= y0 && y < y0 + 4 && x >= x0 && x < x1)
                maaf_pixel_param(0.24f, 0.4f, 8.0f, pairs, 1.0f, PIXEL_WORLD, pr); /* std 12.5 x 0.24 px */
            else
                maaf_pixel_param_plain(2.0f, PIXEL_WORLD, pairs, pr);
            float *ys = in->ysum + i * per;
            for (size_t c = 0; c < per; ++c) ys[c] = frand() - 0.3f;
            for (size_t c = 3; c < per; c += 4) ys[c] = 0.5f + frand();
        }
}

/* 0: agree; else the number of pixels that do not */
static int compare(const Input *in, const float *ref, const float *dev, double *worst)
{
    int bad = 0;
    *worst = 0.0;
    for (int i = 0; i < in->w * in->h; ++i) {
        bool differ = ref[4 * i + 3] != dev[4 * i + 3];
        for (int k = 0; k < 3; ++k) {
            double a = ref[4 * i + k], b = dev[4 * i + k];
            if (isnan(a) || isnan(b) || isinf(a) || isinf(b)) {
                differ = differ || isfinite(a) != isfinite(b);
                continue;
            }
            double e = fabs(a - b) / (1.0 + fabs(a));
            *worst = fmax(*worst, e);
            differ = differ || e > REL_TOL;
        }
        bad += differ;
    }
    return bad;
}

int main(void)
{
    Diag d = {0};
    ClRuntime *rt = cl_test_device_or_skip();
    MaafFilter *f = maaf_filter_create(rt, &d);
    CHECK(f != NULL);
    /* the last two are taller than a band of the pass and its ring of row-pass output
     * (MAAF_BAND_ROWS + 2 MAAF_RADIUS_CAP_PX rows, maaf_filter.c), not a multiple of either: the
     * column pass reads across bands and ring rows that wrap */
    const int sizes[][2] = {{37, 29}, {13, 9}, {8, 40}, {61, 7}, {11, 131}, {19, 97}};
    for (int screen = 0; screen < 2 && f; ++screen)
        for (int pairs = 1; pairs <= MAAF_PAIRS_MAX; ++pairs) {
            const int *sz = sizes[(pairs + screen) % 6];
            Input in;
            input_build(&in, sz[0], sz[1], pairs, screen);
            MaafFilterInput fi = {in.w, in.h, pairs, in.ysum, in.pos4, in.nrm4, in.frame4, in.axis2, in.param,
                                  0.96592583f, 0.05f, MAAF_SHARP_FACTOR_DEFAULT, NULL, NULL};
            size_t n = (size_t)in.w * in.h;
            float *ref = malloc(4 * n * sizeof(float)), *dev = malloc(4 * n * sizeof(float));
            maaf_filter_reference(&fi, ref);
            CHECK(maaf_filter_run(f, &fi, dev, NULL, &d));
            int nan_pixels = 0, filtered = 0;
            for (size_t i = 0; i < n; ++i) {
                nan_pixels += !isfinite(ref[4 * i]) || !isfinite(ref[4 * i + 1]) || !isfinite(ref[4 * i + 2]);
                filtered += ref[4 * i + 3] != 0.0f;
            }
            double worst;
            int bad = compare(&in, ref, dev, &worst);
            printf("%s guides, %dx%d, %d pairs: %d filtered, %d non-finite in the reference, max rel diff %.2e, %d "
                   "pixels differ\n",
                   screen ? "screen" : "world", in.w, in.h, pairs, filtered, nan_pixels, worst, bad);
            CHECK(bad == 0);
            CHECK(filtered > (int)n / 2);
            /* the planted non-finite sums reach the reference's output somewhere (else the
             * guard is not exercised), not to every pixel */
            CHECK(nan_pixels > 0 && nan_pixels < filtered);
            free(ref);
            free(dev);
            input_free(&in);
        }
    /* plain pixels around designed rows, in the middle of a band and across a band's edge (the
     * row pass sums every component in the rows a designed column reader reaches: row_needs),
     * and around a designed patch of one work item's 8 columns (the fill writes every
     * component only of the pixels such a row-pass work item reaches: band_full) */
    for (int k = 0; k < 3 && f; ++k) {
        Input in;
        int y0 = k == 1 ? MAAF_BAND_ROWS - 2 : 12;
        input_build_plain(&in, 29, 70, 3, y0, k == 2 ? 8 : 0, k == 2 ? 16 : 29);
        CHECK(in.param[((size_t)y0 * 29 + 8) * MAAF_PARAM_STRIDE] == 6.0f);
        MaafFilterInput fi = {in.w, in.h, 3, in.ysum, in.pos4, in.nrm4, in.frame4, in.axis2, in.param,
                              0.96592583f, 0.05f, MAAF_SHARP_FACTOR_DEFAULT, NULL, NULL};
        size_t n = (size_t)in.w * in.h;
        float *ref = malloc(4 * n * sizeof(float)), *dev = malloc(4 * n * sizeof(float));
        maaf_filter_reference(&fi, ref);
        CHECK(maaf_filter_run(f, &fi, dev, NULL, &d));
        double worst;
        int bad = compare(&in, ref, dev, &worst);
        printf("plain pixels around designed %s: max rel diff %.2e, %d pixels differ\n", k == 2 ? "pixels" : "rows", worst,
               bad);
        CHECK(bad == 0);
        free(ref);
        free(dev);
        input_free(&in);
    }
    maaf_filter_destroy(f);
    cl_runtime_destroy(rt);
    CHECK_DONE();
}
