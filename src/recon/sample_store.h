/* Per-sample records for the methods that filter individual samples (FSF, LR), owned by the
 * pipeline (DESIGN.md section 9): struct of arrays, only the fields the selected methods
 * declare, allocated only when one asks, sized before rendering from the largest sample
 * count a pixel will take, and refused with a clear message when it would exceed the memory
 * limit (`wedge render --mem-limit`), never left to swap.
 *
 * Layout: field f of sample k of pixel i is at field(f)[(i * capacity + k) * components(f) + c].
 * The store is a SampleSink; a pixel's samples arrive in order and never concurrently
 * (sample_record.h), so its counter needs no lock. Samples past a pixel's capacity are not
 * kept, and counted. */
#ifndef WEDGE_RECON_SAMPLE_STORE_H
#define WEDGE_RECON_SAMPLE_STORE_H

#include <stdbool.h>
#include <stddef.h>

#include "core/diag.h"
#include "recon/dist.h"
#include "render/sample_record.h"

/* The fields a method may ask for. */
enum {
    SAMPLE_FIELD_FILM = 1u << 0,      /* px_raster, py_raster (pixels) */
    SAMPLE_FIELD_LENS = 1u << 1,      /* lens_u, lens_v (unit disk) */
    SAMPLE_FIELD_TIME = 1u << 2,      /* normalised shutter time */
    SAMPLE_FIELD_DEPTH = 1u << 3,     /* camera depth of the first hit (world; +inf on a miss) */
    SAMPLE_FIELD_RADIANCE = 1u << 4,  /* L (rgb) */
    SAMPLE_FIELD_DIRECT = 1u << 5,    /* direct light at the first hit (rgb) */
    SAMPLE_FIELD_INDIRECT = 1u << 6,  /* indirect light at the first hit (rgb) */
    SAMPLE_FIELD_POSITION = 1u << 7,  /* first hit (world) */
    SAMPLE_FIELD_NORMAL = 1u << 8,    /* shading normal at the first hit */
    SAMPLE_FIELD_LIGHT = 1u << 9,     /* the shadow ray's light point (world), d_light, d_occluder
                                       * (world, +inf when unoccluded); needs ray geometry */
    SAMPLE_FIELD_BOUNCE = 1u << 10,   /* the bounce ray's direction and hit distance; needs ray geometry */
    SAMPLE_FIELD_MOTION = 1u << 11,   /* screen velocity of the first hit (px per unit shutter time) */
    SAMPLE_FIELD_SHADING = 1u << 12,  /* beside a shading filter, what LR's samples take its light
                                       * by (lr_shading.h): the first hit's albedo (rgb) and
                                       * object id (-1: a miss), and the delta lights' direct
                                       * light (rgb, part of the unfiltered light); kept only in
                                       * frames where a shading effect is filtered */
    /* Two records in the order a reader that moves samples across pixels (LR, lr_partition.h's
     * LrPlace and LrKey) keeps them, so that it reads them in place instead of copying the
     * fields above into records of its own (the copy was 23 MB of fresh memory a frame, its page
     * faults 2.6% of the frame, at 256x192, 8 spp). The slots marked "the reader's" are left
     * for the reader to fill and are not written by sample_store_add. */
    SAMPLE_FIELD_LR_PLACE = 1u << 13, /* film x, y (pixels), lens u and -v (the lens v flipped:
                                       * raster y runs against camera y), normalised shutter
                                       * time, then 3 floats the reader's (LR: the light) */
    SAMPLE_FIELD_LR_KEY = 1u << 14,   /* camera depth (+inf on a miss), 1 float the reader's
                                       * (LR: the CoC slope), screen motion (2, as MOTION) */
    /* ... and the light the frame's shading filters replace, each kept only where its effect
     * is filtered (6 and 3 of the 16 floats the shading field had: no frame filters both in
     * LR's scenes but motion_defocus_soft_gi) */
    SAMPLE_FIELD_SHADING_DIRECT = 1u << 15,   /* the filterable direct light (rgb) and the first
                                               * hit's diffuse albedo (rgb: what it is demodulated
                                               * by, gbuffer_direct_albedo); soft shadows */
    SAMPLE_FIELD_SHADING_INDIRECT = 1u << 16, /* the filterable indirect light (rgb); indirect */
    SAMPLE_FIELD_COUNT_ = 17
};

typedef struct SampleStore SampleStore;

/* Floats per sample of one field (0 for a combination or an unknown bit). */
int sample_field_components(unsigned field);
/* Field names for messages ("film", "lens", ...). */
const char *sample_field_name(unsigned field);

/* Bytes a store of these fields needs for width x height pixels of up to capacity samples
 * each (SIZE_MAX on overflow). */
size_t sample_store_bytes(unsigned fields, int width, int height, int capacity);

/* The default memory limit: half the machine's physical memory. */
size_t sample_store_default_limit(void);

/* Allocates the store. Over mem_limit bytes: false with d set (exit 3), the message saying
 * how much it needs, the limit, and what to change (--res, --spp, --mem-limit). */
bool sample_store_create(unsigned fields, int width, int height, int capacity, size_t mem_limit,
                         SampleStore **out, Diag *d);
void sample_store_destroy(SampleStore *s);

/* The SampleSink callback (ctx = SampleStore *). */
void sample_store_add(void *ctx, int px, int py, const SampleRecord *r);

unsigned sample_store_fields(const SampleStore *s);
int sample_store_capacity(const SampleStore *s);
/* Samples kept for pixel index i (y * width + x). */
int sample_store_count(const SampleStore *s, size_t i);
/* The array of one field (NULL when the store does not hold it). */
const float *sample_store_field(const SampleStore *s, unsigned field);
/* The same, writable: for the reader's slots of SAMPLE_FIELD_LR_PLACE and SAMPLE_FIELD_LR_KEY. */
float *sample_store_field_mut(SampleStore *s, unsigned field);
/* The store's per-pixel arrays (the counts, then each field's), for gathering (dist.h);
 * returns how many (at most SAMPLE_FIELD_COUNT_ + 1). */
int sample_store_arrays(SampleStore *s, DistArray *out, int max);
/* Samples that arrived past a pixel's capacity (not kept). */
long long sample_store_dropped(const SampleStore *s);

#endif
