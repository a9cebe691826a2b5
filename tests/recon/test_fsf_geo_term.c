/* FSF's geometric-term correction (form 4, fsf_geo_term.h) on a penumbra where the light's
 * geometric term varies strongly: a 1 m square light only 0.6 m above a plane, over a
 * straight occluder edge halfway (a 100 px penumbra at 0.01 m per pixel). The reference is
 * the G-weighted lit fraction S(x) = integral_{lit} G dA / integral G dA, by a fine midpoint
 * sum; the samples carry V G(y) / mean G as the pipeline's demodulated light does. Without
 * the correction the shear reprojects each neighbour's visibility but keeps its term at the
 * light point it was taken at, a bias that does not fall with the samples; with it (passes 1a
 * and 2a and the oracle, the same weight) the error must fall. Twice: the edge across the
 * first light axis (the penumbra along the first gather, pass 1a's factor) and across the
 * second (the penumbra along the second gather, pass 2a's factor). Also: the factored passes
 * follow the oracle with the correction as closely as without it. */
#include <string.h>

#include "check.h"
#include "fsf_synth.h"

enum { LONG = 160, SHORT = 24, L_SAMPLES = 4 };
static int W, H;   /* the frame: LONG along the axis across the edge */
static int AXIS;   /* 0: the edge across the first light axis (along y), 1: across the second */
static const float PIXEL_M = 0.01f;
static const float HALF_M = 0.5f, LIGHT_H_M = 0.6f, OCC_H_M = 0.3f;

/* the receiver's coordinates, centred under the light and the occluder's edge */
static float receiver_x(int x) { return ((float)x + 0.5f - 0.5f * W) * PIXEL_M; }
static float receiver_y(int y) { return ((float)y + 0.5f - 0.5f * H) * PIXEL_M; }

/* the occluder: the half-plane x < 0 (AXIS 0; y < 0 for AXIS 1) at height OCC_H_M; a ray from
 * the receiver coordinate p to the light coordinate y along that axis crosses that height at
 * p + (y - p) OCC_H_M / LIGHT_H_M */
static bool lit_1d(float p, float y) { return p + (y - p) * (OCC_H_M / LIGHT_H_M) >= 0.0f; }
static bool lit(const float *pos, float y1, float y2) { return AXIS ? lit_1d(pos[1], y2) : lit_1d(pos[0], y1); }

/* RMS error of the filter's result against ref over the pixels whose reference is strictly
 * inside the penumbra (the bias lives there) */
static double rms(const float *out, const double *ref)
{
    double sum = 0.0;
    int n = 0;
    for (int i = 0; i < W * H; ++i) {
        if (!(ref[i] > 0.02 && ref[i] < 0.98)) continue;
        double e = (double)out[4 * i] / out[4 * i + 3] - ref[i];
        sum += e * e, ++n;
    }
    return n ? sqrt(sum / n) : INFINITY;
}

/* One orientation: the four errors (factored, with form 4; oracle, with form 4) into e, the
 * largest |factored - oracle| without and with it into d. */
static void run(int axis, double e[4], double d[2])
{
    AXIS = axis, W = axis ? SHORT : LONG, H = axis ? LONG : SHORT;
    FsfSynth f;
    fsf_synth_init(&f, W, H, L_SAMPLES);
    size_t n = (size_t)W * H;
    for (size_t i = 0; i < n; ++i)
        f.pos4[4 * i] = receiver_x((int)(i % W)), f.pos4[4 * i + 1] = receiver_y((int)(i / W));
    FsfGrid g = fsf_grid_default(HALF_M, HALF_M);
    fsf_synth_light(&f, &g, L_SAMPLES, false, 5);
    float *mean_g = malloc(n * sizeof(float));
    FsfGeoTerm geo = fsf_synth_geo(&f, &g, 0.0f, 0.0f, LIGHT_H_M, mean_g);
    /* the reference and the exact mean term (demodulation), by a 200 x 200 midpoint sum */
    double *ref = malloc(n * sizeof(double));
    double g_lo = INFINITY, g_hi = 0.0;
    for (size_t i = 0; i < n; ++i) {
        const float *p = f.pos4 + 4 * i, *nr = f.nrm4 + 4 * i;
        double all = 0.0, lit_sum = 0.0;
        const int M = 200;
        for (int a = 0; a < M; ++a)
            for (int b = 0; b < M; ++b) {
                float z1 = HALF_M * (2.0f * ((float)a + 0.5f) / M - 1.0f), z2 = HALF_M * (2.0f * ((float)b + 0.5f) / M - 1.0f);
                double G = fsf_geo_G(&geo, p, nr, z1, z2);
                all += G, lit_sum += lit(p, z1, z2) ? G : 0.0;
                if (i == (size_t)(H / 2 * W + W / 2)) g_lo = fmin(g_lo, G), g_hi = fmax(g_hi, G);
            }
        ref[i] = lit_sum / all;
        double mean = all / (M * M);
        for (int k = 0; k < f.cap; ++k) {
            size_t slot = i * (size_t)f.cap + (size_t)k;
            float y1 = f.y[2 * slot], y2 = f.y[2 * slot + 1];
            float v = lit(p, y1, y2) ? (float)(fsf_geo_G(&geo, p, nr, y1, y2) / mean) : 0.0f;
            f.v[3 * slot] = f.v[3 * slot + 1] = f.v[3 * slot + 2] = v;
        }
        /* one occluder depth: k = (d_light - d_occ) / d_occ on both axes, the paper's cap */
        f.px[i].eta_m[0] = f.px[i].eta_m[1] = (LIGHT_H_M - OCC_H_M) / OCC_H_M * PIXEL_M;
        f.px[i].sigma_px[0] = f.px[i].sigma_px[1] = 8.0f;
    }
    printf("edge across light axis %d: G over the light at the frame's centre: %.3g to %.3g (1/m^2)\n", axis + 1,
           g_lo, g_hi);
    CHECK(g_hi > 2.5 * g_lo); /* the case needs a term that varies */
    float *out[4];
    for (int k = 0; k < 4; ++k) out[k] = malloc(4 * n * sizeof(float));
    FsfGuides plain = fsf_guides_default(f.pos4, f.nrm4, f.usable), corrected = plain;
    corrected.geo = &geo;
    CHECK(fsf_filter_factored(&f.s, &g, f.px, &plain, out[0]));
    CHECK(fsf_filter_factored(&f.s, &g, f.px, &corrected, out[1]));
    fsf_filter_brute(&f.s, &g, f.px, &plain, out[2]);
    fsf_filter_brute(&f.s, &g, f.px, &corrected, out[3]);
    for (int k = 0; k < 4; ++k) e[k] = rms(out[k], ref);
    printf("  rms error in the penumbra: factored %.4f, with form 4 %.4f; oracle %.4f, with form 4 %.4f\n", e[0], e[1],
           e[2], e[3]);
    d[0] = d[1] = 0.0;
    for (size_t i = 0; i < n; ++i) {
        d[0] = fmax(d[0], fabs(out[0][4 * i] / out[0][4 * i + 3] - out[2][4 * i] / out[2][4 * i + 3]));
        d[1] = fmax(d[1], fabs(out[1][4 * i] / out[1][4 * i + 3] - out[3][4 * i] / out[3][4 * i + 3]));
    }
    printf("  largest |factored - oracle|: %.4f without, %.4f with form 4\n", d[0], d[1]);
    for (int k = 0; k < 4; ++k) free(out[k]);
    free(ref), free(mean_g);
    fsf_synth_free(&f);
}

/* fsf_geo_mean (vector loops over blocks of pixels) against its definition one pixel and one
 * light point at a time through fsf_geo_G: 0 where not usable or a light corner is below the
 * horizon, else the double sum of the 8 x 8 midpoints in a, b order over 64. Receivers above,
 * beside and tilted under a light, some facing away, some straddling (one corner below); 600
 * pixels, so the last block is partial. Must be equal, not close. */
static void geo_mean_exact(void)
{
    enum { NP = 600, M = 8 };
    FsfGeoTerm t = {{0.1f, 1.2f, -0.3f}, {{0.8f, 0.0f, 0.6f}, {0.0f, 1.0f, 0.0f}}, {0.6f, 0.0f, -0.8f}, NULL, {0.0f, 0.0f}, {0.0f, 0.0f}, {0.0f, 0.0f}};
    const float half_m[2] = {0.4f, 0.25f};
    float *pos = malloc(sizeof(float) * 4 * NP), *nrm = malloc(sizeof(float) * 4 * NP), *got = malloc(sizeof(float) * NP);
    unsigned char *usable = malloc(NP);
    unsigned s = 9;
    int kept = 0, corners = 0, only_below[4] = {0}, differ = 0;
    float r[6];
    for (int i = 0; i < NP; ++i) {
        for (int k = 0; k < 6; ++k) s = s * 1664525u + 1013904223u, r[k] = (float)(s >> 8 & 65535) / 65535.0f;
        /* within a metre of the light, below it; a normal anywhere on the sphere */
        pos[4 * i] = 2.0f * r[0] - 0.9f, pos[4 * i + 1] = 1.5f * r[1] - 0.5f, pos[4 * i + 2] = 2.0f * r[2] - 1.3f;
        pos[4 * i + 3] = 1.0f;
        float nx = 2.0f * r[3] - 1.0f, ny = 2.0f * r[4] - 0.7f, nz = 2.0f * r[5] - 1.0f, len = sqrtf(nx * nx + ny * ny + nz * nz);
        nrm[4 * i] = nx / len, nrm[4 * i + 1] = ny / len, nrm[4 * i + 2] = nz / len, nrm[4 * i + 3] = 0.0f;
        usable[i] = i % 11 != 0;
    }
    fsf_geo_mean(&t, pos, nrm, usable, half_m, NP, got);
    for (int i = 0; i < NP; ++i) {
        const float *p = pos + 4 * i, *nr = nrm + 4 * i;
        float want = 0.0f;
        int above = 1, below = 0, which = 0;
        for (int c = 0; c < 4; ++c) {
            int up = fsf_geo_G(&t, p, nr, (c & 1 ? 1.0f : -1.0f) * half_m[0], (c & 2 ? 1.0f : -1.0f) * half_m[1]) > 0.0f;
            above &= up, below += !up, which = up ? which : c;
        }
        if (usable[i] && below == 1) only_below[which]++;
        if (usable[i] && above) {
            double sum = 0.0;
            for (int a = 0; a < M; ++a)
                for (int b = 0; b < M; ++b)
                    sum += fsf_geo_G(&t, p, nr, half_m[0] * (2.0f * ((float)a + 0.5f) / (float)M - 1.0f),
                                     half_m[1] * (2.0f * ((float)b + 0.5f) / (float)M - 1.0f));
            float mean = (float)(sum / (double)(M * M));
            want = isfinite(mean) && mean > 0.0f ? mean : 0.0f;
        }
        kept += want > 0.0f, corners += usable[i] && !above;
        differ += memcmp(&want, &got[i], sizeof(float)) != 0;
    }
    printf("fsf_geo_mean: %d of %d pixels with a mean term, %d with a corner below the horizon (only corner 0, 1, 2, 3: "
           "%d, %d, %d, %d), %d differ\n",
           kept, NP, corners, only_below[0], only_below[1], only_below[2], only_below[3], differ);
    CHECK(differ == 0);
    CHECK(kept > 10 && corners > 10); /* the cases exercised, each corner alone below the horizon too */
    for (int c = 0; c < 4; ++c) CHECK(only_below[c] > 0);
    free(pos), free(nrm), free(got), free(usable);
}

int main(void)
{
    geo_mean_exact();
    double e[4], d[2];
    for (int axis = 0; axis < 2; ++axis) {
        run(axis, e, d);
        /* the correction removes most of the bias, in both forms and along either axis.
         * Measured: edge across axis 1: factored 0.0159 -> 0.0057, oracle 0.0137 -> 0.0047
         * (pass 1a's factor alone: 0.0054, 0.0046); across axis 2: 0.0154 -> 0.0039, oracle
         * 0.0134 -> 0.0032, where pass 1a's factor alone leaves 0.0103, 0.0109 (fails here) */
        CHECK(e[1] < 0.5 * e[0]);
        CHECK(e[3] < 0.5 * e[2]);
        /* the factored passes and the oracle apply the same weight: they differ by the
         * factorisation only, no more with the correction than without */
        CHECK(d[1] < 1.5 * d[0] + 1e-3);
    }
    return check_failures ? 1 : 0;
}
