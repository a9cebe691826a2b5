/* Per-pixel AAF statistics from SampleRecords (see aaf_stats.h). */
#include "recon/aaf/aaf_stats.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/vec.h"
#include "core/zalloc.h"
#include "recon/polygon_irradiance.h"
#include "recon/recon_parallel.h"

/* The statistics' arrays: element size and count per pixel, and the initial value of
 * those that start as "no data yet" (min > max) instead of 0. */
#define AAF_STATS_ARRAYS(X)                                                                                \
    X(shadow_rays, int, 1, 0)                                                                              \
    X(occluded_rays, int, 1, 0)                                                                            \
    X(d1_sum, float, 1, 0)                                                                                 \
    X(ratio_min, float, 1, INFINITY)                                                                       \
    X(ratio_max, float, 1, 0)                                                                              \
    X(light_p_sum, float, 3, 0)                                                                            \
    X(light_pp_sum, float, 6, 0)                                                                           \
    X(zmin, float, 1, INFINITY)                                                                            \
    X(zmax, float, 1, 0)                                                                                   \
    X(coc_min, float, 1, INFINITY)                                                                         \
    X(coc_max, float, 1, -INFINITY)                                                                        \
    X(sigma_min, float, 1, INFINITY)                                                                       \
    X(plane_sum, float, 3, 0)                                                                              \
    X(phong_max, float, 1, 0)

bool aaf_stats_init(AafStats *s, const GBuffer *g)
{
    memset(s, 0, sizeof *s);
    s->width = g->width;
    s->height = g->height;
    s->g = g;
    s->collect_rays = true;
    s->collect_coc = true;
    size_t n = (size_t)g->width * (size_t)g->height;
    if (n == 0) return false;
    bool ok = true;
#define ALLOC(name, type, per, init) ok = ok && (s->name = zalloc((per) * n, sizeof(type))) != NULL;
    AAF_STATS_ARRAYS(ALLOC)
#undef ALLOC
    if (!ok) {
        aaf_stats_free(s);
        return false;
    }
#define INIT(name, type, per, init)                                                                        \
    if ((init) != 0)                                                                                       \
        for (size_t i = 0; i < (per) * n; ++i) s->name[i] = (type)(init);
    AAF_STATS_ARRAYS(INIT)
#undef INIT
    return true;
}

int aaf_stats_arrays(AafStats *s, DistArray *out, int max)
{
    int n = 0;
#define LIST(name, type, per, init)                                                                        \
    if (n < max) out[n++] = (DistArray){s->name, (per) * sizeof(type)};
    AAF_STATS_ARRAYS(LIST)
#undef LIST
    return n;
}

void aaf_stats_free(AafStats *s)
{
#define FREE(name, type, per, init) free(s->name);
    AAF_STATS_ARRAYS(FREE)
#undef FREE
    memset(s, 0, sizeof *s);
}

/* The Gaussian width of AAF-shadow Sec. 4.1 from the exact emitter: sigma = sqrt(A)/2 with A
 * the area the light presents (the same convention as eq. 16's A_l = (2 sigma)^2). A planar
 * emitter split into triangles (a quad light is two) counts as one light of the summed area,
 * grouped by its SceneDesc shape; a sphere presents its silhouette, area/4. */
void aaf_light_geom_from_info(const RenderLightInfo *li, double shape_area, AafLightGeom *out)
{
    memset(out, 0, sizeof *out);
    if (li->kind != RENDER_LIGHT_AREA) return;
    bool planar = v3_dot(li->normal_world, li->normal_world) > 0.5f; /* spheres have no normal */
    double area = li->area_world;
    if (!planar) area *= 0.25;
    else if (shape_area > 0.0) area = shape_area;
    float sigma = (float)(0.5 * sqrt(area));
    out->sigma_world = isfinite(sigma) ? sigma : 0.0f;
    if (planar) {
        out->normal[0] = li->normal_world.x;
        out->normal[1] = li->normal_world.y;
        out->normal[2] = li->normal_world.z;
    }
    out->center[0] = li->center_world.x;
    out->center[1] = li->center_world.y;
    out->center[2] = li->center_world.z;
    /* the emitter itself, for r(x) */
    out->radiance_mean = (li->radiance.x + li->radiance.y + li->radiance.z) / 3.0f;
    out->two_sided = li->two_sided;
    if (li->is_triangle) {
        out->emitter = AAF_EMITTER_TRIANGLE;
        for (int k = 0; k < 3; ++k) {
            out->tri[k][0] = li->tri_world[k].x;
            out->tri[k][1] = li->tri_world[k].y;
            out->tri[k][2] = li->tri_world[k].z;
        }
    } else {
        /* radius of the disk or sphere with the emitter's area (partial shapes and
         * non-uniform scales become the round shape of the same area) */
        out->emitter = planar ? AAF_EMITTER_DISK : AAF_EMITTER_SPHERE;
        double r = sqrt(li->area_world / (planar ? M_PI : 4.0 * M_PI));
        out->radius_world = isfinite(r) ? (float)r : 0.0f;
    }
}

double *aaf_shape_areas(const RenderLightInfo *info, int count)
{
    int max_shape = -1;
    for (int l = 0; l < count; ++l)
        if (info[l].kind == RENDER_LIGHT_AREA && info[l].shape > max_shape) max_shape = info[l].shape;
    double *shape_area = calloc((size_t)max_shape + 2, sizeof(double));
    for (int l = 0; l < count && shape_area; ++l)
        if (info[l].kind == RENDER_LIGHT_AREA && info[l].shape >= 0) shape_area[info[l].shape] += info[l].area_world;
    return shape_area;
}

void aaf_lights_from_renderer(const Renderer *r, AafLightGeom *lights, int count)
{
    RenderLightInfo *info = calloc(count > 0 ? (size_t)count : 1, sizeof *info);
    for (int l = 0; l < count; ++l) {
        memset(&lights[l], 0, sizeof lights[l]);
        if (info && !renderer_light_info(r, l, &info[l])) info[l].kind = RENDER_LIGHT_POINT;
    }
    if (!info) return; /* out of memory: sigma 0, the caller falls back to the estimate */
    double *shape_area = aaf_shape_areas(info, count);
    for (int l = 0; l < count; ++l)
        aaf_light_geom_from_info(&info[l], shape_area && info[l].shape >= 0 ? shape_area[info[l].shape] : 0.0, &lights[l]);
    free(shape_area);
    free(info);
}

void aaf_stats_add(void *ctx, int px, int py, const SampleRecord *r)
{
    AafStats *s = ctx;
    if (px < 0 || py < 0 || px >= s->width || py >= s->height) return;
    size_t i = (size_t)py * (size_t)s->width + (size_t)px;
    if (s->collect_rays && s->collect_coc && s->g->cam.lens_radius_world > 0.0f) {
        float slope = recon_coc_slope_px(&s->g->cam, r->hit ? r->depth_cam : INFINITY);
        s->coc_min[i] = fminf(s->coc_min[i], slope);
        s->coc_max[i] = fmaxf(s->coc_max[i], slope);
    }
    if (!r->hit) return;
    if (!(isfinite(r->p_world.x) && isfinite(r->p_world.y) && isfinite(r->p_world.z))) return;
    if (r->phong_exponent > s->phong_max[i] && isfinite(r->phong_exponent)) s->phong_max[i] = r->phong_exponent;
    if (!s->collect_rays) return;

    for (int k = 0; k < r->shadow_count && k < SAMPLE_RECORD_MAX_SHADOW; ++k) {
        const ShadowRayRecord *sh = &r->shadow[k];
        float d1 = sh->d_light_world;
        if (!(d1 > 0.0f) || !isfinite(d1)) continue;
        s->shadow_rays[i]++;
        s->d1_sum[i] += d1;
        vec3 p = sh->light_p_world;
        float *m = s->light_p_sum + 3 * i, *q = s->light_pp_sum + 6 * i;
        m[0] += p.x, m[1] += p.y, m[2] += p.z;
        q[0] += p.x * p.x, q[1] += p.x * p.y, q[2] += p.x * p.z;
        q[3] += p.y * p.y, q[4] += p.y * p.z, q[5] += p.z * p.z;
        int li = sh->light_index;
        if (s->lights && li >= 0 && li < s->light_count && s->lights[li].sigma_world > 0.0f) {
            /* the exact light of this ray: its width, and the plane eq. 12 measures distances
             * in (a sphere's: perpendicular to the receiver -> centre direction) */
            const AafLightGeom *L = &s->lights[li];
            s->sigma_min[i] = fminf(s->sigma_min[i], L->sigma_world);
            float pn[3] = {L->normal[0], L->normal[1], L->normal[2]};
            if (pn[0] == 0.0f && pn[1] == 0.0f && pn[2] == 0.0f) {
                pn[0] = L->center[0] - r->p_world.x;
                pn[1] = L->center[1] - r->p_world.y;
                pn[2] = L->center[2] - r->p_world.z;
                float len = sqrtf(pn[0] * pn[0] + pn[1] * pn[1] + pn[2] * pn[2]);
                for (int k = 0; k < 3; ++k) pn[k] = len > 0.0f ? pn[k] / len : 0.0f;
            }
            float *ps = s->plane_sum + 3 * i; /* a plane has no side: align before summing */
            float sgn = (ps[0] * pn[0] + ps[1] * pn[1] + ps[2] * pn[2]) < 0.0f ? -1.0f : 1.0f;
            for (int k = 0; k < 3; ++k) ps[k] += sgn * pn[k];
        }
        float t = sh->d_occluder_world;
        if (t >= 0.0f && t < d1) {
            /* AAF-shadow Fig. 2: d2 = d1 - t along the same ray, so d1/d2 is exact per ray
             * even when d1 differs between light samples. */
            float ratio = (d1 - t) / d1;
            s->occluded_rays[i]++;
            s->ratio_min[i] = fminf(s->ratio_min[i], ratio);
            s->ratio_max[i] = fmaxf(s->ratio_max[i], ratio);
        }
    }
    for (int k = 0; k < r->bounce_count && k < SAMPLE_RECORD_MAX_BOUNCE; ++k) {
        const BounceRayRecord *b = &r->bounce[k];
        if (!(b->d_hit_world >= 0.0f) || !isfinite(b->d_hit_world)) continue; /* escaped: no reflector */
        /* AAF-GI Sec. 3.1: z is measured perpendicular to the receiver (x' = x + z v). */
        float z = b->d_hit_world * fabsf(v3_dot(b->dir_world, r->n_shading));
        s->zmin[i] = fminf(s->zmin[i], z);
        s->zmax[i] = fmaxf(s->zmax[i], z);
    }
}

/* ---- derived maps ---- */

/* Eigen-decomposition of a symmetric 3x3 matrix by cyclic Jacobi rotations. */
static void sym3_eigen(double a[3][3], double evals[3], double evecs[3][3])
{
    double v[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int sweep = 0; sweep < 32; ++sweep) {
        double off = fabs(a[0][1]) + fabs(a[0][2]) + fabs(a[1][2]);
        if (off < 1e-30) break;
        for (int p = 0; p < 2; ++p) {
            for (int q = p + 1; q < 3; ++q) {
                if (fabs(a[p][q]) < 1e-300) continue;
                double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                double t = (theta >= 0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(theta * theta + 1.0));
                double c = 1.0 / sqrt(t * t + 1.0), s = t * c;
                for (int k = 0; k < 3; ++k) { /* A <- A J */
                    double akp = a[k][p], akq = a[k][q];
                    a[k][p] = c * akp - s * akq;
                    a[k][q] = s * akp + c * akq;
                }
                for (int k = 0; k < 3; ++k) { /* A <- J^T A */
                    double apk = a[p][k], aqk = a[q][k];
                    a[p][k] = c * apk - s * aqk;
                    a[q][k] = s * apk + c * aqk;
                }
                for (int k = 0; k < 3; ++k) {
                    double vkp = v[k][p], vkq = v[k][q];
                    v[k][p] = c * vkp - s * vkq;
                    v[k][q] = s * vkp + c * vkq;
                }
            }
        }
    }
    for (int k = 0; k < 3; ++k) {
        evals[k] = a[k][k];
        for (int j = 0; j < 3; ++j) evecs[j][k] = v[j][k]; /* column k is eigenvector k */
    }
}

/* The light as one Gaussian (AAF-shadow Sec. 4.1): from the covariance of all light sample
 * points of the frame, the plane normal is the direction of least spread and the light is
 * replaced by a uniform rectangle with the same in-plane variances l1, l2 (sides sqrt(12 l)),
 * whose "effective width" 2 sigma (eq. 16 uses A_l = (2 sigma)^2) gives
 * sigma = sqrt(area)/2 = sqrt(3) (l1 l2)^(1/4). One planar light per frame is assumed;
 * several lights make sigma larger (see docs/algorithms.md). */
static void estimate_light(const AafStats *s, AafDerived *d)
{
    float *sigma_world = &d->light_sigma_world, *normal = d->light_normal;
    size_t n = (size_t)s->width * (size_t)s->height;
    double cnt = 0, m[3] = {0, 0, 0}, q[6] = {0, 0, 0, 0, 0, 0};
    for (size_t i = 0; i < n; ++i) {
        if (s->shadow_rays[i] == 0) continue;
        cnt += s->shadow_rays[i];
        for (int k = 0; k < 3; ++k) m[k] += s->light_p_sum[3 * i + k];
        for (int k = 0; k < 6; ++k) q[k] += s->light_pp_sum[6 * i + k];
    }
    *sigma_world = 0.0f;
    normal[0] = normal[1] = normal[2] = 0.0f;
    if (cnt < 2) return;
    for (int k = 0; k < 3; ++k) m[k] /= cnt;
    double c[3][3] = {{q[0] / cnt - m[0] * m[0], q[1] / cnt - m[0] * m[1], q[2] / cnt - m[0] * m[2]},
                      {0, q[3] / cnt - m[1] * m[1], q[4] / cnt - m[1] * m[2]},
                      {0, 0, q[5] / cnt - m[2] * m[2]}};
    c[1][0] = c[0][1];
    c[2][0] = c[0][2];
    c[2][1] = c[1][2];
    double ev[3], evec[3][3];
    sym3_eigen(c, ev, evec);
    int lo = 0;
    for (int k = 1; k < 3; ++k)
        if (ev[k] < ev[lo]) lo = k;
    double l1 = fmax(ev[(lo + 1) % 3], 0.0), l2 = fmax(ev[(lo + 2) % 3], 0.0);
    double sigma = sqrt(3.0) * pow(l1 * l2, 0.25);
    *sigma_world = isfinite(sigma) ? (float)sigma : 0.0f;
    double len = sqrt(evec[0][lo] * evec[0][lo] + evec[1][lo] * evec[1][lo] + evec[2][lo] * evec[2][lo]);
    if (len > 0 && isfinite(len))
        for (int k = 0; k < 3; ++k) normal[k] = (float)(evec[k][lo] / len);
    /* The same rectangle for the unoccluded-irradiance quadrature: centre, and half-side
     * vectors along the in-plane eigenvectors (uniform on [-a, a] has variance a^2/3). */
    double ha = sqrt(3.0 * l1), hb = sqrt(3.0 * l2);
    int ia = (lo + 1) % 3, ib = (lo + 2) % 3;
    for (int k = 0; k < 3; ++k) {
        d->light_center[k] = (float)m[k];
        d->light_half_u[k] = (float)(evec[k][ia] * ha);
        d->light_half_v[k] = (float)(evec[k][ib] * hb);
    }
    d->light_known = isfinite(ha) && isfinite(hb) && isfinite(m[0] + m[1] + m[2]);
}

void aaf_derived_free(AafDerived *d)
{
    free(d->d1);
    free(d->d2min);
    free(d->d2max);
    free(d->sigma_light);
    free(d->zmin);
    free(d->zmax);
    free(d->coc_min);
    free(d->coc_max);
    free(d->plane4);
    free(d->phong_m);
    memset(d, 0, sizeof *d);
}

/* The per-pixel part of aaf_derive (independent pixels: any split gives the same maps). */
typedef struct {
    const AafStats *s;
    AafDerived *d;
    float sigma_fallback;
} DerivePass;

static void derive_range(void *ctx, size_t begin, size_t end, int part)
{
    (void)part;
    const DerivePass *dp = ctx;
    const AafStats *s = dp->s;
    AafDerived *d = dp->d;
    float sigma_fallback = dp->sigma_fallback;
    for (size_t i = begin; i < end; ++i) {
        d->phong_m[i] = s->phong_max[i];
        const float *ps = s->plane_sum + 3 * i;
        float pl = sqrtf(ps[0] * ps[0] + ps[1] * ps[1] + ps[2] * ps[2]);
        for (int k = 0; k < 3; ++k) d->plane4[4 * i + k] = pl > 0.0f ? ps[k] / pl : d->light_normal[k];
        d->plane4[4 * i + 3] = 0.0f;
        d->sigma_light[i] = d->exact_lights ? (isfinite(s->sigma_min[i]) ? s->sigma_min[i] : sigma_fallback)
                                            : d->light_sigma_world;
        d->coc_min[i] = s->coc_min[i];
        d->coc_max[i] = s->coc_max[i];
        d->zmin[i] = s->zmin[i];
        d->zmax[i] = s->zmax[i];
        if (s->g->sums[i].hits > 0 && s->shadow_rays[i] > 0) {
            float d1 = s->d1_sum[i] / (float)s->shadow_rays[i];
            d->d1[i] = d1;
            if (s->occluded_rays[i] > 0) {
                d->d2min[i] = s->ratio_min[i] * d1;
                d->d2max[i] = s->ratio_max[i] * d1;
            }
        }
    }
}

bool aaf_derive(const AafStats *s, AafDerived *d)
{
    memset(d, 0, sizeof *d);
    int w = s->width, h = s->height;
    size_t n = (size_t)w * (size_t)h;
    d->width = w;
    d->height = h;
    d->g = s->g;
    d->d1 = calloc(n, sizeof(float));
    d->d2min = calloc(n, sizeof(float));
    d->d2max = calloc(n, sizeof(float));
    d->sigma_light = calloc(n, sizeof(float));
    d->zmin = calloc(n, sizeof(float));
    d->zmax = calloc(n, sizeof(float));
    d->coc_min = calloc(n, sizeof(float));
    d->coc_max = calloc(n, sizeof(float));
    d->plane4 = calloc(4 * n, sizeof(float));
    d->phong_m = calloc(n, sizeof(float));
    if (!d->d1 || !d->d2min || !d->d2max || !d->sigma_light || !d->zmin || !d->zmax || !d->coc_min || !d->coc_max ||
        !d->plane4 || !d->phong_m) {
        aaf_derived_free(d);
        return false;
    }
    estimate_light(s, d);
    /* Exact lights (the usual case): pixels without a shadow ray to an area light fall back
     * to the smallest light's width, the conservative choice. */
    float sigma_fallback = d->light_sigma_world;
    if (s->lights && s->light_count > 0) {
        float smallest = INFINITY;
        for (int l = 0; l < s->light_count; ++l)
            if (s->lights[l].sigma_world > 0.0f) smallest = fminf(smallest, s->lights[l].sigma_world);
        if (isfinite(smallest)) {
            d->exact_lights = true;
            sigma_fallback = smallest;
        }
        /* r(x) from the lights, or from their poses over the shutter when one moves */
        const AafLightGeom *em = s->emitters ? s->emitters : s->lights;
        int em_count = s->emitters ? s->emitter_count : s->light_count;
        int emitters = 0;
        for (int l = 0; l < em_count; ++l) emitters += em[l].emitter != AAF_EMITTER_NONE;
        if (emitters > 0 && emitters <= AAF_EXACT_EMITTERS_MAX) {
            d->lights = em;
            d->light_count = em_count;
        }
    }
    DerivePass dp = {s, d, sigma_fallback};
    recon_parallel_for(n, derive_range, &dp);
    return true;
}

/* AAF-shadow eq. 1 factors the direct light into r(x), the unoccluded irradiance, times the
 * light-weighted visibility; only the visibility is what the wedge analysis says is smooth.
 * r(x) is needed up to a constant (it is divided out and multiplied back): with the
 * renderer's emitters, sum_l L_l Phi_l(x) / sum_l L_l A_l, Phi_l the projected solid angle
 * of emitter l (Lambert's polygon formula clipped to the receiver's horizon, exact for
 * triangles) and L_l its mean radiance, so that direct / (albedo r) is the light-weighted
 * visibility times a constant; without them, the same for the light rectangle estimated from
 * the light samples (1/m^2 either way). Deterministic, so it adds no noise. (A 4 x 4 midpoint
 * quadrature over the estimated rectangle was 10-30% off where the light straddles a curved
 * receiver's horizon, and the rectangle itself is rotated arbitrarily for a square light,
 * whose covariance has no preferred axes: the filter spread both errors as bias.) */
enum { ROUND_SIDES = 16 }; /* disks and sphere silhouettes as polygons of this many sides */
_Static_assert((int)ROUND_SIDES < (int)POLYGON_MAX_VERTS, "a clipped round polygon must fit polygon_irradiance");

/* unoccluded_steady: how far r at the tilted normals may move from r at the mean one (a factor,
 * each way), and the coherence above which the normals count as one (a spread under 0.08
 * degrees: flat receivers, and curved ones at pixel scale, skip the four extra polygons). */
#define UNOCCLUDED_SPREAD_RATIO 2.0f
#define UNOCCLUDED_STEADY_COHERENCE 0.999999f

typedef struct {
    const AafDerived *d;
    float *r;
    double quad[4][3];   /* the estimated light rectangle's corners (world) */
    double inv_area;     /* 1 / its area; 0: degenerate, treated as a point at the centre */
    double inv_weight;   /* exact emitters: 1 / sum_l L_l A_l */
} ShadePass;

/* A circle of radius rad around c in the plane with unit normal nrm, as a polygon whose area
 * equals the circle's (so round and triangle emitters keep their relative weights). */
static void round_polygon(const double c[3], const double nrm[3], double rad, double v[ROUND_SIDES][3])
{
    double t[3] = {1, 0, 0};
    if (fabs(nrm[0]) > 0.9) t[0] = 0, t[1] = 1;
    double a[3] = {nrm[1] * t[2] - nrm[2] * t[1], nrm[2] * t[0] - nrm[0] * t[2], nrm[0] * t[1] - nrm[1] * t[0]};
    double la = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    for (int k = 0; k < 3; ++k) a[k] /= la;
    double b[3] = {nrm[1] * a[2] - nrm[2] * a[1], nrm[2] * a[0] - nrm[0] * a[2], nrm[0] * a[1] - nrm[1] * a[0]};
    /* a regular N-gon inscribed in radius R has area (N/2) R^2 sin(2 pi/N) */
    double R = rad * sqrt(2.0 * M_PI / (ROUND_SIDES * sin(2.0 * M_PI / ROUND_SIDES)));
    for (int i = 0; i < ROUND_SIDES; ++i) {
        double phi = 2.0 * M_PI * i / ROUND_SIDES, ca = R * cos(phi), sb = R * sin(phi);
        for (int k = 0; k < 3; ++k) v[i][k] = c[k] + ca * a[k] + sb * b[k];
    }
}

/* Phi of one emitter seen from p (normal n); 0 from behind a one-sided planar emitter and
 * from within its plane (polygon_plane_side). */
static double emitter_phi(const AafLightGeom *L, const double p[3], const double n[3])
{
    double c[3] = {L->center[0], L->center[1], L->center[2]};
    double nl[3] = {L->normal[0], L->normal[1], L->normal[2]};
    if (L->emitter == AAF_EMITTER_TRIANGLE || L->emitter == AAF_EMITTER_DISK) {
        double q[3] = {c[0], c[1], c[2]}; /* a point of the plane */
        if (L->emitter == AAF_EMITTER_TRIANGLE) q[0] = L->tri[0][0], q[1] = L->tri[0][1], q[2] = L->tri[0][2];
        double side = polygon_plane_side(p, q, nl);
        if (side == 0.0) return 0.0;
        if (!L->two_sided && side < 0.0) return 0.0;
    }
    if (L->emitter == AAF_EMITTER_TRIANGLE) {
        double v[3][3];
        for (int i = 0; i < 3; ++i)
            for (int k = 0; k < 3; ++k) v[i][k] = L->tri[i][k];
        return polygon_projected_solid_angle(p, n, v, 3);
    }
    if (!(L->radius_world > 0.0f)) return 0.0;
    double v[ROUND_SIDES][3];
    if (L->emitter == AAF_EMITTER_DISK) {
        round_polygon(c, nl, L->radius_world, v);
        return polygon_projected_solid_angle(p, n, (const double(*)[3])v, ROUND_SIDES);
    }
    if (L->emitter != AAF_EMITTER_SPHERE) return 0.0;
    /* a sphere subtends the cone of its silhouette circle: radius rad sqrt(D^2 - rad^2)/D,
     * centred rad^2/D before the centre, facing the receiver */
    double u[3] = {c[0] - p[0], c[1] - p[1], c[2] - p[2]};
    double D = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]), rad = L->radius_world;
    if (!(D > rad)) return 0.0; /* inside the light */
    for (int k = 0; k < 3; ++k) u[k] /= D;
    /* The silhouette's cone has half-angle a, sin a = rad / D. Wholly above the receiver's
     * horizon (the angle t between n and the centre at most 90 degrees - a: cos t >= sin a) its
     * projected solid angle is exactly pi sin^2 a cos t (the cosine-weighted cap integrates to
     * its axis' cosine); wholly below, 0. Only a cone the horizon cuts needs the polygon. */
    double cos_t = n[0] * u[0] + n[1] * u[1] + n[2] * u[2], sin_a = rad / D;
    if (cos_t >= sin_a) return M_PI * sin_a * sin_a * cos_t;
    if (cos_t <= -sin_a) return 0.0;
    double cc[3];
    for (int k = 0; k < 3; ++k) cc[k] = c[k] - u[k] * (rad * rad / D);
    round_polygon(cc, u, rad * sqrt(D * D - rad * rad) / D, v);
    return polygon_projected_solid_angle(p, n, (const double(*)[3])v, ROUND_SIDES);
}

static float unoccluded_at(const ShadePass *sp, const float *pf, const float *nf)
{
    double p[3] = {pf[0], pf[1], pf[2]}, n[3] = {nf[0], nf[1], nf[2]};
    const AafDerived *d = sp->d;
    if (d->lights) {
        double sum = 0.0;
        for (int l = 0; l < d->light_count; ++l)
            if (d->lights[l].emitter != AAF_EMITTER_NONE)
                sum += (double)d->lights[l].radiance_mean * emitter_phi(&d->lights[l], p, n);
        return (float)(sum * sp->inv_weight);
    }
    if (sp->inv_area > 0.0) return (float)(polygon_projected_solid_angle(p, n, sp->quad, 4) * sp->inv_area);
    /* a point-like light: the limit of the same mean, with an isotropic emitter */
    const float *c = d->light_center;
    double w[3] = {c[0] - p[0], c[1] - p[1], c[2] - p[2]};
    double len2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
    double cos_r = (n[0] * w[0] + n[1] * w[1] + n[2] * w[2]) / sqrt(len2);
    return (len2 > 0.0 && cos_r > 0.0) ? (float)(cos_r / len2) : 0.0f;
}

/* Whether r at the guides' normal n stands for r at the normals of the samples behind it
 * (coherence: gbuffer_shading_normal_coherence). The composite divides the pixel's direct
 * light, which its samples saw at their own normals, by this one r; near a light's horizon r
 * changes by orders of magnitude over a spread of normals (a curved surface moving over the
 * shutter or seen through a wide lens: samples at times it faced the light over r at a mean
 * normal that hardly does), and the quotient, divided by a near-zero r, reached 40x the
 * visibility's range and spread into the neighbours' filtered light (docs/algorithms.md 4.7).
 * The samples' mean cosine to n is the coherence, so some of them lie at least acos(coherence)
 * from it: r at n tilted by that angle each way along two tangent axes must stay within
 * UNOCCLUDED_SPREAD_RATIO of r at n, else the pixel keeps its own direct light (r = 0: below
 * the composite's minimum, as for a receiver facing away). */
static bool unoccluded_steady(const ShadePass *sp, const float *p, const float *n, float coherence, float r_at_n)
{
    if (coherence >= UNOCCLUDED_STEADY_COHERENCE) return true;
    if (!(r_at_n > 0.0f)) return true; /* already left out (the composite's minimum) */
    float spread = acosf(coherence), c = cosf(spread), s = sinf(spread);
    vec3 nv = v3(n[0], n[1], n[2]), t1, t2;
    v3_basis(nv, &t1, &t2);
    const vec3 tangents[4] = {t1, v3_scale(t1, -1.0f), t2, v3_scale(t2, -1.0f)};
    for (int j = 0; j < 4; ++j) {
        vec3 m = v3_add(v3_scale(nv, c), v3_scale(tangents[j], s));
        float tilted[3] = {m.x, m.y, m.z};
        float r = unoccluded_at(sp, p, tilted);
        if (!(r * UNOCCLUDED_SPREAD_RATIO >= r_at_n && r <= UNOCCLUDED_SPREAD_RATIO * r_at_n)) return false;
    }
    return true;
}

static void shade_range(void *ctx, size_t begin, size_t end, int part)
{
    (void)part;
    const ShadePass *sp = ctx;
    const AafDerived *d = sp->d;
    bool known = d->lights || d->light_known;
    for (size_t i = begin; i < end; ++i) {
        sp->r[i] = 0.0f;
        if (!d->g->hit[i] || !known) continue;
        /* at the shading guides: a split pixel's first surface (gbuffer.h), which its direct
         * light is demodulated for */
        float v = unoccluded_at(sp, d->g->spos4 + 4 * i, d->g->snrm4 + 4 * i);
        if (!unoccluded_steady(sp, d->g->spos4 + 4 * i, d->g->snrm4 + 4 * i, gbuffer_shading_normal_coherence(d->g, i), v))
            v = 0.0f;
        sp->r[i] = isfinite(v) ? v : 0.0f;
    }
}

void aaf_unoccluded_irradiance(const AafDerived *d, float *r)
{
    /* Pixels are independent, so the two cores' split does not change the result. */
    ShadePass sp;
    memset(&sp, 0, sizeof sp);
    sp.d = d;
    sp.r = r;
    if (d->lights) {
        double weight = 0.0;
        for (int l = 0; l < d->light_count; ++l) {
            const AafLightGeom *L = &d->lights[l];
            double area = 0.0;
            if (L->emitter == AAF_EMITTER_TRIANGLE) {
                double e1[3], e2[3];
                for (int k = 0; k < 3; ++k) {
                    e1[k] = (double)L->tri[1][k] - L->tri[0][k];
                    e2[k] = (double)L->tri[2][k] - L->tri[0][k];
                }
                double cx = e1[1] * e2[2] - e1[2] * e2[1], cy = e1[2] * e2[0] - e1[0] * e2[2],
                       cz = e1[0] * e2[1] - e1[1] * e2[0];
                area = 0.5 * sqrt(cx * cx + cy * cy + cz * cz);
            }
            if (L->emitter == AAF_EMITTER_DISK || L->emitter == AAF_EMITTER_SPHERE)
                area = M_PI * (double)L->radius_world * L->radius_world;
            if (L->emitter != AAF_EMITTER_NONE) weight += (double)L->radiance_mean * area;
        }
        sp.inv_weight = weight > 0.0 && isfinite(weight) ? 1.0 / weight : 1.0;
    }
    static const double corner[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    double lu = 0.0, lv = 0.0;
    for (int k = 0; k < 3; ++k) {
        lu += (double)d->light_half_u[k] * d->light_half_u[k];
        lv += (double)d->light_half_v[k] * d->light_half_v[k];
    }
    for (int c = 0; c < 4; ++c)
        for (int k = 0; k < 3; ++k)
            sp.quad[c][k] = (double)d->light_center[k] + corner[c][0] * d->light_half_u[k] +
                            corner[c][1] * d->light_half_v[k];
    double area = 4.0 * sqrt(lu) * sqrt(lv);
    /* below 1e-12 of the squared scene size the rectangle is a point for every receiver */
    double scene2 = (double)d->g->scene_size_world * d->g->scene_size_world;
    sp.inv_area = (area > 1e-12 * scene2 && isfinite(area)) ? 1.0 / area : 0.0;
    recon_parallel_for((size_t)d->width * (size_t)d->height, shade_range, &sp);
}

AafPixelStats aaf_derived_pixel_stats(const AafDerived *d)
{
    AafPixelStats st = {0};
    st.width = d->width;
    st.height = d->height;
    st.hit = d->g->hit;
    st.pixel_world = d->g->pixel_world;
    st.d1_world = d->d1;
    st.d2min_world = d->d2min;
    st.d2max_world = d->d2max;
    st.sigma_light_world = d->sigma_light;
    st.zmin_world = d->zmin;
    st.zmax_world = d->zmax;
    st.coc_min_px = d->coc_min;
    st.coc_max_px = d->coc_max;
    st.blinn_phong_m = d->phong_m;
    return st;
}
