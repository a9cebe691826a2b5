/* LR's OpenCL kernels (lr.cl via lr_cl.c) against the plain C reconstruction
 * (lr_reconstruct_c) on small synthetic light fields: diagonal motion (rotated filters),
 * large blurs (clamped filters, many layers), a partial last tile, a non-finite sample, and a
 * smaller frame after a larger one (buffers kept between runs), frames filtered in several
 * batches of tiles (whose launches are padded past the batch's last tile), and frames with an
 * overscan band (LrConfig.inset_px), tiles left out (LrConfig.still_tiles), and static
 * defocused layers (the round screen filter, lr_screen_round). The partition statistics are
 * computed on the device and the layer counts (AOV) must equal the C partitions'; their first
 * sweep adds 8x8 blocks' histograms where every window is whole blocks (bands of 0 and 8 px,
 * widths and heights not multiples of 8: partial blocks at the edges) and bins sample by
 * sample where not (the 19-px band). Dropping a window's partial blocks, or one block, fails.
 * Neighbouring layers merged into one partition (lr_layers_merge: a convoy moving together, a
 * pinhole's static layers) are one run of raw layers in the kernel's reprojection too. A
 * still band per pixel (LrConfig.band_class, docs/algorithms.md 8.40) with every class present:
 * the kernels' per-class along passes (on the rows their pixels read) and across passes against
 * the C passes', and the classes must change the image where a still layer's filter differs.
 * Tiles of 32 px in 64-px windows, the largest the kernels hold (lr_tile_filter keeps a tile's
 * pixels in private arrays), against the C passes too; a larger tile is refused. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../check.h"
#include "lr_scene.h"
#include "recon/lr/lr_band_class.h"
#include "recon/lr/lr_cl.h"

/* LrConfig.gap_slabs of every comparison (0: the fixed focus bounds; 8: the bounds in each
 * window's CoC histogram gaps, chosen by the kernel and by lr_partition.c alike) */
static int gap_slabs = 0;
/* each sample's CoC slope is jittered by up to half this (a tilted surface's spread of slopes):
 * wide enough, a window's histogram has more occupied bins than slabs */
static float coc_jitter_px = 0.6f;
/* the radiance of the front layer's samples is scaled by this: at 300 it is a light far
 * brighter than the rest of its windows, whose layers take the bright clamp (8.24) from the
 * brightness sums the kernel adds up and the C partition alike */
static float front_gain = 1.0f;
/* LrFilterConfig.flat_lens_time of every comparison: false, the samples weigh w_u w_v w_t
 * (eq. 14; lr_gauss), a weight that falls to 0 far out, so the kernel's sums take weights
 * other than 0 and 1 and lr_reproject_layer's weight-0 samples (dropped) are exercised */
static bool flat_weights = true;
/* LrConfig.tile_px and window_px of every comparison (the defaults unless a test sets them) */
static int tile_px = 16, window_px = 32;
/* LrConfig.still_moving_permille of every comparison; and the C partitions of compare_band that
 * took more than the split slabs (a still window's, LrConfig.still_gap_slabs), those of them
 * with moving hits (under the threshold) counted apart: the kernel must choose the same */
static int still_permille = 0, still_slabs = 0;
static int fine_windows = 0, fine_moving_windows = 0;

/* film_spread_px > 0 moves each sample's film position up to that far from its pixel's
 * centre, as a wide pixel filter places them (pbrt's sinc: its radius, 4 px). */
/* inset_px > 0: a band that wide is read but not reconstructed (LrConfig.inset_px, the
 * overscan band); its pixels must keep what the caller put there. */
static void compare_band(LrCl *lr, int w, int h, int spp, const LrTestLayer *layers, int nl, bool poison,
                         float film_spread_px, int inset_px)
{
    LrSample *s = malloc(sizeof(LrSample) * (size_t)w * h * spp);
    lr_test_scene(s, w, h, spp, layers, nl, 31);
    unsigned seed = 5;
    for (int i = 0; i < w * h * spp; ++i) {
        if (s[i].depth == layers[0].depth)
            for (int c = 0; c < 3; ++c) s[i].L[c] *= front_gain;
        s[i].coc_px += coc_jitter_px * (lr_test_unit(&seed) - 0.5f);
    }
    for (int i = 0; i < w * h * spp && film_spread_px > 0.0f; ++i) {
        int pixel = i / spp;
        s[i].x_px = (float)(pixel % w) + 0.5f + film_spread_px * (2.0f * lr_test_unit(&seed) - 1.0f);
        s[i].y_px = (float)(pixel / w) + 0.5f + film_spread_px * (2.0f * lr_test_unit(&seed) - 1.0f);
    }
    if (poison) s[(size_t)(h / 2 * w + w / 2) * spp].L[1] = NAN;
    LrSamples img = lr_samples_split(w, h, spp, s);
    LrConfig cfg = lr_config_default();
    cfg.inset_px = inset_px;
    cfg.gap_slabs = gap_slabs;
    cfg.filter.flat_lens_time = flat_weights;
    cfg.tile_px = tile_px, cfg.window_px = window_px;
    cfg.filter.sigma_clamp_px = (float)(window_px - tile_px) / 4.0f; /* as lr_config_default's (Appendix C) */
    cfg.still_moving_permille = still_permille;
    cfg.still_gap_slabs = still_slabs;
    int ntx, nty;
    lr_tile_count(&img, &cfg, &ntx, &nty);
    for (int t = 0; t < ntx * nty; ++t) {
        LrTile tile;
        lr_tile_partition(&img, &cfg, t % ntx, t / ntx, &tile);
        if (tile.n_depth + tile.n_coc + 1 <= LR_MAX_SPLIT_SLABS) continue;
        fine_windows++;
        int x0, y0, x1, y1;
        lr_tile_window(&img, &cfg, t % ntx, t / ntx, &x0, &y0, &x1, &y1);
        bool moves = false;
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x)
                for (int k = 0; k < spp; ++k) {
                    const LrKey *key = &img.key[((size_t)y * w + x) * spp + k];
                    moves = moves || (key->depth < INFINITY && lr_key_moving(key->motion_px));
                }
        fine_moving_windows += moves;
    }
    size_t n = (size_t)w * h;
    float *a = malloc(sizeof(float) * 3 * n), *b = malloc(sizeof(float) * 3 * n);
    float *la = malloc(sizeof(float) * n), *lb = malloc(sizeof(float) * n), *ea = malloc(sizeof(float) * n), *eb = malloc(sizeof(float) * n);
    const float untouched = -7.0f;
    for (size_t i = 0; i < 3 * n; ++i) a[i] = b[i] = untouched;
    for (size_t i = 0; i < n; ++i) la[i] = lb[i] = ea[i] = eb[i] = untouched;
    LrOutput oc = {a, la, ea, 0}, ok = {b, lb, eb, 0};
    lr_reconstruct_c(&img, &cfg, &oc);
    Diag d = {0};
    CHECK(lr_cl_run(lr, &img, &cfg, &ok, NULL, &d));
    CHECK(oc.nonfinite == (poison ? 1 : 0) && ok.nonfinite == oc.nonfinite);
    double worst = 0;
    int aov_diff = 0, nonfinite = 0, band_written = 0, inner_unwritten = 0;
    for (size_t i = 0; i < n; ++i) {
        int x = (int)(i % (size_t)w), y = (int)(i / (size_t)w);
        bool band = x < inset_px || y < inset_px || x >= w - inset_px || y >= h - inset_px;
        for (int c = 0; c < 3; ++c) {
            if (band) band_written += a[3 * i + c] != untouched || b[3 * i + c] != untouched;
            else inner_unwritten += a[3 * i + c] == untouched || b[3 * i + c] == untouched;
            worst = fmax(worst, fabs(a[3 * i + c] - b[3 * i + c]));
            nonfinite += !isfinite(b[3 * i + c]);
        }
        aov_diff += la[i] != lb[i] || fabsf(ea[i] - eb[i]) > 1e-5f * fabsf(ea[i]);
    }
    /* Same operations in the same order with contraction off, the same Gaussian (lr_gauss,
     * written out in both) and the same tap tables: on PoCL the images are bit for bit equal.
     * The bound leaves room only for a device whose float division or floor differs in the
     * last bit (1e-6 absolute on values <= 1.3). */
    CHECK(worst <= 1e-6);
    if (!(worst <= 1e-6)) fprintf(stderr, "worst %g\n", worst);
    CHECK(aov_diff == 0 && nonfinite == 0);
    CHECK(band_written == 0 && inner_unwritten == 0);
    if (band_written || inner_unwritten) fprintf(stderr, "band written %d, inner unwritten %d\n", band_written, inner_unwritten);
    lr_samples_free(&img);
    free(a), free(b), free(la), free(lb), free(ea), free(eb), free(s);
}

static void compare_spread(LrCl *lr, int w, int h, int spp, const LrTestLayer *layers, int nl, bool poison,
                           float film_spread_px)
{
    compare_band(lr, w, h, spp, layers, nl, poison, film_spread_px, 0);
}

static void compare(LrCl *lr, int w, int h, int spp, const LrTestLayer *layers, int nl, bool poison)
{
    compare_spread(lr, w, h, spp, layers, nl, poison, 0.0f);
}

/* Which partitions count (count_partitions). */
typedef enum { COUNT_BRIGHT, COUNT_ROUND, COUNT_MERGED } PartitionKind;

/* The partitions of compare's frame (its front layer's radiance scaled by gain) that are bright
 * (the bright clamp, 8.24) or take the round screen filter (lr_screen_round, 8.28): the
 * comparisons must exercise both, and a partition is bright only with front_gain. */
static int count_partitions(int w, int h, int spp, const LrTestLayer *layers, int nl, float gain, PartitionKind kind)
{
    LrSample *s = malloc(sizeof(LrSample) * (size_t)w * h * spp);
    lr_test_scene(s, w, h, spp, layers, nl, 31);
    for (int i = 0; i < w * h * spp; ++i)
        if (s[i].depth == layers[0].depth)
            for (int c = 0; c < 3; ++c) s[i].L[c] *= gain;
    LrSamples img = lr_samples_split(w, h, spp, s);
    LrConfig cfg = lr_config_default();
    int ntx, nty, count = 0;
    lr_tile_count(&img, &cfg, &ntx, &nty);
    for (int ty = 0; ty < nty; ++ty)
        for (int tx = 0; tx < ntx; ++tx) {
            LrTile t;
            lr_tile_partition(&img, &cfg, tx, ty, &t);
            if (kind == COUNT_MERGED) { /* non-empty raw layers beyond one a partition (lr_layers_merge) */
                for (int i = 0; i < lr_tile_raw_count(&t); ++i) count += t.compact[i] >= 0;
                count -= t.layer_count;
                continue;
            }
            for (int j = 0; j < t.layer_count; ++j) {
                int r;
                float table[LR_ROUND_TABLE];
                count += kind == COUNT_BRIGHT ? t.layer[j].contrast >= cfg.bright_contrast
                                              : lr_screen_round(&t.layer[j].filter, &cfg, t.layer[j].cos_psi, t.layer[j].sin_psi, &r, table);
            }
        }
    lr_samples_free(&img);
    free(s);
    return count;
}

static int bright_partitions(int w, int h, int spp, const LrTestLayer *layers, int nl, float gain)
{
    return count_partitions(w, h, spp, layers, nl, gain, COUNT_BRIGHT);
}

static int round_partitions(int w, int h, int spp, const LrTestLayer *layers, int nl)
{
    return count_partitions(w, h, spp, layers, nl, 1.0f, COUNT_ROUND);
}

static int merged_layers(int w, int h, int spp, const LrTestLayer *layers, int nl)
{
    return count_partitions(w, h, spp, layers, nl, 1.0f, COUNT_MERGED);
}

/* LrConfig.still_tiles: every other tile marked still. Those tiles get no layers and 0 in
 * the image and AOVs, in the kernels as in the C passes; every other tile is exactly what it
 * is without the mask (a still tile's samples are still read by its neighbours' windows). */
static void compare_still(LrCl *lr, int w, int h, int spp, const LrTestLayer *layers, int nl)
{
    LrSample *s = malloc(sizeof(LrSample) * (size_t)w * h * spp);
    lr_test_scene(s, w, h, spp, layers, nl, 31);
    LrSamples img = lr_samples_split(w, h, spp, s);
    LrConfig cfg = lr_config_default();
    int ntx, nty;
    lr_tile_count(&img, &cfg, &ntx, &nty);
    unsigned char *still = malloc((size_t)ntx * nty);
    for (int t = 0; t < ntx * nty; ++t) still[t] = (unsigned char)((t % ntx + t / ntx) % 2);
    size_t n = (size_t)w * h;
    float *full = malloc(sizeof(float) * 3 * n), *a = malloc(sizeof(float) * 3 * n), *b = malloc(sizeof(float) * 3 * n);
    float *la = malloc(sizeof(float) * n), *lb = malloc(sizeof(float) * n);
    LrOutput of = {full, NULL, NULL, 0}, oc = {a, la, NULL, 0}, ok = {b, lb, NULL, 0};
    lr_reconstruct_c(&img, &cfg, &of);
    cfg.still_tiles = still;
    lr_reconstruct_c(&img, &cfg, &oc);
    Diag d = {0};
    CHECK(lr_cl_run(lr, &img, &cfg, &ok, NULL, &d));
    int still_nonzero = 0, moved = 0, cl_diff = 0, marked = 0;
    for (size_t i = 0; i < n; ++i) {
        int x = (int)(i % (size_t)w), y = (int)(i / (size_t)w);
        bool in_still = still[(y / cfg.tile_px) * ntx + x / cfg.tile_px];
        marked += in_still;
        for (int c = 0; c < 3; ++c) {
            if (in_still) still_nonzero += a[3 * i + c] != 0.0f || b[3 * i + c] != 0.0f;
            else moved += a[3 * i + c] != full[3 * i + c];
            cl_diff += fabsf(a[3 * i + c] - b[3 * i + c]) > 1e-6f;
        }
        if (in_still) still_nonzero += la[i] != 0.0f || lb[i] != 0.0f;
    }
    CHECK(marked > 0 && marked < (int)n);
    CHECK(still_nonzero == 0 && moved == 0 && cl_diff == 0);
    if (still_nonzero || moved || cl_diff) fprintf(stderr, "still tiles: nonzero %d, others changed %d, C/CL differ %d\n", still_nonzero, moved, cl_diff);
    lr_samples_free(&img);
    free(full), free(a), free(b), free(la), free(lb), free(still), free(s);
}

/* A class map with every class: narrow on a few whole rows and a diagonal (so that some
 * tiles have narrow pixels on one row only), wide in 5x3 blocks, the frame's band elsewhere. */
static unsigned char pattern_class(int x, int y)
{
    if (y % 11 == 3 || (x + y) % 23 == 0) return LR_BAND_NARROW;
    return (x / 5 + y / 3) % 2 ? LR_BAND_WIDE : LR_BAND_FRAME;
}

/* The C partitions' layers with a class filter of their own (lr_band_screen) for the narrow
 * and the wide class. */
static void count_band_layers(const LrSamples *img, const LrConfig *cfg, int count[2])
{
    int ntx, nty;
    lr_tile_count(img, cfg, &ntx, &nty);
    count[0] = count[1] = 0;
    for (int ty = 0; ty < nty; ++ty)
        for (int tx = 0; tx < ntx; ++tx) {
            LrTile t;
            lr_tile_partition(img, cfg, tx, ty, &t);
            for (int j = 0; j < t.layer_count; ++j) {
                LrScreen frame, band;
                LrFilter filter;
                lr_screen_make(&t.layer[j].filter, cfg, t.layer[j].cos_psi, t.layer[j].sin_psi, &frame);
                for (int c = LR_BAND_NARROW; c < LR_BAND_CLASSES; ++c)
                    count[c - 1] += lr_band_screen(cfg, &t.layer[j], c, &frame, &band, &filter);
            }
        }
}

/* The band classes of pattern_class at a frame band of 0.45 px (the narrow class differs from
 * it), the samples' CoC jittered by up to coc_jitter_px / 2 (still layers whose slope ranges
 * reach focus): the kernels equal the C passes (bit for bit on PoCL), the frame-class pixels
 * are what they are without the map, and the other classes change the image. (A layer whose
 * frame filter is round, lr_screen_round, is blurred by its lens past the band: no class of
 * it differs, so the class records are the two passes' in practice.) */
static void compare_classes(LrCl *lr, int w, int h, int spp, const LrTestLayer *layers, int nl, int inset_px)
{
    LrSample *s = malloc(sizeof(LrSample) * (size_t)w * h * spp);
    lr_test_scene(s, w, h, spp, layers, nl, 31);
    unsigned seed = 5;
    for (int i = 0; i < w * h * spp; ++i) s[i].coc_px += coc_jitter_px * (lr_test_unit(&seed) - 0.5f);
    LrSamples img = lr_samples_split(w, h, spp, s);
    LrConfig cfg = lr_config_default();
    cfg.inset_px = inset_px;
    cfg.filter.sigma_pixel_still_px = 0.45f;
    size_t n = (size_t)w * h;
    unsigned char *cls = malloc(n);
    int present[3] = {0, 0, 0};
    for (size_t i = 0; i < n; ++i) present[cls[i] = pattern_class((int)(i % (size_t)w), (int)(i / (size_t)w))]++;
    CHECK(present[0] > 0 && present[1] > 0 && present[2] > 0);
    float *plain = malloc(sizeof(float) * 3 * n), *a = malloc(sizeof(float) * 3 * n), *b = malloc(sizeof(float) * 3 * n);
    float *la = malloc(sizeof(float) * n), *lb = malloc(sizeof(float) * n), *ea = malloc(sizeof(float) * n), *eb = malloc(sizeof(float) * n);
    for (size_t i = 0; i < 3 * n; ++i) plain[i] = a[i] = b[i] = 0.0f;
    for (size_t i = 0; i < n; ++i) la[i] = lb[i] = ea[i] = eb[i] = 0.0f;
    LrOutput op = {plain, NULL, NULL, 0}, oc = {a, la, ea, 0}, ok = {b, lb, eb, 0};
    lr_reconstruct_c(&img, &cfg, &op);
    cfg.band_class = cls;
    int layers_with[2];
    count_band_layers(&img, &cfg, layers_with);
    CHECK(layers_with[0] > 0 && layers_with[1] > 0);
    lr_reconstruct_c(&img, &cfg, &oc);
    Diag d = {0};
    CHECK(lr_cl_run(lr, &img, &cfg, &ok, NULL, &d));
    double worst = 0.0;
    int changed[3] = {0, 0, 0}, aov_diff = 0;
    for (size_t i = 0; i < n; ++i) {
        for (int c = 0; c < 3; ++c) {
            worst = fmax(worst, fabs(a[3 * i + c] - b[3 * i + c]));
            changed[cls[i]] += a[3 * i + c] != plain[3 * i + c];
        }
        aov_diff += la[i] != lb[i] || ea[i] != eb[i];
    }
    CHECK(worst <= 1e-6 && aov_diff == 0);
    /* the frame-class pixels keep the frame's filter; the others change */
    CHECK(changed[LR_BAND_FRAME] == 0 && changed[LR_BAND_NARROW] > 0 && changed[LR_BAND_WIDE] > 0);
    if (!(worst <= 1e-6) || changed[0] || !changed[1] || !changed[2])
        fprintf(stderr, "classes: worst %g, changed frame %d narrow %d wide %d\n", worst, changed[0], changed[1], changed[2]);
    lr_samples_free(&img);
    free(cls), free(plain), free(a), free(b), free(la), free(lb), free(ea), free(eb), free(s);
}

int main(void)
{
    Diag d = {0};
    ClRuntime *rt = cl_runtime_create(NULL, &d);
    CHECK(rt != NULL);
    if (!rt) {
        fprintf(stderr, "%s\n", d.message);
        CHECK_DONE();
    }
    LrCl *lr = lr_cl_create(rt, &d);
    CHECK(lr != NULL);
    if (lr) {
        LrTestLayer diag[2] = {{2.0f, -3.0f, {5.0f, 4.0f}, 20.0f, 17.0f, 9.0f, 0.7f}, {8.0f, 5.0f, {-1.0f, 2.0f}, 0, 0, 0, 0.4f}};
        compare(lr, 37, 29, 4, diag, 2, false);
        LrTestLayer big[3] = {{1.0f, -25.0f, {30.0f, -8.0f}, 10.0f, 12.0f, 7.0f, 0.5f},
                              {3.0f, 0.2f, {0.0f, 12.0f}, 30.0f, 20.0f, 10.0f, 0.9f},
                              {9.0f, 18.0f, {0.0f, 0.0f}, 0, 0, 0, 0.3f}};
        compare(lr, 48, 33, 8, big, 3, true);
        /* the device buffers only grow: a smaller frame after a larger one reads no stale cells */
        compare(lr, 37, 29, 4, diag, 2, false);
        /* an in-focus static disk: its layer reaches a few pixels, so its reprojection reads
         * only the rows of its sorted list near the tile (bisection) */
        LrTestLayer sharp[2] = {{2.0f, 0.0f, {0.0f, 0.0f}, 22.0f, 19.0f, 11.0f, 0.7f}, {8.0f, 6.0f, {3.0f, 1.0f}, 0, 0, 0, 0.4f}};
        compare(lr, 48, 40, 4, sharp, 2, false);
        /* frames of more than one batch of tiles (lr_cl.c: BATCH_TILES): 16 x 5 tiles, one row
         * a batch, 7 x 5 tiles in batches of 2 rows (the last one short), and 65 x 2 tiles,
         * one row a batch */
        LrTestLayer wide[2] = {{2.0f, -4.0f, {-9.0f, 3.0f}, 130.0f, 40.0f, 30.0f, 0.8f}, {6.0f, 3.0f, {2.0f, 0.0f}, 0, 0, 0, 0.35f}};
        CHECK(bright_partitions(48, 33, 8, big, 3, 300.0f) > 0 && bright_partitions(256, 80, 4, wide, 2, 300.0f) > 0);
        CHECK(bright_partitions(48, 33, 8, big, 3, 1.0f) == 0 && bright_partitions(256, 80, 4, wide, 2, 1.0f) == 0);
        compare(lr, 256, 80, 4, wide, 2, false);
        compare(lr, 112, 80, 4, wide, 2, true);
        compare(lr, 1040, 20, 2, wide, 2, true);
        /* film positions up to 4 px from their pixel's centre (pbrt's sinc pixel filter) and 9
         * px (a wider one): the reprojection must still visit every source row that can land
         * in a tile's box (with the old fixed slack of 2 rows the 9-px case differs by 0.16) */
        compare_spread(lr, 48, 40, 4, sharp, 2, false, 4.0f);
        compare_spread(lr, 48, 40, 4, sharp, 2, false, 9.0f);
        compare_spread(lr, 48, 33, 8, big, 3, false, 4.0f);
        /* an overscan band of 8 px (LR's window margin): tiles from (8, 8), a partial last
         * tile on both axes, the band's pixels left alone; and a band wider than a tile */
        compare_band(lr, 53, 45, 4, big, 3, true, 0.0f, 8);
        compare_band(lr, 256, 80, 4, wide, 2, false, 0.0f, 8);
        compare_band(lr, 60, 50, 4, diag, 2, false, 0.0f, 19);
        /* static defocused layers in front of and behind focus: the round screen filter
         * (lr_screen_round) reads the grid in lr_across_row, with no along pass */
        LrTestLayer still[2] = {{2.0f, -5.0f, {0.0f, 0.0f}, 20.0f, 17.0f, 9.0f, 0.7f}, {8.0f, 7.0f, {0.0f, 0.0f}, 0, 0, 0, 0.4f}};
        CHECK(round_partitions(48, 40, 4, still, 2) > 0 && round_partitions(48, 33, 8, big, 3) > 0);
        /* layers merged (lr_layers_merge, 8.34): a partition whose own samples are several raw
         * layers, which the kernel's reprojection must take as one run */
        LrTestLayer convoy[3] = {{2.0f, 0.0f, {6.0f, 0.0f}, 20.0f, 17.0f, 9.0f, 0.7f}, {4.0f, 0.0f, {6.0f, 0.0f}, 28.0f, 20.0f, 8.0f, 0.5f},
                                 {9.0f, 0.0f, {6.0f, 0.0f}, 0, 0, 0, 0.4f}};
        LrTestLayer pinhole[3] = {{2.0f, 0.0f, {0.0f, 0.0f}, 20.0f, 17.0f, 9.0f, 0.7f}, {4.0f, 0.0f, {0.0f, 0.0f}, 28.0f, 20.0f, 8.0f, 0.5f},
                                  {9.0f, 0.0f, {0.0f, 0.0f}, 0, 0, 0, 0.4f}};
        CHECK(merged_layers(48, 40, 4, convoy, 3) > 0 && merged_layers(48, 40, 4, pinhole, 3) > 0);
        compare(lr, 48, 40, 4, convoy, 3, false);
        compare(lr, 48, 40, 4, pinhole, 3, true);
        compare_band(lr, 53, 45, 4, convoy, 3, false, 0.0f, 8);
        compare(lr, 48, 40, 4, still, 2, false);
        compare_band(lr, 53, 45, 4, still, 2, false, 0.0f, 8);
        /* the still band per pixel (8.40): static layers near focus (class filters of their
         * own), a moving disk (none), a static disk far out of focus (round, none), diagonal
         * motion over a plane in focus; frames of several batches and with a band */
        LrTestLayer focus[4] = {{2.0f, -1.0f, {0.0f, 0.0f}, 14.0f, 12.0f, 7.0f, 0.9f}, {3.0f, 0.0f, {5.0f, 2.0f}, 34.0f, 24.0f, 8.0f, 0.6f},
                                {4.0f, -6.0f, {0.0f, 0.0f}, 30.0f, 6.0f, 5.0f, 0.7f}, {8.0f, 0.3f, {0.0f, 0.0f}, 0, 0, 0, 1.3f}};
        LrTestLayer diag_focus[2] = {{2.0f, -3.0f, {5.0f, 4.0f}, 20.0f, 17.0f, 9.0f, 0.7f}, {8.0f, 0.4f, {0.0f, 0.0f}, 0, 0, 0, 1.1f}};
        coc_jitter_px = 2.0f;
        compare_classes(lr, 48, 40, 8, focus, 4, 0);
        compare_classes(lr, 53, 45, 4, focus, 4, 8);
        compare_classes(lr, 256, 80, 4, focus, 4, 0);
        compare_classes(lr, 37, 29, 8, diag_focus, 2, 0);
        coc_jitter_px = 0.6f;
        /* still tiles left out (lr_partition.h: LrConfig.still_tiles) */
        compare_still(lr, 48, 33, 8, big, 3);
        compare_still(lr, 256, 80, 4, wide, 2);
        /* the histogram-gap bounds: the device's choice must equal the C partition's */
        for (int g = 0; g <= 8; g += 8) {
            gap_slabs = g;
            coc_jitter_px = 6.0f; /* many occupied bins: the programme's choice matters */
            compare(lr, 37, 29, 4, diag, 2, false);
            compare(lr, 48, 33, 8, big, 3, false);
            coc_jitter_px = 0.6f;
            compare(lr, 48, 33, 8, big, 3, true);
            compare_band(lr, 53, 45, 4, big, 3, false, 0.0f, 8);
            compare(lr, 256, 80, 4, wide, 2, false);
            /* a bright front layer: its partitions take the bright clamp (checked below) */
            front_gain = 300.0f;
            compare(lr, 48, 33, 8, big, 3, true);
            compare(lr, 256, 80, 4, wide, 2, false);
            front_gain = 1.0f;
            /* windows that hardly move take 16 slabs (LrConfig.still_gap_slabs): static
             * layers whose slopes spread over many bins, in 8x8 blocks and sample by sample
             * (the 19-px band); then windows with a moving share up to 30% */
            coc_jitter_px = 6.0f;
            still_slabs = 16;
            compare(lr, 48, 40, 4, still, 2, false);
            compare_band(lr, 60, 50, 4, still, 2, true, 0.0f, 19);
            CHECK(g == 0 ? fine_windows == 0 : fine_windows > 0);
            CHECK(fine_moving_windows == 0);
            still_permille = 300;
            compare(lr, 48, 40, 8, focus, 4, false);
            compare_band(lr, 60, 50, 4, focus, 4, false, 0.0f, 19);
            compare(lr, 256, 80, 4, wide, 2, false);
            CHECK(g == 0 ? fine_moving_windows == 0 : fine_moving_windows > 0);
            if (g > 0 && !fine_moving_windows) fprintf(stderr, "no window with moving hits under the threshold took 16 slabs\n");
            still_permille = 0, still_slabs = 0;
            coc_jitter_px = 0.6f;
        }
        /* Gaussian sample weights: the reprojection's Gaussian branch, weights of every size,
         * samples of weight 0 (lr_gauss' cut-off) among those that land in the box */
        flat_weights = false;
        compare(lr, 37, 29, 4, diag, 2, false);
        compare(lr, 48, 33, 8, big, 3, true);
        compare_spread(lr, 48, 40, 4, sharp, 2, false, 4.0f);
        compare(lr, 48, 40, 4, convoy, 3, false);
        compare_band(lr, 53, 45, 4, still, 2, false, 0.0f, 8);
        compare(lr, 256, 80, 4, wide, 2, true);
        flat_weights = true;
        /* the largest tile the kernels hold: 32 px (in 64-px windows), a partial last tile on
         * both axes, several layers reusing the tile's grids; and 48 px, which is refused */
        tile_px = 32, window_px = 64;
        CHECK(lr_config_default().tile_px == 16 && lr_config_default().window_px == 32);
        compare(lr, 80, 70, 4, big, 3, true);
        compare_band(lr, 90, 75, 4, focus, 4, false, 0.0f, 16);
        {
            LrSample *s = malloc(sizeof(LrSample) * 40 * 40 * 2);
            lr_test_scene(s, 40, 40, 2, diag, 2, 31);
            LrSamples img = lr_samples_split(40, 40, 2, s);
            LrConfig cfg = lr_config_default();
            cfg.tile_px = 48, cfg.window_px = 64;
            float *rgb = malloc(sizeof(float) * 3 * 40 * 40);
            LrOutput out = {rgb, NULL, NULL, 0};
            Diag dd = {0};
            CHECK(!lr_cl_run(lr, &img, &cfg, &out, NULL, &dd) && dd.exit_code != 0 && strstr(dd.message, "larger than the kernels allow"));
            lr_samples_free(&img);
            free(rgb), free(s);
        }
        tile_px = 16, window_px = 32;
        lr_cl_destroy(lr);
    }
    cl_runtime_destroy(rt);
    CHECK_DONE();
}
