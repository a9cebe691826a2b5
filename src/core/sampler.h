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
 * later dimensions of a sample are independent uniform random numbers from s->rng. */
#define SAMPLER_PADDED_DIMS 64
#define SAMPLER_PERM_CACHE_SLOTS 128

typedef struct {
    uint64_t seed;
    uint8_t n; /* 0: empty slot */
    uint8_t perm[SAMPLER_SHUFFLE_MAX];
} SamplerPermSlot;

/* What a pixel's sampler derives once per scalar dimension (with spp <= SAMPLER_SHUFFLE_MAX
 * and sample indices below spp) and then reuses for every sample of the pixel: the
 * dimension's seeds, its padding permutation and, for stratified 2D requests, the
 * multi-jitter sub-strata of each point. A pure cache, filled lazily: the values are the
 * ones the uncached computation gives. */
typedef struct {
    uint8_t kind;                 /* 1: built for sampler_1d, 2: for sampler_2d */
    uint16_t cols_ready, rows_ready; /* stratified 2D: which columns / rows have x_stratum / y_stratum */
    uint16_t points_ready;        /* stratified 2D: which points j have both strata */
    uint64_t seed;                /* dim_seed(.., 2) for 1D Sobol', dim_seed(.., 4) for 2D; 0 for 1D stratified */
    uint8_t pad[SAMPLER_SHUFFLE_MAX];       /* sample index -> point index j */
    uint8_t x_stratum[SAMPLER_SHUFFLE_MAX]; /* point j -> its 1D stratum of n in x */
    uint8_t y_stratum[SAMPLER_SHUFFLE_MAX]; /* ... and in y */
} SamplerDimTable;

typedef struct {
    SamplerKind kind;
    uint64_t seed;
    int spp;          /* samples of this pixel in this pass (>= 1) */
    uint32_t grid_rows, grid_cols; /* the 2D stratification grid of spp points */
    double inv_spp;   /* 1 / spp */
    uint64_t pixel_seed;
    int sample_index; /* current sample, 0 .. spp-1 */
    int dim;          /* next dimension to hand out */
    Pcg32 rng;        /* jitter/scramble stream of the current sample */
    bool rng_ready;   /* rng is seeded for the current sample (always, for stratified) */
    uint64_t perm_valid[SAMPLER_PERM_CACHE_SLOTS / 64]; /* which perm_cache slots hold a permutation */
    uint64_t dims_ready;          /* which dim_table entries are built */
    /* Direct-mapped by seed; a pure cache: the values never depend on what is cached. */
    SamplerPermSlot perm_cache[SAMPLER_PERM_CACHE_SLOTS];
    SamplerDimTable dim_table[SAMPLER_PADDED_DIMS];
} PixelSampler;

/* Starts pixel (px, py) of pass `pass` with spp samples. */
void sampler_start_pixel(PixelSampler *s, SamplerKind kind, uint64_t seed, int px, int py, int pass, int spp);
/* Begins sample i (0 <= i < spp); dimensions restart at 0. */
void sampler_start_sample(PixelSampler *s, int sample_index);
/* Next dimension(s) of the current sample, each in [0, 1). Consumers must request
 * dimensions in a fixed order per sample so strata line up across samples. */
float sampler_1d(PixelSampler *s);
vec2 sampler_2d(PixelSampler *s);

/* Element i of a pseudo-random permutation of {0, ..., n-1} chosen by seed, computed without
 * storing the permutation (cycle-walking a keyed bijection on the next power of two).
 * i >= n is taken modulo n; n = 0 or 1 returns 0. */
uint32_t sampler_permute(uint32_t i, uint32_t n, uint64_t seed);

#endif
