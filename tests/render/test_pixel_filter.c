/* Pixel filters by importance sampling (src/render/pixel_filter.c):
 *  - the unit box hands the film sample through untouched (weight 1): today's images, bit
 *    for bit;
 *  - for every filter, the weighted distribution of the sampled offsets matches the filter
 *    (mass per bin against a fine quadrature of pbrt-v4's Evaluate), and the weights are 1
 *    for positive filters and +-c averaging 1 for mitchell and sinc;
 *  - end to end: the image of a step edge (an emitter covering the right half of the view)
 *    is the step convolved with the normalised filter, column by column;
 *  - the tabulated filters' cell search (a bisection by conditional moves) finds the cell a
 *    plain linear scan of the CDF finds, for random u and for u at and next to every CDF
 *    entry, so the offsets and weights are those of the scan bit for bit;
 *  - bad parameters are errors with exact messages. */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "check.h"
#include "render/pixel_filter.h"
#include "render_test_util.h"

static const char *names[] = {"box", "gaussian", "triangle", "mitchell", "sinc"};

/* Integral of the x-marginal of the filter over [a, b] by the midpoint rule (fine). */
static double marginal_mass(const PixelFilter *pf, double a, double b)
{
    int n = 2000;
    double h = (b - a) / n, s = 0.0;
    for (int i = 0; i < n; ++i) s += pixel_filter_eval(pf, (float)(a + (i + 0.5) * h), 0.0f);
    return s * h;
}

static void test_unit_box(void)
{
    PixelFilter pf;
    Diag err = {0};
    CHECK(pixel_filter_init(&pf, "box", NULL, (SrcLoc){0}, &err));
    CHECK(pf.unit_box);
    int same = 0;
    for (int i = 0; i < 1000; ++i) {
        vec2 u = v2((float)i / 1000.0f, (float)((i * 7919) % 1000) / 1000.0f);
        float w = 0.0f;
        vec2 p = pixel_filter_sample(&pf, u, &w);
        same += p.x == u.x && p.y == u.y && w == 1.0f;
    }
    CHECK(same == 1000);
    /* and a NULL filter (an IntegratorScene that sets none) is the same */
    float w = 0.0f;
    vec2 p = pixel_filter_sample(NULL, v2(0.25f, 0.75f), &w);
    CHECK(p.x == 0.25f && p.y == 0.75f && w == 1.0f);
    pixel_filter_free(&pf);
}

static void test_distribution(const char *name)
{
    PixelFilter pf;
    Diag err = {0};
    CHECK(pixel_filter_init(&pf, name, NULL, (SrcLoc){0}, &err));
    float r = pf.radius[0];
    /* pbrt-v4's default radii */
    double r_expected = !strcmp(name, "box") ? 0.5 : !strcmp(name, "gaussian") ? 1.5 : !strcmp(name, "sinc") ? 4.0 : 2.0;
    CHECK_NEAR(r, r_expected, 0);
    enum { N = 4096, BINS = 16 };
    double mass[BINS] = {0}, wsum = 0.0;
    int weight_bad = 0;
    bool positive = !strcmp(name, "box") || !strcmp(name, "gaussian") || !strcmp(name, "triangle");
    int M = positive ? 1 : 1024; /* a positive filter's weight does not depend on u.y */
    /* u.y over a grid too: the weight is the product of both axes' signs and scales */
    for (int k = 0; k < N * M; ++k) {
        int i = k / M, j = k % M;
        float w;
        vec2 p = pixel_filter_sample(&pf, v2((i + 0.5f) / N, (j + 0.5f) / M), &w);
        double x = p.x - 0.5;
        if (x < -r - 1e-5 || x > r + 1e-5) ++weight_bad;
        if (positive && w != 1.0f) ++weight_bad;
        int b = (int)floor((x + r) / (2.0 * r) * BINS);
        if (b < 0) b = 0;
        if (b >= BINS) b = BINS - 1;
        mass[b] += w;
        wsum += w;
    }
    CHECK(weight_bad == 0);
    /* the weights average to 1 (an unbiased pixel mean): exactly, from the tables, and
     * on the grid up to its resolution */
    for (int a = 0; a < 2 && !positive; ++a) {
        double mean = 0.0;
        for (int c = 0; c < pf.axis[a].cells; ++c)
            mean += (pf.axis[a].cdf[c + 1] - pf.axis[a].cdf[c]) * pf.axis[a].sign[c] * pf.axis[a].abs_over_sum;
        CHECK_NEAR(mean, 1.0, 1e-5);
    }
    CHECK_NEAR(wsum / ((double)N * M), 1.0, 2e-3);
    double total = marginal_mass(&pf, -r, r);
    double worst = 0.0;
    for (int b = 0; b < BINS; ++b) {
        double lo = -r + 2.0 * r * b / BINS, hi = lo + 2.0 * r / BINS;
        double want = marginal_mass(&pf, lo, hi) / total;
        worst = fmax(worst, fabs(mass[b] / ((double)N * M) - want));
    }
    /* box and triangle are sampled exactly (error: the N-point grid, ~1/N per bin); the
     * others from pbrt-v4's tabulation, 16 cells per pixel: midpoint-rule error per bin
     * below h^2/24 max|f''| (2r/BINS) / total, under 2e-3 for these three */
    if (worst > 2e-3) fprintf(stderr, "%s: worst bin mass error %g\n", name, worst);
    CHECK(worst <= 2e-3);
    pixel_filter_free(&pf);
}

/* Step edge at the centre of a 16-pixel-wide image: world x > 0 emits 1, the rest is black.
 * Column i (centre i + 0.5) must show the mass of the normalised filter beyond 8 - (i + 0.5). */
static void test_step_edge(const char *name)
{
    const char *scene =
        "LookAt 0 0 0  0 0 1  0 1 0\n"
        "Camera \"perspective\" \"float fov\" [ 10 ]\n"
        "Film \"rgb\" \"integer xresolution\" [ 16 ] \"integer yresolution\" [ 1 ]\n"
        "Integrator \"path\" \"integer maxdepth\" [ 1 ]\n"
        "WorldBegin\n"
        "AttributeBegin\n"
        "  AreaLightSource \"diffuse\" \"rgb L\" [ 1 1 1 ] \"bool twosided\" true\n"
        "  Shape \"trianglemesh\" \"point3 P\" [ 0 -100 5  0 100 5  100 100 5  100 -100 5 ]\n"
        "        \"integer indices\" [ 0 1 2  0 2 3 ]\n"
        "AttributeEnd\n";
    RenderOptions opt = {0};
    opt.pixel_filter = name;
    opt.sampler_set = true;
    opt.sampler = SAMPLER_STRATIFIED;
    opt.threads = 1;
    /* (pbrt-v4's stratified sampler takes xsamples x ysamples, not pixelsamples). sinc's
     * weights are +-1.83 ((sum |f| / sum f)^2 over the two axes): 16x the samples for the same noise */
    opt.spp = strcmp(name, "sinc") ? 4096 : 65536;
    TestRender t;
    if (!test_render(scene, &opt, &t)) {
        CHECK(false);
        return;
    }
    PixelFilter pf;
    Diag err = {0};
    CHECK(pixel_filter_init(&pf, name, NULL, (SrcLoc){0}, &err));
    double r = pf.radius[0], total = marginal_mass(&pf, -r, r), worst = 0.0;
    for (int i = 0; i < 16; ++i) {
        double d = 8.0 - (i + 0.5); /* edge relative to the pixel centre */
        double want = d >= r ? 0.0 : d <= -r ? 1.0 : marginal_mass(&pf, d, r) / total;
        double rgb[3];
        test_pixel(&t, i, 0, rgb);
        worst = fmax(worst, fabs(rgb[1] - want));
    }
    /* 4096 jittered samples of a 1D step: estimator error ~1e-4; tabulation: < 2e-3 */
    if (worst > 3e-3) fprintf(stderr, "%s: step edge, worst pixel error %g\n", name, worst);
    CHECK(worst <= 3e-3);
    pixel_filter_free(&pf);
    test_render_free(&t);
}

/* pixel_filter_sample's offset along axis 0 and weight for u = (x, 0.5), recomputed with a
 * linear scan for the first cell i with cdf[i + 1] > x (else the last cell) as the oracle. */
static void scan_sample(const PixelFilter *pf, float x, float *offset, float *weight)
{
    const PixelFilterAxis *ax = &pf->axis[0];
    int lo = 0;
    while (lo < ax->cells - 1 && !(ax->cdf[lo + 1] > x)) ++lo;
    float width = ax->cdf[lo + 1] - ax->cdf[lo];
    float t = width > 0.0f ? (x - ax->cdf[lo]) / width : 0.5f;
    t = fminf(fmaxf(t, 0.0f), 1.0f);
    float r = pf->radius[0];
    *offset = 0.5f + (-r + 2.0f * r * ((float)lo + t) / (float)ax->cells);
    /* the weight: the x cell's factor, then the y cell's (u.y = 0.5), in the library's order */
    float w = 1.0f;
    w *= (float)ax->sign[lo] * ax->abs_over_sum;
    const PixelFilterAxis *ay = &pf->axis[1];
    int ly = 0;
    while (ly < ay->cells - 1 && !(ay->cdf[ly + 1] > 0.5f)) ++ly;
    w *= (float)ay->sign[ly] * ay->abs_over_sum;
    *weight = w;
}

static void test_cell_search(const char *name)
{
    PixelFilter pf;
    Diag err = {0};
    CHECK(pixel_filter_init(&pf, name, NULL, (SrcLoc){0}, &err));
    const PixelFilterAxis *ax = &pf.axis[0];
    int n_u = 0, bad = 0;
    uint32_t state = 12345u;
    for (int k = 0; k < 20000 + 3 * (ax->cells + 1); ++k) {
        float x;
        if (k < 20000) {
            state = state * 1664525u + 1013904223u;
            x = (float)(state >> 8) * 0x1p-24f;
        } else { /* at and next to every CDF entry, kept in [0, 1) */
            int i = (k - 20000) / 3, side = (k - 20000) % 3;
            x = ax->cdf[i];
            if (side == 1) x = nextafterf(x, 0.0f);
            if (side == 2) x = nextafterf(x, 1.0f);
            if (!(x < 1.0f)) x = 0x1.fffffep-1f;
        }
        float w = 0.0f, w_scan = 0.0f, off_scan = 0.0f;
        vec2 p = pixel_filter_sample(&pf, v2(x, 0.5f), &w);
        scan_sample(&pf, x, &off_scan, &w_scan);
        ++n_u;
        if (memcmp(&p.x, &off_scan, sizeof p.x) != 0 || memcmp(&w, &w_scan, sizeof w) != 0) ++bad;
    }
    CHECK(n_u > 20000);
    CHECK(bad == 0);
    pixel_filter_free(&pf);
}

static void test_errors(void)
{
    PixelFilter pf;
    Diag err = {0};
    CHECK(!pixel_filter_init(&pf, "lanczos", NULL, (SrcLoc){0}, &err));
    CHECK(strstr(err.message, "unknown pixel filter 'lanczos' (box, gaussian, triangle, mitchell or sinc)") != NULL);
    const char *text = "PixelFilter \"gaussian\" \"float sigma\" [ 0 ]\nWorldBegin\n";
    SceneDesc sc;
    Diag e2 = {0};
    CHECK(scene_parse_string(text, strlen(text), "<test>", NULL, &sc, &e2));
    Diag e3 = {0};
    CHECK(!pixel_filter_init(&pf, sc.filter.type, &sc.filter.params, sc.filter.loc, &e3));
    CHECK(strstr(e3.message, "pixel filter 'gaussian': sigma must be positive, got 0") != NULL);
    scene_desc_free(&sc);
}

int main(void)
{
    test_unit_box();
    for (size_t i = 0; i < sizeof names / sizeof names[0]; ++i) {
        test_distribution(names[i]);
        test_step_edge(names[i]);
    }
    test_cell_search("gaussian"); /* 48 cells a side: not a power of two */
    test_cell_search("mitchell");
    test_cell_search("sinc");
    test_errors();
    return check_failures ? 1 : 0;
}
