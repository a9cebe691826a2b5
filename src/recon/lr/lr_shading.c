/* The light LR's samples carry beside a shading filter (see lr_shading.h). */
#include "recon/lr/lr_shading.h"

#include <math.h>
#include <stdlib.h>

#include "recon/recon_parallel.h"

/* Pixels whose depth differs more than this (relative) are other surfaces. */
#define LR_SAME_SURFACE_DEPTH 0.05f

LrShading lr_shading_of(const SampleStore *st)
{
    LrShading s = {sample_store_field(st, SAMPLE_FIELD_SHADING), sample_store_field(st, SAMPLE_FIELD_SHADING_DIRECT),
                   sample_store_field(st, SAMPLE_FIELD_SHADING_INDIRECT)};
    if (!s.base) s.direct = s.indirect = NULL;
    return s;
}

LrShading lr_shading_from(const LrShading *s, size_t first)
{
    return (LrShading){s->base ? s->base + first * LR_SHADING_BASE_FLOATS : NULL,
                       s->direct ? s->direct + first * LR_SHADING_DIRECT_FLOATS : NULL,
                       s->indirect ? s->indirect + first * LR_SHADING_INDIRECT_FLOATS : NULL};
}

bool lr_filtered_light(const float *value4, const float *factor, size_t i, float out[3])
{
    if (!value4 || value4[4 * i + 3] == 0.0f) return false;
    float f = factor ? factor[i] : 1.0f;
    for (int c = 0; c < 3; ++c) out[c] = f * value4[4 * i + c];
    return isfinite(out[0]) && isfinite(out[1]) && isfinite(out[2]);
}

/* The pixel of a w x h image containing (x_px, y_px), or -1 outside it (or NaN). */
static long pixel_at(int w, int h, float x_px, float y_px)
{
    if (!(x_px >= 0.0f && y_px >= 0.0f && x_px < (float)w && y_px < (float)h)) return -1;
    return (long)(int)y_px * w + (int)x_px;
}

size_t lr_light_pixel(const GBuffer *g, float x0_px, float y0_px, float depth, float object_id, size_t own)
{
    long p = pixel_at(g->width, g->height, x0_px, y0_px);
    if (!(depth < INFINITY) || p < 0) return own;
    size_t q = (size_t)p;
    bool same = g->nrm4[4 * q + 3] == object_id && fabsf(g->pos4[4 * q + 3] - depth) <= LR_SAME_SURFACE_DEPTH * depth;
    return same ? q : own;
}

/* Albedo below this is black: no light per unit albedo (composite.c's MIN_ALBEDO). */
#define LR_MIN_ALBEDO 1.0e-4f

typedef struct {
    const GBuffer *g;
    const SampleStore *st;
    const float *base;
    float *delta4;
} DeltaJob;

/* Pixels [begin, end) of lr_delta_light: each pixel reads only its own samples. */
static void delta_range(void *ctx, size_t begin, size_t end, int part)
{
    (void)part;
    const DeltaJob *j = ctx;
    const GBuffer *g = j->g;
    int cap = sample_store_capacity(j->st);
    for (size_t q = begin; q < end; ++q) {
        int count = sample_store_count(j->st, q);
        double a[3] = {0, 0, 0}, u[3] = {0, 0, 0};
        for (int k = 0; k < count; ++k) {
            const float *sh = j->base + (q * (size_t)cap + (size_t)k) * LR_SHADING_BASE_FLOATS;
            for (int c = 0; c < 3; ++c) a[c] += sh[c], u[c] += sh[4 + c];
        }
        float *d4 = j->delta4 + 4 * q;
        bool ok = count > 0 && g->hit[q] && !g->mixed[q];
        for (int c = 0; c < 3; ++c) {
            ok = ok && a[c] > LR_MIN_ALBEDO * count;
            d4[c] = ok ? (float)(u[c] / a[c]) : 0.0f;
        }
        d4[3] = ok && isfinite(d4[0]) && isfinite(d4[1]) && isfinite(d4[2]);
    }
}

void lr_delta_light(const GBuffer *g, const SampleStore *st, const float *base, float *delta4)
{
    DeltaJob j = {g, st, base, delta4};
    recon_parallel_for((size_t)g->width * (size_t)g->height, delta_range, &j);
}

/* Sample k's light with its filterable direct and indirect light replaced by albedo times the
 * filtered light, and its delta lights' light by albedo times their pixel mean (ed, ei, eu:
 * NULL leaves that part as it is; s: the pixel's rows, NULL for none). */
static void replaced_light(const float *radiance, const LrShading *s, int k, const float *ed, const float *ei,
                           const float *eu, float out[3])
{
    const float *b = s ? s->base + LR_SHADING_BASE_FLOATS * k : NULL;
    const float *d = s && s->direct ? s->direct + LR_SHADING_DIRECT_FLOATS * k : NULL;
    const float *i = s && s->indirect ? s->indirect + LR_SHADING_INDIRECT_FLOATS * k : NULL;
    for (int c = 0; c < 3; ++c) {
        out[c] = radiance[c];
        if (ed && d) out[c] += d[3 + c] * ed[c] - d[c];
        if (ei && i) out[c] += b[c] * ei[c] - i[c];
        if (eu && b) out[c] += b[c] * eu[c] - b[4 + c];
    }
}

/* The centre light of sample k for one part (3 floats), or NULL where it has none. */
static const float *centre_part(const float *centre9, int k, int part)
{
    if (!centre9) return NULL;
    const float *v = centre9 + 9 * k + 3 * part;
    return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]) ? v : NULL;
}

void lr_pixel_light(int n, const float *radiance, const LrShading *shading, const size_t *src,
                    const ReconShadingLight *light, const float *delta4, const float *centre9, const float value[3],
                    float *out)
{
    double sum[3] = {0.0, 0.0, 0.0};
    for (int k = 0; k < n; ++k) {
        float ed_buf[3], ei_buf[3], eu_buf[3];
        const float *ed = NULL, *ei = NULL, *eu = NULL;
        if (shading && shading->base && light && src) {
            /* a part the shading filters left out keeps its own light unless the centre frame
             * has its object's (8.19); a part no filter touched stays as it is */
            ed = lr_filtered_light(light->direct4, light->direct_factor, src[k], ed_buf) ? ed_buf
                 : light->direct4                                                        ? centre_part(centre9, k, 0)
                                                                                         : NULL;
            ei = lr_filtered_light(light->indirect4, NULL, src[k], ei_buf) ? ei_buf
                 : light->indirect4                                      ? centre_part(centre9, k, 1)
                                                                         : NULL;
            eu = lr_filtered_light(delta4, NULL, src[k], eu_buf) ? eu_buf : delta4 ? centre_part(centre9, k, 2) : NULL;
        }
        /* into a local first: summing from out re-read floats just stored one by one, and
         * the processor could not forward them (a stall per sample, ~3% of a warm LR frame) */
        float light_k[3];
        replaced_light(radiance + 3 * k, shading && shading->base ? shading : NULL, k, ed, ei, eu, light_k);
        for (int c = 0; c < 3; ++c) {
            out[3 * k + c] = light_k[c];
            sum[c] += light_k[c];
        }
    }
    for (int c = 0; c < 3; ++c) {
        float shift = n > 0 ? (float)(value[c] - sum[c] / n) : 0.0f;
        if (!isfinite(shift)) shift = 0.0f; /* a non-finite mean: the sample itself counts it */
        for (int k = 0; k < n; ++k) out[3 * k + c] += shift;
    }
}

/* Per bin of the lens-centre, mid-shutter frame and object slot: sums of the filterable
 * direct, indirect and delta lights and of the albedo and the diffuse albedo (the direct
 * light's, LrShading) (rgb each) of one object's samples. A
 * bin has LR_CENTRE_SLOTS slots: where two surfaces meet at mid-shutter (a moving object's
 * edge over the floor it stands on) both keep their light. */
enum { CL_SD = 0, CL_SI = 3, CL_SU = 6, CL_A = 9, CL_AD = 12, CL_SUMS = 15, LR_CENTRE_SLOTS = 2 };

/* The slot of bin q holding object `object`, or -1; with claim, an empty slot is taken. */
static int slot_of(float *id, size_t q, float object, bool claim)
{
    for (int k = 0; k < LR_CENTRE_SLOTS; ++k) {
        float *s = &id[q * LR_CENTRE_SLOTS + (size_t)k];
        if (*s == object) return k;
        if (isnan(*s)) {
            if (!claim) return -1;
            *s = object;
            return k;
        }
    }
    return -1;
}

typedef struct {
    LrCentreLight *cl;
    const float *sums; /* per bin and slot, CL_SUMS floats */
} BoxJob;

/* Rows [begin, end) of the centre light's box (lr_centre_light_build). */
static void box_rows(void *ctx, size_t begin, size_t end, int part)
{
    (void)part;
    const BoxJob *j = ctx;
    LrCentreLight *cl = j->cl;
    float *id = cl->id;
    int w = cl->width, h = cl->height, r = LR_CENTRE_RADIUS_PX;
    for (int y = (int)begin; y < (int)end; ++y)
        for (int x = 0; x < w; ++x)
            for (int a = 0; a < LR_CENTRE_SLOTS; ++a) {
                size_t q = (size_t)y * (size_t)w + (size_t)x, qa = q * LR_CENTRE_SLOTS + (size_t)a;
                float b[CL_SUMS] = {0}, *o = cl->light + qa * 9;
                for (int c = 0; c < 9; ++c) o[c] = NAN;
                if (isnan(id[qa])) continue;
                for (int dy = -r; dy <= r; ++dy)
                    for (int dx = -r; dx <= r; ++dx) {
                        int xx = x + dx, yy = y + dy;
                        if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
                        size_t p = (size_t)yy * (size_t)w + (size_t)xx;
                        int sp = slot_of(id, p, id[qa], false);
                        if (sp < 0) continue;
                        const float *src = j->sums + (p * LR_CENTRE_SLOTS + (size_t)sp) * CL_SUMS;
                        for (int c = 0; c < CL_SUMS; ++c) b[c] += src[c];
                    }
                for (int c = 0; c < 3; ++c) {
                    float alb = b[CL_A + c], alb_d = b[CL_AD + c];
                    if (alb_d > LR_MIN_ALBEDO) o[c] = b[CL_SD + c] / alb_d;
                    if (!(alb > LR_MIN_ALBEDO)) continue;
                    o[3 + c] = b[CL_SI + c] / alb, o[6 + c] = b[CL_SU + c] / alb;
                }
            }
}

bool lr_centre_light_build(LrCentreLight *cl, const GBuffer *g, const SampleStore *st, const LrShading *shading,
                           const float *centre_xy)
{
    size_t n = (size_t)g->width * (size_t)g->height, bins = n * LR_CENTRE_SLOTS;
    int cap = sample_store_capacity(st);
    cl->width = g->width, cl->height = g->height;
    float *sums = calloc(bins * CL_SUMS, sizeof(float));
    cl->id = malloc(sizeof(float) * bins);
    cl->light = malloc(sizeof(float) * 9 * bins);
    if (!sums || !cl->id || !cl->light) {
        free(sums);
        lr_centre_light_free(cl);
        return false;
    }
    float *id = cl->id;
    for (size_t q = 0; q < bins; ++q) id[q] = NAN; /* empty */
    /* Each sample lands in the bin of its point's lens-centre, mid-shutter position; the first
     * objects to land (pixel order: deterministic) get the slots, later ones are dropped. */
    for (size_t i = 0; i < n; ++i)
        for (int k = 0; k < sample_store_count(st, i); ++k) {
            size_t j = i * (size_t)cap + (size_t)k;
            const float *b = shading->base + j * LR_SHADING_BASE_FLOATS;
            long q = pixel_at(g->width, g->height, centre_xy[2 * j], centre_xy[2 * j + 1]);
            int slot = q >= 0 && b[3] >= 0.0f ? slot_of(id, (size_t)q, b[3], true) : -1;
            if (slot < 0) continue;
            float *s = sums + ((size_t)q * LR_CENTRE_SLOTS + (size_t)slot) * CL_SUMS;
            /* a light the frame does not filter keeps 0 sums: its part is never read (lr_pixel_light) */
            const float *d = shading->direct ? shading->direct + j * LR_SHADING_DIRECT_FLOATS : NULL;
            const float *i = shading->indirect ? shading->indirect + j * LR_SHADING_INDIRECT_FLOATS : NULL;
            for (int c = 0; c < 3; ++c) {
                if (d) s[CL_SD + c] += d[c], s[CL_AD + c] += d[3 + c];
                if (i) s[CL_SI + c] += i[c];
                s[CL_SU + c] += b[4 + c], s[CL_A + c] += b[c];
            }
        }
    /* A box of LR_CENTRE_RADIUS_PX around each bin, over the slots of the same object, then
     * the light per unit albedo: each bin's own sum in a fixed order, so rows split freely. */
    BoxJob j = {cl, sums};
    recon_parallel_for_work((size_t)g->height, n, box_rows, &j);
    free(sums);
    return true;
}

const float *lr_centre_light_at(const LrCentreLight *cl, float x_px, float y_px, float object_id)
{
    long q = cl && cl->light ? pixel_at(cl->width, cl->height, x_px, y_px) : -1;
    if (q < 0) return NULL;
    int slot = slot_of(cl->id, (size_t)q, object_id, false);
    return slot >= 0 ? cl->light + ((size_t)q * LR_CENTRE_SLOTS + (size_t)slot) * 9 : NULL;
}

void lr_centre_light_free(LrCentreLight *cl)
{
    free(cl->id), free(cl->light);
    cl->id = cl->light = NULL;
}
