/* Per-pixel samplers: padded stratified (multi-jitter in 2D) and padded
 * Owen-scrambled Sobol'. Every value is a pure function of (pixel seed, sample index,
 * dimension), so tiles can run in any order on any number of threads; what a pixel's
 * sampler keeps (permutations, per-dimension tables) is only a cache of that function,
 * built lazily because the same permutations serve all of a pixel's samples.
 * See docs/sampling.md. */
#include "core/sampler.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

/* ---- seeds ----------------------------------------------------------------------------- */

/* Seed of one scalar dimension of one pixel. `block` counts how many times the caller has
 * wrapped around spp (sample indices >= spp), so every block is a fresh stratified set. */
static uint64_t dim_seed(const PixelSampler *s, int dim, uint32_t block, uint64_t salt)
{
    /* Distinct (dim, salt) give distinct odd-multiplier offsets; the splitmix finaliser
     * then makes the seeds of neighbouring dimensions look independent. */
    uint64_t key = ((uint64_t)(uint32_t)dim << 8 | salt) * 0xd1342543de82ef95ull;
    uint64_t h = hash_u64(s->pixel_seed ^ key);
    return block ? hash_u64(h + block) : h;
}

/* ---- permutations without storage ----------------------------------------------------- */

/* A keyed bijection of [0, mask] with mask = 2^bits - 1. Each step is invertible modulo
 * 2^bits: xor with a constant, multiplication by an odd number, adding a constant, and
 * x ^= x >> k (the top k bits are unchanged, so the lower ones can be recovered top down).
 * Multiplication carries entropy upwards, the right shift carries it back down; four
 * rounds mix small domains (16 to 256 elements) well enough that the permutations of
 * different seeds look independent. The idea (cycle-walking a hash restricted to a power
 * of two) follows Kensler 2013, "Correlated Multi-Jittered Sampling", sec. 3; the steps and
 * constants here are our own. */
static uint32_t permute_pow2(uint32_t x, uint32_t mask, int bits, uint64_t seed)
{
    int shift = bits > 1 ? (bits + 1) / 2 : 1;
    uint32_t k0 = (uint32_t)seed, k1 = (uint32_t)(seed >> 32);
    x ^= k0 & mask;
    x = (x * 0x9e3779b1u) & mask;
    x ^= x >> shift;
    x = (x + k1) & mask;
    x = (x * (0x2c9277b5u | (k0 >> 16) | 1u)) & mask;
    x ^= x >> shift;
    x ^= (k1 >> 8) & mask;
    x = (x * 0x85ebca77u) & mask;
    x ^= x >> shift;
    x = (x + (k0 >> 5)) & mask;
    x = (x * 0xc2b2ae3du) & mask;
    x ^= x >> shift;
    return x;
}

/* Small domains: the keyed bijection above has only a handful of distinct keys on 2-4 bits
 * and is far from a uniformly random permutation (n = 3 after cycle walking: P(0 -> 0) = 1/4
 * instead of 1/3), which biased multi-jitter (E[x y] 2% low at 3 x 3) and correlated the
 * padded dimensions. Up to this size an explicit Fisher-Yates shuffle driven by PCG32 is
 * exact and still cheap (at most 16 steps per call). */
static inline void shuffle_small(uint32_t n, uint64_t seed, uint8_t *perm)
{
    Pcg32 rng;
    pcg32_seed(&rng, seed, 0x9e3779b97f4a7c15ull);
    if (n == 2) { /* the common 2 x 2 multi-jitter case: one draw, swap or not */
        uint32_t j = pcg32_below(&rng, 2);
        perm[0] = (uint8_t)(1u - j), perm[1] = (uint8_t)j;
        return;
    }
    for (uint32_t k = 0; k < n; ++k) perm[k] = (uint8_t)k;
    for (uint32_t k = n - 1; k > 0; --k) {
        /* uniform in [0, k] without modulo bias, and (almost always) without a division */
        uint32_t j = pcg32_below(&rng, k + 1);
        uint8_t t = perm[k];
        perm[k] = perm[j];
        perm[j] = t;
    }
}

static uint32_t permute_small(uint32_t i, uint32_t n, uint64_t seed)
{
    uint8_t perm[SAMPLER_SHUFFLE_MAX];
    shuffle_small(n, seed, perm);
    return perm[i];
}

/* sampler_permute through the pixel's cache: a shuffle costs up to 15 random draws, and the
 * same permutation serves all of a pixel's samples (about 20% of render time otherwise). */
static uint32_t permute_cached(PixelSampler *s, uint32_t i, uint32_t n, uint64_t seed)
{
    if (n <= 1 || n > SAMPLER_SHUFFLE_MAX) return sampler_permute(i, n, seed);
    if (i >= n) i %= n;
    uint32_t k = (uint32_t)(seed ^ (seed >> 29)) & (SAMPLER_PERM_CACHE_SLOTS - 1);
    SamplerPermSlot *slot = &s->perm_cache[k];
    uint64_t bit = 1ull << (k & 63);
    if (!(s->perm_valid[k >> 6] & bit) || slot->n != n || slot->seed != seed) {
        shuffle_small(n, seed, slot->perm);
        slot->n = (uint8_t)n;
        slot->seed = seed;
        s->perm_valid[k >> 6] |= bit;
    }
    return slot->perm[i];
}

uint32_t sampler_permute(uint32_t i, uint32_t n, uint64_t seed)
{
    if (n <= 1) return 0;
    /* An index outside [0, n) could sit on a cycle that never enters it: fold it in. */
    if (i >= n) i %= n;
    if (n <= SAMPLER_SHUFFLE_MAX) return permute_small(i, n, seed);
    uint32_t mask = n - 1;
    mask |= mask >> 1;
    mask |= mask >> 2;
    mask |= mask >> 4;
    mask |= mask >> 8;
    mask |= mask >> 16;
    int bits = 32 - __builtin_clz(mask); /* mask > 0 here */
    /* Cycle walking: apply the bijection until the value falls inside [0, n). Starting from
     * i < n the orbit of a permutation returns to i, so this terminates; since n > mask/2,
     * the expected number of steps is below 2. */
    uint32_t x = i;
    do {
        x = permute_pow2(x, mask, bits, seed);
    } while (x >= n);
    return x;
}

/* ---- stratified ------------------------------------------------------------------------ */

/* (stratum + jitter) / n as a float that stays inside [stratum/n, (stratum+1)/n): rounding
 * the double to float could otherwise step onto the next stratum's edge (or 1.0). For n
 * below 2^24, float * n is exact in double, so the test below is exact. */
static float stratum_value(uint32_t stratum, double jitter, uint32_t n, double inv_n)
{
    /* The product may round differently from the quotient; the loops below settle it. */
    float v = (float)(((double)stratum + jitter) * inv_n);
    /* Fast exit, no change in the result: v = x (1 + e) with x = (stratum + jitter) / n and
     * |e| < 2^-23 (one float rounding, one double product), so v n is within
     * n 2^-23 of stratum + jitter; a jitter that far from 0 and 1 keeps v n strictly
     * inside (stratum, stratum + 1), where neither loop below runs and v < 1. */
    double margin = (double)n * 0x1p-23; /* exact; the compiler keeps it out of loops */
    if (jitter > margin && jitter < 1.0 - margin) return v;
    if (n < (1u << 24)) {
        while ((double)v * n >= (double)stratum + 1.0) v = nextafterf(v, 0.0f);
        while ((double)v * n < (double)stratum) v = nextafterf(v, 1.0f);
    }
    return v < 1.0f ? v : 0x1.fffffep-1f;
}

static double jitter01(Pcg32 *rng) { return (double)pcg32_next(rng) * 0x1p-32; }

/* Splits n into a rows x cols grid, rows the largest divisor of n not above sqrt(n):
 * 16 -> 4 x 4, 12 -> 3 x 4, 8 -> 2 x 4, a prime p -> 1 x p (a Latin hypercube). */
static void grid_shape(uint32_t n, uint32_t *rows, uint32_t *cols)
{
    /* the usual small counts without a square root and a division loop per pixel */
    static const uint8_t small_rows[17] = {1, 1, 1, 1, 2, 1, 2, 1, 2, 3, 2, 1, 3, 1, 2, 3, 4};
    if (n <= 16) {
        *rows = small_rows[n];
        *cols = n / *rows;
        return;
    }
    uint32_t r = (uint32_t)floor(sqrt((double)n));
    while (r > 1 && n % r) --r;
    if (r < 1) r = 1;
    *rows = r;
    *cols = n / r;
}

/* Seeds of the permutation of column c's sub-columns and of row r's sub-rows. */
static uint64_t column_perm_seed(uint64_t seed, uint32_t c) { return hash_u64(seed ^ (0x5bd1e995ull + ((uint64_t)c << 32))); }
static uint64_t row_perm_seed(uint64_t seed, uint32_t r) { return hash_u64(seed ^ (0x27d4eb2full + ((uint64_t)r << 32))); }

/* Multi-jittered point number j of n (Chiu, Shirley, Wang 1994, "Multi-jittered
 * sampling"): the unit square is a rows x cols grid with one point per cell, and each cell
 * is further split into rows sub-columns and cols sub-rows so that the n points also fall
 * one per stratum of width 1/n in x and in y. Point j sits in cell (c = j % cols,
 * r = j / cols); within column c the sub-columns of its rows are a permutation of [0, rows),
 * and within row r the sub-rows of its columns a permutation of [0, cols).
 * We deliberately use an independent permutation per column (and per row), not the single
 * shared one of Kensler 2013's "correlated" variant: with a shared permutation the error of
 * an integrand with a mixed term (f = x y) contains sum_c c * perm(c), which does not
 * average out and decays only as n^-0.75; independent permutations give n^-1, as a plain
 * jittered grid (measured in tests/core/test_sampler.c, about 1.5x lower error than it). */
static vec2 multi_jitter(PixelSampler *s, uint32_t j, uint32_t n, uint64_t seed)
{
    Pcg32 *rng = &s->rng;
    uint32_t rows = s->grid_rows, cols = s->grid_cols;
    uint32_t c = j % cols, r = j / cols;
    uint32_t sub_x = permute_cached(s, r, rows, column_perm_seed(seed, c));
    uint32_t sub_y = permute_cached(s, c, cols, row_perm_seed(seed, r));
    double jx = jitter01(rng), jy = jitter01(rng);
    /* x = (c + (sub_x + jx) / rows) / cols: 1D stratum c * rows + sub_x of n. */
    return v2(stratum_value(c * rows + sub_x, jx, n, s->inv_spp), stratum_value(r * cols + sub_y, jy, n, s->inv_spp));
}

/* ---- Sobol' ---------------------------------------------------------------------------- */

static uint32_t reverse_bits32(uint32_t v)
{
    v = ((v >> 1) & 0x55555555u) | ((v & 0x55555555u) << 1);
    v = ((v >> 2) & 0x33333333u) | ((v & 0x33333333u) << 2);
    v = ((v >> 4) & 0x0f0f0f0fu) | ((v & 0x0f0f0f0fu) << 4);
    /* each byte is reversed now; reversing the byte order finishes the job */
    return __builtin_bswap32(v);
}

/* Sobol' points are built here directly in bit-reversed form (bit 0 = the most significant
 * bit of the fraction), which is the form the scramble below works on; one reversal at the
 * end turns the result into a fraction.
 * First dimension: the base-2 radical inverse (van der Corput), whose reversed form is the
 * index itself. */
static uint32_t sobol_dim0_reversed(uint32_t i) { return i; }

/* Second dimension: its generator matrix is the Pascal matrix modulo 2, whose columns are
 * v_0 = 1/2 and v_{k+1} = v_k xor (v_k >> 1) (direction numbers m = 1, 3, 5, 15, 17, 51,
 * ...); reversed, v_0 = 1 and v_{k+1} = v_k xor (v_k << 1). Together with dim0, every
 * aligned block of 2^k indices is a (0, k, 2)-net in base 2 (Sobol' 1967). */
static uint32_t sobol_dim1_reversed(uint32_t i)
{
    uint32_t r = 0, v = 1u;
    for (; i; i >>= 1, v ^= v << 1)
        if (i & 1u) r ^= v;
    return r;
}

/* Owen's nested uniform scramble, approximated by a hash in the spirit of Laine and Karras
 * 2011 and Burley 2020 ("Practical Hash-based Owen Scrambling", sec. 3-4). Input and output
 * are bit-reversed fractions. Each step flips bit j by a function of bits 0..j-1 only
 * (adding a constant, x ^= x * even, x *= odd: carries only travel upwards), which is
 * exactly the nested-scramble form, so scrambled (0, k, 2)-nets stay nets. The constants
 * are our own; tests/core/test_sampler.c compares the integration error against a
 * brute-force true Owen scramble. */
static uint32_t owen_scramble_reversed(uint32_t v, uint32_t seed)
{
    v += seed;
    v ^= v * 0x6b43a9b6u;
    v *= (seed >> 16) | 1u;
    v ^= v * 0x1d8e4e28u;
    /* A rotated seed: with seed * odd here, bit 0 (the fraction's top bit) would be flipped
     * by seed bit 0 twice (once by the first add) and never scrambled, and bits 1-3 only
     * partly; measured flip rates were 0, 0.25, 0.38, 0.44 instead of 1/2, which made
     * non-power-of-2 sample counts biased (9 spp: means 0.463 instead of 0.5). */
    v += (seed >> 11 | seed << 21) * 0x9e3779b9u;
    v ^= v * 0xa3b195aeu;
    v *= 0x8a5cd789u;
    v ^= v * 0x2f5a6e04u;
    return v;
}

/* 0.32 fixed point to a float in [0, 1): keep the top 24 bits, which a float holds exactly. */
static float fixed_to_float(uint32_t v) { return (float)(v >> 8) * 0x1p-24f; }

static float scrambled_to_float(uint32_t reversed, uint32_t seed)
{
    return fixed_to_float(reverse_bits32(owen_scramble_reversed(reversed, seed)));
}

/* ---- public API ------------------------------------------------------------------------ */

SamplerKind sampler_kind_from_pbrt(const char *name)
{
    if (name && (strcmp(name, "stratified") == 0 || strcmp(name, "independent") == 0))
        return SAMPLER_STRATIFIED;
    return SAMPLER_SOBOL; /* sobol, zsobol, paddedsobol, halton, pmj02bn, and unknown names */
}

const char *sampler_kind_name(SamplerKind kind)
{
    return kind == SAMPLER_STRATIFIED ? "stratified" : "sobol";
}

void sampler_start_pixel(PixelSampler *s, SamplerKind kind, uint64_t seed, int px, int py, int pass, int spp)
{
    /* Everything but the caches, whose validity bits (perm_valid, dims_ready) are cleared
     * with the rest: a few stores per pixel instead of touching kilobytes. */
    memset(s, 0, offsetof(PixelSampler, perm_cache));
    s->kind = kind;
    s->seed = seed;
    s->spp = spp >= 1 ? spp : 1;
    s->inv_spp = 1.0 / (double)s->spp;
    grid_shape((uint32_t)s->spp, &s->grid_rows, &s->grid_cols);
    s->pixel_seed = hash_pixel_seed(seed, px, py, pass);
    sampler_start_sample(s, 0);
}

/* The jitter stream of the current sample: a fresh PCG32 state keyed by (pixel, sample). */
static void seed_sample_rng(PixelSampler *s)
{
    pcg32_seed(&s->rng, hash_u64(s->pixel_seed ^ hash_u64((uint64_t)s->sample_index + 0x51ed27ull)),
               s->pixel_seed >> 1);
    s->rng_ready = true;
}

static Pcg32 *sample_rng(PixelSampler *s)
{
    if (!s->rng_ready) seed_sample_rng(s);
    return &s->rng;
}

void sampler_start_sample(PixelSampler *s, int sample_index)
{
    s->sample_index = sample_index >= 0 ? sample_index : 0;
    s->dim = 0;
    /* The Sobol' sampler draws from the stream only past the padded dimensions: seed it on
     * first use (sample_rng) rather than for every sample. */
    s->rng_ready = false;
    if (s->kind == SAMPLER_STRATIFIED) seed_sample_rng(s);
}

/* Position of the current sample inside the stratified set of spp points of dimension dim
 * (the per-dimension shuffle that decorrelates dimensions: "padding"). */
static uint32_t padded_index(PixelSampler *s, int dim, uint32_t *block, uint64_t salt)
{
    uint32_t n = (uint32_t)s->spp, i = (uint32_t)s->sample_index;
    *block = i / n;
    return permute_cached(s, i % n, n, dim_seed(s, dim, *block, salt));
}

/* ---- per-pixel dimension tables (the common case: spp <= 16, indices below spp) ----- */

/* The table of scalar dimension dim for requests of `kind` (1 or 2), built on first use in
 * this pixel. NULL when the cached path does not apply (the caller computes directly). */
static SamplerDimTable *dim_table(PixelSampler *s, int dim, uint8_t kind)
{
    uint32_t n = (uint32_t)s->spp;
    if (n > SAMPLER_SHUFFLE_MAX || (uint32_t)s->sample_index >= n) return NULL;
    SamplerDimTable *t = &s->dim_table[dim];
    uint64_t bit = 1ull << dim;
    if ((s->dims_ready & bit) && t->kind == kind) return t;
    /* the same seeds and permutation as padded_index() and the per-request paths below */
    shuffle_small(n, dim_seed(s, dim, 0, kind == 1 ? 1 : 3), t->pad);
    /* a stratified 1D dimension has no seed beyond its permutation */
    t->seed = kind == 1 && s->kind == SAMPLER_STRATIFIED ? 0 : dim_seed(s, dim, 0, kind == 1 ? 2 : 4);
    t->kind = kind;
    t->cols_ready = t->rows_ready = t->points_ready = 0;
    s->dims_ready |= bit;
    return t;
}

/* Fills the multi-jitter strata of point j (as multi_jitter computes them): x from column
 * c's sub-column permutation, y from row r's sub-row permutation. Each permutation serves
 * every point of its column / row, so it is drawn once per pixel. */
static void table_fill_point(PixelSampler *s, SamplerDimTable *t, uint32_t j)
{
    uint32_t rows = s->grid_rows, cols = s->grid_cols, c = j % cols, r = j / cols;
    if (!(t->cols_ready & (1u << c))) {
        uint8_t perm[SAMPLER_SHUFFLE_MAX] = {0};
        if (rows > 1) shuffle_small(rows, column_perm_seed(t->seed, c), perm);
        for (uint32_t k = 0; k < rows; ++k) t->x_stratum[k * cols + c] = (uint8_t)(c * rows + perm[k]);
        t->cols_ready |= (uint16_t)(1u << c);
    }
    if (!(t->rows_ready & (1u << r))) {
        uint8_t perm[SAMPLER_SHUFFLE_MAX] = {0};
        if (cols > 1) shuffle_small(cols, row_perm_seed(t->seed, r), perm);
        for (uint32_t k = 0; k < cols; ++k) t->y_stratum[r * cols + k] = (uint8_t)(r * cols + perm[k]);
        t->rows_ready |= (uint16_t)(1u << r);
    }
    t->points_ready |= (uint16_t)(1u << j);
}

float sampler_1d(PixelSampler *s)
{
    int dim = s->dim++;
    if (dim >= SAMPLER_PADDED_DIMS) return pcg32_float(sample_rng(s));
    SamplerDimTable *t = dim_table(s, dim, 1);
    if (t) {
        uint32_t j = t->pad[s->sample_index];
        if (s->kind == SAMPLER_STRATIFIED) return stratum_value(j, jitter01(&s->rng), (uint32_t)s->spp, s->inv_spp);
        return scrambled_to_float(sobol_dim0_reversed(j), (uint32_t)t->seed);
    }
    uint32_t n = (uint32_t)s->spp, block;
    uint32_t j = padded_index(s, dim, &block, 1);
    if (s->kind == SAMPLER_STRATIFIED) return stratum_value(j, jitter01(&s->rng), n, s->inv_spp);
    /* Scrambled van der Corput: one point per stratum of width 1/n when n is a power of 2. */
    uint32_t seed = (uint32_t)dim_seed(s, dim, block, 2);
    return scrambled_to_float(sobol_dim0_reversed(j), seed);
}

vec2 sampler_2d(PixelSampler *s)
{
    int dim = s->dim;
    s->dim += 2;
    if (dim >= SAMPLER_PADDED_DIMS - 1) {
        Pcg32 *rng = sample_rng(s);
        float x = pcg32_float(rng);
        return v2(x, pcg32_float(rng));
    }
    SamplerDimTable *t = dim_table(s, dim, 2);
    if (t) {
        uint32_t j = t->pad[s->sample_index];
        if (s->kind == SAMPLER_STRATIFIED) {
            if (!(t->points_ready & (1u << j))) table_fill_point(s, t, j);
            uint32_t sx = t->x_stratum[j], sy = t->y_stratum[j];
            /* jitter draws in multi_jitter's order: x, then y */
            double jx = jitter01(&s->rng), jy = jitter01(&s->rng);
            return v2(stratum_value(sx, jx, (uint32_t)s->spp, s->inv_spp), stratum_value(sy, jy, (uint32_t)s->spp, s->inv_spp));
        }
        return v2(scrambled_to_float(sobol_dim0_reversed(j), (uint32_t)t->seed),
                  scrambled_to_float(sobol_dim1_reversed(j), (uint32_t)(t->seed >> 32)));
    }
    uint32_t n = (uint32_t)s->spp, block;
    uint32_t j = padded_index(s, dim, &block, 3);
    uint64_t seed = dim_seed(s, dim, block, 4);
    if (s->kind == SAMPLER_STRATIFIED) return multi_jitter(s, j, n, seed);
    return v2(scrambled_to_float(sobol_dim0_reversed(j), (uint32_t)seed),
              scrambled_to_float(sobol_dim1_reversed(j), (uint32_t)(seed >> 32)));
}
