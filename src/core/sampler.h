/* Per-pixel sample generators. Two kinds:
 *  - stratified: jittered strata in every dimension, each 1D/2D dimension stratified on its
 *    own and decorrelated by a random permutation of the sample index (padded stratification);
 *  - sobol: Owen-scrambled Sobol' (0,2)-sequence points per 2D dimension, padded the same way
 *    (the low-discrepancy Monte Carlo baseline).
 * A pixel's samples depend only on (seed, pixel, pass, sample index): images are identical
 * for any thread count and tile order. */
#ifndef WEDGE_CORE_SAMPLER_H
#define WEDGE_CORE_SAMPLER_H

#include <stdbool.h>
#include <stdint.h>

#include "core/rng.h"
#include "core/vec.h"

typedef enum { SAMPLER_STRATIFIED, SAMPLER_SOBOL } SamplerKind;

/* Maps a pbrt-v4 sampler name to ours: "stratified", "independent" -> stratified;
 * "sobol", "zsobol", "paddedsobol", "halton", "pmj02bn" -> sobol. Unknown -> sobol. */
SamplerKind sampler_kind_from_pbrt(const char *name);
const char *sampler_kind_name(SamplerKind kind);

/* Permutations of up to this many elements are drawn by an exact shuffle; a pixel's sampler
 * keeps the ones it has drawn (each serves every sample of the pixel) in a small cache. */
#define SAMPLER_SHUFFLE_MAX 16
/* Scalar dimensions (a 2D request uses two) that get stratified / low-discrepancy values;
 * later dimensions of a sample are independent uniform random numbers (hashed from the
 * sample's key and the dimension). */
#define SAMPLER_PADDED_DIMS 64
#define SAMPLER_PERM_CACHE_SLOTS 128

typedef struct {
    uint64_t seed;
    uint8_t n; /* 0: empty slot */
    uint8_t perm[SAMPLER_SHUFFLE_MAX];
} SamplerPermSlot;

/* What a pixel's sampler derives once per scalar dimension and then reuses for every sample
 * of the pixel. With spp <= SAMPLER_SHUFFLE_MAX: for each sample index i of the current
 * block of spp indices, the point the dimension's padding permutation assigns to it and, for
 * stratified requests, that point's 1D strata, packed 4 bits per index (values < 16). With
 * more samples: the dimension's seeds only (the permutation is computed per sample). A pure
 * cache, filled on first use of the dimension: values do not depend on what it holds. */
typedef struct {
    uint64_t seed;    /* Sobol': the scramble seeds (low word for x, high word for y);
                       * stratified 2D past the tables: the multi-jitter seed */
    uint64_t x;       /* nibble i: stratified, the 1D stratum of x (or of the 1D value);
                       * Sobol', the padded point index. Past the tables: the padding
                       * permutation's seed */
    uint64_t y;       /* nibble i: stratified 2D, the 1D stratum of y */
    /* Stratified 2D past the tables, when the grid has at most 16 rows and 16 columns
     * (grid_packed): multi_jitter's sub-column and sub-row permutations of this dimension,
     * the same for all of the pixel's samples, so drawn once here instead of per sample.
     * Nibble r of sub_x / c of sub_y: the shared shuffles rho_x(r), rho_y(c); nibble c of
     * col_rot / r of row_rot: the per-column / per-row rotations. */
    uint64_t sub_x, sub_y, col_rot, row_rot;
} SamplerDimTable;

/* Stratified 2D past the tables when a grid side exceeds SAMPLER_SHUFFLE_MAX (not
 * grid_packed): one 2D dimension's multi-jitter sub-stratum permutations, the shared
 * permutations rho and the per-row and per-column rotations o, filled entry by entry on first
 * use (a render round may use 4 samples of a 1 x 1009 grid). A pixel's sampler keeps a few,
 * direct-mapped by dimension; a pure cache like SamplerDimTable. */
#define SAMPLER_GRID_SLOTS 4
#define SAMPLER_GRID_ENTRIES 1024 /* rows + cols of the largest grid tabulated (beyond: per sample) */
typedef struct {
    int dim;        /* the 2D dimension it serves (its SamplerDimTable seed) */
    uint64_t seed;  /* that dimension's multi-jitter seed */
    uint64_t rho_x_small, rho_y_small; /* a side of 2..16: its exact shared shuffle, nibbles */
    uint64_t filled[SAMPLER_GRID_ENTRIES / 64]; /* bit e: entry[e] is computed */
    /* entry r < rows: rho_x(r) | o_r << 16 (row r's sub-row rotation); entry rows + c:
     * rho_y(c) | o_c << 16 (column c's sub-column rotation) */
    uint32_t entry[SAMPLER_GRID_ENTRIES];
} SamplerGridTable;

typedef struct {
    SamplerKind kind;
    uint64_t seed;
    int set_spp;      /* samples of this pixel in this pass (>= 1): one set */
    int prefix_spp;   /* 0, or the first prefix_spp samples of the set (< set_spp) are a set of
                       * their own and the rest continues them (sampler_continue_pixel) */
    /* The set, or the part of it, that the current sample belongs to: */
    int spp;          /* its number of points (the strata count) */
    uint32_t grid_rows, grid_cols; /* the 2D stratification grid of spp points */
    double inv_spp;   /* 1 / spp */
    double inv_spp_2m32; /* 2^-32 / spp: 32-bit jitter to the stratum's scale */
    uint64_t margin_bits; /* spp 2^-23 in units of 2^-32 (stratified rounding bound) */
    uint64_t part_key;    /* which part: block | (0 whole or prefix, 1 continuation) << 32 */
    uint64_t perm_key, value_key; /* key the part's padding permutations and its values */
    uint32_t point_offset;        /* Sobol': the part's first sequence index */
    /* Past the tables (spp > SAMPLER_SHUFFLE_MAX), derived from spp once per part: */
    uint32_t perm_mask;  /* the padding permutation's power-of-two domain minus one */
    int perm_shift;      /* its xorshift distance */
    bool grid_packed;    /* stratified 2D: rows and cols <= 16 (SamplerDimTable.sub_x...) */
    bool grid_tabled;    /* stratified 2D, not packed: rows + cols <= SAMPLER_GRID_ENTRIES */
    uint64_t cols_magic; /* 2^64 / grid_cols rounded up: j / cols without a division */
    uint64_t rows_magic; /* the same for grid_rows (remainders modulo rows; need_grid_steps) */
    uint32_t grid_step_x, grid_step_y; /* sides above 16: the lattice steps of rho (multi_jitter) */
    bool grid_steps_ready;             /* grid_step_x and _y are set for this part */
    uint64_t pixel_seed;
    int sample_index; /* current sample, >= 0 (indices >= set_spp start further blocks) */
    uint32_t block, index_in_block; /* sample_index / set_spp, and the index within the part */
    int dim;          /* next dimension to hand out */
    uint64_t sample_key; /* keys the current sample's jitter (counter-based: one hash per request) */
    bool key_ready;   /* sample_key is set for the current sample (always, for stratified) */
    uint64_t perm_valid[SAMPLER_PERM_CACHE_SLOTS / 64]; /* which perm_cache slots hold a permutation */
    uint64_t tables_ready[2];     /* bit d: dim_table[d] is built for 1D ([0]) / 2D ([1]) requests */
    uint64_t seeds_ready[2];      /* spp above the tables: bit d, dim_table[d] holds d's seeds */
    /* Direct-mapped by seed (spp > SAMPLER_SHUFFLE_MAX only); a pure cache. */
    SamplerPermSlot perm_cache[SAMPLER_PERM_CACHE_SLOTS];
    SamplerDimTable dim_table[SAMPLER_PADDED_DIMS];
    SamplerGridTable grid[SAMPLER_GRID_SLOTS]; /* grid_tabled: see SamplerGridTable */
} PixelSampler;

/* Starts pixel (px, py) of pass `pass` with spp samples. */
void sampler_start_pixel(PixelSampler *s, SamplerKind kind, uint64_t seed, int px, int py, int pass, int spp);
/* Starts pixel (px, py) of pass `pass` to continue the spp_before samples that
 * sampler_start_pixel(..., pass, spp_before) gave up to spp samples in all: sample indices
 * [0, spp_before) give exactly those samples again, [spp_before, spp) the continuation.
 * Sobol': the two together are the first spp points of every dimension's scrambled sequence
 * (for spp a power of two, a (0, k, 2)-net), as if the pixel had been one set of spp from
 * the start, the padding permutation aside. Stratified: the continuation is a stratified set
 * of spp - spp_before points of its own (stratified sets do not extend). spp <= spp_before
 * is sampler_start_pixel(..., spp). */
void sampler_continue_pixel(PixelSampler *s, SamplerKind kind, uint64_t seed, int px, int py, int pass,
                            int spp_before, int spp);
/* Begins sample i (i >= 0; each further block of set_spp indices is a fresh stratified set,
 * without a prefix); dimensions restart at 0. */
void sampler_start_sample(PixelSampler *s, int sample_index);
/* Next dimension(s) of the current sample, each in [0, 1). Consumers must request
 * dimensions in a fixed order per sample so strata line up across samples. */
float sampler_1d(PixelSampler *s);
vec2 sampler_2d(PixelSampler *s);
/* Every value is a pure function of (pixel, sample, dimension), so a dimension may also be
 * skipped now (its index reserved: later requests keep their indices) and drawn later, or
 * never, by its index: sampler_1d_at(s, d) is what sampler_1d would have returned as
 * dimension d of the current sample (a 1D request's index is s->dim before the call). */
void sampler_skip(PixelSampler *s, int count);
float sampler_1d_at(PixelSampler *s, int dim);

/* One dimension of several consecutive samples of the pixel at once (a run): out[k] is
 * exactly what sampler_1d / sampler_2d would return as dimension dim (dim, dim + 1) of
 * sample first + k. Drawn dimension by dimension, the work a dimension shares between
 * samples (its table or seeds, the part's constants) is looked up once per run, and the
 * samples' independent hash chains overlap instead of waiting for each other. */
#define SAMPLER_RUN_MAX 128
typedef struct {
    int first, count;      /* samples first .. first + count - 1 (count <= SAMPLER_RUN_MAX) */
    bool one_part;         /* all in one part of the set: the fast path */
    uint64_t part_key, pixel_seed; /* the part and pixel the fast path serves */
    uint32_t index_in_block[SAMPLER_RUN_MAX];
    uint64_t key[SAMPLER_RUN_MAX]; /* each sample's jitter key */
} SamplerRun;
/* Begins a run of min(count, SAMPLER_RUN_MAX) samples from `first` (and starts sample
 * `first`: the per-sample state is left as after sampler_start_sample(s, first)). */
void sampler_run_begin(PixelSampler *s, SamplerRun *run, int first, int count);
/* out has run->count entries. They may interleave with per-sample requests (which change the
 * sampler's current sample, not the run). */
void sampler_run_1d(PixelSampler *s, const SamplerRun *run, int dim, float *out);
void sampler_run_2d(PixelSampler *s, const SamplerRun *run, int dim, vec2 *out);

/* Element i of a pseudo-random permutation of {0, ..., n-1} chosen by seed, computed without
 * storing the permutation (cycle-walking a keyed bijection on the next power of two).
 * i >= n is taken modulo n; n = 0 or 1 returns 0. */
uint32_t sampler_permute(uint32_t i, uint32_t n, uint64_t seed);

#endif
