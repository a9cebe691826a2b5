/* EXR's ZIP chunk compression (see exr_zip.h). */
#include "io/exr_zip.h"

#include <stdlib.h>
#include <libdeflate.h>

struct ZipChunkCompressor {
    int level;
    struct libdeflate_compressor *deflater;
    uint8_t *predicted; /* the transformed chunk */
    size_t predicted_capacity;
};

ZipChunkCompressor *zip_chunk_compressor_create(int level)
{
    ZipChunkCompressor *z = calloc(1, sizeof *z);
    if (!z) return NULL;
    z->level = level;
    if (!(z->deflater = libdeflate_alloc_compressor(level))) {
        free(z);
        return NULL;
    }
    return z;
}

void zip_chunk_compressor_free(ZipChunkCompressor *z)
{
    if (!z) return;
    libdeflate_free_compressor(z->deflater);
    free(z->predicted);
    free(z);
}

size_t zip_chunk_bound(size_t n) { return libdeflate_zlib_compress_bound(NULL, n); }

/* Position i of the split sequence holds b[2i] for i < half (half = ceil(n / 2)) and
 * b[2 (i - half) + 1] after; the byte before position i in that sequence is b[2i - 2] in the
 * even half, b[n - 1 or n - 2] (the last even offset) at i = half, and b[2 (i - half) - 1]
 * in the odd half. Each half is one loop over a stride-2 read, which GCC vectorises. */
void zip_chunk_predict(const uint8_t *packed, size_t n, uint8_t *predicted)
{
    if (n == 0) return;
    size_t half = (n + 1) / 2, odd = n / 2;
    predicted[0] = packed[0];
    for (size_t i = 1; i < half; ++i) predicted[i] = (uint8_t)(packed[2 * i] - packed[2 * i - 2] + 128);
    if (odd == 0) return;
    uint8_t *odd_out = predicted + half;
    odd_out[0] = (uint8_t)(packed[1] - packed[2 * (half - 1)] + 128);
    for (size_t i = 1; i < odd; ++i) odd_out[i] = (uint8_t)(packed[2 * i + 1] - packed[2 * i - 1] + 128);
}

bool zip_chunk_compress(ZipChunkCompressor *z, const uint8_t *packed, size_t n, uint8_t *out, size_t out_capacity,
                        size_t *out_bytes)
{
    *out_bytes = n;
    if (z->predicted_capacity < n) {
        free(z->predicted);
        z->predicted_capacity = 0;
        if (!(z->predicted = malloc(n ? n : 1))) return false;
        z->predicted_capacity = n;
    }
    zip_chunk_predict(packed, n, z->predicted);
    size_t written = libdeflate_zlib_compress(z->deflater, z->predicted, n, out, out_capacity);
    if (written > 0) *out_bytes = written; /* 0: out of room, stored raw */
    return true;
}
