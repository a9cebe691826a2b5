/* The light frame and unoccluded irradiance of FSF (fsf_light.h). */
#include "recon/fsf/fsf_light.h"

#include <math.h>
#include <stdlib.h>

#include "recon/polygon_irradiance.h"
#include "recon/recon_parallel.h"

static float luminance(vec3 c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

bool fsf_light_from_renderer(const Renderer *r, FsfLight *out, Diag *d)
{
    int count = renderer_light_count(r), best = -1;
    float best_power = 0.0f;
    /* the brightest emitter shape: luminance times its triangles' total area */
    for (int l = 0; l < count; ++l) {
        RenderLightInfo a;
        if (!renderer_light_info(r, l, &a) || a.kind != RENDER_LIGHT_AREA || !a.is_triangle) continue;
        float power = 0.0f;
        for (int m = 0; m < count; ++m) {
            RenderLightInfo b;
            if (renderer_light_info(r, m, &b) && b.kind == RENDER_LIGHT_AREA && b.is_triangle && b.shape == a.shape)
                power += luminance(b.radiance) * b.area_world;
        }
        if (power > best_power) best_power = power, best = l;
    }
    if (best < 0) {
        diag_set(d, WEDGE_EXIT_USAGE, (SrcLoc){0},
                 "--filter fsf filters soft shadows of a planar area light made of triangles; the scene has none");
        return false;
    }
    RenderLightInfo first;
    renderer_light_info(r, best, &first);
    vec3 c = v3s(0.0f);
    float area = 0.0f;
    for (int m = 0; m < count; ++m) {
        RenderLightInfo b;
        if (!renderer_light_info(r, m, &b) || b.kind != RENDER_LIGHT_AREA || !b.is_triangle || b.shape != first.shape)
            continue;
        c = v3_madd(c, b.center_world, b.area_world);
        area += b.area_world;
    }
    c = v3_scale(c, 1.0f / area);
    /* u along the first triangle's shortest edge, projected into the light's plane */
    vec3 n = first.normal_world, e = v3_sub(first.tri_world[1], first.tri_world[0]);
    for (int k = 1; k < 3; ++k) {
        vec3 f = v3_sub(first.tri_world[(k + 1) % 3], first.tri_world[k]);
        if (v3_length2(f) < v3_length2(e)) e = f;
    }
    vec3 u = v3_madd(e, n, -v3_dot(e, n));
    u = v3_scale(u, 1.0f / v3_length(u));
    vec3 v = v3_cross(n, u);
    float half[2] = {0.0f, 0.0f};
    for (int m = 0; m < count; ++m) {
        RenderLightInfo b;
        if (!renderer_light_info(r, m, &b) || b.kind != RENDER_LIGHT_AREA || !b.is_triangle || b.shape != first.shape)
            continue;
        for (int k = 0; k < 3; ++k) {
            vec3 q = v3_sub(b.tri_world[k], c);
            half[0] = fmaxf(half[0], fabsf(v3_dot(q, u)));
            half[1] = fmaxf(half[1], fabsf(v3_dot(q, v)));
        }
    }
    if (!(half[0] > 0.0f && half[1] > 0.0f && isfinite(half[0]) && isfinite(half[1]))) {
        diag_set(d, WEDGE_EXIT_USAGE, (SrcLoc){0}, "--filter fsf: the area light has no extent");
        return false;
    }
    out->centre_world = c;
    out->normal_world = n;
    out->axis_world[0] = u;
    out->axis_world[1] = v;
    out->half_m[0] = half[0];
    out->half_m[1] = half[1];
    out->shape = first.shape;
    return true;
}

typedef struct {
    const Renderer *r;
    int shape; /* only this emitter shape's triangles, or -1: every area light's */
    const unsigned char *hit;
    const float *pos4, *nrm4;
    float *out;
} ShadeJob;

static void shade_range(void *ctx, size_t begin, size_t end, int part)
{
    (void)part;
    const ShadeJob *j = ctx;
    int count = renderer_light_count(j->r);
    for (size_t i = begin; i < end; ++i) {
        j->out[i] = 0.0f;
        if (!j->hit[i]) continue;
        double p[3] = {j->pos4[4 * i], j->pos4[4 * i + 1], j->pos4[4 * i + 2]};
        double nr[3] = {j->nrm4[4 * i], j->nrm4[4 * i + 1], j->nrm4[4 * i + 2]};
        double sum = 0.0;
        for (int l = 0; l < count; ++l) {
            RenderLightInfo b;
            if (!renderer_light_info(j->r, l, &b) || b.kind != RENDER_LIGHT_AREA || !b.is_triangle) continue;
            if (j->shape >= 0 && b.shape != j->shape) continue;
            vec3 to = v3_sub(v3((float)p[0], (float)p[1], (float)p[2]), b.center_world);
            if (!b.two_sided && !(v3_dot(to, b.normal_world) > 0.0f)) continue; /* behind a one-sided emitter */
            double v[3][3];
            for (int k = 0; k < 3; ++k)
                v[k][0] = b.tri_world[k].x, v[k][1] = b.tri_world[k].y, v[k][2] = b.tri_world[k].z;
            sum += (double)luminance(b.radiance) * polygon_projected_solid_angle(p, nr, v, 3);
        }
        j->out[i] = isfinite(sum) ? (float)sum : 0.0f;
    }
}

void fsf_unoccluded_irradiance(const Renderer *r, int n, const unsigned char *hit, const float *pos4,
                               const float *nrm4, float *out)
{
    ShadeJob j = {r, -1, hit, pos4, nrm4, out};
    recon_parallel_for((size_t)n, shade_range, &j);
}

void fsf_unoccluded_irradiance_of(const Renderer *r, int shape, int n, const unsigned char *hit, const float *pos4,
                                  const float *nrm4, float *out)
{
    ShadeJob j = {r, shape < 0 ? -2 : shape, hit, pos4, nrm4, out}; /* -2 matches no shape */
    recon_parallel_for((size_t)n, shade_range, &j);
}

void fsf_light_share(int n, const float *own, const float *all, float *share)
{
    for (int i = 0; i < n; ++i) {
        float s = all[i] > 0.0f ? own[i] / all[i] : 0.0f;
        share[i] = isfinite(s) ? fminf(s, 1.0f) : 0.0f;
    }
}
