/* The per-pixel tables' shuffles (spp <= SAMPLER_SHUFFLE_MAX) keep their values: the
 * sampler decodes a Fisher-Yates shuffle's draws from one product (their mixed-radix digits)
 * and swaps with byte shuffles where the CPU has them; the reference here is the algorithm it
 * replaced, kept as it was (one multiply-shift draw per step, swaps on a nibble-packed word).
 * Checked two ways: every element of sampler_permute's permutations of 5 to 16 elements over
 * many seeds against the reference, and a fingerprint of every value of whole pixels (both
 * samplers, 1D and 2D requests, small counts) against the one the sampler gave before the
 * change (main 45965ef), so the multi-jitter tables' use of the shuffles is covered too.
 * The fingerprints also hold the grids' draws decoded from one product (4 x 4 since lowspp3;
 * 1 x 2, 1 x 3, 2 x 2, 2 x 3, 2 x 4, 3 x 3 and 3 x 4, with pi's draw at up to 10 spp, since
 * lowspp4): reading the rows' digits in reverse order fails them at 4, 6, 8, 9 and 12 spp. */
#include <string.h>

#include "check.h"
#include "core/sampler.h"

/* ---- the reference: Lemire draws one at a time (src/core/sampler.c before the change) ---- */

typedef struct {
    uint64_t bits, product;
} RefDraw;

static uint32_t ref_below(RefDraw *d, uint32_t bound)
{
    unsigned __int128 m = (unsigned __int128)d->bits * bound;
    d->bits = (uint64_t)m;
    d->product *= bound;
    return (uint32_t)(m >> 64);
}

static bool ref_accepted(const RefDraw *d) { return d->bits >= d->product || d->bits >= (0u - d->product) % d->product; }

/* A permutation of [0, n), 4 < n <= 16, packed in nibbles, as shuffle_bits_nibbles drew it. */
static uint64_t ref_shuffle(uint32_t n, uint64_t random_bits)
{
    for (;; random_bits = hash_u64(random_bits)) {
        RefDraw d = {random_bits, 1u};
        uint64_t p = 0xfedcba9876543210ull;
        for (uint32_t k = n; k-- > 1;) {
            uint32_t j = ref_below(&d, k + 1);
            uint64_t swap = ((p >> (4u * k)) ^ (p >> (4u * j))) & 15u;
            p ^= (swap << (4u * k)) | (swap << (4u * j));
        }
        if (ref_accepted(&d)) return p;
    }
}

/* sampler_permute on a table size draws the shuffle from hash_u64(seed). Returns the number of
 * elements that differ over `seeds` seeds per size. */
static int permutations_differing(int seeds)
{
    int bad = 0;
    for (uint32_t n = 5; n <= SAMPLER_SHUFFLE_MAX; ++n)
        for (int k = 0; k < seeds; ++k) {
            uint64_t seed = hash_u64((uint64_t)k * 0x9e3779b97f4a7c15ull + n);
            uint64_t expect = ref_shuffle(n, hash_u64(seed));
            for (uint32_t i = 0; i < n; ++i) bad += sampler_permute(i, n, seed) != ((expect >> (4u * i)) & 15u);
        }
    return bad;
}

/* ---- whole pixels against the values before the change ------------------------------- */

static uint64_t mix(uint64_t h, float v)
{
    uint32_t bits;
    memcpy(&bits, &v, sizeof bits);
    return hash_u64(h ^ bits);
}

/* Every sample of `pixels` pixels at spp, scalar dimensions 0 .. SAMPLER_PADDED_DIMS + 1 as
 * 1D and as 2D requests (a dimension's table is built for the kind asked first: both orders
 * occur across samples), folded into one hash. */
static uint64_t pixels_fingerprint(SamplerKind kind, int spp, int pixels)
{
    static PixelSampler s;
    uint64_t h = (uint64_t)spp;
    for (int p = 0; p < pixels; ++p) {
        sampler_start_pixel(&s, kind, 99, p % 16, p / 16, 0, spp);
        for (int i = 0; i < spp; ++i) {
            sampler_start_sample(&s, i);
            for (int dim = 0; dim < SAMPLER_PADDED_DIMS + 2; ++dim) {
                if ((dim + i + p) % 3 == 0) {
                    h = mix(h, sampler_1d_at(&s, dim));
                } else {
                    s.dim = dim;
                    vec2 v = sampler_2d(&s);
                    h = mix(mix(h, v.x), v.y);
                }
            }
        }
    }
    return h;
}

/* The fingerprints main 45965ef gives (this test's code linked against its libwedge_core),
 * 64 pixels each: stratified, then Sobol'. */
static const struct {
    int spp;
    uint64_t stratified, sobol;
} BEFORE[] = {
    {1, 0x9c04c9068df9f610ull, 0x58fe85c7bc8bfe15ull},
    {2, 0x097eb46f6ddf5afcull, 0xa9d7925f02e18cf6ull},
    {3, 0x7e5b4279904b7f08ull, 0xbdd733bbe21448b6ull},
    {4, 0x9f8a2d03fd7749f7ull, 0xba2b18029d9d7e84ull},
    {5, 0x348ed2cc063a62fbull, 0xf9a899238975e9d3ull},
    {6, 0x27d93a3320a4f2ecull, 0xb30fbf05cc3e1cb5ull},
    {7, 0x187279fb592b778bull, 0x441060dd64c3f738ull},
    {8, 0xa8a2a6f54cb95cc0ull, 0x93643e41dd87f86eull},
    {9, 0xe8d65e948b4f8501ull, 0x77e1c0dd4e3d27a8ull},
    {10, 0xf750fd5dfe9c59b6ull, 0xe7175e427bbaafdbull},
    {11, 0xe17e78606a683869ull, 0xe821b222c4b8c103ull},
    {12, 0x7fcd8eae4b37baf6ull, 0xe8a9622b13ddd26aull},
    {13, 0x848848b9f76e1b4aull, 0x3a1381f668ab2f9full},
    {14, 0xe3d8a715ade863eaull, 0x76a4959e68a9e7a8ull},
    {15, 0xf10d2e0c586f318bull, 0x45c4b76a5f5a2572ull},
    {16, 0x4974468339afe480ull, 0x0c54ebdc06bd8d9full},
    {25, 0x343e8c14344a4c9full, 0xb3805ddcd1ee3859ull},
    {32, 0x85d471c6db71e6f0ull, 0xf1427bb9398e8a28ull},
};

int main(void)
{
    CHECK(permutations_differing(4000) == 0);
    for (size_t k = 0; k < sizeof BEFORE / sizeof BEFORE[0]; ++k) {
        CHECK(pixels_fingerprint(SAMPLER_STRATIFIED, BEFORE[k].spp, 64) == BEFORE[k].stratified);
        CHECK(pixels_fingerprint(SAMPLER_SOBOL, BEFORE[k].spp, 64) == BEFORE[k].sobol);
    }
    CHECK_DONE();
}
