/* The per-sample store (see sample_store.h). */
#include "recon/sample_store.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/huge_pages.h"
#include "core/zalloc.h"
#include "recon/gbuffer.h"

static const struct {
    unsigned bit;
    int components;
    const char *name;
} FIELDS[SAMPLE_FIELD_COUNT_] = {
    {SAMPLE_FIELD_FILM, 2, "film"},         {SAMPLE_FIELD_LENS, 2, "lens"},
    {SAMPLE_FIELD_TIME, 1, "time"},         {SAMPLE_FIELD_DEPTH, 1, "depth"},
    {SAMPLE_FIELD_RADIANCE, 3, "radiance"}, {SAMPLE_FIELD_DIRECT, 3, "direct"},
    {SAMPLE_FIELD_INDIRECT, 3, "indirect"}, {SAMPLE_FIELD_POSITION, 3, "position"},
    {SAMPLE_FIELD_NORMAL, 3, "normal"},     {SAMPLE_FIELD_LIGHT, 5, "light"},
    {SAMPLE_FIELD_BOUNCE, 4, "bounce"},     {SAMPLE_FIELD_MOTION, 2, "motion"},
    {SAMPLE_FIELD_SHADING, 7, "shading"},   {SAMPLE_FIELD_LR_PLACE, 8, "lr_place"},
    {SAMPLE_FIELD_LR_KEY, 4, "lr_key"},     {SAMPLE_FIELD_SHADING_DIRECT, 6, "shading_direct"},
    {SAMPLE_FIELD_SHADING_INDIRECT, 3, "shading_indirect"},
};
_Static_assert(SAMPLE_FIELD_COUNT_ == 17 && SAMPLE_FIELD_SHADING == 1u << 12 && SAMPLE_FIELD_MOTION == 1u << 11 &&
                   SAMPLE_FIELD_LR_PLACE == 1u << 13 && SAMPLE_FIELD_LR_KEY == 1u << 14 &&
                   SAMPLE_FIELD_SHADING_DIRECT == 1u << 15 && SAMPLE_FIELD_SHADING_INDIRECT == 1u << 16,
               "sample_store_add writes field 1 << n at field[n]");

struct SampleStore {
    unsigned fields;
    int width, height, capacity;
    int *count;                       /* per pixel */
    float *field[SAMPLE_FIELD_COUNT_];
    long long dropped;                /* atomic */
};

int sample_field_components(unsigned field)
{
    for (int f = 0; f < SAMPLE_FIELD_COUNT_; ++f)
        if (FIELDS[f].bit == field) return FIELDS[f].components;
    return 0;
}

const char *sample_field_name(unsigned field)
{
    for (int f = 0; f < SAMPLE_FIELD_COUNT_; ++f)
        if (FIELDS[f].bit == field) return FIELDS[f].name;
    return "?";
}

size_t sample_store_bytes(unsigned fields, int width, int height, int capacity)
{
    if (width <= 0 || height <= 0 || capacity < 0) return SIZE_MAX;
    size_t pixels = (size_t)width * (size_t)height, floats = 0;
    for (int f = 0; f < SAMPLE_FIELD_COUNT_; ++f)
        if (fields & FIELDS[f].bit) floats += (size_t)FIELDS[f].components;
    if (pixels > SIZE_MAX / sizeof(int)) return SIZE_MAX;
    size_t per_pixel = floats * sizeof(float);
    if (capacity > 0 && per_pixel > SIZE_MAX / (size_t)capacity) return SIZE_MAX;
    per_pixel *= (size_t)capacity;
    if (pixels > (SIZE_MAX - pixels * sizeof(int)) / (per_pixel ? per_pixel : 1)) return SIZE_MAX;
    return pixels * sizeof(int) + pixels * per_pixel;
}

size_t sample_store_default_limit(void)
{
    long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    if (pages <= 0 || page <= 0) return (size_t)4 << 30; /* unknown: 4 GiB */
    return (size_t)pages / 2 * (size_t)page;
}

bool sample_store_create(unsigned fields, int width, int height, int capacity, size_t mem_limit,
                         SampleStore **out, Diag *d)
{
    *out = NULL;
    size_t bytes = sample_store_bytes(fields, width, height, capacity);
    if (bytes == SIZE_MAX || bytes > mem_limit) {
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0},
                 "the per-sample store for %dx%d pixels at %d samples per pixel needs %.2f GiB, over the memory "
                 "limit of %.2f GiB: lower --res or --spp, raise --mem-limit, or choose a filter that keeps "
                 "per-pixel sums (--filter aaf)",
                 width, height, capacity, bytes == SIZE_MAX ? INFINITY : (double)bytes / (1u << 30),
                 (double)mem_limit / (1u << 30));
        return false;
    }
    SampleStore *s = calloc(1, sizeof *s);
    size_t pixels = (size_t)width * (size_t)height;
    bool ok = s && (s->count = zalloc(pixels, sizeof(int))) != NULL;
    for (int f = 0; ok && f < SAMPLE_FIELD_COUNT_; ++f)
        if (fields & FIELDS[f].bit)
            /* written once a frame, sample by sample: in 2 MB pages where the machine has them to spare
             * (huge_pages.h), one page fault per 2 MB instead of per 4 KB; from malloc's start, not a
             * 2 MB boundary (LR's gather reads the fields in step: huge_pages_malloc) */
            ok = (s->field[f] = huge_pages_malloc(pixels * (size_t)capacity * (size_t)FIELDS[f].components *
                                                 sizeof(float) + 1)) != NULL;
    if (!ok) {
        sample_store_destroy(s);
        diag_set(d, WEDGE_EXIT_RUNTIME, (SrcLoc){0}, "out of memory for the per-sample store (%.2f GiB)",
                 (double)bytes / (1u << 30));
        return false;
    }
    s->fields = fields;
    s->width = width;
    s->height = height;
    s->capacity = capacity;
    *out = s;
    return true;
}

void sample_store_destroy(SampleStore *s)
{
    if (!s) return;
    free(s->count);
    for (int f = 0; f < SAMPLE_FIELD_COUNT_; ++f) free(s->field[f]);
    free(s);
}

static void put3(float *dst, vec3 v)
{
    dst[0] = v.x, dst[1] = v.y, dst[2] = v.z;
}

void sample_store_add(void *ctx, int px, int py, const SampleRecord *r)
{
    SampleStore *s = ctx;
    if (px < 0 || py < 0 || px >= s->width || py >= s->height) return;
    size_t i = (size_t)py * (size_t)s->width + (size_t)px;
    int k = s->count[i];
    if (k >= s->capacity) {
        __atomic_add_fetch(&s->dropped, 1, __ATOMIC_RELAXED);
        return;
    }
    s->count[i] = k + 1;
    size_t j = i * (size_t)s->capacity + (size_t)k;
    /* Field by field in straight code, each behind the test whether it is kept (a frame of
     * LR keeps 3 of 17): this runs for every sample, and a loop over the kept fields with a
     * switch cost about 200 instructions per sample. F[n] is field 1 << n (FIELDS' order). */
    float *const *F = s->field;
    float *d;
    if ((d = F[0])) d += 2 * j, d[0] = r->px_raster, d[1] = r->py_raster;          /* film */
    if ((d = F[1])) d += 2 * j, d[0] = r->lens_u, d[1] = r->lens_v;                /* lens */
    if ((d = F[2])) d[j] = r->time;                                                /* time */
    if ((d = F[3])) d[j] = r->hit ? r->depth_cam : INFINITY;                       /* depth */
    if ((d = F[4])) put3(d + 3 * j, r->L);                                         /* radiance */
    if ((d = F[5])) put3(d + 3 * j, r->direct);                                    /* direct */
    if ((d = F[6])) put3(d + 3 * j, r->indirect);                                  /* indirect */
    if ((d = F[7])) put3(d + 3 * j, r->p_world);                                   /* position */
    if ((d = F[8])) put3(d + 3 * j, r->n_shading);                                 /* normal */
    if ((d = F[9])) {                                                              /* light */
        d += 5 * j;
        if (r->shadow_count > 0) {
            put3(d, r->shadow[0].light_p_world);
            d[3] = r->shadow[0].d_light_world, d[4] = r->shadow[0].d_occluder_world;
        } else {
            d[0] = d[1] = d[2] = d[3] = 0.0f, d[4] = INFINITY;
        }
    }
    if ((d = F[10])) {                                                             /* bounce */
        d += 4 * j;
        if (r->bounce_count > 0) {
            put3(d, r->bounce[0].dir_world);
            d[3] = r->bounce[0].d_hit_world;
        } else {
            d[0] = d[1] = d[2] = 0.0f, d[3] = INFINITY;
        }
    }
    if ((d = F[11])) d += 2 * j, d[0] = r->motion_px[0], d[1] = r->motion_px[1];   /* motion */
    if ((d = F[12])) {                                                             /* shading */
        d += 7 * j;
        put3(d, r->albedo);
        d[3] = r->hit ? (float)r->object_id : -1.0f;
        float u[3] = {r->unfiltered_direct.x, r->unfiltered_direct.y, r->unfiltered_direct.z};
        for (int c = 0; c < 3; ++c) d[4 + c] = isfinite(u[c]) && u[c] > 0.0f ? u[c] : 0.0f; /* as the split counts it */
    }
    if (F[15] || F[16]) {
        float ud[3], ui[3]; /* what the shading filters leave alone, as the guides' sums split it */
        gbuffer_unfiltered_split(r, ud, ui);
        if ((d = F[15])) {                                                         /* shading_direct */
            d += 6 * j;
            d[0] = r->direct.x - ud[0], d[1] = r->direct.y - ud[1], d[2] = r->direct.z - ud[2];
            put3(d + 3, r->albedo_diffuse); /* what the filterable direct light was demodulated by */
        }
        if ((d = F[16])) d += 3 * j, d[0] = r->indirect.x - ui[0], d[1] = r->indirect.y - ui[1], d[2] = r->indirect.z - ui[2];
    }
    if ((d = F[13])) {                                                             /* lr_place */
        d += 8 * j;
        d[0] = r->px_raster, d[1] = r->py_raster, d[2] = r->lens_u, d[3] = -r->lens_v, d[4] = r->time;
    }
    if ((d = F[14])) {                                                             /* lr_key */
        d += 4 * j;
        d[0] = r->hit ? r->depth_cam : INFINITY, d[2] = r->motion_px[0], d[3] = r->motion_px[1];
    }
}

int sample_store_arrays(SampleStore *s, DistArray *out, int max)
{
    int n = 0;
    if (n < max) out[n++] = (DistArray){s->count, sizeof(int)};
    for (int f = 0; f < SAMPLE_FIELD_COUNT_ && n < max; ++f)
        if (s->field[f])
            out[n++] = (DistArray){s->field[f], (size_t)s->capacity * (size_t)FIELDS[f].components * sizeof(float)};
    return n;
}

unsigned sample_store_fields(const SampleStore *s) { return s->fields; }
int sample_store_capacity(const SampleStore *s) { return s->capacity; }
int sample_store_count(const SampleStore *s, size_t i) { return s->count[i]; }
long long sample_store_dropped(const SampleStore *s) { return __atomic_load_n(&s->dropped, __ATOMIC_RELAXED); }

float *sample_store_field_mut(SampleStore *s, unsigned field)
{
    return (float *)sample_store_field(s, field);
}

const float *sample_store_field(const SampleStore *s, unsigned field)
{
    for (int f = 0; f < SAMPLE_FIELD_COUNT_; ++f)
        if (FIELDS[f].bit == field) return s->field[f];
    return NULL;
}
