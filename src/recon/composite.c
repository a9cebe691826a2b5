/* The host-side per-pixel passes around the filters (see composite.h), on both cores. */
#include "recon/composite.h"

#include <math.h>

#include "recon/recon_parallel.h"

/* Albedo below this is treated as black: the irradiance cannot be recovered there. */
#define MIN_ALBEDO 1.0e-4f


/* frame_resolve3's per-channel mean (render/frame.c), with the same arithmetic. */
static inline float sum_mean(float sum, float spp, long long *guarded)
{
    float v = spp > 0.0f ? sum / spp : 0.0f;
    if (!isfinite(v)) {
        v = 0.0f;
        ++*guarded;
    }
    return v;
}

/* value4 = radiance / (albedo * factor): what a shading filter assumes smooth. Usable where
 * there is a surface with non-black albedo and factor above its minimum; elsewhere the raw
 * radiance, flagged unusable (passed through, not shared). */
static inline void demodulate_pixel(const float rad[3], const float a[3], float factor, bool usable, float *value4)
{
    bool ok = usable && a[0] > MIN_ALBEDO && a[1] > MIN_ALBEDO && a[2] > MIN_ALBEDO;
    for (int k = 0; k < 3; ++k) value4[k] = ok ? rad[k] / (a[k] * factor) : rad[k];
    value4[3] = ok ? 1.0f : 0.0f;
}

/* A split pixel's first surface demodulated (gbuffer.h, docs/algorithms.md "Mixed pixels: the
 * first surface filtered"): the mean of its filterable light over its samples, divided by their
 * mean albedo times factor, into value4 flagged usable; false (value4 untouched) where that is
 * not stable (albedo black, factor at or below its minimum, a non-finite value), and the pixel
 * is then passed through whole as before. */
static bool demodulate_first_surface(const GBuffer *g, size_t i, bool direct, float factor, bool factor_ok, float *value4)
{
    float count, light[3], albedo[3], v[3];
    if (!factor_ok) return false;
    gbuffer_first_surface_sums(g, i, direct, &count, light, albedo);
    for (int k = 0; k < 3; ++k) {
        /* the means' ratio: light / count over (albedo / count) factor */
        if (!(albedo[k] > MIN_ALBEDO * count)) return false;
        v[k] = light[k] / (albedo[k] * factor);
        if (!isfinite(v[k])) return false;
    }
    for (int k = 0; k < 3; ++k) value4[k] = v[k];
    value4[3] = 1.0f;
    return true;
}

void composite_split_light(const GBuffer *g, size_t i, bool direct, const float *value4, float factor, float out[3])
{
    float count, light[3], albedo[3];
    gbuffer_first_surface_sums(g, i, direct, &count, light, albedo);
    const GBufferOtherSums *o = &g->others[i];
    const float *o_light = direct ? o->direct_sum : o->indirect_sum;
    float spp = g->frame.spp[i], share = g->split_share[i];
    for (int k = 0; k < 3; ++k) {
        /* share x (the first surface's mean albedo x factor x filtered value) + the others' sum / spp;
         * a value that is not finite goes on, as remodulate's does, to composite_finish, which
         * counts it (nonfinite_pixels) and sets the pixel to 0 */
        out[k] = share * (albedo[k] / count) * factor * value4[k] + o_light[k] / spp;
    }
}

typedef struct {
    const GBuffer *g;
    const float *factor;          /* direct light's extra factor (NULL: 1) */
    float factor_min;
    float *value_direct4, *value_indirect4; /* NULL: that light is not filtered */
    long long guarded[RECON_PARTS];
    long long bad_pixels[RECON_PARTS];      /* pixels with a non-finite mean (set to 0) */
} PreparePass;

static void prepare_range(void *ctx, size_t begin, size_t end, int part)
{
    PreparePass *pp = ctx;
    const GBuffer *g = pp->g;
    const Frame *f = &g->frame;
    long long guarded = 0, bad_pixels = 0;
    for (size_t i = begin; i < end; ++i) {
        float spp = f->spp[i];
        float a[3], ad[3], dir[3], ind[3], ud[3], ui[3];
        long long before = guarded;
        for (int k = 0; k < 3; ++k) {
            dir[k] = sum_mean(f->direct[3 * i + k], spp, &guarded);
            ind[k] = sum_mean(f->indirect[3 * i + k], spp, &guarded);
            (void)sum_mean(f->emission[3 * i + k], spp, &guarded); /* counted like the others */
            a[k] = sum_mean(f->albedo[3 * i + k], spp, &guarded);
        }
        gbuffer_direct_albedo(g, i, ad);
        bad_pixels += guarded > before;
        gbuffer_unfiltered_means(g, i, ud, ui);
        for (int k = 0; k < 3; ++k) {
            dir[k] -= ud[k];
            ind[k] -= ui[k];
        }
        bool surface = g->hit[i] && !g->mixed[i];
        bool split = gbuffer_pixel_split(g, i);
        if (pp->value_direct4) {
            float sh = pp->factor ? pp->factor[i] : 1.0f;
            /* the diffuse lobe's direct light over the diffuse albedo (gbuffer.h): the glossy
             * lobes' is in ud, taken out above */
            if (!(split && g->split_direct && demodulate_first_surface(g, i, true, sh, sh > pp->factor_min, pp->value_direct4 + 4 * i)))
                demodulate_pixel(dir, ad, sh, surface && sh > pp->factor_min, pp->value_direct4 + 4 * i);
        }
        if (pp->value_indirect4 && !(split && g->split_indirect && demodulate_first_surface(g, i, false, 1.0f, true, pp->value_indirect4 + 4 * i)))
            demodulate_pixel(ind, a, 1.0f, surface, pp->value_indirect4 + 4 * i);
    }
    pp->guarded[part] = guarded;
    pp->bad_pixels[part] = bad_pixels;
}

typedef struct {
    const GBuffer *g;
    const float *factor;                          /* as in PreparePass */
    const float *filtered_direct4, *filtered_indirect4; /* NULL: that light was not filtered */
    float *rgb;
    float *radiance4;                             /* NULL: no camera-effect filter follows */
} CompositePass;

/* albedo * factor * filtered value, or the raw radiance where it was not demodulated */
static inline float remodulate(const float *value4, int k, float albedo, float factor)
{
    return value4[3] != 0.0f ? albedo * factor * value4[k] : value4[k];
}

static void composite_range(void *ctx, size_t begin, size_t end, int part)
{
    (void)part;
    CompositePass *cp = ctx;
    const Frame *f = &cp->g->frame;
    long long ignored = 0; /* counted by prepare_range already */
    for (size_t i = begin; i < end; ++i) {
        float spp = f->spp[i], ud[3], ui[3], v[3];
        gbuffer_unfiltered_means(cp->g, i, ud, ui);
        float sh = cp->factor ? cp->factor[i] : 1.0f, ad[3];
        gbuffer_direct_albedo(cp->g, i, ad);
        /* a split pixel whose first surface was filtered (usable): composite_split_light */
        float split_dir[3], split_ind[3];
        bool split = gbuffer_pixel_split(cp->g, i);
        bool split_d = split && cp->g->split_direct && cp->filtered_direct4 && cp->filtered_direct4[4 * i + 3] != 0.0f;
        bool split_i = split && cp->g->split_indirect && cp->filtered_indirect4 && cp->filtered_indirect4[4 * i + 3] != 0.0f;
        if (split_d) composite_split_light(cp->g, i, true, cp->filtered_direct4 + 4 * i, sh, split_dir);
        if (split_i) composite_split_light(cp->g, i, false, cp->filtered_indirect4 + 4 * i, 1.0f, split_ind);
        for (int k = 0; k < 3; ++k) {
            size_t j = 3 * i + (size_t)k;
            float a = sum_mean(f->albedo[j], spp, &ignored);
            /* emission + direct + indirect + unfiltered, added in this order */
            v[k] = sum_mean(f->emission[j], spp, &ignored);
            v[k] += split_d ? split_dir[k]
                    : cp->filtered_direct4 ? remodulate(cp->filtered_direct4 + 4 * i, k, ad[k], sh)
                                           : sum_mean(f->direct[j], spp, &ignored) - ud[k];
            v[k] += split_i ? split_ind[k]
                    : cp->filtered_indirect4 ? remodulate(cp->filtered_indirect4 + 4 * i, k, a, 1.0f)
                                             : sum_mean(f->indirect[j], spp, &ignored) - ui[k];
            v[k] += ud[k] + ui[k];
        }
        for (int k = 0; k < 3; ++k) cp->rgb[3 * i + (size_t)k] = v[k];
        if (cp->radiance4) {
            float *rv = cp->radiance4 + 4 * i;
            rv[0] = v[0], rv[1] = v[1], rv[2] = v[2], rv[3] = 1.0f;
        }
    }
}

/* The camera-effect filter's output (if any) into rgb; no non-finite value left, counted. */
typedef struct {
    float *rgb;
    const float *radiance4;       /* NULL: no camera-effect filter ran */
    long long guarded[RECON_PARTS];
    long long bad_pixels[RECON_PARTS];
} FinishPass;

static void finish_range(void *ctx, size_t begin, size_t end, int part)
{
    FinishPass *fp = ctx;
    long long bad = 0, bad_pixels = 0;
    for (size_t i = begin; i < end; ++i) {
        long long before = bad;
        for (int k = 0; k < 3; ++k) {
            float v = fp->radiance4 ? fp->radiance4[4 * i + (size_t)k] : fp->rgb[3 * i + (size_t)k];
            if (!isfinite(v)) {
                v = 0.0f;
                ++bad;
            }
            fp->rgb[3 * i + (size_t)k] = v;
        }
        bad_pixels += bad > before;
    }
    fp->guarded[part] = bad;
    fp->bad_pixels[part] = bad_pixels;
}

CompositeCounts composite_prepare(const GBuffer *g, const float *factor, float factor_min, float *direct4,
                                  float *indirect4)
{
    PreparePass prep = {g, factor, factor_min, direct4, indirect4, {0}, {0}};
    recon_parallel_for((size_t)g->width * (size_t)g->height, prepare_range, &prep);
    CompositeCounts c = {0, 0};
    for (int k = 0; k < RECON_PARTS; ++k) c.guarded += prep.guarded[k], c.bad_pixels += prep.bad_pixels[k];
    return c;
}

void composite_image(const GBuffer *g, const float *factor, const float *direct4, const float *indirect4, float *rgb,
                     float *radiance4)
{
    CompositePass comp = {g, factor, direct4, indirect4, rgb, radiance4};
    recon_parallel_for((size_t)g->width * (size_t)g->height, composite_range, &comp);
}

CompositeCounts composite_finish(float *rgb, const float *radiance4, size_t pixels)
{
    FinishPass fin = {rgb, radiance4, {0}, {0}};
    recon_parallel_for(pixels, finish_range, &fin);
    CompositeCounts c = {0, 0};
    for (int k = 0; k < RECON_PARTS; ++k) c.guarded += fin.guarded[k], c.bad_pixels += fin.bad_pixels[k];
    return c;
}
