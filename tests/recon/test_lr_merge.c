/* LR's merged layers (lr_partition.c: lr_layers_merge, lr_tile_finish; docs/algorithms.md
 * 8.34). (1) Neighbouring layers with the same shear and screen filter composite (eq. 17)
 * exactly as their union: on a convoy (three objects moving together) and a pinhole's static
 * layers, the C reconstruction with merging matches the one without to float rounding, with
 * fewer partitions. (2) The rule at its tolerances: a shift of just under / over
 * merge_shift_sigmas screen sigmas, screen sigmas just within / past merge_sigma_share, another
 * rotation, merging off. (3) lr_tile_finish's runs: raw layers of one partition with an
 * empty raw layer between them map to it, the empty one and the ids past the tile's raw
 * layers to -1, and lr_tile_layer_end ends the run after its last raw layer. (4) A tile whose
 * 17 raw layer ids (8 slabs, moving and static, and the misses) all hold samples keeps 17
 * partitions (the tile's arrays were one short: under ASan an overflow). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../check.h"
#include "lr_scene.h"
#include "recon/lr/lr_reconstruct.h"

static int partitions(const LrSamples *img, const LrConfig *cfg)
{
    int ntx, nty, count = 0;
    lr_tile_count(img, cfg, &ntx, &nty);
    for (int ty = 0; ty < nty; ++ty)
        for (int tx = 0; tx < ntx; ++tx) {
            LrTile t;
            lr_tile_partition(img, cfg, tx, ty, &t);
            count += t.layer_count;
        }
    return count;
}

static void check_exact_merge(const LrTestLayer *layers, int nl)
{
    enum { W = 48, H = 40, SPP = 4 };
    LrSample *s = malloc(sizeof(LrSample) * W * H * SPP);
    lr_test_scene(s, W, H, SPP, layers, nl, 17);
    LrSamples img = lr_samples_split(W, H, SPP, s);
    LrConfig on = lr_config_default(), off = on;
    off.merge_shift_sigmas = 0.0f;
    float *a = malloc(sizeof(float) * 3 * W * H), *b = malloc(sizeof(float) * 3 * W * H);
    LrOutput oa = {a, NULL, NULL, 0}, ob = {b, NULL, NULL, 0};
    lr_reconstruct_c(&img, &off, &oa);
    lr_reconstruct_c(&img, &on, &ob);
    double worst = 0.0;
    for (int i = 0; i < 3 * W * H; ++i) worst = fmax(worst, fabs(a[i] - b[i]));
    int n_off = partitions(&img, &off), n_on = partitions(&img, &on);
    CHECK(n_on < n_off);
    /* values <= ~1.5: a few float roundings of the normalisation */
    CHECK(worst <= 2e-6);
    if (!(worst <= 2e-6) || !(n_on < n_off)) fprintf(stderr, "merge: partitions %d -> %d, worst %g\n", n_off, n_on, worst);
    lr_samples_free(&img);
    free(a), free(b), free(s);
}

static void check_rule(void)
{
    LrConfig cfg = lr_config_default();
    LrSlopes slopes = {2.0f, 2.6f, 3.0f, 3.5f};
    LrFilter a = lr_filter_make(&slopes, &cfg.filter);
    float sigma = fminf(1.0f / a.inv_sigma_x_px, 1.0f / a.inv_sigma_y_px), k = cfg.merge_sigma_share;
    CHECK(sigma > 0.0f && isfinite(sigma));
    LrFilter b = a;
    CHECK(lr_layers_merge(&cfg, &a, 1.0f, 0.0f, &b, 1.0f, 0.0f)); /* the same filter */
    CHECK(!lr_layers_merge(&cfg, &a, 1.0f, 0.0f, &b, 0.8f, 0.6f)); /* another rotation */
    b.eta_px = a.eta_px + 0.99f * cfg.merge_shift_sigmas * sigma;
    CHECK(lr_layers_merge(&cfg, &a, 1.0f, 0.0f, &b, 1.0f, 0.0f));
    b.eta_px = a.eta_px + 1.01f * cfg.merge_shift_sigmas * sigma;
    CHECK(!lr_layers_merge(&cfg, &a, 1.0f, 0.0f, &b, 1.0f, 0.0f));
    b = a, b.xi_px = a.xi_px + 2.02f * cfg.merge_shift_sigmas * sigma; /* xi counts half (|t - 1/2| <= 1/2) */
    CHECK(!lr_layers_merge(&cfg, &a, 1.0f, 0.0f, &b, 1.0f, 0.0f));
    b.xi_px = a.xi_px + 1.98f * cfg.merge_shift_sigmas * sigma;
    CHECK(lr_layers_merge(&cfg, &a, 1.0f, 0.0f, &b, 1.0f, 0.0f));
    b = a, b.inv_sigma_y_px = a.inv_sigma_y_px * (1.0f + 0.99f * k);
    CHECK(lr_layers_merge(&cfg, &a, 1.0f, 0.0f, &b, 1.0f, 0.0f));
    b.inv_sigma_y_px = a.inv_sigma_y_px * (1.0f + 1.01f * k);
    CHECK(!lr_layers_merge(&cfg, &a, 1.0f, 0.0f, &b, 1.0f, 0.0f));
    b = a, b.inv_sigma_t = a.inv_sigma_t + 1.0f; /* other sample weights */
    CHECK(!lr_layers_merge(&cfg, &a, 1.0f, 0.0f, &b, 1.0f, 0.0f));
    cfg.merge_shift_sigmas = 0.0f; /* off */
    CHECK(!lr_layers_merge(&cfg, &a, 1.0f, 0.0f, &a, 1.0f, 0.0f));
}

static void check_runs(void)
{
    LrConfig cfg = lr_config_default();
    cfg.gap_slabs = 0, cfg.focus_bounds = 0; /* 4 uniform slabs, 9 raw layers: ids past them */
    LrTile t;
    lr_tile_bounds(&cfg, 1.0f, 9.0f, &t);
    int raw_n = lr_tile_raw_count(&t);
    CHECK(raw_n >= 5 && raw_n < LR_MAX_LAYERS + 1);
    LrLayerStats st[LR_MAX_LAYERS + 1];
    for (int i = 0; i < raw_n; ++i) st[i] = (LrLayerStats){0, 1.0f, 0.0f, INFINITY, -INFINITY, INFINITY, -INFINITY, 0.0f, 0.0f, {{0}}};
    LrLayerStats same = {50, 1.0f, 0.0f, 1.0f, 1.2f, 0.0f, 0.0f, 0.0f, 50.0f, {{0}}};
    st[1] = same, st[3] = same;                                              /* 2 empty between */
    st[4] = (LrLayerStats){50, 1.0f, 0.0f, 9.0f, 9.5f, 0.0f, 0.0f, 0.0f, 50.0f, {{0}}}; /* far blurrier */
    lr_tile_finish(&cfg, st, &t);
    CHECK(t.layer_count == 2);
    CHECK(t.compact[0] == -1 && t.compact[1] == 0 && t.compact[2] == -1 && t.compact[3] == 0 && t.compact[4] == 1);
    CHECK(t.layer[0].count == 100 && t.layer[1].count == 50);
    CHECK(lr_tile_layer_end(&t, raw_n, 0) == 4 && lr_tile_layer_end(&t, raw_n, 1) == 5);
    int past = 0;
    for (int i = raw_n; i < LR_MAX_LAYERS + 1; ++i) past += t.compact[i] != -1;
    CHECK(past == 0);
    cfg.merge_shift_sigmas = 0.0f; /* off: three partitions */
    lr_tile_bounds(&cfg, 1.0f, 9.0f, &t);
    lr_tile_finish(&cfg, st, &t);
    CHECK(t.layer_count == 3 && t.compact[1] == 0 && t.compact[3] == 1 && t.compact[4] == 2);
}

static void check_full_tile(void)
{
    LrConfig cfg = lr_config_default();
    cfg.merge_shift_sigmas = 0.0f; /* no merging: every raw layer its own partition */
    LrTile t;
    memset(&t, 0, sizeof t);
    t.n_depth = 7; /* 8 slabs: split into moving and static, plus the misses */
    for (int i = 0; i < t.n_depth; ++i) t.depth_bound[i] = 1.0f + (float)i;
    int raw_n = lr_tile_raw_count(&t);
    CHECK(raw_n == LR_MAX_LAYERS + 1);
    LrLayerStats st[LR_MAX_LAYERS + 1];
    for (int i = 0; i < raw_n; ++i) {
        float c = 0.5f + 3.0f * (float)i; /* CoC ranges far apart */
        st[i] = (LrLayerStats){10 + i, 1.0f, 0.0f, c, c + 0.1f, 0.0f, 0.0f, 0.0f, 10.0f, {{0}}};
    }
    lr_tile_finish(&cfg, st, &t);
    CHECK(t.layer_count == raw_n);
    int ok = 1;
    for (int i = 0; i < raw_n && i < t.layer_count; ++i) ok &= t.compact[i] == i && t.layer[i].count == 10 + i;
    CHECK(ok);
}

int main(void)
{
    LrTestLayer convoy[3] = {{2.0f, 0.0f, {6.0f, 0.0f}, 20.0f, 17.0f, 9.0f, 0.7f}, {4.0f, 0.0f, {6.0f, 0.0f}, 28.0f, 20.0f, 8.0f, 0.5f},
                             {9.0f, 0.0f, {6.0f, 0.0f}, 0, 0, 0, 0.4f}};
    LrTestLayer pinhole[3] = {{2.0f, 0.0f, {0.0f, 0.0f}, 20.0f, 17.0f, 9.0f, 0.7f}, {4.0f, 0.0f, {0.0f, 0.0f}, 28.0f, 20.0f, 8.0f, 0.5f},
                              {9.0f, 0.0f, {0.0f, 0.0f}, 0, 0, 0, 0.4f}};
    check_exact_merge(convoy, 3);
    check_exact_merge(pinhole, 3);
    check_rule();
    check_runs();
    check_full_tile();
    CHECK_DONE();
}
