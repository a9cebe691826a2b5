/* The shared per-pixel guides (see gbuffer.h). */
#include "recon/gbuffer.h"

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/zalloc.h"
#include "recon/recon_parallel.h"

ReconCamera recon_camera_from(const Camera *c)
{
    ReconCamera m;
    m.lens_radius_world = c->lens_radius_world;
    m.focal_distance_world = c->focal_distance_world;
    /* screen units per pixel, times tan(fov/2): world size of one pixel at camera depth 1 */
    m.pixel_angle = (c->screen_max[0] - c->screen_min[0]) / (float)c->width_px * c->tan_half_fov;
    return m;
}

/* Thin lens (pbrt-v4): the ray from lens point R u through the in-focus point crosses depth z
 * displaced by R u (1 - F/z) from where the pinhole ray does; one pixel at depth F is
 * F * pixel_angle wide, and the displacement, seen from the lens centre, shrinks with the
 * same F/z as everything else on that plane. Slope = R (1 - F/z) / (F pixel_angle) px per
 * unit u, the form below; z = inf gives R/(F pixel_angle). */
float recon_coc_slope_px(const ReconCamera *cam, float depth_cam)
{
    float R = cam->lens_radius_world, F = cam->focal_distance_world, a = cam->pixel_angle;
    if (!(R > 0.0f) || !(F > 0.0f) || !(a > 0.0f)) return 0.0f;
    float inv_z = (depth_cam > 0.0f) ? 1.0f / depth_cam : 0.0f; /* inf -> 0; behind: treat as far */
    float s = (R / a) * (1.0f / F - inv_z);
    return isfinite(s) ? s : (s > 0.0f ? FLT_MAX : -FLT_MAX);
}

/* The arrays of one GBuffer, in allocation order: element size and count per pixel. */
typedef struct {
    size_t offset, size, per_pixel;
} Slot;

enum { S_SUMS, S_HIT, S_MIXED, S_GLOSSY, S_ALBEDO_VARIES, S_LOBE4, S_POS4, S_NRM4, S_PIXEL_WORLD, S_COUNT };

static const struct {
    size_t size, per_pixel;
} SLOT_SHAPE[S_COUNT] = {
    [S_SUMS] = {sizeof(GBufferSums), 1}, [S_HIT] = {1, 1}, [S_MIXED] = {1, 1}, [S_GLOSSY] = {1, 1}, [S_ALBEDO_VARIES] = {1, 1},
    [S_LOBE4] = {sizeof(float), 4},      [S_POS4] = {sizeof(float), 4}, [S_NRM4] = {sizeof(float), 4},
    [S_PIXEL_WORLD] = {sizeof(float), 1},
};

/* Offsets of every slot in one block (each 16-byte aligned); returns the block's size, 0 on
 * overflow. */
static size_t layout(size_t n, size_t offsets[S_COUNT])
{
    size_t at = 0;
    for (int s = 0; s < S_COUNT; ++s) {
        size_t per = SLOT_SHAPE[s].size * SLOT_SHAPE[s].per_pixel;
        if (n > SIZE_MAX / 2 / per) return 0;
        offsets[s] = at;
        at += (n * per + 15) & ~(size_t)15;
    }
    return at;
}

size_t gbuffer_bytes(int width, int height)
{
    size_t n = (size_t)width * (size_t)height, off[S_COUNT];
    /* the frame: 6 rgb sums and 3 scalars per pixel (render/frame.h) */
    return layout(n, off) + n * (6 * 3 + 3) * sizeof(float);
}

bool gbuffer_init(GBuffer *g, int width, int height, ReconCamera cam)
{
    memset(g, 0, sizeof *g);
    if (width <= 0 || height <= 0) return false;
    size_t n = (size_t)width * (size_t)height, off[S_COUNT];
    size_t bytes = layout(n, off);
    if (bytes == 0 || !frame_init(&g->frame, width, height)) return false;
    unsigned char *b = zalloc(bytes, 1);
    if (!b) {
        frame_free(&g->frame);
        return false;
    }
    g->block_ = b;
    g->width = width;
    g->height = height;
    g->cam = cam;
    g->sums = (GBufferSums *)(b + off[S_SUMS]);
    g->hit = b + off[S_HIT];
    g->mixed = b + off[S_MIXED];
    g->glossy = b + off[S_GLOSSY];
    g->albedo_varies = b + off[S_ALBEDO_VARIES];
    g->lobe4 = (float *)(b + off[S_LOBE4]);
    g->pos4 = (float *)(b + off[S_POS4]);
    g->nrm4 = (float *)(b + off[S_NRM4]);
    g->pixel_world = (float *)(b + off[S_PIXEL_WORLD]);
    /* until gbuffer_track_split */
    g->spos4 = g->pos4, g->snrm4 = g->nrm4, g->spixel_world = g->pixel_world, g->salbedo_varies = g->albedo_varies;
    for (size_t i = 0; i < n; ++i) g->sums[i].object_id = -1;
    return true;
}

bool gbuffer_init_frame(GBuffer *g, int width, int height, ReconCamera cam, unsigned frame_planes)
{
    memset(g, 0, sizeof *g);
    if (width <= 0 || height <= 0 || !frame_init_planes(&g->frame, width, height, frame_planes)) return false;
    g->width = width;
    g->height = height;
    g->cam = cam;
    return true;
}

bool gbuffer_track_split(GBuffer *g, bool direct, bool indirect)
{
    g->split_direct = direct;
    g->split_indirect = indirect;
    if (!direct && !indirect) return true;
    size_t n = (size_t)g->width * (size_t)g->height;
    /* calloc, not zalloc: only the pixels that see a second surface write their others' sums */
    if (!(g->others = calloc(n, sizeof *g->others))) return false;
    g->split_share = calloc(n, sizeof(float));
    g->spos4 = malloc(4 * n * sizeof(float));
    g->snrm4 = malloc(4 * n * sizeof(float));
    g->spixel_world = malloc(n * sizeof(float));
    g->salbedo_varies = malloc(n);
    return g->split_share && g->spos4 && g->snrm4 && g->spixel_world && g->salbedo_varies;
}

void gbuffer_free(GBuffer *g)
{
    frame_free(&g->frame);
    free(g->block_);
    if (g->others) { /* gbuffer_track_split's own arrays */
        free(g->spos4);
        free(g->snrm4);
        free(g->spixel_world);
        free(g->salbedo_varies);
    }
    free(g->others);
    free(g->split_share);
    memset(g, 0, sizeof *g);
}

bool gbuffer_sample_glossy(const SampleRecord *r)
{
    return r->hit && r->phong_exponent > GLOSSY_DIRECT_MIN_EXPONENT &&
           v3_luminance(r->albedo_glossy) > GLOSSY_DIRECT_SHARE * v3_luminance(r->albedo);
}

/* The sample's unfiltered light, split, into the pixel's sums (gbuffer_add's and
 * gbuffer_add_unfiltered's, the same additions in the same order). */
static inline void unfiltered_add(GBufferSums *s, const SampleRecord *r)
{
    float ud[3], ui[3];
    gbuffer_unfiltered_split(r, ud, ui);
    for (int k = 0; k < 3; ++k) {
        s->unf_direct_sum[k] += ud[k];
        s->unf_indirect_sum[k] += ui[k];
    }
}

void gbuffer_add_unfiltered(void *ctx, int px, int py, const SampleRecord *r)
{
    GBuffer *g = ctx;
    /* gbuffer_add's tests: the samples it sums are these */
    if (px < 0 || py < 0 || px >= g->width || py >= g->height) return;
    if (!r->hit) return;
    if (!(isfinite(r->p_world.x) && isfinite(r->p_world.y) && isfinite(r->p_world.z))) return;
    unfiltered_add(&g->sums[(size_t)py * (size_t)g->width + (size_t)px], r);
}

/* A sample off its pixel's first surface into the others' sums (GBufferOtherSums); at_hit: one
 * GBufferSums counted (a hit at a finite position), whose guides' terms come here too. */
static void others_add(GBufferOtherSums *o, const SampleRecord *r, bool at_hit)
{
    float ud[3], ui[3];
    gbuffer_unfiltered_split(r, ud, ui);
    const float dir[3] = {r->direct.x, r->direct.y, r->direct.z}, ind[3] = {r->indirect.x, r->indirect.y, r->indirect.z};
    const float alb[3] = {r->albedo.x, r->albedo.y, r->albedo.z};
    const float alb_d[3] = {r->albedo_diffuse.x, r->albedo_diffuse.y, r->albedo_diffuse.z};
    bool lobed = gbuffer_sample_lobed(r);
    for (int k = 0; k < 3; ++k) {
        o->direct_sum[k] += dir[k] - ud[k];
        o->indirect_sum[k] += ind[k] - ui[k];
        o->albedo_sum[k] += alb[k];
        o->albedo_direct_sum[k] += lobed ? alb_d[k] : alb[k];
    }
    if (!at_hit) return;
    o->hits++;
    float a = v3_luminance(r->albedo);
    if (isfinite(a)) o->albedo_lum_sum += a, o->albedo_lum_sq_sum += a * a;
    o->pos_sum[0] += r->p_world.x, o->pos_sum[1] += r->p_world.y, o->pos_sum[2] += r->p_world.z;
    o->nrm_sum[0] += r->n_shading.x, o->nrm_sum[1] += r->n_shading.y, o->nrm_sum[2] += r->n_shading.z;
    if (isfinite(r->depth_cam)) {
        o->depth_sum += r->depth_cam;
        o->depth_sq_sum += (double)r->depth_cam * (double)r->depth_cam;
    }
}

void gbuffer_add(void *ctx, int px, int py, const SampleRecord *r)
{
    GBuffer *g = ctx;
    if (px < 0 || py < 0 || px >= g->width || py >= g->height) return;
    if (!r->hit) return;
    size_t i = (size_t)py * (size_t)g->width + (size_t)px;
    if (!(isfinite(r->p_world.x) && isfinite(r->p_world.y) && isfinite(r->p_world.z))) {
        /* the frame sums its light and albedo: off the first surface */
        if (g->others) others_add(&g->others[i], r, false);
        return;
    }
    GBufferSums *s = &g->sums[i];
    s->hits++;
    if (s->object_id < 0) s->object_id = r->object_id;
    else if (s->object_id != r->object_id) s->id_mixed = 1;
    if (g->others && !gbuffer_on_first_surface(g, i, r)) others_add(&g->others[i], r, true);
    if (r->unfilterable) s->unfilterable++;
    if (gbuffer_sample_glossy(r)) s->glossy++;
    float a = v3_luminance(r->albedo);
    if (isfinite(a)) s->albedo_sum += a, s->albedo_sq_sum += a * a;
    if (gbuffer_sample_lobed(r)) {
        float *l = g->lobe4 + 4 * ((size_t)py * (size_t)g->width + (size_t)px);
        l[0] += r->albedo.x - r->albedo_diffuse.x;
        l[1] += r->albedo.y - r->albedo_diffuse.y;
        l[2] += r->albedo.z - r->albedo_diffuse.z;
        l[3] += 1.0f;
    }
    unfiltered_add(s, r);
    s->pos_sum[0] += r->p_world.x;
    s->pos_sum[1] += r->p_world.y;
    s->pos_sum[2] += r->p_world.z;
    s->nrm_sum[0] += r->n_shading.x;
    s->nrm_sum[1] += r->n_shading.y;
    s->nrm_sum[2] += r->n_shading.z;
    if (isfinite(r->depth_cam)) {
        s->depth_sum += r->depth_cam;
        s->depth_sq_sum += (double)r->depth_cam * (double)r->depth_cam;
    }
}

void gbuffer_unfiltered_split(const SampleRecord *r, float direct[3], float indirect[3])
{
    float u[3] = {r->unfiltered.x, r->unfiltered.y, r->unfiltered.z};
    float ind[3] = {r->indirect.x, r->indirect.y, r->indirect.z};
    float ud[3] = {r->unfiltered_direct.x, r->unfiltered_direct.y, r->unfiltered_direct.z};
    for (int k = 0; k < 3; ++k) {
        float uk = isfinite(u[k]) && u[k] > 0.0f ? u[k] : 0.0f;
        /* fminf(uk, fmaxf(ind, 0)) as comparisons: the two library calls per channel were
         * most of this function's cost, which runs for every sample of a filtered frame.
         * The same values (a NaN indirect gives 0; uk is never NaN). */
        float ind_pos = ind[k] >= 0.0f ? ind[k] : 0.0f;
        float ui = uk <= ind_pos ? uk : ind_pos;
        float dk = isfinite(ud[k]) && ud[k] > 0.0f ? ud[k] : 0.0f;
        indirect[k] = ui;
        direct[k] = uk - ui + dk;
    }
    /* the glossy lobes' direct light (+0 at a Lambert hit, which skips this) */
    if (!gbuffer_sample_lobed(r)) return;
    float dg[3] = {r->direct_glossy.x, r->direct_glossy.y, r->direct_glossy.z};
    for (int k = 0; k < 3; ++k) direct[k] += dg[k] > 0.0f && dg[k] < INFINITY ? dg[k] : 0.0f;
}

void gbuffer_direct_albedo(const GBuffer *g, size_t i, float a[3])
{
    float spp = g->frame.spp[i], sum[3];
    gbuffer_direct_albedo_sum(g, i, sum);
    for (int k = 0; k < 3; ++k) {
        float v = spp > 0.0f ? sum[k] / spp : 0.0f; /* composite.c's sum_mean */
        a[k] = isfinite(v) ? v : 0.0f;
    }
}

void gbuffer_unfiltered_means(const GBuffer *g, size_t i, float direct[3], float indirect[3])
{
    float spp = g->frame.spp[i];
    float inv = spp > 0.0f ? 1.0f / spp : 0.0f;
    for (int k = 0; k < 3; ++k) {
        float d = g->sums[i].unf_direct_sum[k] * inv, u = g->sums[i].unf_indirect_sum[k] * inv;
        direct[k] = isfinite(d) ? d : 0.0f;
        indirect[k] = isfinite(u) ? u : 0.0f;
    }
}

/* MIXED_NORMAL_COHERENCE, MIXED_DEPTH_REL_STD: gbuffer.h */

/* Pixel i's split guides (gbuffer.h): a mixed pixel's first surface, the samples not in the
 * others' sums, tested by the mixed rule's coherence terms (its samples share one object and
 * are filterable by construction); spos4, snrm4 and spixel_world are pos4, nrm4 and
 * pixel_world elsewhere. */
static void resolve_split(GBuffer *g, size_t i)
{
    memcpy(g->spos4 + 4 * i, g->pos4 + 4 * i, 4 * sizeof(float));
    memcpy(g->snrm4 + 4 * i, g->nrm4 + 4 * i, 4 * sizeof(float));
    g->spixel_world[i] = g->pixel_world[i];
    /* a mixed pixel that is not split is no shading filter's input nor any filter's neighbour */
    g->salbedo_varies[i] = g->albedo_varies[i] && !g->mixed[i];
    g->split_share[i] = 0.0f;
    const GBufferSums *s = &g->sums[i];
    const GBufferOtherSums *o = &g->others[i];
    int hits = s->hits - o->hits;
    float spp = g->frame.spp[i];
    if (!g->mixed[i] || hits <= 0 || !(spp > 0.0f)) return;
    float inv = 1.0f / (float)hits, pos[3], nrm[3], nl = 0.0f;
    for (int k = 0; k < 3; ++k) {
        pos[k] = (s->pos_sum[k] - o->pos_sum[k]) * inv;
        nrm[k] = s->nrm_sum[k] - o->nrm_sum[k];
        nl += nrm[k] * nrm[k];
    }
    nl = sqrtf(nl);
    float depth = (s->depth_sum - o->depth_sum) * inv;
    double var = (s->depth_sq_sum - o->depth_sq_sum) / hits - (double)depth * (double)depth;
    float depth_rel_std = depth > 0.0f && var > 0.0 ? (float)(sqrt(var) / depth) : 0.0f;
    bool coherent = nl >= MIXED_NORMAL_COHERENCE * (float)hits && depth_rel_std <= MIXED_DEPTH_REL_STD;
    if (!coherent || !(depth > 0.0f) || !isfinite(pos[0] + pos[1] + pos[2] + depth)) return;
    for (int k = 0; k < 3; ++k) {
        g->spos4[4 * i + k] = pos[k];
        g->snrm4[4 * i + k] = nrm[k] / nl;
    }
    g->spos4[4 * i + 3] = depth;
    g->snrm4[4 * i + 3] = (float)s->object_id;
    g->spixel_world[i] = depth * g->cam.pixel_angle;
    float a_mean = (s->albedo_sum - o->albedo_lum_sum) * inv, a_var = (s->albedo_sq_sum - o->albedo_lum_sq_sum) * inv - a_mean * a_mean;
    g->salbedo_varies[i] = a_mean > 0.0f && a_var > ALBEDO_VARIES_REL_STD * ALBEDO_VARIES_REL_STD * a_mean * a_mean;
    g->split_share[i] = fminf((float)hits / spp, 1.0f);
}

float gbuffer_shading_normal_coherence(const GBuffer *g, size_t i)
{
    const GBufferSums *s = &g->sums[i];
    bool split = g->others && gbuffer_pixel_split(g, i);
    int hits = s->hits - (split ? g->others[i].hits : 0);
    if (hits <= 0) return 1.0f;
    float nl = 0.0f;
    for (int k = 0; k < 3; ++k) {
        float n = s->nrm_sum[k] - (split ? g->others[i].nrm_sum[k] : 0.0f);
        nl += n * n;
    }
    nl = sqrtf(nl) / (float)hits;
    return nl < 1.0f ? nl : 1.0f;
}

void gbuffer_first_surface_sums(const GBuffer *g, size_t i, bool direct, float *count, float light[3], float albedo[3])
{
    const GBufferSums *s = &g->sums[i];
    const GBufferOtherSums *o = &g->others[i];
    const float *frame_light = direct ? g->frame.direct : g->frame.indirect;
    const float *unf = direct ? s->unf_direct_sum : s->unf_indirect_sum;
    const float *o_light = direct ? o->direct_sum : o->indirect_sum, *o_albedo = direct ? o->albedo_direct_sum : o->albedo_sum;
    float a[3];
    if (direct) gbuffer_direct_albedo_sum(g, i, a);
    else memcpy(a, g->frame.albedo + 3 * i, sizeof a);
    *count = (float)(s->hits - o->hits);
    for (int k = 0; k < 3; ++k) {
        light[k] = frame_light[3 * i + k] - unf[k] - o_light[k];
        float ak = a[k] - o_albedo[k];
        albedo[k] = ak > 0.0f ? ak : 0.0f;
    }
}

/* Each core takes a range of pixels and its own bounding box of the hit points. */
typedef struct {
    GBuffer *g;
    float lo[RECON_PARTS][3], hi[RECON_PARTS][3];
} GuidesPass;

static void guides_range(void *ctx, size_t begin, size_t end, int part)
{
    GuidesPass *gp = ctx;
    GBuffer *g = gp->g;
    float lo[3] = {FLT_MAX, FLT_MAX, FLT_MAX}, hi[3] = {-FLT_MAX, -FLT_MAX, -FLT_MAX};
    for (size_t i = begin; i < end; ++i) {
        const GBufferSums *s = &g->sums[i];
        int hits = s->hits;
        g->hit[i] = hits > 0;
        for (int k = 0; k < 4; ++k) g->pos4[4 * i + k] = g->nrm4[4 * i + k] = 0.0f;
        g->nrm4[4 * i + 3] = -1.0f;
        g->pixel_world[i] = 0.0f;
        g->mixed[i] = 0;
        g->glossy[i] = s->glossy > 0;
        g->albedo_varies[i] = 0;
        if (hits == 0) continue;
        float inv = 1.0f / (float)hits;
        float a_mean = s->albedo_sum * inv, a_var = s->albedo_sq_sum * inv - a_mean * a_mean;
        g->albedo_varies[i] = a_mean > 0.0f && a_var > ALBEDO_VARIES_REL_STD * ALBEDO_VARIES_REL_STD * a_mean * a_mean;
        float nl = 0;
        for (int k = 0; k < 3; ++k) {
            float p = s->pos_sum[k] * inv;
            g->pos4[4 * i + k] = p;
            lo[k] = fminf(lo[k], p);
            hi[k] = fmaxf(hi[k], p);
            nl += s->nrm_sum[k] * s->nrm_sum[k];
        }
        nl = sqrtf(nl);
        for (int k = 0; k < 3; ++k) g->nrm4[4 * i + k] = nl > 0.0f ? s->nrm_sum[k] / nl : 0.0f;
        g->nrm4[4 * i + 3] = (float)s->object_id;
        float depth = s->depth_sum * inv;
        double var = s->depth_sq_sum / hits - (double)depth * (double)depth;
        float depth_rel_std = depth > 0.0f && var > 0.0 ? (float)(sqrt(var) / depth) : 0.0f;
        g->mixed[i] = s->id_mixed || (float)hits < g->frame.spp[i] || s->unfilterable > 0 ||
                      nl < MIXED_NORMAL_COHERENCE * (float)hits || depth_rel_std > MIXED_DEPTH_REL_STD;
        g->pos4[4 * i + 3] = depth;
        /* AAF-shadow Sec. 4.1: d = world length one pixel covers at the receiver (we leave out
         * foreshortening, which only makes d smaller and a filter more conservative). */
        g->pixel_world[i] = depth * g->cam.pixel_angle;
    }
    if (g->split_share)
        for (size_t i = begin; i < end; ++i) resolve_split(g, i);
    for (int k = 0; k < 3; ++k) {
        gp->lo[part][k] = lo[k];
        gp->hi[part][k] = hi[k];
    }
}

void gbuffer_resolve_guides(GBuffer *g)
{
    size_t n = (size_t)g->width * (size_t)g->height;
    GuidesPass gp;
    gp.g = g;
    recon_parallel_for(n, guides_range, &gp);
    /* min and max are exact, so the box does not depend on the split */
    float diag2 = 0;
    for (int k = 0; k < 3; ++k) {
        float lo = FLT_MAX, hi = -FLT_MAX;
        for (int p = 0; p < RECON_PARTS; ++p) {
            lo = fminf(lo, gp.lo[p][k]);
            hi = fmaxf(hi, gp.hi[p][k]);
        }
        diag2 += hi > lo ? (hi - lo) * (hi - lo) : 0.0f;
    }
    g->scene_size_world = sqrtf(diag2);
}
