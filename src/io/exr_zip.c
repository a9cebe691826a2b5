/* EXR's ZIP chunk compression (see exr_zip.h). */
#include "io/exr_zip.h"

#include <stdlib.h>
#include <zlib.h>

struct ZipChunkCompressor {
    int level;
    bool stream_ready; /* stream initialised: reset it for the next chunk */
    z_stream stream;
    uint8_t *predicted; /* the transformed chunk */
    size_t predicted_capacity;
};

ZipChunkCompressor *zip_chunk_compressor_create(int level)
{
    ZipChunkCompressor *z = calloc(1, sizeof *z);
    if (z) z->level = level;
    return z;
}

void zip_chunk_compressor_free(ZipChunkCompressor *z)
{
    if (!z) return;
    if (z->stream_ready) deflateEnd(&z->stream);
    free(z->predicted);
    free(z);
}

size_t zip_chunk_bound(size_t n) { return (size_t)compressBound((uLong)n); }

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
    /* compress2's parameters: deflateInit at the level (15-bit window, memory level 8,
     * default strategy); a reset state gives the same stream as a fresh one */
    int zr = z->stream_ready ? deflateReset(&z->stream) : deflateInit(&z->stream, z->level);
    if (zr != Z_OK) return false;
    z->stream_ready = true;
    z->stream.next_in = z->predicted;
    z->stream.avail_in = (uInt)n;
    z->stream.next_out = out;
    z->stream.avail_out = (uInt)out_capacity;
    zr = deflate(&z->stream, Z_FINISH);
    if (zr == Z_STREAM_END) *out_bytes = (size_t)z->stream.total_out;
    else if (zr != Z_OK && zr != Z_BUF_ERROR) return false; /* Z_OK / Z_BUF_ERROR: out of room, stored raw */
    return true;
}
