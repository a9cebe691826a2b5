/* Random numbers: a 64-bit hash for seeding and PCG32 (O'Neill 2014) as the generator. */
#ifndef WEDGE_CORE_RNG_H
#define WEDGE_CORE_RNG_H

#include <stdint.h>

/* splitmix64 finaliser: a strong 64-bit mix, used to derive independent seeds. */
static inline uint64_t hash_u64(uint64_t x)
{
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

/* Seed of one pixel's sampler in one pass: independent of thread count and tile order. */
static inline uint64_t hash_pixel_seed(uint64_t seed, int px, int py, int pass)
{
    /* Two chained hashes (it starts every pixel's dependency chain): a bijection of the seed
     * stepped by the pass along a Weyl sequence, then mixed with the pixel's 64-bit word. */
    uint64_t h = hash_u64(seed) + (uint64_t)(uint32_t)pass * 0x9e3779b97f4a7c15ull;
    return hash_u64(h ^ ((uint64_t)(uint32_t)px | (uint64_t)(uint32_t)py << 32));
}

typedef struct {
    uint64_t state, inc;
} Pcg32;

static inline uint32_t pcg32_next(Pcg32 *r)
{
    uint64_t old = r->state;
    r->state = old * 6364136223846793005ull + r->inc;
    uint32_t xorshifted = (uint32_t)(((old >> 18u) ^ old) >> 27u);
    uint32_t rot = (uint32_t)(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((-rot) & 31u));
}

static inline void pcg32_seed(Pcg32 *r, uint64_t seed, uint64_t stream)
{
    r->state = 0u;
    r->inc = (stream << 1u) | 1u;
    pcg32_next(r);
    r->state += seed;
    pcg32_next(r);
}

/* Uniform float in [0, 1): 24 random mantissa bits, never rounds up to 1. */
static inline float pcg32_float(Pcg32 *r) { return (float)(pcg32_next(r) >> 8) * 0x1p-24f; }

/* Uniform integer in [0, n) without modulo bias (Lemire 2019). n > 0. */
static inline uint32_t pcg32_below(Pcg32 *r, uint32_t n)
{
    uint64_t m = (uint64_t)pcg32_next(r) * n;
    uint32_t l = (uint32_t)m;
    if (l < n) {
        uint32_t t = (-n) % n;
        while (l < t) {
            m = (uint64_t)pcg32_next(r) * n;
            l = (uint32_t)m;
        }
    }
    return (uint32_t)(m >> 32);
}

#endif
