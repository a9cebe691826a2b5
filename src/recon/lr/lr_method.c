/* Layered reconstruction (LR, seeds/004) as a reconstruction method (recon/method.h).
 *
 *   samples  a fixed count for the whole frame (8 per pixel, or --spp), no plan; the
 *            pipeline's per-sample store keeps film position, lens, time, depth, screen
 *            motion and radiance of every sample
 *   filter   the camera effects (defocus, motion) on the composite radiance: partitions on
 *            the host, reprojection / screen filter / compositing in OpenCL (lr_cl.h)
 *   AOVs     lr.layers (non-empty depth layers of the pixel's tile), lr.extent_px (sigma_x
 *            of the front-most layer with opacity at the pixel, at its band class's band
 *            for a still layer) and lr.band_class (docs/algorithms.md 8.40)
 *
 * Shading filters (another method's soft shadows or indirect light) run before this on the
 * pixel means; their effect reaches LR as a per-pixel additive correction of every sample's
 * radiance (the filtered mean minus the raw mean of the pixel's stored samples), so a pixel
 * that motion or defocus mixes keeps the shading filter's result in its mean and LR moves
 * only each sample's own deviation (docs/algorithms.md 8.7). LR reads the samples every
 * pixel has; a pixel with more (an adaptive method's pass 2) mixes LR's value with its own
 * by lr_share_weight (docs/algorithms.md 8.16). */
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "recon/lr/lr_band_class.h"
#include "recon/lr/lr_cl.h"
#include "recon/lr/lr_coc_slope.h"
#include "recon/lr/lr_noise_share.h"
#include "recon/lr/lr_partition.h"
#include "recon/lr/lr_shading.h"
#include "recon/lr/lr_share.h"
#include "recon/method.h"
#include "recon/recon_parallel.h"

/* The store's records are LrPlace and LrKey (sample_store.h); floats per sample of each. */
enum { LR_PLACE_FLOATS = 8, LR_KEY_FLOATS = 4 };
_Static_assert(sizeof(LrPlace) == LR_PLACE_FLOATS * sizeof(float) && offsetof(LrPlace, u) == 2 * sizeof(float) &&
                   offsetof(LrPlace, t) == 4 * sizeof(float) && offsetof(LrPlace, L) == 5 * sizeof(float) &&
                   sizeof(LrKey) == LR_KEY_FLOATS * sizeof(float) && offsetof(LrKey, coc_px) == sizeof(float) &&
                   offsetof(LrKey, motion_px) == 2 * sizeof(float),
               "SAMPLE_FIELD_LR_PLACE and SAMPLE_FIELD_LR_KEY are LrPlace and LrKey");

/* LR section 8: 4-8 samples per pixel; the default is 8. */
#define LR_DEFAULT_SPP 8

struct ReconMethod {
    const GBuffer *g;
    SampleStore *store;
    EffectMask effects;
    LrConfig cfg;
    LrCl *cl;
    float *layers, *extent_px; /* AOVs, width * height */
    float *band_aov;           /* AOV: each pixel's still band class (lr_band_class.h), 0 at 16 spp and up */
    unsigned char *band_class; /* the frame's class map, width * height */
    LrKey *key;                /* the store's samples as LR reads them (LrSamples' arrays), copied here where */
    LrPlace *place;            /* the store holds more per pixel than all have (else its records are they) */
    size_t copies_cap;         /* kept between frames */
    float *bright;
    size_t bright_cap;
    const LrKey *img_key;      /* the last gather's: the store's records or the copies */
    const LrPlace *img_place;
    float *rgb;                /* LR's output, width * height * 3 */
    unsigned char *moving;     /* per pixel, from the gather: a sample of it moves or is blurred (still_tiles) */
    ReconShadingLight light;   /* the shading filters' results, during filter_radiance */
};

static int lr_pass1_spp(EffectMask effects)
{
    (void)effects;
    return LR_DEFAULT_SPP;
}

static void lr_destroy(ReconMethod *m)
{
    if (!m) return;
    lr_cl_destroy(m->cl);
    free(m->layers);
    free(m->extent_px);
    free(m->band_aov), free(m->band_class);
    free(m->key), free(m->place), free(m->bright);
    free(m->rgb);
    free(m->moving);
    free(m);
}

static bool lr_create(const ReconSetup *s, ReconMethod **out, Diag *d)
{
    ReconMethod *m = calloc(1, sizeof *m);
    *out = NULL;
    size_t n = (size_t)s->gbuffer->width * (size_t)s->gbuffer->height;
    if (m) {
        m->layers = calloc(n, sizeof(float));
        m->extent_px = calloc(n, sizeof(float));
        m->band_aov = calloc(n, sizeof(float));
        m->band_class = malloc(n);
        m->rgb = malloc(sizeof(float) * 3 * n);
        m->moving = malloc(n);
    }
    if (!m || !m->layers || !m->extent_px || !m->band_aov || !m->band_class || !m->rgb || !m->moving || !s->store) {
        lr_destroy(m);
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0},
                 s->store ? "out of memory for LR buffers" : "LR needs the per-sample store (none was given)");
        return false;
    }
    m->g = s->gbuffer;
    m->store = s->store;
    m->effects = s->effects;
    m->cfg = lr_config_default();
    /* the band's pixels only lend their samples: tiles start at the visible corner, as
     * without a band, and the band's tiles are not filtered */
    m->cfg.inset_px = s->band_px;
    *out = m;
    return true;
}

static bool lr_open_device(ReconMethod *m, ClRuntime *rt, Diag *d)
{
    if (m->cl) return true;
    return (m->cl = lr_cl_create(rt, d)) != NULL;
}

/* A sample blurred by less than this by the lens (its circle of confusion's radius, px) is
 * "still" for still_tiles, as one moving less than LR_MOVING_PX over the shutter. */
#define LR_STILL_COC_PX 0.5f

/* Not still: moving by LR_MOVING_PX or more, or (lens_dims: the lens is LR's dimension)
 * blurred by the lens by LR_STILL_COC_PX or more. */
static bool lr_sample_moves(const LrKey *o, bool lens_dims)
{
    float m2 = o->motion_px[0] * o->motion_px[0] + o->motion_px[1] * o->motion_px[1];
    bool blurred = lens_dims && !(fabsf(o->coc_px) < LR_STILL_COC_PX);
    return !(m2 < LR_MOVING_PX * LR_MOVING_PX) || blurred;
}

/* What the per-pixel passes of gather_samples read and write. */
typedef struct {
    const ReconMethod *m;
    const SampleStore *st;
    int cap, spp;
    bool lens_dims;          /* the lens is LR's dimension (else its pinhole reduction) */
    LrCocSlope slope;        /* the camera's, for coc_slope */
    const float *shade;      /* SAMPLE_FIELD_SHADING, NULL: no shading filter in the frame */
    LrShading shading;       /* the store's shading fields (lr_shading_of) */
    const float *value4;     /* the pixels' values (the shading filters' results in them) */
    float *place_rec, *key_rec; /* the store's SAMPLE_FIELD_LR_PLACE and _LR_KEY records (the
                                 * CoC slope and the light are written into their slots) */
    float *centre_xy;        /* per stored sample, 2 floats (NULL without shade) */
    const float *delta4;     /* lr_delta_light's (NULL without shade) */
    const LrCentreLight *centre;
    LrKey *key;              /* spp per pixel: LrSamples' arrays (the store's records themselves
                              * when it holds spp per pixel, else copies) */
    LrPlace *place;
    float *bright;
    unsigned char *moving;   /* per pixel: lr_sample_moves of any of its samples */
    bool failed[RECON_PARTS]; /* a part without memory for its scratch */
    long nonfinite[RECON_PARTS];    /* per part: samples whose light is not finite */
    float film_dev_px[RECON_PARTS]; /* per part: the farthest film position from its pixel's centre */
} GatherJob;

/* A sample's CoC slope at camera depth `depth` (px per unit lens): 0 without the lens
 * dimensions or where it is not finite. recon_coc_slope_px's value, its frame constants taken
 * once (lr_coc_slope.h), not three divisions and a call per sample (3% of a warm filter). */
static float coc_slope(const GatherJob *j, float depth)
{
    float c = j->lens_dims ? lr_coc_slope_px(&j->slope, depth) : 0.0f;
    return isfinite(c) ? c : 0.0f;
}

/* Beside a shading filter, pixels [begin, end): each stored sample's CoC slope (coc_slope),
 * into its LR_KEY record's slot (gather_range reads it there), and where its point is seen
 * through the lens centre at mid-shutter (LR's reprojection to u = v = 0, t = 1/2:
 * lr_partition.h's x = x0 + c u, y = y0 + c v with v the flipped lens v, as LR_PLACE holds it,
 * and the film moving by motion_px per unit shutter time). */
static void coc_and_centre_range(void *ctx, size_t begin, size_t end, int part)
{
    (void)part;
    GatherJob *j = ctx;
    const SampleStore *st = j->st;
    size_t cap = (size_t)j->cap;
    for (size_t i = begin; i < end; ++i)
        for (int k = 0; k < sample_store_count(st, i); ++k) {
            size_t q = i * cap + (size_t)k;
            float *key = j->key_rec + LR_KEY_FLOATS * q;
            const float *pl = j->place_rec + LR_PLACE_FLOATS * q;
            float c = coc_slope(j, key[0]);
            key[1] = c;
            float dt = pl[4] - 0.5f;
            j->centre_xy[2 * q] = pl[0] - c * pl[2] - key[2] * dt;
            j->centre_xy[2 * q + 1] = pl[1] - c * pl[3] - key[3] * dt;
        }
}

/* Pixels [begin, end): their first spp samples as LrSamples, each with its light as
 * lr_pixel_light gives it. */
static void gather_range(void *ctx, size_t begin, size_t end, int part)
{
    GatherJob *j = ctx;
    const ReconMethod *m = j->m;
    const SampleStore *st = j->st;
    size_t cap = (size_t)j->cap;
    const float *shade = j->shade;
    float *light = malloc(sizeof(float) * 3 * cap);
    size_t *src = malloc(sizeof(size_t) * cap);
    float *centre9 = shade ? malloc(sizeof(float) * 9 * cap) : NULL;
    if (!light || !src || (shade && !centre9)) {
        free(light), free(src), free(centre9);
        j->failed[part] = true;
        return;
    }
    const float *rad = sample_store_field(st, SAMPLE_FIELD_RADIANCE);
    long nonfinite = 0;
    float film_dev_px = 0.0f;
    size_t width = (size_t)m->g->width;
    for (size_t i = begin; i < end; ++i) {
        int count = sample_store_count(st, i);
        for (int k = 0; shade && k < count; ++k) {
            const float *xy = &j->centre_xy[2 * (i * cap + k)];
            float object = shade[(i * cap + k) * LR_SHADING_BASE_FLOATS + 3];
            src[k] = lr_light_pixel(m->g, xy[0], xy[1], j->key_rec[LR_KEY_FLOATS * (i * cap + k)], object, i);
            const float *c9 = lr_centre_light_at(j->centre, xy[0], xy[1], object);
            for (int c = 0; c < 9; ++c) centre9[9 * k + c] = c9 ? c9[c] : NAN;
        }
        float value[3] = {j->value4[4 * i], j->value4[4 * i + 1], j->value4[4 * i + 2]};
        bool moves = false;
        LrShading rows = lr_shading_from(&j->shading, i * cap);
        lr_pixel_light(count, rad + i * cap * 3, shade ? &rows : NULL, src, &m->light, j->delta4, centre9, value, light);
        for (int k = 0; k < j->spp; ++k) {
            size_t q = i * cap + k;
            size_t oi = i * (size_t)j->spp + k;
            /* read whole before writing: with spp = cap the destination is the record itself */
            const float *pl = j->place_rec + LR_PLACE_FLOATS * q, *ky = j->key_rec + LR_KEY_FLOATS * q;
            /* the lens only where it is LR's dimension (else its pinhole reduction: in place, the
             * record's lens becomes 0, which a later gather reads only times c = 0) */
            LrPlace o = {pl[0], pl[1], j->lens_dims ? pl[2] : 0.0f, j->lens_dims ? pl[3] : 0.0f, pl[4],
                         {light[3 * k], light[3 * k + 1], light[3 * k + 2]}};
            /* the slope: coc_and_centre_range's beside a shading filter, else taken here (one
             * pass over the records less) */
            LrKey key = {ky[0], shade ? ky[1] : coc_slope(j, ky[0]), {ky[2], ky[3]}};
            j->place[oi] = o;
            j->key[oi] = key;
            j->bright[oi] = lr_bright(o.L);
            /* what lr_cl_run would otherwise measure in a pass of its own over the samples */
            lr_scan_sample(&o, (int)(i % width), (int)(i / width), &nonfinite, &film_dev_px);
            moves = moves || lr_sample_moves(&key, j->lens_dims); /* still_tiles' */
        }
        j->moving[i] = moves;
    }
    j->nonfinite[part] = nonfinite;
    j->film_dev_px[part] = film_dev_px;
    free(light), free(src), free(centre9);
}

/* The store's samples as LrSamples (the smallest per-pixel count, which in a fixed-count
 * frame is every pixel's), each sample's light as lr_pixel_light gives it: the shading
 * filters' light in place of its own where they ran, and its pixel's samples averaging to
 * the pixel's value in value4. Pixels are independent in every pass but the centre light's
 * sums (lr_centre_light_build), so they split between the cores (recon_parallel.h) with the
 * same result. Written into m->img_key, m->img_place and m->bright; false when there are none
 * (*spp_out <= 0) or without memory. */
static bool gather_samples(ReconMethod *m, const float *value4, int *spp_out, long *nonfinite, float *film_dev_px)
{
    const SampleStore *st = m->store;
    int w = m->g->width, h = m->g->height, cap = sample_store_capacity(st);
    size_t n = (size_t)w * (size_t)h;
    int spp = cap;
    for (size_t i = 0; i < n; ++i) {
        int c = sample_store_count(st, i);
        if (c < spp) spp = c;
    }
    *spp_out = spp;
    if (spp <= 0) return false;
    /* Every pixel holds cap samples (a fixed-count frame): LR reads the store's records in
     * place, the CoC slope and the light written into their slots; else copies of the first
     * spp of each pixel's. */
    float *place_rec = sample_store_field_mut(m->store, SAMPLE_FIELD_LR_PLACE);
    float *key_rec = sample_store_field_mut(m->store, SAMPLE_FIELD_LR_KEY);
    bool in_place = spp == cap;
    if (!in_place && n * (size_t)spp > m->copies_cap) {
        free(m->key), free(m->place);
        m->key = malloc(sizeof(LrKey) * n * (size_t)spp);
        m->place = malloc(sizeof(LrPlace) * n * (size_t)spp);
        m->copies_cap = m->key && m->place ? n * (size_t)spp : 0;
        if (!m->copies_cap) return false;
    }
    if (n * (size_t)spp > m->bright_cap) {
        free(m->bright);
        m->bright = malloc(sizeof(float) * n * (size_t)spp);
        m->bright_cap = m->bright ? n * (size_t)spp : 0;
        if (!m->bright_cap) return false;
    }
    m->img_key = in_place ? (const LrKey *)key_rec : m->key;
    m->img_place = in_place ? (const LrPlace *)place_rec : m->place;
    LrShading shading = lr_shading_of(st);
    const float *shade = shading.base; /* NULL: no shading filter in the frame */
    float *delta4 = shade ? malloc(sizeof(float) * 4 * n) : NULL;
    float *centre_xy = shade ? malloc(sizeof(float) * 2 * n * (size_t)cap) : NULL;
    if (shade && (!delta4 || !centre_xy)) {
        free(delta4), free(centre_xy);
        return false;
    }
    LrCentreLight centre = {0};
    /* Motion alone (defocus is another method's, already in the corrected radiance): LR's
     * pinhole reduction, the lens left out of the filter (its variance is noise LR averages
     * along the motion, not a dimension it shears). */
    GatherJob job = {.m = m, .st = st, .cap = cap, .spp = spp, .lens_dims = effect_in(m->effects, EFFECT_DEFOCUS),
                     .slope = lr_coc_slope_of(&m->g->cam),
                     .shade = shade, .shading = shading, .value4 = value4, .place_rec = place_rec, .key_rec = key_rec,
                     .centre_xy = centre_xy, .delta4 = delta4, .centre = &centre,
                     .key = in_place ? (LrKey *)key_rec : m->key, .place = in_place ? (LrPlace *)place_rec : m->place,
                     .bright = m->bright, .moving = m->moving};
    size_t work = n * (size_t)cap;
    if (shade) {
        recon_parallel_for_work(n, work, coc_and_centre_range, &job);
        lr_delta_light(m->g, st, shade, delta4);
        /* without memory for the map, the samples of pass-through pixels keep their own light */
        lr_centre_light_build(&centre, m->g, st, &shading, centre_xy);
    }
    recon_parallel_for_work(n, work, gather_range, &job);
    free(delta4), free(centre_xy);
    lr_centre_light_free(&centre);
    *nonfinite = 0;
    *film_dev_px = 0.0f;
    for (int p = 0; p < RECON_PARTS; ++p) {
        if (job.failed[p]) return false;
        *nonfinite += job.nonfinite[p];
        if (job.film_dev_px[p] > *film_dev_px) *film_dev_px = job.film_dev_px[p];
    }
    return true;
}

static void lr_shading_light(ReconMethod *m, const ReconShadingLight *light)
{
    m->light = *light;
}

/* Per tile (lr_tile_count's order), 1 where the tile's window holds only still samples (no
 * motion and, with the lens as LR's dimension, no blur by it): LR has nothing to move there,
 * and its static layers' screen filter (sigma_pixel 1/3 px) gives back the pixel means within
 * rounding (relMSE to 8 digits the same on motion and motion_shading, 256x256, 8 and 32 spp),
 * so such tiles are left out of the reconstruction and keep their means: the reduction
 * "neither motion nor lens: the unfiltered image", made exact, and half the tiles of a frame
 * where a few objects move over a still background skip LR's kernels. NULL when out of
 * memory (every tile is then reconstructed). moving: per pixel, the gather's lr_sample_moves of
 * any of its samples. */
static unsigned char *still_tiles(const LrSamples *img, const LrConfig *cfg, const unsigned char *moving)
{
    int ntx, nty;
    lr_tile_count(img, cfg, &ntx, &nty);
    unsigned char *still = calloc((size_t)ntx * (size_t)nty + 1, 1);
    if (!still) return NULL;
    for (int ty = 0; ty < nty; ++ty)
        for (int tx = 0; tx < ntx; ++tx) {
            int x0, y0, x1, y1;
            lr_tile_window(img, cfg, tx, ty, &x0, &y0, &x1, &y1);
            bool any = false;
            for (int y = y0; y < y1 && !any; ++y)
                for (int x = x0; x < x1 && !any; ++x) any = moving[(size_t)y * (size_t)img->width + (size_t)x];
            still[ty * ntx + tx] = !any;
        }
    return still;
}

/* Whether pixel (x, y) lies in a tile still_tiles marked. */
static bool in_still_tile(const unsigned char *still, const LrConfig *cfg, int ntx, int x, int y)
{
    return still && still[((y - cfg->inset_px) / cfg->tile_px) * ntx + (x - cfg->inset_px) / cfg->tile_px];
}

static bool lr_filter_radiance(ReconMethod *m, EffectMask effects, float *value4, double *kernel_seconds, Diag *d)
{
    *kernel_seconds = 0.0;
    (void)effects;
    int spp = 0;
    long nonfinite = 0;
    float film_dev_px = 0.0f;
    if (!gather_samples(m, value4, &spp, &nonfinite, &film_dev_px)) {
        if (spp <= 0) return true; /* nothing stored (a cancelled frame): leave the means */
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for LR samples");
        return false;
    }
    int w = m->g->width, h = m->g->height;
    float *rgb = m->rgb;
    bool ok = true;
    LrSamples img = {w, h, spp, m->img_key, m->img_place, m->bright};
    LrOutput out = {rgb, m->layers, m->extent_px, 0};
    LrConfig cfg = m->cfg;
    /* the still layers' band at this count (8.36), wider where their light is noisy (8.37) */
    cfg.filter.sigma_pixel_still_px = lr_still_sigma_pixel_px(spp);
    if (spp < LR_PIXEL_BAND_SPP)
        cfg.filter.sigma_pixel_still_px = lr_still_band_px(cfg.filter.sigma_pixel_still_px, lr_still_noise_share(&img, m->moving));
    cfg.samples_scanned = true; /* the gather measured them (gather_range) */
    cfg.samples_nonfinite = nonfinite;
    cfg.film_dev_px = film_dev_px;
    unsigned char *still = still_tiles(&img, &cfg, m->moving);
    cfg.still_tiles = still;
    /* below 16 spp each pixel's still layers take its band class's screen filter (8.40);
     * with fewer than 2 samples: the frame's band everywhere */
    size_t npix = (size_t)w * (size_t)h;
    cfg.band_class = spp < LR_PIXEL_BAND_SPP && lr_band_classes(&img, m->band_class) ? m->band_class : NULL;
    for (size_t i = 0; i < npix; ++i) m->band_aov[i] = cfg.band_class ? (float)cfg.band_class[i] : 0.0f;
    int ntx, nty;
    lr_tile_count(&img, &cfg, &ntx, &nty);
    if (ok && m->cl) {
        ok = lr_cl_run(m->cl, &img, &cfg, &out, kernel_seconds, d);
    } else if (ok) {
        lr_reconstruct_c(&img, &cfg, &out);
    }
    if (ok) {
        const float *spp_px = m->g->frame.spp;
        int b = cfg.inset_px; /* the band keeps its means (lr_reconstruct.h) */
        for (int y = b; y < h - b; ++y)
            for (int x = b; x < w - b; ++x) {
                size_t i = (size_t)y * (size_t)w + (size_t)x;
                /* a still tile was left out: the pixel keeps its mean */
                float share = in_still_tile(still, &cfg, ntx, x, y) ? 0.0f : lr_share_weight(spp, spp_px[i]);
                for (int c = 0; c < 3; ++c) value4[4 * i + c] = share * rgb[3 * i + c] + (1.0f - share) * value4[4 * i + c];
            }
    }
    free(still);
    m->light = (ReconShadingLight){0}; /* the pipeline's arrays are valid for this call only */
    return ok;
}

static int lr_aovs(ReconMethod *m, ReconAov *out, int max)
{
    int count = 0;
    if (count < max) out[count++] = (ReconAov){"lr.layers", m->layers, "depth layers"};
    if (count < max) out[count++] = (ReconAov){"lr.extent_px", m->extent_px, "filter sigma in pixels"};
    if (count < max) out[count++] = (ReconAov){"lr.band_class", m->band_aov, "still band class: 0 frame, 1 narrow, 2 wide"};
    return count;
}

/* A tile's edge pixels read samples up to the window's margin (N_s - N) / 2 beyond it
 * (section 7, lr_tile_window): at the image border those must be traced (overscan). */
static int lr_overscan_px(void)
{
    LrConfig cfg = lr_config_default();
    return (cfg.window_px - cfg.tile_px) / 2;
}

const ReconMethodClass recon_method_lr = {
    .name = "lr",
    .title = "layered reconstruction (LR): sheared 5D filter per tile and depth layer, fixed samples (default 8)",
    .effects = EFFECT_BIT(EFFECT_DEFOCUS) | EFFECT_BIT(EFFECT_MOTION),
    .adaptive = false,
    .sample_fields = SAMPLE_FIELD_LR_PLACE | SAMPLE_FIELD_LR_KEY | SAMPLE_FIELD_RADIANCE | SAMPLE_FIELD_SHADING |
                     SAMPLE_FIELD_SHADING_DIRECT | SAMPLE_FIELD_SHADING_INDIRECT,
    .shadow_geometry = 0,
    .bounce_geometry = 0,
    .guides_unread = true, /* pos4, nrm4, hit, mixed only with SAMPLE_FIELD_SHADING (lr_shading.h) */
    .pass1_spp = lr_pass1_spp,
    .create = lr_create,
    .open_device = lr_open_device,
    .shading_light = lr_shading_light,
    .filter_radiance = lr_filter_radiance,
    .overscan_px = lr_overscan_px,
    .aovs = lr_aovs,
    .destroy = lr_destroy,
};
