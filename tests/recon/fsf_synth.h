/* Synthetic FSF inputs shared by the FSF tests and benchmark: a flat receiver facing the
 * camera (every neighbour acceptable), per-pixel samples jittered on an l x l grid over the
 * light, and uniform per-pixel filter parameters. */
#ifndef WEDGE_TESTS_FSF_SYNTH_H
#define WEDGE_TESTS_FSF_SYNTH_H

#include <math.h>
#include <stdlib.h>

#include "recon/fsf/fsf_bounce.h"
#include "recon/fsf/fsf_filter.h"

typedef struct {
    int w, h, cap;
    int *count;
    float *y, *v;
    float *pos4, *nrm4;
    unsigned char *usable;
    FsfPixel *px;
    FsfSamples s;
} FsfSynth;

static unsigned fsf_rng(unsigned *st)
{
    *st = *st * 1664525u + 1013904223u;
    return *st >> 8;
}
static float fsf_rand01(unsigned *st) { return (float)fsf_rng(st) / 16777216.0f; }

static inline void fsf_synth_free(FsfSynth *f)
{
    free(f->count), free(f->y), free(f->v), free(f->pos4), free(f->nrm4), free(f->usable), free(f->px);
}

/* w x h pixels of l x l samples; light half extents L (both axes); every pixel at depth 10 on
 * the plane z = 0 with normal +z, one world unit per 100 pixels. */
static inline void fsf_synth_init(FsfSynth *f, int w, int h, int l)
{
    size_t n = (size_t)w * (size_t)h;
    f->w = w, f->h = h, f->cap = l * l;
    f->count = malloc(n * sizeof(int));
    f->y = malloc(n * (size_t)f->cap * 2 * sizeof(float));
    f->v = malloc(n * (size_t)f->cap * 3 * sizeof(float));
    f->pos4 = malloc(n * 4 * sizeof(float));
    f->nrm4 = malloc(n * 4 * sizeof(float));
    f->usable = malloc(n);
    f->px = calloc(n, sizeof(FsfPixel));
    for (size_t i = 0; i < n; ++i) {
        f->count[i] = f->cap;
        float *p = f->pos4 + 4 * i, *nr = f->nrm4 + 4 * i;
        p[0] = (float)(i % (size_t)w) * 0.01f, p[1] = (float)(i / (size_t)w) * 0.01f, p[2] = 0.0f, p[3] = 10.0f;
        nr[0] = 0.0f, nr[1] = 0.0f, nr[2] = 1.0f, nr[3] = 0.0f;
        f->usable[i] = 1;
        FsfPixel *pp = &f->px[i];
        pp->dir[0][0] = 1.0f, pp->dir[0][1] = 0.0f, pp->dir[1][0] = 0.0f, pp->dir[1][1] = 1.0f;
    }
    f->s = (FsfSamples){w, h, f->cap, f->count, f->y, f->v};
}

/* NaN in the values of every sample of the pixels that are not usable: the filter never reads
 * them (fsf_filter.h), so a usable pixel's result must not change and an unusable one's must
 * be exactly 0. The light coordinates stay on the light, so that a pass that did read such a
 * pixel would add the NaN somewhere (a NaN coordinate lands on no node and would hide it). */
static inline void fsf_synth_poison_unusable(FsfSynth *f)
{
    for (size_t i = 0; i < (size_t)f->w * (size_t)f->h; ++i)
        for (size_t e = 0; !f->usable[i] && e < 3 * (size_t)f->cap; ++e) f->v[3 * i * (size_t)f->cap + e] = NAN;
}

/* Light coordinates: jittered l x l strata (bin_centred: y2 at the centre of its FsfGrid y2
 * bin, y1 at the centre of its stratum, no randomness). */
static inline void fsf_synth_light(FsfSynth *f, const FsfGrid *g, int l, bool bin_centred, unsigned seed)
{
    size_t n = (size_t)f->w * (size_t)f->h;
    unsigned st = seed;
    for (size_t i = 0; i < n; ++i)
        for (int a = 0; a < l; ++a)
            for (int b = 0; b < l; ++b) {
                size_t slot = i * (size_t)f->cap + (size_t)(a * l + b);
                float u1 = bin_centred ? 0.5f : fsf_rand01(&st), u2 = bin_centred ? 0.5f : fsf_rand01(&st);
                float y1 = g->half_m[0] * (2.0f * ((float)a + u1) / (float)l - 1.0f);
                float y2 = g->half_m[1] * (2.0f * ((float)b + u2) / (float)l - 1.0f);
                if (bin_centred) { /* the centre of the y2 bin the stratum's centre falls in */
                    int bin = fsf_y2_bin(g, y2);
                    y2 = -g->half_m[1] + ((float)bin + 0.5f) * 2.0f * g->half_m[1] / (float)g->y2_bins;
                }
                f->y[2 * slot] = y1, f->y[2 * slot + 1] = y2;
            }
}

/* The light's geometric term (fsf_geo_term.h) for fsf_synth_init's receiver: the light of
 * g's extents parallel to the plane z = 0, facing it from height h_m above the point
 * (cx_m, cy_m), its axes along x and y. mean_g (one float per pixel, the caller's) gets each
 * pixel's mean term (0 where a normal turns away from the light). */
static inline FsfGeoTerm fsf_synth_geo(const FsfSynth *f, const FsfGrid *g, float cx_m, float cy_m, float h_m,
                                       float *mean_g)
{
    FsfGeoTerm t = {{cx_m, cy_m, h_m}, {{1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}}, {0.0f, 0.0f, -1.0f}, mean_g, {0.0f, 0.0f}, {0.0f, 0.0f}, {0.0f, 0.0f}};
    fsf_geo_mean(&t, f->pos4, f->nrm4, f->usable, g->half_m, (size_t)f->w * (size_t)f->h, mean_g);
    return t;
}

/* Indirect-light samples (fsf_bounce.h) over fsf_synth_init's receiver (the plane z = 0, 0.01 m
 * per pixel; frame t1 = x, t2 = y, n = z): l x l stratified cosine-distributed bounce
 * directions per pixel; a sample is lit (rgb 1, 0.5, 0.75; else 0, 0, 0.25) where its ray
 * hits the disk of radius r_m at height h_m centred above the point (cx_m, cy_m) of the
 * receiver, dark where it passes it. y: v clamped into the box (fsf_bounce_coord), or with
 * clamp false the raw v (samples beyond the box then fall outside the profile: dropped). */
static inline void fsf_synth_bounce_disk(FsfSynth *f, int l, float h_m, float r_m, float cx_m, float cy_m, bool clamp,
                                         unsigned seed)
{
    size_t n = (size_t)f->w * (size_t)f->h;
    unsigned st = seed;
    FsfBounceFrame fr = {{v3(1.0f, 0.0f, 0.0f), v3(0.0f, 1.0f, 0.0f)}, v3(0.0f, 0.0f, 1.0f)};
    for (size_t i = 0; i < n; ++i)
        for (int a = 0; a < l; ++a)
            for (int b = 0; b < l; ++b) {
                size_t slot = i * (size_t)f->cap + (size_t)(a * l + b);
                float u1 = ((float)a + fsf_rand01(&st)) / (float)l, u2 = ((float)b + fsf_rand01(&st)) / (float)l;
                float rad = sqrtf(u1), phi = 6.2831853f * u2, dz = sqrtf(fmaxf(1.0f - u1, 1e-12f));
                vec3 d = v3(rad * cosf(phi), rad * sinf(phi), dz);
                if (clamp) fsf_bounce_coord(&fr, d, f->y + 2 * slot);
                else f->y[2 * slot] = d.x / d.z, f->y[2 * slot + 1] = d.y / d.z;
                /* where the ray pierces the disk's plane, relative to its centre */
                float px = (float)(i % (size_t)f->w) * 0.01f + h_m * d.x / d.z - cx_m;
                float py = (float)(i / (size_t)f->w) * 0.01f + h_m * d.y / d.z - cy_m;
                float lit = px * px + py * py <= r_m * r_m ? 1.0f : 0.0f;
                f->v[3 * slot] = lit, f->v[3 * slot + 1] = 0.5f * lit, f->v[3 * slot + 2] = 0.25f + 0.5f * lit;
            }
}

/* The closed form: the cosine-weighted fraction of the hemisphere that the disk of radius r_m
 * at height h_m covers, seen from a point at horizontal distance d_m from its axis (the view
 * factor of a parallel disk to a differential area). */
static inline double fsf_disk_view_factor(double h_m, double r_m, double d_m)
{
    double a = h_m * h_m + d_m * d_m + r_m * r_m;
    return 0.5 * (1.0 - (h_m * h_m + d_m * d_m - r_m * r_m) / sqrt(a * a - 4.0 * d_m * d_m * r_m * r_m));
}

/* Over the pixels at least 8 from the border of fsf_synth_bounce_disk's receiver: the mean and
 * RMS of (estimate - view factor) for a filtered result out4 (channel 0 over the weight) and
 * the RMS for the pixels' own sample means. */
typedef struct {
    double mean, rms, rms_own;
} FsfDiskErr;
static inline FsfDiskErr fsf_disk_errors(const FsfSynth *f, const float *out4, float h_m, float r_m, float cx_m,
                                         float cy_m)
{
    FsfDiskErr e = {0, 0, 0};
    int cnt = 0;
    for (int y = 8; y < f->h - 8; ++y)
        for (int x = 8; x < f->w - 8; ++x) {
            size_t i = (size_t)y * (size_t)f->w + (size_t)x;
            double dx = x * 0.01 - cx_m, dy = y * 0.01 - cy_m;
            double ref = fsf_disk_view_factor(h_m, r_m, sqrt(dx * dx + dy * dy)), own = 0.0;
            for (int k = 0; k < f->count[i]; ++k) own += f->v[3 * (i * (size_t)f->cap + (size_t)k)];
            own /= f->count[i];
            double d = out4[4 * i] / out4[4 * i + 3] - ref;
            e.mean += d, e.rms += d * d, e.rms_own += (own - ref) * (own - ref);
            ++cnt;
        }
    e.mean /= cnt, e.rms = sqrt(e.rms / cnt), e.rms_own = sqrt(e.rms_own / cnt);
    return e;
}

#endif
