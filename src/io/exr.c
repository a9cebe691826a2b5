/* EXR files through the OpenEXR *C* API (libOpenEXRCore, openexr.h).
 *
 * Writing: one part, scanline (or single-level tiled on request), channels declared in
 * alphabetical order as the file format requires, header attributes, every chunk packed
 * by the library's default encode pipeline and compressed by it, except ZIP and ZIPS
 * chunks, which exr_zip.c compresses (libdeflate). The bytes go to a temporary
 * file next to the destination through our own write callback (io/atomic_file.h), so
 * the destination only ever holds a complete image.
 *
 * Reading: our own read callback (pread on a descriptor we opened, so errors name the
 * file and the library never opens anything itself), the default decode pipeline converts
 * half/float/uint to float for every compression the library knows. */
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include <openexr.h>

/* openexr.h and our contract io/image_io.h both define enumerators named EXR_ATTR_STRING,
 * EXR_ATTR_FLOAT and EXR_ATTR_INT. Keep OpenEXR's under other names, then let the
 * contract's own the plain names in this file. */
enum { OEXR_ATTR_STRING = EXR_ATTR_STRING, OEXR_ATTR_FLOAT = EXR_ATTR_FLOAT,
       OEXR_ATTR_DOUBLE = EXR_ATTR_DOUBLE, OEXR_ATTR_INT = EXR_ATTR_INT };
#define EXR_ATTR_STRING WEDGE_EXR_ATTR_STRING
#define EXR_ATTR_FLOAT WEDGE_EXR_ATTR_FLOAT
#define EXR_ATTR_INT WEDGE_EXR_ATTR_INT

#include "io/atomic_file.h"
#include "io/exr_zip.h"
#include "io/image_io.h"

/* The library reports details through a callback rather than return values; keep the
 * last message per thread so the Diag can carry it. */
static _Thread_local char exr_last_message[512];

static void on_exr_error(exr_const_context_t ctxt, exr_result_t code, const char *msg)
{
    (void)ctxt;
    snprintf(exr_last_message, sizeof exr_last_message, "%s (%s)", msg ? msg : "",
             exr_get_error_code_as_string(code));
}

static const char *exr_reason(exr_result_t rv)
{
    if (exr_last_message[0]) return exr_last_message;
    return exr_get_error_code_as_string(rv);
}

/* Refuse images whose planes could not be addressed with int pixel indices. */
static const long long EXR_MAX_PIXELS = 1LL << 28;

/* ------------------------------------------------------------------ writing */

static int64_t write_to_atomic_file(exr_const_context_t ctxt, void *userdata, const void *buffer,
                                    uint64_t size, uint64_t offset, exr_stream_error_func_ptr_t error_cb)
{
    AtomicFile *af = userdata;
    if (!atomic_file_pwrite(af, buffer, (size_t)size, (long long)offset)) {
        error_cb(ctxt, EXR_ERR_WRITE_IO, "write failed: %s", strerror(errno));
        return -1;
    }
    return (int64_t)size;
}

typedef struct {
    const ExrChannel *channels;
    int count;
} ChannelTable;

static int by_name(const void *a, const void *b)
{
    return strcmp(((const ExrChannel *)a)->name, ((const ExrChannel *)b)->name);
}

/* The caller's channel called name (the encoder lists channels in file order). */
static const ExrChannel *find_channel(const ChannelTable *t, const char *name)
{
    for (int i = 0; i < t->count; ++i)
        if (!strcmp(t->channels[i].name, name)) return &t->channels[i];
    return NULL;
}

/* Copies one chunk of a channel into scratch as the stored type: non-finite values
 * become 0 (counted), uint values are rounded and clamped to [0, 2^32-1]. */
static void pack_chunk(const ExrChannel *ch, int image_width, int x0, int y0, int w, int h,
                       ExrStoreType store, void *scratch, long *nonfinite)
{
    float *out_f = scratch;
    uint32_t *out_u = scratch;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            size_t src = ((size_t)(y0 + y) * (size_t)image_width + (size_t)(x0 + x)) * (size_t)ch->stride;
            float v = ch->data[src];
            if (!isfinite(v)) {
                v = 0.0f;
                ++*nonfinite;
            }
            size_t dst = (size_t)y * (size_t)w + (size_t)x;
            if (store == EXR_STORE_UINT) {
                double r = floor((double)v + 0.5);
                out_u[dst] = r <= 0.0 ? 0u : r >= 4294967295.0 ? 4294967295u : (uint32_t)r;
            } else {
                out_f[dst] = v; /* half: the library rounds float to half when packing */
            }
        }
}

/* The file format stores a chunk raw when compressing does not make it smaller, and
 * readers recognise that case by packed size == unpacked size. OpenEXR 3.1's C encoder
 * keeps a compressed chunk whose size equals the raw size, which readers then take for
 * raw data (seen with ZIP on tiny chunks). This hook runs the compressor (ours for ZIP and
 * ZIPS, the library's for the rest) and falls back to the raw bytes whenever compression
 * did not pay. */
typedef struct {
    exr_result_t (*library_compress)(exr_encode_pipeline_t *);
    ZipChunkCompressor *zip; /* ZIP/ZIPS chunks: ours (exr_zip.h), else NULL */
} CompressHook;

/* The encode pipeline's buffers (ours and the library's) come from malloc and go to free. */
static void *pipeline_alloc(exr_transcoding_pipeline_buffer_id_t id, size_t bytes)
{
    (void)id;
    return malloc(bytes);
}

static void pipeline_free(exr_transcoding_pipeline_buffer_id_t id, void *p)
{
    (void)id;
    free(p);
}

/* A ZIP chunk through zip_chunk_compress into the pipeline's compressed buffer, grown to
 * deflate's bound when it is smaller. */
static exr_result_t compress_zip_chunk(exr_encode_pipeline_t *enc, ZipChunkCompressor *zip)
{
    size_t bound = zip_chunk_bound(enc->packed_bytes);
    if (!enc->compressed_buffer || enc->compressed_alloc_size < bound) {
        free(enc->compressed_buffer);
        enc->compressed_alloc_size = 0;
        if (!(enc->compressed_buffer = malloc(bound))) return EXR_ERR_OUT_OF_MEMORY;
        enc->compressed_alloc_size = bound;
    }
    size_t out_bytes = 0;
    if (!zip_chunk_compress(zip, enc->packed_buffer, enc->packed_bytes, enc->compressed_buffer,
                            enc->compressed_alloc_size, &out_bytes))
        return EXR_ERR_OUT_OF_MEMORY;
    enc->compressed_bytes = out_bytes;
    return EXR_ERR_SUCCESS;
}

static exr_result_t compress_or_store_raw(exr_encode_pipeline_t *enc)
{
    const CompressHook *hook = enc->encoding_user_data;
    exr_result_t rv = hook->zip ? compress_zip_chunk(enc, hook->zip) : hook->library_compress(enc);
    if (rv != EXR_ERR_SUCCESS) return rv;
    if (enc->compressed_bytes >= enc->packed_bytes) {
        if (!enc->compressed_buffer || enc->compressed_alloc_size < enc->packed_bytes) return EXR_ERR_OUT_OF_MEMORY;
        memcpy(enc->compressed_buffer, enc->packed_buffer, enc->packed_bytes);
        enc->compressed_bytes = enc->packed_bytes;
    }
    return EXR_ERR_SUCCESS;
}

/* Packs and writes one chunk (scanline block or tile). */
static exr_result_t write_chunk(exr_context_t ctx, const exr_chunk_info_t *cinfo, int x0, int y0,
                                exr_encode_pipeline_t *enc, bool *first, const ChannelTable *table,
                                int image_width, ExrWriteOptions *opt, float **scratch, CompressHook *hook)
{
    exr_result_t rv = *first ? exr_encoding_initialize(ctx, 0, cinfo, enc)
                             : exr_encoding_update(ctx, 0, cinfo, enc);
    if (rv != EXR_ERR_SUCCESS) return rv;
    for (int c = 0; c < enc->channel_count; ++c) {
        exr_coding_channel_info_t *ci = &enc->channels[c];
        const ExrChannel *ch = find_channel(table, ci->channel_name);
        if (!ch) return EXR_ERR_INVALID_ARGUMENT;
        pack_chunk(ch, image_width, x0, y0, cinfo->width, cinfo->height, opt->store, scratch[c],
                   &opt->nonfinite_replaced);
        ci->encode_from_ptr = (const uint8_t *)scratch[c];
        ci->user_bytes_per_element = 4;
        ci->user_data_type = opt->store == EXR_STORE_UINT ? EXR_PIXEL_UINT : EXR_PIXEL_FLOAT;
        ci->user_pixel_stride = 4;
        ci->user_line_stride = 4 * cinfo->width;
    }
    if (*first) {
        rv = exr_encoding_choose_default_routines(ctx, 0, enc);
        if (rv != EXR_ERR_SUCCESS) return rv;
        if (enc->compress_fn) {
            hook->library_compress = enc->compress_fn;
            enc->alloc_fn = pipeline_alloc;
            enc->free_fn = pipeline_free;
            enc->encoding_user_data = hook;
            enc->compress_fn = compress_or_store_raw;
        }
        *first = false;
    }
    return exr_encoding_run(ctx, 0, enc);
}

static bool check_write_args(const char *path, int width, int height, const ExrChannel *channels,
                             int channel_count, const ExrAttr *attrs, int attr_count, Diag *err)
{
    SrcLoc loc = {path, 0, 0};
    if (width <= 0 || height <= 0 || (long long)width * height > EXR_MAX_PIXELS) {
        diag_set(err, WEDGE_EXIT_RUNTIME, loc, "cannot write a %dx%d image", width, height);
        return false;
    }
    if (channel_count <= 0 || !channels) {
        diag_set(err, WEDGE_EXIT_RUNTIME, loc, "an EXR needs at least one channel");
        return false;
    }
    for (int i = 0; i < channel_count; ++i) {
        if (!channels[i].name || !channels[i].name[0] || !channels[i].data || channels[i].stride <= 0) {
            diag_set(err, WEDGE_EXIT_RUNTIME, loc, "channel %d has no name, data or stride", i);
            return false;
        }
        if (strlen(channels[i].name) > 255) {
            diag_set(err, WEDGE_EXIT_RUNTIME, loc, "channel name longer than 255 bytes");
            return false;
        }
        for (int j = 0; j < i; ++j)
            if (!strcmp(channels[i].name, channels[j].name)) {
                diag_set(err, WEDGE_EXIT_RUNTIME, loc, "channel '%s' given twice", channels[i].name);
                return false;
            }
    }
    for (int i = 0; i < attr_count; ++i)
        if (!attrs[i].name || !attrs[i].name[0] || strlen(attrs[i].name) > 255 ||
            (attrs[i].type == EXR_ATTR_STRING && !attrs[i].s)) {
            diag_set(err, WEDGE_EXIT_RUNTIME, loc, "header attribute %d is malformed", i);
            return false;
        }
    return true;
}

bool exr_write_with(const char *path, int width, int height, const ExrChannel *channels,
                    int channel_count, const ExrAttr *attrs, int attr_count, ExrWriteOptions *opt,
                    Diag *err)
{
    SrcLoc loc = {path, 0, 0};
    opt->nonfinite_replaced = 0;
    if (!check_write_args(path, width, height, channels, channel_count, attrs, attr_count, err))
        return false;

    /* The file format wants the channel list sorted by name. */
    ExrChannel *sorted = malloc(sizeof *sorted * (size_t)channel_count);
    float **scratch = calloc((size_t)channel_count, sizeof *scratch);
    if (!sorted || !scratch) {
        free(sorted);
        free(scratch);
        diag_set(err, WEDGE_EXIT_RUNTIME, loc, "out of memory");
        return false;
    }
    memcpy(sorted, channels, sizeof *sorted * (size_t)channel_count);
    qsort(sorted, (size_t)channel_count, sizeof *sorted, by_name);
    ChannelTable table = {sorted, channel_count};

    AtomicFile af;
    if (!atomic_file_open(&af, path, err)) {
        free(sorted);
        free(scratch);
        return false;
    }

    exr_last_message[0] = '\0';
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = on_exr_error;
    init.user_data = &af;
    init.write_fn = write_to_atomic_file;
    exr_context_t ctx = NULL;
    exr_encode_pipeline_t enc = {0};
    bool enc_started = false, first = true;
    CompressHook hook = {NULL, NULL};
    bool zip = opt->compression == EXRC_ZIP || opt->compression == EXRC_ZIPS;
    int zip_level = opt->zip_level > 0 ? opt->zip_level : EXR_ZIP_LEVEL_DEFAULT;
    int part = 0;
    bool tiled = opt->tile_size > 0;

    exr_result_t rv = exr_start_write(&ctx, path, EXR_WRITE_FILE_DIRECTLY, &init);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_add_part(ctx, "", tiled ? EXR_STORAGE_TILED : EXR_STORAGE_SCANLINE, &part);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_initialize_required_attr_simple(ctx, part, width, height, (exr_compression_t)opt->compression);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_set_zip_compression_level(ctx, part, zip_level);
    if (rv == EXR_ERR_SUCCESS && zip && !(hook.zip = zip_chunk_compressor_create(zip_level))) rv = EXR_ERR_OUT_OF_MEMORY;
    if (rv == EXR_ERR_SUCCESS && tiled)
        rv = exr_set_tile_descriptor(ctx, part, (uint32_t)opt->tile_size, (uint32_t)opt->tile_size,
                                     EXR_TILE_ONE_LEVEL, EXR_TILE_ROUND_DOWN);
    bool long_names = false;
    for (int i = 0; i < channel_count; ++i) long_names |= strlen(sorted[i].name) > 31;
    for (int i = 0; i < attr_count; ++i) long_names |= strlen(attrs[i].name) > 31;
    if (rv == EXR_ERR_SUCCESS && long_names) rv = exr_set_longname_support(ctx, 1);
    exr_pixel_type_t ptype = opt->store == EXR_STORE_HALF   ? EXR_PIXEL_HALF
                             : opt->store == EXR_STORE_UINT ? EXR_PIXEL_UINT
                                                            : EXR_PIXEL_FLOAT;
    for (int i = 0; i < channel_count && rv == EXR_ERR_SUCCESS; ++i)
        rv = exr_add_channel(ctx, part, sorted[i].name, ptype, EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1);
    for (int i = 0; i < attr_count && rv == EXR_ERR_SUCCESS; ++i) {
        const ExrAttr *a = &attrs[i];
        if (a->type == EXR_ATTR_STRING)
            rv = exr_attr_set_string(ctx, part, a->name, a->s);
        else if (a->type == EXR_ATTR_FLOAT)
            rv = exr_attr_set_float(ctx, part, a->name, isfinite(a->f) ? (float)a->f : 0.0f);
        else
            rv = exr_attr_set_int(ctx, part, a->name, a->i);
    }
    if (rv == EXR_ERR_SUCCESS) rv = exr_write_header(ctx);

    /* One scratch plane per channel, as large as the largest chunk. */
    int32_t lines_per_chunk = 1;
    if (rv == EXR_ERR_SUCCESS && !tiled) rv = exr_get_scanlines_per_chunk(ctx, part, &lines_per_chunk);
    size_t chunk_px = tiled ? (size_t)opt->tile_size * (size_t)opt->tile_size
                            : (size_t)width * (size_t)lines_per_chunk;
    for (int c = 0; c < channel_count && rv == EXR_ERR_SUCCESS; ++c)
        if (!(scratch[c] = malloc(chunk_px * 4))) rv = EXR_ERR_OUT_OF_MEMORY;

    exr_chunk_info_t cinfo;
    if (!tiled) {
        for (int y = 0; y < height && rv == EXR_ERR_SUCCESS; y += lines_per_chunk) {
            rv = exr_write_scanline_chunk_info(ctx, part, y, &cinfo);
            if (rv == EXR_ERR_SUCCESS) {
                enc_started = true;
                rv = write_chunk(ctx, &cinfo, 0, y, &enc, &first, &table, width, opt, scratch, &hook);
            }
        }
    } else {
        int ts = opt->tile_size;
        for (int ty = 0; ty * ts < height && rv == EXR_ERR_SUCCESS; ++ty)
            for (int tx = 0; tx * ts < width && rv == EXR_ERR_SUCCESS; ++tx) {
                rv = exr_write_tile_chunk_info(ctx, part, tx, ty, 0, 0, &cinfo);
                if (rv == EXR_ERR_SUCCESS) {
                    enc_started = true;
                    rv = write_chunk(ctx, &cinfo, tx * ts, ty * ts, &enc, &first, &table, width, opt, scratch,
                                     &hook);
                }
            }
    }
    if (enc_started) exr_encoding_destroy(ctx, &enc);
    /* exr_finish writes the chunk offset table: its failure is a failed write too. */
    exr_result_t finish_rv = ctx ? exr_finish(&ctx) : EXR_ERR_SUCCESS;
    if (rv == EXR_ERR_SUCCESS) rv = finish_rv;

    for (int c = 0; c < channel_count; ++c) free(scratch[c]);
    free(scratch);
    free(sorted);
    zip_chunk_compressor_free(hook.zip);
    if (rv != EXR_ERR_SUCCESS) {
        diag_set(err, WEDGE_EXIT_RUNTIME, loc, "cannot write EXR: %s", exr_reason(rv));
        atomic_file_abort(&af);
        return false;
    }
    return atomic_file_commit(&af, err);
}

bool exr_write(const char *path, int width, int height, const ExrChannel *channels, int channel_count,
               const ExrAttr *attrs, int attr_count, Diag *err)
{
    ExrWriteOptions opt = {EXR_STORE_FLOAT, EXRC_ZIP, 0, 0, 0};
    return exr_write_with(path, width, height, channels, channel_count, attrs, attr_count, &opt, err);
}

/* ------------------------------------------------------------------ reading */

typedef struct {
    int fd;
    int64_t size;
} ReadStream;

static int64_t read_from_fd(exr_const_context_t ctxt, void *userdata, void *buffer, uint64_t size,
                            uint64_t offset, exr_stream_error_func_ptr_t error_cb)
{
    ReadStream *rs = userdata;
    uint8_t *p = buffer;
    uint64_t done = 0;
    while (done < size) {
        ssize_t n = pread(rs->fd, p + done, (size_t)(size - done), (off_t)(offset + done));
        if (n < 0) {
            if (errno == EINTR) continue;
            error_cb(ctxt, EXR_ERR_READ_IO, "read failed: %s", strerror(errno));
            return -1;
        }
        if (n == 0) break; /* end of file: the library checks the count */
        done += (uint64_t)n;
    }
    return (int64_t)done;
}

static int64_t size_of_fd(exr_const_context_t ctxt, void *userdata)
{
    (void)ctxt;
    return ((ReadStream *)userdata)->size;
}

static char *dup_string(const char *s)
{
    size_t n = strlen(s) + 1;
    char *d = malloc(n);
    if (d) memcpy(d, s, n);
    return d;
}

void exr_image_free(ExrImage *img)
{
    if (!img) return;
    for (int c = 0; c < img->channel_count; ++c) {
        if (img->names) free(img->names[c]);
        if (img->planes) free(img->planes[c]);
    }
    free(img->names);
    free(img->planes);
    for (int i = 0; i < img->attr_count; ++i) {
        free((char *)img->attrs[i].name);
        free((char *)img->attrs[i].s);
    }
    free(img->attrs);
    memset(img, 0, sizeof *img);
}

/* The largest ratio of a chunk's unpacked to packed size any EXR codec produces (deflate's
 * limit is 1032:1), with a margin. */
#define EXR_MAX_EXPANSION 1100ull

/* Decodes one chunk into the planes; (x0, y0) is its corner relative to the data window. */
static exr_result_t read_chunk(exr_const_context_t ctx, const exr_chunk_info_t *cinfo, int x0, int y0,
                               exr_decode_pipeline_t *dec, bool *first, ExrImage *img)
{
    if (x0 < 0 || y0 < 0 || x0 + cinfo->width > img->width || y0 + cinfo->height > img->height)
        return EXR_ERR_CORRUPT_CHUNK; /* never write outside the planes */
    /* No codec expands data more than deflate does (about 1032:1): a chunk that claims to
     * unpack to more is corrupt, and decoding it would allocate what it claims (1.3 GB from a
     * 2 KB file, found by tools/fuzz-readers exr). */
    if (cinfo->unpacked_size > cinfo->packed_size * EXR_MAX_EXPANSION + 4096) return EXR_ERR_CORRUPT_CHUNK;
    exr_result_t rv = *first ? exr_decoding_initialize(ctx, 0, cinfo, dec)
                             : exr_decoding_update(ctx, 0, cinfo, dec);
    if (rv != EXR_ERR_SUCCESS) return rv;
    for (int c = 0; c < dec->channel_count; ++c) {
        exr_coding_channel_info_t *ci = &dec->channels[c];
        ci->decode_to_ptr = NULL;
        for (int k = 0; k < img->channel_count; ++k)
            if (!strcmp(img->names[k], ci->channel_name)) {
                float *dst = img->planes[k] + (size_t)y0 * (size_t)img->width + (size_t)x0;
                ci->decode_to_ptr = (uint8_t *)dst;
                break;
            }
        ci->user_bytes_per_element = 4;
        ci->user_data_type = EXR_PIXEL_FLOAT;
        ci->user_pixel_stride = 4;
        ci->user_line_stride = 4 * img->width;
    }
    if (*first) {
        rv = exr_decoding_choose_default_routines(ctx, 0, dec);
        if (rv != EXR_ERR_SUCCESS) return rv;
        *first = false;
    }
    return exr_decoding_run(ctx, 0, dec);
}

static void read_attributes(exr_const_context_t ctx, ExrImage *img)
{
    int32_t count = 0;
    if (exr_get_attribute_count(ctx, 0, &count) != EXR_ERR_SUCCESS || count <= 0) return;
    img->attrs = calloc((size_t)count, sizeof *img->attrs);
    if (!img->attrs) return;
    for (int32_t i = 0; i < count; ++i) {
        const exr_attribute_t *a = NULL;
        if (exr_get_attribute_by_index(ctx, 0, EXR_ATTR_LIST_FILE_ORDER, i, &a) != EXR_ERR_SUCCESS || !a)
            continue;
        ExrAttr out = {0};
        int type = (int)a->type;
        if (type == OEXR_ATTR_STRING && a->string) {
            out.type = EXR_ATTR_STRING;
            char *s = malloc((size_t)a->string->length + 1);
            if (!s) continue;
            memcpy(s, a->string->str, (size_t)a->string->length);
            s[a->string->length] = '\0';
            out.s = s;
        } else if (type == OEXR_ATTR_FLOAT) {
            out.type = EXR_ATTR_FLOAT;
            out.f = a->f;
        } else if (type == OEXR_ATTR_DOUBLE) {
            out.type = EXR_ATTR_FLOAT;
            out.f = a->d;
        } else if (type == OEXR_ATTR_INT) {
            out.type = EXR_ATTR_INT;
            out.i = a->i;
        } else {
            continue;
        }
        out.name = dup_string(a->name);
        if (!out.name) {
            free((char *)out.s);
            continue;
        }
        img->attrs[img->attr_count++] = out;
    }
}

bool exr_read(const char *path, ExrImage *img, Diag *err)
{
    memset(img, 0, sizeof *img);
    SrcLoc loc = {path, 0, 0};
    ReadStream rs = {open(path, O_RDONLY | O_CLOEXEC), 0};
    if (rs.fd < 0) {
        diag_set(err, WEDGE_EXIT_INPUT, loc, "cannot open: %s", strerror(errno));
        return false;
    }
    struct stat st;
    if (fstat(rs.fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        diag_set(err, WEDGE_EXIT_INPUT, loc, "not a regular file");
        close(rs.fd);
        return false;
    }
    rs.size = (int64_t)st.st_size;

    exr_last_message[0] = '\0';
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = on_exr_error;
    init.user_data = &rs;
    init.read_fn = read_from_fd;
    init.size_fn = size_of_fd;
    /* A truncated file is an error to report, not something to patch up silently. */
    init.flags = EXR_CONTEXT_FLAG_DISABLE_CHUNK_RECONSTRUCTION;
    exr_context_t ctx = NULL;
    exr_result_t rv = exr_start_read(&ctx, path, &init);
    const char *problem = NULL;
    exr_storage_t storage = EXR_STORAGE_SCANLINE;
    exr_attr_box2i_t dw;
    memset(&dw, 0, sizeof dw);
    const exr_attr_chlist_t *chlist = NULL;
    if (rv == EXR_ERR_SUCCESS) rv = exr_get_storage(ctx, 0, &storage);
    if (rv == EXR_ERR_SUCCESS && storage != EXR_STORAGE_SCANLINE && storage != EXR_STORAGE_TILED)
        problem = "deep EXR files are not supported";
    exr_compression_t compression = EXR_COMPRESSION_NONE;
    if (rv == EXR_ERR_SUCCESS && !problem) rv = exr_get_compression(ctx, 0, &compression);
    if (rv == EXR_ERR_SUCCESS && !problem &&
        (compression == EXR_COMPRESSION_DWAA || compression == EXR_COMPRESSION_DWAB))
        problem = "DWAA/DWAB compression cannot be decoded by the OpenEXR 3.1 C library; re-save the "
                  "file with ZIP or PIZ compression";
    if (rv == EXR_ERR_SUCCESS && !problem) rv = exr_get_data_window(ctx, 0, &dw);
    if (rv == EXR_ERR_SUCCESS && !problem) rv = exr_get_channels(ctx, 0, &chlist);
    long long w = (long long)dw.max.x - dw.min.x + 1, h = (long long)dw.max.y - dw.min.y + 1;
    if (rv == EXR_ERR_SUCCESS && !problem && (w <= 0 || h <= 0 || w * h > EXR_MAX_PIXELS))
        problem = "image size out of range";
    if (rv == EXR_ERR_SUCCESS && !problem && (!chlist || chlist->num_channels <= 0))
        problem = "no channels";
    if (rv == EXR_ERR_SUCCESS && !problem) {
        for (int c = 0; c < chlist->num_channels; ++c)
            if (chlist->entries[c].x_sampling != 1 || chlist->entries[c].y_sampling != 1)
                problem = "subsampled channels are not supported";
    }
    /* Every pixel comes out of some chunk's packed bytes, no chunk unpacks to more than
     * read_chunk allows (EXR_MAX_EXPANSION times its packed size, plus 4096 bytes), and no
     * sample is smaller than a half: a header whose image needs more than the whole file can
     * hold is corrupt, refused before its planes are allocated (a 457-byte file declaring
     * 16,187,399 x 5 pixels took 5.5 s under ASan, found by tools/fuzz-readers exr). */
    int32_t chunks = 0;
    if (rv == EXR_ERR_SUCCESS && !problem) rv = exr_get_chunk_count(ctx, 0, &chunks);
    if (rv == EXR_ERR_SUCCESS && !problem &&
        (unsigned long long)(w * h) * (unsigned long long)chlist->num_channels * 2ull >
            (unsigned long long)rs.size * EXR_MAX_EXPANSION + 4096ull * (unsigned long long)(chunks > 0 ? chunks : 1))
        problem = "the header's image is larger than the file's data could hold (truncated or corrupt)";
    if (rv == EXR_ERR_SUCCESS && !problem) {
        img->width = (int)w;
        img->height = (int)h;
        int n = chlist->num_channels;
        img->names = calloc((size_t)n, sizeof *img->names);
        img->planes = calloc((size_t)n, sizeof *img->planes);
        if (!img->names || !img->planes) rv = EXR_ERR_OUT_OF_MEMORY;
        for (int c = 0; c < n && rv == EXR_ERR_SUCCESS; ++c) {
            img->channel_count = c + 1;
            img->names[c] = dup_string(chlist->entries[c].name.str);
            img->planes[c] = calloc((size_t)(w * h), sizeof(float));
            if (!img->names[c] || !img->planes[c]) rv = EXR_ERR_OUT_OF_MEMORY;
        }
    }
    exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
    bool first = true, dec_started = false;
    exr_chunk_info_t cinfo;
    if (rv == EXR_ERR_SUCCESS && !problem && storage == EXR_STORAGE_SCANLINE) {
        int32_t lines = 1;
        rv = exr_get_scanlines_per_chunk(ctx, 0, &lines);
        for (long long y = dw.min.y; y <= dw.max.y && rv == EXR_ERR_SUCCESS; y += lines) {
            rv = exr_read_scanline_chunk_info(ctx, 0, (int)y, &cinfo);
            if (rv != EXR_ERR_SUCCESS) break;
            dec_started = true;
            rv = read_chunk(ctx, &cinfo, 0, (int)(cinfo.start_y - dw.min.y), &dec, &first, img);
        }
    } else if (rv == EXR_ERR_SUCCESS && !problem) {
        /* Tiled: level 0 of a mip/rip-mapped file is the full-resolution image. */
        int32_t tw = 0, th = 0;
        rv = exr_get_tile_sizes(ctx, 0, 0, 0, &tw, &th);
        if (rv == EXR_ERR_SUCCESS && (tw <= 0 || th <= 0)) problem = "bad tile size";
        for (int ty = 0; !problem && (long long)ty * th < h && rv == EXR_ERR_SUCCESS; ++ty)
            for (int tx = 0; (long long)tx * tw < w && rv == EXR_ERR_SUCCESS; ++tx) {
                rv = exr_read_tile_chunk_info(ctx, 0, tx, ty, 0, 0, &cinfo);
                if (rv != EXR_ERR_SUCCESS) break;
                dec_started = true;
                rv = read_chunk(ctx, &cinfo, tx * tw, ty * th, &dec, &first, img);
            }
    }
    if (dec_started) exr_decoding_destroy(ctx, &dec);
    if (rv == EXR_ERR_SUCCESS && !problem) read_attributes(ctx, img);
    if (ctx) exr_finish(&ctx);
    close(rs.fd);
    if (rv != EXR_ERR_SUCCESS || problem) {
        diag_set(err, WEDGE_EXIT_INPUT, loc, "cannot read EXR: %s", problem ? problem : exr_reason(rv));
        exr_image_free(img);
        return false;
    }
    return true;
}

const float *exr_image_channel(const ExrImage *img, const char *name)
{
    for (int c = 0; c < img->channel_count; ++c)
        if (!strcmp(img->names[c], name)) return img->planes[c];
    return NULL;
}

const ExrAttr *exr_image_attr(const ExrImage *img, const char *name)
{
    for (int i = 0; i < img->attr_count; ++i)
        if (!strcmp(img->attrs[i].name, name)) return &img->attrs[i];
    return NULL;
}

/* "R, G, B" style list of the channels, for error messages. */
static void list_channels(const ExrImage *img, char *buf, size_t size)
{
    buf[0] = '\0';
    size_t used = 0;
    for (int c = 0; c < img->channel_count && used < size; ++c)
        used += (size_t)snprintf(buf + used, size - used, "%s%s", c ? ", " : "", img->names[c]);
}

bool exr_read_channel(const char *path, const char *channel, int *width, int *height, float **data,
                      Diag *err)
{
    ExrImage img;
    if (!exr_read(path, &img, err)) return false;
    for (int c = 0; c < img.channel_count; ++c)
        if (!strcmp(img.names[c], channel)) {
            *width = img.width;
            *height = img.height;
            *data = img.planes[c];
            img.planes[c] = NULL; /* hand the plane over */
            exr_image_free(&img);
            return true;
        }
    char names[1024];
    list_channels(&img, names, sizeof names);
    SrcLoc loc = {path, 0, 0};
    diag_set(err, WEDGE_EXIT_INPUT, loc, "no channel '%s' (the file has: %s)", channel, names);
    exr_image_free(&img);
    return false;
}

bool exr_read_rgb(const char *path, int *width, int *height, float **rgb, Diag *err)
{
    ExrImage img;
    if (!exr_read(path, &img, err)) return false;
    const float *r = exr_image_channel(&img, "R"), *g = exr_image_channel(&img, "G"),
                *b = exr_image_channel(&img, "B");
    if (!(r && g && b)) {
        const float *y = exr_image_channel(&img, "Y");
        if (!y) {
            char names[1024];
            list_channels(&img, names, sizeof names);
            SrcLoc loc = {path, 0, 0};
            diag_set(err, WEDGE_EXIT_INPUT, loc, "no R, G, B or Y channels (the file has: %s)", names);
            exr_image_free(&img);
            return false;
        }
        r = g = b = y; /* a luminance-only file is grey */
    }
    size_t n = (size_t)img.width * (size_t)img.height;
    float *out = malloc(n * 3 * sizeof *out);
    if (!out) {
        SrcLoc loc = {path, 0, 0};
        diag_set(err, WEDGE_EXIT_RUNTIME, loc, "out of memory");
        exr_image_free(&img);
        return false;
    }
    for (size_t i = 0; i < n; ++i) {
        out[3 * i + 0] = r[i];
        out[3 * i + 1] = g[i];
        out[3 * i + 2] = b[i];
    }
    *width = img.width;
    *height = img.height;
    *rgb = out;
    exr_image_free(&img);
    return true;
}
