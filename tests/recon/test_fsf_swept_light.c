/* FSF under an area light that moves during the shutter (docs/algorithms.md 10, "The swept
 * light's density"): its samples' light points lie over the area the light sweeps with a density
 * that is, along each of FSF's light axes, the pose's extent convolved with the motion's (a
 * trapezoid, fsf_swept_profile). Checked:
 *  - the closed form against the renderer's own poses: light points drawn uniformly on the
 *    light's triangles at 2000 shutter times, their coordinates along FSF's axes binned, equal
 *    the trapezoid's mass per bin (a uniform light over the swept extent, FSF before fsf13, does
 *    not), for a motion along one of the light's edges and a diagonal one (whose marginals are
 *    trapezoids too; the joint is not their product, which the filter assumes);
 *  - the density of reprojected samples, sum_t w(t) T(z - eta t) (fsf_density_swept), against
 *    samples drawn from T on every tap and shifted by eta t;
 *  - the joint density of a translating pose (fsf_swept_joint) against the same points binned in
 *    2D: the product of the marginals equals it for the motion along an edge, not the diagonal;
 *  - form 4's mean term over the swept light (fsf_geo_mean) against a fine quadrature of G
 *    weighted by the samples' density, the trapezoids' product and a diagonal sweep's joint
 *    density (the uniform mean, or the product for the diagonal, is off by far more);
 *  - the factored passes against the brute-force oracle on a moving light's frame: equal to
 *    rounding where the factoring loses nothing (bin-centred samples, on-node shears), close on
 *    jittered samples;
 *  - on a penumbra with a closed form under the swept light (an occluder edge at one depth, the
 *    samples drawn from the trapezoid), the filter with the swept profile follows the lit
 *    fraction, and with the box profile it does not. */
#include <string.h>

#include "check.h"
#include "fsf_synth.h"
#include "recon/fsf/fsf_light.h"
#include "moving_light_scene.h"
#include "recon_test_util.h"

/* the 0.8 x 0.8 light slides 2.4 along x (one of its edges), or 1.8 along x and -1.2 along z */
static const char *const ALONG = MOVING_LIGHT_HEAD
    "  ActiveTransform StartTime\n  Translate -1.2 0 0\n  ActiveTransform EndTime\n  Translate 1.2 0 0\n"
    "  ActiveTransform All\n" MOVING_LIGHT_AND_FLOOR;
static const char *const DIAGONAL = MOVING_LIGHT_HEAD
    "  ActiveTransform StartTime\n  Translate -0.9 0 0.6\n  ActiveTransform EndTime\n  Translate 0.9 0 -0.6\n"
    "  ActiveTransform All\n" MOVING_LIGHT_AND_FLOOR;

/* the trapezoid's integral over [a, b] (midpoints; exact enough for the bins' masses) */
static double profile_mass(double a, double b, float half, float ramp)
{
    enum { SUB = 400 };
    double sum = 0.0;
    for (int k = 0; k < SUB; ++k) {
        float z = (float)(a + (b - a) * (k + 0.5) / SUB);
        sum += ramp > 0.0f ? fsf_swept_profile(z, half, ramp) : (fabsf(z) <= half ? 1.0f : 0.0f);
    }
    return sum * (b - a) / SUB;
}

/* The renderer's light points over the shutter against the closed form, per axis: the largest
 * difference of a bin's share of the points from the trapezoid's share of its mass, and the
 * same for the uniform light over the swept extent (*uniform_worst). */
static double light_points_vs_closed_form(const char *scene_text, FsfLight *light, double *uniform_worst,
                                          double *joint_worst, double *product_worst)
{
    SceneDesc scene;
    Renderer *r = NULL;
    if (!recon_test_renderer(scene_text, 1, 4, false, &scene, &r)) return INFINITY;
    Diag d = {0};
    bool found = fsf_light_from_renderer(r, light, &d);
    CHECK(found);
    enum { TIMES = 2000, POINTS = 400, BINS = 32, JB = 12 };
    double hist[2][BINS] = {{0}}, joint[JB][JB] = {{0}}, total = 0.0;
    unsigned st = 12345u;
    for (int k = 0; found && k < TIMES; ++k) {
        float u = (float)((k + 0.5) / TIMES); /* the sampler's time: uniform over the shutter */
        for (int m = 0; m < renderer_light_count(r); ++m) {
            RenderLightInfo b;
            if (!renderer_light_info_at(r, m, u, &b) || b.kind != RENDER_LIGHT_AREA || b.shape != light->shape) continue;
            for (int p = 0; p < POINTS; ++p) { /* uniform on the triangle, each point weighing its area */
                float s = sqrtf(fsf_rand01(&st)), t = fsf_rand01(&st);
                vec3 q = v3_add(v3_scale(b.tri_world[0], 1.0f - s),
                                v3_add(v3_scale(b.tri_world[1], s * (1.0f - t)), v3_scale(b.tri_world[2], s * t)));
                vec3 rel = v3_sub(q, light->centre_world);
                int jb[2];
                for (int a = 0; a < 2; ++a) {
                    float y = v3_dot(rel, light->axis_world[a]);
                    int bin = (int)floorf((y + light->half_m[a]) / (2.0f * light->half_m[a]) * BINS);
                    bin = bin < 0 ? 0 : bin >= BINS ? BINS - 1 : bin;
                    hist[a][bin] += b.area_world / POINTS;
                    int j = (int)floorf((y + light->half_m[a]) / (2.0f * light->half_m[a]) * JB);
                    jb[a] = j < 0 ? 0 : j >= JB ? JB - 1 : j; /* the joint's coarser bins */
                }
                joint[jb[0]][jb[1]] += b.area_world / POINTS;
                total += b.area_world / POINTS;
            }
        }
    }
    double worst = 0.0;
    *uniform_worst = 0.0;
    for (int a = 0; a < 2; ++a) {
        float L = light->half_m[a], ramp = light->ramp_m[a];
        double all = profile_mass(-L, L, L, ramp);
        for (int b = 0; b < BINS; ++b) {
            double lo = -L + 2.0 * L * b / BINS, hi = lo + 2.0 * L / BINS, got = hist[a][b] / total;
            worst = fmax(worst, fabs(got - profile_mass(lo, hi, L, ramp) / all));
            *uniform_worst = fmax(*uniform_worst, fabs(got - 1.0 / BINS));
        }
    }
    /* the joint: fsf_swept_joint's mass per bin (16 x 16 midpoints) against the points', and the
     * product of the two trapezoids' */
    double jmass[JB][JB], pmass[JB][JB], jall = 0.0, pall = 0.0;
    for (int a = 0; a < JB; ++a)
        for (int b = 0; b < JB; ++b) {
            jmass[a][b] = pmass[a][b] = 0.0;
            for (int i = 0; i < 16; ++i)
                for (int k = 0; k < 16; ++k) {
                    float z1 = light->half_m[0] * (2.0f * ((float)a + ((float)i + 0.5f) / 16.0f) / JB - 1.0f);
                    float z2 = light->half_m[1] * (2.0f * ((float)b + ((float)k + 0.5f) / 16.0f) / JB - 1.0f);
                    jmass[a][b] += fsf_swept_joint(z1, z2, light->pose_m, light->motion_m);
                    float t1 = light->ramp_m[0] > 0.0f ? fsf_swept_profile(z1, light->half_m[0], light->ramp_m[0]) : 1.0f;
                    float t2 = light->ramp_m[1] > 0.0f ? fsf_swept_profile(z2, light->half_m[1], light->ramp_m[1]) : 1.0f;
                    pmass[a][b] += (double)t1 * t2;
                }
            jall += jmass[a][b], pall += pmass[a][b];
        }
    *joint_worst = *product_worst = 0.0;
    for (int a = 0; a < JB; ++a)
        for (int b = 0; b < JB; ++b) {
            double got = joint[a][b] / total;
            *joint_worst = fmax(*joint_worst, fabs(got - jmass[a][b] / jall));
            *product_worst = fmax(*product_worst, fabs(got - pmass[a][b] / pall));
        }
    renderer_destroy(r);
    scene_desc_free(&scene);
    return worst;
}

/* a sample of the trapezoid (half extent L, ramp) by rejection from the uniform */
static float draw_trapezoid(unsigned *st, float L, float ramp)
{
    for (;;) {
        float y = L * (2.0f * fsf_rand01(st) - 1.0f);
        if (fsf_rand01(st) < fsf_swept_profile(y, L, ramp)) return y;
    }
}

static void reprojected_density(void)
{
    const float L = 1.0f, ramp = 0.6f, eta = 0.07f, sigma = 4.0f;
    int r = fsf_radius_reach(sigma, FSF_RADIUS_SIGMAS);
    float cum[FSF_CUM];
    fsf_tap_prefix(sigma, r, cum);
    enum { BINS = 50, PER_TAP = 200000 };
    double hist[BINS] = {0}, lo = -L - eta * r, width = 2.0 * (L + eta * r) / BINS;
    unsigned st = 99u;
    for (int t = -r; t <= r; ++t) {
        double w = cum[t + r + 1] - cum[t + r];
        for (int k = 0; k < PER_TAP; ++k) {
            float z = draw_trapezoid(&st, L, ramp) + eta * (float)t; /* seen from the centre */
            int b = (int)floor((z - lo) / width);
            if (b >= 0 && b < BINS) hist[b] += w / PER_TAP;
        }
    }
    double mass = 2.0 * L - ramp, worst = 0.0, peak = 0.0; /* the trapezoid's integral */
    for (int b = 0; b < BINS; ++b) {
        double want = 0.0; /* rho's mean over the bin over T's mass: the samples' expected share */
        for (int k = 0; k < 40; ++k)
            want += fsf_density_swept((float)(lo + width * (b + (k + 0.5) / 40)), eta, L, ramp, r, cum) / 40.0;
        want *= width / mass;
        worst = fmax(worst, fabs(hist[b] - want));
        peak = fmax(peak, want);
    }
    printf("reprojected density: largest bin difference %.3g of a largest bin share %.3g\n", worst, peak);
    CHECK(worst < 0.01 * peak); /* 2e5 samples a tap: ~0.3% of a bin */
    /* no shear: T(z) times the taps' sum; the weight T / rho is then 1 / sum on the light */
    CHECK(fabsf(fsf_density_swept(0.9f, 0.0f, L, ramp, r, cum) - (cum[2 * r + 1] - cum[0]) * fsf_swept_profile(0.9f, L, ramp)) <
          1e-5f);
    CHECK(fsf_swept_weight(1.01f, 0.0f, L, ramp, r, cum) == 0.0f); /* off the light: no weight */
}

static void geo_mean_swept(void)
{
    FsfSynth f;
    fsf_synth_init(&f, 8, 4, 1);
    FsfGrid g = fsf_grid_default(1.3f, 0.4f);
    g.ramp_m[0] = 0.7f; /* kinks at +-0.6: inside the 8 cells of 0.325 */
    float mean_g[32], uniform_g[32];
    FsfGeoTerm t = {{0.02f, 0.01f, 0.9f}, {{1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}}, {0.0f, 0.0f, -1.0f}, mean_g,
                    {g.ramp_m[0], 0.0f}, {0.0f, 0.0f}, {0.0f, 0.0f}};
    fsf_geo_mean(&t, f.pos4, f.nrm4, f.usable, g.half_m, 32, mean_g);
    FsfGeoTerm tu = t;
    tu.mean_g = uniform_g, tu.ramp_m[0] = 0.0f;
    fsf_geo_mean(&tu, f.pos4, f.nrm4, f.usable, g.half_m, 32, uniform_g);
    double worst = 0.0, uniform_off = 0.0;
    for (int i = 0; i < 32; i += 5) {
        enum { N = 400 };
        double sum = 0.0, wsum = 0.0;
        for (int a = 0; a < N; ++a)
            for (int b = 0; b < N; ++b) {
                float z1 = g.half_m[0] * (2.0f * ((float)a + 0.5f) / N - 1.0f), z2 = g.half_m[1] * (2.0f * ((float)b + 0.5f) / N - 1.0f);
                double w = fsf_swept_profile(z1, g.half_m[0], g.ramp_m[0]);
                sum += w * fsf_geo_G(&t, f.pos4 + 4 * i, f.nrm4 + 4 * i, z1, z2), wsum += w;
            }
        double want = sum / wsum;
        worst = fmax(worst, fabs(mean_g[i] / want - 1.0));
        uniform_off = fmax(uniform_off, fabs(uniform_g[i] / want - 1.0));
    }
    printf("form 4's mean over the swept light: largest relative error %.3g (the uniform mean's %.3g)\n", worst,
           uniform_off);
    CHECK(worst < 2e-3);           /* the 24 x 24 rule on G's curvature (8 x 8: 2.3e-3) */
    CHECK(uniform_off > 10 * worst); /* the weighting matters here */

    /* a diagonal sweep (0.6 x 0.6 pose moving 1.9 and 0.6): the joint density (fsf_swept_joint),
     * which the two trapezoids' product is not */
    const float pose[2] = {0.6f, 0.6f}, motion[2] = {1.9f, -0.6f}, half[2] = {1.25f, 0.6f};
    FsfGeoTerm tj = t, tp = t;
    tj.ramp_m[0] = tp.ramp_m[0] = 0.6f, tj.ramp_m[1] = tp.ramp_m[1] = 0.6f;
    memcpy(tj.pose_m, pose, sizeof pose), memcpy(tj.motion_m, motion, sizeof motion);
    tp.mean_g = uniform_g; /* the product's */
    fsf_geo_mean(&tj, f.pos4, f.nrm4, f.usable, half, 32, mean_g);
    fsf_geo_mean(&tp, f.pos4, f.nrm4, f.usable, half, 32, uniform_g);
    worst = 0.0;
    double product_off = 0.0;
    for (int i = 0; i < 32; i += 5) {
        enum { N = 400 };
        double sum = 0.0, wsum = 0.0;
        for (int a = 0; a < N; ++a)
            for (int b = 0; b < N; ++b) {
                float z1 = half[0] * (2.0f * ((float)a + 0.5f) / N - 1.0f), z2 = half[1] * (2.0f * ((float)b + 0.5f) / N - 1.0f);
                double w = fsf_swept_joint(z1, z2, pose, motion);
                sum += w * fsf_geo_G(&t, f.pos4 + 4 * i, f.nrm4 + 4 * i, z1, z2), wsum += w;
            }
        worst = fmax(worst, fabs(mean_g[i] / (sum / wsum) - 1.0));
        product_off = fmax(product_off, fabs(uniform_g[i] / (sum / wsum) - 1.0));
    }
    printf("form 4's mean over a diagonal sweep: largest relative error %.3g (the trapezoids' product's %.3g)\n", worst,
           product_off);
    CHECK(worst < 2e-3); /* 8 x 8 cells: 7e-3 (GEO_M_SWEPT) */
    CHECK(product_off > 5 * worst);
    fsf_synth_free(&f);
}

/* Samples drawn from the swept light: y1 from the trapezoid (stratified in its CDF's inverse,
 * by rejection inside each stratum), y2 jittered uniform (bin-centred: at its y2 bin's centre);
 * values lit where y1 > -k X (an occluder edge at one depth over the receiver's x). */
static void swept_samples(FsfSynth *f, const FsfGrid *g, int l, bool bin_centred, float k, unsigned seed)
{
    unsigned st = seed;
    float L = g->half_m[0], ramp = g->ramp_m[0];
    double mass = profile_mass(-L, L, L, ramp);
    /* the strata's bounds in y1: equal masses of T */
    float bound[17];
    bound[0] = -L, bound[l] = L;
    for (int s = 1; s < l; ++s) {
        double target = mass * s / l, acc = 0.0;
        float y = -L, dy = 2.0f * L / 20000.0f;
        while (acc < target && y < L) acc += fsf_swept_profile(y + 0.5f * dy, L, ramp) * dy, y += dy;
        bound[s] = y;
    }
    for (size_t i = 0; i < (size_t)f->w * (size_t)f->h; ++i)
        for (int a = 0; a < l; ++a)
            for (int b = 0; b < l; ++b) {
                size_t slot = i * (size_t)f->cap + (size_t)(a * l + b);
                float y1;
                do y1 = bound[a] + (bound[a + 1] - bound[a]) * fsf_rand01(&st);
                while (!(fsf_rand01(&st) < fsf_swept_profile(y1, L, ramp)));
                float y2 = g->half_m[1] * (2.0f * ((float)b + fsf_rand01(&st)) / (float)l - 1.0f);
                if (bin_centred) y2 = -g->half_m[1] + ((float)fsf_y2_bin(g, y2) + 0.5f) * 2.0f * g->half_m[1] / (float)g->y2_bins;
                f->y[2 * slot] = y1, f->y[2 * slot + 1] = y2;
                float x_m = ((float)(i % (size_t)f->w) + 0.5f - 0.5f * (float)f->w) * 0.01f;
                float lit = y1 > -k * x_m ? 1.0f : 0.0f;
                f->v[3 * slot] = lit, f->v[3 * slot + 1] = 0.5f * lit, f->v[3 * slot + 2] = 0.25f;
            }
}

static void uniform_params(FsfSynth *f, float eta1, float eta2, float s1, float s2)
{
    for (int i = 0; i < f->w * f->h; ++i)
        f->px[i].eta_m[0] = eta1, f->px[i].eta_m[1] = eta2, f->px[i].sigma_px[0] = s1, f->px[i].sigma_px[1] = s2;
}

/* largest |factored - brute| relative to the brute force's weight (rgb and weight), and the RMS
 * of the normalised difference */
static void factored_vs_brute(const FsfSynth *f, const FsfGrid *g, double *max_rel, double *rms)
{
    size_t n = (size_t)f->w * (size_t)f->h;
    float *a = malloc(4 * n * sizeof(float)), *b = malloc(4 * n * sizeof(float));
    FsfGuides gd = fsf_guides_default(f->pos4, f->nrm4, f->usable);
    fsf_filter_brute(&f->s, g, f->px, &gd, a);
    bool ok = fsf_filter_factored(&f->s, g, f->px, &gd, b);
    CHECK(ok);
    *max_rel = 0.0, *rms = 0.0;
    for (size_t i = 0; i < n; ++i) {
        for (int c = 0; c < 4; ++c) *max_rel = fmax(*max_rel, fabs((double)a[4 * i + c] - b[4 * i + c]) / fmax(a[4 * i + 3], 1e-6));
        double d = (double)a[4 * i] / a[4 * i + 3] - (double)b[4 * i] / b[4 * i + 3];
        *rms += d * d;
    }
    *rms = sqrt(*rms / (double)n);
    free(a), free(b);
}

/* RMS error of the filtered lit fraction against the closed form (the trapezoid's mass beyond
 * -k X over its whole mass) */
static const float TRUE_RAMP = 0.8f; /* the samples' density in case 5, whatever the filter assumes */
static double penumbra_error(const FsfSynth *f, const FsfGrid *g, float k)
{
    size_t n = (size_t)f->w * (size_t)f->h;
    float *out = malloc(4 * n * sizeof(float));
    FsfGuides gd = fsf_guides_default(f->pos4, f->nrm4, f->usable);
    bool ok = fsf_filter_factored(&f->s, g, f->px, &gd, out);
    float L = g->half_m[0], ramp = TRUE_RAMP;
    double mass = profile_mass(-L, L, L, ramp), sum = 0.0;
    for (size_t i = 0; i < n; ++i) {
        float x_m = ((float)(i % (size_t)f->w) + 0.5f - 0.5f * (float)f->w) * 0.01f, edge = -k * x_m;
        double want = edge >= L ? 0.0 : edge <= -L ? 1.0 : profile_mass(edge, L, L, ramp) / mass;
        double e = (double)out[4 * i] / out[4 * i + 3] - want;
        sum += e * e;
    }
    free(out);
    return ok ? sqrt(sum / (double)n) : INFINITY;
}

/* The factored passes against the oracle on samples drawn from a light that ramps along both
 * axes (pass 1a's weights and pass 2b's) */
static void factored_on_swept_samples(void)
{
    const int W = 48, H = 40, l = 4;
    FsfSynth f;
    fsf_synth_init(&f, W, H, l);
    FsfGrid g = fsf_grid_default(1.0f, 0.5f);
    g.ramp_m[0] = 0.8f, g.ramp_m[1] = 0.3f; /* both axes ramp: pass 1a's and pass 2b's weights */
    swept_samples(&f, &g, l, true, 2.0f, 1);
    float dY1 = 4.0f * g.half_m[0] / (float)(g.shift_nodes - 1), dY2 = 4.0f * g.half_m[1] / (float)(g.shift_nodes - 1);
    uniform_params(&f, dY1, -2.0f * dY2, 3.0f, 5.0f);
    double max_rel, rms;
    factored_vs_brute(&f, &g, &max_rel, &rms);
    printf("swept light, bin-centred, on-node shears: max relative difference %.3g\n", max_rel);
    CHECK(max_rel < 1e-5);
    swept_samples(&f, &g, l, false, 2.0f, 7);
    uniform_params(&f, 0.037f, 0.029f, 4.0f, 4.0f);
    factored_vs_brute(&f, &g, &max_rel, &rms);
    printf("swept light, jittered, shears between nodes: rms difference %.4f\n", rms);
    CHECK(rms < 0.02); /* as the static light's default grid (test_fsf_factored) */
    fsf_synth_free(&f);
}

int main(void)
{
    /* 1. the closed form against the renderer's poses */
    FsfLight light;
    double uniform_worst, joint_worst, product_worst;
    double along = light_points_vs_closed_form(ALONG, &light, &uniform_worst, &joint_worst, &product_worst);
    printf("motion along an edge: joint bins off fsf_swept_joint by at most %.3g, off the trapezoids' product by %.3g\n",
           joint_worst, product_worst);
    CHECK(joint_worst < 2e-3 && product_worst < 2e-3); /* the product is the joint here */
    printf("motion along an edge: half extents %.3f %.3f, ramps %.3f %.3f; bins off the trapezoid by at most %.3g "
           "(the uniform light by %.3g)\n",
           light.half_m[0], light.half_m[1], light.ramp_m[0], light.ramp_m[1], along, uniform_worst);
    /* the 0.8 light moving 2.4 along its first axis: 1.6 and 0.8 wide ramps there, none across */
    CHECK(fabsf(light.half_m[0] - 1.6f) < 1e-3f && fabsf(light.ramp_m[0] - 0.8f) < 1e-3f);
    CHECK(fabsf(light.half_m[1] - 0.4f) < 1e-3f && light.ramp_m[1] == 0.0f);
    CHECK(along < 1.5e-3);          /* a bin holds 1/32 of the points at most; 8e5 points a pose set */
    CHECK(uniform_worst > 0.02);    /* the uniform light is off by most of an end bin */
    double diagonal = light_points_vs_closed_form(DIAGONAL, &light, &uniform_worst, &joint_worst, &product_worst);
    printf("diagonal motion: joint bins off fsf_swept_joint by at most %.3g, off the trapezoids' product by %.3g\n",
           joint_worst, product_worst);
    CHECK(joint_worst < 2e-3);
    CHECK(product_worst > 5 * joint_worst); /* a diagonal sweep is not the product of its marginals */
    printf("diagonal motion: half extents %.3f %.3f, ramps %.3f %.3f; bins off by at most %.3g (uniform %.3g)\n",
           light.half_m[0], light.half_m[1], light.ramp_m[0], light.ramp_m[1], diagonal, uniform_worst);
    CHECK(fabsf(light.half_m[0] - 1.3f) < 1e-3f && fabsf(light.half_m[1] - 1.0f) < 1e-3f);
    CHECK(fabsf(light.ramp_m[0] - 0.8f) < 1e-3f && fabsf(light.ramp_m[1] - 0.8f) < 1e-3f);
    CHECK(diagonal < 1.5e-3);
    CHECK(uniform_worst > 0.02);

    /* 2. the density of reprojected samples; 3. form 4's mean */
    reprojected_density();
    geo_mean_swept();

    /* 4. factored against brute force on a swept light's samples */
    factored_on_swept_samples();

    /* 5. the penumbra under the swept light (one ramp, along the edge's axis) */
    const int l = 4;
    FsfSynth f;
    fsf_synth_init(&f, 160, 24, l);
    FsfGrid g = fsf_grid_default(1.0f, 0.5f);
    g.ramp_m[0] = TRUE_RAMP;
    const float k = 4.0f; /* a penumbra 2 L / k = 50 px wide; reprojected up to 0.48 m, 0.6 of the ramp */
    swept_samples(&f, &g, l, false, k, 3);
    uniform_params(&f, k * 0.01f, k * 0.01f, 6.0f, 6.0f);
    double swept = penumbra_error(&f, &g, k);
    FsfGrid box = g;
    box.ramp_m[0] = 0.0f; /* the uniform light over the swept extent (FSF before fsf13) */
    double boxed = penumbra_error(&f, &box, k);
    uniform_params(&f, 0.0f, 0.0f, 0.0f, 0.0f);
    double mc = penumbra_error(&f, &g, k);
    printf("penumbra under the swept light: rms error %.4f with its density, %.4f as a uniform light, Monte Carlo %.4f\n",
           swept, boxed, mc);
    CHECK(swept < 0.2 * mc);    /* measured 0.0013 against 0.027 */
    CHECK(swept < 0.25 * boxed); /* against 0.012: the box tapers the penumbra's ends */
    fsf_synth_free(&f);
    return check_failures ? 1 : 0;
}
