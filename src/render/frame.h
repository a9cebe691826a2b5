/* Per-pixel sums of everything the output and the AOV layers are made of. Each worker adds
 * a pixel's samples of one pass once (accumulated in double first), so the sums do not
 * depend on the thread count.
 *
 * The colour and the sample counts are always there; the parts (direct, indirect, emission)
 * and the guides (albedo, normal, depth, hits) only when the frame is made with them
 * (frame_init_planes): a frame for users that read the image alone (`--filter none` without
 * AOV layers, render_reads.h) leaves them NULL, so their pages are neither populated nor
 * summed into (issue 22: 68 of a full frame's 84 bytes a pixel). */
#ifndef WEDGE_RENDER_FRAME_H
#define WEDGE_RENDER_FRAME_H

#include <stdbool.h>

typedef struct {
    int width, height;
    /* 3 floats per pixel; all but color NULL when the frame was made without them */
    float *color, *direct, *indirect, *emission, *albedo, *normal;
    /* 1 float per pixel; depth and hits NULL without the guides */
    float *depth;   /* sum of camera depth over samples that hit */
    float *hits;    /* samples that hit a surface */
    float *spp;     /* samples taken */
    bool guides_skipped; /* a pass left albedo, normal, depth and hits out (its users declared
                          * that they do not read them, render_reads.h): those sums are
                          * incomplete and must not be read (until frame_clear) */
} Frame;

/* Which sums a frame holds beside its colour and sample counts (frame_init_planes). */
enum {
    FRAME_PLANES_PARTS = 1u << 0,  /* direct, indirect, emission */
    FRAME_PLANES_GUIDES = 1u << 1, /* albedo, normal, depth, hits */
    FRAME_PLANES_ALL = FRAME_PLANES_PARTS | FRAME_PLANES_GUIDES,
};

/* Every sum (frame_init_planes with FRAME_PLANES_ALL). */
bool frame_init(Frame *f, int width, int height);
/* The colour and the counts, and the planes asked for; the others are NULL. Each sum is zeroed
 * and its pages are populated (zalloc) before any worker adds to it. */
bool frame_init_planes(Frame *f, int width, int height, unsigned planes);
/* The FRAME_PLANES_* bits of the planes f holds. */
unsigned frame_planes(const Frame *f);
/* One of a frame's sums: its array (NULL when the frame does not hold it) and floats a pixel. */
typedef struct {
    float *sum;
    int floats_per_pixel;
} FrameSum;
enum { FRAME_SUM_COUNT = 9 };
/* Every sum of f, in one fixed order (color, direct, indirect, emission, albedo, normal, depth,
 * hits, spp): the one list for the code that visits them all (clearing, cropping, exchanging). */
void frame_sums(const Frame *f, FrameSum out[FRAME_SUM_COUNT]);
void frame_free(Frame *f);
/* Clears all sums it holds to zero (and guides_skipped). */
void frame_clear(Frame *f);

/* Mean of a 3-channel sum (color, direct, ...) per pixel into out (3 floats per pixel);
 * pixels without samples are 0. Non-finite results become 0 and are counted. */
long frame_resolve3(const Frame *f, const float *sum3, float *out);
/* Unit mean normal (0 where no hit), mean depth over hits (0 where no hit); the frame must
 * hold the guides. */
long frame_resolve_normal(const Frame *f, float *out3);
long frame_resolve_depth(const Frame *f, float *out1);
/* Average samples per pixel over the image. */
double frame_spp_avg(const Frame *f);

#endif
