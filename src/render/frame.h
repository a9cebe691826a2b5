/* Per-pixel sums of everything the output and the AOV layers are made of. Each worker adds
 * a pixel's samples of one pass once (accumulated in double first), so the sums do not
 * depend on the thread count. */
#ifndef WEDGE_RENDER_FRAME_H
#define WEDGE_RENDER_FRAME_H

#include <stdbool.h>

typedef struct {
    int width, height;
    /* 3 floats per pixel */
    float *color, *direct, *indirect, *emission, *albedo, *normal;
    /* 1 float per pixel */
    float *depth;   /* sum of camera depth over samples that hit */
    float *hits;    /* samples that hit a surface */
    float *spp;     /* samples taken */
    bool guides_skipped; /* a pass left albedo, normal, depth and hits out (its users declared
                          * that they do not read them, render_reads.h): those sums are
                          * incomplete and must not be read (until frame_clear) */
} Frame;

bool frame_init(Frame *f, int width, int height);
void frame_free(Frame *f);
/* Clears all sums to zero (and guides_skipped). */
void frame_clear(Frame *f);

/* Mean of a 3-channel sum (color, direct, ...) per pixel into out (3 floats per pixel);
 * pixels without samples are 0. Non-finite results become 0 and are counted. */
long frame_resolve3(const Frame *f, const float *sum3, float *out);
/* Unit mean normal (0 where no hit), mean depth over hits (0 where no hit). */
long frame_resolve_normal(const Frame *f, float *out3);
long frame_resolve_depth(const Frame *f, float *out1);
/* Average samples per pixel over the image. */
double frame_spp_avg(const Frame *f);

#endif
