/* LR's histogram-gap layer bounds (lr_partition.h: lr_gap_bounds, LrConfig.gap_slabs;
 * docs/algorithms.md 8.22): the dynamic programme against a brute-force search over every
 * choice of split points on small histograms, and on a synthetic window of two surfaces (a
 * disk in front of a plane, each with its own CoC slope) the bounds fall in the histogram's
 * gap: no layer holds samples of both surfaces, and a single bound lies between them. A window
 * whose hits hardly move (LrConfig.still_gap_slabs, still_moving_permille) spends the 17 raw
 * layer ids on twice the slabs, no moving/static split: its layers span less CoC, and a window
 * whose moving share is over the threshold keeps the split slabs.
 * (C vs OpenCL with these bounds: test_lr_cl.c.) */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "../check.h"
#include "lr_scene.h"

/* The cost lr_gap_bounds minimises, of the groups that the given bounds cut the occupied bins into. */
static int64_t cost_of(const int *hist, const float *edges, const float *bounds, int nb)
{
    int64_t total = 0;
    for (int g = 0; g <= nb; ++g) {
        int first = -1, last = -1;
        int64_t n = 0;
        for (int b = 0; b < LR_GAP_BINS; ++b) {
            if (!hist[b]) continue;
            /* a bin's samples lie in (edges[b-1], edges[b]]: its group is the bounds below its upper edge */
            float upper = b < LR_GAP_BINS - 1 ? edges[b] : INFINITY;
            int k = 0;
            for (int i = 0; i < nb; ++i) k += upper > bounds[i];
            if (k != g) continue;
            if (first < 0) first = b;
            last = b, n += hist[b];
        }
        if (first >= 0) total += n * (int64_t)(last - first + 1) * (last - first + 1);
    }
    return total;
}

/* Least cost over every set of at most max_bounds split points between consecutive occupied
 * bins (bitmask enumeration). */
static int64_t brute_force(const int *hist, const float *edges, int max_bounds)
{
    int occ[LR_GAP_BINS], m = 0;
    for (int b = 0; b < LR_GAP_BINS; ++b)
        if (hist[b]) occ[m++] = b;
    int64_t best = INT64_MAX;
    for (unsigned mask = 0; mask < (1u << (m > 1 ? m - 1 : 0)); ++mask) {
        float bounds[LR_GAP_BINS];
        int nb = 0;
        for (int i = 0; i + 1 < m; ++i)
            if (mask & (1u << i)) bounds[nb++] = edges[occ[i]];
        if (nb > max_bounds) continue;
        int64_t c = cost_of(hist, edges, bounds, nb);
        if (c < best) best = c;
    }
    return best;
}

static void test_dp_is_optimal(void)
{
    float edges[LR_GAP_BINS - 1];
    lr_gap_edges(edges);
    for (int i = 0; i + 1 < LR_GAP_BINS - 1; ++i) CHECK(edges[i] < edges[i + 1]);
    CHECK(edges[LR_GAP_BINS / 2 - 1] == 0.0f); /* a bin edge at focus */
    unsigned seed = 11;
    int worse = 0, not_ascending = 0, too_many = 0;
    for (int trial = 0; trial < 300; ++trial) {
        int hist[LR_GAP_BINS] = {0};
        int occupied = 1 + (int)(lr_test_rand(&seed) % 12); /* up to 11 split points: 2048 masks */
        for (int i = 0; i < occupied; ++i) hist[lr_test_rand(&seed) % LR_GAP_BINS] += 1 + (int)(lr_test_rand(&seed) % 500);
        int max_bounds = (int)(lr_test_rand(&seed) % (LR_MAX_COC_BOUNDS + 1)); /* a still window's 15 too */
        float bounds[LR_MAX_COC_BOUNDS];
        int nb = lr_gap_bounds(hist, edges, max_bounds, bounds);
        too_many += nb > max_bounds;
        for (int i = 0; i + 1 < nb; ++i) not_ascending += !(bounds[i] < bounds[i + 1]);
        worse += cost_of(hist, edges, bounds, nb) != brute_force(hist, edges, max_bounds);
    }
    CHECK(worse == 0 && not_ascending == 0 && too_many == 0);
    if (worse) fprintf(stderr, "dynamic programme above the brute-force optimum in %d of 300\n", worse);
}

/* A disk (c = -3 px) over a plane (c = +5 px), c jittered by +-0.6 px as a tilted surface
 * spreads it: the window of tile (1, 1) sees both. */
static void test_two_surfaces(int gap_slabs)
{
    enum { w = 48, h = 40, spp = 8 };
    LrTestLayer layers[2] = {{2.0f, -3.0f, {0.0f, 0.0f}, 22.0f, 19.0f, 11.0f, 0.7f}, {8.0f, 5.0f, {0.0f, 0.0f}, 0, 0, 0, 0.4f}};
    LrSample *s = malloc(sizeof(LrSample) * w * h * spp);
    lr_test_scene(s, w, h, spp, layers, 2, 7);
    unsigned seed = 3;
    for (int i = 0; i < w * h * spp; ++i) s[i].coc_px += 1.2f * (lr_test_unit(&seed) - 0.5f);
    LrSamples img = lr_samples_split(w, h, spp, s);
    LrConfig cfg = lr_config_default();
    cfg.gap_slabs = gap_slabs;
    cfg.still_gap_slabs = 0; /* the window does not move: gap_slabs for it too */
    cfg.tile_px = 16, cfg.window_px = 32; /* tile (1, 1)'s window: pixels [8, 40) */
    LrTile t;
    lr_tile_partition(&img, &cfg, 1, 1, &t);
    /* the gap is (-2.4, 4.4): one bound there, none cutting a surface when only one is allowed */
    int in_gap = 0;
    for (int i = 0; i < t.n_coc; ++i) in_gap += t.coc_bound_px[i] > -2.4f && t.coc_bound_px[i] < 4.4f;
    CHECK(gap_slabs == 2 ? t.n_coc == 1 : t.n_coc > 1);
    CHECK(in_gap == 1);
    int mixed = 0, disk = 0, plane = 0;
    for (int j = 0; j < t.layer_count; ++j) {
        mixed += t.layer[j].slopes.c_min_px < 0.0f && t.layer[j].slopes.c_max_px > 0.0f;
        disk += t.layer[j].slopes.c_max_px < 0.0f;
        plane += t.layer[j].slopes.c_min_px > 0.0f;
    }
    CHECK(mixed == 0 && disk >= 1 && plane >= 1);
    /* with more slabs than one per surface the rest split the surfaces' own slope ranges:
     * each layer then spans less than the surface's 1.2 px */
    if (gap_slabs > 2)
        for (int j = 0; j < t.layer_count; ++j) CHECK(t.layer[j].slopes.c_max_px - t.layer[j].slopes.c_min_px < 1.2f);
    lr_samples_free(&img);
    free(s);
}

/* The largest CoC span of a tile's layers, and whether any layer holds both moving and static
 * samples of the window (counted sample by sample). */
static float widest_layer(const LrSamples *img, const LrConfig *cfg, int tx, int ty, const LrTile *t, bool *mixed)
{
    float span = 0.0f;
    for (int j = 0; j < t->layer_count; ++j) span = fmaxf(span, t->layer[j].slopes.c_max_px - t->layer[j].slopes.c_min_px);
    int has[LR_MAX_LAYERS + 1][2] = {{0}};
    int x0, y0, x1, y1;
    lr_tile_window(img, cfg, tx, ty, &x0, &y0, &x1, &y1);
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x)
            for (int k = 0; k < img->spp; ++k) {
                const LrKey *s = &img->key[((size_t)y * img->width + x) * img->spp + k];
                if (s->depth < INFINITY) has[lr_tile_raw_layer(t, s->depth, s->coc_px, s->motion_px)][lr_key_moving(s->motion_px)] = 1;
            }
    *mixed = false;
    for (int r = 0; r < lr_tile_raw_count(t); ++r) *mixed = *mixed || (has[r][0] && has[r][1]);
    return span;
}

/* A static plane whose slopes spread over [-8, 8] px (far more occupied bins than slabs), with
 * or without a small disk moving 6 px in front of it. Tile (1, 1)'s window: with no moving hit,
 * or a moving share at most still_moving_permille (the threshold at the share's exact per mille,
 * rounded up), it takes still_gap_slabs (16) slabs, 17 raw layers without the split, and its
 * widest layer is narrower than with 8 slabs; one per mille less, it keeps 8 split slabs, and no
 * layer mixes moving and static samples. */
static void test_still_window(void)
{
    enum { w = 48, h = 48, spp = 8 };
    LrTestLayer layers[2] = {{2.0f, 0.0f, {6.0f, 0.0f}, 24.0f, 24.0f, 1.5f, 0.7f}, {8.0f, 0.0f, {0.0f, 0.0f}, 0, 0, 0, 0.4f}};
    for (int disk = 0; disk <= 1; ++disk) {
        LrSample *s = malloc(sizeof(LrSample) * w * h * spp);
        lr_test_scene(s, w, h, spp, disk ? layers : layers + 1, disk ? 2 : 1, 9);
        unsigned seed = 17;
        long hits = 0, moving = 0;
        for (int i = 0; i < w * h * spp; ++i) {
            if (s[i].depth == 8.0f) s[i].coc_px = 16.0f * (lr_test_unit(&seed) - 0.5f);
            int px = (i / spp) % w, py = (i / spp) / w;
            if (px >= 8 && px < 40 && py >= 8 && py < 40 && s[i].depth < INFINITY) hits++, moving += lr_key_moving(s[i].motion_px);
        }
        /* the least per mille that holds the window's moving share */
        int share_permille = (int)((moving * 1000 + hits - 1) / hits);
        CHECK(disk ? moving > 0 && share_permille < 100 : moving == 0);
        LrSamples img = lr_samples_split(w, h, spp, s);
        LrConfig cfg = lr_config_default();
        cfg.tile_px = 16, cfg.window_px = 32; /* tile (1, 1)'s window: pixels [8, 40) */
        cfg.still_gap_slabs = 40; /* clamped to the 16 slabs the 17 raw ids hold */
        CHECK(lr_config_still_gap_slabs(&cfg) == LR_MAX_COC_BOUNDS + 1 && lr_config_gap_slabs(&cfg) == LR_MAX_SPLIT_SLABS);
        float span[3];
        bool mixed[3];
        for (int v = 0; v < 3; ++v) {
            /* v 0: the threshold at the share; v 1: one per mille under it (the threshold 0
             * without the disk); v 2: no rule (still_gap_slabs = gap_slabs) */
            cfg.still_moving_permille = v == 1 && disk ? share_permille - 1 : share_permille;
            cfg.still_gap_slabs = v == 2 ? cfg.gap_slabs : 40;
            LrTile t;
            lr_tile_partition(&img, &cfg, 1, 1, &t);
            bool still = v == 0 || (v == 1 && !disk);
            int slabs = t.n_depth + t.n_coc + 1;
            CHECK(slabs == (still ? 16 : 8));
            CHECK(lr_tile_raw_count(&t) == LR_MAX_LAYERS + 1 && lr_tile_raw_count(&t) == (still ? slabs + 1 : 2 * slabs + 1));
            span[v] = widest_layer(&img, &cfg, 1, 1, &t, &mixed[v]);
        }
        CHECK(span[0] < 0.75f * span[2] && (disk ? span[1] == span[2] : span[1] == span[0]));
        CHECK(mixed[0] == (disk == 1) && !mixed[1] && !mixed[2]);
        if (!(span[0] < 0.75f * span[2])) fprintf(stderr, "still window: widest layer %g px against %g with 8 slabs\n", span[0], span[2]);
        lr_samples_free(&img);
        free(s);
    }
}

/* lr_config_counts_moving says whether a window's moving hits can change its bounds, so that
 * the statistics may skip counting them: off by default (still_gap_slabs 0), with
 * still_gap_slabs equal to gap_slabs, and without gap slabs; on with 12 or (clamped) 40. Its
 * meaning checked on lr_tile_bounds_gaps: a histogram with 24 occupied bins gets the same bounds
 * with no moving hit and with every hit moving exactly when it is off. */
static void test_counts_moving(void)
{
    float edges[LR_GAP_BINS - 1];
    lr_gap_edges(edges);
    int hist[LR_GAP_BINS] = {0};
    long hits = 0;
    for (int b = 12; b < 36; ++b) hist[b] = 5 + b % 7, hits += hist[b];
    struct {
        int gap, still;
        bool counts;
    } cases[] = {{8, 0, false}, {8, 8, false}, {0, 12, false}, {8, 12, true}, {8, 40, true}, {4, 6, true}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        LrConfig cfg = lr_config_default();
        cfg.gap_slabs = cases[i].gap, cfg.still_gap_slabs = cases[i].still;
        CHECK(lr_config_counts_moving(&cfg) == cases[i].counts);
        LrTile none, all;
        if (cfg.gap_slabs > 0) {
            lr_tile_bounds_gaps(&cfg, 1.0f, 9.0f, hist, edges, 0, &none);
            lr_tile_bounds_gaps(&cfg, 1.0f, 9.0f, hist, edges, hits, &all);
        } else {
            lr_tile_bounds(&cfg, 1.0f, 9.0f, &none);
            lr_tile_bounds(&cfg, 1.0f, 9.0f, &all);
        }
        CHECK((memcmp(&none, &all, sizeof none) != 0) == cases[i].counts);
    }
    LrConfig def = lr_config_default(); /* the default: no count */
    CHECK(!lr_config_counts_moving(&def));
}

/* lr_gap_bin (binary lifting, the form lr.cl runs) gives every slope the number of edges
 * below it: at each edge, a float either side of it, between edges, beyond both ends, at
 * +-infinity (47, 0) and NaN (0, as "c > edge" is false for every edge). */
static void test_bin_counts_edges_below(void)
{
    float edges[LR_GAP_BINS - 1];
    lr_gap_edges(edges);
    float probe[8 * LR_GAP_BINS];
    int n = 0;
    for (int i = 0; i < LR_GAP_BINS - 1; ++i) {
        probe[n++] = edges[i];
        probe[n++] = nextafterf(edges[i], -INFINITY);
        probe[n++] = nextafterf(edges[i], INFINITY);
        if (i + 1 < LR_GAP_BINS - 1) probe[n++] = 0.5f * (edges[i] + edges[i + 1]);
    }
    float ends[] = {-1e6f, 1e6f, -INFINITY, INFINITY, NAN, 0.0f, -0.0f};
    for (int i = 0; i < (int)(sizeof ends / sizeof ends[0]); ++i) probe[n++] = ends[i];
    for (int p = 0; p < n; ++p) {
        int below = 0;
        for (int i = 0; i < LR_GAP_BINS - 1; ++i) below += probe[p] > edges[i];
        CHECK(lr_gap_bin(edges, probe[p]) == below);
    }
    CHECK(lr_gap_bin(edges, INFINITY) == LR_GAP_BINS - 1 && lr_gap_bin(edges, -INFINITY) == 0 && lr_gap_bin(edges, NAN) == 0);
}

int main(void)
{
    test_bin_counts_edges_below();
    test_dp_is_optimal();
    test_two_surfaces(2);
    test_two_surfaces(8);
    test_still_window();
    test_counts_moving();
    CHECK_DONE();
}
