/* The OpenCL AAF filter (aaf/aaf.cl, aaf_filter.c) against its plain C reference
 * (aaf_reference.h) on small random inputs, plus properties that hold for any input:
 * constants are preserved, width 0 is the identity, no mixing across objects, no NaN. */
#include <stdlib.h>
#include <string.h>

#include "aaf_reference.h"
#include "check.h"
#include "recon/aaf/aaf_filter.h"
#include "recon/cl/cl_runtime.h"

static unsigned rng_state = 12345u;
static float frand(void) /* uniform [0, 1) */
{
    rng_state = rng_state * 1664525u + 1013904223u;
    return (float)(rng_state >> 8) / 16777216.0f;
}

typedef struct {
    int w, h;
    float *value, *pos, *nrm, *plane, *param, *beta, *pixel_world;
} Input;

static void input_alloc(Input *in, int w, int h)
{
    size_t n = (size_t)w * h;
    in->w = w;
    in->h = h;
    in->value = calloc(4 * n, sizeof(float));
    in->pos = calloc(4 * n, sizeof(float));
    in->nrm = calloc(4 * n, sizeof(float));
    in->plane = calloc(4 * n, sizeof(float));
    in->param = calloc(2 * n, sizeof(float));
    in->beta = calloc(n, sizeof(float));
    in->pixel_world = calloc(n, sizeof(float));
}

static void input_free(Input *in)
{
    free(in->value);
    free(in->pos);
    free(in->nrm);
    free(in->plane);
    free(in->param);
    free(in->beta);
    free(in->pixel_world);
}

/* A scene-like random guide image: three objects (vertical bands), each a tilted plane with a
 * bump, normals jittered by a few degrees, some pixels marked unusable, a few pixels with a
 * depth jump; random values in [0.1, 1] and random widths of 0..6 pixels. */
static void input_random(Input *in)
{
    int w = in->w, h = in->h;
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            int i = y * w + x;
            int obj = (3 * x) / w;
            float pw = 0.01f;
            float px = x * pw, py = y * pw;
            float pz = 2.0f + 0.3f * px * obj - 0.2f * py + (frand() < 0.05f ? 0.5f : 0.0f);
            in->pos[4 * i + 0] = px;
            in->pos[4 * i + 1] = py;
            in->pos[4 * i + 2] = pz;
            in->pos[4 * i + 3] = pz;
            float nx = 0.05f * (frand() - 0.5f) + (obj == 2 ? 0.6f : 0.0f), ny = 0.05f * (frand() - 0.5f), nz = 1.0f;
            float l = sqrtf(nx * nx + ny * ny + nz * nz);
            in->nrm[4 * i + 0] = nx / l;
            in->nrm[4 * i + 1] = ny / l;
            in->nrm[4 * i + 2] = nz / l;
            in->nrm[4 * i + 3] = (float)obj;
            /* per-pixel light planes (a sphere light's plane turns with the receiver) */
            float lx = 0.3f + 0.4f * (frand() - 0.5f), ly = -0.2f + 0.4f * (frand() - 0.5f), lz = -1.0f;
            float ll = sqrtf(lx * lx + ly * ly + lz * lz);
            in->plane[4 * i + 0] = lx / ll;
            in->plane[4 * i + 1] = ly / ll;
            in->plane[4 * i + 2] = lz / ll;
            for (int k = 0; k < 3; ++k) in->value[4 * i + k] = 0.1f + 0.9f * frand();
            in->value[4 * i + 3] = frand() < 0.1f ? 0.0f : 1.0f;
            in->pixel_world[i] = pw;
            in->beta[i] = frand() < 0.15f ? 0.0f : 6.0f * pw * frand();
        }
    }
}

/* Max relative error |k - r| / |r| over rgb; values are >= 0.1 by construction. */
static double max_rel_error(const float *a, const float *b, size_t n)
{
    double worst = 0;
    for (size_t i = 0; i < n; ++i) {
        for (int k = 0; k < 4; ++k) {
            double r = b[4 * i + k], e = fabs((double)a[4 * i + k] - r) / fmax(fabs(r), 1e-3);
            if (e > worst) worst = e;
        }
    }
    return worst;
}

static bool all_finite(const float *a, size_t n)
{
    for (size_t i = 0; i < n; ++i)
        if (!isfinite(a[i])) return false;
    return true;
}

static void test_make_params(void)
{
    /* beta = 2 world at d = 0.5 world/px: 4 px; radius ceil(2 * 4) = 8; 1/(2 beta^2) = 1/8. */
    float beta[6] = {2.0f, 0.1f, 100.0f, NAN, INFINITY, -1.0f};
    float d[6] = {0.5f, 1.0f, 1.0f, 1.0f, 1.0f, 1.0f};
    float p[12];
    aaf_filter_make_params(6, beta, d, 2.0f, 16, p);
    CHECK_NEAR(p[0], 0.125, 1e-7);
    CHECK_NEAR(p[1], 8.0, 0.0);
    /* 0.1 px is below the 0.25 px threshold (neighbour weight exp(-50)): unfiltered. */
    CHECK_NEAR(p[3], 0.0, 0.0);
    /* 100 px: radius capped at 16, Gaussian kept (1/(2*100^2)). */
    CHECK_NEAR(p[5], 16.0, 0.0);
    CHECK_NEAR(p[4], 1.0 / 20000.0, 1e-10);
    /* NaN and negative widths: unfiltered; infinite width: box over the capped radius. */
    CHECK_NEAR(p[7], 0.0, 0.0);
    CHECK_NEAR(p[8], 0.0, 0.0);
    CHECK_NEAR(p[9], 16.0, 0.0);
    CHECK_NEAR(p[11], 0.0, 0.0);
    CHECK(all_finite(p, 12));
}

static void compare_with_reference(AafFilter *f, int w, int h, int mode, bool explicit_plane, float sharp_ratio)
{
    Input in;
    input_alloc(&in, w, h);
    input_random(&in);
    size_t n = (size_t)w * h;
    if (mode == AAF_DIST_PIXEL) /* widths in pixels */
        for (size_t i = 0; i < n; ++i) in.beta[i] /= in.pixel_world[i];
    aaf_filter_make_params((int)n, in.beta, mode == AAF_DIST_PIXEL ? NULL : in.pixel_world, 2.0f, 12, in.param);
    AafFilterRules rules = aaf_filter_rules_default(mode);
    rules.sharp_beta_ratio = sharp_ratio;
    float *got = calloc(4 * n, sizeof(float)), *want = calloc(4 * n, sizeof(float)), *tmp = calloc(4 * n, sizeof(float));
    Diag d = {0};
    CHECK(aaf_filter_set_guides(f, w, h, in.pos, in.nrm, &d));
    double secs = -1;
    /* the explicit plane: a unit normal per pixel (input_random) */
    bool ok = aaf_filter_run(f, in.value, explicit_plane ? in.plane : NULL, in.param, &rules, got, &secs, &d);
    CHECK(ok);
    if (!ok) fprintf(stderr, "%s\n", d.message);
    CHECK(secs >= 0.0);
    /* the kernel ignores the sharpness rule in pixel mode */
    float ref_sharp = mode == AAF_DIST_WORLD ? sharp_ratio : 0.0f;
    ref_aaf_filter(w, h, mode == AAF_DIST_PIXEL, rules.cos_normal_min, rules.depth_tol_rel, ref_sharp, in.value, in.pos,
                   in.nrm, explicit_plane ? in.plane : (mode == AAF_DIST_PIXEL ? NULL : in.nrm), in.param, tmp, want);
    double err = max_rel_error(got, want, n);
    fprintf(stderr, "%dx%d mode %d plane %d sharp %.2f: max relative error %.3g\n", w, h, mode, explicit_plane,
            (double)sharp_ratio, err);
    CHECK(err <= 1e-4);
    /* The filter actually did something (otherwise the comparison proves little). */
    CHECK(max_rel_error(got, in.value, n) > 1e-2);
    free(got);
    free(want);
    free(tmp);
    input_free(&in);
}

static void test_properties(AafFilter *f)
{
    int w = 24, h = 17;
    size_t n = (size_t)w * h;
    Input in;
    input_alloc(&in, w, h);
    input_random(&in);
    for (size_t i = 0; i < n; ++i) {
        in.beta[i] = 0.03f; /* 3 px */
        in.value[4 * i + 3] = 1.0f;
        /* objects 0/1/2 carry constant colours 0.2, 0.5, 0.8 */
        float c = 0.2f + 0.3f * in.nrm[4 * i + 3];
        in.value[4 * i + 0] = in.value[4 * i + 1] = in.value[4 * i + 2] = c;
    }
    aaf_filter_make_params((int)n, in.beta, in.pixel_world, 2.0f, 16, in.param);
    AafFilterRules rules = aaf_filter_rules_default(AAF_DIST_WORLD);
    float *out = calloc(4 * n, sizeof(float));
    Diag d = {0};
    CHECK(aaf_filter_set_guides(f, w, h, in.pos, in.nrm, &d));
    CHECK(aaf_filter_run(f, in.value, NULL, in.param, &rules, out, NULL, &d));
    /* Per-object constants survive exactly: no weight crosses an object id. */
    double worst = 0;
    for (size_t i = 0; i < n; ++i) worst = fmax(worst, fabs(out[4 * i] - in.value[4 * i]));
    CHECK(worst < 1e-6);

    /* Width 0 everywhere: the identity, bit for bit. */
    for (size_t i = 0; i < n; ++i) in.value[4 * i] = frand();
    for (size_t i = 0; i < 2 * n; ++i) in.param[i] = 0.0f;
    CHECK(aaf_filter_run(f, in.value, NULL, in.param, &rules, out, NULL, &d));
    CHECK(memcmp(out, in.value, 4 * n * sizeof(float)) == 0);

    /* Degenerate guides: zero normals, infinite positions and depths, NaN-free output. */
    for (size_t i = 0; i < n; ++i) {
        for (int k = 0; k < 3; ++k) in.nrm[4 * i + k] = 0.0f;
        if (i % 3 == 0) in.pos[4 * i] = INFINITY;
        in.beta[i] = (i % 5 == 0) ? INFINITY : 0.05f;
    }
    aaf_filter_make_params((int)n, in.beta, in.pixel_world, 2.0f, 16, in.param);
    CHECK(aaf_filter_set_guides(f, w, h, in.pos, in.nrm, &d));
    CHECK(aaf_filter_run(f, in.value, NULL, in.param, &rules, out, NULL, &d));
    CHECK(all_finite(out, 4 * n));
    free(out);
    input_free(&in);
}

/* A wide-filtered region next to a sharp one (a contact shadow beside a wide penumbra): with
 * the sharpness rule the wide pixels take nothing from the sharp ones, without it they do. */
static void test_sharp_neighbours(AafFilter *f)
{
    int w = 40, h = 6;
    size_t n = (size_t)w * h;
    Input in;
    input_alloc(&in, w, h);
    input_random(&in);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            size_t i = (size_t)y * w + x;
            /* one flat object facing +z: no other rule rejects anything */
            in.pos[4 * i + 0] = (float)x * in.pixel_world[i];
            in.pos[4 * i + 1] = (float)y * in.pixel_world[i];
            in.pos[4 * i + 2] = 0.0f;
            in.pos[4 * i + 3] = 10.0f;
            in.nrm[4 * i + 0] = in.nrm[4 * i + 1] = 0.0f;
            in.nrm[4 * i + 2] = 1.0f;
            in.nrm[4 * i + 3] = 0.0f;
            bool sharp = x < w / 2;
            in.beta[i] = (sharp ? 0.8f : 4.0f) * in.pixel_world[i]; /* px widths 0.8 and 4 */
            float v = sharp ? 0.0f : 1.0f;
            for (int k = 0; k < 3; ++k) in.value[4 * i + k] = v;
            in.value[4 * i + 3] = 1.0f;
        }
    }
    aaf_filter_make_params((int)n, in.beta, in.pixel_world, 2.0f, 16, in.param);
    AafFilterRules rules = aaf_filter_rules_default(AAF_DIST_WORLD);
    float *out = calloc(4 * n, sizeof(float));
    Diag d = {0};
    CHECK(aaf_filter_set_guides(f, w, h, in.pos, in.nrm, &d));
    size_t edge = (size_t)2 * w + w / 2; /* first wide pixel of row 2 */
    CHECK(aaf_filter_run(f, in.value, NULL, in.param, &rules, out, NULL, &d));
    CHECK(out[4 * edge] < 0.9f); /* without the rule the zeros leak in */
    rules.sharp_beta_ratio = 0.5f;
    CHECK(aaf_filter_run(f, in.value, NULL, in.param, &rules, out, NULL, &d));
    /* every wide pixel keeps exactly 1: the sharp zeros are rejected (a sharp centre may
     * still take from wide neighbours; its own narrow filter resolves them) */
    double worst = 0;
    for (int y = 0; y < h; ++y)
        for (int x = w / 2; x < w; ++x) worst = fmax(worst, fabs((double)out[4 * ((size_t)y * w + x)] - 1.0));
    CHECK(worst < 1e-6);
    free(out);
    input_free(&in);
}

int main(void)
{
    test_make_params();
    Diag d = {0};
    ClRuntime *rt = cl_runtime_create(NULL, &d);
    CHECK(rt != NULL);
    if (!rt) {
        fprintf(stderr, "%s\n", d.message);
        CHECK_DONE();
    }
    AafFilter *f = aaf_filter_create(rt, &d);
    CHECK(f != NULL);
    if (f) {
        compare_with_reference(f, 37, 23, AAF_DIST_WORLD, false, 0.0f);
        compare_with_reference(f, 37, 23, AAF_DIST_WORLD, true, 0.0f);
        compare_with_reference(f, 37, 23, AAF_DIST_WORLD, true, 0.5f);
        compare_with_reference(f, 19, 31, AAF_DIST_PIXEL, false, 0.0f);
        compare_with_reference(f, 19, 31, AAF_DIST_PIXEL, true, 0.5f);
        test_properties(f);
        test_sharp_neighbours(f);
    }
    aaf_filter_destroy(f);
    cl_runtime_destroy(rt);
    CHECK_DONE();
}
