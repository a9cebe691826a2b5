/* The per-pixel guides every reconstruction method shares (DESIGN.md section 9), computed
 * once per frame by the pipeline:
 *
 *   frame     the renderer's per-pixel radiance sums (render_pass writes them: colour,
 *             direct, indirect, emission, albedo, samples taken)
 *   sums      what the pipeline's own sink adds per camera sample: surface hits, position,
 *             shading normal, depth and its square, object id and whether it varies, samples
 *             on unfilterable surfaces, and SampleRecord.unfiltered split into the direct and
 *             indirect parts the filters must not blur
 *   guides    resolved from the sums after each pass (gbuffer_resolve_guides): mean
 *             position and depth, unit normal and object id, whether the pixel saw a surface,
 *             whether its samples saw different surfaces ("mixed"), the world size of a pixel
 *             at its receiver, and the size of the visible scene
 *
 * The sink is called from the thread that owns the pixel (sample_record.h), so no locks. */
#ifndef WEDGE_RECON_GBUFFER_H
#define WEDGE_RECON_GBUFFER_H

#include <math.h>
#include <stdbool.h>
#include <stddef.h>

#include "render/camera.h"
#include "render/frame.h"
#include "render/sample_record.h"

/* What turns a camera-space depth into screen quantities (thin lens, pbrt-v4 conventions). */
typedef struct {
    float lens_radius_world;     /* 0: pinhole */
    float focal_distance_world;  /* depth of the plane in focus */
    float pixel_angle;           /* world size of a pixel at depth 1 (screen units per pixel) */
} ReconCamera;

ReconCamera recon_camera_from(const Camera *c);

/* Signed circle-of-confusion slope of a point at camera depth z (INFINITY allowed), pixels
 * per unit lens coordinate: (R / pixel_angle) (1/F - 1/z), negative in front of the focal
 * plane (docs/algorithms.md 3.1); 0 for a pinhole. */
float recon_coc_slope_px(const ReconCamera *cam, float depth_cam);

/* What the sink adds up for one pixel, kept together so that a sample touches two cache lines
 * rather than one per quantity (as ten separate arrays the sink was 4% of a soft-shadow
 * frame's time). */
typedef struct {
    float pos_sum[3], nrm_sum[3];
    float unf_direct_sum[3], unf_indirect_sum[3]; /* SampleRecord.unfiltered, split (and
                                                   * unfiltered_direct, in the direct sum) */
    float depth_sum;
    int hits;                     /* samples that hit a surface at a finite position */
    int object_id;                /* first hit's object id, -1 until a sample hits */
    int unfilterable;             /* samples whose first hit was unfilterable (dielectric, delta) */
    int glossy;                   /* samples whose first hit reflects mostly through a glossy lobe
                                   * (gbuffer_sample_glossy) */
    float albedo_sum, albedo_sq_sum; /* the first hits' albedo luminance and its square */
    double depth_sq_sum;
    unsigned char id_mixed;       /* a later hit had another object id */
} GBufferSums;

/* A mixed pixel's samples split by surface (docs/algorithms.md, "Mixed pixels: the first
 * surface filtered"): the pixel's first surface is the object its first hit saw (sums.object_id),
 * and the sink adds here the samples that are not on it (another object, an unfilterable hit, a
 * hit at a non-finite position). The first surface's sums are then the pixel's sums less these,
 * so a pixel that never sees a second surface writes nothing here (its pages stay untouched).
 * Only while gbuffer_track_split asks for it. */
typedef struct {
    float direct_sum[3], indirect_sum[3]; /* the light the filters read: direct and indirect less
                                           * gbuffer_unfiltered_split's parts */
    float albedo_sum[3];          /* the albedo, as the frame sums it */
    float albedo_direct_sum[3];   /* the direct light's albedo (gbuffer_direct_albedo_sum's terms:
                                   * albedo_diffuse at a glossy-lobed hit, else the albedo) */
    float pos_sum[3], nrm_sum[3], depth_sum; /* as GBufferSums, over the same samples */
    float albedo_lum_sum, albedo_lum_sq_sum; /* GBufferSums.albedo_sum, albedo_sq_sum's terms */
    int hits;                     /* the samples GBufferSums.hits counts that are here */
    double depth_sq_sum;
} GBufferOtherSums;

typedef struct {
    int width, height;
    ReconCamera cam;
    Frame frame;

    GBufferSums *sums;            /* per pixel (gbuffer_add) */
    GBufferOtherSums *others;     /* per pixel while split pixels are tracked (gbuffer_track_split),
                                   * else NULL */
    bool split_direct, split_indirect; /* which demodulated lights composite.c splits */

    /* guides (gbuffer_resolve_guides) */
    unsigned char *hit;           /* some sample hit a surface */
    unsigned char *mixed;         /* the samples saw different surfaces or an unfilterable one */
    unsigned char *glossy;        /* some sample's first hit was glossy (gbuffer_sample_glossy):
                                   * most of its direct light passes through unfiltered, so the
                                   * adaptive plans give it the mixed pixels' count */
    unsigned char *albedo_varies; /* the albedo varies inside the pixel (ALBEDO_VARIES_REL_STD) */
    float *lobe4;                 /* per pixel, added by the sink (gbuffer_add) for the samples whose
                                   * first hit has a glossy lobe (gbuffer_sample_lobed) alone: their
                                   * albedo less albedo_diffuse (rgb), and their count. Apart from
                                   * `sums` so that a Lambert sample never touches it (GBufferSums
                                   * stays 96 bytes) */
    float *pos4;                  /* mean position (world), mean depth (world) */
    float *nrm4;                  /* unit mean normal, object id (-1: none) */
    float *pixel_world;           /* world length of one pixel at the receiver (0: no hit) */
    float scene_size_world;       /* diagonal of the bounding box of the pixels' positions */
    /* split pixels (gbuffer_track_split; resolved with the guides): a mixed pixel whose first
     * surface alone passes the mixed rule (one object, normals and depths coherent, at least
     * one filterable hit) */
    float *split_share;           /* the first surface's share of the pixel's samples, in (0, 1];
                                   * 0: not split (every pixel while nothing is tracked) */
    float *spos4, *snrm4;         /* the shading filters' guides: the first surface's mean position,
                                   * depth, normal and id in a split pixel, pos4 and nrm4 elsewhere;
                                   * the same arrays as pos4, nrm4 while nothing is tracked */
    float *spixel_world;          /* pixel_world at spos4's depth (pixel_world itself untracked) */
    unsigned char *salbedo_varies; /* albedo_varies over a split pixel's first surface (its
                                    * demodulation is exact when that albedo is uniform), 0 in
                                    * a mixed pixel not split (passed through, read by no
                                    * shading filter), albedo_varies elsewhere (itself untracked) */

    void *block_;                 /* one allocation behind all the arrays above but frame */
} GBuffer;

/* False when out of memory (or a zero size). */
bool gbuffer_init(GBuffer *g, int width, int height, ReconCamera cam);
/* The frame alone, every per-pixel array of the guides NULL: for a frame no filter reads
 * (--filter none), whose guides would be 150-odd bytes a pixel allocated and touched for
 * nothing (315 MB at 1920x1080). The frame holds the planes asked for (frame_init_planes). */
bool gbuffer_init_frame(GBuffer *g, int width, int height, ReconCamera cam, unsigned frame_planes);
void gbuffer_free(GBuffer *g);

/* The soft-shadow filters (AAF-shadow eq. 1, MAAF, FSF) filter direct light / (albedo r(x)),
 * the light-weighted visibility, which holds for a diffuse receiver: its BRDF is the same for
 * every point of the light. A glossy lobe weights the light's points by the lobe instead (the
 * highlight), and its light is not proportional to the diffuse albedo. So every sample's direct
 * light comes split by lobe (SampleRecord.direct_glossy): the glossy lobes' part passes through
 * unfiltered (gbuffer_unfiltered_split counts it as unfiltered direct light), the diffuse
 * lobe's is demodulated by the diffuse albedo (gbuffer_direct_albedo) and filtered
 * (docs/algorithms.md, "Direct light split by lobe").
 *
 * A sample still counts as glossy when the glossy part is more than GLOSSY_DIRECT_SHARE of its
 * albedo (luminance) and the lobe is narrower than Lambert's cosine (Blinn-Phong exponent above
 * GLOSSY_DIRECT_MIN_EXPONENT: cos^m with m <= 1 is at least as wide): most of such a pixel's
 * direct light is the unfiltered glossy part, which the adaptive plans give the mixed pixels'
 * sample count (aaf_method.c, maaf_method.c). */
#define GLOSSY_DIRECT_SHARE 0.5f
#define GLOSSY_DIRECT_MIN_EXPONENT 1.0f
bool gbuffer_sample_glossy(const SampleRecord *r);

/* Whether a sample's first hit has a glossy lobe (a glossy albedo; Lambert's is 0, and so is a
 * miss's): its direct light may have a glossy part (SampleRecord.direct_glossy), and its
 * diffuse albedo may differ from its albedo. One test for the three channels (each >= 0). */
static inline bool gbuffer_sample_lobed(const SampleRecord *r)
{
    return r->albedo_glossy.x + r->albedo_glossy.y + r->albedo_glossy.z > 0.0f;
}

/* A texture edge inside a pixel (the albedo's std over the pixel's samples above this share
 * of its mean, luminance): the filters divide the light by the pixel's mean albedo and
 * multiply it back, so they leave the albedo's own sampling noise (the texture's
 * antialiasing) as it is. An adaptive plan that gives an unshadowed pixel pass 1's few samples
 * because its *light* is smooth leaves that noise at pass 1's level: on a fine checkerboard
 * floor 71% of the pixels kept 9 samples at a 32-spp budget and held 85% of the error (AAF
 * lost to Monte Carlo at equal samples). The plans give these pixels the mixed pixels' count. */
#define ALBEDO_VARIES_REL_STD 0.1f
/* ... unless a defocus filter at least this wide (std, pixels) averages the pixel with its
 * neighbours: the lens filter blurs the composite, texture and its noise included. */
#define ALBEDO_VARIES_DEFOCUS_STD_PX 1.0f

/* Pixel i's mean albedo (luminance) over its samples that hit; -1 when none did. */
static inline float gbuffer_albedo_mean(const GBuffer *g, size_t i)
{
    int hits = g->sums[i].hits;
    return hits > 0 ? g->sums[i].albedo_sum / (float)hits : -1.0f;
}

/* The 4-neighbours of pixel i inside the image, in the order left, right, up, down: their
 * indices in out[0 .. returned count). */
static inline int gbuffer_neighbours4(const GBuffer *g, size_t i, size_t out[4])
{
    int w = g->width, h = g->height, x = (int)(i % (size_t)w), y = (int)(i / (size_t)w), n = 0;
    if (x > 0) out[n++] = i - 1;
    if (x < w - 1) out[n++] = i + 1;
    if (y > 0) out[n++] = i - (size_t)w;
    if (y < h - 1) out[n++] = i + (size_t)w;
    return n;
}

/* Whether an albedo edge may lie inside pixel i though its samples all fell on one side of it:
 * pass 1's few stratified samples (3 x 3) miss an edge that clips the pixel's border (within
 * a sixth of a pixel), and such an edge leaves the 4-neighbour on its other side with another
 * mean albedo. The test is ALBEDO_VARIES_REL_STD's over the two pixels' samples taken together
 * (equal counts: std |a - b| / 2 against the share of the mean, (a + b) / 2). A neighbour whose
 * own samples straddle an edge holds it (its own test marks it), so it does not mark pixel i;
 * only where neither pixel saw the edge inside are both marked, as either may hold it. Without
 * this, the unmarked third of a checkerboard's edge pixels kept pass 1's count and held most
 * of AAF's error at 32 spp (spot_area_mm: Monte Carlo's error at 32 spp, docs/benchmarks.md,
 * "Held-out bench scenes, second round"). */
static inline bool gbuffer_albedo_step(const GBuffer *g, size_t i)
{
    float a = gbuffer_albedo_mean(g, i);
    if (!(a > 0.0f)) return false;
    size_t nb[4];
    for (int k = 0, count = gbuffer_neighbours4(g, i, nb); k < count; ++k) {
        size_t j = nb[k];
        float b = gbuffer_albedo_mean(g, j);
        if (!g->albedo_varies[j] && b > 0.0f && fabsf(a - b) > ALBEDO_VARIES_REL_STD * (a + b)) return true;
    }
    return false;
}

/* Mixed pixels (gbuffer_resolve_guides): a pixel whose samples (over the shutter or the lens) land on surfaces that
 * disagree has a mean position, normal and albedo that belong to no surface; a world-space
 * filter would compare neighbours against that phantom and divide by a phantom albedo (the
 * dark speckled ring around the motion-blurred sphere of the default scene). Such a pixel is
 * detected by: another object id, some samples missing all geometry, mean unit normal
 * shorter than this (normals spread over more than about 25 degrees), or depth spread
 * (std / mean) above this. */
#define MIXED_NORMAL_COHERENCE 0.9f
#define MIXED_DEPTH_REL_STD 0.1f

/* Whether a surface edge (a silhouette, a crease, a surface against the background) may lie
 * inside pixel i though its samples all saw one surface: the geometric twin of
 * gbuffer_albedo_step. Pass 1's 3 x 3 stratified samples miss an edge that clips the pixel's
 * border, and the pixel then looks like a plain surface with pass 1's count; but the
 * 4-neighbour across the edge saw the other side. The test is the mixed rule's over the two
 * pixels' samples taken together (equal counts, the within-pixel spreads left out): another
 * object id or one pixel hit and one not (the mixed rule's "another object", "samples
 * missing all geometry"), mean normal |n_i + n_j| / 2 below MIXED_NORMAL_COHERENCE, or depth
 * std |d_i - d_j| / 2 above MIXED_DEPTH_REL_STD of the mean (d_i + d_j) / 2. As with the
 * albedo, a mixed neighbour holds its edge (its own samples saw it) and marks nothing; pixel i
 * mixed itself is the mixed rule's. On wire_screen these pixels were 1% of the frame and 45%
 * of AAF's error: 40 of them, lit by a sliver of a surface pass 1 never hit, stayed black
 * (docs/benchmarks.md, "Where auto's samples go"). */
static inline bool gbuffer_surface_step(const GBuffer *g, size_t i)
{
    if (g->mixed[i]) return false;
    const float *ni = g->nrm4 + 4 * i;
    float di = g->pos4[4 * i + 3];
    size_t nb[4];
    for (int k = 0, count = gbuffer_neighbours4(g, i, nb); k < count; ++k) {
        size_t j = nb[k];
        if (g->mixed[j]) continue;
        if (g->hit[i] != g->hit[j]) return true;
        if (!g->hit[i]) continue;
        const float *nj = g->nrm4 + 4 * j;
        if (ni[3] != nj[3]) return true; /* object ids */
        float sx = ni[0] + nj[0], sy = ni[1] + nj[1], sz = ni[2] + nj[2];
        if (sqrtf(sx * sx + sy * sy + sz * sz) < 2.0f * MIXED_NORMAL_COHERENCE) return true;
        float dj = g->pos4[4 * j + 3];
        if (fabsf(di - dj) > MIXED_DEPTH_REL_STD * (di + dj)) return true;
    }
    return false;
}

/* Whether pixel i's texture edge needs the mixed pixels' count: its albedo varies, inside it
 * or against a neighbour (gbuffer_albedo_step), and no lens filter at least
 * ALBEDO_VARIES_DEFOCUS_STD_PX wide averages it (lens_std_px: that filter's width; 0 without
 * one; NaN counts as none, so an unknown width asks for the samples). */
static inline bool gbuffer_texture_needs_samples(const GBuffer *g, size_t i, float lens_std_px)
{
    return (g->albedo_varies[i] || gbuffer_albedo_step(g, i)) && !(lens_std_px >= ALBEDO_VARIES_DEFOCUS_STD_PX);
}

/* Pixel i's albedo for its filterable direct light (the diffuse lobe's, direct_glossy taken
 * out), summed over its samples: the frame's albedo sum where no sample's first hit had a
 * glossy lobe (Lambert: the same floats), else that sum less the glossy-lobed samples' albedo
 * less their albedo_diffuse (lobe4), at least 0: the sum of albedo_diffuse to rounding (a
 * conductor's is 0, and its direct light passes through). */
static inline void gbuffer_direct_albedo_sum(const GBuffer *g, size_t i, float sum[3])
{
    const float *a = g->frame.albedo + 3 * i, *l = g->lobe4 + 4 * i;
    bool lobed = l[3] > 0.0f;
    for (int k = 0; k < 3; ++k) {
        float d = a[k] - l[k];
        sum[k] = !lobed ? a[k] : d > 0.0f ? d : 0.0f;
    }
}
/* Its mean over the pixel's samples (0 where not finite; composite_prepare counts the frame's). */
void gbuffer_direct_albedo(const GBuffer *g, size_t i, float a[3]);

/* Whether the shading filters' demodulated direct / indirect light take the first surface of
 * a mixed pixel (composite.c, docs/algorithms.md "Mixed pixels: the first surface filtered"):
 * allocates the others' sums and the split guides when either is set; false when out of
 * memory. Before the first sample. */
bool gbuffer_track_split(GBuffer *g, bool direct, bool indirect);

/* Whether pixel i is split (gbuffer_track_split, after gbuffer_resolve_guides): a mixed pixel
 * whose first surface the shading filters take. */
static inline bool gbuffer_pixel_split(const GBuffer *g, size_t i)
{
    return g->split_share && g->split_share[i] > 0.0f;
}

/* Whether a sample of pixel i (gbuffer_add has taken it) lies on the pixel's first surface:
 * a hit on the first hit's object, filterable, at a finite position. */
static inline bool gbuffer_on_first_surface(const GBuffer *g, size_t i, const SampleRecord *r)
{
    return r->hit && !r->unfilterable && r->object_id == g->sums[i].object_id &&
           isfinite(r->p_world.x + r->p_world.y + r->p_world.z);
}

/* Split pixel i's first surface: its sample count and the sums of its filterable light and
 * albedo (direct: the direct light's albedo, gbuffer_direct_albedo_sum's; else the indirect
 * light and the frame's albedo). Only where split_share[i] > 0. */
void gbuffer_first_surface_sums(const GBuffer *g, size_t i, bool direct, float *count, float light[3], float albedo[3]);

/* The coherence of the normals behind pixel i's shading guides (snrm4): the length of their
 * mean, |sum n_k| / hits in (0, 1], over a split pixel's first surface or else all the pixel's
 * hits; 1 when no sample hit. It is the samples' mean cosine to the mean normal, so some sample
 * lies at least acos(coherence) from it: the spread the guides' one normal stands for
 * (aaf_unoccluded_irradiance). */
float gbuffer_shading_normal_coherence(const GBuffer *g, size_t i);

/* The SampleSink callback (ctx = GBuffer *). */
void gbuffer_add(void *ctx, int px, int py, const SampleRecord *r);
/* The same sink for a frame that reads none of the guides, only the unfiltered light's sums
 * (unf_direct_sum, unf_indirect_sum: the composite subtracts and adds them back even where
 * nothing is filtered, so they decide the image's last bits): the samples gbuffer_add would
 * take, split the same way; every other sum stays 0 (ReconMethodClass.guides_unread). */
void gbuffer_add_unfiltered(void *ctx, int px, int py, const SampleRecord *r);

/* The guides from the sums and the frame's sample counts, after a pass. */
void gbuffer_resolve_guides(GBuffer *g);

/* One sample's light the filters must not blur, split into its direct and indirect parts:
 * `unfiltered` (whose split the record does not give) goes to the indirect light first
 * (mirror images of the scene), the rest to direct (the light seen in a mirror), per channel,
 * so that both filtered remainders stay >= 0; `unfiltered_direct` and `direct_glossy` are
 * direct by construction. Negative or non-finite parts count as 0. */
void gbuffer_unfiltered_split(const SampleRecord *r, float direct[3], float indirect[3]);

/* Per-pixel, per-channel means of the unfiltered light (0 where non-finite). */
void gbuffer_unfiltered_means(const GBuffer *g, size_t i, float direct[3], float indirect[3]);

/* Bytes gbuffer_init allocates for a width x height image (the frame included). */
size_t gbuffer_bytes(int width, int height);

#endif
