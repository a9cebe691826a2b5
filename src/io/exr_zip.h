/* EXR's ZIP chunk compression (ZIP: 16 scanlines a chunk, ZIPS: 1), done here instead of by
 * OpenEXR 3.1's encoder.
 *
 * The format (the OpenEXR file layout's "ZIP compression"): the chunk's packed bytes b[0..n)
 * are split into the bytes at even offsets followed by those at odd offsets; each byte of
 * that sequence after the first is replaced by its difference to the one before, plus 128,
 * modulo 256; the result is one zlib stream. Here the split and the differences are one
 * fused pass (OpenEXR 3.1 makes two scalar passes), and the stream comes from libdeflate,
 * which at level 1 takes about half of zlib's time (zlib through the library before:
 * deflateInit and a fresh ~256 KB state a chunk). Any zlib decoder reads the stream, so
 * readers see the same pixels; the bytes differ from zlib's (files ~1% smaller). */
#ifndef WEDGE_IO_EXR_ZIP_H
#define WEDGE_IO_EXR_ZIP_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct ZipChunkCompressor ZipChunkCompressor;

/* A compressor at deflate level 1-9 (libdeflate's levels); NULL when out of memory. */
ZipChunkCompressor *zip_chunk_compressor_create(int level);
void zip_chunk_compressor_free(ZipChunkCompressor *z);

/* The largest compressed size of n packed bytes (deflate's bound). */
size_t zip_chunk_bound(size_t n);

/* Compresses packed[0..n) into out[0..out_capacity); *out_bytes gets the compressed size.
 * When out_capacity is too small, *out_bytes is n (the caller then stores the chunk raw, as
 * for a chunk that does not shrink). False when out of memory. */
bool zip_chunk_compress(ZipChunkCompressor *z, const uint8_t *packed, size_t n, uint8_t *out, size_t out_capacity,
                        size_t *out_bytes);

/* The split and difference transform alone: predicted[0..n) from packed[0..n). */
void zip_chunk_predict(const uint8_t *packed, size_t n, uint8_t *predicted);

#endif
