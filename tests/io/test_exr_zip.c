/* EXR's ZIP chunk compression (io/exr_zip.h) against the format written out step by step:
 * the split into even and odd offsets, then the differences plus 128, by plain loops over a
 * copy; and the compressed stream decoded by zlib (another implementation than the
 * compressor's) back to those bytes. Sizes 0-300 (odd and even, both halves' boundaries)
 * and a chunk of 16 scanlines; an output buffer too small reports the raw size. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "check.h"
#include "io/exr_zip.h"

/* The format's transform, one step at a time, as the OpenEXR file layout describes it. */
static void reference_predict(const uint8_t *packed, size_t n, uint8_t *out)
{
    uint8_t *split = malloc(n ? n : 1);
    size_t at = 0;
    for (size_t i = 0; i < n; i += 2) split[at++] = packed[i];
    for (size_t i = 1; i < n; i += 2) split[at++] = packed[i];
    for (size_t i = 0; i < n; ++i) out[i] = i == 0 ? split[0] : (uint8_t)((split[i] - split[i - 1] + 384) % 256);
    free(split);
}

static uint64_t rng_state = 0x9e3779b97f4a7c15ull;
static uint8_t next_byte(void)
{
    rng_state ^= rng_state << 13, rng_state ^= rng_state >> 7, rng_state ^= rng_state << 17;
    return (uint8_t)(rng_state >> 24);
}

/* Bytes like a packed float chunk: runs of one value (the alpha plane), slowly changing
 * high bytes and noisy low bytes. */
static void fill_chunk(uint8_t *b, size_t n)
{
    for (size_t i = 0; i < n; ++i) b[i] = i < n / 4 ? 0x3f : (i % 4 == 3 ? (uint8_t)(0x3e + (i / 512) % 3) : next_byte());
}

static void check_size(ZipChunkCompressor *z, size_t n)
{
    uint8_t *packed = malloc(n + 1), *want = malloc(n + 1), *got = malloc(n + 1), *back = malloc(n + 1);
    size_t cap = zip_chunk_bound(n);
    uint8_t *out = malloc(cap);
    fill_chunk(packed, n);
    reference_predict(packed, n, want);
    zip_chunk_predict(packed, n, got);
    CHECK(memcmp(want, got, n) == 0);
    size_t out_bytes = 0;
    CHECK(zip_chunk_compress(z, packed, n, out, cap, &out_bytes));
    CHECK(out_bytes > 0 && out_bytes <= cap);
    uLongf back_bytes = (uLongf)n;
    CHECK(uncompress(back, &back_bytes, out, (uLong)out_bytes) == Z_OK);
    CHECK(back_bytes == n && memcmp(back, want, n) == 0);
    free(packed), free(want), free(got), free(back), free(out);
}

static void test_sizes(void)
{
    ZipChunkCompressor *z = zip_chunk_compressor_create(1);
    CHECK(z != NULL);
    for (size_t n = 0; n <= 300; ++n) check_size(z, n);
    check_size(z, 16 * 512 * 4 * 4); /* ZIP: 16 scanlines of 512 pixels, 4 float channels */
    check_size(z, 3);                 /* a small chunk after a large one (the reused state) */
    zip_chunk_compressor_free(z);
    z = zip_chunk_compressor_create(9);
    check_size(z, 4096);
    zip_chunk_compressor_free(z);
}

static void test_no_room(void)
{
    ZipChunkCompressor *z = zip_chunk_compressor_create(1);
    enum { N = 1000 };
    uint8_t packed[N], out[8];
    for (int i = 0; i < N; ++i) packed[i] = next_byte();
    size_t out_bytes = 0;
    CHECK(zip_chunk_compress(z, packed, N, out, sizeof out, &out_bytes));
    CHECK(out_bytes == N);
    zip_chunk_compressor_free(z);
}

int main(void)
{
    test_sizes();
    test_no_room();
    return check_failures ? 1 : 0;
}
