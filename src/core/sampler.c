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

#include "core/vectorise.h"

/* The hot loops of runs and of the grid tables are loops over arrays (one value per sample
 * or entry, no calls, no early exits) that GCC vectorises (core/vectorise.h). Each does only
 * integer arithmetic and exactly rounded conversions and products, so every compiled copy
 * gives the values of the scalar path bit for bit (tools/bench-sampler's checksums,
 * test_sampler_run). */
#define RUN_KERNEL WEDGE_VECTORISED

/* ---- seeds ----------------------------------------------------------------------------- */

/* Seed of one scalar dimension of one pixel. `part` is the part's perm_key or value_key:
 * its low word counts how many times the caller has wrapped around the set (sample indices
 * >= set_spp), so every block is a fresh stratified set, and bit 32 marks a continuation
 * (sampler_continue_pixel). 0 for a pixel's first (or only) set. */
static uint64_t dim_seed(const PixelSampler *s, int dim, uint64_t part, uint64_t salt)
{
    /* Distinct (dim, salt) give distinct odd-multiplier offsets; the splitmix finaliser
     * then makes the seeds of neighbouring dimensions look independent. */
    uint64_t key = ((uint64_t)(uint32_t)dim << 8 | salt) * 0xd1342543de82ef95ull;
    uint64_t h = hash_u64(s->pixel_seed ^ key);
    return part ? hash_u64(h + part) : h;
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
static inline uint32_t permute_pow2_shift(uint32_t x, uint32_t mask, int shift, uint64_t seed)
{
    /* Reduced modulo 2^bits only before each right shift: the low bits of a sum, an xor or
     * a product depend only on the low bits of the operands, so the bits above the mask
     * that the other steps leave are never read (four masks on the dependency chain
     * instead of eight, the same values). */
    uint32_t k0 = (uint32_t)seed, k1 = (uint32_t)(seed >> 32);
    x = ((x ^ k0) * 0x9e3779b1u) & mask;
    x ^= x >> shift;
    x = ((x + k1) * (0x2c9277b5u | (k0 >> 16) | 1u)) & mask;
    x ^= x >> shift;
    x = ((x ^ (k1 >> 8)) * 0x85ebca77u) & mask;
    x ^= x >> shift;
    x = ((x + (k0 >> 5)) * 0xc2b2ae3du) & mask;
    x ^= x >> shift;
    return x;
}

/* The xorshift distance of permute_pow2 on `bits` bits: about half of them. */
static inline int permute_shift(int bits) { return bits > 1 ? (bits + 1) / 2 : 1; }

static uint32_t permute_pow2(uint32_t x, uint32_t mask, int bits, uint64_t seed)
{
    return permute_pow2_shift(x, mask, permute_shift(bits), seed);
}

/* ---- uniform integers from one 64-bit random number ----------------------------------- */

/* Several uniform integers in [0, b_1), [0, b_2), ... drawn from one 64-bit random number r
 * by repeated multiply-shift: j_1 is the high word of r b_1, whose low word feeds the next
 * draw, and so on (Lemire 2019, "Fast random integer generation in an interval", batched as
 * in Brackett-Rozinsky and Lemire 2024, "Batched ranged random integer generation"). By
 * induction r (b_1 ... b_k) = J 2^64 + low, where J is the mixed-radix number with digits
 * j_1 .. j_k: the draws are J = floor(r P / 2^64) for the product P of the bounds, which is
 * exactly uniform on [0, P) once the rare low < 2^64 mod P are rejected (Lemire's test).
 * One hash per permutation instead of one PCG32 seeding and a draw per element. */
typedef struct {
    uint64_t bits;    /* the unused fraction of the random number (the low word) */
    uint64_t product; /* P: product of the bounds drawn so far (below 2^64 by the callers) */
} BatchDraw;

static inline BatchDraw batch_start(uint64_t random_bits) { return (BatchDraw){random_bits, 1u}; }

static inline uint32_t batch_below(BatchDraw *d, uint32_t bound)
{
    unsigned __int128 m = (unsigned __int128)d->bits * bound;
    d->bits = (uint64_t)m;
    d->product *= bound;
    return (uint32_t)(m >> 64);
}

/* Lemire's acceptance test for the whole batch; low >= P >= 2^64 mod P is the fast path. */
static inline bool batch_accepted(const BatchDraw *d)
{
    return d->bits >= d->product || d->bits >= (0u - d->product) % d->product;
}

/* Element i of a permutation (or table) of at most 16 values packed 4 bits per element. */
static inline uint32_t nibble(uint64_t packed, uint32_t i) { return (uint32_t)(packed >> (4u * i)) & 15u; }

/* All 24 permutations of [0, 4), nibble i holding element i, in the order of the
 * Fisher-Yates decoding of J = q_1 + 2 q_2 + 6 q_3 (q_m in [0, m]: swap elements m and
 * m - q_m, m = 1, 2, 3). The first k! entries are then exactly the permutations of [0, k)
 * that fix the elements from k on, so a uniform J below k! picks a uniform permutation of
 * [0, k) with one draw (tests/core/test_sampler.c: test_small_permutations_uniform). */
static const uint16_t SMALL_PERMS[24] = {
    0x3210, 0x3201, 0x3120, 0x3021, 0x3012, 0x3102, 0x2310, 0x2301, 0x1320, 0x0321, 0x0312, 0x1302,
    0x1230, 0x0231, 0x2130, 0x2031, 0x1032, 0x0132, 0x0213, 0x1203, 0x0123, 0x1023, 0x2013, 0x2103,
};

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#include <immintrin.h>
#define FISHER_YATES_BYTE_SHUFFLE 1

/* n! for n <= 16 (16! < 2^45). */
static const uint64_t FACTORIAL[SAMPLER_SHUFFLE_MAX + 1] = {
    1ull, 1ull, 2ull, 6ull, 24ull, 120ull, 720ull, 5040ull, 40320ull, 362880ull, 3628800ull, 39916800ull,
    479001600ull, 6227020800ull, 87178291200ull, 1307674368000ull, 20922789888000ull,
};

/* A Fisher-Yates shuffle of [0, n) drawn as BatchDraw draws (bounds n, n - 1, ..., 2) takes the
 * mixed-radix digits of one draw `code` below n!: the step at position k (bound k + 1, weight
 * k!) swaps k with j_k = floor(code / k!) mod (k + 1), and j_k = 0 for k >= n (code < k!).
 * Each digit is then its own division by constants, where drawing them one by one is a chain
 * of dependent 128-bit products.
 * The swaps run on 16 bytes with SSSE3's byte shuffle (pshufb): swapping positions k and j is a
 * shuffle by the identity with k and j exchanged, a table row loaded off the dependency chain,
 * which is then one-cycle shuffles. The steps of positions 1..3, 4..5 and 6..7 go as one
 * shuffle each: their digits together are code mod 24, floor(code / 24) mod 30 and
 * floor(code / 720) mod 56 (the digits' own mixed radix), and the table row is the identity
 * after those swaps. Positions 8..15 go two at a time the same way: with h = floor(code / 8!)
 * and a = h mod 11880 (9 10 11 12), b = floor(h / 11880), the pairs' digits are a mod 90
 * (positions 8, 9), floor(a / 90) (10, 11), b mod 182 (12, 13) and floor(b / 182) (14, 15).
 * Positions 8..15 thus take 4 byte shuffles and 6 divisions by constants (until 2026-12-01
 * they went one at a time: 8 shuffles and 16 divisions); a shuffle of 16 elements is 7 byte
 * shuffles instead of 15 dependent swaps.
 * The tables (12 KiB) are filled once when the program is loaded (build_swap_tables).
 * Derivation: docs/algorithms.md, "A Fisher-Yates shuffle from one draw". */
enum { LOW_SWAPS_1_3 = 0, LOW_SWAPS_4_5 = 24, LOW_SWAPS_6_7 = 24 + 30, LOW_SWAPS_ROWS = 24 + 30 + 56 };
static uint8_t LOW_SWAPS[LOW_SWAPS_ROWS][16] __attribute__((aligned(16)));
enum {
    HIGH_SWAPS_8_9 = 0,
    HIGH_SWAPS_10_11 = 90,
    HIGH_SWAPS_12_13 = 90 + 132,
    HIGH_SWAPS_14_15 = 90 + 132 + 182,
    HIGH_SWAPS_ROWS = 90 + 132 + 182 + 240
};
static uint8_t HIGH_SWAPS[HIGH_SWAPS_ROWS][16] __attribute__((aligned(16)));

/* The identity after the swaps of positions hi, hi - 1, .., lo with digits of `index`
 * (mixed radix lo + 1, lo + 2, ..., least significant first). */
static void swapped_identity(uint8_t row[16], uint32_t lo, uint32_t hi, uint32_t index)
{
    uint32_t j[16];
    for (uint32_t k = lo; k <= hi; ++k) j[k] = index % (k + 1), index /= k + 1;
    for (uint32_t i = 0; i < 16; ++i) row[i] = (uint8_t)i;
    for (uint32_t k = hi + 1; k-- > lo;) {
        uint8_t t = row[k];
        row[k] = row[j[k]], row[j[k]] = t;
    }
}

__attribute__((constructor)) static void build_swap_tables(void)
{
    for (uint32_t x = 0; x < 24; ++x) swapped_identity(LOW_SWAPS[LOW_SWAPS_1_3 + x], 1, 3, x);
    for (uint32_t x = 0; x < 30; ++x) swapped_identity(LOW_SWAPS[LOW_SWAPS_4_5 + x], 4, 5, x);
    for (uint32_t x = 0; x < 56; ++x) swapped_identity(LOW_SWAPS[LOW_SWAPS_6_7 + x], 6, 7, x);
    for (uint32_t x = 0; x < 90; ++x) swapped_identity(HIGH_SWAPS[HIGH_SWAPS_8_9 + x], 8, 9, x);
    for (uint32_t x = 0; x < 132; ++x) swapped_identity(HIGH_SWAPS[HIGH_SWAPS_10_11 + x], 10, 11, x);
    for (uint32_t x = 0; x < 182; ++x) swapped_identity(HIGH_SWAPS[HIGH_SWAPS_12_13 + x], 12, 13, x);
    for (uint32_t x = 0; x < 240; ++x) swapped_identity(HIGH_SWAPS[HIGH_SWAPS_14_15 + x], 14, 15, x);
}

__attribute__((target("ssse3"))) static inline __m128i shuffle_by(__m128i p, const uint8_t row[16])
{
    return _mm_shuffle_epi8(p, _mm_load_si128((const __m128i *)row));
}

/* 16 bytes below 16 packed 4 bits each: pairs b_2i + 16 b_2i+1 (pmaddubsw), narrowed
 * (packuswb). */
__attribute__((target("ssse3"))) static inline uint64_t bytes_to_nibbles(__m128i b)
{
    __m128i pairs = _mm_maddubs_epi16(b, _mm_set1_epi16(0x1001));
    return (uint64_t)_mm_cvtsi128_si64(_mm_packus_epi16(pairs, pairs));
}

/* The inverse: nibble i of x to byte i. */
__attribute__((target("ssse3"))) static inline __m128i nibbles_to_bytes(uint64_t x)
{
    __m128i v = _mm_cvtsi64_si128((long long)x), low4 = _mm_set1_epi8(15);
    return _mm_unpacklo_epi8(_mm_and_si128(v, low4), _mm_and_si128(_mm_srli_epi16(v, 4), low4));
}

/* The shuffle of [0, n), 4 < n <= 16, whose draws are the digits of code < n!, packed in
 * nibbles (see above). In the groups, positions k >= n take j_k = k: added to the group's
 * index, where their digit is 0. */
__attribute__((target("ssse3"))) static uint64_t fisher_yates_ssse3(uint64_t code, uint32_t n)
{
    __m128i p = _mm_setr_epi8(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
    uint32_t low = (uint32_t)(code % 40320u), high = (uint32_t)(code / 40320u); /* 8! */
    /* the pairs from the one holding n - 1 down to 8 (constant divisors); when n - 1 is the
     * pair's lower position, its upper one must not swap: its digit is 0, so its own index
     * times its weight (lo + 1) is added, as for the low groups below */
    uint32_t a = high % 11880u, b = high / 11880u;
#define PAIR_ROW(base, lo, index) HIGH_SWAPS[(base) + (index) + (n == (lo) + 1 ? ((lo) + 1) * ((lo) + 1) : 0)]
    switch (n) {
    case 16: case 15: p = shuffle_by(p, PAIR_ROW(HIGH_SWAPS_14_15, 14, b / 182u)); /* fall through */
    case 14: case 13: p = shuffle_by(p, PAIR_ROW(HIGH_SWAPS_12_13, 12, b % 182u)); /* fall through */
    case 12: case 11: p = shuffle_by(p, PAIR_ROW(HIGH_SWAPS_10_11, 10, a / 90u)); /* fall through */
    case 10: case 9: p = shuffle_by(p, PAIR_ROW(HIGH_SWAPS_8_9, 8, a % 90u)); /* fall through */
    default: break;
    }
#undef PAIR_ROW
    /* identity digits in the groups: j_5 = 5 (weight 5), j_6 = 6 and j_7 = 7 (weights 1, 7) */
    uint32_t idle_4_5 = n <= 5 ? 5 * 5 : 0, idle_6_7 = n <= 6 ? 6 + 7 * 7 : n == 7 ? 7 * 7 : 0;
    p = shuffle_by(p, LOW_SWAPS[LOW_SWAPS_6_7 + low / 720u + idle_6_7]);
    p = shuffle_by(p, LOW_SWAPS[LOW_SWAPS_4_5 + low / 24u % 30u + idle_4_5]);
    p = shuffle_by(p, LOW_SWAPS[LOW_SWAPS_1_3 + low % 24u]);
    return bytes_to_nibbles(p);
}

/* Nibble i of the result is outer[middle[inner[i]]] for all 16 i: two byte shuffles. */
__attribute__((target("ssse3"))) static uint64_t compose_nibbles_ssse3(uint64_t outer, uint64_t middle, uint64_t inner)
{
    __m128i by_middle = _mm_shuffle_epi8(nibbles_to_bytes(middle), nibbles_to_bytes(inner));
    return bytes_to_nibbles(_mm_shuffle_epi8(nibbles_to_bytes(outer), by_middle));
}
#endif

/* Nibble i of the result is outer[middle[inner[i]]] for i < n, 0 above. */
static inline uint64_t compose_nibbles(uint64_t outer, uint64_t middle, uint64_t inner, uint32_t n)
{
#ifdef FISHER_YATES_BYTE_SHUFFLE
    if (__builtin_cpu_supports("ssse3")) {
        uint64_t all = compose_nibbles_ssse3(outer, middle, inner);
        return n >= 16 ? all : all & ((1ull << (4u * n)) - 1u);
    }
#endif
    uint64_t y = 0;
    for (uint32_t i = n; i-- > 0;) y = y << 4 | nibble(outer, nibble(middle, nibble(inner, i)));
    return y;
}

/* Fisher-Yates shuffle of [0, n), n <= 16, with the draws taken from d (n! <= 16! < 2^45),
 * on a permutation held in a register, 4 bits per element (elements n..15 stay in place and
 * are never read). Up to n = 4 (the grid's rows and columns at small spp, and spp 4 itself)
 * one draw of bound n! indexes SMALL_PERMS instead: the same uniform distribution without
 * n - 1 dependent draws and nibble swaps by variable shifts. Above, with SSSE3, the n - 1 draws
 * are one draw of bound n! (the same low word, the same product) decoded by fisher_yates_ssse3:
 * the same values as the draws one by one here. */
static inline uint64_t batch_shuffle_nibbles(BatchDraw *d, uint32_t n)
{
    if (n <= 4) {
        static const uint8_t factorial[5] = {1, 1, 2, 6, 24};
        return 0xfedcba9876540000ull | SMALL_PERMS[n > 1 ? batch_below(d, factorial[n]) : 0];
    }
#ifdef FISHER_YATES_BYTE_SHUFFLE
    if (__builtin_cpu_supports("ssse3")) {
        unsigned __int128 m = (unsigned __int128)d->bits * FACTORIAL[n];
        d->bits = (uint64_t)m;
        d->product *= FACTORIAL[n];
        return fisher_yates_ssse3((uint64_t)(m >> 64), n);
    }
#endif
    uint64_t p = 0xfedcba9876543210ull; /* the identity */
    for (uint32_t k = n; k-- > 1;) {
        uint32_t j = batch_below(d, k + 1);
        uint64_t swap = ((p >> (4u * k)) ^ (p >> (4u * j))) & 15u;
        p ^= (swap << (4u * k)) | (swap << (4u * j));
    }
    return p;
}

/* A uniformly random permutation of [0, n), n <= SAMPLER_SHUFFLE_MAX, packed in nibbles, from
 * random_bits, which must be uniform 64 bits (a hash output). Redraws (with probability
 * below n!/2^64 < 2e-6) hash the rejected bits. */
static uint64_t shuffle_bits_nibbles(uint32_t n, uint64_t random_bits)
{
    for (;; random_bits = hash_u64(random_bits)) {
        BatchDraw d = batch_start(random_bits);
        uint64_t p = batch_shuffle_nibbles(&d, n);
        if (batch_accepted(&d)) return p;
    }
}

/* Small domains: the keyed bijection above has only a handful of distinct keys on 2-4 bits
 * and is far from a uniformly random permutation (n = 3 after cycle walking: P(0 -> 0) = 1/4
 * instead of 1/3), which biased multi-jitter (E[x y] 2% low at 3 x 3) and correlated the
 * padded dimensions. Up to this size an explicit Fisher-Yates shuffle is exact and cheap. */
static inline void shuffle_small(uint32_t n, uint64_t seed, uint8_t *perm)
{
    uint64_t p = shuffle_bits_nibbles(n, hash_u64(seed));
    for (uint32_t k = 0; k < n; ++k) perm[k] = (uint8_t)nibble(p, k);
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

/* The smallest 2^k - 1 at or above n - 1 (n >= 2): the domain of the keyed bijection. */
static inline uint32_t pow2_mask(uint32_t n)
{
    uint32_t mask = n - 1;
    mask |= mask >> 1;
    mask |= mask >> 2;
    mask |= mask >> 4;
    mask |= mask >> 8;
    mask |= mask >> 16;
    return mask;
}

uint32_t sampler_permute(uint32_t i, uint32_t n, uint64_t seed)
{
    if (n <= 1) return 0;
    /* An index outside [0, n) could sit on a cycle that never enters it: fold it in. */
    if (i >= n) i %= n;
    if (n <= SAMPLER_SHUFFLE_MAX) return permute_small(i, n, seed);
    uint32_t mask = pow2_mask(n);
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

static float stratum_value_near_edge(const PixelSampler *s, uint32_t stratum, float v);

/* (stratum + jitter_bits 2^-32) / n rounded once to float (see stratum_value). */
static inline float stratum_value_raw(const PixelSampler *s, uint32_t stratum, uint32_t jitter_bits)
{
    /* (stratum 2^32 + bits) 2^-32 is the real stratum + jitter: converted to double it rounds
     * exactly as (double)stratum + jitter does (not at all below 2^21 strata), and the powers
     * of two are exact, so this is the same double as (stratum + jitter) inv_spp. Signed,
     * as it is below 2^63: x86-64 converts signed integers in one instruction. */
    return (float)((double)(int64_t)(((uint64_t)stratum << 32) | jitter_bits) * s->inv_spp_2m32);
}

/* Whether stratum_value_raw is already the answer: the rounded value v = x (1 + e) with
 * x = (stratum + jitter) / n and |e| < 2^-23 (one float rounding, one double product), so
 * v n is within n 2^-23 of stratum + jitter; a jitter that far from 0 and 1 (margin_bits =
 * n 2^-23 in units of 2^-32) keeps v n strictly inside (stratum, stratum + 1), where no
 * correction is needed and v < 1. */
static inline bool jitter_clear_of_edges(const PixelSampler *s, uint32_t jitter_bits)
{
    return jitter_bits > s->margin_bits && jitter_bits < (uint64_t)UINT32_MAX + 1u - s->margin_bits;
}

/* Whether a 2D value's jitters need stratum_value's correction (either is near an edge). */
static inline bool jitters_near_edge(const PixelSampler *s, uint32_t jitter_x, uint32_t jitter_y)
{
    return !jitter_clear_of_edges(s, jitter_x) || !jitter_clear_of_edges(s, jitter_y);
}

/* (stratum + jitter) / n as a float that stays inside [stratum/n, (stratum+1)/n), with
 * jitter = jitter_bits 2^-32: rounding to float could otherwise step onto the next
 * stratum's edge (or 1.0). For n below 2^24, float * n is exact in double, so the test of
 * the correction loops is exact. */
static inline float stratum_value(const PixelSampler *s, uint32_t stratum, uint32_t jitter_bits)
{
    float v = stratum_value_raw(s, stratum, jitter_bits);
    return jitter_clear_of_edges(s, jitter_bits) ? v : stratum_value_near_edge(s, stratum, v);
}

/* stratum_value for a jitter within the rounding bound of a stratum edge (a few in a
 * million): out of line, so that the common case stays small where it is inlined. */
static __attribute__((noinline)) float stratum_value_near_edge(const PixelSampler *s, uint32_t stratum, float v)
{
    uint32_t n = (uint32_t)s->spp;
    if (n < (1u << 24)) {
        while ((double)v * n >= (double)stratum + 1.0) v = nextafterf(v, 0.0f);
        while ((double)v * n < (double)stratum) v = nextafterf(v, 1.0f);
    }
    return v < 1.0f ? v : 0x1.fffffep-1f;
}

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

/* A uniform integer in [0, m) from 64 random bits (Lemire's test; a rejection rehashes). */
static inline uint32_t uniform_below(uint64_t random_bits, uint32_t m)
{
    for (;; random_bits = hash_u64(random_bits)) {
        BatchDraw d = batch_start(random_bits);
        uint32_t v = batch_below(&d, m);
        if (batch_accepted(&d)) return v;
    }
}

/* Binary (Stein's) gcd of a, b >= 1: shifts and subtractions, no divisions. */
static uint32_t gcd_u32(uint32_t a, uint32_t b)
{
    int shift = __builtin_ctz(a | b);
    a >>= __builtin_ctz(a);
    while (b) {
        b >>= __builtin_ctz(b);
        if (a > b) {
            uint32_t t = a;
            a = b, b = t;
        }
        b -= a;
    }
    return a << shift;
}

/* The step of rho past 16 elements (see grid_sub_permute): the unit modulo m nearest to
 * m / phi, phi the golden ratio, so that i -> step i mod m is a permutation whose points
 * (i, step i mod m) form a Fibonacci-like rank-1 lattice (the generator of the Fibonacci
 * lattices, Sloan and Joe 1994, "Lattice Methods for Multiple Integration", sec. 5.2). The
 * search ends at the latest at 1. */
static uint32_t golden_step(uint32_t m)
{
    if (m <= SAMPLER_SHUFFLE_MAX) return 0; /* unused: LATTICE_NIBBLES or an exact shuffle */
    uint32_t a = (uint32_t)((double)m * 0.6180339887498949 + 0.5);
    for (uint32_t d = 0;; ++d) {
        if (a > d && gcd_u32(a - d, m) == 1) return a - d;
        if (a + d < m && gcd_u32(a + d, m) == 1) return a + d;
    }
}

/* The shared permutation rho of a grid side of m <= 16 elements, nibble i holding step i mod m
 * (golden_step's rule for m, steps 3, 4, 5, 5, 7, 7, 7, 8, 9, 8, 9 for m = 5, 7, 8, ..., 16;
 * tests/core/test_sampler.c recomputes them): past 16 spp (grid_sub_permute) and for the rows
 * of the tables up to 16 (batch_rows_packed). 0 marks the sides whose rho stays an exact
 * shuffle: up to 4 and 6, whose only units are +-1 (the lattice would be a diagonal; on sides
 * of 3 and 4 it measured 2-3% worse than the shuffle at 8, 12 and 16 spp). Measured past 16
 * (RMS error against the shared rotated shuffle, smooth / edge integrand): 0.71x / 0.88x at
 * 256 spp (16 x 16), 0.82x / 0.91x at 64 (8 x 8), 0.73x / 0.77x at 26 (2 x 13), 0.91x /
 * 0.95x at 25 (docs/sampling.md, tests/core/small_count_sets.c). */
static const uint64_t LATTICE_NIBBLES[SAMPLER_SHUFFLE_MAX + 1] = {
    [5] = 0x24130ull,          [7] = 0x3625140ull,         [8] = 0x36147250ull,
    [9] = 0x483726150ull,      [10] = 0x3692581470ull,     [11] = 0x4815926a370ull,
    [12] = 0x5a3816b49270ull,  [13] = 0x5a27c4916b380ull,  [14] = 0x5a16b27c38d490ull,
    [15] = 0x7e6d5c4b3a29180ull, [16] = 0x7e5c3a18f6d4b290ull};

/* rho of a side of 2..16 elements, packed: the lattice, or the exact shuffle keyed by key
 * (the bits shuffle_small draws for it, so that permute_cached gives the same elements). */
static uint64_t small_side_rho(uint32_t m, uint64_t key)
{
    return LATTICE_NIBBLES[m] ? LATTICE_NIBBLES[m] : shuffle_bits_nibbles(m, hash_u64(key));
}

/* step i mod m, i < m; magic = 2^64 / m rounded up. Below 2^16 elements the product fits
 * 32 bits and the remainder is Lemire, Kaser, Kurz 2019's direct computation. */
static inline uint32_t lattice_rho(uint32_t i, uint32_t m, uint32_t step, uint64_t magic)
{
    if (m < (1u << 16)) return (uint32_t)(((unsigned __int128)(magic * (step * i)) * m) >> 64);
    return (uint32_t)((uint64_t)step * i % m);
}

/* The part's lattice steps (and rows_magic), on the first stratified 2D request that needs
 * them, not per part: a Sobol' pixel or a packed grid never does, and the gcds and the
 * 64-bit division cost Sobol' 2-4% at 418 and 1000 spp when done per part. */
static void need_grid_steps(PixelSampler *s)
{
    if (s->grid_steps_ready) return;
    s->grid_step_x = golden_step(s->grid_rows);
    s->grid_step_y = golden_step(s->grid_cols);
    s->rows_magic = s->grid_rows > 1 ? UINT64_MAX / s->grid_rows + 1u : 0;
    s->grid_steps_ready = true;
}

/* Element i of the sub-permutation of [0, m) of one grid column (or row) of multi_jitter,
 * past the tables (spp > SAMPLER_SHUFFLE_MAX). It is one permutation rho shared by the
 * dimension's columns, rotated by an offset o drawn uniformly per column (from own_seed):
 * sigma_c(i) = (rho(i) + o_c) mod m. rho is the lattice permutation i -> step i mod m (up to
 * m = SAMPLER_SHUFFLE_MAX from LATTICE_NIBBLES), except on sides of 2-4 and 6, where it is
 * an exact shuffle (key shared_seed, cached).
 * Independent shuffles per column would each be drawn afresh in every round of a pass (the
 * pixel's sampler, and its cache, live for one round): about one shuffle per sample per 2D
 * dimension, most of the render time at 64-256 spp. The rotations keep what the estimator
 * needs: each column's sub-columns are still a permutation (the strata), each sample's
 * sub-column is exactly uniform and independent of its row's sub-row (so every sample is
 * uniform: unbiased), and the per-column terms of a mixed integrand (sum_r r sigma_c(r) for
 * f = x y) are uncorrelated between columns, because their mean over o_c does not depend on
 * rho; a shared unrotated permutation (Kensler's correlated multi-jitter) would correlate
 * them (see multi_jitter). None of this asks rho to be random: for every fixed rho the
 * rotations alone make each sample uniform and the columns' terms independent, with mean
 * the integral. rho is therefore the lattice permutation: above 16 elements one multiply
 * per element instead of an exact shuffle of up to m draws (a render round may take 4
 * samples of a 1 x 1009 grid) or a cycle-walked bijection per element; its points are
 * spread evenly, where a random rho sometimes lines them up (measured: lower error than
 * independent random permutations per column, tests/core/test_sampler.c), and from 5
 * elements on a lower error than a shared shuffle (LATTICE_NIBBLES). Until 2026-11 the sides
 * above 16 had a keyed bijection per column, hashed and walked per sample (issue 22). */
static uint32_t grid_sub_permute(PixelSampler *s, uint32_t i, uint32_t m, uint32_t step, uint64_t magic,
                                 uint64_t shared_seed, uint64_t own_seed)
{
    if (m <= 1) return 0;
    uint32_t rho = m > SAMPLER_SHUFFLE_MAX ? lattice_rho(i, m, step, magic)
                   : LATTICE_NIBBLES[m]     ? nibble(LATTICE_NIBBLES[m], i)
                                            : permute_cached(s, i, m, shared_seed);
    uint32_t v = rho + uniform_below(own_seed, m);
    return v >= m ? v - m : v;
}

/* Keys of a 2D dimension's shared sub-column and sub-row shuffles (grid_sub_permute's rho). */
#define SUB_COLUMN_SALT 0x243f6a8885a308d3ull
#define SUB_ROW_SALT 0x13198a2e03707344ull

/* Multi-jittered point number j of n (Chiu, Shirley, Wang 1994, "Multi-jittered
 * sampling"): the unit square is a rows x cols grid with one point per cell, and each cell
 * is further split into rows sub-columns and cols sub-rows so that the n points also fall
 * one per stratum of width 1/n in x and in y. Point j sits in cell (c = j % cols,
 * r = j / cols); within column c the sub-columns of its rows are a permutation of [0, rows),
 * and within row r the sub-rows of its columns a permutation of [0, cols).
 * The columns' permutations must not be one shared permutation, as in Kensler 2013's
 * "correlated" variant: then the error of an integrand with a mixed term (f = x y) contains
 * sum_c c * perm(c), which does not average out and decays only as n^-0.75. Independent
 * permutations give n^-1, as a plain jittered grid (measured in tests/core/test_sampler.c,
 * about 1.5x lower error than it); so do the rotated shared ones of grid_sub_permute, which
 * this function draws. multi_jitter_packed and multi_jitter_tabled give the same values
 * from tables; this path serves the grids past SAMPLER_GRID_ENTRIES. */
static vec2 multi_jitter(PixelSampler *s, uint32_t j, uint64_t seed, uint64_t jitter_bits)
{
    uint32_t rows = s->grid_rows, cols = s->grid_cols;
    uint32_t c = j % cols, r = j / cols;
    need_grid_steps(s);
    uint32_t sub_x = grid_sub_permute(s, r, rows, s->grid_step_x, s->rows_magic, seed ^ SUB_COLUMN_SALT,
                                      column_perm_seed(seed, c));
    uint32_t sub_y = grid_sub_permute(s, c, cols, s->grid_step_y, s->cols_magic, seed ^ SUB_ROW_SALT,
                                      row_perm_seed(seed, r));
    /* x = (c + (sub_x + jx) / rows) / cols: 1D stratum c * rows + sub_x of n. */
    return v2(stratum_value(s, c * rows + sub_x, (uint32_t)jitter_bits),
              stratum_value(s, r * cols + sub_y, (uint32_t)(jitter_bits >> 32)));
}

/* ---- Sobol' ---------------------------------------------------------------------------- */

static inline uint32_t reverse_bits32(uint32_t v)
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
static inline uint32_t sobol_dim0_reversed(uint32_t i) { return i; }

/* Second dimension: its generator matrix is the Pascal matrix modulo 2, whose columns are
 * v_0 = 1/2 and v_{k+1} = v_k xor (v_k >> 1) (direction numbers m = 1, 3, 5, 15, 17, 51,
 * ...); reversed, v_0 = 1 and v_{k+1} = v_k xor (v_k << 1). Together with dim0, every
 * aligned block of 2^k indices is a (0, k, 2)-net in base 2 (Sobol' 1967). */
static inline uint32_t sobol_dim1_reversed(uint32_t i)
{
    /* The first eight columns, v = 1, 3, 5, 15, 17, 51, 85, 255, selected without branches:
     * the (padded) point index of a pixel's samples is random, and a data-dependent loop
     * mispredicts (up to 256 samples per pixel no loop runs at all). */
    uint32_t r = ((0u - (i & 1u)) & 1u) ^ ((0u - (i >> 1 & 1u)) & 3u) ^ ((0u - (i >> 2 & 1u)) & 5u) ^
                 ((0u - (i >> 3 & 1u)) & 15u) ^ ((0u - (i >> 4 & 1u)) & 17u) ^ ((0u - (i >> 5 & 1u)) & 51u) ^
                 ((0u - (i >> 6 & 1u)) & 85u) ^ ((0u - (i >> 7 & 1u)) & 255u);
    uint32_t v = 257u; /* v_8 */
    for (i >>= 8; i; i >>= 1, v ^= v << 1)
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
static inline uint32_t owen_scramble_reversed(uint32_t v, uint32_t seed)
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
static inline float fixed_to_float(uint32_t v) { return (float)(v >> 8) * 0x1p-24f; }

static inline float scrambled_to_float(uint32_t reversed, uint32_t seed)
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

/* 1 / n and ceil(2^64 / n) (cols_magic) for the usual small counts, folded by the compiler
 * (the same correctly rounded quotient as at run time): a part of at most 16 samples starts
 * every pixel at low counts, and the two divisions (a 64-bit one of tens of cycles) were on
 * each pixel's path. */
#define SMALL_PART_MAX SAMPLER_SHUFFLE_MAX
#define INV(n) (1.0 / (double)(n))
static const double INV_SMALL[SMALL_PART_MAX + 1] = {
    0.0,     INV(1),  INV(2),  INV(3),  INV(4),  INV(5),  INV(6),  INV(7),  INV(8),
    INV(9),  INV(10), INV(11), INV(12), INV(13), INV(14), INV(15), INV(16),
};
#undef INV
#define MAGIC(d) ((d) > 1 ? UINT64_MAX / (d) + 1u : 0u)
static const uint64_t MAGIC_SMALL[SMALL_PART_MAX + 1] = {
    0,         MAGIC(1),  MAGIC(2),  MAGIC(3),  MAGIC(4),  MAGIC(5),  MAGIC(6),  MAGIC(7),  MAGIC(8),
    MAGIC(9),  MAGIC(10), MAGIC(11), MAGIC(12), MAGIC(13), MAGIC(14), MAGIC(15), MAGIC(16),
};
#undef MAGIC

/* The strata count and everything derived from it, for the part a sample is in. */
static void set_part_size(PixelSampler *s, int spp)
{
    s->spp = spp;
    s->inv_spp = spp <= SMALL_PART_MAX ? INV_SMALL[spp] : 1.0 / (double)spp;
    s->inv_spp_2m32 = s->inv_spp * 0x1p-32;
    s->margin_bits = (uint64_t)spp << 9; /* n 2^-23 = n 2^9 2^-32 */
    grid_shape((uint32_t)spp, &s->grid_rows, &s->grid_cols);
    /* Past the tables: what sampler_permute and multi_jitter would derive from spp on
     * every request. */
    uint32_t n = (uint32_t)spp;
    s->perm_mask = n > 1 ? pow2_mask(n) : 0;
    s->perm_shift = n > 1 ? permute_shift(32 - __builtin_clz(s->perm_mask)) : 1;
    s->grid_packed = n > SAMPLER_SHUFFLE_MAX && s->grid_rows <= SAMPLER_SHUFFLE_MAX && s->grid_cols <= SAMPLER_SHUFFLE_MAX;
    s->grid_tabled = n > SAMPLER_SHUFFLE_MAX && !s->grid_packed && s->grid_rows + s->grid_cols <= SAMPLER_GRID_ENTRIES;
    /* Lemire, Kaser, Kurz 2019, "Faster remainder by direct computation": with
     * c = ceil(2^64 / d), floor(c j / 2^64) = floor(j / d) for every 32-bit j and
     * 2 <= d < 2^32 (64 fraction bits >= 32 + log2 d). */
    s->cols_magic = s->grid_cols <= SMALL_PART_MAX ? MAGIC_SMALL[s->grid_cols]
                    : UINT64_MAX / s->grid_cols + 1u; /* cols > 16 > 1 */
    s->grid_steps_ready = false; /* need_grid_steps */
}

/* Marks a set continued from its first part (a key no block number reaches). */
#define CONTINUATION_KEY (1ull << 32)

void sampler_continue_pixel(PixelSampler *s, SamplerKind kind, uint64_t seed, int px, int py, int pass,
                            int spp_before, int spp)
{
    /* Everything but the caches, whose validity bits (perm_valid, tables_ready) are cleared
     * with the rest: a few stores per pixel instead of touching kilobytes. Field by field:
     * a memset of the header compiles to a `rep stos`, whose start-up cost per pixel was
     * measurable. */
    s->perm_valid[0] = s->perm_valid[1] = 0;
    s->tables_ready[0] = s->tables_ready[1] = 0;
    s->seeds_ready[0] = s->seeds_ready[1] = 0;
    s->sample_key = 0;
    s->kind = kind;
    s->seed = seed;
    s->set_spp = spp >= 1 ? spp : 1;
    s->prefix_spp = spp_before >= 1 && spp_before < s->set_spp ? spp_before : 0;
    s->part_key = UINT64_MAX; /* no part yet: sampler_start_sample sets it up */
    s->pixel_seed = hash_pixel_seed(seed, px, py, pass);
    sampler_start_sample(s, 0);
}

void sampler_start_pixel(PixelSampler *s, SamplerKind kind, uint64_t seed, int px, int py, int pass, int spp)
{
    sampler_continue_pixel(s, kind, seed, px, py, pass, 0, spp);
}

/* The key of the current sample's random numbers. Jitter (and every dimension past the
 * padded ones) is counter-based: request `dim` of a sample takes output dim + 1 of a
 * SplitMix64 stream started at this key (Steele, Lea, Flood 2014, "Fast splittable
 * pseudorandom number generators"), one hash per request, in any order, and nothing to
 * seed per sample but the key itself. */
static inline uint64_t sample_key_of(const PixelSampler *s, int sample_index)
{
    return hash_u64(s->pixel_seed ^ ((uint64_t)(uint32_t)sample_index * 0xd6e8feb86659fd93ull));
}

static void set_sample_key(PixelSampler *s)
{
    s->sample_key = sample_key_of(s, s->sample_index);
    s->key_ready = true;
}

/* 64 random bits of request `dim` of the current sample (hash_u64 adds the stream's
 * increment itself). */
static inline uint64_t key_bits(uint64_t sample_key, int dim)
{
    return hash_u64(sample_key + (uint64_t)(uint32_t)dim * 0x9e3779b97f4a7c15ull);
}

static inline uint64_t request_bits(PixelSampler *s, int dim)
{
    if (!s->key_ready) set_sample_key(s);
    return key_bits(s->sample_key, dim);
}

/* Top 24 bits of a 32-bit word as a float in [0, 1). */
static inline float float_of(uint32_t bits) { return (float)(bits >> 8) * 0x1p-24f; }

/* Switches the sampler to the part of the set with key `key` (sampler_start_sample):
 * its size, the keys of its seeds, and the tables, which described another part. */
static __attribute__((noinline)) void enter_part(PixelSampler *s, uint64_t key)
{
    bool continuation = (key & CONTINUATION_KEY) != 0;
    int prefix = s->block == 0 ? s->prefix_spp : 0;
    set_part_size(s, continuation ? s->set_spp - prefix : prefix > 0 ? prefix : s->set_spp);
    s->part_key = key;
    /* The continuation gets padding permutations of its own. A stratified continuation is a
     * new stratified set, so its strata and jitter are keyed anew too; a Sobol' one keeps
     * the scrambles of the first part, so that both take their points from one scrambled
     * sequence, the continuation from index prefix on. */
    s->perm_key = key;
    s->value_key = (continuation && s->kind == SAMPLER_SOBOL) ? (key & ~CONTINUATION_KEY) : key;
    s->point_offset = continuation && s->kind == SAMPLER_SOBOL ? (uint32_t)prefix : 0u;
    s->tables_ready[0] = s->tables_ready[1] = 0;
    s->seeds_ready[0] = s->seeds_ready[1] = 0;
}

/* The key of the part sample i (>= 0) is in, its block and its index within the part. */
static inline uint64_t part_of_sample(const PixelSampler *s, uint32_t i, uint32_t *block, uint32_t *index_in_block)
{
    uint32_t n = (uint32_t)s->set_spp;
    if (i < n) { /* the usual case: no division */
        *block = 0, *index_in_block = i;
    } else {
        *block = i / n, *index_in_block = i % n;
    }
    uint64_t key = *block;
    if (*block == 0 && s->prefix_spp > 0 && i >= (uint32_t)s->prefix_spp) {
        key |= CONTINUATION_KEY;
        *index_in_block = i - (uint32_t)s->prefix_spp;
    }
    return key;
}

void sampler_start_sample(PixelSampler *s, int sample_index)
{
    s->sample_index = sample_index >= 0 ? sample_index : 0;
    uint64_t key = part_of_sample(s, (uint32_t)s->sample_index, &s->block, &s->index_in_block);
    if (key != s->part_key) enter_part(s, key);
    s->dim = 0;
    /* The Sobol' sampler needs the key only past the padded dimensions: set it on first
     * use (request_bits) rather than for every sample. */
    s->key_ready = false;
    if (s->kind == SAMPLER_STRATIFIED) set_sample_key(s);
}

/* ---- per-pixel dimension tables (spp <= SAMPLER_SHUFFLE_MAX) ------------------------ */

/* count independent shuffles p_k of [0, size) side by side (count size <= 16), block k in
 * nibbles [k size, (k + 1) size) holding p_k scale + k step (each below 16: nibbles never
 * carry into each other). */
static inline uint64_t batch_shuffles_packed(BatchDraw *d, uint32_t count, uint32_t size, uint32_t scale, uint32_t step)
{
    if (size == 16) return batch_shuffle_nibbles(d, 16); /* count is 1, scale 1 */
    uint64_t keep = (1ull << (4u * size)) - 1u, ones = keep / 15u, packed = 0;
    for (uint32_t k = 0; k < count; ++k)
        packed |= ((batch_shuffle_nibbles(d, size) & keep) * scale + k * step * ones) << (4u * size * k);
    return packed;
}

/* Rows of the tables' grid whose side cols is a lattice side (5, 7, 11 or 13 at up to 16
 * spp: the counts 5, 7, 10, 11, 13, 14, 15; see LATTICE_NIBBLES) do not shuffle their
 * sub-rows: row r's permutation is the rank-1 lattice c -> step c mod cols rotated by a
 * uniform offset per row, the rule grid_sub_permute applies past 16 spp. A 1 x p grid is
 * then a randomly shifted Fibonacci-like lattice of p x p cells with one jittered point per
 * cell instead of a random Latin hypercube, whose points can clump. The rotation keeps each
 * sample's sub-row uniform and independent of the rest (the set stays unbiased and
 * stratified in y), and the rows' terms of a mixed integrand uncorrelated. Measured against
 * the shuffles (RMS error, smooth integrand / half-plane edge): 0.72x / 0.74x at 13 spp,
 * 0.79x / 0.78x at 11, 0.89x / 0.87x at 7, 0.92x / 0.90x at 5, 0.93x at 10, 0.90x / 0.88x
 * at 14, 0.94x / 0.95x at 15 (docs/sampling.md, tests/core/small_count_sets.c). Sides of 2,
 * 3 and 4 keep their shuffles: 4, 6, 8, 9, 12 and 16 spp keep their values.
 * This is the y_of_cell table (see mj_tables) of such a grid (cols <= 13 up to 16 spp, so a
 * row fits 52 bits): block r holds row r's lattice permutation rotated by a uniform o_r,
 * plus r cols. Rotating the positions
 * (nibble c takes the lattice's element (c + o) mod cols, i.e. step c + step o) is the same
 * as rotating the values by the uniform step o, and is one shift pair on the packed word. */
static inline uint64_t batch_lattice_rows_packed(BatchDraw *d, uint32_t rows, uint32_t cols)
{
    uint32_t width = 4u * cols;
    uint64_t lattice = LATTICE_NIBBLES[cols], keep = (1ull << width) - 1u, ones = keep / 15u, packed = 0;
    for (uint32_t r = 0; r < rows; ++r) {
        uint32_t shift = 4u * batch_below(d, cols);
        uint64_t rotated = ((lattice >> shift) | (lattice << (width - shift))) & keep;
        packed |= (rotated + r * cols * ones) << (width * r);
    }
    return packed;
}

/* The y_of_cell table: independent shuffles per row, or the rotated lattice above. */
static inline uint64_t batch_rows_packed(BatchDraw *d, uint32_t rows, uint32_t cols)
{
    if (LATTICE_NIBBLES[cols]) return batch_lattice_rows_packed(d, rows, cols);
    return batch_shuffles_packed(d, rows, cols, 1, cols);
}

/* Two of SMALL_PERMS side by side: entry d1 24 + d2 holds SMALL_PERMS[d1] in its low and
 * SMALL_PERMS[d2] in its high 16 bits (batch_grid_4x4's pairs of base-24 digits). */
static uint32_t SMALL_PERM_PAIRS[24 * 24];

__attribute__((constructor)) static void build_small_perm_pairs(void)
{
    for (uint32_t d = 0; d < 24 * 24; ++d) SMALL_PERM_PAIRS[d] = SMALL_PERMS[d / 24u] | (uint32_t)SMALL_PERMS[d % 24u] << 16;
}

/* The grid permutations of a 4 x 4 grid (16 spp): `cell`'s four shuffles of [0, 4) (one per
 * column) then `y_of_cell`'s four (one per row), the values batch_shuffles_packed and
 * batch_rows_packed give. Their eight draws of bound 24 are the base-24 digits of one draw
 * below 24^8, the first draw the most significant (BatchDraw's induction, with the same low
 * word and product after it), so one product gives them all and each digit is a division by
 * constants off the others' path, where drawing them one by one is a chain of eight
 * dependent 128-bit products and table loads. */
static inline void batch_grid_4x4(BatchDraw *d, uint64_t *cell, uint64_t *y_of_cell)
{
    const uint64_t draws_bound = 110075314176ull; /* 24^8 */
    unsigned __int128 m = (unsigned __int128)d->bits * draws_bound;
    d->bits = (uint64_t)m;
    d->product *= draws_bound;
    uint64_t code = (uint64_t)(m >> 64);
    uint32_t hi = (uint32_t)(code / 331776u), lo = (uint32_t)(code % 331776u); /* 24^4 */
    /* the pairs of digits below 24^2, each two permutations side by side (SMALL_PERM_PAIRS);
     * a permutation's nibbles times 4 (cell's sub-rows, values below 4) and the blocks' offsets
     * k 0x1111 (k cols, k rows 0x1111 for y) stay below 16: no nibble carries */
    uint64_t c = SMALL_PERM_PAIRS[hi / 576u] | (uint64_t)SMALL_PERM_PAIRS[hi % 576u] << 32;
    uint64_t y = SMALL_PERM_PAIRS[lo / 576u] | (uint64_t)SMALL_PERM_PAIRS[lo % 576u] << 32;
    *cell = c * 4u + 0x3333222211110000ull, *y_of_cell = y + 0xcccc888844440000ull;
}

/* The same for the other grids up to 16 spp whose sides are all shuffles of at most 4
 * elements: 2 (1 x 2), 3 (1 x 3), 4 (2 x 2), 6 (2 x 3), 8 (2 x 4), 9 (3 x 3) and 12 (3 x 4).
 * The draws are, in order: pi's (bound n!) when pi shares the random number (n <= 10,
 * pi_bound = n!; else pi_bound = 1 and pi is not made), cols draws of bound rows! (`cell`'s
 * shuffles, batch_shuffles_packed(d, cols, rows, cols, 1)) and rows draws of bound cols!
 * (`y_of_cell`'s, batch_rows_packed: no side here is a lattice side). A draw of bound 1 (a
 * side of one) leaves the low word and the product as they were, so it can be counted in.
 * As for 4 x 4 they are the mixed-radix digits of one draw J below their product, the first
 * the most significant (docs/algorithms.md, "A Fisher-Yates shuffle from one draw"); each
 * digit is floor(J / weight) mod bound, the weight the product of the later bounds, and
 * rows and cols are constants at every call (mj_tables' switch), so each is a division by
 * constants off the others' path instead of the next link of a chain of 128-bit products. */
static inline __attribute__((always_inline)) uint64_t
batch_grid_small(BatchDraw *d, uint64_t pi_bound, uint32_t rows, uint32_t cols, uint64_t *cell,
                 uint64_t *y_of_cell)
{
    static const uint8_t factorial[5] = {1, 1, 2, 6, 24};
    uint64_t a = factorial[rows], b = factorial[cols], grid_bound = 1;
    for (uint32_t k = 0; k < cols; ++k) grid_bound *= a;
    for (uint32_t r = 0; r < rows; ++r) grid_bound *= b;
    uint64_t draws_bound = pi_bound * grid_bound;
    unsigned __int128 m = (unsigned __int128)d->bits * draws_bound;
    d->bits = (uint64_t)m;
    d->product *= draws_bound;
    /* the grid's digits below grid_bound < 2^32 (at most 6^4 24^3 here): 32-bit divisions */
    uint64_t code = (uint64_t)(m >> 64), pi_code = code / grid_bound, c = 0, y = 0;
    uint32_t grid_code = (uint32_t)(code - pi_code * grid_bound), weight = (uint32_t)grid_bound;
    uint64_t keep_c = (1ull << (4u * rows)) - 1u, ones_c = keep_c / 15u;
    uint64_t keep_y = (1ull << (4u * cols)) - 1u, ones_y = keep_y / 15u;
    for (uint32_t k = 0; k < cols; ++k) {
        weight /= (uint32_t)a;
        uint64_t perm = SMALL_PERMS[grid_code / weight % (uint32_t)a] & keep_c;
        c |= (perm * cols + k * ones_c) << (4u * rows * k);
    }
    for (uint32_t r = 0; r < rows; ++r) {
        weight /= (uint32_t)b;
        uint64_t perm = SMALL_PERMS[grid_code / weight % (uint32_t)b] & keep_y;
        y |= (perm + r * cols * ones_y) << (4u * cols * r);
    }
    *cell = c, *y_of_cell = y;
    return pi_code; /* pi's draw (0 when pi_bound = 1) */
}

/* pi, a shuffle of [0, n) (n <= 10), from its draw `code` below n!, as batch_shuffle_nibbles
 * gives it. Only with the byte shuffle (see batch_grid_tables). */
static inline uint64_t shuffle_of_code(uint64_t code, uint32_t n)
{
    if (n <= 4) return 0xfedcba9876540000ull | SMALL_PERMS[code];
#ifdef FISHER_YATES_BYTE_SHUFFLE
    return fisher_yates_ssse3(code, n);
#else
    (void)n;
    return 0; /* unreachable: batch_grid_tables declines */
#endif
}

/* mj_tables' draws for the counts batch_grid_small serves (n <= 10: pi and the grid from
 * bits_pi; 12: the grid alone, from bits_grid). Returns false for the other counts (and
 * without the byte shuffle, for n > 4), which take the draws one by one. */
static bool batch_grid_tables(uint32_t n, uint64_t bits_pi, uint64_t bits_grid, uint64_t *pi, uint64_t *cell,
                              uint64_t *y_of_cell)
{
#ifdef FISHER_YATES_BYTE_SHUFFLE
    bool byte_shuffle = __builtin_cpu_supports("ssse3");
#else
    bool byte_shuffle = false;
#endif
    if (n > 4 && !byte_shuffle && n != 12) return false;
    uint64_t bits = n == 12 ? bits_grid : bits_pi;
    for (;; bits = hash_u64(bits)) {
        BatchDraw d = batch_start(bits);
        uint64_t code;
        switch (n) {
        case 2: code = batch_grid_small(&d, 2, 1, 2, cell, y_of_cell); break;
        case 3: code = batch_grid_small(&d, 6, 1, 3, cell, y_of_cell); break;
        case 4: code = batch_grid_small(&d, 24, 2, 2, cell, y_of_cell); break;
        case 6: code = batch_grid_small(&d, 720, 2, 3, cell, y_of_cell); break;
        case 8: code = batch_grid_small(&d, 40320, 2, 4, cell, y_of_cell); break;
        case 9: code = batch_grid_small(&d, 362880, 3, 3, cell, y_of_cell); break;
        case 12: code = batch_grid_small(&d, 1, 3, 4, cell, y_of_cell); break;
        default: return false;
        }
        if (batch_accepted(&d)) {
            if (n != 12) *pi = shuffle_of_code(code, n);
            return true;
        }
    }
}

/* The two strata tables of a multi-jittered 2D dimension (multi_jitter's construction for
 * the points, padded by a uniform permutation of the sample indices), built directly per
 * sample index without materialising the points. Sample i's x stratum is pi(i) for a
 * uniform permutation pi; that puts it in grid column c = pi(i) / rows with sub-column
 * a = pi(i) % rows. Within column c the sample of sub-column a lies in row sigma_c(a), and
 * within row r the point of column c has sub-row tau_r(c), for independent uniform
 * permutations sigma_c of [0, rows) and tau_r of [0, cols); its y stratum is
 * r cols + tau_r(c). Every valid padded multi-jitter assignment (x strata a permutation,
 * one sample per grid cell, distinct sub-columns in a column and sub-rows in a row) comes
 * from exactly one (pi, sigma, tau), and there are n! (rows!)^cols (cols!)^rows of both,
 * so this is the same uniform distribution as padding the points of multi_jitter (which
 * draws sigma_c inverted, and scatters and re-gathers the points: slower). When cols is a
 * lattice side each tau_r is a rotated lattice instead (batch_lattice_rows_packed):
 * the padded assignments are then uniform over those with lattice rows.
 * Packed as lookups: nibble x of `cell` is the grid cell sigma_c(a) cols + c of x stratum
 * x = c rows + a, and nibble z of `y_of_cell` the y stratum r cols + tau_r(c) of cell
 * z = r cols + c. All draws come from one random number where their product (at most
 * 10! 2^5 (5!)^2 < 2^41 for n <= 10) leaves Lemire's rejection negligible; above that pi
 * uses bits_pi and the grid permutations bits_grid (at most (4!)^8 < 2^37). */
static void mj_tables(uint32_t n, uint32_t rows, uint32_t cols, uint64_t bits_pi, uint64_t bits_grid, uint64_t *x_out,
                      uint64_t *y_out)
{
    uint64_t pi, cell, y_of_cell;
    if (batch_grid_tables(n, bits_pi, bits_grid, &pi, &cell, &y_of_cell)) {
        if (n == 12) pi = shuffle_bits_nibbles(n, bits_pi);
    } else if (n <= 10) {
        for (;; bits_pi = hash_u64(bits_pi)) {
            BatchDraw d = batch_start(bits_pi);
            pi = batch_shuffle_nibbles(&d, n);
            cell = batch_shuffles_packed(&d, cols, rows, cols, 1);
            y_of_cell = batch_rows_packed(&d, rows, cols);
            if (batch_accepted(&d)) break;
        }
    } else {
        pi = shuffle_bits_nibbles(n, bits_pi);
        for (;; bits_grid = hash_u64(bits_grid)) {
            BatchDraw d = batch_start(bits_grid);
            if (rows == 4 && cols == 4) {
                batch_grid_4x4(&d, &cell, &y_of_cell);
            } else {
                cell = batch_shuffles_packed(&d, cols, rows, cols, 1);
                y_of_cell = batch_rows_packed(&d, rows, cols);
            }
            if (batch_accepted(&d)) break;
        }
    }
    *x_out = pi, *y_out = compose_nibbles(y_of_cell, cell, pi, n);
}

/* Builds the table of scalar dimension dim for requests of `kind` (1 or 2) in the current
 * block of sample indices. Out of line: inlined, its register pressure made every request
 * (mostly table hits) save and restore six registers. */
static __attribute__((noinline)) const SamplerDimTable *build_dim_table(PixelSampler *s, int dim, int kind)
{
    uint32_t n = (uint32_t)s->spp;
    SamplerDimTable *t = &s->dim_table[dim];
    if (s->kind == SAMPLER_STRATIFIED && kind == 2) {
        /* the second random number only when the draws do not fit in one (n > 10) */
        uint64_t bits_grid = n > 10 ? dim_seed(s, dim, s->value_key, 4) : 0;
        mj_tables(n, s->grid_rows, s->grid_cols, dim_seed(s, dim, s->value_key, 3), bits_grid, &t->x, &t->y);
    } else {
        /* a 1D stratified value's stratum is its padded index; Sobol' keeps the index */
        t->x = shuffle_bits_nibbles(n, dim_seed(s, dim, s->perm_key, kind == 1 ? 1 : 3));
        if (s->kind == SAMPLER_SOBOL) t->seed = dim_seed(s, dim, s->value_key, kind == 1 ? 2 : 4);
    }
    uint64_t bit = 1ull << dim;
    s->tables_ready[kind - 1] |= bit;
    s->tables_ready[2 - kind] &= ~bit; /* the entry now holds the other kind's table */
    return t;
}

/* The table of scalar dimension dim for requests of `kind` (1 or 2) in the current block,
 * built on first use. NULL when spp is too large for tables (the caller computes directly). */
static inline const SamplerDimTable *dim_table(PixelSampler *s, int dim, int kind)
{
    if (s->spp > SAMPLER_SHUFFLE_MAX) return NULL;
    if (s->tables_ready[kind - 1] & (1ull << dim)) return &s->dim_table[dim];
    return build_dim_table(s, dim, kind);
}

/* uniform_below(bits, m) for m <= 16 in 32-bit pieces (a 64 x 64-bit high product does not
 * vectorise): bits m = (hi 2^32 + lo) m, whose high word is (hi m + (lo m >> 32)) >> 32 and
 * whose low word tells Lemire's test. Sets *maybe_rejected when that word is below m (the
 * only case the test can reject; the caller then asks uniform_below). */
static inline uint32_t uniform_below_small(uint64_t bits, uint32_t m, uint32_t *maybe_rejected)
{
    uint64_t lo = (uint64_t)(uint32_t)bits * m, mid = (bits >> 32) * m + (lo >> 32);
    uint64_t low_word = mid << 32 | (uint32_t)lo;
    *maybe_rejected |= (uint32_t)(low_word < m);
    return (uint32_t)(mid >> 32);
}

/* The rotations of a packed grid's sub-columns and sub-rows (grid_sub_permute's o: per
 * column a uniform draw below rows, per row one below cols; 0 on a single row or column),
 * both loops vectorised (see RUN_KERNEL). */
static RUN_KERNEL void grid_rotations_vec(uint64_t seed, uint32_t rows, uint32_t cols, uint32_t *col_rot,
                                          uint32_t *row_rot, uint32_t *maybe_rejected)
{
    uint32_t rejected = 0;
    for (uint32_t c = 0; c < cols; ++c) col_rot[c] = uniform_below_small(column_perm_seed(seed, c), rows, &rejected);
    for (uint32_t r = 0; r < rows; ++r) row_rot[r] = uniform_below_small(row_perm_seed(seed, r), cols, &rejected);
    *maybe_rejected = rejected;
}

static void grid_rotations(uint64_t seed, uint32_t rows, uint32_t cols, uint32_t *col_rot, uint32_t *row_rot)
{
    uint32_t maybe_rejected;
    grid_rotations_vec(seed, rows, cols, col_rot, row_rot, &maybe_rejected);
    if (maybe_rejected) { /* about 16 in 2^64: the exact draws */
        for (uint32_t c = 0; c < cols; ++c) col_rot[c] = uniform_below(column_perm_seed(seed, c), rows);
        for (uint32_t r = 0; r < rows; ++r) row_rot[r] = uniform_below(row_perm_seed(seed, r), cols);
    }
    /* grid_sub_permute gives 0 on a single row (or column) */
    if (rows == 1) memset(col_rot, 0, cols * sizeof *col_rot);
    if (cols == 1) memset(row_rot, 0, rows * sizeof *row_rot);
}

/* multi_jitter's sub-column and sub-row permutations of one 2D dimension (seed t->seed),
 * drawn as grid_sub_permute draws them, packed 4 bits per element (grid_packed: rows and
 * cols <= 16, so every element fits). They are the same for every sample of the pixel;
 * per sample they cost two hashes and two cache look-ups. All of them are drawn here, even
 * in a render round that takes only 4 of the pixel's samples (and so touches only a few
 * columns and rows): drawing each rotation on first use instead was measured slower
 * (tools/bench-sampler: a data-dependent branch per request that mispredicts, against
 * rows + cols hashes in a loop without one). */
static void build_grid_tables(PixelSampler *s, SamplerDimTable *t)
{
    uint32_t rows = s->grid_rows, cols = s->grid_cols;
    uint64_t seed = t->seed;
    /* grid_sub_permute gives 0 on a single row (or column): shuffle and rotations 0 */
    t->sub_x = rows > 1 ? small_side_rho(rows, seed ^ SUB_COLUMN_SALT) : 0;
    t->sub_y = cols > 1 ? small_side_rho(cols, seed ^ SUB_ROW_SALT) : 0;
    uint32_t col_rot[SAMPLER_SHUFFLE_MAX], row_rot[SAMPLER_SHUFFLE_MAX];
    grid_rotations(seed, rows, cols, col_rot, row_rot);
    t->col_rot = t->row_rot = 0;
    for (uint32_t c = 0; c < cols; ++c) t->col_rot |= (uint64_t)col_rot[c] << (4u * c);
    for (uint32_t r = 0; r < rows; ++r) t->row_rot |= (uint64_t)row_rot[r] << (4u * r);
}

/* multi_jitter through the tables of build_grid_tables: the same values. */
static inline vec2 multi_jitter_packed(const PixelSampler *s, const SamplerDimTable *t, uint32_t j, uint64_t jitter_bits)
{
    uint32_t rows = s->grid_rows, cols = s->grid_cols;
    uint32_t r = (uint32_t)(((unsigned __int128)s->cols_magic * j) >> 64), c = j - r * cols;
    uint32_t sub_x = nibble(t->sub_x, r) + nibble(t->col_rot, c);
    uint32_t sub_y = nibble(t->sub_y, c) + nibble(t->row_rot, r);
    sub_x = sub_x >= rows ? sub_x - rows : sub_x; /* (rho(i) + o) mod m, as grid_sub_permute */
    sub_y = sub_y >= cols ? sub_y - cols : sub_y;
    return v2(stratum_value(s, c * rows + sub_x, (uint32_t)jitter_bits),
              stratum_value(s, r * cols + sub_y, (uint32_t)(jitter_bits >> 32)));
}

/* ---- multi-jitter tables of grids with a side above 16 (grid_tabled) ---------------- */

/* The slot of 2D dimension dim (direct-mapped: a wave's stage draws a few 2D dimensions of
 * a pixel one after the other, so a clash costs a refill, never a wrong value). */
static inline SamplerGridTable *grid_slot(PixelSampler *s, int dim)
{
    return &s->grid[(unsigned)(dim >> 1) & (SAMPLER_GRID_SLOTS - 1)];
}

/* Gives slot g to dimension dim with multi-jitter seed `seed`, every entry still to fill:
 * a few words to clear, whatever the grid (a 1 x 1009 grid clears 16 words). */
static void grid_claim(PixelSampler *s, SamplerGridTable *g, int dim, uint64_t seed)
{
    uint32_t rows = s->grid_rows, cols = s->grid_cols;
    g->dim = dim;
    g->seed = seed;
    need_grid_steps(s);
    /* the shuffles permute_cached would draw for grid_sub_permute (shuffle_small's bits) */
    g->rho_x_small = rows > 1 && rows <= SAMPLER_SHUFFLE_MAX ? small_side_rho(rows, seed ^ SUB_COLUMN_SALT) : 0;
    g->rho_y_small = cols > 1 && cols <= SAMPLER_SHUFFLE_MAX ? small_side_rho(cols, seed ^ SUB_ROW_SALT) : 0;
    memset(g->filled, 0, ((rows + cols + 63u) / 64u) * sizeof g->filled[0]);
}

/* Element i of grid_sub_permute's shared permutation rho of [0, m). */
static inline uint32_t grid_rho(uint32_t i, uint32_t m, uint64_t small, uint32_t step, uint64_t magic)
{
    if (m <= 1) return 0;
    return m <= SAMPLER_SHUFFLE_MAX ? nibble(small, i) : lattice_rho(i, m, step, magic);
}

/* Computes entry e of g (see SamplerGridTable): the values grid_sub_permute gives. Out of
 * line: the common case is a filled entry. */
static __attribute__((noinline)) void grid_fill(const PixelSampler *s, SamplerGridTable *g, uint32_t e)
{
    uint32_t rows = s->grid_rows, cols = s->grid_cols, rho, rot;
    if (e < rows) { /* row e: rho_x(e), and the rotation of its sub-rows */
        rho = grid_rho(e, rows, g->rho_x_small, s->grid_step_x, s->rows_magic);
        rot = cols > 1 ? uniform_below(row_perm_seed(g->seed, e), cols) : 0;
    } else { /* column c: rho_y(c), and the rotation of its sub-columns */
        uint32_t c = e - rows;
        rho = grid_rho(c, cols, g->rho_y_small, s->grid_step_y, s->cols_magic);
        rot = rows > 1 ? uniform_below(column_perm_seed(g->seed, c), rows) : 0;
    }
    g->entry[e] = rho | rot << 16;
    g->filled[e >> 6] |= 1ull << (e & 63);
}

/* The entries of one side of m > 16 elements of a tabled grid: lattice_rho(i) = step i mod m
 * and the rotations rot[i]. step i < m^2 <= 2^20 and m < 2^10, so a 32-bit reciprocal gives
 * the quotient exactly (32 fraction bits >= 20 + 10; Lemire, Kaser, Kurz 2019). */
static RUN_KERNEL void grid_lattice_entries(uint32_t m, uint32_t step, const uint32_t *restrict rot,
                                            uint32_t *restrict entry)
{
    uint32_t magic = UINT32_MAX / m + 1u;
    for (uint32_t i = 0; i < m; ++i) {
        uint32_t x = step * i, q = (uint32_t)(((uint64_t)x * magic) >> 32);
        entry[i] = (x - q * m) | rot[i] << 16;
    }
}

/* Every entry of g at once (the values grid_fill gives one by one): the rotations by
 * grid_rotations, whose hashes vectorise, and the shared rho's lattice in another
 * vectorised loop (grid_lattice_entries). For a run that
 * reads most of the entries: entry by entry, a hash and a division each cost a sixth of a
 * render at 83 spp (a 1 x 83 grid; docs/benchmarks.md, "CPU per sample at counts that are
 * not whole rounds"). */
static void grid_fill_all(const PixelSampler *s, SamplerGridTable *g)
{
    uint32_t rows = s->grid_rows, cols = s->grid_cols, entries = rows + cols;
    uint32_t col_rot[SAMPLER_GRID_ENTRIES], row_rot[SAMPLER_GRID_ENTRIES];
    grid_rotations(g->seed, rows, cols, col_rot, row_rot);
    for (int side = 0; side < 2; ++side) {
        uint32_t m = side == 0 ? rows : cols, step = side == 0 ? s->grid_step_x : s->grid_step_y;
        uint64_t small = side == 0 ? g->rho_x_small : g->rho_y_small;
        const uint32_t *rot = side == 0 ? row_rot : col_rot;
        uint32_t *entry = g->entry + (side == 0 ? 0 : rows);
        if (m <= 1) entry[0] = 0u | rot[0] << 16;
        else if (m <= SAMPLER_SHUFFLE_MAX)
            for (uint32_t i = 0; i < m; ++i) entry[i] = nibble(small, i) | rot[i] << 16;
        else
            grid_lattice_entries(m, step, rot, entry);
    }
    for (uint32_t w = 0; w < (entries + 63u) / 64u; ++w) g->filled[w] = UINT64_MAX;
}

static inline uint32_t grid_entry(const PixelSampler *s, SamplerGridTable *g, uint32_t e)
{
    if (!(g->filled[e >> 6] >> (e & 63) & 1u)) grid_fill(s, g, e);
    return g->entry[e];
}

/* The table of 2D dimension dim (whose seeds t holds), claimed again if another dimension
 * took the slot since. */
static inline SamplerGridTable *grid_table(PixelSampler *s, const SamplerDimTable *t, int dim)
{
    SamplerGridTable *g = grid_slot(s, dim);
    if (g->dim != dim || g->seed != t->seed) grid_claim(s, g, dim, t->seed);
    return g;
}

/* multi_jitter through the lazily filled tables of grid_table: the same values. */
static inline vec2 multi_jitter_tabled(const PixelSampler *s, SamplerGridTable *g, uint32_t j, uint64_t jitter_bits)
{
    uint32_t rows = s->grid_rows, cols = s->grid_cols;
    uint32_t r = (uint32_t)(((unsigned __int128)s->cols_magic * j) >> 64), c = j - r * cols;
    uint32_t row = grid_entry(s, g, r), col = grid_entry(s, g, rows + c);
    uint32_t sub_x = (row & 0xffffu) + (col >> 16), sub_y = (col & 0xffffu) + (row >> 16);
    sub_x = sub_x >= rows ? sub_x - rows : sub_x;
    sub_y = sub_y >= cols ? sub_y - cols : sub_y;
    return v2(stratum_value(s, c * rows + sub_x, (uint32_t)jitter_bits),
              stratum_value(s, r * cols + sub_y, (uint32_t)(jitter_bits >> 32)));
}

/* Past the tables (spp above SAMPLER_SHUFFLE_MAX): the seeds of scalar dimension dim for
 * requests of `kind` (1 or 2) in the current block, hashed on first use. x keys the padding
 * permutation, the per-dimension shuffle of sample indices that decorrelates dimensions;
 * seed keys the values (Sobol' scramble, stratified 2D multi-jitter). Two hashes per
 * request otherwise, on the critical path of every sample. */
static __attribute__((noinline)) SamplerDimTable *build_dim_seeds(PixelSampler *s, int dim, int kind)
{
    SamplerDimTable *t = &s->dim_table[dim];
    t->x = dim_seed(s, dim, s->perm_key, kind == 1 ? 1 : 3);
    t->seed = dim_seed(s, dim, s->value_key, kind == 1 ? 2 : 4);
    if (kind == 2 && s->kind == SAMPLER_STRATIFIED) {
        if (s->grid_packed) build_grid_tables(s, t);
        else if (s->grid_tabled) grid_claim(s, grid_slot(s, dim), dim, t->seed);
    }
    uint64_t bit = 1ull << dim;
    s->seeds_ready[kind - 1] |= bit;
    s->seeds_ready[2 - kind] &= ~bit; /* the entry now holds the other kind's seeds */
    return t;
}

static inline SamplerDimTable *dim_seeds(PixelSampler *s, int dim, int kind)
{
    if (s->seeds_ready[kind - 1] & (1ull << dim)) return &s->dim_table[dim];
    return build_dim_seeds(s, dim, kind);
}

/* Position of sample index i (in the current part) inside the stratified set of spp points
 * (its padded index), past the tables. */
static inline uint32_t padded_index(const PixelSampler *s, const SamplerDimTable *seeds, uint32_t i)
{
    uint32_t n = (uint32_t)s->spp;
    if (n <= SAMPLER_SHUFFLE_MAX) return sampler_permute(i, n, seeds->x);
    /* sampler_permute's cycle walk with the part's mask and shift (i < n) */
    uint32_t x = i;
    do {
        x = permute_pow2_shift(x, s->perm_mask, s->perm_shift, seeds->x);
    } while (x >= n);
    return x;
}

/* True when dimension dim's table for requests of `kind` is built (spp <= 16 implied). */
static inline bool table_ready(const PixelSampler *s, int dim, int kind)
{
    return dim < SAMPLER_PADDED_DIMS - 1 && (s->tables_ready[kind - 1] >> dim & 1u);
}

/* What every sample of the part shares for a padded dimension of `kind` (1 or 2): its
 * table (spp <= SAMPLER_SHUFFLE_MAX) or its seeds, built on first use. */
static inline const SamplerDimTable *padded_dim(PixelSampler *s, int dim, int kind)
{
    const SamplerDimTable *t = dim_table(s, dim, kind);
    return t ? t : dim_seeds(s, dim, kind);
}

/* The Sobol' values of padded point j of the part (its dimension's seeds t). 1D: scrambled
 * van der Corput, one point per stratum of width 1/n when n is a power of 2. */
static inline float sobol_value_1d(const PixelSampler *s, const SamplerDimTable *t, uint32_t j)
{
    return scrambled_to_float(sobol_dim0_reversed(j + s->point_offset), (uint32_t)t->seed);
}

static inline vec2 sobol_value_2d(const PixelSampler *s, const SamplerDimTable *t, uint32_t j)
{
    j += s->point_offset;
    return v2(scrambled_to_float(sobol_dim0_reversed(j), (uint32_t)t->seed),
              scrambled_to_float(sobol_dim1_reversed(j), (uint32_t)(t->seed >> 32)));
}

/* A padded 1D value of the sample with index i in the current part, given its dimension's
 * padded_dim and (stratified) the request's jitter bits. */
static inline float value_1d_padded(PixelSampler *s, const SamplerDimTable *t, uint32_t i, uint64_t bits)
{
    uint32_t j = s->spp <= SAMPLER_SHUFFLE_MAX ? nibble(t->x, i) : padded_index(s, t, i);
    if (s->kind == SAMPLER_STRATIFIED) return stratum_value(s, j, (uint32_t)bits);
    return sobol_value_1d(s, t, j);
}

/* The same for a padded 2D value of dimension dim. */
static inline vec2 value_2d_padded(PixelSampler *s, const SamplerDimTable *t, int dim, uint32_t i, uint64_t bits)
{
    uint32_t j;
    if (s->spp <= SAMPLER_SHUFFLE_MAX) {
        if (s->kind == SAMPLER_STRATIFIED)
            return v2(stratum_value(s, nibble(t->x, i), (uint32_t)bits),
                      stratum_value(s, nibble(t->y, i), (uint32_t)(bits >> 32)));
        j = nibble(t->x, i);
    } else {
        j = padded_index(s, t, i);
        if (s->kind == SAMPLER_STRATIFIED) {
            if (s->grid_packed) return multi_jitter_packed(s, t, j, bits);
            if (s->grid_tabled) return multi_jitter_tabled(s, grid_table(s, t, dim), j, bits);
            return multi_jitter(s, j, t->seed, bits);
        }
    }
    return sobol_value_2d(s, t, j);
}

/* Scalar dimension dim of the current sample as a 1D value, every case. Out of line (see
 * build_dim_table). */
static __attribute__((noinline)) float value_1d(PixelSampler *s, int dim)
{
    if (dim >= SAMPLER_PADDED_DIMS) return float_of((uint32_t)request_bits(s, dim));
    const SamplerDimTable *t = padded_dim(s, dim, 1);
    /* Sobol' values take no jitter: no key, no hash */
    uint64_t bits = s->kind == SAMPLER_STRATIFIED ? request_bits(s, dim) : 0;
    return value_1d_padded(s, t, s->index_in_block, bits);
}

/* Inline common case as in sampler_2d; value_1d gives the same values in every case. */
static inline float sample_1d_fast(PixelSampler *s, int dim)
{
    if (table_ready(s, dim, 1)) {
        uint32_t j = nibble(s->dim_table[dim].x, s->index_in_block);
        if (s->kind == SAMPLER_STRATIFIED) {
            uint32_t jitter = (uint32_t)request_bits(s, dim);
            if (jitter_clear_of_edges(s, jitter)) return stratum_value_raw(s, j, jitter);
        } else {
            return scrambled_to_float(sobol_dim0_reversed(j + s->point_offset), (uint32_t)s->dim_table[dim].seed);
        }
    }
    return value_1d(s, dim);
}

float sampler_1d(PixelSampler *s) { return sample_1d_fast(s, s->dim++); }

float sampler_1d_at(PixelSampler *s, int dim) { return sample_1d_fast(s, dim >= 0 ? dim : 0); }

void sampler_skip(PixelSampler *s, int count)
{
    if (count > 0) s->dim += count;
}

/* sampler_2d for dimension dim, every case. Out of line (see build_dim_table). */
static __attribute__((noinline)) vec2 value_2d(PixelSampler *s, int dim)
{
    if (dim >= SAMPLER_PADDED_DIMS - 1) {
        uint64_t bits = request_bits(s, dim);
        return v2(float_of((uint32_t)bits), float_of((uint32_t)(bits >> 32)));
    }
    const SamplerDimTable *t = padded_dim(s, dim, 2);
    uint64_t bits = s->kind == SAMPLER_STRATIFIED ? request_bits(s, dim) : 0;
    return value_2d_padded(s, t, dim, s->index_in_block, bits);
}

/* The common case inline, without calls (so without registers to save): a built table and,
 * for stratified values, jitter away from the stratum edges; value_2d does the rest and
 * gives the same values. */
vec2 sampler_2d(PixelSampler *s)
{
    int dim = s->dim;
    s->dim += 2;
    if (table_ready(s, dim, 2)) {
        const SamplerDimTable *t = &s->dim_table[dim];
        uint32_t i = s->index_in_block;
        if (s->kind == SAMPLER_STRATIFIED) {
            uint64_t bits = request_bits(s, dim);
            uint32_t jx = (uint32_t)bits, jy = (uint32_t)(bits >> 32);
            if (jitter_clear_of_edges(s, jx) && jitter_clear_of_edges(s, jy))
                return v2(stratum_value_raw(s, nibble(t->x, i), jx), stratum_value_raw(s, nibble(t->y, i), jy));
        } else {
            uint32_t j = nibble(t->x, i) + s->point_offset;
            return v2(scrambled_to_float(sobol_dim0_reversed(j), (uint32_t)t->seed),
                      scrambled_to_float(sobol_dim1_reversed(j), (uint32_t)(t->seed >> 32)));
        }
    }
    return value_2d(s, dim);
}

/* ---- runs: one dimension of several samples ---------------------------------------- */


/* The jitter keys of samples first .. first + count - 1 (sample_key_of). */
static RUN_KERNEL void run_keys(uint64_t pixel_seed, uint32_t first, int count, uint64_t *key)
{
    for (int k = 0; k < count; ++k)
        key[k] = hash_u64(pixel_seed ^ ((uint64_t)(first + (uint32_t)k) * 0xd6e8feb86659fd93ull));
}

void sampler_run_begin(PixelSampler *s, SamplerRun *run, int first, int count)
{
    if (first < 0) first = 0;
    run->first = first;
    run->count = count < 0 ? 0 : count > SAMPLER_RUN_MAX ? SAMPLER_RUN_MAX : count;
    run->one_part = false;
    if (run->count == 0) return;
    /* The fast path needs every sample in the part of the first (the usual case: a round's
     * slice of a pixel lies in one part); the part of the last decides, as parts are
     * consecutive ranges of indices. */
    uint32_t last_block, last_index;
    uint64_t last_part = part_of_sample(s, (uint32_t)(first + run->count - 1), &last_block, &last_index);
    sampler_start_sample(s, first);
    run->part_key = s->part_key;
    run->pixel_seed = s->pixel_seed;
    run->one_part = last_part == run->part_key;
    if (!run->one_part) return;
    for (int k = 0; k < run->count; ++k) run->index_in_block[k] = s->index_in_block + (uint32_t)k;
    /* Sobol' values past the padded dimensions only need the keys: set them always, one
     * hash per sample and run (stratified values need them for every request) */
    run_keys(s->pixel_seed, (uint32_t)first, run->count, run->key);
}

/* Whether the run can be served from the part's tables: run_begin found one part, and the
 * sampler is still in it (else the per-sample path re-enters the right part). A sampler
 * set up for another pixel since is the caller's error: the per-sample path then gives
 * that pixel's values, never a mix. */
static inline bool run_fast(const PixelSampler *s, const SamplerRun *run)
{
    return run->one_part && s->part_key == run->part_key && s->pixel_seed == run->pixel_seed;
}

/* permute_pow2_shift on a domain of at most 2^16 elements, in 16-bit arithmetic: the low 16
 * bits of a sum, an xor or a product depend only on the low 16 bits of the operands, and
 * every right shift reads a value already reduced below 2^16, so this gives the same
 * values. Vectorised, its lanes are half as wide, and a 16-bit multiply has half the
 * latency of a 32-bit one on x86 (vpmullw against vpmulld), which bounds the walk below. */
typedef struct {
    uint16_t mask, k0, k1, m1, k1_8, k0_5;
    int shift;
} Permute16;

static inline Permute16 permute16_of(uint32_t mask, int shift, uint64_t seed)
{
    uint32_t k0 = (uint32_t)seed, k1 = (uint32_t)(seed >> 32);
    return (Permute16){(uint16_t)mask, (uint16_t)k0, (uint16_t)k1, (uint16_t)(0x2c9277b5u | (k0 >> 16) | 1u),
                       (uint16_t)(k1 >> 8), (uint16_t)(k0 >> 5), shift};
}

/* 32 lanes of 16 bits, 64 bytes (GCC vector extensions: written as vectors because GCC 12's
 * vectoriser widens a 16-bit shift to 32-bit lanes). */
typedef uint16_t v32u16 __attribute__((vector_size(64)));

/* In place (a 64-byte vector is neither passed nor returned: the baseline ABI has no AVX-512). */
static inline __attribute__((always_inline)) void permute16(v32u16 *xp, Permute16 p)
{
    v32u16 x = *xp;
    x = (v32u16)((x ^ p.k0) * (uint16_t)0x79b1u) & p.mask;
    x ^= x >> p.shift;
    x = (v32u16)((x + p.k1) * p.m1) & p.mask;
    x ^= x >> p.shift;
    x = (v32u16)((x ^ p.k1_8) * (uint16_t)0xca77u) & p.mask;
    x ^= x >> p.shift;
    x = (v32u16)((x + p.k0_5) * (uint16_t)0xae3du) & p.mask;
    x ^= x >> p.shift;
    *xp = x;
}

/* The padded indices of a run past the tables (padded_index for each sample): the
 * bijection's first step for all samples in one vectorised loop, and when spp is not a power
 * of two the rest of the cycle walk in passes over all of them, each stepping the samples
 * still outside [0, n), until none is. Sample by sample, the walk's exit was a branch taken
 * at random (about half the time at 65 spp) whose mispredictions cost a fifth of a 65-spp
 * render. A pass's steps are independent, so it costs about one step's latency: the walk
 * costs the run's longest walk (about 7 steps of 65 samples at 65 spp, 5 at 83), in 16-bit
 * lanes up to 2^16 points (docs/benchmarks.md, "CPU per sample at counts that are not whole
 * rounds"). */
static RUN_KERNEL void run_padded_first_step(const uint32_t *index, int count, uint32_t mask, int shift, uint64_t seed,
                                             uint32_t *j)
{
    for (int k = 0; k < count; ++k) j[k] = permute_pow2_shift(index[k], mask, shift, seed);
}

/* One pass of the walk in 32-bit lanes: lanes with j >= n take a step. Returns whether some
 * lane is still outside. */
static RUN_KERNEL bool run_padded_walk_step(uint32_t *j, int count, uint32_t n, uint32_t mask, int shift, uint64_t seed)
{
    uint32_t outside = 0;
    for (int k = 0; k < count; ++k) {
        uint32_t x = j[k];
        uint32_t y = x >= n ? permute_pow2_shift(x, mask, shift, seed) : x;
        j[k] = y;
        outside |= (uint32_t)(y >= n);
    }
    return outside != 0;
}

/* The whole walk (first step included) in 16-bit lanes: n <= 2^16, index[k] < n. Lanes
 * past count are 0, inside, and take no step. */
static RUN_KERNEL void run_padded_walk16(const uint32_t *index, int count, uint32_t n, Permute16 p, uint32_t *j)
{
    enum { LANES = sizeof(v32u16) / sizeof(uint16_t), CHUNKS = SAMPLER_RUN_MAX / LANES };
    uint16_t x16[SAMPLER_RUN_MAX];
    int chunks = (count + LANES - 1) / LANES;
    for (int k = 0; k < chunks * LANES; ++k) x16[k] = k < count ? (uint16_t)index[k] : 0u;
    v32u16 x[CHUNKS], last = {0}, lane = {0}, outside = {0};
    last += (uint16_t)(n - 1u); /* inside: x <= n - 1 */
    for (int l = 0; l < LANES; ++l) lane[l] = (uint16_t)l;
    for (int c = 0; c < chunks; ++c) {
        memcpy(&x[c], x16 + c * LANES, sizeof x[c]);
        permute16(&x[c], p);
        x[c] &= (v32u16)(lane < (uint16_t)(count - c * LANES)); /* lanes past count: 0, inside */
        outside |= (v32u16)(x[c] > last);
    }
    for (;;) {
        uint64_t any[sizeof outside / sizeof(uint64_t)], some = 0;
        memcpy(any, &outside, sizeof any);
        for (size_t i = 0; i < sizeof any / sizeof any[0]; ++i) some |= any[i];
        if (!some) break;
        outside ^= outside;
        for (int c = 0; c < chunks; ++c) {
            v32u16 out = (v32u16)(x[c] > last), y = x[c];
            permute16(&y, p);
            x[c] = (y & out) | (x[c] & ~out);
            outside |= (v32u16)(x[c] > last);
        }
    }
    for (int c = 0; c < chunks; ++c) memcpy(x16 + c * LANES, &x[c], sizeof x[c]);
    for (int k = 0; k < count; ++k) j[k] = x16[k];
}

static void run_padded_indices(const PixelSampler *s, const SamplerDimTable *t, const SamplerRun *run, uint32_t *j)
{
    uint32_t n = (uint32_t)s->spp;
    if (s->perm_mask + 1u != n && s->perm_mask >= 31u && s->perm_mask <= 0xffffu) {
        run_padded_walk16(run->index_in_block, run->count, n, permute16_of(s->perm_mask, s->perm_shift, t->x), j);
        return;
    }
    /* a power of two: the first step is the permutation (as before the walk was vectorised) */
    run_padded_first_step(run->index_in_block, run->count, s->perm_mask, s->perm_shift, t->x, j);
    if (s->perm_mask + 1u == n) return;
    while (run_padded_walk_step(j, run->count, n, s->perm_mask, s->perm_shift, t->x)) {
    }
}

/* The jitter bits of dimension dim of a run's samples (key_bits), as x's low and y's high
 * 32 bits (in lanes of 32 bits the value loops vectorise). */
static RUN_KERNEL void run_jitter_bits(const uint64_t *key, int count, int dim, uint32_t *jx, uint32_t *jy)
{
    uint64_t step = (uint64_t)(uint32_t)dim * 0x9e3779b97f4a7c15ull;
    for (int k = 0; k < count; ++k) {
        uint64_t bits = hash_u64(key[k] + step);
        jx[k] = (uint32_t)bits, jy[k] = (uint32_t)(bits >> 32);
    }
}

/* What the vectorised stratum conversion needs of the part (stratum_value). */
typedef struct {
    double scale;    /* inv_spp_2m32 */
    uint32_t lo, hi; /* jitter_clear_of_edges: lo < jitter < hi */
} StratumScale;

static inline StratumScale stratum_scale(const PixelSampler *s)
{
    /* margin_bits = spp 2^9 < 2^32: UINT32_MAX + 1 - margin as a 32-bit number */
    return (StratumScale){s->inv_spp_2m32, (uint32_t)s->margin_bits, (uint32_t)(0u - (uint32_t)s->margin_bits)};
}

/* stratum_value_raw without a 64-bit integer conversion (which x86 vectorises only with
 * AVX-512): stratum 2^32 + bits is below 2^53 (stratum < 2^21), so it is the exact sum of
 * the exactly converted stratum 2^32 and bits (bits converted as a signed number offset by
 * 2^31), the same double, hence the same product and the same float. */
static inline float stratum_value_vec(uint32_t stratum, uint32_t bits, double scale)
{
    double jitter = (double)(int32_t)(bits ^ 0x80000000u) + 2147483648.0;
    return (float)(((double)stratum * 4294967296.0 + jitter) * scale);
}

/* Element i < 16 of a table of nibbles given as its two 32-bit halves (a 32-bit shift per
 * lane, which vectorises where the 64-bit one does not as well). */
static inline uint32_t nibble32(uint32_t lo, uint32_t hi, uint32_t i)
{
    uint32_t half = i < 8u ? lo : hi;
    return (half >> (4u * (i & 7u))) & 15u;
}

/* The end of a run's multi-jittered point in cell (c, r) (run_packed_values,
 * run_tabled_values): sub-column ax and sub-row ay, not yet reduced mod rows and cols, to
 * its strata and values. Returns whether a jitter lies within rounding of a stratum edge. */
static inline __attribute__((always_inline)) uint32_t mj_point(uint32_t c, uint32_t r, uint32_t ax, uint32_t ay,
                                                               uint32_t rows, uint32_t cols, uint32_t jx, uint32_t jy,
                                                               StratumScale sc, uint32_t *stratum_x, uint32_t *stratum_y,
                                                               float *fx, float *fy)
{
    ax = ax >= rows ? ax - rows : ax; /* (rho(i) + o) mod m, as grid_sub_permute */
    ay = ay >= cols ? ay - cols : ay;
    uint32_t x = c * rows + ax, y = r * cols + ay;
    *stratum_x = x, *stratum_y = y;
    *fx = stratum_value_vec(x, jx, sc.scale);
    *fy = stratum_value_vec(y, jy, sc.scale);
    return (uint32_t)!(jx > sc.lo && jx < sc.hi) | (uint32_t)!(jy > sc.lo && jy < sc.hi);
}

/* multi_jitter_packed for a run: padded indices j, jitter bits; the values go to out_xy
 * as x, y pairs (a vec2 array: two floats each, no padding), stored in the loop (no arrays
 * of x and y to interleave after it, no strata kept for the rare correction: 1-2% of the
 * sampler at 64-256 spp, tools/bench-sampler). Returns whether some jitter lies within
 * rounding of a stratum edge (the caller then redoes those samples by multi_jitter_packed). */
static RUN_KERNEL bool run_packed_values(const uint32_t *j, const uint32_t *jitter_x, const uint32_t *jitter_y, int count, uint32_t rows, uint32_t cols,
                                         uint64_t sub_x, uint64_t sub_y, uint64_t col_rot, uint64_t row_rot,
                                         StratumScale sc, float *out_xy)
{
    /* r = j / cols by a 16-bit reciprocal: packed grids have j < 256 and cols <= 16, and
     * 16 fraction bits >= 8 + 4 make it exact (Lemire, Kaser, Kurz 2019) */
    uint32_t magic = 65536u / cols + 1u;
    uint32_t sxl = (uint32_t)sub_x, sxh = (uint32_t)(sub_x >> 32), syl = (uint32_t)sub_y, syh = (uint32_t)(sub_y >> 32);
    uint32_t crl = (uint32_t)col_rot, crh = (uint32_t)(col_rot >> 32), rrl = (uint32_t)row_rot, rrh = (uint32_t)(row_rot >> 32);
    uint32_t near_edge = 0;
    for (int k = 0; k < count; ++k) {
        uint32_t r = (j[k] * magic) >> 16, c = j[k] - r * cols;
        uint32_t ax = nibble32(sxl, sxh, r) + nibble32(crl, crh, c);
        uint32_t ay = nibble32(syl, syh, c) + nibble32(rrl, rrh, r), sx, sy;
        near_edge |= mj_point(c, r, ax, ay, rows, cols, jitter_x[k], jitter_y[k], sc, &sx, &sy, &out_xy[2 * k],
                              &out_xy[2 * k + 1]);
    }
    return near_edge != 0;
}

/* multi_jitter_tabled for a run, every entry of the table filled (grid_fill_all): the
 * same outputs as run_packed_values. Tabled grids have rows + cols <= SAMPLER_GRID_ENTRIES,
 * so j < n <= 2^18 and cols < 2^10, and a 32-bit reciprocal gives j / cols exactly (32
 * fraction bits >= 18 + 10; Lemire, Kaser, Kurz 2019). */
static RUN_KERNEL bool run_tabled_values(const uint32_t *restrict j, const uint32_t *restrict jitter_x,
                                         const uint32_t *restrict jitter_y, int count, uint32_t rows, uint32_t cols,
                                         const uint32_t *restrict entry, StratumScale sc, uint32_t *restrict stratum_x,
                                         uint32_t *restrict stratum_y, float *restrict out_xy)
{
    uint32_t magic = UINT32_MAX / cols + 1u; /* cols >= 2 past 16 points (grid_shape: rows <= cols) */
    uint32_t near_edge = 0;
    float fx[SAMPLER_RUN_MAX], fy[SAMPLER_RUN_MAX];
    for (int k = 0; k < count; ++k) {
        uint32_t r = (uint32_t)(((uint64_t)j[k] * magic) >> 32), c = j[k] - r * cols;
        /* signed indices: GCC gathers with 32-bit offsets only when they are signed */
        uint32_t row = entry[(int32_t)r], col = entry[(int32_t)(rows + c)];
        uint32_t ax = (row & 0xffffu) + (col >> 16), ay = (col & 0xffffu) + (row >> 16);
        near_edge |= mj_point(c, r, ax, ay, rows, cols, jitter_x[k], jitter_y[k], sc, &stratum_x[k], &stratum_y[k], &fx[k],
                              &fy[k]);
    }
    for (int k = 0; k < count; ++k) out_xy[2 * k] = fx[k], out_xy[2 * k + 1] = fy[k];
    return near_edge != 0;
}

/* 16 lanes of 32 bits (GCC vector extensions, as v32u16). */
typedef uint32_t v16u32 __attribute__((vector_size(64)));

/* run_tabled_values for grids whose sides both have at most 32 elements (17 to 1024 points
 * that are not packed: 512 = 16 x 32): the same outputs. A side's entries fit two 16-lane
 * vectors, so the two look-ups per sample are two-register permutes (__builtin_shuffle:
 * AVX-512's vpermt2d) instead of gathers, which GCC 12 emulates with a scalar load and an
 * insert per lane when tuning for generic x86 (two gathers were about two thirds of
 * run_tabled_values at 512 spp). The cell's row and column come first for all samples
 * (vectorised), then the look-ups by chunks of 16, then run_tabled_values's value loop. */
static RUN_KERNEL bool run_tabled_values_small(const uint32_t *restrict j, const uint32_t *restrict jitter_x,
                                               const uint32_t *restrict jitter_y, int count, uint32_t rows,
                                               uint32_t cols, const uint32_t *restrict entry, StratumScale sc,
                                               uint32_t *restrict stratum_x, uint32_t *restrict stratum_y,
                                               float *restrict out_xy)
{
    enum { LANES = sizeof(v16u32) / sizeof(uint32_t), CHUNKS = SAMPLER_RUN_MAX / LANES };
    uint32_t magic = UINT32_MAX / cols + 1u; /* as run_tabled_values */
    int chunks = (count + LANES - 1) / LANES;
    uint32_t row_of[SAMPLER_RUN_MAX], col_of[SAMPLER_RUN_MAX];
    for (int k = 0; k < count; ++k) {
        uint32_t r = (uint32_t)(((uint64_t)j[k] * magic) >> 32);
        row_of[k] = r, col_of[k] = j[k] - r * cols;
    }
    for (int k = count; k < chunks * LANES; ++k) row_of[k] = col_of[k] = 0; /* lanes past count: entry 0 */
    /* the sides' entries, zero past each side (never selected: r < rows, c < cols) */
    uint32_t side_x[2 * LANES] = {0}, side_y[2 * LANES] = {0};
    memcpy(side_x, entry, rows * sizeof *entry);
    memcpy(side_y, entry + rows, cols * sizeof *entry);
    v16u32 x_lo, x_hi, y_lo, y_hi;
    memcpy(&x_lo, side_x, sizeof x_lo), memcpy(&x_hi, side_x + LANES, sizeof x_hi);
    memcpy(&y_lo, side_y, sizeof y_lo), memcpy(&y_hi, side_y + LANES, sizeof y_hi);
    uint32_t row[SAMPLER_RUN_MAX], col[SAMPLER_RUN_MAX];
    for (int ch = 0; ch < chunks && ch < CHUNKS; ++ch) {
        v16u32 r, c;
        memcpy(&r, row_of + ch * LANES, sizeof r), memcpy(&c, col_of + ch * LANES, sizeof c);
        v16u32 row_entry = __builtin_shuffle(x_lo, x_hi, r), col_entry = __builtin_shuffle(y_lo, y_hi, c);
        memcpy(row + ch * LANES, &row_entry, sizeof row_entry), memcpy(col + ch * LANES, &col_entry, sizeof col_entry);
    }
    uint32_t near_edge = 0;
    float fx[SAMPLER_RUN_MAX], fy[SAMPLER_RUN_MAX];
    for (int k = 0; k < count; ++k) {
        uint32_t ax = (row[k] & 0xffffu) + (col[k] >> 16), ay = (col[k] & 0xffffu) + (row[k] >> 16);
        near_edge |= mj_point(col_of[k], row_of[k], ax, ay, rows, cols, jitter_x[k], jitter_y[k], sc, &stratum_x[k],
                              &stratum_y[k], &fx[k], &fy[k]);
    }
    for (int k = 0; k < count; ++k) out_xy[2 * k] = fx[k], out_xy[2 * k + 1] = fy[k];
    return near_edge != 0;
}

/* One side of a tabled grid as run_grid_values_direct needs it: m elements, rho's lattice
 * step (m > 16) or its packed shuffle (2 <= m <= 16). */
typedef struct {
    uint32_t m, step;
    uint64_t small;
} GridSide;

/* rho(i[k]) of one side for a run: grid_rho's values (grid_fill_all's entries' low halves).
 * Past 16 elements the lattice's remainder by a 32-bit reciprocal, exact as in
 * grid_lattice_entries (step i < m^2 <= 2^20, m < 2^10). */
static inline __attribute__((always_inline)) void side_rho_run(const uint32_t *restrict i, int count, GridSide side,
                                                               uint32_t *restrict rho)
{
    if (side.m <= 1) {
        for (int k = 0; k < count; ++k) rho[k] = 0;
    } else if (side.m <= SAMPLER_SHUFFLE_MAX) {
        uint32_t lo = (uint32_t)side.small, hi = (uint32_t)(side.small >> 32);
        for (int k = 0; k < count; ++k) rho[k] = nibble32(lo, hi, i[k]);
    } else {
        uint32_t magic = UINT32_MAX / side.m + 1u;
        for (int k = 0; k < count; ++k) {
            uint32_t x = side.step * i[k], q = (uint32_t)(((uint64_t)x * magic) >> 32);
            rho[k] = x - q * side.m;
        }
    }
}

/* run_tabled_values without the table: each sample's row and column entries computed for
 * that sample alone (its row's rotation, its column's, the two rho), all of it in
 * vectorised loops without a look-up. A run fills the table with rows + cols hashes, and
 * this costs two a sample: at 8192 spp (64 x 128) a round's 64 samples took 192 hashes and
 * two emulated 16-lane gathers a sample (GCC 12 emits no vpgatherdd under generic tuning),
 * here 128 hashes and none (docs/benchmarks.md, branch samp2). The same outputs as
 * run_tabled_values unless some rotation's draw may need Lemire's rejection
 * (uniform_below_small's flag: m 2^-64 a draw below m): then it returns
 * RUN_DIRECT_REJECTED and writes nothing the caller may use (the caller redraws the run
 * through the table, whose rotations grid_rotations draws exactly). Else the bit
 * RUN_DIRECT_NEAR_EDGE says as run_tabled_values's result does. */
enum { RUN_DIRECT_NEAR_EDGE = 1, RUN_DIRECT_REJECTED = 2 };
static RUN_KERNEL uint32_t run_grid_values_direct(const uint32_t *restrict j, const uint32_t *restrict jitter_x,
                                                  const uint32_t *restrict jitter_y, int count, GridSide side_x,
                                                  GridSide side_y, uint64_t seed, StratumScale sc,
                                                  uint32_t *restrict stratum_x, uint32_t *restrict stratum_y,
                                                  float *restrict out_xy)
{
    uint32_t rows = side_x.m, cols = side_y.m;
    uint32_t magic = UINT32_MAX / cols + 1u; /* as run_tabled_values */
    uint32_t r[SAMPLER_RUN_MAX], c[SAMPLER_RUN_MAX];
    for (int k = 0; k < count; ++k) {
        uint32_t q = (uint32_t)(((uint64_t)j[k] * magic) >> 32);
        r[k] = q, c[k] = j[k] - q * cols;
    }
    /* the rotations: row r's sub-rows (a draw below cols), column c's sub-columns (below rows) */
    uint32_t row_rot[SAMPLER_RUN_MAX], col_rot[SAMPLER_RUN_MAX], rejected = 0;
    for (int k = 0; k < count; ++k) {
        row_rot[k] = uniform_below_small(row_perm_seed(seed, r[k]), cols, &rejected);
        col_rot[k] = uniform_below_small(column_perm_seed(seed, c[k]), rows, &rejected);
    }
    if (rejected) return RUN_DIRECT_REJECTED;
    uint32_t rho_x[SAMPLER_RUN_MAX], rho_y[SAMPLER_RUN_MAX];
    side_rho_run(r, count, side_x, rho_x);
    side_rho_run(c, count, side_y, rho_y);
    uint32_t near_edge = 0;
    float fx[SAMPLER_RUN_MAX], fy[SAMPLER_RUN_MAX];
    for (int k = 0; k < count; ++k) {
        uint32_t ax = rho_x[k] + col_rot[k], ay = rho_y[k] + row_rot[k];
        near_edge |= mj_point(c[k], r[k], ax, ay, rows, cols, jitter_x[k], jitter_y[k], sc, &stratum_x[k], &stratum_y[k],
                              &fx[k], &fy[k]);
    }
    for (int k = 0; k < count; ++k) out_xy[2 * k] = fx[k], out_xy[2 * k + 1] = fy[k];
    return near_edge ? RUN_DIRECT_NEAR_EDGE : 0u;
}

/* 1D stratified values of a run past the tables: stratum j[k], jitter bits[k]. */
static RUN_KERNEL bool run_strata_1d(const uint32_t *j, const uint32_t *jitter, int count, StratumScale sc, float *out)
{
    uint32_t near_edge = 0;
    for (int k = 0; k < count; ++k) {
        uint32_t jx = jitter[k];
        out[k] = stratum_value_vec(j[k], jx, sc.scale);
        near_edge |= (uint32_t)!(jx > sc.lo && jx < sc.hi);
    }
    return near_edge != 0;
}

/* The strata of a run's samples in a per-pixel table of nibbles (spp <= SAMPLER_SHUFFLE_MAX):
 * nibble index[k] of packed, by 32-bit halves (nibble32), so that the loop vectorises. */
static RUN_KERNEL void run_table_strata(const uint32_t *index, int count, uint64_t packed, uint32_t *j)
{
    uint32_t lo = (uint32_t)packed, hi = (uint32_t)(packed >> 32);
    for (int k = 0; k < count; ++k) j[k] = nibble32(lo, hi, index[k]);
}

/* value_2d_padded's stratified case with per-pixel tables for a run: strata nibble index[k]
 * of tx and of ty, jitter bits jx and jy; the values go to out_xy as x, y pairs, stored in
 * the loop as run_packed_values does. Returns whether some jitter lies within rounding of a
 * stratum edge (the caller then redoes those samples by value_2d_padded). */
static RUN_KERNEL bool run_table_values_2d(const uint32_t *index, const uint32_t *jitter_x, const uint32_t *jitter_y,
                                           int count, uint64_t tx, uint64_t ty, StratumScale sc, float *out_xy)
{
    uint32_t txl = (uint32_t)tx, txh = (uint32_t)(tx >> 32), tyl = (uint32_t)ty, tyh = (uint32_t)(ty >> 32);
    uint32_t near_edge = 0;
    for (int k = 0; k < count; ++k) {
        uint32_t x = nibble32(txl, txh, index[k]), y = nibble32(tyl, tyh, index[k]), jx = jitter_x[k], jy = jitter_y[k];
        out_xy[2 * k] = stratum_value_vec(x, jx, sc.scale);
        out_xy[2 * k + 1] = stratum_value_vec(y, jy, sc.scale);
        near_edge |= (uint32_t)!(jx > sc.lo && jx < sc.hi) | (uint32_t)!(jy > sc.lo && jy < sc.hi);
    }
    return near_edge != 0;
}

/* A run's 2D values again by the scalar stratum_value, from their strata and jitter bits: what
 * the vectorised loops' callers do when some jitter lies within rounding of a stratum edge.
 * Only those samples: where both jitters are clear of the edges stratum_value is
 * stratum_value_raw, whose value the vectorised loop wrote already (stratum_value_vec). At
 * 8192 spp (a margin of 2^-10 on each side) about a quarter of a 64-sample run's calls
 * redid every sample (1% of the render). */
static void run_values_2d_exact(const PixelSampler *s, int count, const uint32_t *sx, const uint32_t *sy,
                                const uint32_t *jx, const uint32_t *jy, vec2 *out)
{
    for (int k = 0; k < count; ++k)
        if (jitters_near_edge(s, jx[k], jy[k])) out[k] = v2(stratum_value(s, sx[k], jx[k]), stratum_value(s, sy[k], jy[k]));
}

void sampler_run_1d(PixelSampler *s, const SamplerRun *run, int dim, float *out)
{
    if (dim < 0) dim = 0;
    if (!run_fast(s, run) || dim >= SAMPLER_PADDED_DIMS) {
        for (int k = 0; k < run->count; ++k) {
            sampler_start_sample(s, run->first + k);
            out[k] = sampler_1d_at(s, dim);
        }
        return;
    }
    const SamplerDimTable *t = padded_dim(s, dim, 1);
    bool jitter = s->kind == SAMPLER_STRATIFIED;
    if (jitter) { /* value_1d_padded's stratified case in the loops above: the strata from the
                   * padded indices, or at spp <= SAMPLER_SHUFFLE_MAX from the per-pixel table */
        uint32_t j[SAMPLER_RUN_MAX], jx[SAMPLER_RUN_MAX], jy[SAMPLER_RUN_MAX];
        if (s->spp > SAMPLER_SHUFFLE_MAX) run_padded_indices(s, t, run, j);
        else run_table_strata(run->index_in_block, run->count, t->x, j);
        run_jitter_bits(run->key, run->count, dim, jx, jy);
        if (run_strata_1d(j, jx, run->count, stratum_scale(s), out))
            for (int k = 0; k < run->count; ++k) out[k] = stratum_value(s, j[k], jx[k]);
        return;
    }
    if (s->spp > SAMPLER_SHUFFLE_MAX) { /* Sobol': the padded indices in one walk (run_padded_indices) */
        uint32_t j[SAMPLER_RUN_MAX];
        run_padded_indices(s, t, run, j);
        for (int k = 0; k < run->count; ++k) out[k] = sobol_value_1d(s, t, j[k]);
        return;
    }
    for (int k = 0; k < run->count; ++k) out[k] = value_1d_padded(s, t, run->index_in_block[k], 0); /* Sobol' */
}

/* A run fills a tabled grid's rows + cols entries all at once (grid_fill_all, vectorised)
 * rather than entry by entry on first use (grid_fill: a hash and a division each, scalar)
 * when they number at most this many times the most it can touch, min(rows, count) +
 * min(cols, count). The vectorised fill measured 4.5-8 times cheaper per entry
 * (tools/bench-sampler --runs, rounds of 64: 8192 spp = 64 x 128, 0.42x the sampler's time;
 * 32768 = 128 x 256, 0.69x; 211 = 1 x 211, 0.92x; 509 = 1 x 509 lost 1.2x at a ratio of 8,
 * so 4; docs/benchmarks.md, "Cost per sample against resolution"). Until 2026-11-30 the rule
 * was entries <= 2 count, which sent a 64-sample round of a 64 x 128 grid entry by entry: a
 * render at 8192 spp cost 1.35x the CPU per sample of one at 512. */
enum { GRID_FILL_ALL_RATIO = 4 };

/* Grids whose sides both have at most this many elements are looked up in the table by
 * in-register permutes (run_tabled_values_small); larger ones compute each sample's entries
 * for it alone (run_grid_values_direct), and use the table only when a rotation's draw may
 * be rejected. tools/bench-sampler --runs (rounds of 64, against the table): direct 1.52x
 * cheaper at 8192 spp (64 x 128), 1.38x at 4096, 1.32x at 2048, 1.26x at 1000 (25 x 40:
 * 65 entries, about as many hashes as the run's 64 samples), 2.1x at 1009 (1 x 1009,
 * filled entry by entry); 0.955x (dearer) at 512 and 1024, whose permutes beat it. */
enum { GRID_PERMUTE_SIDE_MAX = 32 };

/* sampler_run_2d's stratified values past the per-pixel tables with a packed or a tabled grid.
 * Out of line, so that the other cases' loop stays as small as it was (Sobol' measured 2-4%
 * slower with this inlined). */
static __attribute__((noinline)) void run_2d_multi_jitter(PixelSampler *s, const SamplerRun *run,
                                                          const SamplerDimTable *t, int dim, vec2 *out)
{
    /* value_2d_padded's cases in loops of their own: first the padding walks, so their
     * mispredicted exits do not stall the look-ups (tools/bench-sampler: 1.05x at 100 and
     * 144 spp, 1.2x at 418 and 1000); packed grids then in the vectorised loop; past
     * 16 x 16 with a side above GRID_PERMUTE_SIDE_MAX, each sample's entries for it alone;
     * else (or when a draw there may be rejected) the grid entries in one pass when the run
     * may touch a large share of them (each sample two of rows + cols; GRID_FILL_ALL_RATIO),
     * so that the value loop finds them all */
    uint32_t j[SAMPLER_RUN_MAX];
    run_padded_indices(s, t, run, j);
    if (s->grid_packed) {
        uint32_t jx[SAMPLER_RUN_MAX], jy[SAMPLER_RUN_MAX];
        run_jitter_bits(run->key, run->count, dim, jx, jy);
        if (run_packed_values(j, jx, jy, run->count, s->grid_rows, s->grid_cols, t->sub_x, t->sub_y, t->col_rot,
                              t->row_rot, stratum_scale(s), &out[0].x))
            for (int k = 0; k < run->count; ++k) /* those samples again, as one request would take them */
                if (jitters_near_edge(s, jx[k], jy[k])) out[k] = multi_jitter_packed(s, t, j[k], (uint64_t)jy[k] << 32 | jx[k]);
        return;
    }
    SamplerGridTable *g = grid_table(s, t, dim);
    uint32_t rows = s->grid_rows, cols = s->grid_cols, count = (uint32_t)run->count;
    bool permutes = rows <= GRID_PERMUTE_SIDE_MAX && cols <= GRID_PERMUTE_SIDE_MAX;
    if (!permutes) {
        uint32_t jx[SAMPLER_RUN_MAX], jy[SAMPLER_RUN_MAX], sx[SAMPLER_RUN_MAX], sy[SAMPLER_RUN_MAX];
        run_jitter_bits(run->key, run->count, dim, jx, jy);
        need_grid_steps(s);
        GridSide side_x = {rows, s->grid_step_x, g->rho_x_small}, side_y = {cols, s->grid_step_y, g->rho_y_small};
        uint32_t got = run_grid_values_direct(j, jx, jy, run->count, side_x, side_y, g->seed, stratum_scale(s), sx, sy,
                                              &out[0].x);
        if (got == RUN_DIRECT_NEAR_EDGE) run_values_2d_exact(s, run->count, sx, sy, jx, jy, out);
        if (got != RUN_DIRECT_REJECTED) return;
    }
    uint32_t touched_max = (rows < count ? rows : count) + (cols < count ? cols : count);
    if (rows + cols <= GRID_FILL_ALL_RATIO * touched_max) {
        grid_fill_all(s, g);
        uint32_t jx[SAMPLER_RUN_MAX], jy[SAMPLER_RUN_MAX], sx[SAMPLER_RUN_MAX], sy[SAMPLER_RUN_MAX];
        run_jitter_bits(run->key, run->count, dim, jx, jy);
        bool near_edge = permutes
                             ? run_tabled_values_small(j, jx, jy, run->count, rows, cols, g->entry, stratum_scale(s),
                                                       sx, sy, &out[0].x)
                             : run_tabled_values(j, jx, jy, run->count, rows, cols, g->entry, stratum_scale(s), sx, sy,
                                                 &out[0].x);
        if (near_edge) run_values_2d_exact(s, run->count, sx, sy, jx, jy, out);
        return;
    }
    for (int k = 0; k < run->count; ++k) out[k] = multi_jitter_tabled(s, g, j[k], key_bits(run->key[k], dim));
}

void sampler_run_2d(PixelSampler *s, const SamplerRun *run, int dim, vec2 *out)
{
    if (dim < 0) dim = 0;
    if (!run_fast(s, run) || dim >= SAMPLER_PADDED_DIMS - 1) {
        for (int k = 0; k < run->count; ++k) {
            sampler_start_sample(s, run->first + k);
            s->dim = dim;
            out[k] = sampler_2d(s);
        }
        return;
    }
    const SamplerDimTable *t = padded_dim(s, dim, 2);
    bool jitter = s->kind == SAMPLER_STRATIFIED;
    if (jitter && (s->grid_packed || s->grid_tabled)) {
        run_2d_multi_jitter(s, run, t, dim, out);
        return;
    }
    if (!jitter && s->spp > SAMPLER_SHUFFLE_MAX) { /* Sobol': as in sampler_run_1d */
        uint32_t j[SAMPLER_RUN_MAX];
        run_padded_indices(s, t, run, j);
        for (int k = 0; k < run->count; ++k) out[k] = sobol_value_2d(s, t, j[k]);
        return;
    }
    if (jitter && s->spp <= SAMPLER_SHUFFLE_MAX) { /* value_2d_padded's case with tables, vectorised */
        uint32_t jx[SAMPLER_RUN_MAX], jy[SAMPLER_RUN_MAX];
        run_jitter_bits(run->key, run->count, dim, jx, jy);
        if (run_table_values_2d(run->index_in_block, jx, jy, run->count, t->x, t->y, stratum_scale(s), &out[0].x))
            for (int k = 0; k < run->count; ++k) /* those samples again, as one request would take them */
                if (jitters_near_edge(s, jx[k], jy[k]))
                    out[k] = value_2d_padded(s, t, dim, run->index_in_block[k], (uint64_t)jy[k] << 32 | jx[k]);
        return;
    }
    for (int k = 0; k < run->count; ++k)
        out[k] = value_2d_padded(s, t, dim, run->index_in_block[k], jitter ? key_bits(run->key[k], dim) : 0);
}
