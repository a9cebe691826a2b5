/* The reconstruction stage's two-way parallel for (recon_parallel.c) and the per-pixel maps
 * that use it: every index is visited exactly once whatever the size, and a parameter map
 * computed on both cores (an image large enough to be split) equals a brute-force,
 * single-threaded evaluation of the same formulas pixel by pixel. */
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>

#include "check.h"
#include "recon/aaf/aaf_pixel_params.h"
#include "recon/recon_parallel.h"

typedef struct {
    unsigned char *visits;
    size_t begin[RECON_PARTS], end[RECON_PARTS];
    int calls[RECON_PARTS];
} Coverage;

static void mark(void *ctx, size_t begin, size_t end, int part)
{
    Coverage *c = ctx;
    c->begin[part] = begin;
    c->end[part] = end;
    c->calls[part]++;
    for (size_t i = begin; i < end; ++i) c->visits[i]++;
}

static void test_coverage(size_t n)
{
    Coverage c = {calloc(n ? n : 1, 1), {0}, {0}, {0}};
    recon_parallel_for(n, mark, &c);
    for (size_t i = 0; i < n; ++i) CHECK(c.visits[i] == 1);
    /* one call per part, consecutive ranges from 0 to n */
    for (int p = 0; p < RECON_PARTS; ++p) CHECK(c.calls[p] == 1);
    CHECK(c.begin[0] == 0);
    CHECK(c.end[RECON_PARTS - 1] == n);
    for (int p = 1; p < RECON_PARTS; ++p) CHECK(c.begin[p] == c.end[p - 1]);
    free(c.visits);
}

/* Shadow parameters on a 160 x 120 image (split between the cores, summed-area tables built
 * two per core) against the formulas applied pixel by pixel with the neighbours' averages
 * summed directly over each pixel's window, and far pixels' widths from a brute-force search
 * for the nearest occluded pixel. */
static void test_shadow_map_matches_brute_force(void)
{
    enum { W = 160, H = 120, R = 5 };
    size_t n = (size_t)W * H;
    unsigned char *hit = malloc(n);
    float *pw = malloc(n * 4), *d1 = malloc(n * 4), *d2min = calloc(n, 4), *d2max = calloc(n, 4), *sig = malloc(n * 4);
    float *beta = malloc(n * 4);
    int *spp = malloc(n * sizeof(int));
    unsigned s = 12345u;
    for (size_t i = 0; i < n; ++i) {
        s = s * 1664525u + 1013904223u;
        float u = (float)(s >> 8) / 16777216.0f;
        hit[i] = (s >> 3) % 10 != 0;      /* some pixels see the background */
        pw[i] = 0.002f + 0.001f * u;
        d1[i] = 2.0f + u;
        sig[i] = 0.1f;
        if ((s >> 5) % 3 == 0) {          /* a third of the pixels saw an occluder */
            d2min[i] = d1[i] * (0.2f + 0.3f * u);
            d2max[i] = d2min[i] + 0.3f * u;
        }
    }
    /* a block with no occluder anywhere near: the far width */
    for (int y = 40; y < 80; ++y)
        for (int x = 60; x < 120; ++x) d2min[(size_t)y * W + x] = d2max[(size_t)y * W + x] = 0.0f;
    AafPixelStats st = {0};
    st.width = W;
    st.height = H;
    st.hit = hit;
    st.pixel_world = pw;
    st.d1_world = d1;
    st.d2min_world = d2min;
    st.d2max_world = d2max;
    st.sigma_light_world = sig;
    AafShadowConfig c = aaf_shadow_config_default();
    /* far width 8 px (reach 16): wider than the block's border, so it gets narrowed there */
    AafImageConfig ic = {R, 9, 200.0f, 8.0f, 12};
    int filtered = aaf_shadow_params_image(&st, &c, &ic, beta, spp);
    int expect_filtered = 0, mismatches = 0;
    int reach = (int)ceilf(2.0f * ic.far_beta_px);
    for (int y = 0; y < H; ++y) {
        for (int x = 0; x < W; ++x) {
            size_t i = (size_t)y * W + x;
            float eb = 0.0f;
            int es = ic.spp_min;
            if (hit[i]) {
                bool self = d2max[i] > 0.0f;
                float a = 0, b = 0, cc = 0;
                bool have = false;
                /* leave-one-out mean over the 3 x 3 window, else the borrow window */
                int radii[2] = {1, R};
                for (int k = 0; k < 2 && !have; ++k) {
                    double s1 = 0, s2 = 0, s3 = 0, cnt = 0;
                    for (int yy = y - radii[k]; yy <= y + radii[k]; ++yy)
                        for (int xx = x - radii[k]; xx <= x + radii[k]; ++xx) {
                            if (xx < 0 || yy < 0 || xx >= W || yy >= H || (xx == x && yy == y)) continue;
                            size_t j = (size_t)yy * W + xx;
                            if (!hit[j] || !(d2max[j] > 0.0f)) continue;
                            s1 += d1[j], s2 += d2min[j], s3 += d2max[j], cnt += 1;
                        }
                    if (cnt > 0) {
                        a = (float)(s1 / cnt), b = (float)(s2 / cnt), cc = (float)(s3 / cnt);
                        have = true;
                    }
                }
                if (!have && self) { /* isolated: its own rays */
                    a = d1[i], b = d2min[i], cc = d2max[i];
                    have = true;
                }
                if (have) {
                    float sl1, sl2;
                    aaf_shadow_slopes(a, b, cc, &sl1, &sl2);
                    eb = aaf_shadow_beta_world(sl2, sig[i], pw[i], &c);
                    es = aaf_clamp_spp(aaf_shadow_spp(sl1, sl2, sig[i], pw[i], &c), ic.spp_min, ic.spp_cap);
                } else {
                    /* far: the Chebyshev distance to the nearest pixel that saw an occluder
                     * bounds the filter radius (taps end one pixel before it) */
                    int dist = reach + 1;
                    for (size_t j = 0; j < n; ++j) {
                        if (!hit[j] || !(d2max[j] > 0.0f)) continue;
                        int dx = abs((int)(j % W) - x), dy = abs((int)(j / W) - y);
                        int dd = dx > dy ? dx : dy;
                        if (dd < dist) dist = dd;
                    }
                    float bpx = ic.far_beta_px;
                    if (dist <= reach && 0.4995f * (float)(dist - 1) < bpx) bpx = 0.4995f * (float)(dist - 1);
                    eb = bpx * pw[i];
                    es = ic.far_spp;
                    if (ceilf(2.0f * bpx) >= (float)dist) ++mismatches; /* a tap would reach it */
                }
            }
            if (eb > 0.0f) ++expect_filtered;
            /* the table and the direct sum round differently: widths agree to float precision */
            bool same = fabsf(beta[i] - eb) <= 1e-5f * eb + 1e-12f && abs(spp[i] - es) <= 1;
            if (!same) ++mismatches;
        }
    }
    CHECK(mismatches == 0);
    CHECK(filtered == expect_filtered);
    free(hit);
    free(pw);
    free(d1);
    free(d2min);
    free(d2max);
    free(sig);
    free(beta);
    free(spp);
}

int main(void)
{
    size_t sizes[] = {0, 1, 3, 4095, 4096, 100003};
    for (size_t k = 0; k < sizeof sizes / sizeof sizes[0]; ++k) test_coverage(sizes[k]);
    test_shadow_map_matches_brute_force();
    CHECK_DONE();
}
